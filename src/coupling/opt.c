/* -coupling opt: the optimization-based decoupling with TAO (seed Algorithm 3.3 and its
   relatives). TAO minimizes 1/2 ||F(x)||^2 + eps/2 ||x||^2 over the scaled control:
   brgn (Gauss-Newton, CG on the normal equations inside), lmvm, bncg, or the seed's
   relaxed steepest descent (Algorithm 4.11, TAO type "sdrelaxed"). The run's own test
   stops it: the interface jump below -coupling_tol, or a stall. */
#include "opt_impl.h"
#include "options.h"
#include "logging.h"

/* PETSc fixes the signatures of TAO callbacks; each uses a few of their arguments. */
#pragma GCC diagnostic ignored "-Wunused-parameter"

PetscErrorCode TaoCreate_RelaxedSteepestDescent(Tao);
PetscErrorCode TaoRelaxedSDSetTikhonov(Tao, PetscReal);

const char *const OptInnerNames[] = {"cgls", "gmres", "bicgstab", "chord", "OptInner", "OPT_INNER_", NULL};

PetscErrorCode OptResidual(Coupling C, Vec x, Vec F)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogStagePop()); /* the subproblems log in their own stages */
  PetscCall(CouplingProblemResidual(C->problem, x, F));
  PetscCall(PetscLogStagePush(FSIOPT_STAGE_OPTIMIZER));
  PetscFunctionReturn(0);
}

static PetscErrorCode Residual(Tao tao, Vec x, Vec F, void *ctx)
{
  PetscFunctionBeginUser;
  PetscCall(OptResidual((Coupling)ctx, x, F));
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

/* Stops on the interface jump (docs/design.md §3): converged below -coupling_tol; stalled when the
   objective has not improved by 1 % over -coupling_stall_its iterations; failed past
   -coupling_max_it. */
PetscErrorCode OptTestIteration(Coupling C, PetscInt its, PetscReal f, PetscInt inner_total, OptVerdict *verdict)
{
  Opt        *opt = (Opt *)C->data;
  PetscReal   jump, tol = opt->tol;
  PetscInt    inner;
  const char *failure;

  PetscFunctionBeginUser;
  /* TAO and SNES iterate on C->x itself */
  PetscCall(CouplingProblemJump(C->problem, C->x, &jump));
  opt->last_iteration = its;
  PetscCall(CouplingProblemGetFailure(C->problem, &failure));
  if (failure) {
    *verdict = opt->verdict = OPT_FAILED;
    PetscFunctionReturn(0);
  }
  inner = opt->inner_type == OPT_INNER_CHORD ? 0 : inner_total - opt->inner_seen; /* preonly counts one */
  PetscCall(HistoryAppend(C->history, opt->step, C->dt, its, f, jump, inner));
  /* J moved away from the explicit one (a flag swinging): build it anew for the next solve */
  if (opt->explicit_jacobian && opt->rebuild_inner > 0 && inner > opt->rebuild_inner)
    PetscCall(ExplicitJacobianRequestRebuild(opt->explicit_jacobian));
  if (its > 0 && (opt->inner_type == OPT_INNER_CGLS || inner > 0)) opt->linearized_iterations++;
  C->stats.inner_iterations += inner;
  opt->inner_seen = inner_total;
  if (its == 0) opt->first_jump = jump;
  else if (opt->inner_type == OPT_INNER_CHORD && opt->explicit_jacobian &&
           jump > opt->chord_contraction * opt->last_jump)
    PetscCall(ExplicitJacobianRequestRebuild(opt->explicit_jacobian)); /* J0 no longer contracts */
  opt->last_jump = jump;
  if (its <= C->max_it) opt->objectives[its] = f;
  if (opt->tol_relative > 0) { /* the tighter of the absolute and the relative tolerance */
    PetscCall(CouplingProblemInterfaceVelocity(C->problem, C->x, &opt->last_velocity));
    tol = PetscMin(tol, opt->tol_relative * PetscMax(opt->velocity_scale, opt->last_velocity));
  }
  opt->last_tol = tol;
  if (opt->snes) { /* the Newton step's Krylov method aims at a fraction of the tolerance in force */
    KSP ksp;
    PetscCall(SNESGetKSP(opt->snes, &ksp));
    PetscCall(KSPSetTolerances(ksp, 1e-12, opt->krylov_jump_fraction * tol, PETSC_DEFAULT, 100));
  }
  if (jump <= tol) *verdict = OPT_CONVERGED;
  else if (PetscIsInfOrNanReal(jump) || (its > 0 && jump > 1e3 * opt->first_jump)) *verdict = OPT_DIVERGED;
  else if (its >= opt->stall_its && f > 0.99 * opt->objectives[its - opt->stall_its]) {
    *verdict     = OPT_CONVERGED;
    opt->stalled = PETSC_TRUE;
  } else if (its >= C->max_it) *verdict = OPT_MAX_IT;
  else *verdict = OPT_CONTINUE;
  opt->verdict = *verdict;
  PetscFunctionReturn(0);
}

static PetscErrorCode ConvergenceTest(Tao tao, void *ctx)
{
  Coupling           C = (Coupling)ctx;
  PetscInt           its, inner_total;
  PetscReal          f;
  OptVerdict         verdict;
  TaoConvergedReason reason;

  PetscFunctionBeginUser;
  PetscCall(TaoGetSolutionStatus(tao, &its, &f, NULL, NULL, NULL, NULL));
  PetscCall(TaoGetLinearSolveIterations(tao, &inner_total));
  PetscCall(PetscLogStagePop());
  PetscCall(OptTestIteration(C, its, f, inner_total, &verdict));
  PetscCall(PetscLogStagePush(FSIOPT_STAGE_OPTIMIZER));
  switch (verdict) {
  case OPT_CONTINUE:
    reason = TAO_CONTINUE_ITERATING;
    break;
  case OPT_CONVERGED:
    reason = TAO_CONVERGED_USER;
    break;
  case OPT_MAX_IT:
    reason = TAO_DIVERGED_MAXITS;
    break;
  default:
    reason = TAO_DIVERGED_USER;
  }
  PetscCall(TaoSetConvergedReason(tao, reason));
  PetscFunctionReturn(0);
}

/* After a checkpoint the explicit Jacobian is forgotten and built at the next iteration that
   needs it, as a restarted run (which starts without one) does; after a new dt, because J
   depends on it. */
static PetscErrorCode OptResynchronize(Coupling C)
{
  Opt *opt = (Opt *)C->data;

  PetscFunctionBeginUser;
  if (opt->explicit_jacobian) PetscCall(ExplicitJacobianForget(opt->explicit_jacobian));
  PetscCall(OptRecycleForget(opt));
  PetscFunctionReturn(0);
}

/* The relative tolerance's scale is the largest wall velocity of the run so far: a run from
   rest is held to a fraction of its own motion, and a wall that comes to rest (a steady state)
   is not held to a vanishing tolerance. A restart carries it on, and the forcing's quadratic
   constant (opt_newton_krylov.c) with it, so that it repeats the run. */
static PetscErrorCode OptCheckpoint(Coupling C, Checkpoint cp, PetscBool load)
{
  Opt               *opt     = (Opt *)C->data;
  const char *const  names[] = {"velocity_scale", "newton_quadratic_constant"};
  PetscReal         *values[] = {&opt->velocity_scale, &opt->quadratic_constant};

  PetscFunctionBeginUser;
  for (int i = 0; i < 2; ++i) {
    PetscBool has = PETSC_TRUE;
    if (load) PetscCall(CheckpointHasAttribute(cp, names[i], &has));
    if (has) PetscCall(CheckpointReal(cp, names[i], values[i], load));
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode OptIterate(Coupling C, PetscInt step, CouplingIterations *it)
{
  Opt        *opt = (Opt *)C->data;
  const char *failure, *reason = NULL;

  PetscFunctionBeginUser;
  /* below it the optimizer stops, so no Jacobian is needed there: a lower bound of this step's
     tolerance, whose relative part only grows with the velocity of the iterates */
  PetscCall(CouplingProblemSetConvergedJump(C->problem, opt->tol_relative > 0
                                                          ? PetscMin(opt->tol, opt->tol_relative * opt->velocity_scale)
                                                          : opt->tol));
  opt->step                  = step;
  opt->stalled               = PETSC_FALSE;
  opt->linearized_iterations = 0;
  opt->verdict               = OPT_CONTINUE;
  if (step == 1 && opt->test_adjoint) PetscCall(CouplingProblemTestAdjoint(C->problem, C->x));
  if (step == opt->test_taylor_step && opt->test_taylor) {
    Vec change = NULL; /* the start's change from the last control: how the control moves */
    if (C->start.npast > 0) {
      PetscCall(VecDuplicate(C->x, &change));
      PetscCall(VecWAXPY(change, -1.0, C->start.past[0], C->x));
    }
    PetscCall(CouplingProblemTestTaylor(C->problem, C->x, change));
    PetscCall(VecDestroy(&change));
  }
  opt->inner_seen = 0; /* TaoSolve and SNESSolve restart their counts */
  if (opt->explicit_jacobian && opt->rebuild_every > 0 && (step - 1) % opt->rebuild_every == 0)
    PetscCall(ExplicitJacobianRequestRebuild(opt->explicit_jacobian));
  if (opt->inner_type == OPT_INNER_CGLS) {
    TaoConvergedReason tao_reason;
    PetscCall(TaoSetSolution(opt->tao, C->x));
    PetscCall(PetscLogStagePush(FSIOPT_STAGE_OPTIMIZER));
    PetscCall(TaoSolve(opt->tao));
    PetscCall(PetscLogStagePop());
    PetscCall(TaoGetConvergedReason(opt->tao, &tao_reason));
    if (tao_reason <= 0) reason = TaoConvergedReasons[tao_reason];
  } else PetscCall(OptNewtonKrylovSolve(C, &reason));
  if (opt->tol_relative > 0 && opt->verdict == OPT_CONVERGED)
    opt->velocity_scale = PetscMax(opt->velocity_scale, opt->last_velocity);
  it->iterations       = opt->last_iteration;
  it->linearized_pairs = opt->linearized_iterations;
  it->jump             = opt->last_jump;
  it->stalled          = opt->stalled && opt->last_jump > opt->last_tol ? PETSC_TRUE : PETSC_FALSE;
  PetscCall(CouplingProblemGetFailure(C->problem, &failure));
  if (failure) {
    PetscCall(StepFailureSet(&C->failure,
                             "coupling opt (%s) at step %" PetscInt_FMT ", iteration %" PetscInt_FMT ": %s",
                             C->ops.optimizer(C), step, opt->last_iteration, failure));
    PetscFunctionReturn(0);
  }
  if (reason)
    PetscCall(StepFailureSet(&C->failure,
                             "coupling opt (%s) failed at step %" PetscInt_FMT ", iteration %" PetscInt_FMT
                             ": %s reason %s, interface jump %.3e > the tolerance %.3e%s",
                             C->ops.optimizer(C), step, opt->last_iteration,
                             opt->inner_type == OPT_INNER_CGLS ? "TAO" : "SNES", reason, (double)opt->last_jump,
                             (double)opt->last_tol,
                             opt->verdict == OPT_DIVERGED ? " (the jump grew 1000-fold: diverging)" : ""));
  PetscFunctionReturn(0);
}

/* The accepted control leaves a jump up to -coupling_tol; extrapolated, that error would
   start the next step. Corrected by the chord step -J0^{-1} F(x), with F the accepted
   state's (in hand) and J0 the explicit Jacobian's LU, the past controls are those of a
   jump of O(tol ||I - J J0^{-1}||), for one dense triangular solve and no fluid solve. The
   state stays the accepted one: only the extrapolation's values change. */
static PetscErrorCode OptEndStep(Coupling C)
{
  Opt      *opt = (Opt *)C->data;
  PetscBool solved;

  PetscFunctionBeginUser;
  if (!opt->start_correction) PetscFunctionReturn(0);
  PetscCall(CouplingProblemResidual(C->problem, C->x, opt->F)); /* the accepted state's, in hand */
  PetscCall(ExplicitJacobianSolve(opt->explicit_jacobian, opt->F, opt->correction, &solved));
  if (solved) PetscCall(VecAXPY(C->x, -1.0, opt->correction));
  PetscFunctionReturn(0);
}

PetscErrorCode OptExplicitJacobianCreate(Coupling C, Mat J, PetscBool normal_equations, KSP ksp)
{
  Opt *opt = (Opt *)C->data;

  PetscFunctionBeginUser;
  PetscCall(ExplicitJacobianCreate(J, opt->build_block, normal_equations, ksp, &opt->explicit_jacobian));
  if (opt->probing_rings > 0) {
    InterfaceProbing probing;
    PetscCall(CouplingProblemCreateProbing(C->problem, opt->probing_rings, &probing));
    PetscCall(InterfaceProbingGetColors(probing, &opt->probing_colors));
    PetscCall(ExplicitJacobianSetProbing(opt->explicit_jacobian, probing, opt->probing_rtol));
  }
  PetscFunctionReturn(0);
}

/* "brgn", or the Newton-Krylov inner method ("gmres") */
static const char *OptOptimizer(Coupling C)
{
  Opt    *opt = (Opt *)C->data;
  TaoType type;
  if (opt->inner_type != OPT_INNER_CGLS) return OptInnerNames[opt->inner_type];
  (void)TaoGetType(opt->tao, &type);
  return type;
}

/* What the first line and the closing lines say of the method: the inner solver the regime
   chose, with J0's schedule, and the measure the tolerance bounds. */
static PetscErrorCode OptDescribe(Coupling C, PetscBool fluid_krylov)
{
  Opt  *opt = (Opt *)C->data;
  char  j0[64] = "", extras[64] = "";
  const char *how;

  PetscFunctionBeginUser;
  if (opt->rebuild_every > 0 && opt->probing_colors > 0)
    PetscCall(PetscSNPrintf(j0, sizeof(j0), "%s J0 probed with %" PetscInt_FMT " colours every %" PetscInt_FMT " steps",
                            opt->inner_type == OPT_INNER_CHORD ? "on" : "preconditioned by", opt->probing_colors,
                            opt->rebuild_every));
  else if (opt->rebuild_every > 0)
    PetscCall(PetscSNPrintf(j0, sizeof(j0), "%s J0 every %" PetscInt_FMT " steps",
                            opt->inner_type == OPT_INNER_CHORD ? "on" : "preconditioned by", opt->rebuild_every));
  else PetscCall(PetscStrncpy(j0, opt->inner_type == OPT_INNER_CGLS ? "" : "unpreconditioned", sizeof(j0)));
  if (opt->secants > 0 || opt->start_correction)
    PetscCall(PetscSNPrintf(extras, sizeof(extras), "%s%s", opt->secants > 0 ? ", secant updates" : "",
                            opt->start_correction ? ", corrected start" : ""));
  switch (opt->inner_type) {
  case OPT_INNER_CHORD: how = "chord"; break;
  case OPT_INNER_GMRES: how = "Newton-GMRES"; break;
  case OPT_INNER_BICGSTAB: how = "Newton-BiCGStab"; break;
  default: how = "Gauss-Newton CGLS";
  }
  PetscCall(PetscSNPrintf(C->setting, sizeof(C->setting), "opt (%s%s%s%s; %s fluid)", how, j0[0] ? " " : "", j0,
                          extras, fluid_krylov ? "iterative" : "factored"));
  if (opt->tol_relative > 0)
    PetscCall(PetscSNPrintf(C->measure, sizeof(C->measure),
                            "interface jump ||u - v_s||_L2(Gamma_I) (-coupling_tol %g, -coupling_tol_relative %g)",
                            (double)opt->tol, (double)opt->tol_relative));
  else
    PetscCall(PetscSNPrintf(C->measure, sizeof(C->measure), "interface jump ||u - v_s||_L2(Gamma_I) (-coupling_tol %g)",
                            (double)opt->tol));
  PetscFunctionReturn(0);
}

static PetscErrorCode OptDestroy(Coupling C)
{
  Opt *opt = (Opt *)C->data;

  PetscFunctionBeginUser;
  PetscCall(TaoDestroy(&opt->tao));
  PetscCall(OptNewtonKrylovDestroy(C));
  PetscCall(MatDestroy(&opt->J));
  PetscCall(VecDestroy(&opt->F));
  PetscCall(VecDestroy(&opt->correction));
  PetscCall(ExplicitJacobianDestroy(&opt->explicit_jacobian));
  PetscCall(PetscFree(opt->objectives));
  PetscCall(PetscFree(C->data));
  PetscFunctionReturn(0);
}

static PetscErrorCode OptSetUp(Coupling C)
{
  Opt      *opt = (Opt *)C->data;
  PetscBool isbrgn, given, fluid_krylov;
  char      ls_type[64];

  PetscFunctionBeginUser;
  PetscCall(OptSetFromOptions(C, &fluid_krylov));
  PetscCall(PetscMalloc1(C->max_it + 1, &opt->objectives));
  PetscCall(VecDuplicate(C->x, &opt->F));
  PetscCall(VecDuplicate(C->x, &opt->correction));
  PetscCall(CouplingProblemCreateJacobian(C->problem, &opt->J));
  if (opt->inner_type != OPT_INNER_CGLS) {
    PetscCall(OptNewtonKrylovSetUp(C));
    PetscCall(OptDescribe(C, fluid_krylov));
    PetscFunctionReturn(0);
  }
  PetscCall(TaoRegister("sdrelaxed", TaoCreate_RelaxedSteepestDescent));

  /* Defaults that reproduce the seed's Gauss-Newton (Algorithm 3.3): unit steps, CG on
     the normal equations without preconditioner, and no TAO stopping test but ours. */
  PetscCall(OptionsSetDefault("-tao_type", "brgn"));
  PetscCall(OptionsSetDefault("-tao_brgn_regularization_type", "l2pure"));
  PetscCall(OptionsSetDefault("-tao_brgn_subsolver_tao_bnk_ksp_type", "cg"));
  PetscCall(OptionsSetDefault("-tao_brgn_subsolver_tao_bnk_pc_type", "none"));
  /* inexact Gauss-Newton: the inner CG stops at 1e-4 of its start. On channel2d, the same
     Gauss-Newton iterations as at 1e-10 with half the CG iterations (first 300 steps); the
     manufactured scenes keep 1e-10, the seed's exact steps */
  PetscCall(OptionsSetDefault("-tao_brgn_subsolver_tao_bnk_ksp_rtol", "1e-4"));
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
    PetscCall(OptExplicitJacobianCreate(C, opt->J, PETSC_TRUE, ksp));
  }
  PetscCall(OptDescribe(C, fluid_krylov));
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
  C->ops.end_step      = OptEndStep;
  C->ops.checkpoint    = OptCheckpoint;
  C->ops.restartable   = PETSC_TRUE;
  PetscFunctionReturn(0);
}
