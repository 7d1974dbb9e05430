/* Materials per region of the wall: -structure_region_NAME_model linear|svk and its
   _youngs_modulus, _poisson_ratio, _density (each defaulting to the -structure_ value), NAME
   a region of the mesh (a gmsh physical group of the mesh's dimension, "Cell Sets") by name
   or number. The cells' materials are an auxiliary P0 field (rho/rho_s, mu, lambda, model):
   PETSc's kernels read it (structure_kernels.c), libCEED's operator gets it per point
   (qfunctions_elasticity.h). A wall without regions pays nothing: no field, the constants. */
#include "structure_impl.h"
#include "mesh.h"
#include "options.h"

#define MAX_REGIONS 16
static const char *const suffixes[] = {"_model", "_youngs_modulus", "_poisson_ratio", "_density"};

/* the NAMEs of the -structure_region_NAME_* options given */
static PetscErrorCode RegionNames(PetscInt *count, char names[MAX_REGIONS][64])
{
  const char *family = "structure_region_";
  PetscInt    n;
  char      **left, **values;

  PetscFunctionBeginUser;
  *count = 0;
  PetscCall(PetscOptionsLeftGet(NULL, &n, &left, &values));
  for (PetscInt i = 0; i < n; ++i) {
    const size_t all = strlen(left[i]);
    char         name[64];
    PetscBool    ours, seen = PETSC_FALSE;
    PetscCall(PetscStrncmp(left[i], family, strlen(family), &ours));
    if (!ours) continue;
    name[0] = 0;
    for (size_t k = 0; k < sizeof(suffixes) / sizeof(suffixes[0]) && !name[0]; ++k) {
      const size_t ls = strlen(suffixes[k]), ln = all - strlen(family) - ls;
      if (all > strlen(family) + ls && !strcmp(left[i] + all - ls, suffixes[k]) && ln < sizeof(name)) {
        PetscCall(PetscStrncpy(name, left[i] + strlen(family), ln + 1));
      }
    }
    if (!name[0]) {
      char option[256];
      PetscCall(PetscSNPrintf(option, sizeof(option), "-%s", left[i]));
      PetscCall(PetscOptionsLeftRestore(NULL, &n, &left, &values));
      SETERRQ(PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG,
              "option %s: expected -structure_region_NAME_model, _youngs_modulus, _poisson_ratio or _density", option);
    }
    for (PetscInt k = 0; k < *count && !seen; ++k) seen = strcmp(names[k], name) ? PETSC_FALSE : PETSC_TRUE;
    if (seen) continue;
    if (*count == MAX_REGIONS) {
      PetscCall(PetscOptionsLeftRestore(NULL, &n, &left, &values));
      SETERRQ(PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE, "options -structure_region_NAME_*: at most %d regions",
              MAX_REGIONS);
    }
    PetscCall(PetscStrncpy(names[(*count)++], name, 64));
  }
  PetscCall(PetscOptionsLeftRestore(NULL, &n, &left, &values));
  PetscFunctionReturn(0);
}

/* a region's values: rho/rho_s, mu, lambda, model */
static PetscErrorCode ReadRegion(Structure s, PetscOptionItems *PetscOptionsObject, const char name[], PetscScalar m[4])
{
  const char *const *models = StructureModelNames;
  char               option[4][160];
  PetscReal   E = s->youngs_modulus, nu = s->poisson_ratio, rho = s->rho;
  PetscInt    model = s->model;

  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < 4; ++k)
    PetscCall(PetscSNPrintf(option[k], sizeof(option[k]), "-structure_region_%s%s", name, suffixes[k]));
  PetscCall(OptionsDeclareUnit(option[1], UNIT_PRESSURE));
  PetscCall(OptionsDeclareUnit(option[3], UNIT_DENSITY));
  PetscCall(PetscOptionsEList(option[0], "the region's constitutive law (default -structure_model's)", NULL, models, 2,
                              models[model], &model, NULL));
  PetscCall(OptionsPositiveReal(PetscOptionsObject, option[1], "the region's Young's modulus", &E));
  PetscCall(OptionsRealInRange(PetscOptionsObject, option[2], "the region's Poisson ratio", -1.0, 0.5, &nu));
  PetscCall(OptionsPositiveReal(PetscOptionsObject, option[3], "the region's density", &rho));
  PetscCheck(nu < 0.5, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE, "option %s: expected < 0.5 (incompressible)",
             option[2]);
  m[0] = rho / s->rho;
  m[1] = E / (2.0 * (1.0 + nu));
  m[2] = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
  m[3] = model;
  PetscFunctionReturn(0);
}

PetscErrorCode StructureMaterialsSetUp(Structure s)
{
  char             names[MAX_REGIONS][64], path[PETSC_MAX_PATH_LEN], list[512] = "";
  PetscInt         count, nknown = 0, values[MAX_REGIONS], dim, cStart, cEnd;
  MeshPhysicalName known[64];
  PetscScalar      m[MAX_REGIONS + 1][4], *a;
  PetscBool        file;
  DMLabel          cells;
  PetscSection     section;
  PetscFE          displacement;

  PetscFunctionBeginUser;
  PetscCall(RegionNames(&count, names));
  if (!count) PetscFunctionReturn(0);
  PetscCall(DMGetDimension(s->dm, &dim));
  PetscCall(PetscOptionsGetString(NULL, NULL, "-structure_dm_plex_filename", path, sizeof(path), &file));
  if (file) PetscCall(MeshGmshPhysicalNames(s->comm, path, dim, 64, &nknown, known));
  for (PetscInt i = 0; i < nknown; ++i) {
    PetscCall(PetscStrlcat(list, i ? ", " : "", sizeof(list)));
    PetscCall(PetscStrlcat(list, known[i].name, sizeof(list)));
  }
  PetscCall(DMGetLabel(s->dm, "Cell Sets", &cells));
  m[count][0] = 1.0; /* the cells of no region named: -structure_*'s material */
  m[count][1] = s->mu;
  m[count][2] = s->lambda;
  m[count][3] = s->model;
  PetscOptionsBegin(s->comm, NULL, "Structure: materials per region", "structure");
  for (PetscInt r = 0; r < count; ++r) {
    PetscCall(MeshFaceSetFind(nknown, known, names[r], &values[r]));
    PetscCheck(values[r] > 0, s->comm, PETSC_ERR_ARG_WRONG,
               "option -structure_region_%s_*: the structure mesh has no region %s; expected a number or one of its "
               "names (%s)",
               names[r], names[r], nknown ? list : "none: its file names no region");
    PetscCall(ReadRegion(s, PetscOptionsObject, names[r], m[r]));
    if (m[r][3] == (PetscScalar)STRUCTURE_SVK) s->model = STRUCTURE_SVK; /* Newton where any cell needs it */
  }
  PetscOptionsEnd();
  {
    PetscInt present = 0; /* a region number no cell carries is a mistake too */
    for (PetscInt r = 0; r < count; ++r) {
      IS       is = NULL;
      PetscInt n  = 0;
      if (cells) PetscCall(DMLabelGetStratumIS(cells, values[r], &is));
      if (is) PetscCall(ISGetLocalSize(is, &n));
      PetscCall(ISDestroy(&is));
      PetscCallMPI(MPI_Allreduce(&n, &present, 1, MPIU_INT, MPI_SUM, s->comm));
      PetscCheck(present > 0, s->comm, PETSC_ERR_ARG_WRONG,
                 "option -structure_region_%s_*: no cell of the structure mesh is in region %" PetscInt_FMT, names[r],
                 values[r]);
    }
  }
  PetscCall(DMGetField(s->dm, 0, NULL, (PetscObject *)&displacement));
  PetscCall(DMClone(s->dm, &s->dm_material));
  PetscCall(FEMCreateField(s->dm_material, 0, "material", 4, 0, displacement));
  PetscCall(DMCreateDS(s->dm_material));
  PetscCall(DMCreateLocalVector(s->dm_material, &s->material));
  PetscCall(DMGetLocalSection(s->dm_material, &section));
  PetscCall(DMPlexGetHeightStratum(s->dm_material, 0, &cStart, &cEnd));
  PetscCall(VecGetArray(s->material, &a));
  for (PetscInt c = cStart; c < cEnd; ++c) {
    PetscInt off, value = -1, r = 0;
    if (cells) PetscCall(DMLabelGetValue(cells, c, &value));
    while (r < count && values[r] != value) ++r;
    PetscCall(PetscSectionGetOffset(section, c, &off));
    for (PetscInt k = 0; k < 4; ++k) a[off + k] = m[r][k];
  }
  PetscCall(VecRestoreArray(s->material, &a));
  PetscFunctionReturn(0);
}
