/* history.csv (history.h): one row per coupling iteration, and one per failed attempt of
   a step, written through a PartialFile. */
#include "history.h"

struct _p_History {
  PartialFile file;
};

PetscErrorCode HistoryOpen(MPI_Comm comm, const char dir[], History *history)
{
  History h;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&h));
  PetscCall(PartialFileOpen(comm, dir, "history.csv", &h->file));
  PetscCall(PetscFPrintf(comm, h->file.fp, "step,iteration,objective,jump,inner_iterations,dt,event\n"));
  *history = h;
  PetscFunctionReturn(0);
}

PetscErrorCode HistoryAppend(History h, PetscInt step, PetscReal dt, PetscInt iteration, PetscReal objective,
                             PetscReal jump, PetscInt inner)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFPrintf(h->file.comm, h->file.fp,
                         "%" PetscInt_FMT ",%" PetscInt_FMT ",%.10e,%.10e,%" PetscInt_FMT ",%.10e,\n", step, iteration,
                         (double)objective, (double)jump, inner, (double)dt));
  PetscCall(PartialFileCheck(&h->file));
  PetscFunctionReturn(0);
}

PetscErrorCode HistoryAppendEvent(History h, PetscInt step, PetscReal dt, const char event[])
{
  PetscFunctionBeginUser;
  PetscCall(
    PetscFPrintf(h->file.comm, h->file.fp, "%" PetscInt_FMT ",-1,nan,nan,0,%.10e,%s\n", step, (double)dt, event));
  PetscCall(PartialFileCheck(&h->file));
  PetscFunctionReturn(0);
}

PetscErrorCode HistoryClose(History *history, PetscBool complete)
{
  PetscFunctionBeginUser;
  if (!*history) PetscFunctionReturn(0);
  PetscCall(PartialFileClose(&(*history)->file, complete));
  PetscCall(PetscFree(*history));
  PetscFunctionReturn(0);
}
