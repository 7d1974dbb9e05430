/* The fluid's residual and Jacobian on the backend -fem_backend chose. PETSc: its pointwise
   integration of the whole weak form on the fluid DM, the reference. ceed: the volume
   terms by libCEED (src/ceed/ceed_fluid.c) into a matrix of its own COO pattern; the
   boundary terms (scene tractions, backflow, the interface's convective term) by PETSc's
   integration on their faces only; the scene's volume loads, which only manufactured
   solutions have, by PETSc on a copy of the DM that holds nothing else.
   -fem_backend_check compares the two at the start of the first steps. */
#include <petsc/private/petscimpl.h> /* PetscObjectStateGet */
#include "fluid_impl.h"
#include "fem.h"
#include "logging.h"

static PetscErrorCode BoundaryTerms(Fluid f, Vec xlocal, Vec flocal, Mat A)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_BOUNDARY_TERMS, 0, 0, 0, 0));
  PetscCall(FEMBoundaryTerms(f->dm, f->time, xlocal, flocal, A, &f->tractions));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_BOUNDARY_TERMS, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* the libCEED context follows the fluid DM's constants */
static PetscErrorCode Synchronize(Fluid f)
{
  PetscDS            ds;
  PetscInt           n;
  const PetscScalar *constants;

  PetscFunctionBeginUser;
  PetscCall(DMGetDS(f->dm, &ds));
  PetscCall(PetscDSGetConstants(ds, &n, &constants));
  PetscCall(FEMCeedFluidSetConstants(f->ceed, constants));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidOperatorResidual(Fluid f, Vec xlocal, PetscBool old_mass, Vec F)
{
  Vec flocal;

  PetscFunctionBeginUser;
  if (!f->backend_ceed) {
    PetscCall(FEMResidual(f->dm, xlocal, F));
    if (old_mass) {
      PetscCall(FluidOldMassMult(f, xlocal, f->work));
      PetscCall(VecAXPY(F, 1.0, f->work));
    }
    PetscFunctionReturn(0);
  }
  PetscCall(Synchronize(f));
  PetscCall(DMGetLocalVector(f->dm, &flocal));
  PetscCall(FEMCeedFluidResidual(f->ceed, xlocal, f->moving ? f->z_local : NULL, old_mass, flocal));
  PetscCall(BoundaryTerms(f, xlocal, flocal, NULL));
  PetscCall(FEMLoadsAdd(f->dm, f->dm_loads, xlocal, flocal));
  PetscCall(VecZeroEntries(F));
  PetscCall(DMLocalToGlobal(f->dm, flocal, ADD_VALUES, F));
  PetscCall(DMRestoreLocalVector(f->dm, &flocal));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidVolumeResidualAll(Fluid f, Vec xlocal, PetscBool old_mass, Vec yall)
{
  Vec flocal;

  PetscFunctionBeginUser;
  PetscCall(Synchronize(f));
  PetscCall(DMGetLocalVector(f->dm_all, &flocal));
  PetscCall(FEMCeedFluidResidual(f->ceed, xlocal, f->z_local, old_mass, flocal));
  PetscCall(FEMLoadsAdd(f->dm, f->dm_loads, xlocal, flocal));
  PetscCall(VecZeroEntries(yall));
  PetscCall(DMLocalToGlobal(f->dm_all, flocal, ADD_VALUES, yall));
  PetscCall(DMRestoreLocalVector(f->dm_all, &flocal));
  PetscFunctionReturn(0);
}

/* the libCEED volume blocks and PETSc's boundary terms at xlocal into A, a matrix of the
   libCEED pattern */
static PetscErrorCode AssembleCeed(Fluid f, Vec xlocal, PetscBool old_mass, Mat A)
{
  PetscFunctionBeginUser;
  PetscCall(Synchronize(f));
  PetscCall(FEMCeedFluidJacobian(f->ceed, xlocal, f->moving ? f->z_local : NULL, old_mass, A));
  PetscCall(BoundaryTerms(f, xlocal, NULL, A));
  PetscCall(MatAssemblyBegin(A, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(A, MAT_FINAL_ASSEMBLY));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidOperatorJacobian(Fluid f, Vec xlocal, PetscBool old_mass, Mat J, Mat P)
{
  PetscFunctionBeginUser;
  if (!f->backend_ceed) {
    PetscCall(DMPlexSNESComputeJacobianFEM(f->dm, xlocal, J, P, NULL));
    if (old_mass && f->mass_old) PetscCall(MatAXPY(P, 1.0, f->mass_old, SUBSET_NONZERO_PATTERN));
    if (old_mass && f->mass_old && J != P) PetscCall(MatAXPY(J, 1.0, f->mass_old, SUBSET_NONZERO_PATTERN));
    PetscFunctionReturn(0);
  }
  PetscCall(AssembleCeed(f, xlocal, old_mass, f->ceed_jacobian));
  /* another matrix of the same pattern (the Dirichlet fluid's) gets a copy */
  if (P != f->ceed_jacobian) PetscCall(MatCopy(f->ceed_jacobian, P, SAME_NONZERO_PATTERN));
  if (J != P && J != f->ceed_jacobian) PetscCall(MatCopy(f->ceed_jacobian, J, SAME_NONZERO_PATTERN));
  PetscFunctionReturn(0);
}

/* x with its boundary values. PETSc's backend projects them at every call (the reference);
   libCEED's keeps them until the time or the mesh changes, which saves the projection
   at each residual of a step (the scenes' Dirichlet data depend on t and x only) */
static PetscErrorCode StateToLocal(Fluid f, Vec x, Vec xlocal)
{
  Vec                coordinates;
  PetscObjectId      id;
  PetscObjectState   state;
  const PetscScalar *b;
  PetscScalar       *a;

  PetscFunctionBeginUser;
  if (!f->backend_ceed) {
    PetscCall(FEMGlobalToLocal(f->dm, x, xlocal));
    PetscFunctionReturn(0);
  }
  PetscCall(DMGetCoordinatesLocal(f->dm, &coordinates));
  PetscCall(PetscObjectGetId((PetscObject)coordinates, &id));
  PetscCall(PetscObjectStateGet((PetscObject)coordinates, &state));
  if (!f->boundary_values) {
    PetscSection section;
    PetscInt     pStart, pEnd, n = 0;
    PetscCall(DMCreateLocalVector(f->dm, &f->boundary_values));
    PetscCall(DMGetLocalSection(f->dm, &section));
    PetscCall(PetscSectionGetChart(section, &pStart, &pEnd));
    for (PetscInt p = pStart; p < pEnd; ++p) {
      PetscInt cdof;
      PetscCall(PetscSectionGetConstraintDof(section, p, &cdof));
      n += cdof;
    }
    PetscCall(PetscMalloc1(n, &f->boundary_dofs));
    f->n_boundary_dofs = 0;
    for (PetscInt p = pStart; p < pEnd; ++p) {
      PetscInt        cdof, off;
      const PetscInt *cind;
      PetscCall(PetscSectionGetConstraintDof(section, p, &cdof));
      if (!cdof) continue;
      PetscCall(PetscSectionGetOffset(section, p, &off));
      PetscCall(PetscSectionGetConstraintIndices(section, p, &cind));
      for (PetscInt k = 0; k < cdof; ++k) f->boundary_dofs[f->n_boundary_dofs++] = off + cind[k];
    }
    f->boundary_values_time = PETSC_MAX_REAL;
  }
  if (f->boundary_values_time != f->time || id != f->boundary_values_id || state != f->boundary_values_state) {
    PetscCall(VecZeroEntries(f->boundary_values));
    PetscCall(DMPlexInsertBoundaryValues(f->dm, PETSC_TRUE, f->boundary_values, 0.0, NULL, NULL, NULL));
    f->boundary_values_time  = f->time;
    f->boundary_values_id    = id;
    f->boundary_values_state = state;
  }
  PetscCall(DMGlobalToLocal(f->dm, x, INSERT_VALUES, xlocal));
  PetscCall(VecGetArray(xlocal, &a));
  PetscCall(VecGetArrayRead(f->boundary_values, &b));
  for (PetscInt i = 0; i < f->n_boundary_dofs; ++i) a[f->boundary_dofs[i]] = b[f->boundary_dofs[i]];
  PetscCall(VecRestoreArrayRead(f->boundary_values, &b));
  PetscCall(VecRestoreArray(xlocal, &a));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidSNESResidual(SNES snes, Vec x, Vec F, void *ctx)
{
  Fluid f = (Fluid)ctx;

  PetscFunctionBeginUser;
  (void)snes;
  PetscCall(StateToLocal(f, x, f->xlocal_work));
  /* on a moving mesh the time derivative acts through the old domains' mass (fluid_ale.c) */
  PetscCall(FluidOperatorResidual(f, f->xlocal_work, f->moving, F));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidSNESJacobian(SNES snes, Vec x, Mat J, Mat P, void *ctx)
{
  Fluid f = (Fluid)ctx;

  PetscFunctionBeginUser;
  (void)snes;
  PetscCall(StateToLocal(f, x, f->xlocal_work));
  PetscCall(FluidOperatorJacobian(f, f->xlocal_work, f->moving, J, P));
  f->counts.factorizations++;
  PetscFunctionReturn(0);
}

PetscErrorCode FluidBackendSetUp(Fluid f)
{
  FEMBackend         backend;
  PetscDS            ds;
  PetscInt           n;
  const PetscScalar *constants;

  PetscFunctionBeginUser;
  PetscCall(FEMBackendGet(&backend, &f->check_backends));
  if (backend != FEM_BACKEND_CEED && !f->check_backends) PetscFunctionReturn(0);
  PetscCall(DMGetDS(f->dm, &ds));
  PetscCall(PetscDSGetConstants(ds, &n, &constants));
  PetscCall(FEMCeedFluidCreate(f->dm, f->moving ? f->dm_aux : NULL, constants, &f->ceed));
  PetscCall(FEMCeedFluidCreateMatrix(f->ceed, &f->ceed_jacobian));
  PetscCall(FEMLoadsCreate(f->dm, f->data.load_value_kernel, f->data.load_stress_kernel, f->moving ? f->z_local : NULL,
                           &f->dm_loads));
  if (backend != FEM_BACKEND_CEED) PetscFunctionReturn(0); /* built for the check only */
  f->backend_ceed = PETSC_TRUE;
  PetscCall(SNESSetJacobian(f->snes, f->ceed_jacobian, f->ceed_jacobian, NULL, NULL));
  /* the callbacks FluidALESetUp installs on a moving mesh; on a fixed one they replace DMPlex's */
  PetscCall(SNESSetFunction(f->snes, NULL, FluidSNESResidual, f));
  PetscCall(SNESSetJacobian(f->snes, NULL, NULL, FluidSNESJacobian, f));
  PetscFunctionReturn(0);
}

/* ||a - b|| / ||b|| of the residuals of both backends at the global state x; the same for
   the Jacobians, each in a matrix of its own (the solver's keep their values and factors) */
static PetscErrorCode CompareAt(Fluid f, Vec x, PetscReal *residual, PetscReal *jacobian)
{
  const PetscBool backend = f->backend_ceed;
  /* the old domains' mass where both backends have it: -fem_backend petsc keeps both */
  const PetscBool old_mass = f->moving && f->mass_old_all ? PETSC_TRUE : PETSC_FALSE;
  Vec             xlocal, F_petsc, F_ceed;
  Mat             J_petsc, J_ceed;
  PetscReal       norm;

  PetscFunctionBeginUser;
  PetscCall(DMGetLocalVector(f->dm, &xlocal));
  PetscCall(VecDuplicate(x, &F_petsc));
  PetscCall(VecDuplicate(x, &F_ceed));
  PetscCall(FEMGlobalToLocal(f->dm, x, xlocal));
  f->backend_ceed = PETSC_FALSE;
  PetscCall(FluidOperatorResidual(f, xlocal, old_mass, F_petsc));
  f->backend_ceed = PETSC_TRUE;
  PetscCall(FluidOperatorResidual(f, xlocal, old_mass, F_ceed));
  f->backend_ceed = backend;
  PetscCall(VecAXPY(F_ceed, -1.0, F_petsc));
  PetscCall(VecNorm(F_ceed, NORM_2, residual));
  PetscCall(DMCreateMatrix(f->dm, &J_petsc));
  PetscCall(DMPlexSNESComputeJacobianFEM(f->dm, xlocal, J_petsc, J_petsc, NULL));
  if (old_mass) PetscCall(MatAXPY(J_petsc, 1.0, f->mass_old, SUBSET_NONZERO_PATTERN));
  PetscCall(FEMCeedFluidCreateMatrix(f->ceed, &J_ceed));
  PetscCall(AssembleCeed(f, xlocal, old_mass, J_ceed));
  {
    /* the residual's difference relative to R(0), the data, plus ||J||_F ||x|| / sqrt(N),
       the root mean square of a row's bound, a scale of the state's part before the
       assembly cancels it (near an equilibrium R(x) itself is mostly round-off) */
    Vec       zero, zlocal, F_zero;
    PetscReal data, jnorm, xnorm;
    PetscInt  N;
    PetscCall(VecDuplicate(F_petsc, &zero));
    PetscCall(VecDuplicate(F_petsc, &F_zero));
    PetscCall(VecZeroEntries(zero));
    PetscCall(DMGetLocalVector(f->dm, &zlocal));
    PetscCall(FEMGlobalToLocal(f->dm, zero, zlocal));
    f->backend_ceed = PETSC_FALSE;
    PetscCall(FluidOperatorResidual(f, zlocal, old_mass, F_zero));
    f->backend_ceed = backend;
    PetscCall(DMRestoreLocalVector(f->dm, &zlocal));
    PetscCall(VecNorm(F_zero, NORM_2, &data));
    PetscCall(MatNorm(J_petsc, NORM_FROBENIUS, &jnorm));
    PetscCall(VecNorm(xlocal, NORM_2, &xnorm));
    PetscCall(VecGetSize(F_petsc, &N));
    norm = data + jnorm * xnorm / PetscSqrtReal((PetscReal)N);
    if (norm > 0) *residual /= norm; /* else both are zero */
    PetscCall(VecDestroy(&zero));
    PetscCall(VecDestroy(&F_zero));
  }
  PetscCall(FEMCeedMatDifference(J_ceed, J_petsc, jacobian));
  PetscCall(MatDestroy(&J_petsc));
  PetscCall(MatDestroy(&J_ceed));
  PetscCall(VecDestroy(&F_petsc));
  PetscCall(VecDestroy(&F_ceed));
  PetscCall(DMRestoreLocalVector(f->dm, &xlocal));
  PetscFunctionReturn(0);
}

#define BACKEND_CHECK_STEPS 3
#define BACKEND_CHECK_TOL   1e-12

PetscErrorCode FluidBackendCheck(Fluid f)
{
  PetscReal   residual[2], jacobian[2];
  Vec         x;
  PetscRandom random;

  PetscFunctionBeginUser;
  if (!f->check_backends || f->step > BACKEND_CHECK_STEPS || f->step == f->backend_checked_step) PetscFunctionReturn(0);
  f->backend_checked_step = f->step;
  PetscCall(CompareAt(f, f->x, &residual[0], &jacobian[0]));
  PetscCall(VecDuplicate(f->x, &x));
  PetscCall(PetscRandomCreate(f->comm, &random));
  PetscCall(PetscRandomSetInterval(random, -1.0, 1.0));
  PetscCall(VecSetRandom(x, random));
  PetscCall(PetscRandomDestroy(&random));
  PetscCall(CompareAt(f, x, &residual[1], &jacobian[1]));
  PetscCall(VecDestroy(&x));
  PetscCall(PetscPrintf(f->comm,
                        "fsiopt: backend check: step %" PetscInt_FMT
                        ": fluid residual %.2e (the step's start) %.2e (a random state), Jacobian %.2e %.2e, "
                        "libCEED relative to PETSc\n",
                        f->step, (double)residual[0], (double)residual[1], (double)jacobian[0], (double)jacobian[1]));
  for (PetscInt i = 0; i < 2; ++i)
    PetscCheck(residual[i] <= BACKEND_CHECK_TOL && jacobian[i] <= BACKEND_CHECK_TOL, f->comm, PETSC_ERR_PLIB,
               "option -fem_backend_check: at step %" PetscInt_FMT
               " the fluid's libCEED operators differ from PETSc's by %.2e (residual), %.2e (Jacobian), more than %g",
               f->step, (double)residual[i], (double)jacobian[i], BACKEND_CHECK_TOL);
  PetscFunctionReturn(0);
}

PetscErrorCode FluidBackendDestroy(Fluid f)
{
  PetscFunctionBeginUser;
  PetscCall(FEMCeedFluidDestroy(&f->ceed));
  PetscCall(MatDestroy(&f->ceed_jacobian));
  PetscCall(DMDestroy(&f->dm_loads));
  PetscCall(VecDestroy(&f->boundary_values));
  PetscCall(PetscFree(f->boundary_dofs));
  PetscCall(FEMTractionCacheDestroy(&f->tractions));
  PetscFunctionReturn(0);
}
