/* The fluid's nonlinear solves: Newton, or chord iterations on the Jacobian of another state
   (the coupling's last linearization point), with a fallback to Newton when chord fails.

   A chord iteration contracts the residual by about the distance from the Jacobian's state
   to the solution: the larger the coupling's step (and the finer the mesh, whose convective
   and moving-mesh terms weigh more against rho/dt M), the slower. With a Krylov solver a
   fresh Jacobian costs one assembly, its preconditioner staying the lagged one, and the
   iterations after it contract far faster; with LU it would cost a factorization. So with
   a Krylov solver, an iteration that reduced the residual by less than
   -fluid_chord_refresh_rate, and that leaves more than one iteration to go at that rate,
   makes the next one assemble the Jacobian at the iterate in hand. */
#include "fluid.h"
#include "fem.h"
#include "fluid_impl.h"

/* SNESConvergedDefault, and the refresh decision from the rate it just saw */
static PetscErrorCode ConvergedOrRefresh(SNES snes, PetscInt it, PetscReal xnorm, PetscReal snorm, PetscReal fnorm,
                                         SNESConvergedReason *reason, void *ctx)
{
  Fluid     f = (Fluid)ctx;
  PetscReal atol, rtol;
  PetscInt  lag;

  PetscFunctionBeginUser;
  PetscCall(SNESConvergedDefault(snes, it, xnorm, snorm, fnorm, reason, NULL));
  if (it == 0) f->refresh.first = fnorm;
  else if (f->refresh.active && *reason == SNES_CONVERGED_ITERATING && f->refresh.last > 0) {
    const PetscReal rate = fnorm / f->refresh.last;

    PetscCall(SNESGetTolerances(snes, &atol, &rtol, NULL, NULL, NULL));
    PetscCall(SNESGetLagJacobian(snes, &lag)); /* a user's lag K (-fluid_snes_lag_jacobian) is kept */
    if (lag == -1 && rate > f->refresh.rate && rate * fnorm > PetscMax(atol, rtol * f->refresh.first)) {
      /* the next iteration's Jacobian, then lagged again; its preconditioner stays the one
         in hand (a Jacobian made stale by a new dt was rebuilt whole at iteration 0): tube3d
         level 3, three steps, a rebuilt one made the Fluid stage 54.7 s against 45.8 s */
      PetscCall(SNESSetLagJacobian(snes, -2));
      PetscCall(SNESSetLagPreconditioner(snes, -1));
    }
  }
  f->refresh.last = fnorm;
  PetscFunctionReturn(0);
}

PetscErrorCode FluidNonlinearSolveSetUp(Fluid f)
{
  PetscFunctionBeginUser;
  PetscCall(SNESSetConvergenceTest(f->snes, ConvergedOrRefresh, f, NULL));
  PetscFunctionReturn(0);
}

/* A nonlinear solve from f->x. Chord iterations (factors from another state) that fail
   are retried once from the same start by Newton with fresh Jacobians and backtracking. */
PetscErrorCode FluidNonlinearSolve(Fluid f, SNES snes, Vec rhs, PetscBool chord, PetscInt step, const char what[])
{
  SNESConvergedReason reason;
  PetscInt            its, lag_preconditioner;
  KSP                 ksp;
  PetscReal           rtol, abstol, dtol;
  PetscInt            maxits;
  PetscBool           krylov;

  PetscFunctionBeginUser;
  /* A Newton step needs only to reduce the residual, which the next step measures again; the
     products' linearized solves are the derivative itself and keep the solver's tolerance */
  PetscCall(SNESGetKSP(snes, &ksp));
  PetscCall(KSPGetTolerances(ksp, &rtol, &abstol, &dtol, &maxits));
  PetscCall(FEMSolverIsKrylov(ksp, &krylov));
  if (f->newton_ksp_rtol > 0) PetscCall(KSPSetTolerances(ksp, f->newton_ksp_rtol, abstol, dtol, maxits));
  if (chord) PetscCall(VecCopy(f->x, f->x_start));
  f->refresh.active = (PetscBool)(snes == f->snes && chord && krylov && f->refresh.rate > 0);
  f->refresh.last   = 0;
  PetscCall(SNESGetLagPreconditioner(snes, &lag_preconditioner));
  PetscCall(SNESSolve(snes, rhs, f->x));
  PetscCall(SNESSetLagPreconditioner(snes, lag_preconditioner));
  f->refresh.active = PETSC_FALSE;
  if (snes == f->snes && f->lag_after_rebuild) {
    PetscCall(SNESSetLagJacobian(snes, f->lag_after_rebuild));
    f->lag_after_rebuild = 0;
  }
  PetscCall(SNESGetConvergedReason(snes, &reason));
  PetscCall(SNESGetIterationNumber(snes, &its));
  if (reason < 0 && chord) {
    SNESLineSearch ls;
    f->counts.linear_solves += PetscMax(its, 1);
    f->chord_restarts++;
    PetscCall(VecCopy(f->x_start, f->x));
    PetscCall(SNESGetLineSearch(snes, &ls));
    PetscCall(SNESLineSearchSetType(ls, SNESLINESEARCHBT));
    PetscCall(SNESSetLagJacobian(snes, 1));
    PetscCall(SNESSolve(snes, rhs, f->x));
    PetscCall(SNESGetConvergedReason(snes, &reason));
    PetscCall(SNESGetIterationNumber(snes, &its));
    PetscCall(SNESLineSearchSetType(ls, SNESLINESEARCHBASIC));
    PetscCall(SNESSetLagJacobian(snes, -1)); /* the fresh factors serve from now on */
  }
  if (f->newton_ksp_rtol > 0) PetscCall(KSPSetTolerances(ksp, rtol, abstol, dtol, maxits));
  f->counts.nonlinear_solves += 1;
  if (reason <= 0) PetscCall(StepFailureCheckMemory(snes, "fluid"));
  if (reason <= 0)
    PetscCall(StepFailureSet(&f->failure,
                             "fluid solve%s failed at step %" PetscInt_FMT " (t = %g) after %" PetscInt_FMT
                             " Newton iterations: SNES reason %s",
                             what, step, (double)f->time, its, SNESConvergedReasons[reason]));
  f->counts.linear_solves += PetscMax(its, 1);
  PetscFunctionReturn(0);
}
