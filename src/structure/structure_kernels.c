/* Weak form of one step of linear elastodynamics in displacement eta:

     m (eta, xi) + op [ 2 mu_s (eps(eta), eps(xi)) + lambda (div eta, div xi) ]
       - load [ (f_s, xi) + (h, xi)_{Gamma_N} ]  =  right-hand side of the scheme,

   where m = rho_s/dt^2 (first order, seed eq. 2.42) or 4 rho_s/dt^2 (midpoint,
   seed eqs. 2.40-2.41 with the velocity eliminated). */
#include "structure.h"

/* PETSc fixes the signatures of pointwise kernels; each uses a few of their arguments. */
#pragma GCC diagnostic ignored "-Wunused-parameter"


void StructureF0Mass(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[], const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[], const PetscInt aOff_x[], const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[], PetscReal t, const PetscReal x[], PetscInt numConstants, const PetscScalar constants[], PetscScalar f0[])
{
  for (PetscInt c = 0; c < dim; ++c) f0[c] = constants[STRUCTURE_MASS] * u[uOff[0] + c];
}

void StructureF1LinearStress(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[], const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[], const PetscInt aOff_x[], const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[], PetscReal t, const PetscReal x[], PetscInt numConstants, const PetscScalar constants[], PetscScalar f1[])
{
  const PetscScalar op = constants[STRUCTURE_OPERATOR], mu = constants[STRUCTURE_MU], lambda = constants[STRUCTURE_LAMBDA];
  PetscScalar       divergence = 0;

  for (PetscInt d = 0; d < dim; ++d) divergence += u_x[uOff_x[0] + d * dim + d];
  for (PetscInt c = 0; c < dim; ++c)
    for (PetscInt d = 0; d < dim; ++d) f1[c * dim + d] = op * (mu * (u_x[uOff_x[0] + c * dim + d] + u_x[uOff_x[0] + d * dim + c]) + (c == d ? lambda * divergence : 0.0));
}


void StructureG0Mass(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[], const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[], const PetscInt aOff_x[], const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[], PetscReal t, PetscReal u_tShift, const PetscReal x[], PetscInt numConstants, const PetscScalar constants[], PetscScalar g0[])
{
  for (PetscInt c = 0; c < dim; ++c) g0[c * dim + c] = constants[STRUCTURE_MASS];
}

void StructureG3LinearElasticity(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[], const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[], const PetscInt aOff_x[], const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[], PetscReal t, PetscReal u_tShift, const PetscReal x[], PetscInt numConstants, const PetscScalar constants[], PetscScalar g3[])
{
  const PetscScalar op = constants[STRUCTURE_OPERATOR], mu = op * constants[STRUCTURE_MU], lambda = op * constants[STRUCTURE_LAMBDA];

  for (PetscInt c = 0; c < dim; ++c)
    for (PetscInt d = 0; d < dim; ++d) {
      g3[((c * dim + c) * dim + d) * dim + d] += mu;
      g3[((c * dim + d) * dim + d) * dim + c] += mu;
      g3[((c * dim + d) * dim + c) * dim + d] += lambda;
    }
}
