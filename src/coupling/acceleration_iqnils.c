/* -coupling iqnils: interface quasi-Newton with an inverse-Jacobian least-squares model
   (Degroote et al. 2009; the algorithm of preCICE and CoCoNuT). Its columns (residual
   differences V, sweep differences W, acceleration_iqn.c) of the last q steps are reused
   (-coupling_iqn_reuse). The update is u = S(u_k) + W c, c = argmin ||V c + r_k||; a step
   without any column yet takes one relaxed step (-coupling_omega). */
#include "acceleration_iqn.h"
#include "options.h"

typedef struct {
  IQNColumns columns;
  PetscInt   reuse;
  Vec        update; /* W c */
} IQNILS;

static PetscErrorCode IQNILSSetUp(Acceleration acc, Vec model)
{
  IQNILS *qn = (IQNILS *)acc->data;

  PetscFunctionBeginUser;
  qn->reuse = 8;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Interface quasi-Newton (IQN-ILS)", "coupling");
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-coupling_iqn_reuse",
                              "iqnils: reuse the columns of this many previous time steps", 0, 1000, &qn->reuse));
  PetscOptionsEnd();
  PetscCall(IQNColumnsSetUp(&qn->columns, model, "iqnils"));
  PetscCall(VecDuplicate(model, &qn->update));
  PetscFunctionReturn(0);
}

/* Drops the columns older than the reuse window (and the oldest past max_cols). */
static PetscErrorCode IQNILSBeginStep(Acceleration acc, PetscInt step)
{
  IQNILS *qn = (IQNILS *)acc->data;

  PetscFunctionBeginUser;
  PetscCall(IQNColumnsDropBefore(&qn->columns, step, qn->reuse));
  PetscFunctionReturn(0);
}

static PetscErrorCode IQNILSUpdate(Acceleration acc, PetscInt step, PetscInt k, Vec u, Vec sweep, Vec r)
{
  IQNILS *qn = (IQNILS *)acc->data;

  PetscFunctionBeginUser;
  PetscCall(IQNColumnsRecord(&qn->columns, step, k, sweep, r));
  if (qn->columns.ncols) {
    PetscCall(IQNColumnsFactor(&qn->columns));
    PetscCall(IQNColumnsLeastSquares(&qn->columns, r, qn->update, NULL));
    PetscCall(VecWAXPY(u, 1.0, sweep, qn->update));
  } else PetscCall(VecAXPY(u, acc->omega, r)); /* no model yet: one relaxed step */
  PetscFunctionReturn(0);
}

/* The columns were built with another dt (or before a checkpoint). */
static PetscErrorCode IQNILSReset(Acceleration acc)
{
  PetscFunctionBeginUser;
  ((IQNILS *)acc->data)->columns.ncols = 0;
  PetscFunctionReturn(0);
}

static PetscErrorCode IQNILSDestroy(Acceleration acc)
{
  IQNILS *qn = (IQNILS *)acc->data;

  PetscFunctionBeginUser;
  PetscCall(IQNColumnsDestroy(&qn->columns));
  PetscCall(VecDestroy(&qn->update));
  PetscCall(PetscFree(acc->data));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingCreate_IQNILS(Coupling C)
{
  Acceleration acc;
  IQNILS      *qn;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&acc));
  PetscCall(PetscNew(&qn));
  acc->data           = qn;
  acc->omega          = 0.05;
  acc->model_its      = 4;
  acc->ops.setup      = IQNILSSetUp;
  acc->ops.begin_step = IQNILSBeginStep;
  acc->ops.update     = IQNILSUpdate;
  acc->ops.reset      = IQNILSReset;
  acc->ops.destroy    = IQNILSDestroy;
  PetscCall(CouplingCreate_Partitioned(C, acc));
  PetscFunctionReturn(0);
}
