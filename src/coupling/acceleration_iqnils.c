/* -coupling iqnils: interface quasi-Newton with an inverse-Jacobian least-squares model
   (Degroote et al. 2009; the algorithm of preCICE and CoCoNuT). Its columns are residual
   differences V and sweep differences W, newest first; those of the last q steps are
   reused (-coupling_iqn_reuse), nearly dependent ones are filtered out by a QR
   (-coupling_iqn_filter). The update is u = S(u_k) + W c, c = argmin ||V c + r_k||; a step
   without any column yet takes one relaxed step (-coupling_omega). */
#include "acceleration.h"
#include "options.h"

typedef struct {
  PetscReal filter;
  PetscInt  reuse, ncols, max_cols, *col_step; /* col_step: the step each column came from */
  Vec      *V, *W, *Q;                         /* Q: V's orthonormal basis, work of the QR */
  Vec       r_before, sweep_before, update;    /* r_{k-1}, S(u_{k-1}), W c */
} IQNILS;

static PetscErrorCode IQNILSSetUp(Acceleration acc, Vec model)
{
  IQNILS *qn = (IQNILS *)acc->data;

  PetscFunctionBeginUser;
  qn->reuse    = 8;
  qn->max_cols = 100;
  qn->filter   = 1e-8;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Interface quasi-Newton (IQN-ILS)", "coupling");
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-coupling_iqn_reuse",
                              "iqnils: reuse the columns of this many previous time steps", 0, 1000, &qn->reuse));
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-coupling_iqn_columns", "iqnils: at most this many columns", 1,
                              10000, &qn->max_cols));
  PetscCall(OptionsPositiveReal(PetscOptionsObject, "-coupling_iqn_filter",
                                "iqnils: drop a column whose part orthogonal to the newer ones is below this fraction "
                                "of its norm",
                                &qn->filter));
  PetscOptionsEnd();
  PetscCall(VecDuplicate(model, &qn->r_before));
  PetscCall(VecDuplicate(model, &qn->sweep_before));
  PetscCall(VecDuplicate(model, &qn->update));
  PetscCall(VecDuplicateVecs(model, qn->max_cols, &qn->Q));
  PetscCall(VecDuplicateVecs(model, qn->max_cols, &qn->V));
  PetscCall(VecDuplicateVecs(model, qn->max_cols, &qn->W));
  PetscCall(PetscMalloc1(qn->max_cols, &qn->col_step));
  PetscFunctionReturn(0);
}

/* Drops the columns older than the reuse window (and the oldest past max_cols). */
static PetscErrorCode IQNILSBeginStep(Acceleration acc, PetscInt step)
{
  IQNILS *qn = (IQNILS *)acc->data;

  PetscFunctionBeginUser;
  while (qn->ncols > 0 && (qn->ncols > qn->max_cols || qn->col_step[qn->ncols - 1] <= step - 1 - qn->reuse))
    qn->ncols--;
  PetscFunctionReturn(0);
}

static PetscErrorCode AddColumn(IQNILS *qn, PetscInt step, Vec dr, Vec dxt)
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

/* c = argmin ||V c + r|| by modified Gram-Schmidt QR; a column whose new part is below
   filter * its norm is dropped (it would make R nearly singular). Returns dx = W c. */
static PetscErrorCode QuasiNewtonUpdate(IQNILS *qn, Vec r, Vec dx)
{
  PetscInt     n = qn->ncols, kept = 0;
  Vec         *Q = qn->Q;
  PetscScalar *R, *rhs, *c;
  PetscInt    *keep;

  PetscFunctionBeginUser;
  PetscCall(VecZeroEntries(dx));
  if (!n) PetscFunctionReturn(0);
  PetscCall(PetscCalloc4(n * n, &R, n, &rhs, n, &c, n, &keep));
  for (PetscInt j = 0; j < n; ++j) {
    PetscReal norm0, norm;
    PetscCall(VecCopy(qn->V[j], Q[kept]));
    PetscCall(VecNorm(Q[kept], NORM_2, &norm0));
    for (PetscInt i = 0; i < kept; ++i) {
      PetscScalar d;
      PetscCall(VecDot(Q[kept], Q[i], &d));
      R[i * n + kept] = d;
      PetscCall(VecAXPY(Q[kept], -d, Q[i]));
    }
    PetscCall(VecNorm(Q[kept], NORM_2, &norm));
    if (norm0 == 0 || norm < qn->filter * norm0) continue;
    R[kept * n + kept] = norm;
    PetscCall(VecScale(Q[kept], 1.0 / norm));
    keep[kept++] = j;
  }
  for (PetscInt i = 0; i < kept; ++i) {
    PetscCall(VecDot(r, Q[i], &rhs[i]));
    rhs[i] = -rhs[i];
  }
  for (PetscInt i = kept - 1; i >= 0; --i) {
    PetscScalar s = rhs[i];
    for (PetscInt k = i + 1; k < kept; ++k) s -= R[i * n + k] * c[k];
    c[i] = s / R[i * n + i];
  }
  for (PetscInt i = 0; i < kept; ++i) PetscCall(VecAXPY(dx, c[i], qn->W[keep[i]]));
  PetscCall(PetscFree4(R, rhs, c, keep));
  PetscFunctionReturn(0);
}

static PetscErrorCode IQNILSUpdate(Acceleration acc, PetscInt step, PetscInt k, Vec u, Vec sweep, Vec r)
{
  IQNILS *qn = (IQNILS *)acc->data;

  PetscFunctionBeginUser;
  if (k > 0) {
    PetscCall(VecAYPX(qn->r_before, -1.0, r));         /* r_k - r_{k-1} */
    PetscCall(VecAYPX(qn->sweep_before, -1.0, sweep)); /* S_k - S_{k-1} */
    PetscCall(AddColumn(qn, step, qn->r_before, qn->sweep_before));
  }
  PetscCall(VecCopy(r, qn->r_before));
  PetscCall(VecCopy(sweep, qn->sweep_before));
  if (qn->ncols) {
    PetscCall(QuasiNewtonUpdate(qn, r, qn->update));
    PetscCall(VecWAXPY(u, 1.0, sweep, qn->update));
  } else PetscCall(VecAXPY(u, acc->omega, r)); /* no model yet: one relaxed step */
  PetscFunctionReturn(0);
}

/* The columns were built with another dt (or before a checkpoint). */
static PetscErrorCode IQNILSReset(Acceleration acc)
{
  PetscFunctionBeginUser;
  ((IQNILS *)acc->data)->ncols = 0;
  PetscFunctionReturn(0);
}

static PetscErrorCode IQNILSDestroy(Acceleration acc)
{
  IQNILS *qn = (IQNILS *)acc->data;

  PetscFunctionBeginUser;
  PetscCall(VecDestroy(&qn->r_before));
  PetscCall(VecDestroy(&qn->sweep_before));
  PetscCall(VecDestroy(&qn->update));
  if (qn->Q) PetscCall(VecDestroyVecs(qn->max_cols, &qn->Q));
  if (qn->V) PetscCall(VecDestroyVecs(qn->max_cols, &qn->V));
  if (qn->W) PetscCall(VecDestroyVecs(qn->max_cols, &qn->W));
  PetscCall(PetscFree(qn->col_step));
  PetscCall(PetscFree(acc->data));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingCreate_IQNILS(Coupling C)
{
  Acceleration acc;
  IQNILS      *qn;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&acc));
  PetscCall(PetscNew(&qn));
  acc->data           = qn;
  acc->omega          = 0.05;
  acc->model_its      = 4;
  acc->ops.setup      = IQNILSSetUp;
  acc->ops.begin_step = IQNILSBeginStep;
  acc->ops.update     = IQNILSUpdate;
  acc->ops.reset      = IQNILSReset;
  acc->ops.destroy    = IQNILSDestroy;
  PetscCall(CouplingCreate_Partitioned(C, acc));
  PetscFunctionReturn(0);
}
