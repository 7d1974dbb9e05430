/* The seed's manufactured FSI solution (eqs. 3.22 and 5.76, after Astorino and Grandmont),
   shared by the scenes mms-stokes and mms-ns. With a = x + t, b = y + t, s = sin(a + b),
   c = cos(a + b), on Omega_f = [0,1]^2 and Omega_s = [0,1] x [1,1.5]:

     u   = (s, -s)                                   (= d eta/dt, so velocities match everywhere)
     p   = 2 mu (sin a sin b - cos a cos b) + 2 mu_s cos a sin b
     eta = (sin a sin b, cos a cos b)

   The seed's text lost its digit 2: these are the factors that make sigma_f n = sigma_s n
   on y = 1 (checked in the scene's comment). Its fluid viscosity was lost entirely; we
   read it as mu = 2 (-fluid_viscosity). */
#ifndef FSIOPT_MMS_FSI_H
#define FSIOPT_MMS_FSI_H
#include "scene.h"

PetscErrorCode SceneCreate_MMSFSI(Scene *, const char fluid_model[]);
#endif
