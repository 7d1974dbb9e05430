#include "output.h"
#include "options.h"
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

void OutputSetUpDone(void)
{
  setup_done = PETSC_TRUE;
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
    PetscFunctionReturn(0);
  }
  PetscCall(PetscSNPrintf(file->path, sizeof(file->path), "%s/%s", dir, name));
  PetscCall(PetscSNPrintf(file->partial, sizeof(file->partial), "%s/%s.partial", dir, name));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (!rank) PetscCall(OutputMakeDirectories(dir));
  PetscCallMPI(MPI_Barrier(comm));
  PetscCall(PetscFOpen(comm, file->partial, "w", &file->fp));
  PetscCall(OutputRegisterSetUpFile(file->partial));
  PetscFunctionReturn(0);
}

PetscErrorCode PartialFileClose(PartialFile *file, PetscBool complete)
{
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  if (!file->fp) PetscFunctionReturn(0);
  PetscCall(PetscFClose(file->comm, file->fp));
  file->fp = NULL;
  PetscCallMPI(MPI_Comm_rank(file->comm, &rank));
  if (complete && !rank && file->path[0])
    PetscCheck(rename(file->partial, file->path) == 0, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot rename %s to %s",
               file->partial, file->path);
  PetscFunctionReturn(0);
}
