/* -coupling_inner_recycle K: the Newton-Krylov loop starts each Krylov solve J h = F from the
   products J h_i of this step's and the last K steps' solves. Their images span much of the
   jumps the coupling meets from step to step, so the least-squares fit h0 = W c,
   c = argmin ||V c - F|| (V the products, W their h; the filtered QR the interface
   quasi-Newton methods use) leaves the Krylov method only the part of F they miss. J
   changes from step to step, so V c is only J_old h0: one product measures the true
   residual F - J h0, and the start is dropped if that is no smaller than F. Taking V c
   instead saves that product but lets the stale part into the Gauss-Newton step: tube3d
   level 1, ten steps, 36 Gauss-Newton iterations instead of 20 (docs/solvers.md). */
#include "opt_impl.h"

/* PETSc fixes the signatures of KSP callbacks; each uses a few of their arguments. */
#pragma GCC diagnostic ignored "-Wunused-parameter"

static PetscErrorCode PreSolve(KSP ksp, Vec b, Vec x, void *ctx)
{
  Coupling  C   = (Coupling)ctx;
  Opt      *opt = (Opt *)C->data;
  PetscReal bnorm, rnorm;

  PetscFunctionBeginUser;
  opt->recycle_active = PETSC_FALSE;
  PetscCall(IQNColumnsDropBefore(&opt->recycled, opt->step, opt->recycle_steps));
  if (!opt->recycled.ncols) PetscFunctionReturn(0);
  PetscCall(IQNColumnsFactor(&opt->recycled));
  if (!opt->recycled.kept) PetscFunctionReturn(0);
  PetscCall(VecCopy(b, opt->recycle_rhs));
  PetscCall(VecNorm(b, NORM_2, &bnorm));
  PetscCall(VecScale(b, -1.0));
  /* c = argmin ||V c - F||, h0 = W c */
  PetscCall(IQNColumnsLeastSquares(&opt->recycled, b, opt->recycle_start, NULL));
  /* b = F - J h0; the product is the Krylov method's first, so its tolerance is too */
  opt->product_rnorm = bnorm;
  PetscCall(MatMult(opt->J_newton, opt->recycle_start, b));
  opt->product_rnorm = 0;
  PetscCall(VecAYPX(b, -1.0, opt->recycle_rhs));
  PetscCall(VecNorm(b, NORM_2, &rnorm));
  if (rnorm >= bnorm) {
    PetscCall(VecCopy(opt->recycle_rhs, b));
    PetscCall(PetscInfo(ksp, "step %" PetscInt_FMT ": recycled start dropped, residual %g against %g from zero\n",
                        opt->step, (double)rnorm, (double)bnorm));
    PetscFunctionReturn(0);
  }
  opt->recycle_active = PETSC_TRUE;
  PetscFunctionReturn(0);
}

static PetscErrorCode PostSolve(KSP ksp, Vec b, Vec x, void *ctx)
{
  Coupling C   = (Coupling)ctx;
  Opt     *opt = (Opt *)C->data;

  PetscFunctionBeginUser;
  if (!opt->recycle_active) PetscFunctionReturn(0);
  PetscCall(VecAXPY(x, 1.0, opt->recycle_start));
  PetscCall(VecCopy(opt->recycle_rhs, b));
  opt->recycle_active = PETSC_FALSE;
  PetscFunctionReturn(0);
}

PetscErrorCode OptRecycleSetUp(Coupling C, KSP ksp)
{
  Opt *opt = (Opt *)C->data;

  PetscFunctionBeginUser;
  if (!opt->recycle_steps) PetscFunctionReturn(0);
  PetscCall(IQNColumnsAllocate(&opt->recycled, C->x, opt->recycle_columns, 1e-8));
  PetscCall(VecDuplicate(C->x, &opt->recycle_start));
  PetscCall(VecDuplicate(C->x, &opt->recycle_rhs));
  PetscCall(KSPSetPreSolve(ksp, PreSolve, C));
  PetscCall(KSPSetPostSolve(ksp, PostSolve, C));
  PetscFunctionReturn(0);
}

PetscErrorCode OptRecycleRecord(Opt *opt, Vec h, Vec Jh)
{
  PetscFunctionBeginUser;
  if (opt->recycle_steps) PetscCall(IQNColumnsAdd(&opt->recycled, opt->step, Jh, h));
  PetscFunctionReturn(0);
}

PetscErrorCode OptRecycleForget(Opt *opt)
{
  PetscFunctionBeginUser;
  opt->recycled.ncols = 0;
  PetscFunctionReturn(0);
}

PetscErrorCode OptRecycleDestroy(Opt *opt)
{
  PetscFunctionBeginUser;
  if (!opt->recycle_steps) PetscFunctionReturn(0);
  PetscCall(IQNColumnsDestroy(&opt->recycled));
  PetscCall(VecDestroy(&opt->recycle_start));
  PetscCall(VecDestroy(&opt->recycle_rhs));
  PetscFunctionReturn(0);
}
