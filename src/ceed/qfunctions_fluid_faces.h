/* libCEED pointwise functions of the fluid's face terms (the boundary kernels of
   fluid_kernels.c): -1/2 rho op conv ((u - z).n) (u, v) on the interface (the convective
   term the control absorbs), and the same where (u - z).n < 0 only on open boundaries
   (backflow stabilization), with their linearizations. qdata: [w |J_face|, n] per point;
   the mesh velocity z an input only on moving meshes. */
#ifndef FSIOPT_QFUNCTIONS_FLUID_FACES_H
#define FSIOPT_QFUNCTIONS_FLUID_FACES_H
#include "qfunctions_fluid_context.h"

CEED_QFUNCTION_HELPER CeedScalar FaceNormalVelocity(CeedInt dim, const CeedScalar *u, const CeedScalar *z,
                                                    const CeedScalar *qdata, CeedInt i, CeedInt Q)
{
  CeedScalar un = 0;
  for (CeedInt d = 0; d < dim; ++d) un += CONVECTING(u, z, d, i, Q) * qdata[(1 + d) * Q + i];
  return un;
}

CEED_QFUNCTION_HELPER int FaceConvectionResidual(const FluidVolume *fv, CeedInt backflow, CeedInt Q,
                                                 const CeedScalar *const *in, CeedScalar *const *out)
{
  const CeedInt     dim = fv->dim;
  const CeedScalar *u = in[0], *z = fv->moving ? in[1] : NULL, *qdata = in[fv->moving ? 2 : 1];
  const CeedScalar  half_rho = 0.5 * fv->rho * fv->op * fv->convection;
  CeedScalar       *v        = out[0];

  for (CeedInt i = 0; i < Q; ++i) {
    const CeedScalar un = FaceNormalVelocity(dim, u, z, qdata, i, Q), active = backflow && un >= 0 ? 0.0 : 1.0;
    for (CeedInt c = 0; c < dim; ++c) v[c * Q + i] = -active * qdata[i] * half_rho * un * u[c * Q + i];
  }
  return 0;
}

/* the linearization at u0 applied to du */
CEED_QFUNCTION_HELPER int FaceConvectionJacobian(const FluidVolume *fv, CeedInt backflow, CeedInt Q,
                                                 const CeedScalar *const *in, CeedScalar *const *out)
{
  const CeedInt     dim = fv->dim;
  const CeedScalar *du = in[0], *u0 = in[1], *z = fv->moving ? in[2] : NULL, *qdata = in[fv->moving ? 3 : 2];
  const CeedScalar  half_rho = 0.5 * fv->rho * fv->op * fv->convection;
  CeedScalar       *v        = out[0];

  for (CeedInt i = 0; i < Q; ++i) {
    const CeedScalar un = FaceNormalVelocity(dim, u0, z, qdata, i, Q), active = backflow && un >= 0 ? 0.0 : 1.0;
    const CeedScalar scale = -active * qdata[i] * half_rho;
    for (CeedInt c = 0; c < dim; ++c) {
      CeedScalar s = un * du[c * Q + i];
      /* g0[c][d] = u0_c n_d + (c == d) un */
      for (CeedInt d = 0; d < dim; ++d) s += u0[c * Q + i] * qdata[(1 + d) * Q + i] * du[d * Q + i];
      v[c * Q + i] = scale * s;
    }
  }
  return 0;
}

CEED_QFUNCTION(FluidBackflowResidual)(void *ctx, CeedInt Q, const CeedScalar *const *in, CeedScalar *const *out)
{
  return FaceConvectionResidual((const FluidVolume *)ctx, 1, Q, in, out);
}
CEED_QFUNCTION(FluidConvectionResidual)(void *ctx, CeedInt Q, const CeedScalar *const *in, CeedScalar *const *out)
{
  return FaceConvectionResidual((const FluidVolume *)ctx, 0, Q, in, out);
}
CEED_QFUNCTION(FluidBackflowJacobian)(void *ctx, CeedInt Q, const CeedScalar *const *in, CeedScalar *const *out)
{
  return FaceConvectionJacobian((const FluidVolume *)ctx, 1, Q, in, out);
}
CEED_QFUNCTION(FluidConvectionJacobian)(void *ctx, CeedInt Q, const CeedScalar *const *in, CeedScalar *const *out)
{
  return FaceConvectionJacobian((const FluidVolume *)ctx, 0, Q, in, out);
}
#endif
