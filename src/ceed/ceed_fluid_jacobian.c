/* The libCEED fluid's assembled Jacobian (ceed_fluid.c holds the operators): its pattern,
   and its values per assembly. The velocity-velocity block, most of the entries and of the
   work, is formed here in closed form from a few coefficients per quadrature point
   (FluidJacobianUUCoefficients): libCEED's generic linearization calls the block's pointwise
   function once per input mode and component and stores the (1 + dim) dim squared entries
   of D at every point, and our generic element matrices (ceed_element_matrices.c) then
   contract them with the bases. The other blocks, small, keep that generic route. */
#include "ceed_fluid_impl.h"
#include "logging.h"
#include "qfunctions_fluid_jacobian.h"
#include <ceed/backend.h>

/* the velocity-pressure, pressure-velocity, pressure-pressure blocks after the
   velocity-velocity one, then the faces' */
#define FLUID_VOLUME_BLOCKS 4

/* the operator of the velocity-velocity block's coefficients, made with the matrix's pattern */
static PetscErrorCode VelocityBlockCreate(FEMCeedFluid o)
{
  Ceed          ceed = o->ceed;
  const CeedInt dim = o->volume.dim, size = 2 + 2 * dim * dim + dim;

  PetscFunctionBeginUser;
  PetscCallCeed(ceed, CeedQFunctionCreateInterior(ceed, 1, FluidJacobianUUCoefficients, FluidJacobianUUCoefficients_loc,
                                                  &o->qf_uu_coefficients));
  PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_uu_coefficients, "u0", dim, CEED_EVAL_INTERP));
  PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_uu_coefficients, "du0", dim * dim, CEED_EVAL_GRAD));
  PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_uu_coefficients, "qdata", 1 + dim * dim, CEED_EVAL_NONE));
  if (o->volume.moving) {
    PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_uu_coefficients, "z", dim, CEED_EVAL_INTERP));
    PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_uu_coefficients, "m", 1, CEED_EVAL_NONE));
  }
  PetscCallCeed(ceed, CeedQFunctionAddOutput(o->qf_uu_coefficients, "c", size, CEED_EVAL_NONE));
  PetscCallCeed(ceed, CeedQFunctionSetContext(o->qf_uu_coefficients, o->context));
  PetscCall(FEMCeedPointRestriction(ceed, o->r_u, o->b_u, size, &o->r_uu_coefficients, &o->uu_coefficients));
  PetscCallCeed(ceed, CeedOperatorCreate(ceed, o->qf_uu_coefficients, NULL, NULL, &o->op_uu_coefficients));
  CeedOperator op = o->op_uu_coefficients;
  PetscCallCeed(ceed, CeedOperatorSetField(op, "u0", o->r_u, o->b_u, o->state));
  PetscCallCeed(ceed, CeedOperatorSetField(op, "du0", o->r_u, o->b_u, o->state));
  PetscCallCeed(ceed, CeedOperatorSetField(op, "qdata", o->r_q, CEED_BASIS_NONE, o->qdata));
  if (o->volume.moving) {
    PetscCallCeed(ceed, CeedOperatorSetField(op, "z", o->r_z, o->b_z, o->mesh_velocity));
    PetscCallCeed(ceed, CeedOperatorSetField(op, "m", o->r_w, CEED_BASIS_NONE, o->mass_weight));
  }
  PetscCallCeed(ceed, CeedOperatorSetField(op, "c", o->r_uu_coefficients, CEED_BASIS_NONE, CEED_VECTOR_ACTIVE));
  PetscFunctionReturn(0);
}

/* The block's element matrices, in FEMCeedElementPattern's order (element, input component
   c, output component c', input node j, output node i): the part every component pair has,
   R G0[c'][c] phi_j phi_i + W op mu g_j[c'] g_i[c], plus on the diagonal pairs the part the
   components share, (m0 phi_j + R B (u0 - z) . grad phi_j) phi_i + W op mu g_j . g_i */
static PetscErrorCode VelocityBlockValues(void *ctx, FEMCeedValuesSink sink)
{
  FEMCeedFluid      o    = (FEMCeedFluid)ctx;
  Ceed              ceed = o->ceed;
  const CeedInt     dim = o->volume.dim, size = 2 + 2 * dim * dim + dim;
  CeedInt           n_elem, P, Q;
  const CeedScalar *interp, *grad, *coefficients;
  CeedScalar       *g, *convection, *shared, *products, *values;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_CEED_LINEARIZE, 0, 0, 0, 0));
  PetscCallCeed(ceed,
                CeedOperatorApply(o->op_uu_coefficients, CEED_VECTOR_NONE, o->uu_coefficients, CEED_REQUEST_IMMEDIATE));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_CEED_LINEARIZE, 0, 0, 0, 0));
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_CEED_ELEMENT_MATRICES, 0, 0, 0, 0));
  PetscCallCeed(ceed, CeedElemRestrictionGetNumElements(o->r_u, &n_elem));
  PetscCallCeed(ceed, CeedElemRestrictionGetElementSize(o->r_u, &P));
  PetscCallCeed(ceed, CeedBasisGetNumQuadraturePoints(o->b_u, &Q));
  PetscCallCeed(ceed, CeedBasisGetInterp(o->b_u, &interp)); /* [q][node] */
  PetscCallCeed(ceed, CeedBasisGetGrad(o->b_u, &grad));     /* [direction][q][node] */
  const CeedSize per_element = (CeedSize)dim * dim * P * P;
  PetscCall(PetscMalloc5(P * dim, &g, P, &convection, P * P, &shared, P * P, &products,
                         FEM_CEED_CHUNK_ELEMENTS * per_element, &values));
  PetscCallCeed(ceed, CeedVectorGetArrayRead(o->uu_coefficients, CEED_MEM_HOST, &coefficients));
  for (CeedInt e = 0; e < n_elem; ++e) {
    CeedScalar *element = values + (e % FEM_CEED_CHUNK_ELEMENTS) * per_element;
    PetscCall(PetscArrayzero(shared, P * P));
    PetscCall(PetscArrayzero(element, dim * dim * P * P));
    for (CeedInt q = 0; q < Q; ++q) {
      /* the point's coefficients: FEMCeedPointRestriction's layout, points fastest */
      const CeedScalar *c = coefficients + (CeedSize)e * Q * size + q, *phi = interp + q * P;
      const CeedScalar  m0 = c[0], viscous = c[Q], *B = c + 2 * Q, *RG0 = c + (2 + dim * dim) * Q,
                       *RBz = c + (2 + 2 * dim * dim) * Q;
      for (CeedInt j = 0; j < P; ++j) {
        convection[j] = 0;
        for (CeedInt k = 0; k < dim; ++k) g[j * dim + k] = 0;
        for (CeedInt a = 0; a < dim; ++a) {
          const CeedScalar dphi = grad[(a * Q + q) * P + j];
          convection[j] += RBz[a * Q] * dphi;
          for (CeedInt k = 0; k < dim; ++k) g[j * dim + k] += B[(a * dim + k) * Q] * dphi;
        }
      }
      for (CeedInt j = 0; j < P; ++j) {
        for (CeedInt i = 0; i < P; ++i) {
          CeedScalar gg = 0;
          for (CeedInt k = 0; k < dim; ++k) gg += g[j * dim + k] * g[i * dim + k];
          products[j * P + i] = phi[j] * phi[i];
          shared[j * P + i] += (m0 * phi[j] + convection[j]) * phi[i] + viscous * gg;
        }
      }
      for (CeedInt ci = 0; ci < dim; ++ci)
        for (CeedInt co = 0; co < dim; ++co) {
          const CeedScalar r     = RG0[(co * dim + ci) * Q];
          CeedScalar      *block = element + (ci * dim + co) * P * P;
          for (CeedInt j = 0; j < P; ++j) {
            const CeedScalar gj = viscous * g[j * dim + co];
            for (CeedInt i = 0; i < P; ++i) block[j * P + i] += r * products[j * P + i] + gj * g[i * dim + ci];
          }
        }
    }
    for (CeedInt c = 0; c < dim; ++c)
      for (CeedInt k = 0; k < P * P; ++k) element[(c * dim + c) * P * P + k] += shared[k];
    if (e % FEM_CEED_CHUNK_ELEMENTS == FEM_CEED_CHUNK_ELEMENTS - 1 || e == n_elem - 1) {
      const CeedInt first = e - e % FEM_CEED_CHUNK_ELEMENTS;
      PetscCall(sink.add(sink.ctx, first * per_element, (e - first + 1) * per_element, values));
    }
  }
  PetscCallCeed(ceed, CeedVectorRestoreArrayRead(o->uu_coefficients, &coefficients));
  PetscCall(PetscFree5(g, convection, shared, products, values));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_CEED_ELEMENT_MATRICES, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedFluidCreateMatrix(FEMCeedFluid o, Mat *A)
{
  CeedOperator pattern[FLUID_VOLUME_BLOCKS + FEM_CEED_MAX_FACE_SETS * FEM_CEED_MAX_CELL_FACES] =
    {o->op_block[0], o->op_block[1], o->op_block[2], o->op_block[3] ? o->op_block[3] : o->op_pressure_pattern};
  const PetscInt n = FLUID_VOLUME_BLOCKS + o->n_face_ops;

  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < o->n_face_ops; ++k) pattern[FLUID_VOLUME_BLOCKS + k] = o->face_jacobian[k];
  if (!o->op_uu_coefficients) PetscCall(VelocityBlockCreate(o));
  if (!o->counts) PetscCall(PetscMalloc1(n, &o->counts));
  PetscCall(FEMCeedCreateCOOMatrix(o->dm, A));
  PetscCall(FEMCeedAssemblySetUp(o->ceed, o->dm, n, pattern, *A, o->counts));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedFluidJacobian(FEMCeedFluid o, Vec xlocal, Vec zlocal, PetscBool old_mass, Mat A)
{
  CeedOperator       blocks[FLUID_VOLUME_BLOCKS + FEM_CEED_MAX_FACE_SETS * FEM_CEED_MAX_CELL_FACES] = {o->op_block[0],
                                                                                                       o->op_block[1],
                                                                                                       o->op_block[2],
                                                                                                       o->op_block[3]};
  FEMCeedBlockValues custom[FLUID_VOLUME_BLOCKS + FEM_CEED_MAX_FACE_SETS * FEM_CEED_MAX_CELL_FACES] = {
    {VelocityBlockValues, o}
  };
  const PetscInt n = FLUID_VOLUME_BLOCKS + o->n_face_ops;

  PetscFunctionBeginUser;
  PetscCheck(o->counts, PETSC_COMM_SELF, PETSC_ERR_ORDER, "libCEED fluid: a Jacobian before its matrix's pattern");
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_CEED_JACOBIAN, 0, 0, 0, 0));
  for (PetscInt k = 0; k < o->n_face_ops; ++k) blocks[FLUID_VOLUME_BLOCKS + k] = o->face_jacobian[k];
  PetscCall(FEMCeedFluidPointsSet(o, zlocal, old_mass));
  PetscCall(FEMCeedFluidFacesGeometry(o));
  PetscCall(FEMCeedVectorCopyFrom(o->ceed, o->state, xlocal));
  PetscCall(FEMCeedAssembleBlocks(o->ceed, n, blocks, custom, o->counts, A));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_CEED_JACOBIAN, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}
