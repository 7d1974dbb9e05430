/* Expressions in x, y, z and t that a user writes in an options file (a velocity inlet, a
   traction), compiled once by muparser and evaluated where the data are needed: in a
   boundary condition's callback or a pointwise kernel. Syntax: muparser's (+ - * / ^,
   sin cos tan exp log sqrt abs min max, c ? a : b, pi or _pi, _e; x y z t); a vector is its components
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

/* Compiles `text`, which `option` gave, expecting `ncomponents` values, with the nfunctions
   functions it may call: a text that does not parse, names an unknown variable or function
   or gives another number of values stops the run with one line naming the option, the
   position and muparser's message. */
PetscErrorCode ExpressionCreate(MPI_Comm, const char option[], const char text[], PetscInt ncomponents,
                                PetscInt nfunctions, const ExpressionFunction functions[], Expression *);
/* The values at (t, x) (dim coordinates; the others 0). */
void           ExpressionEvaluate(Expression, PetscReal t, PetscInt dim, const PetscReal x[], PetscScalar value[]);
PetscErrorCode ExpressionDestroy(Expression *);
#endif
