/* The fields file opened (fields.h): new, or continued across a restart. A checkpoint
   records the steps the run's fields file holds, where the file is and which run wrote it.
   The restarted run's file starts as a copy of those steps from that file, so a step the
   interrupted run wrote after its last checkpoint is dropped and written once, by the
   restarted run; the copy is built under a temporary name and renamed, so a second
   interruption while it is built loses nothing. */
#include <sys/stat.h>
#include "fields_impl.h"
#include "options.h"
#include "error_reporting.h"
#include "output_files.h"

PetscErrorCode FieldWriterCheckpoint(FieldWriter w, Checkpoint cp, PetscBool load)
{
  PetscInt     n;
  PetscBool    has, ok = PETSC_TRUE;
  Vec          steps;
  PetscScalar *a;

  PetscFunctionBeginUser;
  if (!w || !CheckpointIsFile(cp)) PetscFunctionReturn(0); /* a retried step rewrites no field */
  n = w->nwritten;
  PetscCall(CheckpointPushGroup(cp, "/fields"));
  if (load) {
    PetscCall(CheckpointHasAttribute(cp, "written", &has));
    PetscCheck(has, w->comm, PETSC_ERR_ARG_INCOMP,
               "option -restart: the checkpoint was written without -write_fields, so there are no fields to "
               "continue (restart without -write_fields)");
  }
  PetscCall(CheckpointInt(cp, "written", &n, load));
  PetscCheck(n > 0 && n <= w->steps + 1, w->comm, PETSC_ERR_FILE_UNEXPECTED,
             "option -restart: the checkpoint lists %" PetscInt_FMT " written field steps for a run of %" PetscInt_FMT
             " steps",
             n, w->steps);
  PetscCall(CheckpointString(cp, "origin", load ? w->source_origin : w->origin, sizeof(w->origin), load));
  PetscCall(CheckpointString(cp, "file", load ? w->source : w->path, sizeof(w->path), load));
  PetscCall(VecCreateMPI(w->comm, w->rank ? 0 : n, PETSC_DETERMINE, &steps));
  if (!load) {
    PetscCall(VecGetArray(steps, &a));
    for (PetscInt i = 0; i < n && !w->rank; ++i) a[i] = (PetscScalar)w->written[i];
    PetscCall(VecRestoreArray(steps, &a));
  }
  PetscCall(CheckpointVec(cp, "steps", steps, load));
  PetscCall(CheckpointPopGroup(cp));
  if (load) {
    PetscCall(VecGetArray(steps, &a));
    for (PetscInt i = 0; i < n && !w->rank; ++i) {
      w->written[i] = (PetscInt)PetscRealPart(a[i]);
      if (w->written[i] < 0 || w->written[i] >= w->steps || (i && w->written[i] <= w->written[i - 1])) ok = PETSC_FALSE;
    }
    PetscCall(VecRestoreArray(steps, &a));
    PetscCallMPI(MPI_Bcast(&ok, 1, MPIU_BOOL, 0, w->comm));
    PetscCheck(ok, w->comm, PETSC_ERR_FILE_UNEXPECTED,
               "option -restart: the checkpoint's field steps are not increasing steps of this run");
    PetscCallMPI(MPI_Bcast(w->written, (PetscMPIInt)n, MPIU_INT, 0, w->comm));
    w->nwritten   = n;
    w->restarting = PETSC_TRUE;
  }
  PetscCall(VecDestroy(&steps));
  PetscFunctionReturn(0);
}

/* What the root found wrong with the continued run's fields file */
typedef enum {
  SOURCE_OK,
  SOURCE_MISSING,
  SOURCE_NOT_HDF5,
  SOURCE_OTHER_RUN,
  SOURCE_STEP_MISSING,
  SOURCE_OTHER_MESH,
  SOURCE_TEMPORARY
} SourceStatus;

static PetscErrorCode OpenQuietly(const char path[], PetscViewer *viewer, SourceStatus *status)
{
  PetscErrorCode ierr;
  H5E_auto2_t    report;
  void          *report_data;

  PetscFunctionBeginUser;
  /* HDF5 would print its own diagnostic stack for a file that is not HDF5 (or was cut short) */
  H5Eget_auto2(H5E_DEFAULT, &report, &report_data);
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  ierr = PetscViewerHDF5Open(PETSC_COMM_SELF, path, FILE_MODE_READ, viewer);
  H5Eset_auto2(H5E_DEFAULT, report, report_data);
  if (ierr) {
    PetscCall(ErrorReportingForget());
    *viewer = NULL;
    *status = SOURCE_NOT_HDF5;
  }
  PetscFunctionReturn(0);
}

/* The same run (origin), every step listed with all its datasets, the same cells. */
static PetscErrorCode CheckSource(FieldWriter w, PetscViewer in, SourceStatus *status)
{
  PetscBool has;
  char     *origin = NULL;

  PetscFunctionBeginUser;
  PetscCall(PetscViewerHDF5HasAttribute(in, "/", "origin", &has));
  if (has) PetscCall(PetscViewerHDF5ReadAttribute(in, "/", "origin", PETSC_STRING, NULL, &origin));
  if (!has || strcmp(origin, w->source_origin)) *status = SOURCE_OTHER_RUN;
  PetscCall(PetscFree(origin));
  for (PetscInt p = 0; p < 3 && *status == SOURCE_OK; ++p) {
    const Part *P = &w->part[p];
    char        path[128];

    if (!P->nnodes) continue;
    for (PetscInt i = 0; i < w->nwritten && *status == SOURCE_OK; ++i)
      for (PetscInt k = 0; k <= P->nfields && *status == SOURCE_OK; ++k) {
        const char *name;
        PetscInt    columns;

        FieldsDataset(P, k, &name, &columns);
        PetscCall(PetscSNPrintf(path, sizeof(path), "/%s/step_%05" PetscInt_FMT "/%s", P->name, w->written[i], name));
        PetscCall(PetscViewerHDF5HasDataset(in, path, &has));
        if (!has) *status = SOURCE_STEP_MISSING;
      }
    PetscCall(PetscSNPrintf(path, sizeof(path), "/%s/topology", P->name));
    PetscCall(PetscViewerHDF5HasDataset(in, path, &has));
    if (!has) *status = SOURCE_OTHER_MESH;
    else {
      IS              is;
      PetscInt        n;
      const PetscInt *cells;

      PetscCall(ISCreate(PETSC_COMM_SELF, &is));
      PetscCall(PetscObjectSetName((PetscObject)is, "topology"));
      PetscCall(PetscSNPrintf(path, sizeof(path), "/%s", P->name));
      PetscCall(PetscViewerHDF5PushGroup(in, path));
      PetscCall(ISLoad(is, in));
      PetscCall(PetscViewerHDF5PopGroup(in));
      PetscCall(ISGetLocalSize(is, &n));
      PetscCall(ISGetIndices(is, &cells));
      if (n != P->ncells * P->nv) *status = SOURCE_OTHER_MESH;
      for (PetscInt j = 0; j < n && *status == SOURCE_OK; ++j)
        if (cells[j] != P->cells[j]) *status = SOURCE_OTHER_MESH;
      PetscCall(ISRestoreIndices(is, &cells));
      PetscCall(ISDestroy(&is));
    }
  }
  PetscFunctionReturn(0);
}

/* One step of one grid, its datasets and its time, from in to out. */
static PetscErrorCode CopyStep(const Part *P, PetscInt step, PetscViewer in, PetscViewer out)
{
  char      group[64];
  PetscReal t;

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(group, sizeof(group), "/%s/step_%05" PetscInt_FMT, P->name, step));
  for (PetscInt k = 0; k <= P->nfields; ++k) {
    const char *name;
    PetscInt    columns;
    Vec         v;

    FieldsDataset(P, k, &name, &columns);
    PetscCall(VecCreate(PETSC_COMM_SELF, &v));
    PetscCall(VecSetBlockSize(v, columns));
    PetscCall(PetscObjectSetName((PetscObject)v, name));
    PetscCall(PetscViewerHDF5PushGroup(in, group));
    PetscCall(VecLoad(v, in));
    PetscCall(PetscViewerHDF5PopGroup(in));
    PetscCall(PetscViewerHDF5PushGroup(out, group));
    PetscCall(VecView(v, out));
    PetscCall(PetscViewerHDF5PopGroup(out));
    PetscCall(VecDestroy(&v));
  }
  PetscCall(PetscViewerHDF5ReadAttribute(in, group, "time", PETSC_REAL, NULL, &t));
  PetscCall(PetscViewerHDF5WriteAttribute(out, group, "time", PETSC_REAL, &t));
  PetscFunctionReturn(0);
}

/* The root's part: finds and checks the source, builds the new file, renames it to the .partial. */
static PetscErrorCode BuildOnRoot(FieldWriter w, char source[], size_t len, SourceStatus *status)
{
  PetscViewer in = NULL, out;
  char        tmp[PETSC_MAX_PATH_LEN];
  FILE       *fp;

  PetscFunctionBeginUser;
  /* <file>.partial while that run was going or after it was killed, <file> once it
     completed; a .partial of another run (a later restart of it killed) is passed over */
  *status = SOURCE_MISSING;
  for (PetscInt c = 0; c < 2 && *status != SOURCE_OK; ++c) {
    SourceStatus found = SOURCE_OK;
    struct stat  st;

    PetscCall(PetscSNPrintf(tmp, sizeof(tmp), "%s%s", w->source, c ? "" : ".partial"));
    if (stat(tmp, &st)) continue;
    PetscCall(OpenQuietly(tmp, &in, &found));
    if (found == SOURCE_OK) PetscCall(CheckSource(w, in, &found));
    if (found != SOURCE_OK) PetscCall(PetscViewerDestroy(&in));
    if (*status == SOURCE_MISSING || found == SOURCE_OK) {
      *status = found;
      PetscCall(PetscStrncpy(source, tmp, len));
    }
  }
  if (*status == SOURCE_OK) {
    PetscCall(OutputMakeDirectories(w->dir));
    PetscCall(PetscSNPrintf(tmp, sizeof(tmp), "%s/fields.h5.restart.partial", w->dir));
    fp = fopen(tmp, "w");
    if (fp) fclose(fp);
    else *status = SOURCE_TEMPORARY;
  }
  if (*status != SOURCE_OK) {
    PetscCall(PetscViewerDestroy(&in));
    PetscFunctionReturn(0);
  }
  PetscCall(PetscViewerHDF5Open(PETSC_COMM_SELF, tmp, FILE_MODE_WRITE, &out));
  PetscCall(FieldsWriteHeader(w, out));
  for (PetscInt p = 0; p < 3; ++p)
    for (PetscInt i = 0; i < w->nwritten && w->part[p].nnodes; ++i)
      PetscCall(CopyStep(&w->part[p], w->written[i], in, out));
  PetscCall(PetscViewerDestroy(&in));
  PetscCall(PetscViewerDestroy(&out));
  if (rename(tmp, w->partial)) *status = SOURCE_TEMPORARY;
  PetscFunctionReturn(0);
}

/* FieldWriterOpen's restart: the new file from the fields of the continued run */
static PetscErrorCode RestartOpen(FieldWriter w)
{
  char         source[PETSC_MAX_PATH_LEN] = "";
  SourceStatus status                     = SOURCE_OK;
  int          s;

  PetscFunctionBeginUser;
  if (!w->rank) PetscCall(BuildOnRoot(w, source, sizeof(source), &status));
  s = (int)status;
  PetscCallMPI(MPI_Bcast(&s, 1, MPI_INT, 0, w->comm));
  PetscCallMPI(MPI_Bcast(source, sizeof(source), MPI_CHAR, 0, w->comm));
  status = (SourceStatus)s;
  PetscCheck(status != SOURCE_MISSING, w->comm, PETSC_ERR_FILE_OPEN,
             "option -restart: the fields of the run it continues are gone (neither %s.partial nor %s exists)",
             w->source, w->source);
  PetscCheck(status != SOURCE_NOT_HDF5, w->comm, PETSC_ERR_FILE_UNEXPECTED,
             "option -restart: the fields of the run it continues, %s, are not a readable HDF5 file", source);
  PetscCheck(status != SOURCE_OTHER_RUN, w->comm, PETSC_ERR_FILE_UNEXPECTED,
             "option -restart: %s was written by another run than the checkpoint's (%s)", source, w->source_origin);
  PetscCheck(status != SOURCE_STEP_MISSING, w->comm, PETSC_ERR_FILE_UNEXPECTED,
             "option -restart: %s lacks field steps the checkpoint lists", source);
  PetscCheck(status != SOURCE_OTHER_MESH, w->comm, PETSC_ERR_FILE_UNEXPECTED,
             "option -restart: %s was written on another mesh, or on another distribution of it over the ranks",
             source);
  PetscCheck(status != SOURCE_TEMPORARY, w->comm, PETSC_ERR_FILE_WRITE,
             "option -write_fields: cannot write %s/fields.h5.restart.partial or rename it to %s", w->dir, w->partial);
  /* the steps from here on go after the copied ones */
  if (!w->rank) PetscCall(PetscViewerHDF5Open(PETSC_COMM_SELF, w->partial, FILE_MODE_APPEND, &w->viewer));
  PetscFunctionReturn(0);
}

PetscErrorCode FieldWriterOpen(FieldWriter w)
{
  PetscBool ok = PETSC_TRUE;

  PetscFunctionBeginUser;
  if (!w || w->opened) PetscFunctionReturn(0);
  if (w->restarting) PetscCall(RestartOpen(w));
  else {
    if (!w->rank) {
      FILE *fp;

      PetscCall(OutputMakeDirectories(w->dir));
      /* HDF5's own failure is a multi-line trace: test the path first */
      fp = fopen(w->partial, "w");
      ok = fp ? PETSC_TRUE : PETSC_FALSE;
      if (fp) fclose(fp);
    }
    PetscCallMPI(MPI_Bcast(&ok, 1, MPIU_BOOL, 0, w->comm));
    PetscCheck(ok, w->comm, PETSC_ERR_FILE_OPEN, "option -write_fields: cannot create %s", w->partial);
    if (!w->rank) PetscCall(PetscViewerHDF5Open(PETSC_COMM_SELF, w->partial, FILE_MODE_WRITE, &w->viewer));
    PetscCall(OutputRegisterSetUpFile(w->partial));
    if (!w->rank) PetscCall(FieldsWriteHeader(w, w->viewer));
  }
  w->opened = PETSC_TRUE;
  PetscFunctionReturn(0);
}
