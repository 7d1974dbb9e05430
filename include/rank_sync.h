#ifndef FSIOPT_RANK_SYNC_H
#define FSIOPT_RANK_SYNC_H
#include "fsiopt.h"

/* -check_rank_sync (a developer's check, off by default): whether every rank of obj's
   communicator has created the same number of PETSc objects on it. Each creation takes a tag
   of the communicator; an object created on some ranks only (a cache PETSc fills lazily on
   the ranks that reach it) puts their tags out of step, and a later collective hangs or
   fails with an MPI error far from the cause. This check fails at once instead, naming
   `what` (the subproblem) and `when` (set-up, a step). Collective on obj's communicator. */
PetscErrorCode RankSyncCheck(PetscObject obj, const char what[], const char when[]);
#endif
