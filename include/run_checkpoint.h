#ifndef FSIOPT_RUN_CHECKPOINT_H
#define FSIOPT_RUN_CHECKPOINT_H
#include "fsiopt.h"
#include "fluid.h"
#include "structure.h"
#include "coupling.h"
#include "probes.h"
#include "fields.h"
#include "summary.h"
#include "step_retry.h"

/* A run's checkpoints (checkpoint.h): the options, and the whole state to or from a file. */
typedef struct {
  PetscInt  every;                       /* -checkpoint_every K, 0: none */
  char      file[PETSC_MAX_PATH_LEN];    /* -checkpoint_file */
  char      restart[PETSC_MAX_PATH_LEN]; /* -restart */
  PetscBool restarting;
  PetscBool change_dt;    /* -restart_change_dt: the checkpoint may have been written with another dt */
  char      change[1024]; /* -restart_change a,b: problem options that may differ from the checkpoint's */
  PetscBool possible;     /* this set-up can write one: then SIGINT/SIGTERM write one too */
  PetscInt  last;         /* the step of the last one written, -1: none */
  PetscReal layouts[2];   /* MeshLayoutSignature of the fluid and structure meshes at set-up, before they moved */
  PetscInt  structure_ranks; /* of a fluid | structure split, 0: both on every rank */
} RunCheckpointParams;

/* The run's -checkpoint_file is its own from the start (OutputLockTakeFile; in its
   -output_dir through the directory's lock): a second run writing it would replace the
   first's checkpoints with its own. Even a run that writes none unless stopped by a signal
   takes it. */
PetscErrorCode RunCheckpointLock(const RunParams *);
/* structure_ranks: K of a fluid | structure split, 0 for both on every rank; restartable:
   the coupling method (if any) keeps all its state in checkpoints. */
PetscErrorCode RunCheckpointSetFromOptions(const RunParams *, PetscInt structure_ranks, PetscBool restartable,
                                           RunCheckpointParams *);
/* The options that define the discrete problem, "name value" lines (run_fingerprint.c); and
   the first difference of a checkpoint's from this run's, outside `change`, refused. */
PetscErrorCode RunFingerprint(char text[], size_t len);
PetscErrorCode RunFingerprintCompare(const char path[], const char written[], const char mine[], const char change[]);
/* The meshes' layout signatures, taken at set-up (the meshes at rest). */
PetscErrorCode RunCheckpointSetLayouts(RunCheckpointParams *, Fluid, Structure);
/* What the next step needs, to or from `path`; `step` is the step the state ends (of this
   run's dt). A load checks that the file was written with the same t_start, unknowns and
   ranks, the same split of the meshes, and the same dt unless -restart_change_dt is given:
   then a checkpoint of another dt whose time is a whole number of this run's steps goes on
   through the step-change path of a retried step (StepRetrySetTimeStep). */
PetscErrorCode RunCheckpoint(const char path[], PetscBool load, PetscInt *step, const RunParams *,
                             const RunCheckpointParams *, const RunSummary *, Fluid, Structure, Coupling, Probes,
                             FieldWriter, StepRetry);
#endif
