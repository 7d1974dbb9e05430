/* -coupling iqnimvj: interface quasi-Newton with a multi-vector inverse Jacobian (Lindner,
   Mehl and Uekermann 2015; preCICE's IQN-IMVJ). Within a step the model is the previous
   steps' inverse Jacobian J_prev corrected by this step's columns (acceleration_iqn.c):
     J = J_prev + (W - J_prev V) (V^T V)^{-1} V^T,
     u = S(u_k) - J r_k = S(u_k) + W c - J_prev (r_k + V c),  c = argmin ||V c + r_k||,
   and at the next step's start J_prev becomes that J. Where IQN-ILS keeps the last steps'
   columns, this keeps their effect in a dense matrix of the interface's size squared.
   The model grows stale as the flow changes; -coupling_imvj_restart_mode says what happens
   to it every -coupling_imvj_restart K steps (0: never), the restart modes of Scheufele and
   Mehl (2017) as preCICE has them:
     zero   J_prev starts from zero again;
     ls     J_prev becomes the least-squares model W V^+ of the last -coupling_imvj_ls_reuse
            steps' columns (IQN-ILS's model, as a matrix);
     svd    J_prev keeps only its singular triplets above -coupling_imvj_svd_truncation
            times the largest;
     slide  at every step J_prev is rebuilt from zero by the chain of the last K steps'
            corrections (a sliding window; K >= 1).
   The first step, without any model, takes one relaxed step (-coupling_omega). */
#include "acceleration_iqn.h"
#include "options.h"
#include <petscblaslapack.h>

typedef enum {
  IMVJ_RESTART_ZERO,
  IMVJ_RESTART_LS,
  IMVJ_RESTART_SVD,
  IMVJ_RESTART_SLIDE
} IMVJRestartMode;
static const char *const IMVJRestartModes[] = {"zero", "ls", "svd", "slide"};

typedef struct {
  IQNColumns      columns;   /* this step's, and for ls and slide the last steps' */
  Mat             J_prev;    /* dense, the model's row layout */
  PetscBool       has_model; /* J_prev is not zero */
  IMVJRestartMode mode;
  PetscInt        restart;    /* every K steps (slide: the window) */
  PetscInt        keep_steps; /* the steps whose columns stay after a step: ls' reuse, slide's window */
  PetscReal       truncation; /* svd */
  Vec             update, remainder, work;
} IQNIMVJ;

static PetscErrorCode IQNIMVJSetUp(Acceleration acc, Vec model)
{
  IQNIMVJ *qn   = (IQNIMVJ *)acc->data;
  PetscInt mode = IMVJ_RESTART_ZERO, ls_reuse = 8, n, N;

  PetscFunctionBeginUser;
  qn->restart    = 0;
  qn->truncation = 1e-2;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Interface quasi-Newton (IQN-IMVJ)", "coupling");
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-coupling_imvj_restart",
                              "iqnimvj: restart the inverse Jacobian every this many steps (0: never; slide: the "
                              "window of steps it is rebuilt from at every step)",
                              0, 1000000, &qn->restart));
  PetscCall(PetscOptionsEList("-coupling_imvj_restart_mode",
                              "iqnimvj: what a restart does: zero (start from zero), ls (the least-squares model of "
                              "the last steps' columns), svd (truncate the small singular values), slide (rebuild "
                              "at every step from the last -coupling_imvj_restart steps)",
                              NULL, IMVJRestartModes, 4, IMVJRestartModes[mode], &mode, NULL));
  qn->mode = (IMVJRestartMode)mode;
  if (qn->mode == IMVJ_RESTART_LS)
    PetscCall(OptionsIntInRange(PetscOptionsObject, "-coupling_imvj_ls_reuse",
                                "iqnimvj, restart mode ls: the model is rebuilt from the columns of this many steps", 1,
                                1000, &ls_reuse));
  if (qn->mode == IMVJ_RESTART_SVD)
    PetscCall(OptionsNonNegativeReal(PetscOptionsObject, "-coupling_imvj_svd_truncation",
                                     "iqnimvj, restart mode svd: keep the singular values above this fraction of the "
                                     "largest",
                                     &qn->truncation));
  PetscOptionsEnd();
  PetscCheck(qn->mode != IMVJ_RESTART_SLIDE || qn->restart > 0, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
             "option -coupling_imvj_restart: restart mode slide needs a window of at least 1 step, got %" PetscInt_FMT,
             qn->restart);
  qn->keep_steps = qn->mode == IMVJ_RESTART_LS ? ls_reuse : qn->mode == IMVJ_RESTART_SLIDE ? qn->restart : 0;
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

/* J_prev += (W - J_prev V) R^{-1} Q^T on the columns first .. first + count - 1 (V = Q R
   after the filter): (V^T V)^{-1} V^T = R^{-1} Q^T */
static PetscErrorCode Fold(IQNIMVJ *qn, PetscInt first, PetscInt count)
{
  IQNColumns *c = &qn->columns;
  Mat         A, Qm, update;
  PetscInt    n, N;

  PetscFunctionBeginUser;
  PetscCall(IQNColumnsFactorRange(c, first, count));
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

static PetscErrorCode ZeroModel(IQNIMVJ *qn)
{
  PetscFunctionBeginUser;
  PetscCall(MatZeroEntries(qn->J_prev));
  qn->has_model = PETSC_FALSE;
  PetscFunctionReturn(0);
}

/* J_prev <- sum of s_i u_i v_i^T over s_i > truncation s_1. The matrix is gathered on the
   first rank (the interface's size squared), decomposed by LAPACK and scattered back. */
static PetscErrorCode TruncateSVD(IQNIMVJ *qn)
{
  MPI_Comm     comm = PetscObjectComm((PetscObject)qn->J_prev);
  PetscMPIInt  rank, size, *counts = NULL, *displs = NULL;
  PetscInt     n, N, kept = 0;
  PetscScalar *local, *blocks = NULL, *full = NULL;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(MatGetLocalSize(qn->J_prev, &n, NULL));
  PetscCall(MatGetSize(qn->J_prev, &N, NULL));
  if (!rank) {
    PetscCall(PetscMalloc2(size, &counts, size, &displs));
    PetscCall(PetscMalloc2(N * N, &blocks, N * N, &full));
  }
  {
    PetscMPIInt mine = (PetscMPIInt)(n * N);
    PetscCallMPI(MPI_Gather(&mine, 1, MPI_INT, counts, 1, MPI_INT, 0, comm));
    if (!rank)
      for (PetscMPIInt r = 0; r < size; ++r) displs[r] = r ? displs[r - 1] + counts[r - 1] : 0;
    /* each rank's rows, column-major with its own leading dimension n */
    PetscCall(MatDenseGetArray(qn->J_prev, &local));
    PetscCallMPI(MPI_Gatherv(local, mine, MPIU_SCALAR, blocks, counts, displs, MPIU_SCALAR, 0, comm));
  }
  if (!rank) {
    PetscBLASInt bn, lwork, info;
    PetscScalar *U, *VT, *work, query;
    PetscReal   *sigma;
    PetscInt     row0 = 0;

    for (PetscMPIInt r = 0; r < size; ++r) {
      const PetscInt rows = counts[r] / N;
      for (PetscInt j = 0; j < N; ++j)
        for (PetscInt i = 0; i < rows; ++i) full[row0 + i + j * N] = blocks[displs[r] + i + j * rows];
      row0 += rows;
    }
    PetscCall(PetscBLASIntCast(N, &bn));
    PetscCall(PetscMalloc3(N * N, &U, N * N, &VT, N, &sigma));
    lwork = -1;
    LAPACKgesvd_("S", "S", &bn, &bn, full, &bn, sigma, U, &bn, VT, &bn, &query, &lwork, &info);
    PetscCall(PetscBLASIntCast((PetscInt)PetscRealPart(query), &lwork));
    PetscCall(PetscMalloc1(lwork, &work));
    LAPACKgesvd_("S", "S", &bn, &bn, full, &bn, sigma, U, &bn, VT, &bn, work, &lwork, &info);
    PetscCheck(info == 0, PETSC_COMM_SELF, PETSC_ERR_LIB, "iqnimvj: LAPACK gesvd failed (info %d)", (int)info);
    while (kept < N && sigma[kept] > qn->truncation * sigma[0]) kept++;
    PetscCall(PetscArrayzero(full, N * N));
    for (PetscInt k = 0; k < kept; ++k)
      for (PetscInt j = 0; j < N; ++j)
        for (PetscInt i = 0; i < N; ++i) full[i + j * N] += sigma[k] * U[i + k * N] * VT[k + j * N];
    row0 = 0;
    for (PetscMPIInt r = 0; r < size; ++r) {
      const PetscInt rows = counts[r] / N;
      for (PetscInt j = 0; j < N; ++j)
        for (PetscInt i = 0; i < rows; ++i) blocks[displs[r] + i + j * rows] = full[row0 + i + j * N];
      row0 += rows;
    }
    PetscCall(PetscFree(work));
    PetscCall(PetscFree3(U, VT, sigma));
  }
  PetscCallMPI(MPI_Scatterv(blocks, counts, displs, MPIU_SCALAR, local, (PetscMPIInt)(n * N), MPIU_SCALAR, 0, comm));
  PetscCall(MatDenseRestoreArray(qn->J_prev, &local));
  PetscCallMPI(MPI_Bcast(&kept, 1, MPIU_INT, 0, comm));
  PetscCall(
    PetscInfo(NULL, "iqnimvj: svd restart kept %" PetscInt_FMT " of %" PetscInt_FMT " singular values\n", kept, N));
  qn->has_model = kept > 0 ? PETSC_TRUE : PETSC_FALSE;
  if (!rank) {
    PetscCall(PetscFree2(counts, displs));
    PetscCall(PetscFree2(blocks, full));
  }
  PetscFunctionReturn(0);
}

/* The step that ended goes into J_prev (or, slide, J_prev is rebuilt from the window);
   then a restart if one is due. The columns of older steps are dropped unless ls or slide
   needs them. */
static PetscErrorCode IQNIMVJBeginStep(Acceleration acc, PetscInt step)
{
  IQNIMVJ        *qn  = (IQNIMVJ *)acc->data;
  IQNColumns     *c   = &qn->columns;
  const PetscBool due = qn->restart > 0 && (step - 1) % qn->restart == 0 ? PETSC_TRUE : PETSC_FALSE;

  PetscFunctionBeginUser;
  if (qn->mode == IMVJ_RESTART_SLIDE) {
    /* the chain of the window's corrections, oldest first */
    PetscCall(IQNColumnsDropBefore(c, step, qn->keep_steps));
    PetscCall(ZeroModel(qn));
    for (PetscInt end = c->ncols; end > 0;) {
      PetscInt begin = end - 1;
      while (begin > 0 && c->col_step[begin - 1] == c->col_step[end - 1]) begin--;
      PetscCall(Fold(qn, begin, end - begin));
      end = begin;
    }
    PetscFunctionReturn(0);
  }
  if (c->ncols) PetscCall(Fold(qn, 0, IQNColumnsOfStep(c, c->col_step[0])));
  if (qn->mode == IMVJ_RESTART_LS) PetscCall(IQNColumnsDropBefore(c, step, qn->keep_steps));
  else c->ncols = 0;
  if (due && qn->has_model) {
    if (qn->mode == IMVJ_RESTART_ZERO) PetscCall(ZeroModel(qn));
    else if (qn->mode == IMVJ_RESTART_SVD) PetscCall(TruncateSVD(qn));
    else { /* ls: W V^+ of the kept steps' columns */ PetscCall(ZeroModel(qn));
      PetscCall(Fold(qn, 0, c->ncols));
    }
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode IQNIMVJUpdate(Acceleration acc, PetscInt step, PetscInt k, Vec u, Vec sweep, Vec r)
{
  IQNIMVJ *qn = (IQNIMVJ *)acc->data;
  PetscInt mine;

  PetscFunctionBeginUser;
  PetscCall(IQNColumnsRecord(&qn->columns, step, k, sweep, r));
  mine = IQNColumnsOfStep(&qn->columns, step);
  if (!mine && !qn->has_model) { /* no model yet: one relaxed step */
    PetscCall(VecAXPY(u, acc->omega, r));
    PetscFunctionReturn(0);
  }
  PetscCall(IQNColumnsFactorRange(&qn->columns, 0, mine));
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
  PetscCall(ZeroModel(qn));
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
