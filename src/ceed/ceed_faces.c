/* Face sets of a DMPlex for libCEED (fem_ceed.h), integrated as PETSc's boundary
   integration does (DMPlexComputeBdResidualSingle): a face's terms live on the closure of its
   first supporting cell; the cell's basis is PETSc's face tabulation of the reference cell's
   face with the face's local number, at the face quadrature; the weights and normals are
   PETSc's face geometry (FaceGeometry). libCEED has one basis per operator, so the
   faces are grouped by their local number in the supporting cell: one operator per group. */
#include <petsc/private/petscimpl.h> /* PetscObjectStateGet */
#include "fem_ceed.h"
#include "qfunctions_mass.h"

/* the cells' rows of a field's restriction (DMPlexGetLocalOffsets) for the supporting cells */
static PetscErrorCode CellsRestriction(Ceed ceed, DM dm, PetscInt field, PetscInt n, const PetscInt cells[],
                                       CeedElemRestriction *restriction)
{
  PetscInt ncells, cell_size, ncomp, l_size, *offsets, cstart;
  CeedInt *rows;

  PetscFunctionBeginUser;
  PetscCall(DMPlexGetHeightStratum(dm, 0, &cstart, NULL));
  PetscCall(DMPlexGetLocalOffsets(dm, NULL, 0, 0, field, &ncells, &cell_size, &ncomp, &l_size, &offsets));
  PetscCall(PetscMalloc1(n * cell_size, &rows));
  for (PetscInt e = 0; e < n; ++e) {
    const PetscInt c = cells[e] - cstart;
    PetscCheck(c >= 0 && c < ncells, PETSC_COMM_SELF, PETSC_ERR_PLIB,
               "libCEED faces: cell %" PetscInt_FMT " out of range", cells[e]);
    for (PetscInt i = 0; i < cell_size; ++i) rows[e * cell_size + i] = (CeedInt)offsets[c * cell_size + i];
  }
  PetscCallCeed(ceed, CeedElemRestrictionCreate(ceed, (CeedInt)n, (CeedInt)cell_size, (CeedInt)ncomp, 1, l_size,
                                                CEED_MEM_HOST, CEED_COPY_VALUES, rows, restriction));
  PetscCall(PetscFree(rows));
  PetscCall(PetscFree(offsets));
  PetscFunctionReturn(0);
}

/* the scalar basis of fe's face tabulation on the reference cell's face `face` (PETSc orders
   its functions node by node, one per component) */
static PetscErrorCode FaceBasis(Ceed ceed, DM dm, PetscFE fe, PetscInt face, CeedBasis *basis)
{
  PetscTabulation  T;
  PetscQuadrature  quadrature;
  PetscInt         dim, nq;
  const PetscReal *weights;
  CeedScalar      *interp, *grad, *qref, *qweight;
  CeedElemTopology topology;
  DMPolytopeType   type;
  PetscInt         cstart;

  PetscFunctionBeginUser;
  PetscCall(DMGetDimension(dm, &dim));
  PetscCall(PetscFEGetFaceQuadrature(fe, &quadrature));
  PetscCall(PetscQuadratureGetData(quadrature, NULL, NULL, &nq, NULL, &weights));
  PetscCall(PetscFEGetFaceTabulation(fe, 1, &T));
  PetscCheck(T->Np == nq && face < T->Nr, PETSC_COMM_SELF, PETSC_ERR_PLIB, "libCEED faces: unexpected face tabulation");
  PetscCall(DMPlexGetHeightStratum(dm, 0, &cstart, NULL));
  PetscCall(DMPlexGetCellType(dm, cstart, &type));
  topology = type == DM_POLYTOPE_TRIANGLE      ? CEED_TOPOLOGY_TRIANGLE
           : type == DM_POLYTOPE_QUADRILATERAL ? CEED_TOPOLOGY_QUAD
           : type == DM_POLYTOPE_TETRAHEDRON   ? CEED_TOPOLOGY_TET
                                               : CEED_TOPOLOGY_HEX;
  {
    const PetscInt   nb = T->Nb, nc = T->Nc, nodes = nb / nc;
    const PetscReal *values = T->T[0] + face * nq * nb * nc, *derivatives = T->T[1] + face * nq * nb * nc * dim;
    PetscCall(PetscCalloc4(nq * nodes, &interp, dim * nq * nodes, &grad, nq * dim, &qref, nq, &qweight));
    for (PetscInt q = 0; q < nq; ++q) {
      for (PetscInt s = 0; s < nodes; ++s) {
        const PetscInt function = q * nb + s * nc;
        interp[q * nodes + s]   = values[function * nc];
        for (PetscInt d = 0; d < dim; ++d) grad[(d * nq + q) * nodes + s] = derivatives[function * nc * dim + d];
      }
      qweight[q] = weights[q]; /* qref: the points in the cell are not needed and left zero */
    }
    PetscCallCeed(ceed, CeedBasisCreateH1(ceed, topology, (CeedInt)nc, (CeedInt)nodes, (CeedInt)nq, interp, grad, qref,
                                          qweight, basis));
    PetscCall(PetscFree4(interp, grad, qref, qweight));
  }
  PetscFunctionReturn(0);
}

/* What PETSc creates and caches the first time FaceGeometry and DMPlexGetLocalOffsets run,
   made on every rank of the DM (those run on the ranks with faces only): the coordinate field,
   the face (height 1) spaces of the coordinates' and the field's elements, and the sections
   (building them completes the boundary labels, a collective). A PETSc object created on
   some ranks of a communicator only takes a tag the others do not, and their next
   collective hangs (-check_rank_sync). */
PetscErrorCode FEMFacesMakeSharedObjects(DM dm, PetscFE fe)
{
  DMField      coordinates;
  DM           cdm;
  PetscObject  disc = NULL;
  PetscFE      face;
  PetscSection section;

  PetscFunctionBeginUser;
  PetscCall(DMGetLocalSection(dm, &section));
  PetscCall(DMGetGlobalSection(dm, &section));
  PetscCall(DMGetCoordinateField(dm, &coordinates));
  PetscCall(DMGetCoordinateDM(dm, &cdm));
  PetscCall(DMGetField(cdm, 0, NULL, &disc));
  if (disc && disc->classid == PETSCFE_CLASSID) PetscCall(PetscFEGetHeightSubspace((PetscFE)disc, 1, &face));
  PetscCall(PetscFEGetHeightSubspace(fe, 1, &face));
  PetscFunctionReturn(0);
}

/* PETSc's face geometry of the faces: as DMPlexComputeBdResidualSingle computes it, with the
   coordinate field's default quadrature when it is of degree 1 (one normal and |J| per face,
   at its centre) and the face quadrature otherwise */
PetscErrorCode FEMFaceGeometry(DM dm, PetscFE fe, IS points, PetscFEGeom **geometry)
{
  DMField         coordinates;
  PetscQuadrature quadrature = NULL;
  PetscInt        degree;

  PetscFunctionBeginUser;
  PetscCall(DMGetCoordinateField(dm, &coordinates));
  PetscCall(DMFieldGetDegree(coordinates, points, NULL, &degree));
  if (degree <= 1) PetscCall(DMFieldCreateDefaultQuadrature(coordinates, points, &quadrature));
  if (!quadrature) {
    PetscCall(PetscFEGetFaceQuadrature(fe, &quadrature));
    PetscCall(PetscObjectReference((PetscObject)quadrature));
  }
  PetscCall(DMFieldCreateFEGeom(coordinates, points, quadrature, PETSC_TRUE, geometry));
  PetscCall(PetscQuadratureDestroy(&quadrature));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedFacesCreate(DM dm, PetscFE fe, PetscInt field, DM dm_aux, DMLabel label, PetscInt nvalues,
                                  const PetscInt values[], FEMCeedFaces *faces)
{
  FEMCeedFaces o;
  IS           all = NULL;
  PetscInt     fstart, fend, n, dim;
  PetscFE      fe_aux = NULL;

  PetscFunctionBeginUser;
  PetscCall(FEMFacesMakeSharedObjects(dm, fe));
  if (dm_aux) {
    PetscSection section;
    PetscCall(DMGetLocalSection(dm_aux, &section));
    PetscCall(DMGetGlobalSection(dm_aux, &section));
  }
  PetscCall(PetscNew(&o));
  PetscCall(FEMCeedGet(&o->ceed));
  o->dm = dm;
  PetscCall(PetscObjectReference((PetscObject)fe));
  o->fe = fe;
  PetscCall(DMGetDimension(dm, &dim));
  o->dim = (CeedInt)dim;
  PetscCall(DMPlexGetHeightStratum(dm, 1, &fstart, &fend));
  for (PetscInt v = 0; v < nvalues; ++v) { /* the faces of the values, as PETSc's integration takes them */
    IS stratum;
    PetscCall(DMLabelGetStratumIS(label, values[v], &stratum));
    if (!stratum) continue;
    if (all) {
      IS both;
      PetscCall(ISExpand(all, stratum, &both));
      PetscCall(ISDestroy(&all));
      all = both;
    } else {
      all = stratum;
      PetscCall(PetscObjectReference((PetscObject)stratum));
    }
    PetscCall(ISDestroy(&stratum));
  }
  {
    const PetscInt *points;
    PetscInt        npoints = 0, *list;
    if (all) PetscCall(ISGetLocalSize(all, &npoints));
    if (all) PetscCall(ISGetIndices(all, &points));
    PetscCall(PetscMalloc1(npoints, &list));
    n = 0;
    for (PetscInt i = 0; i < npoints; ++i)
      if (points[i] >= fstart && points[i] < fend) list[n++] = points[i];
    if (all) PetscCall(ISRestoreIndices(all, &points));
    PetscCall(ISDestroy(&all));
    PetscCall(PetscSortRemoveDupsInt(&n, list));
    PetscCall(ISCreateGeneral(PETSC_COMM_SELF, n, list, PETSC_OWN_POINTER, &o->points));
  }
  o->n = n;
  if (dm_aux) PetscCall(DMGetField(dm_aux, 0, NULL, (PetscObject *)&fe_aux));
  {
    PetscQuadrature quadrature;
    PetscInt        nq;
    PetscCall(PetscFEGetFaceQuadrature(fe, &quadrature));
    PetscCall(PetscQuadratureGetData(quadrature, NULL, NULL, &nq, NULL, NULL));
    o->nq = (CeedInt)nq;
    if (fe_aux) {
      PetscInt nq_aux;
      PetscCall(PetscFEGetFaceQuadrature(fe_aux, &quadrature));
      PetscCall(PetscQuadratureGetData(quadrature, NULL, NULL, &nq_aux, NULL, NULL));
      PetscCheck(nq_aux == nq, PETSC_COMM_SELF, PETSC_ERR_SUP,
                 "libCEED faces: the auxiliary field needs the same face quadrature");
    }
  }
  /* the local face numbers, from PETSc's face geometry; the groups */
  PetscCall(PetscMalloc1(n, &o->group_of));
  if (n) {
    PetscFEGeom *geometry;
    PetscCall(FEMFaceGeometry(dm, fe, o->points, &geometry));
    for (PetscInt e = 0; e < n; ++e) {
      const PetscInt k = geometry->face[e][0];
      PetscCheck(k >= 0 && k < FEM_CEED_MAX_CELL_FACES, PETSC_COMM_SELF, PETSC_ERR_PLIB,
                 "libCEED faces: local face %" PetscInt_FMT, k);
      o->group_of[e] = k;
    }
    PetscCall(PetscFEGeomDestroy(&geometry));
  }
  {
    const PetscInt *points;
    PetscInt       *cells;
    PetscCall(ISGetIndices(o->points, &points));
    PetscCall(PetscMalloc1(n, &cells));
    for (PetscInt k = 0; k < FEM_CEED_MAX_CELL_FACES; ++k) {
      PetscInt m = 0;
      for (PetscInt e = 0; e < n; ++e) {
        const PetscInt *support;
        if (o->group_of[e] != k) continue;
        PetscCall(DMPlexGetSupport(dm, points[e], &support));
        cells[m++] = support[0];
      }
      if (!m) continue;
      FEMCeedFaceGroup *g = &o->groups[o->n_groups++];
      g->local_face       = k;
      g->n                = (CeedInt)m;
      PetscCall(CellsRestriction(o->ceed, dm, field, m, cells, &g->r_u));
      PetscCall(FaceBasis(o->ceed, dm, fe, k, &g->b_u));
      if (dm_aux) {
        PetscCall(CellsRestriction(o->ceed, dm_aux, 0, m, cells, &g->r_z));
        PetscCall(FaceBasis(o->ceed, dm_aux, fe_aux, k, &g->b_z));
      }
      {
        const CeedInt size = 1 + o->dim, strides[3] = {1, o->nq, o->nq * size};
        PetscCallCeed(o->ceed, CeedElemRestrictionCreateStrided(o->ceed, g->n, o->nq, size,
                                                                (CeedSize)g->n * o->nq * size, strides, &g->r_q));
        PetscCallCeed(o->ceed, CeedVectorCreate(o->ceed, (CeedSize)g->n * o->nq * size, &g->qdata));
        PetscCallCeed(o->ceed, CeedVectorSetValue(g->qdata, 0.0));
      }
    }
    PetscCall(PetscFree(cells));
    PetscCall(ISRestoreIndices(o->points, &points));
  }
  o->coordinates_state = -1;
  PetscCall(FEMCeedFacesGeometry(o));
  *faces = o;
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedFacesGeometry(FEMCeedFaces o)
{
  Vec              coordinates_local;
  PetscObjectId    id;
  PetscObjectState state;
  PetscFEGeom     *geometry;
  PetscQuadrature  quadrature;
  const PetscReal *weights;
  const CeedInt    size = 1 + o->dim;

  PetscFunctionBeginUser;
  PetscCall(FEMFacesMakeSharedObjects(o->dm, o->fe)); /* moved coordinates drop the coordinate field */
  PetscCall(DMGetCoordinatesLocal(o->dm, &coordinates_local));
  PetscCall(PetscObjectGetId((PetscObject)coordinates_local, &id));
  PetscCall(PetscObjectStateGet((PetscObject)coordinates_local, &state));
  if (id == o->coordinates_id && state == o->coordinates_state) PetscFunctionReturn(0);
  o->coordinates_id    = id;
  o->coordinates_state = state;
  if (!o->n) PetscFunctionReturn(0);
  PetscCall(PetscFEGetFaceQuadrature(o->fe, &quadrature));
  PetscCall(PetscQuadratureGetData(quadrature, NULL, NULL, NULL, NULL, &weights));
  PetscCall(FEMFaceGeometry(o->dm, o->fe, o->points, &geometry));
  {
    /* an affine face geometry holds its values at the face's first point (PetscFEGeomGetPoint) */
    const PetscInt np = geometry->numPoints, every = !geometry->isAffine && np == o->nq;
    for (PetscInt k = 0; k < o->n_groups; ++k) {
      FEMCeedFaceGroup *g = &o->groups[k];
      CeedScalar       *q;
      PetscInt          m = 0;
      PetscCallCeed(o->ceed, CeedVectorGetArrayWrite(g->qdata, CEED_MEM_HOST, &q));
      for (PetscInt e = 0; e < o->n; ++e) {
        if (o->group_of[e] != g->local_face) continue;
        for (CeedInt i = 0; i < o->nq; ++i) {
          const PetscInt p        = e * np + (every ? i : 0);
          q[m * o->nq * size + i] = weights[i] * geometry->detJ[p];
          for (CeedInt d = 0; d < o->dim; ++d) q[m * o->nq * size + (1 + d) * o->nq + i] = geometry->n[p * o->dim + d];
        }
        ++m;
      }
      PetscCallCeed(o->ceed, CeedVectorRestoreArray(g->qdata, &q));
    }
  }
  PetscCall(PetscFEGeomDestroy(&geometry));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedFacesDestroy(FEMCeedFaces *faces)
{
  FEMCeedFaces o = *faces;

  PetscFunctionBeginUser;
  if (!o) PetscFunctionReturn(0);
  for (PetscInt k = 0; k < o->n_groups; ++k) {
    FEMCeedFaceGroup *g = &o->groups[k];
    PetscCallCeed(o->ceed, CeedElemRestrictionDestroy(&g->r_u));
    PetscCallCeed(o->ceed, CeedElemRestrictionDestroy(&g->r_z));
    PetscCallCeed(o->ceed, CeedElemRestrictionDestroy(&g->r_q));
    PetscCallCeed(o->ceed, CeedBasisDestroy(&g->b_u));
    PetscCallCeed(o->ceed, CeedBasisDestroy(&g->b_z));
    PetscCallCeed(o->ceed, CeedVectorDestroy(&g->qdata));
  }
  PetscCall(ISDestroy(&o->points));
  PetscCall(PetscFree(o->group_of));
  PetscCall(PetscFEDestroy(&o->fe));
  PetscCall(PetscFree(o));
  *faces = NULL;
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedFaceMass(DM dm, DMLabel label, PetscInt value, Mat *A)
{
  FEMCeedFaces         faces;
  PetscFE              fe;
  Ceed                 ceed;
  CeedQFunction        qf;
  CeedQFunctionContext context;
  CeedOperator         ops[FEM_CEED_MAX_CELL_FACES];
  CeedSize             counts[FEM_CEED_MAX_CELL_FACES];
  SpaceShape           shape;
  PetscInt             ncomp;

  PetscFunctionBeginUser;
  PetscCall(DMGetField(dm, 0, NULL, (PetscObject *)&fe));
  PetscCall(PetscFEGetNumComponents(fe, &ncomp));
  PetscCall(FEMCeedFacesCreate(dm, fe, 0, NULL, label, 1, &value, &faces));
  ceed        = faces->ceed;
  shape.dim   = faces->dim;
  shape.ncomp = (CeedInt)ncomp;
  PetscCallCeed(ceed, CeedQFunctionContextCreate(ceed, &context));
  PetscCallCeed(ceed, CeedQFunctionContextSetData(context, CEED_MEM_HOST, CEED_COPY_VALUES, sizeof(shape), &shape));
  PetscCallCeed(ceed, CeedQFunctionCreateInterior(ceed, 1, ApplyMass, ApplyMass_loc, &qf));
  PetscCallCeed(ceed, CeedQFunctionAddInput(qf, "u", shape.ncomp, CEED_EVAL_INTERP));
  PetscCallCeed(ceed, CeedQFunctionAddInput(qf, "qdata", 1 + shape.dim, CEED_EVAL_NONE));
  PetscCallCeed(ceed, CeedQFunctionAddOutput(qf, "v", shape.ncomp, CEED_EVAL_INTERP));
  PetscCallCeed(ceed, CeedQFunctionSetContext(qf, context));
  for (PetscInt k = 0; k < faces->n_groups; ++k) {
    FEMCeedFaceGroup *g = &faces->groups[k];
    PetscCallCeed(ceed, CeedOperatorCreate(ceed, qf, NULL, NULL, &ops[k]));
    PetscCallCeed(ceed, CeedOperatorSetField(ops[k], "u", g->r_u, g->b_u, CEED_VECTOR_ACTIVE));
    PetscCallCeed(ceed, CeedOperatorSetField(ops[k], "qdata", g->r_q, CEED_BASIS_NONE, g->qdata));
    PetscCallCeed(ceed, CeedOperatorSetField(ops[k], "v", g->r_u, g->b_u, CEED_VECTOR_ACTIVE));
  }
  PetscCall(FEMCeedCreateCOOMatrix(dm, A));
  PetscCall(FEMCeedAssemblySetUp(ceed, dm, faces->n_groups, ops, *A, counts));
  PetscCall(FEMCeedAssemble(ceed, faces->n_groups, ops, counts, *A));
  PetscCall(MatAssemblyBegin(*A, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(*A, MAT_FINAL_ASSEMBLY));
  for (PetscInt k = 0; k < faces->n_groups; ++k) PetscCallCeed(ceed, CeedOperatorDestroy(&ops[k]));
  PetscCallCeed(ceed, CeedQFunctionDestroy(&qf));
  PetscCallCeed(ceed, CeedQFunctionContextDestroy(&context));
  PetscCall(FEMCeedFacesDestroy(&faces));
  PetscFunctionReturn(0);
}
