#ifndef FSIOPT_FEM_H
#define FSIOPT_FEM_H
#include "fsiopt.h"

/* The pieces the fluid and structure solvers share: fields, boundary data, residual
   evaluation on a given state, counted Jacobians and error norms. */

PetscErrorCode FEMCreateField(DM dm, PetscInt field, const char name[], PetscInt Nc, PetscInt degree, PetscFE quadrature_from);
/* Registers the essential and natural boundaries of `data` on field `field`.
   `datums` must live as long as the DM; `time` is the solver's current time. */
PetscErrorCode FEMAddBoundaries(DM dm, PetscInt field, const PhysicsData *data, DirichletDatum datums[], const PetscReal *time);
/* Residual of the DM's weak form at the local state xlocal (boundary values already in it). */
PetscErrorCode FEMResidual(DM dm, Vec xlocal, Vec fglobal);
/* Global state to local state with the boundary values of the current time. */
PetscErrorCode FEMGlobalToLocal(DM dm, Vec xglobal, Vec xlocal);
/* The SNES of one subproblem: boundary insertion at the solver's time, a Jacobian that
   counts its assemblies (= LU factorizations), MUMPS LU by default, and with
   `constant_jacobian` one linear solve per step on a matrix factored once per run.
   Options under `prefix` override all of it. */
PetscErrorCode FEMCreateSNES(DM dm, const char prefix[], PetscBool constant_jacobian, PetscInt *jacobian_assemblies, SNES *snes);
/* Per field: L2 error and L2 error of the gradient against closed forms at time t
   (a NULL closed form gives 0; h1 may be NULL). At most two fields. */
PetscErrorCode FEMErrors(DM dm, Vec xglobal, PetscReal t, const FieldFn exact[], const GradientFn gradient[], PetscReal l2[], PetscReal h1[]);
#endif
