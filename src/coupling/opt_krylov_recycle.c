/* -coupling_inner_recycle K: a preconditioner for the Newton-Krylov loop's GMRES built from
   the products J h_i it computed in this step and the last K steps. On their span it is
   J^-1: P r = W c for r = V c (V the products, W their h_i), with c = argmin ||V c - r||
   through the filtered QR the interface quasi-Newton methods use. Off the span it is the
   identity scaled by ||W|| / ||V||, J^-1's typical size, so the preconditioned operator's two
   parts are alike (unscaled, tube3d's first steps needed 60 GMRES iterations instead of 10).
   It costs no product: each GMRES iteration computes one anyway, and its pair (h, J h) is
   kept whatever P made h. Right preconditioning keeps GMRES's residual the true one.
   Where P takes r further than that size (||P r|| > scale ||r||: the directions J barely
   moves), the product's loads are that much larger than its result, so the relaxed
   products' tolerance (-coupling_inexact_products) is tightened by the same factor. Without
   that, tube3d level 3 broke down from its third step (13 Gauss-Newton iterations instead of
   3); with exact products it did not (docs/coupling-and-solvers.md). The columns are fixed for a solve
   (GMRES needs a fixed preconditioner) and forgotten after a checkpoint file, in the run
   that writes it and in the run that restarts from it, and after a change of dt. */
#include "opt_impl.h"

/* PETSc fixes the signatures of KSP callbacks; each uses a few of their arguments. */
#pragma GCC diagnostic ignored "-Wunused-parameter"

/* the columns of this solve: factored, their h copied (new products shift the store) */
static PetscErrorCode PreSolve(KSP ksp, Vec b, Vec x, void *ctx)
{
  Coupling    C   = (Coupling)ctx;
  Opt        *opt = (Opt *)C->data;
  IQNColumns *qn  = &opt->recycled;
  PetscReal   vv = 0, ww = 0, t;

  PetscFunctionBeginUser;
  PetscCall(IQNColumnsDropBefore(qn, opt->step, opt->recycle_steps));
  PetscCall(IQNColumnsFactor(qn));
  for (PetscInt i = 0; i < qn->kept; ++i) {
    PetscCall(VecCopy(qn->W[qn->keep[i]], opt->recycle_W[i]));
    PetscCall(VecNorm(opt->recycle_W[i], NORM_2, &t));
    ww += t * t;
    PetscCall(VecNorm(qn->V[qn->keep[i]], NORM_2, &t));
    vv += t * t;
  }
  opt->recycle_scale = vv > 0 ? PetscSqrtReal(ww / vv) : 1.0;
  PetscFunctionReturn(0);
}

/* y = W c + scale (r - V c), c = argmin ||V c - r||, V c = Q Q^T r */
static PetscErrorCode ApplyPC(PC pc, Vec r, Vec y)
{
  Coupling     C;
  Opt         *opt;
  IQNColumns  *qn;
  PetscInt     kept, n;
  PetscScalar *qtr, *c;

  PetscFunctionBeginUser;
  PetscCall(PCShellGetContext(pc, &C));
  opt  = (Opt *)C->data;
  qn   = &opt->recycled;
  kept = qn->kept;
  n    = qn->max_cols;
  PetscCall(VecCopy(r, y));
  opt->recycle_stretch = 1.0;
  if (!kept) PetscFunctionReturn(0);
  PetscCall(PetscCalloc2(kept, &qtr, kept, &c));
  PetscCall(VecMDot(r, kept, qn->Q, qtr));
  for (PetscInt i = kept - 1; i >= 0; --i) {
    PetscScalar s = qtr[i];
    for (PetscInt k = i + 1; k < kept; ++k) s -= qn->R[i * n + k] * c[k];
    c[i] = s / qn->R[i * n + i];
  }
  for (PetscInt i = 0; i < kept; ++i) qtr[i] = -qtr[i];
  PetscCall(VecMAXPY(y, kept, qtr, qn->Q));
  PetscCall(VecScale(y, opt->recycle_scale));
  PetscCall(VecMAXPY(y, kept, c, opt->recycle_W));
  PetscCall(PetscFree2(qtr, c));
  {
    /* the next product's tolerance factor (see above) */
    PetscReal rn, yn;
    PetscCall(VecNorm(r, NORM_2, &rn));
    PetscCall(VecNorm(y, NORM_2, &yn));
    opt->recycle_stretch = yn > opt->recycle_scale * rn ? opt->recycle_scale * rn / yn : 1.0;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode OptRecycleSetUp(Coupling C, KSP ksp)
{
  Opt *opt = (Opt *)C->data;
  PC   pc;

  PetscFunctionBeginUser;
  if (!opt->recycle_steps) PetscFunctionReturn(0);
  PetscCheck(!opt->explicit_jacobian, PETSC_COMM_WORLD, PETSC_ERR_ARG_INCOMP,
             "option -coupling_inner_recycle: preconditions the Krylov method by earlier products; expected "
             "-coupling_explicit_jacobian 0 (it preconditions by the explicit J0), got %" PetscInt_FMT,
             opt->rebuild_every);
  PetscCall(IQNColumnsAllocate(&opt->recycled, C->x, opt->recycle_columns, opt->recycle_filter));
  PetscCall(VecDuplicateVecs(C->x, opt->recycle_columns, &opt->recycle_W));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PCSetType(pc, PCSHELL));
  PetscCall(PCShellSetContext(pc, C));
  PetscCall(PCShellSetApply(pc, ApplyPC));
  PetscCall(PCShellSetName(pc, "recycled products"));
  PetscCall(KSPSetPreSolve(ksp, PreSolve, C));
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
  PetscCall(VecDestroyVecs(opt->recycle_columns, &opt->recycle_W));
  PetscFunctionReturn(0);
}
