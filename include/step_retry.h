#ifndef FSIOPT_STEP_RETRY_H
#define FSIOPT_STEP_RETRY_H
#include "fsiopt.h"
#include "fluid.h"
#include "structure.h"
#include "coupling.h"

/* Advancing the run by one step of -dt. A step whose solve fails (StepFailure: a
   subproblem's Newton solve, a mesh that inverts, the coupling not converging) goes back
   to the state it started from, kept in memory, and is taken again as two steps of half
   the dt, each of which may be halved again, down to -dt_min (default dt/16; -dt_min
   equal to -dt: no retries, and no copy of the state). The steps after it go back to -dt.
   Each failed attempt is a row of history.csv (coupled runs) and a line on stdout. */
typedef struct _p_StepRetry *StepRetry;
typedef struct {
  PetscInt  retried_steps;   /* steps that needed a smaller dt */
  PetscInt  failed_attempts; /* attempts that failed, over all steps */
  PetscReal smallest_dt;     /* the smallest dt a step was completed with */
} StepRetryStats;

PetscErrorCode StepRetryCreate(const RunParams *, Fluid, Structure, Coupling, StepRetry *);
/* Takes step `step` (from t_start + (step-1) dt to t_start + step dt). On return *failure
   is NULL, or the reason the step failed with the smallest dt allowed; the state is then
   the failed attempt's. A stopping signal caught when an attempt from the step's start has
   failed ends the step there instead of retrying it: *failure is NULL, the state is the
   one the step started from, and StepRetryGetStop names the signal. Collective. */
PetscErrorCode StepRetryAdvance(StepRetry, PetscInt step, const char **failure);
/* The signal that ended the last step before its retries (0: none) */
PetscErrorCode StepRetryGetStop(StepRetry, int *signum);
/* Sets the dt of the fluid, structure and coupling, as a retried step does: BDF2 starts
   again with one backward-Euler step and the coupling drops its extrapolation history. */
PetscErrorCode StepRetrySetTimeStep(StepRetry, PetscReal dt);
PetscErrorCode StepRetryGetStats(StepRetry, StepRetryStats *);
PetscErrorCode StepRetryDestroy(StepRetry *);
#endif
