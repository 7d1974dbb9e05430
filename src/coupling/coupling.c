/* The coupling-method interface: create by name, advance one step, report. */
#include "coupling_impl.h"
#include "options.h"
#include "checkpoint.h"

PetscErrorCode CouplingCreate(const char method[], CouplingProblem problem, const char output_dir[], PetscReal t0, PetscReal dt, Coupling *coupling)
{
  Coupling  C;
  PetscBool opt, partitioned = PETSC_FALSE;
  PetscInt  degree, points;

  PetscFunctionBeginUser;
  PetscCall(PetscStrcmp(method, "opt", &opt));
  for (const char **m = (const char *[]){"dn", "aitken", "iqnils", NULL}; *m && !partitioned; ++m) PetscCall(PetscStrcmp(method, *m, &partitioned));
  PetscCheck(opt || partitioned, PETSC_COMM_WORLD, PETSC_ERR_SUP, "option -coupling %s: unknown coupling method; expected opt, dn, aitken or iqnils", method);
  PetscCall(PetscNew(&C));
  PetscCall(PetscStrncpy(C->method, method, sizeof(C->method)));
  C->problem = problem;
  C->dt      = dt;
  C->tol     = 1e-10;
  C->max_it  = opt ? 50 : 500; /* relaxation methods may need hundreds */
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Coupling options", "coupling");
  PetscCall(OptionsPositiveReal(PetscOptionsObject, "-coupling_tol", "stop when ||u - v_s||_{L2(Gamma_I)} falls below this", &C->tol));
  degree = 1;
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-coupling_extrapolation", "each step starts from the control extrapolated from the last K+1 steps by a polynomial of degree K (0: the last control, seed Remark 3.4)", 0, FSIOPT_EXTRAPOLATION_MAX, &degree));
  points = degree + 1;
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-coupling_extrapolation_points", "fit that polynomial by least squares to the last M >= K+1 steps: a larger M damps the error of controls accepted at the tolerance", 1, FSIOPT_EXTRAPOLATION_POINTS_MAX, &points));
  PetscCheck(points > degree, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE, "option -coupling_extrapolation_points: expected at least -coupling_extrapolation + 1 = %" PetscInt_FMT " steps, got %" PetscInt_FMT, degree + 1, points);
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-coupling_max_it", "coupling iterations per step before the run stops with an error", 1, 100000, &C->max_it));
  PetscOptionsEnd();
  C->stats.max_jump = 0;
  PetscCall(CouplingProblemSetConvergedJump(problem, C->tol));
  PetscCall(CouplingProblemCreateControl(problem, &C->x));
  PetscCall(CouplingProblemInitialControl(problem, t0, C->x));
  PetscCall(ExtrapolationCreate(C->x, degree, points, &C->start));
  PetscCall(HistoryOpen(PETSC_COMM_WORLD, output_dir, &C->history));
  if (opt) PetscCall(CouplingCreate_Opt(C));
  else PetscCall(CouplingCreate_Partitioned(C));
  *coupling = C;
  PetscFunctionReturn(0);
}

PetscErrorCode ExtrapolationCreate(Vec model, PetscInt degree, PetscInt points, Extrapolation *e)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(e, sizeof(*e)));
  e->degree = degree;
  e->points = points;
  for (PetscInt i = 0; i < points; ++i) PetscCall(VecDuplicate(model, &e->past[i]));
  PetscFunctionReturn(0);
}

PetscErrorCode ExtrapolationRecord(Extrapolation *e, Vec x)
{
  Vec oldest = e->past[e->points - 1];

  PetscFunctionBeginUser;
  for (PetscInt i = e->points - 1; i > 0; --i) e->past[i] = e->past[i - 1];
  e->past[0] = oldest;
  PetscCall(VecCopy(x, e->past[0]));
  e->npast = PetscMin(e->npast + 1, e->points);
  PetscFunctionReturn(0);
}

/* The weights w with sum_i w_i p(-i-1) = p(0) for the least-squares fit p of degree
   `degree` to `n` values at times -1, ..., -n (binomial coefficients with alternating
   signs when n = degree + 1): w = V y with (V^T V) y = e_0, V the Vandermonde matrix. */
static void ExtrapolationWeights(PetscInt degree, PetscInt n, PetscScalar w[])
{
  const PetscInt m = degree + 1;
  PetscReal      gram[FSIOPT_EXTRAPOLATION_MAX + 1][FSIOPT_EXTRAPOLATION_MAX + 2] = {{0}};

  for (PetscInt r = 0; r < m; ++r) {
    for (PetscInt c = 0; c < m; ++c)
      for (PetscInt i = 0; i < n; ++i) gram[r][c] += PetscPowRealInt(-(i + 1.0), r + c);
    gram[r][m] = r == 0;
  }
  for (PetscInt k = 0; k < m; ++k) /* the Gram matrix is positive definite: no pivoting */
    for (PetscInt r = k + 1; r < m; ++r)
      for (PetscInt c = m; c >= k; --c) gram[r][c] -= gram[r][k] / gram[k][k] * gram[k][c];
  for (PetscInt r = m - 1; r >= 0; --r) {
    for (PetscInt c = r + 1; c < m; ++c) gram[r][m] -= gram[r][c] * gram[c][m];
    gram[r][m] /= gram[r][r];
  }
  for (PetscInt i = 0; i < n; ++i) {
    w[i] = 0;
    for (PetscInt r = 0; r < m; ++r) w[i] += PetscPowRealInt(-(i + 1.0), r) * gram[r][m];
  }
}

PetscErrorCode ExtrapolationPredict(Extrapolation *e, Vec x)
{
  PetscScalar    weights[FSIOPT_EXTRAPOLATION_POINTS_MAX];
  const PetscInt degree = PetscMin(e->degree, e->npast - 1);

  PetscFunctionBeginUser;
  if (degree < 0) PetscFunctionReturn(0); /* nothing recorded: x stays */
  ExtrapolationWeights(degree, e->npast, weights);
  PetscCall(VecZeroEntries(x));
  PetscCall(VecMAXPY(x, e->npast, weights, e->past));
  PetscFunctionReturn(0);
}

PetscErrorCode ExtrapolationDestroy(Extrapolation *e)
{
  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < e->points; ++i) PetscCall(VecDestroy(&e->past[i]));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingStep(Coupling C, PetscInt step)
{
  PetscFunctionBeginUser;
  StepFailureClear(&C->failure);
  PetscCall(ExtrapolationRecord(&C->start, C->x));
  PetscCall(ExtrapolationPredict(&C->start, C->x));
  PetscCall((*C->ops.step)(C, step));
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

PetscErrorCode ExtrapolationCheckpoint(Extrapolation *e, Checkpoint cp, const char name[], PetscBool load)
{
  char key[64];

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(key, sizeof(key), "past_%ss", name));
  PetscCall(CheckpointInt(cp, key, &e->npast, load));
  PetscCheck(e->npast <= e->points, PETSC_COMM_WORLD, PETSC_ERR_FILE_UNEXPECTED, "option -restart: the checkpoint keeps %" PetscInt_FMT " past %ss, -coupling_extrapolation_points is %" PetscInt_FMT, e->npast, name, e->points);
  for (PetscInt i = 0; i < e->npast; ++i) {
    PetscCall(PetscSNPrintf(key, sizeof(key), "past_%s_%" PetscInt_FMT, name, i));
    PetscCall(CheckpointVec(cp, key, e->past[i], load));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingCheckpoint(Coupling C, Checkpoint cp, PetscBool load)
{
  PetscFunctionBeginUser;
  PetscCheck(C->ops.restartable || !CheckpointIsFile(cp), PETSC_COMM_WORLD, PETSC_ERR_SUP, "option %s: checkpoints are supported for -coupling opt, not %s (its past iterates are not saved)", load ? "-restart" : "-checkpoint_every", C->method);
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
  *stats = C->stats;
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
  if (C->ops.destroy) PetscCall((*C->ops.destroy)(C));
  PetscCall(HistoryClose(&C->history, PETSC_FALSE));
  PetscCall(VecDestroy(&C->x));
  PetscCall(ExtrapolationDestroy(&C->start));
  PetscCall(PetscFree(*coupling));
  PetscFunctionReturn(0);
}
