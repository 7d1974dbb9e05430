/* Nodal values of a pointwise function of a field and its gradient (a velocity gradient, a
   stress) for output: each cell evaluates the function at the Lagrange nodes of a
   continuous space of the field's degree (DMProjectFieldLocal), and a node shared by
   cells (on any rank) gets their mean. A gradient that is continuous across cells (a
   polynomial solution the space holds) comes out exact; otherwise the mean is the usual
   recovered nodal value. The kernel reads the DM's constants and auxiliary fields, as the
   solver's own kernels do. */
#include "fem.h"

struct _n_FEMNodalAverage {
  DM        dm;             /* a clone of the field's DM with the output space */
  Vec       sum, global;    /* local sums, and their global sum */
  Vec       inverse_count;  /* local: 1 / the number of cells that share each node */
  Vec       value;          /* local: the means */
  ResidualKernel kernel;
};

static void One(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[],
                const PetscInt aOff_x[], const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[],
                PetscReal t, const PetscReal x[], PetscInt numConstants, const PetscScalar constants[],
                PetscScalar f[])
{
  (void)dim, (void)Nf, (void)NfAux, (void)uOff, (void)uOff_x, (void)u, (void)u_t, (void)u_x, (void)aOff,
    (void)aOff_x, (void)a, (void)a_t, (void)a_x, (void)t, (void)x, (void)numConstants, (void)constants;
  f[0] = 1.0;
}

PetscErrorCode FEMSumOverRanks(DM dm, Vec local, Vec global)
{
  PetscFunctionBeginUser;
  PetscCall(VecZeroEntries(global));
  PetscCall(DMLocalToGlobal(dm, local, ADD_VALUES, global));
  PetscCall(DMGlobalToLocal(dm, global, INSERT_VALUES, local));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMNodalAverageCreate(DM dm, PetscInt degree, PetscInt nc, const char name[], ResidualKernel kernel,
                                     FEMNodalAverage *out)
{
  FEMNodalAverage    avg;
  Vec                aux;
  ResidualKernel          one = One;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&avg));
  avg->kernel = kernel;
  PetscCall(DMClone(dm, &avg->dm));
  PetscCall(FEMCreateField(avg->dm, 0, name, nc, degree, NULL));
  PetscCall(DMCreateDS(avg->dm));
  PetscCall(DMGetAuxiliaryVec(dm, NULL, 0, 0, &aux));
  if (aux) PetscCall(DMSetAuxiliaryVec(avg->dm, NULL, 0, 0, aux));
  PetscCall(DMCreateLocalVector(avg->dm, &avg->sum));
  PetscCall(DMCreateGlobalVector(avg->dm, &avg->global));
  PetscCall(VecDuplicate(avg->sum, &avg->value));
  PetscCall(VecDuplicate(avg->sum, &avg->inverse_count));
  /* the cells that share each node: a function of 1 summed like the values, in a space of
     one component (so the kernel fills its whole value), spread over the nc components */
  {
    DM                 scalar;
    Vec                ones, count, global;
    const PetscScalar *c;
    PetscScalar       *inv;
    PetscInt           n;

    PetscCall(DMClone(dm, &scalar));
    PetscCall(FEMCreateField(scalar, 0, "count", 1, degree, NULL));
    PetscCall(DMCreateDS(scalar));
    PetscCall(DMCreateLocalVector(dm, &ones));
    PetscCall(DMCreateLocalVector(scalar, &count));
    PetscCall(DMCreateGlobalVector(scalar, &global));
    PetscCall(DMProjectFieldLocal(scalar, 0.0, ones, &one, ADD_VALUES, count));
    PetscCall(FEMSumOverRanks(scalar, count, global));
    PetscCall(VecGetLocalSize(count, &n));
    PetscCall(VecGetArrayRead(count, &c));
    PetscCall(VecGetArray(avg->inverse_count, &inv));
    for (PetscInt i = 0; i < n; ++i)
      for (PetscInt k = 0; k < nc; ++k) inv[i * nc + k] = PetscRealPart(c[i]) > 0 ? 1.0 / c[i] : 0.0;
    PetscCall(VecRestoreArray(avg->inverse_count, &inv));
    PetscCall(VecRestoreArrayRead(count, &c));
    PetscCall(VecDestroy(&ones));
    PetscCall(VecDestroy(&count));
    PetscCall(VecDestroy(&global));
    PetscCall(DMDestroy(&scalar));
  }
  *out = avg;
  PetscFunctionReturn(0);
}

PetscErrorCode FEMNodalAverageCompute(FEMNodalAverage avg, Vec local_field, PetscReal t, Vec *value)
{
  DM                 dm;
  PetscDS            ds, ds_in;
  PetscInt           n;
  const PetscScalar *constants;

  PetscFunctionBeginUser;
  /* the field's constants as its solver last set them */
  PetscCall(VecGetDM(local_field, &dm));
  PetscCall(DMGetDS(dm, &ds_in));
  PetscCall(DMGetDS(avg->dm, &ds));
  PetscCall(PetscDSGetConstants(ds_in, &n, &constants));
  if (n) PetscCall(PetscDSSetConstants(ds, n, (PetscScalar *)constants));
  PetscCall(VecZeroEntries(avg->sum));
  PetscCall(DMProjectFieldLocal(avg->dm, t, local_field, &avg->kernel, ADD_VALUES, avg->sum));
  PetscCall(FEMSumOverRanks(avg->dm, avg->sum, avg->global));
  PetscCall(VecPointwiseMult(avg->value, avg->sum, avg->inverse_count));
  *value = avg->value;
  PetscFunctionReturn(0);
}

PetscErrorCode FEMNodalAverageValue(FEMNodalAverage avg, Vec *value)
{
  PetscFunctionBeginUser;
  *value = avg->value;
  PetscFunctionReturn(0);
}

PetscErrorCode FEMNodalAverageGetSection(FEMNodalAverage avg, PetscSection *section)
{
  PetscFunctionBeginUser;
  PetscCall(DMGetLocalSection(avg->dm, section));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMNodalAverageDestroy(FEMNodalAverage *avg)
{
  PetscFunctionBeginUser;
  if (!*avg) PetscFunctionReturn(0);
  PetscCall(VecDestroy(&(*avg)->sum));
  PetscCall(VecDestroy(&(*avg)->global));
  PetscCall(VecDestroy(&(*avg)->value));
  PetscCall(VecDestroy(&(*avg)->inverse_count));
  PetscCall(DMDestroy(&(*avg)->dm));
  PetscCall(PetscFree(*avg));
  PetscFunctionReturn(0);
}
