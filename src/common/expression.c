/* Expressions in x, y, z, t (expression.h) on muparser's C interface: a parser per
   expression, its variables bound to the expression's own x, y, z, t. */
#include <muParserDLL.h>
#include "expression.h"

struct _p_Expression {
  muParserHandle_t parser;
  PetscInt         ncomponents;
  double           x, y, z, t;
};

PetscErrorCode ExpressionCreate(MPI_Comm comm, const char option[], const char text[], PetscInt ncomponents,
                                const ExpressionSymbols *symbols, Expression *expression)
{
  Expression e;
  int        n = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&e));
  e->ncomponents = ncomponents;
  e->parser      = mupCreate(muBASETYPE_FLOAT);
  mupDefineVar(e->parser, "x", &e->x);
  mupDefineVar(e->parser, "y", &e->y);
  mupDefineVar(e->parser, "z", &e->z);
  mupDefineVar(e->parser, "t", &e->t);
  /* muparser's own _pi and _e have 13 digits: an inlet pulse off by 7e-13 */
  mupDefineConst(e->parser, "_pi", PETSC_PI);
  mupDefineConst(e->parser, "pi", PETSC_PI);
  mupDefineConst(e->parser, "_e", PetscExpReal(1.0));
  for (PetscInt f = 0; symbols && f < symbols->nfunctions; ++f)
    mupDefineFunUserData1(e->parser, symbols->functions[f].name, symbols->functions[f].fn, symbols->functions[f].ctx,
                          0 /* not constant */);
  for (PetscInt p = 0; symbols && p < symbols->nparameters; ++p)
    mupDefineVar(e->parser, symbols->parameter_names[p], &symbols->parameter_values[p]);
  mupSetExpr(e->parser, text);
  if (!mupError(e->parser)) (void)mupEvalMulti(e->parser, &n); /* muparser compiles at the first evaluation */
  if (mupError(e->parser)) {
    char      message[256];
    const int position = (int)mupGetErrorPos(e->parser);
    PetscCall(PetscStrncpy(message, mupGetErrorMsg(e->parser), sizeof(message)));
    mupRelease(e->parser);
    PetscCall(PetscFree(e));
    SETERRQ(comm, PETSC_ERR_ARG_WRONG, "option %s: the expression \"%s\" does not parse at position %d: %s", option,
            text, position, message);
  }
  if (n != ncomponents) {
    mupRelease(e->parser);
    PetscCall(PetscFree(e));
    SETERRQ(comm, PETSC_ERR_ARG_WRONG,
            "option %s: the expression \"%s\" gives %d value%s; expected %" PetscInt_FMT " (components separated by "
            "commas)",
            option, text, n, n == 1 ? "" : "s", ncomponents);
  }
  *expression = e;
  PetscFunctionReturn(0);
}

void ExpressionEvaluate(Expression e, PetscReal t, PetscInt dim, const PetscReal x[], PetscScalar value[])
{
  const double *v;
  int           n;

  e->t = t;
  e->x = x[0];
  e->y = dim > 1 ? x[1] : 0;
  e->z = dim > 2 ? x[2] : 0;
  v    = mupEvalMulti(e->parser, &n);
  for (PetscInt c = 0; c < e->ncomponents; ++c) value[c] = v[c];
}

PetscErrorCode ExpressionDestroy(Expression *expression)
{
  PetscFunctionBeginUser;
  if (!*expression) PetscFunctionReturn(0);
  mupRelease((*expression)->parser);
  PetscCall(PetscFree(*expression));
  PetscFunctionReturn(0);
}
