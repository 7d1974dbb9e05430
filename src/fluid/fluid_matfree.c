/* -fluid_matfree: the fluid's Jacobian as a matrix-free operator, for Krylov solvers
   (-fluid_ksp_type gmres, ...) preconditioned by the assembled matrix. The volume terms are
   libCEED's operators applied at the state of the last Jacobian (ceed_fluid.c); the boundary
   terms (backflow, the interface's convective term), which live on a few faces, are a
   sparse matrix of their own, assembled with each Jacobian. Its transpose, for the adjoint
   solves, changes only the velocity-velocity block. With the default direct solver
   (preonly and LU) the operator is never applied and the run is unchanged. */
#include "fluid_impl.h"

static PetscErrorCode Apply(Mat A, Vec x, Vec y, PetscBool transpose)
{
  Fluid f;
  Vec   xlocal, ylocal;

  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(A, &f));
  PetscCall(DMGetLocalVector(f->dm, &xlocal));
  PetscCall(DMGetLocalVector(f->dm, &ylocal));
  /* the constrained entries, which the global vector does not hold, stay zero */
  PetscCall(VecZeroEntries(xlocal));
  PetscCall(DMGlobalToLocal(f->dm, x, INSERT_VALUES, xlocal));
  PetscCall(FEMCeedFluidJacobianApply(f->ceed, transpose, xlocal, ylocal));
  PetscCall(VecZeroEntries(y));
  PetscCall(DMLocalToGlobal(f->dm, ylocal, ADD_VALUES, y));
  PetscCall(DMRestoreLocalVector(f->dm, &xlocal));
  PetscCall(DMRestoreLocalVector(f->dm, &ylocal));
  if (transpose) PetscCall(MatMultTransposeAdd(f->boundary_jacobian, x, y, y));
  else PetscCall(MatMultAdd(f->boundary_jacobian, x, y, y));
  PetscFunctionReturn(0);
}

static PetscErrorCode Mult(Mat A, Vec x, Vec y)
{
  PetscFunctionBeginUser;
  PetscCall(Apply(A, x, y, PETSC_FALSE));
  PetscFunctionReturn(0);
}

static PetscErrorCode MultTranspose(Mat A, Vec x, Vec y)
{
  PetscFunctionBeginUser;
  PetscCall(Apply(A, x, y, PETSC_TRUE));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidMatFreeSetUp(Fluid f)
{
  PetscInt m, n, M, N;

  PetscFunctionBeginUser;
  if (!f->matfree) PetscFunctionReturn(0);
  PetscCall(MatGetLocalSize(f->ceed_jacobian, &m, &n));
  PetscCall(MatGetSize(f->ceed_jacobian, &M, &N));
  PetscCall(MatCreateShell(f->comm, m, n, M, N, f, &f->matfree_jacobian));
  PetscCall(MatShellSetOperation(f->matfree_jacobian, MATOP_MULT, (void (*)(void))Mult));
  PetscCall(MatShellSetOperation(f->matfree_jacobian, MATOP_MULT_TRANSPOSE, (void (*)(void))MultTranspose));
  PetscCall(PetscObjectSetName((PetscObject)f->matfree_jacobian, "fluid Jacobian (libCEED, matrix-free)"));
  /* the boundary terms' pattern is found at their first assembly and kept */
  PetscCall(MatCreate(f->comm, &f->boundary_jacobian));
  PetscCall(MatSetSizes(f->boundary_jacobian, m, n, M, N));
  PetscCall(MatSetType(f->boundary_jacobian, MATAIJ));
  PetscCall(MatSeqAIJSetPreallocation(f->boundary_jacobian, 0, NULL));
  PetscCall(MatMPIAIJSetPreallocation(f->boundary_jacobian, 0, NULL, 0, NULL));
  PetscCall(MatSetOption(f->boundary_jacobian, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_FALSE));
  PetscCall(MatAssemblyBegin(f->boundary_jacobian, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(f->boundary_jacobian, MAT_FINAL_ASSEMBLY));
  PetscCall(SNESSetJacobian(f->snes, f->matfree_jacobian, f->ceed_jacobian, FluidSNESJacobian, f));
  PetscFunctionReturn(0);
}

/* the operator's state: the libCEED linearization and the boundary terms' matrix */
static PetscErrorCode SetState(Fluid f, Vec xlocal, PetscBool old_mass)
{
  PetscFunctionBeginUser;
  PetscCall(FEMCeedFluidJacobianApplySetUp(f->ceed, xlocal, f->moving ? f->z_local : NULL, old_mass));
  PetscCall(MatZeroEntries(f->boundary_jacobian));
  PetscCall(FEMBoundaryTerms(f->dm, f->time, xlocal, NULL, f->boundary_jacobian, &f->tractions));
  PetscCall(MatAssemblyBegin(f->boundary_jacobian, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(f->boundary_jacobian, MAT_FINAL_ASSEMBLY));
  PetscFunctionReturn(0);
}

/* ||(A - assembled) x|| / ||assembled x|| and the same transposed, x random */
static PetscErrorCode Compare(Fluid f, Mat assembled, PetscReal difference[2])
{
  Vec         x, y, z;
  PetscRandom random;
  PetscReal   norm;

  PetscFunctionBeginUser;
  PetscCall(MatCreateVecs(assembled, &x, &y));
  PetscCall(VecDuplicate(y, &z));
  PetscCall(PetscRandomCreate(PETSC_COMM_SELF, &random));
  PetscCall(PetscRandomSetInterval(random, -1.0, 1.0));
  PetscCall(VecSetRandom(x, random));
  PetscCall(PetscRandomDestroy(&random));
  for (PetscInt t = 0; t < 2; ++t) {
    PetscCall((t ? MatMultTranspose : MatMult)(f->matfree_jacobian, x, y));
    PetscCall((t ? MatMultTranspose : MatMult)(assembled, x, z));
    PetscCall(VecNorm(z, NORM_2, &norm));
    PetscCall(VecAXPY(y, -1.0, z));
    PetscCall(VecNorm(y, NORM_2, &difference[t]));
    difference[t] /= norm > 0 ? norm : 1.0;
  }
  PetscCall(VecDestroy(&x));
  PetscCall(VecDestroy(&y));
  PetscCall(VecDestroy(&z));
  PetscFunctionReturn(0);
}

/* -fem_backend_check: the operator and its transpose against the assembled Jacobian at the
   solver's state (its own matrix, just made) and at a random state (a matrix of its own),
   which wakes the boundary terms' Jacobian up (backflow needs an inflow) */
static PetscErrorCode Check(Fluid f, Vec xlocal, PetscBool old_mass)
{
  PetscReal   at_state[2], at_random[2];
  PetscRandom random;
  Vec         xrandom;
  Mat         A;

  PetscFunctionBeginUser;
  if (f->operator_only) { /* the solver's matrix is the lagged preconditioner's: one at this state */
    PetscCall(FEMCeedFluidCreateMatrix(f->ceed, &A));
    PetscCall(FluidCeedAssemble(f, xlocal, old_mass, A));
    PetscCall(Compare(f, A, at_state));
    PetscCall(MatDestroy(&A));
  } else PetscCall(Compare(f, f->ceed_jacobian, at_state));
  PetscCall(DMGetLocalVector(f->dm, &xrandom));
  PetscCall(PetscRandomCreate(PETSC_COMM_SELF, &random));
  PetscCall(PetscRandomSetInterval(random, -1.0, 1.0));
  PetscCall(VecSetRandom(xrandom, random));
  PetscCall(PetscRandomDestroy(&random));
  PetscCall(FEMCeedFluidCreateMatrix(f->ceed, &A));
  PetscCall(FluidCeedAssemble(f, xrandom, old_mass, A));
  PetscCall(SetState(f, xrandom, old_mass));
  PetscCall(Compare(f, A, at_random));
  PetscCall(SetState(f, xlocal, old_mass));
  PetscCall(MatDestroy(&A));
  PetscCall(DMRestoreLocalVector(f->dm, &xrandom));
  PetscCall(PetscPrintf(f->comm,
                        "fsiopt: backend check: step %" PetscInt_FMT ": fluid matrix-free Jacobian product %.2e "
                        "(the solver's state) %.2e (a random state), transposed %.2e %.2e, relative to the assembled "
                        "matrix's\n",
                        f->step, (double)at_state[0], (double)at_random[0], (double)at_state[1], (double)at_random[1]));
  PetscCheck(PetscMax(PetscMax(at_state[0], at_state[1]), PetscMax(at_random[0], at_random[1])) <=
               FEM_BACKEND_CHECK_TOL,
             f->comm, PETSC_ERR_PLIB,
             "-fem_backend_check: the fluid's matrix-free Jacobian differs from the assembled one by more than %.0e at "
             "step %" PetscInt_FMT,
             (double)FEM_BACKEND_CHECK_TOL, f->step);
  PetscFunctionReturn(0);
}

PetscErrorCode FluidMatFreeUpdate(Fluid f, Vec xlocal, PetscBool old_mass)
{
  PetscFunctionBeginUser;
  PetscCall(SetState(f, xlocal, old_mass));
  if (f->check_backends && f->step <= FEM_BACKEND_CHECK_STEPS && f->step != f->matfree_checked_step) {
    f->matfree_checked_step = f->step;
    PetscCall(Check(f, xlocal, old_mass));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FluidMatFreeDestroy(Fluid f)
{
  PetscFunctionBeginUser;
  PetscCall(MatDestroy(&f->matfree_jacobian));
  PetscCall(MatDestroy(&f->boundary_jacobian));
  PetscFunctionReturn(0);
}
