/* Scene gcl: the geometric conservation check. A uniform flow U = (1, 0.5), p = 0 on
   [0,1]^2 (Dirichlet U on the bottom, left and top sides, traction-free on the right)
   while the interior of the mesh moves by d = A sin(pi x) sin(pi y) sin(omega t) (1, -1/2)
   with -gcl_amplitude A and -gcl_frequency omega. The exact discrete solution is U
   itself when the moving-mesh scheme conserves geometry: every error is round-off. */
#include "scene.h"
#include "options.h"
#include "prescribed_motion.h"

#pragma GCC diagnostic ignored "-Wunused-parameter"

/* the scene's context: the mesh motion's parameters */
typedef struct {
  PetscReal amplitude, frequency;
} GCL;

static PetscErrorCode Velocity(PetscInt dim, PetscReal t, const PetscReal x[], PetscInt Nc, PetscScalar *u, void *ctx)
{
  u[0] = 1.0;
  u[1] = 0.5;
  if (dim == 3) u[2] = 0.0; /* also on a 3D box, for the 3D cell checks */
  return 0;
}

static PetscErrorCode Pressure(PetscInt dim, PetscReal t, const PetscReal x[], PetscInt Nc, PetscScalar *p, void *ctx)
{
  p[0] = 0.0;
  return 0;
}

static PetscErrorCode Motion(PetscInt dim, PetscReal t, const PetscReal x[], PetscInt Nc, PetscScalar *d, void *ctx)
{
  const GCL *gcl = (const GCL *)ctx;

  for (PetscInt c = 0; c < Nc; ++c) d[c] = 0.0;
  PrescribedMotion(gcl->amplitude, gcl->frequency, t, x, d);
  return 0;
}

PetscErrorCode SceneCreate_GCL(Scene *scene)
{
  PhysicsData *fluid = &scene->fluid;
  GCL         *gcl;

  PetscFunctionBeginUser;
  PetscCall(SceneCreateContext(sizeof(*gcl), (void **)&gcl));
  gcl->amplitude = 0.15;
  gcl->frequency = 20.0;
  PetscCall(OptionsDeclareHelpGroup("gcl_"));
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Scene gcl: a uniform flow on a moving mesh", "scene");
  PetscCall(
    OptionsNonNegativeReal(PetscOptionsObject, "-gcl_amplitude",
                           "amplitude of the mesh motion (beyond about 0.3 the cells of the default mesh invert)",
                           &gcl->amplitude));
  PetscCheck(gcl->amplitude <= 1.0, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
             "option -gcl_amplitude: expected an amplitude of at most 1, got %g", (double)gcl->amplitude);
  PetscCall(OptionsNonNegativeReal(PetscOptionsObject, "-gcl_frequency", "angular frequency of the mesh motion",
                                   &gcl->frequency));
  PetscOptionsEnd();
  PetscCall(OptionsSetDefault("-fluid_dm_plex_simplex", "0"));
  PetscCall(OptionsSetDefault("-fluid_dm_plex_box_faces", "8,8"));
  scene->has_fluid          = PETSC_TRUE;
  fluid->n_dirichlet        = 3;
  fluid->dirichlet_faces[0] = FACE_BOTTOM;
  fluid->dirichlet_faces[1] = FACE_LEFT;
  fluid->dirichlet_faces[2] = FACE_TOP;
  for (PetscInt b = 0; b < 3; ++b) fluid->dirichlet_fn[b] = Velocity;
  fluid->n_traction        = 1;
  fluid->traction_faces[0] = FACE_RIGHT;
  fluid->exact[0]          = Velocity;
  fluid->exact[1]          = Pressure;
  fluid->mesh_displacement = Motion;
  fluid->ctx               = gcl;
  PetscFunctionReturn(0);
}
