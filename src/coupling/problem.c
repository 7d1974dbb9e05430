/* The control problem of one time step (coupling.h has the algebra and the signs): the
   object that owns the work vectors and reads the options, and the frame of a step around
   the evaluations, so that every evaluation starts from the same reset state and a
   subproblem's failure is known on every rank before anything else runs. The evaluations
   are in control_maps.c, residual.c, products.c and sweep.c, the checks in
   derivative_checks.c; what they share is in problem_impl.h. */
#include "problem_impl.h"
#include "checkpoint.h"
#include "fem.h"
#include "options.h"
#include "logging.h"

static const char *const ControlVariants[]  = {"traction", "convective", "ControlVariant", "CONTROL_", NULL};
static const char *const DomainUpdates[]    = {"lagged", "current", "DomainUpdate", "DOMAIN_", NULL};
static const char *const VelocityMeasures[] = {"scheme", "difference", "StructureVelocityMeasure",
                                               "STRUCTURE_VELOCITY_", NULL};

/* A subproblem's failure, made known on every rank (the fluid's and the structure's may
   be different ones) with the reason of the first failing rank; failed may be NULL.
   Collective. */
PetscErrorCode CouplingProblemCollectFailure(CouplingProblem P, PetscBool *failed)
{
  const char *reason = NULL;
  PetscMPIInt rank, size, mine, first;
  PetscBool   any;

  PetscFunctionBeginUser;
  if (P->fluid) PetscCall(FluidGetFailure(P->fluid, &reason));
  if (!reason && P->structure) PetscCall(StructureGetFailure(P->structure, &reason));
  PetscCallMPI(MPI_Comm_rank(P->comm, &rank));
  PetscCallMPI(MPI_Comm_size(P->comm, &size));
  mine = reason || StepFailed(&P->failure) ? rank : size;
  PetscCallMPI(MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, P->comm));
  any = first < size ? PETSC_TRUE : PETSC_FALSE;
  if (failed) *failed = any;
  if (!any || StepFailed(&P->failure)) PetscFunctionReturn(0);
  if (rank == first) PetscCall(PetscStrncpy(P->failure.reason, reason, sizeof(P->failure.reason)));
  PetscCallMPI(MPI_Bcast(P->failure.reason, sizeof(P->failure.reason), MPI_CHAR, first, P->comm));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingProblemGetFailure(CouplingProblem P, const char **reason)
{
  PetscFunctionBeginUser;
  *reason = StepFailureReason(&P->failure);
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingProblemSetTimeStep(CouplingProblem P, PetscReal dt)
{
  PetscFunctionBeginUser;
  if (P->fluid) PetscCall(FluidSetTimeStep(P->fluid, dt));
  if (P->structure) {
    PetscCall(StructureSetTimeStep(P->structure, dt));
    P->velocity_coefficient = StructureVelocityCoefficient(P->structure, P->measure);
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &P->velocity_coefficient, 1, MPIU_REAL, MPI_MAX, P->comm));
  P->spacing_changed = PETSC_TRUE;
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingProblemGetControlVariant(ControlVariant *variant)
{
  PetscFunctionBeginUser;
  *variant = CONTROL_TRACTION;
  PetscCall(PetscOptionsGetEnum(NULL, NULL, "-coupling_control", ControlVariants, (PetscEnum *)variant, NULL));
  PetscFunctionReturn(0);
}

/* The discrete initial state must satisfy the coupling condition: a fluid started from
   its Stokes projection has an interface trace O(h^3) away from the structure's
   interpolated velocity, and with a small dt the first step would turn that into an
   O(h^3/dt) acceleration. The structure, without a constraint to keep, takes the fluid's
   trace instead (a no-op for scenes that start at rest). */
static PetscErrorCode MatchInitialVelocity(CouplingProblem P)
{
  Vec etadot = NULL;

  PetscFunctionBeginUser;
  if (P->fluid) {
    Vec state;
    PetscCall(FluidGetSolution(P->fluid, &state));
    PetscCall(FluidGlobalToLocal(P->fluid, state, P->fluid_local));
  }
  PetscCall(InterfaceFluidTrace(P->itf, P->fluid_local, P->all_a));
  if (P->structure) PetscCall(StructureGetVelocityLocal(P->structure, &etadot));
  PetscCall(InterfaceStructureInsertLocal(P->itf, P->all_a, etadot));
  if (P->structure) PetscCall(StructureRestoreVelocityLocal(P->structure, &etadot));
  PetscFunctionReturn(0);
}

/* The options of the coupled problem, checked against the fluid's solver; the structure's
   velocity coefficient, agreed on by every rank */
static PetscErrorCode CouplingProblemSetFromOptions(CouplingProblem P)
{
  PetscBool lag_set = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscOptionsBegin(P->comm, NULL, "Coupling problem options", "coupling");
  PetscCall(PetscOptionsEnum("-coupling_control",
                             "What the control replaces: the fluid traction (Kuberry 2015 ch. 3, 6) or the traction minus the "
                             "convective boundary flux 1/2 rho ((u-z).n) u (Kuberry 2015 ch. 4, 5)",
                             NULL, ControlVariants, (PetscEnum)P->variant, (PetscEnum *)&P->variant, NULL));
  PetscCall(PetscOptionsEnum("-coupling_velocity",
                             "Structure velocity matched on the interface: the scheme's own (Kuberry 2015 ch. 3, 6) or (eta^n "
                             "- eta^{n-1})/dt (Kuberry 2015 ch. 4, 5)",
                             NULL, VelocityMeasures, (PetscEnum)P->measure, (PetscEnum *)&P->measure, NULL));
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-coupling_jacobian_lag",
                              "refactor the fluid Jacobian at every K-th Gauss-Newton iteration (1: exact "
                              "Gauss-Newton; more: an older Jacobian in J h and J^T r; with a Krylov fluid solver "
                              "and -coupling_lag_preconditioner_only, only its preconditioner is that old)",
                              1, 1000000, &P->jacobian_lag));
  PetscCall(PetscOptionsBool("-coupling_lag_preconditioner_only",
                             "with a Krylov fluid solver: assemble the fluid Jacobian at every Gauss-Newton iteration "
                             "(exact J h and J^T r, Newton steps in the fluid solves) and lag only its preconditioner "
                             "by -coupling_jacobian_lag",
                             NULL, P->lag_preconditioner_only, &P->lag_preconditioner_only, &lag_set));
  PetscCall(PetscOptionsBool("-coupling_predictor",
                             "start each fluid solve of a step from the last state plus its linearized response to the "
                             "control's change (one solve with the factors in hand)",
                             NULL, P->predict, &P->predict, NULL));
  PetscCall(PetscOptionsEnum("-coupling_domain",
                             "Fluid domain of an evaluation of F(g): the structure's displacement of the previous "
                             "Gauss-Newton iteration (Kuberry 2015 Algorithm 3.3: fluid and structure solve at the same time) "
                             "or of this one (the structure solves first, then the mesh moves, then the fluid solves)",
                             NULL, DomainUpdates, (PetscEnum)P->domain, (PetscEnum *)&P->domain, NULL));
  PetscCall(PetscOptionsBool("-coupling_mesh_extrapolate",
                             "start each step on the fluid mesh 2 d^{n-1} - d^{n-2} instead of d^{n-1}: the first "
                             "iterations see a domain O(dt^2) (not O(dt)) from the one they will end on",
                             NULL, P->extrapolate_mesh, &P->extrapolate_mesh, NULL));
  PetscCall(OptionsNonNegativeReal(PetscOptionsObject, "-coupling_tikhonov",
                                   "Tikhonov weight epsilon (delta) of eps/2 ||g||^2_{L2(Gamma_I)}", &P->tikhonov));
  PetscOptionsEnd();
  if (P->fluid) {
    PetscBool krylov;
    PetscCall(FluidSolverIsKrylov(P->fluid, &krylov));
    P->fluid_krylov = krylov;
    PetscCheck(krylov || !lag_set || !P->lag_preconditioner_only, P->comm, PETSC_ERR_ARG_INCOMP,
               "option -coupling_lag_preconditioner_only: expected a Krylov fluid solver (-fluid_ksp_type other than "
               "preonly); a factorization is its own preconditioner");
    P->lag_preconditioner_only = (PetscBool)(P->lag_preconditioner_only && krylov);
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &P->fluid_krylov, 1, MPIU_BOOL, MPI_LOR, P->comm));
  if (P->structure) P->velocity_coefficient = StructureVelocityCoefficient(P->structure, P->measure);
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &P->velocity_coefficient, 1, MPIU_REAL, MPI_MAX, P->comm));

  PetscFunctionReturn(0);
}

/* The control's weight (square roots of the lumped interface mass), the work vectors on the
   interface and on each subproblem this rank holds, and the fluid mesh's motion */
static PetscErrorCode CouplingProblemCreateVectors(CouplingProblem P)
{
  PetscReal wmin;

  PetscFunctionBeginUser;
  PetscCall(InterfaceGetMass(P->itf, &P->mass));
  PetscCall(InterfaceCreateControlVector(P->itf, &P->weight_sqrt));
  {
    Vec lumped;
    PetscCall(InterfaceGetLumpedControlMass(P->itf, &lumped));
    PetscCall(VecMin(lumped, NULL, &wmin));
    PetscCheck(wmin > 0, P->comm, PETSC_ERR_SUP,
               "interface: the lumped interface mass has a non-positive entry (%g); its weight needs positive ones",
               (double)wmin);
    PetscCall(VecCopy(lumped, P->weight_sqrt));
    PetscCall(VecSqrtAbs(P->weight_sqrt));
  }
  PetscCall(VecDuplicate(P->weight_sqrt, &P->g));
  PetscCall(VecDuplicate(P->weight_sqrt, &P->r));
  PetscCall(VecDuplicate(P->weight_sqrt, &P->state_x));
  PetscCall(VecDuplicate(P->weight_sqrt, &P->accepted));
  PetscCall(VecDuplicate(P->weight_sqrt, &P->state_F));
  PetscCall(VecDuplicate(P->weight_sqrt, &P->jacobian_x));
  PetscCall(VecDuplicate(P->weight_sqrt, &P->control_change));
  PetscCall(InterfaceCreateVector(P->itf, &P->all_a));
  PetscCall(VecDuplicate(P->all_a, &P->all_b));
  PetscCall(VecDuplicate(P->all_a, &P->all_q));
  PetscCall(VecDuplicate(P->all_a, &P->datum_load));
  PetscCall(VecDuplicate(P->all_a, &P->all_velocity));
  PetscCall(VecDuplicate(P->all_a, &P->all_mass_velocity));
  if (P->fluid) {
    DM dm;
    PetscCall(FluidGetDM(P->fluid, &dm));
    PetscCall(DMCreateGlobalVector(dm, &P->fluid_vec));
    PetscCall(VecDuplicate(P->fluid_vec, &P->fluid_sol));
    PetscCall(DMCreateLocalVector(dm, &P->fluid_local));
  }
  if (P->structure) {
    DM dm;
    PetscCall(StructureGetDM(P->structure, &dm));
    PetscCall(DMCreateGlobalVector(dm, &P->structure_vec));
    PetscCall(VecDuplicate(P->structure_vec, &P->structure_sol));
    PetscCall(DMCreateLocalVector(dm, &P->structure_local));
  }
  P->moving = P->fluid_data.n_fixed_mesh_faces ? PETSC_TRUE : PETSC_FALSE;
  if (P->moving) {
    if (P->fluid) {
      DM  dm;
      Vec d;
      PetscCall(FluidGetDM(P->fluid, &dm));
      PetscCall(MeshMotionCreate(dm, P->fluid_data.interface_face, P->fluid_data.n_fixed_mesh_faces,
                                 P->fluid_data.fixed_mesh_faces, &P->motion));
      PetscCall(FluidGetMeshDisplacement(P->fluid, &d));
      PetscCall(VecDuplicate(d, &P->mesh_displacement));
      PetscCall(VecDuplicate(d, &P->mesh_displacement_before));
      PetscCall(VecCopy(d, P->mesh_displacement_before));
    }
  }
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingProblemCreate(MPI_Comm comm, Fluid fluid, Structure structure, Interface itf,
                                     const PhysicsData *fluid_data, CouplingProblem *problem)
{
  CouplingProblem P;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&P));
  P->comm                    = comm;
  P->fluid                   = fluid;
  P->structure               = structure;
  P->itf                     = itf;
  P->fluid_data              = *fluid_data;
  P->variant                 = CONTROL_TRACTION;
  P->measure                 = STRUCTURE_VELOCITY_SCHEME;
  P->converged_jump          = -1;
  P->jacobian_lag            = 1;
  P->lag_preconditioner_only = PETSC_TRUE;
  P->predict                 = PETSC_TRUE;
  P->extrapolate_mesh        = PETSC_TRUE;
  PetscCall(CouplingProblemSetFromOptions(P));
  PetscCall(CouplingProblemCreateVectors(P));
  PetscCall(MatchInitialVelocity(P));
  *problem = P;
  PetscFunctionReturn(0);
}

static PetscErrorCode MeshDisplacementsCheckpoint(CouplingProblem P, DM dm, Checkpoint cp, PetscBool load)
{
  DM cdm;

  PetscFunctionBeginUser;
  PetscCall(DMGetCoordinateDM(dm, &cdm));
  PetscCall(CheckpointLocalVec(cp, "mesh_displacement", cdm, P->mesh_displacement, load));
  PetscCall(CheckpointLocalVec(cp, "mesh_displacement_before", cdm, P->mesh_displacement_before, load));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingProblemCheckpoint(CouplingProblem P, Checkpoint cp, PetscBool load)
{
  DM dm = NULL;

  PetscFunctionBeginUser;
  /* the mesh displacements are the fluid ranks' part */
  if (P->fluid) PetscCall(FluidGetDM(P->fluid, &dm));
  PetscCall(CheckpointBeginPart(cp, dm ? PetscObjectComm((PetscObject)dm) : MPI_COMM_NULL));
  PetscCall(CheckpointEndPart(cp, P->motion ? MeshDisplacementsCheckpoint(P, dm, cp, load) : 0));
  if (CheckpointResynchronizes(cp, load))
    P->jacobian_age = 0; /* the fluid refactors at the next step (FluidCheckpoint) */
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingProblemDestroy(CouplingProblem *problem)
{
  CouplingProblem P = *problem;

  PetscFunctionBeginUser;
  if (!P) PetscFunctionReturn(0);
  PetscCall(VecDestroy(&P->weight_sqrt));
  PetscCall(VecDestroy(&P->g));
  PetscCall(VecDestroy(&P->r));
  PetscCall(VecDestroy(&P->state_x));
  PetscCall(VecDestroy(&P->accepted));
  PetscCall(VecDestroy(&P->state_F));
  PetscCall(VecDestroy(&P->jacobian_x));
  PetscCall(VecDestroy(&P->control_change));
  PetscCall(VecDestroy(&P->all_a));
  PetscCall(VecDestroy(&P->all_velocity));
  PetscCall(VecDestroy(&P->all_mass_velocity));
  PetscCall(VecDestroy(&P->all_b));
  PetscCall(VecDestroy(&P->all_q));
  PetscCall(VecDestroy(&P->datum_load));
  PetscCall(VecDestroy(&P->fluid_vec));
  PetscCall(VecDestroy(&P->fluid_sol));
  PetscCall(VecDestroy(&P->fluid_local));
  PetscCall(VecDestroy(&P->structure_vec));
  PetscCall(VecDestroy(&P->structure_sol));
  PetscCall(VecDestroy(&P->structure_local));
  PetscCall(MatDestroy(&P->fluid_rhs_block));
  PetscCall(MatDestroy(&P->fluid_sol_block));
  PetscCall(MatDestroy(&P->structure_rhs_block));
  PetscCall(MatDestroy(&P->structure_sol_block));
  PetscCall(VecDestroy(&P->mesh_displacement));
  PetscCall(VecDestroy(&P->mesh_displacement_before));
  PetscCall(KSPDestroy(&P->control_mass_ksp));
  PetscCall(ISDestroy(&P->fluid_interface_rows));
  PetscCall(MeshMotionDestroy(&P->motion));
  PetscCall(PetscFree(*problem));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingProblemCreateControl(CouplingProblem P, Vec *x)
{
  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(P->weight_sqrt, x));
  PetscCall(VecZeroEntries(*x));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingProblemFluidSolverIsKrylov(CouplingProblem P, PetscBool *krylov)
{
  PetscFunctionBeginUser;
  *krylov = P->fluid_krylov;
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingProblemGetTikhonov(CouplingProblem P, PetscReal *eps)
{
  PetscFunctionBeginUser;
  *eps = P->tikhonov;
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingProblemBeginStep(CouplingProblem P, PetscInt step)
{
  PetscFunctionBeginUser;
  P->step           = step;
  P->state_valid    = PETSC_FALSE;
  P->swept          = PETSC_FALSE;
  P->jacobian_valid = PETSC_FALSE;
  StepFailureClear(&P->failure);
  if (P->fluid) PetscCall(FluidBeginStep(P->fluid, step));
  if (P->motion) {
    Vec d;
    PetscCall(PetscLogStagePush(FSIOPT_STAGE_MESH_MOTION));
    PetscCall(FluidGetMeshDisplacement(P->fluid, &d));
    PetscCall(MeshMotionBeginStep(P->motion, d));
    PetscCall(PetscLogStagePop());
  }
  if (P->motion && P->extrapolate_mesh && P->domain == DOMAIN_LAGGED) {
    /* the domain lags one iteration (seed Algorithm 3.3): started on Omega^{n-1}, the
       first iteration's step is spent on the domain's own move */
    Vec d;
    PetscCall(FluidGetMeshDisplacement(P->fluid, &d));
    if (P->spacing_changed) PetscCall(VecCopy(d, P->mesh_displacement_before));
    PetscCall(VecAXPBYPCZ(P->mesh_displacement, 2.0, -1.0, 0.0, d, P->mesh_displacement_before));
    PetscCall(VecCopy(d, P->mesh_displacement_before));
    PetscCall(FluidSetMeshDisplacement(P->fluid, P->mesh_displacement));
  }
  P->spacing_changed = PETSC_FALSE;
  if (P->structure) PetscCall(StructureBeginStep(P->structure));
  PetscCall(CouplingProblemCollectFailure(P, NULL));
  PetscCall(VecZeroEntries(P->datum_load));
  if (P->variant == CONTROL_CONVECTIVE && P->fluid_data.convective_interface_datum) {
    PetscReal t = 0;
    if (P->fluid) PetscCall(FluidGetTime(P->fluid, &t));
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &t, 1, MPIU_REAL, MPI_MAX, P->comm));
    PetscCall(InterfaceInterpolate(P->itf, P->fluid_data.convective_interface_datum, P->fluid_data.ctx, t, P->all_b));
    PetscCall(MatMult(P->mass, P->all_b, P->datum_load));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingProblemEndStep(CouplingProblem P, Vec x)
{
  PetscFunctionBeginUser;
  PetscCall(VecCopy(x, P->accepted));
  if (!P->swept) {
    PetscCall(CouplingProblemEnsureState(P, x));
    if (P->domain == DOMAIN_LAGGED && !StepFailed(&P->failure)) PetscCall(CouplingProblemMoveMesh(P));
  }
  if (StepFailed(&P->failure)) PetscFunctionReturn(0);
  if (P->structure) PetscCall(StructureEndStep(P->structure));
  PetscFunctionReturn(0);
}
