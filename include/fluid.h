/* The fluid subproblem: ALE Navier-Stokes (or Stokes) in (Q2,Q1) or (P2,P1) Taylor-Hood,
   backward Euler or BDF2, solved with a traction (the control) on the interface as its
   Neumann datum, and its linearized and adjoint solves for the coupling's products. */
#ifndef FSIOPT_FLUID_H
#define FSIOPT_FLUID_H
#include "fsiopt.h"
#include "memory_estimate.h"
#include "fluid_constants.h"

typedef struct _p_Fluid *Fluid;

PetscErrorCode FluidCreate(MPI_Comm, Fluid *);
PetscErrorCode FluidSetFromOptions(Fluid);
PetscErrorCode FluidSetUp(Fluid, DM mesh, const PhysicsData *, PetscReal t0, PetscReal dt);
PetscErrorCode FluidStep(Fluid, PetscInt step);
/* The next steps' dt (a retried step's, step_retry.c). */
PetscErrorCode FluidSetTimeStep(Fluid, PetscReal dt);
/* The reason the step in progress failed (StepFailure), NULL if it has not. */
PetscErrorCode FluidGetFailure(Fluid, const char **reason);

/* Coupled use. FluidSetInterface (before FluidSetUp) names the interface face set and
   whether the residual carries the convective boundary term the control absorbs
   (-1/2 rho ((u.n) u, v) there). A coupled Navier-Stokes fluid recomputes and factors
   its Jacobian only when asked (FluidUpdateJacobian); its nonlinear solves reuse the
   factorization in hand. */
PetscErrorCode FluidSetInterface(Fluid, PetscInt face, PetscBool convective_term);
PetscErrorCode FluidBeginStep(Fluid, PetscInt step);       /* old-domain term, t += dt */
PetscErrorCode FluidSolve(Fluid, Vec load, PetscInt step); /* R(x) = history + load */
/* A = dR/dx at the current state, factored; or, reuse_preconditioner (Krylov solvers), the
   preconditioner of the last full update kept for it */
PetscErrorCode FluidUpdateJacobian(Fluid, PetscBool reuse_preconditioner);
PetscErrorCode FluidSolverIsKrylov(Fluid, PetscBool *krylov);
PetscErrorCode FluidLinearSolve(Fluid, Vec rhs, Vec x, PetscBool transpose); /* with the factors in hand */
PetscErrorCode FluidLinearSolveBlock(Fluid, Mat rhs, Mat x);                 /* dense columns, forward */
PetscErrorCode FluidLinearSolveGuess(Fluid, Vec rhs, Vec x); /* forward, a first guess's accuracy */
/* Dirichlet-Neumann use: solves with the interface rows (global indices) set to `values`
   (a global vector; only those rows are read) and returns the reaction R(x) - history on
   those rows (0 elsewhere): the load a traction-controlled fluid would need there. */
PetscErrorCode FluidSetUpDirichlet(Fluid, IS rows); /* its solver and options (-fluid_dirichlet_) */
PetscErrorCode FluidSolveDirichlet(Fluid, IS rows, Vec values, Vec reaction, PetscInt step);
/* For a method that solves the coupled system at once: the SNES whose function is R(x) (a
   step solves R(x) = history + load) and its history; FluidGetSolution's x is the state. */
PetscErrorCode FluidGetNonlinearSystem(Fluid, SNES *, Vec *history);
PetscErrorCode FluidGetDM(Fluid, DM *);
PetscErrorCode FluidGetSolution(Fluid, Vec *);
PetscErrorCode FluidGlobalToLocal(Fluid, Vec x, Vec xlocal); /* with the Dirichlet values of the fluid's time */
PetscErrorCode FluidGetTime(Fluid, PetscReal *);

/* Moving meshes (fluid_ale.c). Displacements are local vectors in the coordinate layout
   (vertex values), relative to the reference mesh. */
PetscErrorCode FluidEnableMeshMotion(Fluid); /* before FluidSetUp */
/* The fields FluidSetUp will put on its mesh (after FluidSetFromOptions), for the memory
   estimate: velocity, pressure and, on a moving mesh, its displacement */
PetscErrorCode FluidGetMeshFields(Fluid, MeshFields *);
PetscErrorCode FluidSetMeshDisplacement(Fluid, Vec displacement);
PetscErrorCode FluidGetMeshDisplacement(Fluid, Vec *displacement);
/* the mesh velocity of the last step, a local vector of its own DM (NULL, NULL: fixed mesh) */
PetscErrorCode FluidGetMeshVelocity(Fluid, DM *, Vec *local);
PetscErrorCode FluidErrors(Fluid, ErrorTable *);
PetscErrorCode FluidGetCounts(Fluid, SolverCounts *);
/* moving meshes: the smallest ratio of a cell corner's area (3D: volume) to its reference
   one over the meshes the steps ended on, and the time of that mesh; -1, -1 otherwise */
PetscErrorCode FluidGetMeshQuality(Fluid, PetscReal *worst_ratio, PetscReal *time);
PetscErrorCode FluidGetInfo(Fluid, PetscInt *dim, PetscInt *ndofs);
/* The force of the fluid on the scene's body faces (PhysicsData.force_faces) at the current
   state, on every fluid rank (fluid_forces.c). */
PetscErrorCode FluidBodyForce(Fluid, PetscReal force[3]);
/* The same force as the boundary integral of sigma n of the discrete solution (a check on
   the volume-weighted form; fluid_face_integrals.c). */
PetscErrorCode FluidBodyForceSurface(Fluid, PetscReal force[3]);
/* Integrals over face sets of the current state, n the fluid's outward normal: the area
   (2D: the length), the flow rate int u.n (out of the fluid), int p, the force
   -int sigma n of the fluid on what lies beyond, and int |tau_w| of the wall shear stress
   tau_w = t - (t.n) n, t = sigma n (fluid_face_integrals.c); collective. */
typedef struct {
  PetscReal area, flow_rate, pressure, force[3], shear;
} FluidFaceIntegral;
PetscErrorCode FluidFaceSetIntegral(Fluid, PetscInt n, const PetscInt values[], FluidFaceIntegral *);
/* Integrals over the region `region` ("Cell Sets"; -1: every cell) of the current state: its
   volume (2D: area), int p and the kinetic energy int rho |u|^2 / 2 (fluid_region_integrals.c);
   collective. */
typedef struct {
  PetscReal volume, pressure, kinetic;
} FluidRegionIntegrals;
PetscErrorCode FluidRegionIntegral(Fluid, PetscInt region, FluidRegionIntegrals *);
/* The 0D outlets' (PhysicsData.outlets) flow rate and pressure at the current state; the
   boundary kernel of outlet k, for its face set's traction slot (fluid_outlets.c). */
PetscErrorCode   FluidGetOutletState(Fluid, PetscReal q[], PetscReal p[]);
BdResidualKernel FluidOutletKernel(PetscInt k);
/* The scene's data the fluid was set up with */
PetscErrorCode FluidGetData(Fluid, const PhysicsData **);
/* Saves or loads the state the next step needs (checkpoint.h); either way the next
   coupled step refactors the Jacobian. */
PetscErrorCode FluidCheckpoint(Fluid, Checkpoint, PetscBool load);
PetscErrorCode FluidDestroy(Fluid *);

/* Pointwise kernels (fluid_kernels.c). */
void FluidF0Backflow(PetscInt, PetscInt, PetscInt, const PetscInt[], const PetscInt[], const PetscScalar[],
                     const PetscScalar[], const PetscScalar[], const PetscInt[], const PetscInt[], const PetscScalar[],
                     const PetscScalar[], const PetscScalar[], PetscReal, const PetscReal[], const PetscReal[],
                     PetscInt, const PetscScalar[], PetscScalar[]);
void FluidG0Backflow(PetscInt, PetscInt, PetscInt, const PetscInt[], const PetscInt[], const PetscScalar[],
                     const PetscScalar[], const PetscScalar[], const PetscInt[], const PetscInt[], const PetscScalar[],
                     const PetscScalar[], const PetscScalar[], PetscReal, PetscReal, const PetscReal[],
                     const PetscReal[], PetscInt, const PetscScalar[], PetscScalar[]);
void FluidF0InterfaceConvection(PetscInt, PetscInt, PetscInt, const PetscInt[], const PetscInt[], const PetscScalar[],
                                const PetscScalar[], const PetscScalar[], const PetscInt[], const PetscInt[],
                                const PetscScalar[], const PetscScalar[], const PetscScalar[], PetscReal,
                                const PetscReal[], const PetscReal[], PetscInt, const PetscScalar[], PetscScalar[]);
void FluidG0InterfaceConvection(PetscInt, PetscInt, PetscInt, const PetscInt[], const PetscInt[], const PetscScalar[],
                                const PetscScalar[], const PetscScalar[], const PetscInt[], const PetscInt[],
                                const PetscScalar[], const PetscScalar[], const PetscScalar[], PetscReal, PetscReal,
                                const PetscReal[], const PetscReal[], PetscInt, const PetscScalar[], PetscScalar[]);
void FluidF0MassStokes(PetscInt, PetscInt, PetscInt, const PetscInt[], const PetscInt[], const PetscScalar[],
                       const PetscScalar[], const PetscScalar[], const PetscInt[], const PetscInt[],
                       const PetscScalar[], const PetscScalar[], const PetscScalar[], PetscReal, const PetscReal[],
                       PetscInt, const PetscScalar[], PetscScalar[]);
void FluidF0MassConvection(PetscInt, PetscInt, PetscInt, const PetscInt[], const PetscInt[], const PetscScalar[],
                           const PetscScalar[], const PetscScalar[], const PetscInt[], const PetscInt[],
                           const PetscScalar[], const PetscScalar[], const PetscScalar[], PetscReal, const PetscReal[],
                           PetscInt, const PetscScalar[], PetscScalar[]);
void FluidF1Stress(PetscInt, PetscInt, PetscInt, const PetscInt[], const PetscInt[], const PetscScalar[],
                   const PetscScalar[], const PetscScalar[], const PetscInt[], const PetscInt[], const PetscScalar[],
                   const PetscScalar[], const PetscScalar[], PetscReal, const PetscReal[], PetscInt,
                   const PetscScalar[], PetscScalar[]);
void FluidF0Continuity(PetscInt, PetscInt, PetscInt, const PetscInt[], const PetscInt[], const PetscScalar[],
                       const PetscScalar[], const PetscScalar[], const PetscInt[], const PetscInt[],
                       const PetscScalar[], const PetscScalar[], const PetscScalar[], PetscReal, const PetscReal[],
                       PetscInt, const PetscScalar[], PetscScalar[]);
void FluidG0MassStokes(PetscInt, PetscInt, PetscInt, const PetscInt[], const PetscInt[], const PetscScalar[],
                       const PetscScalar[], const PetscScalar[], const PetscInt[], const PetscInt[],
                       const PetscScalar[], const PetscScalar[], const PetscScalar[], PetscReal, PetscReal,
                       const PetscReal[], PetscInt, const PetscScalar[], PetscScalar[]);
void FluidG0MassConvection(PetscInt, PetscInt, PetscInt, const PetscInt[], const PetscInt[], const PetscScalar[],
                           const PetscScalar[], const PetscScalar[], const PetscInt[], const PetscInt[],
                           const PetscScalar[], const PetscScalar[], const PetscScalar[], PetscReal, PetscReal,
                           const PetscReal[], PetscInt, const PetscScalar[], PetscScalar[]);
void FluidG1Convection(PetscInt, PetscInt, PetscInt, const PetscInt[], const PetscInt[], const PetscScalar[],
                       const PetscScalar[], const PetscScalar[], const PetscInt[], const PetscInt[],
                       const PetscScalar[], const PetscScalar[], const PetscScalar[], PetscReal, PetscReal,
                       const PetscReal[], PetscInt, const PetscScalar[], PetscScalar[]);
void FluidG3Viscous(PetscInt, PetscInt, PetscInt, const PetscInt[], const PetscInt[], const PetscScalar[],
                    const PetscScalar[], const PetscScalar[], const PetscInt[], const PetscInt[], const PetscScalar[],
                    const PetscScalar[], const PetscScalar[], PetscReal, PetscReal, const PetscReal[], PetscInt,
                    const PetscScalar[], PetscScalar[]);
void FluidG2Pressure(PetscInt, PetscInt, PetscInt, const PetscInt[], const PetscInt[], const PetscScalar[],
                     const PetscScalar[], const PetscScalar[], const PetscInt[], const PetscInt[], const PetscScalar[],
                     const PetscScalar[], const PetscScalar[], PetscReal, PetscReal, const PetscReal[], PetscInt,
                     const PetscScalar[], PetscScalar[]);
void FluidG1Continuity(PetscInt, PetscInt, PetscInt, const PetscInt[], const PetscInt[], const PetscScalar[],
                       const PetscScalar[], const PetscScalar[], const PetscInt[], const PetscInt[],
                       const PetscScalar[], const PetscScalar[], const PetscScalar[], PetscReal, PetscReal,
                       const PetscReal[], PetscInt, const PetscScalar[], PetscScalar[]);
void FluidF1PressureStabilization(PetscInt, PetscInt, PetscInt, const PetscInt[], const PetscInt[], const PetscScalar[],
                                  const PetscScalar[], const PetscScalar[], const PetscInt[], const PetscInt[],
                                  const PetscScalar[], const PetscScalar[], const PetscScalar[], PetscReal,
                                  const PetscReal[], PetscInt, const PetscScalar[], PetscScalar[]);
void FluidG3PressureStabilization(PetscInt, PetscInt, PetscInt, const PetscInt[], const PetscInt[], const PetscScalar[],
                                  const PetscScalar[], const PetscScalar[], const PetscInt[], const PetscInt[],
                                  const PetscScalar[], const PetscScalar[], const PetscScalar[], PetscReal, PetscReal,
                                  const PetscReal[], PetscInt, const PetscScalar[], PetscScalar[]);
#endif
