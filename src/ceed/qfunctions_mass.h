/* The mass of an H1 space, v = w|J| u per component: on cells with FEMCeedGeometry's qdata
   [w |det A|, B] (the spaces check) and on faces with FEMCeedFaces' [w |J_face|, n] (the
   interface mass); both start with the weight. */
#ifndef FSIOPT_QFUNCTIONS_MASS_H
#define FSIOPT_QFUNCTIONS_MASS_H
#include <ceed.h>

typedef struct {
  CeedInt dim, ncomp;
} SpaceShape;

CEED_QFUNCTION(ApplyMass)(void *ctx, CeedInt Q, const CeedScalar *const *in, CeedScalar *const *out)
{
  const SpaceShape *shape = (const SpaceShape *)ctx;

  for (CeedInt c = 0; c < shape->ncomp; ++c)
    for (CeedInt i = 0; i < Q; ++i) out[0][c * Q + i] = in[1][i] * in[0][c * Q + i];
  return 0;
}

#endif
