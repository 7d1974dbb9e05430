#ifndef FSIOPT_EXPLICIT_JACOBIAN_H
#define FSIOPT_EXPLICIT_JACOBIAN_H
#include <petscksp.h>

/* A preconditioner from an explicitly built Jacobian J0 (one sensitivity product per
   control, `block` of them per multi-right-hand-side solve; a dense LU on every rank):
   for CG on the Gauss-Newton normal equations J^T J d = -J^T F (normal_equations) the
   inverse (J0^T J0)^{-1} = J0^{-1} J0^{-T}, for a Krylov method on J d = -F itself J0^{-1}.
   J changes little from step to step, so J0 from an earlier step leaves the Krylov method
   a handful of iterations. */
typedef struct _p_ExplicitJacobian *ExplicitJacobian;

PetscErrorCode ExplicitJacobianCreate(Mat J, PetscInt block, PetscBool normal_equations, KSP ksp, ExplicitJacobian *);
/* J0 sparse, by probing with the colouring and pattern of `probing` (coupling.h), which it
   takes over; its products' iterative subproblem solves to the relative tolerance build_rtol */
typedef struct _p_InterfaceProbing *InterfaceProbing;
PetscErrorCode ExplicitJacobianSetProbing(ExplicitJacobian, InterfaceProbing probing, PetscReal build_rtol);
/* x = J0^{-1} b with the J0 in hand; solved is false when none has been built */
PetscErrorCode ExplicitJacobianSolve(ExplicitJacobian, Vec b, Vec x, PetscBool *solved);
/* For J d = -F (not the normal equations): correct the inverse by a Broyden secant update
   from a step s and the change y of F it caused (at most `max_secants`, then they start again from J0;
   0: none, the default) */
PetscErrorCode ExplicitJacobianSetSecants(ExplicitJacobian, PetscInt max_secants);
PetscErrorCode ExplicitJacobianSecantUpdate(ExplicitJacobian, Vec s, Vec y);
PetscErrorCode ExplicitJacobianGetBuilds(ExplicitJacobian, PetscInt *builds);
PetscErrorCode ExplicitJacobianRequestRebuild(ExplicitJacobian);
PetscErrorCode ExplicitJacobianForget(ExplicitJacobian);
PetscErrorCode ExplicitJacobianDestroy(ExplicitJacobian *);
#endif
