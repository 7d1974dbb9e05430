/* probes.csv (probes.h): the displacement at the scene's probe points and the scalar
   columns its caller computes, one row per step; rank 0 keeps the series for the
   quantities of summary.json and saves it in checkpoints. */
#include "probes.h"
#include "units.h"
#include "output_files.h"
#include "options.h"
#include "checkpoint.h"

struct _p_Probes {
  MPI_Comm comm;
  PetscInt npoints, dim, nextra, ncolumns;
  char (*names)[48];
  VecScatter  to_zero;
  Vec         values; /* on rank 0: npoints * dim */
  PartialFile file;
  PetscInt    nrecords, capacity; /* rank 0: the series, one row of ncolumns per record */
  PetscReal  *t, *series;
  PetscReal   window;
};

/* The global index of the first component at each point, found among the nodes. */
static PetscErrorCode FindPoints(Probes P, Vec layout, PetscInt nodes, const PetscReal coords[],
                                 const PetscReal points[][3], PetscInt index[])
{
  PetscInt start;

  PetscFunctionBeginUser;
  PetscCall(VecGetOwnershipRange(layout, &start, NULL));
  for (PetscInt p = 0; p < P->npoints; ++p) {
    PetscInt found = -1;
    for (PetscInt i = 0; i < nodes && found < 0; ++i) {
      PetscReal dist = 0;
      for (PetscInt d = 0; d < P->dim; ++d) dist = PetscMax(dist, PetscAbsReal(coords[i * P->dim + d] - points[p][d]));
      if (dist < 1e-6) found = start + i * P->dim; /* gmsh places nodes on arcs to about 1e-9 */
    }
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &found, 1, MPIU_INT, MPI_MAX, P->comm));
    PetscCheck(found >= 0, P->comm, PETSC_ERR_ARG_WRONG,
               "probe (%g, %g, %g): not a vertex of the mesh it watches (the fluid-structure interface, or the "
               "structure)",
               (double)points[p][0], (double)points[p][1], (double)(P->dim == 3 ? points[p][2] : 0));
    for (PetscInt d = 0; d < P->dim; ++d) index[p * P->dim + d] = found + d;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode ProbesCreate(MPI_Comm comm, PetscInt dim, PetscInt nodes, const PetscReal coords[], PetscInt npoints,
                            const PetscReal points[][3], PetscInt nextra, const char *const extra_names[],
                            const UnitDimension extra_units[], const char units[], const char dir[], const char name[],
                            Probes *probes)
{
  Probes      P;
  PetscMPIInt rank;
  PetscInt    column = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&P));
  P->comm     = comm;
  P->npoints  = npoints;
  P->dim      = dim;
  P->nextra   = nextra;
  P->ncolumns = npoints * dim + nextra;
  PetscCheck(P->ncolumns <= FSIOPT_MAX_QUANTITIES, comm, PETSC_ERR_ARG_OUTOFRANGE,
             "at most %d probe columns, asked for %" PetscInt_FMT, FSIOPT_MAX_QUANTITIES, P->ncolumns);
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(OptionsDeclareUnit("-quantities_window", UNIT_TIME));
  PetscOptionsBegin(comm, NULL, "Probes and the quantities of summary.json", "probes");
  PetscCall(OptionsNonNegativeReal(PetscOptionsObject, "-quantities_window",
                                   "report mean, amplitude and frequency of every probe column over the run's last T "
                                   "seconds (0: final values only)",
                                   &P->window));
  PetscOptionsEnd();
  PetscCall(PetscMalloc1(P->ncolumns, &P->names));
  for (PetscInt p = 0; p < npoints; ++p)
    for (PetscInt d = 0; d < dim; ++d, ++column) {
      if (dim == 3)
        PetscCall(PetscSNPrintf(P->names[column], sizeof(P->names[column]), "d%c(%g;%g;%g)", "xyz"[d],
                                (double)points[p][0], (double)points[p][1], (double)points[p][2]));
      else
        PetscCall(PetscSNPrintf(P->names[column], sizeof(P->names[column]), "d%c(%g;%g)", "xyz"[d],
                                (double)points[p][0], (double)points[p][1]));
    }
  for (PetscInt e = 0; e < nextra; ++e, ++column)
    PetscCall(PetscStrncpy(P->names[column], extra_names[e], sizeof(P->names[column])));
  if (npoints) {
    PetscInt *index;
    IS        from;
    Vec       layout;

    /* a vector of the layout the displacements come in: nodes blocks of dim on this rank */
    PetscCall(VecCreateMPIWithArray(comm, 1, nodes * dim, PETSC_DECIDE, NULL, &layout));
    PetscCall(PetscMalloc1(npoints * dim, &index));
    PetscCall(FindPoints(P, layout, nodes, coords, points, index));
    PetscCall(VecCreateSeq(PETSC_COMM_SELF, rank ? 0 : npoints * dim, &P->values));
    PetscCall(ISCreateGeneral(comm, rank ? 0 : npoints * dim, index, PETSC_COPY_VALUES, &from));
    PetscCall(VecScatterCreate(layout, from, P->values, NULL, &P->to_zero));
    PetscCall(ISDestroy(&from));
    PetscCall(PetscFree(index));
    PetscCall(VecDestroy(&layout));
  }
  PetscCall(PartialFileOpen(comm, dir, name, &P->file));
  {
    /* each header says its unit in the scene's system: "dy(1.5;1) [cm]"; the forces on a 2D
       body are per unit depth */
    const char *time = UnitName(units, UNIT_TIME);
    PetscCall(PetscFPrintf(comm, P->file.fp, "t [%s]", time ? time : "1"));
    for (PetscInt c = 0; c < P->ncolumns; ++c) {
      const PetscInt      e = c - npoints * dim;
      const UnitDimension d = e < 0 ? UNIT_LENGTH : extra_units ? extra_units[e] : dim == 2 ? UNIT_FORCE_PER_DEPTH : UNIT_FORCE;
      const char         *unit = UnitName(units, d);
      PetscCall(PetscFPrintf(comm, P->file.fp, ",%s [%s]", P->names[c], unit ? unit : "1"));
    }
  }
  PetscCall(PetscFPrintf(comm, P->file.fp, "\n"));
  *probes = P;
  PetscFunctionReturn(0);
}

/* Rank 0: one row of every column, kept and written. */
static PetscErrorCode AppendRow(Probes P, PetscReal t, const PetscReal row[])
{
  PetscFunctionBeginUser;
  if (P->nrecords == P->capacity) {
    P->capacity = PetscMax(64, 2 * P->capacity);
    PetscCall(PetscRealloc(sizeof(PetscReal) * P->capacity, &P->t));
    PetscCall(PetscRealloc(sizeof(PetscReal) * P->capacity * P->ncolumns, &P->series));
  }
  P->t[P->nrecords] = t;
  PetscCall(PetscArraycpy(&P->series[P->nrecords * P->ncolumns], row, P->ncolumns));
  P->nrecords++;
  PetscCall(PetscFPrintf(PETSC_COMM_SELF, P->file.fp, "%.10g", (double)t));
  for (PetscInt c = 0; c < P->ncolumns; ++c)
    PetscCall(PetscFPrintf(PETSC_COMM_SELF, P->file.fp, ",%.12e", (double)row[c]));
  PetscCall(PetscFPrintf(PETSC_COMM_SELF, P->file.fp, "\n"));
  PetscFunctionReturn(0);
}

PetscErrorCode ProbesRecord(Probes P, PetscReal t, Vec displacement, const PetscReal extra[])
{
  PetscMPIInt rank;
  PetscReal   row[FSIOPT_MAX_QUANTITIES];

  PetscFunctionBeginUser;
  if (P->npoints) {
    PetscCall(VecScatterBegin(P->to_zero, displacement, P->values, INSERT_VALUES, SCATTER_FORWARD));
    PetscCall(VecScatterEnd(P->to_zero, displacement, P->values, INSERT_VALUES, SCATTER_FORWARD));
  }
  PetscCallMPI(MPI_Comm_rank(P->comm, &rank));
  if (!rank) {
    if (P->npoints) {
      const PetscScalar *v;
      PetscCall(VecGetArrayRead(P->values, &v));
      for (PetscInt i = 0; i < P->npoints * P->dim; ++i) row[i] = PetscRealPart(v[i]);
      PetscCall(VecRestoreArrayRead(P->values, &v));
    }
    for (PetscInt e = 0; e < P->nextra; ++e) row[P->npoints * P->dim + e] = extra[e];
    PetscCall(AppendRow(P, t, row));
  }
  PetscCall(PartialFileCheck(&P->file)); /* the row reached the disk, or the run stops here */
  PetscFunctionReturn(0);
}

/* The series so far: one vector on rank 0, rows of (t, columns). Loading writes its rows
   to this run's probes.csv, which then starts at the beginning of the run. */
PetscErrorCode ProbesCheckpoint(Probes P, Checkpoint cp, PetscBool load)
{
  PetscMPIInt  rank;
  PetscInt     records = P->nrecords, columns = P->ncolumns;
  Vec          series;
  PetscScalar *a;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(P->comm, &rank));
  PetscCall(CheckpointPushGroup(cp, "/probes"));
  PetscCallMPI(MPI_Bcast(&records, 1, MPIU_INT, 0, P->comm));
  PetscCall(CheckpointInt(cp, "records", &records, load));
  PetscCall(CheckpointInt(cp, "columns", &columns, load));
  PetscCheck(columns == P->ncolumns, P->comm, PETSC_ERR_FILE_UNEXPECTED,
             "option -restart: the checkpoint's probes have %" PetscInt_FMT " columns, this run's %" PetscInt_FMT,
             columns, P->ncolumns);
  PetscCall(VecCreateMPI(P->comm, rank ? 0 : records * (columns + 1), PETSC_DETERMINE, &series));
  if (!load) {
    PetscCall(VecGetArray(series, &a));
    for (PetscInt r = 0; r < records && !rank; ++r) {
      a[r * (columns + 1)] = P->t[r];
      for (PetscInt c = 0; c < columns; ++c) a[r * (columns + 1) + 1 + c] = P->series[r * columns + c];
    }
    PetscCall(VecRestoreArray(series, &a));
  }
  PetscCall(CheckpointVec(cp, "series", series, load));
  PetscCall(CheckpointPopGroup(cp));
  if (load && !rank) {
    const PetscScalar *b;
    PetscReal          row[FSIOPT_MAX_QUANTITIES];

    PetscCall(VecGetArrayRead(series, &b));
    for (PetscInt r = 0; r < records; ++r) {
      for (PetscInt c = 0; c < columns; ++c) row[c] = PetscRealPart(b[r * (columns + 1) + 1 + c]);
      PetscCall(AppendRow(P, PetscRealPart(b[r * (columns + 1)]), row));
    }
    PetscCall(VecRestoreArrayRead(series, &b));
  }
  PetscCall(VecDestroy(&series));
  PetscFunctionReturn(0);
}

PetscErrorCode ProbesQuantities(Probes P, QuantityTable *table)
{
  PetscReal     *column;
  const PetscInt first = table->n;

  PetscFunctionBeginUser;
  PetscCheck(first + P->ncolumns <= FSIOPT_MAX_QUANTITIES, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE,
             "at most %d quantities, asked for %" PetscInt_FMT, FSIOPT_MAX_QUANTITIES, first + P->ncolumns);
  table->n      = first + P->ncolumns;
  table->window = P->window;
  PetscCall(PetscMalloc1(P->nrecords + 1, &column));
  for (PetscInt c = 0; c < P->ncolumns; ++c) {
    const PetscInt q = first + c;
    for (PetscInt r = 0; r < P->nrecords; ++r) column[r] = P->series[r * P->ncolumns + c];
    PetscCall(PetscStrncpy(table->name[q], P->names[c], sizeof(table->name[q])));
    PetscCall(QuantityAnalyze(P->nrecords, P->t, column, P->window, &table->final[q], &table->mean[q],
                              &table->amplitude[q], &table->frequency[q]));
  }
  PetscCall(PetscFree(column));
  PetscFunctionReturn(0);
}

PetscErrorCode ProbesClose(Probes *probes, PetscBool complete)
{
  Probes P = *probes;

  PetscFunctionBeginUser;
  if (!P) PetscFunctionReturn(0);
  PetscCall(PartialFileClose(&P->file, complete));
  PetscCall(VecScatterDestroy(&P->to_zero));
  PetscCall(VecDestroy(&P->values));
  PetscCall(PetscFree(P->names));
  PetscCall(PetscFree(P->t));
  PetscCall(PetscFree(P->series));
  PetscCall(PetscFree(*probes));
  PetscFunctionReturn(0);
}
