#ifndef FSIOPT_HISTORY_H
#define FSIOPT_HISTORY_H
#include <petscsys.h>

/* history.csv: one row per coupling iteration (the layout of the seed's Table 3.1).
   Rows go to history.csv.partial; HistoryClose renames it into place, so a failed run
   never leaves a history that looks complete. */
typedef struct _p_History *History;

PetscErrorCode HistoryOpen(MPI_Comm, const char dir[], History *);
PetscErrorCode HistoryAppend(History, PetscInt step, PetscInt iteration, PetscReal objective, PetscReal jump, PetscInt inner_iterations);
PetscErrorCode HistoryClose(History *, PetscBool complete);
PetscErrorCode OutputMakeDirectories(const char dir[]);
#endif
