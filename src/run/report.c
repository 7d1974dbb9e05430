/* A run's report (run.h): summary.json, the closing lines on stdout, and why the run
   stopped early when it did. */
#include "run_impl.h"
#include "logging.h"

static PetscErrorCode PrintClosingLines(Run run)
{
  const RunSummary *s     = &run->summary;
  const PetscInt    steps = PetscMax(s->steps_done - run->first_step + 1, 1);

  PetscFunctionBeginUser;
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "fsiopt: scene %s, %" PetscInt_FMT " steps to t = %g:", run->params.scene,
                        run->params.steps, (double)run->params.t_final));
  for (PetscInt i = 0; i < s->errors.n; ++i)
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, " %s %.3e", s->errors.name[i], (double)s->errors.value[i]));
  if (run->coupling)
    PetscCall(PetscPrintf(PETSC_COMM_WORLD,
                          "\nfsiopt: %" PetscInt_FMT " coupling iterations (%.2f per step), %" PetscInt_FMT
                          " inner, max interface jump %.3e, work factor %.2f",
                          s->coupling_iterations, (double)s->coupling_iterations / steps, s->inner_iterations,
                          (double)s->max_interface_jump, (double)s->work_factor));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "\nfsiopt: outputs in %s/\n", run->params.output_dir));
  PetscFunctionReturn(0);
}

/* The run's last word, raised on every rank after everything is freed (main.c). */
static PetscErrorCode SetStopReason(Run run)
{
  const RunSummary *s                                = &run->summary;
  char              restart[PETSC_MAX_PATH_LEN + 64] = "";

  PetscFunctionBeginUser;
  if (run->failure) {
    if (run->checkpoint.last >= 0)
      PetscCall(PetscSNPrintf(restart, sizeof(restart), "; the last checkpoint (step %" PetscInt_FMT ") is %s",
                              run->checkpoint.last, run->checkpoint.file));
    PetscCall(PetscSNPrintf(run->stop_reason, sizeof(run->stop_reason),
                            "%s; the outputs in %s/ go to step %" PetscInt_FMT "%s", run->failure,
                            run->params.output_dir, s->steps_done, restart));
  } else if (run->signal_caught) {
    run->stop_code = PETSC_ERR_SIG;
    if (run->checkpoint.last == s->steps_done)
      PetscCall(PetscSNPrintf(restart, sizeof(restart), "; go on with -restart %s", run->checkpoint.file));
    PetscCall(PetscSNPrintf(run->stop_reason, sizeof(run->stop_reason),
                            "interrupted by %s after step %" PetscInt_FMT " of %" PetscInt_FMT
                            " (t = %g); the outputs in %s/ go to that step%s",
                            s->interrupted, s->steps_done, run->params.steps,
                            (double)(run->params.t_start + s->steps_done * run->params.dt), run->params.output_dir,
                            restart));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode RunReport(Run run)
{
  RunSummary    *s = &run->summary;
  PetscLogDouble end;

  PetscFunctionBeginUser;
  if (run->help) PetscFunctionReturn(0);
  PetscCall(PetscLogStagePush(FSIOPT_STAGE_OUTPUT));
  PetscCall(SummaryGather(s, run->scene.has_fluid, run->scene.has_structure, run->fluid, run->structure, run->coupling,
                          run->retry));
  PetscCall(OutputsFinish(run->outputs, &s->quantities));
  PetscCall(PetscTime(&end));
  s->params      = &run->params;
  s->units       = run->scene.units;
  s->wall_time_s = end - run->start;
  s->converged   = s->stalled_steps == 0 && !run->signal_caught && !run->failure ? PETSC_TRUE : PETSC_FALSE;
  PetscCall(SummaryWrite(PETSC_COMM_WORLD, run->params.output_dir, s));
  PetscCall(PrintClosingLines(run));
  PetscCall(PetscLogStagePop());
  PetscCall(SetStopReason(run));
  PetscFunctionReturn(0);
}
