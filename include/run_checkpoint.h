#ifndef FSIOPT_RUN_CHECKPOINT_H
#define FSIOPT_RUN_CHECKPOINT_H
#include "fsiopt.h"
#include "fluid.h"
#include "structure.h"
#include "coupling.h"
#include "probes.h"
#include "fields.h"
#include "summary.h"

/* A run's checkpoints (checkpoint.h): the options, and the whole state to or from a file. */
typedef struct {
  PetscInt  every;                       /* -checkpoint_every K, 0: none */
  char      file[PETSC_MAX_PATH_LEN];    /* -checkpoint_file */
  char      restart[PETSC_MAX_PATH_LEN]; /* -restart */
  PetscBool restarting;
  PetscBool possible; /* this set-up can write one: then SIGINT/SIGTERM write one too */
  PetscInt  last;     /* the step of the last one written, -1: none */
} RunCheckpointParams;

/* restartable: the coupling method (if any) keeps all its state in checkpoints. */
PetscErrorCode RunCheckpointSetFromOptions(const RunParams *, PetscBool separate_ranks, PetscBool restartable,
                                           RunCheckpointParams *);
/* What the next step needs, to or from `path`; `step` is the step the state ends. A load
   checks that the file was written with the same dt, unknowns and ranks. */
PetscErrorCode RunCheckpoint(const char path[], PetscBool load, PetscInt *step, const RunParams *, const RunSummary *,
                             Fluid, Structure, Coupling, Probes, FieldWriter);
#endif
