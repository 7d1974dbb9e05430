/* The derived fields -write_fields_derived asks for, computed at each write and only then:
   the fluid's vorticity and Q-criterion (from its velocity gradient), the wall's Cauchy
   stress and von Mises stress, and on the fluid's walls (-write_fields_walls, by default the
   interface) the traction sigma n with n out of the fluid (on the interface: the traction
   the control g stands for, as the fluid's stress gives it), its normal part n . sigma n and
   the wall shear stress, the shear the fluid exerts on the wall: (n . sigma n) n - sigma n,
   along the flow beside the wall. Gradients and stresses are nodal means of
   each cell's values (fem_nodal_average.c), so a state the space holds comes out exact; a
   wall's normal at a node is the mean of its faces' normals, weighted by their areas. */
#include "fields_impl.h"
#include "fem.h"
#include "mesh.h"
#include "units.h"
#include "fluid_constants.h"
#include "coupling.h"
#include "interface.h"

#pragma GCC diagnostic ignored "-Wunused-parameter" /* PETSc fixes the kernels' signatures */

enum {
  VORTICITY,
  Q_CRITERION,
  STRESS,
  VON_MISES,
  TRACTION,
  NORMAL_STRESS,
  WALL_SHEAR_STRESS,
  INTERFACE_TRACTION,
  NUM_DERIVED
};
static const char *const derived_names[] = {"vorticity",     "q_criterion",      "stress", "von_mises", "traction",
                                            "normal_stress", "wall_shear_stress", "interface_traction"};

struct _n_FieldsDerived {
  PetscBool       want[NUM_DERIVED];
  PetscInt        slot[NUM_DERIVED]; /* the field's number in its grid */
  FEMNodalAverage gradient;          /* the fluid's grad u */
  FEMNodalAverage stress;            /* the wall's Cauchy stress */
  DM              normals;           /* the walls' normals at the velocity's nodes */
  Vec             normal_local, normal_global;
  Vec             traction_all, traction_local; /* the control's traction: on the interface, on the walls' nodes */
  PetscInt        nwalls, walls[16];
  PetscInt        gradient_written; /* the write whose gradient is in hand, -1: none */
  PetscLogEvent   event;
  PetscReal       mu;
};

static void VelocityGradient(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                             const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[],
                             const PetscInt aOff[], const PetscInt aOff_x[], const PetscScalar a[],
                             const PetscScalar a_t[], const PetscScalar a_x[], PetscReal t, const PetscReal x[],
                             PetscInt numConstants, const PetscScalar constants[], PetscScalar f[])
{
  for (PetscInt i = 0; i < dim * dim; ++i) f[i] = u_x[uOff_x[0] + i];
}

void FieldsTransform(FieldTransform kind, PetscInt dim, PetscReal mu, const PetscScalar in[], PetscScalar out[])
{
  const PetscScalar *G = in;
  PetscScalar        sigma[9] = {0}, t[3] = {0}, tn = 0;

  switch (kind) {
  case FIELD_COPY:
    return;
  case FIELD_VORTICITY:
    if (dim == 2) out[0] = G[2] - G[1];
    else {
      out[0] = G[7] - G[5];
      out[1] = G[2] - G[6];
      out[2] = G[3] - G[1];
    }
    return;
  case FIELD_Q_CRITERION:
    out[0] = 0;
    for (PetscInt i = 0; i < dim; ++i)
      for (PetscInt j = 0; j < dim; ++j) out[0] -= G[i * dim + j] * G[j * dim + i] / 2; /* (|W|^2 - |S|^2)/2 */
    return;
  case FIELD_VON_MISES: {
    const PetscScalar *s = in, dxy = s[0] - s[4], dyz = s[4] - s[8], dzx = s[8] - s[0];
    out[0] = PetscSqrtScalar((dxy * dxy + dyz * dyz + dzx * dzx) / 2 + 3 * (s[1] * s[1] + s[5] * s[5] + s[2] * s[2]));
    return;
  }
  default: /* the walls: in = grad u, p, n */
    break;
  }
  for (PetscInt i = 0; i < dim; ++i)
    for (PetscInt j = 0; j < dim; ++j)
      sigma[i * dim + j] = mu * (G[i * dim + j] + G[j * dim + i]) - (i == j ? in[dim * dim] : 0.0);
  for (PetscInt i = 0; i < dim; ++i) {
    for (PetscInt j = 0; j < dim; ++j) t[i] += sigma[i * dim + j] * in[dim * dim + 1 + j];
    tn += t[i] * in[dim * dim + 1 + i];
  }
  if (kind == FIELD_NORMAL_STRESS) out[0] = tn;
  else
    for (PetscInt i = 0; i < dim; ++i) out[i] = kind == FIELD_TRACTION ? t[i] : tn * in[dim * dim + 1 + i] - t[i];
}

/* Appends a derived field to a grid. */
static void AddField(Part *P, FieldsDerived d, PetscInt which, PetscInt nc, FieldTransform transform, const char *unit,
                     PetscInt nsources, const PetscInt source_nc[])
{
  const PetscInt f = P->nfields++;

  d->slot[which]  = f;
  P->field[f]     = derived_names[which];
  P->nc[f]        = nc;
  P->unit[f]      = unit;
  P->transform[f] = transform;
  P->nsources[f]  = nsources;
  for (PetscInt k = 0; k < nsources; ++k) P->source_nc[f][k] = source_nc[k];
}

/* The walls' face sets: -write_fields_walls, or the interface. */
static PetscErrorCode ReadWalls(FieldWriter w, FieldsDerived d)
{
  char            *texts[16];
  PetscInt         n = 16, nnames = 0, interface = 0, dim = w->part[0].dim;
  PetscBool        given;
  MeshPhysicalName known[64];

  PetscFunctionBeginUser;
  PetscOptionsBegin(w->comm, NULL, "Field output for ParaView", "fsiopt");
  PetscCall(PetscOptionsStringArray("-write_fields_walls",
                                    "the fluid's face sets (names or numbers) where -write_fields_derived's traction, "
                                    "normal_stress and wall_shear_stress are written (default: the interface)",
                                    NULL, texts, &n, &given));
  PetscOptionsEnd();
  if (w->fluid) {
    const PhysicsData *data;
    PetscCall(FluidGetData(w->fluid, &data));
    interface = data->interface_face;
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &interface, 1, MPIU_INT, MPI_MAX, w->comm));
  if (!given) {
    PetscCheck(interface > 0, w->comm, PETSC_ERR_ARG_WRONG,
               "option -write_fields_derived: traction, normal_stress and wall_shear_stress need -write_fields_walls "
               "(the fluid's face sets) in a scene without an interface");
    d->nwalls   = 1;
    d->walls[0] = interface;
    PetscFunctionReturn(0);
  }
  PetscCall(MeshFaceSetNames(w->comm, "fluid_", dim, 64, &nnames, known));
  for (PetscInt i = 0; i < n; ++i) {
    PetscInt faces = 0;
    PetscCall(MeshFaceSetFind(nnames, known, texts[i], &d->walls[i]));
    if (w->fluid && d->walls[i] > 0) { /* a number the mesh lacks would write an empty grid */
      DM      dm;
      DMLabel label;
      PetscCall(FluidGetDM(w->fluid, &dm));
      PetscCall(DMGetLabel(dm, "Face Sets", &label));
      if (label) PetscCall(DMLabelGetStratumSize(label, d->walls[i], &faces));
    }
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &faces, 1, MPIU_INT, MPI_SUM, w->comm));
    PetscCheck(d->walls[i] > 0 && faces > 0, w->comm, PETSC_ERR_ARG_WRONG,
               "option -write_fields_walls: the fluid mesh has no face set %s; expected a name or a number of its face "
               "sets",
               texts[i]);
    PetscCall(PetscFree(texts[i]));
  }
  d->nwalls = n;
  PetscFunctionReturn(0);
}

static PetscErrorCode ReadDerived(FieldWriter w, PetscBool want[])
{
  char     *texts[NUM_DERIVED + 1];
  PetscInt  n = NUM_DERIVED + 1;
  PetscBool given;
  char      list[256] = "";

  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < NUM_DERIVED; ++k) {
    PetscCall(PetscStrlcat(list, k ? ", " : "", sizeof(list)));
    PetscCall(PetscStrlcat(list, derived_names[k], sizeof(list)));
  }
  PetscOptionsBegin(w->comm, NULL, "Field output for ParaView", "fsiopt");
  PetscCall(PetscOptionsStringArray("-write_fields_derived",
                                    "derived fields to write, comma-separated: vorticity, q_criterion (fluid), stress, "
                                    "von_mises (wall), traction, normal_stress, wall_shear_stress (the fluid's walls), "
                                    "interface_traction (the control g, coupled scenes)",
                                    NULL, texts, &n, &given));
  PetscOptionsEnd();
  for (PetscInt i = 0; given && i < n; ++i) {
    PetscInt k = 0;
    while (k < NUM_DERIVED && strcmp(texts[i], derived_names[k])) ++k;
    PetscCheck(k < NUM_DERIVED, w->comm, PETSC_ERR_ARG_WRONG, "option -write_fields_derived: unknown field %s; expected %s",
               texts[i], list);
    want[k] = PETSC_TRUE;
    PetscCall(PetscFree(texts[i]));
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode NormalsSetUp(FieldWriter w, FieldsDerived d, PetscInt degree)
{
  PetscFunctionBeginUser;
  if (!w->fluid) PetscFunctionReturn(0);
  {
    DM dm;
    PetscCall(FluidGetDM(w->fluid, &dm));
    PetscCall(DMClone(dm, &d->normals));
  }
  PetscCall(FEMCreateField(d->normals, 0, "normal", -1, degree, NULL));
  PetscCall(DMCreateDS(d->normals));
  PetscCall(DMCreateLocalVector(d->normals, &d->normal_local));
  PetscCall(VecDuplicate(d->normal_local, &d->traction_local));
  PetscCall(DMCreateGlobalVector(d->normals, &d->normal_global));
  PetscFunctionReturn(0);
}

PetscErrorCode FieldsDerivedCreate(FieldWriter w)
{
  FieldsDerived  d;
  Part          *F = &w->part[0], *S = &w->part[1], *W = &w->part[2];
  const PetscInt dim = F->nnodes ? F->dim : S->dim;
  const char    *pressure = UnitName(w->units, UNIT_PRESSURE), *time = UnitName(w->units, UNIT_TIME);
  PetscBool      walls, stresses;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&d));
  d->gradient_written = -1;
  w->derived          = d;
  PetscCall(PetscLogEventRegister("FieldsDerived", PETSC_VIEWER_CLASSID, &d->event));
  PetscCall(ReadDerived(w, d->want));
  stresses = d->want[TRACTION] || d->want[NORMAL_STRESS] || d->want[WALL_SHEAR_STRESS] ? PETSC_TRUE : PETSC_FALSE;
  walls    = stresses || d->want[INTERFACE_TRACTION] ? PETSC_TRUE : PETSC_FALSE;
  PetscCheck(!d->want[INTERFACE_TRACTION] || w->problem, w->comm, PETSC_ERR_ARG_WRONG,
             "option -write_fields_derived: interface_traction needs a coupled scene (a fluid, a structure and their "
             "interface)");
  if (d->want[INTERFACE_TRACTION]) PetscCall(InterfaceCreateVector(w->itf, &d->traction_all));
  for (PetscInt k = 0; k < NUM_DERIVED; ++k)
    PetscCheck(!d->want[k] || (k == STRESS || k == VON_MISES ? S->nnodes : F->nnodes), w->comm, PETSC_ERR_ARG_WRONG,
               "option -write_fields_derived: %s needs the %s, which this scene does not have", derived_names[k],
               k == STRESS || k == VON_MISES ? "structure" : "fluid");
  if (w->fluid && walls) {
    MeshFields fields;
    PetscCall(FluidGetMeshFields(w->fluid, &fields));
    PetscCall(NormalsSetUp(w, d, fields.degree[0]));
  }
  if (w->fluid && (d->want[VORTICITY] || d->want[Q_CRITERION] || stresses)) {
    DM         dm;
    MeshFields fields;
    PetscCall(FluidGetDM(w->fluid, &dm));
    PetscCall(FluidGetMeshFields(w->fluid, &fields));
    PetscCall(FEMNodalAverageCreate(dm, fields.degree[0], dim * dim, "velocity_gradient", VelocityGradient, &d->gradient));
    {
      PetscDS            ds;
      PetscInt           n;
      const PetscScalar *constants;
      PetscCall(DMGetDS(dm, &ds));
      PetscCall(PetscDSGetConstants(ds, &n, &constants));
      d->mu = PetscRealPart(constants[FLUID_MU]);
    }
  }
  if (w->structure && (d->want[STRESS] || d->want[VON_MISES])) {
    DM         dm;
    MeshFields fields;
    PetscCall(StructureGetDM(w->structure, &dm));
    PetscCall(StructureGetMeshFields(w->structure, &fields));
    PetscCall(FEMNodalAverageCreate(dm, fields.degree[0], 9, "cauchy_stress", StructureCauchyStress, &d->stress));
  }
  {
    const PetscInt gradient[] = {dim * dim}, tensor[] = {9}, wall[] = {dim * dim, 1, dim};
    if (d->want[VORTICITY]) AddField(F, d, VORTICITY, dim == 2 ? 1 : 3, FIELD_VORTICITY, time ? "1/s" : NULL, 1, gradient);
    if (d->want[Q_CRITERION]) AddField(F, d, Q_CRITERION, 1, FIELD_Q_CRITERION, time ? "1/s^2" : NULL, 1, gradient);
    if (d->want[STRESS]) AddField(S, d, STRESS, 9, FIELD_COPY, pressure, 1, tensor);
    if (d->want[VON_MISES]) AddField(S, d, VON_MISES, 1, FIELD_VON_MISES, pressure, 1, tensor);
    if (walls) {
      Sources src;
      *W = (Part){.name = "walls"};
      if (d->want[TRACTION]) AddField(W, d, TRACTION, dim, FIELD_TRACTION, pressure, 3, wall);
      if (d->want[NORMAL_STRESS]) AddField(W, d, NORMAL_STRESS, 1, FIELD_NORMAL_STRESS, pressure, 3, wall);
      if (d->want[WALL_SHEAR_STRESS]) AddField(W, d, WALL_SHEAR_STRESS, dim, FIELD_WALL_SHEAR_STRESS, pressure, 3, wall);
      if (d->want[INTERFACE_TRACTION]) AddField(W, d, INTERFACE_TRACTION, dim, FIELD_COPY, pressure, 1, wall + 2);
      PetscCall(ReadWalls(w, d));
      PetscCall(FieldsWriterSources(w, 2, PETSC_FALSE, &src));
      PetscCall(FieldsGridSetUp(w->comm, W, &src.grid, w->all_nodes));
    }
  }
  PetscFunctionReturn(0);
}

/* Area-weighted normals out of the fluid, summed at the walls' nodes over faces and ranks. */
static PetscErrorCode WallNormals(FieldWriter w, FieldsDerived d, const FieldsGridSources *g)
{
  PetscSection s;
  PetscScalar *a;
  PetscInt     n, *faces, dim;
  DM           dm = g->dm;

  PetscFunctionBeginUser;
  PetscCall(DMGetCoordinateDim(dm, &dim));
  PetscCall(DMGetLocalSection(d->normals, &s));
  PetscCall(FieldsGridCells(dm, g, &n, &faces));
  PetscCall(VecZeroEntries(d->normal_local));
  PetscCall(VecGetArray(d->normal_local, &a));
  for (PetscInt i = 0; i < n; ++i) {
    const PetscInt *support;
    PetscReal       area, centroid[3], normal[3], cell[3], out = 0, length = 0;
    PetscInt       *closure = NULL, m;

    PetscCall(DMPlexComputeCellGeometryFVM(dm, faces[i], &area, centroid, normal));
    PetscCall(DMPlexGetSupport(dm, faces[i], &support));
    PetscCall(DMPlexComputeCellGeometryFVM(dm, support[0], NULL, cell, NULL));
    for (PetscInt c = 0; c < dim; ++c) {
      out += (centroid[c] - cell[c]) * normal[c];
      length += normal[c] * normal[c];
    }
    length = (out < 0 ? -1 : 1) * area / PetscSqrtReal(length);
    PetscCall(DMPlexGetTransitiveClosure(dm, faces[i], PETSC_TRUE, &m, &closure));
    for (PetscInt k = 0; k < 2 * m; k += 2) {
      PetscInt ndof, off;
      PetscCall(PetscSectionGetDof(s, closure[k], &ndof));
      PetscCall(PetscSectionGetOffset(s, closure[k], &off));
      for (PetscInt c = 0; c < ndof && c < dim; ++c) a[off + c] += length * normal[c];
    }
    PetscCall(DMPlexRestoreTransitiveClosure(dm, faces[i], PETSC_TRUE, &m, &closure));
  }
  PetscCall(VecRestoreArray(d->normal_local, &a));
  PetscCall(PetscFree(faces));
  PetscCall(FEMSumOverRanks(d->normals, d->normal_local, d->normal_global));
  PetscCall(VecGetLocalSize(d->normal_local, &n));
  PetscCall(VecGetArray(d->normal_local, &a));
  for (PetscInt i = 0; i + dim <= n; i += dim) {
    PetscReal length = 0;
    for (PetscInt c = 0; c < dim; ++c) length += PetscRealPart(a[i + c] * a[i + c]);
    for (PetscInt c = 0; c < dim && length > 0; ++c) a[i + c] /= PetscSqrtReal(length);
  }
  PetscCall(VecRestoreArray(d->normal_local, &a));
  PetscFunctionReturn(0);
}

/* The control's traction at this rank's interface nodes, put at their points (collective on
   the interface's communicator). */
static PetscErrorCode InterfaceTraction(FieldWriter w, FieldsDerived d)
{
  PetscInt           n, dim = w->part[0].dim;
  const PetscInt    *points;
  const PetscScalar *g;
  PetscScalar       *a;
  PetscSection       s;

  PetscFunctionBeginUser;
  PetscCall(CouplingProblemInterfaceTraction(w->problem, d->traction_all));
  if (!d->normals) PetscFunctionReturn(0);
  PetscCall(InterfaceGetFluidNodes(w->itf, &n, &points, NULL));
  PetscCall(DMGetLocalSection(d->normals, &s));
  PetscCall(VecZeroEntries(d->traction_local));
  PetscCall(VecGetArrayRead(d->traction_all, &g));
  PetscCall(VecGetArray(d->traction_local, &a));
  for (PetscInt i = 0; i < n; ++i) {
    PetscInt off;
    PetscCall(PetscSectionGetOffset(s, points[i], &off));
    for (PetscInt c = 0; c < dim; ++c) a[off + c] = g[i * dim + c];
  }
  PetscCall(VecRestoreArray(d->traction_local, &a));
  PetscCall(VecRestoreArrayRead(d->traction_all, &g));
  PetscFunctionReturn(0);
}

static PetscErrorCode SetSource(Sources *src, PetscInt f, PetscInt k, PetscSection s, PetscInt number, Vec local)
{
  PetscFunctionBeginUser;
  src->section[f][k] = s;
  src->number[f][k]  = number;
  src->local[f][k]   = local;
  PetscFunctionReturn(0);
}

static PetscErrorCode DerivedSources(FieldWriter, PetscInt, PetscBool, Sources *);

PetscErrorCode FieldsDerivedSources(FieldWriter w, PetscInt p, PetscBool values, Sources *src)
{
  PetscFunctionBeginUser;
  if (w->derived && values) PetscCall(PetscLogEventBegin(w->derived->event, 0, 0, 0, 0));
  PetscCall(DerivedSources(w, p, values, src));
  if (w->derived && values) PetscCall(PetscLogEventEnd(w->derived->event, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

static PetscErrorCode DerivedSources(FieldWriter w, PetscInt p, PetscBool values, Sources *src)
{
  FieldsDerived d = w->derived;
  PetscSection  s;
  Vec           v = NULL;

  PetscFunctionBeginUser;
  src->mu = d ? d->mu : 0;
  if (d && p == 2 && values && d->want[INTERFACE_TRACTION]) PetscCall(InterfaceTraction(w, d));
  if (!d || !src->grid.dm) PetscFunctionReturn(0);
  if (p == 1 && d->stress) {
    if (values) {
      Vec eta;
      PetscCall(StructureGetDisplacementLocal(w->structure, &eta));
      PetscCall(FEMNodalAverageCompute(d->stress, eta, 0.0, &v));
    }
    PetscCall(FEMNodalAverageGetSection(d->stress, &s));
    for (PetscInt k = STRESS; k <= VON_MISES; ++k)
      if (d->want[k]) PetscCall(SetSource(src, d->slot[k], 0, s, -1, v));
    PetscFunctionReturn(0);
  }
  if (p == 1) PetscFunctionReturn(0);
  if (p == 2) {
    src->grid.faces  = NULL;
    src->grid.nfaces = d->nwalls;
    for (PetscInt k = 0; k < d->nwalls; ++k) src->grid.face_values[k] = d->walls[k];
    PetscCall(DMGetLabel(src->grid.dm, "Face Sets", &src->grid.faces));
    if (d->want[INTERFACE_TRACTION]) {
      PetscSection normals;
      PetscCall(DMGetLocalSection(d->normals, &normals));
      PetscCall(SetSource(src, d->slot[INTERFACE_TRACTION], 0, normals, -1, values ? d->traction_local : NULL));
    }
  }
  if (!d->gradient || (p == 0 && !d->want[VORTICITY] && !d->want[Q_CRITERION]) ||
      (p == 2 && !d->want[TRACTION] && !d->want[NORMAL_STRESS] && !d->want[WALL_SHEAR_STRESS]))
    PetscFunctionReturn(0);
  /* one gradient per write serves the fluid's grid and the walls' */
  if (values && d->gradient_written != w->nwritten) PetscCall(FEMNodalAverageCompute(d->gradient, src->borrowed, 0.0, &v));
  else if (values) PetscCall(FEMNodalAverageValue(d->gradient, &v));
  d->gradient_written = values ? w->nwritten : d->gradient_written;
  PetscCall(FEMNodalAverageGetSection(d->gradient, &s));
  if (p == 0) {
    for (PetscInt k = VORTICITY; k <= Q_CRITERION; ++k)
      if (d->want[k]) PetscCall(SetSource(src, d->slot[k], 0, s, -1, v));
    PetscFunctionReturn(0);
  }
  if (values) PetscCall(WallNormals(w, d, &src->grid));
  for (PetscInt k = TRACTION; k <= WALL_SHEAR_STRESS; ++k) {
    PetscSection fluid, normals;
    if (!d->want[k]) continue;
    PetscCall(DMGetLocalSection(src->grid.dm, &fluid));
    PetscCall(DMGetLocalSection(d->normals, &normals));
    PetscCall(SetSource(src, d->slot[k], 0, s, -1, v));
    PetscCall(SetSource(src, d->slot[k], 1, fluid, 1, src->borrowed));
    PetscCall(SetSource(src, d->slot[k], 2, normals, -1, values ? d->normal_local : NULL));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FieldsDerivedDestroy(FieldsDerived *d)
{
  PetscFunctionBeginUser;
  if (!*d) PetscFunctionReturn(0);
  PetscCall(FEMNodalAverageDestroy(&(*d)->gradient));
  PetscCall(FEMNodalAverageDestroy(&(*d)->stress));
  PetscCall(VecDestroy(&(*d)->normal_local));
  PetscCall(VecDestroy(&(*d)->traction_local));
  PetscCall(VecDestroy(&(*d)->traction_all));
  PetscCall(VecDestroy(&(*d)->normal_global));
  PetscCall(DMDestroy(&(*d)->normals));
  PetscCall(PetscFree(*d));
  PetscFunctionReturn(0);
}
