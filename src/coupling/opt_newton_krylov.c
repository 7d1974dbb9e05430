/* -coupling opt -coupling_inner gmres|bicgstab|chord: Newton on the square interface system
   F(x) = 0 (SNES newtonls, unit steps). With no Tikhonov term the control and the jump live
   in the same interface space, so an iteration's step solves J h = -F itself: by GMRES or
   BiCGStab right-preconditioned by the LU of the explicit J0 in hand or by the earlier
   products (-coupling_inner_recycle, opt_krylov_recycle.c) (one linearized solve per
   Krylov iteration, no adjoint solve, the conditioning of J instead of J^T J), or as the
   chord step h = -J0^{-1} F, which costs no linearized solve at all. The Krylov method stops
   when the linearized jump ||F + J h|| is below -coupling_inner_jump_fraction x -coupling_tol,
   or sooner, at the Eisenstat-Walker forcing term (below): solving further only sharpens a
   prediction the next residual replaces. */
#include "opt_impl.h"
#include "options.h"
#include "logging.h"
#include "fem.h"

/* PETSc fixes the signatures of SNES callbacks; each uses a few of their arguments. */
#pragma GCC diagnostic ignored "-Wunused-parameter"

static PetscErrorCode Residual(SNES snes, Vec x, Vec F, void *ctx)
{
  PetscFunctionBeginUser;
  PetscCall(OptResidual((Coupling)ctx, x, F));
  PetscFunctionReturn(0);
}

/* fresh: refactor the fluid whatever the lag */
static PetscErrorCode Linearize(Coupling C, PetscBool fresh)
{
  Opt *opt = (Opt *)C->data;

  PetscFunctionBeginUser;
  if (opt->linearization_current && !fresh) PetscFunctionReturn(0);
  PetscCall(PetscLogStagePop());
  if (fresh) PetscCall(CouplingProblemRefreshJacobian(C->problem, opt->x_linearization));
  else PetscCall(CouplingProblemUpdateJacobian(C->problem, opt->x_linearization));
  PetscCall(PetscLogStagePush(FSIOPT_STAGE_OPTIMIZER));
  opt->linearization_current = PETSC_TRUE;
  PetscFunctionReturn(0);
}

/* The problem linearizes at x at once, also for a chord step, which multiplies by no J:
   the factors in hand (lagged by -coupling_jacobian_lag) then predict the next fluid
   solve's start (-coupling_predictor), which saves that solve a Newton iteration. */
static PetscErrorCode Jacobian(SNES snes, Vec x, Mat A, Mat B, void *ctx)
{
  Coupling C   = (Coupling)ctx;
  Opt     *opt = (Opt *)C->data;

  PetscFunctionBeginUser;
  PetscCall(VecCopy(x, opt->x_linearization));
  opt->linearization_current = PETSC_FALSE;
  PetscCall(Linearize(C, PETSC_FALSE));
  if (A != B) {
    /* -coupling_snes_mf_operator: differences of F are the operator, J the preconditioner's
       matrix; the assembly sets the differences' base point */
    PetscCall(MatAssemblyBegin(A, MAT_FINAL_ASSEMBLY));
    PetscCall(MatAssemblyEnd(A, MAT_FINAL_ASSEMBLY));
  }
  PetscFunctionReturn(0);
}

/* With -coupling_inexact_products theta, a product may be the less accurate the smaller the
   Krylov residual r already is (relaxed inexact Krylov, Simoncini and Szyld 2003): its
   error enters the residual scaled by the step's coefficient, which shrinks like |r|. The
   products' linearized solves stop at theta x abstol / |r|, capped at 0.1, and never
   tighter than the solvers' own -*_ksp_rtol. Under the forcing below, a solve stops above
   abstol, yet its products keep abstol's accuracy: scaled to the forcing term's target
   instead, they spoiled the Newton step (tube3d level 3: the first step's second jump 7.3e-3
   against 3.0e-3, the second step's first 0.50 against 0.27). The converged jump is the
   nonlinear residual's, so inexact products change the iterations, not the answer. The step
   expected to be the last (||F_k|| shrunk once more by the ratio ||F_k|| / ||F_k-1|| lands
   within 20 x abstol, 10 x -coupling_tol) must reach abstol itself, so its products use the
   smaller theta of -coupling_inexact_products_last: the earlier steps' errors are swamped by the
   nonlinearity the next iteration corrects anyway. The prediction is linear convergence's:
   with the fluid's Jacobian at the current state (-coupling_lag_preconditioner_only) Newton
   converges faster and the rule may miss a last step (tube3d level 1: jumps 10.7, 0.11,
   5e-5), whose products are then as loose as the others'; a quadratic prediction caught it
   but fired a step early on level 2 (predicted 6e-6, landed at 6.5e-4), 7 % more fluid Krylov
   iterations for the same Gauss-Newton iterations. */
static PetscErrorCode NewtonMult(Mat A, Vec h, Vec y)
{
  Coupling C;
  Opt     *opt;

  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(A, &C));
  opt = (Opt *)C->data;
  PetscCall(Linearize(C, PETSC_FALSE));
  if (opt->inexact_products > 0) {
    KSP       ksp;
    PetscReal rnorm, abstol, theta = opt->inexact_products;
    PetscCall(SNESGetKSP(opt->snes, &ksp));
    PetscCall(KSPGetResidualNorm(ksp, &rnorm));
    PetscCall(KSPGetTolerances(ksp, NULL, &abstol, NULL, NULL));
    if (opt->fnorm_previous > 0 && opt->fnorm * (opt->fnorm / opt->fnorm_previous) <= 20 * abstol)
      theta = PetscMin(theta, opt->inexact_products_last);
    /* tighter where the recycled preconditioner stretched h (opt_krylov_recycle.c) */
    PetscCall(FEMSetLinearizedRtol((rnorm > 0 ? PetscMin(0.1, theta * abstol / rnorm) : 0.1) * opt->recycle_stretch));
    opt->recycle_stretch = 1.0;
  }
  PetscCall(CouplingProblemJacobianMult(C->problem, h, y));
  PetscCall(FEMSetLinearizedRtol(0));
  PetscCall(OptRecycleRecord(opt, h, y));
  PetscFunctionReturn(0);
}

static PetscErrorCode NewtonMultTranspose(Mat A, Vec rho, Vec y)
{
  Coupling C;

  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(A, &C));
  PetscCall(Linearize(C, PETSC_FALSE));
  PetscCall(CouplingProblemJacobianMultTranspose(C->problem, rho, y));
  PetscFunctionReturn(0);
}

/* the explicit J0's columns, a block of them per multi-right-hand-side solve: J0 serves many
   iterations, so it is built on fresh fluid factors */
static PetscErrorCode NewtonMatMult(Mat A, Mat H, Mat Y, void *product_data)
{
  Coupling C;

  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(A, &C));
  PetscCall(Linearize(C, PETSC_TRUE));
  PetscCall(CouplingProblemJacobianMultBlock(C->problem, H, Y));
  PetscFunctionReturn(0);
}

/* Eisenstat-Walker forcing (PETSc's, -coupling_snes_ksp_ew*, version 2 with alpha 2): Newton
   on F converges quadratically, ||F_k+1|| = C ||F_k||^2, so the step's Krylov solve needs a
   linearized jump only a fraction gamma of that, rtol_k = gamma (||F_k|| / ||F_k-1||)^2 =
   gamma C ||F_k||; solving further sharpens a prediction the nonlinearity spoils anyway.
   PETSc's first solve of a step takes the fixed rtol_0; unless the user gave
   -coupling_snes_ksp_ew_rtol0, it is gamma C ||F_0|| with C = ||F_1|| / ||F_0||^2 of the step
   before, at most 0.1. */
static PetscErrorCode ForcingFirstSolve(SNES snes, Opt *opt, PetscInt its, PetscReal Fnorm)
{
  PetscBool ew;
  PetscReal gamma;

  PetscFunctionBeginUser;
  PetscCall(SNESKSPGetUseEW(snes, &ew));
  if (!ew || !opt->forcing_first_adaptive) PetscFunctionReturn(0);
  if (its == 1 && opt->fnorm_previous > 0) opt->quadratic_constant = Fnorm / PetscSqr(opt->fnorm_previous);
  if (its != 0 || opt->quadratic_constant <= 0) PetscFunctionReturn(0);
  PetscCall(SNESKSPGetParametersEW(snes, NULL, NULL, NULL, &gamma, NULL, NULL, NULL));
  PetscCall(SNESKSPSetParametersEW(snes, PETSC_DEFAULT, PetscMin(0.1, gamma * opt->quadratic_constant * Fnorm),
                                   PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT));
  PetscFunctionReturn(0);
}

static PetscErrorCode ConvergenceTest(SNES snes, PetscInt its, PetscReal xnorm, PetscReal step_norm, PetscReal Fnorm,
                                      SNESConvergedReason *reason, void *ctx)
{
  Coupling   C   = (Coupling)ctx;
  Opt       *opt = (Opt *)C->data;
  PetscInt   krylov_total;
  OptVerdict verdict;

  PetscFunctionBeginUser;
  if (opt->secants > 0 && opt->explicit_jacobian) {
    /* J0^{-1} learns from the step just taken: H y = s for s = x_k - x_{k-1}, y = F_k - F_{k-1} */
    Vec F;
    PetscCall(SNESGetFunction(snes, &F, NULL, NULL));
    if (its > 0) {
      PetscCall(VecAYPX(opt->x_previous, -1.0, C->x));
      PetscCall(VecAYPX(opt->F_previous, -1.0, F));
      PetscCall(ExplicitJacobianSecantUpdate(opt->explicit_jacobian, opt->x_previous, opt->F_previous));
    }
    PetscCall(VecCopy(C->x, opt->x_previous));
    PetscCall(VecCopy(F, opt->F_previous));
  }
  opt->fnorm_previous = its > 0 ? opt->fnorm : 0;
  opt->fnorm          = Fnorm;
  PetscCall(ForcingFirstSolve(snes, opt, its, Fnorm));
  PetscCall(SNESGetLinearSolveIterations(snes, &krylov_total));
  PetscCall(PetscLogStagePop());
  PetscCall(OptTestIteration(C, its, 0.5 * Fnorm * Fnorm, krylov_total, &verdict));
  PetscCall(PetscLogStagePush(FSIOPT_STAGE_OPTIMIZER));
  switch (verdict) {
  case OPT_CONTINUE:
    *reason = SNES_CONVERGED_ITERATING;
    break;
  case OPT_CONVERGED:
    *reason = SNES_CONVERGED_FNORM_ABS;
    break;
  case OPT_MAX_IT:
    *reason = SNES_DIVERGED_MAX_IT;
    break;
  case OPT_DIVERGED:
    *reason = SNES_DIVERGED_DTOL;
    break;
  default:
    *reason = SNES_DIVERGED_INNER;
  }
  PetscFunctionReturn(0);
}

/* PETSc reads the forcing's options without their ranges; a first solve at rtol 2 would stop
   at once, every step */
static PetscErrorCode ForcingCheck(SNES snes)
{
  PetscBool ew;
  PetscInt  version;
  PetscReal rtol0, rtol_max, gamma, alpha;

  PetscFunctionBeginUser;
  PetscCall(SNESKSPGetUseEW(snes, &ew));
  if (!ew) PetscFunctionReturn(0);
  PetscCall(SNESKSPGetParametersEW(snes, &version, &rtol0, &rtol_max, &gamma, &alpha, NULL, NULL));
  PetscCheck(version >= 1 && version <= 3, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
             "option -coupling_snes_ksp_ew_version: expected 1, 2 or 3, got %" PetscInt_FMT, version);
  PetscCheck(rtol0 >= 0 && rtol0 < 1, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
             "option -coupling_snes_ksp_ew_rtol0: expected a relative tolerance in [0, 1), got %g", (double)rtol0);
  PetscCheck(rtol_max >= 0 && rtol_max < 1, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
             "option -coupling_snes_ksp_ew_rtolmax: expected a relative tolerance in [0, 1), got %g",
             (double)rtol_max);
  PetscCheck(gamma >= 0 && gamma <= 1, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
             "option -coupling_snes_ksp_ew_gamma: expected a value in [0, 1], got %g", (double)gamma);
  PetscCheck(alpha > 1 && alpha <= 2, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
             "option -coupling_snes_ksp_ew_alpha: expected a value in (1, 2], got %g", (double)alpha);
  PetscFunctionReturn(0);
}

PetscErrorCode OptNewtonKrylovSetUp(Coupling C)
{
  Opt           *opt     = (Opt *)C->data;
  const KSPType  types[] = {NULL, KSPGMRES, KSPBCGS, KSPPREONLY};
  KSP            ksp;
  SNESLineSearch linesearch;
  PetscInt       n, N;
  PetscBool      given;

  PetscFunctionBeginUser;
  PetscCheck(opt->tikhonov == 0, PETSC_COMM_WORLD, PETSC_ERR_ARG_INCOMP,
             "option -coupling_inner %s: Newton on the square system solves F(x) = 0; expected -coupling_tikhonov 0, "
             "got %g (use -coupling_inner cgls)",
             OptInnerNames[opt->inner_type], (double)opt->tikhonov);
  PetscCheck(opt->inner_type != OPT_INNER_CHORD || opt->rebuild_every > 0, PETSC_COMM_WORLD, PETSC_ERR_ARG_INCOMP,
             "option -coupling_inner chord: the chord step is -J0^-1 F with the explicit J0; expected "
             "-coupling_explicit_jacobian K > 0");
  PetscCheck(opt->inner_type != OPT_INNER_CHORD || !opt->recycle_steps, PETSC_COMM_WORLD, PETSC_ERR_ARG_INCOMP,
             "option -coupling_inner_recycle: preconditions a Krylov method by earlier products; expected "
             "-coupling_inner gmres or bicgstab, got chord");
  PetscCall(VecDuplicate(C->x, &opt->x_linearization));
  PetscCall(VecGetLocalSize(C->x, &n));
  PetscCall(VecGetSize(C->x, &N));
  PetscCall(MatCreateShell(PETSC_COMM_WORLD, n, n, N, N, C, &opt->J_newton));
  PetscCall(MatShellSetOperation(opt->J_newton, MATOP_MULT, (void (*)(void))NewtonMult));
  PetscCall(MatShellSetOperation(opt->J_newton, MATOP_MULT_TRANSPOSE, (void (*)(void))NewtonMultTranspose));
  PetscCall(
    MatShellSetMatProductOperation(opt->J_newton, MATPRODUCT_AB, NULL, NewtonMatMult, NULL, MATSEQDENSE, MATDENSE));
  PetscCall(
    MatShellSetMatProductOperation(opt->J_newton, MATPRODUCT_AB, NULL, NewtonMatMult, NULL, MATMPIDENSE, MATDENSE));

  PetscCall(SNESCreate(PETSC_COMM_WORLD, &opt->snes));
  PetscCall(SNESSetOptionsPrefix(opt->snes, "coupling_"));
  PetscCall(SNESSetType(opt->snes, SNESNEWTONLS));
  PetscCall(SNESGetLineSearch(opt->snes, &linesearch));
  PetscCall(SNESLineSearchSetType(linesearch, SNESLINESEARCHBASIC));
  PetscCall(SNESSetFunction(opt->snes, opt->F, Residual, C));
  PetscCall(SNESSetJacobian(opt->snes, opt->J_newton, opt->J_newton, Jacobian, C));
  PetscCall(SNESSetConvergenceTest(opt->snes, ConvergenceTest, C, NULL));
  PetscCall(SNESSetTolerances(opt->snes, 0.0, 0.0, 0.0, C->max_it + 1, 100 * (C->max_it + 1)));
  /* a Krylov method stopped at its iteration limit still gives a step; the jump judges it */
  PetscCall(SNESSetMaxLinearSolveFailures(opt->snes, C->max_it + 2));
  PetscCall(SNESGetKSP(opt->snes, &ksp));
  PetscCall(KSPSetType(ksp, types[opt->inner_type]));
  if (opt->inner_type != OPT_INNER_CHORD) PetscCall(KSPSetPCSide(ksp, PC_RIGHT)); /* the true ||F + J h|| */
  PetscCall(KSPSetTolerances(ksp, 1e-12, opt->krylov_jump_fraction * opt->tol, PETSC_DEFAULT, 100));
  if (opt->rebuild_every > 0) {
    PetscCall(OptExplicitJacobianCreate(C, opt->J_newton, PETSC_FALSE, ksp));
    PetscCall(ExplicitJacobianSetSecants(opt->explicit_jacobian, opt->secants));
    PetscCall(VecDuplicate(C->x, &opt->x_previous));
    PetscCall(VecDuplicate(C->x, &opt->F_previous));
  } else {
    PC pc;
    PetscCall(KSPGetPC(ksp, &pc));
    PetscCall(PCSetType(pc, PCNONE));
  }
  PetscCall(OptRecycleSetUp(C, ksp));
  if (opt->inner_type != OPT_INNER_CHORD && !opt->recycle_steps) {
    /* tube3d, iterative files, 10 steps: 0.67x, 0.63x, 0.61x the GMRES iterations on levels
       2-4 at the same Gauss-Newton iterations (docs/coupling-and-solvers.md). Not with
       recycled products: their preconditioner is built in the KSP's one pre-solve hook,
       which PETSc's forcing would need as well */
    PetscCall(PetscOptionsHasName(NULL, NULL, "-coupling_snes_ksp_ew_rtol0", &given));
    opt->forcing_first_adaptive = (PetscBool)!given;
    PetscCall(OptionsSetDefault("-coupling_snes_ksp_ew", "true"));
    PetscCall(OptionsSetDefault("-coupling_snes_ksp_ew_version", "2"));
    PetscCall(OptionsSetDefault("-coupling_snes_ksp_ew_gamma", "0.1"));
    PetscCall(OptionsSetDefault("-coupling_snes_ksp_ew_alpha", "2"));
    PetscCall(OptionsSetDefault("-coupling_snes_ksp_ew_rtol0", "0.003"));
  }
  PetscCall(SNESSetFromOptions(opt->snes));
  PetscCall(ForcingCheck(opt->snes));
  PetscFunctionReturn(0);
}

PetscErrorCode OptNewtonKrylovSolve(Coupling C, const char **failed_reason)
{
  Opt                *opt = (Opt *)C->data;
  SNESConvergedReason reason;

  PetscFunctionBeginUser;
  opt->linearization_current = PETSC_FALSE;
  PetscCall(PetscLogStagePush(FSIOPT_STAGE_OPTIMIZER));
  PetscCall(SNESSolve(opt->snes, NULL, C->x));
  PetscCall(PetscLogStagePop());
  PetscCall(SNESGetConvergedReason(opt->snes, &reason));
  *failed_reason = reason < 0 ? SNESConvergedReasons[reason] : NULL;
  PetscFunctionReturn(0);
}

PetscErrorCode OptNewtonKrylovDestroy(Coupling C)
{
  Opt *opt = (Opt *)C->data;

  PetscFunctionBeginUser;
  PetscCall(SNESDestroy(&opt->snes));
  PetscCall(MatDestroy(&opt->J_newton));
  PetscCall(VecDestroy(&opt->x_linearization));
  PetscCall(VecDestroy(&opt->x_previous));
  PetscCall(VecDestroy(&opt->F_previous));
  PetscCall(OptRecycleDestroy(opt));
  PetscFunctionReturn(0);
}
