/* The explicitly built Jacobian J0 of the coupling residual as a preconditioner
   (explicit_jacobian.h): dense, one sensitivity product per control, and its LU on every
   rank; or sparse, by probing (jacobian_probing.c), a few products whatever the mesh, and a
   parallel sparse LU (-coupling_explicit_jacobian_ksp_type, _pc_type: MUMPS by default).
   Rebuilt on request, with Broyden secant corrections in between. */
#include "explicit_jacobian.h"
#include "coupling.h"
#include "fem.h"

struct _p_ExplicitJacobian {
  Mat        J;            /* the Jacobian shell */
  Mat        J0;           /* dense, sequential, the same on every rank; or sparse, parallel (probing) */
  InterfaceProbing probing; /* NULL: dense */
  KSP              solver;  /* the sparse J0's */
  PC               pc;      /* the shell that applies J0^-1 */
  Vec        e, all, y, z; /* e: the control layout */
  Vec        e_full, x_part, y_part; /* the probed J0's: the control layout, its part on J0's ranks */
  PetscBool  probed_set_up;
  PetscReal  build_rtol; /* the probed build's subproblem solves' relative tolerance */
  VecScatter to_all;
  PetscBool  rebuild, factored;
  PetscBool  normal_equations; /* apply (J0^T J0)^{-1}, else J0^{-1} */
  PetscInt   builds;
  PetscInt   block;         /* at most this many columns per product J [e_j ...] */
  Mat        units, images; /* one width for every block and build: the products' work
                               blocks are allocated once */
  /* J^{-1} ~ J0^{-1} + sum_i a_i b_i^T: Broyden's secant corrections since the last build */
  PetscInt max_secants, nsecants;
  Vec     *secant_a, *secant_b;
};

static PetscErrorCode BuildProbed(ExplicitJacobian E)
{
  PetscFunctionBeginUser;
  if (!E->probed_set_up) {
    MPI_Comm comm;
    PetscInt n, N;
    E->probed_set_up = PETSC_TRUE;
    PetscCall(InterfaceProbingCreateMatrix(E->probing, &E->J0));
    if (E->J0) {
      PetscCall(PetscObjectGetComm((PetscObject)E->J0, &comm));
      PetscCall(MatGetLocalSize(E->J0, &n, NULL));
      PetscCall(MatGetSize(E->J0, &N, NULL));
      PetscCall(VecCreateMPIWithArray(comm, 1, n, N, NULL, &E->x_part));
      PetscCall(VecDuplicate(E->x_part, &E->y_part));
    }
  }
  if (E->J0 && !E->solver) {
    PC pc;
    PetscCall(KSPCreate(PetscObjectComm((PetscObject)E->J0), &E->solver));
    PetscCall(KSPSetOptionsPrefix(E->solver, "coupling_explicit_jacobian_"));
    PetscCall(KSPSetType(E->solver, KSPPREONLY));
    PetscCall(KSPGetPC(E->solver, &pc));
    PetscCall(PCSetType(pc, PCLU));
    PetscCall(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
    PetscCall(KSPSetFromOptions(E->solver));
  }
  /* a preconditioner's entries need a few digits: iterative subproblem solves to
     E->build_rtol (a factored one is exact anyway) */
  PetscCall(FEMSetLinearizedRtol(E->build_rtol));
  PetscCall(InterfaceProbingBuild(E->probing, E->J, E->block, E->J0));
  PetscCall(FEMSetLinearizedRtol(0));
  if (E->J0) {
    PetscCall(KSPSetOperators(E->solver, E->J0, E->J0));
    PetscCall(KSPSetUp(E->solver));
  }
  E->factored = PETSC_TRUE;
  E->rebuild  = PETSC_FALSE;
  E->nsecants = 0;
  E->builds++;
  PetscFunctionReturn(0);
}

static PetscErrorCode Build(ExplicitJacobian E)
{
  PetscInt N, n, rstart, rend;

  PetscFunctionBeginUser;
  if (E->probing) {
    PetscCall(BuildProbed(E));
    PetscFunctionReturn(0);
  }
  /* the dense J0 lives on every rank: the controls gathered there (the probed one needs none) */
  if (!E->to_all) PetscCall(VecScatterCreateToAll(E->e, &E->to_all, &E->all));
  PetscCall(VecGetSize(E->e, &N));
  PetscCall(VecGetLocalSize(E->e, &n));
  PetscCall(VecGetOwnershipRange(E->e, &rstart, &rend));
  PetscCall(MatDestroy(&E->J0));
  PetscCall(MatCreateSeqDense(PETSC_COMM_SELF, N, N, NULL, &E->J0));
  /* the fewest blocks of at most E->block columns, all of one width; the last one's
     unused columns are zero */
  const PetscInt nblocks = (N + E->block - 1) / E->block, width = (N + nblocks - 1) / nblocks;
  if (!E->units)
    PetscCall(MatCreateDense(PetscObjectComm((PetscObject)E->J), n, PETSC_DECIDE, N, width, NULL, &E->units));
  for (PetscInt first = 0; first < N; first += width) {
    const PetscInt columns = PetscMin(width, N - first);

    PetscCall(MatZeroEntries(E->units));
    for (PetscInt j = 0; j < columns; ++j)
      if (first + j >= rstart && first + j < rend) PetscCall(MatSetValue(E->units, first + j, j, 1.0, INSERT_VALUES));
    PetscCall(MatAssemblyBegin(E->units, MAT_FINAL_ASSEMBLY));
    PetscCall(MatAssemblyEnd(E->units, MAT_FINAL_ASSEMBLY));
    PetscCall(MatMatMult(E->J, E->units, E->images ? MAT_REUSE_MATRIX : MAT_INITIAL_MATRIX, PETSC_DEFAULT, &E->images));
    for (PetscInt j = 0; j < columns; ++j) {
      Vec image, column;
      PetscCall(MatDenseGetColumnVecRead(E->images, j, &image));
      PetscCall(VecScatterBegin(E->to_all, image, E->all, INSERT_VALUES, SCATTER_FORWARD));
      PetscCall(VecScatterEnd(E->to_all, image, E->all, INSERT_VALUES, SCATTER_FORWARD));
      PetscCall(MatDenseRestoreColumnVecRead(E->images, j, &image));
      PetscCall(MatDenseGetColumnVecWrite(E->J0, first + j, &column));
      PetscCall(VecCopy(E->all, column));
      PetscCall(MatDenseRestoreColumnVecWrite(E->J0, first + j, &column));
    }
  }
  PetscCall(MatLUFactor(E->J0, NULL, NULL, NULL));
  if (!E->y) PetscCall(VecDuplicate(E->all, &E->y));
  if (!E->z) PetscCall(VecDuplicate(E->all, &E->z));
  E->factored = PETSC_TRUE;
  E->rebuild  = PETSC_FALSE;
  E->nsecants = 0; /* J0 is J now */
  E->builds++;
  PetscFunctionReturn(0);
}

/* out = J0^{-1} x or J0^{-T} x with the probed J0, on the ranks that hold it */
static PetscErrorCode SolveProbed(ExplicitJacobian E, PetscBool transpose, Vec x, Vec out)
{
  const PetscScalar *xa;
  PetscScalar       *ya;

  PetscFunctionBeginUser;
  if (!E->J0) PetscFunctionReturn(0);
  PetscCall(VecGetArrayRead(x, &xa));
  PetscCall(VecGetArray(out, &ya));
  PetscCall(VecPlaceArray(E->x_part, xa));
  PetscCall(VecPlaceArray(E->y_part, ya));
  if (transpose) PetscCall(KSPSolveTranspose(E->solver, E->x_part, E->y_part));
  else PetscCall(KSPSolve(E->solver, E->x_part, E->y_part));
  PetscCall(VecResetArray(E->x_part));
  PetscCall(VecResetArray(E->y_part));
  PetscCall(VecRestoreArray(out, &ya));
  PetscCall(VecRestoreArrayRead(x, &xa));
  PetscFunctionReturn(0);
}

/* out = (J0^{-1} + sum_i a_i b_i^T) x, J0 factored */
static PetscErrorCode ApplyInverse(ExplicitJacobian E, Vec x, Vec out)
{
  PetscScalar dots[64];

  PetscFunctionBeginUser;
  if (E->probing) PetscCall(SolveProbed(E, PETSC_FALSE, x, out));
  else {
    PetscCall(VecScatterBegin(E->to_all, x, E->all, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterEnd(E->to_all, x, E->all, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(MatSolve(E->J0, E->all, E->z));
    PetscCall(VecScatterBegin(E->to_all, E->z, out, INSERT_VALUES, SCATTER_REVERSE));
    PetscCall(VecScatterEnd(E->to_all, E->z, out, INSERT_VALUES, SCATTER_REVERSE));
  }
  if (E->nsecants) {
    PetscCall(VecMDot(x, E->nsecants, E->secant_b, dots));
    PetscCall(VecMAXPY(out, E->nsecants, dots, E->secant_a));
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode Apply(PC pc, Vec x, Vec out)
{
  ExplicitJacobian E;

  PetscFunctionBeginUser;
  PetscCall(PCShellGetContext(pc, &E));
  if (E->rebuild || !E->factored) PetscCall(Build(E));
  if (!E->normal_equations) {
    PetscCall(ApplyInverse(E, x, out));
    PetscFunctionReturn(0);
  }
  if (E->probing) {
    if (!E->e_full) PetscCall(VecDuplicate(E->e, &E->e_full));
    PetscCall(SolveProbed(E, PETSC_TRUE, x, E->e_full)); /* J0^{-T} x */
    PetscCall(SolveProbed(E, PETSC_FALSE, E->e_full, out)); /* J0^{-1} J0^{-T} x */
    PetscFunctionReturn(0);
  }
  PetscCall(VecScatterBegin(E->to_all, x, E->all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(E->to_all, x, E->all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(MatSolveTranspose(E->J0, E->all, E->y)); /* J0^{-T} x */
  PetscCall(MatSolve(E->J0, E->y, E->z));            /* J0^{-1} J0^{-T} x */
  PetscCall(VecScatterBegin(E->to_all, E->z, out, INSERT_VALUES, SCATTER_REVERSE));
  PetscCall(VecScatterEnd(E->to_all, E->z, out, INSERT_VALUES, SCATTER_REVERSE));
  PetscFunctionReturn(0);
}

PetscErrorCode ExplicitJacobianCreate(Mat J, PetscInt block, PetscBool normal_equations, KSP ksp,
                                      ExplicitJacobian *explicit_jacobian)
{
  ExplicitJacobian E;
  PC               pc;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&E));
  E->J                = J;
  E->block            = block;
  E->normal_equations = normal_equations;
  E->rebuild          = PETSC_TRUE;
  PetscCall(MatCreateVecs(J, &E->e, NULL));
  PetscCall(KSPGetPC(ksp, &pc));
  E->pc = pc;
  PetscCall(PCSetType(pc, PCSHELL));
  PetscCall(PCShellSetContext(pc, E));
  PetscCall(PCShellSetApply(pc, Apply));
  PetscCall(PCShellSetName(pc, normal_equations ? "explicit Gauss-Newton Jacobian (LU of J0, applied as (J0^T J0)^-1)"
                                                : "explicit Jacobian (LU of J0, applied as J0^-1)"));
  *explicit_jacobian = E;
  PetscFunctionReturn(0);
}

/* J0 by probing, with the colouring and pattern of `probing` (taken over) */
PetscErrorCode ExplicitJacobianSetProbing(ExplicitJacobian E, InterfaceProbing probing, PetscReal build_rtol)
{
  PetscFunctionBeginUser;
  E->probing    = probing;
  E->build_rtol = build_rtol;
  PetscCall(PCShellSetName(E->pc, E->normal_equations
                                    ? "probed Gauss-Newton Jacobian (sparse LU of J0, applied as (J0^T J0)^-1)"
                                    : "probed Jacobian (sparse LU of J0, applied as J0^-1)"));
  PetscFunctionReturn(0);
}

PetscErrorCode ExplicitJacobianRequestRebuild(ExplicitJacobian E)
{
  PetscFunctionBeginUser;
  E->rebuild = PETSC_TRUE;
  PetscFunctionReturn(0);
}

/* As a run restarted here has it: no J0 until the next one is built (the start correction of a
   step accepted at its start then has none, in both runs) */
PetscErrorCode ExplicitJacobianForget(ExplicitJacobian E)
{
  PetscFunctionBeginUser;
  E->rebuild  = PETSC_TRUE;
  E->factored = PETSC_FALSE;
  E->nsecants = 0;
  PetscFunctionReturn(0);
}

PetscErrorCode ExplicitJacobianSolve(ExplicitJacobian E, Vec b, Vec x, PetscBool *solved)
{
  PetscFunctionBeginUser;
  *solved = E && E->factored ? PETSC_TRUE : PETSC_FALSE;
  if (!*solved) PetscFunctionReturn(0);
  PetscCall(ApplyInverse(E, b, x));
  PetscFunctionReturn(0);
}

/* "Bad" Broyden on the inverse: H+ = H + (s - H y) y^T / (y^T y), so that H+ y = s. When
   the corrections fill up they start again from J0^{-1}. */
PetscErrorCode ExplicitJacobianSecantUpdate(ExplicitJacobian E, Vec s, Vec y)
{
  PetscReal yy;

  PetscFunctionBeginUser;
  if (!E->factored || E->rebuild || E->max_secants == 0) PetscFunctionReturn(0);
  if (E->nsecants == E->max_secants) E->nsecants = 0;
  PetscCall(VecNorm(y, NORM_2, &yy));
  if (!(yy > 0)) PetscFunctionReturn(0);
  if (!E->secant_a) {
    PetscCall(VecDuplicateVecs(E->e, E->max_secants, &E->secant_a));
    PetscCall(VecDuplicateVecs(E->e, E->max_secants, &E->secant_b));
  }
  {
    Vec a = E->secant_a[E->nsecants], b = E->secant_b[E->nsecants];
    PetscCall(ApplyInverse(E, y, a));
    PetscCall(VecAYPX(a, -1.0, s)); /* s - H y */
    PetscCall(VecScale(a, 1.0 / (yy * yy)));
    PetscCall(VecCopy(y, b));
  }
  E->nsecants++;
  PetscFunctionReturn(0);
}

PetscErrorCode ExplicitJacobianSetSecants(ExplicitJacobian E, PetscInt max_secants)
{
  PetscFunctionBeginUser;
  PetscCheck(max_secants <= 64, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "at most 64 secant corrections");
  E->max_secants = max_secants;
  PetscFunctionReturn(0);
}

PetscErrorCode ExplicitJacobianGetBuilds(ExplicitJacobian E, PetscInt *builds)
{
  PetscFunctionBeginUser;
  *builds = E ? E->builds : 0;
  PetscFunctionReturn(0);
}

PetscErrorCode ExplicitJacobianDestroy(ExplicitJacobian *explicit_jacobian)
{
  ExplicitJacobian E = *explicit_jacobian;

  PetscFunctionBeginUser;
  if (!E) PetscFunctionReturn(0);
  PetscCall(MatDestroy(&E->J0));
  PetscCall(MatDestroy(&E->units));
  PetscCall(MatDestroy(&E->images));
  PetscCall(VecDestroy(&E->e));
  PetscCall(VecDestroy(&E->all));
  PetscCall(VecDestroy(&E->y));
  PetscCall(VecDestroy(&E->z));
  PetscCall(VecDestroy(&E->e_full));
  PetscCall(VecDestroy(&E->x_part));
  PetscCall(VecDestroy(&E->y_part));
  PetscCall(KSPDestroy(&E->solver));
  PetscCall(InterfaceProbingDestroy(&E->probing));
  if (E->secant_a) {
    PetscCall(VecDestroyVecs(E->max_secants, &E->secant_a));
    PetscCall(VecDestroyVecs(E->max_secants, &E->secant_b));
  }
  PetscCall(VecScatterDestroy(&E->to_all));
  PetscCall(PetscFree(*explicit_jacobian));
  PetscFunctionReturn(0);
}
