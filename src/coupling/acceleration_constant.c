/* -coupling dn: Dirichlet-Neumann with a fixed relaxation, u + omega r (-coupling_omega,
   default 1: unrelaxed). The plainest of the partitioned family; with a heavy fluid on a
   light wall it diverges (the added-mass effect), which is what it is kept to show. */
#include "acceleration.h"

static PetscErrorCode ConstantUpdate(Acceleration acc, PETSC_UNUSED PetscInt step, PETSC_UNUSED PetscInt k, Vec u,
                                     PETSC_UNUSED Vec sweep, Vec r)
{
  PetscFunctionBeginUser;
  PetscCall(VecAXPY(u, acc->omega, r));
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingCreate_DN(Coupling C)
{
  Acceleration acc;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&acc));
  acc->omega      = 1.0;
  acc->ops.update = ConstantUpdate;
  PetscCall(CouplingCreate_Partitioned(C, acc));
  PetscFunctionReturn(0);
}
