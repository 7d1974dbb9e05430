#ifndef FSIOPT_MESH_H
#define FSIOPT_MESH_H
#include "fsiopt.h"

/* Builds one subdomain's mesh from the options under `prefix` (-fluid_dm_plex_*,
   -structure_dm_plex_*: a box, or a gmsh file with -<prefix>dm_plex_filename),
   refines it `refine` times, distributes it, and checks that every face set in
   `required` is present. */
PetscErrorCode MeshCreate(MPI_Comm, const char prefix[], PetscInt refine, PetscInt nrequired, const PetscInt required[], DM *);
#endif
