/* Weak form of one step of elastodynamics in displacement eta:

     m (eta, xi) + op (P(eta), grad xi) - load [ (f_s, xi) + (h, xi)_{Gamma_N} ]
       =  right-hand side of the scheme,

   where m = rho_s/dt^2 (first order, seed eq. 2.42) or 4 rho_s/dt^2 (midpoint,
   seed eqs. 2.40-2.41 with the velocity eliminated; for St. Venant-Kirchhoff eq. 6.17,
   the stresses of both ends averaged) and P the stress of the model:
     linear: sigma = 2 mu_s eps(eta) + lambda (div eta) I,
     St. Venant-Kirchhoff: P = F Sigma, F = I + grad eta, Sigma = lambda tr(E) I + 2 mu_s E,
       E = (F^T F - I)/2 (seed eq. 6.7). */
#include "structure.h"

/* PETSc fixes the signatures of pointwise kernels; each uses a few of their arguments. */
#pragma GCC diagnostic ignored "-Wunused-parameter"

/* The point's material: with materials per region (structure_materials.c) the auxiliary field
   (rho/rho_s, mu, lambda, model), else the constants and the kernel's own model. */
typedef struct {
  StructureModel model;
  PetscReal      density_scale, mu, lambda;
} PointMaterial;

static inline PointMaterial MaterialAt(StructureModel model, PetscInt NfAux, const PetscInt aOff[],
                                       const PetscScalar a[], const PetscScalar constants[])
{
  PointMaterial m = {model, 1.0, PetscRealPart(constants[STRUCTURE_MU]), PetscRealPart(constants[STRUCTURE_LAMBDA])};

  if (NfAux > 0) {
    const PetscScalar *v = &a[aOff[0]];
    m.density_scale      = PetscRealPart(v[0]);
    m.mu                 = PetscRealPart(v[1]);
    m.lambda             = PetscRealPart(v[2]);
    m.model              = PetscRealPart(v[3]) > 0.5 ? STRUCTURE_SVK : STRUCTURE_LINEAR;
  }
  return m;
}

void StructureF0Mass(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                     const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[],
                     const PetscInt aOff_x[], const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[],
                     PetscReal t, const PetscReal x[], PetscInt numConstants, const PetscScalar constants[],
                     PetscScalar f0[])
{
  const PetscScalar mass = constants[STRUCTURE_MASS] * MaterialAt(STRUCTURE_LINEAR, NfAux, aOff, a, constants).density_scale;

  for (PetscInt c = 0; c < dim; ++c) f0[c] = mass * u[uOff[0] + c];
}

void StructureF1LinearStress(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                             const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[],
                             const PetscInt aOff[], const PetscInt aOff_x[], const PetscScalar a[],
                             const PetscScalar a_t[], const PetscScalar a_x[], PetscReal t, const PetscReal x[],
                             PetscInt numConstants, const PetscScalar constants[], PetscScalar f1[])
{
  const PetscScalar   op = constants[STRUCTURE_OPERATOR];
  const PointMaterial m  = MaterialAt(STRUCTURE_LINEAR, NfAux, aOff, a, constants);
  PetscScalar         sigma[9];

  StructureStress(m.model, dim, m.mu, m.lambda, &u_x[uOff_x[0]], sigma);
  for (PetscInt i = 0; i < dim * dim; ++i) f1[i] = op * sigma[i];
}

/* F = I + G and the second Piola stress S = lambda tr(E) I + 2 mu_s E, E = (F^T F - I)/2 */
static void SVKDeformation(PetscInt dim, PetscScalar mu, PetscScalar lambda, const PetscScalar G[], PetscScalar F[],
                           PetscScalar S[])
{
  PetscScalar trace = 0;

  for (PetscInt i = 0; i < dim * dim; ++i) F[i] = G[i] + (i % (dim + 1) == 0 ? 1.0 : 0.0);
  for (PetscInt k = 0; k < dim; ++k) /* S = 2 mu E for now */
    for (PetscInt d = 0; d < dim; ++d) {
      PetscScalar ftf = 0;
      for (PetscInt a = 0; a < dim; ++a) ftf += F[a * dim + k] * F[a * dim + d];
      S[k * dim + d] = mu * (ftf - (k == d ? 1.0 : 0.0));
    }
  for (PetscInt d = 0; d < dim; ++d) trace += S[d * dim + d] / (2 * mu);
  for (PetscInt d = 0; d < dim; ++d) S[d * dim + d] += lambda * trace;
}

void StructureStress(StructureModel model, PetscInt dim, PetscReal mu, PetscReal lambda, const PetscScalar G[],
                     PetscScalar P[])
{
  PetscScalar F[9], S[9], trace = 0;

  if (model == STRUCTURE_LINEAR) {
    for (PetscInt d = 0; d < dim; ++d) trace += G[d * dim + d];
    for (PetscInt c = 0; c < dim; ++c)
      for (PetscInt d = 0; d < dim; ++d)
        P[c * dim + d] = mu * (G[c * dim + d] + G[d * dim + c]) + (c == d ? lambda * trace : 0.0);
    return;
  }
  SVKDeformation(dim, mu, lambda, G, F, S);
  for (PetscInt c = 0; c < dim; ++c)
    for (PetscInt d = 0; d < dim; ++d) {
      P[c * dim + d] = 0;
      for (PetscInt k = 0; k < dim; ++k) P[c * dim + d] += F[c * dim + k] * S[k * dim + d];
    }
}

void StructureF1SVKStress(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                          const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[],
                          const PetscInt aOff[], const PetscInt aOff_x[], const PetscScalar a[],
                          const PetscScalar a_t[], const PetscScalar a_x[], PetscReal t, const PetscReal x[],
                          PetscInt numConstants, const PetscScalar constants[], PetscScalar f1[])
{
  const PetscScalar   op = constants[STRUCTURE_OPERATOR];
  const PointMaterial m  = MaterialAt(STRUCTURE_SVK, NfAux, aOff, a, constants);
  PetscScalar         P[9];

  StructureStress(m.model, dim, m.mu, m.lambda, &u_x[uOff_x[0]], P);
  for (PetscInt i = 0; i < dim * dim; ++i) f1[i] = op * P[i];
}

void StructureG0Mass(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                     const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[],
                     const PetscInt aOff_x[], const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[],
                     PetscReal t, PetscReal u_tShift, const PetscReal x[], PetscInt numConstants,
                     const PetscScalar constants[], PetscScalar g0[])
{
  const PetscScalar mass = constants[STRUCTURE_MASS] * MaterialAt(STRUCTURE_LINEAR, NfAux, aOff, a, constants).density_scale;

  for (PetscInt c = 0; c < dim; ++c) g0[c * dim + c] = mass;
}

/* op dP/dG at G of the point's material */
static void Tangent(PointMaterial m, PetscInt dim, PetscScalar op, const PetscScalar G[], PetscScalar g3[]);

void StructureG3LinearElasticity(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[],
                                 const PetscInt uOff_x[], const PetscScalar u[], const PetscScalar u_t[],
                                 const PetscScalar u_x[], const PetscInt aOff[], const PetscInt aOff_x[],
                                 const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[], PetscReal t,
                                 PetscReal u_tShift, const PetscReal x[], PetscInt numConstants,
                                 const PetscScalar constants[], PetscScalar g3[])
{
  Tangent(MaterialAt(STRUCTURE_LINEAR, NfAux, aOff, a, constants), dim, constants[STRUCTURE_OPERATOR],
          &u_x[uOff_x[0]], g3);
}

/* dP_cd/dG_ef = delta_ce S_fd + lambda F_cd F_ef + mu_s F_cf F_ed + mu_s (F F^T)_ce delta_df
   (seed eq. 6.19), at g3[test c][trial e][test derivative d][trial derivative f]. */
void StructureG3SVK(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                    const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[],
                    const PetscInt aOff_x[], const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[],
                    PetscReal t, PetscReal u_tShift, const PetscReal x[], PetscInt numConstants,
                    const PetscScalar constants[], PetscScalar g3[])
{
  Tangent(MaterialAt(STRUCTURE_SVK, NfAux, aOff, a, constants), dim, constants[STRUCTURE_OPERATOR], &u_x[uOff_x[0]],
          g3);
}

static void Tangent(PointMaterial m, PetscInt dim, PetscScalar op, const PetscScalar G[], PetscScalar g3[])
{
  const PetscScalar mu = m.mu, lambda = m.lambda;
  PetscScalar       F[9], S[9], FFt[9];

  if (m.model == STRUCTURE_LINEAR) {
    for (PetscInt c = 0; c < dim; ++c)
      for (PetscInt d = 0; d < dim; ++d) {
        g3[((c * dim + c) * dim + d) * dim + d] += op * mu;
        g3[((c * dim + d) * dim + d) * dim + c] += op * mu;
        g3[((c * dim + d) * dim + c) * dim + d] += op * lambda;
      }
    return;
  }
  SVKDeformation(dim, mu, lambda, G, F, S);
  for (PetscInt k = 0; k < dim; ++k)
    for (PetscInt d = 0; d < dim; ++d) {
      FFt[k * dim + d] = 0;
      for (PetscInt a = 0; a < dim; ++a) FFt[k * dim + d] += F[k * dim + a] * F[d * dim + a];
    }
  for (PetscInt c = 0; c < dim; ++c)
    for (PetscInt e = 0; e < dim; ++e)
      for (PetscInt d = 0; d < dim; ++d)
        for (PetscInt f = 0; f < dim; ++f) {
          PetscScalar v = lambda * F[c * dim + d] * F[e * dim + f] + mu * F[c * dim + f] * F[e * dim + d];
          if (c == e) v += S[f * dim + d];
          if (d == f) v += mu * FFt[c * dim + e];
          g3[((c * dim + e) * dim + d) * dim + f] += op * v;
        }
}

/* The Cauchy stress as a 3 x 3 tensor, for output: sigma = J^-1 P F^T (P = sigma for the
   linear model); in 2D the plane strain's sigma_zz, lambda div eta (linear) or
   J^-1 lambda tr E (St. Venant-Kirchhoff, F_zz = 1). */
void StructureCauchyStress(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                           const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[],
                           const PetscInt aOff_x[], const PetscScalar a[], const PetscScalar a_t[],
                           const PetscScalar a_x[], PetscReal t, const PetscReal x[], PetscInt numConstants,
                           const PetscScalar constants[], PetscScalar f[])
{
  const PointMaterial m = MaterialAt((StructureModel)PetscRealPart(constants[STRUCTURE_MODEL]), NfAux, aOff, a, constants);
  const PetscScalar  *G = &u_x[uOff_x[0]];
  PetscScalar         P[9], F[9], J = 1, zz = 0;

  for (PetscInt i = 0; i < 9; ++i) f[i] = 0;
  StructureStress(m.model, dim, m.mu, m.lambda, G, P);
  for (PetscInt i = 0; i < dim * dim; ++i) F[i] = G[i] + (i % (dim + 1) == 0 ? 1.0 : 0.0);
  if (m.model == STRUCTURE_LINEAR) {
    for (PetscInt c = 0; c < dim; ++c)
      for (PetscInt d = 0; d < dim; ++d) f[c * 3 + d] = P[c * dim + d];
    for (PetscInt d = 0; d < dim; ++d) zz += m.lambda * G[d * dim + d];
  } else {
    PetscScalar trace = 0;
    J = dim == 2 ? F[0] * F[3] - F[1] * F[2]
                 : F[0] * (F[4] * F[8] - F[5] * F[7]) - F[1] * (F[3] * F[8] - F[5] * F[6]) + F[2] * (F[3] * F[7] - F[4] * F[6]);
    for (PetscInt c = 0; c < dim; ++c)
      for (PetscInt d = 0; d < dim; ++d) {
        PetscScalar s = 0;
        for (PetscInt k = 0; k < dim; ++k) s += P[c * dim + k] * F[d * dim + k];
        f[c * 3 + d] = s / J;
      }
    for (PetscInt c = 0; c < dim * dim; ++c) trace += F[c] * F[c];
    zz = m.lambda * (trace - dim) / 2 / J;
  }
  if (dim == 2) f[8] = zz;
}
