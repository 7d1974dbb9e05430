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

/* The Dirichlet fluid lives as long as the fluid; its solver, from the first
   FluidSetUpDirichlet until a restart resets it */
struct _n_FluidDirichlet {
  SNES         snes;
  Mat          jacobian;
  Vec          rhs;
  PetscInt     n_rows, *rows; /* local offsets of the interface rows */
  IS           rows_global;
  PetscScalar *residual; /* R(x) on them at the last evaluation */
  PetscInt     step;     /* of the last solve; -1: factor anew at the next */
  PetscInt     lag;      /* -fluid_dirichlet_snes_lag_jacobian K > 0: factors kept across steps */
};

/* R(x) with the interface rows replaced by x_i; their values R(x)_i are kept: at the
   converged state they are the reaction */
static PetscErrorCode DirichletFunction(SNES snes, Vec x, Vec F, void *ctx)
{
  Fluid              f = (Fluid)ctx;
  FluidDirichlet     d = f->dirichlet;
  const PetscScalar *xa;
  PetscScalar       *Fa;

  PetscFunctionBeginUser;
  (void)snes;
  PetscCall(SNESComputeFunction(f->snes, x, F));
  PetscCall(VecGetArrayRead(x, &xa));
  PetscCall(VecGetArray(F, &Fa));
  for (PetscInt i = 0; i < d->n_rows; ++i) {
    d->residual[i] = Fa[d->rows[i]];
    Fa[d->rows[i]] = xa[d->rows[i]];
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
  PetscCall(MatZeroRowsIS(P, f->dirichlet->rows_global, 1.0, NULL, NULL));
  if (J != P) {
    PetscCall(MatAssemblyBegin(J, MAT_FINAL_ASSEMBLY));
    PetscCall(MatAssemblyEnd(J, MAT_FINAL_ASSEMBLY));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FluidDirichletCreate(FluidDirichlet *d)
{
  PetscFunctionBeginUser;
  PetscCall(PetscNew(d));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidDirichletRefactor(FluidDirichlet d)
{
  PetscFunctionBeginUser;
  d->step = -1;
  PetscFunctionReturn(0);
}

/* its solver, rows and factors go; the next FluidSetUpDirichlet makes them anew */
static PetscErrorCode SolverDestroy(FluidDirichlet d)
{
  PetscFunctionBeginUser;
  PetscCall(SNESDestroy(&d->snes));
  PetscCall(MatDestroy(&d->jacobian));
  PetscCall(VecDestroy(&d->rhs));
  PetscCall(PetscFree2(d->rows, d->residual));
  PetscCall(ISDestroy(&d->rows_global));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidDirichletReset(FluidDirichlet d)
{
  PetscFunctionBeginUser;
  if (!d->snes) PetscFunctionReturn(0);
  PetscCall(SolverDestroy(d));
  d->step = -1;
  PetscFunctionReturn(0);
}

PetscErrorCode FluidDirichletDestroy(FluidDirichlet *d)
{
  PetscFunctionBeginUser;
  if (!*d) PetscFunctionReturn(0);
  PetscCall(SolverDestroy(*d));
  PetscCall(PetscFree(*d));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidSetUpDirichlet(Fluid f, IS rows)
{
  FluidDirichlet  d = f->dirichlet;
  Mat             J;
  KSP             ksp;
  PC              pc;
  PetscInt        rstart, n;
  const PetscInt *idx;

  PetscFunctionBeginUser;
  if (d->snes) PetscFunctionReturn(0);
  PetscCall(ISGetLocalSize(rows, &n));
  PetscCall(ISGetIndices(rows, &idx));
  PetscCall(VecGetOwnershipRange(f->x, &rstart, NULL));
  PetscCall(PetscMalloc2(n, &d->rows, n, &d->residual));
  for (PetscInt i = 0; i < n; ++i) d->rows[i] = idx[i] - rstart;
  d->n_rows = n;
  PetscCall(ISRestoreIndices(rows, &idx));
  PetscCall(PetscObjectReference((PetscObject)rows));
  d->rows_global = rows;
  PetscCall(SNESSetUp(f->snes));
  PetscCall(SNESGetJacobian(f->snes, NULL, &J, NULL, NULL)); /* the assembled one (-fluid_matfree) */
  PetscCall(MatDuplicate(J, MAT_DO_NOT_COPY_VALUES, &d->jacobian));
  PetscCall(MatSetOption(d->jacobian, MAT_KEEP_NONZERO_PATTERN, PETSC_TRUE));
  PetscCall(VecDuplicate(f->x, &d->rhs));
  /* no DM: the callbacks stay off the fluid DM's own DMSNES */
  PetscCall(SNESCreate(f->comm, &d->snes));
  PetscCall(SNESSetOptionsPrefix(d->snes, "fluid_dirichlet_"));
  PetscCall(SNESSetFunction(d->snes, NULL, DirichletFunction, f));
  PetscCall(SNESSetJacobian(d->snes, d->jacobian, d->jacobian, DirichletJacobian, f));
  PetscCall(SNESGetKSP(d->snes, &ksp));
  PetscCall(KSPSetType(ksp, KSPPREONLY));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(FEMDirectSolverDefaults("fluid_dirichlet_"));
  PetscCall(PCSetType(pc, PCLU));
  PetscCall(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
  {
    SNESLineSearch ls;
    PetscCall(SNESGetLineSearch(d->snes, &ls));
    PetscCall(SNESLineSearchSetType(ls, SNESLINESEARCHBASIC));
  }
  PetscCall(SNESSetLagJacobian(d->snes, -2));
  PetscCall(SNESSetLagJacobianPersists(d->snes, PETSC_TRUE));
  /* the reaction is a small part of a residual dominated by rho/dt M u: it needs a
     tighter solve than the state alone (relative to the first residual of each solve) */
  PetscCall(SNESSetTolerances(d->snes, f->atol, 1e-10, PETSC_DEFAULT, 50, PETSC_DEFAULT));
  /* the factors kept across steps, refreshed every 20th Newton iteration, as the
     traction-controlled fluid keeps its own: iqnimvj 1.26x faster on channel2d's pulse, and at
     each -coupling_rtol on fsi3's swing 16-24 % faster at about the same probe error
     (docs/coupling-and-solvers.md); -2: a factorization every step */
  PetscCall(OptionsSetDefault("-fluid_dirichlet_snes_lag_jacobian", "20"));
  PetscCall(SNESSetFromOptions(d->snes));
  PetscCall(SNESGetLagJacobian(d->snes, &d->lag));
  if (d->lag < 1) d->lag = 0;
  PetscFunctionReturn(0);
}

PetscErrorCode FluidSolveDirichlet(Fluid f, IS rows, Vec values, Vec reaction, PetscInt step)
{
  FluidDirichlet     d;
  PetscScalar       *b;
  const PetscScalar *v;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_FLUID_SOLVE, 0, 0, 0, 0));
  PetscCall(FluidSetUpDirichlet(f, rows)); /* once: the coupling's set-up made it already */
  d = f->dirichlet;
  /* one factorization per time step: later iterations of the step reuse it (chord); a
     user's lag keeps the factors across steps too, as the traction-controlled fluid's does,
     except after a change of the time step (FluidSetTimeStep) */
  if (d->step != step && (!d->lag || d->step < 0)) PetscCall(SNESSetLagJacobian(d->snes, -2));
  d->step = step;
  PetscCall(VecCopy(f->history, d->rhs));
  PetscCall(VecGetArray(d->rhs, &b));
  PetscCall(VecGetArrayRead(values, &v));
  for (PetscInt i = 0; i < d->n_rows; ++i) b[d->rows[i]] = v[d->rows[i]];
  PetscCall(VecRestoreArrayRead(values, &v));
  PetscCall(VecRestoreArray(d->rhs, &b));
  {
    PetscReal rhs_norm;
    PetscCall(VecNorm(d->rhs, NORM_2, &rhs_norm));
    PetscCall(SNESSetTolerances(d->snes, PetscMax(f->atol, 1e-13 * rhs_norm), PETSC_DEFAULT, PETSC_DEFAULT,
                                PETSC_DEFAULT, PETSC_DEFAULT));
  }
  PetscCall(
    FluidNonlinearSolve(f, d->snes, d->rhs, PETSC_TRUE, step, " with the interface velocity prescribed"));
  if (d->lag) PetscCall(SNESSetLagJacobian(d->snes, d->lag));
  /* the reaction: what the interface rows of R(x) = history + load would need as load */
  {
    const PetscScalar *h;
    PetscScalar       *r;
    PetscCall(VecZeroEntries(reaction));
    PetscCall(VecGetArrayRead(f->history, &h));
    PetscCall(VecGetArray(reaction, &r));
    for (PetscInt i = 0; i < d->n_rows; ++i) r[d->rows[i]] = d->residual[i] - h[d->rows[i]];
    PetscCall(VecRestoreArray(reaction, &r));
    PetscCall(VecRestoreArrayRead(f->history, &h));
  }
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_FLUID_SOLVE, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}
