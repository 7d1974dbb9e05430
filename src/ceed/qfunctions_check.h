/* libCEED pointwise functions of the checks of ceed_check.c: the mass and the Laplacian of
   an H1 space, each a set-up that stores the geometry at the quadrature points and an apply.
   Gradients come as [direction][component][point], as libCEED lays out CEED_EVAL_GRAD. */
#ifndef FSIOPT_QFUNCTIONS_CHECK_H
#define FSIOPT_QFUNCTIONS_CHECK_H
#include "qfunctions_geometry.h"

typedef struct {
  CeedInt dim, ncomp;
} SpaceShape;

/* qdata = w |det A| */
CEED_QFUNCTION(SetupMass)(void *ctx, CeedInt Q, const CeedScalar *const *in, CeedScalar *const *out)
{
  const SpaceShape *shape = (const SpaceShape *)ctx;
  CeedScalar        B[3][3];

  for (CeedInt i = 0; i < Q; ++i) out[0][i] = in[1][i] * fabs(Invert(shape->dim, in[0], i, Q, B));
  return 0;
}

CEED_QFUNCTION(ApplyMass)(void *ctx, CeedInt Q, const CeedScalar *const *in, CeedScalar *const *out)
{
  const SpaceShape *shape = (const SpaceShape *)ctx;

  for (CeedInt c = 0; c < shape->ncomp; ++c)
    for (CeedInt i = 0; i < Q; ++i) out[0][c * Q + i] = in[1][i] * in[0][c * Q + i];
  return 0;
}

/* qdata[j][l] = w |det A| sum_k B[j][k] B[l][k] */
CEED_QFUNCTION(SetupLaplacian)(void *ctx, CeedInt Q, const CeedScalar *const *in, CeedScalar *const *out)
{
  const SpaceShape *shape = (const SpaceShape *)ctx;
  const CeedInt     dim   = shape->dim;
  CeedScalar        B[3][3];

  for (CeedInt i = 0; i < Q; ++i) {
    const CeedScalar scale = in[1][i] * fabs(Invert(dim, in[0], i, Q, B));
    for (CeedInt j = 0; j < dim; ++j)
      for (CeedInt l = 0; l < dim; ++l) {
        CeedScalar g = 0;
        for (CeedInt k = 0; k < dim; ++k) g += B[j][k] * B[l][k];
        out[0][(j * dim + l) * Q + i] = scale * g;
      }
  }
  return 0;
}

CEED_QFUNCTION(ApplyLaplacian)(void *ctx, CeedInt Q, const CeedScalar *const *in, CeedScalar *const *out)
{
  const SpaceShape *shape = (const SpaceShape *)ctx;
  const CeedInt     dim = shape->dim, nc = shape->ncomp;

  for (CeedInt i = 0; i < Q; ++i)
    for (CeedInt c = 0; c < nc; ++c)
      for (CeedInt l = 0; l < dim; ++l) {
        CeedScalar v = 0;
        for (CeedInt j = 0; j < dim; ++j) v += in[1][(j * dim + l) * Q + i] * in[0][(j * nc + c) * Q + i];
        out[0][(l * nc + c) * Q + i] = v;
      }
  return 0;
}
#endif
