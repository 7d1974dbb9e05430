#include "explicit_jacobian.h"

struct _p_ExplicitJacobian {
  Mat        J;       /* the Jacobian shell */
  Mat        J0;      /* dense, sequential, the same on every rank */
  Vec        e, Je, all, y, z;
  VecScatter to_all;
  PetscBool  rebuild, factored;
  PetscInt   builds;
};

static PetscErrorCode Build(ExplicitJacobian E)
{
  PetscInt     N, rstart, rend;
  PetscScalar *column;

  PetscFunctionBeginUser;
  PetscCall(VecGetSize(E->e, &N));
  PetscCall(VecGetOwnershipRange(E->e, &rstart, &rend));
  PetscCall(MatDestroy(&E->J0));
  PetscCall(MatCreateSeqDense(PETSC_COMM_SELF, N, N, NULL, &E->J0));
  for (PetscInt j = 0; j < N; ++j) {
    const PetscScalar *a;
    PetscCall(VecZeroEntries(E->e));
    if (j >= rstart && j < rend) PetscCall(VecSetValue(E->e, j, 1.0, INSERT_VALUES));
    PetscCall(VecAssemblyBegin(E->e));
    PetscCall(VecAssemblyEnd(E->e));
    PetscCall(MatMult(E->J, E->e, E->Je));
    PetscCall(VecScatterBegin(E->to_all, E->Je, E->all, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterEnd(E->to_all, E->Je, E->all, INSERT_VALUES, SCATTER_FORWARD));
    {
      Vec col;
      PetscCall(MatDenseGetColumnVecWrite(E->J0, j, &col));
      PetscCall(VecGetArrayRead(E->all, &a));
      PetscCall(VecGetArray(col, &column));
      for (PetscInt i = 0; i < N; ++i) column[i] = a[i];
      PetscCall(VecRestoreArray(col, &column));
      PetscCall(VecRestoreArrayRead(E->all, &a));
      PetscCall(MatDenseRestoreColumnVecWrite(E->J0, j, &col));
    }
  }
  PetscCall(MatLUFactor(E->J0, NULL, NULL, NULL));
  if (!E->y) PetscCall(VecDuplicate(E->all, &E->y));
  if (!E->z) PetscCall(VecDuplicate(E->all, &E->z));
  E->factored = PETSC_TRUE;
  E->rebuild  = PETSC_FALSE;
  E->builds++;
  PetscFunctionReturn(0);
}

static PetscErrorCode Apply(PC pc, Vec x, Vec out)
{
  ExplicitJacobian E;

  PetscFunctionBeginUser;
  PetscCall(PCShellGetContext(pc, &E));
  if (E->rebuild || !E->factored) PetscCall(Build(E));
  PetscCall(VecScatterBegin(E->to_all, x, E->all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(E->to_all, x, E->all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(MatSolveTranspose(E->J0, E->all, E->y)); /* J0^{-T} x */
  PetscCall(MatSolve(E->J0, E->y, E->z));            /* J0^{-1} J0^{-T} x */
  PetscCall(VecScatterBegin(E->to_all, E->z, out, INSERT_VALUES, SCATTER_REVERSE));
  PetscCall(VecScatterEnd(E->to_all, E->z, out, INSERT_VALUES, SCATTER_REVERSE));
  PetscFunctionReturn(0);
}

PetscErrorCode ExplicitJacobianCreate(Mat J, KSP ksp, ExplicitJacobian *explicit_jacobian)
{
  ExplicitJacobian E;
  PC               pc;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&E));
  E->J       = J;
  E->rebuild = PETSC_TRUE;
  PetscCall(MatCreateVecs(J, &E->e, &E->Je));
  PetscCall(VecScatterCreateToAll(E->Je, &E->to_all, &E->all));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PCSetType(pc, PCSHELL));
  PetscCall(PCShellSetContext(pc, E));
  PetscCall(PCShellSetApply(pc, Apply));
  PetscCall(PCShellSetName(pc, "explicit Gauss-Newton Jacobian (LU)"));
  *explicit_jacobian = E;
  PetscFunctionReturn(0);
}

PetscErrorCode ExplicitJacobianRequestRebuild(ExplicitJacobian E)
{
  PetscFunctionBeginUser;
  E->rebuild = PETSC_TRUE;
  PetscFunctionReturn(0);
}

PetscErrorCode ExplicitJacobianDestroy(ExplicitJacobian *explicit_jacobian)
{
  ExplicitJacobian E = *explicit_jacobian;

  PetscFunctionBeginUser;
  if (!E) PetscFunctionReturn(0);
  PetscCall(MatDestroy(&E->J0));
  PetscCall(VecDestroy(&E->e));
  PetscCall(VecDestroy(&E->Je));
  PetscCall(VecDestroy(&E->all));
  PetscCall(VecDestroy(&E->y));
  PetscCall(VecDestroy(&E->z));
  PetscCall(VecScatterDestroy(&E->to_all));
  PetscCall(PetscFree(*explicit_jacobian));
  PetscFunctionReturn(0);
}
