/* The structure's object as the files of src/structure/ share it: material, solver, the
   displacement and velocity of the time scheme, and the operator object (PETSc or libCEED)
   that assembles. */
#ifndef FSIOPT_STRUCTURE_IMPL_H
#define FSIOPT_STRUCTURE_IMPL_H
#include "structure.h"
#include "fem.h"
#include "structure_operator.h"

struct _p_Structure {
  MPI_Comm       comm;
  DM             dm;      /* with the Dirichlet constraints */
  DM             dm_free; /* the same space without constraints: for fields that are not displacements */
  SNES           snes;
  PetscReal      rho, youngs_modulus, poisson_ratio, mu, lambda;
  PetscInt       degree, time_order;
  StructureModel model;
  PetscBool      initial_projection;
  PetscReal      time, dt;
  Vec            eta;                             /* global displacement at `time` */
  Vec            eta_local;                       /* the same with its boundary values */
  Vec            etadot_local;                    /* velocity, all dofs */
  Vec            eta_old_local, etadot_old_local; /* the previous step's, during a step */
  Vec            work_local, history, work, rhs;
  Vec            load, load_old; /* interface load B_s g of this and of the previous step */
  Vec            tangent_at;     /* St. Venant-Kirchhoff: the local state of the factored tangent */
  DM             dm_material; /* materials per region: their P0 field's space, NULL without */
  Vec            material;    /* local: rho/rho_s, mu, lambda, model per cell */
  PhysicsData    data;
  DirichletDatum datums[FSIOPT_MAX_BOUNDARIES];
  SolverCounts   counts;
  StepFailure    failure; /* of the step in progress */
  /* the operators (structure_operator.c): the solver's, and with -fem_backend_check the
     other backend's beside it */
  StructureOperator op, check;
};

/* structure_operator.c: the solver's operator from -fem_backend (and the check's), after the
   initial projection; -fem_backend_check at the start of the first steps' solves */
PetscErrorCode StructureOperatorsSetUp(Structure);
PetscErrorCode StructureOperatorsCheck(Structure, PetscInt step);
PetscErrorCode StructureOperatorsDestroy(Structure);
extern const char *const StructureModelNames[]; /* by StructureModel */
/* structure_materials.c: the materials per region the options give (the auxiliary field and
   the model: St. Venant-Kirchhoff where any region is) */
PetscErrorCode StructureMaterialsSetUp(Structure);
/* structure_robin.c: the Robin supports' natural boundaries, and their coefficients
   s_b = op k_b + rate c_b as the last n_robin of the DS's nconstants constants */
PetscErrorCode StructureRobinAddBoundaries(Structure);
void           StructureRobinShifts(Structure, PetscReal op, PetscReal rate, PetscInt nconstants, PetscScalar constants[]);
#endif
