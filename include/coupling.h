#ifndef FSIOPT_COUPLING_H
#define FSIOPT_COUPLING_H
#include "fsiopt.h"
#include "fluid.h"
#include "structure.h"
#include "interface.h"
#include <petscviewer.h>

/* The control problem of one time step (docs/design.md §3), on the parent communicator.

   The optimizer's variable is the scaled control x = W^{1/2} g, with W the lumped
   interface mass on the control nodes: the Euclidean norm of x is then the L2(Gamma_I)
   norm of g, so TAO's inner products, Tikhonov terms and stopping tests are mesh
   independent. With r = u - v_s the interface velocity jump,

     F(x)    = W^{1/2} r(g),                       ||F|| ~ ||u - v_s||_{L2(Gamma_I)}
     J h     = W^{1/2} P [T_f A_f^{-1} S_f + c T_s A_s^{-1} S_s] M P^T W^{-1/2} h
     J^T rho = W^{-1/2} P M [T_f A_f^{-T} S_f + c T_s A_s^{-T} S_s] P^T W^{1/2} rho

   where M is the interface mass matrix, P restricts to the control nodes, T and S = T^T
   are the velocity traces and their spreading into the free rows, A the factored
   Jacobians and c = d v_s / d eta^n. The fluid satisfies R_f(x_f) = B_f g and the
   structure R_s(x_s) = -B_s g (B = S M P^T), hence the two plus signs above.
   In src/coupling/: problem.c (the object, its options, a step's begin and end),
   control_maps.c (a control's interface load M P^T W^{-1/2} x, a traction's control),
   residual.c (F), products.c (J h, J^T rho), sweep.c (the Dirichlet-Neumann sweep),
   derivative_checks.c. */
typedef enum {
  CONTROL_TRACTION,
  CONTROL_CONVECTIVE
} ControlVariant;
typedef enum {
  DOMAIN_LAGGED,
  DOMAIN_CURRENT
} DomainUpdate; /* -coupling_domain */

typedef struct _p_CouplingProblem *CouplingProblem;

PetscErrorCode CouplingProblemCreate(MPI_Comm, Fluid, Structure, Interface, const PhysicsData *fluid_data,
                                     CouplingProblem *);
PetscErrorCode CouplingProblemDestroy(CouplingProblem *);
PetscErrorCode CouplingProblemCheckpoint(CouplingProblem, Checkpoint, PetscBool load); /* checkpoint.h */
PetscErrorCode CouplingProblemGetControlVariant(
  ControlVariant *); /* -coupling_control, readable before the solvers exist */
PetscErrorCode CouplingProblemCreateControl(CouplingProblem, Vec *);
PetscErrorCode CouplingProblemCreateJacobian(CouplingProblem, Mat *);
PetscErrorCode CouplingProblemGetTikhonov(CouplingProblem, PetscReal *);
/* Whether the fluid's linear (and linearized) solves iterate; the same on every rank */
PetscErrorCode CouplingProblemFluidSolverIsKrylov(CouplingProblem, PetscBool *);
/* The traction g of the control the last step ended with, on all interface nodes (an
   interface vector; 0 where the fluid's velocity is prescribed, and before a first step). */
PetscErrorCode CouplingProblemInterfaceTraction(CouplingProblem, Vec all);
/* The control the first step starts from: the scene's exact traction at t0, or 0. */
PetscErrorCode CouplingProblemInitialControl(CouplingProblem, PetscReal t0, Vec x);

PetscErrorCode CouplingProblemBeginStep(CouplingProblem, PetscInt step);
PetscErrorCode CouplingProblemSetTimeStep(CouplingProblem, PetscReal dt);
/* Why the step in progress failed (a subproblem's StepFailure, the same on every rank),
   NULL if it has not. After a failure the evaluations below return F = 0 and J = I. */
PetscErrorCode CouplingProblemGetFailure(CouplingProblem, const char **reason);
PetscErrorCode CouplingProblemResidual(CouplingProblem, Vec x, Vec F);
PetscErrorCode CouplingProblemUpdateJacobian(CouplingProblem, Vec x);
/* the same, with the fluid refactored at x whatever the lag (for an explicit J0 that many
   iterations will use) */
PetscErrorCode CouplingProblemRefreshJacobian(CouplingProblem, Vec x);
/* Jumps at or below this need no new Jacobian: the optimizer accepts the point. */
PetscErrorCode CouplingProblemSetConvergedJump(CouplingProblem, PetscReal);
PetscErrorCode CouplingProblemJacobianMult(CouplingProblem, Vec h, Vec y);
PetscErrorCode CouplingProblemJacobianMultBlock(CouplingProblem, Mat H, Mat Y); /* dense columns */
PetscErrorCode CouplingProblemJacobianMultTranspose(CouplingProblem, Vec rho, Vec y);
/* A sparse J0 by probing (jacobian_probing.c): J's blocks between interface nodes within
   `rings` rings of each other, from one product per colour and component of a colouring of
   the interface's nodes, whose number is set by the interface's connectivity, not its size. */
typedef struct _p_InterfaceProbing *InterfaceProbing;
PetscErrorCode CouplingProblemCreateProbing(CouplingProblem, PetscInt rings, InterfaceProbing *);
PetscErrorCode InterfaceProbingGetColors(InterfaceProbing, PetscInt *ncolors);
/* J0's pattern, no values, on the ranks that hold controls (NULL elsewhere) */
PetscErrorCode InterfaceProbingCreateMatrix(InterfaceProbing, Mat *J0);
PetscErrorCode InterfaceProbingBuild(InterfaceProbing, Mat J, PetscInt block, Mat J0);
PetscErrorCode InterfaceProbingDestroy(InterfaceProbing *);
/* the products of the run so far: J h (a block's columns each) and J^T rho, one linearized
   solve of each subproblem apiece */
PetscErrorCode CouplingProblemGetProductCounts(CouplingProblem, PetscInt *forward, PetscInt *adjoint);
/* ||u - v_s||_{L2(Gamma_I)} at x (with the consistent interface mass) */
PetscErrorCode CouplingProblemJump(CouplingProblem, Vec x, PetscReal *jump);
/* ||v_s||_{L2(Gamma_I)}, the structure's interface velocity under the control x: the scale of
   a relative coupling tolerance */
PetscErrorCode CouplingProblemInterfaceVelocity(CouplingProblem, Vec x, PetscReal *velocity);
PetscErrorCode CouplingProblemEndStep(CouplingProblem, Vec x);
/* One Dirichlet-Neumann sweep (the partitioned baselines): the structure under the
   control x, the fluid mesh moved to its displacement, the fluid with the structure's
   interface velocity prescribed, and x_new: the control whose load equals the fluid's
   reaction on the interface. A fixed point is a solution of the coupled step. */
PetscErrorCode CouplingProblemSweep(CouplingProblem, Vec x, Vec x_new);
/* At set-up: the sweep needs the traction control and a fluid boundary with a traction. */
PetscErrorCode CouplingProblemCheckSweepable(CouplingProblem);
/* The same sweep started from the fluid (the seed's arrangement, relaxing the wall's
   motion): the fluid with the interface velocity v prescribed on the mesh of the last
   structure solve, x the control equal to its reaction, the structure under x and v_new
   its interface velocity. v, v_new: interface vectors (InterfaceCreateVector layout). */
PetscErrorCode CouplingProblemSweepVelocity(CouplingProblem, Vec v, Vec x, Vec v_new);
PetscErrorCode CouplingProblemCreateInterfaceVector(CouplingProblem, Vec *);
/* ||u - v_s||_{L2(Gamma_I)} of the last sweep's state (zero up to the solvers' tolerance
   for the traction sweep) */
PetscErrorCode CouplingProblemSweepJump(CouplingProblem, PetscReal *jump);
/* The structure's displacement on the interface nodes (fluid node order). Collective. */
PetscErrorCode CouplingProblemInterfaceDisplacement(CouplingProblem, Vec all);

/* Checks a user can run on any scene (-coupling_test_adjoint, -coupling_test_taylor). */
PetscErrorCode CouplingProblemTestAdjoint(CouplingProblem, Vec x);
PetscErrorCode CouplingProblemTestTaylor(CouplingProblem, Vec x, Vec direction); /* NULL: a random one */

/* A coupling method advances the coupled system by one step (one file per method). */
typedef struct _p_Coupling *Coupling;
typedef struct {
  PetscInt iterations;       /* coupling iterations (Gauss-Newton or sweeps), summed over steps */
  PetscInt linearized_pairs; /* iterations that also solved the linearized and adjoint problems */
  PetscInt inner_iterations;
  PetscInt forward_products, adjoint_products; /* linearized and adjoint solves (CouplingProblemGetProductCounts) */
  PetscInt stalled_steps;
  PetscReal
    max_jump; /* largest final interface velocity jump of a step (partitioned: zero to the solvers' tolerance) */
  PetscReal last_jump;   /* that of the last step completed */
  PetscReal max_measure; /* largest final value of the method's convergence measure over the steps */
  const char *measure;   /* its name and tolerance ("interface jump ||u - v_s||_L2(Gamma_I) <= 1e-4") */
  const char *setting;   /* how the method iterates ("chord on J0 ...") */
} CouplingStats;

/* The methods by name (-coupling), as the scenes are: CouplingRegisterAll() adds opt, dn,
   aitken, iqnils and iqnimvj; a new method is one file whose create function fills the method's
   operations (coupling_impl.h) and one CouplingRegister line. */
extern PetscFunctionList CouplingList;
PetscErrorCode           CouplingRegister(const char name[], PetscErrorCode (*create)(Coupling));
PetscErrorCode           CouplingRegisterAll(void);
PetscErrorCode           CouplingListNames(char names[], size_t len);
PetscErrorCode           CouplingCheckMethod(const char method[]); /* an error naming the known ones */
PetscErrorCode           CouplingFinalize(void);
PetscErrorCode CouplingCreate(const char method[], CouplingProblem, const char output_dir[], PetscReal t0, PetscReal dt,
                              Coupling *);
PetscErrorCode CouplingStep(Coupling, PetscInt step);
/* Why the step failed (a subproblem, or the method not converging), NULL if it has not. */
PetscErrorCode CouplingGetFailure(Coupling, const char **reason);
/* The next steps' dt (a retried step's, step_retry.c). */
PetscErrorCode CouplingSetTimeStep(Coupling, PetscReal dt);
/* A history.csv row for a step's attempt that failed (event: what follows). */
PetscErrorCode CouplingLogRetry(Coupling, PetscInt step, const char event[]);
PetscErrorCode CouplingGetStats(Coupling, CouplingStats *);
PetscErrorCode CouplingGetOptimizer(Coupling, const char **);
PetscErrorCode CouplingFinish(Coupling); /* closes the history */
/* The control and its past values (checkpoint.h). Files for opt only: the partitioned
   methods keep past iterates (IQN-ILS) that are not saved; memory for every method. */
PetscErrorCode CouplingCheckpoint(Coupling, Checkpoint, PetscBool load);
PetscErrorCode CouplingIsRestartable(Coupling, PetscBool *);
PetscErrorCode CouplingDestroy(Coupling *);
#endif
