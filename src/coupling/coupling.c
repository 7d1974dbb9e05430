/* The coupling-method interface: create by name, advance one step, report. */
#include "coupling_impl.h"
#include "options.h"

PetscErrorCode CouplingCreate(const char method[], CouplingProblem problem, const char output_dir[], PetscReal t0, Coupling *coupling)
{
  Coupling  C;
  PetscBool opt, partitioned = PETSC_FALSE;
  PetscInt  degree;

  PetscFunctionBeginUser;
  PetscCall(PetscStrcmp(method, "opt", &opt));
  for (const char **m = (const char *[]){"dn", "aitken", "iqnils", NULL}; *m && !partitioned; ++m) PetscCall(PetscStrcmp(method, *m, &partitioned));
  PetscCheck(opt || partitioned, PETSC_COMM_WORLD, PETSC_ERR_SUP, "option -coupling %s: unknown coupling method; expected opt, dn, aitken or iqnils", method);
  PetscCall(PetscNew(&C));
  PetscCall(PetscStrncpy(C->method, method, sizeof(C->method)));
  C->problem = problem;
  C->tol     = 1e-10;
  C->max_it  = opt ? 50 : 500; /* relaxation methods may need hundreds */
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Coupling options", "coupling");
  PetscCall(OptionsPositiveReal(PetscOptionsObject, "-coupling_tol", "stop when ||u - v_s||_{L2(Gamma_I)} falls below this", &C->tol));
  degree = 1;
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-coupling_extrapolation", "each step starts from the control extrapolated from the last K+1 steps by a polynomial of degree K (0: the last control, seed Remark 3.4)", 0, FSIOPT_EXTRAPOLATION_MAX, &degree));
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-coupling_max_it", "coupling iterations per step before the run stops with an error", 1, 100000, &C->max_it));
  PetscOptionsEnd();
  C->stats.max_jump = 0;
  PetscCall(CouplingProblemSetConvergedJump(problem, C->tol));
  PetscCall(CouplingProblemCreateControl(problem, &C->x));
  PetscCall(CouplingProblemInitialControl(problem, t0, C->x));
  PetscCall(ExtrapolationCreate(C->x, degree, &C->start));
  PetscCall(HistoryOpen(PETSC_COMM_WORLD, output_dir, &C->history));
  if (opt) PetscCall(CouplingCreate_Opt(C));
  else PetscCall(CouplingCreate_Partitioned(C));
  *coupling = C;
  PetscFunctionReturn(0);
}

PetscErrorCode ExtrapolationCreate(Vec model, PetscInt degree, Extrapolation *e)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(e, sizeof(*e)));
  e->degree = degree;
  for (PetscInt i = 0; i <= FSIOPT_EXTRAPOLATION_MAX; ++i) PetscCall(VecDuplicate(model, &e->past[i]));
  PetscFunctionReturn(0);
}

PetscErrorCode ExtrapolationRecord(Extrapolation *e, Vec x)
{
  Vec oldest = e->past[FSIOPT_EXTRAPOLATION_MAX];

  PetscFunctionBeginUser;
  for (PetscInt i = FSIOPT_EXTRAPOLATION_MAX; i > 0; --i) e->past[i] = e->past[i - 1];
  e->past[0] = oldest;
  PetscCall(VecCopy(x, e->past[0]));
  e->npast = PetscMin(e->npast + 1, FSIOPT_EXTRAPOLATION_MAX + 1);
  PetscFunctionReturn(0);
}

/* the weights of the newest, second newest, ... values: binomial coefficients with
   alternating signs */
PetscErrorCode ExtrapolationPredict(Extrapolation *e, Vec x)
{
  static const PetscScalar weights[4][4] = {{1, 0, 0, 0}, {2, -1, 0, 0}, {3, -3, 1, 0}, {4, -6, 4, -1}};
  const PetscInt           degree        = PetscMin(e->degree, e->npast - 1);

  PetscFunctionBeginUser;
  if (degree < 0) PetscFunctionReturn(0); /* nothing recorded: x stays */
  PetscCall(VecZeroEntries(x));
  PetscCall(VecMAXPY(x, degree + 1, weights[degree], e->past));
  PetscFunctionReturn(0);
}

PetscErrorCode ExtrapolationDestroy(Extrapolation *e)
{
  PetscFunctionBeginUser;
  for (PetscInt i = 0; i <= FSIOPT_EXTRAPOLATION_MAX; ++i) PetscCall(VecDestroy(&e->past[i]));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingStep(Coupling C, PetscInt step)
{
  PetscFunctionBeginUser;
  PetscCall(ExtrapolationRecord(&C->start, C->x));
  PetscCall(ExtrapolationPredict(&C->start, C->x));
  PetscCall((*C->ops.step)(C, step));
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
