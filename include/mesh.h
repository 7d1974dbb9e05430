#ifndef FSIOPT_MESH_H
#define FSIOPT_MESH_H
#include "fsiopt.h"
#include "memory_estimate.h"

/* Builds one subdomain's mesh from the options under `prefix` (-fluid_dm_plex_*,
   -structure_dm_plex_*: a box, or a gmsh file with -<prefix>dm_plex_filename),
   refines it `refine` times, distributes it, and checks it: the dimension the scene
   needs (`dim`, 0: any), every face set in `required`, and no inverted or degenerate
   cell. Before refining, the memory the `fields` will need on the refined mesh is estimated
   and the run refused if a node cannot hold it (memory_estimate.h). */
PetscErrorCode MeshCreate(MPI_Comm, const char prefix[], PetscInt refine, PetscInt dim, PetscInt nrequired,
                          const PetscInt required[], const MeshFields *fields, DM *);
/* The unknowns `fields` will have on the mesh MeshCreate would build (MemoryEstimateDofs on
   the mesh as read, checked as MeshCreate checks it); nothing is kept. Collective. */
PetscErrorCode MeshCountDofs(MPI_Comm, const char prefix[], PetscInt refine, PetscInt dim, PetscInt nrequired,
                             const PetscInt required[], const MeshFields *fields, PetscReal *dofs);
/* A number that changes when the mesh is split or numbered differently: the owned cells'
   centroids weighted by their global numbers, summed over the ranks. A checkpoint's
   vectors are in that numbering; collective. */
PetscErrorCode MeshLayoutSignature(DM, PetscReal *);
/* A gmsh file's own consistency (gmsh_check.c), before PETSc reads it: counts, node tags,
   element types and dimension (dim: the scene's, 0: any), no crack. One line naming the
   option, the file and the first problem; collective. */
PetscErrorCode MeshCheckGmshFile(MPI_Comm, const char option[], const char path[], PetscInt dim);
/* The physical groups of dimension dim that a gmsh file names (gmsh_names.c): at most max,
   on every rank; none when the file has no $PhysicalNames. Collective. */
typedef struct {
  char     name[64];
  PetscInt value; /* its number: the value of "Face Sets" (dim - 1) or "Cell Sets" (dim) */
} MeshPhysicalName;
PetscErrorCode MeshGmshPhysicalNames(MPI_Comm, const char path[], PetscInt dim, PetscInt max, PetscInt *n,
                                     MeshPhysicalName names[]);
/* The named face sets of a side's mesh (prefix "fluid_" or "structure_", dim the mesh's):
   the gmsh file's physical names of dimension dim - 1, or bottom, right, top, left of a 2D
   box; none for a file without names. Collective. */
PetscErrorCode MeshFaceSetNames(MPI_Comm, const char prefix[], PetscInt dim, PetscInt max, PetscInt *n,
                                MeshPhysicalName sets[]);
/* A .geo given as -PREFIXdm_plex_filename: meshed by gmsh (in dim dimensions, with
   -PREFIXgeo_setnumber NAME,VALUE,...) beside it as .msh, which the option then names; a
   mesh newer than the .geo and its includes is reused (gmsh_geo.c). Collective. */
PetscErrorCode MeshFromGeo(MPI_Comm, const char prefix[], PetscInt dim);
/* The face set `text` names: one of sets by name, or a positive number; -1 for neither. */
PetscErrorCode MeshFaceSetFind(PetscInt n, const MeshPhysicalName sets[], const char text[], PetscInt *value);
#endif
