/* Scene mms-structure: the structure alone on [0,1]x[1,1.5] against the seed's
   manufactured displacement (src/scenes/mms_fields.h). Dirichlet data on the left,
   right and top sides, the exact traction on the bottom side (the interface). */
#include "scene.h"
#include "structure.h"
#include "options.h"
#include "mms_fields.h"

/* PETSc fixes the signatures of pointwise kernels and callbacks; most use a few of their arguments. */
#pragma GCC diagnostic ignored "-Wunused-parameter"

static PetscErrorCode Displacement(PetscInt dim, PetscReal t, const PetscReal x[], PetscInt Nc, PetscScalar *eta, void *ctx)
{
  MMSStructureDisplacement(t, x, eta);
  return 0;
}

static PetscErrorCode Velocity(PetscInt dim, PetscReal t, const PetscReal x[], PetscInt Nc, PetscScalar *etadot, void *ctx)
{
  MMSStructureVelocity(t, x, etadot);
  return 0;
}

static PetscErrorCode DisplacementGradient(PetscInt dim, PetscReal t, const PetscReal x[], PetscInt Nc, PetscScalar *g, void *ctx)
{
  MMSStructureDisplacementGradient(t, x, g);
  return 0;
}

/* The data enter in volume form, as in mms-fluid (see there why):
   (f_s, xi) + (sigma n, xi)_{Gamma_N} = (rho_s eta_tt, xi) + (sigma, grad xi). */
static void LoadValue(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[], const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[], const PetscInt aOff_x[], const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[], PetscReal t, const PetscReal x[], PetscInt numConstants, const PetscScalar constants[], PetscScalar f0[])
{
  PetscScalar f[2];

  MMSStructureInertia(PetscRealPart(constants[STRUCTURE_TIME]), x, PetscRealPart(constants[STRUCTURE_RHO]), f);
  for (PetscInt c = 0; c < dim; ++c) f0[c] -= constants[STRUCTURE_LOAD] * f[c];
}

/* sigma = mu_s (grad eta + grad eta^T) + lambda (div eta) I of the exact solution */
static void LoadStress(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[], const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[], const PetscInt aOff_x[], const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[], PetscReal t, const PetscReal x[], PetscInt numConstants, const PetscScalar constants[], PetscScalar f1[])
{
  const PetscScalar mu = constants[STRUCTURE_MU], lambda = constants[STRUCTURE_LAMBDA], load = constants[STRUCTURE_LOAD];
  PetscScalar       g[4];

  MMSStructureDisplacementGradient(PetscRealPart(constants[STRUCTURE_TIME]), x, g);
  for (PetscInt c = 0; c < 2; ++c)
    for (PetscInt d = 0; d < 2; ++d) f1[c * 2 + d] -= load * (mu * (g[c * 2 + d] + g[d * 2 + c]) + (c == d ? lambda * (g[0] + g[3]) : 0.0));
}

PetscErrorCode SceneCreate_MMSStructure(Scene *scene)
{
  PhysicsData *structure = &scene->structure;

  PetscFunctionBeginUser;
  PetscCall(OptionsSetDefault("-structure_dm_plex_simplex", "0"));
  PetscCall(OptionsSetDefault("-structure_dm_plex_box_faces", "4,2"));
  PetscCall(OptionsSetDefault("-structure_dm_plex_box_lower", "0,1"));
  PetscCall(OptionsSetDefault("-structure_dm_plex_box_upper", "1,1.5"));

  scene->has_structure          = PETSC_TRUE;
  structure->n_dirichlet        = 3;
  structure->dirichlet_faces[0] = FACE_RIGHT;
  structure->dirichlet_faces[1] = FACE_TOP;
  structure->dirichlet_faces[2] = FACE_LEFT;
  for (PetscInt b = 0; b < 3; ++b) structure->dirichlet_fn[b] = Displacement;
  structure->n_traction         = 1;
  structure->traction_faces[0]  = FACE_BOTTOM;
  structure->load_value_kernel  = LoadValue;
  structure->load_stress_kernel = LoadStress;
  structure->exact[0]           = Displacement;
  structure->exact_gradient[0]  = DisplacementGradient;
  structure->exact_rate         = Velocity;
  PetscFunctionReturn(0);
}
