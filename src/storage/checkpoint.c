/* Reading and writing the pieces of a checkpoint, to an HDF5 file or to memory; what goes
   in it is each module's (FluidCheckpoint, StructureCheckpoint, CouplingCheckpoint,
   ProbesCheckpoint). */
#include "checkpoint.h"
#include "checksum.h"
#include "logging.h"
#include "output_files.h"
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>
#include "options.h"
#include "error_reporting.h"

typedef struct {
  char      name[128]; /* group/name */
  Vec       vec;       /* NULL for a number */
  PetscInt  integer;
  PetscReal real;
} MemoryEntry;

struct _p_Checkpoint {
  PetscViewer   viewer; /* NULL: in memory, or in a part this rank does not hold */
  PetscBool     file, load;
  MPI_Comm      comm;                          /* a file's: the ranks that open it */
  char          open_name[PETSC_MAX_PATH_LEN]; /* the file open: path, or its temporary while written */
  PetscBool     in_part;                       /* between CheckpointBeginPart and CheckpointEndPart */
  ChecksumTable checksums; /* a file's (NULL: one an fsiopt without checksums wrote, read unchecked) */
  PetscInt      parts;     /* parts begun, and where the part in progress's checksums begin */
  PetscInt      part_first;
  char          path[PETSC_MAX_PATH_LEN];
  char          group[64];
  MemoryEntry  *entries;
  PetscInt      n, max;
};

PetscBool CheckpointResynchronizes(Checkpoint cp, PetscBool load)
{
  return load || cp->file ? PETSC_TRUE : PETSC_FALSE;
}

PetscBool CheckpointIsFile(Checkpoint cp)
{
  return cp->file;
}

PetscBool CheckpointHasChecksums(Checkpoint cp)
{
  return cp->checksums ? PETSC_TRUE : PETSC_FALSE;
}

PetscErrorCode CheckpointHasGroup(Checkpoint cp, const char group[], PetscBool *has)
{
  PetscFunctionBeginUser;
  *has = PETSC_FALSE;
  if (cp->viewer) PetscCall(PetscViewerHDF5HasGroup(cp->viewer, group, has));
  PetscFunctionReturn(0);
}

PetscErrorCode CheckpointCreateInMemory(Checkpoint *cp)
{
  PetscFunctionBeginUser;
  PetscCall(PetscNew(cp));
  PetscFunctionReturn(0);
}

PetscErrorCode CheckpointDestroy(Checkpoint *cp)
{
  PetscFunctionBeginUser;
  if (!*cp) PetscFunctionReturn(0);
  for (PetscInt i = 0; i < (*cp)->n; ++i) PetscCall(VecDestroy(&(*cp)->entries[i].vec));
  PetscCall(PetscFree((*cp)->entries));
  PetscCall(PetscViewerDestroy(&(*cp)->viewer));
  PetscCall(ChecksumTableDestroy(&(*cp)->checksums));
  PetscCall(PetscFree(*cp));
  PetscFunctionReturn(0);
}

PetscErrorCode CheckpointPushGroup(Checkpoint cp, const char group[])
{
  PetscFunctionBeginUser;
  if (cp->viewer) PetscCall(PetscViewerHDF5PushGroup(cp->viewer, group));
  PetscCall(PetscStrncpy(cp->group, group, sizeof(cp->group))); /* a file's, for a part's reopening */
  PetscFunctionReturn(0);
}

PetscErrorCode CheckpointPopGroup(Checkpoint cp)
{
  PetscFunctionBeginUser;
  if (cp->viewer) PetscCall(PetscViewerHDF5PopGroup(cp->viewer));
  cp->group[0] = 0;
  PetscFunctionReturn(0);
}

/* The memory entry of `name` in the current group (its full name in full), or NULL. */
static PetscErrorCode MemoryEntryFind(Checkpoint cp, const char name[], char full[128], MemoryEntry **entry)
{
  PetscFunctionBeginUser;
  *entry = NULL;
  PetscCall(PetscSNPrintf(full, 128, "%s/%s", cp->group, name));
  for (PetscInt i = 0; i < cp->n && !*entry; ++i) {
    PetscBool same;
    PetscCall(PetscStrcmp(cp->entries[i].name, full, &same));
    if (same) *entry = &cp->entries[i];
  }
  PetscFunctionReturn(0);
}

/* The memory entry of `name` in the current group; a save creates it, a load must find it. */
static PetscErrorCode MemoryEntryGet(Checkpoint cp, const char name[], PetscBool load, MemoryEntry **entry)
{
  char full[128];

  PetscFunctionBeginUser;
  PetscCall(MemoryEntryFind(cp, name, full, entry));
  if (*entry) PetscFunctionReturn(0);
  PetscCheck(!load, PETSC_COMM_SELF, PETSC_ERR_PLIB, "the in-memory state has no '%s'", full);
  if (cp->n == cp->max) {
    MemoryEntry *more;
    cp->max = PetscMax(2 * cp->max, 16);
    PetscCall(PetscCalloc1(cp->max, &more));
    PetscCall(PetscArraycpy(more, cp->entries, cp->n));
    PetscCall(PetscFree(cp->entries));
    cp->entries = more;
  }
  *entry = &cp->entries[cp->n++];
  PetscCall(PetscStrncpy((*entry)->name, full, sizeof((*entry)->name)));
  PetscFunctionReturn(0);
}

static PetscErrorCode MemoryVec(Checkpoint cp, const char name[], Vec v, PetscBool load)
{
  MemoryEntry *e;

  PetscFunctionBeginUser;
  PetscCall(MemoryEntryGet(cp, name, load, &e));
  if (load) PetscCall(VecCopy(e->vec, v));
  else {
    if (!e->vec) PetscCall(VecDuplicate(v, &e->vec));
    PetscCall(VecCopy(v, e->vec));
  }
  PetscFunctionReturn(0);
}

/* Through a plain vector of the same layout: a vector with a DMPlex would go to the
   DM's own HDF5 layout (/fields, /vertex_fields), not this group. */
/* the number of values of dataset group/name (every dimension's extent multiplied) */
static PetscErrorCode DatasetSize(PetscViewer viewer, const char group[], const char name[], PetscInt *size)
{
  hid_t   file, dataset, space;
  hsize_t dims[8];
  int     ndims;
  char    full[PETSC_MAX_PATH_LEN];

  PetscFunctionBeginUser;
  PetscCall(PetscViewerHDF5GetFileId(viewer, &file));
  PetscCall(PetscSNPrintf(full, sizeof(full), "%s/%s", group, name));
  *size   = -1;
  dataset = H5Dopen2(file, full, H5P_DEFAULT);
  if (dataset < 0) PetscFunctionReturn(0);
  space = H5Dget_space(dataset);
  ndims = space >= 0 ? H5Sget_simple_extent_ndims(space) : -1;
  if (ndims >= 0 && ndims <= 8 && H5Sget_simple_extent_dims(space, dims, NULL) >= 0) {
    *size = 1;
    for (int d = 0; d < ndims; ++d) *size *= (PetscInt)dims[d];
  }
  if (space >= 0) H5Sclose(space);
  H5Dclose(dataset);
  PetscFunctionReturn(0);
}

/* What a damaged or foreign file holds where a value is expected: HDF5 converts an integer
   to a float silently and fails with its diagnostic stack on a string; a dataset of another
   shape would be read as if it were ours. `expected`: H5T_INTEGER, H5T_FLOAT (8 bytes) or
   H5T_STRING; an attribute holds one value, a dataset one dimension. */
static PetscErrorCode CheckStoredType(Checkpoint cp, const char name[], PetscBool attribute, H5T_class_t expected)
{
  static const char *const what[] = {"an integer",     "a float",
                                     "a time",         "a string",
                                     "a bit field",    "an opaque value",
                                     "a compound",     "a reference",
                                     "an enumeration", "a variable-length value",
                                     "an array"};
  hid_t                    file, object, type, space;
  H5T_class_t              stored = H5T_NO_CLASS;
  size_t                   size   = 0;
  int                      ndims  = -1;
  hssize_t                 points = -1;
  char                    *group;
  H5E_auto2_t              handler;
  void                    *handler_data;

  PetscFunctionBeginUser;
  PetscCall(PetscViewerHDF5GetFileId(cp->viewer, &file));
  PetscCall(PetscViewerHDF5GetGroup(cp->viewer, NULL, &group));
  H5Eget_auto2(H5E_DEFAULT, &handler, &handler_data);
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  object = attribute ? H5Aopen_by_name(file, group ? group : "/", name, H5P_DEFAULT, H5P_DEFAULT)
                     : H5Dopen2(file, name, H5P_DEFAULT);
  if (!attribute && object < 0) {
    char full[PETSC_MAX_PATH_LEN];
    PetscCall(PetscSNPrintf(full, sizeof(full), "%s/%s", group ? group : "", name));
    object = H5Dopen2(file, full, H5P_DEFAULT);
  }
  if (object >= 0) {
    type  = attribute ? H5Aget_type(object) : H5Dget_type(object);
    space = attribute ? H5Aget_space(object) : H5Dget_space(object);
    if (type >= 0) {
      stored = H5Tget_class(type);
      size   = H5Tget_size(type);
      H5Tclose(type);
    }
    if (space >= 0) {
      ndims  = H5Sget_simple_extent_ndims(space);
      points = H5Sget_simple_extent_npoints(space);
      H5Sclose(space);
    }
    if (attribute) H5Aclose(object);
    else H5Dclose(object);
  }
  H5Eset_auto2(H5E_DEFAULT, handler, handler_data);
  PetscCheck(stored == expected && (expected != H5T_FLOAT || size == 8), PetscObjectComm((PetscObject)cp->viewer),
             PETSC_ERR_FILE_UNEXPECTED,
             "option -restart %s: %s '%s' in %s holds %s%s, expected %s (damaged, or not an fsiopt checkpoint)",
             cp->path, attribute ? "attribute" : "dataset", name, group ? group : "/",
             stored >= 0 && stored < (H5T_class_t)(sizeof(what) / sizeof(*what)) ? what[stored] : "nothing readable",
             stored == H5T_FLOAT && size != 8 ? " of another precision" : "",
             expected == H5T_INTEGER ? "an integer"
             : expected == H5T_FLOAT ? "a float"
                                     : "a string");
  PetscCheck(attribute ? points == 1 : ndims == 1, PetscObjectComm((PetscObject)cp->viewer), PETSC_ERR_FILE_UNEXPECTED,
             "option -restart %s: %s '%s' in %s has %s, expected %s (damaged, or not an fsiopt checkpoint)", cp->path,
             attribute ? "attribute" : "dataset", name, group ? group : "/",
             attribute ? "more than one value" : "another shape", attribute ? "one" : "one dimension");
  PetscCall(PetscFree(group));
  PetscFunctionReturn(0);
}

/* A dataset's (of its vector v) or an attribute's checksum (sum): into the table of a file
   written, against it in a file read. */
static PetscErrorCode ItemChecksum(Checkpoint cp, const char name[], PetscBool dataset, Vec v, uint64_t sum,
                                   PetscBool load)
{
  char item[PETSC_MAX_PATH_LEN + 64];

  PetscFunctionBeginUser;
  if (!cp->checksums) PetscFunctionReturn(0);
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_CHECKSUM, 0, 0, 0, 0));
  PetscCall(ChecksumItem(cp->group, name, dataset, item, sizeof(item)));
  if (load) {
    /* at once, before the module's own checks of the values */
    if (dataset) PetscCall(ChecksumVec(v, &sum));
    PetscCall(ChecksumTableCheck(cp->checksums, PetscObjectComm((PetscObject)cp->viewer), cp->path, item, sum));
  } else {
    if (dataset) PetscCall(ChecksumVecLocal(v, &sum));
    PetscCall(ChecksumTableAdd(cp->checksums, item, sum, dataset ? PETSC_FALSE : PETSC_TRUE));
  }
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_CHECKSUM, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode CheckpointVec(Checkpoint cp, const char name[], Vec v, PetscBool load)
{
  PetscViewer viewer = cp->viewer;
  Vec         plain;
  PetscInt    n, N;

  PetscFunctionBeginUser;
  if (!viewer) {
    PetscCall(MemoryVec(cp, name, v, load));
    PetscFunctionReturn(0);
  }
  PetscCall(VecGetLocalSize(v, &n));
  PetscCall(VecGetSize(v, &N));
  PetscCall(VecCreateMPI(PetscObjectComm((PetscObject)v), n, N, &plain));
  PetscCall(PetscObjectSetName((PetscObject)plain, name));
  if (load) {
    PetscBool has;
    char     *group;
    PetscReal norm;
    PetscInt  stored;
    PetscCall(PetscViewerHDF5GetGroup(viewer, NULL, &group));
    PetscCall(PetscViewerHDF5HasObject(viewer, (PetscObject)plain, &has));
    PetscCheck(has, PetscObjectComm((PetscObject)v), PETSC_ERR_FILE_UNEXPECTED,
               "option -restart %s: the checkpoint has no dataset %s/%s (written by another scene or set-up, or "
               "damaged)",
               cp->path, group, name);
    PetscCall(CheckStoredType(cp, name, PETSC_FALSE, H5T_FLOAT));
    PetscCall(DatasetSize(viewer, group, name, &stored));
    PetscCheck(stored == N, PetscObjectComm((PetscObject)v), PETSC_ERR_FILE_UNEXPECTED,
               "option -restart %s: dataset %s/%s has %" PetscInt_FMT " values, this run's has %" PetscInt_FMT
               " (written by another set-up, or damaged)",
               cp->path, group, name, stored, N);
    PetscCall(VecLoad(plain, viewer));
    PetscCall(VecNorm(plain, NORM_INFINITY, &norm));
    PetscCheck(!PetscIsInfOrNanReal(norm), PetscObjectComm((PetscObject)v), PETSC_ERR_FILE_UNEXPECTED,
               "option -restart %s: dataset %s/%s holds NaN or Inf values (damaged, or written by a run that "
               "diverged)",
               cp->path, group, name);
    PetscCall(PetscFree(group));
    PetscCall(ItemChecksum(cp, name, PETSC_TRUE, plain, 0, load));
    PetscCall(VecCopy(plain, v));
  } else {
    PetscCall(VecCopy(v, plain));
    PetscCall(VecView(plain, viewer));
    PetscCall(ItemChecksum(cp, name, PETSC_TRUE, plain, 0, load));
  }
  PetscCall(VecDestroy(&plain));
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckpointAttribute(Checkpoint cp, const char name[], PetscDataType type, void *value,
                                          PetscBool load)
{
  PetscViewer viewer = cp->viewer;

  PetscFunctionBeginUser;
  if (!viewer) {
    MemoryEntry *e;
    PetscCall(MemoryEntryGet(cp, name, load, &e));
    if (type == PETSC_INT) {
      if (load) *(PetscInt *)value = e->integer;
      else e->integer = *(PetscInt *)value;
    } else {
      if (load) *(PetscReal *)value = e->real;
      else e->real = *(PetscReal *)value;
    }
  } else if (load) {
    PetscBool has;
    PetscCall(PetscViewerHDF5HasAttribute(viewer, NULL, name, &has));
    PetscCheck(has, PetscObjectComm((PetscObject)viewer), PETSC_ERR_FILE_UNEXPECTED,
               "option -restart %s: the checkpoint has no attribute '%s': not an fsiopt checkpoint of this set-up",
               cp->path, name);
    PetscCall(CheckStoredType(cp, name, PETSC_TRUE, type == PETSC_INT ? H5T_INTEGER : H5T_FLOAT));
    PetscCall(PetscViewerHDF5ReadAttribute(viewer, NULL, name, type, NULL, value));
  } else PetscCall(PetscViewerHDF5WriteAttribute(viewer, NULL, name, type, value));
  if (viewer) {
    const uint64_t sum = type == PETSC_INT ? ChecksumInt(*(PetscInt *)value) : ChecksumReal(*(PetscReal *)value);
    PetscCall(ItemChecksum(cp, name, PETSC_FALSE, NULL, sum, load));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode CheckpointHasAttribute(Checkpoint cp, const char name[], PetscBool *has)
{
  PetscFunctionBeginUser;
  *has = PETSC_FALSE;
  if (cp->viewer) PetscCall(PetscViewerHDF5HasAttribute(cp->viewer, NULL, name, has));
  else {
    char         full[128];
    MemoryEntry *e;
    PetscCall(MemoryEntryFind(cp, name, full, &e));
    *has = e ? PETSC_TRUE : PETSC_FALSE;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode CheckpointInt(Checkpoint cp, const char name[], PetscInt *value, PetscBool load)
{
  PetscFunctionBeginUser;
  PetscCall(CheckpointAttribute(cp, name, PETSC_INT, value, load));
  PetscFunctionReturn(0);
}

PetscErrorCode CheckpointReal(Checkpoint cp, const char name[], PetscReal *value, PetscBool load)
{
  PetscFunctionBeginUser;
  PetscCall(CheckpointAttribute(cp, name, PETSC_REAL, value, load));
  PetscFunctionReturn(0);
}

PetscErrorCode CheckpointString(Checkpoint cp, const char name[], char value[], size_t len, PetscBool load)
{
  PetscViewer viewer = cp->viewer;
  PetscBool   has;
  char       *read = NULL;

  PetscFunctionBeginUser;
  PetscCheck(viewer, PETSC_COMM_SELF, PETSC_ERR_SUP, "a checkpoint in memory keeps no strings ('%s')", name);
  if (!load) {
    PetscCall(PetscViewerHDF5WriteAttribute(viewer, NULL, name, PETSC_STRING, value));
    PetscCall(ItemChecksum(cp, name, PETSC_FALSE, NULL, ChecksumString(value), load));
    PetscFunctionReturn(0);
  }
  PetscCall(PetscViewerHDF5HasAttribute(viewer, NULL, name, &has));
  PetscCheck(has, PetscObjectComm((PetscObject)viewer), PETSC_ERR_FILE_UNEXPECTED,
             "option -restart: the checkpoint has no attribute '%s': not an fsiopt checkpoint of this set-up", name);
  PetscCall(CheckStoredType(cp, name, PETSC_TRUE, H5T_STRING));
  PetscCall(PetscViewerHDF5ReadAttribute(viewer, NULL, name, PETSC_STRING, NULL, &read));
  /* of the whole string read, before a cut to len */
  PetscCall(ItemChecksum(cp, name, PETSC_FALSE, NULL, ChecksumString(read), load));
  PetscCall(PetscStrncpy(value, read, len));
  PetscCall(PetscFree(read));
  PetscFunctionReturn(0);
}

PetscErrorCode CheckpointLocalVec(Checkpoint cp, const char name[], DM dm, Vec local, PetscBool load)
{
  Vec global;

  PetscFunctionBeginUser;
  if (!cp->viewer) {
    PetscCall(MemoryVec(cp, name, local, load));
    PetscFunctionReturn(0);
  }
  PetscCall(DMGetGlobalVector(dm, &global));
  if (!load) PetscCall(DMLocalToGlobal(dm, local, INSERT_VALUES, global));
  PetscCall(CheckpointVec(cp, name, global, load));
  if (load) PetscCall(DMGlobalToLocal(dm, global, INSERT_VALUES, local));
  PetscCall(DMRestoreGlobalVector(dm, &global));
  PetscFunctionReturn(0);
}

static PetscErrorCode TemporaryName(const char path[], char tmp[], size_t len)
{
  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(tmp, len, "%s.tmp", path));
  PetscFunctionReturn(0);
}

PetscErrorCode CheckpointOpen(MPI_Comm comm, const char path[], PetscBool load, Checkpoint *cp)
{
  char        tmp[PETSC_MAX_PATH_LEN] = "";
  PetscViewer   viewer;
  ChecksumTable checksums;

  PetscFunctionBeginUser;
  if (load) {
    PetscCall(OptionsCheckReadableFile(comm, "-restart", path));
    {
      PetscErrorCode ierr;
      /* HDF5 would print its own diagnostic stack for a file that is not HDF5 */
      H5E_auto2_t report;
      void       *report_data;
      H5Eget_auto2(H5E_DEFAULT, &report, &report_data);
      H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
      ierr = PetscViewerHDF5Open(comm, path, FILE_MODE_READ, &viewer);
      H5Eset_auto2(H5E_DEFAULT, report, report_data);
      if (ierr) {
        PetscCall(ErrorReportingForget());
        SETERRQ(comm, PETSC_ERR_FILE_UNEXPECTED,
                "option -restart %s: not an HDF5 file (truncated, or not a checkpoint)", path);
      }
    }
  } else {
    PetscCall(TemporaryName(path, tmp, sizeof(tmp)));
    /* a failing write (a full disk) is reported in one line by the caller, not by HDF5's
       own diagnostic stack */
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
    PetscCall(PetscViewerHDF5Open(comm, tmp, FILE_MODE_WRITE, &viewer));
    PetscCall(ChecksumTableCreate(&checksums));
  }
  if (load) PetscCall(ChecksumTableRead(viewer, path, &checksums));
  PetscCall(PetscNew(cp));
  (*cp)->viewer    = viewer;
  (*cp)->file      = PETSC_TRUE;
  (*cp)->load      = load;
  (*cp)->comm      = comm;
  (*cp)->checksums = checksums;
  PetscCall(PetscStrncpy((*cp)->path, path, sizeof((*cp)->path)));
  PetscCall(PetscStrncpy((*cp)->open_name, load ? path : tmp, sizeof((*cp)->open_name)));
  PetscFunctionReturn(0);
}

static PetscErrorCode Reopen(Checkpoint cp, MPI_Comm comm)
{
  PetscFunctionBeginUser;
  PetscCall(PetscViewerHDF5Open(comm, cp->open_name, cp->load ? FILE_MODE_READ : FILE_MODE_APPEND, &cp->viewer));
  if (cp->group[0]) PetscCall(PetscViewerHDF5PushGroup(cp->viewer, cp->group));
  PetscFunctionReturn(0);
}

PetscErrorCode CheckpointBeginPart(Checkpoint cp, MPI_Comm part)
{
  PetscMPIInt size, part_size = 0;

  PetscFunctionBeginUser;
  PetscCheck(!cp->in_part, PETSC_COMM_SELF, PETSC_ERR_ORDER, "checkpoint parts do not nest");
  if (!cp->file) PetscFunctionReturn(0);
  PetscCallMPI(MPI_Comm_size(cp->comm, &size));
  if (part != MPI_COMM_NULL) PetscCallMPI(MPI_Comm_size(part, &part_size));
  if (part_size == size) PetscFunctionReturn(0); /* every rank holds it */
  cp->in_part = PETSC_TRUE;
  ++cp->parts;
  if (cp->checksums && !cp->load) cp->part_first = ChecksumTablePending(cp->checksums);
  PetscCall(PetscViewerDestroy(&cp->viewer));
  PetscCallMPI(MPI_Barrier(cp->comm)); /* closed on every rank before it opens on some */
  if (part != MPI_COMM_NULL) PetscCall(Reopen(cp, part));
  PetscFunctionReturn(0);
}

PetscErrorCode CheckpointEndPart(Checkpoint cp, PetscErrorCode part_error)
{
  PetscErrorCode closing;

  PetscFunctionBeginUser;
  if (!cp->in_part) {
    PetscCall(part_error);
    PetscFunctionReturn(0);
  }
  cp->in_part = PETSC_FALSE;
  if (cp->checksums && !cp->load && cp->viewer) {
    /* the part's checksums, written by its ranks while they hold the file: shared with the
       others instead, they would cost collectives of every rank per part (once all its
       ranks have written it: one that failed would not join) */
    int failed = part_error != 0;
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &failed, 1, MPI_INT, MPI_MAX, PetscObjectComm((PetscObject)cp->viewer)));
    if (!failed) part_error = ChecksumTableWritePart(cp->checksums, cp->viewer, cp->part_first, cp->parts);
  }
  closing = PetscViewerDestroy(&cp->viewer);
  PetscCall(ErrorReportingAgree(cp->comm, part_error ? part_error : closing));
  PetscCall(Reopen(cp, cp->comm));
  PetscFunctionReturn(0);
}

PetscErrorCode CheckpointEnsureSpace(MPI_Comm comm, const char path[], double at_least, PetscBool *enough,
                                     double *free_bytes, double *needed)
{
  PetscMPIInt rank;
  double      sizes[2] = {0, 0};

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (!rank) {
    char           dir[PETSC_MAX_PATH_LEN];
    struct statvfs fs;
    struct stat    st;
    char          *slash;
    PetscCall(PetscStrncpy(dir, path, sizeof(dir)));
    slash = strrchr(dir, '/');
    if (slash) *slash = 0;
    else PetscCall(PetscStrncpy(dir, ".", sizeof(dir)));
    sizes[1] = at_least;
    if (stat(path, &st) == 0) sizes[1] = PetscMax(sizes[1], (double)st.st_size); /* the last one written */
    sizes[1] = 1.1 * sizes[1] + 65536;
    sizes[0] = statvfs(dir[0] ? dir : "/", &fs) == 0 ? (double)fs.f_bavail * (double)fs.f_frsize : 1e300;
  }
  PetscCallMPI(MPI_Bcast(sizes, 2, MPI_DOUBLE, 0, comm));
  *free_bytes = sizes[0];
  *needed     = sizes[1];
  *enough     = sizes[0] >= sizes[1] ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(0);
}

void CheckpointRemoveTemporary(const char path[])
{
  char tmp[PETSC_MAX_PATH_LEN];

  OutputHDF5WriteFailed();
  (void)snprintf(tmp, sizeof(tmp), "%s.tmp", path);
  (void)unlink(tmp); /* every rank: the ones that did not create it get ENOENT */
}

PetscErrorCode CheckpointClose(MPI_Comm comm, const char path[], PetscBool load, Checkpoint *cp)
{
  char        tmp[PETSC_MAX_PATH_LEN];
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  if (!load) PetscCall(ChecksumTableWrite((*cp)->checksums, (*cp)->viewer));
  PetscCall(CheckpointDestroy(cp));
  if (load) PetscFunctionReturn(0);
  PetscCall(TemporaryName(path, tmp, sizeof(tmp)));
  PetscCallMPI(MPI_Barrier(comm));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (!rank)
    PetscCheck(rename(tmp, path) == 0, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE,
               "option -checkpoint_file %s: cannot rename %s into place", path, tmp);
  PetscCallMPI(MPI_Barrier(comm));
  PetscFunctionReturn(0);
}
