/* The fluid's object as the files of src/fluid/ share it: the solver and state fluid.c
   owns, and the parts that one file each owns (moving meshes, forces, a prescribed interface
   velocity, the matrix-free Jacobian) with the operator object that assembles. */
#ifndef FSIOPT_FLUID_IMPL_H
#define FSIOPT_FLUID_IMPL_H
#include "fluid.h"
#include "fem.h"
#include "fluid_operator.h"

typedef enum {
  FLUID_STOKES,
  FLUID_NAVIER_STOKES
} FluidModel;

/* The parts of the fluid that one file owns, each with its create and destroy there */
typedef struct _n_FluidALE       *FluidALE;       /* moving meshes (fluid_ale.c) */
typedef struct _n_FluidForces    *FluidForces;    /* the force on a body (fluid_forces.c) */
typedef struct _n_FluidDirichlet *FluidDirichlet; /* the interface velocity prescribed (fluid_dirichlet.c) */
typedef struct _n_FluidMatFree   *FluidMatFree;   /* -fluid_matfree (fluid_matfree.c) */
typedef struct _n_FluidOutlets   *FluidOutlets;   /* 0D outlets (fluid_outlets.c) */

/* the constants' array: the solver's, the scene's (PhysicsData.extra), the outlets' pressures */
#define FLUID_MAX_CONSTANTS (FLUID_NUM_CONSTANTS + FSIOPT_MAX_EXTRA + FSIOPT_MAX_OUTLETS)

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
  Vec        xlocal_work;
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
  struct {                      /* chord iterations' Jacobian refreshed (fluid_nonlinear.c) */
    PetscReal rate;             /* -fluid_chord_refresh_rate: refresh above this contraction */
    PetscBool active;           /* in this solve: chord on f->snes with a Krylov solver */
    PetscReal first, last;      /* this solve's initial and latest residual norms */
  } refresh;
  PetscInt   interface_face;    /* 0: no interface */
  PetscBool  interface_convective_term; /* -1/2 rho ((u.n) u, v) on the interface: the control absorbs it */
  PetscBool  initial_projection;
  PetscBool  backflow, backflow_faces_given;
  PetscInt   n_backflow_faces, backflow_faces[FSIOPT_MAX_BOUNDARIES];
  PetscReal  atol;            /* the user's (or our default) absolute residual tolerance */
  PetscReal  rhs_rtol;        /* and one relative to the right-hand side */
  PetscReal  newton_ksp_rtol; /* the Krylov tolerance of the Newton steps (0: the solver's own) */
  PetscBool  moving;          /* the mesh moves (fluid_ale.c) */
  PetscBool  use_matfree;     /* -fluid_matfree */
  struct {                    /* the field split's Schur preconditioning matrix (fluid_schur_laplacian.c) */
    PetscBool use;            /* -fluid_schur_pressure_laplacian */
    Mat       matrix;         /* -(tau + 1/m) K with Dirichlet rows */
    PetscReal scale;          /* tau + 1/m it holds */
  } schur_laplacian;
  /* the operators (fluid_operator.c): the solver's, and with -fem_backend_check the other
     backend's beside it */
  FluidOperator  op, check;
  FluidALE       ale;       /* NULL on a fixed mesh */
  FluidForces    forces;    /* NULL without body faces */
  FluidDirichlet dirichlet; /* its solver made when a Dirichlet-Neumann coupling asks */
  FluidMatFree   matfree;   /* NULL without -fluid_matfree */
  FluidOutlets   outlets;   /* NULL without 0D outlets */
  PhysicsData    data;
  DirichletDatum datums[FSIOPT_MAX_BOUNDARIES];
  SolverCounts   counts;
  StepFailure    failure; /* of the step in progress */
};

PetscErrorCode FluidSetConstants(Fluid, PetscReal mass, PetscReal op, PetscReal load);
PetscErrorCode FluidSetVolumeWeakForm(Fluid, DM, DMLabel region);
/* fluid_nonlinear.c */
PetscErrorCode FluidNonlinearSolveSetUp(Fluid);
PetscErrorCode FluidNonlinearSolve(Fluid, SNES, Vec rhs, PetscBool chord, PetscInt step, const char what[]);

/* fluid_operator.c: the solver's operator from -fem_backend (and the check's), after the
   initial projection; -fem_backend_check at the start of the first steps */
PetscErrorCode FluidOperatorsSetUp(Fluid);
PetscErrorCode FluidOperatorsCheck(Fluid);
PetscErrorCode FluidOperatorsDestroy(Fluid);
/* the fluid's SNES evaluates through f->op (FluidSNESResidual, FluidSNESJacobian) instead of
   DMPlex's own callbacks: on moving meshes and on libCEED's backend */
PetscErrorCode FluidSNESUseOperator(Fluid);
PetscErrorCode FluidSNESResidual(SNES, Vec x, Vec F, void *);
PetscErrorCode FluidSNESJacobian(SNES, Vec x, Mat J, Mat P, void *);

/* fluid_ale.c */
PetscErrorCode FluidALECreate(Fluid, FluidALE *); /* with the scene's motion at the fluid's time */
PetscErrorCode FluidALEDestroy(FluidALE *);
PetscErrorCode FluidALEBeginStep(Fluid);
PetscErrorCode FluidALEFollowScene(Fluid); /* the scene's closed-form motion at the fluid's time */
PetscErrorCode FluidALECheckpoint(Fluid, Checkpoint, PetscBool load, PetscBool bdf2_state);
/* the copy of the DM without constraints (the fields and volume terms on every row; during a
   step on the old domain), and the step's history term on it */
PetscErrorCode FluidALEGetAll(Fluid, DM *dm_all, Vec *history_all);
/* out = the free rows of a global vector of that copy */
PetscErrorCode FluidALEFreeRows(Fluid, Vec all, Vec out);
/* the step in progress (counted in steps_at_dt) is BDF2: not the first at its dt */
static inline PetscBool FluidStepIsBDF2(Fluid f)
{
  return f->time_order == 2 && f->steps_at_dt > 1 ? PETSC_TRUE : PETSC_FALSE;
}

/* fluid_forces.c: the faces of the scene's body (its force_faces) on this rank, sorted, each once */
PetscErrorCode FluidBodyFaces(Fluid, IS *faces);
/* fluid_face_integrals.c: the faces of the face sets `values` on this rank, sorted, each
   once; the integrals over such faces of a local state (collective) */
PetscErrorCode FluidFaceSetFaces(Fluid, PetscInt n, const PetscInt values[], IS *faces);
PetscErrorCode FluidIntegrateFaces(Fluid, Vec xlocal, IS faces, FluidFaceIntegral *, Vec flux_local);
PetscErrorCode FluidInterpolatedFlux(void *fluid, PetscInt face, FieldFn, void *fn_ctx, PetscReal *flux); /* FluxMeasure */
PetscErrorCode FluidForcesCreate(Fluid, FluidForces *);

/* fluid_outlets.c: made at set-up when the scene has 0D outlets; each residual sets their
   pressures from its iterate (FluidOutletsSetIterate); a step begins from the state the last
   one left. FluidOutletsGetPressures writes them in the constants' order (the last, outlet 0)
   and returns how many. */
PetscErrorCode FluidOutletsCreate(Fluid);
PetscErrorCode FluidOutletsDestroy(FluidOutlets *);
PetscErrorCode FluidOutletsSetIterate(Fluid, Vec xlocal);
/* their rank-one terms into the assembled Jacobian P, and into J when it is another assembled one (else NULL) */
PetscErrorCode FluidOutletsAddJacobian(Fluid, Vec xlocal, Mat P, Mat J);
PetscErrorCode FluidOutletsBeginStep(Fluid);
PetscErrorCode FluidOutletsCheckpoint(Fluid, Checkpoint, PetscBool load);
PetscInt       FluidOutletsGetPressures(Fluid, PetscScalar constants[]);
PetscErrorCode FluidForcesDestroy(FluidForces *);

/* fluid_dirichlet.c: created with the fluid, its solver by FluidSetUpDirichlet; Refactor:
   the next solve factors anew (a change of dt); Reset: the solver goes, made anew at the
   next sweep (a restart) */
PetscErrorCode FluidDirichletCreate(FluidDirichlet *);
PetscErrorCode FluidDirichletRefactor(FluidDirichlet);
PetscErrorCode FluidDirichletReset(FluidDirichlet);
PetscErrorCode FluidDirichletDestroy(FluidDirichlet *);

/* fluid_matfree.c: the shell operator of the solver's SNES, preconditioned by the assembled
   matrix the solver's operator set (after FluidOperatorsSetUp made it). The SNES's Jacobian
   moves its state (FluidMatFreeUpdate; with -fem_backend_check compared with the assembled
   one); with OperatorOnly set (FluidUpdateJacobian reusing the preconditioner) only that. */
PetscErrorCode FluidMatFreeCreate(Fluid, FluidMatFree *);
PetscBool      FluidMatFreeIsOperator(FluidMatFree, Mat J);
PetscErrorCode FluidMatFreeSetOperatorOnly(FluidMatFree, PetscBool);
PetscBool      FluidMatFreeOperatorOnly(FluidMatFree, Mat J);
PetscErrorCode FluidMatFreeUpdate(Fluid, Vec xlocal, PetscBool old_mass);
PetscErrorCode FluidMatFreeDestroy(FluidMatFree *);

/* fluid_weak_form.c */
PetscErrorCode FluidSetConstantsFull(Fluid, PetscReal mass, PetscReal op, PetscReal load, PetscReal convection,
                                     PetscReal projection);
PetscErrorCode FluidSetUpWeakForm(Fluid);
PetscErrorCode FluidSchurLaplacianSetUp(Fluid);
PetscErrorCode FluidSchurLaplacianBeginStep(Fluid);
PetscErrorCode FluidProjectExact(
  Fluid); /* adds its kernel to the weak form; the Stokes projection of the exact solution at f->time into f->x */
PetscErrorCode FluidSetPressureStabilization(Fluid);
#endif
