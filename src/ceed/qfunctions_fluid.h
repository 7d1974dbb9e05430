/* libCEED pointwise functions of the fluid's volume residual (the weak form of
   fluid_kernels.c): m (u, v) + op [rho conv (((u - z) . grad) u, v) + 2 mu (D(u), D(v))
   - (p, div v) - (q, div u)] on the geometry of FEMCeedGeometry, z the mesh velocity (an
   input only on moving meshes). Gradients are [direction][component][point]. */
#ifndef FSIOPT_QFUNCTIONS_FLUID_H
#define FSIOPT_QFUNCTIONS_FLUID_H
#include "qfunctions_geometry.h"
#include "qfunctions_fluid_context.h"

/* the weak form's (f1, grad v) at point i in the reference gradients libCEED applies:
   dv[j][c] = w |det A| sum_k f1[c][k] B[j][k], B = A^{-1} */
CEED_QFUNCTION_HELPER void TestGradient(CeedInt dim, CeedScalar f1[3][3], CeedScalar B[3][3], CeedScalar wdet,
                                        CeedScalar *dv, CeedInt i, CeedInt Q)
{
  for (CeedInt j = 0; j < dim; ++j)
    for (CeedInt c = 0; c < dim; ++c) {
      CeedScalar s = 0;
      for (CeedInt k = 0; k < dim; ++k) s += f1[c][k] * B[j][k];
      dv[(j * dim + c) * Q + i] = wdet * s;
    }
}

CEED_QFUNCTION(FluidVolumeResidual)(void *ctx, CeedInt Q, const CeedScalar *const *in, CeedScalar *const *out)
{
  const FluidVolume *fv  = (const FluidVolume *)ctx;
  const CeedInt      dim = fv->dim;
  const CeedScalar  *u = in[0], *du = in[1], *p = in[2], *qdata = in[3], *z = fv->moving ? in[4] : NULL;
  const CeedScalar  *m = fv->moving && fv->old_mass ? in[5] : NULL;
  CeedScalar        *v = out[0], *dv = out[1], *q = out[2];

  for (CeedInt i = 0; i < Q; ++i) {
    const CeedScalar wdet = qdata[i];
    CeedScalar       B[3][3], G[3][3], f1[3][3], divergence = 0;
    PhysicalGradient(dim, du, qdata, i, Q, B, G);
    for (CeedInt d = 0; d < dim; ++d) divergence += G[d][d];
    for (CeedInt c = 0; c < dim; ++c) {
      CeedScalar convection = 0;
      for (CeedInt d = 0; d < dim; ++d) convection += CONVECTING(u, z, d, i, Q) * G[c][d];
      v[c * Q + i] = wdet * (fv->mass * u[c * Q + i] + fv->rho * fv->op * fv->convection * convection) +
                     (m ? m[i] * u[c * Q + i] : 0.0);
      for (CeedInt d = 0; d < dim; ++d) f1[c][d] = fv->op * (fv->mu * (G[c][d] + G[d][c]) - (c == d ? p[i] : 0.0));
    }
    TestGradient(dim, f1, B, wdet, dv, i, Q);
    q[i] = -wdet * fv->op * divergence;
  }
  return 0;
}
/* the velocity-velocity block of the Jacobian at the state u0 (mass, both convection terms,
   viscosity) applied to w, or its transpose (for the adjoint's matrix-free products: the test
   and trial roles of the convection terms swapped; mass and viscosity are symmetric) */
CEED_QFUNCTION_HELPER int JacobianUU(const FluidVolume *fv, CeedInt transpose, CeedInt Q, const CeedScalar *const *in,
                                     CeedScalar *const *out)
{
  const CeedInt     dim = fv->dim;
  const CeedScalar *w = in[0], *dw = in[1], *u0 = in[2], *du0 = in[3], *qdata = in[4], *z = fv->moving ? in[5] : NULL;
  CeedScalar       *v = out[0], *dv = out[1];

  for (CeedInt i = 0; i < Q; ++i) {
    const CeedScalar wdet = qdata[i], rho_conv = fv->rho * fv->op * fv->convection;
    CeedScalar       B[3][3], G[3][3], G0[3][3], f1[3][3];
    PhysicalGradient(dim, dw, qdata, i, Q, B, G);
    PhysicalGradient(dim, du0, qdata, i, Q, B, G0);
    for (CeedInt c = 0; c < dim; ++c) {
      CeedScalar convection = 0;
      for (CeedInt d = 0; d < dim; ++d)
        convection += transpose ? w[d * Q + i] * G0[d][c]
                                : w[d * Q + i] * G0[c][d] + CONVECTING(u0, z, d, i, Q) * G[c][d];
      v[c * Q + i] = wdet * (fv->mass * w[c * Q + i] + rho_conv * convection);
      for (CeedInt d = 0; d < dim; ++d)
        f1[c][d] = fv->op * fv->mu * (G[c][d] + G[d][c]) +
                   (transpose ? rho_conv * CONVECTING(u0, z, d, i, Q) * w[c * Q + i] : 0.0);
    }
    TestGradient(dim, f1, B, wdet, dv, i, Q);
  }
  return 0;
}
CEED_QFUNCTION(FluidJacobianUU)(void *ctx, CeedInt Q, const CeedScalar *const *in, CeedScalar *const *out)
{
  return JacobianUU((const FluidVolume *)ctx, 0, Q, in, out);
}
CEED_QFUNCTION(FluidJacobianUUTranspose)(void *ctx, CeedInt Q, const CeedScalar *const *in, CeedScalar *const *out)
{
  return JacobianUU((const FluidVolume *)ctx, 1, Q, in, out);
}

/* the velocity-pressure block: -(q, div v) */
CEED_QFUNCTION(FluidJacobianUP)(void *ctx, CeedInt Q, const CeedScalar *const *in, CeedScalar *const *out)
{
  const FluidVolume *fv  = (const FluidVolume *)ctx;
  const CeedInt      dim = fv->dim;
  const CeedScalar  *p = in[0], *qdata = in[1];
  CeedScalar        *dv = out[0];

  for (CeedInt i = 0; i < Q; ++i)
    for (CeedInt j = 0; j < dim; ++j)
      for (CeedInt c = 0; c < dim; ++c)
        dv[(j * dim + c) * Q + i] = -qdata[i] * fv->op * p[i] * qdata[(1 + j * dim + c) * Q + i];
  return 0;
}

/* the pressure-velocity block: -(q, div u) */
CEED_QFUNCTION(FluidJacobianPU)(void *ctx, CeedInt Q, const CeedScalar *const *in, CeedScalar *const *out)
{
  const FluidVolume *fv  = (const FluidVolume *)ctx;
  const CeedInt      dim = fv->dim;
  const CeedScalar  *du = in[0], *qdata = in[1];
  CeedScalar        *q = out[0];

  for (CeedInt i = 0; i < Q; ++i) {
    CeedScalar B[3][3], G[3][3], divergence = 0;
    PhysicalGradient(dim, du, qdata, i, Q, B, G);
    for (CeedInt d = 0; d < dim; ++d) divergence += G[d][d];
    q[i] = -qdata[i] * fv->op * divergence;
  }
  return 0;
}
/* the pressure stabilization of equal-order pairs, -tau (grad p, grad q): the residual's
   term and, being linear, the pressure-pressure block of the Jacobian */
CEED_QFUNCTION(FluidPressureStabilization)(void *ctx, CeedInt Q, const CeedScalar *const *in, CeedScalar *const *out)
{
  const FluidVolume *fv  = (const FluidVolume *)ctx;
  const CeedInt      dim = fv->dim;
  const CeedScalar  *dp = in[0], *qdata = in[1];
  CeedScalar        *dq = out[0];

  for (CeedInt i = 0; i < Q; ++i) {
    CeedScalar B[3][3], grad[3];
    GeometryInverse(dim, qdata, i, Q, B);
    for (CeedInt k = 0; k < dim; ++k) {
      grad[k] = 0;
      for (CeedInt j = 0; j < dim; ++j) grad[k] += dp[j * Q + i] * B[j][k];
    }
    for (CeedInt j = 0; j < dim; ++j) {
      CeedScalar s = 0;
      for (CeedInt k = 0; k < dim; ++k) s += grad[k] * B[j][k];
      dq[j * Q + i] = -qdata[i] * fv->tau * s;
    }
  }
  return 0;
}
/* the old domains' mass on the velocity, v = m u, with the per-point weights m of
   FEMCeedFluidMassWeights (the sum of w |det A| of the old domains times their coefficients) */
CEED_QFUNCTION(FluidOldMass)(void *ctx, CeedInt Q, const CeedScalar *const *in, CeedScalar *const *out)
{
  const FluidVolume *fv = (const FluidVolume *)ctx;
  const CeedScalar  *u = in[0], *m = in[1];
  CeedScalar        *v = out[0];

  for (CeedInt c = 0; c < fv->dim; ++c)
    for (CeedInt i = 0; i < Q; ++i) v[c * Q + i] = m[i] * u[c * Q + i];
  return 0;
}

/* w |det A| of a domain at the quadrature points */
CEED_QFUNCTION(FluidDomainWeight)(void *ctx, CeedInt Q, const CeedScalar *const *in, CeedScalar *const *out)
{
  const FluidVolume *fv = (const FluidVolume *)ctx;
  CeedScalar         B[3][3];

  for (CeedInt i = 0; i < Q; ++i) out[0][i] = in[1][i] * fabs(Invert(fv->dim, in[0], i, Q, B));
  return 0;
}
#endif
