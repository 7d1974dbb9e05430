/* Integrals over the fluid's face sets and regions as columns of probes.csv
   (face_integrals.h): the flow rate int u.n (out of the fluid), the mean pressure
   int p / |face set| and the force -int sigma n of the fluid on the face set, by the fluid's
   face integration on its current mesh; a region's volume, mean pressure and kinetic energy
   (fluid_region_integrals.c); then each 0D outlet's flow rate and pressure. */
#include "face_integrals.h"
#include "mesh.h"
#include "options.h"

#define MAX_SETS 16

typedef enum {
  FLOW_RATE,
  MEAN_PRESSURE,
  FORCE,
  WALL_SHEAR_STRESS,
  REGION_VOLUME,
  REGION_MEAN_PRESSURE,
  REGION_KINETIC_ENERGY,
  NUM_KINDS
} IntegralKind;
#define IsRegionKind(k) ((k) >= REGION_VOLUME)
#define ALL_CELLS       (-2) /* the region "all": FluidRegionIntegral's any negative */

static const struct {
  const char *option, *help, *symbol;
} kinds[NUM_KINDS] = {
  {"-integrals_flow_rate", "face sets (names or numbers, comma-separated) whose flow rate out of the fluid probes.csv records",
   "Q"},
  {"-integrals_mean_pressure", "face sets whose mean pressure (int p over the face set / its area) probes.csv records",
   "p_mean"},
  {"-integrals_force", "face sets whose force from the fluid (-int sigma n) probes.csv records", "F"},
  {"-integrals_wall_shear_stress", "face sets whose mean wall shear stress int |tau_w| / area (tau_w the traction's "
   "part along the face) probes.csv records", "tau_w"},
  {"-integrals_region_volume", "regions of the fluid mesh (names or numbers; all: the whole mesh) whose volume (2D: "
   "area) on the moving mesh probes.csv records", "V"},
  {"-integrals_region_mean_pressure", "regions of the fluid mesh (all: the whole mesh) whose mean pressure probes.csv "
   "records", "p_region"},
  {"-integrals_region_kinetic_energy", "regions of the fluid mesh (all: the whole mesh) whose kinetic energy "
   "int rho |u|^2/2 probes.csv records", "E_kin"},
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

/* The face sets (regions) an option names, checked against the fluid mesh's names; a
   region "all" is every cell (ALL_CELLS) */
static PetscErrorCode ReadSets(FaceIntegrals fi, PetscOptionItems *PetscOptionsObject, IntegralKind k, PetscInt nnames,
                               const MeshPhysicalName known[], char *texts[MAX_SETS])
{
  const char *what = IsRegionKind(k) ? "region" : "face set";
  PetscInt  n = MAX_SETS;
  PetscBool given;
  char      list[512] = "";
  PetscBool present;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsStringArray(kinds[k].option, kinds[k].help, NULL, texts, &n, &given));
  PetscCall(PetscOptionsHasName(NULL, NULL, kinds[k].option, &present));
  if (!given && !present) PetscFunctionReturn(0);
  PetscCheck(given && n > 0, fi->comm, PETSC_ERR_ARG_WRONG, "option %s: expected %ss (names or numbers, comma-separated)",
             kinds[k].option, what);
  PetscCheck(fi->fluid || fi->nfluid_ranks, fi->comm, PETSC_ERR_ARG_INCOMP, "option %s: this scene has no fluid",
             kinds[k].option);
  for (PetscInt i = 0; i < nnames; ++i) {
    PetscCall(PetscStrlcat(list, i ? ", " : "", sizeof(list)));
    PetscCall(PetscStrlcat(list, known[i].name, sizeof(list)));
  }
  for (PetscInt i = 0; i < n; ++i) {
    PetscInt value;
    PetscCall(MeshFaceSetFind(nnames, known, texts[i], &value));
    if (IsRegionKind(k)) { /* a region the file names (a box names none), or all */
      PetscBool named = PETSC_FALSE;
      for (PetscInt j = 0; j < nnames; ++j) named = named || known[j].value == value ? PETSC_TRUE : PETSC_FALSE;
      value = !strcmp(texts[i], "all") ? ALL_CELLS : named ? value : -1;
    }
    PetscCheck(value > 0 || value == ALL_CELLS, fi->comm, PETSC_ERR_ARG_WRONG,
               "option %s: the fluid mesh has no %s %s; expected a number or one of its names (%s%s)", kinds[k].option,
               what, texts[i], nnames ? list : "none: its file has no physical names",
               IsRegionKind(k) ? "; all: the whole mesh" : "");
    fi->sets[k][i] = value;
  }
  fi->nsets[k] = n;
  PetscFunctionReturn(0);
}

PetscErrorCode FaceIntegralsCreate(MPI_Comm comm, PetscInt dim, Fluid fluid, FaceIntegrals *integrals)
{
  FaceIntegrals    fi;
  MeshPhysicalName known[64], regions[64];
  PetscInt         nknown = 0, nregions = 0;
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
  if (fi->nfluid_ranks) {
    char      path[PETSC_MAX_PATH_LEN];
    PetscBool file;
    PetscCall(MeshFaceSetNames(comm, "fluid_", dim, 64, &nknown, known));
    PetscCall(PetscOptionsGetString(NULL, NULL, "-fluid_dm_plex_filename", path, sizeof(path), &file));
    if (file) PetscCall(MeshGmshPhysicalNames(comm, path, dim, 64, &nregions, regions));
  }
  if (fluid) {
    PetscCall(FluidGetData(fluid, &data));
    fi->noutlets = data->n_outlets;
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &fi->noutlets, 1, MPIU_INT, MPI_MAX, comm));
  PetscOptionsBegin(comm, NULL, "Integrals over the fluid's face sets and regions", "probes");
  for (PetscInt k = 0; k < NUM_KINDS; ++k)
    PetscCall(ReadSets(fi, PetscOptionsObject, (IntegralKind)k, IsRegionKind(k) ? nregions : nknown,
                       IsRegionKind(k) ? regions : known, texts[k]));
  PetscOptionsEnd();
  {
    PetscInt ncolumns = fi->nsets[FLOW_RATE] + fi->nsets[MEAN_PRESSURE] + dim * fi->nsets[FORCE] + fi->nsets[WALL_SHEAR_STRESS] +
                        2 * fi->noutlets;
    for (PetscInt k = REGION_VOLUME; k < NUM_KINDS; ++k) ncolumns += fi->nsets[k];
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
        const UnitDimension unit = k == FLOW_RATE              ? flow
                                   : k == REGION_VOLUME         ? (dim == 2 ? UNIT_AREA : UNIT_VOLUME)
                                   : k == REGION_KINETIC_ENERGY ? (dim == 2 ? UNIT_ENERGY_PER_DEPTH : UNIT_ENERGY)
                                                                : UNIT_PRESSURE;
        PetscCall(PetscSNPrintf(name, sizeof(name), "%s(%s)", kinds[k].symbol, texts[k][i]));
        PetscCall(AddColumn(fi, name, unit));
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
    /* each face set and region integrated once, whatever the kinds asked of it */
    PetscInt             nfaces = 0, nregions = 0, faces[NUM_KINDS * MAX_SETS], regions[NUM_KINDS * MAX_SETS];
    FluidFaceIntegral    face_integral[NUM_KINDS * MAX_SETS];
    FluidRegionIntegrals region_integral[NUM_KINDS * MAX_SETS];

    for (PetscInt k = 0; k < NUM_KINDS; ++k)
      for (PetscInt i = 0; i < fi->nsets[k]; ++i) {
        const PetscInt value = fi->sets[k][i];
        PetscInt       j     = 0;
        if (IsRegionKind(k)) {
          const FluidRegionIntegrals *r;
          while (j < nregions && regions[j] != value) ++j;
          if (j == nregions) {
            regions[nregions] = value;
            PetscCall(FluidRegionIntegral(fi->fluid, value, &region_integral[nregions++]));
          }
          r             = &region_integral[j];
          out[column++] = k == REGION_VOLUME ? r->volume : k == REGION_KINETIC_ENERGY ? r->kinetic
                                                                                     : r->pressure / r->volume;
        } else {
          const FluidFaceIntegral *f;
          while (j < nfaces && faces[j] != value) ++j;
          if (j == nfaces) {
            faces[nfaces] = value;
            PetscCall(FluidFaceSetIntegral(fi->fluid, 1, &value, &face_integral[nfaces++]));
          }
          f = &face_integral[j];
          if (k == FLOW_RATE) out[column++] = f->flow_rate;
          else if (k == MEAN_PRESSURE) out[column++] = f->area > 0 ? f->pressure / f->area : 0;
          else if (k == WALL_SHEAR_STRESS) out[column++] = f->area > 0 ? f->shear / f->area : 0;
          else
            for (PetscInt c = 0; c < fi->dim; ++c) out[column++] = f->force[c];
        }
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
