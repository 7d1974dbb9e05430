/* One rank's assembly of element matrices straight into the AIJ matrix's values, through a
   map from each element entry to its place in the compressed rows, made once with the
   pattern. MatSetValuesCOO gathers every nonzero's contributions through a permutation of
   the whole entry array, a random read of the entries (on tube3d level 4, 63 million of
   them, 0.5 GB), and keeps that permutation beside the matrix; here each block's entries
   are added where they belong as they come, in element order, so the writes stay in a band
   of rows a mesh in reverse Cuthill-McKee order keeps in cache. Matrices across ranks keep
   MatSetValuesCOO, which also moves the entries of rows another rank owns. */
#include "fem_ceed.h"

typedef struct {
  PetscInt *map; /* per entry of the pattern, its index in the values, -1: dropped */
  PetscInt  nz;  /* the matrix's nonzeros */
} Direct;

/* a block's run of entries, added where they belong */
typedef struct {
  const PetscInt *map; /* the block's part of Direct's */
  PetscScalar    *a;   /* the matrix's values */
} Target;

static PetscErrorCode DirectDestroy(void *ctx)
{
  Direct *d = (Direct *)ctx;

  PetscFunctionBeginUser;
  PetscCall(PetscFree(d->map));
  PetscCall(PetscFree(d));
  PetscFunctionReturn(0);
}

static PetscErrorCode DirectGet(Mat A, Direct **d)
{
  PetscContainer container;

  PetscFunctionBeginUser;
  *d = NULL;
  PetscCall(PetscObjectQuery((PetscObject)A, "fsiopt_direct_assembly", (PetscObject *)&container));
  if (container) PetscCall(PetscContainerGetPointer(container, (void **)d));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedDirectSetUp(Mat A, PetscCount total, const PetscInt rows[], const PetscInt cols[],
                                  PetscBool *done)
{
  PetscMPIInt    size;
  PetscInt       m, *ia, *ja, *fill;
  Direct        *d;
  PetscContainer container;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(PetscObjectComm((PetscObject)A), &size));
  *done = (PetscBool)(size == 1);
  if (!*done) PetscFunctionReturn(0);
  PetscCheck(total < PETSC_MAX_INT, PETSC_COMM_SELF, PETSC_ERR_SUP,
             "direct assembly: %" PetscCount_FMT " entries do not fit a PetscInt", total);
  PetscCall(MatGetLocalSize(A, &m, NULL));
  /* the entries by row (a counting sort), then each row's columns sorted and unique */
  PetscCall(PetscCalloc1(m + 1, &ia));
  for (PetscCount k = 0; k < total; ++k)
    if (rows[k] >= 0 && cols[k] >= 0) ia[rows[k] + 1]++;
  for (PetscInt r = 0; r < m; ++r) ia[r + 1] += ia[r];
  PetscCall(PetscMalloc1(ia[m], &ja));
  PetscCall(PetscMalloc1(m, &fill));
  PetscCall(PetscArraycpy(fill, ia, m));
  for (PetscCount k = 0; k < total; ++k)
    if (rows[k] >= 0 && cols[k] >= 0) ja[fill[rows[k]]++] = cols[k];
  { /* compacted in place: row r's start is read before it is overwritten */
    PetscInt at = 0;
    for (PetscInt r = 0; r < m; ++r) {
      PetscInt n = ia[r + 1] - ia[r];
      PetscCall(PetscSortRemoveDupsInt(&n, ja + ia[r]));
      PetscCall(PetscArraymove(ja + at, ja + ia[r], n));
      ia[r] = at;
      at += n;
    }
    ia[m] = at;
  }
  PetscCall(PetscFree(fill));
  PetscCall(PetscNew(&d));
  d->nz = ia[m];
  PetscCall(PetscMalloc1(total, &d->map));
  for (PetscCount k = 0; k < total; ++k) {
    PetscInt at = -1;
    if (rows[k] >= 0 && cols[k] >= 0) {
      PetscCall(PetscFindInt(cols[k], ia[rows[k] + 1] - ia[rows[k]], ja + ia[rows[k]], &at));
      at += ia[rows[k]];
    }
    d->map[k] = at;
  }
  PetscCall(MatSeqAIJSetPreallocationCSR(A, ia, ja, NULL));
  PetscCall(PetscFree(ia));
  PetscCall(PetscFree(ja));
  PetscCall(PetscContainerCreate(PETSC_COMM_SELF, &container));
  PetscCall(PetscContainerSetPointer(container, d));
  PetscCall(PetscContainerSetUserDestroy(container, DirectDestroy));
  PetscCall(PetscObjectCompose((PetscObject)A, "fsiopt_direct_assembly", (PetscObject)container));
  PetscCall(PetscContainerDestroy(&container));
  PetscFunctionReturn(0);
}

static PetscErrorCode AddValues(void *ctx, CeedSize offset, CeedSize n, const CeedScalar *values)
{
  const Target   *t   = (const Target *)ctx;
  const PetscInt *map = t->map + offset;
  PetscScalar    *a   = t->a;

  PetscFunctionBeginUser;
  for (CeedSize k = 0; k < n; ++k)
    if (map[k] >= 0) a[map[k]] += values[k];
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedDirectAssemble(Ceed ceed, PetscInt n, const CeedOperator ops[], const FEMCeedBlockValues custom[],
                                     const CeedSize counts[], Mat A, PetscBool *done)
{
  Direct      *d;
  PetscScalar *a;
  CeedSize     at = 0;

  PetscFunctionBeginUser;
  PetscCall(DirectGet(A, &d));
  *done = (PetscBool)(d != NULL);
  if (!d) PetscFunctionReturn(0);
  PetscCall(MatSeqAIJGetArrayWrite(A, &a));
  PetscCall(PetscArrayzero(a, d->nz));
  for (PetscInt b = 0; b < n; ++b) {
    Target                  target = {d->map + at, a};
    const FEMCeedValuesSink sink   = {AddValues, &target};

    at += counts[b];
    if (!ops[b]) continue; /* a block with no values in this assembly: its zeros stand */
    if (custom && custom[b].values) PetscCall(custom[b].values(custom[b].ctx, sink));
    else PetscCall(FEMCeedElementMatrices(ceed, ops[b], sink));
  }
  PetscCall(MatSeqAIJRestoreArrayWrite(A, &a));
  PetscFunctionReturn(0);
}
