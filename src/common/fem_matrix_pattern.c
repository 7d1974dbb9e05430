/* Entries beyond the weak form's stencil that every Jacobian of a DM must hold (fem.h): a
   0D outlet's dense block couples every velocity node of its face set. Kept with the DM, so
   that whichever backend makes the matrix puts them in its pattern: libCEED's COO pattern
   (ceed_assembly.c) is fixed once made, and an entry outside it cannot be added later.
   And the other way round: the part of a vector operator that couples each component with
   itself, without the zero couplings between components its pattern holds. */
#include "fem.h"

typedef struct {
  PetscInt  n;
  PetscInt *rows, *cols;
} ExtraPattern;

static PetscErrorCode ExtraPatternDestroy(void *ctx)
{
  ExtraPattern *p = (ExtraPattern *)ctx;

  PetscFunctionBeginUser;
  PetscCall(PetscFree2(p->rows, p->cols));
  PetscCall(PetscFree(p));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMAddExtraPattern(DM dm, PetscInt n, const PetscInt rows[], const PetscInt cols[])
{
  PetscContainer container;
  ExtraPattern  *p;
  PetscInt      *r, *c, old = 0;
  const PetscInt *old_rows = NULL, *old_cols = NULL;

  PetscFunctionBeginUser;
  PetscCall(FEMGetExtraPattern(dm, &old, &old_rows, &old_cols));
  PetscCall(PetscMalloc2(old + n, &r, old + n, &c));
  PetscCall(PetscArraycpy(r, old_rows, old));
  PetscCall(PetscArraycpy(c, old_cols, old));
  PetscCall(PetscArraycpy(r + old, rows, n));
  PetscCall(PetscArraycpy(c + old, cols, n));
  PetscCall(PetscNew(&p));
  p->n    = old + n;
  p->rows = r;
  p->cols = c;
  PetscCall(PetscContainerCreate(PETSC_COMM_SELF, &container));
  PetscCall(PetscContainerSetPointer(container, p));
  PetscCall(PetscContainerSetUserDestroy(container, ExtraPatternDestroy));
  PetscCall(PetscObjectCompose((PetscObject)dm, "fsiopt_extra_pattern", (PetscObject)container));
  PetscCall(PetscContainerDestroy(&container));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMGetExtraPattern(DM dm, PetscInt *n, const PetscInt **rows, const PetscInt **cols)
{
  PetscContainer container;
  ExtraPattern  *p;

  PetscFunctionBeginUser;
  *n = 0;
  if (rows) *rows = NULL;
  if (cols) *cols = NULL;
  PetscCall(PetscObjectQuery((PetscObject)dm, "fsiopt_extra_pattern", (PetscObject *)&container));
  if (!container) PetscFunctionReturn(0);
  PetscCall(PetscContainerGetPointer(container, (void **)&p));
  *n = p->n;
  if (rows) *rows = p->rows;
  if (cols) *cols = p->cols;
  PetscFunctionReturn(0);
}

/* The couplings of each component with itself, of a matrix whose dofs come in groups of
   bs components (a vector field on vertices). A vector Laplacian assembled on the vector
   field's pattern stores the couplings between components, all zero: two thirds of its
   entries in 3D, which every product and every multigrid level would read. The pattern is
   the rule's, not the values', so a B in hand keeps it (and a factorization of it its
   symbolic part): MAT_REUSE_MATRIX refills its values. */
PetscErrorCode FEMMatrixSameComponentPart(Mat A, PetscInt bs, MatReuse reuse, Mat *B)
{
  PetscInt     rstart, rend, cstart, cend, m, n, M, N, *d_nnz = NULL, *o_nnz = NULL, *keep_cols, max_row = 0;
  PetscScalar *keep_values;
  PetscBool    set, flag;

  PetscFunctionBeginUser;
  PetscCall(MatGetOwnershipRange(A, &rstart, &rend));
  PetscCall(MatGetOwnershipRangeColumn(A, &cstart, &cend));
  if (reuse == MAT_INITIAL_MATRIX) PetscCall(PetscCalloc2(rend - rstart, &d_nnz, rend - rstart, &o_nnz));
  for (PetscInt r = rstart; r < rend; ++r) {
    PetscInt        nc;
    const PetscInt *cols;
    PetscCall(MatGetRow(A, r, &nc, &cols, NULL));
    max_row = PetscMax(max_row, nc);
    if (reuse == MAT_INITIAL_MATRIX)
      for (PetscInt k = 0; k < nc; ++k) {
        if (cols[k] % bs != r % bs) continue;
        if (cols[k] >= cstart && cols[k] < cend) d_nnz[r - rstart]++;
        else o_nnz[r - rstart]++;
      }
    PetscCall(MatRestoreRow(A, r, &nc, &cols, NULL));
  }
  if (reuse == MAT_INITIAL_MATRIX) {
    PetscCall(MatGetLocalSize(A, &m, &n));
    PetscCall(MatGetSize(A, &M, &N));
    PetscCall(MatCreate(PetscObjectComm((PetscObject)A), B));
    PetscCall(MatSetSizes(*B, m, n, M, N));
    PetscCall(MatSetBlockSizesFromMats(*B, A, A));
    PetscCall(MatSetType(*B, MATAIJ));
    PetscCall(MatSeqAIJSetPreallocation(*B, 0, d_nnz));
    PetscCall(MatMPIAIJSetPreallocation(*B, 0, d_nnz, 0, o_nnz));
    PetscCall(PetscFree2(d_nnz, o_nnz));
  }
  PetscCall(PetscMalloc2(max_row, &keep_cols, max_row, &keep_values));
  for (PetscInt r = rstart; r < rend; ++r) {
    PetscInt           nc, kept = 0;
    const PetscInt    *cols;
    const PetscScalar *values;
    PetscCall(MatGetRow(A, r, &nc, &cols, &values));
    for (PetscInt k = 0; k < nc; ++k) {
      if (cols[k] % bs != r % bs) continue;
      keep_cols[kept]     = cols[k];
      keep_values[kept++] = values[k];
    }
    PetscCall(MatSetValues(*B, 1, &r, kept, keep_cols, keep_values, INSERT_VALUES));
    PetscCall(MatRestoreRow(A, r, &nc, &cols, &values));
  }
  PetscCall(PetscFree2(keep_cols, keep_values));
  PetscCall(MatAssemblyBegin(*B, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(*B, MAT_FINAL_ASSEMBLY));
  PetscCall(MatIsSymmetricKnown(A, &set, &flag));
  if (set) PetscCall(MatSetOption(*B, MAT_SYMMETRIC, flag));
  PetscFunctionReturn(0);
}
