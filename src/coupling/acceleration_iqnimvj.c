/* -coupling iqnimvj: interface quasi-Newton with a multi-vector inverse Jacobian (Lindner,
   Mehl and Uekermann 2015; preCICE's IQN-IMVJ). Within a step the model is the previous
   steps' inverse Jacobian J_prev corrected by this step's columns (acceleration_iqn.c):
     J = J_prev + (W - J_prev V) (V^T V)^{-1} V^T,
     u = S(u_k) - J r_k = S(u_k) + W c - J_prev (r_k + V c),  c = argmin ||V c + r_k||,
   and at the next step's start J_prev becomes that J. Where IQN-ILS keeps the last steps'
   columns, this keeps their effect in a dense matrix of the interface's size squared.
   -coupling_imvj_restart K starts J_prev from zero every K steps (preCICE's RS-ZERO;
   0: never). The first step, without any model, takes one relaxed step (-coupling_omega). */
#include "acceleration_iqn.h"
#include "options.h"

typedef struct {
  IQNColumns columns;
  Mat        J_prev;    /* dense, the model's row layout */
  PetscBool  has_model; /* J_prev is not zero */
  PetscInt   restart;
  Vec        update, remainder, work;
} IQNIMVJ;

static PetscErrorCode IQNIMVJSetUp(Acceleration acc, Vec model)
{
  IQNIMVJ *qn = (IQNIMVJ *)acc->data;
  PetscInt n, N;

  PetscFunctionBeginUser;
  qn->restart = 0;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Interface quasi-Newton (IQN-IMVJ)", "coupling");
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-coupling_imvj_restart",
                              "iqnimvj: start the inverse Jacobian from zero every this many steps (0: never)", 0,
                              1000000, &qn->restart));
  PetscOptionsEnd();
  PetscCall(IQNColumnsSetUp(&qn->columns, model, "iqnimvj"));
  PetscCall(VecDuplicate(model, &qn->update));
  PetscCall(VecDuplicate(model, &qn->remainder));
  PetscCall(VecDuplicate(model, &qn->work));
  PetscCall(VecGetLocalSize(model, &n));
  PetscCall(VecGetSize(model, &N));
  PetscCall(MatCreateDense(PetscObjectComm((PetscObject)model), n, n, N, N, NULL, &qn->J_prev));
  PetscCall(MatZeroEntries(qn->J_prev));
  PetscFunctionReturn(0);
}

/* J_prev += (W - J_prev V) R^{-1} Q^T on the kept columns of the step that ended (V = Q R):
   (V^T V)^{-1} V^T = R^{-1} Q^T */
static PetscErrorCode Fold(IQNIMVJ *qn)
{
  IQNColumns *c = &qn->columns;
  Mat         A, Qm, update;
  PetscInt    n, N;

  PetscFunctionBeginUser;
  PetscCall(IQNColumnsFactor(c));
  if (!c->kept) PetscFunctionReturn(0);
  PetscCall(VecGetLocalSize(c->V[0], &n));
  PetscCall(VecGetSize(c->V[0], &N));
  PetscCall(MatCreateDense(PetscObjectComm((PetscObject)qn->J_prev), n, PETSC_DECIDE, N, c->kept, NULL, &A));
  PetscCall(MatCreateDense(PetscObjectComm((PetscObject)qn->J_prev), n, PETSC_DECIDE, N, c->kept, NULL, &Qm));
  for (PetscInt j = 0; j < c->kept; ++j) {
    Vec a, q;
    PetscCall(MatDenseGetColumnVecWrite(A, j, &a));
    /* a_j = (d_j - sum_{i<j} a_i R_ij) / R_jj, d_j = W_j - J_prev V_j: A R = D column by column */
    PetscCall(VecCopy(c->W[c->keep[j]], a));
    if (qn->has_model) {
      PetscCall(MatMult(qn->J_prev, c->V[c->keep[j]], qn->work));
      PetscCall(VecAXPY(a, -1.0, qn->work));
    }
    PetscCall(MatDenseRestoreColumnVecWrite(A, j, &a));
    for (PetscInt i = 0; i < j; ++i) {
      Vec ai;
      PetscCall(MatDenseGetColumnVecRead(A, i, &ai));
      PetscCall(VecCopy(ai, qn->work));
      PetscCall(MatDenseRestoreColumnVecRead(A, i, &ai));
      PetscCall(MatDenseGetColumnVecWrite(A, j, &a));
      PetscCall(VecAXPY(a, -c->R[i * c->max_cols + j], qn->work));
      PetscCall(MatDenseRestoreColumnVecWrite(A, j, &a));
    }
    PetscCall(MatDenseGetColumnVecWrite(A, j, &a));
    PetscCall(VecScale(a, 1.0 / c->R[j * c->max_cols + j]));
    PetscCall(MatDenseRestoreColumnVecWrite(A, j, &a));
    PetscCall(MatDenseGetColumnVecWrite(Qm, j, &q));
    PetscCall(VecCopy(c->Q[j], q));
    PetscCall(MatDenseRestoreColumnVecWrite(Qm, j, &q));
  }
  PetscCall(MatAssemblyBegin(A, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(A, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyBegin(Qm, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(Qm, MAT_FINAL_ASSEMBLY));
  PetscCall(MatMatTransposeMult(A, Qm, MAT_INITIAL_MATRIX, PETSC_DEFAULT, &update));
  PetscCall(MatAXPY(qn->J_prev, 1.0, update, SAME_NONZERO_PATTERN));
  qn->has_model = PETSC_TRUE;
  PetscCall(MatDestroy(&update));
  PetscCall(MatDestroy(&A));
  PetscCall(MatDestroy(&Qm));
  PetscFunctionReturn(0);
}

/* the step that ended goes into J_prev; its columns are not kept */
static PetscErrorCode IQNIMVJBeginStep(Acceleration acc, PetscInt step)
{
  IQNIMVJ *qn = (IQNIMVJ *)acc->data;

  PetscFunctionBeginUser;
  if (qn->columns.ncols) PetscCall(Fold(qn));
  qn->columns.ncols = 0;
  if (qn->restart > 0 && (step - 1) % qn->restart == 0 && qn->has_model) {
    PetscCall(MatZeroEntries(qn->J_prev));
    qn->has_model = PETSC_FALSE;
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode IQNIMVJUpdate(Acceleration acc, PetscInt step, PetscInt k, Vec u, Vec sweep, Vec r)
{
  IQNIMVJ *qn = (IQNIMVJ *)acc->data;

  PetscFunctionBeginUser;
  PetscCall(IQNColumnsRecord(&qn->columns, step, k, sweep, r));
  if (!qn->columns.ncols && !qn->has_model) { /* no model yet: one relaxed step */
    PetscCall(VecAXPY(u, acc->omega, r));
    PetscFunctionReturn(0);
  }
  PetscCall(IQNColumnsFactor(&qn->columns));
  PetscCall(IQNColumnsLeastSquares(&qn->columns, r, qn->update, qn->remainder));
  if (qn->has_model) { /* what the columns do not span, J_prev takes */
    PetscCall(MatMult(qn->J_prev, qn->remainder, qn->work));
    PetscCall(VecAXPY(qn->update, -1.0, qn->work));
  }
  PetscCall(VecWAXPY(u, 1.0, sweep, qn->update));
  PetscFunctionReturn(0);
}

/* The model was built with another dt (or before a checkpoint). */
static PetscErrorCode IQNIMVJReset(Acceleration acc)
{
  IQNIMVJ *qn = (IQNIMVJ *)acc->data;

  PetscFunctionBeginUser;
  qn->columns.ncols = 0;
  PetscCall(MatZeroEntries(qn->J_prev));
  qn->has_model = PETSC_FALSE;
  PetscFunctionReturn(0);
}

static PetscErrorCode IQNIMVJDestroy(Acceleration acc)
{
  IQNIMVJ *qn = (IQNIMVJ *)acc->data;

  PetscFunctionBeginUser;
  PetscCall(IQNColumnsDestroy(&qn->columns));
  PetscCall(MatDestroy(&qn->J_prev));
  PetscCall(VecDestroy(&qn->update));
  PetscCall(VecDestroy(&qn->remainder));
  PetscCall(VecDestroy(&qn->work));
  PetscCall(PetscFree(acc->data));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingCreate_IQNIMVJ(Coupling C)
{
  Acceleration acc;
  IQNIMVJ     *qn;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&acc));
  PetscCall(PetscNew(&qn));
  acc->data           = qn;
  acc->omega          = 0.05;
  acc->model_its      = 4;
  acc->ops.setup      = IQNIMVJSetUp;
  acc->ops.begin_step = IQNIMVJBeginStep;
  acc->ops.update     = IQNIMVJUpdate;
  acc->ops.reset      = IQNIMVJReset;
  acc->ops.destroy    = IQNIMVJDestroy;
  PetscCall(CouplingCreate_Partitioned(C, acc));
  PetscFunctionReturn(0);
}
