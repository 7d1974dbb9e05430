#ifndef FSIOPT_PROGRESS_H
#define FSIOPT_PROGRESS_H
#include "fsiopt.h"
#include "coupling.h"

/* What a run prints while it goes (rank 0, stdout, flushed): a first line before the first
   step (scene, unknowns per side, ranks, dt, steps), then a line every -progress_interval
   steps or, by default, about every 2 s of wall time (step k/N, t, coupling iterations of
   the step and on average, interface jump, wall time, ETA). -quiet prints neither. */
typedef struct _p_Progress *Progress;

PetscErrorCode ProgressCreate(MPI_Comm, Progress *);
/* collective: the unknowns of a side are known on its ranks; structure_ranks: K of a
   fluid | structure split, else anything outside 1..ranks-1 */
PetscErrorCode ProgressStart(Progress, const RunParams *, PetscInt first_step, PetscInt fluid_dofs,
                             PetscInt structure_dofs, const char method[], PetscMPIInt structure_ranks);
/* coupling may be NULL (a scene with one side) */
PetscErrorCode ProgressStep(Progress, PetscInt step, Coupling);
PetscErrorCode ProgressDestroy(Progress *);
#endif
