/* The structure's operators behind one interface: what the time step and
   -fem_backend_check evaluate, the solver's Jacobian too. An implementation fills
   StructureOperatorOps in its create function, listed by name in structure_operator.c's
   backend table: PETSc's pointwise integration (structure_operator_petsc.c, the reference)
   and libCEED's (structure_operator_ceed.c). The solver's operator is built once at set-up
   from -fem_backend and puts its residual and Jacobian on the structure's SNES;
   -fem_backend_check builds the other one beside it and compares the two. */
#ifndef FSIOPT_STRUCTURE_OPERATOR_H
#define FSIOPT_STRUCTURE_OPERATOR_H
#include "structure.h"

typedef struct _n_StructureOperator *StructureOperator;

/* What an operator is built for: the solver (its matrix and callbacks on the structure's
   SNES), or the check beside it */
typedef enum {
  STRUCTURE_OPERATOR_SOLVER,
  STRUCTURE_OPERATOR_CHECK
} StructureOperatorUse;

/* States xlocal are local, with their boundary values; F is global */
typedef struct {
  PetscErrorCode (*residual)(StructureOperator, Vec xlocal, Vec F);
  /* into a new matrix of its own (the solver's keep their values and factors) */
  PetscErrorCode (*jacobian_matrix)(StructureOperator, Vec xlocal, Mat *A);
  PetscErrorCode (*destroy)(StructureOperator);
} StructureOperatorOps;

struct _n_StructureOperator {
  Structure            structure;
  const char          *name;  /* -fem_backend's value */
  const char          *title; /* in messages */
  StructureOperatorOps ops;
  void                *data;         /* the implementation's */
  PetscInt             checked_step; /* -fem_backend_check: the step it was last checked at */
};

/* An implementation: fills op->ops and op->data for the use */
PetscErrorCode StructureOperatorCreate_PETSc(Structure, StructureOperatorUse, StructureOperator);
PetscErrorCode StructureOperatorCreate_Ceed(Structure, StructureOperatorUse, StructureOperator);

PetscErrorCode StructureOperatorCreate(Structure, const char name[], StructureOperatorUse, StructureOperator *);
PetscErrorCode StructureOperatorDestroy(StructureOperator *);
PetscErrorCode StructureOperatorResidual(StructureOperator, Vec xlocal, Vec F);
#endif
