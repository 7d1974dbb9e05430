/* A step of the run, retried with half the dt while it fails (step_retry.h). */
#include "step_retry.h"
#include "checkpoint.h"
#include "options.h"
#include "logging.h"
#include "interrupt.h"

struct _p_StepRetry {
  const RunParams *params;
  Fluid            fluid; /* NULL on ranks without them */
  Structure        structure;
  Coupling         coupling; /* coupled runs step through it; NULL: single physics */
  PetscReal        dt_min;
  Checkpoint       start; /* the state the attempt in progress started from; NULL: no retries */
  StepFailure      failure;
  StepRetryStats   stats;
  PetscReal        step_start; /* t at the start of the step in progress */
  int              stopped;    /* the signal that ended the step in progress before a retry (0: none) */
};

PetscErrorCode StepRetryCreate(const RunParams *params, Fluid fluid, Structure structure, Coupling coupling,
                               StepRetry *retry)
{
  StepRetry R;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&R));
  R->params    = params;
  R->coupling  = coupling;
  R->fluid     = fluid;
  R->structure = structure;
  R->dt_min    = params->dt / 16;
  PetscCall(OptionsDeclareUnit("-dt_min", UNIT_TIME));
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Diverging steps", "fsiopt");
  PetscCall(OptionsPositiveReal(PetscOptionsObject, "-dt_min",
                                "a failing step is retried as two steps of half its dt, down to this dt (default "
                                "-dt/16; -dt: no retries)",
                                &R->dt_min));
  PetscOptionsEnd();
  PetscCheck(R->dt_min <= params->dt * (1 + 1e-12), PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
             "option -dt_min: expected at most -dt = %g, got %g", (double)params->dt, (double)R->dt_min);
  if (R->dt_min <= params->dt / 2 * (1 + 1e-12)) PetscCall(CheckpointCreateInMemory(&R->start));
  R->stats.smallest_dt = params->dt;
  *retry               = R;
  PetscFunctionReturn(0);
}

PetscErrorCode StepRetrySetTimeStep(StepRetry R, PetscReal dt)
{
  PetscFunctionBeginUser;
  if (R->coupling) PetscCall(CouplingSetTimeStep(R->coupling, dt)); /* and its fluid and structure */
  else if (R->fluid) PetscCall(FluidSetTimeStep(R->fluid, dt));
  else if (R->structure) PetscCall(StructureSetTimeStep(R->structure, dt));
  PetscFunctionReturn(0);
}

/* Saves (load = PETSC_FALSE) or restores the state the attempt in progress started from. */
static PetscErrorCode KeepStart(StepRetry R, PetscBool load)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_STEP_START, 0, 0, 0, 0));
  if (R->fluid) PetscCall(FluidCheckpoint(R->fluid, R->start, load));
  if (R->structure) PetscCall(StructureCheckpoint(R->structure, R->start, load));
  if (R->coupling) PetscCall(CouplingCheckpoint(R->coupling, R->start, load));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_STEP_START, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

static PetscErrorCode TakeStep(StepRetry R, PetscInt step, const char **failure)
{
  PetscFunctionBeginUser;
  *failure = NULL;
  if (R->coupling) {
    PetscCall(CouplingStep(R->coupling, step));
    PetscCall(CouplingGetFailure(R->coupling, failure));
    PetscFunctionReturn(0);
  }
  if (R->fluid) {
    PetscCall(PetscLogStagePush(FSIOPT_STAGE_FLUID));
    PetscCall(FluidStep(R->fluid, step));
    PetscCall(PetscLogStagePop());
    PetscCall(FluidGetFailure(R->fluid, failure));
  }
  if (R->structure && !*failure) {
    PetscCall(PetscLogStagePush(FSIOPT_STAGE_STRUCTURE));
    PetscCall(StructureStep(R->structure, step));
    PetscCall(PetscLogStagePop());
    PetscCall(StructureGetFailure(R->structure, failure));
  }
  PetscFunctionReturn(0);
}

/* One step of size dt from the present state; on failure, two of dt/2 from the same state. */
static PetscErrorCode Attempt(StepRetry R, PetscInt step, PetscReal t, PetscReal dt, PetscBool *failed)
{
  const char *reason;
  PetscBool   retry;

  PetscFunctionBeginUser;
  if (R->start) PetscCall(KeepStart(R, PETSC_FALSE));
  PetscCall(StepRetrySetTimeStep(R, dt));
  PetscCall(TakeStep(R, step, &reason));
  *failed = reason ? PETSC_TRUE : PETSC_FALSE;
  if (!*failed) {
    R->stats.smallest_dt = PetscMin(R->stats.smallest_dt, dt);
    PetscFunctionReturn(0);
  }
  R->stats.failed_attempts++;
  retry = R->start && dt / 2 >= R->dt_min * (1 - 1e-12) ? PETSC_TRUE : PETSC_FALSE;
  if (retry && t == R->step_start) {
    /* A stop asked for now would otherwise wait for every retry (a diverging step may take
       minutes, longer than a batch system's grace before SIGKILL). From the step's start the
       state kept is the one the step began with: back to it, at the run's dt, and stop there. */
    int signum;
    PetscCall(InterruptTestAfterFailure());
    PetscCall(InterruptStopPending(PETSC_COMM_WORLD, &signum));
    if (signum) {
      if (R->coupling) PetscCall(CouplingLogRetry(R->coupling, step, "failed"));
      PetscCall(StepRetrySetTimeStep(R, R->params->dt));
      PetscCall(KeepStart(R, PETSC_TRUE));
      R->stopped = signum;
      PetscCall(PetscPrintf(PETSC_COMM_WORLD, "fsiopt: %s; not retried: %s asks the run to stop\n", reason,
                            InterruptName(signum)));
      PetscFunctionReturn(0);
    }
  }
  if (R->coupling) PetscCall(CouplingLogRetry(R->coupling, step, retry ? "retry" : "failed"));
  if (!retry) {
    if (!R->start)
      PetscCall(StepFailureSet(&R->failure, "%s (from t = %g with dt %g; no retries: -dt_min is -dt)", reason,
                               (double)t, (double)dt));
    else
      PetscCall(StepFailureSet(&R->failure, "%s (from t = %g with dt %g, halved down to -dt_min %g)", reason, (double)t,
                               (double)dt, (double)R->dt_min));
    PetscFunctionReturn(0);
  }
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "fsiopt: %s; retrying with dt = %g\n", reason, (double)(dt / 2)));
  PetscCall(KeepStart(R, PETSC_TRUE));
  *failed = PETSC_FALSE;
  /* a stopped half returns failed, which ends this loop too */
  for (PetscInt half = 0; half < 2 && !*failed; ++half) PetscCall(Attempt(R, step, t + half * dt / 2, dt / 2, failed));
  PetscFunctionReturn(0);
}

PetscErrorCode StepRetryAdvance(StepRetry R, PetscInt step, const char **failure)
{
  const PetscInt failed_before = R->stats.failed_attempts;
  PetscBool      failed;

  PetscFunctionBeginUser;
  StepFailureClear(&R->failure);
  R->step_start = R->params->t_start + (step - 1) * R->params->dt;
  R->stopped    = 0;
  PetscCall(Attempt(R, step, R->step_start, R->params->dt, &failed));
  if (R->stats.failed_attempts > failed_before && !failed) R->stats.retried_steps++;
  *failure = failed && !R->stopped ? R->failure.reason : NULL;
  PetscFunctionReturn(0);
}

PetscErrorCode StepRetryGetStop(StepRetry R, int *signum)
{
  PetscFunctionBeginUser;
  *signum = R->stopped;
  PetscFunctionReturn(0);
}

PetscErrorCode StepRetryGetStats(StepRetry R, StepRetryStats *stats)
{
  PetscFunctionBeginUser;
  *stats = R->stats;
  PetscFunctionReturn(0);
}

PetscErrorCode StepRetryDestroy(StepRetry *retry)
{
  PetscFunctionBeginUser;
  if (!*retry) PetscFunctionReturn(0);
  PetscCall(CheckpointDestroy(&(*retry)->start));
  PetscCall(PetscFree(*retry));
  PetscFunctionReturn(0);
}
