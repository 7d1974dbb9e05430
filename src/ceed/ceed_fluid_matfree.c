/* The fluid's volume Jacobian without a matrix (fem_ceed.h): operators of their own (libCEED
   0.12 assembles an operator wrongly after it was applied), frozen with the linearization's
   state, mesh velocity, geometry and old-domain weights, so that they apply the matrix
   FEMCeedFluidJacobian assembled; the transpose changes only the velocity-velocity block. */
#include "ceed_fluid_impl.h"
#include "logging.h"

PetscErrorCode FEMCeedFluidJacobianApplySetUp(FEMCeedFluid o, Vec xlocal, Vec zlocal, PetscBool old_mass)
{
  Ceed ceed = o->ceed;

  PetscFunctionBeginUser;
  PetscCheck(!old_mass || o->volume.moving, PETSC_COMM_SELF, PETSC_ERR_ARG_WRONG,
             "libCEED fluid: no old-domain mass on a fixed mesh");
  if (!o->op_apply[0]) {
    CeedOperator t;
    CeedSize     n;
    PetscCallCeed(ceed, CeedVectorGetLength(o->state, &n));
    PetscCallCeed(ceed, CeedVectorCreate(ceed, n, &o->apply_state));
    PetscCallCeed(ceed, CeedVectorSetValue(o->apply_state, 0.0));
    PetscCallCeed(ceed, CeedVectorGetLength(o->qdata, &n));
    PetscCallCeed(ceed, CeedVectorCreate(ceed, n, &o->apply_qdata));
    PetscCallCeed(ceed, CeedVectorSetValue(o->apply_qdata, 0.0));
    if (o->volume.moving) {
      PetscCallCeed(ceed, CeedVectorGetLength(o->mesh_velocity, &n));
      PetscCallCeed(ceed, CeedVectorCreate(ceed, n, &o->apply_mesh_velocity));
      PetscCallCeed(ceed, CeedVectorSetValue(o->apply_mesh_velocity, 0.0));
      PetscCallCeed(ceed, CeedVectorGetLength(o->mass_weight, &n));
      PetscCallCeed(ceed, CeedVectorCreate(ceed, n, &o->apply_mass_weight));
      PetscCallCeed(ceed, CeedVectorSetValue(o->apply_mass_weight, 0.0));
    }
    PetscCall(FEMCeedFluidBlockOperatorsCreate(o, o->qf_block[0], o->apply_state, o->apply_mesh_velocity,
                                               o->apply_qdata, o->op_apply));
    PetscCallCeed(ceed, CeedOperatorCreate(ceed, o->qf_uu_transpose, NULL, NULL, &o->op_apply_uu_transpose));
    t = o->op_apply_uu_transpose;
    PetscCallCeed(ceed, CeedOperatorSetField(t, "w", o->r_u, o->b_u, CEED_VECTOR_ACTIVE));
    PetscCallCeed(ceed, CeedOperatorSetField(t, "dw", o->r_u, o->b_u, CEED_VECTOR_ACTIVE));
    PetscCallCeed(ceed, CeedOperatorSetField(t, "u0", o->r_u, o->b_u, o->apply_state));
    PetscCallCeed(ceed, CeedOperatorSetField(t, "du0", o->r_u, o->b_u, o->apply_state));
    PetscCallCeed(ceed, CeedOperatorSetField(t, "qdata", o->r_q, CEED_BASIS_NONE, o->apply_qdata));
    if (o->volume.moving) PetscCallCeed(ceed, CeedOperatorSetField(t, "z", o->r_z, o->b_z, o->apply_mesh_velocity));
    PetscCallCeed(ceed, CeedOperatorSetField(t, "v", o->r_u, o->b_u, CEED_VECTOR_ACTIVE));
    PetscCallCeed(ceed, CeedOperatorSetField(t, "dv", o->r_u, o->b_u, CEED_VECTOR_ACTIVE));
    if (o->volume.moving) { /* the old domains' mass, at the weights of this Jacobian's step */
      PetscCallCeed(ceed, CeedOperatorCreate(ceed, o->qf_mass, NULL, NULL, &o->op_apply[4]));
      PetscCallCeed(ceed, CeedOperatorSetField(o->op_apply[4], "u", o->r_u, o->b_u, CEED_VECTOR_ACTIVE));
      PetscCallCeed(ceed, CeedOperatorSetField(o->op_apply[4], "m", o->r_w, CEED_BASIS_NONE, o->apply_mass_weight));
      PetscCallCeed(ceed, CeedOperatorSetField(o->op_apply[4], "v", o->r_u, o->b_u, CEED_VECTOR_ACTIVE));
    }
  }
  /* the linearization is frozen with its geometry and old-domain weights, as the assembled
     matrix is: a mesh move between Jacobians changes neither */
  PetscCall(FEMCeedGeometryFollow(o->ceed, o->dm, o->velocity_fe, &o->geometry, &o->r_q, &o->qdata));
  PetscCallCeed(ceed, CeedVectorCopy(o->qdata, o->apply_qdata));
  if (o->volume.moving) PetscCallCeed(ceed, CeedVectorCopy(o->mass_weight, o->apply_mass_weight));
  PetscCall(FEMCeedVectorCopyFrom(ceed, o->apply_state, xlocal));
  if (o->volume.moving) {
    PetscCheck(zlocal, PETSC_COMM_SELF, PETSC_ERR_ARG_NULL, "libCEED fluid: a moving mesh needs its mesh velocity");
    PetscCall(FEMCeedVectorCopyFrom(ceed, o->apply_mesh_velocity, zlocal));
  }
  o->apply_old_mass = old_mass;
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedFluidJacobianApply(FEMCeedFluid o, PetscBool transpose, Vec xlocal, Vec ylocal)
{
  Ceed         ceed = o->ceed;
  CeedOperator ops[5];
  PetscInt     n = 0;

  PetscFunctionBeginUser;
  PetscCheck(o->op_apply[0], PETSC_COMM_SELF, PETSC_ERR_ORDER, "libCEED fluid: no Jacobian to apply yet");
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_FLUID_MATFREE, 0, 0, 0, 0));
  /* the divergence blocks are each other's transposes, the others symmetric */
  ops[n++] = transpose ? o->op_apply_uu_transpose : o->op_apply[0];
  ops[n++] = o->op_apply[1];
  ops[n++] = o->op_apply[2];
  if (o->op_apply[3]) ops[n++] = o->op_apply[3];
  if (o->apply_old_mass) ops[n++] = o->op_apply[4];
  PetscCall(FEMCeedApply(ceed, n, ops, o->x, o->f, xlocal, ylocal));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_FLUID_MATFREE, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}
