/* -coupling aitken: Aitken's dynamic relaxation (the seed's reference method, §3.6.1):
   omega_k = -omega_{k-1} (r_{k-1}, r_k - r_{k-1}) / ||r_k - r_{k-1}||^2, each step
   starting again from -coupling_omega (default 0.05, the seed's). */
#include "acceleration.h"

typedef struct {
  PetscReal first_omega; /* each step's first relaxation */
  Vec       r_before;    /* r_{k-1} */
} Aitken;

static PetscErrorCode AitkenSetUp(Acceleration acc, Vec model)
{
  Aitken *ai = (Aitken *)acc->data;

  PetscFunctionBeginUser;
  ai->first_omega = acc->omega;
  PetscCall(VecDuplicate(model, &ai->r_before));
  PetscFunctionReturn(0);
}

static PetscErrorCode AitkenBeginStep(Acceleration acc, PETSC_UNUSED PetscInt step)
{
  PetscFunctionBeginUser;
  acc->omega = ((Aitken *)acc->data)->first_omega;
  PetscFunctionReturn(0);
}

static PetscErrorCode AitkenUpdate(Acceleration acc, PETSC_UNUSED PetscInt step, PetscInt k, Vec u,
                                   PETSC_UNUSED Vec sweep, Vec r)
{
  Aitken *ai = (Aitken *)acc->data;

  PetscFunctionBeginUser;
  if (k > 0) {
    PetscScalar num, den;
    PetscCall(VecAYPX(ai->r_before, -1.0, r)); /* r_k - r_{k-1} */
    PetscCall(VecDot(ai->r_before, r, &num));
    PetscCall(VecDot(ai->r_before, ai->r_before, &den));
    /* (r_{k-1}, d) = (r_k, d) - (d, d) */
    if (PetscAbsScalar(den) > 0) acc->omega = -acc->omega * PetscRealPart(num - den) / PetscRealPart(den);
  }
  PetscCall(VecCopy(r, ai->r_before));
  PetscCall(VecAXPY(u, acc->omega, r));
  PetscFunctionReturn(0);
}

static PetscErrorCode AitkenDestroy(Acceleration acc)
{
  Aitken *ai = (Aitken *)acc->data;

  PetscFunctionBeginUser;
  PetscCall(VecDestroy(&ai->r_before));
  PetscCall(PetscFree(acc->data));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingCreate_Aitken(Coupling C)
{
  Acceleration acc;
  Aitken      *ai;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&acc));
  PetscCall(PetscNew(&ai));
  acc->data           = ai;
  acc->omega          = 0.05;
  acc->ops.setup      = AitkenSetUp;
  acc->ops.begin_step = AitkenBeginStep;
  acc->ops.update     = AitkenUpdate;
  acc->ops.destroy    = AitkenDestroy;
  PetscCall(CouplingCreate_Partitioned(C, acc));
  PetscFunctionReturn(0);
}
