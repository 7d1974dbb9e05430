/* The cells' geometry at a quadrature point, shared by the libCEED pointwise functions. */
#ifndef FSIOPT_QFUNCTIONS_GEOMETRY_H
#define FSIOPT_QFUNCTIONS_GEOMETRY_H
#include <ceed.h>
#include <math.h>

/* A = dx/dxi at point i of Q (a[c][j] = dx_c/dxi_j); returns det A, and B = A^{-1} */
CEED_QFUNCTION_HELPER CeedScalar Invert(CeedInt dim, const CeedScalar *J, CeedInt i, CeedInt Q, CeedScalar B[3][3])
{
  CeedScalar a[3][3], det;

  for (CeedInt j = 0; j < dim; ++j)
    for (CeedInt c = 0; c < dim; ++c) a[c][j] = J[(j * dim + c) * Q + i];
  if (dim == 2) {
    det     = a[0][0] * a[1][1] - a[0][1] * a[1][0];
    B[0][0] = a[1][1] / det;
    B[0][1] = -a[0][1] / det;
    B[1][0] = -a[1][0] / det;
    B[1][1] = a[0][0] / det;
    return det;
  }
  det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
        a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
  for (CeedInt r = 0; r < 3; ++r)
    for (CeedInt c = 0; c < 3; ++c) {
      const CeedInt r1 = (c + 1) % 3, r2 = (c + 2) % 3, c1 = (r + 1) % 3, c2 = (r + 2) % 3;
      B[r][c] = (a[r1][c1] * a[r2][c2] - a[r1][c2] * a[r2][c1]) / det;
    }
  return det;
}

/* B at point i of such qdata */
CEED_QFUNCTION_HELPER void GeometryInverse(CeedInt dim, const CeedScalar *qdata, CeedInt i, CeedInt Q,
                                           CeedScalar B[3][3])
{
  for (CeedInt j = 0; j < dim; ++j)
    for (CeedInt k = 0; k < dim; ++k) B[j][k] = qdata[(1 + j * dim + k) * Q + i];
}

/* physical gradients G[c][k] = du_c/dx_k of a reference gradient at point i */
CEED_QFUNCTION_HELPER void PhysicalGradient(CeedInt dim, const CeedScalar *du, const CeedScalar *qdata, CeedInt i,
                                            CeedInt Q, CeedScalar B[3][3], CeedScalar G[3][3])
{
  GeometryInverse(dim, qdata, i, Q, B);
  for (CeedInt c = 0; c < dim; ++c)
    for (CeedInt k = 0; k < dim; ++k) {
      G[c][k] = 0;
      for (CeedInt j = 0; j < dim; ++j) G[c][k] += du[(j * dim + c) * Q + i] * B[j][k];
    }
}
#endif
