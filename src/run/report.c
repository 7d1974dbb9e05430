/* A run's report (run.h): summary.json, the closing lines on stdout, and why the run
   stopped early when it did. */
#include "run_impl.h"
#include "logging.h"

/* The values a case is run for: every probe column when there are a few (a Turek-Hron
   case's displacement of A, drag and lift), else the forces on the body; final values, or
   mean +- amplitude over the quantities' window when they swing. */
static PetscErrorCode PrintQuantities(const QuantityTable *q)
{
  PetscBool any = PETSC_FALSE;

  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < q->n; ++i) {
    const char *name = q->name[i];
    PetscBool   force, drag, lift;

    PetscCall(PetscStrbeginswith(name, "drag", &drag));
    PetscCall(PetscStrbeginswith(name, "lift", &lift));
    PetscCall(PetscStrbeginswith(name, "force", &force));
    if (q->n > 4 && !(drag || lift || force)) continue;
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s %s ", any ? "," : "\nfsiopt:", name));
    if (q->amplitude[i] > 0 && q->frequency[i] > 0)
      PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%.6g +- %.4g (mean +- amplitude over the last %g)",
                            (double)q->mean[i], (double)q->amplitude[i], (double)q->window));
    else PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%.6g", (double)q->final[i]));
    any = PETSC_TRUE;
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode PrintClosingLines(Run run)
{
  const RunSummary *s     = &run->summary;
  const PetscInt    steps = PetscMax(s->steps_done - run->first_step + 1, 1);

  PetscFunctionBeginUser;
  if (s->steps_done < run->params.steps)
    PetscCall(PetscPrintf(PETSC_COMM_WORLD,
                          "fsiopt: scene %s, stopped after step %" PetscInt_FMT " of %" PetscInt_FMT
                          " (t = %g of %g, %s):",
                          run->params.scene, s->steps_done, run->params.steps,
                          (double)(run->params.t_start + s->steps_done * run->params.dt), (double)run->params.t_final,
                          s->interrupted ? s->interrupted : "a step failed"));
  else
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "fsiopt: scene %s, %" PetscInt_FMT " steps to t = %g:", run->params.scene,
                          run->params.steps, (double)run->params.t_final));
  for (PetscInt i = 0; i < s->errors.n; ++i)
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, " %s %.3e", s->errors.name[i], (double)s->errors.value[i]));
  if (run->coupling) {
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "\nfsiopt: %" PetscInt_FMT " coupling iterations (%.2f per step), ",
                          s->coupling_iterations, (double)s->coupling_iterations / steps));
    if (s->inner_iterations) PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%" PetscInt_FMT " inner, ", s->inner_iterations));
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "work factor %.2f", (double)s->work_factor));
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "\nfsiopt: tolerance on the %s; the largest a step ended with: %.3e",
                          s->convergence_measure, (double)s->max_convergence_measure));
  }
  PetscCall(PrintQuantities(&s->quantities));
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
  StepRetryStats retry;
  PetscLogDouble end;

  PetscFunctionBeginUser;
  if (run->help) PetscFunctionReturn(0);
  PetscCall(PetscLogStagePush(FSIOPT_STAGE_OUTPUT));
  PetscCall(StepRetryGetStats(run->retry, &retry));
  s->retried_steps   = retry.retried_steps;
  s->failed_attempts = retry.failed_attempts;
  s->smallest_dt     = retry.smallest_dt;
  PetscCall(
    SummaryGather(s, run->scene.has_fluid, run->scene.has_structure, run->fluid, run->structure, run->coupling));
  if (run->coupling) PetscCall(CouplingFinish(run->coupling)); /* history.csv under its final name */
  PetscCall(StepOutputsFinish(run->outputs, &s->quantities));
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
