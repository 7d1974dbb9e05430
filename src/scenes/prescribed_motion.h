/* A smooth interior mesh motion for scenes that test moving meshes on [0,1]^2:
   d = A sin(pi x) sin(pi y) sin(omega t) (1, -1/2), zero on the boundary of the square. */
#ifndef FSIOPT_PRESCRIBED_MOTION_H
#define FSIOPT_PRESCRIBED_MOTION_H
#include <petscsys.h>

static inline void PrescribedMotion(PetscReal amplitude, PetscReal omega, PetscReal t, const PetscReal x[],
                                    PetscScalar d[])
{
  const PetscReal s = amplitude * PetscSinReal(PETSC_PI * x[0]) * PetscSinReal(PETSC_PI * x[1]) *
                      PetscSinReal(omega * t);
  d[0] = s;
  d[1] = -0.5 * s;
}
#endif
