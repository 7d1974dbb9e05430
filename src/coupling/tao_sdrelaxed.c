/* TAO type "sdrelaxed": the relaxed steepest descent of Kuberry 2015 (Algorithm 4.11),
     g_{k+1} = (1 - alpha) g_k - (alpha/delta) (adjoint trace)  =  g_k - (alpha/delta) grad J_delta(g_k),
   a fixed step alpha/delta along the negative gradient of the Tikhonov-regularized
   objective. Convergence for small alpha is the seed's Theorem 5.3. */
#include <petsc/private/taoimpl.h>
#include "options.h"

typedef struct {
  PetscReal alpha, delta;
} TaoRelaxedSD;

PetscErrorCode TaoRelaxedSDSetTikhonov(Tao tao, PetscReal delta)
{
  TaoRelaxedSD *sd = (TaoRelaxedSD *)tao->data;

  PetscFunctionBeginUser;
  sd->delta = delta;
  PetscFunctionReturn(0);
}

static PetscErrorCode TaoSolve_RelaxedSD(Tao tao)
{
  TaoRelaxedSD *sd = (TaoRelaxedSD *)tao->data;
  PetscReal     f, gnorm, step;

  PetscFunctionBeginUser;
  PetscCheck(sd->delta > 0, PetscObjectComm((PetscObject)tao), PETSC_ERR_ARG_WRONG,
             "option -tao_type sdrelaxed: the relaxed steepest descent steps by alpha/delta; expected "
             "-coupling_tikhonov > 0");
  step        = sd->alpha / sd->delta;
  tao->reason = TAO_CONTINUE_ITERATING;
  tao->niter  = 0;
  PetscCall(TaoComputeObjectiveAndGradient(tao, tao->solution, &f, tao->gradient));
  PetscCall(VecNorm(tao->gradient, NORM_2, &gnorm));
  PetscCall(TaoLogConvergenceHistory(tao, f, gnorm, 0.0, tao->ksp_its));
  PetscCall(TaoMonitor(tao, tao->niter, f, gnorm, 0.0, 0.0));
  PetscUseTypeMethod(tao, convergencetest, tao->cnvP);
  while (tao->reason == TAO_CONTINUE_ITERATING) {
    if (tao->ops->update) PetscCall((*tao->ops->update)(tao, tao->niter, tao->user_update));
    PetscCall(VecAXPY(tao->solution, -step, tao->gradient));
    tao->niter++;
    PetscCall(TaoComputeObjectiveAndGradient(tao, tao->solution, &f, tao->gradient));
    PetscCall(VecNorm(tao->gradient, NORM_2, &gnorm));
    PetscCall(TaoLogConvergenceHistory(tao, f, gnorm, 0.0, tao->ksp_its));
    PetscCall(TaoMonitor(tao, tao->niter, f, gnorm, 0.0, step));
    PetscUseTypeMethod(tao, convergencetest, tao->cnvP);
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode TaoSetUp_RelaxedSD(Tao tao)
{
  PetscFunctionBeginUser;
  if (!tao->gradient) PetscCall(VecDuplicate(tao->solution, &tao->gradient));
  PetscFunctionReturn(0);
}

static PetscErrorCode TaoSetFromOptions_RelaxedSD(Tao tao, PetscOptionItems *PetscOptionsObject)
{
  TaoRelaxedSD *sd = (TaoRelaxedSD *)tao->data;

  PetscFunctionBeginUser;
  PetscOptionsHeadBegin(PetscOptionsObject, "Relaxed steepest descent (Kuberry 2015 Algorithm 4.11)");
  PetscCall(OptionsPositiveReal(PetscOptionsObject, "-tao_sdrelaxed_alpha",
                                "relaxation alpha: the step is alpha/delta along the negative gradient", &sd->alpha));
  PetscOptionsHeadEnd();
  PetscFunctionReturn(0);
}

static PetscErrorCode TaoDestroy_RelaxedSD(Tao tao)
{
  PetscFunctionBeginUser;
  if (tao->gradient) PetscCall(VecDestroy(&tao->gradient));
  PetscCall(PetscFree(tao->data));
  PetscFunctionReturn(0);
}

PetscErrorCode TaoCreate_RelaxedSteepestDescent(Tao tao)
{
  TaoRelaxedSD *sd;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&sd));
  sd->alpha                = 0.5;
  tao->data                = sd;
  tao->ops->solve          = TaoSolve_RelaxedSD;
  tao->ops->setup          = TaoSetUp_RelaxedSD;
  tao->ops->setfromoptions = TaoSetFromOptions_RelaxedSD;
  tao->ops->destroy        = TaoDestroy_RelaxedSD;
  PetscFunctionReturn(0);
}
