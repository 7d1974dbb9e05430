/* -coupling opt: the optimization-based decoupling with TAO (seed Algorithm 3.3 and its
   relatives). TAO minimizes 1/2 ||F(x)||^2 + eps/2 ||x||^2 over the scaled control:
   brgn (Gauss-Newton, CG on the normal equations inside), lmvm, bncg, or the seed's
   relaxed steepest descent (Algorithm 4.11, TAO type "sdrelaxed"). The run's own test
   stops it: the interface jump below -coupling_tol, or a stall. */
#include "coupling_impl.h"
#include "options.h"
#include "logging.h"
#include <petsctao.h>
#include "explicit_jacobian.h"

/* PETSc fixes the signatures of TAO callbacks; each uses a few of their arguments. */
#pragma GCC diagnostic ignored "-Wunused-parameter"

PetscErrorCode TaoCreate_RelaxedSteepestDescent(Tao);
PetscErrorCode TaoRelaxedSDSetTikhonov(Tao, PetscReal);

typedef struct {
  Tao        tao, inner; /* inner: the Tao that iterates (brgn's subsolver, or tao) */
  Vec        F;
  Mat        J;
  PetscReal  tikhonov, tol; /* -coupling_tikhonov, -coupling_tol */
  PetscInt   step, stall_its, inner_seen;
  PetscReal *objectives; /* this step's, by iteration */
  PetscBool  stalled, test_adjoint, test_taylor;
  PetscReal  last_jump, first_jump;
  /* the explicit-Jacobian preconditioner of the inner CG (explicit_jacobian.c) */
  ExplicitJacobian explicit_jacobian;
  PetscInt         rebuild_every, build_block;
  PetscInt         rebuild_inner; /* and when a Gauss-Newton iteration's CG needed more than this */
  PetscInt         last_iteration;
} Opt;

static PetscErrorCode Residual(Tao tao, Vec x, Vec F, void *ctx)
{
  Coupling C = (Coupling)ctx;

  PetscFunctionBeginUser;
  PetscCall(PetscLogStagePop());
  PetscCall(CouplingProblemResidual(C->problem, x, F));
  PetscCall(PetscLogStagePush(FSIOPT_STAGE_OPTIMIZER));
  PetscFunctionReturn(0);
}

static PetscErrorCode Jacobian(Tao tao, Vec x, Mat J, Mat Jpre, void *ctx)
{
  Coupling C = (Coupling)ctx;

  PetscFunctionBeginUser;
  PetscCall(PetscLogStagePop());
  PetscCall(CouplingProblemUpdateJacobian(C->problem, x));
  PetscCall(PetscLogStagePush(FSIOPT_STAGE_OPTIMIZER));
  PetscFunctionReturn(0);
}

/* For the optimizers that see only the objective: f = 1/2 ||F||^2 + eps/2 ||x||^2,
   gradient J^T F + eps x (one adjoint product). */
static PetscErrorCode ObjectiveAndGradient(Tao tao, Vec x, PetscReal *f, Vec g, void *ctx)
{
  Coupling  C   = (Coupling)ctx;
  Opt      *opt = (Opt *)C->data;
  PetscReal Fnorm, xnorm;

  PetscFunctionBeginUser;
  PetscCall(PetscLogStagePop());
  PetscCall(CouplingProblemResidual(C->problem, x, opt->F));
  PetscCall(CouplingProblemUpdateJacobian(C->problem, x));
  PetscCall(CouplingProblemJacobianMultTranspose(C->problem, opt->F, g));
  PetscCall(PetscLogStagePush(FSIOPT_STAGE_OPTIMIZER));
  PetscCall(VecAXPY(g, opt->tikhonov, x));
  PetscCall(VecNorm(opt->F, NORM_2, &Fnorm));
  PetscCall(VecNorm(x, NORM_2, &xnorm));
  *f = 0.5 * Fnorm * Fnorm + 0.5 * opt->tikhonov * xnorm * xnorm;
  PetscFunctionReturn(0);
}

/* Stops on the interface jump (DESIGN §3): converged below -coupling_tol; stalled when the
   objective has not improved by 1 % over -coupling_stall_its iterations; failed past
   -coupling_max_it. Also writes the history row of the iteration. */
static PetscErrorCode ConvergenceTest(Tao tao, void *ctx)
{
  Coupling           C   = (Coupling)ctx;
  Opt               *opt = (Opt *)C->data;
  PetscInt           its, inner_total;
  PetscReal          f, jump;
  TaoConvergedReason reason;
  Vec                x;

  const char *failure;

  PetscFunctionBeginUser;
  PetscCall(TaoGetSolutionStatus(tao, &its, &f, NULL, NULL, NULL, &reason));
  PetscCall(TaoGetSolution(tao, &x));
  PetscCall(PetscLogStagePop());
  PetscCall(CouplingProblemJump(C->problem, x, &jump));
  PetscCall(PetscLogStagePush(FSIOPT_STAGE_OPTIMIZER));
  opt->last_iteration = its;
  PetscCall(CouplingProblemGetFailure(C->problem, &failure));
  if (failure) {
    PetscCall(TaoSetConvergedReason(tao, TAO_DIVERGED_USER));
    PetscFunctionReturn(0);
  }
  PetscCall(TaoGetLinearSolveIterations(tao, &inner_total));
  PetscCall(HistoryAppend(C->history, opt->step, C->dt, its, f, jump, inner_total - opt->inner_seen));
  /* J moved away from the explicit one (a flag swinging): build it anew for the next solve */
  if (opt->explicit_jacobian && opt->rebuild_inner > 0 && inner_total - opt->inner_seen > opt->rebuild_inner)
    PetscCall(ExplicitJacobianRequestRebuild(opt->explicit_jacobian));
  C->stats.inner_iterations += inner_total - opt->inner_seen;
  opt->inner_seen = inner_total;
  opt->last_jump  = jump;
  if (its <= C->max_it) opt->objectives[its] = f;
  if (its == 0) opt->first_jump = jump;
  if (jump <= opt->tol) reason = TAO_CONVERGED_USER;
  else if (PetscIsInfOrNanReal(jump) || (its > 0 && jump > 1e3 * opt->first_jump))
    reason = TAO_DIVERGED_USER; /* blowing up */
  else if (its >= opt->stall_its && f > 0.99 * opt->objectives[its - opt->stall_its]) {
    reason       = TAO_CONVERGED_USER;
    opt->stalled = PETSC_TRUE;
  } else if (its >= C->max_it) reason = TAO_DIVERGED_MAXITS;
  else reason = TAO_CONTINUE_ITERATING;
  PetscCall(TaoSetConvergedReason(tao, reason));
  PetscFunctionReturn(0);
}

/* After a checkpoint the explicit Jacobian is rebuilt at the next step, as a restarted run
   (which starts without one) builds it; after a new dt, because J depends on it. */
static PetscErrorCode OptResynchronize(Coupling C)
{
  Opt *opt = (Opt *)C->data;

  PetscFunctionBeginUser;
  if (opt->explicit_jacobian) PetscCall(ExplicitJacobianRequestRebuild(opt->explicit_jacobian));
  PetscFunctionReturn(0);
}

static PetscErrorCode OptIterate(Coupling C, PetscInt step, CouplingIterations *it)
{
  Opt               *opt = (Opt *)C->data;
  TaoConvergedReason reason;
  const char        *failure;

  PetscFunctionBeginUser;
  opt->step       = step;
  opt->stalled    = PETSC_FALSE;
  opt->inner_seen = 0;
  if (step == 1 && opt->test_adjoint) PetscCall(CouplingProblemTestAdjoint(C->problem, C->x));
  if (step == 1 && opt->test_taylor) PetscCall(CouplingProblemTestTaylor(C->problem, C->x));
  opt->inner_seen = 0; /* TaoSolve restarts TAO's count */
  if (opt->explicit_jacobian && opt->rebuild_every > 0 && (step - 1) % opt->rebuild_every == 0)
    PetscCall(ExplicitJacobianRequestRebuild(opt->explicit_jacobian));
  PetscCall(TaoSetSolution(opt->tao, C->x));
  PetscCall(PetscLogStagePush(FSIOPT_STAGE_OPTIMIZER));
  PetscCall(TaoSolve(opt->tao));
  PetscCall(PetscLogStagePop());
  PetscCall(TaoGetConvergedReason(opt->tao, &reason));
  it->iterations       = opt->last_iteration;
  it->linearized_pairs = opt->last_iteration;
  it->jump             = opt->last_jump;
  it->stalled          = opt->stalled && opt->last_jump > opt->tol ? PETSC_TRUE : PETSC_FALSE;
  PetscCall(CouplingProblemGetFailure(C->problem, &failure));
  if (failure) {
    PetscCall(StepFailureSet(&C->failure,
                             "coupling opt (%s) at step %" PetscInt_FMT ", iteration %" PetscInt_FMT ": %s",
                             C->ops.optimizer(C), step, opt->last_iteration, failure));
    PetscFunctionReturn(0);
  }
  if (reason <= 0)
    PetscCall(StepFailureSet(&C->failure,
                             "coupling opt (%s) failed at step %" PetscInt_FMT ", iteration %" PetscInt_FMT
                             ": TAO reason %s, interface jump %.3e > -coupling_tol %.3e%s",
                             C->ops.optimizer(C), step, opt->last_iteration, TaoConvergedReasons[reason],
                             (double)opt->last_jump, (double)opt->tol,
                             reason == TAO_DIVERGED_USER ? " (the jump grew 1000-fold: diverging)" : ""));
  PetscFunctionReturn(0);
}

static const char *OptOptimizer(Coupling C)
{
  Opt    *opt = (Opt *)C->data;
  TaoType type;
  (void)TaoGetType(opt->tao, &type);
  return type;
}

static PetscErrorCode OptDestroy(Coupling C)
{
  Opt *opt = (Opt *)C->data;

  PetscFunctionBeginUser;
  PetscCall(TaoDestroy(&opt->tao));
  PetscCall(MatDestroy(&opt->J));
  PetscCall(VecDestroy(&opt->F));
  PetscCall(ExplicitJacobianDestroy(&opt->explicit_jacobian));
  PetscCall(PetscFree(opt->objectives));
  PetscCall(PetscFree(C->data));
  PetscFunctionReturn(0);
}

static PetscErrorCode OptSetUp(Coupling C)
{
  Opt      *opt = (Opt *)C->data;
  PetscBool isbrgn, given;
  char      ls_type[64];

  PetscFunctionBeginUser;
  opt->stall_its = 5;
  opt->tol       = 1e-10;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Optimization-based coupling", "coupling");
  PetscCall(OptionsPositiveReal(PetscOptionsObject, "-coupling_tol",
                                "stop when ||u - v_s||_{L2(Gamma_I)} falls below this", &opt->tol));
  opt->rebuild_every = 0;
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-coupling_explicit_jacobian",
                              "Precondition the inner CG with the LU of an explicitly built J, rebuilt every K steps "
                              "(0: no preconditioner, the seed's plain CGLS)",
                              0, 1000000, &opt->rebuild_every));
  opt->build_block = 32;
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-coupling_explicit_jacobian_block",
                              "build that J from products J [e_j ...] of at most this many columns (all blocks of one "
                              "width), one multi-right-hand-side solve each (1: one solve per control)",
                              1, 100000, &opt->build_block));
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-coupling_explicit_jacobian_rebuild_its",
                              "also rebuild that J after a Gauss-Newton iteration whose CG needed more than N "
                              "iterations (0: only every K steps)",
                              0, 1000000, &opt->rebuild_inner));
  PetscCall(
    OptionsIntInRange(PetscOptionsObject, "-coupling_stall_its",
                      "stop a step as stalled when the objective has not improved by 1% over this many iterations", 1,
                      1000, &opt->stall_its));
  PetscCall(PetscOptionsBool("-coupling_test_adjoint", "At the first step, check <J h, r> = <h, J^T r> for random h, r",
                             NULL, opt->test_adjoint, &opt->test_adjoint, NULL));
  PetscCall(PetscOptionsBool("-coupling_test_taylor",
                             "At the first step, print the Taylor remainders ||F(x+th) - F(x) - t J h|| for halving t",
                             NULL, opt->test_taylor, &opt->test_taylor, NULL));
  PetscOptionsEnd();
  PetscCall(CouplingProblemSetConvergedJump(C->problem, opt->tol));
  PetscCall(PetscMalloc1(C->max_it + 1, &opt->objectives));
  PetscCall(CouplingProblemGetTikhonov(C->problem, &opt->tikhonov));
  PetscCall(VecDuplicate(C->x, &opt->F));
  PetscCall(CouplingProblemCreateJacobian(C->problem, &opt->J));
  PetscCall(TaoRegister("sdrelaxed", TaoCreate_RelaxedSteepestDescent));

  /* Defaults that reproduce the seed's Gauss-Newton (Algorithm 3.3): unit steps, CG on
     the normal equations without preconditioner, and no TAO stopping test but ours. */
  PetscCall(OptionsSetDefault("-tao_type", "brgn"));
  PetscCall(OptionsSetDefault("-tao_brgn_regularization_type", "l2pure"));
  PetscCall(OptionsSetDefault("-tao_brgn_subsolver_tao_bnk_ksp_type", "cg"));
  PetscCall(OptionsSetDefault("-tao_brgn_subsolver_tao_bnk_pc_type", "none"));
  PetscCall(OptionsSetDefault("-tao_brgn_subsolver_tao_bnk_ksp_rtol", "1e-10"));
  PetscCall(OptionsSetDefault("-tao_brgn_subsolver_tao_bnk_init_type", "constant"));
  PetscCall(PetscOptionsGetString(NULL, NULL, "-tao_ls_type", ls_type, sizeof(ls_type), &given));
  PetscCall(OptionsSetDefault("-tao_brgn_subsolver_tao_ls_type", given ? ls_type : "unit"));

  PetscCall(TaoCreate(PETSC_COMM_WORLD, &opt->tao));
  PetscCall(TaoSetTolerances(opt->tao, 0.0, 0.0, 0.0));
  PetscCall(TaoSetMaximumIterations(opt->tao, C->max_it + 1));
  PetscCall(TaoSetMaximumFunctionEvaluations(opt->tao, 100 * (C->max_it + 1)));
  PetscCall(TaoSetSolution(opt->tao, C->x));
  PetscCall(TaoSetResidualRoutine(opt->tao, opt->F, Residual, C));
  PetscCall(TaoSetJacobianResidualRoutine(opt->tao, opt->J, opt->J, Jacobian, C));
  PetscCall(TaoSetObjectiveAndGradient(opt->tao, NULL, ObjectiveAndGradient, C));
  PetscCall(TaoSetFromOptions(opt->tao));
  PetscCall(PetscObjectTypeCompare((PetscObject)opt->tao, TAOBRGN, &isbrgn));
  if (isbrgn) {
    PetscCall(TaoBRGNSetRegularizerWeight(opt->tao, opt->tikhonov));
    PetscCall(TaoBRGNGetSubsolver(opt->tao, &opt->inner));
  } else opt->inner = opt->tao;
  {
    PetscBool issd;
    PetscCall(PetscObjectTypeCompare((PetscObject)opt->tao, "sdrelaxed", &issd));
    /* refused here, at set-up, rather than in the first step's solve */
    PetscCheck(!issd || opt->tikhonov > 0, PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG,
               "option -tao_type sdrelaxed: the relaxed steepest descent steps by alpha/delta; expected "
               "-coupling_tikhonov > 0");
    if (issd) PetscCall(TaoRelaxedSDSetTikhonov(opt->tao, opt->tikhonov));
  }
  PetscCall(TaoSetConvergenceTest(opt->inner, ConvergenceTest, C));
  if (isbrgn && opt->rebuild_every > 0) {
    KSP ksp;
    PetscCall(TaoGetKSP(opt->inner, &ksp));
    PetscCheck(ksp, PETSC_COMM_WORLD, PETSC_ERR_SUP,
               "option -coupling_explicit_jacobian: the Gauss-Newton subsolver has no KSP");
    PetscCall(ExplicitJacobianCreate(opt->J, opt->build_block, ksp, &opt->explicit_jacobian));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingCreate_Opt(Coupling C)
{
  Opt *opt;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&opt));
  C->data              = opt;
  C->max_it            = 50;
  C->ops.setup         = OptSetUp;
  C->ops.iterate       = OptIterate;
  C->ops.destroy       = OptDestroy;
  C->ops.optimizer     = OptOptimizer;
  C->ops.resynchronize = OptResynchronize;
  C->ops.restartable   = PETSC_TRUE;
  PetscFunctionReturn(0);
}
