/* Restrictions, bases and coordinates of a DMPlex for libCEED (fem_ceed.h). PETSc's own
   tabulation at its own quadrature is handed to CeedBasisCreateH1, so that a libCEED
   operator and PETSc's integration see the same numbers at the same points. */
#include <petsc/private/petscimpl.h> /* PetscObjectStateGet */
#include "fem_ceed.h"
#include "qfunctions_geometry.h"

PetscErrorCode FEMCeedRestriction(Ceed ceed, DM dm, PetscInt field, CeedElemRestriction *restriction)
{
  PetscInt ncells, cell_size, ncomp, l_size, *offsets;
  CeedInt *ceed_offsets;

  PetscFunctionBeginUser;
  PetscCall(DMPlexGetLocalOffsets(dm, NULL, 0, 0, field, &ncells, &cell_size, &ncomp, &l_size, &offsets));
  PetscCall(PetscMalloc1(ncells * cell_size, &ceed_offsets));
  for (PetscInt i = 0; i < ncells * cell_size; ++i) ceed_offsets[i] = (CeedInt)offsets[i];
  PetscCallCeed(ceed, CeedElemRestrictionCreate(ceed, ncells, cell_size, ncomp, 1, l_size, CEED_MEM_HOST,
                                                CEED_COPY_VALUES, ceed_offsets, restriction));
  PetscCall(PetscFree(ceed_offsets));
  PetscCall(PetscFree(offsets));
  PetscFunctionReturn(0);
}

static PetscErrorCode Topology(DM dm, CeedElemTopology *topology)
{
  PetscInt       start;
  DMPolytopeType type;

  PetscFunctionBeginUser;
  PetscCall(DMPlexGetHeightStratum(dm, 0, &start, NULL));
  PetscCall(DMPlexGetCellType(dm, start, &type));
  switch (type) {
  case DM_POLYTOPE_TRIANGLE:
    *topology = CEED_TOPOLOGY_TRIANGLE;
    break;
  case DM_POLYTOPE_QUADRILATERAL:
    *topology = CEED_TOPOLOGY_QUAD;
    break;
  case DM_POLYTOPE_TETRAHEDRON:
    *topology = CEED_TOPOLOGY_TET;
    break;
  case DM_POLYTOPE_HEXAHEDRON:
    *topology = CEED_TOPOLOGY_HEX;
    break;
  default:
    SETERRQ(PetscObjectComm((PetscObject)dm), PETSC_ERR_SUP, "libCEED operators: cells of type %s are not supported",
            DMPolytopeTypes[type]);
  }
  PetscFunctionReturn(0);
}

/* The scalar basis of a tabulation of an Nc-component PetscFE: PETSc orders its functions
   node by node, one per component, each nonzero in its own component only. */
static PetscErrorCode BasisFromTabulation(Ceed ceed, DM dm, PetscTabulation T, PetscInt dim, const PetscReal points[],
                                          const PetscReal weights[], CeedBasis *basis)
{
  const PetscInt   nq = T->Np, nb = T->Nb, nc = T->Nc, nodes = nb / nc;
  CeedScalar      *interp, *grad, *qref, *qweight;
  CeedElemTopology topology = CEED_TOPOLOGY_QUAD;

  PetscFunctionBeginUser;
  PetscCall(Topology(dm, &topology));
  PetscCall(PetscMalloc4(nq * nodes, &interp, dim * nq * nodes, &grad, nq * dim, &qref, nq, &qweight));
  for (PetscInt q = 0; q < nq; ++q) {
    for (PetscInt s = 0; s < nodes; ++s) {
      const PetscInt function = q * nb + s * nc; /* the node's function of component 0 */
      interp[q * nodes + s]   = T->T[0][function * nc];
      for (PetscInt d = 0; d < dim; ++d) grad[(d * nq + q) * nodes + s] = T->T[1][function * nc * dim + d];
    }
    for (PetscInt d = 0; d < dim; ++d) qref[q * dim + d] = points[q * dim + d];
    qweight[q] = weights[q];
  }
  PetscCallCeed(ceed, CeedBasisCreateH1(ceed, topology, nc, nodes, nq, interp, grad, qref, qweight, basis));
  PetscCall(PetscFree4(interp, grad, qref, qweight));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedBasis(Ceed ceed, DM dm, PetscFE fe, CeedBasis *basis)
{
  PetscQuadrature  quadrature;
  PetscTabulation  T;
  PetscInt         dim, nq;
  const PetscReal *points, *weights;

  PetscFunctionBeginUser;
  PetscCall(PetscFEGetQuadrature(fe, &quadrature));
  PetscCall(PetscQuadratureGetData(quadrature, &dim, NULL, &nq, &points, &weights));
  PetscCall(PetscFEGetCellTabulation(fe, 1, &T));
  PetscCall(BasisFromTabulation(ceed, dm, T, dim, points, weights, basis));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedCoordinates(Ceed ceed, DM dm, PetscFE fe, CeedElemRestriction *restriction, CeedBasis *basis,
                                  CeedVector *coordinates)
{
  DM                 cdm;
  PetscFE            coordinate_fe;
  PetscObject        field;
  PetscClassId       id = 0;
  PetscQuadrature    quadrature;
  PetscTabulation    T;
  PetscInt           dim, nq, n;
  const PetscReal   *points, *weights;
  Vec                local;
  const PetscScalar *x;

  PetscFunctionBeginUser;
  PetscCall(DMGetCoordinateDM(dm, &cdm));
  PetscCall(DMGetField(cdm, 0, NULL, &field));
  if (field) PetscCall(PetscObjectGetClassId(field, &id));
  if (id == PETSCFE_CLASSID) {
    coordinate_fe = (PetscFE)field;
    PetscCall(PetscObjectReference(field));
  } else {
    PetscInt       cdim, start;
    DMPolytopeType type;
    PetscCall(DMGetCoordinateDim(dm, &cdim));
    PetscCall(DMPlexGetHeightStratum(dm, 0, &start, NULL));
    PetscCall(DMPlexGetCellType(dm, start, &type));
    PetscCall(PetscFECreateLagrange(PETSC_COMM_SELF, cdim, cdim, DMPolytopeTypeGetNumVertices(type) == cdim + 1, 1,
                                    PETSC_DETERMINE, &coordinate_fe));
  }
  PetscCall(PetscFEGetQuadrature(fe, &quadrature));
  PetscCall(PetscQuadratureGetData(quadrature, &dim, NULL, &nq, &points, &weights));
  PetscCall(PetscFECreateTabulation(coordinate_fe, 1, nq, points, 1, &T));
  PetscCall(BasisFromTabulation(ceed, dm, T, dim, points, weights, basis));
  PetscCall(PetscTabulationDestroy(&T));
  PetscCall(PetscFEDestroy(&coordinate_fe));
  PetscCall(FEMCeedRestriction(ceed, cdm, 0, restriction));
  PetscCall(DMGetCoordinatesLocal(dm, &local));
  PetscCall(VecGetLocalSize(local, &n));
  PetscCallCeed(ceed, CeedVectorCreate(ceed, n, coordinates));
  PetscCall(VecGetArrayRead(local, &x));
  PetscCallCeed(ceed, CeedVectorSetArray(*coordinates, CEED_MEM_HOST, CEED_COPY_VALUES, (CeedScalar *)x));
  PetscCall(VecRestoreArrayRead(local, &x));
  PetscFunctionReturn(0);
}

/* The geometry every operator reads at its quadrature points, stored once per mesh:
   qdata = [w |det A|, B] with B = A^{-1} (b[j][k] = dxi_j/dx_k), 1 + dim^2 values. */
CEED_QFUNCTION(SetupGeometry)(void *ctx, CeedInt Q, const CeedScalar *const *in, CeedScalar *const *out)
{
  const CeedInt dim = *(const CeedInt *)ctx;
  CeedScalar    B[3][3];

  for (CeedInt i = 0; i < Q; ++i) {
    out[0][i] = in[1][i] * fabs(Invert(dim, in[0], i, Q, B));
    for (CeedInt j = 0; j < dim; ++j)
      for (CeedInt k = 0; k < dim; ++k) out[0][(1 + j * dim + k) * Q + i] = B[j][k];
  }
  return 0;
}

/* the operator from the coordinates to qdata, and the CeedVector of the coordinates it reads */
static PetscErrorCode GeometryOperator(Ceed ceed, DM dm, PetscFE fe, FEMCeedGeometryKey *g, CeedElemRestriction *r_q,
                                       CeedVector *qdata)
{
  CeedQFunction        qf;
  CeedQFunctionContext context;
  CeedInt              ncells, nq, dim;
  PetscInt             cdim;

  PetscFunctionBeginUser;
  PetscCall(DMGetDimension(dm, &cdim));
  dim                 = (CeedInt)cdim;
  const CeedInt qsize = 1 + dim * dim;
  PetscCall(FEMCeedCoordinates(ceed, dm, fe, &g->r_x, &g->b_x, &g->coordinates));
  PetscCallCeed(ceed, CeedElemRestrictionGetNumElements(g->r_x, &ncells));
  PetscCallCeed(ceed, CeedBasisGetNumQuadraturePoints(g->b_x, &nq));
  PetscCallCeed(ceed, CeedElemRestrictionCreateStrided(ceed, ncells, nq, qsize, (CeedSize)ncells * nq * qsize,
                                                       CEED_STRIDES_BACKEND, r_q));
  PetscCallCeed(ceed, CeedVectorCreate(ceed, (CeedSize)ncells * nq * qsize, qdata));
  PetscCallCeed(ceed, CeedQFunctionContextCreate(ceed, &context));
  PetscCallCeed(ceed, CeedQFunctionContextSetData(context, CEED_MEM_HOST, CEED_COPY_VALUES, sizeof(dim), &dim));
  PetscCallCeed(ceed, CeedQFunctionCreateInterior(ceed, 1, SetupGeometry, SetupGeometry_loc, &qf));
  PetscCallCeed(ceed, CeedQFunctionAddInput(qf, "dx", dim * dim, CEED_EVAL_GRAD));
  PetscCallCeed(ceed, CeedQFunctionAddInput(qf, "weight", 1, CEED_EVAL_WEIGHT));
  PetscCallCeed(ceed, CeedQFunctionAddOutput(qf, "qdata", qsize, CEED_EVAL_NONE));
  PetscCallCeed(ceed, CeedQFunctionSetContext(qf, context));
  PetscCallCeed(ceed, CeedOperatorCreate(ceed, qf, NULL, NULL, &g->op));
  PetscCallCeed(ceed, CeedOperatorSetField(g->op, "dx", g->r_x, g->b_x, CEED_VECTOR_ACTIVE));
  PetscCallCeed(ceed, CeedOperatorSetField(g->op, "weight", CEED_ELEMRESTRICTION_NONE, g->b_x, CEED_VECTOR_NONE));
  PetscCallCeed(ceed, CeedOperatorSetField(g->op, "qdata", *r_q, CEED_BASIS_NONE, CEED_VECTOR_ACTIVE));
  PetscCallCeed(ceed, CeedQFunctionDestroy(&qf));
  PetscCallCeed(ceed, CeedQFunctionContextDestroy(&context));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedGeometry(Ceed ceed, DM dm, PetscFE fe, CeedElemRestriction *r_q, CeedVector *qdata)
{
  FEMCeedGeometryKey g = {0};

  PetscFunctionBeginUser;
  PetscCall(FEMCeedGeometryFollow(ceed, dm, fe, &g, r_q, qdata));
  PetscCall(FEMCeedGeometryKeyDestroy(ceed, &g));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedGeometryFollow(Ceed ceed, DM dm, PetscFE fe, FEMCeedGeometryKey *g, CeedElemRestriction *r_q,
                                     CeedVector *qdata)
{
  Vec              coordinates;
  PetscObjectId    id;
  PetscObjectState state;

  PetscFunctionBeginUser;
  PetscCall(DMGetCoordinatesLocal(dm, &coordinates));
  PetscCall(PetscObjectGetId((PetscObject)coordinates, &id));
  PetscCall(PetscObjectStateGet((PetscObject)coordinates, &state));
  if (g->op && id == g->id && state == g->state) PetscFunctionReturn(0);
  if (!g->op) PetscCall(GeometryOperator(ceed, dm, fe, g, r_q, qdata));
  else PetscCall(FEMCeedVectorCopyFrom(ceed, g->coordinates, coordinates));
  PetscCallCeed(ceed, CeedOperatorApply(g->op, g->coordinates, *qdata, CEED_REQUEST_IMMEDIATE));
  g->id    = id;
  g->state = state;
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedGeometryKeyDestroy(Ceed ceed, FEMCeedGeometryKey *g)
{
  PetscFunctionBeginUser;
  PetscCallCeed(ceed, CeedOperatorDestroy(&g->op));
  PetscCallCeed(ceed, CeedVectorDestroy(&g->coordinates));
  PetscCallCeed(ceed, CeedBasisDestroy(&g->b_x));
  PetscCallCeed(ceed, CeedElemRestrictionDestroy(&g->r_x));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedPointRestriction(Ceed ceed, CeedElemRestriction cells, CeedBasis basis, CeedInt size,
                                       CeedElemRestriction *points, CeedVector *values)
{
  CeedInt ncells, nq;

  PetscFunctionBeginUser;
  PetscCallCeed(ceed, CeedElemRestrictionGetNumElements(cells, &ncells));
  PetscCallCeed(ceed, CeedBasisGetNumQuadraturePoints(basis, &nq));
  const CeedInt strides[3] = {1, nq, nq * size}; /* point, component, cell */
  PetscCallCeed(ceed, CeedElemRestrictionCreateStrided(ceed, ncells, nq, size, (CeedSize)ncells * nq * size, strides,
                                                       points));
  if (values) {
    PetscCallCeed(ceed, CeedVectorCreate(ceed, (CeedSize)ncells * nq * size, values));
    PetscCallCeed(ceed, CeedVectorSetValue(*values, 0.0));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedLocalVectors(Ceed ceed, DM dm, PetscInt n, CeedVector *vectors[])
{
  Vec      local;
  PetscInt size;

  PetscFunctionBeginUser;
  PetscCall(DMGetLocalVector(dm, &local));
  PetscCall(VecGetLocalSize(local, &size));
  PetscCall(DMRestoreLocalVector(dm, &local));
  for (PetscInt i = 0; i < n; ++i) {
    PetscCallCeed(ceed, CeedVectorCreate(ceed, size, vectors[i]));
    PetscCallCeed(ceed, CeedVectorSetValue(*vectors[i], 0.0));
  }
  PetscFunctionReturn(0);
}
