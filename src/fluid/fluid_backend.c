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

/* PETSc's part of the boundary terms: the tractions alone where libCEED has the others */
static PetscErrorCode BoundaryTerms(Fluid f, Vec xlocal, Vec flocal, Mat A)
{
  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_BOUNDARY_TERMS, 0, 0, 0, 0));
  if (!FEMCeedFluidHasFaces(f->ceed)) PetscCall(FEMBoundaryTerms(f->dm, f->time, xlocal, flocal, A, &f->tractions));
  else if (flocal) PetscCall(FEMBoundaryTractions(f->dm, f->time, xlocal, flocal, &f->tractions));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_BOUNDARY_TERMS, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* libCEED face operators for the weak form's non-traction boundary terms, when it knows
   every one of them (backflow, the interface's convective term); else PETSc keeps them all */
static PetscErrorCode FacesSetUp(Fluid f)
{
  PetscDS  ds;
  PetscInt nb;
  struct {
    DMLabel         label;
    PetscInt        nv;
    const PetscInt *values;
    PetscBool       backflow;
  } sets[16];
  PetscInt n = 0;

  PetscFunctionBeginUser;
  PetscCall(DMGetDS(f->dm, &ds));
  PetscCall(PetscDSGetNumBoundary(ds, &nb));
  for (PetscInt b = 0; b < nb; ++b) {
    PetscWeakForm           wf;
    DMBoundaryConditionType type;
    DMLabel                 label;
    const char             *name;
    PetscInt                nv, field, n0, n1;
    const PetscInt         *values;
    PetscBool               traction;
    void (**f0)(void), (**f1)(void);

    PetscCall(PetscDSGetBoundary(ds, b, &wf, &type, &name, &label, &nv, &values, &field, NULL, NULL, NULL, NULL, NULL));
    if (type != DM_BC_NATURAL) continue;
    PetscCall(PetscStrncmp(name, FEM_TRACTION_BOUNDARY, sizeof(FEM_TRACTION_BOUNDARY) - 1, &traction));
    if (traction) continue;
    if (field != 0 || nv < 1 || n == 16) PetscFunctionReturn(0);
    for (PetscInt v = 0; v < nv; ++v) {
      PetscCall(PetscWeakFormGetBdResidual(wf, label, values[v], field, 0, &n0, (void *)&f0, &n1, (void *)&f1));
      if (n0 != 1 || n1 != 0 ||
          (f0[0] != (void (*)(void))FluidF0Backflow && f0[0] != (void (*)(void))FluidF0InterfaceConvection))
        PetscFunctionReturn(0);
    }
    PetscCall(PetscWeakFormGetBdResidual(wf, label, values[0], field, 0, &n0, (void *)&f0, &n1, (void *)&f1));
    sets[n].label    = label;
    sets[n].nv       = nv;
    sets[n].values   = values;
    sets[n].backflow = f0[0] == (void (*)(void))FluidF0Backflow ? PETSC_TRUE : PETSC_FALSE;
    ++n;
  }
  for (PetscInt k = 0; k < n; ++k)
    PetscCall(FEMCeedFluidAddFaces(f->ceed, sets[k].label, sets[k].nv, sets[k].values, sets[k].backflow));
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
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_FLUID_RESIDUAL, 0, 0, 0, 0));
  PetscCall(Synchronize(f));
  PetscCall(DMGetLocalVector(f->dm, &flocal));
  PetscCall(FEMCeedFluidResidual(f->ceed, xlocal, f->moving ? f->z_local : NULL, old_mass, PETSC_TRUE, flocal));
  PetscCall(BoundaryTerms(f, xlocal, flocal, NULL));
  PetscCall(FEMLoadsAdd(f->dm, f->dm_loads, xlocal, flocal));
  PetscCall(VecZeroEntries(F));
  PetscCall(DMLocalToGlobal(f->dm, flocal, ADD_VALUES, F));
  PetscCall(DMRestoreLocalVector(f->dm, &flocal));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_FLUID_RESIDUAL, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidVolumeResidualAll(Fluid f, Vec xlocal, PetscBool old_mass, Vec yall)
{
  Vec flocal;

  PetscFunctionBeginUser;
  PetscCall(Synchronize(f));
  PetscCall(DMGetLocalVector(f->dm_all, &flocal));
  PetscCall(FEMCeedFluidResidual(f->ceed, xlocal, f->z_local, old_mass, PETSC_FALSE, flocal));
  PetscCall(FEMLoadsAdd(f->dm, f->dm_loads, xlocal, flocal));
  PetscCall(VecZeroEntries(yall));
  PetscCall(DMLocalToGlobal(f->dm_all, flocal, ADD_VALUES, yall));
  PetscCall(DMRestoreLocalVector(f->dm_all, &flocal));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidCeedAssemble(Fluid f, Vec xlocal, PetscBool old_mass, Mat A)
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
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_FLUID_JACOBIAN, 0, 0, 0, 0));
  PetscCall(FluidCeedAssemble(f, xlocal, old_mass, f->ceed_jacobian));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_FLUID_JACOBIAN, 0, 0, 0, 0));
  /* another matrix of the same pattern (the Dirichlet fluid's) gets a copy; the solver's
     matrix-free operator (-fluid_matfree) the state */
  if (P != f->ceed_jacobian) PetscCall(FEMCeedCopyMatrix(f->ceed_jacobian, P));
  if (J && J == f->matfree_jacobian) PetscCall(FluidMatFreeUpdate(f, xlocal, old_mass));
  else if (J != P && J != f->ceed_jacobian) PetscCall(FEMCeedCopyMatrix(f->ceed_jacobian, J));
  PetscFunctionReturn(0);
}

/* x with its boundary values. PETSc's backend projects them at every call (the reference);
   libCEED's keeps them until the time or the constrained nodes move (the scenes' Dirichlet
   data depend on t and x only), which saves the projection at each residual of a step,
   also while the interface, and with it the mesh, moves */
PetscErrorCode FluidGlobalToLocal(Fluid f, Vec x, Vec xlocal)
{
  PetscFunctionBeginUser;
  if (!f->backend_ceed) {
    PetscCall(FEMGlobalToLocal(f->dm, x, xlocal));
    PetscFunctionReturn(0);
  }
  if (!f->dirichlet_values) PetscCall(FEMDirichletValuesCreate(f->dm, &f->time, &f->dirichlet_values));
  PetscCall(FEMDirichletValuesGlobalToLocal(f->dirichlet_values, x, xlocal));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidSNESResidual(SNES snes, Vec x, Vec F, void *ctx)
{
  Fluid f = (Fluid)ctx;

  PetscFunctionBeginUser;
  (void)snes;
  PetscCall(FluidGlobalToLocal(f, x, f->xlocal_work));
  /* on a moving mesh the time derivative acts through the old domains' mass (fluid_ale.c) */
  PetscCall(FluidOperatorResidual(f, f->xlocal_work, f->moving, F));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidSNESJacobian(SNES snes, Vec x, Mat J, Mat P, void *ctx)
{
  Fluid f = (Fluid)ctx;

  PetscFunctionBeginUser;
  (void)snes;
  PetscCall(FluidGlobalToLocal(f, x, f->xlocal_work));
  if (f->operator_only && J == f->matfree_jacobian) { /* P, the lagged preconditioner's, stays */
    PetscCall(FluidMatFreeUpdate(f, f->xlocal_work, f->moving));
    PetscFunctionReturn(0);
  }
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
  PetscCheck(!f->matfree || backend == FEM_BACKEND_CEED, f->comm, PETSC_ERR_ARG_INCOMP,
             "option -fluid_matfree: needs -fem_backend ceed (the matrix-free operator is libCEED's)");
  if (backend != FEM_BACKEND_CEED && !f->check_backends) PetscFunctionReturn(0);
  PetscCall(DMGetDS(f->dm, &ds));
  PetscCall(PetscDSGetConstants(ds, &n, &constants));
  PetscCall(FEMCeedFluidCreate(f->dm, f->moving ? f->dm_aux : NULL, constants, &f->ceed));
  PetscCall(FacesSetUp(f));
  PetscCall(FEMLoadsCreate(f->dm, f->data.load_value_kernel, f->data.load_stress_kernel, f->moving ? f->z_local : NULL,
                           &f->dm_loads));
  if (backend != FEM_BACKEND_CEED) PetscFunctionReturn(0); /* built for the check only */
  f->backend_ceed = PETSC_TRUE;
  PetscCall(FEMCeedFluidCreateMatrix(f->ceed, &f->ceed_jacobian));
  PetscCall(SNESSetJacobian(f->snes, f->ceed_jacobian, f->ceed_jacobian, NULL, NULL));
  /* the callbacks FluidALESetUp installs on a moving mesh; on a fixed one they replace DMPlex's */
  PetscCall(SNESSetFunction(f->snes, NULL, FluidSNESResidual, f));
  PetscCall(SNESSetJacobian(f->snes, NULL, NULL, FluidSNESJacobian, f));
  PetscCall(FluidMatFreeSetUp(f));
  PetscFunctionReturn(0);
}

/* -fem_backend_check: on a moving mesh with the old domains' mass where both backends have
   it (-fem_backend petsc keeps both) */
static PetscErrorCode CheckResidual(void *ctx, PetscBool ceed, Vec xlocal, Vec F)
{
  Fluid           f       = (Fluid)ctx;
  const PetscBool backend = f->backend_ceed;

  PetscFunctionBeginUser;
  f->backend_ceed = ceed;
  PetscCall(FluidOperatorResidual(f, xlocal, f->moving && f->mass_old_all ? PETSC_TRUE : PETSC_FALSE, F));
  f->backend_ceed = backend;
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckJacobians(void *ctx, Vec xlocal, Mat *petsc, Mat *ceed)
{
  Fluid           f        = (Fluid)ctx;
  const PetscBool old_mass = f->moving && f->mass_old_all ? PETSC_TRUE : PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(DMCreateMatrix(f->dm, petsc));
  PetscCall(DMPlexSNESComputeJacobianFEM(f->dm, xlocal, *petsc, *petsc, NULL));
  if (old_mass) PetscCall(MatAXPY(*petsc, 1.0, f->mass_old, SUBSET_NONZERO_PATTERN));
  PetscCall(FEMCeedFluidCreateMatrix(f->ceed, ceed));
  PetscCall(FluidCeedAssemble(f, xlocal, old_mass, *ceed));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidBackendCheck(Fluid f)
{
  const FEMBackendPair pair = {f->dm, CheckResidual, CheckJacobians, f};

  PetscFunctionBeginUser;
  if (!f->check_backends || f->step > FEM_BACKEND_CHECK_STEPS || f->step == f->backend_checked_step)
    PetscFunctionReturn(0);
  f->backend_checked_step = f->step;
  PetscCall(FEMBackendCheckStep(&pair, "fluid", f->step, f->x, 1.0));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidBackendDestroy(Fluid f)
{
  PetscFunctionBeginUser;
  PetscCall(FEMCeedFluidDestroy(&f->ceed));
  PetscCall(MatDestroy(&f->ceed_jacobian));
  PetscCall(DMDestroy(&f->dm_loads));
  PetscCall(FEMDirichletValuesDestroy(&f->dirichlet_values));
  PetscCall(FEMTractionCacheDestroy(&f->tractions));
  PetscCall(FluidMatFreeDestroy(f));
  PetscFunctionReturn(0);
}
