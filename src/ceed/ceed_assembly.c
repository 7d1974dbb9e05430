/* Assembly of libCEED operators into PETSc matrices by COO (fem_ceed.h): the pattern of
   every operator's entries once, their values per assembly. A mixed Jacobian is one
   operator per block: libCEED assembles an operator with one active input and one active
   output restriction. */
#include "fem_ceed.h"

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
    PetscCallCeed(ceed, CeedOperatorLinearAssembleSymbolic(ops[b], &counts[b], &r, &c));
    PetscCall(PetscRealloc(sizeof(PetscInt) * (total + counts[b]), &rows));
    PetscCall(PetscRealloc(sizeof(PetscInt) * (total + counts[b]), &cols));
    for (CeedSize i = 0; i < counts[b]; ++i) {
      rows[total + i] = r[i];
      cols[total + i] = c[i];
    }
    total += counts[b];
    free(r);
    free(c);
  }
  /* local (L-vector) rows and columns, numbered globally; constrained ones become negative
     and MatSetValuesCOO drops them */
  PetscCall(DMGetLocalToGlobalMapping(dm, &ltog));
  PetscCall(ISLocalToGlobalMappingApply(ltog, (PetscInt)total, rows, rows));
  PetscCall(ISLocalToGlobalMappingApply(ltog, (PetscInt)total, cols, cols));
  PetscCall(MatSetPreallocationCOO(A, (PetscCount)total, rows, cols));
  PetscCall(PetscFree(rows));
  PetscCall(PetscFree(cols));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedAssemble(Ceed ceed, PetscInt n, const CeedOperator ops[], const CeedSize counts[], Mat A)
{
  PetscScalar *values;
  CeedSize     total = 0, at = 0;

  PetscFunctionBeginUser;
  for (PetscInt b = 0; b < n; ++b) total += counts[b];
  PetscCall(PetscCalloc1(total, &values));
  for (PetscInt b = 0; b < n; ++b) {
    CeedVector block;
    if (!ops[b]) { /* a block of the pattern with no values in this assembly: zeros */
      at += counts[b];
      continue;
    }
    PetscCallCeed(ceed, CeedVectorCreate(ceed, counts[b], &block));
    PetscCallCeed(ceed, CeedVectorSetArray(block, CEED_MEM_HOST, CEED_USE_POINTER, values + at));
    PetscCallCeed(ceed, CeedOperatorLinearAssemble(ops[b], block));
    PetscCallCeed(ceed, CeedVectorTakeArray(block, CEED_MEM_HOST, NULL));
    PetscCallCeed(ceed, CeedVectorDestroy(&block));
    at += counts[b];
  }
  PetscCall(MatSetValuesCOO(A, values, INSERT_VALUES));
  PetscCall(PetscFree(values));
  PetscFunctionReturn(0);
}
