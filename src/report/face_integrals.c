/* Integrals over the fluid's face sets as columns of probes.csv (face_integrals.h): the flow
   rate int u.n (out of the fluid), the mean pressure int p / |face set| and the force
   -int sigma n of the fluid on the face set, by the fluid's face integration on its current
   mesh; then each 0D outlet's flow rate and pressure. */
#include "face_integrals.h"
#include "mesh.h"
#include "options.h"

#define MAX_SETS 16

typedef enum {
  FLOW_RATE,
  MEAN_PRESSURE,
  FORCE,
  NUM_KINDS
} IntegralKind;

static const struct {
  const char *option, *help, *symbol;
} kinds[NUM_KINDS] = {
  {"-integrals_flow_rate", "face sets (names or numbers, comma-separated) whose flow rate out of the fluid probes.csv records",
   "Q"},
  {"-integrals_mean_pressure", "face sets whose mean pressure (int p over the face set / its area) probes.csv records",
   "p_mean"},
  {"-integrals_force", "face sets whose force from the fluid (-int sigma n) probes.csv records", "F"},
};

struct _p_FaceIntegrals {
  MPI_Comm      comm;
  PetscInt      dim;
  Fluid         fluid;
  PetscInt      nsets[NUM_KINDS], sets[NUM_KINDS][MAX_SETS];
  PetscInt      noutlets;
  PetscInt      ncolumns, nfluid_ranks;
  char        **names;
  UnitDimension units[NUM_KINDS * MAX_SETS * 3 + 2 * FSIOPT_MAX_OUTLETS];
};

static PetscErrorCode AddColumn(FaceIntegrals fi, const char name[], UnitDimension unit)
{
  PetscFunctionBeginUser;
  PetscCall(PetscStrallocpy(name, &fi->names[fi->ncolumns]));
  fi->units[fi->ncolumns++] = unit;
  PetscFunctionReturn(0);
}

/* The face sets an option names, checked against the fluid mesh's names */
static PetscErrorCode ReadSets(FaceIntegrals fi, PetscOptionItems *PetscOptionsObject, IntegralKind k, PetscInt nnames,
                               const MeshPhysicalName known[], char *texts[MAX_SETS])
{
  PetscInt  n = MAX_SETS;
  PetscBool given;
  char      list[512] = "";
  PetscBool present;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsStringArray(kinds[k].option, kinds[k].help, NULL, texts, &n, &given));
  PetscCall(PetscOptionsHasName(NULL, NULL, kinds[k].option, &present));
  if (!given && !present) PetscFunctionReturn(0);
  PetscCheck(given && n > 0, fi->comm, PETSC_ERR_ARG_WRONG, "option %s: expected face sets (names or numbers, comma-separated)",
             kinds[k].option);
  PetscCheck(fi->fluid || fi->nfluid_ranks, fi->comm, PETSC_ERR_ARG_INCOMP, "option %s: this scene has no fluid",
             kinds[k].option);
  for (PetscInt i = 0; i < nnames; ++i) {
    PetscCall(PetscStrlcat(list, i ? ", " : "", sizeof(list)));
    PetscCall(PetscStrlcat(list, known[i].name, sizeof(list)));
  }
  for (PetscInt i = 0; i < n; ++i) {
    PetscInt value;
    PetscCall(MeshFaceSetFind(nnames, known, texts[i], &value));
    PetscCheck(value > 0, fi->comm, PETSC_ERR_ARG_WRONG,
               "option %s: the fluid mesh has no face set %s; expected a number or one of its names (%s)",
               kinds[k].option, texts[i], nnames ? list : "none: its file has no physical names");
    fi->sets[k][i] = value;
  }
  fi->nsets[k] = n;
  PetscFunctionReturn(0);
}

PetscErrorCode FaceIntegralsCreate(MPI_Comm comm, PetscInt dim, Fluid fluid, FaceIntegrals *integrals)
{
  FaceIntegrals    fi;
  MeshPhysicalName known[64];
  PetscInt         nknown = 0;
  char            *texts[NUM_KINDS][MAX_SETS];
  const PhysicsData *data = NULL;
  const UnitDimension flow = dim == 2 ? UNIT_FLOW_RATE_PER_DEPTH : UNIT_FLOW_RATE,
                      force = dim == 2 ? UNIT_FORCE_PER_DEPTH : UNIT_FORCE;

  PetscFunctionBeginUser;
  *integrals = NULL;
  PetscCall(PetscNew(&fi));
  fi->comm         = comm;
  fi->dim          = dim;
  fi->fluid        = fluid;
  fi->nfluid_ranks = fluid ? 1 : 0;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &fi->nfluid_ranks, 1, MPIU_INT, MPI_SUM, comm));
  if (fi->nfluid_ranks) PetscCall(MeshFaceSetNames(comm, "fluid_", dim, 64, &nknown, known));
  if (fluid) {
    PetscCall(FluidGetData(fluid, &data));
    fi->noutlets = data->n_outlets;
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &fi->noutlets, 1, MPIU_INT, MPI_MAX, comm));
  PetscOptionsBegin(comm, NULL, "Integrals over the fluid's face sets", "probes");
  for (PetscInt k = 0; k < NUM_KINDS; ++k) PetscCall(ReadSets(fi, PetscOptionsObject, (IntegralKind)k, nknown, known, texts[k]));
  PetscOptionsEnd();
  {
    PetscInt ncolumns = fi->nsets[FLOW_RATE] + fi->nsets[MEAN_PRESSURE] + dim * fi->nsets[FORCE] + 2 * fi->noutlets;
    if (!ncolumns) {
      PetscCall(PetscFree(fi));
      PetscFunctionReturn(0);
    }
    PetscCall(PetscCalloc1(ncolumns, &fi->names));
  }
  for (PetscInt k = 0; k < NUM_KINDS; ++k)
    for (PetscInt i = 0; i < fi->nsets[k]; ++i) {
      char name[128];
      if (k == FORCE)
        for (PetscInt c = 0; c < dim; ++c) {
          PetscCall(PetscSNPrintf(name, sizeof(name), "F_%c(%s)", "xyz"[c], texts[k][i]));
          PetscCall(AddColumn(fi, name, force));
        }
      else {
        PetscCall(PetscSNPrintf(name, sizeof(name), "%s(%s)", kinds[k].symbol, texts[k][i]));
        PetscCall(AddColumn(fi, name, k == FLOW_RATE ? flow : UNIT_PRESSURE));
      }
      PetscCall(PetscFree(texts[k][i]));
    }
  for (PetscInt o = 0; o < fi->noutlets; ++o) {
    char name[128];
    PetscCall(PetscSNPrintf(name, sizeof(name), "Q_outlet(%s)", data ? data->outlets[o].name : ""));
    PetscCall(AddColumn(fi, name, flow));
    PetscCall(PetscSNPrintf(name, sizeof(name), "p_outlet(%s)", data ? data->outlets[o].name : ""));
    PetscCall(AddColumn(fi, name, UNIT_PRESSURE));
  }
  *integrals = fi;
  PetscFunctionReturn(0);
}

PetscErrorCode FaceIntegralsEvaluate(FaceIntegrals fi, PetscReal out[])
{
  PetscInt column = 0;

  PetscFunctionBeginUser;
  for (PetscInt c = 0; c < fi->ncolumns; ++c) out[c] = 0;
  if (fi->fluid) {
    for (PetscInt k = 0; k < NUM_KINDS; ++k)
      for (PetscInt i = 0; i < fi->nsets[k]; ++i) {
        FluidFaceIntegral integral;
        PetscCall(FluidFaceSetIntegral(fi->fluid, 1, &fi->sets[k][i], &integral));
        if (k == FLOW_RATE) out[column++] = integral.flow_rate;
        else if (k == MEAN_PRESSURE) out[column++] = integral.area > 0 ? integral.pressure / integral.area : 0;
        else
          for (PetscInt c = 0; c < fi->dim; ++c) out[column++] = integral.force[c];
      }
    if (fi->noutlets) {
      PetscReal q[FSIOPT_MAX_OUTLETS], p[FSIOPT_MAX_OUTLETS];
      PetscCall(FluidGetOutletState(fi->fluid, q, p));
      for (PetscInt o = 0; o < fi->noutlets; ++o) {
        out[column++] = q[o];
        out[column++] = p[o];
      }
    }
  }
  /* the fluid's ranks hold the same values; the others none */
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, out, (PetscMPIInt)fi->ncolumns, MPIU_REAL, MPIU_SUM, fi->comm));
  for (PetscInt c = 0; c < fi->ncolumns; ++c) out[c] /= fi->nfluid_ranks;
  PetscFunctionReturn(0);
}

PetscErrorCode FaceIntegralsGetColumns(FaceIntegrals fi, PetscInt *n, const char *const **names,
                                       const UnitDimension **units)
{
  PetscFunctionBeginUser;
  *n = fi ? fi->ncolumns : 0;
  if (names) *names = fi ? (const char *const *)fi->names : NULL;
  if (units) *units = fi ? fi->units : NULL;
  PetscFunctionReturn(0);
}

PetscErrorCode FaceIntegralsDestroy(FaceIntegrals *integrals)
{
  PetscFunctionBeginUser;
  if (!*integrals) PetscFunctionReturn(0);
  for (PetscInt c = 0; c < (*integrals)->ncolumns; ++c) PetscCall(PetscFree((*integrals)->names[c]));
  PetscCall(PetscFree((*integrals)->names));
  PetscCall(PetscFree(*integrals));
  PetscFunctionReturn(0);
}
