#include "history.h"
#include <stdio.h>

struct _p_History {
  MPI_Comm comm;
  FILE    *fp;
  char     path[PETSC_MAX_PATH_LEN], partial[PETSC_MAX_PATH_LEN];
};

PetscErrorCode HistoryOpen(MPI_Comm comm, const char dir[], History *history)
{
  History h;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&h));
  h->comm = comm;
  PetscCall(PetscSNPrintf(h->path, sizeof(h->path), "%s/history.csv", dir));
  PetscCall(PetscSNPrintf(h->partial, sizeof(h->partial), "%s/history.csv.partial", dir));
  {
    PetscMPIInt rank;
    PetscCallMPI(MPI_Comm_rank(comm, &rank));
    if (!rank) PetscCall(OutputMakeDirectories(dir));
    PetscCallMPI(MPI_Barrier(comm));
  }
  PetscCall(PetscFOpen(comm, h->partial, "w", &h->fp));
  PetscCall(PetscFPrintf(comm, h->fp, "step,iteration,objective,jump,inner_iterations\n"));
  *history = h;
  PetscFunctionReturn(0);
}

PetscErrorCode HistoryAppend(History h, PetscInt step, PetscInt iteration, PetscReal objective, PetscReal jump, PetscInt inner)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFPrintf(h->comm, h->fp, "%" PetscInt_FMT ",%" PetscInt_FMT ",%.10e,%.10e,%" PetscInt_FMT "\n", step, iteration, (double)objective, (double)jump, inner));
  PetscFunctionReturn(0);
}

PetscErrorCode HistoryClose(History *history, PetscBool complete)
{
  History     h = *history;
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  if (!h) PetscFunctionReturn(0);
  PetscCall(PetscFClose(h->comm, h->fp));
  PetscCallMPI(MPI_Comm_rank(h->comm, &rank));
  if (complete && rank == 0) PetscCheck(rename(h->partial, h->path) == 0, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot rename %s to %s", h->partial, h->path);
  PetscCall(PetscFree(*history));
  PetscFunctionReturn(0);
}
