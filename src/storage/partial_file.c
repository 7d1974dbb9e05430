/* Files that become final only when the run completes (output_files.h): a CSV written as
   NAME.partial and renamed, the set-up's files removed when the set-up is refused, the
   text of a write error, and the flag that an HDF5 write failed. */
#include "output_files.h"
#include "options.h"
#include <errno.h>
#include <libgen.h>
#include <string.h>
#include <sys/statvfs.h>
#include <unistd.h>

#define MAX_SETUP_FILES 8
static char      setup_files[MAX_SETUP_FILES][PETSC_MAX_PATH_LEN];
static int       n_setup_files = 0;
static PetscBool setup_done    = PETSC_FALSE;

PetscErrorCode OutputRegisterSetUpFile(const char path[])
{
  PetscFunctionBeginUser;
  if (setup_done || n_setup_files == MAX_SETUP_FILES) PetscFunctionReturn(0);
  PetscCall(PetscStrncpy(setup_files[n_setup_files++], path, PETSC_MAX_PATH_LEN));
  PetscFunctionReturn(0);
}

const char *const OutputFileNames[] = {"probes.csv", "history.csv", "summary.json", "fields.h5", "fields.xdmf",
                                       "force_surface.csv", ".fsiopt.lock", NULL};

void OutputSetUpDone(const char dir[])
{
  int rank = 0;

  setup_done = PETSC_TRUE;
  (void)MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  if (rank || !dir) return;
  /* This run writes its files as NAME.partial; a finished NAME in the directory it owns is an
     earlier run's and would sit beside this run's outputs as if it were one of them (fields
     of a run that wrote fields, a summary of a run that ended otherwise). A restart has
     copied what it needed from them by now. */
  for (int i = 0; OutputFileNames[i]; ++i) {
    char path[PETSC_MAX_PATH_LEN];
    if (OutputFileNames[i][0] == '.') continue; /* the lock: this run's own */
    (void)snprintf(path, sizeof(path), "%s/%s", dir, OutputFileNames[i]);
    (void)unlink(path);
  }
}

void OutputRemoveSetUpFiles(void)
{
  if (setup_done) return;
  for (int i = 0; i < n_setup_files; ++i) (void)unlink(setup_files[i]); /* a rank that did not create it gets ENOENT */
  n_setup_files = 0;
}

PetscErrorCode PartialFileOpen(MPI_Comm comm, const char dir[], const char name[], PartialFile *file)
{
  PetscMPIInt rank;
  PetscBool   help;

  PetscFunctionBeginUser;
  file->comm = comm;
  help       = OptionsHelpRequested();
  if (help) { /* -help runs no step and leaves no trace: the writers write to nothing */
    file->path[0] = file->partial[0] = 0;
    PetscCall(PetscFOpen(comm, "/dev/null", "w", &file->fp));
    file->open = PETSC_TRUE;
    PetscFunctionReturn(0);
  }
  PetscCall(PetscSNPrintf(file->path, sizeof(file->path), "%s/%s", dir, name));
  PetscCall(PetscSNPrintf(file->partial, sizeof(file->partial), "%s/%s.partial", dir, name));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (!rank) PetscCall(OutputMakeDirectories(dir));
  PetscCallMPI(MPI_Barrier(comm));
  PetscCall(PetscFOpen(comm, file->partial, "w", &file->fp));
  file->open = PETSC_TRUE;
  PetscCall(OutputRegisterSetUpFile(file->partial));
  PetscFunctionReturn(0);
}

static PetscBool hdf5_failed = PETSC_FALSE;

void OutputHDF5WriteFailed(void)
{
  hdf5_failed = PETSC_TRUE;
}

PetscBool OutputHDF5Failed(void)
{
  return hdf5_failed;
}

PetscErrorCode OutputWriteErrorText(const char path[], int errnum, char why[], size_t len)
{
  char           dir[PETSC_MAX_PATH_LEN];
  struct statvfs fs;

  PetscFunctionBeginUser;
  /* errnum -1 or 0: not known (a stream's earlier error, a library's): the file system tells */
  if (errnum == ENOSPC || errnum == EDQUOT || errnum == EIO || errnum == EROFS || errnum == EACCES || errnum == EFBIG) {
    PetscCall(PetscSNPrintf(why, len, "%s", strerror(errnum)));
    PetscFunctionReturn(0);
  }
  PetscCall(PetscStrncpy(dir, path, sizeof(dir)));
  /* a write of a few KiB failing with less than 1 MiB left ran out of space */
  if (statvfs(dirname(dir), &fs) == 0 && (double)fs.f_bavail * (double)fs.f_frsize < 1048576.0)
    PetscCall(PetscSNPrintf(why, len, "%s", strerror(ENOSPC)));
  else if (statvfs(dir, &fs) == 0 && (fs.f_flag & ST_RDONLY)) PetscCall(PetscSNPrintf(why, len, "%s", strerror(EROFS)));
  else PetscCall(PetscSNPrintf(why, len, "%s", errnum > 0 ? strerror(errnum) : "write failed"));
  PetscFunctionReturn(0);
}

/* rank 0 writes: it says whether the writes so far reached the file */
static PetscErrorCode Flushed(PartialFile *file, PetscBool closing)
{
  PetscMPIInt rank;
  int         cause = 0;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(file->comm, &rank));
  if (!rank && file->fp) {
    errno = 0;
    if (fflush(file->fp) != 0 || ferror(file->fp)) cause = errno ? errno : -1; /* -1: the stream's earlier error */
    if (closing) {
      if (fclose(file->fp) != 0 && !cause) cause = errno ? errno : -1;
    }
  }
  if (closing) {
    file->fp   = NULL;
    file->open = PETSC_FALSE;
  }
  PetscCallMPI(MPI_Bcast(&cause, 1, MPI_INT, 0, file->comm));
  if (cause) {
    char why[256];
    PetscCall(OutputWriteErrorText(file->partial, cause, why, sizeof(why)));
    SETERRQ(file->comm, PETSC_ERR_FILE_WRITE, "cannot write %s (%s); what was written is in %s", file->path, why,
            file->partial);
  }
  PetscFunctionReturn(0);
}

PetscErrorCode PartialFileCheck(PartialFile *file)
{
  PetscFunctionBeginUser;
  if (file->open && file->path[0]) PetscCall(Flushed(file, PETSC_FALSE));
  PetscFunctionReturn(0);
}

PetscErrorCode PartialFileClose(PartialFile *file, PetscBool complete)
{
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  if (!file->open) PetscFunctionReturn(0);
  if (file->path[0]) PetscCall(Flushed(file, PETSC_TRUE)); /* never renamed when incomplete */
  else {
    PetscCall(PetscFClose(file->comm, file->fp));
    file->fp   = NULL;
    file->open = PETSC_FALSE;
  }
  PetscCallMPI(MPI_Comm_rank(file->comm, &rank));
  if (complete && !rank && file->path[0])
    PetscCheck(rename(file->partial, file->path) == 0, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot rename %s to %s",
               file->partial, file->path);
  PetscFunctionReturn(0);
}
