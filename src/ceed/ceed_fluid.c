/* The fluid's volume operators through libCEED (fem_ceed.h): the residual of the weak form
   of fluid_kernels.c in one operator, its Jacobian one operator per block (libCEED
   assembles an operator with one active input and one active output restriction;
   ceed_fluid_jacobian.c assembles them), the pressure stabilization of equal-order pairs as
   operators of its own, built only when tau > 0, and the mesh velocity as an input only on
   moving meshes. The geometry is recomputed when the coordinates change. */
#include "ceed_fluid_impl.h"
#include "logging.h"
#include "qfunctions_fluid.h"

/* -tau (grad p, grad q) on the active pressure: the residual's term or the Jacobian's block
   (one pointwise function for all) */
static PetscErrorCode StabilizationCreate(FEMCeedFluid o, CeedVector qdata, CeedOperator *op)
{
  Ceed          ceed = o->ceed;
  const CeedInt dim  = o->volume.dim;

  PetscFunctionBeginUser;
  if (!o->qf_stabilization) {
    PetscCallCeed(ceed, CeedQFunctionCreateInterior(ceed, 1, FluidPressureStabilization, FluidPressureStabilization_loc,
                                                    &o->qf_stabilization));
    PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_stabilization, "dp", dim, CEED_EVAL_GRAD));
    PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_stabilization, "qdata", 1 + dim * dim, CEED_EVAL_NONE));
    PetscCallCeed(ceed, CeedQFunctionAddOutput(o->qf_stabilization, "dq", dim, CEED_EVAL_GRAD));
    PetscCallCeed(ceed, CeedQFunctionSetContext(o->qf_stabilization, o->context));
  }
  PetscCallCeed(ceed, CeedOperatorCreate(ceed, o->qf_stabilization, NULL, NULL, op));
  PetscCallCeed(ceed, CeedOperatorSetField(*op, "dp", o->r_p, o->b_p, CEED_VECTOR_ACTIVE));
  PetscCallCeed(ceed, CeedOperatorSetField(*op, "qdata", o->r_q, CEED_BASIS_NONE, qdata));
  PetscCallCeed(ceed, CeedOperatorSetField(*op, "dq", o->r_p, o->b_p, CEED_VECTOR_ACTIVE));
  PetscFunctionReturn(0);
}

static PetscErrorCode ResidualCreate(FEMCeedFluid o)
{
  Ceed          ceed = o->ceed;
  const CeedInt dim = o->volume.dim, qsize = 1 + dim * dim;

  PetscFunctionBeginUser;
  PetscCallCeed(ceed,
                CeedQFunctionCreateInterior(ceed, 1, FluidVolumeResidual, FluidVolumeResidual_loc, &o->qf_residual));
  PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_residual, "u", dim, CEED_EVAL_INTERP));
  PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_residual, "du", dim * dim, CEED_EVAL_GRAD));
  PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_residual, "p", 1, CEED_EVAL_INTERP));
  PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_residual, "qdata", qsize, CEED_EVAL_NONE));
  if (o->volume.moving) {
    PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_residual, "z", dim, CEED_EVAL_INTERP));
    PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_residual, "m", 1, CEED_EVAL_NONE));
  }
  PetscCallCeed(ceed, CeedQFunctionAddOutput(o->qf_residual, "v", dim, CEED_EVAL_INTERP));
  PetscCallCeed(ceed, CeedQFunctionAddOutput(o->qf_residual, "dv", dim * dim, CEED_EVAL_GRAD));
  PetscCallCeed(ceed, CeedQFunctionAddOutput(o->qf_residual, "q", 1, CEED_EVAL_INTERP));
  PetscCallCeed(ceed, CeedQFunctionSetContext(o->qf_residual, o->context));
  PetscCallCeed(ceed, CeedOperatorCreate(ceed, o->qf_residual, NULL, NULL, &o->op_residual));
  PetscCallCeed(ceed, CeedOperatorSetField(o->op_residual, "u", o->r_u, o->b_u, CEED_VECTOR_ACTIVE));
  PetscCallCeed(ceed, CeedOperatorSetField(o->op_residual, "du", o->r_u, o->b_u, CEED_VECTOR_ACTIVE));
  PetscCallCeed(ceed, CeedOperatorSetField(o->op_residual, "p", o->r_p, o->b_p, CEED_VECTOR_ACTIVE));
  PetscCallCeed(ceed, CeedOperatorSetField(o->op_residual, "qdata", o->r_q, CEED_BASIS_NONE, o->qdata));
  if (o->volume.moving) {
    PetscCallCeed(ceed, CeedOperatorSetField(o->op_residual, "z", o->r_z, o->b_z, o->mesh_velocity));
    PetscCallCeed(ceed, CeedOperatorSetField(o->op_residual, "m", o->r_w, CEED_BASIS_NONE, o->mass_weight));
  }
  PetscCallCeed(ceed, CeedOperatorSetField(o->op_residual, "v", o->r_u, o->b_u, CEED_VECTOR_ACTIVE));
  PetscCallCeed(ceed, CeedOperatorSetField(o->op_residual, "dv", o->r_u, o->b_u, CEED_VECTOR_ACTIVE));
  PetscCallCeed(ceed, CeedOperatorSetField(o->op_residual, "q", o->r_p, o->b_p, CEED_VECTOR_ACTIVE));
  if (o->volume.tau > 0) PetscCall(StabilizationCreate(o, o->qdata, &o->op_stabilization));
  PetscFunctionReturn(0);
}

/* the pointwise functions of the blocks at the passive state u0 (o->state): velocity-velocity
   (and its transpose), velocity-pressure, pressure-velocity */
static PetscErrorCode BlockQFunctionsCreate(FEMCeedFluid o)
{
  Ceed          ceed = o->ceed;
  const CeedInt dim = o->volume.dim, qsize = 1 + dim * dim;

  PetscFunctionBeginUser;
  for (PetscInt t = 0; t < 2; ++t) {
    CeedQFunction *qf = t ? &o->qf_uu_transpose : &o->qf_block[0];
    PetscCallCeed(ceed,
                  t ? CeedQFunctionCreateInterior(ceed, 1, FluidJacobianUUTranspose, FluidJacobianUUTranspose_loc, qf)
                    : CeedQFunctionCreateInterior(ceed, 1, FluidJacobianUU, FluidJacobianUU_loc, qf));
    PetscCallCeed(ceed, CeedQFunctionAddInput(*qf, "w", dim, CEED_EVAL_INTERP));
    PetscCallCeed(ceed, CeedQFunctionAddInput(*qf, "dw", dim * dim, CEED_EVAL_GRAD));
    PetscCallCeed(ceed, CeedQFunctionAddInput(*qf, "u0", dim, CEED_EVAL_INTERP));
    PetscCallCeed(ceed, CeedQFunctionAddInput(*qf, "du0", dim * dim, CEED_EVAL_GRAD));
    PetscCallCeed(ceed, CeedQFunctionAddInput(*qf, "qdata", qsize, CEED_EVAL_NONE));
    if (o->volume.moving) PetscCallCeed(ceed, CeedQFunctionAddInput(*qf, "z", dim, CEED_EVAL_INTERP));
    PetscCallCeed(ceed, CeedQFunctionAddOutput(*qf, "v", dim, CEED_EVAL_INTERP));
    PetscCallCeed(ceed, CeedQFunctionAddOutput(*qf, "dv", dim * dim, CEED_EVAL_GRAD));
    PetscCallCeed(ceed, CeedQFunctionSetContext(*qf, o->context));
  }
  PetscCallCeed(ceed, CeedQFunctionCreateInterior(ceed, 1, FluidJacobianUP, FluidJacobianUP_loc, &o->qf_block[1]));
  PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_block[1], "p", 1, CEED_EVAL_INTERP));
  PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_block[1], "qdata", qsize, CEED_EVAL_NONE));
  PetscCallCeed(ceed, CeedQFunctionAddOutput(o->qf_block[1], "dv", dim * dim, CEED_EVAL_GRAD));
  PetscCallCeed(ceed, CeedQFunctionCreateInterior(ceed, 1, FluidJacobianPU, FluidJacobianPU_loc, &o->qf_block[2]));
  PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_block[2], "du", dim * dim, CEED_EVAL_GRAD));
  PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_block[2], "qdata", qsize, CEED_EVAL_NONE));
  PetscCallCeed(ceed, CeedQFunctionAddOutput(o->qf_block[2], "q", 1, CEED_EVAL_INTERP));
  for (PetscInt b = 1; b < 3; ++b) PetscCallCeed(ceed, CeedQFunctionSetContext(o->qf_block[b], o->context));
  PetscFunctionReturn(0);
}

/* the block operators, velocity-velocity from qf_uu; the pressure-pressure one only with a
   stabilization */
PetscErrorCode FEMCeedFluidBlockOperatorsCreate(FEMCeedFluid o, CeedQFunction qf_uu, CeedVector state, CeedVector z,
                                                CeedVector qdata, CeedOperator ops[4])
{
  Ceed ceed = o->ceed;

  PetscFunctionBeginUser;
  PetscCallCeed(ceed, CeedOperatorCreate(ceed, qf_uu, NULL, NULL, &ops[0]));
  for (PetscInt b = 1; b < 3; ++b) PetscCallCeed(ceed, CeedOperatorCreate(ceed, o->qf_block[b], NULL, NULL, &ops[b]));
  PetscCallCeed(ceed, CeedOperatorSetField(ops[0], "w", o->r_u, o->b_u, CEED_VECTOR_ACTIVE));
  PetscCallCeed(ceed, CeedOperatorSetField(ops[0], "dw", o->r_u, o->b_u, CEED_VECTOR_ACTIVE));
  PetscCallCeed(ceed, CeedOperatorSetField(ops[0], "u0", o->r_u, o->b_u, state));
  PetscCallCeed(ceed, CeedOperatorSetField(ops[0], "du0", o->r_u, o->b_u, state));
  PetscCallCeed(ceed, CeedOperatorSetField(ops[0], "qdata", o->r_q, CEED_BASIS_NONE, qdata));
  if (o->volume.moving) PetscCallCeed(ceed, CeedOperatorSetField(ops[0], "z", o->r_z, o->b_z, z));
  PetscCallCeed(ceed, CeedOperatorSetField(ops[0], "v", o->r_u, o->b_u, CEED_VECTOR_ACTIVE));
  PetscCallCeed(ceed, CeedOperatorSetField(ops[0], "dv", o->r_u, o->b_u, CEED_VECTOR_ACTIVE));
  PetscCallCeed(ceed, CeedOperatorSetField(ops[1], "p", o->r_p, o->b_p, CEED_VECTOR_ACTIVE));
  PetscCallCeed(ceed, CeedOperatorSetField(ops[1], "qdata", o->r_q, CEED_BASIS_NONE, qdata));
  PetscCallCeed(ceed, CeedOperatorSetField(ops[1], "dv", o->r_u, o->b_u, CEED_VECTOR_ACTIVE));
  PetscCallCeed(ceed, CeedOperatorSetField(ops[2], "du", o->r_u, o->b_u, CEED_VECTOR_ACTIVE));
  PetscCallCeed(ceed, CeedOperatorSetField(ops[2], "qdata", o->r_q, CEED_BASIS_NONE, qdata));
  PetscCallCeed(ceed, CeedOperatorSetField(ops[2], "q", o->r_p, o->b_p, CEED_VECTOR_ACTIVE));
  if (o->volume.tau > 0) PetscCall(StabilizationCreate(o, qdata, &ops[3]));
  PetscFunctionReturn(0);
}

static PetscErrorCode JacobianCreate(FEMCeedFluid o)
{
  PetscFunctionBeginUser;
  PetscCall(BlockQFunctionsCreate(o));
  PetscCall(FEMCeedFluidBlockOperatorsCreate(o, o->qf_block[0], o->state, o->mesh_velocity, o->qdata, o->op_block));
  /* PETSc's boundary integration adds whole element matrices, zeros of the pressure-pressure
     block included: without a stabilization that block is in the pattern with zeros */
  if (o->volume.tau <= 0) PetscCall(StabilizationCreate(o, o->qdata, &o->op_pressure_pattern));
  PetscFunctionReturn(0);
}

/* the old-domain mass and the operator giving a domain's w |det A| from its coordinates */
static PetscErrorCode MassCreate(FEMCeedFluid o)
{
  Ceed          ceed = o->ceed;
  const CeedInt dim  = o->volume.dim;

  PetscFunctionBeginUser;
  PetscCall(FEMCeedCoordinates(ceed, o->dm, o->velocity_fe, &o->r_x, &o->b_x, &o->coordinates));
  PetscCall(FEMCeedPointRestriction(ceed, o->r_u, o->b_u, 1, &o->r_w, &o->domain_weight[0]));
  PetscCallCeed(ceed, CeedElemRestrictionCreateVector(o->r_w, &o->domain_weight[1], NULL));
  PetscCallCeed(ceed, CeedElemRestrictionCreateVector(o->r_w, &o->mass_weight, NULL));
  PetscCallCeed(ceed, CeedVectorSetValue(o->domain_weight[1], 0.0));
  PetscCallCeed(ceed, CeedVectorSetValue(o->mass_weight, 0.0));
  PetscCallCeed(ceed, CeedQFunctionCreateInterior(ceed, 1, FluidDomainWeight, FluidDomainWeight_loc, &o->qf_domain));
  PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_domain, "dx", dim * dim, CEED_EVAL_GRAD));
  PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_domain, "weight", 1, CEED_EVAL_WEIGHT));
  PetscCallCeed(ceed, CeedQFunctionAddOutput(o->qf_domain, "w", 1, CEED_EVAL_NONE));
  PetscCallCeed(ceed, CeedQFunctionSetContext(o->qf_domain, o->context));
  PetscCallCeed(ceed, CeedOperatorCreate(ceed, o->qf_domain, NULL, NULL, &o->op_domain));
  PetscCallCeed(ceed, CeedOperatorSetField(o->op_domain, "dx", o->r_x, o->b_x, CEED_VECTOR_ACTIVE));
  PetscCallCeed(ceed,
                CeedOperatorSetField(o->op_domain, "weight", CEED_ELEMRESTRICTION_NONE, o->b_x, CEED_VECTOR_NONE));
  PetscCallCeed(ceed, CeedOperatorSetField(o->op_domain, "w", o->r_w, CEED_BASIS_NONE, CEED_VECTOR_ACTIVE));
  PetscCallCeed(ceed, CeedQFunctionCreateInterior(ceed, 1, FluidOldMass, FluidOldMass_loc, &o->qf_mass));
  PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_mass, "u", dim, CEED_EVAL_INTERP));
  PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_mass, "m", 1, CEED_EVAL_NONE));
  PetscCallCeed(ceed, CeedQFunctionAddOutput(o->qf_mass, "v", dim, CEED_EVAL_INTERP));
  PetscCallCeed(ceed, CeedQFunctionSetContext(o->qf_mass, o->context));
  /* applied only: the Jacobian's velocity-velocity block holds the assembled mass */
  PetscCallCeed(ceed, CeedOperatorCreate(ceed, o->qf_mass, NULL, NULL, &o->op_mass));
  PetscCallCeed(ceed, CeedOperatorSetField(o->op_mass, "u", o->r_u, o->b_u, CEED_VECTOR_ACTIVE));
  PetscCallCeed(ceed, CeedOperatorSetField(o->op_mass, "m", o->r_w, CEED_BASIS_NONE, o->mass_weight));
  PetscCallCeed(ceed, CeedOperatorSetField(o->op_mass, "v", o->r_u, o->b_u, CEED_VECTOR_ACTIVE));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedFluidMassDomain(FEMCeedFluid o, DM dm_domain, PetscInt slot)
{
  Vec local;

  PetscFunctionBeginUser;
  PetscCheck(o->op_mass && slot >= 0 && slot < 2, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG,
             "libCEED fluid: no old-domain mass (fixed mesh) or no slot %" PetscInt_FMT, slot);
  PetscCall(DMGetCoordinatesLocal(dm_domain, &local));
  PetscCall(FEMCeedVectorCopyFrom(o->ceed, o->coordinates, local));
  PetscCallCeed(o->ceed,
                CeedOperatorApply(o->op_domain, o->coordinates, o->domain_weight[slot], CEED_REQUEST_IMMEDIATE));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedFluidMassWeights(FEMCeedFluid o, PetscScalar a0, PetscScalar a1)
{
  PetscFunctionBeginUser;
  PetscCallCeed(o->ceed, CeedVectorSetValue(o->mass_weight, 0.0));
  PetscCallCeed(o->ceed, CeedVectorAXPY(o->mass_weight, a0, o->domain_weight[0]));
  if (a1 != 0.0) PetscCallCeed(o->ceed, CeedVectorAXPY(o->mass_weight, a1, o->domain_weight[1]));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedFluidMassApply(FEMCeedFluid o, Vec xlocal, Vec ylocal)
{
  PetscFunctionBeginUser;
  PetscCall(FEMCeedApply(o->ceed, 1, &o->op_mass, o->x, o->f, xlocal, ylocal));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedFluidSetConstants(FEMCeedFluid o, const PetscScalar constants[])
{
  FluidVolume *fv;

  PetscFunctionBeginUser;
  PetscCallCeed(o->ceed, CeedQFunctionContextGetData(o->context, CEED_MEM_HOST, &fv));
  fv->rho        = constants[FLUID_RHO];
  fv->mu         = constants[FLUID_MU];
  fv->mass       = constants[FLUID_MASS];
  fv->op         = constants[FLUID_OPERATOR];
  fv->convection = constants[FLUID_CONVECTION];
  fv->tau        = o->volume.tau > 0 ? constants[FLUID_OPERATOR] * constants[FLUID_PRESSURE_STABILIZATION] : 0.0;
  PetscCallCeed(o->ceed, CeedQFunctionContextRestoreData(o->context, &fv));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedFluidMeshVelocitySet(FEMCeedFluid o, Vec z)
{
  PetscFunctionBeginUser;
  if (!o->volume.moving) PetscFunctionReturn(0);
  PetscCheck(z, PETSC_COMM_SELF, PETSC_ERR_ARG_NULL, "libCEED fluid: a moving mesh needs its mesh velocity");
  PetscCall(FEMCeedVectorCopyFrom(o->ceed, o->mesh_velocity, z));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedFluidPointsSet(FEMCeedFluid o, Vec z, PetscBool old_mass)
{
  FluidVolume *fv;

  PetscFunctionBeginUser;
  PetscCheck(!old_mass || o->volume.moving, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG,
             "libCEED fluid: no old-domain mass on a fixed mesh");
  PetscCallCeed(o->ceed, CeedQFunctionContextGetData(o->context, CEED_MEM_HOST, &fv));
  fv->old_mass = old_mass ? 1 : 0;
  PetscCallCeed(o->ceed, CeedQFunctionContextRestoreData(o->context, &fv));
  PetscCall(FEMCeedGeometryFollow(o->ceed, o->dm, o->velocity_fe, &o->geometry, &o->r_q, &o->qdata));
  PetscCall(FEMCeedFluidMeshVelocitySet(o, z));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedFluidCreate(DM dm, DM dm_mesh_velocity, const PetscScalar constants[], FEMCeedFluid *fluid)
{
  FEMCeedFluid o;
  PetscFE      pressure;
  CeedInt      nq, nq_p;
  PetscInt     dim;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&o));
  PetscCall(FEMCeedGet(&o->ceed));
  Ceed ceed = o->ceed;
  o->dm     = dm;
  PetscCall(DMGetDimension(dm, &dim));
  PetscCall(DMGetField(dm, 0, NULL, (PetscObject *)&o->velocity_fe));
  PetscCall(DMGetField(dm, 1, NULL, (PetscObject *)&pressure));
  PetscCall(FEMCeedRestriction(ceed, dm, 0, &o->r_u));
  PetscCall(FEMCeedRestriction(ceed, dm, 1, &o->r_p));
  PetscCall(FEMCeedBasis(ceed, dm, o->velocity_fe, &o->b_u));
  PetscCall(FEMCeedBasis(ceed, dm, pressure, &o->b_p));
  PetscCall(FEMCeedGeometryFollow(o->ceed, o->dm, o->velocity_fe, &o->geometry, &o->r_q, &o->qdata));
  PetscCallCeed(ceed, CeedBasisGetNumQuadraturePoints(o->b_u, &nq));
  PetscCallCeed(ceed, CeedBasisGetNumQuadraturePoints(o->b_p, &nq_p));
  PetscCheck(nq == nq_p, PETSC_COMM_SELF, PETSC_ERR_SUP, "libCEED fluid: velocity and pressure need one quadrature");
  o->volume.dim       = (CeedInt)dim;
  o->volume.tau       = PetscRealPart(constants[FLUID_PRESSURE_STABILIZATION]);
  o->volume.moving    = dm_mesh_velocity ? 1 : 0;
  o->dm_mesh_velocity = dm_mesh_velocity;
  if (dm_mesh_velocity) {
    PetscFE  z_fe;
    CeedSize zsize;
    PetscCall(DMGetField(dm_mesh_velocity, 0, NULL, (PetscObject *)&z_fe));
    PetscCall(FEMCeedRestriction(ceed, dm_mesh_velocity, 0, &o->r_z));
    PetscCall(FEMCeedBasis(ceed, dm_mesh_velocity, z_fe, &o->b_z));
    PetscCallCeed(ceed, CeedElemRestrictionGetLVectorSize(o->r_z, &zsize));
    PetscCallCeed(ceed, CeedVectorCreate(ceed, zsize, &o->mesh_velocity));
    PetscCallCeed(ceed, CeedVectorSetValue(o->mesh_velocity, 0.0));
  }
  PetscCallCeed(ceed, CeedQFunctionContextCreate(ceed, &o->context));
  PetscCallCeed(ceed, CeedQFunctionContextSetData(o->context, CEED_MEM_HOST, CEED_COPY_VALUES, sizeof(o->volume),
                                                  &o->volume));
  PetscCall(FEMCeedFluidSetConstants(o, constants));
  {
    CeedVector *vectors[] = {&o->x, &o->f, &o->state};
    PetscCall(FEMCeedLocalVectors(ceed, dm, 3, vectors));
  }
  if (dm_mesh_velocity) PetscCall(MassCreate(o));
  PetscCall(ResidualCreate(o));
  PetscCall(JacobianCreate(o));
  *fluid = o;
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedFluidDestroy(FEMCeedFluid *fluid)
{
  FEMCeedFluid o = *fluid;

  PetscFunctionBeginUser;
  if (!o) PetscFunctionReturn(0);
  Ceed ceed = o->ceed;
  for (PetscInt b = 0; b < 4; ++b) {
    PetscCallCeed(ceed, CeedOperatorDestroy(&o->op_block[b]));
    PetscCallCeed(ceed, CeedOperatorDestroy(&o->op_apply[b]));
  }
  PetscCallCeed(ceed, CeedOperatorDestroy(&o->op_apply[4]));
  PetscCallCeed(ceed, CeedVectorDestroy(&o->apply_state));
  PetscCallCeed(ceed, CeedVectorDestroy(&o->apply_mesh_velocity));
  PetscCallCeed(ceed, CeedVectorDestroy(&o->apply_qdata));
  PetscCallCeed(ceed, CeedVectorDestroy(&o->apply_mass_weight));
  for (PetscInt b = 0; b < 3; ++b) PetscCallCeed(ceed, CeedQFunctionDestroy(&o->qf_block[b]));
  PetscCallCeed(ceed, CeedQFunctionDestroy(&o->qf_uu_transpose));
  PetscCallCeed(ceed, CeedOperatorDestroy(&o->op_apply_uu_transpose));
  for (PetscInt k = 0; k < o->n_face_ops; ++k) {
    PetscCallCeed(ceed, CeedOperatorDestroy(&o->face_residual[k]));
    PetscCallCeed(ceed, CeedOperatorDestroy(&o->face_jacobian[k]));
  }
  for (PetscInt k = 0; k < o->n_face_sets; ++k) PetscCall(FEMCeedFacesDestroy(&o->face_sets[k]));
  for (PetscInt b = 0; b < 2; ++b)
    for (PetscInt j = 0; j < 2; ++j) PetscCallCeed(ceed, CeedQFunctionDestroy(&o->qf_face[b][j]));
  PetscCall(PetscFree(o->counts));
  PetscCallCeed(ceed, CeedOperatorDestroy(&o->op_stabilization));
  PetscCallCeed(ceed, CeedOperatorDestroy(&o->op_pressure_pattern));
  PetscCallCeed(ceed, CeedOperatorDestroy(&o->op_mass));
  PetscCallCeed(ceed, CeedOperatorDestroy(&o->op_uu_coefficients));
  PetscCallCeed(ceed, CeedQFunctionDestroy(&o->qf_uu_coefficients));
  PetscCallCeed(ceed, CeedElemRestrictionDestroy(&o->r_uu_coefficients));
  PetscCallCeed(ceed, CeedVectorDestroy(&o->uu_coefficients));
  PetscCallCeed(ceed, CeedOperatorDestroy(&o->op_domain));
  PetscCallCeed(ceed, CeedQFunctionDestroy(&o->qf_mass));
  PetscCallCeed(ceed, CeedQFunctionDestroy(&o->qf_domain));
  PetscCallCeed(ceed, CeedVectorDestroy(&o->coordinates));
  PetscCallCeed(ceed, CeedVectorDestroy(&o->domain_weight[0]));
  PetscCallCeed(ceed, CeedVectorDestroy(&o->domain_weight[1]));
  PetscCallCeed(ceed, CeedVectorDestroy(&o->mass_weight));
  PetscCallCeed(ceed, CeedElemRestrictionDestroy(&o->r_x));
  PetscCallCeed(ceed, CeedElemRestrictionDestroy(&o->r_w));
  PetscCallCeed(ceed, CeedBasisDestroy(&o->b_x));
  PetscCallCeed(ceed, CeedQFunctionDestroy(&o->qf_stabilization));
  PetscCallCeed(ceed, CeedOperatorDestroy(&o->op_residual));
  PetscCallCeed(ceed, CeedQFunctionDestroy(&o->qf_residual));
  PetscCallCeed(ceed, CeedQFunctionContextDestroy(&o->context));
  PetscCallCeed(ceed, CeedVectorDestroy(&o->qdata));
  PetscCall(FEMCeedGeometryKeyDestroy(ceed, &o->geometry));
  PetscCallCeed(ceed, CeedVectorDestroy(&o->x));
  PetscCallCeed(ceed, CeedVectorDestroy(&o->f));
  PetscCallCeed(ceed, CeedVectorDestroy(&o->state));
  PetscCallCeed(ceed, CeedVectorDestroy(&o->mesh_velocity));
  PetscCallCeed(ceed, CeedElemRestrictionDestroy(&o->r_q));
  PetscCallCeed(ceed, CeedElemRestrictionDestroy(&o->r_p));
  PetscCallCeed(ceed, CeedElemRestrictionDestroy(&o->r_u));
  PetscCallCeed(ceed, CeedElemRestrictionDestroy(&o->r_z));
  PetscCallCeed(ceed, CeedBasisDestroy(&o->b_p));
  PetscCallCeed(ceed, CeedBasisDestroy(&o->b_u));
  PetscCallCeed(ceed, CeedBasisDestroy(&o->b_z));
  PetscCall(PetscFree(o));
  *fluid = NULL;
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedFluidResidual(FEMCeedFluid o, Vec xlocal, Vec zlocal, PetscBool old_mass, PetscBool faces,
                                    Vec flocal)
{
  CeedOperator ops[2 + FEM_CEED_MAX_FACE_SETS * FEM_CEED_MAX_CELL_FACES];
  PetscInt     n = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_CEED_RESIDUAL, 0, 0, 0, 0));
  PetscCall(FEMCeedFluidPointsSet(o, zlocal, old_mass));
  ops[n++] = o->op_residual;
  if (o->op_stabilization) ops[n++] = o->op_stabilization;
  if (faces) {
    PetscCall(FEMCeedFluidFacesGeometry(o));
    for (PetscInt k = 0; k < o->n_face_ops; ++k) ops[n++] = o->face_residual[k];
  }
  PetscCall(FEMCeedApply(o->ceed, n, ops, o->x, o->f, xlocal, flocal));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_CEED_RESIDUAL, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}
