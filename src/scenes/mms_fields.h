/* Closed-form manufactured fields, written once and used both by the scene callbacks
   (projection, Dirichlet data, error norms) and inside pointwise kernels (forcing,
   traction). With a = x + t, b = y + t:

   fluid (divergence free, with a convective term that does not vanish):
     u = (sin a cos b, -cos a sin b),  p = sin a sin b
   structure (the seed's eq. 5.76 / 3.22 displacement, divergence free):
     eta = (sin a sin b, cos a cos b) */
#ifndef FSIOPT_MMS_FIELDS_H
#define FSIOPT_MMS_FIELDS_H
#include <petscsys.h>

static inline void MMSFluidVelocity(PetscReal t, const PetscReal x[], PetscScalar u[])
{
  const PetscReal a = x[0] + t, b = x[1] + t;
  u[0] = PetscSinReal(a) * PetscCosReal(b);
  u[1] = -PetscCosReal(a) * PetscSinReal(b);
}

static inline PetscScalar MMSFluidPressure(PetscReal t, const PetscReal x[])
{
  return PetscSinReal(x[0] + t) * PetscSinReal(x[1] + t);
}

/* g[c*2 + d] = d u_c / d x_d */
static inline void MMSFluidVelocityGradient(PetscReal t, const PetscReal x[], PetscScalar g[])
{
  const PetscReal a = x[0] + t, b = x[1] + t;
  g[0] = PetscCosReal(a) * PetscCosReal(b);
  g[1] = -PetscSinReal(a) * PetscSinReal(b);
  g[2] = PetscSinReal(a) * PetscSinReal(b);
  g[3] = -PetscCosReal(a) * PetscCosReal(b);
}

/* rho (du/dt + (u . grad) u): the body force plus div sigma. When `discrete_time`,
   du/dt is replaced by the backward difference (u(t) - u(t-dt))/dt, so that the exact
   field also solves the time-discrete problem: the error left is the spatial one. */
static inline void MMSFluidInertia(PetscReal t, const PetscReal x[], PetscReal rho, PetscBool convection,
                                   PetscBool discrete_time, PetscReal dt, PetscScalar f[])
{
  const PetscReal a = x[0] + t, b = x[1] + t;
  PetscScalar     u[2], dudt[2];

  MMSFluidVelocity(t, x, u);
  if (discrete_time) {
    PetscScalar u_old[2];
    MMSFluidVelocity(t - dt, x, u_old);
    dudt[0] = (u[0] - u_old[0]) / dt;
    dudt[1] = (u[1] - u_old[1]) / dt;
  } else {
    dudt[0] = PetscCosReal(a + b);
    dudt[1] = -PetscCosReal(a + b);
  }
  f[0] = rho * dudt[0];
  f[1] = rho * dudt[1];
  if (convection) {
    f[0] += rho * PetscSinReal(a) * PetscCosReal(a);
    f[1] += rho * PetscSinReal(b) * PetscCosReal(b);
  }
}

static inline void MMSStructureDisplacement(PetscReal t, const PetscReal x[], PetscScalar eta[])
{
  const PetscReal a = x[0] + t, b = x[1] + t;
  eta[0] = PetscSinReal(a) * PetscSinReal(b);
  eta[1] = PetscCosReal(a) * PetscCosReal(b);
}

static inline void MMSStructureVelocity(PetscReal t, const PetscReal x[], PetscScalar etadot[])
{
  const PetscReal s = PetscSinReal(x[0] + x[1] + 2.0 * t);
  etadot[0]         = s;
  etadot[1]         = -s;
}

static inline void MMSStructureDisplacementGradient(PetscReal t, const PetscReal x[], PetscScalar g[])
{
  const PetscReal a = x[0] + t, b = x[1] + t;
  g[0] = PetscCosReal(a) * PetscSinReal(b);
  g[1] = PetscSinReal(a) * PetscCosReal(b);
  g[2] = -PetscSinReal(a) * PetscCosReal(b);
  g[3] = -PetscCosReal(a) * PetscSinReal(b);
}

/* rho_s d2eta/dt2: the body force plus div sigma */
static inline void MMSStructureInertia(PetscReal t, const PetscReal x[], PetscReal rho, PetscScalar f[])
{
  const PetscReal c = PetscCosReal(x[0] + x[1] + 2.0 * t);
  f[0]              = 2.0 * rho * c;
  f[1]              = -2.0 * rho * c;
}
#endif
