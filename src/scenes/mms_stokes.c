/* Scene mms-stokes (seed §3.6.2, Fig 3.7): Stokes + linear elasticity on fixed domains
   against the manufactured solution of mms_fsi.h; time-step convergence on [0.5, 1]. */
#include "mms_fsi.h"

PetscErrorCode SceneCreate_MMSStokes(Scene *scene)
{
  PetscFunctionBeginUser;
  scene->dim = 2;
  PetscCall(SceneCreate_MMSFSI(scene, "stokes"));
  PetscFunctionReturn(0);
}
