/* Scene mms-fluid: the fluid alone on [0,1]^2 against a manufactured solution
   (src/scenes/mms_fields.h). Dirichlet data on the bottom, left and right sides,
   the exact traction on the top side (where the interface will be), exact body force. */
#include "scene.h"
#include "fluid.h"
#include "options.h"
#include "mms_fields.h"
#include "prescribed_motion.h"

/* PETSc fixes the signatures of pointwise kernels and callbacks; most use a few of their arguments. */
#pragma GCC diagnostic ignored "-Wunused-parameter"

enum {
  MMS_DISCRETE_TIME = FLUID_NUM_CONSTANTS
};

static PetscErrorCode Velocity(PetscInt dim, PetscReal t, const PetscReal x[], PetscInt Nc, PetscScalar *u, void *ctx)
{
  MMSFluidVelocity(t, x, u);
  return 0;
}

static PetscErrorCode Pressure(PetscInt dim, PetscReal t, const PetscReal x[], PetscInt Nc, PetscScalar *p, void *ctx)
{
  p[0] = MMSFluidPressure(t, x);
  return 0;
}

static PetscErrorCode VelocityGradient(PetscInt dim, PetscReal t, const PetscReal x[], PetscInt Nc, PetscScalar *g,
                                       void *ctx)
{
  MMSFluidVelocityGradient(t, x, g);
  return 0;
}

/* The data enter in volume form: with f = rho (u_t + (u.grad)u) - div sigma and
   sigma n = h on the traction side, (f, v) + (h, v)_{Gamma_N} = (rho (u_t + (u.grad)u), v)
   + (sigma, grad v) for every v vanishing on the Dirichlet sides. This is exact, and it
   avoids PETSc 3.18's boundary integration, which pairs the quadrature points of
   reversed quadrilateral faces (top, left) with mirrored basis values. */
static void LoadValue(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                      const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[],
                      const PetscInt aOff_x[], const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[],
                      PetscReal t, const PetscReal x[], PetscInt numConstants, const PetscScalar constants[],
                      PetscScalar f0[])
{
  PetscScalar f[2];

  MMSFluidInertia(PetscRealPart(constants[FLUID_TIME]), x, PetscRealPart(constants[FLUID_RHO]),
                  constants[FLUID_CONVECTION] != 0.0, constants[MMS_DISCRETE_TIME] != 0.0,
                  PetscRealPart(constants[FLUID_DT]), f);
  for (PetscInt c = 0; c < dim; ++c) f0[c] -= constants[FLUID_LOAD] * f[c];
}

/* sigma = mu (grad u + grad u^T) - p I of the exact solution */
static void LoadStress(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                       const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[],
                       const PetscInt aOff_x[], const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[],
                       PetscReal t, const PetscReal x[], PetscInt numConstants, const PetscScalar constants[],
                       PetscScalar f1[])
{
  const PetscReal   time = PetscRealPart(constants[FLUID_TIME]);
  const PetscScalar mu = constants[FLUID_MU], p = MMSFluidPressure(time, x), load = constants[FLUID_LOAD];
  PetscScalar       g[4];

  MMSFluidVelocityGradient(time, x, g);
  for (PetscInt c = 0; c < 2; ++c)
    for (PetscInt d = 0; d < 2; ++d) f1[c * 2 + d] -= load * (mu * (g[c * 2 + d] + g[d * 2 + c]) - (c == d ? p : 0.0));
}

/* the scene's context: the prescribed mesh motion's parameters */
typedef struct {
  PetscReal motion_amplitude, motion_frequency;
} MMSFluid;

static PetscErrorCode Motion(PetscInt dim, PetscReal t, const PetscReal x[], PetscInt Nc, PetscScalar *d, void *ctx)
{
  const MMSFluid *mms = (const MMSFluid *)ctx;

  PrescribedMotion(mms->motion_amplitude, mms->motion_frequency, t, x, d);
  return 0;
}

PetscErrorCode SceneCreate_MMSFluid(Scene *scene)
{
  PhysicsData *fluid         = &scene->fluid;
  PetscBool    discrete_time = PETSC_FALSE;
  MMSFluid    *mms;

  PetscFunctionBeginUser;
  scene->dim = 2;
  PetscCall(SceneCreateContext(sizeof(*mms), (void **)&mms));
  mms->motion_amplitude = 0.0;
  mms->motion_frequency = 10.0;
  PetscCall(OptionsDeclareHelpGroup("mms_"));
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Scene mms-fluid: the fluid alone against a manufactured solution",
                    "scene");
  PetscCall(OptionsNonNegativeReal(PetscOptionsObject, "-mms_mesh_motion",
                                   "amplitude of a prescribed interior mesh motion (ALE check; 0: fixed mesh)",
                                   &mms->motion_amplitude));
  PetscCheck(mms->motion_amplitude <= 0.2, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
             "option -mms_mesh_motion: expected an amplitude of at most 0.2 (cells would invert), got %g",
             (double)mms->motion_amplitude);
  PetscCall(PetscOptionsBool("-mms_discrete_time",
                             "Force with the backward difference of the exact velocity, leaving only the spatial error",
                             NULL, discrete_time, &discrete_time, NULL));
  PetscOptionsEnd();
  if (discrete_time) {
    PetscInt order = 0;
    /* the scene's default for this forcing; the check reads the value the fluid will use
       (not a copy of the fluid's own default) */
    PetscCall(OptionsSetDefault("-fluid_time_order", "1"));
    PetscCall(PetscOptionsGetInt(NULL, NULL, "-fluid_time_order", &order, NULL));
    PetscCheck(order == 1, PETSC_COMM_WORLD, PETSC_ERR_ARG_INCOMP,
               "option -mms_discrete_time: its forcing is the backward-Euler difference; expected -fluid_time_order 1, "
               "got %" PetscInt_FMT,
               order);
  }
  PetscCall(SceneMMSFluidBox());
  PetscCall(OptionsSetDefault("-fluid_density", "1.0"));
  PetscCall(OptionsSetDefault("-fluid_viscosity", "1.0"));

  scene->has_fluid          = PETSC_TRUE;
  fluid->n_dirichlet        = 3;
  fluid->dirichlet_faces[0] = FACE_BOTTOM;
  fluid->dirichlet_faces[1] = FACE_RIGHT;
  fluid->dirichlet_faces[2] = FACE_LEFT;
  for (PetscInt b = 0; b < 3; ++b) fluid->dirichlet_fn[b] = Velocity;
  fluid->n_traction         = 1;
  fluid->traction_faces[0]  = FACE_TOP;
  fluid->load_value_kernel  = LoadValue;
  fluid->load_stress_kernel = LoadStress;
  fluid->exact[0]           = Velocity;
  fluid->exact[1]           = Pressure;
  fluid->exact_gradient[0]  = VelocityGradient;
  fluid->mesh_displacement  = mms->motion_amplitude > 0 ? Motion : NULL;
  fluid->ctx                = mms;
  /* The force on the bottom side: with the exact traction inside the volume-form data, the
     recorded drag and lift are those of the discrete solution minus the exact ones. */
  fluid->n_force_faces  = 1;
  fluid->force_faces[0] = FACE_BOTTOM;
  fluid->n_extra        = 1;
  fluid->extra[0]       = discrete_time ? 1.0 : 0.0;
  PetscFunctionReturn(0);
}
