/* A run's time loop (run.h): each step taken (with its retries, step_retry.c), its outputs
   recorded, checkpoints written, a signal ending the run after the step in progress. */
#include "run_impl.h"
#include "logging.h"
#include "interrupt.h"
#include "output.h"
#include "options.h"

static PetscErrorCode WriteCheckpoint(Run run, PetscInt step)
{
  PetscInt    saved = step;
  Probes      probes;
  FieldWriter fields;

  PetscFunctionBeginUser;
  PetscCall(OutputsGetProbes(run->outputs, &probes));
  PetscCall(OutputsGetFields(run->outputs, &fields));
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_CHECKPOINT, 0, 0, 0, 0));
  PetscCall(RunCheckpoint(run->checkpoint.file, PETSC_FALSE, &saved, &run->params, &run->checkpoint, &run->summary,
                          run->fluid, run->structure, run->coupling, probes, fields, run->retry));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_CHECKPOINT, 0, 0, 0, 0));
  run->checkpoint.last = step;
  PetscFunctionReturn(0);
}

PetscErrorCode RunAdvance(Run run)
{
  RunSummary *s         = &run->summary;
  PetscBool   requested = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(InterruptInstall());
  s->steps_done = run->params.steps;
  s->first_step = run->first_step;
  if (run->first_step <= run->params.steps)
    PetscCall(ProgressStart(run->progress, &run->params, run->first_step, s->fluid_dofs, s->structure_dofs,
                            run->coupled ? run->params.coupling : NULL));
  for (PetscInt step = run->first_step; step <= run->params.steps; ++step) {
    PetscCall(StepRetryAdvance(run->retry, step, &run->failure));
    if (run->failure) {
      /* the outputs end with the last step completed; the last checkpoint stays */
      s->steps_done = step - 1;
      s->failure    = run->failure;
      break;
    }
    PetscCall(OutputsRecord(run->outputs, step));
    if (step == run->first_step) {
      /* options PETSc reads in its solves have been read now; a refusal still leaves no outputs */
      PetscCall(OptionsCheckUnused(PETSC_COMM_WORLD, PETSC_TRUE));
      OutputSetUpDone();
    }
    PetscCall(ProgressStep(run->progress, step, run->coupling));
    PetscCall(InterruptTestAfterStep(step));
    PetscCall(InterruptCheck(PETSC_COMM_WORLD, &run->signal_caught, &requested));
    /* an interrupted run leaves a checkpoint of its last step when its set-up can */
    if ((run->checkpoint.every && step % run->checkpoint.every == 0) ||
        ((run->signal_caught || requested) && run->checkpoint.possible && step < run->params.steps))
      PetscCall(WriteCheckpoint(run, step));
    if (requested && !run->signal_caught) {
      if (run->checkpoint.last == step)
        PetscCall(PetscPrintf(PETSC_COMM_WORLD,
                              "fsiopt: SIGUSR1: checkpoint of step %" PetscInt_FMT " in %s; the run goes on\n", step,
                              run->checkpoint.file));
      else
        PetscCall(PetscPrintf(PETSC_COMM_WORLD, "fsiopt: SIGUSR1 after step %" PetscInt_FMT ": %s; the run goes on\n",
                              step,
                              step == run->params.steps ? "the last step, no checkpoint needed"
                                                        : "this set-up writes no checkpoints"));
    }
    if (run->signal_caught) {
      s->steps_done  = step;
      s->interrupted = InterruptName(run->signal_caught);
      break;
    }
  }
  PetscFunctionReturn(0);
}
