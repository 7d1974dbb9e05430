/* The Dirichlet-Neumann sweep of the partitioned baselines (partitioned.c; opt never
   calls it): the same subproblems and loads as F(x), but the fluid gets the structure's
   interface velocity and returns its reaction as a control, so that the baselines and
   the optimization differ only in how they couple, not in what they solve. */
#include "problem_impl.h"
#include "fem.h"
#include "logging.h"

PetscErrorCode CouplingProblemCheckSweepable(CouplingProblem P)
{
  PetscFunctionBeginUser;
  PetscCheck(P->variant == CONTROL_TRACTION, P->comm, PETSC_ERR_SUP,
             "option -coupling_control convective: the Dirichlet-Neumann methods exchange the traction itself; use "
             "-coupling_control traction");
  /* with the interface velocity prescribed too, an enclosed fluid's pressure is
     undetermined and its volume cannot change (the incompressibility dilemma) */
  PetscCheck(P->fluid_data.n_traction > 0, P->comm, PETSC_ERR_SUP,
             "option -coupling: the Dirichlet-Neumann methods (dn, aitken, iqnils, iqnimvj) need a fluid boundary with "
             "a "
             "traction condition besides the interface; this scene's fluid is enclosed (incompressibility dilemma): "
             "use -coupling opt");
  /* the Dirichlet fluid's solver now, so that its options are read before the run checks them */
  if (P->fluid) {
    if (!P->fluid_interface_rows) PetscCall(InterfaceGetFluidRows(P->itf, &P->fluid_interface_rows));
    PetscCall(FluidSetUpDirichlet(P->fluid, P->fluid_interface_rows));
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode SweepBegin(CouplingProblem P)
{
  PetscFunctionBeginUser;
  P->state_valid = PETSC_FALSE; /* the state will not be the traction-controlled one */
  P->swept       = PETSC_TRUE;
  PetscFunctionReturn(0);
}

/* The structure under the control x; v_s (all interface nodes) its interface velocity. */
static PetscErrorCode StructureUnderControl(CouplingProblem P, Vec x, Vec v_s)
{
  PetscFunctionBeginUser;
  PetscCall(CouplingProblemStructureLoad(P, x));
  PetscCall(CouplingProblemSolveStructure(P));
  PetscCall(InterfaceStructureTrace(P->itf, P->structure ? P->structure_local : NULL, v_s));
  PetscFunctionReturn(0);
}

/* The fluid with the interface velocity v (all interface nodes) prescribed; x the control
   whose load equals its reaction. */
static PetscErrorCode FluidUnderVelocity(CouplingProblem P, Vec v, Vec x)
{
  PetscFunctionBeginUser;
  if (P->fluid) {
    Vec state;
    PetscCall(VecZeroEntries(P->fluid_vec)); /* its rows: CouplingProblemCheckSweepable */
    PetscCall(InterfaceFluidSpread(P->itf, v, P->fluid_vec));
    PetscCall(PetscLogStagePush(FSIOPT_STAGE_FLUID));
    PetscCall(FluidSolveDirichlet(P->fluid, P->fluid_interface_rows, P->fluid_vec, P->fluid_sol, P->step));
    PetscCall(PetscLogStagePop());
    PetscCall(FluidGetSolution(P->fluid, &state));
    PetscCall(FluidGlobalToLocal(P->fluid, state, P->fluid_local));
  }
  PetscCall(InterfaceFluidGather(P->itf, P->fluid ? P->fluid_sol : NULL, P->all_a));
  PetscCall(InterfaceRestrict(P->itf, P->all_a, P->r));
  PetscCall(CouplingProblemControlMassSolve(P, P->r, x));
  PetscCall(VecPointwiseMult(x, x, P->weight_sqrt));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingProblemSweep(CouplingProblem P, Vec x, Vec x_new)
{
  PetscBool failed;

  PetscFunctionBeginUser;
  PetscCall(SweepBegin(P));
  PetscCall(StructureUnderControl(P, x, P->all_b));
  PetscCall(CouplingProblemCollectFailure(P, &failed));
  if (!failed) PetscCall(CouplingProblemMoveMesh(P));
  if (!StepFailed(&P->failure)) PetscCall(FluidUnderVelocity(P, P->all_b, x_new));
  PetscCall(CouplingProblemCollectFailure(P, &failed));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingProblemSweepVelocity(CouplingProblem P, Vec v, Vec x, Vec v_new)
{
  PetscBool failed;

  PetscFunctionBeginUser;
  PetscCall(SweepBegin(P));
  PetscCall(CouplingProblemMoveMesh(P)); /* the wall of the last structure solve: the domain lags one sweep */
  if (!StepFailed(&P->failure)) PetscCall(FluidUnderVelocity(P, v, x));
  PetscCall(CouplingProblemCollectFailure(P, &failed));
  if (!failed) PetscCall(StructureUnderControl(P, x, v_new));
  PetscCall(CouplingProblemCollectFailure(P, &failed));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingProblemCreateInterfaceVector(CouplingProblem P, Vec *v)
{
  PetscFunctionBeginUser;
  PetscCall(InterfaceCreateVector(P->itf, v));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingProblemSweepJump(CouplingProblem P, PetscReal *jump)
{
  PetscFunctionBeginUser;
  PetscCheck(P->swept, P->comm, PETSC_ERR_ORDER, "no sweep to measure");
  PetscCall(CouplingProblemStateJump(P, 1.0, P->r, jump));
  PetscFunctionReturn(0);
}
