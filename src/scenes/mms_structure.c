/* Scene mms-structure: the structure alone on [0,1]x[1,1.5] against the seed's
   manufactured displacement (src/scenes/mms_fields.h). Dirichlet data on the left,
   right and top sides, the exact traction on the bottom side (the interface). */
#include "scene.h"
#include "structure.h"
#include "options.h"
#include "mms_fields.h"

/* PETSc fixes the signatures of pointwise kernels and callbacks; most use a few of their arguments. */
#pragma GCC diagnostic ignored "-Wunused-parameter"

/* The manufactured displacement is scaled by `amplitude`; its load is that of the model
   being solved (the discrete solution then converges to the manufactured one), or that
   of linear elasticity whatever the model: a St. Venant-Kirchhoff wall under the linear
   load departs from the linear wall by O(amplitude^2). The closed forms read the
   amplitude from the scene's context, the load kernels the amplitude and the linear-load
   switch from the PetscDS constants. */
typedef struct {
  PetscReal amplitude;
} MMSStructure;

enum {
  MMS_AMPLITUDE = STRUCTURE_NUM_CONSTANTS,
  MMS_LINEAR_LOAD
};

static PetscErrorCode Displacement(PetscInt dim, PetscReal t, const PetscReal x[], PetscInt Nc, PetscScalar *eta,
                                   void *ctx)
{
  const MMSStructure *mms = (const MMSStructure *)ctx;

  MMSStructureDisplacement(t, x, eta);
  for (PetscInt c = 0; c < Nc; ++c) eta[c] *= mms->amplitude;
  return 0;
}

static PetscErrorCode Velocity(PetscInt dim, PetscReal t, const PetscReal x[], PetscInt Nc, PetscScalar *etadot,
                               void *ctx)
{
  const MMSStructure *mms = (const MMSStructure *)ctx;

  MMSStructureVelocity(t, x, etadot);
  for (PetscInt c = 0; c < Nc; ++c) etadot[c] *= mms->amplitude;
  return 0;
}

static PetscErrorCode DisplacementGradient(PetscInt dim, PetscReal t, const PetscReal x[], PetscInt Nc, PetscScalar *g,
                                           void *ctx)
{
  const MMSStructure *mms = (const MMSStructure *)ctx;

  MMSStructureDisplacementGradient(t, x, g);
  for (PetscInt i = 0; i < Nc * dim; ++i) g[i] *= mms->amplitude;
  return 0;
}

/* The data enter in volume form, as in mms-fluid (see there why):
   (f_s, xi) + (sigma n, xi)_{Gamma_N} = (rho_s eta_tt, xi) + (sigma, grad xi). */
static void LoadValue(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                      const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[],
                      const PetscInt aOff_x[], const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[],
                      PetscReal t, const PetscReal x[], PetscInt numConstants, const PetscScalar constants[],
                      PetscScalar f0[])
{
  PetscScalar f[2];

  MMSStructureInertia(PetscRealPart(constants[STRUCTURE_TIME]), x, PetscRealPart(constants[STRUCTURE_RHO]), f);
  for (PetscInt c = 0; c < dim; ++c) f0[c] -= constants[STRUCTURE_LOAD] * constants[MMS_AMPLITUDE] * f[c];
}

/* the stress of the exact solution, of the model being solved (linear or St. Venant-Kirchhoff) */
static void LoadStress(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                       const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[],
                       const PetscInt aOff_x[], const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[],
                       PetscReal t, const PetscReal x[], PetscInt numConstants, const PetscScalar constants[],
                       PetscScalar f1[])
{
  const PetscScalar load = constants[STRUCTURE_LOAD];
  PetscScalar       g[4], stress[4];

  MMSStructureDisplacementGradient(PetscRealPart(constants[STRUCTURE_TIME]), x, g);
  for (PetscInt i = 0; i < 4; ++i) g[i] *= constants[MMS_AMPLITUDE];
  StructureStress(constants[MMS_LINEAR_LOAD] != 0.0 ? STRUCTURE_LINEAR
                                                    : (StructureModel)PetscRealPart(constants[STRUCTURE_MODEL]),
                  dim, PetscRealPart(constants[STRUCTURE_MU]), PetscRealPart(constants[STRUCTURE_LAMBDA]), g, stress);
  for (PetscInt i = 0; i < 4; ++i) f1[i] -= load * stress[i];
}

PetscErrorCode SceneCreate_MMSStructure(Scene *scene)
{
  PhysicsData  *structure   = &scene->structure;
  PetscBool     linear_load = PETSC_FALSE;
  MMSStructure *mms;

  PetscFunctionBeginUser;
  scene->dim = 2;
  PetscCall(SceneCreateContext(sizeof(*mms), (void **)&mms));
  mms->amplitude = 1.0;
  PetscCall(OptionsDeclareHelpGroup("mms_"));
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Scene mms-structure: the structure against a manufactured displacement",
                    "scene");
  PetscCall(OptionsPositiveReal(PetscOptionsObject, "-mms_amplitude", "factor on the manufactured displacement",
                                &mms->amplitude));
  PetscCall(PetscOptionsBool("-mms_linear_load",
                             "load of linear elasticity whatever -structure_model (the solution is then manufactured "
                             "for the linear wall only)",
                             NULL, linear_load, &linear_load, NULL));
  PetscOptionsEnd();
  PetscCall(SceneMMSStructureBox());

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
  structure->ctx                = mms;
  structure->n_extra            = 2;
  structure->extra[0]           = mms->amplitude;
  structure->extra[1]           = linear_load ? 1.0 : 0.0;
  PetscFunctionReturn(0);
}
