/* The partitioned baselines (issue 5): Dirichlet-Neumann fixed-point iterations
   u_{k+1} = u_k + update(r_k), r_k = S(u_k) - u_k, S one sweep. The iterate u is the
   interface traction (structure under the traction, fluid with the structure's interface
   velocity, the fluid's reaction as the new traction; CouplingProblemSweep) or, with
   -coupling_relax_velocity, the interface velocity (fluid under the velocity, structure
   under the fluid's reaction, the structure's velocity as the new one; the seed's
   arrangement, CouplingProblemSweepVelocity).
     dn      fixed relaxation: x + omega r                    (-coupling_omega)
     aitken  Aitken's dynamic relaxation, the seed's reference (§3.6.1)
     iqnils  interface quasi-Newton with an inverse-Jacobian least-squares model
             (Degroote et al. 2009; the algorithm of preCICE and CoCoNuT): columns of
             residual and sweep differences, those of the last q steps reused
             (-coupling_iqn_reuse), nearly dependent columns filtered out by a QR
             (-coupling_iqn_filter).
   A step has converged when ||r|| <= max(-coupling_rtol ||S(u)||, -coupling_atol) (for the
   traction: the change in L2(Gamma_I)); iterations past -coupling_max_it or a residual
   1000x its first one (iqnils: after its first four iterations, which build its model)
   fail the step with a message naming the step and the iteration. */
#include "coupling_impl.h"
#include "options.h"
#include "logging.h"
#include "checkpoint.h"

typedef enum { PARTITIONED_DN, PARTITIONED_AITKEN, PARTITIONED_IQNILS } PartitionedKind;

typedef struct {
  PartitionedKind kind;
  PetscReal       omega, rtol, atol, filter;
  PetscInt        reuse;
  PetscBool       relax_velocity;              /* iterate on the interface velocity (the seed's) */
  Vec             u;                           /* the iterate: the control C->x, or pt->v */
  Vec             v;                           /* the velocity iterate */
  Extrapolation   v_start;                     /* its start from the last converged values */
  Vec             sweep, r, r_before, sweep_before; /* S(u_k), r_k, r_{k-1}, S(u_{k-1}) */
  Vec             update;                           /* iqnils: W c */
  /* iqnils: columns V (residual differences) and W (sweep differences), newest first,
     with the step each came from */
  PetscInt        ncols, max_cols, *col_step;
  Vec            *V, *W, *Q; /* Q: V's orthonormal basis, work of the QR */
} Partitioned;

static const char *PartitionedName(Coupling C)
{
  (void)C;
  return NULL; /* no optimizer */
}

/* Drops the columns older than the reuse window (and the oldest past max_cols). */
static PetscErrorCode TrimColumns(Partitioned *pt, PetscInt step)
{
  PetscFunctionBeginUser;
  while (pt->ncols > 0 && (pt->ncols > pt->max_cols || pt->col_step[pt->ncols - 1] <= step - 1 - pt->reuse)) pt->ncols--;
  PetscFunctionReturn(0);
}

static PetscErrorCode AddColumn(Partitioned *pt, PetscInt step, Vec dr, Vec dxt)
{
  Vec v, w;

  PetscFunctionBeginUser;
  if (pt->ncols == pt->max_cols) pt->ncols--; /* the oldest goes */
  v = pt->V[pt->ncols];
  w = pt->W[pt->ncols];
  for (PetscInt j = pt->ncols; j > 0; --j) {
    pt->V[j]        = pt->V[j - 1];
    pt->W[j]        = pt->W[j - 1];
    pt->col_step[j] = pt->col_step[j - 1];
  }
  pt->V[0] = v;
  pt->W[0] = w;
  PetscCall(VecCopy(dr, v));
  PetscCall(VecCopy(dxt, w));
  pt->col_step[0] = step;
  pt->ncols++;
  PetscFunctionReturn(0);
}

/* c = argmin ||V c + r|| by modified Gram-Schmidt QR; a column whose new part is below
   filter * its norm is dropped (it would make R nearly singular). Returns the update
   W c (+ r is added by the caller through sweep). */
static PetscErrorCode QuasiNewtonUpdate(Partitioned *pt, Vec r, Vec dx)
{
  PetscInt     n = pt->ncols, kept = 0;
  Vec         *Q = pt->Q;
  PetscScalar *R, *rhs, *c;
  PetscInt    *keep;

  PetscFunctionBeginUser;
  PetscCall(VecZeroEntries(dx));
  if (!n) PetscFunctionReturn(0);
  PetscCall(PetscCalloc4(n * n, &R, n, &rhs, n, &c, n, &keep));
  for (PetscInt j = 0; j < n; ++j) {
    PetscReal norm0, norm;
    PetscCall(VecCopy(pt->V[j], Q[kept]));
    PetscCall(VecNorm(Q[kept], NORM_2, &norm0));
    for (PetscInt i = 0; i < kept; ++i) {
      PetscScalar d;
      PetscCall(VecDot(Q[kept], Q[i], &d));
      R[i * n + kept] = d;
      PetscCall(VecAXPY(Q[kept], -d, Q[i]));
    }
    PetscCall(VecNorm(Q[kept], NORM_2, &norm));
    if (norm0 == 0 || norm < pt->filter * norm0) continue;
    R[kept * n + kept] = norm;
    PetscCall(VecScale(Q[kept], 1.0 / norm));
    keep[kept++] = j;
  }
  for (PetscInt i = 0; i < kept; ++i) {
    PetscCall(VecDot(r, Q[i], &rhs[i]));
    rhs[i] = -rhs[i];
  }
  for (PetscInt i = kept - 1; i >= 0; --i) {
    PetscScalar s = rhs[i];
    for (PetscInt k = i + 1; k < kept; ++k) s -= R[i * n + k] * c[k];
    c[i] = s / R[i * n + i];
  }
  for (PetscInt i = 0; i < kept; ++i) PetscCall(VecAXPY(dx, c[i], pt->W[keep[i]]));
  PetscCall(PetscFree4(R, rhs, c, keep));
  PetscFunctionReturn(0);
}

static PetscErrorCode PartitionedStep(Coupling C, PetscInt step)
{
  Partitioned *pt = (Partitioned *)C->data;
  PetscReal    omega = pt->omega, first = 0, rnorm = 0, xnorm;
  PetscInt     k;

  PetscFunctionBeginUser;
  PetscCall(CouplingProblemBeginStep(C->problem, step));
  if (pt->kind == PARTITIONED_IQNILS) PetscCall(TrimColumns(pt, step));
  if (pt->relax_velocity) PetscCall(ExtrapolationPredict(&pt->v_start, pt->v));
  for (k = 0;; ++k) {
    const char *failure;
    PetscCall(CouplingProblemGetFailure(C->problem, &failure));
    if (!failure) {
      if (pt->relax_velocity) PetscCall(CouplingProblemSweepVelocity(C->problem, pt->v, C->x, pt->sweep));
      else PetscCall(CouplingProblemSweep(C->problem, C->x, pt->sweep));
      PetscCall(CouplingProblemGetFailure(C->problem, &failure));
    }
    if (failure) {
      C->stats.iterations += k;
      PetscCall(StepFailureSet(&C->failure, "coupling %s at step %" PetscInt_FMT ", iteration %" PetscInt_FMT ": %s", C->method, step, k, failure));
      PetscFunctionReturn(0);
    }
    PetscCall(VecWAXPY(pt->r, -1.0, pt->u, pt->sweep));
    PetscCall(VecNorm(pt->r, NORM_2, &rnorm));
    PetscCall(VecNorm(pt->sweep, NORM_2, &xnorm));
    /* history: the objective column holds 1/2 ||r||^2, the jump column ||r|| (traction or velocity) */
    PetscCall(HistoryAppend(C->history, step, C->dt, k, 0.5 * rnorm * rnorm, rnorm, 0));
    if (k == 0) first = rnorm;
    if (rnorm <= PetscMax(pt->rtol * xnorm, pt->atol)) break;
    if (PetscIsInfOrNanReal(rnorm) || (k > (pt->kind == PARTITIONED_IQNILS ? 4 : 0) && rnorm > 1e3 * first)) PetscCall(StepFailureSet(&C->failure, "coupling %s diverged at step %" PetscInt_FMT ", iteration %" PetscInt_FMT ": residual %.3e, 1000 times its first value %.3e (relaxation -coupling_omega %g)", C->method, step, k, (double)rnorm, (double)first, (double)omega));
    else if (k >= C->max_it) PetscCall(StepFailureSet(&C->failure, "coupling %s did not converge at step %" PetscInt_FMT " in -coupling_max_it %" PetscInt_FMT " iterations: residual %.3e > -coupling_rtol %.1e times the iterate %.3e and > -coupling_atol %.1e", C->method, step, C->max_it, (double)rnorm, (double)pt->rtol, (double)xnorm, (double)pt->atol));
    if (StepFailed(&C->failure)) {
      C->stats.iterations += k + 1;
      PetscFunctionReturn(0);
    }
    PetscCall(PetscLogStagePush(FSIOPT_STAGE_OPTIMIZER)); /* the method's own work */
    switch (pt->kind) {
    case PARTITIONED_DN:
      PetscCall(VecAXPY(pt->u, omega, pt->r));
      break;
    case PARTITIONED_AITKEN:
      if (k > 0) {
        /* omega_k = -omega_{k-1} (r_{k-1}, r_k - r_{k-1}) / ||r_k - r_{k-1}||^2 */
        PetscScalar num, den;
        PetscCall(VecAYPX(pt->r_before, -1.0, pt->r)); /* r_k - r_{k-1} */
        PetscCall(VecDot(pt->r_before, pt->r, &num));
        PetscCall(VecDot(pt->r_before, pt->r_before, &den));
        /* (r_{k-1}, d) = (r_k, d) - (d, d) */
        if (PetscAbsScalar(den) > 0) omega = -omega * PetscRealPart(num - den) / PetscRealPart(den);
      }
      PetscCall(VecCopy(pt->r, pt->r_before));
      PetscCall(VecAXPY(pt->u, omega, pt->r));
      break;
    case PARTITIONED_IQNILS: {
      if (k > 0) {
        PetscCall(VecAYPX(pt->r_before, -1.0, pt->r));                 /* r_k - r_{k-1} */
        PetscCall(VecAYPX(pt->sweep_before, -1.0, pt->sweep));     /* S_k - S_{k-1} */
        PetscCall(AddColumn(pt, step, pt->r_before, pt->sweep_before));
      }
      PetscCall(VecCopy(pt->r, pt->r_before));
      PetscCall(VecCopy(pt->sweep, pt->sweep_before));
      if (pt->ncols) {
        /* x = S(x_k) + W c, c = argmin ||V c + r_k|| */
        PetscCall(QuasiNewtonUpdate(pt, pt->r, pt->update));
        PetscCall(VecWAXPY(pt->u, 1.0, pt->sweep, pt->update));
      } else PetscCall(VecAXPY(pt->u, omega, pt->r)); /* no model yet: one relaxed step */
    } break;
    }
    PetscCall(PetscLogStagePop());
  }
  {
    PetscReal jump;
    PetscCall(CouplingProblemSweepJump(C->problem, &jump));
    C->stats.max_jump = PetscMax(C->stats.max_jump, jump);
  }
  PetscCall(CouplingProblemEndStep(C->problem, C->x));
  if (pt->relax_velocity) PetscCall(ExtrapolationRecord(&pt->v_start, pt->v));
  C->stats.iterations += k + 1; /* sweeps */
  PetscFunctionReturn(0);
}

static PetscErrorCode PartitionedDestroy(Coupling C)
{
  Partitioned *pt = (Partitioned *)C->data;

  PetscFunctionBeginUser;
  PetscCall(VecDestroy(&pt->sweep));
  PetscCall(VecDestroy(&pt->update));
  if (pt->relax_velocity) {
    PetscCall(VecDestroy(&pt->v));
    PetscCall(ExtrapolationDestroy(&pt->v_start));
  }
  PetscCall(VecDestroy(&pt->r));
  PetscCall(VecDestroy(&pt->r_before));
  PetscCall(VecDestroy(&pt->sweep_before));
  if (pt->Q) PetscCall(VecDestroyVecs(pt->max_cols, &pt->Q));
  if (pt->V) PetscCall(VecDestroyVecs(pt->max_cols, &pt->V));
  if (pt->W) PetscCall(VecDestroyVecs(pt->max_cols, &pt->W));
  PetscCall(PetscFree(pt->col_step));
  PetscCall(PetscFree(C->data));
  PetscFunctionReturn(0);
}

/* The columns of IQN-ILS were built with another dt (or before a checkpoint). */
static PetscErrorCode PartitionedResynchronize(Coupling C)
{
  Partitioned *pt = (Partitioned *)C->data;

  PetscFunctionBeginUser;
  pt->ncols = 0;
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

PetscErrorCode CouplingCreate_Partitioned(Coupling C)
{
  Partitioned *pt;
  PetscBool    is;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&pt));
  C->data          = pt;
  C->ops.step      = PartitionedStep;
  C->ops.destroy   = PartitionedDestroy;
  C->ops.optimizer = PartitionedName;
  C->ops.resynchronize = PartitionedResynchronize;
  C->ops.checkpoint    = PartitionedCheckpoint;
  pt->kind         = PARTITIONED_DN;
  PetscCall(PetscStrcmp(C->method, "aitken", &is));
  if (is) pt->kind = PARTITIONED_AITKEN;
  PetscCall(PetscStrcmp(C->method, "iqnils", &is));
  if (is) pt->kind = PARTITIONED_IQNILS;
  pt->omega       = pt->kind == PARTITIONED_DN ? 1.0 : 0.05;
  pt->rtol        = 1e-5;
  pt->atol        = 1e-7;
  pt->reuse       = 8;
  pt->max_cols    = 100;
  pt->filter      = 1e-8;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Partitioned (Dirichlet-Neumann) coupling", "coupling");
  PetscCall(OptionsPositiveReal(PetscOptionsObject, "-coupling_omega", "relaxation: fixed for dn (default 1, unrelaxed), the first step of aitken and iqnils (default 0.05, the seed's)", &pt->omega));
  PetscCall(OptionsPositiveReal(PetscOptionsObject, "-coupling_rtol", "a step has converged when the traction changes by less than this, relative, in L2(Gamma_I)", &pt->rtol));
  PetscCall(OptionsNonNegativeReal(PetscOptionsObject, "-coupling_atol", "or by less than this, absolute: the floor set by the subproblems' solver tolerances while the traction is tiny", &pt->atol));
  PetscCall(PetscOptionsBool("-coupling_relax_velocity", "iterate on the interface velocity (fluid first, the structure's velocity relaxed: the seed's arrangement) instead of the traction", NULL, pt->relax_velocity, &pt->relax_velocity, NULL));
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-coupling_iqn_reuse", "iqnils: reuse the columns of this many previous time steps", 0, 1000, &pt->reuse));
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-coupling_iqn_columns", "iqnils: at most this many columns", 1, 10000, &pt->max_cols));
  PetscCall(OptionsPositiveReal(PetscOptionsObject, "-coupling_iqn_filter", "iqnils: drop a column whose part orthogonal to the newer ones is below this fraction of its norm", &pt->filter));
  PetscOptionsEnd();
  pt->u = C->x;
  if (pt->relax_velocity) {
    PetscCall(CouplingProblemCreateInterfaceVector(C->problem, &pt->v));
    PetscCall(VecZeroEntries(pt->v));
    PetscCall(ExtrapolationCreate(pt->v, 1, 2, &pt->v_start)); /* the wall's velocity: linear */
    pt->u = pt->v;
  }
  PetscCall(VecDuplicate(pt->u, &pt->sweep));
  PetscCall(VecDuplicate(pt->u, &pt->r));
  PetscCall(VecDuplicate(pt->u, &pt->r_before));
  PetscCall(VecDuplicate(pt->u, &pt->sweep_before));
  if (pt->kind == PARTITIONED_IQNILS) {
    PetscCall(VecDuplicate(pt->u, &pt->update));
    PetscCall(VecDuplicateVecs(pt->u, pt->max_cols, &pt->Q));
    PetscCall(VecDuplicateVecs(pt->u, pt->max_cols, &pt->V));
    PetscCall(VecDuplicateVecs(pt->u, pt->max_cols, &pt->W));
    PetscCall(PetscMalloc1(pt->max_cols, &pt->col_step));
  }
  PetscFunctionReturn(0);
}
