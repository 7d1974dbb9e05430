#ifndef FSIOPT_HISTORY_H
#define FSIOPT_HISTORY_H
#include "output.h"

/* history.csv: one row per coupling iteration (the layout of the seed's Table 3.1),
   a PartialFile until the run completes. */
typedef struct _p_History *History;

PetscErrorCode HistoryOpen(MPI_Comm, const char dir[], History *);
PetscErrorCode HistoryAppend(History, PetscInt step, PetscInt iteration, PetscReal objective, PetscReal jump, PetscInt inner_iterations);
PetscErrorCode HistoryClose(History *, PetscBool complete);
#endif
