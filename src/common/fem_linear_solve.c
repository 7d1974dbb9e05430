/* The linearized solves of a subproblem (the sensitivity and adjoint products), with its
   operator or its transpose. A solve that does not converge stops the run with one line:
   with LU it never happens; an iterative solver's limits are options. A factorization
   solves with its own transpose, and so do Krylov methods with most
   preconditioners. PETSc 3.18's PCFIELDSPLIT does not apply the transpose of its Schur
   factorization: on tube3d the transposed fluid solves took 1000 FGMRES iterations where
   the forward ones took 75. For it a second KSP solves with the explicit transpose, built
   by the same options and fields, and rebuilt when the operator changes. */
#include <petsc/private/petscimpl.h> /* PetscObjectStateGet */
#include "fem.h"

typedef struct {
  KSP              ksp;          /* on A^T, with the forward KSP's prefix and DM */
  Mat              A_transposed; /* explicit when A is P; else A's transpose applied by its MatMultTranspose */
  Mat              P_transposed; /* explicit: the split's blocks come from it */
  PetscObjectState state;        /* of P when P_transposed was made */
} TransposedSolver;

static PetscErrorCode TransposedSolverDestroy(void *ctx)
{
  TransposedSolver *ts = (TransposedSolver *)ctx;

  PetscFunctionBeginUser;
  PetscCall(KSPDestroy(&ts->ksp));
  PetscCall(MatDestroy(&ts->A_transposed));
  PetscCall(MatDestroy(&ts->P_transposed));
  PetscCall(PetscFree(ts));
  PetscFunctionReturn(0);
}

static PetscErrorCode TransposedSolverGet(SNES snes, KSP ksp, TransposedSolver **solver)
{
  PetscContainer    container;
  TransposedSolver *ts;
  Mat               A, P;
  PetscObjectState  state;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectQuery((PetscObject)snes, "fsiopt_transposed_solver", (PetscObject *)&container));
  PetscCall(KSPGetOperators(ksp, &A, &P));
  if (!container) {
    const char *prefix;
    DM          dm;

    PetscCall(PetscNew(&ts));
    PetscCall(KSPCreate(PetscObjectComm((PetscObject)ksp), &ts->ksp));
    PetscCall(KSPGetOptionsPrefix(ksp, &prefix));
    PetscCall(KSPSetOptionsPrefix(ts->ksp, prefix));
    PetscCall(KSPGetDM(ksp, &dm));
    if (dm) {
      PetscCall(KSPSetDM(ts->ksp, dm)); /* the split's fields */
      PetscCall(KSPSetDMActive(ts->ksp, PETSC_FALSE));
    }
    PetscCall(KSPSetFromOptions(ts->ksp));
    { /* a Schur preconditioning matrix of the forward split's (symmetric: fluid_schur_laplacian.c) */
      Mat schur;
      PC  pc;
      PetscCall(PetscObjectQuery((PetscObject)snes, "fsiopt_schur_preconditioning_matrix", (PetscObject *)&schur));
      PetscCall(KSPGetPC(ts->ksp, &pc));
      if (schur) PetscCall(PCFieldSplitSetSchurPre(pc, PC_FIELDSPLIT_SCHUR_PRE_USER, schur));
    }
    PetscCall(PetscContainerCreate(PetscObjectComm((PetscObject)ksp), &container));
    PetscCall(PetscContainerSetPointer(container, ts));
    PetscCall(PetscContainerSetUserDestroy(container, TransposedSolverDestroy));
    PetscCall(PetscObjectCompose((PetscObject)snes, "fsiopt_transposed_solver", (PetscObject)container));
    PetscCall(PetscContainerDestroy(&container));
  } else PetscCall(PetscContainerGetPointer(container, (void **)&ts));
  PetscCall(PetscObjectStateGet((PetscObject)P, &state));
  if (!ts->P_transposed || state != ts->state) {
    PetscCall(MatTranspose(P, ts->P_transposed ? MAT_REUSE_MATRIX : MAT_INITIAL_MATRIX, &ts->P_transposed));
    if (!ts->A_transposed) {
      if (A == P) {
        PetscCall(PetscObjectReference((PetscObject)ts->P_transposed));
        ts->A_transposed = ts->P_transposed;
      } else PetscCall(MatCreateTranspose(A, &ts->A_transposed)); /* -fluid_matfree: follows A */
    }
    PetscCall(KSPSetOperators(ts->ksp, ts->A_transposed, ts->P_transposed));
    ts->state = state;
  }
  { /* the forward solver's preconditioner lagged behind its operator: so is this one */
    PetscBool reuse;
    PetscCall(KSPGetReusePreconditioner(ksp, &reuse));
    PetscCall(KSPSetReusePreconditioner(ts->ksp, reuse));
  }
  *solver = ts;
  PetscFunctionReturn(0);
}

/* which solve failed, and the options that would change it */
static PetscErrorCode CheckConverged(KSP ksp, const char what[])
{
  KSPConvergedReason reason;
  PetscInt           its;
  const char        *prefix;

  PetscFunctionBeginUser;
  PetscCall(KSPGetConvergedReason(ksp, &reason));
  if (reason >= 0) PetscFunctionReturn(0);
  PetscCall(KSPGetIterationNumber(ksp, &its));
  PetscCall(KSPGetOptionsPrefix(ksp, &prefix));
  if (!prefix) prefix = "";
  SETERRQ(PetscObjectComm((PetscObject)ksp), PETSC_ERR_NOT_CONVERGED,
          "%s linearized solve (-%sksp_type) did not converge: %s after %" PetscInt_FMT
          " iterations (-%sksp_rtol, -%sksp_max_it, -%spc_type set it)",
          what, prefix, KSPConvergedReasons[reason], its, prefix, prefix, prefix);
}

/* set by the coupling around an inexact product (-coupling_inexact_products) */
static PetscReal linearized_rtol = 0;

PetscErrorCode FEMSetLinearizedRtol(PetscReal rtol)
{
  PetscFunctionBeginUser;
  linearized_rtol = rtol;
  PetscFunctionReturn(0);
}

/* The KSP's rtol raised to linearized_rtol where that is larger (*rtol: its own, for
   RestoreTolerance) */
static PetscErrorCode RelaxTolerance(KSP ksp, PetscReal *rtol)
{
  PetscReal abstol, dtol;
  PetscInt  maxits;

  PetscFunctionBeginUser;
  PetscCall(KSPGetTolerances(ksp, rtol, &abstol, &dtol, &maxits));
  if (linearized_rtol > *rtol) PetscCall(KSPSetTolerances(ksp, linearized_rtol, abstol, dtol, maxits));
  PetscFunctionReturn(0);
}

static PetscErrorCode RestoreTolerance(KSP ksp, PetscReal rtol)
{
  PetscReal relaxed, abstol, dtol;
  PetscInt  maxits;

  PetscFunctionBeginUser;
  if (!(linearized_rtol > rtol)) PetscFunctionReturn(0);
  PetscCall(KSPGetTolerances(ksp, &relaxed, &abstol, &dtol, &maxits));
  PetscCall(KSPSetTolerances(ksp, rtol, abstol, dtol, maxits));
  PetscFunctionReturn(0);
}

/* KSPSolve or KSPSolveTranspose at the larger of the KSP's rtol and linearized_rtol */
static PetscErrorCode SolveAtTolerance(KSP ksp, Vec rhs, Vec x, PetscBool transpose, const char what[])
{
  PetscReal rtol;

  PetscFunctionBeginUser;
  PetscCall(RelaxTolerance(ksp, &rtol));
  if (transpose) PetscCall(KSPSolveTranspose(ksp, rhs, x));
  else PetscCall(KSPSolve(ksp, rhs, x));
  PetscCall(RestoreTolerance(ksp, rtol));
  PetscCall(CheckConverged(ksp, what));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMLinearSolve(SNES snes, Vec rhs, Vec x, PetscBool transpose)
{
  KSP       ksp;
  PC        pc;
  PetscBool split;

  PetscFunctionBeginUser;
  PetscCall(SNESGetKSP(snes, &ksp));
  if (!transpose) {
    PetscCall(SolveAtTolerance(ksp, rhs, x, PETSC_FALSE, "a"));
    PetscFunctionReturn(0);
  }
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCFIELDSPLIT, &split));
  if (split) {
    TransposedSolver *ts = NULL;
    PetscCall(TransposedSolverGet(snes, ksp, &ts));
    PetscCall(SolveAtTolerance(ts->ksp, rhs, x, PETSC_FALSE, "a transposed"));
  } else PetscCall(SolveAtTolerance(ksp, rhs, x, PETSC_TRUE, "a transposed"));
  PetscFunctionReturn(0);
}

/* The columns of the dense rhs at once: a factorization reads its factors once for the
   block (KSPMatSolve falls back to one solve per column for an iterative KSP). */
PetscErrorCode FEMLinearSolveBlock(SNES snes, Mat rhs, Mat x)
{
  KSP       ksp;
  PetscReal rtol;

  PetscFunctionBeginUser;
  PetscCall(SNESGetKSP(snes, &ksp));
  PetscCall(RelaxTolerance(ksp, &rtol));
  PetscCall(KSPMatSolve(ksp, rhs, x));
  PetscCall(RestoreTolerance(ksp, rtol));
  PetscCall(CheckConverged(ksp, "a block"));
  PetscFunctionReturn(0);
}
