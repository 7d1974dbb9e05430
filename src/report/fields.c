/* -write_fields (fields.h): each grid's fields (the fluid's, the structure's, the walls')
   gathered on rank 0 in the order of the grid's global node numbers (fields_grid.c), with
   the derived ones computed from their sources at each node (fields_derived.c), written to
   fields.h5 every few steps, and fields.xdmf, which ParaView opens, written when the run
   completes. */
#include <errno.h>
#include <time.h>
#include <hdf5.h>
#include <unistd.h>
#include "fields_impl.h"
#include "fem.h"
#include "options.h"
#include "error_reporting.h"
#include "output_files.h"
#include "units.h"

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

/* The primary fields' sources (the derived ones come from fields_derived.c); values =
   PETSC_FALSE: the sections only. */
PetscErrorCode FieldsWriterSources(FieldWriter w, PetscInt p, PetscBool values, Sources *s)
{
  FieldsGridSources *g = &s->grid;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(s, sizeof(*s)));
  for (PetscInt f = 0; f < FIELDS_MAX; ++f) s->number[f][0] = -1;
  if (p != 1 && w->fluid) {
    DM  aux;
    Vec z, x;

    PetscCall(FluidGetDM(w->fluid, &g->dm));
    PetscCall(DMGetLocalSection(g->dm, &s->section[0][0]));
    s->section[1][0] = s->section[0][0];
    s->number[0][0]  = 0;
    s->number[1][0]  = 1;
    if (values) {
      /* the global solution lacks the Dirichlet values */
      PetscCall(FluidGetSolution(w->fluid, &x));
      PetscCall(DMGetLocalVector(g->dm, &s->borrowed));
      PetscCall(FEMGlobalToLocal(g->dm, x, s->borrowed));
      s->local[0][0] = s->local[1][0] = s->borrowed;
    }
    PetscCall(FluidGetMeshVelocity(w->fluid, &aux, &z));
    if (aux && p == 0) {
      PetscCall(DMGetLocalSection(aux, &s->section[2][0]));
      s->number[2][0] = 0;
      s->local[2][0]  = z;
    }
    /* the walls' nodes are those of the velocity */
    g->nfields = p == 0 ? (s->section[2][0] ? 3 : 2) : 1;
  } else if (p == 1 && w->structure) {
    PetscCall(StructureGetDM(w->structure, &g->dm));
    PetscCall(DMGetLocalSection(g->dm, &s->section[0][0]));
    s->section[1][0] = s->section[0][0]; /* the velocity's local vector has the displacement's layout */
    s->number[0][0] = s->number[1][0] = 0;
    if (values) {
      PetscCall(StructureGetDisplacementLocal(w->structure, &s->local[0][0]));
      PetscCall(StructureGetVelocityLocal(w->structure, &s->local[1][0]));
    }
    g->nfields = 2;
  }
  if (g->dm) {
    PetscInt dim;
    PetscCall(DMGetCoordinateDim(g->dm, &dim));
    for (PetscInt f = 0; f < g->nfields; ++f) {
      g->section[f] = s->section[f][0];
      g->number[f]  = s->number[f][0];
      g->nc[f]      = f == 1 && p == 0 ? 1 : dim; /* the pressure, or a vector */
    }
  }
  PetscCall(FieldsDerivedSources(w, p, values, s));
  PetscFunctionReturn(0);
}

PetscErrorCode FieldsWriterSourcesRestore(Sources *s)
{
  PetscFunctionBeginUser;
  if (s->borrowed) PetscCall(DMRestoreLocalVector(s->grid.dm, &s->borrowed));
  PetscFunctionReturn(0);
}

void FieldsDataset(const Part *P, PetscInt k, const char **name, PetscInt *columns)
{
  const PetscInt nc = k ? P->nc[k - 1] : P->dim;

  *name    = k ? P->field[k - 1] : "geometry";
  *columns = k == 0 || nc == 1 ? nc : nc <= 3 ? 3 : 9;
}

PetscErrorCode FieldsWriteHeader(FieldWriter w, PetscViewer viewer)
{
  PetscFunctionBeginUser;
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "origin", PETSC_STRING, w->origin));
  for (PetscInt p = 0; p < 3; ++p) {
    const Part *P = &w->part[p];
    IS          is;
    char        group[64], unit[64];

    if (!P->nnodes) continue;
    PetscCall(PetscSNPrintf(group, sizeof(group), "/%s", P->name));
    PetscCall(ISCreateGeneral(PETSC_COMM_SELF, P->ncells * P->nv, P->cells, PETSC_USE_POINTER, &is));
    PetscCall(ISSetBlockSize(is, P->nv));
    PetscCall(PetscObjectSetName((PetscObject)is, "topology"));
    PetscCall(PetscViewerHDF5PushGroup(viewer, group));
    PetscCall(ISView(is, viewer));
    PetscCall(PetscViewerHDF5PopGroup(viewer));
    PetscCall(ISDestroy(&is));
    /* each dataset's unit, as attributes "<dataset> unit" of the grid's group */
    for (PetscInt k = 0; k <= P->nfields; ++k) {
      const char *name, *u = k ? P->unit[k - 1] : UnitName(w->units, UNIT_LENGTH);
      PetscInt    columns;
      FieldsDataset(P, k, &name, &columns);
      PetscCall(PetscSNPrintf(unit, sizeof(unit), "%s unit", name));
      PetscCall(PetscViewerHDF5WriteAttribute(viewer, group, unit, PETSC_STRING, u ? u : "nondimensional"));
    }
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

/* A field's values at own node i, computed from its sources' values there. */
static PetscErrorCode NodeValue(const Part *P, const Sources *src, const PetscScalar *const u[][FIELD_SOURCES],
                                PetscInt f, PetscInt i, PetscScalar out[])
{
  PetscScalar in[32];
  PetscInt    n = 0;

  PetscFunctionBeginUser;
  if (P->transform[f] == FIELD_COPY) {
    PetscCall(FieldsGridValue(P, i, src->section[f][0], src->number[f][0], P->nc[f], u[f][0], out));
    PetscFunctionReturn(0);
  }
  for (PetscInt k = 0; k < P->nsources[f]; ++k) {
    PetscCall(FieldsGridValue(P, i, src->section[f][k], src->number[f][k], P->source_nc[f][k], u[f][k], &in[n]));
    n += P->source_nc[f][k];
  }
  FieldsTransform(P->transform[f], P->dim, src->mu, in, out);
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
  if (src->grid.dm) {
    Vec                X;
    PetscSection       cs;
    const PetscScalar *x, *u[FIELDS_MAX][FIELD_SOURCES] = {{NULL}};

    PetscCall(DMGetCoordinatesLocal(src->grid.dm, &X));
    PetscCall(DMGetCoordinateSection(src->grid.dm, &cs));
    PetscCall(VecGetArrayRead(X, &x));
    for (PetscInt f = 0; f < P->nfields; ++f)
      for (PetscInt k = 0; k < FIELD_SOURCES; ++k)
        if (src->local[f][k]) PetscCall(VecGetArrayRead(src->local[f][k], &u[f][k]));
    PetscCall(PetscMalloc1(P->nown * ncomp, &buf));
    for (PetscInt i = 0; i < P->nown; ++i) {
      PetscScalar *b = buf + i * ncomp;

      PetscCall(FieldsGridValue(P, i, cs, -1, P->dim, x, b));
      b += P->dim;
      for (PetscInt f = 0; f < P->nfields; ++f) {
        PetscCall(NodeValue(P, src, (const PetscScalar *const(*)[FIELD_SOURCES])u, f, i, b));
        b += P->nc[f];
      }
    }
    for (PetscInt f = 0; f < P->nfields; ++f)
      for (PetscInt k = 0; k < FIELD_SOURCES; ++k)
        if (src->local[f][k]) PetscCall(VecRestoreArrayRead(src->local[f][k], &u[f][k]));
    PetscCall(VecRestoreArrayRead(X, &x));
  }
  PetscCall(FieldsGatherOnRoot(w->comm, P->nown * ncomp, MPIU_SCALAR, buf, (void **)&all, &total));
  if (!w->rank && !w->write_error) {
    const PetscInt N                 = P->nnodes;
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

PetscErrorCode FieldWriterCreate(MPI_Comm comm, const RunParams *params, const char units[], Fluid fluid,
                                 Structure structure, Interface itf, CouplingProblem problem, FieldWriter *writer)
{
  FieldWriter w;
  PetscBool   on = PETSC_FALSE, help, moving = PETSC_FALSE,
            exists[2] = {fluid ? PETSC_TRUE : PETSC_FALSE, structure ? PETSC_TRUE : PETSC_FALSE};
  PetscInt    interval = 10, nodes = 0;
  const char *node_sets[] = {"all", "vertices"};

  PetscFunctionBeginUser;
  *writer = NULL;
  PetscOptionsBegin(comm, NULL, "Field output for ParaView", "fsiopt");
  PetscCall(PetscOptionsBool("-write_fields",
                             "write <output_dir>/fields.h5 and fields.xdmf (fluid and structure fields over time)",
                             NULL, on, &on, NULL));
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-write_fields_interval",
                              "write the fields every K-th step (the first and the last always)", 1, PETSC_MAX_INT,
                              &interval));
  PetscCall(PetscOptionsEList("-write_fields_nodes",
                              "all: every Lagrange node of a field of degree 2 (each cell written as its once-refined "
                              "cells); vertices: the vertex values on the mesh's own cells",
                              NULL, node_sets, 2, node_sets[nodes], &nodes, NULL));
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
  w->itf       = itf;
  w->problem   = problem;
  w->interval  = interval;
  w->steps     = params->steps;
  w->t0        = params->t_start;
  w->dt        = params->dt;
  w->units     = units;
  w->all_nodes = nodes == 0 ? PETSC_TRUE : PETSC_FALSE;
  w->part[0]   = (Part){
      .name    = "fluid",
      .field   = {"velocity", "pressure", "mesh_velocity"},
      .unit    = {UnitName(units, UNIT_VELOCITY), UnitName(units, UNIT_PRESSURE), UnitName(units, UNIT_VELOCITY)},
      .nfields = moving ? 3 : 2,
      .nc      = {-1, 1, -1}
  };
  w->part[1] = (Part){
    .name    = "structure",
    .field   = {"displacement", "velocity"},
    .unit    = {UnitName(units, UNIT_LENGTH), UnitName(units, UNIT_VELOCITY)},
    .nfields = 2,
    .nc      = {-1, -1},
    .deform  = PETSC_TRUE
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
    PetscCall(FieldsWriterSources(w, p, PETSC_FALSE, &src));
    PetscCall(FieldsGridSetUp(comm, &w->part[p], &src.grid, w->all_nodes));
    for (PetscInt f = 0; f < w->part[p].nfields; ++f)
      if (w->part[p].nc[f] < 0) w->part[p].nc[f] = w->part[p].dim;
  }
  PetscCall(FieldsDerivedCreate(w));
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
  for (PetscInt p = 0; p < 3; ++p) {
    Sources src;
    char    group[64];

    if (!w->part[p].nnodes) continue; /* not in this scene */
    PetscCall(FieldsWriterSources(w, p, PETSC_TRUE, &src));
    PetscCall(PetscSNPrintf(group, sizeof(group), "/%s/step_%05" PetscInt_FMT, w->part[p].name, step));
    PetscCall(PartWrite(w, &w->part[p], &src, group, w->t0 + step * w->dt));
    PetscCall(FieldsWriterSourcesRestore(&src));
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
  const char *topology = P->polytope == DM_POLYTOPE_SEGMENT       ? "Polyline"
                       : P->polytope == DM_POLYTOPE_TRIANGLE      ? "Triangle"
                       : P->polytope == DM_POLYTOPE_QUADRILATERAL ? "Quadrilateral"
                       : P->polytope == DM_POLYTOPE_TETRAHEDRON   ? "Tetrahedron"
                                                                  : "Hexahedron";
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
  PetscCall(XdmfItem(comm, fp, "          ", P->nnodes, P->dim, "Float", sizeof(PetscScalar), path));
  PetscCall(PetscFPrintf(comm, fp, "        </Geometry>\n"));
  for (PetscInt k = 1; k <= P->nfields; ++k) {
    const char *name;
    PetscInt    columns;

    FieldsDataset(P, k, &name, &columns);
    PetscCall(PetscFPrintf(comm, fp, "        <Attribute Name=\"%s\" AttributeType=\"%s\" Center=\"Node\">\n", name,
                           columns == 9 ? "Tensor" : columns == 3 ? "Vector" : "Scalar"));
    PetscCall(PetscFPrintf(comm, fp, "          <Information Name=\"unit\" Value=\"%s\"/>\n",
                           P->unit[k - 1] ? P->unit[k - 1] : "nondimensional"));
    PetscCall(PetscSNPrintf(path, sizeof(path), "/%s/step_%05" PetscInt_FMT "/%s", P->name, step, name));
    PetscCall(XdmfItem(comm, fp, "          ", P->nnodes, columns, "Float", sizeof(PetscScalar), path));
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
    for (PetscInt p = 0; p < 3; ++p)
      if (w->part[p].nnodes) PetscCall(XdmfGrid(w->comm, xdmf.fp, &w->part[p], w->written[i]));
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
  for (PetscInt p = 0; p < 3; ++p) PetscCall(FieldsGridDestroy(&w->part[p]));
  PetscCall(FieldsDerivedDestroy(&w->derived));
  PetscCall(PetscFree(w->written));
  PetscCall(PetscFree(*writer));
  PetscFunctionReturn(0);
}
