/* Expressions in x, y, z and t that a user writes in an options file (a velocity inlet, a
   traction), compiled once by muparser and evaluated where the data are needed: in a
   boundary condition's callback or a pointwise kernel. Syntax: muparser's (+ - * / ^,
   sin cos tan exp log sqrt abs min max, c ? a : b, pi or _pi, _e; x y z t; the symbols given); a vector is its components
   separated by commas, "1e3*(1-cos(2*_pi*t/0.025)), 0". */
#ifndef FSIOPT_EXPRESSION_H
#define FSIOPT_EXPRESSION_H
#include <petscsys.h>

typedef struct _p_Expression *Expression;

/* A function of one argument an expression may call by name: a waveform, flow(t). */
typedef struct {
  const char *name;
  PetscReal (*fn)(void *ctx, PetscReal);
  void *ctx;
} ExpressionFunction;

/* The names an expression may use besides x, y, z, t and muparser's own: functions of one
   argument, and parameters (named numbers: variables to muparser, which does not fold them
   into its constants, so that the arithmetic is done as written). */
typedef struct {
  PetscInt                  nfunctions;
  const ExpressionFunction *functions;
  PetscInt                  nparameters;
  const char *const        *parameter_names;
  double                   *parameter_values; /* they live as long as the expressions */
} ExpressionSymbols;

/* Compiles `text`, which `option` gave, expecting `ncomponents` values, with the symbols it
   may use (NULL: none): a text that does not parse, names an unknown variable or function
   or gives another number of values stops the run with one line naming the option, the
   position and muparser's message. */
PetscErrorCode ExpressionCreate(MPI_Comm, const char option[], const char text[], PetscInt ncomponents,
                                const ExpressionSymbols *, Expression *);
/* The values at (t, x) (dim coordinates; the others 0). */
void           ExpressionEvaluate(Expression, PetscReal t, PetscInt dim, const PetscReal x[], PetscScalar value[]);
PetscErrorCode ExpressionDestroy(Expression *);
#endif
