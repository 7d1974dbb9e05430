/* The libCEED pointwise function giving the coefficients of the fluid Jacobian's
   velocity-velocity block at the quadrature points (ceed_fluid_jacobian.c assembles from
   them). */
#ifndef FSIOPT_QFUNCTIONS_FLUID_JACOBIAN_H
#define FSIOPT_QFUNCTIONS_FLUID_JACOBIAN_H
#include "qfunctions_geometry.h"
#include "qfunctions_fluid_context.h"

/* The velocity-velocity block's coefficients at each point, from which
   ceed_fluid_jacobian.c forms its element matrices in closed form (libCEED's linearization
   would call FluidJacobianUU once per input mode and component). With g_j = B^T grad phi_j
   the physical gradients (B = A^{-1}) and W = w |det A| the point's weight, the entry of
   input node j, component c and output node i, component c' sums over the points
     (m0 d_cc' + R G0[c'][c]) phi_j phi_i + d_cc' R ((u0 - z) . g_j) phi_i
     + W op mu (d_cc' g_j . g_i + g_j[c'] g_i[c])
   (mass, the two convection terms, the symmetric gradient's viscosity): m0 = W mass plus the
   old domains' mass m when the context says so, R = W rho op convection. Inputs u0, du0,
   qdata, then on moving meshes z and m. Output per point, 2 + 2 dim^2 + dim values: m0,
   W op mu, B[a][k] at 2 + a dim + k, R G0[c'][c] at 2 + dim^2 + c' dim + c, and R B (u0 - z)
   (the convection against the reference gradients) at 2 + 2 dim^2 + a. */
CEED_QFUNCTION(FluidJacobianUUCoefficients)(void *ctx, CeedInt Q, const CeedScalar *const *in, CeedScalar *const *out)
{
  const FluidVolume *fv  = (const FluidVolume *)ctx;
  const CeedInt      dim = fv->dim;
  const CeedScalar  *u0 = in[0], *du0 = in[1], *qdata = in[2], *z = fv->moving ? in[3] : NULL;
  const CeedScalar  *m = fv->moving && fv->old_mass ? in[4] : NULL;
  CeedScalar        *c = out[0];

  for (CeedInt i = 0; i < Q; ++i) {
    const CeedScalar wdet = qdata[i], rho_conv = wdet * fv->rho * fv->op * fv->convection;
    CeedScalar       B[3][3], G0[3][3];
    PhysicalGradient(dim, du0, qdata, i, Q, B, G0);
    c[i]     = wdet * fv->mass + (m ? m[i] : 0.0);
    c[Q + i] = wdet * fv->op * fv->mu;
    for (CeedInt a = 0; a < dim; ++a) {
      CeedScalar convection = 0;
      for (CeedInt k = 0; k < dim; ++k) {
        c[(2 + a * dim + k) * Q + i]             = B[a][k];
        c[(2 + dim * dim + a * dim + k) * Q + i] = rho_conv * G0[a][k];
        convection += B[a][k] * CONVECTING(u0, z, k, i, Q);
      }
      c[(2 + 2 * dim * dim + a) * Q + i] = rho_conv * convection;
    }
  }
  return 0;
}
#endif
