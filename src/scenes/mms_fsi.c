/* Data of the manufactured FSI solution (see mms_fsi.h). Body forces carry everything
   (f = rho (u_t + (u.grad)u) - div sigma_f, f_s = rho_s eta_tt - div sigma_s), so only
   the control acts on the interface. On y = 1, with n_f = (0, 1):
     sigma_f n_f = (mu (u1_y + u2_x), 2 mu u2_y - p) = (0, -2 mu_s cos a sin b) = sigma_s n_f,
   the exact control is g = sigma_f n_f, and the structure receives -g = sigma_s n_s. */
#include "mms_fsi.h"
#include "fluid.h"
#include "structure.h"
#include "options.h"

#pragma GCC diagnostic ignored "-Wunused-parameter"

enum {
  MMS_MU_S = FLUID_NUM_CONSTANTS,
  MMS_DISCRETE_TIME
};

/* The closed forms below need the physical parameters the solvers read; the scene reads
   the same options once at creation into its context. */
typedef struct {
  PetscReal rho, mu, mu_s;
} MMSFSI;

static PetscErrorCode Velocity(PetscInt dim, PetscReal t, const PetscReal x[], PetscInt Nc, PetscScalar *u, void *ctx)
{
  const PetscReal s = PetscSinReal(x[0] + x[1] + 2 * t);
  u[0]              = s;
  u[1]              = -s;
  return 0;
}

static PetscScalar PressureAt(PetscReal mu, PetscReal mu_s, PetscReal t, const PetscReal x[])
{
  const PetscReal a = x[0] + t, b = x[1] + t;
  return 2 * mu * (PetscSinReal(a) * PetscSinReal(b) - PetscCosReal(a) * PetscCosReal(b)) +
         2 * mu_s * PetscCosReal(a) * PetscSinReal(b);
}

static PetscErrorCode Pressure(PetscInt dim, PetscReal t, const PetscReal x[], PetscInt Nc, PetscScalar *p, void *ctx)
{
  const MMSFSI *mms = (const MMSFSI *)ctx;

  p[0] = PressureAt(mms->mu, mms->mu_s, t, x);
  return 0;
}

static PetscErrorCode VelocityGradient(PetscInt dim, PetscReal t, const PetscReal x[], PetscInt Nc, PetscScalar *g,
                                       void *ctx)
{
  const PetscReal c = PetscCosReal(x[0] + x[1] + 2 * t);
  g[0]              = c;
  g[1]              = c;
  g[2]              = -c;
  g[3]              = -c;
  return 0;
}

/* g = sigma_f n_f on the interface y = 1 */
static PetscErrorCode InterfaceTraction(PetscInt dim, PetscReal t, const PetscReal x[], PetscInt Nc, PetscScalar *g,
                                        void *ctx)
{
  const MMSFSI *mms = (const MMSFSI *)ctx;
  PetscScalar   grad[4];

  (void)VelocityGradient(dim, t, x, Nc, grad, NULL);
  g[0] = mms->mu * (grad[1] + grad[2]);
  g[1] = 2 * mms->mu * grad[3] - PressureAt(mms->mu, mms->mu_s, t, x);
  return 0;
}

/* The fluid residual with the convective boundary term carries -1/2 rho ((u.n) u, v) on
   the interface; the exact solution needs this traction on top of g = sigma_f n_f. */
static PetscErrorCode ConvectiveDatum(PetscInt dim, PetscReal t, const PetscReal x[], PetscInt Nc, PetscScalar *d,
                                      void *ctx)
{
  const MMSFSI *mms = (const MMSFSI *)ctx;
  PetscScalar   u[2];

  (void)Velocity(dim, t, x, Nc, u, NULL);
  d[0] = -0.5 * mms->rho * u[1] * u[0];
  d[1] = -0.5 * mms->rho * u[1] * u[1];
  return 0;
}

static void FluidLoad(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                      const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[],
                      const PetscInt aOff_x[], const PetscScalar a_[], const PetscScalar a_t[], const PetscScalar a_x[],
                      PetscReal t_, const PetscReal x[], PetscInt numConstants, const PetscScalar constants[],
                      PetscScalar f0[])
{
  const PetscReal t = PetscRealPart(constants[FLUID_TIME]), rho = PetscRealPart(constants[FLUID_RHO]),
                  mu = PetscRealPart(constants[FLUID_MU]), mu_s = PetscRealPart(constants[MMS_MU_S]);
  const PetscReal a = x[0] + t, b = x[1] + t, s = PetscSinReal(a + b), c = PetscCosReal(a + b);
  PetscReal       dudt = 2 * c; /* u = (s, -s); (u.grad) u = 0 */

  if (constants[MMS_DISCRETE_TIME] != 0.0) {
    const PetscReal dt = PetscRealPart(constants[FLUID_DT]);
    dudt               = (s - PetscSinReal(a + b - 2 * dt)) / dt;
  }
  f0[0] -= constants[FLUID_LOAD] * (rho * dudt + 4 * mu * s - 2 * mu_s * PetscSinReal(a) * PetscSinReal(b));
  f0[1] -= constants[FLUID_LOAD] * (-rho * dudt + 2 * mu_s * PetscCosReal(a) * PetscCosReal(b));
}

static PetscErrorCode Displacement(PetscInt dim, PetscReal t, const PetscReal x[], PetscInt Nc, PetscScalar *eta,
                                   void *ctx)
{
  const PetscReal a = x[0] + t, b = x[1] + t;
  eta[0] = PetscSinReal(a) * PetscSinReal(b);
  eta[1] = PetscCosReal(a) * PetscCosReal(b);
  return 0;
}

static PetscErrorCode DisplacementGradient(PetscInt dim, PetscReal t, const PetscReal x[], PetscInt Nc, PetscScalar *g,
                                           void *ctx)
{
  const PetscReal a = x[0] + t, b = x[1] + t;
  g[0] = PetscCosReal(a) * PetscSinReal(b);
  g[1] = PetscSinReal(a) * PetscCosReal(b);
  g[2] = -PetscSinReal(a) * PetscCosReal(b);
  g[3] = -PetscCosReal(a) * PetscSinReal(b);
  return 0;
}

/* f_s = rho_s eta_tt - div sigma_s = rho_s (2c, -2c) + 2 mu_s eta (div eta = 0) */
static void StructureLoad(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                          const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[],
                          const PetscInt aOff[], const PetscInt aOff_x[], const PetscScalar a_[],
                          const PetscScalar a_t[], const PetscScalar a_x[], PetscReal t_, const PetscReal x[],
                          PetscInt numConstants, const PetscScalar constants[], PetscScalar f0[])
{
  const PetscReal t = PetscRealPart(constants[STRUCTURE_TIME]), rho = PetscRealPart(constants[STRUCTURE_RHO]),
                  mu = PetscRealPart(constants[STRUCTURE_MU]);
  const PetscReal c  = PetscCosReal(x[0] + x[1] + 2 * t);
  PetscScalar     eta[2];

  (void)Displacement(dim, t, x, dim, eta, NULL);
  f0[0] -= constants[STRUCTURE_LOAD] * (2 * rho * c + 2 * mu * eta[0]);
  f0[1] -= constants[STRUCTURE_LOAD] * (-2 * rho * c + 2 * mu * eta[1]);
}

/* an option the scene has just given its default, so always set: its value has that one home */
static PetscErrorCode ReadReal(const char name[], PetscReal *value)
{
  PetscBool set;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetReal(NULL, NULL, name, value, &set));
  PetscCheck(set, PETSC_COMM_WORLD, PETSC_ERR_PLIB, "option %s: expected the scene's default", name);
  PetscFunctionReturn(0);
}

PetscErrorCode SceneCreate_MMSFSI(Scene *scene, const char fluid_model[])
{
  PhysicsData *fluid = &scene->fluid, *structure = &scene->structure;
  PetscBool    discrete_time = PETSC_FALSE;
  PetscReal    E, nu;
  MMSFSI      *mms;

  PetscFunctionBeginUser;
  PetscCall(SceneCreateContext(sizeof(*mms), (void **)&mms));
  PetscCall(OptionsDeclareHelpGroup("mms_"));
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Manufactured FSI solution (mms-stokes, mms-ns)", "scene");
  PetscCall(PetscOptionsBool("-mms_discrete_time",
                             "Force the fluid with the backward difference of the exact velocity, leaving its spatial "
                             "error only",
                             NULL, discrete_time, &discrete_time, NULL));
  PetscOptionsEnd();
  PetscCall(OptionsSetDefault("-fluid_model", fluid_model));
  PetscCall(SceneMMSFluidBox());
  PetscCall(SceneMMSStructureBox());
  /* the seed's rho = 1, rho_s = 1.9, mu_s = 3, lambda = 4.5 (E = 7.8, nu = 0.3) and our mu = 2 */
  PetscCall(OptionsSetDefault("-fluid_density", "1.0"));
  PetscCall(OptionsSetDefault("-fluid_viscosity", "2.0"));
  PetscCall(OptionsSetDefault("-structure_density", "1.9"));
  PetscCall(OptionsSetDefault("-structure_youngs_modulus", "7.8"));
  PetscCall(OptionsSetDefault("-structure_poisson_ratio", "0.3"));
  PetscCall(OptionsSetDefault("-fluid_initial_projection", "1"));
  /* with -coupling_inner cgls: the seed's Gauss-Newton steps, each normal equation solved to
     1e-10 (the time-convergence tests measure the scheme, not the inner solver) */
  PetscCall(OptionsSetDefault("-tao_brgn_subsolver_tao_bnk_ksp_rtol", "1e-10"));
  PetscCall(ReadReal("-fluid_density", &mms->rho));
  PetscCall(ReadReal("-fluid_viscosity", &mms->mu));
  PetscCall(ReadReal("-structure_youngs_modulus", &E));
  PetscCall(ReadReal("-structure_poisson_ratio", &nu));
  mms->mu_s = E / (2 * (1 + nu));

  scene->has_fluid          = PETSC_TRUE;
  fluid->n_dirichlet        = 3;
  fluid->dirichlet_faces[0] = FACE_BOTTOM;
  fluid->dirichlet_faces[1] = FACE_RIGHT;
  fluid->dirichlet_faces[2] = FACE_LEFT;
  for (PetscInt b = 0; b < 3; ++b) fluid->dirichlet_fn[b] = Velocity;
  fluid->interface_face             = FACE_TOP;
  fluid->interface_traction         = InterfaceTraction;
  fluid->convective_interface_datum = ConvectiveDatum;
  fluid->load_value_kernel          = FluidLoad;
  fluid->exact[0]                   = Velocity;
  fluid->exact[1]                   = Pressure;
  fluid->exact_gradient[0]          = VelocityGradient;
  fluid->ctx                        = mms;
  fluid->n_extra                    = 2;
  fluid->extra[0]                   = mms->mu_s;
  fluid->extra[1]                   = discrete_time ? 1.0 : 0.0;

  scene->has_structure          = PETSC_TRUE;
  structure->n_dirichlet        = 3;
  structure->dirichlet_faces[0] = FACE_RIGHT;
  structure->dirichlet_faces[1] = FACE_TOP;
  structure->dirichlet_faces[2] = FACE_LEFT;
  for (PetscInt b = 0; b < 3; ++b) structure->dirichlet_fn[b] = Displacement;
  structure->interface_face    = FACE_BOTTOM;
  structure->load_value_kernel = StructureLoad;
  structure->exact[0]          = Displacement;
  structure->exact_gradient[0] = DisplacementGradient;
  structure->exact_rate        = Velocity;
  PetscFunctionReturn(0);
}
