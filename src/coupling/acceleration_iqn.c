/* The columns and the filtered QR the interface quasi-Newton methods share
   (acceleration_iqn.h): IQN-ILS (acceleration_iqnils.c) and IQN-IMVJ
   (acceleration_iqnimvj.c). */
#include "acceleration_iqn.h"
#include "options.h"

PetscErrorCode IQNColumnsSetUp(IQNColumns *qn, Vec model, const char title[])
{
  char columns[128], filter[160];

  PetscFunctionBeginUser;
  qn->max_cols = 100;
  qn->filter   = 1e-8;
  PetscCall(PetscSNPrintf(columns, sizeof(columns), "%s: at most this many columns", title));
  PetscCall(
    PetscSNPrintf(filter, sizeof(filter),
                  "%s: drop a column whose part orthogonal to the newer ones is below this fraction of its norm",
                  title));
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Interface quasi-Newton columns", "coupling");
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-coupling_iqn_columns", columns, 1, 10000, &qn->max_cols));
  PetscCall(OptionsPositiveReal(PetscOptionsObject, "-coupling_iqn_filter", filter, &qn->filter));
  PetscOptionsEnd();
  PetscCall(IQNColumnsAllocate(qn, model, qn->max_cols, qn->filter));
  PetscFunctionReturn(0);
}

PetscErrorCode IQNColumnsAllocate(IQNColumns *qn, Vec model, PetscInt max_cols, PetscReal filter)
{
  PetscFunctionBeginUser;
  qn->max_cols = max_cols;
  qn->filter   = filter;
  PetscCall(VecDuplicate(model, &qn->r_before));
  PetscCall(VecDuplicate(model, &qn->sweep_before));
  PetscCall(VecDuplicateVecs(model, qn->max_cols, &qn->Q));
  PetscCall(VecDuplicateVecs(model, qn->max_cols, &qn->V));
  PetscCall(VecDuplicateVecs(model, qn->max_cols, &qn->W));
  PetscCall(PetscMalloc1(qn->max_cols, &qn->col_step));
  PetscCall(PetscMalloc2(qn->max_cols, &qn->keep, qn->max_cols * qn->max_cols, &qn->R));
  PetscFunctionReturn(0);
}

PetscErrorCode IQNColumnsDropBefore(IQNColumns *qn, PetscInt step, PetscInt reuse)
{
  PetscFunctionBeginUser;
  while (qn->ncols > 0 && (qn->ncols > qn->max_cols || qn->col_step[qn->ncols - 1] <= step - 1 - reuse)) qn->ncols--;
  PetscFunctionReturn(0);
}

PetscErrorCode IQNColumnsAdd(IQNColumns *qn, PetscInt step, Vec dr, Vec dxt)
{
  Vec v, w;

  PetscFunctionBeginUser;
  if (qn->ncols == qn->max_cols) qn->ncols--; /* the oldest goes */
  v = qn->V[qn->ncols];
  w = qn->W[qn->ncols];
  for (PetscInt j = qn->ncols; j > 0; --j) {
    qn->V[j]        = qn->V[j - 1];
    qn->W[j]        = qn->W[j - 1];
    qn->col_step[j] = qn->col_step[j - 1];
  }
  qn->V[0] = v;
  qn->W[0] = w;
  PetscCall(VecCopy(dr, v));
  PetscCall(VecCopy(dxt, w));
  qn->col_step[0] = step;
  qn->ncols++;
  PetscFunctionReturn(0);
}

PetscErrorCode IQNColumnsRecord(IQNColumns *qn, PetscInt step, PetscInt k, Vec sweep, Vec r)
{
  PetscFunctionBeginUser;
  if (k > 0) {
    PetscCall(VecAYPX(qn->r_before, -1.0, r));         /* r_k - r_{k-1} */
    PetscCall(VecAYPX(qn->sweep_before, -1.0, sweep)); /* S_k - S_{k-1} */
    PetscCall(IQNColumnsAdd(qn, step, qn->r_before, qn->sweep_before));
  }
  PetscCall(VecCopy(r, qn->r_before));
  PetscCall(VecCopy(sweep, qn->sweep_before));
  PetscFunctionReturn(0);
}

PetscErrorCode IQNColumnsFactor(IQNColumns *qn)
{
  PetscFunctionBeginUser;
  PetscCall(IQNColumnsFactorRange(qn, 0, qn->ncols));
  PetscFunctionReturn(0);
}

PetscErrorCode IQNColumnsFactorRange(IQNColumns *qn, PetscInt first, PetscInt count)
{
  const PetscInt n = qn->max_cols;
  Vec           *Q = qn->Q;

  PetscFunctionBeginUser;
  qn->kept = 0;
  PetscCall(PetscArrayzero(qn->R, n * n));
  for (PetscInt j = first; j < first + count && j < qn->ncols; ++j) {
    const PetscInt kept = qn->kept;
    PetscReal      norm0, norm;
    PetscCall(VecCopy(qn->V[j], Q[kept]));
    PetscCall(VecNorm(Q[kept], NORM_2, &norm0));
    for (PetscInt i = 0; i < kept; ++i) {
      PetscScalar d;
      PetscCall(VecDot(Q[kept], Q[i], &d));
      qn->R[i * n + kept] = d;
      PetscCall(VecAXPY(Q[kept], -d, Q[i]));
    }
    PetscCall(VecNorm(Q[kept], NORM_2, &norm));
    if (norm0 == 0 || norm < qn->filter * norm0) {
      for (PetscInt i = 0; i < kept; ++i) qn->R[i * n + kept] = 0;
      continue;
    }
    qn->R[kept * n + kept] = norm;
    PetscCall(VecScale(Q[kept], 1.0 / norm));
    qn->keep[qn->kept++] = j;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode IQNColumnsLeastSquares(IQNColumns *qn, Vec r, Vec dx, Vec remainder)
{
  const PetscInt n = qn->max_cols, kept = qn->kept;
  PetscScalar   *rhs, *c;

  PetscFunctionBeginUser;
  PetscCall(VecZeroEntries(dx));
  if (remainder) PetscCall(VecCopy(r, remainder));
  if (!kept) PetscFunctionReturn(0);
  PetscCall(PetscCalloc2(kept, &rhs, kept, &c));
  for (PetscInt i = 0; i < kept; ++i) {
    PetscCall(VecDot(r, qn->Q[i], &rhs[i]));
    rhs[i] = -rhs[i];
    if (remainder) PetscCall(VecAXPY(remainder, rhs[i], qn->Q[i])); /* r - Q Q^T r = r + V c */
  }
  for (PetscInt i = kept - 1; i >= 0; --i) {
    PetscScalar s = rhs[i];
    for (PetscInt k = i + 1; k < kept; ++k) s -= qn->R[i * n + k] * c[k];
    c[i] = s / qn->R[i * n + i];
  }
  for (PetscInt i = 0; i < kept; ++i) PetscCall(VecAXPY(dx, c[i], qn->W[qn->keep[i]]));
  PetscCall(PetscFree2(rhs, c));
  PetscFunctionReturn(0);
}

PetscInt IQNColumnsOfStep(const IQNColumns *qn, PetscInt step)
{
  PetscInt n = 0;

  while (n < qn->ncols && qn->col_step[n] == step) n++;
  return n;
}

PetscErrorCode IQNColumnsDestroy(IQNColumns *qn)
{
  PetscFunctionBeginUser;
  PetscCall(VecDestroy(&qn->r_before));
  PetscCall(VecDestroy(&qn->sweep_before));
  if (qn->Q) PetscCall(VecDestroyVecs(qn->max_cols, &qn->Q));
  if (qn->V) PetscCall(VecDestroyVecs(qn->max_cols, &qn->V));
  if (qn->W) PetscCall(VecDestroyVecs(qn->max_cols, &qn->W));
  PetscCall(PetscFree(qn->col_step));
  PetscCall(PetscFree2(qn->keep, qn->R));
  PetscFunctionReturn(0);
}
