#ifndef FSIOPT_STRUCTURE_H
#define FSIOPT_STRUCTURE_H
#include "fsiopt.h"
#include "memory_estimate.h"

/* Constants handed to the structure's pointwise kernels; scene kernels read them too.
   MASS is the coefficient of (eta, xi) (c rho_s with c = 1/dt^2 or 4/dt^2); MODEL is a
   StructureModel. */
enum {
  STRUCTURE_RHO,
  STRUCTURE_MU,
  STRUCTURE_LAMBDA,
  STRUCTURE_MASS,
  STRUCTURE_OPERATOR,
  STRUCTURE_LOAD,
  STRUCTURE_TIME,
  STRUCTURE_DT,
  STRUCTURE_PROJECTION,
  STRUCTURE_MODEL,
  STRUCTURE_NUM_CONSTANTS
};
typedef enum {
  STRUCTURE_LINEAR,
  STRUCTURE_SVK
} StructureModel;

typedef struct _p_Structure *Structure;

PetscErrorCode StructureCreate(MPI_Comm, Structure *);
PetscErrorCode StructureSetFromOptions(Structure);
PetscErrorCode StructureSetUp(Structure, DM mesh, const PhysicsData *, PetscReal t0, PetscReal dt);
PetscErrorCode StructureStep(Structure, PetscInt step);
/* The next steps' dt (a retried step's, step_retry.c). */
PetscErrorCode StructureSetTimeStep(Structure, PetscReal dt);
/* The reason the step in progress failed (StepFailure), NULL if it has not. */
PetscErrorCode StructureGetFailure(Structure, const char **reason);

/* Coupled use: R(eta) + load = history, with load = B_s g from the coupling.
   The interface velocity is measured either by the scheme's own velocity
   (etadot^n: seed ch. 3, 6) or by the difference quotient (eta^n - eta^{n-1})/dt
   (seed ch. 4, 5); both are affine in eta^n with slope StructureVelocityCoefficient. */
typedef enum {
  STRUCTURE_VELOCITY_SCHEME,
  STRUCTURE_VELOCITY_DIFFERENCE
} StructureVelocityMeasure;
PetscErrorCode StructureBeginStep(Structure);
PetscErrorCode StructureSolve(Structure, Vec load, PetscInt step);
PetscErrorCode StructureEndStep(Structure);
PetscErrorCode StructureSetInitialLoad(Structure, Vec load); /* B_s g^0, for the midpoint scheme's first step */
PetscErrorCode StructureVelocityLocal(Structure, StructureVelocityMeasure, Vec velocity_local);
PetscReal      StructureVelocityCoefficient(Structure, StructureVelocityMeasure);
PetscErrorCode StructureLinearSolve(Structure, Vec rhs, Vec x, PetscBool transpose);
PetscErrorCode StructureLinearSolveBlock(Structure, Mat rhs, Mat x);
PetscErrorCode StructureGetDM(Structure, DM *);
/* Probes on a structure alone: a vector of the displacement at every owned node (blocks of
   dim) and the coordinates of those nodes that are mesh vertices (others: PETSC_MAX_REAL). */
PetscErrorCode StructureCreateNodeVector(Structure, Vec *, PetscInt *nnodes, PetscReal **coords);
PetscErrorCode StructureGetNodeDisplacement(Structure, Vec);
/* Access to the velocity (all dofs, local) for changing it; Restore updates the ghosts. */
PetscErrorCode StructureGetVelocityLocal(Structure, Vec *);
PetscErrorCode StructureGetDisplacementLocal(Structure, Vec *); /* eta^n with its boundary values; do not modify */
PetscErrorCode StructureRestoreVelocityLocal(Structure, Vec *);
PetscErrorCode StructureErrors(Structure, ErrorTable *);
PetscErrorCode StructureGetCounts(Structure, SolverCounts *);
PetscErrorCode StructureGetInfo(Structure, PetscInt *dim, PetscInt *ndofs);
/* The displacement field StructureSetUp will put on its mesh, for the memory estimate */
PetscErrorCode StructureGetMeshFields(Structure, MeshFields *);
PetscErrorCode StructureCheckpoint(Structure, Checkpoint, PetscBool load); /* checkpoint.h */
/* For a method that solves the coupled system at once: the SNES whose function is R(eta)
   (a step solves R(eta) = history - load), its history and eta^n (global, NULL: not
   asked; read only: StructureSetDisplacement sets it); and the step's state set from
   outside: eta^n (global) and its load (B_s g, NULL: none). */
PetscErrorCode StructureGetNonlinearSystem(Structure, SNES *, Vec *history, Vec *eta);
PetscErrorCode StructureSetDisplacement(Structure, Vec eta, Vec load);
PetscErrorCode StructureDestroy(Structure *);

/* The stress paired with grad xi for the displacement gradient grad_eta (row-major,
   [c*dim+d] = d eta_c / d x_d): sigma(eta) (linear) or the first Piola stress F Sigma
   (St. Venant-Kirchhoff). Scenes use it for manufactured loads. */
void StructureStress(StructureModel, PetscInt dim, PetscReal mu, PetscReal lambda, const PetscScalar grad_eta[],
                     PetscScalar stress[]);
/* The Cauchy stress (3 x 3, row-major; the plane strain's sigma_zz in 2D) of the point's
   material: a pointwise function for FEMNodalAverage (fem.h). */
void StructureCauchyStress(PetscInt, PetscInt, PetscInt, const PetscInt[], const PetscInt[], const PetscScalar[],
                           const PetscScalar[], const PetscScalar[], const PetscInt[], const PetscInt[],
                           const PetscScalar[], const PetscScalar[], const PetscScalar[], PetscReal, const PetscReal[],
                           PetscInt, const PetscScalar[], PetscScalar[]);

/* Pointwise kernels (structure_kernels.c). */
void StructureF0Mass(PetscInt, PetscInt, PetscInt, const PetscInt[], const PetscInt[], const PetscScalar[],
                     const PetscScalar[], const PetscScalar[], const PetscInt[], const PetscInt[], const PetscScalar[],
                     const PetscScalar[], const PetscScalar[], PetscReal, const PetscReal[], PetscInt,
                     const PetscScalar[], PetscScalar[]);
void StructureF1LinearStress(PetscInt, PetscInt, PetscInt, const PetscInt[], const PetscInt[], const PetscScalar[],
                             const PetscScalar[], const PetscScalar[], const PetscInt[], const PetscInt[],
                             const PetscScalar[], const PetscScalar[], const PetscScalar[], PetscReal,
                             const PetscReal[], PetscInt, const PetscScalar[], PetscScalar[]);
void StructureG0Mass(PetscInt, PetscInt, PetscInt, const PetscInt[], const PetscInt[], const PetscScalar[],
                     const PetscScalar[], const PetscScalar[], const PetscInt[], const PetscInt[], const PetscScalar[],
                     const PetscScalar[], const PetscScalar[], PetscReal, PetscReal, const PetscReal[], PetscInt,
                     const PetscScalar[], PetscScalar[]);
void StructureF1SVKStress(PetscInt, PetscInt, PetscInt, const PetscInt[], const PetscInt[], const PetscScalar[],
                          const PetscScalar[], const PetscScalar[], const PetscInt[], const PetscInt[],
                          const PetscScalar[], const PetscScalar[], const PetscScalar[], PetscReal, const PetscReal[],
                          PetscInt, const PetscScalar[], PetscScalar[]);
void StructureG3SVK(PetscInt, PetscInt, PetscInt, const PetscInt[], const PetscInt[], const PetscScalar[],
                    const PetscScalar[], const PetscScalar[], const PetscInt[], const PetscInt[], const PetscScalar[],
                    const PetscScalar[], const PetscScalar[], PetscReal, PetscReal, const PetscReal[], PetscInt,
                    const PetscScalar[], PetscScalar[]);
void StructureG3LinearElasticity(PetscInt, PetscInt, PetscInt, const PetscInt[], const PetscInt[], const PetscScalar[],
                                 const PetscScalar[], const PetscScalar[], const PetscInt[], const PetscInt[],
                                 const PetscScalar[], const PetscScalar[], const PetscScalar[], PetscReal, PetscReal,
                                 const PetscReal[], PetscInt, const PetscScalar[], PetscScalar[]);
#endif
