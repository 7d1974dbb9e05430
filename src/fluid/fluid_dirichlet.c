/* The fluid with a prescribed interface velocity, for the Dirichlet-Neumann baselines
   (-coupling dn|aitken|iqnils|iqnimvj). The interface rows of R(x) = rhs are replaced by
   x_i = v_i; the DM, its kernels, the moving mesh and the boundary data are the ones of
   the traction-controlled fluid, and the reaction R(x)_i - history_i on those rows is the
   interface load B_f g that fluid would need for the same state: the consistent (weak)
   interface traction, kept from the solve's last residual evaluation. Its own SNES
   (options prefix -fluid_dirichlet_) and factors. */
#include "fluid_impl.h"
#include "fem.h"
#include "logging.h"
#include "options.h"

/* R(x) with the interface rows replaced by x_i; their values R(x)_i are kept: at the
   converged state they are the reaction */
static PetscErrorCode DirichletFunction(SNES snes, Vec x, Vec F, void *ctx)
{
  Fluid              f = (Fluid)ctx;
  const PetscScalar *xa;
  PetscScalar       *Fa;

  PetscFunctionBeginUser;
  (void)snes;
  PetscCall(SNESComputeFunction(f->snes, x, F));
  PetscCall(VecGetArrayRead(x, &xa));
  PetscCall(VecGetArray(F, &Fa));
  for (PetscInt i = 0; i < f->n_dirichlet_rows; ++i) {
    f->dirichlet_residual[i] = Fa[f->dirichlet_rows[i]];
    Fa[f->dirichlet_rows[i]] = xa[f->dirichlet_rows[i]];
  }
  PetscCall(VecRestoreArray(F, &Fa));
  PetscCall(VecRestoreArrayRead(x, &xa));
  PetscFunctionReturn(0);
}

/* The fluid's own Jacobian routine (not SNESComputeJacobian, whose lag would skip it),
   then identity rows on the interface */
static PetscErrorCode DirichletJacobian(SNES snes, Vec x, Mat J, Mat P, void *ctx)
{
  Fluid f = (Fluid)ctx;
  PetscErrorCode (*jacobian)(SNES, Vec, Mat, Mat, void *);
  void *jctx;

  PetscFunctionBeginUser;
  (void)snes;
  PetscCall(SNESGetJacobian(f->snes, NULL, NULL, &jacobian, &jctx));
  PetscCall((*jacobian)(f->snes, x, P, P, jctx));
  PetscCall(MatZeroRowsIS(P, f->dirichlet_rows_global, 1.0, NULL, NULL));
  if (J != P) {
    PetscCall(MatAssemblyBegin(J, MAT_FINAL_ASSEMBLY));
    PetscCall(MatAssemblyEnd(J, MAT_FINAL_ASSEMBLY));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FluidSetUpDirichlet(Fluid f, IS rows)
{
  Mat             J;
  KSP             ksp;
  PC              pc;
  PetscInt        rstart, n;
  const PetscInt *idx;

  PetscFunctionBeginUser;
  if (f->snes_dirichlet) PetscFunctionReturn(0);
  PetscCall(ISGetLocalSize(rows, &n));
  PetscCall(ISGetIndices(rows, &idx));
  PetscCall(VecGetOwnershipRange(f->x, &rstart, NULL));
  PetscCall(PetscMalloc2(n, &f->dirichlet_rows, n, &f->dirichlet_residual));
  for (PetscInt i = 0; i < n; ++i) f->dirichlet_rows[i] = idx[i] - rstart;
  f->n_dirichlet_rows = n;
  PetscCall(ISRestoreIndices(rows, &idx));
  PetscCall(PetscObjectReference((PetscObject)rows));
  f->dirichlet_rows_global = rows;
  PetscCall(SNESSetUp(f->snes));
  PetscCall(SNESGetJacobian(f->snes, NULL, &J, NULL, NULL)); /* the assembled one (-fluid_matfree) */
  PetscCall(MatDuplicate(J, MAT_DO_NOT_COPY_VALUES, &f->dirichlet_jacobian));
  PetscCall(MatSetOption(f->dirichlet_jacobian, MAT_KEEP_NONZERO_PATTERN, PETSC_TRUE));
  PetscCall(VecDuplicate(f->x, &f->dirichlet_rhs));
  /* no DM: the callbacks stay off the fluid DM's own DMSNES */
  PetscCall(SNESCreate(f->comm, &f->snes_dirichlet));
  PetscCall(SNESSetOptionsPrefix(f->snes_dirichlet, "fluid_dirichlet_"));
  PetscCall(SNESSetFunction(f->snes_dirichlet, NULL, DirichletFunction, f));
  PetscCall(SNESSetJacobian(f->snes_dirichlet, f->dirichlet_jacobian, f->dirichlet_jacobian, DirichletJacobian, f));
  PetscCall(SNESGetKSP(f->snes_dirichlet, &ksp));
  PetscCall(KSPSetType(ksp, KSPPREONLY));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(FEMDirectSolverDefaults("fluid_dirichlet_"));
  PetscCall(PCSetType(pc, PCLU));
  PetscCall(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
  {
    SNESLineSearch ls;
    PetscCall(SNESGetLineSearch(f->snes_dirichlet, &ls));
    PetscCall(SNESLineSearchSetType(ls, SNESLINESEARCHBASIC));
  }
  PetscCall(SNESSetLagJacobian(f->snes_dirichlet, -2));
  PetscCall(SNESSetLagJacobianPersists(f->snes_dirichlet, PETSC_TRUE));
  /* the reaction is a small part of a residual dominated by rho/dt M u: it needs a
     tighter solve than the state alone (relative to the first residual of each solve) */
  PetscCall(SNESSetTolerances(f->snes_dirichlet, f->atol, 1e-10, PETSC_DEFAULT, 50, PETSC_DEFAULT));
  /* the factors kept across steps, refreshed every 20th Newton iteration, as the
     traction-controlled fluid keeps its own: iqnimvj 1.26x faster on channel2d's pulse, and at
     each -coupling_rtol on fsi3's swing 16-24 % faster at about the same probe error
     (docs/coupling-and-solvers.md); -2: a factorization every step */
  PetscCall(OptionsSetDefault("-fluid_dirichlet_snes_lag_jacobian", "20"));
  PetscCall(SNESSetFromOptions(f->snes_dirichlet));
  PetscCall(SNESGetLagJacobian(f->snes_dirichlet, &f->dirichlet_lag));
  if (f->dirichlet_lag < 1) f->dirichlet_lag = 0;
  PetscFunctionReturn(0);
}

PetscErrorCode FluidSolveDirichlet(Fluid f, IS rows, Vec values, Vec reaction, PetscInt step)
{
  PetscScalar       *b;
  const PetscScalar *v;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_FLUID_SOLVE, 0, 0, 0, 0));
  PetscCall(FluidSetUpDirichlet(f, rows)); /* once: the coupling's set-up made it already */
  /* one factorization per time step: later iterations of the step reuse it (chord); a
     user's lag keeps the factors across steps too, as the traction-controlled fluid's does,
     except after a change of the time step (FluidSetTimeStep) */
  if (f->dirichlet_step != step && (!f->dirichlet_lag || f->dirichlet_step < 0))
    PetscCall(SNESSetLagJacobian(f->snes_dirichlet, -2));
  f->dirichlet_step = step;
  PetscCall(VecCopy(f->history, f->dirichlet_rhs));
  PetscCall(VecGetArray(f->dirichlet_rhs, &b));
  PetscCall(VecGetArrayRead(values, &v));
  for (PetscInt i = 0; i < f->n_dirichlet_rows; ++i) b[f->dirichlet_rows[i]] = v[f->dirichlet_rows[i]];
  PetscCall(VecRestoreArrayRead(values, &v));
  PetscCall(VecRestoreArray(f->dirichlet_rhs, &b));
  {
    PetscReal rhs_norm;
    PetscCall(VecNorm(f->dirichlet_rhs, NORM_2, &rhs_norm));
    PetscCall(SNESSetTolerances(f->snes_dirichlet, PetscMax(f->atol, 1e-13 * rhs_norm), PETSC_DEFAULT, PETSC_DEFAULT,
                                PETSC_DEFAULT, PETSC_DEFAULT));
  }
  PetscCall(FluidNonlinearSolve(f, f->snes_dirichlet, f->dirichlet_rhs, PETSC_TRUE, step,
                                " with the interface velocity prescribed"));
  if (f->dirichlet_lag) PetscCall(SNESSetLagJacobian(f->snes_dirichlet, f->dirichlet_lag));
  /* the reaction: what the interface rows of R(x) = history + load would need as load */
  {
    const PetscScalar *h;
    PetscScalar       *r;
    PetscCall(VecZeroEntries(reaction));
    PetscCall(VecGetArrayRead(f->history, &h));
    PetscCall(VecGetArray(reaction, &r));
    for (PetscInt i = 0; i < f->n_dirichlet_rows; ++i)
      r[f->dirichlet_rows[i]] = f->dirichlet_residual[i] - h[f->dirichlet_rows[i]];
    PetscCall(VecRestoreArray(reaction, &r));
    PetscCall(VecRestoreArrayRead(f->history, &h));
  }
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_FLUID_SOLVE, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidDirichletDestroy(Fluid f)
{
  PetscFunctionBeginUser;
  PetscCall(SNESDestroy(&f->snes_dirichlet));
  PetscCall(MatDestroy(&f->dirichlet_jacobian));
  PetscCall(VecDestroy(&f->dirichlet_rhs));
  PetscCall(PetscFree2(f->dirichlet_rows, f->dirichlet_residual));
  PetscCall(ISDestroy(&f->dirichlet_rows_global));
  PetscFunctionReturn(0);
}
