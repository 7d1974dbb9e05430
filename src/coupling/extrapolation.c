/* A step's start from the values of the last steps: the polynomial fitted by least squares
   to them (coupling_impl.h). The control of every method and the velocity iterate of the
   partitioned methods start from one. */
#include "coupling_impl.h"
#include "checkpoint.h"

PetscErrorCode ExtrapolationCreate(Vec model, PetscInt degree, PetscInt points, Extrapolation *e)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(e, sizeof(*e)));
  e->degree = degree;
  e->points = points;
  for (PetscInt i = 0; i < points; ++i) PetscCall(VecDuplicate(model, &e->past[i]));
  PetscFunctionReturn(0);
}

PetscErrorCode ExtrapolationRecord(Extrapolation *e, Vec x)
{
  Vec oldest = e->past[e->points - 1];

  PetscFunctionBeginUser;
  for (PetscInt i = e->points - 1; i > 0; --i) e->past[i] = e->past[i - 1];
  e->past[0] = oldest;
  PetscCall(VecCopy(x, e->past[0]));
  e->npast = PetscMin(e->npast + 1, e->points);
  PetscFunctionReturn(0);
}

/* The weights w with sum_i w_i p(-i-1) = p(0) for the least-squares fit p of degree
   `degree` to `n` values at times -1, ..., -n (binomial coefficients with alternating
   signs when n = degree + 1): w = V y with (V^T V) y = e_0, V the Vandermonde matrix. */
static void ExtrapolationWeights(PetscInt degree, PetscInt n, PetscScalar w[])
{
  const PetscInt m                                                                = degree + 1;
  PetscReal      gram[FSIOPT_EXTRAPOLATION_MAX + 1][FSIOPT_EXTRAPOLATION_MAX + 2] = {{0}};

  for (PetscInt r = 0; r < m; ++r) {
    for (PetscInt c = 0; c < m; ++c)
      for (PetscInt i = 0; i < n; ++i) gram[r][c] += PetscPowRealInt(-(i + 1.0), r + c);
    gram[r][m] = r == 0;
  }
  for (PetscInt k = 0; k < m; ++k) /* the Gram matrix is positive definite: no pivoting */
    for (PetscInt r = k + 1; r < m; ++r)
      for (PetscInt c = m; c >= k; --c) gram[r][c] -= gram[r][k] / gram[k][k] * gram[k][c];
  for (PetscInt r = m - 1; r >= 0; --r) {
    for (PetscInt c = r + 1; c < m; ++c) gram[r][m] -= gram[r][c] * gram[c][m];
    gram[r][m] /= gram[r][r];
  }
  for (PetscInt i = 0; i < n; ++i) {
    w[i] = 0;
    for (PetscInt r = 0; r < m; ++r) w[i] += PetscPowRealInt(-(i + 1.0), r) * gram[r][m];
  }
}

/* Solves the n x n system A a = b in place (Gaussian elimination with partial pivoting);
   false when it is singular to working precision. */
static PetscBool SmallSolve(PetscInt n, PetscReal A[][FSIOPT_EXTRAPOLATION_POINTS_MAX], PetscReal b[])
{
  for (PetscInt k = 0; k < n; ++k) {
    PetscInt piv = k;
    for (PetscInt r = k + 1; r < n; ++r)
      if (PetscAbsReal(A[r][k]) > PetscAbsReal(A[piv][k])) piv = r;
    if (PetscAbsReal(A[piv][k]) <= 1e-14 * PetscAbsReal(A[0][0])) return PETSC_FALSE;
    for (PetscInt c = 0; c < n; ++c) {
      PetscReal t = A[k][c];
      A[k][c]     = A[piv][c];
      A[piv][c]   = t;
    }
    {
      PetscReal t = b[k];
      b[k]        = b[piv];
      b[piv]      = t;
    }
    for (PetscInt r = k + 1; r < n; ++r) {
      const PetscReal f = A[r][k] / A[k][k];
      for (PetscInt c = k; c < n; ++c) A[r][c] -= f * A[k][c];
      b[r] -= f * b[k];
    }
  }
  for (PetscInt r = n - 1; r >= 0; --r) {
    for (PetscInt c = r + 1; c < n; ++c) b[r] -= A[r][c] * b[c];
    b[r] /= A[r][r];
  }
  return PETSC_TRUE;
}

/* The recurrence y_j = sum_{i=1..p} a_i y_{j+i} fitted by least squares to the past values
   y_first, ..., y_{n-1} (newest first, Gram matrix G of their inner products) */
static PetscBool FitRecurrence(PetscInt p, PetscInt first, PetscInt n, PetscReal G[][FSIOPT_EXTRAPOLATION_POINTS_MAX],
                               PetscReal a[])
{
  PetscReal A[FSIOPT_EXTRAPOLATION_POINTS_MAX][FSIOPT_EXTRAPOLATION_POINTS_MAX] = {{0}};

  if (n - first - p < 1) return PETSC_FALSE;
  for (PetscInt i = 0; i < p; ++i) {
    a[i] = 0;
    for (PetscInt l = 0; l < p; ++l)
      for (PetscInt j = first; j + p < n; ++j) A[i][l] += G[j + 1 + i][j + 1 + l];
    for (PetscInt j = first; j + p < n; ++j) a[i] += G[j][j + 1 + i];
  }
  return SmallSolve(p, A, a);
}

/* ||y_target - sum_i w_i y_{from+i}||^2 from the Gram matrix */
static PetscReal PredictionError(PetscInt target, PetscInt from, PetscInt n, const PetscReal w[],
                                 PetscReal G[][FSIOPT_EXTRAPOLATION_POINTS_MAX])
{
  PetscReal e = G[target][target];

  for (PetscInt i = 0; i < n; ++i) {
    e -= 2 * w[i] * G[target][from + i];
    for (PetscInt l = 0; l < n; ++l) e += w[i] * w[l] * G[from + i][from + l];
  }
  return e;
}

PetscErrorCode ExtrapolationPredict(Extrapolation *e, Vec x)
{
  PetscScalar    weights[FSIOPT_EXTRAPOLATION_POINTS_MAX];
  const PetscInt degree = PetscMin(e->degree, e->npast - 1);

  PetscFunctionBeginUser;
  if (degree < 0) PetscFunctionReturn(0); /* nothing recorded: x stays */
  ExtrapolationWeights(degree, e->npast, weights);
  e->predictions++;
  if (e->ar_order > 0 && e->npast >= e->ar_from) {
    /* the recurrence replaces the polynomial when, fitted without the newest value, it
       predicted that value better than the polynomial through the same older values did.
       While fewer than P+3 values are recorded, its order is the highest that still fits two
       of them without the newest: the first steps of a run, which the polynomial alone
       predicts worst (order n - 2 fits one, exactly, and never won on tube3d) */
    const PetscInt n = e->npast, p = PetscMin(e->ar_order, n - 3);
    PetscReal      G[FSIOPT_EXTRAPOLATION_POINTS_MAX][FSIOPT_EXTRAPOLATION_POINTS_MAX];
    PetscReal      a[FSIOPT_EXTRAPOLATION_POINTS_MAX], older[FSIOPT_EXTRAPOLATION_POINTS_MAX];
    PetscScalar    dots[FSIOPT_EXTRAPOLATION_POINTS_MAX], w_older[FSIOPT_EXTRAPOLATION_POINTS_MAX];

    for (PetscInt s = 0; s < n; ++s) {
      PetscCall(VecMDot(e->past[s], n, e->past, dots));
      for (PetscInt t = 0; t < n; ++t) G[s][t] = PetscRealPart(dots[t]);
    }
    ExtrapolationWeights(PetscMin(e->degree, n - 2), n - 1, w_older);
    for (PetscInt i = 0; i < n - 1; ++i) older[i] = PetscRealPart(w_older[i]);
    if (FitRecurrence(p, 1, n, G, a)) {
      const PetscReal recurrence_error = PredictionError(0, 1, p, a, G);
      const PetscReal polynomial_error = PredictionError(0, 1, n - 1, older, G);
      if (recurrence_error < polynomial_error && FitRecurrence(p, 0, n, G, a)) {
        for (PetscInt i = 0; i < n; ++i) weights[i] = i < p ? a[i] : 0;
        e->recurrence_predictions++;
      }
    }
  }
  PetscCall(VecZeroEntries(x));
  PetscCall(VecMAXPY(x, e->npast, weights, e->past));
  PetscFunctionReturn(0);
}

PetscErrorCode ExtrapolationDestroy(Extrapolation *e)
{
  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < e->points; ++i) PetscCall(VecDestroy(&e->past[i]));
  PetscFunctionReturn(0);
}

PetscErrorCode ExtrapolationCheckpoint(Extrapolation *e, Checkpoint cp, const char name[], PetscBool load)
{
  char key[64];

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(key, sizeof(key), "past_%ss", name));
  PetscCall(CheckpointInt(cp, key, &e->npast, load));
  /* a restart that fits fewer points (-restart_change coupling) starts from the newest */
  if (load) e->npast = PetscMin(e->npast, e->points);
  for (PetscInt i = 0; i < e->npast; ++i) {
    PetscCall(PetscSNPrintf(key, sizeof(key), "past_%s_%" PetscInt_FMT, name, i));
    PetscCall(CheckpointVec(cp, key, e->past[i], load));
  }
  PetscFunctionReturn(0);
}
