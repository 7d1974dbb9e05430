/* Weak form of one backward-Euler step of incompressible Navier-Stokes (or Stokes):

     m (u, v) + op [ rho (((u - z) . grad) u, v) + 2 mu (D(u), D(v)) - (p, div v) - (q, div u) ]
       - load [ (f, v) + (h, v)_{Gamma_N} ]  =  m (u^{n-1}, v)_{Omega^{n-1}}

   with m = rho/dt. The right-hand side is the same form evaluated with op = load = 0
   on the previous state; the body force f and the traction h are the scene's kernels.
   The continuity row carries the minus sign so that the Stokes matrix is symmetric; an
   equal-order pair adds -op tau (grad p, grad q) to it (Brezzi-Pitkaranta). */
#include "fluid.h"

/* The mesh velocity z, an auxiliary field on moving meshes (absent on fixed ones). */
#define MESH_VELOCITY(d) (NfAux > 0 ? a[aOff[0] + (d)] : 0.0)

/* PETSc fixes the signatures of pointwise kernels; each uses a few of their arguments. */
#pragma GCC diagnostic ignored "-Wunused-parameter"

void FluidF0MassStokes(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                       const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[],
                       const PetscInt aOff_x[], const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[],
                       PetscReal t, const PetscReal x[], PetscInt numConstants, const PetscScalar constants[],
                       PetscScalar f0[])
{
  for (PetscInt c = 0; c < dim; ++c) f0[c] = constants[FLUID_MASS] * u[uOff[0] + c];
}

void FluidF0MassConvection(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                           const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[],
                           const PetscInt aOff[], const PetscInt aOff_x[], const PetscScalar a[],
                           const PetscScalar a_t[], const PetscScalar a_x[], PetscReal t, const PetscReal x[],
                           PetscInt numConstants, const PetscScalar constants[], PetscScalar f0[])
{
  const PetscScalar rho_op = constants[FLUID_RHO] * constants[FLUID_OPERATOR] * constants[FLUID_CONVECTION];

  for (PetscInt c = 0; c < dim; ++c) {
    PetscScalar convection = 0;
    for (PetscInt d = 0; d < dim; ++d) convection += (u[uOff[0] + d] - MESH_VELOCITY(d)) * u_x[uOff_x[0] + c * dim + d];
    f0[c] = constants[FLUID_MASS] * u[uOff[0] + c] + rho_op * convection;
  }
}

void FluidF1Stress(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                   const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[],
                   const PetscInt aOff_x[], const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[],
                   PetscReal t, const PetscReal x[], PetscInt numConstants, const PetscScalar constants[],
                   PetscScalar f1[])
{
  const PetscScalar mu = constants[FLUID_MU], op = constants[FLUID_OPERATOR], p = u[uOff[1]];

  for (PetscInt c = 0; c < dim; ++c)
    for (PetscInt d = 0; d < dim; ++d)
      f1[c * dim + d] = op * (mu * (u_x[uOff_x[0] + c * dim + d] + u_x[uOff_x[0] + d * dim + c]) - (c == d ? p : 0.0));
}

void FluidF0Continuity(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                       const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[],
                       const PetscInt aOff_x[], const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[],
                       PetscReal t, const PetscReal x[], PetscInt numConstants, const PetscScalar constants[],
                       PetscScalar f0[])
{
  PetscScalar divergence = 0;

  for (PetscInt d = 0; d < dim; ++d) divergence += u_x[uOff_x[0] + d * dim + d];
  f0[0] = -constants[FLUID_OPERATOR] * divergence;
}

void FluidG0MassStokes(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                       const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[],
                       const PetscInt aOff_x[], const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[],
                       PetscReal t, PetscReal u_tShift, const PetscReal x[], PetscInt numConstants,
                       const PetscScalar constants[], PetscScalar g0[])
{
  for (PetscInt c = 0; c < dim; ++c) g0[c * dim + c] = constants[FLUID_MASS];
}

void FluidG0MassConvection(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                           const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[],
                           const PetscInt aOff[], const PetscInt aOff_x[], const PetscScalar a[],
                           const PetscScalar a_t[], const PetscScalar a_x[], PetscReal t, PetscReal u_tShift,
                           const PetscReal x[], PetscInt numConstants, const PetscScalar constants[], PetscScalar g0[])
{
  const PetscScalar rho_op = constants[FLUID_RHO] * constants[FLUID_OPERATOR] * constants[FLUID_CONVECTION];

  for (PetscInt c = 0; c < dim; ++c) {
    for (PetscInt d = 0; d < dim; ++d) g0[c * dim + d] = rho_op * u_x[uOff_x[0] + c * dim + d];
    g0[c * dim + c] += constants[FLUID_MASS];
  }
}

void FluidG1Convection(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                       const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[],
                       const PetscInt aOff_x[], const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[],
                       PetscReal t, PetscReal u_tShift, const PetscReal x[], PetscInt numConstants,
                       const PetscScalar constants[], PetscScalar g1[])
{
  const PetscScalar rho_op = constants[FLUID_RHO] * constants[FLUID_OPERATOR] * constants[FLUID_CONVECTION];

  for (PetscInt c = 0; c < dim; ++c)
    for (PetscInt d = 0; d < dim; ++d) g1[(c * dim + c) * dim + d] = rho_op * (u[uOff[0] + d] - MESH_VELOCITY(d));
}

void FluidG3Viscous(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                    const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[],
                    const PetscInt aOff_x[], const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[],
                    PetscReal t, PetscReal u_tShift, const PetscReal x[], PetscInt numConstants,
                    const PetscScalar constants[], PetscScalar g3[])
{
  const PetscScalar mu_op = constants[FLUID_MU] * constants[FLUID_OPERATOR];

  for (PetscInt c = 0; c < dim; ++c)
    for (PetscInt d = 0; d < dim; ++d) {
      g3[((c * dim + c) * dim + d) * dim + d] += mu_op;
      g3[((c * dim + d) * dim + d) * dim + c] += mu_op;
    }
}

void FluidG2Pressure(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                     const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[],
                     const PetscInt aOff_x[], const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[],
                     PetscReal t, PetscReal u_tShift, const PetscReal x[], PetscInt numConstants,
                     const PetscScalar constants[], PetscScalar g2[])
{
  for (PetscInt d = 0; d < dim; ++d) g2[d * dim + d] = -constants[FLUID_OPERATOR];
}

void FluidG1Continuity(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                       const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[],
                       const PetscInt aOff_x[], const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[],
                       PetscReal t, PetscReal u_tShift, const PetscReal x[], PetscInt numConstants,
                       const PetscScalar constants[], PetscScalar g1[])
{
  for (PetscInt d = 0; d < dim; ++d) g1[d * dim + d] = -constants[FLUID_OPERATOR];
}

/* The convective boundary term the control absorbs in the seed's chapters 4-5:
   -1/2 rho ((u . n) u, v) on the interface, and its linearization. Only u and n enter,
   so PETSc's tabulation of reversed faces integrates it exactly. */
void FluidF0InterfaceConvection(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[],
                                const PetscInt uOff_x[], const PetscScalar u[], const PetscScalar u_t[],
                                const PetscScalar u_x[], const PetscInt aOff[], const PetscInt aOff_x[],
                                const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[], PetscReal t,
                                const PetscReal x[], const PetscReal n[], PetscInt numConstants,
                                const PetscScalar constants[], PetscScalar f0[])
{
  const PetscScalar half_rho = 0.5 * constants[FLUID_RHO] * constants[FLUID_OPERATOR] * constants[FLUID_CONVECTION];
  PetscScalar       un       = 0;

  for (PetscInt d = 0; d < dim; ++d) un += (u[uOff[0] + d] - MESH_VELOCITY(d)) * n[d];
  for (PetscInt c = 0; c < dim; ++c) f0[c] = -half_rho * un * u[uOff[0] + c];
}

void FluidG0InterfaceConvection(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[],
                                const PetscInt uOff_x[], const PetscScalar u[], const PetscScalar u_t[],
                                const PetscScalar u_x[], const PetscInt aOff[], const PetscInt aOff_x[],
                                const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[], PetscReal t,
                                PetscReal u_tShift, const PetscReal x[], const PetscReal n[], PetscInt numConstants,
                                const PetscScalar constants[], PetscScalar g0[])
{
  const PetscScalar half_rho = 0.5 * constants[FLUID_RHO] * constants[FLUID_OPERATOR] * constants[FLUID_CONVECTION];
  PetscScalar       un       = 0;

  for (PetscInt d = 0; d < dim; ++d) un += (u[uOff[0] + d] - MESH_VELOCITY(d)) * n[d];
  for (PetscInt c = 0; c < dim; ++c)
    for (PetscInt d = 0; d < dim; ++d) g0[c * dim + d] = -half_rho * (u[uOff[0] + c] * n[d] + (c == d ? un : 0.0));
}

/* Backflow stabilization on open boundaries: -1/2 rho ((u - z).n)_- (u, v), which cancels
   the energy a traction-free boundary lets in where the flow turns inward. */
void FluidF0Backflow(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                     const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[],
                     const PetscInt aOff_x[], const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[],
                     PetscReal t, const PetscReal x[], const PetscReal n[], PetscInt numConstants,
                     const PetscScalar constants[], PetscScalar f0[])
{
  const PetscScalar half_rho = 0.5 * constants[FLUID_RHO] * constants[FLUID_OPERATOR] * constants[FLUID_CONVECTION];
  PetscScalar       un       = 0;

  for (PetscInt d = 0; d < dim; ++d) un += (u[uOff[0] + d] - MESH_VELOCITY(d)) * n[d];
  if (PetscRealPart(un) >= 0) return;
  for (PetscInt c = 0; c < dim; ++c) f0[c] -= half_rho * un * u[uOff[0] + c];
}

void FluidG0Backflow(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                     const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[],
                     const PetscInt aOff_x[], const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[],
                     PetscReal t, PetscReal u_tShift, const PetscReal x[], const PetscReal n[], PetscInt numConstants,
                     const PetscScalar constants[], PetscScalar g0[])
{
  const PetscScalar half_rho = 0.5 * constants[FLUID_RHO] * constants[FLUID_OPERATOR] * constants[FLUID_CONVECTION];
  PetscScalar       un       = 0;

  for (PetscInt d = 0; d < dim; ++d) un += (u[uOff[0] + d] - MESH_VELOCITY(d)) * n[d];
  if (PetscRealPart(un) >= 0) return;
  for (PetscInt c = 0; c < dim; ++c)
    for (PetscInt d = 0; d < dim; ++d) g0[c * dim + d] -= half_rho * (u[uOff[0] + c] * n[d] + (c == d ? un : 0.0));
}

void FluidF1PressureStabilization(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[],
                                  const PetscInt uOff_x[], const PetscScalar u[], const PetscScalar u_t[],
                                  const PetscScalar u_x[], const PetscInt aOff[], const PetscInt aOff_x[],
                                  const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[], PetscReal t,
                                  const PetscReal x[], PetscInt numConstants, const PetscScalar constants[],
                                  PetscScalar f1[])
{
  const PetscScalar tau = constants[FLUID_OPERATOR] * constants[FLUID_PRESSURE_STABILIZATION];

  for (PetscInt d = 0; d < dim; ++d) f1[d] = -tau * u_x[uOff_x[1] + d];
}

void FluidG3PressureStabilization(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[],
                                  const PetscInt uOff_x[], const PetscScalar u[], const PetscScalar u_t[],
                                  const PetscScalar u_x[], const PetscInt aOff[], const PetscInt aOff_x[],
                                  const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[], PetscReal t,
                                  PetscReal u_tShift, const PetscReal x[], PetscInt numConstants,
                                  const PetscScalar constants[], PetscScalar g3[])
{
  const PetscScalar tau = constants[FLUID_OPERATOR] * constants[FLUID_PRESSURE_STABILIZATION];

  for (PetscInt d = 0; d < dim; ++d) g3[d * dim + d] = -tau;
}
