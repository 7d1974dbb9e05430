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

PetscErrorCode ExtrapolationPredict(Extrapolation *e, Vec x)
{
  PetscScalar    weights[FSIOPT_EXTRAPOLATION_POINTS_MAX];
  const PetscInt degree = PetscMin(e->degree, e->npast - 1);

  PetscFunctionBeginUser;
  if (degree < 0) PetscFunctionReturn(0); /* nothing recorded: x stays */
  ExtrapolationWeights(degree, e->npast, weights);
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
  PetscCheck(e->npast <= e->points, PETSC_COMM_WORLD, PETSC_ERR_FILE_UNEXPECTED,
             "option -restart: the checkpoint keeps %" PetscInt_FMT
             " past %ss, -coupling_extrapolation_points is %" PetscInt_FMT,
             e->npast, name, e->points);
  for (PetscInt i = 0; i < e->npast; ++i) {
    PetscCall(PetscSNPrintf(key, sizeof(key), "past_%s_%" PetscInt_FMT, name, i));
    PetscCall(CheckpointVec(cp, key, e->past[i], load));
  }
  PetscFunctionReturn(0);
}
