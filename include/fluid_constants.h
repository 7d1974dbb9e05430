#ifndef FSIOPT_FLUID_CONSTANTS_H
#define FSIOPT_FLUID_CONSTANTS_H
/* The layout of the fluid's constants: one contract between the fluid's PetscDS kernels
   (src/fluid/), the scenes' kernels and the libCEED fluid's context (src/ceed/). */
/* Constants handed to the fluid's pointwise kernels; scene kernels read them too.
   MASS is the coefficient of (u, v) (rho/dt in a step), OPERATOR and LOAD switch the
   spatial operator and the data on and off, so one weak form also yields the
   old-domain mass term M(Omega^{n-1}) u^{n-1}. */
enum {
  FLUID_RHO,
  FLUID_MU,
  FLUID_MASS,
  FLUID_OPERATOR,
  FLUID_LOAD,
  FLUID_TIME,
  FLUID_DT,
  FLUID_CONVECTION,
  FLUID_PROJECTION,
  FLUID_PRESSURE_STABILIZATION,
  FLUID_NUM_CONSTANTS
};
#endif
