/* The pressure pulse into an elastic tube, shared by tube3d (straight) and bend3d (curved
   axis): an overpressure P on the inlet for a while, a traction-free outlet, the wall's
   ends clamped and its outside traction-free; cgs units, blood-like fluid and an arterial
   wall (seed §6.5, docs/design.md §4). The fluid mesh follows the wall, its inlet and outlet
   discs staying put. Face sets (the .geo files): fluid 4 inlet, 2 outlet, 3 interface;
   wall 1 interface, 3 outside, 4 and 2 its ends. */
#include "scene.h"
#include "fluid.h"
#include "options.h"

#pragma GCC diagnostic ignored "-Wunused-parameter"

enum {
  INLET_PRESSURE = FLUID_NUM_CONSTANTS,
  INLET_DURATION
};

/* the overpressure on the inlet: the traction -P n, on a disc of any orientation */
static void InletTraction(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                          const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[],
                          const PetscInt aOff[], const PetscInt aOff_x[], const PetscScalar a[],
                          const PetscScalar a_t[], const PetscScalar a_x[], PetscReal t, const PetscReal x[],
                          const PetscReal n[], PetscInt numConstants, const PetscScalar constants[], PetscScalar f0[])
{
  const PetscReal time = PetscRealPart(constants[FLUID_TIME]);

  if (time <= PetscRealPart(constants[INLET_DURATION]) * (1 + 1e-12))
    for (PetscInt d = 0; d < dim; ++d) f0[d] += constants[FLUID_LOAD] * constants[INLET_PRESSURE] * n[d];
}

PetscErrorCode ScenePressurePulse(Scene *scene, const char fluid_mesh[], const char wall_mesh[])
{
  PhysicsData *fluid    = &scene->fluid;
  PetscReal    pressure = 1.333e4, duration = 0.003;
  char         title[128];

  PetscFunctionBeginUser;
  scene->dim   = 3;
  scene->units = "cgs";
  PetscCall(PetscSNPrintf(title, sizeof(title), "Scene %s: a pressure pulse into an elastic tube", scene->name));
  PetscCall(OptionsDeclareHelpGroup("tube_"));
  PetscCall(OptionsDeclareUnit("-tube_inlet_pressure", UNIT_PRESSURE));
  PetscCall(OptionsDeclareUnit("-tube_inlet_duration", UNIT_TIME));
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, title, "scene");
  PetscCall(OptionsNonNegativeReal(PetscOptionsObject, "-tube_inlet_pressure", "overpressure P on the inlet, dyn/cm^2",
                                   &pressure));
  PetscCall(
    OptionsPositiveReal(PetscOptionsObject, "-tube_inlet_duration", "how long the overpressure acts, s", &duration));
  PetscOptionsEnd();
  PetscCall(SceneSetDefaultMesh("-fluid_dm_plex_filename", fluid_mesh));
  PetscCall(SceneSetDefaultMesh("-structure_dm_plex_filename", wall_mesh));
  PetscCall(OptionsSetDefault("-fluid_density", "1.0"));
  PetscCall(OptionsSetDefault("-fluid_viscosity", "0.03"));
  PetscCall(OptionsSetDefault("-structure_density", "1.2"));
  PetscCall(OptionsSetDefault("-structure_youngs_modulus", "3e6"));
  PetscCall(OptionsSetDefault("-structure_poisson_ratio", "0.3"));

  scene->has_fluid           = PETSC_TRUE;
  fluid->n_traction          = 2;
  fluid->traction_faces[0]   = FACE_LEFT; /* the inlet */
  fluid->traction_kernel[0]  = InletTraction;
  fluid->traction_faces[1]   = FACE_RIGHT; /* the outlet, traction-free */
  fluid->interface_face      = FACE_TOP;
  fluid->n_fixed_mesh_faces  = 2;
  fluid->fixed_mesh_faces[0] = FACE_LEFT;
  fluid->fixed_mesh_faces[1] = FACE_RIGHT;
  fluid->n_extra             = 2;
  fluid->extra[0]            = pressure;
  fluid->extra[1]            = duration;
  PetscCall(SceneClampedWall(scene));
  PetscFunctionReturn(0);
}
