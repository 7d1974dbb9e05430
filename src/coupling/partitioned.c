/* The partitioned baselines: Dirichlet-Neumann fixed-point iterations
   u_{k+1} = update(u_k, S(u_k), r_k), r_k = S(u_k) - u_k, S one sweep, the update an
   acceleration (acceleration.h: dn, aitken, iqnils, iqnimvj). The iterate u is the interface
   traction (structure under the traction, fluid with the structure's interface velocity,
   the fluid's reaction as the new traction; CouplingProblemSweep) or, with
   -coupling_relax_velocity, the interface velocity (fluid under the velocity, structure
   under the fluid's reaction, the structure's velocity as the new one; the seed's
   arrangement, CouplingProblemSweepVelocity).
   A step has converged when ||r|| <= max(-coupling_rtol ||S(u)||, -coupling_atol) (for the
   traction: the change in L2(Gamma_I)); iterations past -coupling_max_it or a residual
   1000x its first one (after the iterations that build the acceleration's model) fail
   the step with a message naming the step and the iteration. -coupling_tol, the
   interface velocity jump of opt, is not read: velocity continuity holds by construction
   here (an option nothing reads is reported before the first step). */
#include "acceleration.h"
#include "options.h"
#include "logging.h"
#include "checkpoint.h"

typedef struct {
  Acceleration  acc;
  PetscReal     rtol, atol;
  PetscBool     relax_velocity; /* iterate on the interface velocity (the seed's) */
  Vec           u;              /* the iterate: the control C->x, or v */
  Vec           v;              /* the velocity iterate */
  Extrapolation v_start;        /* its start from the last converged values */
  Vec           sweep, r;       /* S(u_k), r_k */
  PetscReal     ratio;          /* ||r_k|| / ||S(u_k)|| of the last iteration tested */
} Partitioned;

/* The convergence and divergence tests of iteration k: true when the step ends there. */
static PetscErrorCode PartitionedTest(Coupling C, PetscInt step, PetscInt k, PetscReal *first, PetscBool *done)
{
  Partitioned *pt = (Partitioned *)C->data;
  PetscReal    rnorm, xnorm;

  PetscFunctionBeginUser;
  PetscCall(VecWAXPY(pt->r, -1.0, pt->u, pt->sweep));
  PetscCall(VecNorm(pt->r, NORM_2, &rnorm));
  PetscCall(VecNorm(pt->sweep, NORM_2, &xnorm));
  /* history: the objective column holds 1/2 ||r||^2, the jump column ||r|| (traction or velocity) */
  PetscCall(HistoryAppend(C->history, step, C->dt, k, 0.5 * rnorm * rnorm, rnorm, 0));
  if (k == 0) *first = rnorm;
  pt->ratio = xnorm > 0 ? rnorm / xnorm : (rnorm > 0 ? PETSC_INFINITY : 0);
  *done     = PETSC_TRUE;
  if (rnorm <= PetscMax(pt->rtol * xnorm, pt->atol)) PetscFunctionReturn(0);
  if (PetscIsInfOrNanReal(rnorm) || (k > pt->acc->model_its && rnorm > 1e3 * *first))
    PetscCall(StepFailureSet(&C->failure,
                             "coupling %s diverged at step %" PetscInt_FMT ", iteration %" PetscInt_FMT
                             ": residual %.3e, 1000 times its first value %.3e (relaxation -coupling_omega %g)",
                             C->method, step, k, (double)rnorm, (double)*first, (double)pt->acc->omega));
  else if (k >= C->max_it)
    PetscCall(StepFailureSet(&C->failure,
                             "coupling %s did not converge at step %" PetscInt_FMT " in -coupling_max_it %" PetscInt_FMT
                             " iterations: residual %.3e > -coupling_rtol %.1e times the iterate %.3e and > "
                             "-coupling_atol %.1e",
                             C->method, step, C->max_it, (double)rnorm, (double)pt->rtol, (double)xnorm,
                             (double)pt->atol));
  else *done = PETSC_FALSE;
  PetscFunctionReturn(0);
}

static PetscErrorCode PartitionedIterate(Coupling C, PetscInt step, CouplingIterations *it)
{
  Partitioned *pt    = (Partitioned *)C->data;
  PetscReal    first = 0;
  PetscInt     k;

  PetscFunctionBeginUser;
  if (pt->acc->ops.begin_step) PetscCall((*pt->acc->ops.begin_step)(pt->acc, step));
  if (pt->relax_velocity) PetscCall(ExtrapolationPredict(&pt->v_start, pt->v));
  for (k = 0;; ++k) {
    const char *failure;
    PetscBool   done;

    if (pt->relax_velocity) PetscCall(CouplingProblemSweepVelocity(C->problem, pt->v, C->x, pt->sweep));
    else PetscCall(CouplingProblemSweep(C->problem, C->x, pt->sweep));
    PetscCall(CouplingProblemGetFailure(C->problem, &failure));
    if (failure) {
      it->iterations = k;
      PetscCall(StepFailureSet(&C->failure, "coupling %s at step %" PetscInt_FMT ", iteration %" PetscInt_FMT ": %s",
                               C->method, step, k, failure));
      PetscFunctionReturn(0);
    }
    PetscCall(PartitionedTest(C, step, k, &first, &done));
    if (done) break;
    PetscCall(PetscLogStagePush(FSIOPT_STAGE_OPTIMIZER)); /* the method's own work */
    PetscCall((*pt->acc->ops.update)(pt->acc, step, k, pt->u, pt->sweep, pt->r));
    PetscCall(PetscLogStagePop());
  }
  it->iterations = k + 1; /* sweeps */
  it->measure    = pt->ratio;
  if (StepFailed(&C->failure)) PetscFunctionReturn(0);
  PetscCall(CouplingProblemSweepJump(C->problem, &it->jump));
  if (pt->relax_velocity) PetscCall(ExtrapolationRecord(&pt->v_start, pt->v));
  PetscFunctionReturn(0);
}

static PetscErrorCode PartitionedDestroy(Coupling C)
{
  Partitioned *pt = (Partitioned *)C->data;

  PetscFunctionBeginUser;
  if (pt->acc->ops.destroy) PetscCall((*pt->acc->ops.destroy)(pt->acc));
  PetscCall(PetscFree(pt->acc));
  PetscCall(VecDestroy(&pt->sweep));
  PetscCall(VecDestroy(&pt->r));
  if (pt->relax_velocity) {
    PetscCall(VecDestroy(&pt->v));
    PetscCall(ExtrapolationDestroy(&pt->v_start));
  }
  PetscCall(PetscFree(C->data));
  PetscFunctionReturn(0);
}

static PetscErrorCode PartitionedResynchronize(Coupling C)
{
  Partitioned *pt = (Partitioned *)C->data;

  PetscFunctionBeginUser;
  if (pt->acc->ops.reset) PetscCall((*pt->acc->ops.reset)(pt->acc));
  PetscFunctionReturn(0);
}

/* The velocity iterate and its past values: a retried step starts from them again. */
static PetscErrorCode PartitionedCheckpoint(Coupling C, Checkpoint cp, PetscBool load)
{
  Partitioned *pt = (Partitioned *)C->data;

  PetscFunctionBeginUser;
  if (!pt->relax_velocity) PetscFunctionReturn(0);
  PetscCall(CheckpointVec(cp, "velocity", pt->v, load));
  PetscCall(ExtrapolationCheckpoint(&pt->v_start, cp, "velocity", load));
  PetscFunctionReturn(0);
}

static const char *PartitionedOptimizer(PETSC_UNUSED Coupling C)
{
  return NULL; /* no optimizer */
}

static PetscErrorCode PartitionedSetUp(Coupling C)
{
  Partitioned *pt = (Partitioned *)C->data;

  PetscFunctionBeginUser;
  pt->rtol = 1e-5;
  pt->atol = 1e-7;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Partitioned (Dirichlet-Neumann) coupling", "coupling");
  PetscCall(
    OptionsPositiveReal(PetscOptionsObject, "-coupling_omega",
                        "relaxation: fixed for dn (default 1, unrelaxed), the first step of aitken, iqnils and iqnimvj "
                        "(default 0.05, Kuberry 2015's)",
                        &pt->acc->omega));
  PetscCall(
    OptionsPositiveReal(PetscOptionsObject, "-coupling_rtol",
                        "a step has converged when the traction changes by less than this, relative, in L2(Gamma_I)",
                        &pt->rtol));
  PetscCall(OptionsNonNegativeReal(PetscOptionsObject, "-coupling_atol",
                                   "or by less than this, absolute: the floor set by the subproblems' solver "
                                   "tolerances while the traction is tiny",
                                   &pt->atol));
  PetscCall(PetscOptionsBool("-coupling_relax_velocity",
                             "iterate on the interface velocity (fluid first, the structure's velocity relaxed: "
                             "Kuberry 2015's arrangement) instead of the traction",
                             NULL, pt->relax_velocity, &pt->relax_velocity, NULL));
  PetscOptionsEnd();
  PetscCall(CouplingProblemCheckSweepable(C->problem)); /* after the options: a bad value is named first */
  PetscCall(PetscSNPrintf(C->measure, sizeof(C->measure),
                          "final relative %s change ||r||/||S(u)|| (-coupling_rtol %g, or ||r|| <= -coupling_atol %g)",
                          pt->relax_velocity ? "velocity" : "traction", (double)pt->rtol, (double)pt->atol));
  PetscCall(PetscSNPrintf(C->setting, sizeof(C->setting), "%s on the interface %s", C->method,
                          pt->relax_velocity ? "velocity" : "traction"));
  pt->u = C->x;
  if (pt->relax_velocity) {
    PetscCall(CouplingProblemCreateInterfaceVector(C->problem, &pt->v));
    PetscCall(VecZeroEntries(pt->v));
    PetscCall(ExtrapolationCreate(pt->v, 1, 2, &pt->v_start)); /* the wall's velocity: linear */
    pt->u = pt->v;
  }
  PetscCall(VecDuplicate(pt->u, &pt->sweep));
  PetscCall(VecDuplicate(pt->u, &pt->r));
  if (pt->acc->ops.setup) PetscCall((*pt->acc->ops.setup)(pt->acc, pt->u));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingCreate_Partitioned(Coupling C, Acceleration acc)
{
  Partitioned *pt;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&pt));
  pt->acc              = acc;
  C->data              = pt;
  C->max_it            = 500; /* relaxation methods may need hundreds */
  C->ops.setup         = PartitionedSetUp;
  C->ops.iterate       = PartitionedIterate;
  C->ops.destroy       = PartitionedDestroy;
  C->ops.optimizer     = PartitionedOptimizer;
  C->ops.resynchronize = PartitionedResynchronize;
  C->ops.checkpoint    = PartitionedCheckpoint;
  /* the model of the past steps (iqnils' reused columns, iqnimvj's inverse Jacobian) is
     dropped at a checkpoint file, as a restarted run starts without it */
  C->ops.restartable = PETSC_TRUE;
  PetscFunctionReturn(0);
}
