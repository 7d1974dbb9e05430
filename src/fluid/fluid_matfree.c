/* -fluid_matfree: the fluid's Jacobian as a matrix-free operator, for Krylov solvers
   (-fluid_ksp_type gmres, ...) preconditioned by the assembled matrix. The volume terms are
   the solver's operator's product at the state of the last Jacobian (fluid_operator.h; the
   libCEED backend has one, ceed_fluid_matfree.c); the boundary terms (backflow, the
   interface's convective term), which live on a few faces, are a sparse matrix of their own,
   assembled with each Jacobian. Its transpose, for the adjoint solves, changes only the
   velocity-velocity block. With the default direct solver (preonly and LU) the operator is
   never applied and the run is unchanged. */
#include "fluid_impl.h"
#include "fem_ceed.h"

struct _n_FluidMatFree {
  Mat       shell;             /* the SNES's operator */
  Mat       assembled;         /* its preconditioning matrix, the operator's Jacobian */
  Mat       boundary_jacobian; /* the boundary terms at the state */
  PetscBool operator_only;     /* the next Jacobian moves the shell's state only */
  PetscInt  checked_step;      /* -fem_backend_check */
};

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
  PetscCall(FluidOperatorProduct(f->op, transpose, xlocal, ylocal));
  PetscCall(VecZeroEntries(y));
  PetscCall(DMLocalToGlobal(f->dm, ylocal, ADD_VALUES, y));
  PetscCall(DMRestoreLocalVector(f->dm, &xlocal));
  PetscCall(DMRestoreLocalVector(f->dm, &ylocal));
  if (transpose) PetscCall(MatMultTransposeAdd(f->matfree->boundary_jacobian, x, y, y));
  else PetscCall(MatMultAdd(f->matfree->boundary_jacobian, x, y, y));
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

PetscErrorCode FluidMatFreeCreate(Fluid f, FluidMatFree *matfree)
{
  FluidMatFree mf;
  PetscInt     m, n, M, N;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&mf));
  *matfree = mf;
  PetscCall(SNESGetJacobian(f->snes, NULL, &mf->assembled, NULL, NULL));
  PetscCall(MatGetLocalSize(mf->assembled, &m, &n));
  PetscCall(MatGetSize(mf->assembled, &M, &N));
  PetscCall(MatCreateShell(f->comm, m, n, M, N, f, &mf->shell));
  PetscCall(MatShellSetOperation(mf->shell, MATOP_MULT, (void (*)(void))Mult));
  PetscCall(MatShellSetOperation(mf->shell, MATOP_MULT_TRANSPOSE, (void (*)(void))MultTranspose));
  PetscCall(PetscObjectSetName((PetscObject)mf->shell, "fluid Jacobian (libCEED, matrix-free)"));
  /* the boundary terms' pattern is found at their first assembly and kept */
  PetscCall(MatCreate(f->comm, &mf->boundary_jacobian));
  PetscCall(MatSetSizes(mf->boundary_jacobian, m, n, M, N));
  PetscCall(MatSetType(mf->boundary_jacobian, MATAIJ));
  PetscCall(MatSeqAIJSetPreallocation(mf->boundary_jacobian, 0, NULL));
  PetscCall(MatMPIAIJSetPreallocation(mf->boundary_jacobian, 0, NULL, 0, NULL));
  PetscCall(MatSetOption(mf->boundary_jacobian, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_FALSE));
  PetscCall(MatAssemblyBegin(mf->boundary_jacobian, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(mf->boundary_jacobian, MAT_FINAL_ASSEMBLY));
  PetscCall(SNESSetJacobian(f->snes, mf->shell, mf->assembled, FluidSNESJacobian, f));
  PetscFunctionReturn(0);
}

PetscBool FluidMatFreeIsOperator(FluidMatFree mf, Mat J)
{
  return mf && J && J == mf->shell ? PETSC_TRUE : PETSC_FALSE;
}

PetscErrorCode FluidMatFreeSetOperatorOnly(FluidMatFree mf, PetscBool operator_only)
{
  PetscFunctionBeginUser;
  if (mf) mf->operator_only = operator_only;
  PetscFunctionReturn(0);
}

PetscBool FluidMatFreeOperatorOnly(FluidMatFree mf, Mat J)
{
  return FluidMatFreeIsOperator(mf, J) && mf->operator_only ? PETSC_TRUE : PETSC_FALSE;
}

/* the operator's state: the product's linearization and the boundary terms' matrix (a
   Jacobian alone: no tractions, whose cache only a residual needs) */
static PetscErrorCode SetState(Fluid f, Vec xlocal, PetscBool old_mass)
{
  FluidMatFree mf = f->matfree;

  PetscFunctionBeginUser;
  PetscCall(FluidOperatorProductSetUp(f->op, xlocal, old_mass));
  PetscCall(MatZeroEntries(mf->boundary_jacobian));
  PetscCall(FEMBoundaryTerms(f->dm, f->time, xlocal, NULL, mf->boundary_jacobian, NULL));
  PetscCall(MatAssemblyBegin(mf->boundary_jacobian, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(mf->boundary_jacobian, MAT_FINAL_ASSEMBLY));
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
    PetscCall((t ? MatMultTranspose : MatMult)(f->matfree->shell, x, y));
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
  if (f->matfree->operator_only) { /* the solver's matrix is the lagged preconditioner's: one at this state */
    PetscCall(FluidOperatorJacobianMatrix(f->op, xlocal, old_mass, &A));
    PetscCall(Compare(f, A, at_state));
    PetscCall(MatDestroy(&A));
  } else PetscCall(Compare(f, f->matfree->assembled, at_state));
  PetscCall(DMGetLocalVector(f->dm, &xrandom));
  PetscCall(PetscRandomCreate(PETSC_COMM_SELF, &random));
  PetscCall(PetscRandomSetInterval(random, -1.0, 1.0));
  PetscCall(VecSetRandom(xrandom, random));
  PetscCall(PetscRandomDestroy(&random));
  PetscCall(FluidOperatorJacobianMatrix(f->op, xrandom, old_mass, &A));
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
  FluidMatFree mf = f->matfree;

  PetscFunctionBeginUser;
  PetscCall(SetState(f, xlocal, old_mass));
  if (f->check && f->step <= FEM_BACKEND_CHECK_STEPS && f->step != mf->checked_step) {
    mf->checked_step = f->step;
    PetscCall(Check(f, xlocal, old_mass));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FluidMatFreeDestroy(FluidMatFree *matfree)
{
  PetscFunctionBeginUser;
  if (!*matfree) PetscFunctionReturn(0);
  PetscCall(MatDestroy(&(*matfree)->shell));
  PetscCall(MatDestroy(&(*matfree)->boundary_jacobian));
  PetscCall(PetscFree(*matfree));
  PetscFunctionReturn(0);
}
