/* The fluid's operator interface (fluid_operator.h): the backend table, the methods, the
   SNES callbacks that evaluate through the solver's operator, and -fem_backend_check, which
   compares the solver's operator with the other backend's at the start of the first steps. */
#include "fluid_impl.h"
#include "fem_ceed.h"

/* The backends by -fem_backend's name; the first, PETSc's integration, is the reference the
   check compares another against */
static const struct {
  const char *name, *title;
  PetscErrorCode (*create)(Fluid, FluidOperatorUse, FluidOperator);
} backends[] = {
  {"petsc", "PETSc",   FluidOperatorCreate_PETSc},
  {"ceed",  "libCEED", FluidOperatorCreate_Ceed },
};
#define NUM_BACKENDS ((PetscInt)(sizeof(backends) / sizeof(backends[0])))

PetscErrorCode FluidOperatorCreate(Fluid f, const char name[], FluidOperatorUse use, FluidOperator *op)
{
  PetscInt  b;
  PetscBool found = PETSC_FALSE;

  PetscFunctionBeginUser;
  for (b = 0; b < NUM_BACKENDS && !found; ++b) PetscCall(PetscStrcmp(name, backends[b].name, &found));
  PetscCheck(found, f->comm, PETSC_ERR_ARG_UNKNOWN_TYPE, "fluid: no operator backend %s", name);
  PetscCall(PetscNew(op));
  (*op)->fluid = f;
  (*op)->name  = backends[b - 1].name;
  (*op)->title = backends[b - 1].title;
  PetscCall(backends[b - 1].create(f, use, *op));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidOperatorDestroy(FluidOperator *op)
{
  PetscFunctionBeginUser;
  if (!*op) PetscFunctionReturn(0);
  if ((*op)->ops.destroy) PetscCall((*op)->ops.destroy(*op));
  PetscCall(PetscFree(*op));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidOperatorResidual(FluidOperator op, Vec xlocal, PetscBool old_mass, Vec F)
{
  PetscFunctionBeginUser;
  PetscCall(op->ops.residual(op, xlocal, old_mass, F));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidOperatorJacobianMatrix(FluidOperator op, Vec xlocal, PetscBool old_mass, Mat *A)
{
  PetscFunctionBeginUser;
  PetscCall(op->ops.jacobian_matrix(op, xlocal, old_mass, A));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidOperatorResidualAll(FluidOperator op, Vec xlocal, PetscBool old_mass, Vec yall)
{
  PetscFunctionBeginUser;
  PetscCall(op->ops.residual_all(op, xlocal, old_mass, yall));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidOperatorOldDomain(FluidOperator op, PetscInt slot, PetscReal coefficient)
{
  PetscFunctionBeginUser;
  if (op) PetscCall(op->ops.old_domain(op, slot, coefficient));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidOperatorOldMassStep(FluidOperator op, PetscBool bdf2, Vec xold, Vec xprevious, Vec history_all)
{
  PetscFunctionBeginUser;
  if (op) PetscCall(op->ops.old_mass_step(op, bdf2, xold, xprevious, history_all));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidOperatorProductSetUp(FluidOperator op, Vec xlocal, PetscBool old_mass)
{
  PetscFunctionBeginUser;
  PetscCall(op->ops.product_set_up(op, xlocal, old_mass));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidOperatorProduct(FluidOperator op, PetscBool transpose, Vec xlocal, Vec ylocal)
{
  PetscFunctionBeginUser;
  PetscCall(op->ops.product(op, transpose, xlocal, ylocal));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidGlobalToLocal(Fluid f, Vec x, Vec xlocal)
{
  PetscFunctionBeginUser;
  PetscCall(f->op->ops.global_to_local(f->op, x, xlocal));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidSNESResidual(SNES snes, Vec x, Vec F, void *ctx)
{
  Fluid f = (Fluid)ctx;

  PetscFunctionBeginUser;
  (void)snes;
  PetscCall(FluidGlobalToLocal(f, x, f->xlocal_work));
  PetscCall(FluidOutletsSetIterate(f, f->xlocal_work));
  /* on a moving mesh the time derivative acts through the old domains' mass (fluid_ale.c) */
  PetscCall(FluidOperatorResidual(f->op, f->xlocal_work, f->moving, F));
  PetscFunctionReturn(0);
}

/* With -fluid_matfree J is the shell operator: P, the assembled matrix, is the operator's
   Jacobian, and J follows its state */
PetscErrorCode FluidSNESJacobian(SNES snes, Vec x, Mat J, Mat P, void *ctx)
{
  Fluid           f       = (Fluid)ctx;
  const PetscBool matfree = FluidMatFreeIsOperator(f->matfree, J);
  FluidOperator   op      = f->op;

  PetscFunctionBeginUser;
  (void)snes;
  PetscCall(FluidGlobalToLocal(f, x, f->xlocal_work));
  if (FluidMatFreeOperatorOnly(f->matfree, J)) { /* P, the lagged preconditioner's, stays */
    PetscCall(FluidMatFreeUpdate(f, f->xlocal_work, f->moving));
    PetscFunctionReturn(0);
  }
  PetscCall(op->ops.jacobian(op, f->xlocal_work, f->moving, matfree ? P : J, P));
  PetscCall(FluidOutletsAddJacobian(f, f->xlocal_work, P, J != P && !matfree ? J : NULL));
  if (matfree) PetscCall(FluidMatFreeUpdate(f, f->xlocal_work, f->moving));
  f->counts.factorizations++;
  PetscFunctionReturn(0);
}

PetscErrorCode FluidSNESUseOperator(Fluid f)
{
  PetscFunctionBeginUser;
  PetscCall(SNESSetFunction(f->snes, NULL, FluidSNESResidual, f));
  PetscCall(SNESSetJacobian(f->snes, NULL, NULL, FluidSNESJacobian, f));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidOperatorsSetUp(Fluid f)
{
  const char *name;
  PetscBool   check, reference;

  PetscFunctionBeginUser;
  PetscCall(FEMBackendGetName(&name, &check));
  PetscCall(FluidOperatorCreate(f, name, FLUID_OPERATOR_SOLVER, &f->op));
  PetscCheck(!f->use_matfree || f->op->ops.product, f->comm, PETSC_ERR_ARG_INCOMP,
             "option -fluid_matfree: needs -fem_backend ceed (the matrix-free operator is libCEED's)");
  if (f->use_matfree) PetscCall(FluidMatFreeCreate(f, &f->matfree));
  if (!check) PetscFunctionReturn(0);
  /* the reference beside any other backend; beside the reference, the next one */
  PetscCall(PetscStrcmp(name, backends[0].name, &reference));
  PetscCall(FluidOperatorCreate(f, backends[reference ? 1 : 0].name, FLUID_OPERATOR_CHECK, &f->check));
  PetscFunctionReturn(0);
}

/* -fem_backend_check: on a moving mesh with the old domains' mass */
static PetscErrorCode CheckResidual(void *ctx, Vec xlocal, Vec F)
{
  FluidOperator op = (FluidOperator)ctx;

  PetscFunctionBeginUser;
  PetscCall(FluidOperatorResidual(op, xlocal, op->fluid->moving, F));
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckJacobian(void *ctx, Vec xlocal, Mat *A)
{
  FluidOperator op = (FluidOperator)ctx;

  PetscFunctionBeginUser;
  PetscCall(FluidOperatorJacobianMatrix(op, xlocal, op->fluid->moving, A));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidOperatorsCheck(Fluid f)
{
  PetscBool     reference;
  FluidOperator first, second;

  PetscFunctionBeginUser;
  if (!f->check || f->step > FEM_BACKEND_CHECK_STEPS || f->step == f->check->checked_step) PetscFunctionReturn(0);
  f->check->checked_step = f->step;
  PetscCall(PetscStrcmp(f->op->name, backends[0].name, &reference));
  first  = reference ? f->op : f->check;
  second = reference ? f->check : f->op;
  {
    const FEMBackendPair pair = {.dm              = f->dm,
                                 .residual        = CheckResidual,
                                 .jacobian        = CheckJacobian,
                                 .reference       = first,
                                 .tested          = second,
                                 .reference_title = first->title,
                                 .tested_title    = second->title};
    PetscCall(FEMBackendCheckStep(&pair, "fluid", f->step, f->x, 1.0));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FluidOperatorsDestroy(Fluid f)
{
  PetscFunctionBeginUser;
  PetscCall(FluidMatFreeDestroy(&f->matfree));
  PetscCall(FluidOperatorDestroy(&f->op));
  PetscCall(FluidOperatorDestroy(&f->check));
  PetscFunctionReturn(0);
}
