#ifndef FSIOPT_CHECKPOINT_H
#define FSIOPT_CHECKPOINT_H
#include <petscviewerhdf5.h>
#include "fsiopt.h"

/* The state the next step needs, saved by each module's *Checkpoint function into a store
   that is either
   - an HDF5 file: every -checkpoint_every K steps to -checkpoint_file (default
     <output_dir>/checkpoint.h5), written to a temporary file and renamed, so a run killed
     while writing keeps its last good checkpoint; -restart FILE continues from one. A file
     is also a resynchronization point: the fluid's factors and the coupling's explicit
     Jacobian are rebuilt at the next step, in the run that wrote it as in the run that
     restarts from it, so the two go on identically;
   - memory: the state a step starts from, kept while the step may still be retried with a
     smaller dt (step_retry.c). Saving there rebuilds nothing; loading rebuilds what a new
     dt invalidates. */
PetscErrorCode CheckpointOpen(MPI_Comm, const char path[], PetscBool load, Checkpoint *);
/* Closes; a written file is renamed from its temporary name into place. */
PetscErrorCode CheckpointClose(MPI_Comm, const char path[], PetscBool load, Checkpoint *);
/* After a write that failed: path's temporary goes, path itself (the last complete one) stays
   (and OutputHDF5WriteFailed is called). */
void CheckpointRemoveTemporary(const char path[]);
/* Whether path's file system has room for a checkpoint of at least `at_least` bytes (or of
   the size of the one at path, if larger), with a margin; collective. */
PetscErrorCode CheckpointEnsureSpace(MPI_Comm, const char path[], double at_least, PetscBool *enough,
                                     double *free_bytes, double *needed);
PetscErrorCode CheckpointCreateInMemory(Checkpoint *);
PetscErrorCode CheckpointDestroy(Checkpoint *);
PetscBool      CheckpointIsFile(Checkpoint);
/* A file whose values carry checksums (checksum.h): false for a file read that an fsiopt
   without checksums wrote, whose values are read unchecked. */
PetscBool CheckpointHasChecksums(Checkpoint);
/* Whether a file holds the group (a path from the root, or below the current group). */
PetscErrorCode CheckpointHasGroup(Checkpoint, const char group[], PetscBool *has);
/* Whether the solvers rebuild their factors after this save or load (see above). */
PetscBool CheckpointResynchronizes(Checkpoint, PetscBool load);

/* A part only some ranks hold (the fluid's and the structure's states on fluid | structure
   ranks): parallel HDF5 creates a dataset on every rank that has the file open, so between
   these two calls (collective on the file's ranks) the file is open on `part` alone
   (MPI_COMM_NULL on the others), one part after another. EndPart takes the error of the
   part's work on this rank (0 on the others) and returns on every rank the first failed
   rank's. A part held by every rank, or a checkpoint in memory, keeps the file as it is. */
PetscErrorCode CheckpointBeginPart(Checkpoint, MPI_Comm part);
PetscErrorCode CheckpointEndPart(Checkpoint, PetscErrorCode part_error);

/* Names below go into the current group. */
PetscErrorCode CheckpointPushGroup(Checkpoint, const char group[]);
PetscErrorCode CheckpointPopGroup(Checkpoint);
/* Saves (load = PETSC_FALSE) or loads a vector, without renaming the caller's vector. */
PetscErrorCode CheckpointVec(Checkpoint, const char name[], Vec, PetscBool load);
PetscErrorCode CheckpointInt(Checkpoint, const char name[], PetscInt *, PetscBool load);
/* in the current group; for state a set-up may add to an older checkpoint's */
PetscErrorCode CheckpointHasAttribute(Checkpoint, const char name[], PetscBool *has);
PetscErrorCode CheckpointReal(Checkpoint, const char name[], PetscReal *, PetscBool load);
/* files only: value[len], cut to len - 1 characters on load */
PetscErrorCode CheckpointString(Checkpoint, const char name[], char value[], size_t len, PetscBool load);
/* A local vector in a DM's local layout (in a file through its global vector: the owners'
   values). */
PetscErrorCode CheckpointLocalVec(Checkpoint, const char name[], DM, Vec local, PetscBool load);
#endif
