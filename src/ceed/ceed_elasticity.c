/* Vector stiffness forms through libCEED (fem_ceed.h): the structure's linear and St.
   Venant-Kirchhoff residual and tangent, and the mesh motion's harmonic and elastic
   operators with their per-cell stiffening weights (qfunctions_elasticity.h). The residual
   is applied by one operator and the Jacobian assembled from another (libCEED 0.12
   assembles an operator wrongly in some elements after it was applied to other vectors). */
#include "fem_ceed.h"
#include "logging.h"
#include "qfunctions_elasticity.h"

struct _n_FEMCeedElasticity {
  Ceed                 ceed;
  DM                   dm;
  PetscFE              fe;
  ElasticityForm       form;
  CeedElemRestriction  r_u, r_q, r_w; /* r_w: the per-cell values' */
  CeedBasis            b_u;
  CeedVector           qdata, x, f, state, weight;
  FEMCeedGeometryKey   geometry;
  CeedQFunctionContext context;
  CeedQFunction        qf_residual, qf_jacobian;
  CeedOperator         op_residual, op_jacobian;
  CeedSize             count;
};

static PetscErrorCode OperatorsCreate(FEMCeedElasticity o)
{
  Ceed          ceed = o->ceed;
  const CeedInt dim = o->form.dim, qsize = 1 + dim * dim;

  PetscFunctionBeginUser;
  PetscCallCeed(ceed,
                CeedQFunctionCreateInterior(ceed, 1, ElasticityResidual, ElasticityResidual_loc, &o->qf_residual));
  PetscCallCeed(ceed,
                CeedQFunctionCreateInterior(ceed, 1, ElasticityJacobian, ElasticityJacobian_loc, &o->qf_jacobian));
  for (PetscInt k = 0; k < 2; ++k) {
    CeedQFunction qf = k ? o->qf_jacobian : o->qf_residual;
    PetscCallCeed(ceed, CeedQFunctionAddInput(qf, "u", dim, CEED_EVAL_INTERP));
    PetscCallCeed(ceed, CeedQFunctionAddInput(qf, "du", dim * dim, CEED_EVAL_GRAD));
    PetscCallCeed(ceed, CeedQFunctionAddInput(qf, "qdata", qsize, CEED_EVAL_NONE));
    if (o->form.cell_values) PetscCallCeed(ceed, CeedQFunctionAddInput(qf, "c", o->form.cell_values, CEED_EVAL_NONE));
    if (k && o->form.svk) PetscCallCeed(ceed, CeedQFunctionAddInput(qf, "du0", dim * dim, CEED_EVAL_GRAD));
    PetscCallCeed(ceed, CeedQFunctionAddOutput(qf, "v", dim, CEED_EVAL_INTERP));
    PetscCallCeed(ceed, CeedQFunctionAddOutput(qf, "dv", dim * dim, CEED_EVAL_GRAD));
    PetscCallCeed(ceed, CeedQFunctionSetContext(qf, o->context));
  }
  for (PetscInt k = 0; k < 2; ++k) {
    CeedOperator *op = k ? &o->op_jacobian : &o->op_residual;
    PetscCallCeed(ceed, CeedOperatorCreate(ceed, k ? o->qf_jacobian : o->qf_residual, NULL, NULL, op));
    PetscCallCeed(ceed, CeedOperatorSetField(*op, "u", o->r_u, o->b_u, CEED_VECTOR_ACTIVE));
    PetscCallCeed(ceed, CeedOperatorSetField(*op, "du", o->r_u, o->b_u, CEED_VECTOR_ACTIVE));
    PetscCallCeed(ceed, CeedOperatorSetField(*op, "qdata", o->r_q, CEED_BASIS_NONE, o->qdata));
    if (o->form.cell_values) PetscCallCeed(ceed, CeedOperatorSetField(*op, "c", o->r_w, CEED_BASIS_NONE, o->weight));
    if (k && o->form.svk) PetscCallCeed(ceed, CeedOperatorSetField(*op, "du0", o->r_u, o->b_u, o->state));
    PetscCallCeed(ceed, CeedOperatorSetField(*op, "v", o->r_u, o->b_u, CEED_VECTOR_ACTIVE));
    PetscCallCeed(ceed, CeedOperatorSetField(*op, "dv", o->r_u, o->b_u, CEED_VECTOR_ACTIVE));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedElasticityCreate(DM dm, PetscBool svk, FEMCeedCellValues cells, FEMCeedElasticity *elasticity)
{
  FEMCeedElasticity o;
  PetscInt          dim;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&o));
  PetscCall(FEMCeedGet(&o->ceed));
  Ceed ceed = o->ceed;
  o->dm     = dm;
  PetscCall(DMGetDimension(dm, &dim));
  PetscCall(DMGetField(dm, 0, NULL, (PetscObject *)&o->fe));
  PetscCall(FEMCeedRestriction(ceed, dm, 0, &o->r_u));
  PetscCall(FEMCeedBasis(ceed, dm, o->fe, &o->b_u));
  PetscCall(FEMCeedGeometryFollow(ceed, dm, o->fe, &o->geometry, &o->r_q, &o->qdata));
  o->form.dim      = (CeedInt)dim;
  o->form.svk      = svk ? 1 : 0;
  o->form.cell_values = (CeedInt)cells;
  PetscCallCeed(ceed, CeedQFunctionContextCreate(ceed, &o->context));
  PetscCallCeed(ceed,
                CeedQFunctionContextSetData(o->context, CEED_MEM_HOST, CEED_COPY_VALUES, sizeof(o->form), &o->form));
  {
    CeedVector *vectors[] = {&o->x, &o->f, &o->state};
    PetscCall(FEMCeedLocalVectors(ceed, dm, 3, vectors));
  }
  PetscCall(FEMCeedPointRestriction(ceed, o->r_u, o->b_u, cells ? (CeedInt)cells : 1, &o->r_w, &o->weight));
  PetscCallCeed(ceed, CeedVectorSetValue(o->weight, 1.0));
  PetscCall(OperatorsCreate(o));
  *elasticity = o;
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedElasticitySetForm(FEMCeedElasticity o, PetscScalar mass, PetscScalar op, PetscScalar mu,
                                        PetscScalar lambda, PetscScalar harmonic)
{
  ElasticityForm *e;

  PetscFunctionBeginUser;
  PetscCallCeed(o->ceed, CeedQFunctionContextGetData(o->context, CEED_MEM_HOST, &e));
  e->mass     = mass;
  e->op       = op;
  e->mu       = mu;
  e->lambda   = lambda;
  e->harmonic = harmonic;
  PetscCallCeed(o->ceed, CeedQFunctionContextRestoreData(o->context, &e));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedElasticitySetCellValues(FEMCeedElasticity o, DM dm_cells, Vec values_local)
{
  PetscSection       section;
  const PetscScalar *w;
  CeedScalar        *c;
  CeedInt            nq;
  const CeedInt      size = o->form.cell_values;
  PetscInt           cStart, cEnd;

  PetscFunctionBeginUser;
  PetscCheck(size, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG, "libCEED elasticity: created without per-cell values");
  PetscCallCeed(o->ceed, CeedBasisGetNumQuadraturePoints(o->b_u, &nq));
  PetscCall(DMGetLocalSection(dm_cells, &section));
  PetscCall(DMPlexGetHeightStratum(dm_cells, 0, &cStart, &cEnd));
  PetscCall(VecGetArrayRead(values_local, &w));
  PetscCallCeed(o->ceed, CeedVectorGetArrayWrite(o->weight, CEED_MEM_HOST, &c));
  /* the cells in the order of DMPlexGetLocalOffsets, each value at every point
     (FEMCeedPointRestriction's strides: point, component, cell) */
  for (PetscInt cell = cStart; cell < cEnd; ++cell) {
    PetscInt off;
    PetscCall(PetscSectionGetOffset(section, cell, &off));
    for (CeedInt k = 0; k < size; ++k)
      for (CeedInt q = 0; q < nq; ++q) c[((cell - cStart) * size + k) * nq + q] = w[off + k];
  }
  PetscCallCeed(o->ceed, CeedVectorRestoreArray(o->weight, &c));
  PetscCall(VecRestoreArrayRead(values_local, &w));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedElasticityResidual(FEMCeedElasticity o, Vec xlocal, Vec flocal)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_CEED_RESIDUAL, 0, 0, 0, 0));
  PetscCall(FEMCeedGeometryFollow(o->ceed, o->dm, o->fe, &o->geometry, &o->r_q, &o->qdata));
  PetscCall(FEMCeedApply(o->ceed, 1, &o->op_residual, o->x, o->f, xlocal, flocal));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_CEED_RESIDUAL, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedElasticityCreateMatrix(FEMCeedElasticity o, Mat *A)
{
  PetscFunctionBeginUser;
  PetscCall(FEMCeedCreateCOOMatrix(o->dm, A));
  PetscCall(FEMCeedAssemblySetUp(o->ceed, o->dm, 1, &o->op_jacobian, *A, &o->count));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedElasticityJacobian(FEMCeedElasticity o, Vec xlocal, Mat A)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_CEED_JACOBIAN, 0, 0, 0, 0));
  PetscCall(FEMCeedGeometryFollow(o->ceed, o->dm, o->fe, &o->geometry, &o->r_q, &o->qdata));
  if (o->form.svk) {
    PetscCheck(xlocal, PETSC_COMM_SELF, PETSC_ERR_ARG_NULL, "libCEED elasticity: the tangent needs its state");
    PetscCall(FEMCeedVectorCopyFrom(o->ceed, o->state, xlocal));
  }
  PetscCall(FEMCeedAssemble(o->ceed, 1, &o->op_jacobian, &o->count, A));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_CEED_JACOBIAN, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedElasticityDestroy(FEMCeedElasticity *elasticity)
{
  FEMCeedElasticity o = *elasticity;

  PetscFunctionBeginUser;
  if (!o) PetscFunctionReturn(0);
  Ceed ceed = o->ceed;
  PetscCallCeed(ceed, CeedOperatorDestroy(&o->op_residual));
  PetscCallCeed(ceed, CeedOperatorDestroy(&o->op_jacobian));
  PetscCallCeed(ceed, CeedQFunctionDestroy(&o->qf_residual));
  PetscCallCeed(ceed, CeedQFunctionDestroy(&o->qf_jacobian));
  PetscCallCeed(ceed, CeedQFunctionContextDestroy(&o->context));
  PetscCallCeed(ceed, CeedVectorDestroy(&o->qdata));
  PetscCall(FEMCeedGeometryKeyDestroy(ceed, &o->geometry));
  PetscCallCeed(ceed, CeedVectorDestroy(&o->x));
  PetscCallCeed(ceed, CeedVectorDestroy(&o->f));
  PetscCallCeed(ceed, CeedVectorDestroy(&o->state));
  PetscCallCeed(ceed, CeedVectorDestroy(&o->weight));
  PetscCallCeed(ceed, CeedElemRestrictionDestroy(&o->r_u));
  PetscCallCeed(ceed, CeedElemRestrictionDestroy(&o->r_q));
  PetscCallCeed(ceed, CeedElemRestrictionDestroy(&o->r_w));
  PetscCallCeed(ceed, CeedBasisDestroy(&o->b_u));
  PetscCall(PetscFree(o));
  *elasticity = NULL;
  PetscFunctionReturn(0);
}
