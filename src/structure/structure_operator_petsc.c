/* The structure's operators by PETSc's pointwise integration of the whole weak form
   (structure_kernels.c): the reference backend (-fem_backend petsc) that -fem_backend_check
   compares another against. The solver keeps DMPlex's own SNES callbacks; St. Venant-Kirchhoff
   gets a Jacobian that keeps the tangent factored after a solve. */
#include "structure_impl.h"

static PetscErrorCode Residual(StructureOperator op, Vec xlocal, Vec F)
{
  PetscFunctionBeginUser;
  PetscCall(FEMResidual(op->structure->dm, xlocal, F));
  PetscFunctionReturn(0);
}

static PetscErrorCode JacobianMatrix(StructureOperator op, Vec xlocal, Mat *A)
{
  PetscFunctionBeginUser;
  PetscCall(DMCreateMatrix(op->structure->dm, A));
  PetscCall(DMPlexSNESComputeJacobianFEM(op->structure->dm, xlocal, *A, *A, NULL));
  PetscFunctionReturn(0);
}

/* The tangent factored after a solve is the first Newton Jacobian of the next solve, which
   starts from that solution (structure.c): assembled and factored once, not twice. */
static PetscErrorCode TangentJacobian(DM dm, Vec xlocal, Mat J, Mat P, void *ctx)
{
  Structure s    = (Structure)ctx;
  PetscBool same = PETSC_FALSE;

  PetscFunctionBeginUser;
  if (s->tangent_at) PetscCall(VecEqual(xlocal, s->tangent_at, &same));
  if (same) PetscFunctionReturn(0);
  PetscCall(DMPlexSNESComputeJacobianFEM(dm, xlocal, J, P, NULL));
  ++s->counts.factorizations;
  if (!s->tangent_at) PetscCall(VecDuplicate(xlocal, &s->tangent_at));
  PetscCall(VecCopy(xlocal, s->tangent_at));
  PetscFunctionReturn(0);
}

PetscErrorCode StructureOperatorCreate_PETSc(Structure s, StructureOperatorUse use, StructureOperator op)
{
  PetscFunctionBeginUser;
  op->ops.residual        = Residual;
  op->ops.jacobian_matrix = JacobianMatrix;
  if (use == STRUCTURE_OPERATOR_SOLVER && s->model == STRUCTURE_SVK)
    PetscCall(DMSNESSetJacobianLocal(s->dm, TangentJacobian, s));
  PetscFunctionReturn(0);
}
