/* The fluid's operators by PETSc's pointwise integration of the whole weak form on the fluid
   DM: the reference backend (-fem_backend petsc) that -fem_backend_check compares another
   against. On a fixed mesh the solver keeps DMPlex's own SNES callbacks, which integrate the
   same form. On a moving mesh the old domains' mass is a matrix assembled at each step
   (fluid_ale.c) on the ALE's copy of the DM without constraints: M(Omega^{n-1}), for BDF2
   also M(Omega^{n-2}); the free rows of their combination enter the solver's residual and
   Jacobian. */
#include "fluid_impl.h"

typedef struct {
  Vec all_x, all_y, work; /* the ALE copy's global vectors, the fluid's */
  Mat mass_old_all, mass_older_all; /* the step's old-domain mass, all rows; BDF2: 1/2 rho/dt M(Omega^{n-2}) */
  Mat mass_old;                     /* its free rows */
  IS  free_in_all;
} OperatorPETSc;

/* coefficient M on the present coordinates of the ALE's copy, every dof. Assembled here
   rather than through DMPlexSNESComputeJacobianFEM, whose generic element loop (every
   component pair of the vector basis, with the g1..g3 slots) costs as much as the full
   Navier-Stokes Jacobian: the mass needs only sum_q w_q |J_q| phi_i . phi_j on the velocity
   block. */
static PetscErrorCode AssembleMass(Fluid f, Mat target, PetscReal coefficient)
{
  DM               dm_all;
  PetscDS          ds;
  PetscFE          fe;
  PetscQuadrature  quad;
  PetscTabulation  T;
  const PetscReal *weights;
  PetscReal       *v, *J, *invJ, *detJ;
  PetscScalar     *element;
  PetscInt         dim, Nq, Nb, Nc, totDim, cStart, cEnd;

  PetscFunctionBeginUser;
  PetscCall(FluidALEGetAll(f, &dm_all, NULL));
  PetscCall(DMGetDimension(dm_all, &dim));
  PetscCall(DMGetDS(dm_all, &ds));
  PetscCall(PetscDSGetTotalDimension(ds, &totDim));
  PetscCall(PetscDSGetDiscretization(ds, 0, (PetscObject *)&fe));
  PetscCall(PetscFEGetQuadrature(fe, &quad));
  PetscCall(PetscQuadratureGetData(quad, NULL, NULL, &Nq, NULL, &weights));
  PetscCall(PetscFEGetDimension(fe, &Nb));
  PetscCall(PetscFEGetNumComponents(fe, &Nc));
  PetscCall(PetscFEGetCellTabulation(fe, 0, &T));
  PetscCall(
    PetscMalloc5(Nq * dim, &v, Nq * dim * dim, &J, Nq * dim * dim, &invJ, Nq, &detJ, totDim * totDim, &element));
  PetscCall(DMPlexGetHeightStratum(dm_all, 0, &cStart, &cEnd));
  PetscCall(MatZeroEntries(target));
  for (PetscInt cell = cStart; cell < cEnd; ++cell) {
    PetscCall(DMPlexComputeCellGeometryFEM(dm_all, cell, quad, v, J, invJ, detJ));
    PetscCall(PetscArrayzero(element, totDim * totDim));
    for (PetscInt q = 0; q < Nq; ++q) {
      const PetscReal *phi = &T->T[0][q * Nb * Nc];
      const PetscReal  wq  = coefficient * weights[q] * detJ[q];
      for (PetscInt i = 0; i < Nb; ++i)
        for (PetscInt j = 0; j < Nb; ++j) {
          PetscReal dot = 0;
          for (PetscInt c = 0; c < Nc; ++c) dot += phi[i * Nc + c] * phi[j * Nc + c];
          element[i * totDim + j] += wq * dot;
        }
    }
    PetscCall(DMPlexMatSetClosure(dm_all, NULL, NULL, target, cell, element, ADD_VALUES));
  }
  PetscCall(MatAssemblyBegin(target, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(target, MAT_FINAL_ASSEMBLY));
  PetscCall(PetscFree5(v, J, invJ, detJ, element));
  PetscFunctionReturn(0);
}

/* the old-domain mass times the local state x on the global rows of the ALE's copy (y = or
   y +=): zero before a step assembled it (the initial projection's operator has none) */
static PetscErrorCode OldMassMultAll(FluidOperator op, Vec xlocal, Vec yall, PetscBool add)
{
  OperatorPETSc *p = (OperatorPETSc *)op->data;
  DM             dm_all;

  PetscFunctionBeginUser;
  if (!p->mass_old_all) {
    if (!add) PetscCall(VecZeroEntries(yall));
    PetscFunctionReturn(0);
  }
  PetscCall(FluidALEGetAll(op->fluid, &dm_all, NULL));
  PetscCall(DMLocalToGlobal(dm_all, xlocal, INSERT_VALUES, p->all_x));
  if (add) PetscCall(MatMultAdd(p->mass_old_all, p->all_x, yall, yall));
  else PetscCall(MatMult(p->mass_old_all, p->all_x, yall));
  PetscFunctionReturn(0);
}

static PetscErrorCode GlobalToLocal(FluidOperator op, Vec x, Vec xlocal)
{
  PetscFunctionBeginUser;
  PetscCall(FEMGlobalToLocal(op->fluid->dm, x, xlocal));
  PetscFunctionReturn(0);
}

static PetscErrorCode Residual(FluidOperator op, Vec xlocal, PetscBool old_mass, Vec F)
{
  OperatorPETSc *p = (OperatorPETSc *)op->data;
  Fluid          f = op->fluid;

  PetscFunctionBeginUser;
  PetscCall(FEMResidual(f->dm, xlocal, F));
  if (old_mass) {
    PetscCall(OldMassMultAll(op, xlocal, p->all_y, PETSC_FALSE));
    PetscCall(FluidALEFreeRows(f, p->all_y, p->work));
    PetscCall(VecAXPY(F, 1.0, p->work));
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode Jacobian(FluidOperator op, Vec xlocal, PetscBool old_mass, Mat J, Mat P)
{
  OperatorPETSc *p = (OperatorPETSc *)op->data;

  PetscFunctionBeginUser;
  PetscCall(DMPlexSNESComputeJacobianFEM(op->fluid->dm, xlocal, J, P, NULL));
  if (old_mass && p->mass_old) PetscCall(MatAXPY(P, 1.0, p->mass_old, SUBSET_NONZERO_PATTERN));
  if (old_mass && p->mass_old && J != P) PetscCall(MatAXPY(J, 1.0, p->mass_old, SUBSET_NONZERO_PATTERN));
  PetscFunctionReturn(0);
}

static PetscErrorCode JacobianMatrix(FluidOperator op, Vec xlocal, PetscBool old_mass, Mat *A)
{
  PetscFunctionBeginUser;
  PetscCall(DMCreateMatrix(op->fluid->dm, A));
  PetscCall(Jacobian(op, xlocal, old_mass, *A, *A));
  PetscFunctionReturn(0);
}

static PetscErrorCode ResidualAll(FluidOperator op, Vec xlocal, PetscBool old_mass, Vec yall)
{
  DM dm_all;

  PetscFunctionBeginUser;
  PetscCall(FluidALEGetAll(op->fluid, &dm_all, NULL));
  PetscCall(FEMResidual(dm_all, xlocal, yall));
  if (old_mass) PetscCall(OldMassMultAll(op, xlocal, yall, PETSC_TRUE));
  PetscFunctionReturn(0);
}

static PetscErrorCode OldDomain(FluidOperator op, PetscInt slot, PetscReal coefficient)
{
  OperatorPETSc *p = (OperatorPETSc *)op->data;

  PetscFunctionBeginUser;
  PetscCall(AssembleMass(op->fluid, slot ? p->mass_older_all : p->mass_old_all, coefficient));
  PetscFunctionReturn(0);
}

static PetscErrorCode OldMassStep(FluidOperator op, PetscBool bdf2, Vec xold, Vec xprevious, Vec history_all)
{
  OperatorPETSc *p = (OperatorPETSc *)op->data;
  DM             dm_all;

  PetscFunctionBeginUser;
  PetscCall(FluidALEGetAll(op->fluid, &dm_all, NULL));
  if (history_all) {
    PetscCall(DMLocalToGlobal(dm_all, xold, INSERT_VALUES, p->all_x));
    PetscCall(MatMult(p->mass_old_all, p->all_x, history_all));
    if (bdf2) {
      PetscCall(DMLocalToGlobal(dm_all, xprevious, INSERT_VALUES, p->all_x));
      PetscCall(MatMult(p->mass_older_all, p->all_x, p->all_y));
      PetscCall(VecAXPY(history_all, -1.0, p->all_y));
    }
  }
  if (bdf2) PetscCall(MatAXPY(p->mass_old_all, -1.0, p->mass_older_all, SAME_NONZERO_PATTERN));
  PetscCall(MatCreateSubMatrix(p->mass_old_all, p->free_in_all, p->free_in_all, MAT_REUSE_MATRIX, &p->mass_old));
  PetscFunctionReturn(0);
}

static PetscErrorCode Destroy(FluidOperator op)
{
  OperatorPETSc *p = (OperatorPETSc *)op->data;

  PetscFunctionBeginUser;
  PetscCall(MatDestroy(&p->mass_old));
  PetscCall(MatDestroy(&p->mass_older_all));
  PetscCall(MatDestroy(&p->mass_old_all));
  PetscCall(ISDestroy(&p->free_in_all));
  PetscCall(VecDestroy(&p->all_x));
  PetscCall(VecDestroy(&p->all_y));
  PetscCall(VecDestroy(&p->work));
  PetscCall(PetscFree(op->data));
  PetscFunctionReturn(0);
}

/* the solver's residual and Jacobian: DMPlex's callbacks on a fixed mesh, the fluid's on a
   moving one (which FluidALECreate installed) */
PetscErrorCode FluidOperatorCreate_PETSc(Fluid f, FluidOperatorUse use, FluidOperator op)
{
  OperatorPETSc *p;
  DM             dm_all;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&p));
  op->data                = p;
  op->ops.global_to_local = GlobalToLocal;
  op->ops.residual        = Residual;
  op->ops.jacobian        = Jacobian;
  op->ops.jacobian_matrix = JacobianMatrix;
  op->ops.residual_all    = ResidualAll;
  op->ops.old_domain      = OldDomain;
  op->ops.old_mass_step   = OldMassStep;
  op->ops.destroy         = Destroy;
  if (!f->moving) PetscFunctionReturn(0);
  PetscCall(FluidALEGetAll(f, &dm_all, NULL));
  PetscCall(DMCreateGlobalVector(dm_all, &p->all_x));
  PetscCall(VecDuplicate(p->all_x, &p->all_y));
  PetscCall(DMCreateGlobalVector(f->dm, &p->work));
  if (use == FLUID_OPERATOR_PROJECTION) PetscFunctionReturn(0); /* no step: no old-domain mass */
  PetscCall(DMCreateMatrix(dm_all, &p->mass_old_all));
  PetscCall(MatAssemblyBegin(p->mass_old_all, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(p->mass_old_all, MAT_FINAL_ASSEMBLY));
  if (f->time_order == 2) PetscCall(MatDuplicate(p->mass_old_all, MAT_DO_NOT_COPY_VALUES, &p->mass_older_all));
  PetscCall(FEMFreeDofs(f->dm, dm_all, &p->free_in_all));
  PetscCall(MatCreateSubMatrix(p->mass_old_all, p->free_in_all, p->free_in_all, MAT_INITIAL_MATRIX, &p->mass_old));
  PetscFunctionReturn(0);
}
