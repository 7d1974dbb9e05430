/* The fluid subproblem: (Q2,Q1) or (P2,P1) Taylor-Hood on DMPlex, backward Euler,
   Newton (Navier-Stokes) or one linear solve with a single factorization (Stokes). */
#include "fluid.h"
#include "fem.h"
#include "options.h"
#include "logging.h"
#include "checkpoint.h"
#include "fem_ceed.h" /* FEMBackendGet */
#include "fluid_impl.h"

static const char *const FluidModels[] = {"stokes", "navier-stokes", "FluidModel", "FLUID_", NULL};

PetscErrorCode FluidCreate(MPI_Comm comm, Fluid *fluid)
{
  Fluid f;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&f));
  f->comm            = comm;
  f->model           = FLUID_NAVIER_STOKES;
  f->rho             = 1.0;
  f->mu              = 1.0;
  f->velocity_degree = 2;
  f->rhs_rtol        = 1e-13;
  f->extrapolate     = PETSC_TRUE;
  f->time_order      = 1;
  f->pressure_degree = 1;
  PetscCall(FluidDirichletCreate(&f->dirichlet));
  *fluid = f;
  PetscFunctionReturn(0);
}

PetscErrorCode FluidSetFromOptions(Fluid f)
{
  PetscFunctionBeginUser;
  PetscCall(OptionsDeclareUnit("-fluid_density", UNIT_DENSITY));
  PetscCall(OptionsDeclareUnit("-fluid_viscosity", UNIT_VISCOSITY));
  PetscOptionsBegin(f->comm, NULL, "Fluid options", "fluid");
  PetscCall(PetscOptionsEnum("-fluid_model", "Fluid equations", NULL, FluidModels, (PetscEnum)f->model,
                             (PetscEnum *)&f->model, NULL));
  PetscCall(OptionsPositiveReal(PetscOptionsObject, "-fluid_density", "fluid density rho", &f->rho));
  PetscCall(OptionsPositiveReal(PetscOptionsObject, "-fluid_viscosity", "fluid dynamic viscosity mu", &f->mu));
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-fluid_velocity_degree", "polynomial degree of the velocity", 1, 4,
                              &f->velocity_degree));
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-fluid_pressure_degree", "polynomial degree of the pressure", 1, 3,
                              &f->pressure_degree));
  PetscCall(
    OptionsNonNegativeReal(PetscOptionsObject, "-fluid_pressure_stabilization",
                           "alpha of the pressure stabilization -tau (grad p, grad q), tau = alpha h^2 / (rho h^2/dt + "
                           "mu), h the mean cell size (Brezzi-Pitkaranta; needed by equal-order pairs)",
                           &f->pressure_stabilization));
  PetscCall(
    PetscOptionsBool("-fluid_backflow_stabilization",
                     "Add -1/2 rho ((u-z).n)_- (u, v) on the traction boundaries, against backflow instabilities", NULL,
                     f->backflow, &f->backflow, NULL));
  f->n_backflow_faces = FSIOPT_MAX_BOUNDARIES;
  PetscCall(OptionsCheckIntegers(PetscOptionsObject->comm, NULL, "-fluid_backflow_faces", "face-set numbers"));
  PetscCall(PetscOptionsIntArray("-fluid_backflow_faces",
                                 "Face sets that get the backflow stabilization (default: every traction face)", NULL,
                                 f->backflow_faces, &f->n_backflow_faces, &f->backflow_faces_given));
  PetscCall(PetscOptionsBool("-fluid_steady",
                             "Drop the time derivative: every step solves the steady equations with the data of its "
                             "time (a continuation in the data)",
                             NULL, f->steady, &f->steady, NULL));
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-fluid_time_order",
                              "1: backward Euler, 2: BDF2 (its first step, and the first after a change of dt, "
                              "backward Euler; on a moving mesh in the GCL-exact form of fluid_ale.c)",
                              1, 2, &f->time_order));
  PetscCall(PetscOptionsBool("-fluid_extrapolate",
                             "start each step's nonlinear solve from 2 u^{n-1} - u^{n-2} instead of u^{n-1}", NULL,
                             f->extrapolate, &f->extrapolate, NULL));
  PetscCall(OptionsPositiveReal(PetscOptionsObject, "-fluid_rhs_rtol",
                                "nonlinear solves also stop when ||F|| <= rhs_rtol ||rhs||, a relative accuracy of the "
                                "state that does not depend on how good the initial guess was",
                                &f->rhs_rtol));
  PetscCall(OptionsNonNegativeReal(PetscOptionsObject, "-fluid_newton_ksp_rtol",
                                   "relative Krylov tolerance of the nonlinear solves' Newton steps, apart from the "
                                   "linearized solves of the coupling's products (which keep -fluid_ksp_rtol); 0: "
                                   "-fluid_ksp_rtol for both. With LU it changes nothing",
                                   &f->newton_ksp_rtol));
  PetscCall(OptionsNonNegativeReal(PetscOptionsObject, "-fluid_chord_refresh_rate",
                                   "with a Krylov solver, a chord iteration of the nonlinear solves that reduces the "
                                   "residual by less than this factor makes the next one assemble the Jacobian at its "
                                   "iterate, the preconditioner staying the one in hand; 0: never. With LU it changes "
                                   "nothing",
                                   &f->refresh.rate));
  PetscCheck(f->refresh.rate < 1, f->comm, PETSC_ERR_ARG_OUTOFRANGE,
             "option -fluid_chord_refresh_rate: expected a contraction factor in [0, 1), got %g",
             (double)f->refresh.rate);
  PetscCall(PetscOptionsBool("-fluid_initial_projection",
                             "Start from the Stokes projection of the scene's exact solution (discretely divergence "
                             "free) instead of its interpolant",
                             NULL, f->initial_projection, &f->initial_projection, NULL));
  PetscCall(PetscOptionsBool("-fluid_schur_pressure_laplacian",
                             "With -fluid_pc_fieldsplit_type schur: precondition the Schur complement with the "
                             "pressure Laplacian -(tau + dt/rho)(grad p, grad q), its pressure fixed where a traction "
                             "is given, instead of -fluid_pc_fieldsplit_schur_precondition's matrix (time-dependent "
                             "flows whose velocity block is dominated by rho/dt M)",
                             NULL, f->schur_laplacian.use, &f->schur_laplacian.use, NULL));
  PetscCall(PetscOptionsBool("-fluid_matfree",
                             "The solver's operator is libCEED's matrix-free Jacobian, preconditioned by the "
                             "assembled one: for Krylov solvers (-fluid_ksp_type gmres); -fem_backend ceed only",
                             NULL, f->use_matfree, &f->use_matfree, NULL));
  PetscOptionsEnd();
  PetscCall(FEMBackendGet(NULL, NULL)); /* read with the fluid's options, for -help */
  PetscCheck(f->pressure_degree < f->velocity_degree ||
               (f->pressure_degree == f->velocity_degree && f->pressure_stabilization > 0),
             f->comm, PETSC_ERR_ARG_INCOMP,
             "option -fluid_pressure_degree: expected a degree below -fluid_velocity_degree (%" PetscInt_FMT
             ") for an inf-sup stable Taylor-Hood pair, or equal to it with -fluid_pressure_stabilization > 0, got "
             "%" PetscInt_FMT,
             f->velocity_degree, f->pressure_degree);
  PetscFunctionReturn(0);
}

PetscErrorCode FluidSetInterface(Fluid f, PetscInt face, PetscBool convective_term)
{
  PetscFunctionBeginUser;
  f->interface_face            = face;
  f->interface_convective_term = convective_term;
  PetscFunctionReturn(0);
}

/* The Jacobian in hand carries another mass coefficient: rebuild it at the next solve. A
   Jacobian rebuilt at every Newton iteration needs nothing; a lagged one (chord steps,
   -fluid_snes_lag_jacobian K) is rebuilt once, and a user's lag K resumes after that solve. */
static PetscErrorCode FluidJacobianIsStale(Fluid f)
{
  PetscInt lag;

  PetscFunctionBeginUser;
  PetscCall(SNESGetLagJacobian(f->snes, &lag));
  if (lag == 1) PetscFunctionReturn(0);
  if (lag > 1) f->lag_after_rebuild = lag;
  PetscCall(SNESSetLagJacobian(f->snes, -2));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidSetTimeStep(Fluid f, PetscReal dt)
{
  PetscFunctionBeginUser;
  if (dt == f->dt) PetscFunctionReturn(0);
  f->dt          = dt;
  f->steps_at_dt = 0;
  PetscCall(FluidDirichletRefactor(f->dirichlet));
  PetscCall(FluidSetPressureStabilization(f));
  PetscCall(FluidJacobianIsStale(f));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidSetUp(Fluid f, DM mesh, const PhysicsData *data, PetscReal t0, PetscReal dt)
{
  FEMJacobianPolicy policy = FEM_JACOBIAN_NEWTON;

  PetscFunctionBeginUser;
  f->dm   = mesh;
  f->data = *data;
  f->time = t0;
  f->dt   = dt;
  PetscCall(PetscObjectReference((PetscObject)mesh));
  if (f->pressure_stabilization > 0) {
    PetscReal volume = 0;
    PetscInt  cStart, cEnd, dim, ncells;

    PetscCall(DMGetDimension(mesh, &dim));
    PetscCall(DMGetCoordinatesLocalSetUp(mesh));
    PetscCall(DMPlexGetHeightStratum(mesh, 0, &cStart, &cEnd));
    for (PetscInt c = cStart; c < cEnd; ++c) {
      PetscReal v;
      PetscCall(DMPlexComputeCellGeometryFVM(mesh, c, &v, NULL, NULL));
      volume += v;
    }
    ncells = cEnd - cStart;
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &volume, 1, MPIU_REAL, MPIU_SUM, f->comm));
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &ncells, 1, MPIU_INT, MPI_SUM, f->comm));
    f->cell_size = PetscPowReal(volume / ncells, 1.0 / dim);
  }
  PetscCall(FluidSetPressureStabilization(f));
  PetscCall(FluidSetUpWeakForm(f));
  PetscCall(FluidOutletsCreate(f)); /* on the DM's fields, before the constants hold their pressures */
  PetscCall(FluidSetConstants(f, 0.0, 1.0, 1.0));
  { /* on the DM's fields and constants */
    const FluxMeasure measure = {FluidInterpolatedFlux, f};
    for (PetscInt b = 0; b < data->n_dirichlet; ++b)
      if (data->dirichlet_setup[b])
        PetscCall(
          data->dirichlet_setup[b](mesh, data->dirichlet_faces[b], f->mu / f->rho, &measure, data->dirichlet_ctx[b]));
  }
  if (f->model == FLUID_STOKES) policy = FEM_JACOBIAN_CONSTANT;
  else if (f->interface_face) policy = FEM_JACOBIAN_ON_REQUEST;
  f->chord = policy == FEM_JACOBIAN_ON_REQUEST ? PETSC_TRUE : PETSC_FALSE;
  PetscCall(FEMCreateSNES(f->dm, "fluid_", policy, &f->counts.factorizations, &f->snes));
  PetscCall(FluidNonlinearSolveSetUp(f));
  PetscCall(FluidSchurLaplacianSetUp(f));
  PetscCall(SNESGetTolerances(f->snes, &f->atol, NULL, NULL, NULL, NULL));
  if (data->mesh_displacement) f->moving = PETSC_TRUE;
  PetscCall(DMCreateGlobalVector(f->dm, &f->x));
  PetscCall(PetscObjectSetName((PetscObject)f->x, "fluid"));
  PetscCall(VecDuplicate(f->x, &f->history));
  PetscCall(VecDuplicate(f->x, &f->rhs));
  PetscCall(VecDuplicate(f->x, &f->x_start));
  PetscCall(VecDuplicate(f->x, &f->x_before));
  PetscCall(DMCreateLocalVector(f->dm, &f->xlocal_old));
  PetscCall(DMCreateLocalVector(f->dm, &f->xlocal_work));
  PetscCheck(!(f->steady && f->moving), f->comm, PETSC_ERR_ARG_INCOMP,
             "option -fluid_steady: a moving mesh needs the time derivative; expected a fixed fluid domain");
  PetscCheck(f->time_order == 1 || !f->steady, f->comm, PETSC_ERR_ARG_INCOMP,
             "option -fluid_time_order 2: a steady fluid (-fluid_steady) has no time derivative; expected 1");
  if (f->time_order == 2) PetscCall(DMCreateLocalVector(f->dm, &f->xlocal_previous));
  if (f->moving) PetscCall(FluidALECreate(f, &f->ale));
  PetscCall(FluidForcesCreate(f, &f->forces));
  if (data->exact[0] && data->exact[1]) {
    FieldFn exact[2] = {data->exact[0], data->exact[1]};
    void   *ctxs[2]  = {data->ctx, data->ctx};
    PetscCall(DMProjectFunction(f->dm, t0, exact, ctxs, INSERT_ALL_VALUES, f->x));
    if (f->initial_projection) {
      PetscCheck(data->exact_gradient[0], f->comm, PETSC_ERR_ARG_WRONG,
                 "option -fluid_initial_projection: the scene has no exact velocity gradient to project");
      /* PETSc's integration solves it; on a moving mesh the fluid's SNES callbacks serve it, on a
         PETSc operator of its own (no step yet: no old-domain mass) */
      if (f->moving) PetscCall(FluidOperatorCreate(f, "petsc", FLUID_OPERATOR_PROJECTION, &f->op));
      PetscCall(FluidProjectExact(f));
      PetscCall(FluidOperatorDestroy(&f->op));
    }
  } else {
    PetscCheck(!f->initial_projection, f->comm, PETSC_ERR_ARG_WRONG,
               "option -fluid_initial_projection: the scene has no exact solution to project");
    PetscCall(VecZeroEntries(f->x));
  }
  PetscCall(FluidOperatorsSetUp(f)); /* after the projection, which PETSc's integration solves */
  if (f->outlets) PetscCall(FluidSNESUseOperator(f)); /* whose residual sets the outlets' pressures */
  PetscFunctionReturn(0);
}

PetscErrorCode FluidBeginStep(Fluid f, PetscInt step)
{
  const PetscBool first_at_dt = f->steps_at_dt == 0; /* no u^{n-2} one step of this dt back */

  PetscFunctionBeginUser;
  StepFailureClear(&f->failure);
  PetscCall(FluidOutletsBeginStep(f)); /* from the state the last step accepted, on its mesh */
  f->steps_at_dt++;
  /* Old-domain mass term, evaluated before the time and the mesh move on. */
  PetscCall(FluidGlobalToLocal(f, f->x, f->xlocal_old));
  if (f->steady) PetscCall(VecZeroEntries(f->history));
  else {
    const PetscBool bdf2 = FluidStepIsBDF2(f);
    const PetscReal mass = f->rho / f->dt * (bdf2 ? 1.5 : 1.0);

    if (mass != f->mass_coefficient && f->mass_coefficient > 0) PetscCall(FluidJacobianIsStale(f));
    f->mass_coefficient = mass;
    PetscCall(FluidSchurLaplacianBeginStep(f));
    if (f->moving) PetscCall(FluidALEBeginStep(f));
    else {
      if (bdf2) {
        /* rho/dt (3/2 u^n - 2 u^{n-1} + 1/2 u^{n-2}) = 3/2 rho/dt (u^n - h), h = 4/3 u^{n-1} - 1/3 u^{n-2}:
           the history and the body force see h where backward Euler has u^{n-1}; the two
           vectors swap, so that xlocal_previous keeps u^{n-1} */
        Vec h = f->xlocal_previous;
        PetscCall(VecAXPBY(h, 4.0 / 3.0, -1.0 / 3.0, f->xlocal_old));
        f->xlocal_previous = f->xlocal_old;
        f->xlocal_old      = h;
      } else if (f->time_order == 2) PetscCall(VecCopy(f->xlocal_old, f->xlocal_previous));
      PetscCall(FluidSetConstants(f, mass, 0.0, 0.0));
      PetscCall(FluidOperatorResidual(f->op, f->xlocal_old, PETSC_FALSE, f->history));
    }
  }
  if (f->extrapolate && f->model == FLUID_NAVIER_STOKES) {
    /* the nonlinear solve starts from 2 u^{n-1} - u^{n-2}: one chord iteration fewer */
    if (first_at_dt) PetscCall(VecCopy(f->x, f->x_before));
    PetscCall(VecAXPBY(f->x_before, 1.0, -1.0, f->x)); /* u^{n-1} - u^{n-2} */
    PetscCall(VecAXPY(f->x, 1.0, f->x_before));
    PetscCall(VecAYPX(f->x_before, -1.0, f->x)); /* u^{n-1} again */
  }
  f->time += f->dt;
  f->step = step;
  if (f->moving && f->data.mesh_displacement) PetscCall(FluidALEFollowScene(f));
  /* on a moving mesh the mass acts through the old domains' mass (fluid_ale.c) */
  PetscCall(FluidSetConstants(f, f->moving || f->steady ? 0.0 : f->mass_coefficient, 1.0, 1.0));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidEnableMeshMotion(Fluid f)
{
  PetscFunctionBeginUser;
  f->moving = PETSC_TRUE;
  PetscFunctionReturn(0);
}

PetscErrorCode FluidGetMeshFields(Fluid f, MeshFields *fields)
{
  PetscFunctionBeginUser;
  fields->n             = f->moving ? 3 : 2;
  fields->degree[0]     = f->velocity_degree;
  fields->components[0] = -1;
  fields->degree[1]     = f->pressure_degree;
  fields->components[1] = 1;
  fields->degree[2]     = 1; /* the mesh displacement (motion.c) */
  fields->components[2] = -1;
  PetscFunctionReturn(0);
}

PetscErrorCode FluidSolve(Fluid f, Vec load, PetscInt step)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_FLUID_SOLVE, 0, 0, 0, 0));
  if (load) PetscCall(VecWAXPY(f->rhs, 1.0, load, f->history));
  else PetscCall(VecCopy(f->history, f->rhs));
  {
    /* With a small dt the residual is a difference of terms of size rho/dt: it cannot fall
       below round-off of the right-hand side (1e-13), whatever the absolute tolerance says. */
    PetscReal rhs_norm;
    PetscCall(VecNorm(f->rhs, NORM_2, &rhs_norm));
    PetscCall(SNESSetTolerances(f->snes, PetscMax(f->atol, PetscMax(f->rhs_rtol, 1e-13) * rhs_norm), PETSC_DEFAULT,
                                PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT));
  }
  PetscCall(FluidOperatorsCheck(f));
  PetscCall(FluidNonlinearSolve(f, f->snes, f->rhs, f->chord, step, ""));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_FLUID_SOLVE, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidStep(Fluid f, PetscInt step)
{
  PetscFunctionBeginUser;
  PetscCall(FluidBeginStep(f, step));
  if (!StepFailed(&f->failure)) PetscCall(FluidSolve(f, NULL, step));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidUpdateJacobian(Fluid f, PetscBool reuse_preconditioner)
{
  PetscFunctionBeginUser;
  if (f->model == FLUID_STOKES) PetscFunctionReturn(0); /* constant: factored once */
  PetscCall(FluidMatFreeSetOperatorOnly(f->matfree, reuse_preconditioner));
  PetscCall(FEMUpdateJacobian(f->snes, f->x, reuse_preconditioner));
  PetscCall(FluidMatFreeSetOperatorOnly(f->matfree, PETSC_FALSE));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidSolverIsKrylov(Fluid f, PetscBool *krylov)
{
  KSP ksp;

  PetscFunctionBeginUser;
  PetscCall(SNESGetKSP(f->snes, &ksp));
  PetscCall(FEMSolverIsKrylov(ksp, krylov));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidLinearSolve(Fluid f, Vec rhs, Vec x, PetscBool transpose)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_FLUID_LINEAR, 0, 0, 0, 0));
  PetscCall(FEMLinearSolve(f->snes, rhs, x, transpose));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_FLUID_LINEAR, 0, 0, 0, 0));
  f->counts.linear_solves += 1;
  PetscFunctionReturn(0);
}

/* A first guess needs no more accuracy than a Newton step: a Krylov solver stops at
   -fluid_newton_ksp_rtol (tube3d level 3 at -fluid_ksp_rtol 1e-10: 1.9 s a solve, 28.3 s of
   the Fluid stage's 97 s over five steps) */
PetscErrorCode FluidLinearSolveGuess(Fluid f, Vec rhs, Vec x)
{
  PetscFunctionBeginUser;
  PetscCall(FEMSetLinearizedRtol(f->newton_ksp_rtol));
  PetscCall(FluidLinearSolve(f, rhs, x, PETSC_FALSE));
  PetscCall(FEMSetLinearizedRtol(0));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidLinearSolveBlock(Fluid f, Mat rhs, Mat x)
{
  PetscInt columns;

  PetscFunctionBeginUser;
  PetscCall(MatGetSize(rhs, NULL, &columns));
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_FLUID_LINEAR, 0, 0, 0, 0));
  PetscCall(FEMLinearSolveBlock(f->snes, rhs, x));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_FLUID_LINEAR, 0, 0, 0, 0));
  f->counts.linear_solves += columns;
  PetscFunctionReturn(0);
}

PetscErrorCode FluidCheckpoint(Fluid f, Checkpoint cp, PetscBool load)
{
  PetscBool bdf2_state = f->time_order == 2;

  PetscFunctionBeginUser;
  PetscCall(CheckpointPushGroup(cp, "/fluid"));
  PetscCall(CheckpointReal(cp, "time", &f->time, load));
  PetscCall(CheckpointInt(cp, "step", &f->step, load));
  if (load && f->time_order == 2) {
    /* a backward-Euler run's checkpoint: BDF2 goes on from it as after a change of dt */
    PetscCall(CheckpointHasAttribute(cp, "steps_at_dt", &bdf2_state));
    if (!bdf2_state) {
      f->steps_at_dt = 0;
      PetscCall(PetscPrintf(f->comm, "fsiopt: the checkpoint was written by backward Euler (-fluid_time_order 1): BDF2 "
                                     "starts with one backward-Euler step\n"));
    }
  }
  PetscCall(CheckpointVec(cp, "state", f->x, load));
  PetscCall(CheckpointVec(cp, "state_before", f->x_before, load));
  if (f->moving) PetscCall(FluidALECheckpoint(f, cp, load, bdf2_state));
  PetscCall(FluidOutletsCheckpoint(f, cp, load));
  if (bdf2_state) {
    PetscCall(CheckpointInt(cp, "steps_at_dt", &f->steps_at_dt, load));
    if (CheckpointIsFile(cp)) {
      /* a file keeps the free values; the boundary values are those of t - dt */
      Vec       previous;
      PetscReal t = f->time;
      PetscCall(DMGetGlobalVector(f->dm, &previous));
      if (!load) PetscCall(DMLocalToGlobal(f->dm, f->xlocal_previous, INSERT_VALUES, previous));
      PetscCall(CheckpointVec(cp, "previous_state", previous, load));
      f->time = t - f->dt;
      if (load) PetscCall(FluidGlobalToLocal(f, previous, f->xlocal_previous));
      f->time = t;
      PetscCall(DMRestoreGlobalVector(f->dm, &previous));
    } else PetscCall(CheckpointLocalVec(cp, "previous_state", f->dm, f->xlocal_previous, load));
  }
  PetscCall(CheckpointPopGroup(cp));
  /* state_before is u^{n-2} (backward Euler keeps no count) */
  if (load && f->time_order == 1) f->steps_at_dt = 1;
  /* chord factors from before it are not in the checkpoint, nor are the partitioned
     methods' Dirichlet solver and factors, whose lag counts Newton iterations from the
     solver's creation: both sides of a restart make them anew at the next sweep */
  if (f->chord && CheckpointResynchronizes(cp, load)) PetscCall(SNESSetLagJacobian(f->snes, -2));
  if (CheckpointResynchronizes(cp, load)) PetscCall(FluidDirichletReset(f->dirichlet));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidGetFailure(Fluid f, const char **reason)
{
  PetscFunctionBeginUser;
  *reason = StepFailureReason(&f->failure);
  PetscFunctionReturn(0);
}

PetscErrorCode FluidGetData(Fluid f, const PhysicsData **data)
{
  PetscFunctionBeginUser;
  *data = &f->data;
  PetscFunctionReturn(0);
}

PetscErrorCode FluidGetNonlinearSystem(Fluid f, SNES *snes, Vec *history)
{
  PetscFunctionBeginUser;
  *snes    = f->snes;
  *history = f->history;
  PetscFunctionReturn(0);
}

PetscErrorCode FluidGetDM(Fluid f, DM *dm)
{
  PetscFunctionBeginUser;
  *dm = f->dm;
  PetscFunctionReturn(0);
}

PetscErrorCode FluidGetSolution(Fluid f, Vec *x)
{
  PetscFunctionBeginUser;
  *x = f->x;
  PetscFunctionReturn(0);
}

PetscErrorCode FluidGetTime(Fluid f, PetscReal *t)
{
  PetscFunctionBeginUser;
  *t = f->time;
  PetscFunctionReturn(0);
}

PetscErrorCode FluidErrors(Fluid f, ErrorTable *errors)
{
  PetscReal l2[2], h1[2];

  PetscFunctionBeginUser;
  if (!f->data.exact[0] || !f->data.exact[1]) PetscFunctionReturn(0);
  PetscCall(FEMErrors(f->dm, f->x, f->time, f->data.exact, f->data.exact_gradient, f->data.ctx, l2, h1));
  PetscCall(ErrorTableAdd(errors, "u_L2", l2[0]));
  if (f->data.exact_gradient[0]) PetscCall(ErrorTableAdd(errors, "u_H1", h1[0]));
  PetscCall(ErrorTableAdd(errors, "p_L2", l2[1]));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidGetCounts(Fluid f, SolverCounts *counts)
{
  PetscFunctionBeginUser;
  *counts = f->counts;
  PetscFunctionReturn(0);
}

PetscErrorCode FluidGetInfo(Fluid f, PetscInt *dim, PetscInt *ndofs)
{
  PetscFunctionBeginUser;
  if (dim) PetscCall(DMGetDimension(f->dm, dim));
  if (ndofs) PetscCall(VecGetSize(f->x, ndofs));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidDestroy(Fluid *fluid)
{
  Fluid f = *fluid;

  PetscFunctionBeginUser;
  if (!f) PetscFunctionReturn(0);
  PetscCall(VecDestroy(&f->x));
  PetscCall(VecDestroy(&f->history));
  PetscCall(VecDestroy(&f->rhs));
  PetscCall(VecDestroy(&f->x_start));
  PetscCall(VecDestroy(&f->x_before));
  PetscCall(FluidOperatorsDestroy(f));
  PetscCall(FluidALEDestroy(&f->ale));
  PetscCall(FluidForcesDestroy(&f->forces));
  PetscCall(FluidDirichletDestroy(&f->dirichlet));
  PetscCall(FluidOutletsDestroy(&f->outlets));
  PetscCall(VecDestroy(&f->xlocal_old));
  PetscCall(VecDestroy(&f->xlocal_work));
  PetscCall(VecDestroy(&f->xlocal_previous));
  PetscCall(SNESDestroy(&f->snes));
  PetscCall(MatDestroy(&f->schur_laplacian.matrix));
  PetscCall(DMDestroy(&f->dm));
  PetscCall(PetscFree(*fluid));
  PetscFunctionReturn(0);
}
