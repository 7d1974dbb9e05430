/* libCEED pointwise functions of the checks of ceed_check.c: the mass and the Laplacian of
   an H1 space on the geometry FEMCeedGeometry stores.
   Gradients come as [direction][component][point], as libCEED lays out CEED_EVAL_GRAD. */
#ifndef FSIOPT_QFUNCTIONS_CHECK_H
#define FSIOPT_QFUNCTIONS_CHECK_H
#include "qfunctions_geometry.h"
#include "qfunctions_mass.h"

/* w |det A| (grad u, grad v) = w |det A| sum_k (B^T du)_k (B^T dv)_k */
CEED_QFUNCTION(ApplyLaplacian)(void *ctx, CeedInt Q, const CeedScalar *const *in, CeedScalar *const *out)
{
  const SpaceShape *shape = (const SpaceShape *)ctx;
  const CeedInt     dim = shape->dim, nc = shape->ncomp;

  for (CeedInt i = 0; i < Q; ++i) {
    CeedScalar B[3][3];
    GeometryInverse(dim, in[1], i, Q, B);
    for (CeedInt c = 0; c < nc; ++c)
      for (CeedInt l = 0; l < dim; ++l) {
        CeedScalar v = 0;
        for (CeedInt j = 0; j < dim; ++j) {
          CeedScalar g = 0;
          for (CeedInt k = 0; k < dim; ++k) g += B[j][k] * B[l][k];
          v += in[1][i] * g * in[0][(j * nc + c) * Q + i];
        }
        out[0][(l * nc + c) * Q + i] = v;
      }
  }
  return 0;
}
#endif
