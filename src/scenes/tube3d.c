/* Scene tube3d (seed §6.5, Figs 6.3-6.4, Table 6.1): a pressure wave in a straight tube.
   Fluid: the cylinder r <= 0.5, z in [0, 5]; wall: the annulus 0.5 <= r <= 0.6 around it
   (meshes/tube3d-fluid.geo, tube3d-wall.geo: hexahedra, conforming on r = 0.5). The
   pulse, the materials and the boundary conditions: pressure_pulse.c. */
#include "scene.h"

PetscErrorCode SceneCreate_Tube3D(Scene *scene)
{
  PetscFunctionBeginUser;
  PetscCall(ScenePressurePulse(scene, "tube3d-fluid.msh", "tube3d-wall.msh"));
  /* the wall's displacement at (0.5, 0) a quarter, half and three quarters down the tube */
  scene->n_probes = 3;
  for (PetscInt i = 0; i < 3; ++i) {
    scene->probes[i][0] = 0.5;
    scene->probes[i][1] = 0.0;
    scene->probes[i][2] = 1.25 * (i + 1);
  }
  PetscFunctionReturn(0);
}
