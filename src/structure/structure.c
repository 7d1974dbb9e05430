/* The structure subproblem: linear or St. Venant-Kirchhoff elasticity with the seed's first-order (eq. 2.42) or
   second-order midpoint (eqs. 2.40-2.41) time stepping. With the velocity eliminated,
   both schemes read
     m M eta^n + K eta^n = m M (eta^{n-1} + dt etadot^{n-1}) + L^n            (order 1, m = rho_s/dt^2)
     m M eta^n + K eta^n = m M (eta^{n-1} + dt etadot^{n-1}) + L^n + L^{n-1} - K eta^{n-1}
                                                                               (order 2, m = 4 rho_s/dt^2)
   and the velocity follows as etadot^n = (eta^n - eta^{n-1})/dt, resp.
   2 (eta^n - eta^{n-1})/dt - etadot^{n-1}. For the linear wall the matrix m M + K never
   changes: it is assembled and factored once per run. For St. Venant-Kirchhoff, K eta is
   (F Sigma, grad xi) (seed eq. 6.17), each step is a Newton solve, and the tangent at the
   solution is factored once more after it: the sensitivity and adjoint products solve with
   the exact linearization (seed eq. 6.19). */
#include "structure_impl.h"
#include "fem.h"
#include "options.h"
#include "logging.h"
#include "checkpoint.h"

/* PETSc fixes the signatures of pointwise kernels; the projection kernel uses a few of their arguments. */
#pragma GCC diagnostic ignored "-Wunused-parameter"

PetscErrorCode StructureCreate(MPI_Comm comm, Structure *structure)
{
  Structure s;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&s));
  s->comm           = comm;
  s->rho            = 1.0;
  s->youngs_modulus = 1.0;
  s->poisson_ratio  = 0.3;
  s->degree         = 2;
  s->time_order     = 2;
  *structure        = s;
  PetscFunctionReturn(0);
}

/* -structure_model's and each region's choices, in StructureModel's order */
const char *const StructureModelNames[] = {"linear", "svk"};

PetscErrorCode StructureSetFromOptions(Structure s)
{
  const char *const *models = StructureModelNames;
  PetscInt           model  = s->model;

  PetscFunctionBeginUser;
  PetscCall(OptionsDeclareUnit("-structure_density", UNIT_DENSITY));
  PetscCall(OptionsDeclareUnit("-structure_youngs_modulus", UNIT_PRESSURE));
  PetscOptionsBegin(s->comm, NULL, "Structure options", "structure");
  PetscCall(PetscOptionsEList("-structure_model", "Constitutive law: linear elasticity or St. Venant-Kirchhoff (svk)",
                              NULL, models, 2, models[model], &model, NULL));
  s->model = (StructureModel)model;
  PetscCall(OptionsPositiveReal(PetscOptionsObject, "-structure_density", "structure density rho_s", &s->rho));
  PetscCall(
    OptionsPositiveReal(PetscOptionsObject, "-structure_youngs_modulus", "Young's modulus E", &s->youngs_modulus));
  PetscCall(OptionsRealInRange(PetscOptionsObject, "-structure_poisson_ratio", "Poisson ratio nu_s", -1.0, 0.5,
                               &s->poisson_ratio));
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-structure_degree", "polynomial degree of the displacement", 1, 4,
                              &s->degree));
  PetscCall(PetscOptionsBool("-structure_initial_projection",
                             "Start from the elastic (Ritz) projection of the scene's exact displacement instead of "
                             "its interpolant",
                             NULL, s->initial_projection, &s->initial_projection, NULL));
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-structure_time_order",
                              "0: static (no inertia: each step is the equilibrium under the data of its time), 1: "
                              "first order (Kuberry 2015 eq. 2.42), 2: midpoint (Kuberry 2015 eqs. 2.40-2.41)",
                              0, 2, &s->time_order));
  PetscOptionsEnd();
  s->mu     = s->youngs_modulus / (2.0 * (1.0 + s->poisson_ratio));
  s->lambda = s->youngs_modulus * s->poisson_ratio / ((1.0 + s->poisson_ratio) * (1.0 - 2.0 * s->poisson_ratio));
  PetscFunctionReturn(0);
}

static PetscReal StructureMassCoefficient(Structure s)
{
  const PetscReal factor[] = {0.0, 1.0, 4.0};
  return factor[s->time_order] * s->rho / (s->dt * s->dt);
}

static PetscErrorCode StructureSetConstantsFull(Structure, PetscReal, PetscReal, PetscReal, PetscReal, PetscReal,
                                                PetscReal);

/* the weak form's coefficients: mass, operator, load; the Robin supports' dashpots with the
   velocity's coefficient `rate` (structure_robin.c) */
static PetscErrorCode StructureSetConstants(Structure s, PetscReal mass, PetscReal op, PetscReal load, PetscReal time,
                                            PetscReal rate)
{
  PetscFunctionBeginUser;
  PetscCall(StructureSetConstantsFull(s, mass, op, load, time, 0.0, rate));
  PetscFunctionReturn(0);
}

static PetscErrorCode StructureSetConstantsFull(Structure s, PetscReal mass, PetscReal op, PetscReal load,
                                                PetscReal time, PetscReal projection, PetscReal rate)
{
  PetscDS        ds;
  PetscScalar    c[STRUCTURE_NUM_CONSTANTS + FSIOPT_MAX_EXTRA + FSIOPT_MAX_BOUNDARIES];
  const PetscInt n = STRUCTURE_NUM_CONSTANTS + s->data.n_extra + s->data.n_robin;

  PetscFunctionBeginUser;
  c[STRUCTURE_RHO]        = s->rho;
  c[STRUCTURE_MU]         = s->mu;
  c[STRUCTURE_LAMBDA]     = s->lambda;
  c[STRUCTURE_MASS]       = mass;
  c[STRUCTURE_OPERATOR]   = op;
  c[STRUCTURE_LOAD]       = load;
  c[STRUCTURE_TIME]       = time;
  c[STRUCTURE_DT]         = s->dt;
  c[STRUCTURE_PROJECTION] = projection;
  c[STRUCTURE_MODEL]      = s->model;
  for (PetscInt i = 0; i < s->data.n_extra; ++i) c[STRUCTURE_NUM_CONSTANTS + i] = s->data.extra[i];
  PetscCall(DMGetDS(s->dm, &ds));
  StructureRobinShifts(s, op, rate, n, c);
  PetscCall(PetscDSSetConstants(ds, n, c));
  PetscFunctionReturn(0);
}

static PetscErrorCode StructureSetUpWeakForm(Structure s)
{
  PetscDS       ds;
  PetscWeakForm wf;

  PetscFunctionBeginUser;
  /* Cloned before any field exists, so that it shares the mesh but not the constraints. */
  PetscCall(DMClone(s->dm, &s->dm_free));
  PetscCall(FEMCreateField(s->dm_free, 0, "velocity", -1, s->degree, NULL));
  PetscCall(DMCreateDS(s->dm_free));
  PetscCall(FEMCreateField(s->dm, 0, "displacement", -1, s->degree, NULL));
  PetscCall(DMCreateDS(s->dm));
  PetscCall(StructureMaterialsSetUp(s));
  if (s->material) PetscCall(DMSetAuxiliaryVec(s->dm, NULL, 0, 0, s->material));
  PetscCall(StructureSetConstants(s, 0.0, 1.0, 0.0, s->time, 0.0)); /* the stresses written before a first solve */
  PetscCall(DMGetDS(s->dm, &ds));
  if (s->model == STRUCTURE_SVK) {
    PetscCall(PetscDSSetResidual(ds, 0, StructureF0Mass, StructureF1SVKStress));
    PetscCall(PetscDSSetJacobian(ds, 0, 0, StructureG0Mass, NULL, NULL, StructureG3SVK));
  } else {
    PetscCall(PetscDSSetResidual(ds, 0, StructureF0Mass, StructureF1LinearStress));
    PetscCall(PetscDSSetJacobian(ds, 0, 0, StructureG0Mass, NULL, NULL, StructureG3LinearElasticity));
  }
  PetscCall(PetscDSGetWeakForm(ds, &wf));
  if (s->data.load_value_kernel || s->data.load_stress_kernel)
    PetscCall(PetscWeakFormAddResidual(wf, NULL, 0, 0, 0, s->data.load_value_kernel, s->data.load_stress_kernel));
  PetscCall(FEMAddBoundaries(s->dm, 0, &s->data, s->datums, &s->time));
  PetscCall(StructureRobinAddBoundaries(s));
  PetscFunctionReturn(0);
}

/* The elastic projection of the exact displacement: a(eta_h, xi) = (sigma_ex, eps(xi)) with
   the Dirichlet data at t0. An interpolant's discrete acceleration M^{-1}(f - K eta_I) is
   only O(h) accurate, and a coupled first step with a small dt hands that error to the
   fluid pressure; the projection's is O(h^{k+1}). The kernel reads the closed form here. */
static struct {
  GradientFn gradient;
  void      *ctx;
  PetscReal  t;
} projection_target;

static void ProjectionStress(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                             const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[],
                             const PetscInt aOff[], const PetscInt aOff_x[], const PetscScalar a[],
                             const PetscScalar a_t[], const PetscScalar a_x[], PetscReal t, const PetscReal x[],
                             PetscInt numConstants, const PetscScalar constants[], PetscScalar f1[])
{
  PetscScalar g[9] = {0}, stress[9];

  if (constants[STRUCTURE_PROJECTION] == 0.0) return;
  (void)projection_target.gradient(dim, projection_target.t, x, dim, g, projection_target.ctx);
  StructureStress((StructureModel)PetscRealPart(constants[STRUCTURE_MODEL]), dim,
                  PetscRealPart(constants[STRUCTURE_MU]), PetscRealPart(constants[STRUCTURE_LAMBDA]), g, stress);
  for (PetscInt i = 0; i < dim * dim; ++i) f1[i] -= stress[i];
}

static PetscErrorCode StructureProjectExact(Structure s)
{
  PetscDS       ds;
  PetscWeakForm wf;

  PetscFunctionBeginUser;
  PetscCheck(s->data.exact_gradient[0], s->comm, PETSC_ERR_ARG_WRONG,
             "option -structure_initial_projection: the scene has no exact displacement gradient to project");
  projection_target.gradient = s->data.exact_gradient[0];
  projection_target.ctx      = s->data.ctx;
  projection_target.t        = s->time;
  PetscCall(DMGetDS(s->dm, &ds));
  PetscCall(PetscDSGetWeakForm(ds, &wf));
  PetscCall(PetscWeakFormAddResidual(wf, NULL, 0, 0, 0, NULL, ProjectionStress));
  PetscCall(StructureSetConstantsFull(s, 0.0, 1.0, 0.0, s->time, 1.0, 0.0));
  PetscCall(FEMSolveSteady(s->dm, "structure_projection_", &s->counts.factorizations, s->eta));
  PetscCall(FEMGlobalToLocal(s->dm, s->eta, s->eta_local));
  PetscCall(StructureSetConstants(s, 0.0, 1.0, 1.0, s->time, 0.0));
  PetscFunctionReturn(0);
}

static PetscErrorCode RigidBodyModes(DM dm, PetscInt field_ignored, PetscInt field, MatNullSpace *modes)
{
  PetscFunctionBeginUser;
  PetscCall(DMPlexCreateRigidBody(dm, field, modes));
  PetscFunctionReturn(0);
}

/* GAMG builds its coarse spaces from the operator's near-nullspace, which for elasticity
   are the rigid-body modes; without them it takes the translations only. A factorization
   needs none. A composite preconditioner gets them too: its GAMG part reads them from the
   same matrix. */
static PetscErrorCode SetRigidBodyModes(Structure s)
{
  KSP       ksp;
  PC        pc;
  Mat       A;
  PetscBool gamg;

  PetscFunctionBeginUser;
  PetscCall(SNESGetKSP(s->snes, &ksp));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PetscObjectTypeCompareAny((PetscObject)pc, &gamg, PCGAMG, PCCOMPOSITE, ""));
  if (!gamg) PetscFunctionReturn(0);
  PetscCall(SNESGetJacobian(s->snes, &A, NULL, NULL, NULL));
  if (A) {
    MatNullSpace modes;
    PetscCall(DMPlexCreateRigidBody(s->dm, 0, &modes));
    PetscCall(MatSetNearNullSpace(A, modes));
    PetscCall(MatNullSpaceDestroy(&modes));
  } else PetscCall(DMSetNearNullSpaceConstructor(s->dm, 0, RigidBodyModes)); /* DMCreateMatrix attaches them */
  PetscFunctionReturn(0);
}

PetscErrorCode StructureSetUp(Structure s, DM mesh, const PhysicsData *data, PetscReal t0, PetscReal dt)
{
  PetscFunctionBeginUser;
  s->dm   = mesh;
  s->data = *data;
  s->time = t0;
  s->dt   = dt;
  PetscCall(PetscObjectReference((PetscObject)mesh));
  PetscCall(StructureSetUpWeakForm(s));
  PetscCall(FEMCreateSNES(s->dm, "structure_", s->model == STRUCTURE_SVK ? FEM_JACOBIAN_NEWTON : FEM_JACOBIAN_CONSTANT,
                          &s->counts.factorizations, &s->snes));
  if (s->model == STRUCTURE_SVK) {
    /* A step starts near its solution and the wall's stiffness (E/h^2 against rho_s/dt^2)
       makes the residual's round-off floor 1e-8 or more of its start, where a test
       relative to it never ends; Newton converges quadratically, so a step below 1e-8 of
       the displacement leaves an error at the floor. */
    PetscCall(SNESSetTolerances(s->snes, 1e-12, 1e-10, 1e-8, 50, PETSC_DEFAULT));
    if (s->time_order == 0) {
      /* Full Newton steps: from rest a thin wall's first step raises the residual norm
         a thousandfold (membrane forces of the bending rotation) and converges after it,
         where a backtracking line search stalls. */
      SNESLineSearch ls;
      PetscCall(SNESGetLineSearch(s->snes, &ls));
      PetscCall(SNESLineSearchSetType(ls, SNESLINESEARCHBASIC));
    }
    PetscCall(SNESSetFromOptions(s->snes));
  }
  PetscCall(DMCreateGlobalVector(s->dm, &s->eta));
  PetscCall(PetscObjectSetName((PetscObject)s->eta, "displacement"));
  PetscCall(VecDuplicate(s->eta, &s->history));
  PetscCall(VecDuplicate(s->eta, &s->work));
  PetscCall(VecDuplicate(s->eta, &s->rhs));
  PetscCall(VecDuplicate(s->eta, &s->load));
  PetscCall(VecDuplicate(s->eta, &s->load_old));
  PetscCall(DMCreateLocalVector(s->dm, &s->eta_local));
  PetscCall(VecDuplicate(s->eta_local, &s->eta_old_local));
  PetscCall(VecDuplicate(s->eta_local, &s->etadot_old_local));
  PetscCall(VecDuplicate(s->eta_local, &s->etadot_local));
  PetscCall(VecDuplicate(s->eta_local, &s->work_local));
  if (data->exact[0]) {
    PetscCall(DMProjectFunctionLocal(s->dm, t0, &s->data.exact[0], &s->data.ctx, INSERT_ALL_VALUES, s->eta_local));
    PetscCall(DMLocalToGlobal(s->dm, s->eta_local, INSERT_VALUES, s->eta));
    PetscCheck(!s->initial_projection || s->model == STRUCTURE_LINEAR, s->comm, PETSC_ERR_ARG_INCOMP,
               "option -structure_initial_projection: the elastic projection is defined for -structure_model linear "
               "only");
    if (s->initial_projection) PetscCall(StructureProjectExact(s));
  } else
    PetscCheck(!s->initial_projection, s->comm, PETSC_ERR_ARG_WRONG,
               "option -structure_initial_projection: the scene has no exact solution to project");
  if (data->exact_rate)
    PetscCall(DMProjectFunctionLocal(s->dm, t0, &s->data.exact_rate, &s->data.ctx, INSERT_ALL_VALUES, s->etadot_local));
  PetscCall(StructureOperatorsSetUp(s)); /* after the projection, which PETSc's integration solves */
  PetscCall(SetRigidBodyModes(s));
  PetscFunctionReturn(0);
}

PetscErrorCode StructureBeginStep(Structure s)
{
  const PetscReal mass = StructureMassCoefficient(s), t_old = s->time,
                  rate = StructureVelocityCoefficient(s, STRUCTURE_VELOCITY_SCHEME);

  PetscFunctionBeginUser;
  StepFailureClear(&s->failure);
  PetscCall(VecCopy(s->eta_local, s->eta_old_local));
  PetscCall(VecCopy(s->etadot_local, s->etadot_old_local));
  /* history = m M (eta^{n-1} + dt etadot^{n-1}) [- K eta^{n-1} + L^{n-1} - B_s g^{n-1}]
     + the Robin supports' part in eta^{n-1}: (c/dt) eta^{n-1}, or (2c/dt - k) eta^{n-1} */
  if (s->time_order == 0) PetscCall(VecZeroEntries(s->history));
  else {
    PetscCall(VecWAXPY(s->work_local, s->dt, s->etadot_local, s->eta_local));
    PetscCall(StructureSetConstants(s, mass, 0.0, 0.0, t_old, 0.0));
    PetscCall(StructureOperatorResidual(s->op, s->work_local, s->history));
  }
  if (s->time_order == 2) {
    PetscCall(StructureSetConstants(s, 0.0, 1.0, 1.0, t_old, -rate));
    PetscCall(StructureOperatorResidual(s->op, s->eta_local, s->work));
    PetscCall(VecAXPY(s->history, -1.0, s->work));
    PetscCall(VecAXPY(s->history, -1.0, s->load_old));
  } else if (s->data.n_robin) { /* the supports' faces alone: their only natural-boundary terms in eta */
    PetscCall(StructureSetConstants(s, 0.0, 0.0, 0.0, t_old, -rate));
    PetscCall(FEMNaturalBoundaryResidual(s->dm, t_old, s->eta_local, s->work));
    PetscCall(VecAXPY(s->history, -1.0, s->work));
  }
  s->time += s->dt;
  PetscCall(StructureSetConstants(s, mass, 1.0, 1.0, s->time, rate));
  PetscFunctionReturn(0);
}

PetscErrorCode StructureSolve(Structure s, Vec load, PetscInt step)
{
  SNESConvergedReason reason;
  PetscInt            newton_its;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_STRUCTURE_SOLVE, 0, 0, 0, 0));
  if (load) PetscCall(VecCopy(load, s->load));
  else PetscCall(VecZeroEntries(s->load));
  PetscCall(VecWAXPY(s->rhs, -1.0, s->load, s->history));
  PetscCall(StructureOperatorsCheck(s, step));
  PetscCall(SNESSolve(s->snes, s->rhs, s->eta));
  PetscCall(SNESGetConvergedReason(s->snes, &reason));
  s->counts.nonlinear_solves += 1;
  if (reason <= 0) {
    PetscCall(StepFailureCheckMemory(s->snes, "structure"));
    PetscCall(SNESGetIterationNumber(s->snes, &newton_its));
    PetscCall(StepFailureSet(&s->failure,
                             "structure solve failed at step %" PetscInt_FMT " (t = %g) after %" PetscInt_FMT
                             " Newton iterations: SNES reason %s",
                             step, (double)s->time, newton_its, SNESConvergedReasons[reason]));
    PetscCall(PetscLogEventEnd(FSIOPT_EVENT_STRUCTURE_SOLVE, 0, 0, 0, 0));
    PetscFunctionReturn(0);
  }
  PetscCall(FEMGlobalToLocal(s->dm, s->eta, s->eta_local));
  if (s->model == STRUCTURE_SVK) {
    PetscCall(SNESGetIterationNumber(s->snes, &newton_its));
    s->counts.linear_solves += newton_its;
    PetscCall(FEMFactorJacobianAt(s->snes, s->eta));
  } else s->counts.linear_solves += 1;
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_STRUCTURE_SOLVE, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* d(velocity)/d(eta^n) of the chosen velocity measure */
PetscReal StructureVelocityCoefficient(Structure s, StructureVelocityMeasure measure)
{
  return (measure == STRUCTURE_VELOCITY_SCHEME && s->time_order == 2 ? 2.0 : 1.0) / s->dt;
}

PetscErrorCode StructureVelocityLocal(Structure s, StructureVelocityMeasure measure, Vec velocity_local)
{
  PetscFunctionBeginUser;
  /* c (eta^n - eta^{n-1}) [- etadot^{n-1} for the midpoint scheme's own velocity] */
  PetscCall(VecWAXPY(velocity_local, -1.0, s->eta_old_local, s->eta_local));
  PetscCall(VecScale(velocity_local, StructureVelocityCoefficient(s, measure)));
  if (measure == STRUCTURE_VELOCITY_SCHEME && s->time_order == 2)
    PetscCall(VecAXPY(velocity_local, -1.0, s->etadot_old_local));
  PetscFunctionReturn(0);
}

PetscErrorCode StructureEndStep(Structure s)
{
  PetscFunctionBeginUser;
  PetscCall(StructureVelocityLocal(s, STRUCTURE_VELOCITY_SCHEME, s->etadot_local));
  PetscCall(VecCopy(s->load, s->load_old));
  PetscFunctionReturn(0);
}

PetscErrorCode StructureStep(Structure s, PetscInt step)
{
  PetscFunctionBeginUser;
  PetscCall(StructureBeginStep(s));
  PetscCall(StructureSolve(s, NULL, step));
  if (!StepFailed(&s->failure)) PetscCall(StructureEndStep(s));
  PetscFunctionReturn(0);
}

PetscErrorCode StructureSetTimeStep(Structure s, PetscReal dt)
{
  PetscFunctionBeginUser;
  if (dt == s->dt) PetscFunctionReturn(0);
  s->dt = dt;
  /* the linear wall's single factorization carries rho_s/dt^2 */
  if (s->model == STRUCTURE_LINEAR) PetscCall(SNESSetLagJacobian(s->snes, -2));
  PetscFunctionReturn(0);
}

PetscErrorCode StructureGetFailure(Structure s, const char **reason)
{
  PetscFunctionBeginUser;
  *reason = StepFailureReason(&s->failure);
  PetscFunctionReturn(0);
}

PetscErrorCode StructureSetInitialLoad(Structure s, Vec load)
{
  PetscFunctionBeginUser;
  PetscCall(VecCopy(load, s->load_old));
  PetscFunctionReturn(0);
}

PetscErrorCode StructureLinearSolve(Structure s, Vec rhs, Vec x, PetscBool transpose)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_STRUCTURE_LINEAR, 0, 0, 0, 0));
  PetscCall(FEMLinearSolve(s->snes, rhs, x, transpose));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_STRUCTURE_LINEAR, 0, 0, 0, 0));
  s->counts.linear_solves += 1;
  PetscFunctionReturn(0);
}

PetscErrorCode StructureLinearSolveBlock(Structure s, Mat rhs, Mat x)
{
  PetscInt columns;

  PetscFunctionBeginUser;
  PetscCall(MatGetSize(rhs, NULL, &columns));
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_STRUCTURE_LINEAR, 0, 0, 0, 0));
  PetscCall(FEMLinearSolveBlock(s->snes, rhs, x));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_STRUCTURE_LINEAR, 0, 0, 0, 0));
  s->counts.linear_solves += columns;
  PetscFunctionReturn(0);
}

PetscErrorCode StructureCheckpoint(Structure s, Checkpoint cp, PetscBool load)
{
  PetscFunctionBeginUser;
  PetscCall(CheckpointPushGroup(cp, "/structure"));
  PetscCall(CheckpointReal(cp, "time", &s->time, load));
  PetscCall(CheckpointVec(cp, "displacement", s->eta, load));
  PetscCall(CheckpointLocalVec(cp, "velocity", s->dm_free, s->etadot_local, load));
  PetscCall(CheckpointVec(cp, "load_old", s->load_old, load));
  if (load) PetscCall(FEMGlobalToLocal(s->dm, s->eta, s->eta_local));
  PetscCall(CheckpointPopGroup(cp));
  PetscFunctionReturn(0);
}

PetscErrorCode StructureGetDM(Structure s, DM *dm)
{
  PetscFunctionBeginUser;
  *dm = s->dm;
  PetscFunctionReturn(0);
}

PetscErrorCode StructureErrors(Structure s, ErrorTable *errors)
{
  PetscReal eta_l2, eta_h1, etadot_l2;

  PetscFunctionBeginUser;
  if (s->data.exact[0]) {
    PetscCall(FEMErrors(s->dm, s->eta, s->time, s->data.exact, s->data.exact_gradient, s->data.ctx, &eta_l2, &eta_h1));
    PetscCall(ErrorTableAdd(errors, "eta_L2", eta_l2));
    if (s->data.exact_gradient[0]) PetscCall(ErrorTableAdd(errors, "eta_H1", eta_h1));
  }
  if (s->data.exact_rate) {
    Vec etadot;

    PetscCall(DMGetGlobalVector(s->dm_free, &etadot));
    PetscCall(DMLocalToGlobal(s->dm_free, s->etadot_local, INSERT_VALUES, etadot));
    PetscCall(FEMErrors(s->dm_free, etadot, s->time, &s->data.exact_rate, NULL, s->data.ctx, &etadot_l2, NULL));
    PetscCall(DMRestoreGlobalVector(s->dm_free, &etadot));
    PetscCall(ErrorTableAdd(errors, "etadot_L2", etadot_l2));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode StructureGetCounts(Structure s, SolverCounts *counts)
{
  PetscFunctionBeginUser;
  *counts = s->counts;
  PetscFunctionReturn(0);
}

PetscErrorCode StructureGetMeshFields(Structure s, MeshFields *fields)
{
  PetscFunctionBeginUser;
  fields->n             = 1;
  fields->degree[0]     = s->degree;
  fields->components[0] = -1;
  PetscFunctionReturn(0);
}

PetscErrorCode StructureGetInfo(Structure s, PetscInt *dim, PetscInt *ndofs)
{
  PetscFunctionBeginUser;
  if (dim) PetscCall(DMGetDimension(s->dm, dim));
  if (ndofs) PetscCall(VecGetSize(s->eta, ndofs));
  PetscFunctionReturn(0);
}

PetscErrorCode StructureDestroy(Structure *structure)
{
  Structure s = *structure;

  PetscFunctionBeginUser;
  if (!s) PetscFunctionReturn(0);
  PetscCall(VecDestroy(&s->eta));
  PetscCall(VecDestroy(&s->eta_local));
  PetscCall(VecDestroy(&s->etadot_local));
  PetscCall(VecDestroy(&s->work_local));
  PetscCall(VecDestroy(&s->history));
  PetscCall(VecDestroy(&s->work));
  PetscCall(VecDestroy(&s->rhs));
  PetscCall(VecDestroy(&s->load));
  PetscCall(VecDestroy(&s->load_old));
  PetscCall(VecDestroy(&s->tangent_at));
  PetscCall(VecDestroy(&s->eta_old_local));
  PetscCall(VecDestroy(&s->etadot_old_local));
  PetscCall(StructureOperatorsDestroy(s));
  PetscCall(VecDestroy(&s->material));
  PetscCall(DMDestroy(&s->dm_material));
  PetscCall(SNESDestroy(&s->snes));
  PetscCall(DMDestroy(&s->dm_free));
  PetscCall(DMDestroy(&s->dm));
  PetscCall(PetscFree(*structure));
  PetscFunctionReturn(0);
}
