/* The fluid's operators on libCEED (-fem_backend ceed, the default): the volume terms by
   libCEED (src/ceed/ceed_fluid.c) into a matrix of its own COO pattern; the boundary terms
   (scene tractions, backflow, the interface's convective term) by libCEED's face operators
   where it has them all, else by PETSc's integration on their faces only; the scene's volume
   loads, which only manufactured solutions have, by PETSc on a copy of the DM that holds
   nothing else. Moving meshes keep the old domains' weights per quadrature point, not
   matrices. The Dirichlet values of a state are kept until the time or the constrained
   nodes move. */
#include "fluid_impl.h"
#include "fem_ceed.h"
#include "logging.h"

typedef struct {
  FEMCeedFluid       ceed;
  Mat                jacobian;         /* of its COO pattern: the solver's matrix (NULL for the check) */
  DM                 dm_loads;         /* the scene's volume loads alone, NULL without */
  DM                 dm_all;           /* moving meshes: the ALE's copy without constraints */
  Vec                z_local;          /* moving meshes: the mesh velocity */
  PetscReal          coefficients[2];  /* of the old domains (OldDomain) */
  FEMDirichletValues dirichlet_values; /* kept per time and boundary position */
  FEMTractionCache   tractions;        /* the scene's traction terms of a time and mesh */
} OperatorCeed;

/* PETSc's part of the boundary terms: the tractions alone where libCEED has the others */
static PetscErrorCode BoundaryTerms(FluidOperator op, Vec xlocal, Vec flocal, Mat A)
{
  OperatorCeed *c = (OperatorCeed *)op->data;
  Fluid         f = op->fluid;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_BOUNDARY_TERMS, 0, 0, 0, 0));
  if (!FEMCeedFluidHasFaces(c->ceed)) PetscCall(FEMBoundaryTerms(f->dm, f->time, xlocal, flocal, A, &c->tractions));
  else if (flocal) PetscCall(FEMBoundaryTractions(f->dm, f->time, xlocal, flocal, &c->tractions));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_BOUNDARY_TERMS, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* libCEED face operators for the weak form's non-traction boundary terms, when it knows
   every one of them (backflow, the interface's convective term); else PETSc keeps them all */
static PetscErrorCode FacesSetUp(Fluid f, FEMCeedFluid ceed)
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
    PetscCall(FEMCeedFluidAddFaces(ceed, sets[k].label, sets[k].nv, sets[k].values, sets[k].backflow));
  PetscFunctionReturn(0);
}

/* the libCEED context follows the fluid DM's constants */
static PetscErrorCode Synchronize(FluidOperator op)
{
  OperatorCeed      *c = (OperatorCeed *)op->data;
  PetscDS            ds;
  PetscInt           n;
  const PetscScalar *constants;

  PetscFunctionBeginUser;
  PetscCall(DMGetDS(op->fluid->dm, &ds));
  PetscCall(PetscDSGetConstants(ds, &n, &constants));
  PetscCall(FEMCeedFluidSetConstants(c->ceed, constants));
  PetscFunctionReturn(0);
}

/* The scenes' Dirichlet data depend on t and x only: kept, they save the projection at each
   residual of a step, also while the interface, and with it the mesh, moves */
static PetscErrorCode GlobalToLocal(FluidOperator op, Vec x, Vec xlocal)
{
  OperatorCeed *c = (OperatorCeed *)op->data;

  PetscFunctionBeginUser;
  if (!c->dirichlet_values) PetscCall(FEMDirichletValuesCreate(op->fluid->dm, &op->fluid->time, &c->dirichlet_values));
  PetscCall(FEMDirichletValuesGlobalToLocal(c->dirichlet_values, x, xlocal));
  PetscFunctionReturn(0);
}

static PetscErrorCode Residual(FluidOperator op, Vec xlocal, PetscBool old_mass, Vec F)
{
  OperatorCeed *c = (OperatorCeed *)op->data;
  Fluid         f = op->fluid;
  Vec           flocal;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_FLUID_RESIDUAL, 0, 0, 0, 0));
  PetscCall(Synchronize(op));
  PetscCall(DMGetLocalVector(f->dm, &flocal));
  PetscCall(FEMCeedFluidResidual(c->ceed, xlocal, c->z_local, old_mass, PETSC_TRUE, flocal));
  PetscCall(BoundaryTerms(op, xlocal, flocal, NULL));
  PetscCall(FEMLoadsAdd(f->dm, c->dm_loads, xlocal, flocal));
  PetscCall(VecZeroEntries(F));
  PetscCall(DMLocalToGlobal(f->dm, flocal, ADD_VALUES, F));
  PetscCall(DMRestoreLocalVector(f->dm, &flocal));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_FLUID_RESIDUAL, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* the volume blocks and PETSc's boundary terms at xlocal into A, a matrix of the COO pattern */
static PetscErrorCode Assemble(FluidOperator op, Vec xlocal, PetscBool old_mass, Mat A)
{
  OperatorCeed *c = (OperatorCeed *)op->data;

  PetscFunctionBeginUser;
  PetscCall(Synchronize(op));
  PetscCall(FEMCeedFluidJacobian(c->ceed, xlocal, c->z_local, old_mass, A));
  PetscCall(BoundaryTerms(op, xlocal, NULL, A));
  PetscCall(MatAssemblyBegin(A, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(A, MAT_FINAL_ASSEMBLY));
  PetscFunctionReturn(0);
}

/* into the solver's matrix; another matrix of the same pattern (the Dirichlet fluid's) gets a copy */
static PetscErrorCode Jacobian(FluidOperator op, Vec xlocal, PetscBool old_mass, Mat J, Mat P)
{
  OperatorCeed *c = (OperatorCeed *)op->data;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_FLUID_JACOBIAN, 0, 0, 0, 0));
  PetscCall(Assemble(op, xlocal, old_mass, c->jacobian));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_FLUID_JACOBIAN, 0, 0, 0, 0));
  if (P != c->jacobian) PetscCall(FEMCeedCopyMatrix(c->jacobian, P));
  if (J != P && J != c->jacobian) PetscCall(FEMCeedCopyMatrix(c->jacobian, J));
  PetscFunctionReturn(0);
}

static PetscErrorCode JacobianMatrix(FluidOperator op, Vec xlocal, PetscBool old_mass, Mat *A)
{
  OperatorCeed *c = (OperatorCeed *)op->data;

  PetscFunctionBeginUser;
  PetscCall(FEMCeedFluidCreateMatrix(c->ceed, A));
  PetscCall(Assemble(op, xlocal, old_mass, *A));
  PetscFunctionReturn(0);
}

static PetscErrorCode ResidualAll(FluidOperator op, Vec xlocal, PetscBool old_mass, Vec yall)
{
  OperatorCeed *c = (OperatorCeed *)op->data;
  Fluid         f = op->fluid;
  Vec           flocal;

  PetscFunctionBeginUser;
  PetscCall(Synchronize(op));
  PetscCall(DMGetLocalVector(c->dm_all, &flocal));
  PetscCall(FEMCeedFluidResidual(c->ceed, xlocal, c->z_local, old_mass, PETSC_FALSE, flocal));
  PetscCall(FEMLoadsAdd(f->dm, c->dm_loads, xlocal, flocal));
  PetscCall(VecZeroEntries(yall));
  PetscCall(DMLocalToGlobal(c->dm_all, flocal, ADD_VALUES, yall));
  PetscCall(DMRestoreLocalVector(c->dm_all, &flocal));
  PetscFunctionReturn(0);
}

static PetscErrorCode OldDomain(FluidOperator op, PetscInt slot, PetscReal coefficient)
{
  OperatorCeed *c = (OperatorCeed *)op->data;

  PetscFunctionBeginUser;
  PetscCall(FEMCeedFluidMassDomain(c->ceed, c->dm_all, slot));
  c->coefficients[slot] = coefficient;
  PetscFunctionReturn(0);
}

/* the mass of the present weights times xlocal on the ALE copy's global rows (y = or y +=) */
static PetscErrorCode MassMultAll(OperatorCeed *c, Vec xlocal, Vec yall, PetscBool add)
{
  Vec ylocal;

  PetscFunctionBeginUser;
  PetscCall(DMGetLocalVector(c->dm_all, &ylocal));
  PetscCall(FEMCeedFluidMassApply(c->ceed, xlocal, ylocal));
  if (!add) PetscCall(VecZeroEntries(yall));
  PetscCall(DMLocalToGlobal(c->dm_all, ylocal, ADD_VALUES, yall));
  PetscCall(DMRestoreLocalVector(c->dm_all, &ylocal));
  PetscFunctionReturn(0);
}

/* the history's parts with weights of one domain each, then their sum for the step */
static PetscErrorCode OldMassStep(FluidOperator op, PetscBool bdf2, Vec xold, Vec xprevious, Vec history_all)
{
  OperatorCeed   *c     = (OperatorCeed *)op->data;
  const PetscReal old   = c->coefficients[0];
  const PetscReal older = bdf2 ? c->coefficients[1] : 0.0;

  PetscFunctionBeginUser;
  if (history_all) {
    PetscCall(FEMCeedFluidMassWeights(c->ceed, old, 0.0));
    PetscCall(MassMultAll(c, xold, history_all, PETSC_FALSE));
    if (bdf2) {
      PetscCall(FEMCeedFluidMassWeights(c->ceed, 0.0, -older));
      PetscCall(MassMultAll(c, xprevious, history_all, PETSC_TRUE));
    }
  }
  PetscCall(FEMCeedFluidMassWeights(c->ceed, old, bdf2 ? -older : 0.0));
  PetscFunctionReturn(0);
}

static PetscErrorCode ProductSetUp(FluidOperator op, Vec xlocal, PetscBool old_mass)
{
  OperatorCeed *c = (OperatorCeed *)op->data;

  PetscFunctionBeginUser;
  PetscCall(FEMCeedFluidJacobianApplySetUp(c->ceed, xlocal, c->z_local, old_mass));
  PetscFunctionReturn(0);
}

static PetscErrorCode Product(FluidOperator op, PetscBool transpose, Vec xlocal, Vec ylocal)
{
  OperatorCeed *c = (OperatorCeed *)op->data;

  PetscFunctionBeginUser;
  PetscCall(FEMCeedFluidJacobianApply(c->ceed, transpose, xlocal, ylocal));
  PetscFunctionReturn(0);
}

static PetscErrorCode Destroy(FluidOperator op)
{
  OperatorCeed *c = (OperatorCeed *)op->data;

  PetscFunctionBeginUser;
  PetscCall(FEMCeedFluidDestroy(&c->ceed));
  PetscCall(MatDestroy(&c->jacobian));
  PetscCall(DMDestroy(&c->dm_loads));
  PetscCall(FEMDirichletValuesDestroy(&c->dirichlet_values));
  PetscCall(FEMTractionCacheDestroy(&c->tractions));
  PetscCall(PetscFree(op->data));
  PetscFunctionReturn(0);
}

/* The solver's: its matrix and the fluid's callbacks on the SNES, in place of DMPlex's */
PetscErrorCode FluidOperatorCreate_Ceed(Fluid f, FluidOperatorUse use, FluidOperator op)
{
  OperatorCeed      *c;
  PetscDS            ds;
  PetscInt           n;
  const PetscScalar *constants;
  DM                 dm_aux;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&c));
  op->data                = c;
  op->ops.global_to_local = GlobalToLocal;
  op->ops.residual        = Residual;
  op->ops.jacobian        = Jacobian;
  op->ops.jacobian_matrix = JacobianMatrix;
  op->ops.residual_all    = ResidualAll;
  op->ops.old_domain      = OldDomain;
  op->ops.old_mass_step   = OldMassStep;
  op->ops.product_set_up  = ProductSetUp;
  op->ops.product         = Product;
  op->ops.destroy         = Destroy;
  PetscCall(FluidGetMeshVelocity(f, &dm_aux, &c->z_local));
  if (f->moving) PetscCall(FluidALEGetAll(f, &c->dm_all, NULL));
  PetscCall(DMGetDS(f->dm, &ds));
  PetscCall(PetscDSGetConstants(ds, &n, &constants));
  PetscCall(FEMCeedFluidCreate(f->dm, dm_aux, constants, &c->ceed));
  PetscCall(FacesSetUp(f, c->ceed));
  PetscCall(FEMLoadsCreate(f->dm, f->data.load_value_kernel, f->data.load_stress_kernel, c->z_local, &c->dm_loads));
  if (use != FLUID_OPERATOR_SOLVER) PetscFunctionReturn(0);
  PetscCall(FEMCeedFluidCreateMatrix(c->ceed, &c->jacobian));
  PetscCall(SNESSetJacobian(f->snes, c->jacobian, c->jacobian, NULL, NULL));
  PetscCall(FluidSNESUseOperator(f));
  PetscFunctionReturn(0);
}
