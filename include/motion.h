#ifndef FSIOPT_MOTION_H
#define FSIOPT_MOTION_H
#include "fsiopt.h"
#include "interface.h"

/* The fluid mesh displacement: the harmonic (or -mesh_motion elastic, biharmonic)
   extension of the interface displacement into the fluid's reference domain, zero on
   the fixed boundaries. The operator never changes (one factorization per run), unless
   -mesh_motion_incremental: then each step extends its increment from the step's start. */
typedef struct _p_MeshMotion *MeshMotion;

PetscErrorCode MeshMotionCreate(DM fluid, PetscInt interface_face, PetscInt nfixed, const PetscInt fixed_faces[],
                                MeshMotion *);
/* interface: an interface vector (fluid node order) of displacements; displacement, a local
   vector in the fluid's coordinate layout, holds the mesh in hand on entry (an iterative
   solver's first guess, -mesh_motion_warm_start) and the result on exit. Collective on
   the fluid's ranks. */
PetscErrorCode MeshMotionSolve(MeshMotion, Interface, Vec interface, Vec displacement);
/* the displacement at the step's start (coordinate layout); incremental motions rebuild
   their operator on that mesh. Collective on the fluid's ranks. */
PetscErrorCode MeshMotionBeginStep(MeshMotion, Vec displacement);
PetscErrorCode MeshMotionDestroy(MeshMotion *);
#endif
