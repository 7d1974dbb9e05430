#ifndef FSIOPT_MEMORY_ESTIMATE_H
#define FSIOPT_MEMORY_ESTIMATE_H
#include "fsiopt.h"

/* The finite-element fields a subproblem will put on a mesh: what its solver memory grows
   with. */
typedef struct {
  PetscInt n;
  PetscInt degree[4], components[4]; /* components -1: one per space dimension */
} MeshFields;

/* The dofs of `fields` on `coarse` after `refine` uniform refinements, from the exact point
   counts of the refined mesh (points on a partition boundary counted on each rank that has
   them); -1 when the mesh is not interpolated. Collective. */
PetscErrorCode MemoryEstimateDofs(DM coarse, PetscInt refine, const MeshFields *, PetscReal *dofs);
/* Adds what a subproblem of `dofs` unknowns in `dim` dimensions will need (its factors,
   matrices and vectors, the model in memory_estimate.c; `prefix` names its solver options)
   to this rank's estimate (`source` names the mesh and its refinement in the message), and refuses the run, with the estimate, when the ranks of `comm`
   on one node would need more than that node has (-memory_per_node_gib, else its available
   memory), unless -force. Collective on `comm`. */
PetscErrorCode MemoryEstimateAdd(MPI_Comm, const char prefix[], PetscInt dim, PetscReal dofs, const char source[]);
/* A mesh of `points` points (cells, faces, edges, vertices) built on one rank before it is
   distributed (a box): refused, with one line naming `source`, when PETSc's integers cannot
   number its points, or when building it needs more memory than the node has (unless -force).
   Collective. */
PetscErrorCode MemoryEstimateCheckMeshPoints(MPI_Comm, const char source[], PetscReal points);
/* This rank's estimate so far, bytes (not collective: for an error message). */
PetscReal MemoryEstimateThisRank(void);
/* The estimate and the peak resident memory (getrusage), each summed over the ranks of
   PETSC_COMM_WORLD, in bytes. Collective. */
PetscErrorCode MemoryEstimateGetTotals(PetscReal *estimate, PetscReal *peak);
#endif
