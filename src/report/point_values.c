/* Field values at any points (point_values.h): each point is located in a cell (DMLocatePoints),
   mapped to the cell's reference coordinates, and the field's finite element is tabulated
   there and applied to the cell's closure, so a Q2 or P2 field is evaluated at its full order.
   The rank that owns the cell (the lowest, for a point on a boundary between ranks) evaluates;
   a sum over the ranks hands the value to all. */
#include "point_values.h"
#include "options.h"
#include <petscsf.h>

#define MAX_POINTS 16

typedef enum {
  FLUID_VELOCITY,
  FLUID_PRESSURE,
  STRUCTURE_DISPLACEMENT,
  STRUCTURE_VELOCITY,
  NUM_KINDS
} PointKind;

static const struct {
  const char   *option, *help, *symbol;
  PetscBool     fluid, vector;
  PetscInt      field;
  UnitDimension unit;
} kinds[NUM_KINDS] = {
  {"-probes_fluid_velocity", "points x,y[,z],... where probes.csv records the fluid velocity (current configuration)",
   "u", PETSC_TRUE, PETSC_TRUE, 0, UNIT_VELOCITY},
  {"-probes_fluid_pressure", "points x,y[,z],... where probes.csv records the fluid pressure (current configuration)",
   "p", PETSC_TRUE, PETSC_FALSE, 1, UNIT_PRESSURE},
  {"-probes_structure_displacement",
   "points x,y[,z],... where probes.csv records the structure displacement (reference configuration)", "eta",
   PETSC_FALSE, PETSC_TRUE, 0, UNIT_LENGTH},
  {"-probes_structure_velocity",
   "points x,y[,z],... where probes.csv records the structure velocity (reference configuration)", "etadot", PETSC_FALSE,
   PETSC_TRUE, 0, UNIT_VELOCITY},
};

struct _p_PointValues {
  MPI_Comm      comm;
  PetscInt      dim;
  Fluid         fluid;
  Structure     structure;
  PetscInt      npoints[NUM_KINDS];
  PetscReal     points[NUM_KINDS][MAX_POINTS * 3];
  PetscInt      owner[NUM_KINDS][MAX_POINTS], cell[NUM_KINDS][MAX_POINTS]; /* where each point was found */
  PetscBool     located[NUM_KINDS]; /* the structure's points: once, in the reference configuration */
  PetscInt      ncolumns;
  char        **names;
  UnitDimension units[NUM_KINDS * MAX_POINTS * 3];
};

/* The value of `field` (nc components) at x in `cell`, from the local vector. */
static PetscErrorCode EvaluateInCell(DM dm, PetscInt field, Vec local, PetscInt cell, const PetscReal x[], PetscInt nc,
                                     PetscReal value[])
{
  PetscDS         ds;
  PetscFE         fe;
  PetscTabulation T;
  PetscScalar    *closure = NULL;
  PetscReal       reference[3];
  PetscInt        dim, offset, nb, size;

  PetscFunctionBeginUser;
  PetscCall(DMGetDimension(dm, &dim));
  PetscCall(DMGetDS(dm, &ds));
  PetscCall(PetscDSGetDiscretization(ds, field, (PetscObject *)&fe));
  PetscCall(PetscDSGetFieldOffset(ds, field, &offset)); /* a closure holds its fields one after the other */
  PetscCall(PetscFEGetDimension(fe, &nb));
  PetscCall(DMPlexCoordinatesToReference(dm, cell, 1, x, reference));
  PetscCall(PetscFECreateTabulation(fe, 1, 1, reference, 0, &T));
  PetscCall(DMPlexVecGetClosure(dm, NULL, local, cell, &size, &closure));
  for (PetscInt c = 0; c < nc; ++c) {
    PetscReal v = 0;
    for (PetscInt b = 0; b < nb; ++b) v += PetscRealPart(closure[offset + b]) * T->T[0][b * nc + c];
    value[c] = v;
  }
  PetscCall(DMPlexVecRestoreClosure(dm, NULL, local, cell, &size, &closure));
  PetscCall(PetscTabulationDestroy(&T));
  PetscFunctionReturn(0);
}

/* The rank and cell of each point of one kind: found where dm is (NULL on the other ranks),
   the lowest rank of those that found it owning it. */
static PetscErrorCode Locate(PointValues P, PointKind k, DM dm)
{
  const PetscInt n = P->npoints[k];
  PetscMPIInt    rank, size;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(P->comm, &rank));
  PetscCallMPI(MPI_Comm_size(P->comm, &size));
  for (PetscInt p = 0; p < n; ++p) P->owner[k][p] = size;
  if (dm) {
    Vec                points;
    PetscSF            located = NULL; /* DMLocatePoints creates it only when NULL */
    PetscInt           nfound;
    const PetscInt    *found;
    const PetscSFNode *cells;

    PetscCall(VecCreateSeqWithArray(PETSC_COMM_SELF, P->dim, n * P->dim, P->points[k], &points));
    /* REMOVE: the leaves are the points found, each with its cell (as DMInterpolationSetUp reads them) */
    PetscCall(DMLocatePoints(dm, points, DM_POINTLOCATION_REMOVE, &located));
    PetscCall(PetscSFGetGraph(located, NULL, &nfound, &found, &cells));
    for (PetscInt i = 0; i < nfound; ++i) {
      const PetscInt p = found ? found[i] : i;
      if (cells[i].index < 0) continue;
      P->owner[k][p] = rank;
      P->cell[k][p]  = cells[i].index;
    }
    PetscCall(PetscSFDestroy(&located));
    PetscCall(VecDestroy(&points));
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, P->owner[k], (PetscMPIInt)n, MPIU_INT, MPI_MIN, P->comm));
  for (PetscInt p = 0; p < n; ++p) {
    const PetscReal *x = &P->points[k][p * P->dim];
    PetscCheck(P->owner[k][p] < size, P->comm, PETSC_ERR_ARG_OUTOFRANGE,
               "option %s: the point (%g, %g, %g) is outside the %s's mesh", kinds[k].option, (double)x[0],
               (double)x[1], (double)(P->dim == 3 ? x[2] : 0), kinds[k].fluid ? "fluid" : "structure");
  }
  P->located[k] = PETSC_TRUE;
  PetscFunctionReturn(0);
}

/* The values of one kind at its points, evaluated by their owners and summed over comm. The
   fluid's points are located anew each time: its mesh moves. */
static PetscErrorCode EvaluateKind(PointValues P, PointKind k, DM dm, Vec local, PetscReal out[])
{
  const PetscInt n = P->npoints[k], nc = kinds[k].vector ? P->dim : 1;
  PetscMPIInt    rank;
  PetscReal      values[MAX_POINTS * 3] = {0};

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(P->comm, &rank));
  if (kinds[k].fluid || !P->located[k]) PetscCall(Locate(P, k, dm));
  for (PetscInt p = 0; p < n; ++p)
    if (P->owner[k][p] == rank)
      PetscCall(EvaluateInCell(dm, kinds[k].field, local, P->cell[k][p], &P->points[k][p * P->dim], nc, &values[p * nc]));
  PetscCallMPI(MPI_Allreduce(values, out, (PetscMPIInt)(n * nc), MPIU_REAL, MPIU_SUM, P->comm));
  PetscFunctionReturn(0);
}

PetscErrorCode PointValuesEvaluate(PointValues P, PetscReal out[])
{
  DM       fluid_dm = NULL;
  Vec      fluid_local = NULL; /* one for the fluid's velocity and pressure points */
  PetscInt column = 0;

  PetscFunctionBeginUser;
  if (P->fluid && (P->npoints[FLUID_VELOCITY] || P->npoints[FLUID_PRESSURE])) {
    Vec state;
    PetscCall(FluidGetDM(P->fluid, &fluid_dm));
    PetscCall(FluidGetSolution(P->fluid, &state));
    PetscCall(DMGetLocalVector(fluid_dm, &fluid_local));
    PetscCall(FluidGlobalToLocal(P->fluid, state, fluid_local));
  }
  for (PetscInt k = 0; k < NUM_KINDS; ++k) {
    DM  dm    = NULL;
    Vec local = NULL;

    if (!P->npoints[k]) continue;
    if (kinds[k].fluid) {
      dm    = fluid_dm;
      local = fluid_local;
    } else if (P->structure) {
      PetscCall(StructureGetDM(P->structure, &dm));
      if (k == STRUCTURE_DISPLACEMENT) PetscCall(StructureGetDisplacementLocal(P->structure, &local));
      else PetscCall(StructureGetVelocityLocal(P->structure, &local));
    }
    PetscCall(EvaluateKind(P, (PointKind)k, dm, local, &out[column]));
    if (k == STRUCTURE_VELOCITY && P->structure) PetscCall(StructureRestoreVelocityLocal(P->structure, &local));
    column += P->npoints[k] * (kinds[k].vector ? P->dim : 1);
  }
  if (fluid_local) PetscCall(DMRestoreLocalVector(fluid_dm, &fluid_local));
  PetscFunctionReturn(0);
}

/* The columns' names and units, in the order of the kinds and of their points. */
static PetscErrorCode NameColumns(PointValues P)
{
  PetscInt column = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscCalloc1(P->ncolumns, &P->names));
  for (PetscInt k = 0; k < NUM_KINDS; ++k)
    for (PetscInt p = 0; p < P->npoints[k]; ++p) {
      const PetscReal *x = &P->points[k][p * P->dim];
      char             at[96];
      if (P->dim == 3) PetscCall(PetscSNPrintf(at, sizeof(at), "(%g;%g;%g)", (double)x[0], (double)x[1], (double)x[2]));
      else PetscCall(PetscSNPrintf(at, sizeof(at), "(%g;%g)", (double)x[0], (double)x[1]));
      for (PetscInt c = 0; c < (kinds[k].vector ? P->dim : 1); ++c, ++column) {
        char name[128];
        if (kinds[k].vector) PetscCall(PetscSNPrintf(name, sizeof(name), "%s_%c%s", kinds[k].symbol, "xyz"[c], at));
        else PetscCall(PetscSNPrintf(name, sizeof(name), "%s%s", kinds[k].symbol, at));
        PetscCall(PetscStrallocpy(name, &P->names[column]));
        P->units[column] = kinds[k].unit;
      }
    }
  PetscFunctionReturn(0);
}

PetscErrorCode PointValuesCreate(MPI_Comm comm, PetscInt dim, Fluid fluid, Structure structure, PointValues *values)
{
  PointValues P;
  PetscBool   has_fluid = fluid ? PETSC_TRUE : PETSC_FALSE, has_structure = structure ? PETSC_TRUE : PETSC_FALSE;

  PetscFunctionBeginUser;
  *values = NULL;
  PetscCall(PetscNew(&P));
  P->comm      = comm;
  P->dim       = dim;
  P->fluid     = fluid;
  P->structure = structure;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &has_fluid, 1, MPIU_BOOL, MPI_LOR, comm));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &has_structure, 1, MPIU_BOOL, MPI_LOR, comm));
  for (PetscInt k = 0; k < NUM_KINDS; ++k) PetscCall(OptionsDeclareUnit(kinds[k].option, UNIT_LENGTH));
  PetscOptionsBegin(comm, NULL, "Probes at any point", "probes");
  for (PetscInt k = 0; k < NUM_KINDS; ++k) {
    PetscInt  n = MAX_POINTS * dim;
    PetscBool given;
    PetscCall(PetscOptionsRealArray(kinds[k].option, kinds[k].help, NULL, P->points[k], &n, &given));
    if (!given) continue;
    PetscCheck(n > 0 && n % dim == 0, comm, PETSC_ERR_ARG_WRONG,
               "option %s: expected the %" PetscInt_FMT " coordinates of each point, one point after the other "
               "(x1,y1%s,x2,...); got %" PetscInt_FMT " numbers",
               kinds[k].option, dim, dim == 3 ? ",z1" : "", n);
    PetscCheck(kinds[k].fluid ? has_fluid : has_structure, comm, PETSC_ERR_ARG_INCOMP,
               "option %s: this scene has no %s", kinds[k].option, kinds[k].fluid ? "fluid" : "structure");
    P->npoints[k] = n / dim;
    P->ncolumns += P->npoints[k] * (kinds[k].vector ? dim : 1);
  }
  PetscOptionsEnd();
  if (!P->ncolumns) {
    PetscCall(PetscFree(P));
    PetscFunctionReturn(0);
  }
  PetscCall(NameColumns(P));
  *values = P;
  PetscFunctionReturn(0);
}

PetscErrorCode PointValuesGetColumns(PointValues P, PetscInt *n, const char *const **names, const UnitDimension **units)
{
  PetscFunctionBeginUser;
  *n = P ? P->ncolumns : 0;
  if (names) *names = P ? (const char *const *)P->names : NULL;
  if (units) *units = P ? P->units : NULL;
  PetscFunctionReturn(0);
}

PetscErrorCode PointValuesDestroy(PointValues *values)
{
  PetscFunctionBeginUser;
  if (!*values) PetscFunctionReturn(0);
  for (PetscInt c = 0; c < (*values)->ncolumns; ++c) PetscCall(PetscFree((*values)->names[c]));
  PetscCall(PetscFree((*values)->names));
  PetscCall(PetscFree(*values));
  PetscFunctionReturn(0);
}
