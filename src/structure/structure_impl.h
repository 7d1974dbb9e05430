#ifndef FSIOPT_STRUCTURE_IMPL_H
#define FSIOPT_STRUCTURE_IMPL_H
#include "structure.h"
#include "fem.h"
#include "fem_ceed.h"

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
  PhysicsData    data;
  DirichletDatum datums[FSIOPT_MAX_BOUNDARIES];
  SolverCounts   counts;
  StepFailure    failure; /* of the step in progress */
  /* the operators on the libCEED backend (structure_backend.c) */
  PetscBool         backend_ceed;
  FEMCeedElasticity ceed;
  Mat               ceed_jacobian; /* of its COO pattern: the solver's matrix */
  DM                dm_loads;      /* the scene's volume loads alone, NULL without */
  FEMTractionCache  tractions;
  PetscInt          backend_checked_step;
};

/* structure_backend.c: R(eta) into the global F on the chosen backend (eta local, with its
   boundary values); the solver's callbacks on libCEED's */
PetscErrorCode StructureOperatorResidual(Structure, Vec xlocal, Vec F);
PetscErrorCode StructureBackendSetUp(Structure);
/* -fem_backend_check: both backends at the start of the first steps' solves */
PetscErrorCode StructureBackendCheck(Structure, PetscInt step);
PetscErrorCode StructureBackendDestroy(Structure);
#endif
