/* -coupling monolithic: Newton's method on the whole discrete system of a step, the fluid
   x_f, the structure x_s and the interface traction (the scaled control x) as the
   multiplier of velocity continuity (problem_monolithic.c), so that it converges to the
   solution opt and the partitioned methods converge to: the accuracy reference for them.
   The Jacobian [A_f 0 C_fx; 0 A_s C_sx; C_xf C_xs 0] is assembled (a MATNEST of the
   subproblems' own matrices and the coupling blocks, converted to AIJ) and factored by
   MUMPS. On a moving mesh each residual moves the fluid mesh to the structure's x_s, and
   the Jacobian leaves that dependence out (inexact Newton, as opt's J does); with
   -coupling_monolithic_snes_mf_operator the Newton direction solves with the exact
   directional derivative (differences of the residual, the mesh moved each time), the
   assembled matrix preconditioning it. Options: -coupling_monolithic_snes_*, _ksp_*, _pc_*. */
#include "coupling_impl.h"
#include "problem_impl.h"
#include "options.h"
#include "logging.h"

typedef struct {
  SNES      snes;
  Mat       block[9], nest, J;
  IS        is[3];       /* the rows of x_f, x_s and x in the system's vectors */
  IS        subproblems; /* those of x_f and x_s together: a field split's first block */
  Vec       X, F;
  PetscInt  step;
  PetscReal first; /* ||F|| at the step's first iterate */
  PetscReal tol;   /* -coupling_tol: the interface jump a converged iterate is within */
  PetscReal last;  /* ||F|| of the iteration before */
  PetscInt  lag;   /* -coupling_monolithic_jacobian_lag: Newton iterations a factored Jacobian serves */
  PetscInt  fresh; /* -coupling_monolithic_jacobian_refresh: a step's iteration from which it is rebuilt */
  PetscInt  age;   /* iterations the Jacobian in hand has served; 0: none in hand */
  PetscInt  done;  /* a step's iterations before a restart on a fresh Jacobian; 0: none */
} Monolithic;

/* PETSc's test on ||F|| and, besides, the interface jump within -coupling_tol. ||F|| sums
   terms of size rho/dt and stops falling at their round-off: once it is 1e-6 of its first
   value and falls by less than half in an iteration, it has converged as far as it can. */
static PetscErrorCode Converged(SNES snes, PetscInt k, PetscReal xnorm, PetscReal step, PetscReal fnorm,
                                SNESConvergedReason *reason, void *ctx)
{
  Coupling    C = (Coupling)ctx;
  Monolithic *m = (Monolithic *)C->data;
  PetscBool   floor;

  PetscFunctionBeginUser;
  PetscCall(SNESConvergedDefault(snes, k, xnorm, step, fnorm, reason, NULL));
  floor   = k > 0 && fnorm <= 1e-6 * m->first && fnorm > 0.5 * m->last ? PETSC_TRUE : PETSC_FALSE;
  m->last = fnorm;
  if (*reason == SNES_CONVERGED_ITERATING && floor) *reason = SNES_CONVERGED_FNORM_RELATIVE;
  if (*reason > 0 && C->problem->state_jump > m->tol && k < C->max_it) *reason = SNES_CONVERGED_ITERATING;
  PetscFunctionReturn(0);
}

static PetscErrorCode Split(Monolithic *m, Vec V, Vec part[3])
{
  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < 3; ++k) PetscCall(VecGetSubVector(V, m->is[k], &part[k]));
  PetscFunctionReturn(0);
}

static PetscErrorCode Join(Monolithic *m, Vec V, Vec part[3])
{
  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < 3; ++k) PetscCall(VecRestoreSubVector(V, m->is[k], &part[k]));
  PetscFunctionReturn(0);
}

static PetscErrorCode Residual(SNES snes, Vec X, Vec F, void *ctx)
{
  Coupling    C = (Coupling)ctx;
  Monolithic *m = (Monolithic *)C->data;
  Vec         x[3], f[3];

  PetscFunctionBeginUser;
  (void)snes;
  PetscCall(Split(m, X, x));
  PetscCall(Split(m, F, f));
  PetscCall(CouplingProblemCoupledResidual(C->problem, x[0], x[1], x[2], f[0], f[1], f[2]));
  PetscCall(Join(m, F, f));
  PetscCall(Join(m, X, x));
  PetscFunctionReturn(0);
}

static PetscErrorCode Jacobian(SNES snes, Vec X, Mat J, Mat Pmat, void *ctx)
{
  Coupling        C = (Coupling)ctx;
  Monolithic     *m = (Monolithic *)C->data;
  CouplingProblem P = C->problem;
  Vec             x[3];
  SNES            sub;
  Vec             history;
  Mat             A;

  PetscInt        k;

  PetscFunctionBeginUser;
  /* the factors in hand serve -coupling_monolithic_jacobian_lag iterations across steps, but
     not past -coupling_monolithic_jacobian_refresh iterations of one step: left unchanged, the
     matrix is not factored again */
  PetscCall(SNESGetIterationNumber(snes, &k));
  if (m->age > 0 && m->age < m->lag && k < m->fresh) {
    m->age++;
    PetscFunctionReturn(0);
  }
  m->age = 1;
  PetscCall(Split(m, X, x));
  /* the subproblems' Jacobians at the iterate, on the mesh its residual moved to */
  PetscCall(PetscLogStagePush(FSIOPT_STAGE_FLUID));
  PetscCall(FluidGetNonlinearSystem(P->fluid, &sub, &history));
  PetscCall(CouplingProblemSystemJacobian(sub, x[0], &A));
  PetscCall(PetscLogStagePop());
  PetscCall(PetscLogStagePush(FSIOPT_STAGE_STRUCTURE));
  PetscCall(StructureGetNonlinearSystem(P->structure, &sub, &history, NULL));
  PetscCall(CouplingProblemSystemJacobian(sub, x[1], &A));
  PetscCall(PetscLogStagePop());
  PetscCall(Join(m, X, x));
  PetscCall(PetscLogStagePush(FSIOPT_STAGE_OPTIMIZER));
  PetscCall(MatConvert(m->nest, MATAIJ, MAT_REUSE_MATRIX, &Pmat));
  PetscCall(PetscLogStagePop());
  if (J != Pmat) { /* -snes_mf_operator: the differences of the residual at this iterate */
    PetscCall(MatAssemblyBegin(J, MAT_FINAL_ASSEMBLY));
    PetscCall(MatAssemblyEnd(J, MAT_FINAL_ASSEMBLY));
  }
  PetscFunctionReturn(0);
}

/* the whole system's factorization and solves in -log_view's Optimizer stage, the method's
   own work */
static PetscErrorCode StagePush(KSP ksp, Vec b, Vec x, void *ctx)
{
  PetscFunctionBeginUser;
  (void)ksp, (void)b, (void)x, (void)ctx;
  PetscCall(PetscLogStagePush(FSIOPT_STAGE_OPTIMIZER));
  PetscFunctionReturn(0);
}

static PetscErrorCode StagePop(KSP ksp, Vec b, Vec x, void *ctx)
{
  PetscFunctionBeginUser;
  (void)ksp, (void)b, (void)x, (void)ctx;
  PetscCall(PetscLogStagePop());
  PetscFunctionReturn(0);
}

/* each iteration in history.csv: 1/2 ||F||^2 and the interface jump */
static PetscErrorCode Monitor(SNES snes, PetscInt k, PetscReal norm, void *ctx)
{
  Coupling    C = (Coupling)ctx;
  Monolithic *m = (Monolithic *)C->data;

  PetscFunctionBeginUser;
  (void)snes;
  if (k == 0 && m->done) PetscFunctionReturn(0); /* a restart's first iterate: the last one already */
  if (k == 0) m->first = norm;
  PetscCall(HistoryAppend(C->history, m->step, C->dt, m->done + k, 0.5 * norm * norm, C->problem->state_jump, 0));
  PetscFunctionReturn(0);
}

static PetscErrorCode MonolithicIterate(Coupling C, PetscInt step, CouplingIterations *it)
{
  Monolithic         *m = (Monolithic *)C->data;
  CouplingProblem     P = C->problem;
  SNESConvergedReason reason;
  PetscInt            its;
  PetscReal           norm;
  Vec                 x[3], state, history;
  SNES                sub;

  PetscFunctionBeginUser;
  m->step = step;
  /* from the subproblems' last state and the extrapolated control */
  PetscCall(Split(m, m->X, x));
  PetscCall(FluidGetSolution(P->fluid, &state));
  PetscCall(VecCopy(state, x[0]));
  PetscCall(StructureGetNonlinearSystem(P->structure, &sub, &history, &state));
  PetscCall(VecCopy(state, x[1]));
  PetscCall(VecCopy(C->x, x[2]));
  PetscCall(Join(m, m->X, x));
  PetscCall(SNESSolve(m->snes, NULL, m->X));
  PetscCall(SNESGetConvergedReason(m->snes, &reason));
  PetscCall(SNESGetIterationNumber(m->snes, &its));
  /* a Jacobian lagged past where its step still descends: Newton again from the last iterate on
     a fresh one, once, before the step fails (Turek-Hron fsi3's first step of 0.01: the third
     iteration on the first Jacobian found no decrease down to a step of 1e-6, where round-off
     decided between going on and halving dt) */
  if (reason == SNES_DIVERGED_LINE_SEARCH && m->age > 1) {
    PetscInt more;
    PetscCall(PetscInfo(m->snes,
                        "step %" PetscInt_FMT ": no descent on a Jacobian of age %" PetscInt_FMT " after %" PetscInt_FMT
                        " iterations; again on a fresh one\n",
                        step, m->age, its));
    m->age  = 0;
    m->done = its;
    PetscCall(SNESSolve(m->snes, NULL, m->X));
    m->done = 0;
    PetscCall(SNESGetConvergedReason(m->snes, &reason));
    PetscCall(SNESGetIterationNumber(m->snes, &more));
    its += more;
  }
  PetscCall(SNESGetFunctionNorm(m->snes, &norm));
  it->iterations       = its;
  it->linearized_pairs = its;
  if (reason <= 0) {
    PetscCall(StepFailureCheckMemory(m->snes, "monolithic system"));
    PetscCall(StepFailureSet(&C->failure,
                             "coupling monolithic did not converge at step %" PetscInt_FMT " after %" PetscInt_FMT
                             " Newton iterations: SNES reason %s, ||F|| %.3e of its first %.3e",
                             step, its, SNESConvergedReasons[reason], (double)norm, (double)m->first));
    PetscFunctionReturn(0);
  }
  /* the state of the solution: the residual SNES evaluated there left it in hand */
  PetscCall(Split(m, m->X, x));
  PetscCall(VecCopy(x[2], C->x));
  PetscCall(Join(m, m->X, x));
  it->jump    = P->state_jump;
  it->measure = m->first > 0 ? norm / m->first : 0;
  PetscFunctionReturn(0);
}

static PetscErrorCode MonolithicSetUp(Coupling C)
{
  Monolithic     *m = (Monolithic *)C->data;
  CouplingProblem P = C->problem;
  PetscBool       shared = P->fluid && P->structure ? PETSC_TRUE : PETSC_FALSE;
  SNES            sub;
  Vec             history, state;
  KSP             ksp;
  PC              pc;
  PetscReal       rtol = 1e-10;

  PetscFunctionBeginUser;
  m->tol = 1e-4;
  PetscOptionsBegin(P->comm, NULL, "Monolithic coupling", "coupling");
  PetscCall(OptionsPositiveReal(PetscOptionsObject, "-coupling_tol",
                                "a Newton iterate has converged when, besides ||F|| <= -coupling_monolithic_snes_rtol "
                                "||F_0||, the interface jump ||u - v_s||_L2(Gamma_I) is at most this",
                                &m->tol));
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-coupling_monolithic_jacobian_lag",
                              "Newton iterations (across steps) that one assembled and factored Jacobian serves (1: "
                              "Newton's method itself)",
                              1, PETSC_MAX_INT, &m->lag));
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-coupling_monolithic_jacobian_refresh",
                              "a step's Newton iteration from which the Jacobian is rebuilt whatever its age", 1,
                              PETSC_MAX_INT, &m->fresh));

  PetscOptionsEnd();
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &shared, 1, MPIU_BOOL, MPI_LAND, P->comm));
  PetscCheck(shared, P->comm, PETSC_ERR_SUP,
             "option -coupling monolithic: the fluid and the structure must share every rank (drop -structure_ranks)");
  /* the blocks: the subproblems' own Jacobians, assembled at their state for the pattern,
     and the coupling blocks */
  PetscCall(FluidGetNonlinearSystem(P->fluid, &sub, &history));
  PetscCall(FluidGetSolution(P->fluid, &state));
  PetscCall(CouplingProblemSystemJacobian(sub, state, &m->block[0]));
  PetscCall(StructureGetNonlinearSystem(P->structure, &sub, &history, &state));
  PetscCall(CouplingProblemSystemJacobian(sub, state, &m->block[4]));
  PetscCall(PetscObjectReference((PetscObject)m->block[0]));
  PetscCall(PetscObjectReference((PetscObject)m->block[4]));
  PetscCall(CouplingProblemCouplingBlocks(P, &m->block[2], &m->block[5], &m->block[6], &m->block[7]));
  PetscCall(MatCreateNest(P->comm, 3, NULL, 3, NULL, m->block, &m->nest));
  PetscCall(MatNestGetISs(m->nest, m->is, NULL));
  for (PetscInt k = 0; k < 3; ++k) PetscCall(PetscObjectReference((PetscObject)m->is[k]));
  PetscCall(MatConvert(m->nest, MATAIJ, MAT_INITIAL_MATRIX, &m->J));
  PetscCall(MatCreateVecs(m->J, &m->X, &m->F));
  PetscCall(SNESCreate(P->comm, &m->snes));
  PetscCall(SNESSetOptionsPrefix(m->snes, "coupling_monolithic_"));
  PetscCall(SNESSetFunction(m->snes, m->F, Residual, C));
  PetscCall(SNESSetJacobian(m->snes, m->J, m->J, Jacobian, C));
  PetscCall(SNESMonitorSet(m->snes, Monitor, C, NULL));
  PetscCall(SNESSetConvergenceTest(m->snes, Converged, C, NULL));
  PetscCall(SNESSetTolerances(m->snes, 0.0, rtol, 0.0, C->max_it, PETSC_DEFAULT));
  PetscCall(SNESGetKSP(m->snes, &ksp));
  PetscCall(KSPSetType(ksp, KSPPREONLY));
  PetscCall(KSPSetPreSolve(ksp, StagePush, NULL));
  PetscCall(KSPSetPostSolve(ksp, StagePop, NULL));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PCSetType(pc, PCLU));
  PetscCall(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
  PetscCall(SNESSetFromOptions(m->snes));
  /* -coupling_monolithic_pc_type fieldsplit: the fluid and the structure (whose block of the
     Jacobian is block diagonal, the two not touching) and the interface traction, named
     "subproblems" and "interface" for their options; PCLU ignores them */
  PetscCall(ISExpand(m->is[0], m->is[1], &m->subproblems));
  PetscCall(PCFieldSplitSetIS(pc, "subproblems", m->subproblems));
  PetscCall(PCFieldSplitSetIS(pc, "interface", m->is[2]));
  {
    PetscBool split;
    PCType    type;
    PetscCall(PCGetType(pc, &type));
    PetscCall(PetscSNPrintf(C->setting, sizeof(C->setting),
                            "monolithic Newton on fluid, structure and interface traction (assembled, %s; Jacobian "
                            "every %" PetscInt_FMT " iterations)",
                            type, m->lag));
    PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCFIELDSPLIT, &split));
    if (split) { /* the splits' solvers now, so that the run's options check finds their options read */
      PetscCall(KSPSetOperators(ksp, m->J, m->J));
      PetscCall(KSPSetUp(ksp));
    }
  }
  { /* -snes_mf_operator's differencing matrix reads its -coupling_monolithic_mat_mffd_* options when SNES
       sets up: now, before the run's options check */
    PetscBool mf_operator, mf;
    PetscCall(SNESGetUseMatrixFree(m->snes, &mf_operator, &mf));
    if (mf_operator || mf) {
      PetscCall(SNESSetSolution(m->snes, m->X));
      PetscCall(SNESSetUp(m->snes));
    }
  }
  PetscCall(SNESGetTolerances(m->snes, NULL, &rtol, NULL, NULL, NULL));
  PetscCall(PetscSNPrintf(C->measure, sizeof(C->measure),
                          "Newton's ||F||/||F_0|| (-coupling_monolithic_snes_rtol %g; jump <= -coupling_tol %g)",
                          (double)rtol, (double)m->tol));
  PetscFunctionReturn(0);
}

static PetscErrorCode MonolithicDestroy(Coupling C)
{
  Monolithic *m = (Monolithic *)C->data;

  PetscFunctionBeginUser;
  PetscCall(SNESDestroy(&m->snes));
  for (PetscInt k = 0; k < 9; ++k) PetscCall(MatDestroy(&m->block[k]));
  for (PetscInt k = 0; k < 3; ++k) PetscCall(ISDestroy(&m->is[k]));
  PetscCall(ISDestroy(&m->subproblems));
  PetscCall(MatDestroy(&m->nest));
  PetscCall(MatDestroy(&m->J));
  PetscCall(VecDestroy(&m->X));
  PetscCall(VecDestroy(&m->F));
  PetscCall(PetscFree(C->data));
  PetscFunctionReturn(0);
}

static const char *MonolithicOptimizer(PETSC_UNUSED Coupling C)
{
  return "newton";
}

/* after a checkpoint file or a new dt: a fresh Jacobian at the next iteration, on both sides
   of a restart */
static PetscErrorCode MonolithicResynchronize(Coupling C)
{
  Monolithic *m = (Monolithic *)C->data;

  PetscFunctionBeginUser;
  m->age = 0;
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingCreate_Monolithic(Coupling C)
{
  Monolithic *m;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&m));
  C->data              = m;
  C->max_it            = 50;
  m->lag               = 50;
  m->fresh             = 6;
  C->ops.setup         = MonolithicSetUp;
  C->ops.iterate       = MonolithicIterate;
  C->ops.destroy       = MonolithicDestroy;
  C->ops.optimizer     = MonolithicOptimizer;
  C->ops.resynchronize = MonolithicResynchronize;
  C->ops.restartable   = PETSC_TRUE;
  PetscFunctionReturn(0);
}
