/* libCEED pointwise functions of vector-valued stiffness forms on the geometry of
   FEMCeedGeometry: m (u, v) + op c (P(grad u), grad v), with c a per-point weight (the mesh
   motion's stiffening, else 1), or a per-point material (rho_scale, mu, lambda, svk: the
   structure's regions) that replaces the form's mu, lambda and model and scales m, and P
     linear: h G + mu (G + G^T) + lambda tr(G) I (h: a harmonic part, the mesh motion's),
     St. Venant-Kirchhoff: F S, F = I + G, S = lambda tr(E) I + 2 mu E, E = (F^T F - I)/2,
   the weak forms of structure_kernels.c and motion.c. Gradients are [direction][component][point]. */
#ifndef FSIOPT_QFUNCTIONS_ELASTICITY_H
#define FSIOPT_QFUNCTIONS_ELASTICITY_H
#include "qfunctions_geometry.h"

typedef struct {
  CeedInt    dim, svk, cell_values; /* cell_values: 0, 1 (a weight) or 4 (a material) */
  CeedScalar mass, op, mu, lambda, harmonic;
} ElasticityForm;

/* P(G) of the model */
CEED_QFUNCTION_HELPER void ElasticityStress(const ElasticityForm *e, CeedScalar G[3][3], CeedScalar P[3][3])
{
  const CeedInt dim   = e->dim;
  CeedScalar    trace = 0;

  if (!e->svk) {
    for (CeedInt d = 0; d < dim; ++d) trace += G[d][d];
    for (CeedInt c = 0; c < dim; ++c)
      for (CeedInt d = 0; d < dim; ++d)
        P[c][d] = e->harmonic * G[c][d] + e->mu * (G[c][d] + G[d][c]) + (c == d ? e->lambda * trace : 0.0);
    return;
  }
  CeedScalar F[3][3], S[3][3];
  for (CeedInt c = 0; c < dim; ++c)
    for (CeedInt d = 0; d < dim; ++d) F[c][d] = G[c][d] + (c == d ? 1.0 : 0.0);
  for (CeedInt k = 0; k < dim; ++k)
    for (CeedInt d = 0; d < dim; ++d) {
      CeedScalar ftf = 0;
      for (CeedInt a = 0; a < dim; ++a) ftf += F[a][k] * F[a][d];
      S[k][d] = 0.5 * (ftf - (k == d ? 1.0 : 0.0)); /* E */
    }
  for (CeedInt d = 0; d < dim; ++d) trace += S[d][d];
  for (CeedInt k = 0; k < dim; ++k)
    for (CeedInt d = 0; d < dim; ++d) S[k][d] = 2 * e->mu * S[k][d] + (k == d ? e->lambda * trace : 0.0);
  for (CeedInt c = 0; c < dim; ++c)
    for (CeedInt d = 0; d < dim; ++d) {
      P[c][d] = 0;
      for (CeedInt k = 0; k < dim; ++k) P[c][d] += F[c][k] * S[k][d];
    }
}

/* dP(G0)[dG]: the linear stress of dG, or St. Venant-Kirchhoff's dG S + F dS */
CEED_QFUNCTION_HELPER void ElasticityStressIncrement(const ElasticityForm *e, CeedScalar G0[3][3], CeedScalar dG[3][3],
                                                     CeedScalar dP[3][3])
{
  const CeedInt dim = e->dim;

  if (!e->svk) {
    ElasticityStress(e, dG, dP);
    return;
  }
  CeedScalar F[3][3], E[3][3], S[3][3], dE[3][3], dS[3][3], trace = 0, dtrace = 0;
  for (CeedInt c = 0; c < dim; ++c)
    for (CeedInt d = 0; d < dim; ++d) F[c][d] = G0[c][d] + (c == d ? 1.0 : 0.0);
  for (CeedInt k = 0; k < dim; ++k)
    for (CeedInt d = 0; d < dim; ++d) {
      CeedScalar ftf = 0, dftf = 0;
      for (CeedInt a = 0; a < dim; ++a) {
        ftf += F[a][k] * F[a][d];
        dftf += dG[a][k] * F[a][d] + F[a][k] * dG[a][d];
      }
      E[k][d]  = 0.5 * (ftf - (k == d ? 1.0 : 0.0));
      dE[k][d] = 0.5 * dftf;
    }
  for (CeedInt d = 0; d < dim; ++d) {
    trace += E[d][d];
    dtrace += dE[d][d];
  }
  for (CeedInt k = 0; k < dim; ++k)
    for (CeedInt d = 0; d < dim; ++d) {
      S[k][d]  = 2 * e->mu * E[k][d] + (k == d ? e->lambda * trace : 0.0);
      dS[k][d] = 2 * e->mu * dE[k][d] + (k == d ? e->lambda * dtrace : 0.0);
    }
  for (CeedInt c = 0; c < dim; ++c)
    for (CeedInt d = 0; d < dim; ++d) {
      dP[c][d] = 0;
      for (CeedInt k = 0; k < dim; ++k) dP[c][d] += dG[c][k] * S[k][d] + F[c][k] * dS[k][d];
    }
}

/* v = w|det| m u, dv = w|det| op c P B^T */
CEED_QFUNCTION_HELPER void ElasticityOutput(const ElasticityForm *e, CeedInt i, CeedInt Q, CeedScalar wdet,
                                            CeedScalar weight, const CeedScalar *u, CeedScalar B[3][3],
                                            CeedScalar P[3][3], CeedScalar *v, CeedScalar *dv)
{
  const CeedInt dim = e->dim;

  for (CeedInt c = 0; c < dim; ++c) v[c * Q + i] = wdet * e->mass * u[c * Q + i];
  for (CeedInt j = 0; j < dim; ++j)
    for (CeedInt c = 0; c < dim; ++c) {
      CeedScalar s = 0;
      for (CeedInt k = 0; k < dim; ++k) s += P[c][k] * B[j][k];
      dv[(j * dim + c) * Q + i] = wdet * e->op * weight * s;
    }
}

/* the form at point i: e's, or with the point's material; its weight into *weight */
CEED_QFUNCTION_HELPER ElasticityForm ElasticityAtPoint(const ElasticityForm *e, const CeedScalar *c, CeedInt i,
                                                      CeedInt Q, CeedScalar *weight)
{
  ElasticityForm f = *e;

  *weight = e->cell_values == 1 ? c[i] : 1.0;
  if (e->cell_values == 4) {
    f.mass *= c[i];
    f.mu     = c[Q + i];
    f.lambda = c[2 * Q + i];
    f.svk    = c[3 * Q + i] > 0.5;
  }
  return f;
}

/* inputs u, du, qdata[, cell values]; outputs v, dv */
CEED_QFUNCTION(ElasticityResidual)(void *ctx, CeedInt Q, const CeedScalar *const *in, CeedScalar *const *out)
{
  const ElasticityForm *e = (const ElasticityForm *)ctx;
  const CeedScalar     *u = in[0], *du = in[1], *qdata = in[2], *c = e->cell_values ? in[3] : NULL;

  for (CeedInt i = 0; i < Q; ++i) {
    CeedScalar     B[3][3], G[3][3], P[3][3], weight;
    ElasticityForm f = ElasticityAtPoint(e, c, i, Q, &weight);
    PhysicalGradient(e->dim, du, qdata, i, Q, B, G);
    ElasticityStress(&f, G, P);
    ElasticityOutput(&f, i, Q, qdata[i], weight, u, B, P, out[0], out[1]);
  }
  return 0;
}

/* inputs w, dw, qdata[, cell values][, du0: St. Venant-Kirchhoff's state]; outputs v, dv */
CEED_QFUNCTION(ElasticityJacobian)(void *ctx, CeedInt Q, const CeedScalar *const *in, CeedScalar *const *out)
{
  const ElasticityForm *e = (const ElasticityForm *)ctx;
  const CeedScalar     *w = in[0], *dw = in[1], *qdata = in[2], *c = e->cell_values ? in[3] : NULL;
  const CeedScalar     *du0 = e->svk ? in[e->cell_values ? 4 : 3] : NULL;

  for (CeedInt i = 0; i < Q; ++i) {
    CeedScalar     B[3][3], dG[3][3], G0[3][3] = {{0}}, dP[3][3], weight;
    ElasticityForm f = ElasticityAtPoint(e, c, i, Q, &weight);
    PhysicalGradient(e->dim, dw, qdata, i, Q, B, dG);
    if (du0) PhysicalGradient(e->dim, du0, qdata, i, Q, B, G0);
    ElasticityStressIncrement(&f, G0, dG, dP);
    ElasticityOutput(&f, i, Q, qdata[i], weight, w, B, dP, out[0], out[1]);
  }
  return 0;
}
#endif
