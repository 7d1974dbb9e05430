/* The structure's operator interface (structure_operator.h): the backend table, the
   methods, and -fem_backend_check, which compares the solver's operator with the other
   backend's at the start of the first steps' solves. */
#include "structure_impl.h"
#include "fem_ceed.h"

/* The backends by -fem_backend's name; the first, PETSc's integration, is the reference the
   check compares another against */
static const struct {
  const char *name, *title;
  PetscErrorCode (*create)(Structure, StructureOperatorUse, StructureOperator);
} backends[] = {
  {"petsc", "PETSc",   StructureOperatorCreate_PETSc},
  {"ceed",  "libCEED", StructureOperatorCreate_Ceed },
};
#define NUM_BACKENDS ((PetscInt)(sizeof(backends) / sizeof(backends[0])))

PetscErrorCode StructureOperatorCreate(Structure s, const char name[], StructureOperatorUse use, StructureOperator *op)
{
  PetscInt  b;
  PetscBool found = PETSC_FALSE;

  PetscFunctionBeginUser;
  for (b = 0; b < NUM_BACKENDS && !found; ++b) PetscCall(PetscStrcmp(name, backends[b].name, &found));
  PetscCheck(found, s->comm, PETSC_ERR_ARG_UNKNOWN_TYPE, "structure: no operator backend %s", name);
  PetscCall(PetscNew(op));
  (*op)->structure = s;
  (*op)->name      = backends[b - 1].name;
  (*op)->title     = backends[b - 1].title;
  PetscCall(backends[b - 1].create(s, use, *op));
  PetscFunctionReturn(0);
}

PetscErrorCode StructureOperatorDestroy(StructureOperator *op)
{
  PetscFunctionBeginUser;
  if (!*op) PetscFunctionReturn(0);
  if ((*op)->ops.destroy) PetscCall((*op)->ops.destroy(*op));
  PetscCall(PetscFree(*op));
  PetscFunctionReturn(0);
}

PetscErrorCode StructureOperatorResidual(StructureOperator op, Vec xlocal, Vec F)
{
  PetscFunctionBeginUser;
  PetscCall(op->ops.residual(op, xlocal, F));
  PetscFunctionReturn(0);
}

PetscErrorCode StructureOperatorsSetUp(Structure s)
{
  const char *name;
  PetscBool   check, reference;

  PetscFunctionBeginUser;
  PetscCall(FEMBackendGetName(&name, &check));
  PetscCall(StructureOperatorCreate(s, name, STRUCTURE_OPERATOR_SOLVER, &s->op));
  if (!check) PetscFunctionReturn(0);
  /* the reference beside any other backend; beside the reference, the next one */
  PetscCall(PetscStrcmp(name, backends[0].name, &reference));
  PetscCall(StructureOperatorCreate(s, backends[reference ? 1 : 0].name, STRUCTURE_OPERATOR_CHECK, &s->check));
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckResidual(void *ctx, Vec xlocal, Vec F)
{
  PetscFunctionBeginUser;
  PetscCall(StructureOperatorResidual((StructureOperator)ctx, xlocal, F));
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckJacobian(void *ctx, Vec xlocal, Mat *A)
{
  StructureOperator op = (StructureOperator)ctx;

  PetscFunctionBeginUser;
  PetscCall(op->ops.jacobian_matrix(op, xlocal, A));
  PetscFunctionReturn(0);
}

PetscErrorCode StructureOperatorsCheck(Structure s, PetscInt step)
{
  PetscBool         reference;
  StructureOperator first, second;

  PetscFunctionBeginUser;
  if (!s->check || step > FEM_BACKEND_CHECK_STEPS || step == s->check->checked_step) PetscFunctionReturn(0);
  s->check->checked_step = step;
  PetscCall(PetscStrcmp(s->op->name, backends[0].name, &reference));
  first  = reference ? s->op : s->check;
  second = reference ? s->check : s->op;
  {
    const FEMBackendPair pair = {.dm              = s->dm,
                                 .residual        = CheckResidual,
                                 .jacobian        = CheckJacobian,
                                 .reference       = first,
                                 .tested          = second,
                                 .reference_title = first->title,
                                 .tested_title    = second->title};
    /* a random state of strains of a percent: St. Venant-Kirchhoff's range */
    PetscCall(FEMBackendCheckStep(&pair, "structure", step, s->eta, 1e-2));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode StructureOperatorsDestroy(Structure s)
{
  PetscFunctionBeginUser;
  PetscCall(StructureOperatorDestroy(&s->op));
  PetscCall(StructureOperatorDestroy(&s->check));
  PetscFunctionReturn(0);
}
