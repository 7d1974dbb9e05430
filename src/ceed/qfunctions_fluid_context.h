/* The context of the fluid's libCEED pointwise functions (qfunctions_fluid.h,
   qfunctions_fluid_faces.h): the constants of the weak form and what the operators hold. */
#ifndef FSIOPT_QFUNCTIONS_FLUID_CONTEXT_H
#define FSIOPT_QFUNCTIONS_FLUID_CONTEXT_H
#include <ceed.h>

typedef struct {
  CeedInt    dim;
  CeedScalar rho, mu, mass, op, convection;
  CeedScalar tau;      /* op times the pressure stabilization's tau; 0: none */
  CeedInt    moving;   /* the last inputs are the mesh velocity z and the old domains' mass weights m */
  CeedInt    old_mass; /* the residual adds m u (moving meshes) */
} FluidVolume;
/* the convecting velocity u - z, component d at point i */
#define CONVECTING(u, z, d, i, Q) ((u)[(d) * (Q) + (i)] - ((z) ? (z)[(d) * (Q) + (i)] : 0.0))
#endif
