#ifndef FSIOPT_SCENE_H
#define FSIOPT_SCENE_H
#include "fsiopt.h"

/* A scene is a named problem: which physics it needs, their data, its exact solution.
   A scene's create function reads the scene's own options and sets its defaults
   (meshes, parameters) with OptionsSetDefault, so an options file or the command line
   always wins: that is each value's one home, and an options file does not repeat it.
   A scene's closed forms read their parameters from a context of the scene's own
   (PhysicsData's ctx, made by SceneCreateContext), its pointwise kernels from the PetscDS
   constants (PhysicsData's extra), not from file-level variables (two exceptions: the
   interface data of mms_fsi.c and the traction expressions of general.c, see there). */
typedef struct {
  char        name[64];
  PetscBool   has_fluid, has_structure;
  PetscInt    dim; /* of its meshes; 0: any */
  PhysicsData fluid, structure;
  const char *units;    /* of its parameters and outputs, for summary.json: "SI", "cgs", "nondimensional" */
  PetscInt    n_probes; /* interface points whose structure displacement goes to probes.csv */
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
/* The default meshes of the manufactured solutions (mms-fluid, mms-structure, mms-stokes,
   mms-ns): the fluid [0,1]^2 in 4x4 quadrilaterals, the structure [0,1]x[1,1.5] in 4x2. */
PetscErrorCode SceneMMSFluidBox(void);
PetscErrorCode SceneMMSStructureBox(void);

#endif
