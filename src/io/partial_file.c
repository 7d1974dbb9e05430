#include "output.h"

PetscErrorCode PartialFileOpen(MPI_Comm comm, const char dir[], const char name[], PartialFile *file)
{
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  file->comm = comm;
  PetscCall(PetscSNPrintf(file->path, sizeof(file->path), "%s/%s", dir, name));
  PetscCall(PetscSNPrintf(file->partial, sizeof(file->partial), "%s/%s.partial", dir, name));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (!rank) PetscCall(OutputMakeDirectories(dir));
  PetscCallMPI(MPI_Barrier(comm));
  PetscCall(PetscFOpen(comm, file->partial, "w", &file->fp));
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
  if (complete && !rank) PetscCheck(rename(file->partial, file->path) == 0, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot rename %s to %s", file->partial, file->path);
  PetscFunctionReturn(0);
}
