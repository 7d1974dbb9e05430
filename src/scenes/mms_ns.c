/* Scene mms-ns (seed §5.6, Tables 5.1-5.6): Navier-Stokes (Eulerian, z = 0) + linear
   elasticity against the manufactured solution of mms_fsi.h; single-step spatial
   convergence at t0 = 0.5 and 0.8, space-time convergence on [0.5, 1]. */
#include "mms_fsi.h"

PetscErrorCode SceneCreate_MMSNS(Scene *scene)
{
  PetscFunctionBeginUser;
  scene->dim = 2;
  PetscCall(SceneCreate_MMSFSI(scene, "navier-stokes"));
  PetscFunctionReturn(0);
}
