#ifndef FSIOPT_H
#define FSIOPT_H

#include <petscdmplex.h>
#include <petscsnes.h>
#include <petscds.h>

/* Face-set values of the box meshes and of the gmsh geometries in meshes/: one convention for every scene. */
enum {
  FACE_BOTTOM = 1,
  FACE_RIGHT  = 2,
  FACE_TOP    = 3,
  FACE_LEFT   = 4
};

/* A closed-form field, as PETSc projects and integrates it. */
typedef PetscErrorCode (*FieldFn)(PetscInt dim, PetscReal t, const PetscReal x[], PetscInt Nc, PetscScalar *u,
                                  void *ctx);
/* The gradient of a closed-form field: g[c*dim + d] = d u_c / d x_d. */
typedef PetscErrorCode (*GradientFn)(PetscInt dim, PetscReal t, const PetscReal x[], PetscInt Nc, PetscScalar *g,
                                     void *ctx);

typedef void (*ResidualKernel)(PetscInt, PetscInt, PetscInt, const PetscInt[], const PetscInt[], const PetscScalar[],
                               const PetscScalar[], const PetscScalar[], const PetscInt[], const PetscInt[],
                               const PetscScalar[], const PetscScalar[], const PetscScalar[], PetscReal,
                               const PetscReal[], PetscInt, const PetscScalar[], PetscScalar[]);
typedef void (*BdResidualKernel)(PetscInt, PetscInt, PetscInt, const PetscInt[], const PetscInt[], const PetscScalar[],
                                 const PetscScalar[], const PetscScalar[], const PetscInt[], const PetscInt[],
                                 const PetscScalar[], const PetscScalar[], const PetscScalar[], PetscReal,
                                 const PetscReal[], const PetscReal[], PetscInt, const PetscScalar[], PetscScalar[]);

#define FSIOPT_MAX_BOUNDARIES 8
#define FSIOPT_MAX_EXTRA      8

/* Dirichlet datum of one face set. The time comes from the owning solver, not from PETSc's
   argument: PETSc's SNES and integral helpers insert boundary values at time 0 or PETSC_MIN_REAL. */
typedef struct {
  FieldFn          fn;
  void            *ctx;
  const PetscReal *time;
} DirichletDatum;

/* The flow rate int u.n (n out of the fluid) through the face set `face` of the velocity
   field fn as the fluid interpolates and integrates it (its nodal values, its elements). */
typedef struct {
  PetscErrorCode (*flux)(void *ctx, PetscInt face, FieldFn fn, void *fn_ctx, PetscReal *flux);
  void *ctx;
} FluxMeasure;

/* A 0D outlet of the fluid (fluid_outlets.c): on its face set the traction -p n with
   p = R_p Q + P_c, Q the flow rate out through it, and C dP_c/dt = Q - (P_c - P_d)/R_d (the
   three-element Windkessel, RCR); C = 0: the resistance p = R_p Q + P_d. */
#define FSIOPT_MAX_OUTLETS 8
typedef struct {
  char      name[64];
  PetscInt  face;
  PetscReal proximal_resistance, capacitance, distal_resistance, distal_pressure;
} OutletModel;

/* What a single-physics solver needs from a scene: boundary data, loads, exact solution. */
typedef struct {
  PetscInt n_dirichlet, dirichlet_faces[FSIOPT_MAX_BOUNDARIES];
  FieldFn  dirichlet_fn[FSIOPT_MAX_BOUNDARIES];
  void    *dirichlet_ctx[FSIOPT_MAX_BOUNDARIES]; /* its ctx argument; NULL: the scene's ctx below */
  /* fluid: called with the fluid's mesh, the face set, nu = mu/rho and the fluid's flux
     measure before the datum is first used (a flow-rate inlet measures its face set); NULL: none */
  PetscErrorCode (*dirichlet_setup[FSIOPT_MAX_BOUNDARIES])(DM, PetscInt face, PetscReal nu, const FluxMeasure *, void *ctx);
  PetscInt n_traction, traction_faces[FSIOPT_MAX_BOUNDARIES];
  BdResidualKernel
    traction_kernel[FSIOPT_MAX_BOUNDARIES]; /* adds -load*h(x,t); NULL: traction-free or given in volume form */
  ResidualKernel load_value_kernel;         /* f0 part of the data: adds -load*f(x,t), may be NULL */
  ResidualKernel load_stress_kernel;        /* f1 part of the data, may be NULL */
  FieldFn        exact[2];                  /* by field; NULL when unknown */
  GradientFn     exact_gradient[2];
  FieldFn        exact_rate;         /* structure: exact velocity d(eta)/dt */
  PetscInt       interface_face;     /* face set of the fluid-structure interface, 0: none */
  FieldFn        interface_traction; /* fluid: the exact control g = sigma_f n_f at t, for g^0 (NULL: 0) */
  FieldFn
    convective_interface_datum; /* fluid: traction the exact solution adds when the control absorbs the convective term */
  FieldFn     mesh_displacement;                       /* fluid: a prescribed mesh motion d(X, t), NULL: none */
  PetscInt    n_fixed_mesh_faces;                      /* fluid: > 0 makes the mesh follow the interface, */
  PetscInt    fixed_mesh_faces[FSIOPT_MAX_BOUNDARIES]; /* these face sets staying put */
  PetscInt    n_outlets;                               /* fluid: its 0D outlets, each also a traction face */
  OutletModel outlets[FSIOPT_MAX_OUTLETS];             /* set whose kernel is FluidOutletKernel(k) */
  PetscInt    n_robin;                                 /* structure: Robin supports, the traction */
  PetscInt    robin_faces[FSIOPT_MAX_BOUNDARIES];      /* -(k eta + c etadot) on these face sets */
  PetscReal   robin_stiffness[FSIOPT_MAX_BOUNDARIES];  /* k per unit area */
  PetscReal   robin_damping[FSIOPT_MAX_BOUNDARIES];    /* c per unit area */
  PetscInt    n_force_faces;                           /* fluid: face sets of the body whose force (drag, lift) */
  PetscInt    force_faces[FSIOPT_MAX_BOUNDARIES];      /* is recorded each step */
  PetscInt    n_extra;                                 /* scene constants appended after the solver's: */
  PetscScalar extra[FSIOPT_MAX_EXTRA];                 /* the pointwise kernels' scene parameters */
  void       *ctx;                                     /* the closed forms' scene parameters: their ctx */
                                                       /* argument (owned by the scene; see interface_traction) */
} PhysicsData;

/* Counters every solver keeps for summary.json. */
typedef struct {
  PetscInt nonlinear_solves, linear_solves, factorizations;
} SolverCounts;

/* Named error norms a scene with an exact solution reports. */
#define FSIOPT_MAX_ERRORS 8
typedef struct {
  PetscInt  n;
  char      name[FSIOPT_MAX_ERRORS][16];
  PetscReal value[FSIOPT_MAX_ERRORS];
} ErrorTable;

PetscErrorCode ErrorTableAdd(ErrorTable *, const char[], PetscReal);

/* A saved state (checkpoint.h): an HDF5 file or memory. */
typedef struct _p_Checkpoint *Checkpoint;

/* Why a solve inside a time step failed. A failing subproblem (a nonlinear solver that does
   not converge, a mesh that inverts, an optimizer that gives up) records the reason here
   and returns normally, like a SNES with a negative converged reason, so that the time
   loop can retry the step with a smaller dt (step_retry.c). reason[0] == 0: no failure. */
typedef struct {
  char reason[512];
} StepFailure;
PetscErrorCode StepFailureSet(StepFailure *, const char format[], ...) PETSC_ATTRIBUTE_FORMAT(2, 3);
/* A failed solve whose factorization ran out of memory stops the run (no retry mends it),
   with one line naming `solver` and the estimate. Collective on the SNES. */
PetscErrorCode StepFailureCheckMemory(SNES, const char solver[]);
#define StepFailed(failure) ((failure)->reason[0] != 0)
static inline void StepFailureClear(StepFailure *failure)
{
  failure->reason[0] = 0;
}
/* the reason, NULL if there is no failure */
static inline const char *StepFailureReason(const StepFailure *failure)
{
  return failure->reason[0] ? failure->reason : NULL;
}

/* Common run parameters (docs/design.md §6). */
typedef struct {
  char      scene[64];
  char      coupling[16];
  char      output_dir[PETSC_MAX_PATH_LEN];
  PetscInt  refine;
  PetscReal dt, t_start, t_final;
  PetscInt  steps;
} RunParams;

#endif
