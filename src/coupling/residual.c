/* F(x), the interface velocity jump under the control x: one nonlinear solve of each
   subproblem. The state of the last x is kept, and with it the fluid's factors, because
   TAO asks for F, J h and J^T r at the same point several times and products.c solves
   with those factors; here is decided when a new factorization is worth its cost. */
#include "problem_impl.h"
#include "fem.h"
#include "logging.h"

/* r = P (T_f fluid_local - T_s structure_local), the jump at the control nodes; and its L2 norm */
PetscErrorCode CouplingProblemStateJump(CouplingProblem P, PetscReal structure_scale, Vec r, PetscReal *l2)
{
  PetscFunctionBeginUser;
  PetscCall(InterfaceFluidTrace(P->itf, P->fluid_local, P->all_a));
  PetscCall(InterfaceStructureTrace(P->itf, P->structure_local, P->all_b));
  PetscCall(VecAXPY(P->all_a, -structure_scale, P->all_b));
  PetscCall(InterfaceRestrict(P->itf, P->all_a, r));
  if (l2) {
    PetscScalar dot;
    PetscCall(InterfaceExtend(P->itf, r, P->all_a));
    PetscCall(MatMult(P->mass, P->all_a, P->all_b));
    PetscCall(VecDot(P->all_a, P->all_b, &dot));
    *l2 = PetscSqrtReal(PetscMax(PetscRealPart(dot), 0.0));
  }
  PetscFunctionReturn(0);
}

/* The fluid domain follows the structure's interface displacement: the one of the last
   evaluation (lagged, seed Algorithm 3.3) or of this one (current). Collective. */
PetscErrorCode CouplingProblemMoveMesh(CouplingProblem P)
{
  PetscFunctionBeginUser;
  if (!P->moving) PetscFunctionReturn(0);
  {
    Vec eta = NULL;
    if (P->structure) PetscCall(StructureGetDisplacementLocal(P->structure, &eta));
    PetscCall(InterfaceStructureTrace(P->itf, eta, P->all_a));
  }
  if (P->motion) {
    PetscCall(PetscLogStagePush(FSIOPT_STAGE_MESH_MOTION));
    PetscCall(MeshMotionSolve(P->motion, P->itf, P->all_a, P->mesh_displacement));
    PetscCall(FluidSetMeshDisplacement(P->fluid, P->mesh_displacement));
    PetscCall(PetscLogStagePop());
  }
  PetscCall(CouplingProblemCollectFailure(P, NULL));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingProblemSolveStructure(CouplingProblem P)
{
  PetscFunctionBeginUser;
  if (!P->structure) PetscFunctionReturn(0);
  PetscCall(PetscLogStagePush(FSIOPT_STAGE_STRUCTURE));
  PetscCall(StructureSolve(P->structure, P->structure_vec, P->step));
  PetscCall(StructureVelocityLocal(P->structure, P->measure, P->structure_local));
  PetscCall(PetscLogStagePop());
  PetscFunctionReturn(0);
}

/* After a subproblem failed in this step, every further evaluation is skipped: F = 0,
   J = I, and the step's caller reads the failure (CouplingProblemGetFailure). */
PetscErrorCode CouplingProblemResidual(CouplingProblem P, Vec x, Vec F)
{
  PetscBool same = PETSC_FALSE, failed = StepFailed(&P->failure);

  PetscFunctionBeginUser;
  if (failed) {
    PetscCall(VecZeroEntries(F));
    PetscFunctionReturn(0);
  }
  if (P->state_valid) PetscCall(VecEqual(x, P->state_x, &same));
  if (same) {
    PetscCall(VecCopy(P->state_F, F));
    PetscFunctionReturn(0);
  }
  if (P->predict && P->state_valid && P->jacobian_valid) {
    /* u(x) ~ u(x_last) + du/dg (x - x_last): then the chord iterations start within
       O(|x - x_last|^2) of the solution and the state-relative tolerance ends them early */
    PetscCall(VecWAXPY(P->control_change, -1.0, P->state_x, x));
    PetscCall(CouplingProblemControlToLoad(P, P->control_change, P->all_q));
    if (P->fluid) {
      Vec state;
      PetscCall(VecZeroEntries(P->fluid_vec));
      PetscCall(InterfaceFluidSpread(P->itf, P->all_q, P->fluid_vec));
      PetscCall(PetscLogStagePush(FSIOPT_STAGE_FLUID));
      PetscCall(FluidLinearSolveGuess(P->fluid, P->fluid_vec, P->fluid_sol));
      PetscCall(PetscLogStagePop());
      PetscCall(FluidGetSolution(P->fluid, &state));
      PetscCall(VecAXPY(state, 1.0, P->fluid_sol));
    }
  }
  PetscCall(CouplingProblemStructureLoad(P, x));
  PetscCall(VecAXPY(P->all_q, 1.0, P->datum_load));
  if (P->fluid) {
    PetscCall(VecZeroEntries(P->fluid_vec));
    PetscCall(InterfaceFluidSpread(P->itf, P->all_q, P->fluid_vec));
  }
  /* On separate ranks these two run at the same time on a lagged domain; on the current
     one the fluid waits for the structure's displacement. */
  if (P->domain == DOMAIN_CURRENT) {
    PetscCall(CouplingProblemSolveStructure(P));
    PetscCall(CouplingProblemCollectFailure(P, &failed));
    if (!failed) PetscCall(CouplingProblemMoveMesh(P));
    if (StepFailed(&P->failure)) {
      PetscCall(VecZeroEntries(F));
      PetscFunctionReturn(0);
    }
  }
  if (P->fluid) {
    Vec state;
    PetscCall(PetscLogStagePush(FSIOPT_STAGE_FLUID));
    PetscCall(FluidSolve(P->fluid, P->fluid_vec, P->step));
    PetscCall(FluidGetSolution(P->fluid, &state));
    PetscCall(FluidGlobalToLocal(P->fluid, state, P->fluid_local));
    PetscCall(PetscLogStagePop());
  }
  if (P->domain == DOMAIN_LAGGED) PetscCall(CouplingProblemSolveStructure(P));
  PetscCall(CouplingProblemCollectFailure(P, &failed));
  if (failed) {
    PetscCall(VecZeroEntries(F));
    PetscFunctionReturn(0);
  }
  PetscCall(CouplingProblemStateJump(P, 1.0, P->r, &P->state_jump));
  PetscCall(VecPointwiseMult(F, P->r, P->weight_sqrt));
  PetscCall(VecCopy(x, P->state_x));
  PetscCall(VecCopy(F, P->state_F));
  P->state_valid = PETSC_TRUE;
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingProblemEnsureState(CouplingProblem P, Vec x)
{
  PetscFunctionBeginUser;
  PetscCall(CouplingProblemResidual(P, x, P->r));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingProblemJump(CouplingProblem P, Vec x, PetscReal *jump)
{
  PetscFunctionBeginUser;
  PetscCall(CouplingProblemEnsureState(P, x));
  *jump = P->state_jump;
  PetscFunctionReturn(0);
}

/* only when asked (a relative tolerance): from the state of x, in hand */
PetscErrorCode CouplingProblemInterfaceVelocity(CouplingProblem P, Vec x, PetscReal *velocity)
{
  PetscScalar dot;

  PetscFunctionBeginUser;
  PetscCall(CouplingProblemEnsureState(P, x));
  /* from the structure's state: structure_local is the products' work vector once they ran at x */
  if (P->structure) {
    DM  dm;
    Vec velocity_local;

    PetscCall(StructureGetDM(P->structure, &dm));
    PetscCall(DMGetLocalVector(dm, &velocity_local));
    PetscCall(StructureVelocityLocal(P->structure, P->measure, velocity_local));
    PetscCall(InterfaceStructureTrace(P->itf, velocity_local, P->all_velocity));
    PetscCall(DMRestoreLocalVector(dm, &velocity_local));
  } else PetscCall(InterfaceStructureTrace(P->itf, NULL, P->all_velocity));
  PetscCall(MatMult(P->mass, P->all_velocity, P->all_mass_velocity));
  PetscCall(VecDot(P->all_velocity, P->all_mass_velocity, &dot));
  *velocity = PetscSqrtReal(PetscMax(PetscRealPart(dot), 0.0));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingProblemSetConvergedJump(CouplingProblem P, PetscReal jump)
{
  PetscFunctionBeginUser;
  P->converged_jump = jump;
  PetscFunctionReturn(0);
}

/* force: the fluid's factors of x even where the jump has converged or the lag would keep
   older ones */
static PetscErrorCode UpdateJacobian(CouplingProblem P, Vec x, PetscBool force)
{
  PetscBool same = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(CouplingProblemEnsureState(P, x));
  if (StepFailed(&P->failure)) PetscFunctionReturn(0);
  /* TAO asks for the gradient at every new point, also at the one its stopping test will
     accept: there the factors in hand serve (the gradient is only reported), and the
     next step's chord iterations start from them. */
  if (!force && P->state_jump <= P->converged_jump) PetscFunctionReturn(0);
  if (P->domain == DOMAIN_LAGGED) PetscCall(CouplingProblemMoveMesh(P));
  if (StepFailed(&P->failure)) PetscFunctionReturn(0);
  if (P->jacobian_valid) PetscCall(VecEqual(x, P->jacobian_x, &same));
  if (same && (!force || P->jacobian_fresh)) PetscFunctionReturn(0);
  /* the same decision on every rank */
  P->jacobian_fresh = force || ++P->jacobian_age >= P->jacobian_lag ? PETSC_TRUE : PETSC_FALSE;
  if (P->fluid && (P->jacobian_fresh || P->lag_preconditioner_only)) {
    PetscCall(PetscLogStagePush(FSIOPT_STAGE_FLUID));
    PetscCall(FluidUpdateJacobian(P->fluid, (PetscBool)!P->jacobian_fresh));
    PetscCall(PetscLogStagePop());
  }
  if (P->jacobian_fresh) P->jacobian_age = 0;
  PetscCall(VecCopy(x, P->jacobian_x));
  P->jacobian_valid = PETSC_TRUE;
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingProblemUpdateJacobian(CouplingProblem P, Vec x)
{
  PetscFunctionBeginUser;
  PetscCall(UpdateJacobian(P, x, PETSC_FALSE));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingProblemRefreshJacobian(CouplingProblem P, Vec x)
{
  PetscFunctionBeginUser;
  PetscCall(UpdateJacobian(P, x, PETSC_TRUE));
  PetscFunctionReturn(0);
}
