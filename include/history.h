#ifndef FSIOPT_HISTORY_H
#define FSIOPT_HISTORY_H
#include "output_files.h"

/* history.csv: one row per coupling iteration (the layout of the seed's Table 3.1) with the
   step's dt, a PartialFile until the run completes. An attempt of a step that failed ends
   with a row of iteration -1 naming what follows in the column event ("retry": the step is
   retried with half the dt; "failed": past -dt_min, the run stops). */
typedef struct _p_History *History;

PetscErrorCode HistoryOpen(MPI_Comm, const char dir[], History *);
PetscErrorCode HistoryAppend(History, PetscInt step, PetscReal dt, PetscInt iteration, PetscReal objective,
                             PetscReal jump, PetscInt inner_iterations);
PetscErrorCode HistoryAppendEvent(History, PetscInt step, PetscReal dt, const char event[]);
PetscErrorCode HistoryClose(History *, PetscBool complete);
#endif
