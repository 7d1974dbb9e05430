#ifndef FSIOPT_FLUID_IMPL_H
#define FSIOPT_FLUID_IMPL_H
#include "fluid.h"
#include "fem_ceed.h"
#include "fem.h"

typedef enum {
  FLUID_STOKES,
  FLUID_NAVIER_STOKES
} FluidModel;

struct _p_Fluid {
  MPI_Comm   comm;
  DM         dm;
  SNES       snes;
  FluidModel model;
  PetscReal  rho, mu;
  PetscInt   velocity_degree, pressure_degree;
  PetscReal  pressure_stabilization, pressure_tau; /* alpha and tau of -tau (grad p, grad q) */
  PetscReal  time, dt;
  PetscInt   step;
  Vec        x;          /* (u, p) at `time` */
  Vec        xlocal_old; /* previous state with its boundary values */
  Vec        history;    /* rho/dt M(Omega^{n-1}) u^{n-1} (BDF2 on a moving mesh: fluid_ale.c) */
  Vec        rhs, x_start;
  Vec        x_before; /* u^{n-2} while a step starts, for the extrapolated first guess */
  PetscBool  extrapolate;
  PetscInt   time_order;        /* 1: backward Euler, 2: BDF2 */
  PetscInt   steps_at_dt;       /* steps taken since dt last changed: BDF2 and the extrapolated start need one */
  PetscReal  mass_coefficient;  /* of (u^n, v) in this step: rho/dt, or 3/2 rho/dt (BDF2) */
  PetscInt   lag_after_rebuild; /* the user's Jacobian lag, resumed after a forced rebuild */
  Vec        xlocal_previous;   /* BDF2: u^{n-1} with its boundary values, u^{n-2} while a step starts */
  PetscReal  cell_size;         /* mean, for the pressure stabilization */
  PetscBool  steady;            /* no time derivative: each step is a steady solve at its time */
  PetscBool  chord;             /* nonlinear solves on factors from another state */
  PetscInt   chord_restarts;    /* solves that needed fresh factors */
  PetscInt   interface_face;    /* 0: no interface */
  PetscBool  interface_convective_term; /* -1/2 rho ((u.n) u, v) on the interface: the control absorbs it */
  PetscBool  initial_projection;
  PetscBool  backflow, backflow_faces_given;
  PetscInt   n_backflow_faces, backflow_faces[FSIOPT_MAX_BOUNDARIES];
  PetscReal  atol;     /* the user's (or our default) absolute residual tolerance */
  PetscReal  rhs_rtol; /* and one relative to the right-hand side */
  PetscReal  newton_ksp_rtol; /* the Krylov tolerance of the Newton steps (0: the solver's own) */
  /* moving meshes (fluid_ale.c) */
  PetscBool moving;
  DM        dm_aux; /* the mesh velocity z, Q1 */
  Vec       z_local;
  Vec       coordinates_reference, displacement, displacement_old; /* coordinate layout */
  Vec       displacement_previous;                                 /* BDF2: d^{n-2} */
  PetscInt *corners, ncorners; /* per cell corner: cell, its vertex's and its dim edge neighbours' coordinate offsets */
  PetscReal corner_ratio;      /* the smallest corner area (volume) / its reference one, present mesh */
  PetscReal worst_corner_ratio, worst_corner_time; /* the smallest over the meshes steps ended on, and its time */
  PetscBool corner_ratio_of_step;                  /* corner_ratio is of a mesh a step of this run moved to */
  DM        dm_all; /* the same fields and volume terms without constraints (fluid_forces.c) */
  Mat       mass_old,
    mass_old_all; /* rho/dt M(Omega^{n-1}), BDF2 rho/dt (2 M(Omega^{n-1}) - 1/2 M(Omega^{n-2})): free rows, all rows */
  Mat mass_older_all; /* BDF2: 1/2 rho/dt M(Omega^{n-2}) */
  Vec history_all;    /* the history on all rows of dm_all (global) */
  IS  free_in_all;
  Vec all_x, all_y, all_local, xlocal_work, work;
  /* the force on a body (fluid_forces.c) */
  DM       dm_force;                  /* the fields on the cells that touch the body */
  Vec      force_x, force_residual;   /* its local vectors */
  PetscInt n_force_copy, *force_copy; /* per point: its offset in dm_force, in dm, its dofs */
  PetscInt n_force_rows, *force_rows; /* the body's velocity nodes (first component): in dm_force's
                                                    local array; on a moving mesh the owned ones in dm_all's global array */
  /* the interface velocity prescribed (fluid_dirichlet.c) */
  SNES         snes_dirichlet;
  Mat          dirichlet_jacobian;
  Vec          dirichlet_rhs;
  PetscInt     n_dirichlet_rows, *dirichlet_rows; /* local offsets of the interface rows */
  IS           dirichlet_rows_global;
  PetscScalar *dirichlet_residual; /* R(x) on them at the last evaluation */
  PetscInt     dirichlet_step;
  PetscInt     dirichlet_lag; /* -fluid_dirichlet_snes_lag_jacobian K > 0: factors kept across steps */
  /* the operators on the libCEED backend (fluid_backend.c) */
  PetscBool        backend_ceed;                    /* the solver's operators are libCEED's */
  FEMCeedFluid     ceed;                            /* NULL on the PETSc backend without -fem_backend_check */
  Mat              ceed_jacobian;                   /* of its COO pattern: the solver's matrix on the libCEED backend */
  DM               dm_loads;                        /* the scene's volume loads alone, NULL without */
  FEMDirichletValues dirichlet_values; /* kept per time and boundary position (libCEED's backend) */
  FEMTractionCache tractions; /* the scene's traction terms of a time and mesh */
  PetscBool        matfree;   /* -fluid_matfree (fluid_matfree.c) */
  PetscInt         matfree_checked_step;
  Mat              matfree_jacobian; /* the SNES's operator; ceed_jacobian its preconditioner */
  PetscBool        operator_only;    /* the next Jacobian moves matfree_jacobian's state only */
  Mat              boundary_jacobian;
  PetscBool        check_backends;
  PetscInt         backend_checked_step;
  PhysicsData      data;
  DirichletDatum   datums[FSIOPT_MAX_BOUNDARIES];
  SolverCounts     counts;
  StepFailure      failure; /* of the step in progress */
};

PetscErrorCode FluidSetConstants(Fluid, PetscReal mass, PetscReal op, PetscReal load);
PetscErrorCode FluidSetVolumeWeakForm(Fluid, DM, DMLabel region);

/* fluid_forces.c */
/* the faces of the scene's body (its force_faces) on this rank, sorted, each once */
PetscErrorCode FluidBodyFaces(Fluid, IS *faces);
PetscErrorCode FluidForcesSetUp(Fluid);
PetscErrorCode FluidForcesDestroy(Fluid);

PetscErrorCode FluidNonlinearSolve(Fluid, SNES, Vec rhs, PetscBool chord, PetscInt step, const char what[]);
PetscErrorCode FluidDirichletDestroy(Fluid);

/* fluid_backend.c: R(x) into the global F, and its Jacobian, on the chosen backend, with
   the old domains' mass term when old_mass (moving meshes); x a local state with its
   boundary values */
PetscErrorCode FluidOperatorResidual(Fluid, Vec xlocal, PetscBool old_mass, Vec F);
PetscErrorCode FluidOperatorJacobian(Fluid, Vec xlocal, PetscBool old_mass, Mat J, Mat P);
/* libCEED's backend, moving meshes: the volume terms alone (with the old domains' mass term
   when old_mass) on every row of dm_all, for the body force */
PetscErrorCode FluidVolumeResidualAll(Fluid, Vec xlocal, PetscBool old_mass, Vec yall);
PetscErrorCode FluidBackendSetUp(Fluid);
/* libCEED's backend: the volume blocks and PETSc's boundary terms at xlocal into A, a matrix
   of the libCEED pattern (FEMCeedFluidCreateMatrix) */
PetscErrorCode FluidCeedAssemble(Fluid, Vec xlocal, PetscBool old_mass, Mat A);
/* the SNES callbacks of the operators (on a moving mesh with the old domains' mass); PETSc's
   backend on a fixed mesh keeps DMPlex's own */
PetscErrorCode FluidSNESResidual(SNES, Vec x, Vec F, void *);
PetscErrorCode FluidSNESJacobian(SNES, Vec x, Mat J, Mat P, void *);
PetscErrorCode FluidBackendCheck(Fluid);
/* fluid_matfree.c: the shell operator and its boundary matrix (SetUp after the backend's);
   Update at each of the solver's Jacobians (with -fem_backend_check: compared with it) */
PetscErrorCode FluidMatFreeSetUp(Fluid);
PetscErrorCode FluidMatFreeUpdate(Fluid, Vec xlocal, PetscBool old_mass);
PetscErrorCode FluidMatFreeDestroy(Fluid);
PetscErrorCode FluidBackendDestroy(Fluid);
/* fluid_ale.c */
PetscErrorCode FluidPrescribedDisplacement(Fluid, FieldFn motion, PetscReal t, Vec displacement);
PetscErrorCode FluidALESetUp(Fluid);
PetscErrorCode FluidALEBeginStep(Fluid);
/* the step's old-domain mass times the local state x: on dm_all's global rows (y = or y +=),
   or on the free rows */
PetscErrorCode FluidOldMassMultAll(Fluid, Vec xlocal, Vec yall, PetscBool add);
PetscErrorCode FluidOldMassMult(Fluid, Vec xlocal, Vec out);
/* the step in progress (counted in steps_at_dt) is BDF2: not the first at its dt */
static inline PetscBool FluidStepIsBDF2(Fluid f)
{
  return f->time_order == 2 && f->steps_at_dt > 1 ? PETSC_TRUE : PETSC_FALSE;
}
PetscErrorCode FluidALEDestroy(Fluid);
/* fluid_weak_form.c */
PetscErrorCode FluidSetConstantsFull(Fluid, PetscReal mass, PetscReal op, PetscReal load, PetscReal convection,
                                     PetscReal projection);
PetscErrorCode FluidSetUpWeakForm(Fluid);
PetscErrorCode FluidProjectExact(
  Fluid); /* adds its kernel to the weak form; the Stokes projection of the exact solution at f->time into f->x */
PetscErrorCode FluidSetPressureStabilization(Fluid);
#endif
