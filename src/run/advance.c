/* A run's time loop (run.h): each step taken (with its retries, step_retry.c), its outputs
   recorded, checkpoints written, a signal ending the run after the step in progress. */
#include <errno.h>
#include "run_impl.h"
#include "checkpoint.h"
#include "logging.h"
#include "interrupt.h"
#include "output_files.h"
#include "options.h"
#include "rank_sync.h"

static PetscErrorCode WriteCheckpoint(Run run, PetscInt step)
{
  PetscInt       saved = step;
  Probes         probes;
  FieldWriter    fields;
  PetscErrorCode ierr;
  int            cause;

  PetscFunctionBeginUser;
  PetscCall(StepOutputsGetProbes(run->outputs, &probes));
  PetscCall(StepOutputsGetFields(run->outputs, &fields));
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_CHECKPOINT, 0, 0, 0, 0));
  /* a write that fails (a full disk, a quota, an I/O error) stops the run with one line; the
     last complete checkpoint stays and no temporary is left */
  {
    /* a write that runs out of room part-way fails inside MPI-IO: refuse it before it starts */
    PetscBool enough;
    double    free_bytes, needed, lower = 8.0 * 3 * (run->summary.fluid_dofs + run->summary.structure_dofs);
    PetscCall(CheckpointEnsureSpace(PETSC_COMM_WORLD, run->checkpoint.file, lower, &enough, &free_bytes, &needed));
    if (!enough) {
      if (run->checkpoint.last >= 0)
        SETERRQ(PETSC_COMM_WORLD, PETSC_ERR_FILE_WRITE,
                "cannot write the checkpoint of step %" PetscInt_FMT " to %s: %.0f kB free on its file system, it "
                "needs about %.0f kB; the one of step %" PetscInt_FMT " stays",
                step, run->checkpoint.file, free_bytes / 1024, needed / 1024, run->checkpoint.last);
      SETERRQ(PETSC_COMM_WORLD, PETSC_ERR_FILE_WRITE,
              "cannot write the checkpoint of step %" PetscInt_FMT " to %s: %.0f kB free on its file system, it needs "
              "about %.0f kB; no earlier checkpoint",
              step, run->checkpoint.file, free_bytes / 1024, needed / 1024);
    }
  }
  PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
  errno = 0;
  ierr  = RunCheckpoint(run->checkpoint.file, PETSC_FALSE, &saved, &run->params, &run->checkpoint, &run->summary,
                        run->fluid, run->structure, run->coupling, probes, fields, run->retry);
  cause = errno;
  PetscCall(PetscPopErrorHandler());
  if (ierr) {
    char why[256];
    CheckpointRemoveTemporary(run->checkpoint.file);
    PetscCall(OutputWriteErrorText(run->checkpoint.file, cause, why, sizeof(why)));
    if (run->checkpoint.last >= 0)
      SETERRQ(PETSC_COMM_WORLD, PETSC_ERR_FILE_WRITE,
              "cannot write the checkpoint of step %" PetscInt_FMT " to %s (%s); the one of step %" PetscInt_FMT
              " stays",
              step, run->checkpoint.file, why, run->checkpoint.last);
    SETERRQ(PETSC_COMM_WORLD, PETSC_ERR_FILE_WRITE,
            "cannot write the checkpoint of step %" PetscInt_FMT " to %s (%s); no earlier checkpoint", step,
            run->checkpoint.file, why);
  }
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
  if (run->first_step <= run->params.steps) {
    CouplingStats stats = {0};
    if (run->coupling) PetscCall(CouplingGetStats(run->coupling, &stats));
    PetscCall(ProgressStart(run->progress, &run->params, run->first_step, s->fluid_dofs, s->structure_dofs,
                            run->coupled ? (stats.setting && stats.setting[0] ? stats.setting : run->params.coupling)
                                         : NULL,
                            s->structure_ranks));
  }
  for (PetscInt step = run->first_step; step <= run->params.steps; ++step) {
    PetscCall(StepRetryAdvance(run->retry, step, &run->failure));
    {
      int stopped;
      PetscCall(StepRetryGetStop(run->retry, &stopped));
      if (stopped) {
        /* the step failed and was not retried: the state and the outputs are those of the step before */
        run->signal_caught = stopped;
        s->steps_done      = step - 1;
        s->interrupted     = InterruptName(stopped);
        if (run->checkpoint.possible && step - 1 >= run->first_step && run->checkpoint.last != step - 1)
          PetscCall(WriteCheckpoint(run, step - 1));
        break;
      }
    }
    if (run->failure) {
      /* the outputs end with the last step completed; the last checkpoint stays */
      s->steps_done = step - 1;
      s->failure    = run->failure;
      break;
    }
    PetscCall(StepOutputsRecord(run->outputs, step));
    {
      char when[64];
      PetscCall(PetscSNPrintf(when, sizeof(when), "step %" PetscInt_FMT, step));
      PetscCall(RunCheckRankSync(run, when));
    }
    if (step == run->first_step) {
      /* options PETSc reads in its solves have been read now; a refusal still leaves no outputs */
      PetscCall(OptionsCheckUnused(PETSC_COMM_WORLD, PETSC_TRUE));
      OutputSetUpDone(run->params.output_dir);
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
