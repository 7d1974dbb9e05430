/* J h and J^T rho (coupling.h): linear solves with the factors residual.c left, one pair
   per product or one multi-right-hand-side pair for a block of controls, and the MATSHELL
   through which TAO and the explicit Jacobian reach them. */
#include "problem_impl.h"
#include "logging.h"

/* fluid_vec and structure_vec = the subproblems' loads of the interface load all_q. */
static PetscErrorCode SpreadLoad(CouplingProblem P)
{
  PetscFunctionBeginUser;
  if (P->structure) PetscCall(VecZeroEntries(P->structure_vec));
  PetscCall(InterfaceStructureSpread(P->itf, P->all_q, P->structure ? P->structure_vec : NULL));
  if (P->fluid) {
    PetscCall(VecZeroEntries(P->fluid_vec));
    PetscCall(InterfaceFluidSpread(P->itf, P->all_q, P->fluid_vec));
  }
  PetscFunctionReturn(0);
}

/* out = the jump of the responses fluid_sol and structure_sol (see SolveAndTrace). */
static PetscErrorCode TraceResponses(CouplingProblem P, Vec out)
{
  DM dm;

  PetscFunctionBeginUser;
  if (P->fluid) {
    PetscCall(FluidGetDM(P->fluid, &dm));
    PetscCall(VecZeroEntries(P->fluid_local));
    PetscCall(DMGlobalToLocal(dm, P->fluid_sol, INSERT_VALUES, P->fluid_local));
  }
  if (P->structure) {
    PetscCall(StructureGetDM(P->structure, &dm));
    PetscCall(VecZeroEntries(P->structure_local));
    PetscCall(DMGlobalToLocal(dm, P->structure_sol, INSERT_VALUES, P->structure_local));
  }
  /* the structure responds to -B_s h with -delta eta; the jump carries -c delta eta */
  PetscCall(CouplingProblemStateJump(P, -P->velocity_coefficient, out, NULL));
  PetscFunctionReturn(0);
}

/* The common body of J h and J^T rho: solve both subproblems (forward or transposed)
   with the interface load all_q, and leave their velocity traces' sum in `out`. */
static PetscErrorCode SolveAndTrace(CouplingProblem P, PetscBool transpose, Vec out)
{
  PetscFunctionBeginUser;
  PetscCall(SpreadLoad(P));
  if (P->fluid) PetscCall(FluidLinearSolve(P->fluid, P->fluid_vec, P->fluid_sol, transpose));
  if (P->structure) PetscCall(StructureLinearSolve(P->structure, P->structure_vec, P->structure_sol, transpose));
  PetscCall(TraceResponses(P, out));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingProblemJacobianMult(CouplingProblem P, Vec h, Vec y)
{
  PetscFunctionBeginUser;
  if (StepFailed(&P->failure)) {
    PetscCall(VecCopy(h, y));
    PetscFunctionReturn(0);
  }
  P->forward_products++;
  PetscCall(PetscLogStagePush(FSIOPT_STAGE_SENSITIVITY));
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_SENSITIVITY, 0, 0, 0, 0));
  PetscCall(CouplingProblemControlToLoad(P, h, P->all_q));
  PetscCall(SolveAndTrace(P, PETSC_FALSE, y));
  PetscCall(VecPointwiseMult(y, y, P->weight_sqrt));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_SENSITIVITY, 0, 0, 0, 0));
  PetscCall(PetscLogStagePop());
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingProblemJacobianMultTranspose(CouplingProblem P, Vec rho, Vec y)
{
  PetscFunctionBeginUser;
  if (StepFailed(&P->failure)) {
    PetscCall(VecCopy(rho, y));
    PetscFunctionReturn(0);
  }
  P->adjoint_products++;
  PetscCall(PetscLogStagePush(FSIOPT_STAGE_ADJOINT));
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_ADJOINT, 0, 0, 0, 0));
  PetscCall(VecPointwiseMult(P->g, rho, P->weight_sqrt));
  PetscCall(InterfaceExtend(P->itf, P->g, P->all_q));
  PetscCall(SolveAndTrace(P, PETSC_TRUE, P->r));
  PetscCall(InterfaceExtend(P->itf, P->r, P->all_a));
  PetscCall(MatMult(P->mass, P->all_a, P->all_b));
  PetscCall(InterfaceRestrict(P->itf, P->all_b, y));
  PetscCall(VecPointwiseDivide(y, y, P->weight_sqrt));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_ADJOINT, 0, 0, 0, 0));
  PetscCall(PetscLogStagePop());
  PetscFunctionReturn(0);
}

/* Dense work blocks of `columns` columns laid out like v (NULL v: none on this rank). */
static PetscErrorCode EnsureBlocks(Vec v, PetscInt columns, Mat *rhs, Mat *sol)
{
  PetscInt n, N, have = -1;

  PetscFunctionBeginUser;
  if (!v) PetscFunctionReturn(0);
  if (*rhs) PetscCall(MatGetSize(*rhs, NULL, &have));
  if (have == columns) PetscFunctionReturn(0);
  PetscCall(MatDestroy(rhs));
  PetscCall(MatDestroy(sol));
  PetscCall(VecGetLocalSize(v, &n));
  PetscCall(VecGetSize(v, &N));
  PetscCall(MatCreateDense(PetscObjectComm((PetscObject)v), n, PETSC_DECIDE, N, columns, NULL, rhs));
  PetscCall(MatDuplicate(*rhs, MAT_DO_NOT_COPY_VALUES, sol));
  PetscFunctionReturn(0);
}

static PetscErrorCode CopyToColumn(Vec v, Mat block, PetscInt j)
{
  Vec column;

  PetscFunctionBeginUser;
  PetscCall(MatDenseGetColumnVecWrite(block, j, &column));
  PetscCall(VecCopy(v, column));
  PetscCall(MatDenseRestoreColumnVecWrite(block, j, &column));
  PetscFunctionReturn(0);
}

static PetscErrorCode CopyFromColumn(Mat block, PetscInt j, Vec v)
{
  Vec column;

  PetscFunctionBeginUser;
  PetscCall(MatDenseGetColumnVecRead(block, j, &column));
  PetscCall(VecCopy(column, v));
  PetscCall(MatDenseRestoreColumnVecRead(block, j, &column));
  PetscFunctionReturn(0);
}

/* Y = J H column by column as CouplingProblemJacobianMult, but with one solve of each
   subproblem for the whole block: the explicit Jacobian's columns come from a handful of
   multi-right-hand-side solves instead of one pair of solves per control. */
PetscErrorCode CouplingProblemJacobianMultBlock(CouplingProblem P, Mat H, Mat Y)
{
  PetscInt columns;

  PetscFunctionBeginUser;
  if (StepFailed(&P->failure)) {
    PetscCall(MatCopy(H, Y, SAME_NONZERO_PATTERN));
    PetscFunctionReturn(0);
  }
  PetscCall(PetscLogStagePush(FSIOPT_STAGE_SENSITIVITY));
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_SENSITIVITY, 0, 0, 0, 0));
  PetscCall(MatGetSize(H, NULL, &columns));
  P->forward_products += columns;
  PetscCall(EnsureBlocks(P->fluid ? P->fluid_vec : NULL, columns, &P->fluid_rhs_block, &P->fluid_sol_block));
  PetscCall(
    EnsureBlocks(P->structure ? P->structure_vec : NULL, columns, &P->structure_rhs_block, &P->structure_sol_block));
  for (PetscInt j = 0; j < columns; ++j) {
    Vec h;
    PetscCall(MatDenseGetColumnVecRead(H, j, &h));
    PetscCall(CouplingProblemControlToLoad(P, h, P->all_q));
    PetscCall(MatDenseRestoreColumnVecRead(H, j, &h));
    PetscCall(SpreadLoad(P));
    if (P->structure) PetscCall(CopyToColumn(P->structure_vec, P->structure_rhs_block, j));
    if (P->fluid) PetscCall(CopyToColumn(P->fluid_vec, P->fluid_rhs_block, j));
  }
  if (P->fluid) PetscCall(FluidLinearSolveBlock(P->fluid, P->fluid_rhs_block, P->fluid_sol_block));
  if (P->structure) PetscCall(StructureLinearSolveBlock(P->structure, P->structure_rhs_block, P->structure_sol_block));
  for (PetscInt j = 0; j < columns; ++j) {
    Vec y;
    if (P->fluid) PetscCall(CopyFromColumn(P->fluid_sol_block, j, P->fluid_sol));
    if (P->structure) PetscCall(CopyFromColumn(P->structure_sol_block, j, P->structure_sol));
    PetscCall(MatDenseGetColumnVecWrite(Y, j, &y));
    PetscCall(TraceResponses(P, y));
    PetscCall(VecPointwiseMult(y, y, P->weight_sqrt));
    PetscCall(MatDenseRestoreColumnVecWrite(Y, j, &y));
  }
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_SENSITIVITY, 0, 0, 0, 0));
  PetscCall(PetscLogStagePop());
  PetscFunctionReturn(0);
}

static PetscErrorCode ShellMult(Mat J, Vec h, Vec y)
{
  CouplingProblem P;

  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(J, &P));
  PetscCall(CouplingProblemJacobianMult(P, h, y));
  PetscFunctionReturn(0);
}

static PetscErrorCode ShellMatMult(Mat J, Mat H, Mat Y, PETSC_UNUSED void *product_data)
{
  CouplingProblem P;

  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(J, &P));
  PetscCall(CouplingProblemJacobianMultBlock(P, H, Y));
  PetscFunctionReturn(0);
}

static PetscErrorCode ShellMultTranspose(Mat J, Vec rho, Vec y)
{
  CouplingProblem P;

  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(J, &P));
  PetscCall(CouplingProblemJacobianMultTranspose(P, rho, y));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingProblemGetProductCounts(CouplingProblem P, PetscInt *forward, PetscInt *adjoint)
{
  PetscFunctionBeginUser;
  *forward = P->forward_products;
  *adjoint = P->adjoint_products;
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingProblemCreateJacobian(CouplingProblem P, Mat *J)
{
  PetscInt n, N;

  PetscFunctionBeginUser;
  PetscCall(VecGetLocalSize(P->weight_sqrt, &n));
  PetscCall(VecGetSize(P->weight_sqrt, &N));
  PetscCall(MatCreateShell(P->comm, n, n, N, N, P, J));
  PetscCall(MatShellSetOperation(*J, MATOP_MULT, (void (*)(void))ShellMult));
  PetscCall(MatShellSetOperation(*J, MATOP_MULT_TRANSPOSE, (void (*)(void))ShellMultTranspose));
  /* MatMatMult(J, H) on a dense block of controls, on one rank or several */
  PetscCall(MatShellSetMatProductOperation(*J, MATPRODUCT_AB, NULL, ShellMatMult, NULL, MATSEQDENSE, MATDENSE));
  PetscCall(MatShellSetMatProductOperation(*J, MATPRODUCT_AB, NULL, ShellMatMult, NULL, MATMPIDENSE, MATDENSE));
  PetscFunctionReturn(0);
}
