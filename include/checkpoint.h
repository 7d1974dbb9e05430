#ifndef FSIOPT_CHECKPOINT_H
#define FSIOPT_CHECKPOINT_H
#include <petscviewerhdf5.h>
#include "fsiopt.h"

/* Checkpoints (HDF5): every -checkpoint_every K steps the state that the next step needs
   goes to -checkpoint_file (default <output_dir>/checkpoint.h5), written to a temporary
   file and renamed, so a run killed while writing keeps its last good checkpoint.
   -restart FILE continues from one. A checkpoint is also a resynchronization point: the
   fluid's factors and the coupling's explicit Jacobian are rebuilt at the next step, in the
   run that wrote it as in the run that restarts from it, so the two go on identically. */

/* Saves (load = PETSC_FALSE) or loads a vector under `name` in the viewer's current group,
   without renaming the caller's vector. */
PetscErrorCode CheckpointVec(PetscViewer, const char name[], Vec, PetscBool load);
/* The same for an integer or a real attribute of the current group. */
PetscErrorCode CheckpointInt(PetscViewer, const char name[], PetscInt *, PetscBool load);
PetscErrorCode CheckpointReal(PetscViewer, const char name[], PetscReal *, PetscBool load);
/* A local vector in a DM's local layout, through its global vector (owners' values). */
PetscErrorCode CheckpointLocalVec(PetscViewer, const char name[], DM, Vec local, PetscBool load);

PetscErrorCode CheckpointOpen(MPI_Comm, const char path[], PetscBool load, PetscViewer *);
/* Closes; a written checkpoint is renamed from its temporary name into place. */
PetscErrorCode CheckpointClose(MPI_Comm, const char path[], PetscBool load, PetscViewer *);
#endif
