/* The fluid's operators behind one interface: what the solver, the time step, the body force
   and -fem_backend_check evaluate. An implementation fills FluidOperatorOps in its create
   function, listed by name in fluid_operator.c's backend table: PETSc's pointwise
   integration (fluid_operator_petsc.c, the reference) and libCEED's (fluid_operator_ceed.c).
   The solver's operator is built once at set-up from -fem_backend; -fem_backend_check builds
   the other one beside it and compares the two. */
#ifndef FSIOPT_FLUID_OPERATOR_H
#define FSIOPT_FLUID_OPERATOR_H
#include "fluid.h"

typedef struct _n_FluidOperator *FluidOperator;

/* What an operator is built for: the solver (its matrices and callbacks on the fluid's SNES),
   the check beside it, or the initial projection on a moving mesh (no step yet: no
   old-domain mass) */
typedef enum {
  FLUID_OPERATOR_SOLVER,
  FLUID_OPERATOR_CHECK,
  FLUID_OPERATOR_PROJECTION
} FluidOperatorUse;

/* States xlocal are local, with their boundary values; F is global; old_mass adds the old
   domains' mass term of a moving mesh (fluid_ale.c). Methods a backend lacks stay NULL. */
typedef struct {
  /* x with the boundary values of the fluid's time */
  PetscErrorCode (*global_to_local)(FluidOperator, Vec x, Vec xlocal);
  PetscErrorCode (*residual)(FluidOperator, Vec xlocal, PetscBool old_mass, Vec F);
  /* into the solver's matrices */
  PetscErrorCode (*jacobian)(FluidOperator, Vec xlocal, PetscBool old_mass, Mat J, Mat P);
  /* into a new matrix of its own (the solver's keep their values and factors) */
  PetscErrorCode (*jacobian_matrix)(FluidOperator, Vec xlocal, PetscBool old_mass, Mat *A);
  /* moving meshes: the volume terms alone on every row of the ALE's copy of the DM without
     constraints, a global vector of it (the body force) */
  PetscErrorCode (*residual_all)(FluidOperator, Vec xlocal, PetscBool old_mass, Vec yall);
  /* moving meshes, as a step begins: the old domain `slot` (0: Omega^{n-1}, 1: Omega^{n-2},
     BDF2) at the present coordinates of that copy, with its coefficient; then the step's
     mass (BDF2: the first less the second) and, when history_all is not NULL, the history
     term M(Omega^{n-1}) xold [- M(Omega^{n-2}) xprevious] into it */
  PetscErrorCode (*old_domain)(FluidOperator, PetscInt slot, PetscReal coefficient);
  PetscErrorCode (*old_mass_step)(FluidOperator, PetscBool bdf2, Vec xold, Vec xprevious, Vec history_all);
  /* the volume Jacobian without a matrix (-fluid_matfree): its state, then ylocal = J xlocal
     or J^T xlocal */
  PetscErrorCode (*product_set_up)(FluidOperator, Vec xlocal, PetscBool old_mass);
  PetscErrorCode (*product)(FluidOperator, PetscBool transpose, Vec xlocal, Vec ylocal);
  PetscErrorCode (*destroy)(FluidOperator);
} FluidOperatorOps;

struct _n_FluidOperator {
  Fluid            fluid;
  const char      *name;  /* -fem_backend's value */
  const char      *title; /* in messages */
  FluidOperatorOps ops;
  void            *data;         /* the implementation's */
  PetscInt         checked_step; /* -fem_backend_check: the step it was last checked at */
};

/* An implementation: fills op->ops and op->data for the use */
PetscErrorCode FluidOperatorCreate_PETSc(Fluid, FluidOperatorUse, FluidOperator);
PetscErrorCode FluidOperatorCreate_Ceed(Fluid, FluidOperatorUse, FluidOperator);

/* The operator of the backend `name` in the table */
PetscErrorCode FluidOperatorCreate(Fluid, const char name[], FluidOperatorUse, FluidOperator *);
PetscErrorCode FluidOperatorDestroy(FluidOperator *);
/* The methods; on a NULL operator (no check) old_domain and old_mass_step do nothing */
PetscErrorCode FluidOperatorResidual(FluidOperator, Vec xlocal, PetscBool old_mass, Vec F);
PetscErrorCode FluidOperatorJacobianMatrix(FluidOperator, Vec xlocal, PetscBool old_mass, Mat *A);
PetscErrorCode FluidOperatorResidualAll(FluidOperator, Vec xlocal, PetscBool old_mass, Vec yall);
PetscErrorCode FluidOperatorOldDomain(FluidOperator, PetscInt slot, PetscReal coefficient);
PetscErrorCode FluidOperatorOldMassStep(FluidOperator, PetscBool bdf2, Vec xold, Vec xprevious, Vec history_all);
PetscErrorCode FluidOperatorProductSetUp(FluidOperator, Vec xlocal, PetscBool old_mass);
PetscErrorCode FluidOperatorProduct(FluidOperator, PetscBool transpose, Vec xlocal, Vec ylocal);
#endif
