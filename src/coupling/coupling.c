/* The coupling-method interface: the registry of methods by name, and the step skeleton
   they share (begin the step, collect failures, count, end the step), so that a method is
   only its iteration. */
#include "coupling_impl.h"
#include "options.h"
#include "checkpoint.h"

PetscFunctionList CouplingList = NULL;

/* The methods by name, each one file: a new method is its file and a line here. */
#define COUPLING_METHODS(METHOD) \
  METHOD("opt", CouplingCreate_Opt)         /* opt.c */ \
  METHOD("dn", CouplingCreate_DN)           /* acceleration_constant.c */ \
  METHOD("aitken", CouplingCreate_Aitken)   /* acceleration_aitken.c */ \
  METHOD("iqnils", CouplingCreate_IQNILS)   /* acceleration_iqnils.c */ \
  METHOD("iqnimvj", CouplingCreate_IQNIMVJ) /* acceleration_iqnimvj.c */ \
  METHOD("monolithic", CouplingCreate_Monolithic) /* monolithic.c */
#define DECLARE(name, create) PetscErrorCode create(Coupling);
COUPLING_METHODS(DECLARE)
#undef DECLARE

PetscErrorCode CouplingRegister(const char name[], PetscErrorCode (*create)(Coupling))
{
  PetscFunctionBeginUser;
  PetscCall(PetscFunctionListAdd(&CouplingList, name, create));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingRegisterAll(void)
{
  PetscFunctionBeginUser;
  if (CouplingList) PetscFunctionReturn(0);
#define REGISTER(name, create) PetscCall(CouplingRegister(name, create));
  COUPLING_METHODS(REGISTER)
#undef REGISTER
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingListNames(char names[], size_t len)
{
  PetscFunctionBeginUser;
  PetscCall(OptionsListNames(CouplingList, names, len));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingCheckMethod(const char method[])
{
  PetscErrorCode (*create)(Coupling) = NULL;
  char names[256];

  PetscFunctionBeginUser;
  PetscCall(PetscFunctionListFind(CouplingList, method, &create));
  if (create) PetscFunctionReturn(0);
  PetscCall(CouplingListNames(names, sizeof(names)));
  SETERRQ(PETSC_COMM_WORLD, PETSC_ERR_ARG_UNKNOWN_TYPE,
          "option -coupling %s: unknown coupling method; expected one of: %s", method, names);
}

PetscErrorCode CouplingFinalize(void)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFunctionListDestroy(&CouplingList));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingCreate(const char method[], CouplingProblem problem, const char output_dir[], PetscReal t0,
                              PetscReal dt, Coupling *coupling)
{
  Coupling C;
  PetscInt degree, points, ar_order, ar_from;
  PetscErrorCode (*create)(Coupling) = NULL;

  PetscFunctionBeginUser;
  PetscCall(PetscFunctionListFind(CouplingList, method, &create));
  if (!create) PetscCall(CouplingCheckMethod(method)); /* the error naming the known methods */
  PetscCall(PetscNew(&C));
  PetscCall(PetscStrncpy(C->method, method, sizeof(C->method)));
  C->problem = problem;
  C->dt      = dt;
  /* the method's operations and defaults (max_it among them), before the options */
  PetscCall((*create)(C));
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Coupling options", "coupling");
  degree = 1;
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-coupling_extrapolation",
                              "each step starts from the control extrapolated from the last K+1 steps by a polynomial "
                              "of degree K (0: the last control, Kuberry 2015 Remark 3.4)",
                              0, FSIOPT_EXTRAPOLATION_MAX, &degree));
  points = degree + 1;
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-coupling_extrapolation_points",
                              "fit that polynomial by least squares to the last M >= K+1 steps: a larger M damps the "
                              "error of controls accepted at the tolerance",
                              1, FSIOPT_EXTRAPOLATION_POINTS_MAX, &points));
  PetscCheck(points > degree, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
             "option -coupling_extrapolation_points: expected at least -coupling_extrapolation + 1 = %" PetscInt_FMT
             " steps, got %" PetscInt_FMT,
             degree + 1, points);
  ar_order = 0;
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-coupling_extrapolation_recurrence",
                              "also fit the linear recurrence g^n = sum_{i<=P} a_i g^{n-i} to the last steps' controls "
                              "(least squares) and start from it when, fitted without the last control, it predicted "
                              "that control better than the polynomial did (0: the polynomial only)",
                              0, FSIOPT_EXTRAPOLATION_POINTS_MAX - 3, &ar_order));
  PetscCheck(ar_order == 0 || points >= ar_order + 3, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
             "option -coupling_extrapolation_recurrence %" PetscInt_FMT
             ": its fit needs the last P+3 controls; expected -coupling_extrapolation_points >= %" PetscInt_FMT
             ", got %" PetscInt_FMT,
             ar_order, ar_order + 3, points);
  ar_from = 4;
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-coupling_extrapolation_recurrence_from",
                              "fit the recurrence once this many controls are recorded, of order min(P, count - 3) "
                              "while fewer than P+3 are (P+3: only of order P)",
                              4, FSIOPT_EXTRAPOLATION_POINTS_MAX, &ar_from));
  PetscCheck(ar_order == 0 || ar_from <= points, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
             "option -coupling_extrapolation_recurrence_from %" PetscInt_FMT
             ": no more than -coupling_extrapolation_points = %" PetscInt_FMT " controls are recorded",
             ar_from, points);
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-coupling_max_it",
                              "coupling iterations per step before the step fails", 1, 100000, &C->max_it));
  PetscOptionsEnd();
  C->stats.max_jump = 0;
  PetscCall(CouplingProblemCreateControl(problem, &C->x));
  PetscCall(CouplingProblemInitialControl(problem, t0, C->x));
  PetscCall(ExtrapolationCreate(C->x, degree, points, &C->start));
  C->start.ar_order = ar_order;
  C->start.ar_from  = ar_from;
  PetscCall(HistoryOpen(PETSC_COMM_WORLD, output_dir, &C->history));
  PetscCall((*C->ops.setup)(C));
  *coupling = C;
  PetscFunctionReturn(0);
}

/* "opt (brgn)" or "iqnils": how failure messages name the method */
static void CouplingLabel(Coupling C, char label[], size_t len)
{
  const char *optimizer = C->ops.optimizer ? C->ops.optimizer(C) : NULL;

  if (optimizer) (void)PetscSNPrintf(label, len, "%s (%s)", C->method, optimizer);
  else (void)PetscStrncpy(label, C->method, len);
}

/* A subproblem's failure outside the method's iteration: the step fails, naming where. */
static PetscErrorCode CheckProblemFailure(Coupling C, PetscInt step, const char where[], PetscBool *failed)
{
  const char *failure;
  char        label[64];

  PetscFunctionBeginUser;
  PetscCall(CouplingProblemGetFailure(C->problem, &failure));
  *failed = failure ? PETSC_TRUE : PETSC_FALSE;
  if (!failure) PetscFunctionReturn(0);
  CouplingLabel(C, label, sizeof(label));
  PetscCall(StepFailureSet(&C->failure, "coupling %s %s step %" PetscInt_FMT ": %s", label, where, step, failure));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingStep(Coupling C, PetscInt step)
{
  CouplingIterations it = {0, 0, 0, -1, PETSC_FALSE};
  PetscBool          failed;

  PetscFunctionBeginUser;
  StepFailureClear(&C->failure);
  PetscCall(ExtrapolationRecord(&C->start, C->x));
  PetscCall(ExtrapolationPredict(&C->start, C->x));
  PetscCall(CouplingProblemBeginStep(C->problem, step));
  PetscCall(CheckProblemFailure(C, step, "before the first iteration of", &failed));
  if (failed) PetscFunctionReturn(0);
  PetscCall((*C->ops.iterate)(C, step, &it));
  /* a failed attempt's work counts too */
  C->stats.iterations += it.iterations;
  C->stats.linearized_pairs += it.linearized_pairs;
  if (StepFailed(&C->failure)) PetscFunctionReturn(0);
  PetscCall(CouplingProblemEndStep(C->problem, C->x));
  PetscCall(CheckProblemFailure(C, step, "at the end of", &failed));
  if (failed) PetscFunctionReturn(0);
  if (C->ops.end_step) PetscCall((*C->ops.end_step)(C));
  if (it.stalled) {
    char label[64];
    CouplingLabel(C, label, sizeof(label));
    C->stats.stalled_steps++;
    PetscCall(PetscPrintf(PETSC_COMM_WORLD,
                          "fsiopt: warning: step %" PetscInt_FMT " stalled after %" PetscInt_FMT
                          " iterations (%s) at interface jump %.3e\n",
                          step, it.iterations, label, (double)it.jump));
  }
  C->stats.max_jump    = PetscMax(C->stats.max_jump, it.jump);
  C->stats.last_jump   = it.jump;
  C->stats.max_measure = PetscMax(C->stats.max_measure, it.measure < 0 ? it.jump : it.measure);
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingGetFailure(Coupling C, const char **reason)
{
  PetscFunctionBeginUser;
  *reason = StepFailureReason(&C->failure);
  PetscFunctionReturn(0);
}

/* The past controls were a step of the old dt apart: the next step starts from the last. */
PetscErrorCode CouplingSetTimeStep(Coupling C, PetscReal dt)
{
  PetscFunctionBeginUser;
  if (dt == C->dt) PetscFunctionReturn(0);
  C->dt = dt;
  PetscCall(CouplingProblemSetTimeStep(C->problem, dt));
  C->start.npast = 0;
  if (C->ops.resynchronize) PetscCall((*C->ops.resynchronize)(C));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingLogRetry(Coupling C, PetscInt step, const char event[])
{
  PetscFunctionBeginUser;
  PetscCall(HistoryAppendEvent(C->history, step, C->dt, event));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingCheckpoint(Coupling C, Checkpoint cp, PetscBool load)
{
  PetscFunctionBeginUser;
  PetscCheck(C->ops.restartable || !CheckpointIsFile(cp), PETSC_COMM_WORLD, PETSC_ERR_SUP,
             "option %s: checkpoints are not supported for -coupling %s (its past iterates are not saved)",
             load ? "-restart" : "-checkpoint_every", C->method);
  PetscCall(CheckpointPushGroup(cp, "/coupling"));
  PetscCall(CheckpointVec(cp, "control", C->x, load));
  PetscCall(ExtrapolationCheckpoint(&C->start, cp, "control", load));
  if (C->ops.checkpoint) PetscCall((*C->ops.checkpoint)(C, cp, load));
  PetscCall(CouplingProblemCheckpoint(C->problem, cp, load));
  PetscCall(CheckpointPopGroup(cp));
  if (CheckpointResynchronizes(cp, load) && C->ops.resynchronize) PetscCall((*C->ops.resynchronize)(C));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingIsRestartable(Coupling C, PetscBool *restartable)
{
  PetscFunctionBeginUser;
  *restartable = C->ops.restartable;
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingGetStats(Coupling C, CouplingStats *stats)
{
  PetscFunctionBeginUser;
  *stats         = C->stats;
  stats->measure = C->measure;
  stats->setting = C->setting;
  PetscCall(CouplingProblemGetProductCounts(C->problem, &stats->forward_products, &stats->adjoint_products));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingGetOptimizer(Coupling C, const char **name)
{
  PetscFunctionBeginUser;
  *name = C->ops.optimizer ? C->ops.optimizer(C) : NULL;
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingFinish(Coupling C)
{
  PetscFunctionBeginUser;
  PetscCall(HistoryClose(&C->history, PETSC_TRUE));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingDestroy(Coupling *coupling)
{
  Coupling C = *coupling;

  PetscFunctionBeginUser;
  if (!C) PetscFunctionReturn(0);
  if (C->start.ar_order > 0)
    PetscCall(PetscInfo(NULL, "the fitted recurrence started %" PetscInt_FMT " of %" PetscInt_FMT " steps\n",
                        C->start.recurrence_predictions, C->start.predictions));
  if (C->ops.destroy) PetscCall((*C->ops.destroy)(C));
  PetscCall(HistoryClose(&C->history, PETSC_FALSE));
  PetscCall(VecDestroy(&C->x));
  PetscCall(ExtrapolationDestroy(&C->start));
  PetscCall(PetscFree(*coupling));
  PetscFunctionReturn(0);
}
