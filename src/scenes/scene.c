/* The registry of scenes by name (scene.h) and the helpers scenes share: a context for
   their parameters and the manufactured solutions' boxes. A case that needs no
   closed form is an options file of the general scene (general.c), not a scene here. */
#include "scene.h"
#include "options.h"

static PetscFunctionList scene_list = NULL;

/* The scenes by name, each one file: a new scene is its file and a line here (a case without
   a closed form needs none: an options file of the general scene). */
#define SCENES(SCENE) \
  SCENE("mms-fluid", SceneCreate_MMSFluid)         /* mms_fluid.c */ \
  SCENE("mms-structure", SceneCreate_MMSStructure) /* mms_structure.c */ \
  SCENE("mms-stokes", SceneCreate_MMSStokes)       /* mms_stokes.c */ \
  SCENE("mms-ns", SceneCreate_MMSNS)               /* mms_ns.c */ \
  SCENE("gcl", SceneCreate_GCL)                    /* gcl.c */ \
  SCENE("general", SceneCreate_General)            /* general.c */
#define DECLARE(name, create) PetscErrorCode create(Scene *);
SCENES(DECLARE)
#undef DECLARE

PetscErrorCode SceneRegisterAll(void)
{
  PetscFunctionBeginUser;
  if (scene_list) PetscFunctionReturn(0);
#define REGISTER(name, create) PetscCall(PetscFunctionListAdd(&scene_list, name, create));
  SCENES(REGISTER)
#undef REGISTER
  PetscFunctionReturn(0);
}

PetscErrorCode SceneListNames(char names[], size_t len)
{
  PetscFunctionBeginUser;
  PetscCall(OptionsListNames(scene_list, names, len));
  PetscFunctionReturn(0);
}

PetscErrorCode SceneCreate(const char name[], Scene *scene)
{
  SceneCreateFn create;
  char          names[256];

  PetscFunctionBeginUser;
  PetscCall(PetscFunctionListFind(scene_list, name, &create));
  if (!create) {
    PetscCall(SceneListNames(names, sizeof(names)));
    SETERRQ(PETSC_COMM_WORLD, PETSC_ERR_ARG_UNKNOWN_TYPE, "option -scene: unknown scene '%s'; expected one of: %s",
            name, names);
  }
  PetscCall(PetscMemzero(scene, sizeof(*scene)));
  PetscCall(PetscStrncpy(scene->name, name, sizeof(scene->name)));
  scene->units = "nondimensional";
  PetscCall((*create)(scene));
  PetscFunctionReturn(0);
}

PetscErrorCode SceneRequiredFaces(const PhysicsData *data, PetscInt *n, PetscInt faces[])
{
  PetscFunctionBeginUser;
  *n = 0;
  for (PetscInt b = 0; b < data->n_dirichlet; ++b) faces[(*n)++] = data->dirichlet_faces[b];
  for (PetscInt b = 0; b < data->n_traction; ++b) faces[(*n)++] = data->traction_faces[b];
  if (data->interface_face) faces[(*n)++] = data->interface_face;
  PetscFunctionReturn(0);
}

PetscErrorCode SceneFinalize(void)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFunctionListDestroy(&scene_list));
  PetscFunctionReturn(0);
}

/* main keeps its Scene by value and ends with SceneFinalize(), which sees no scene: the
   context goes to a container that PetscFinalize destroys (with PetscFree). */
PetscErrorCode SceneCreateContext(size_t size, void **ctx)
{
  PetscContainer container;

  PetscFunctionBeginUser;
  PetscCall(PetscCalloc(size, ctx));
  PetscCall(PetscContainerCreate(PETSC_COMM_SELF, &container));
  PetscCall(PetscContainerSetPointer(container, *ctx));
  PetscCall(PetscContainerSetUserDestroy(container, PetscContainerUserDestroyDefault));
  PetscCall(PetscObjectRegisterDestroy((PetscObject)container));
  PetscFunctionReturn(0);
}

/* shared by the fluid-only and the coupled manufactured scenes (the PETSc box's default
   [0,1]^2 is the fluid's domain) */
PetscErrorCode SceneMMSFluidBox(void)
{
  PetscFunctionBeginUser;
  PetscCall(OptionsSetDefault("-fluid_dm_plex_simplex", "0"));
  PetscCall(OptionsSetDefault("-fluid_dm_plex_box_faces", "4,4"));
  PetscFunctionReturn(0);
}

/* shared by the structure-only and the coupled manufactured scenes: on top of the fluid's */
PetscErrorCode SceneMMSStructureBox(void)
{
  PetscFunctionBeginUser;
  PetscCall(OptionsSetDefault("-structure_dm_plex_simplex", "0"));
  PetscCall(OptionsSetDefault("-structure_dm_plex_box_faces", "4,2"));
  PetscCall(OptionsSetDefault("-structure_dm_plex_box_lower", "0,1"));
  PetscCall(OptionsSetDefault("-structure_dm_plex_box_upper", "1,1.5"));
  PetscFunctionReturn(0);
}
