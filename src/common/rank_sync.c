/* -check_rank_sync (rank_sync.h): whether every rank of a communicator created the same
   PETSc objects, so that a cache filled on some ranks only is named where it happens. */
#include "rank_sync.h"

static PetscBool checked = PETSC_FALSE, enabled = PETSC_FALSE;

PetscErrorCode RankSyncCheck(PetscObject obj, const char what[], const char when[])
{
  PetscMPIInt tag, range[2];

  PetscFunctionBeginUser;
  if (!checked) {
    PetscOptionsBegin(PetscObjectComm(obj), NULL, "Developer checks", "fsiopt");
    PetscCall(PetscOptionsBool("-check_rank_sync",
                               "after the set-up and every step, check that every rank created the same PETSc objects "
                               "on the fluid's and the structure's communicators (their tags agree)",
                               NULL, enabled, &enabled, NULL));
    PetscOptionsEnd();
    checked = PETSC_TRUE;
  }
  if (!enabled) PetscFunctionReturn(0);
  PetscCall(PetscObjectGetNewTag(obj, &tag));
  range[0] = -tag;
  range[1] = tag;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, range, 2, MPI_INT, MPI_MAX, PetscObjectComm(obj)));
  PetscCheck(-range[0] == range[1], PetscObjectComm(obj), PETSC_ERR_PLIB,
             "-check_rank_sync: after %s the ranks of the %s have created different numbers of PETSc objects (%d "
             "more on some rank): an object created on some ranks only",
             when, what, (int)(range[1] + range[0]));
  PetscFunctionReturn(0);
}
