#ifndef FSIOPT_RUN_H
#define FSIOPT_RUN_H
#include <petscsys.h>
/* A run (docs/design.md §6): set up from the options (scene, meshes, solvers, coupling, outputs),
   advanced step by step to -t_final, reported in summary.json. A new scene, coupling
   method or output registers itself in its own module: nothing here changes. */
typedef struct _p_Run *Run;
/* *run is NULL when there is nothing to run (-help without a scene: the scenes listed) */
PetscErrorCode RunCreate(Run *);
PetscErrorCode RunAdvance(Run);
PetscErrorCode RunReport(Run);
/* Why the run stopped before its end (a failed step, a signal), NULL if it did not; the
   same on every rank. */
PetscErrorCode RunGetStop(Run, PetscErrorCode *code, const char **reason);
PetscErrorCode RunDestroy(Run *);
#endif
