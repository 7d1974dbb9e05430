/* The maps between the optimizer's scaled control x = W^{1/2} g and the interface loads
   the subproblems see, both ways: every evaluation (residual.c, products.c, sweep.c)
   and the first step's control go through them, so the scaling and the interface mass
   are applied in one place only. */
#include "problem_impl.h"

PetscErrorCode CouplingProblemInterfaceDisplacement(CouplingProblem P, Vec all)
{
  Vec eta = NULL;

  PetscFunctionBeginUser;
  if (P->structure) PetscCall(StructureGetDisplacementLocal(P->structure, &eta));
  PetscCall(InterfaceStructureTrace(P->itf, eta, all));
  PetscFunctionReturn(0);
}

/* The interface traction g = P^T W^{-1/2} x of the control the last step ended with, on all
   interface nodes (0 where the fluid's velocity is prescribed); 0 before a first step. */
PetscErrorCode CouplingProblemInterfaceTraction(CouplingProblem P, Vec all)
{
  PetscFunctionBeginUser;
  PetscCall(VecPointwiseDivide(P->g, P->accepted, P->weight_sqrt));
  PetscCall(InterfaceExtend(P->itf, P->g, all));
  PetscFunctionReturn(0);
}

/* q = M P^T W^{-1/2} x: the interface load of a scaled control, on all interface nodes. */
PetscErrorCode CouplingProblemControlToLoad(CouplingProblem P, Vec x, Vec q)
{
  PetscFunctionBeginUser;
  PetscCall(VecPointwiseDivide(P->g, x, P->weight_sqrt));
  PetscCall(InterfaceExtend(P->itf, P->g, P->all_a));
  PetscCall(MatMult(P->mass, P->all_a, q));
  PetscFunctionReturn(0);
}

/* structure_vec = B_s g for the scaled control x (the structure solves R_s = -B_s g);
   all_q keeps the interface load M P^T g. */
PetscErrorCode CouplingProblemStructureLoad(CouplingProblem P, Vec x)
{
  PetscFunctionBeginUser;
  PetscCall(CouplingProblemControlToLoad(P, x, P->all_q));
  if (P->structure) PetscCall(VecZeroEntries(P->structure_vec));
  PetscCall(InterfaceStructureSpread(P->itf, P->all_q, P->structure ? P->structure_vec : NULL));
  PetscFunctionReturn(0);
}

static PetscErrorCode ControlMassMult(Mat A, Vec x, Vec y)
{
  CouplingProblem P;

  PetscFunctionBeginUser;
  PetscCall(MatShellGetContext(A, &P));
  PetscCall(InterfaceExtend(P->itf, x, P->all_a));
  PetscCall(MatMult(P->mass, P->all_a, P->all_b));
  PetscCall(InterfaceRestrict(P->itf, P->all_b, y));
  PetscFunctionReturn(0);
}

/* g = (P M P^T)^{-1} b: the control whose load on the control rows is b. CG on the
   (small, well-conditioned) interface mass, kept for the run. */
PetscErrorCode CouplingProblemControlMassSolve(CouplingProblem P, Vec b, Vec g)
{
  PetscFunctionBeginUser;
  if (!P->control_mass_ksp) {
    Mat      A;
    PC       pc;
    PetscInt n, N;
    PetscCall(VecGetLocalSize(g, &n));
    PetscCall(VecGetSize(g, &N));
    PetscCall(MatCreateShell(P->comm, n, n, N, N, P, &A));
    PetscCall(MatShellSetOperation(A, MATOP_MULT, (void (*)(void))ControlMassMult));
    PetscCall(KSPCreate(P->comm, &P->control_mass_ksp));
    PetscCall(KSPSetType(P->control_mass_ksp, KSPCG));
    PetscCall(KSPSetOperators(P->control_mass_ksp, A, A));
    PetscCall(KSPGetPC(P->control_mass_ksp, &pc));
    PetscCall(PCSetType(pc, PCNONE));
    PetscCall(KSPSetTolerances(P->control_mass_ksp, 1e-14, 1e-300, PETSC_DEFAULT, 1000));
    PetscCall(MatDestroy(&A));
  }
  PetscCall(KSPSolve(P->control_mass_ksp, b, g));
  PetscFunctionReturn(0);
}

/* The control that acts on the free rows as the traction t does: the solution of
   P M P^T g = P M t. Restricting t's nodal values instead would drop its part on the
   constrained nodes, an O(1) error in the elements next to them. */
static PetscErrorCode TractionToControl(CouplingProblem P, Vec traction_all, Vec g)
{
  Vec b;

  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(g, &b));
  PetscCall(MatMult(P->mass, traction_all, P->all_b));
  PetscCall(InterfaceRestrict(P->itf, P->all_b, b));
  PetscCall(CouplingProblemControlMassSolve(P, b, g));
  PetscCall(VecDestroy(&b));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingProblemInitialControl(CouplingProblem P, PetscReal t0, Vec x)
{
  PetscFunctionBeginUser;
  PetscCall(VecZeroEntries(x));
  if (P->fluid_data.interface_traction) {
    PetscCall(InterfaceInterpolate(P->itf, P->fluid_data.interface_traction, P->fluid_data.ctx, t0, P->all_q));
    PetscCall(TractionToControl(P, P->all_q, x));
    PetscCall(VecPointwiseMult(x, x, P->weight_sqrt));
  }
  /* the midpoint structure averages the traction of this and the previous step */
  PetscCall(CouplingProblemStructureLoad(P, x));
  if (P->structure) PetscCall(StructureSetInitialLoad(P->structure, P->structure_vec));
  PetscFunctionReturn(0);
}
