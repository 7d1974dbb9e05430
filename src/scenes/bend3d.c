/* Scene bend3d: the pressure pulse of tube3d in a tube with a curved axis, on tetrahedra,
   the shape a haemodynamics user brings. The axis (meshes/bend3d-path.geoinc): 1 straight
   along +z, a 90-degree bend of axis radius 1.5 about the line x = 1.5, z = 1 (along y),
   1 straight along +x; fluid r <= 0.5 around it, wall 0.5 <= r <= 0.6 (bend3d-fluid.geo,
   bend3d-wall.geo, conforming on r = 0.5). The pulse, the materials and the boundary
   conditions: pressure_pulse.c. */
#include "scene.h"

PetscErrorCode SceneCreate_Bend3D(Scene *scene)
{
  const PetscReal straight = 1.0, bend_radius = 1.5, r = 0.5, c = PetscSqrtReal(0.5);

  PetscFunctionBeginUser;
  PetscCall(ScenePressurePulse(scene, "bend3d-fluid.msh", "bend3d-wall.msh"));
  /* the wall's displacement at vertices of the interface (y = 0, in the bend's plane):
     half-way along the inlet, on the outside and the inside of the bend half-way round
     it, and half-way along the outlet on the outside */
  scene->n_probes     = 4;
  scene->probes[0][0] = -r;
  scene->probes[0][2] = straight / 2;
  scene->probes[1][0] = bend_radius - (bend_radius + r) * c;
  scene->probes[1][2] = straight + (bend_radius + r) * c;
  scene->probes[2][0] = bend_radius - (bend_radius - r) * c;
  scene->probes[2][2] = straight + (bend_radius - r) * c;
  scene->probes[3][0] = bend_radius + straight / 2;
  scene->probes[3][2] = straight + bend_radius + r;
  PetscFunctionReturn(0);
}
