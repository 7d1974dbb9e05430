#ifndef FSIOPT_ACCELERATION_IQN_H
#define FSIOPT_ACCELERATION_IQN_H
#include "acceleration.h"

/* What the interface quasi-Newton methods share (acceleration_iqn.c): the columns, residual
   differences V and sweep differences W, newest first, each with the step it came from; and
   their QR with filtering (Q orthonormal, R upper triangular on the kept columns). */
typedef struct {
  PetscReal    filter;
  PetscInt     ncols, max_cols, *col_step;
  Vec         *V, *W, *Q;
  Vec          r_before, sweep_before; /* r_{k-1}, S(u_{k-1}) */
  PetscInt     kept, *keep;            /* of the last factorization: the kept columns */
  PetscScalar *R;                      /* max_cols x max_cols, row-major */
} IQNColumns;

/* -coupling_iqn_columns, -coupling_iqn_filter (title: the method's name in -help) */
PetscErrorCode IQNColumnsSetUp(IQNColumns *, Vec model, const char title[]);
/* the same without options: at most max_cols columns, the given filter */
PetscErrorCode IQNColumnsAllocate(IQNColumns *, Vec model, PetscInt max_cols, PetscReal filter);
/* a column (v, w) of step `step`, newest first; the oldest goes when all max_cols are taken */
PetscErrorCode IQNColumnsAdd(IQNColumns *, PetscInt step, Vec v, Vec w);
/* a new column from (r_k, S_k) and the previous pair (k > 0); remembers the pair */
PetscErrorCode IQNColumnsRecord(IQNColumns *, PetscInt step, PetscInt k, Vec sweep, Vec r);
/* drops the columns of steps before step - reuse (and past max_cols) */
PetscErrorCode IQNColumnsDropBefore(IQNColumns *, PetscInt step, PetscInt reuse);
/* QR of the columns by modified Gram-Schmidt; a column whose new part is below filter times
   its norm is dropped (it would make R nearly singular) */
PetscErrorCode IQNColumnsFactor(IQNColumns *);
/* the same on the columns first .. first + count - 1 only (keep[] holds their indices) */
PetscErrorCode IQNColumnsFactorRange(IQNColumns *, PetscInt first, PetscInt count);
/* how many of the newest columns came from step `step` */
PetscInt IQNColumnsOfStep(const IQNColumns *, PetscInt step);
/* after Factor: c = argmin ||V c + r||, dx = W c; remainder (may be NULL) = r + V c, the part
   of r the columns do not span */
PetscErrorCode IQNColumnsLeastSquares(IQNColumns *, Vec r, Vec dx, Vec remainder);
PetscErrorCode IQNColumnsDestroy(IQNColumns *);
#endif
