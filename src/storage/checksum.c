/* The checksums of a checkpoint file (checksum.h): computed from the values written and
   stored in the file's table, recomputed from the values read at a restart. A bit flipped on
   disk in a state vector or a step number would otherwise be read as a valid state and the
   run would go on silently wrong. */
#include "checksum.h"
#include "logging.h"
#include <inttypes.h>
#include <stdio.h>
#include <string.h>

/* splitmix64's finalizer: xor-shifts and odd multipliers, each invertible, so the whole is a
   bijection of 64-bit words that spreads a one-bit change over the word */
static uint64_t Finalize(uint64_t z)
{
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

/* the index enters through an odd multiple of it, so that two values swapped change the sum;
   for one index the xor and Finalize are both one-to-one in the bits */
uint64_t ChecksumEntry(uint64_t index, uint64_t bits)
{
  return Finalize(bits ^ (index + 1) * 0x9e3779b97f4a7c15ULL);
}

uint64_t ChecksumInt(PetscInt value)
{
  /* as 64 bits: the same checksum from builds with 32- and 64-bit PetscInt */
  return ChecksumEntry(0, (uint64_t)(int64_t)value);
}

static uint64_t RealBits(PetscReal value)
{
  double   d = (double)value;
  uint64_t bits;

  memcpy(&bits, &d, sizeof(bits));
  return bits;
}

uint64_t ChecksumReal(PetscReal value)
{
  return ChecksumEntry(0, RealBits(value));
}

uint64_t ChecksumString(const char text[])
{
  uint64_t h = 0xcbf29ce484222325ULL; /* FNV-1a 64 */

  for (const unsigned char *c = (const unsigned char *)text; *c; ++c) h = (h ^ *c) * 0x100000001b3ULL;
  return ChecksumEntry(0, h);
}

PetscErrorCode ChecksumVecLocal(Vec v, uint64_t *local)
{
  const PetscScalar *a;
  PetscInt           lo, hi;

  PetscFunctionBeginUser;
  PetscCall(VecGetOwnershipRange(v, &lo, &hi));
  PetscCall(VecGetArrayRead(v, &a));
  *local = 0;
  /* unsigned: the sum wraps mod 2^64, in any order of the ranks' parts */
  for (PetscInt i = lo; i < hi; ++i) *local += ChecksumEntry((uint64_t)i, RealBits(PetscRealPart(a[i - lo])));
  PetscCall(VecRestoreArrayRead(v, &a));
  PetscFunctionReturn(0);
}

PetscErrorCode ChecksumVec(Vec v, uint64_t *sum)
{
  uint64_t local;

  PetscFunctionBeginUser;
  PetscCall(ChecksumVecLocal(v, &local));
  PetscCallMPI(MPI_Allreduce(&local, sum, 1, MPI_UINT64_T, MPI_SUM, PetscObjectComm((PetscObject)v)));
  PetscFunctionReturn(0);
}

typedef struct {
  char     item[PETSC_MAX_PATH_LEN + 64];
  uint64_t sum;
  int      replicated;
} Pending;

struct _p_ChecksumTable {
  char    *text; /* the kind's line, then one line per item */
  size_t   len, max;
  Pending *pending; /* added, not flushed */
  PetscInt npending, maxpending;
};

static PetscErrorCode Append(ChecksumTable t, const char text[], size_t n)
{
  PetscFunctionBeginUser;
  if (t->len + n + 1 > t->max) {
    char *more;
    t->max = PetscMax(2 * t->max, t->len + n + 1024);
    PetscCall(PetscMalloc1(t->max, &more));
    PetscCall(PetscArraycpy(more, t->text, t->len + 1));
    PetscCall(PetscFree(t->text));
    t->text = more;
  }
  PetscCall(PetscArraycpy(t->text + t->len, text, n));
  t->len += n;
  t->text[t->len] = 0;
  PetscFunctionReturn(0);
}

static PetscErrorCode Create(ChecksumTable *t)
{
  PetscFunctionBeginUser;
  PetscCall(PetscNew(t));
  PetscCall(PetscCalloc1(1, &(*t)->text));
  (*t)->max = 1;
  PetscFunctionReturn(0);
}

PetscErrorCode ChecksumTableCreate(ChecksumTable *t)
{
  PetscFunctionBeginUser;
  PetscCall(Create(t));
  PetscCall(Append(*t, CHECKSUM_KIND "\n", strlen(CHECKSUM_KIND) + 1));
  PetscFunctionReturn(0);
}

PetscErrorCode ChecksumTableDestroy(ChecksumTable *t)
{
  PetscFunctionBeginUser;
  if (!*t) PetscFunctionReturn(0);
  PetscCall(PetscFree((*t)->text));
  PetscCall(PetscFree((*t)->pending));
  PetscCall(PetscFree(*t));
  PetscFunctionReturn(0);
}

PetscErrorCode ChecksumTableAdd(ChecksumTable t, const char item[], uint64_t sum, PetscBool replicated)
{
  Pending *p;

  PetscFunctionBeginUser;
  if (t->npending == t->maxpending) {
    Pending *more;
    t->maxpending = PetscMax(2 * t->maxpending, 16);
    PetscCall(PetscMalloc1(t->maxpending, &more));
    PetscCall(PetscArraycpy(more, t->pending, t->npending));
    PetscCall(PetscFree(t->pending));
    t->pending = more;
  }
  p = &t->pending[t->npending++];
  PetscCall(PetscStrncpy(p->item, item, sizeof(p->item)));
  p->sum        = sum;
  p->replicated = replicated ? 1 : 0;
  PetscFunctionReturn(0);
}

PetscInt ChecksumTablePending(ChecksumTable t)
{
  return t->npending;
}

/* the pending items from `first` on, summed over comm, as lines (replacing text's) */
static PetscErrorCode Flush(ChecksumTable t, PetscInt first, MPI_Comm comm, ChecksumTable into)
{
  PetscMPIInt    rank;
  uint64_t      *sums;
  const PetscInt n = t->npending - first;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(PetscMalloc1(n + 1, &sums));
  /* an attribute's checksum is every rank's: counted once */
  for (PetscInt i = 0; i < n; ++i) sums[i] = t->pending[first + i].replicated && rank ? 0 : t->pending[first + i].sum;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sums, (PetscMPIInt)n, MPI_UINT64_T, MPI_SUM, comm));
  for (PetscInt i = 0; i < n; ++i) {
    char line[PETSC_MAX_PATH_LEN + 96];
    int  len = snprintf(line, sizeof(line), "%016" PRIx64 " %s\n", sums[i], t->pending[first + i].item);
    PetscCall(Append(into, line, (size_t)len));
  }
  t->npending = first;
  PetscCall(PetscFree(sums));
  PetscFunctionReturn(0);
}

PetscErrorCode ChecksumTableWritePart(ChecksumTable t, PetscViewer viewer, PetscInt first, PetscInt index)
{
  ChecksumTable part;
  char          name[32];

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_CHECKSUM, 0, 0, 0, 0));
  PetscCall(Create(&part));
  PetscCall(Flush(t, first, PetscObjectComm((PetscObject)viewer), part));
  PetscCall(PetscSNPrintf(name, sizeof(name), "checksums %" PetscInt_FMT, index));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", name, PETSC_STRING, part->text));
  PetscCall(ChecksumTableDestroy(&part));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_CHECKSUM, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode ChecksumTableWrite(ChecksumTable t, PetscViewer viewer)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_CHECKSUM, 0, 0, 0, 0));
  PetscCall(Flush(t, 0, PetscObjectComm((PetscObject)viewer), t));
  /* an attribute in the root's header holds at most 64 KiB (HDF5's default file format) */
  PetscCheck(t->len < 60000, PetscObjectComm((PetscObject)viewer), PETSC_ERR_SUP,
             "the checkpoint's table of checksums has %zu characters, more than an HDF5 attribute holds", t->len);
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "checksums", PETSC_STRING, t->text));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_CHECKSUM, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

static herr_t CountAttribute(hid_t object, const char *name, const H5A_info_t *info, void *count)
{
  (void)object, (void)name, (void)info;
  ++*(int *)count;
  return 0;
}

/* A fixed-length string attribute of the root, through HDF5 itself, quietly: PETSc's reader
   would stop with HDF5's diagnostic stack on an attribute damaged into another type. *text:
   NULL if absent; "" if not such a string. */
static PetscErrorCode ReadRootString(hid_t root, const char name[], char **text)
{
  hid_t  a, type;
  size_t size = 0;

  PetscFunctionBeginUser;
  *text = NULL;
  if (H5Aexists(root, name) <= 0) PetscFunctionReturn(0);
  a    = H5Aopen(root, name, H5P_DEFAULT);
  type = a >= 0 ? H5Aget_type(a) : -1;
  if (type >= 0 && H5Tget_class(type) == H5T_STRING && H5Tis_variable_str(type) == 0) size = H5Tget_size(type);
  PetscCall(PetscCalloc1(size + 1, text));
  if (size && H5Aread(a, type, *text) < 0) (*text)[0] = 0;
  if (type >= 0) H5Tclose(type);
  if (a >= 0) H5Aclose(a);
  PetscFunctionReturn(0);
}

PetscErrorCode ChecksumTableRead(PetscViewer viewer, const char path[], ChecksumTable *t)
{
  MPI_Comm    comm = PetscObjectComm((PetscObject)viewer);
  hid_t       file, root;
  H5E_auto2_t handler;
  void       *handler_data;
  int         attributes = 0;
  char       *text, *end, name[32];

  PetscFunctionBeginUser;
  *t = NULL;
  PetscCall(PetscViewerHDF5GetFileId(viewer, &file));
  H5Eget_auto2(H5E_DEFAULT, &handler, &handler_data);
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  root = H5Gopen2(file, "/", H5P_DEFAULT);
  if (root >= 0) {
    hsize_t at = 0;
    (void)H5Aiterate2(root, H5_INDEX_NAME, H5_ITER_NATIVE, &at, CountAttribute, &attributes);
  }
  PetscCall(ReadRootString(root, "checksums", &text));
  /* an older fsiopt wrote no attribute at the root: one there without the table is damage */
  PetscCheck(text || !attributes, comm, PETSC_ERR_FILE_UNEXPECTED,
             "option -restart %s: the file's root has attributes but not its table of checksums (attribute "
             "'checksums' of /): damaged",
             path);
  end = text ? strchr(text, '\n') : NULL;
  if (end) *end = 0;
  PetscCheck(!text || (end && !strcmp(text, CHECKSUM_KIND)), comm, PETSC_ERR_FILE_UNEXPECTED,
             "option -restart %s: its table of checksums (attribute 'checksums' of /) %s%s%s, this fsiopt checks '%s' "
             "(damaged, or written by another fsiopt)",
             path, end ? "is of kind '" : "is unreadable", end ? text : "", end ? "'" : "", CHECKSUM_KIND);
  if (text) {
    *end = '\n';
    PetscCall(Create(t));
    PetscCall(Append(*t, text, strlen(text)));
    /* the parts' tables, in order; one missing leaves its items without a checksum */
    for (PetscInt k = 1;; ++k) {
      PetscCall(PetscFree(text));
      PetscCall(PetscSNPrintf(name, sizeof(name), "checksums %" PetscInt_FMT, k));
      PetscCall(ReadRootString(root, name, &text));
      if (!text) break;
      PetscCall(Append(*t, text, strlen(text)));
    }
  }
  if (root >= 0) H5Gclose(root);
  H5Eset_auto2(H5E_DEFAULT, handler, handler_data);
  PetscFunctionReturn(0);
}

/* 16 hex digits */
static PetscBool ParseHex(const char text[], uint64_t *sum)
{
  *sum = 0;
  for (int k = 0; k < 16; ++k) {
    const char c     = text[k];
    const int  digit = c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10 : -1;
    if (digit < 0) return PETSC_FALSE;
    *sum = *sum << 4 | (uint64_t)digit;
  }
  return PETSC_TRUE;
}

PetscErrorCode ChecksumTableCheck(ChecksumTable t, MPI_Comm comm, const char path[], const char item[],
                                  uint64_t computed)
{
  const size_t n     = strlen(item);
  const char  *found = NULL;
  uint64_t     stored;

  PetscFunctionBeginUser;
  /* a line: 16 hex digits, a space, the item, the end of the line */
  for (const char *line = strchr(t->text, '\n'); line && !found; line = strchr(line + 1, '\n'))
    if (strlen(line + 1) >= 17 + n && line[17] == ' ' && !strncmp(line + 18, item, n) &&
        (line[18 + n] == '\n' || !line[18 + n]))
      found = line + 1;
  PetscCheck(found, comm, PETSC_ERR_FILE_UNEXPECTED,
             "option -restart %s: %s has no checksum in the file's table of checksums: damaged", path, item);
  PetscCheck(ParseHex(found, &stored), comm, PETSC_ERR_FILE_UNEXPECTED,
             "option -restart %s: the checksum of %s is not 16 hex digits: damaged", path, item);
  PetscCheck(stored == computed, comm, PETSC_ERR_FILE_UNEXPECTED,
             "option -restart %s: %s does not match its checksum (the file was damaged after it was written)", path,
             item);
  PetscFunctionReturn(0);
}

PetscErrorCode ChecksumItem(const char group[], const char name[], PetscBool dataset, char item[], size_t len)
{
  const PetscBool root = !group || !group[0] || !strcmp(group, "/") ? PETSC_TRUE : PETSC_FALSE;

  PetscFunctionBeginUser;
  if (dataset) PetscCall(PetscSNPrintf(item, len, "dataset %s/%s", root ? "" : group, name));
  else PetscCall(PetscSNPrintf(item, len, "attribute '%s' in %s", name, root ? "/" : group));
  PetscFunctionReturn(0);
}
