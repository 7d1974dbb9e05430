/* The fluid's face terms through libCEED (qfunctions_fluid_faces.h): the backflow
   stabilization and the interface's convective term, one residual and one Jacobian operator
   per group of a face set (ceed_faces.c); the Jacobians join the COO pattern. */
#include "ceed_fluid_impl.h"
#include "qfunctions_fluid_faces.h"

static PetscErrorCode FaceQFunction(FEMCeedFluid o, PetscBool backflow, PetscBool jacobian, CeedQFunction *qf)
{
  Ceed          ceed = o->ceed;
  const CeedInt dim  = o->volume.dim;

  PetscFunctionBeginUser;
  if (jacobian)
    PetscCallCeed(ceed,
                  backflow
                    ? CeedQFunctionCreateInterior(ceed, 1, FluidBackflowJacobian, FluidBackflowJacobian_loc, qf)
                    : CeedQFunctionCreateInterior(ceed, 1, FluidConvectionJacobian, FluidConvectionJacobian_loc, qf));
  else
    PetscCallCeed(ceed,
                  backflow
                    ? CeedQFunctionCreateInterior(ceed, 1, FluidBackflowResidual, FluidBackflowResidual_loc, qf)
                    : CeedQFunctionCreateInterior(ceed, 1, FluidConvectionResidual, FluidConvectionResidual_loc, qf));
  PetscCallCeed(ceed, CeedQFunctionAddInput(*qf, jacobian ? "du" : "u", dim, CEED_EVAL_INTERP));
  if (jacobian) PetscCallCeed(ceed, CeedQFunctionAddInput(*qf, "u0", dim, CEED_EVAL_INTERP));
  if (o->volume.moving) PetscCallCeed(ceed, CeedQFunctionAddInput(*qf, "z", dim, CEED_EVAL_INTERP));
  PetscCallCeed(ceed, CeedQFunctionAddInput(*qf, "qdata", 1 + dim, CEED_EVAL_NONE));
  PetscCallCeed(ceed, CeedQFunctionAddOutput(*qf, "v", dim, CEED_EVAL_INTERP));
  PetscCallCeed(ceed, CeedQFunctionSetContext(*qf, o->context));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedFluidAddFaces(FEMCeedFluid o, DMLabel label, PetscInt nvalues, const PetscInt values[],
                                    PetscBool backflow)
{
  Ceed         ceed = o->ceed;
  FEMCeedFaces faces;

  PetscFunctionBeginUser;
  PetscCheck(!o->counts, PETSC_COMM_SELF, PETSC_ERR_ORDER, "libCEED fluid: faces after the matrix pattern");
  PetscCheck(o->n_face_sets < FEM_CEED_MAX_FACE_SETS, PETSC_COMM_SELF, PETSC_ERR_SUP,
             "libCEED fluid: too many face sets");
  PetscCall(FEMCeedFacesCreate(o->dm, o->velocity_fe, 0, o->dm_mesh_velocity, label, nvalues, values, &faces));
  o->face_sets[o->n_face_sets++] = faces;
  for (PetscInt j = 0; j < 2; ++j)
    if (!o->qf_face[backflow][j])
      PetscCall(FaceQFunction(o, backflow, j ? PETSC_TRUE : PETSC_FALSE, &o->qf_face[backflow][j]));
  for (PetscInt k = 0; k < faces->n_groups; ++k) {
    FEMCeedFaceGroup *g = &faces->groups[k];
    for (PetscInt j = 0; j < 2; ++j) {
      CeedOperator *op = j ? &o->face_jacobian[o->n_face_ops] : &o->face_residual[o->n_face_ops];
      PetscCallCeed(ceed, CeedOperatorCreate(ceed, o->qf_face[backflow][j], NULL, NULL, op));
      PetscCallCeed(ceed, CeedOperatorSetField(*op, j ? "du" : "u", g->r_u, g->b_u, CEED_VECTOR_ACTIVE));
      if (j) PetscCallCeed(ceed, CeedOperatorSetField(*op, "u0", g->r_u, g->b_u, o->state));
      if (o->volume.moving) PetscCallCeed(ceed, CeedOperatorSetField(*op, "z", g->r_z, g->b_z, o->mesh_velocity));
      PetscCallCeed(ceed, CeedOperatorSetField(*op, "qdata", g->r_q, CEED_BASIS_NONE, g->qdata));
      PetscCallCeed(ceed, CeedOperatorSetField(*op, "v", g->r_u, g->b_u, CEED_VECTOR_ACTIVE));
    }
    ++o->n_face_ops;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedFluidFacesGeometry(FEMCeedFluid o)
{
  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < o->n_face_sets; ++k) PetscCall(FEMCeedFacesGeometry(o->face_sets[k]));
  PetscFunctionReturn(0);
}

PetscBool FEMCeedFluidHasFaces(FEMCeedFluid o)
{
  return o && o->n_face_sets > 0 ? PETSC_TRUE : PETSC_FALSE;
}
