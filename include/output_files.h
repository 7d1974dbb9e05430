#ifndef FSIOPT_OUTPUT_FILES_H
#define FSIOPT_OUTPUT_FILES_H
#include <stdio.h>
#include <petscsys.h>

/* The run's output directory and the files written into it (src/storage/output_dir.c,
   partial_file.c). The directory, made with its parents: */
PetscErrorCode OutputMakeDirectories(const char dir[]);
/* the same without raising: 0, or 1 with one line in why naming -output_dir */
int OutputMakeDirectoriesWhy(const char dir[], char why[], size_t len);

/* A run owns its -output_dir: rank 0 creates <dir>/.fsiopt.lock (pid, host, start time)
   or refuses, on every rank, with one line naming the directory and its owner. A lock of
   a run that no longer runs on this host is taken over with a notice. Released (and a
   directory made for the run removed if empty) by OutputLockRelease, also on main's error
   path (no PETSc calls). Collective. */
PetscErrorCode OutputLockTake(MPI_Comm, const char dir[]);
/* One writer for a file the run writes (its -checkpoint_file), refused with one line naming
   `option`, the file and the run that holds it; `noun` names the file in the notice of a
   take-over. In the run's own -output_dir (`in_output_dir`) the directory's lock covers it:
   only another live run's <file>.lock is refused (a dead run's removed). Elsewhere the run
   takes <file>.lock, released with the directory's, and refuses a file in another live
   run's output directory. A lock that cannot be created (no such directory) is neither
   taken nor refused: the run's own check of the file says why it cannot write there.
   Collective. */
PetscErrorCode OutputLockTakeFile(MPI_Comm, const char option[], const char file[], const char noun[],
                                  PetscBool in_output_dir);
void           OutputLockRelease(void);
/* A rank that ends the whole job (its error is not the others'): the job's lock goes. */
void OutputLockReleaseForJob(void);

/* A CSV written by rank 0 as <dir>/<name>.partial and renamed to <dir>/<name> only when
   the run completes: a failed run never leaves a file that looks complete. */
typedef struct {
  MPI_Comm  comm;
  FILE     *fp; /* rank 0's; NULL elsewhere */
  PetscBool open;
  char      path[PETSC_MAX_PATH_LEN], partial[PETSC_MAX_PATH_LEN];
} PartialFile;

PetscErrorCode PartialFileOpen(MPI_Comm, const char dir[], const char name[], PartialFile *);
/* Flushes what was written so far; a write error (a full disk, a quota, an I/O error)
   stops the run with one line naming the file, the .partial kept. Collective. */
PetscErrorCode PartialFileCheck(PartialFile *);
/* Why writing `path` failed: the errno text, or what the file system says (no space left,
   read-only) when the error came through a library without one. */
PetscErrorCode OutputWriteErrorText(const char path[], int errnum, char why[], size_t len);
/* An HDF5 write (checkpoint, fields) failed: HDF5 still holds the file it could not write and
   would write it again (and MPI-IO crash) when MPI finalizes; main then exits without
   finalizing. */
void      OutputHDF5WriteFailed(void);
PetscBool OutputHDF5Failed(void);

/* The files the set-up opens (the .partial outputs) are removed when the run stops with an
   error before its first step is recorded and its options checked: a refused set-up leaves
   no outputs. After OutputSetUpDone they stay, the record of the steps done. */
PetscErrorCode OutputRegisterSetUpFile(const char path[]);
/* The set-up is done: the finished outputs an earlier run left in dir go (rank 0). */
void OutputSetUpDone(const char dir[]);
/* The names of the files a run writes in its -output_dir, each also as NAME.partial or NAME.tmp
   while it is written; NULL-terminated. */
extern const char *const OutputFileNames[];
/* Whether `file` would lie in output_dir (their real paths), and then the name of the run's
   own output it would overwrite or be overwritten by (its name starts with one of
   OutputFileNames), else NULL. Not collective. */
PetscBool OutputDirHolds(const char file[], const char output_dir[], const char **clash);
/* An option asking PETSc to write a file (a viewer's type:FILE, -log_view's :FILE) that is one
   of the run's own (an output in output_dir, the checkpoint) is refused with one line naming
   it, before the first step rather than overwritten after the last. Collective. */
PetscErrorCode OutputCheckViewerFiles(MPI_Comm, const char output_dir[], const char checkpoint[]);
void           OutputRemoveSetUpFiles(void); /* main's error path: no PETSc calls */
PetscErrorCode PartialFileClose(PartialFile *, PetscBool complete);
#endif
