/* Assembly of libCEED operators into PETSc matrices (fem_ceed.h): the pattern of every
   operator's entries once, their values per assembly; by COO across ranks, on one rank
   straight into the matrix (ceed_assembly_direct.c). A mixed Jacobian is one
   operator per block: libCEED assembles an operator with one active input and one active
   output restriction. */
#include "fem_ceed.h"
#include "fem.h"

/* A bare AIJ matrix of dm's global size: MatSetPreallocationCOO on DMCreateMatrix's would
   leak its variable block sizes (PETSc 3.18, valgrind) */
PetscErrorCode FEMCeedCreateCOOMatrix(DM dm, Mat *A)
{
  Vec      global;
  PetscInt n, N;

  PetscFunctionBeginUser;
  PetscCall(DMGetGlobalVector(dm, &global));
  PetscCall(VecGetLocalSize(global, &n));
  PetscCall(VecGetSize(global, &N));
  PetscCall(DMRestoreGlobalVector(dm, &global));
  PetscCall(MatCreate(PetscObjectComm((PetscObject)dm), A));
  PetscCall(MatSetSizes(*A, n, n, N, N));
  PetscCall(MatSetType(*A, MATAIJ));
  PetscFunctionReturn(0);
}

/* the count of the DM's extra entries at the end of a matrix's COO pattern, kept with it */
static PetscErrorCode ExtraCount(Mat A, PetscBool set, PetscInt *n)
{
  PetscContainer container;
  PetscInt      *count;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectQuery((PetscObject)A, "fsiopt_coo_extra", (PetscObject *)&container));
  if (!container && !set) {
    *n = 0;
    PetscFunctionReturn(0);
  }
  if (!container) {
    PetscCall(PetscNew(&count));
    PetscCall(PetscContainerCreate(PETSC_COMM_SELF, &container));
    PetscCall(PetscContainerSetPointer(container, count));
    PetscCall(PetscContainerSetUserDestroy(container, PetscContainerUserDestroyDefault));
    PetscCall(PetscObjectCompose((PetscObject)A, "fsiopt_coo_extra", (PetscObject)container));
    PetscCall(PetscContainerDestroy(&container));
  } else PetscCall(PetscContainerGetPointer(container, (void **)&count));
  if (set) *count = *n;
  else *n = *count;
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedAssemblySetUp(Ceed ceed, DM dm, PetscInt n, const CeedOperator ops[], Mat A, CeedSize counts[])
{
  CeedSize               total = 0;
  PetscInt              *rows, *cols;
  ISLocalToGlobalMapping ltog;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(1, &rows));
  PetscCall(PetscMalloc1(1, &cols));
  for (PetscInt b = 0; b < n; ++b) {
    CeedInt *r, *c;
    counts[b] = 0;
    if (!ops[b]) continue;
    PetscCall(FEMCeedElementPattern(ceed, ops[b], &counts[b], &r, &c));
    /* a rank without any of these elements keeps its arrays: MPI refuses NULL buffers in the
       collective MatSetPreallocationCOO (seen on 3 ranks, a rank without a face set) */
    if (counts[b]) {
      PetscCall(PetscRealloc(sizeof(PetscInt) * (total + counts[b]), &rows));
      PetscCall(PetscRealloc(sizeof(PetscInt) * (total + counts[b]), &cols));
    }
    for (CeedSize i = 0; i < counts[b]; ++i) {
      rows[total + i] = r[i];
      cols[total + i] = c[i];
    }
    total += counts[b];
    PetscCall(PetscFree2(r, c));
  }
  /* local (L-vector) rows and columns, numbered globally; constrained ones become negative
     and MatSetValuesCOO drops them */
  PetscCall(DMGetLocalToGlobalMapping(dm, &ltog));
  PetscCall(ISLocalToGlobalMappingApply(ltog, (PetscInt)total, rows, rows));
  PetscCall(ISLocalToGlobalMappingApply(ltog, (PetscInt)total, cols, cols));
  { /* and the DM's entries beyond the stencil (global already), zero at each assembly */
    const PetscInt *extra_rows, *extra_cols;
    PetscInt        nextra;
    PetscCall(FEMGetExtraPattern(dm, &nextra, &extra_rows, &extra_cols));
    if (nextra) {
      PetscCall(PetscRealloc(sizeof(PetscInt) * (total + nextra), &rows));
      PetscCall(PetscRealloc(sizeof(PetscInt) * (total + nextra), &cols));
      PetscCall(PetscArraycpy(rows + total, extra_rows, nextra));
      PetscCall(PetscArraycpy(cols + total, extra_cols, nextra));
      total += nextra;
    }
    if (nextra) PetscCall(ExtraCount(A, PETSC_TRUE, &nextra));
  }
  {
    PetscBool direct;
    PetscCall(FEMCeedDirectSetUp(A, (PetscCount)total, rows, cols, &direct));
    if (!direct) PetscCall(MatSetPreallocationCOO(A, (PetscCount)total, rows, cols));
  }
  PetscCall(PetscFree(rows));
  PetscCall(PetscFree(cols));
  PetscFunctionReturn(0);
}

/* The values array of A's COO pattern, kept with A: a Jacobian of tube3d level 2 has 12
   million entries, and a fresh array at each assembly costs its page faults again */
static PetscErrorCode COOValues(Mat A, CeedSize total, PetscScalar **values)
{
  PetscContainer container;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectQuery((PetscObject)A, "fsiopt_coo_values", (PetscObject *)&container));
  if (!container) {
    PetscScalar *array;
    PetscCall(PetscMalloc1(total, &array));
    PetscCall(PetscContainerCreate(PetscObjectComm((PetscObject)A), &container));
    PetscCall(PetscContainerSetPointer(container, array));
    PetscCall(PetscContainerSetUserDestroy(container, PetscContainerUserDestroyDefault));
    PetscCall(PetscObjectCompose((PetscObject)A, "fsiopt_coo_values", (PetscObject)container));
    PetscCall(PetscContainerDestroy(&container));
    PetscCall(PetscObjectQuery((PetscObject)A, "fsiopt_coo_values", (PetscObject *)&container));
  }
  PetscCall(PetscContainerGetPointer(container, (void **)values));
  PetscFunctionReturn(0);
}

/* a block's run of entries copied to its place in the COO values */
static PetscErrorCode CopyValues(void *ctx, CeedSize offset, CeedSize n, const CeedScalar *values)
{
  PetscFunctionBeginUser;
  PetscCall(PetscArraycpy((PetscScalar *)ctx + offset, values, n));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedAssemble(Ceed ceed, PetscInt n, const CeedOperator ops[], const CeedSize counts[], Mat A)
{
  PetscFunctionBeginUser;
  PetscCall(FEMCeedAssembleBlocks(ceed, n, ops, NULL, counts, A));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedAssembleBlocks(Ceed ceed, PetscInt n, const CeedOperator ops[], const FEMCeedBlockValues custom[],
                                     const CeedSize counts[], Mat A)
{
  PetscScalar *values;
  CeedSize     total = 0, at = 0;
  PetscInt     nextra;
  PetscBool    direct;

  PetscFunctionBeginUser;
  PetscCall(FEMCeedDirectAssemble(ceed, n, ops, custom, counts, A, &direct));
  if (direct) PetscFunctionReturn(0);
  for (PetscInt b = 0; b < n; ++b) total += counts[b];
  PetscCall(ExtraCount(A, PETSC_FALSE, &nextra));
  PetscCall(COOValues(A, total + nextra, &values));
  PetscCall(PetscArrayzero(values + total, nextra));
  for (PetscInt b = 0; b < n; ++b) {
    const FEMCeedValuesSink sink = {CopyValues, values + at};
    /* a block of the pattern with no values in this assembly gets zeros */
    if (ops[b] && custom && custom[b].values) PetscCall(custom[b].values(custom[b].ctx, sink));
    else if (ops[b]) PetscCall(FEMCeedElementMatrices(ceed, ops[b], sink));
    else PetscCall(PetscArrayzero(values + at, counts[b]));
    at += counts[b];
  }
  PetscCall(MatSetValuesCOO(A, values, INSERT_VALUES));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedCopyMatrix(Mat A, Mat B)
{
  PetscFunctionBeginUser;
  PetscCall(MatCopy(A, B, SAME_NONZERO_PATTERN));
  PetscCall(MatAssemblyBegin(B, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(B, MAT_FINAL_ASSEMBLY));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedApply(Ceed ceed, PetscInt n, const CeedOperator ops[], CeedVector x, CeedVector y, Vec xlocal,
                            Vec ylocal)
{
  PetscScalar *xa, *ya;

  PetscFunctionBeginUser;
  PetscCall(VecGetArray(xlocal, &xa));
  PetscCall(VecGetArray(ylocal, &ya));
  PetscCallCeed(ceed, CeedVectorSetArray(x, CEED_MEM_HOST, CEED_USE_POINTER, xa));
  PetscCallCeed(ceed, CeedVectorSetArray(y, CEED_MEM_HOST, CEED_USE_POINTER, ya));
  PetscCallCeed(ceed, CeedOperatorApply(ops[0], x, y, CEED_REQUEST_IMMEDIATE));
  for (PetscInt k = 1; k < n; ++k) PetscCallCeed(ceed, CeedOperatorApplyAdd(ops[k], x, y, CEED_REQUEST_IMMEDIATE));
  PetscCallCeed(ceed, CeedVectorTakeArray(x, CEED_MEM_HOST, &xa));
  PetscCallCeed(ceed, CeedVectorTakeArray(y, CEED_MEM_HOST, &ya));
  PetscCall(VecRestoreArray(xlocal, &xa));
  PetscCall(VecRestoreArray(ylocal, &ya));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedVectorCopyFrom(Ceed ceed, CeedVector target, Vec source)
{
  const PetscScalar *a;

  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(source, &a));
  PetscCallCeed(ceed, CeedVectorSetArray(target, CEED_MEM_HOST, CEED_COPY_VALUES, (CeedScalar *)a));
  PetscCall(VecRestoreArrayRead(source, &a));
  PetscFunctionReturn(0);
}
