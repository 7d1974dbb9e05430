/* Scene tube3d (seed §6.5, Figs 6.3-6.4, Table 6.1): a pressure wave in a straight tube.
   Fluid: the cylinder r <= 0.5, z in [0, 5]; wall: the annulus 0.5 <= r <= 0.6 around it
   (meshes/tube3d-fluid.geo, tube3d-wall.geo: hexahedra, conforming on r = 0.5). An
   overpressure P = 1.333e4 dyn/cm^2 acts on the inlet z = 0 for t <= 0.003 s, the outlet
   z = 5 is traction-free, the wall's ends are clamped and its outside traction-free.
   cgs units; rho = 1, mu = 0.03, rho_s = 1.2, E = 3e6, nu_s = 0.3 (DESIGN §4). The fluid
   mesh follows the wall, its inlet and outlet discs staying put. */
#include "scene.h"
#include "fluid.h"
#include "options.h"

#pragma GCC diagnostic ignored "-Wunused-parameter"

enum {
  INLET_PRESSURE = FLUID_NUM_CONSTANTS,
  INLET_DURATION
};

/* the overpressure on the inlet disc: the traction -P n = P e_z there */
static void InletTraction(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                          const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[],
                          const PetscInt aOff[], const PetscInt aOff_x[], const PetscScalar a[],
                          const PetscScalar a_t[], const PetscScalar a_x[], PetscReal t, const PetscReal x[],
                          const PetscReal n[], PetscInt numConstants, const PetscScalar constants[], PetscScalar f0[])
{
  const PetscReal time = PetscRealPart(constants[FLUID_TIME]);

  if (time <= PetscRealPart(constants[INLET_DURATION]) * (1 + 1e-12))
    f0[2] -= constants[FLUID_LOAD] * constants[INLET_PRESSURE];
}

PetscErrorCode SceneCreate_Tube3D(Scene *scene)
{
  PhysicsData *fluid    = &scene->fluid;
  PetscReal    pressure = 1.333e4, duration = 0.003;

  PetscFunctionBeginUser;
  scene->dim   = 3;
  scene->units = "cgs";
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Scene tube3d: the pressure wave in a straight tube", "scene");
  PetscCall(OptionsNonNegativeReal(PetscOptionsObject, "-tube_inlet_pressure", "overpressure P on the inlet, dyn/cm^2",
                                   &pressure));
  PetscCall(
    OptionsPositiveReal(PetscOptionsObject, "-tube_inlet_duration", "how long the overpressure acts, s", &duration));
  PetscOptionsEnd();
  PetscCall(SceneSetDefaultMesh("-fluid_dm_plex_filename", "tube3d-fluid.msh"));
  PetscCall(SceneSetDefaultMesh("-structure_dm_plex_filename", "tube3d-wall.msh"));
  PetscCall(OptionsSetDefault("-fluid_density", "1.0"));
  PetscCall(OptionsSetDefault("-fluid_viscosity", "0.03"));
  PetscCall(OptionsSetDefault("-structure_density", "1.2"));
  PetscCall(OptionsSetDefault("-structure_youngs_modulus", "3e6"));
  PetscCall(OptionsSetDefault("-structure_poisson_ratio", "0.3"));

  scene->has_fluid           = PETSC_TRUE;
  fluid->n_traction          = 2;
  fluid->traction_faces[0]   = FACE_LEFT; /* z = 0 */
  fluid->traction_kernel[0]  = InletTraction;
  fluid->traction_faces[1]   = FACE_RIGHT; /* z = 5, traction-free */
  fluid->interface_face      = FACE_TOP;   /* r = 0.5 */
  fluid->n_fixed_mesh_faces  = 2;
  fluid->fixed_mesh_faces[0] = FACE_LEFT;
  fluid->fixed_mesh_faces[1] = FACE_RIGHT;
  fluid->n_extra             = 2;
  fluid->extra[0]            = pressure;
  fluid->extra[1]            = duration;

  /* the wall: ends clamped, outside (r = 0.6) traction-free, inside (r = 0.5) on the fluid */
  PetscCall(SceneClampedWall(scene));

  /* the wall's displacement at (0.5, 0) a quarter, half and three quarters down the tube */
  scene->n_probes = 3;
  for (PetscInt i = 0; i < 3; ++i) {
    scene->probes[i][0] = 0.5;
    scene->probes[i][1] = 0.0;
    scene->probes[i][2] = 1.25 * (i + 1);
  }
  PetscFunctionReturn(0);
}
