/* PC "ilubaij": ILU on a copy of the operator in block AIJ format (MATSEQBAIJ), its blocks the
   operator's own block size (a vector field's components at a node). PETSc's ILU of an AIJ
   matrix solves row by row, one column index per number; of a BAIJ matrix, block by block,
   one index per 3 x 3 block of a velocity, and its triangular solves are where a field split
   of tube3d's fluid spends a quarter of its time. The copy keeps its pattern across the
   operator's refreshes and takes only the new values. An operator whose rows are not whole
   blocks (a component held by a boundary condition) keeps its AIJ format and PETSc's ILU.
   Used as the block Jacobi's sub-PC (options/solvers/fluid-velocity-ilu.yaml); the inner ILU
   reads the options of the PC's prefix followed by ilubaij_ (-..._ilubaij_pc_factor_levels). */
#include <petsc/private/pcimpl.h>
#include "pc_ilu_baij.h"

typedef struct {
  Mat              blocked; /* the operator's values in MATSEQBAIJ */
  PC               ilu;
  PetscObjectState copied; /* the operator's state when its values were copied */
} PC_ILUBAIJ;

/* Rows bs k .. bs k + bs - 1 hold whole bs x bs blocks, in the same columns */
static PetscBool WholeBlocks(const PetscInt *ia, const PetscInt *ja, PetscInt bs, PetscInt k)
{
  const PetscInt start = ia[bs * k], width = ia[bs * k + 1] - start;

  if (width % bs) return PETSC_FALSE;
  for (PetscInt r = 1; r < bs; ++r) {
    if (ia[bs * k + r + 1] - ia[bs * k + r] != width) return PETSC_FALSE;
    for (PetscInt j = 0; j < width; ++j)
      if (ja[ia[bs * k + r] + j] != ja[start + j]) return PETSC_FALSE;
  }
  for (PetscInt j = 0; j < width; ++j)
    if (ja[start + j] != ja[start + j - j % bs] + j % bs || ja[start + j - j % bs] % bs) return PETSC_FALSE;
  return PETSC_TRUE;
}

/* every block row of A whole blocks (WholeBlocks), so that a BAIJ copy holds A exactly */
static PetscErrorCode HasWholeBlocks(Mat A, PetscInt bs, PetscBool *whole)
{
  const PetscInt *ia, *ja;
  PetscInt        n;
  PetscBool       done;

  PetscFunctionBeginUser;
  PetscCall(MatGetRowIJ(A, 0, PETSC_FALSE, PETSC_FALSE, &n, &ia, &ja, &done));
  *whole = (PetscBool)(done && bs > 1 && n % bs == 0);
  for (PetscInt k = 0; *whole && k < n / bs; ++k) *whole = WholeBlocks(ia, ja, bs, k);
  PetscCall(MatRestoreRowIJ(A, 0, PETSC_FALSE, PETSC_FALSE, &n, &ia, &ja, &done));
  PetscFunctionReturn(0);
}

/* block row k of B from rows bs k .. bs k + bs - 1 of A; preallocate: B's pattern too (the
   first copy), else only the values */
static PetscErrorCode CopyValues(Mat A, Mat B, PetscInt bs, PetscBool preallocate)
{
  const PetscInt    *ia, *ja;
  const PetscScalar *a;
  PetscInt           n, nb, *columns, *counts, widest = 0;
  PetscScalar       *values;
  PetscBool          done;

  PetscFunctionBeginUser;
  PetscCall(MatGetRowIJ(A, 0, PETSC_FALSE, PETSC_FALSE, &n, &ia, &ja, &done));
  nb = n / bs;
  for (PetscInt k = 0; k < nb; ++k) widest = PetscMax(widest, ia[bs * k + 1] - ia[bs * k]);
  if (preallocate) {
    PetscCall(PetscMalloc1(nb, &counts));
    for (PetscInt k = 0; k < nb; ++k) counts[k] = (ia[bs * k + 1] - ia[bs * k]) / bs;
    PetscCall(MatXAIJSetPreallocation(B, bs, counts, NULL, NULL, NULL));
    PetscCall(PetscFree(counts));
    PetscCall(MatSetOption(B, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));
  }
  PetscCall(MatSeqAIJGetArrayRead(A, &a));
  PetscCall(PetscMalloc2(widest / bs, &columns, bs * widest, &values));
  for (PetscInt k = 0; k < nb; ++k) {
    const PetscInt start = ia[bs * k], width = ia[bs * k + 1] - start;
    for (PetscInt j = 0; j < width / bs; ++j) columns[j] = ja[start + bs * j] / bs;
    for (PetscInt r = 0; r < bs; ++r) PetscCall(PetscArraycpy(values + r * width, a + ia[bs * k + r], width));
    PetscCall(MatSetValuesBlocked(B, 1, &k, width / bs, columns, values, INSERT_VALUES)); /* row-oriented */
  }
  PetscCall(PetscFree2(columns, values));
  PetscCall(MatSeqAIJRestoreArrayRead(A, &a));
  PetscCall(MatRestoreRowIJ(A, 0, PETSC_FALSE, PETSC_FALSE, &n, &ia, &ja, &done));
  PetscCall(MatAssemblyBegin(B, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(B, MAT_FINAL_ASSEMBLY));
  PetscFunctionReturn(0);
}

static PetscErrorCode PCSetUp_ILUBAIJ(PC pc)
{
  PC_ILUBAIJ      *data = (PC_ILUBAIJ *)pc->data;
  PetscInt         bs, n;
  PetscBool        aij, whole = PETSC_FALSE;
  PetscObjectState state;
  const char      *prefix;

  PetscFunctionBeginUser;
  PetscCall(PCGetOptionsPrefix(pc, &prefix));
  PetscCall(PetscObjectTypeCompare((PetscObject)pc->pmat, MATSEQAIJ, &aij));
  PetscCheck(aij, PetscObjectComm((PetscObject)pc), PETSC_ERR_SUP,
             "option -%spc_type ilubaij: expected a one-rank AIJ matrix (use it as -sub_pc_type of bjacobi), got %s",
             prefix ? prefix : "", ((PetscObject)pc->pmat)->type_name);
  PetscCall(MatGetBlockSize(pc->pmat, &bs));
  PetscCall(PetscObjectStateGet((PetscObject)pc->pmat, &state));
  if (!pc->setupcalled || pc->flag == DIFFERENT_NONZERO_PATTERN) {
    PetscCall(MatDestroy(&data->blocked));
    PetscCall(HasWholeBlocks(pc->pmat, bs, &whole));
    if (whole) {
      PetscCall(MatGetLocalSize(pc->pmat, &n, NULL));
      PetscCall(MatCreate(PETSC_COMM_SELF, &data->blocked));
      PetscCall(MatSetSizes(data->blocked, n, n, n, n));
      PetscCall(MatSetType(data->blocked, MATSEQBAIJ));
      PetscCall(CopyValues(pc->pmat, data->blocked, bs, PETSC_TRUE));
    } else /* a component held by a boundary condition, say: PETSc's ILU of the AIJ matrix */
      PetscCall(PetscInfo(pc, "rows not in whole %" PetscInt_FMT " x %" PetscInt_FMT " blocks: ILU of the AIJ matrix\n",
                          bs, bs));
  } else if (data->blocked && state != data->copied) PetscCall(CopyValues(pc->pmat, data->blocked, bs, PETSC_FALSE));
  data->copied = state;
  if (data->blocked) PetscCall(PCSetOperators(data->ilu, data->blocked, data->blocked));
  else PetscCall(PCSetOperators(data->ilu, pc->pmat, pc->pmat));
  PetscCall(PCSetUp(data->ilu));
  PetscFunctionReturn(0);
}

static PetscErrorCode PCApply_ILUBAIJ(PC pc, Vec x, Vec y)
{
  PC_ILUBAIJ *data = (PC_ILUBAIJ *)pc->data;

  PetscFunctionBeginUser;
  PetscCall(PCApply(data->ilu, x, y));
  PetscFunctionReturn(0);
}

static PetscErrorCode PCApplyTranspose_ILUBAIJ(PC pc, Vec x, Vec y)
{
  PC_ILUBAIJ *data = (PC_ILUBAIJ *)pc->data;

  PetscFunctionBeginUser;
  PetscCall(PCApplyTranspose(data->ilu, x, y));
  PetscFunctionReturn(0);
}

/* the inner ILU reads its own options, under the prefix the PC has by now */
static PetscErrorCode PCSetFromOptions_ILUBAIJ(PC pc, PetscOptionItems *PetscOptionsObject)
{
  PC_ILUBAIJ *data = (PC_ILUBAIJ *)pc->data;
  const char *prefix;

  PetscFunctionBeginUser;
  (void)PetscOptionsObject;
  PetscCall(PCGetOptionsPrefix(pc, &prefix));
  PetscCall(PCSetOptionsPrefix(data->ilu, prefix));
  PetscCall(PCAppendOptionsPrefix(data->ilu, "ilubaij_"));
  PetscCall(PCSetFromOptions(data->ilu));
  PetscFunctionReturn(0);
}

static PetscErrorCode PCView_ILUBAIJ(PC pc, PetscViewer viewer)
{
  PC_ILUBAIJ *data = (PC_ILUBAIJ *)pc->data;

  PetscFunctionBeginUser;
  PetscCall(PetscViewerASCIIPrintf(viewer, data->blocked
                                             ? "ILU of the operator copied to block AIJ:\n"
                                             : "ILU of the AIJ operator (its rows are not whole blocks):\n"));
  PetscCall(PetscViewerASCIIPushTab(viewer));
  PetscCall(PCView(data->ilu, viewer));
  PetscCall(PetscViewerASCIIPopTab(viewer));
  PetscFunctionReturn(0);
}

static PetscErrorCode PCReset_ILUBAIJ(PC pc)
{
  PC_ILUBAIJ *data = (PC_ILUBAIJ *)pc->data;

  PetscFunctionBeginUser;
  PetscCall(MatDestroy(&data->blocked));
  PetscCall(PCReset(data->ilu));
  PetscFunctionReturn(0);
}

static PetscErrorCode PCDestroy_ILUBAIJ(PC pc)
{
  PC_ILUBAIJ *data = (PC_ILUBAIJ *)pc->data;

  PetscFunctionBeginUser;
  PetscCall(MatDestroy(&data->blocked));
  PetscCall(PCDestroy(&data->ilu));
  PetscCall(PetscFree(pc->data));
  PetscFunctionReturn(0);
}

static PetscErrorCode PCCreate_ILUBAIJ(PC pc)
{
  PC_ILUBAIJ *data;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&data));
  pc->data = data;
  PetscCall(PCCreate(PetscObjectComm((PetscObject)pc), &data->ilu));
  PetscCall(PCSetType(data->ilu, PCILU));
  pc->ops->setup          = PCSetUp_ILUBAIJ;
  pc->ops->apply          = PCApply_ILUBAIJ;
  pc->ops->applytranspose = PCApplyTranspose_ILUBAIJ;
  pc->ops->setfromoptions = PCSetFromOptions_ILUBAIJ;
  pc->ops->view           = PCView_ILUBAIJ;
  pc->ops->reset          = PCReset_ILUBAIJ;
  pc->ops->destroy        = PCDestroy_ILUBAIJ;
  PetscFunctionReturn(0);
}

PetscErrorCode PCRegisterILUBAIJ(void)
{
  PetscFunctionBeginUser;
  PetscCall(PCRegister("ilubaij", PCCreate_ILUBAIJ));
  PetscFunctionReturn(0);
}
