#ifndef FSIOPT_SCENE_H
#define FSIOPT_SCENE_H
#include "fsiopt.h"

/* A scene is a named problem: which physics it needs, their data, its exact solution.
   A scene's create function reads the scene's own options and sets its defaults
   (meshes, parameters) with OptionsSetDefault, so an options file or the command line
   always wins; each value has that one home (an options file sets only what differs).
   A scene's closed forms read their parameters from a context of the scene's own
   (PhysicsData's ctx, made by SceneCreateContext), its pointwise kernels from the PetscDS
   constants (PhysicsData's extra): no scene keeps values in file-level variables. */
typedef struct {
  char        name[64];
  PetscBool   has_fluid, has_structure;
  PetscInt    dim;           /* of its meshes; 0: any */
  PhysicsData fluid, structure;
  PetscInt    n_probes;      /* interface points whose structure displacement goes to probes.csv */
  PetscReal   probes[8][3];
} Scene;

typedef PetscErrorCode (*SceneCreateFn)(Scene *);

PetscErrorCode SceneRegisterAll(void);
PetscErrorCode SceneCreate(const char name[], Scene *);
PetscErrorCode SceneListNames(char names[], size_t len);
PetscErrorCode SceneRequiredFaces(const PhysicsData *, PetscInt *n, PetscInt faces[]);
PetscErrorCode SceneFinalize(void);
/* A zeroed context of `size` bytes for a scene's parameters, freed by PetscFinalize. */
PetscErrorCode SceneCreateContext(size_t size, void **ctx);
/* A wall clamped on its LEFT and RIGHT face sets (its ends), traction-free on TOP, on the
   fluid along BOTTOM: channel2d's and tube3d's. */
PetscErrorCode SceneClampedWall(Scene *);
/* The default of a mesh option: meshes/<name> of the working directory when it is there,
   else of the repository the binary was built in (FSIOPT_ROOT). */
PetscErrorCode SceneSetDefaultMesh(const char option[], const char name[]);

/* The scenes (src/scenes/), one file each. */
PetscErrorCode SceneCreate_MMSFluid(Scene *);
PetscErrorCode SceneCreate_MMSStructure(Scene *);
PetscErrorCode SceneCreate_MMSStokes(Scene *);
PetscErrorCode SceneCreate_MMSNS(Scene *);
PetscErrorCode SceneCreate_GCL(Scene *);
PetscErrorCode SceneCreate_Channel2D(Scene *);
PetscErrorCode SceneCreate_Tube3D(Scene *);
PetscErrorCode SceneCreate_TurekHron(Scene *);
#endif
