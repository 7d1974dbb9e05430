/* The coupling-method interface: create by name, advance one step, report. */
#include "coupling_impl.h"
#include "options.h"

PetscErrorCode CouplingCreate(const char method[], CouplingProblem problem, const char output_dir[], PetscReal t0, Coupling *coupling)
{
  Coupling  C;
  PetscBool opt, partitioned = PETSC_FALSE;

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
  C->extrapolation = 1;
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-coupling_extrapolation", "each step starts from the control extrapolated from the last K+1 steps by a polynomial of degree K (0: the last control, seed Remark 3.4)", 0, FSIOPT_EXTRAPOLATION_MAX, &C->extrapolation));
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-coupling_max_it", "coupling iterations per step before the run stops with an error", 1, 100000, &C->max_it));
  PetscOptionsEnd();
  C->stats.max_jump = 0;
  PetscCall(CouplingProblemSetConvergedJump(problem, C->tol));
  PetscCall(CouplingProblemCreateControl(problem, &C->x));
  PetscCall(CouplingProblemInitialControl(problem, t0, C->x));
  for (PetscInt i = 0; i <= FSIOPT_EXTRAPOLATION_MAX; ++i) PetscCall(VecDuplicate(C->x, &C->past[i]));
  PetscCall(HistoryOpen(PETSC_COMM_WORLD, output_dir, &C->history));
  if (opt) PetscCall(CouplingCreate_Opt(C));
  else PetscCall(CouplingCreate_Partitioned(C));
  *coupling = C;
  PetscFunctionReturn(0);
}

/* x^n starts from the polynomial of degree -coupling_extrapolation through the last
   controls (lower while the run has fewer steps behind it): the weights of x^{n-1},
   x^{n-2}, ... are the binomial coefficients with alternating signs */
static PetscErrorCode Extrapolate(Coupling C)
{
  static const PetscScalar weights[4][4] = {{1, 0, 0, 0}, {2, -1, 0, 0}, {3, -3, 1, 0}, {4, -6, 4, -1}};
  Vec                      oldest       = C->past[FSIOPT_EXTRAPOLATION_MAX];
  PetscInt                 degree;

  PetscFunctionBeginUser;
  for (PetscInt i = FSIOPT_EXTRAPOLATION_MAX; i > 0; --i) C->past[i] = C->past[i - 1];
  C->past[0] = oldest;
  PetscCall(VecCopy(C->x, C->past[0]));
  C->npast = PetscMin(C->npast + 1, FSIOPT_EXTRAPOLATION_MAX + 1);
  degree   = PetscMin(C->extrapolation, C->npast - 1);
  PetscCall(VecZeroEntries(C->x));
  PetscCall(VecMAXPY(C->x, degree + 1, weights[degree], C->past));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingStep(Coupling C, PetscInt step)
{
  PetscFunctionBeginUser;
  PetscCall(Extrapolate(C));
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
  for (PetscInt i = 0; i <= FSIOPT_EXTRAPOLATION_MAX; ++i) PetscCall(VecDestroy(&C->past[i]));
  PetscCall(PetscFree(*coupling));
  PetscFunctionReturn(0);
}
