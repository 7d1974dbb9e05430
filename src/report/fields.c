/* -write_fields (fields.h): the fluid's (velocity, pressure, mesh velocity) and the
   structure's (displacement, velocity) fields gathered on rank 0 in
   each grid's global vertex order, written to fields.h5 every few steps, and fields.xdmf,
   which ParaView opens, written when the run completes. */
#include <errno.h>
#include <time.h>
#include <hdf5.h>
#include <unistd.h>
#include "fields_impl.h"
#include "fem.h"
#include "options.h"
#include "error_reporting.h"
#include "output_files.h"

/* Concatenates every rank's n values on the root, in rank order. */
static PetscErrorCode GatherOnRoot(MPI_Comm comm, PetscInt n, MPI_Datatype type, const void *send, void **recv,
                                   PetscInt *total)
{
  PetscMPIInt rank, size, mine = (PetscMPIInt)n, *counts = NULL, *displs = NULL, unit;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCallMPI(MPI_Type_size(type, &unit));
  *recv  = NULL;
  *total = 0;
  if (!rank) PetscCall(PetscMalloc2(size, &counts, size, &displs));
  PetscCallMPI(MPI_Gather(&mine, 1, MPI_INT, counts, 1, MPI_INT, 0, comm));
  for (PetscMPIInt r = 0; !rank && r < size; ++r) {
    displs[r] = (PetscMPIInt)*total;
    *total += counts[r];
  }
  if (!rank) PetscCall(PetscMalloc((size_t)PetscMax(*total, 1) * (size_t)unit, recv));
  PetscCallMPI(MPI_Gatherv(send, mine, type, *recv, counts, displs, type, 0, comm));
  if (!rank) PetscCall(PetscFree2(counts, displs));
  PetscFunctionReturn(0);
}

static PetscErrorCode WriteArray(PetscViewer viewer, const char name[], PetscInt bs, PetscInt n, const PetscScalar a[])
{
  Vec v;

  PetscFunctionBeginUser;
  PetscCall(VecCreateSeqWithArray(PETSC_COMM_SELF, bs, n * bs, a, &v));
  PetscCall(PetscObjectSetName((PetscObject)v, name));
  PetscCall(VecView(v, viewer));
  PetscCall(VecDestroy(&v));
  PetscFunctionReturn(0);
}

/* Where a grid's fields live on this rank: each in a local vector with its own section
   (the fluid's mesh velocity is on a DM of its own). */
typedef struct {
  DM           dm; /* NULL: this rank holds no part of the grid */
  PetscSection section[FIELDS_MAX];
  PetscInt     number[FIELDS_MAX]; /* the field's number in its section */
  Vec          local[FIELDS_MAX];
  Vec          borrowed; /* the fluid's local solution, returned by SourcesRestore */
} Sources;

/* values = PETSC_FALSE: the sections only */
static PetscErrorCode SourcesGet(FieldWriter w, PetscInt p, PetscBool values, Sources *s)
{
  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(s, sizeof(*s)));
  if (p == 0 && w->fluid) {
    DM  aux;
    Vec z, x;

    PetscCall(FluidGetDM(w->fluid, &s->dm));
    PetscCall(DMGetLocalSection(s->dm, &s->section[0]));
    s->section[1] = s->section[0];
    s->number[1]  = 1;
    if (values) {
      /* the global solution lacks the Dirichlet values */
      PetscCall(FluidGetSolution(w->fluid, &x));
      PetscCall(DMGetLocalVector(s->dm, &s->borrowed));
      PetscCall(FEMGlobalToLocal(s->dm, x, s->borrowed));
      s->local[0] = s->local[1] = s->borrowed;
    }
    PetscCall(FluidGetMeshVelocity(w->fluid, &aux, &z));
    if (aux) {
      PetscCall(DMGetLocalSection(aux, &s->section[2]));
      s->local[2] = z;
    }
  } else if (p == 1 && w->structure) {
    PetscCall(StructureGetDM(w->structure, &s->dm));
    PetscCall(DMGetLocalSection(s->dm, &s->section[0]));
    s->section[1] = s->section[0]; /* the velocity's local vector has the displacement's layout */
    if (values) {
      PetscCall(StructureGetDisplacementLocal(w->structure, &s->local[0]));
      PetscCall(StructureGetVelocityLocal(w->structure, &s->local[1]));
    }
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode SourcesRestore(Sources *s)
{
  PetscFunctionBeginUser;
  if (s->borrowed) PetscCall(DMRestoreLocalVector(s->dm, &s->borrowed));
  PetscFunctionReturn(0);
}

void FieldsDataset(const Part *P, PetscInt k, const char **name, PetscInt *columns)
{
  *name    = k ? P->field[k - 1] : "geometry";
  *columns = k ? (P->nc[k - 1] > 1 ? 3 : P->nc[k - 1]) : P->dim;
}

#define MAX_CELL_VERTICES 8

/* The grid's cells and owned vertices; its topology is kept on the root for FieldsWriteHeader. */
static PetscErrorCode PartSetUp(FieldWriter w, Part *P, const Sources *src)
{
  PetscInt  info[2] = {0, 0}, ncells = 0, *cells = NULL, *global = NULL, total;
  PetscBool bad = PETSC_FALSE;
  DM        dm  = src->dm;

  PetscFunctionBeginUser;
  if (dm) {
    IS              vnum, cnum;
    const PetscInt *vn, *cn;
    PetscInt        vStart, vEnd, cStart, cEnd;

    PetscCall(DMGetCoordinateDim(dm, &info[0]));
    PetscCall(DMPlexGetDepthStratum(dm, 0, &vStart, &vEnd));
    PetscCall(DMPlexGetHeightStratum(dm, 0, &cStart, &cEnd));
    PetscCall(DMPlexGetVertexNumbering(dm, &vnum));
    PetscCall(DMPlexGetCellNumbering(dm, &cnum));
    PetscCall(ISGetIndices(vnum, &vn));
    PetscCall(ISGetIndices(cnum, &cn));
    PetscCall(PetscMalloc1(vEnd - vStart, &P->own));
    PetscCall(PetscMalloc1(vEnd - vStart, &global));
    for (PetscInt v = vStart; v < vEnd; ++v) {
      if (vn[v - vStart] < 0) continue; /* another rank writes it */
      P->own[P->nown]   = v;
      global[P->nown++] = vn[v - vStart];
      /* a Lagrange field keeps its vertex value at the vertex point: one dof per component */
      for (PetscInt f = 0; f < P->nfields; ++f) {
        PetscInt ndof;
        PetscCall(PetscSectionGetFieldDof(src->section[f], v, src->number[f], &ndof));
        if (ndof != (P->nc[f] < 0 ? info[0] : P->nc[f])) bad = PETSC_TRUE;
      }
    }
    PetscCall(PetscMalloc1((cEnd - cStart) * MAX_CELL_VERTICES, &cells));
    for (PetscInt c = cStart; c < cEnd; ++c) {
      PetscInt *closure = NULL, n, nv = 0;

      if (cn[c - cStart] < 0) continue;
      PetscCall(DMPlexGetTransitiveClosure(dm, c, PETSC_TRUE, &n, &closure));
      for (PetscInt i = 0; i < 2 * n; i += 2) {
        const PetscInt p = closure[i];
        if (p < vStart || p >= vEnd) continue;
        if (nv < MAX_CELL_VERTICES)
          cells[ncells * MAX_CELL_VERTICES + nv] = vn[p - vStart] < 0 ? -(vn[p - vStart] + 1) : vn[p - vStart];
        ++nv;
      }
      PetscCall(DMPlexRestoreTransitiveClosure(dm, c, PETSC_TRUE, &n, &closure));
      if (!info[1]) info[1] = nv;
      if (nv != info[1] || nv > MAX_CELL_VERTICES) bad = PETSC_TRUE;
      ++ncells;
    }
    PetscCall(ISRestoreIndices(vnum, &vn));
    PetscCall(ISRestoreIndices(cnum, &cn));
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &bad, 1, MPIU_BOOL, MPI_LOR, w->comm));
  PetscCheck(!bad, w->comm, PETSC_ERR_SUP,
             "option -write_fields: the %s needs a mesh of one cell type and Lagrange fields with values at the "
             "vertices",
             P->name);
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, info, 2, MPIU_INT, MPI_MAX, w->comm));
  P->dim = info[0];
  P->nv  = info[1];
  PetscCheck((P->dim == 2 && (P->nv == 3 || P->nv == 4)) || (P->dim == 3 && (P->nv == 4 || P->nv == 8)), w->comm,
             PETSC_ERR_SUP,
             "option -write_fields: the %s mesh has cells of %" PetscInt_FMT " vertices in %" PetscInt_FMT
             "D; only triangles, quadrilaterals, tetrahedra and hexahedra are written",
             P->name, P->nv, P->dim);
  for (PetscInt f = 0; f < P->nfields; ++f)
    if (P->nc[f] < 0) P->nc[f] = P->dim;
  for (PetscInt c = 0; c < ncells; ++c) {
    for (PetscInt i = 0; i < P->nv; ++i) cells[c * P->nv + i] = cells[c * MAX_CELL_VERTICES + i];
    /* DMPlex lists a hexahedron's bottom face with its normal outward, XDMF (VTK) inward */
    if (P->nv == 8) PetscCall(DMPlexInvertCell(DM_POLYTOPE_HEXAHEDRON, &cells[c * P->nv]));
  }
  PetscCall(GatherOnRoot(w->comm, ncells * P->nv, MPIU_INT, cells, (void **)&P->cells, &total));
  P->ncells = total / P->nv;
  PetscCall(GatherOnRoot(w->comm, P->nown, MPIU_INT, global, (void **)&P->index, &P->nvertices));
  PetscCallMPI(MPI_Bcast(&P->nvertices, 1, MPIU_INT, 0, w->comm));
  PetscCallMPI(MPI_Bcast(&P->ncells, 1, MPIU_INT, 0, w->comm));
  PetscCall(PetscFree(cells));
  PetscCall(PetscFree(global));
  PetscFunctionReturn(0);
}

PetscErrorCode FieldsWriteHeader(FieldWriter w, PetscViewer viewer)
{
  PetscFunctionBeginUser;
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "origin", PETSC_STRING, w->origin));
  for (PetscInt p = 0; p < 2; ++p) {
    const Part *P = &w->part[p];
    IS          is;
    char        group[64];

    if (!P->nvertices) continue;
    PetscCall(PetscSNPrintf(group, sizeof(group), "/%s", P->name));
    PetscCall(ISCreateGeneral(PETSC_COMM_SELF, P->ncells * P->nv, P->cells, PETSC_USE_POINTER, &is));
    PetscCall(ISSetBlockSize(is, P->nv));
    PetscCall(PetscObjectSetName((PetscObject)is, "topology"));
    PetscCall(PetscViewerHDF5PushGroup(viewer, group));
    PetscCall(ISView(is, viewer));
    PetscCall(PetscViewerHDF5PopGroup(viewer));
    PetscCall(ISDestroy(&is));
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode WriteGroup(PetscViewer viewer, const char group[], PetscInt nq, const char *name[],
                                 const PetscInt bs[], PetscInt n, PetscScalar *q[], PetscReal t)
{
  PetscFunctionBeginUser;
  PetscCall(PetscViewerHDF5PushGroup(viewer, group));
  for (PetscInt k = 0; k < nq; ++k) PetscCall(WriteArray(viewer, name[k], bs[k], n, q[k]));
  PetscCall(PetscViewerHDF5PopGroup(viewer));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, group, "time", PETSC_REAL, &t));
  PetscFunctionReturn(0);
}

static PetscErrorCode PartWrite(FieldWriter w, const Part *P, const Sources *src, const char group[], PetscReal t)
{
  const PetscInt nq = 1 + P->nfields;
  PetscInt       bs[1 + FIELDS_MAX], obs[1 + FIELDS_MAX], ncomp = 0, total;
  const char    *name[1 + FIELDS_MAX];
  PetscScalar   *buf = NULL, *all;

  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < nq; ++k) {
    FieldsDataset(P, k, &name[k], &obs[k]);
    bs[k] = k ? P->nc[k - 1] : P->dim;
    ncomp += bs[k];
  }
  if (src->dm) {
    Vec                X;
    PetscSection       cs;
    const PetscScalar *x, *u[FIELDS_MAX];

    PetscCall(DMGetCoordinatesLocal(src->dm, &X));
    PetscCall(DMGetCoordinateSection(src->dm, &cs));
    PetscCall(VecGetArrayRead(X, &x));
    for (PetscInt f = 0; f < P->nfields; ++f) PetscCall(VecGetArrayRead(src->local[f], &u[f]));
    PetscCall(PetscMalloc1(P->nown * ncomp, &buf));
    for (PetscInt i = 0; i < P->nown; ++i) {
      PetscScalar *b = buf + i * ncomp;
      PetscInt     off;

      PetscCall(PetscSectionGetOffset(cs, P->own[i], &off));
      for (PetscInt d = 0; d < P->dim; ++d) *b++ = x[off + d];
      for (PetscInt f = 0; f < P->nfields; ++f) {
        PetscCall(PetscSectionGetFieldOffset(src->section[f], P->own[i], src->number[f], &off));
        for (PetscInt c = 0; c < P->nc[f]; ++c) *b++ = u[f][off + c];
      }
    }
    for (PetscInt f = 0; f < P->nfields; ++f) PetscCall(VecRestoreArrayRead(src->local[f], &u[f]));
    PetscCall(VecRestoreArrayRead(X, &x));
  }
  PetscCall(GatherOnRoot(w->comm, P->nown * ncomp, MPIU_SCALAR, buf, (void **)&all, &total));
  if (!w->rank && !w->write_error) {
    const PetscInt N                 = P->nvertices;
    PetscScalar   *q[1 + FIELDS_MAX] = {NULL};

    for (PetscInt k = 0; k < nq; ++k) PetscCall(PetscCalloc1(N * obs[k], &q[k]));
    for (PetscInt j = 0; j < N; ++j) {
      const PetscInt     g = P->index[j];
      const PetscScalar *a = all + j * ncomp;

      for (PetscInt k = 0; k < nq; ++k)
        for (PetscInt c = 0; c < bs[k]; ++c) q[k][g * obs[k] + c] = *a++;
      if (P->deform)
        for (PetscInt d = 0; d < P->dim; ++d) q[0][g * P->dim + d] += q[1][g * obs[1] + d];
    }
    /* a failed write (a full disk) is kept, not raised: the other ranks do not write, and all
       of them stop together in FieldWriterWrite */
    w->write_error = WriteGroup(w->viewer, group, nq, name, obs, N, q, t);
    for (PetscInt k = 0; k < nq; ++k) PetscCall(PetscFree(q[k]));
  }
  PetscCall(PetscFree(all));
  PetscCall(PetscFree(buf));
  PetscFunctionReturn(0);
}

/* Distinguishes this run's fields file from another run's that a restart might find. */
static PetscErrorCode MakeOrigin(FieldWriter w)
{
  PetscFunctionBeginUser;
  if (!w->rank) {
    char host[64];
    PetscCall(PetscGetHostName(host, sizeof(host)));
    PetscCall(PetscSNPrintf(w->origin, sizeof(w->origin), "%s pid %d at %ld", host, (int)getpid(), (long)time(NULL)));
  }
  PetscCallMPI(MPI_Bcast(w->origin, sizeof(w->origin), MPI_CHAR, 0, w->comm));
  PetscFunctionReturn(0);
}

PetscErrorCode FieldWriterCreate(MPI_Comm comm, const RunParams *params, Fluid fluid, Structure structure,
                                 FieldWriter *writer)
{
  FieldWriter w;
  PetscBool   on = PETSC_FALSE, help, moving = PETSC_FALSE,
            exists[2] = {fluid ? PETSC_TRUE : PETSC_FALSE, structure ? PETSC_TRUE : PETSC_FALSE};
  PetscInt interval   = 10;

  PetscFunctionBeginUser;
  *writer = NULL;
  PetscOptionsBegin(comm, NULL, "Field output for ParaView", "fsiopt");
  PetscCall(PetscOptionsBool("-write_fields",
                             "write <output_dir>/fields.h5 and fields.xdmf (fluid and structure fields over time)",
                             NULL, on, &on, NULL));
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-write_fields_interval",
                              "write the fields every K-th step (the first and the last always)", 1, PETSC_MAX_INT,
                              &interval));
  PetscOptionsEnd();
  help = OptionsHelpRequested();
  if (!on || help) PetscFunctionReturn(0); /* a -help run runs no step: nothing to show */
  if (fluid) {
    DM  aux;
    Vec z;
    PetscCall(FluidGetMeshVelocity(fluid, &aux, &z));
    moving = aux ? PETSC_TRUE : PETSC_FALSE;
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &moving, 1, MPIU_BOOL, MPI_LOR, comm));
  PetscCall(PetscNew(&w));
  w->comm      = comm;
  w->fluid     = fluid;
  w->structure = structure;
  w->interval  = interval;
  w->steps     = params->steps;
  w->t0        = params->t_start;
  w->dt        = params->dt;
  w->part[0]   = (Part){
      .name = "fluid", .field = {"velocity", "pressure", "mesh_velocity"},
           .nfields = moving ? 3 : 2, .nc = {-1,         1,          -1             }
  };
  w->part[1] = (Part){
    .name = "structure", .field = {"displacement", "velocity"},
       .nfields = 2, .nc = {-1, -1},
       .deform = PETSC_TRUE
  };
  PetscCall(PetscMalloc1(w->steps + 1, &w->written));
  PetscCall(PetscStrncpy(w->dir, params->output_dir, sizeof(w->dir)));
  PetscCall(PetscSNPrintf(w->path, sizeof(w->path), "%s/fields.h5", w->dir));
  PetscCall(PetscSNPrintf(w->partial, sizeof(w->partial), "%s/fields.h5.partial", w->dir));
  PetscCall(PetscLogEventRegister("FieldsWrite", PETSC_VIEWER_CLASSID, &w->event));
  PetscCallMPI(MPI_Comm_rank(comm, &w->rank));
  *writer = w; /* from here on FieldWriterDestroy cleans up after a failure */
  PetscCall(MakeOrigin(w));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, exists, 2, MPIU_BOOL, MPI_LOR, comm));
  for (PetscInt p = 0; p < 2; ++p) {
    Sources src;
    if (!exists[p]) continue;
    PetscCall(SourcesGet(w, p, PETSC_FALSE, &src));
    PetscCall(PartSetUp(w, &w->part[p], &src));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FieldWriterWrite(FieldWriter w, PetscInt step)
{
  PetscFunctionBeginUser;
  if (!w || (step % w->interval && step != 0 && step != w->steps)) PetscFunctionReturn(0);
  if (step > w->steps || (w->nwritten && w->written[w->nwritten - 1] >= step)) PetscFunctionReturn(0);
  PetscCheck(w->opened, w->comm, PETSC_ERR_ORDER, "FieldWriterOpen before FieldWriterWrite");
  PetscCall(PetscLogEventBegin(w->event, 0, 0, 0, 0));
  if (!w->rank) {
    /* a failing write is reported in one line (below), not by HDF5's diagnostic stack */
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
    errno = 0;
  }
  for (PetscInt p = 0; p < 2; ++p) {
    Sources src;
    char    group[64];

    if (!w->part[p].nvertices) continue; /* not in this scene */
    PetscCall(SourcesGet(w, p, PETSC_TRUE, &src));
    PetscCall(PetscSNPrintf(group, sizeof(group), "/%s/step_%05" PetscInt_FMT, w->part[p].name, step));
    PetscCall(PartWrite(w, &w->part[p], &src, group, w->t0 + step * w->dt));
    PetscCall(SourcesRestore(&src));
  }
  if (!w->rank && !w->write_error) w->write_error = PetscViewerFlush(w->viewer);
  {
    PetscErrorCode failed = w->write_error;
    int            cause  = errno;

    PetscCallMPI(MPI_Bcast(&failed, 1, MPI_INT, 0, w->comm));
    PetscCallMPI(MPI_Bcast(&cause, 1, MPI_INT, 0, w->comm));
    if (failed) {
      char why[256];
      OutputHDF5WriteFailed();
      PetscCall(ErrorReportingForget()); /* HDF5's and PETSc's messages name their internals */
      PetscCall(OutputWriteErrorText(w->partial, cause, why, sizeof(why)));
      SETERRQ(w->comm, PETSC_ERR_FILE_WRITE,
              "cannot write %s (%s) at step %" PetscInt_FMT "; what was written is in %s", w->path, why, step,
              w->partial);
    }
  }
  w->written[w->nwritten++] = step;
  PetscCall(PetscLogEventEnd(w->event, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

static PetscErrorCode XdmfItem(MPI_Comm comm, FILE *fp, const char *indent, PetscInt n, PetscInt bs, const char type[],
                               size_t precision, const char path[])
{
  PetscFunctionBeginUser;
  PetscCall(PetscFPrintf(comm, fp, "%s<DataItem Dimensions=\"%" PetscInt_FMT, indent, n));
  if (bs > 1) PetscCall(PetscFPrintf(comm, fp, " %" PetscInt_FMT, bs));
  PetscCall(PetscFPrintf(comm, fp, "\" NumberType=\"%s\" Precision=\"%d\" Format=\"HDF\">fields.h5:%s</DataItem>\n",
                         type, (int)precision, path));
  PetscFunctionReturn(0);
}

/* A grid name per time (fluid_step_00010): with the same name at every time, ParaView's
   XDMF (Xdmf2) reader and Xdmf3ReaderT list the blocks as fluid, fluid[1], fluid[2], ... */
static PetscErrorCode XdmfGrid(MPI_Comm comm, FILE *fp, const Part *P, PetscInt step)
{
  const char *topology = P->dim == 3 ? (P->nv == 8 ? "Hexahedron" : "Tetrahedron")
                       : P->nv == 3  ? "Triangle"
                                     : "Quadrilateral";
  char        path[128];

  PetscFunctionBeginUser;
  PetscCall(
    PetscFPrintf(comm, fp, "      <Grid Name=\"%s_step_%05" PetscInt_FMT "\" GridType=\"Uniform\">\n", P->name, step));
  PetscCall(PetscFPrintf(comm, fp,
                         "        <Topology TopologyType=\"%s\" NumberOfElements=\"%" PetscInt_FMT
                         "\" NodesPerElement=\"%" PetscInt_FMT "\">\n",
                         topology, P->ncells, P->nv));
  PetscCall(PetscSNPrintf(path, sizeof(path), "/%s/topology", P->name));
  PetscCall(XdmfItem(comm, fp, "          ", P->ncells, P->nv, "Int", sizeof(PetscInt), path));
  PetscCall(PetscFPrintf(comm, fp, "        </Topology>\n        <Geometry GeometryType=\"%s\">\n",
                         P->dim == 3 ? "XYZ" : "XY"));
  PetscCall(PetscSNPrintf(path, sizeof(path), "/%s/step_%05" PetscInt_FMT "/geometry", P->name, step));
  PetscCall(XdmfItem(comm, fp, "          ", P->nvertices, P->dim, "Float", sizeof(PetscScalar), path));
  PetscCall(PetscFPrintf(comm, fp, "        </Geometry>\n"));
  for (PetscInt k = 1; k <= P->nfields; ++k) {
    const char *name;
    PetscInt    columns;

    FieldsDataset(P, k, &name, &columns);
    PetscCall(PetscFPrintf(comm, fp, "        <Attribute Name=\"%s\" AttributeType=\"%s\" Center=\"Node\">\n", name,
                           columns > 1 ? "Vector" : "Scalar"));
    PetscCall(PetscSNPrintf(path, sizeof(path), "/%s/step_%05" PetscInt_FMT "/%s", P->name, step, name));
    PetscCall(XdmfItem(comm, fp, "          ", P->nvertices, columns, "Float", sizeof(PetscScalar), path));
    PetscCall(PetscFPrintf(comm, fp, "        </Attribute>\n"));
  }
  PetscCall(PetscFPrintf(comm, fp, "      </Grid>\n"));
  PetscFunctionReturn(0);
}

/* The run completed: fields.h5 gets its name, then the XDMF that refers to it is written. */
PetscErrorCode FieldWriterFinish(FieldWriter w)
{
  PartialFile xdmf;
  PetscBool   renamed = PETSC_TRUE;

  PetscFunctionBeginUser;
  if (!w || !w->opened) PetscFunctionReturn(0);
  if (!w->rank) {
    PetscCall(PetscViewerDestroy(&w->viewer));
    renamed = rename(w->partial, w->path) == 0 ? PETSC_TRUE : PETSC_FALSE;
  }
  PetscCallMPI(MPI_Bcast(&renamed, 1, MPIU_BOOL, 0, w->comm));
  PetscCheck(renamed, w->comm, PETSC_ERR_FILE_WRITE, "option -write_fields: cannot rename %s to %s", w->partial,
             w->path);
  PetscCall(PartialFileOpen(w->comm, w->dir, "fields.xdmf", &xdmf));
  PetscCall(PetscFPrintf(w->comm, xdmf.fp,
                         "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n<Xdmf Version=\"3.0\">\n  "
                         "<Domain>\n"));
  PetscCall(
    PetscFPrintf(w->comm, xdmf.fp, "    <Grid Name=\"fsiopt\" GridType=\"Collection\" CollectionType=\"Temporal\">\n"));
  for (PetscInt i = 0; i < w->nwritten; ++i) {
    PetscCall(PetscFPrintf(w->comm, xdmf.fp,
                           "    <Grid Name=\"step_%05" PetscInt_FMT
                           "\" GridType=\"Collection\" CollectionType=\"Spatial\">\n",
                           w->written[i]));
    PetscCall(
      PetscFPrintf(w->comm, xdmf.fp, "      <Time Value=\"%.12g\"/>\n", (double)(w->t0 + w->written[i] * w->dt)));
    for (PetscInt p = 0; p < 2; ++p)
      if (w->part[p].nvertices) PetscCall(XdmfGrid(w->comm, xdmf.fp, &w->part[p], w->written[i]));
    PetscCall(PetscFPrintf(w->comm, xdmf.fp, "    </Grid>\n"));
  }
  PetscCall(PetscFPrintf(w->comm, xdmf.fp, "    </Grid>\n  </Domain>\n</Xdmf>\n"));
  PetscCall(PartialFileClose(&xdmf, PETSC_TRUE));
  PetscFunctionReturn(0);
}

/* Without FieldWriterFinish the files keep their .partial names. */
PetscErrorCode FieldWriterDestroy(FieldWriter *writer)
{
  FieldWriter w = *writer;

  PetscFunctionBeginUser;
  if (!w) PetscFunctionReturn(0);
  PetscCall(PetscViewerDestroy(&w->viewer));
  for (PetscInt p = 0; p < 2; ++p) {
    PetscCall(PetscFree(w->part[p].own));
    PetscCall(PetscFree(w->part[p].index));
    PetscCall(PetscFree(w->part[p].cells));
  }
  PetscCall(PetscFree(w->written));
  PetscCall(PetscFree(*writer));
  PetscFunctionReturn(0);
}
