#ifndef FSIOPT_PROBLEM_IMPL_H
#define FSIOPT_PROBLEM_IMPL_H
/* What the files of the coupling problem share: the object, and the helpers that more
   than one of them calls. The coupling methods see coupling.h only; one file per job:
   problem.c (the object, its options and a step's frame), control_maps.c (control <->
   load), residual.c (F and the cached state), products.c (J h, J^T rho), sweep.c
   (Dirichlet-Neumann), derivative_checks.c. */
#include "coupling.h"
#include "motion.h"

struct _p_CouplingProblem {
  MPI_Comm                 comm;
  Fluid                    fluid;     /* NULL on ranks without the fluid */
  Structure                structure; /* NULL on ranks without the structure */
  Interface                itf;
  PhysicsData              fluid_data;
  ControlVariant           variant;
  StructureVelocityMeasure measure;
  PetscReal                tikhonov, velocity_coefficient;
  PetscInt                 step;
  Mat                      mass;
  Vec                      weight_sqrt;                     /* W^{1/2} on the control nodes */
  Vec                      g, r;                            /* control layout */
  Vec                      all_a, all_b, all_q, datum_load; /* all interface nodes */
  Vec                      all_velocity, all_mass_velocity; /* the structure's interface velocity, M times it */
  Vec                      fluid_vec, fluid_sol, fluid_local, structure_vec, structure_sol, structure_local;
  Mat                      fluid_rhs_block, fluid_sol_block, structure_rhs_block, structure_sol_block; /* J H */
  Vec                      state_x, state_F, jacobian_x;
  Vec                      accepted; /* the control the last step ended with */
  PetscBool                state_valid, jacobian_valid;
  PetscBool                jacobian_fresh; /* the fluid was factored at jacobian_x, not lagged */
  PetscReal                state_jump;
  PetscReal                converged_jump;             /* at or below it, no new Jacobian: the optimizer stops there */
  PetscInt                 jacobian_lag, jacobian_age; /* refactor the fluid every jacobian_lag requests */
  PetscBool                lag_preconditioner_only;    /* in between, assemble anew under the lagged preconditioner */
  PetscBool                fluid_krylov;               /* the fluid's linear solves iterate (known on every rank) */
  PetscBool                predict;                    /* fluid's first guess from the linearization */
  Vec                      control_change;
  MeshMotion               motion; /* fluid ranks of a moving interface; NULL otherwise */
  PetscBool                moving; /* the same on every rank */
  PetscBool                extrapolate_mesh;
  DomainUpdate             domain;
  Vec                      mesh_displacement, mesh_displacement_before; /* d^{n-2} */
  KSP                      control_mass_ksp;
  PetscBool                swept;                              /* the state is the last sweep's */
  IS                       fluid_interface_rows;               /* Dirichlet-Neumann sweeps */
  PetscBool                spacing_changed;                    /* d^{n-2} is not one step of this dt back */
  StepFailure              failure;                            /* of the step in progress, on every rank */
  PetscInt                 forward_products, adjoint_products; /* linearized and adjoint solves of the run */
};

/* problem.c */
PetscErrorCode CouplingProblemCollectFailure(CouplingProblem, PetscBool *failed);

/* control_maps.c: the first two overwrite the work vectors all_a and g, the third all_b */
PetscErrorCode CouplingProblemControlToLoad(CouplingProblem, Vec x, Vec q);
PetscErrorCode CouplingProblemStructureLoad(CouplingProblem, Vec x);
PetscErrorCode CouplingProblemControlMassSolve(CouplingProblem, Vec b, Vec g);

/* residual.c */
PetscErrorCode CouplingProblemStateJump(CouplingProblem, PetscReal structure_scale, Vec r, PetscReal *l2);
PetscErrorCode CouplingProblemMoveMesh(CouplingProblem);
/* the structure under its load structure_vec; structure_local its interface velocity */
PetscErrorCode CouplingProblemSolveStructure(CouplingProblem);
/* the state of the control x (a residual evaluation unless it is the one in hand) */
PetscErrorCode CouplingProblemEnsureState(CouplingProblem, Vec x);
/* problem_monolithic.c: the step's coupled system in (x_f, x_s, x) for monolithic.c: its
   residual (which leaves the state of x in hand, as CouplingProblemResidual does), the
   coupling blocks of its Jacobian, and a subproblem's assembled Jacobian at a state */
PetscErrorCode CouplingProblemCoupledResidual(CouplingProblem, Vec xf, Vec xs, Vec x, Vec Ff, Vec Fs, Vec Fx);
PetscErrorCode CouplingProblemCouplingBlocks(CouplingProblem, Mat *Cfx, Mat *Csx, Mat *Cxf, Mat *Cxs);
PetscErrorCode CouplingProblemSystemJacobian(SNES, Vec x, Mat *A);
#endif
