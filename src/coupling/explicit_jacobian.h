#ifndef FSIOPT_EXPLICIT_JACOBIAN_H
#define FSIOPT_EXPLICIT_JACOBIAN_H
#include <petscksp.h>

/* A preconditioner for CG on the Gauss-Newton normal equations J^T J d = -J^T F: the
   inverse (J0^T J0)^{-1} = J0^{-1} J0^{-T} of an explicitly built Jacobian J0 (one
   sensitivity product per control, `block` of them per multi-right-hand-side solve; a
   dense LU on every rank). J changes little from step
   to step, so J0 from an earlier step leaves CG a handful of iterations. */
typedef struct _p_ExplicitJacobian *ExplicitJacobian;

PetscErrorCode ExplicitJacobianCreate(Mat J, PetscInt block, KSP ksp, ExplicitJacobian *);
PetscErrorCode ExplicitJacobianRequestRebuild(ExplicitJacobian);
PetscErrorCode ExplicitJacobianDestroy(ExplicitJacobian *);
#endif
