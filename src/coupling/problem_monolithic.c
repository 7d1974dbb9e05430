/* The coupled system of a step as one set of equations in (x_f, x_s, x), x the scaled
   control (coupling.h):
     F_f = R_f(x_f; mesh(x_s)) - history_f - S_f (M P^T W^{-1/2} x + datum)
     F_s = R_s(x_s) - history_s + S_s M P^T W^{-1/2} x
     F_x = W^{1/2} P (T_f u(x_f) - T_s v_s(x_s))
   whose solution is the one every other method converges to; and the coupling blocks of
   its Jacobian, the products of injections S (interface values into a subproblem's rows),
   the interface mass M and the control's scaling, assembled once:
     dF_f/dx = -S_f M Q,  dF_s/dx = S_s M Q,  dF_x/dx_f = D S_f^T,  dF_x/dx_s = -c D S_s^T,
   Q = P^T W^{-1/2}, D = W^{1/2} P, c = dv_s/d eta. The mesh's dependence on x_s is left
   out of the Jacobian (monolithic.c says how to include it). */
#include "problem_impl.h"
#include "logging.h"

/* An interface vector with, at each interface entry, 1 + the global index that `map`
   sends a vector of global indices (1 + index) to: fluid and structure rows, control entries. */
static PetscErrorCode IndexVector(Vec v)
{
  PetscInt     lo, hi;
  PetscScalar *a;

  PetscFunctionBeginUser;
  PetscCall(VecGetOwnershipRange(v, &lo, &hi));
  PetscCall(VecGetArray(v, &a));
  for (PetscInt i = lo; i < hi; ++i) a[i - lo] = (PetscScalar)(i + 1);
  PetscCall(VecRestoreArray(v, &a));
  PetscFunctionReturn(0);
}

/* E[map(k) - 1, k] = scale(k) (transpose: E[k, map(k) - 1]) for the interface entries k
   with map(k) > 0; rows (columns) in the layout of `model`. */
static PetscErrorCode Injection(Vec model, Vec map, Vec scale, PetscBool transpose, Mat *E)
{
  PetscInt           n, N, m, M, lo;
  const PetscScalar *a, *s = NULL;
  MPI_Comm           comm;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)map, &comm));
  PetscCall(VecGetLocalSize(model, &n));
  PetscCall(VecGetSize(model, &N));
  PetscCall(VecGetLocalSize(map, &m));
  PetscCall(VecGetSize(map, &M));
  PetscCall(VecGetOwnershipRange(map, &lo, NULL));
  if (transpose) PetscCall(MatCreateAIJ(comm, m, n, M, N, 1, NULL, 1, NULL, E));
  else PetscCall(MatCreateAIJ(comm, n, m, N, M, 1, NULL, 1, NULL, E));
  PetscCall(MatSetOption(*E, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_FALSE));
  PetscCall(VecGetArrayRead(map, &a));
  if (scale) PetscCall(VecGetArrayRead(scale, &s));
  for (PetscInt k = 0; k < m; ++k) {
    const PetscInt target = (PetscInt)PetscRealPart(a[k]) - 1, entry = lo + k;
    if (target < 0) continue;
    if (transpose) PetscCall(MatSetValue(*E, entry, target, s ? s[k] : 1.0, INSERT_VALUES));
    else PetscCall(MatSetValue(*E, target, entry, s ? s[k] : 1.0, INSERT_VALUES));
  }
  if (scale) PetscCall(VecRestoreArrayRead(scale, &s));
  PetscCall(VecRestoreArrayRead(map, &a));
  PetscCall(MatAssemblyBegin(*E, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(*E, MAT_FINAL_ASSEMBLY));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingProblemCouplingBlocks(CouplingProblem P, Mat *Cfx, Mat *Csx, Mat *Cxf, Mat *Cxs)
{
  Vec      rows, all_f, all_s, all_x, w, winv, index, local;
  Mat      Sf, Ss, Tf, Ts, Q, D;
  DM       dm;

  PetscFunctionBeginUser;
  PetscCheck(P->fluid && P->structure, P->comm, PETSC_ERR_SUP, "the coupled system needs the fluid and the structure on every rank");
  PetscCall(VecDuplicate(P->all_a, &all_f));
  PetscCall(VecDuplicate(P->all_a, &all_s));
  PetscCall(VecDuplicate(P->all_a, &all_x));
  PetscCall(VecDuplicate(P->all_a, &w));
  PetscCall(VecDuplicate(P->all_a, &winv));
  /* the fluid's free rows at the interface entries */
  PetscCall(VecDuplicate(P->fluid_vec, &rows));
  PetscCall(IndexVector(rows));
  PetscCall(InterfaceFluidGather(P->itf, rows, all_f));
  PetscCall(Injection(rows, all_f, NULL, PETSC_FALSE, &Sf));
  PetscCall(Injection(rows, all_f, NULL, PETSC_TRUE, &Tf));
  PetscCall(VecDestroy(&rows));
  /* the structure's free rows: through a local vector whose constrained entries stay 0 */
  PetscCall(StructureGetDM(P->structure, &dm));
  PetscCall(VecDuplicate(P->structure_vec, &rows));
  PetscCall(IndexVector(rows));
  PetscCall(DMGetLocalVector(dm, &local));
  PetscCall(VecZeroEntries(local));
  PetscCall(DMGlobalToLocal(dm, rows, INSERT_VALUES, local));
  PetscCall(InterfaceStructureTrace(P->itf, local, all_s));
  PetscCall(DMRestoreLocalVector(dm, &local));
  PetscCall(Injection(rows, all_s, NULL, PETSC_FALSE, &Ss));
  PetscCall(Injection(rows, all_s, NULL, PETSC_TRUE, &Ts));
  PetscCall(VecDestroy(&rows));
  /* the control entries, and W^{1/2}, W^{-1/2} there */
  PetscCall(VecDuplicate(P->weight_sqrt, &index));
  PetscCall(IndexVector(index));
  PetscCall(InterfaceExtend(P->itf, index, all_x));
  PetscCall(InterfaceExtend(P->itf, P->weight_sqrt, w));
  PetscCall(VecCopy(P->weight_sqrt, P->g));
  PetscCall(VecReciprocal(P->g));
  PetscCall(InterfaceExtend(P->itf, P->g, winv));
  PetscCall(Injection(index, all_x, winv, PETSC_TRUE, &Q));
  PetscCall(Injection(index, all_x, w, PETSC_FALSE, &D));
  PetscCall(VecDestroy(&index));
  PetscCall(MatMatMatMult(Sf, P->mass, Q, MAT_INITIAL_MATRIX, PETSC_DEFAULT, Cfx));
  PetscCall(MatScale(*Cfx, -1.0));
  PetscCall(MatMatMatMult(Ss, P->mass, Q, MAT_INITIAL_MATRIX, PETSC_DEFAULT, Csx));
  PetscCall(MatMatMult(D, Tf, MAT_INITIAL_MATRIX, PETSC_DEFAULT, Cxf));
  PetscCall(MatMatMult(D, Ts, MAT_INITIAL_MATRIX, PETSC_DEFAULT, Cxs));
  PetscCall(MatScale(*Cxs, -StructureVelocityCoefficient(P->structure, P->measure)));
  for (Mat *m = (Mat[]){Sf, Ss, Tf, Ts, Q, D}, *e = m + 6; m < e; ++m) PetscCall(MatDestroy(m));
  for (Vec *v = (Vec[]){all_f, all_s, all_x, w, winv}, *e = v + 5; v < e; ++v) PetscCall(VecDestroy(v));
  PetscFunctionReturn(0);
}

/* R(x) of a subproblem's nonlinear system, its own callback (SNESComputeFunction would
   subtract the right-hand side of its last solve) */
static PetscErrorCode SystemFunction(SNES snes, Vec x, Vec F)
{
  PetscErrorCode (*fn)(SNES, Vec, Vec, void *);
  void *ctx;

  PetscFunctionBeginUser;
  PetscCall(SNESGetFunction(snes, NULL, &fn, &ctx));
  PetscCall((*fn)(snes, x, F, ctx));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingProblemSystemJacobian(SNES snes, Vec x, Mat *A)
{
  PetscErrorCode (*fn)(SNES, Vec, Mat, Mat, void *);
  void *ctx;
  Mat   J;

  PetscFunctionBeginUser;
  PetscCall(SNESGetJacobian(snes, &J, A, &fn, &ctx));
  if (!*A) { /* PETSc's integration leaves the matrices to the SNES's set-up (the DM's) */
    PetscCall(SNESSetUp(snes));
    PetscCall(SNESGetJacobian(snes, &J, A, &fn, &ctx));
  }
  PetscCall((*fn)(snes, x, J, *A, ctx));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingProblemCoupledResidual(CouplingProblem P, Vec xf, Vec xs, Vec x, Vec Ff, Vec Fs, Vec Fx)
{
  SNES snes;
  Vec  history, state;

  PetscFunctionBeginUser;
  /* the structure at x_s under the load of x; then the mesh follows it */
  PetscCall(CouplingProblemStructureLoad(P, x));
  PetscCall(StructureSetDisplacement(P->structure, xs, P->structure_vec));
  PetscCall(CouplingProblemMoveMesh(P));
  PetscCall(StructureGetNonlinearSystem(P->structure, &snes, &history, NULL));
  PetscCall(PetscLogStagePush(FSIOPT_STAGE_STRUCTURE));
  PetscCall(SystemFunction(snes, xs, Fs));
  PetscCall(PetscLogStagePop());
  PetscCall(VecAXPY(Fs, -1.0, history));
  PetscCall(VecAXPY(Fs, 1.0, P->structure_vec));
  PetscCall(StructureVelocityLocal(P->structure, P->measure, P->structure_local));
  /* the fluid at x_f under the load of x */
  PetscCall(VecAXPY(P->all_q, 1.0, P->datum_load));
  PetscCall(VecZeroEntries(P->fluid_vec));
  PetscCall(InterfaceFluidSpread(P->itf, P->all_q, P->fluid_vec));
  PetscCall(FluidGetSolution(P->fluid, &state));
  PetscCall(VecCopy(xf, state));
  PetscCall(FluidGetNonlinearSystem(P->fluid, &snes, &history));
  PetscCall(PetscLogStagePush(FSIOPT_STAGE_FLUID));
  PetscCall(SystemFunction(snes, xf, Ff));
  PetscCall(PetscLogStagePop());
  PetscCall(VecAXPY(Ff, -1.0, history));
  PetscCall(VecAXPY(Ff, -1.0, P->fluid_vec));
  PetscCall(FluidGlobalToLocal(P->fluid, xf, P->fluid_local));
  /* the jump; and the state of x, which the step's end then finds in hand */
  PetscCall(CouplingProblemStateJump(P, 1.0, P->r, &P->state_jump));
  PetscCall(VecPointwiseMult(Fx, P->r, P->weight_sqrt));
  PetscCall(VecCopy(x, P->state_x));
  PetscCall(VecCopy(Fx, P->state_F));
  P->state_valid = PETSC_TRUE;
  PetscFunctionReturn(0);
}
