/* A subdomain's mesh (mesh.h): a box or a gmsh file read, checked (dimension, face sets,
   inverted cells, memory), refined and distributed; and a signature of its partition for
   checkpoints. */
#include "mesh.h"
#include "options.h"
#include "error_reporting.h"
#include "logging.h"
#include <stdio.h>
#include <string.h>
#include <scotch/scotch.h> /* SCOTCH_randomSeed: the partitioner under PETSc (libscotch-dev) */

static PetscErrorCode MeshCheckFaceSets(DM dm, const char prefix[], const char source[], PetscInt nrequired,
                                        const PetscInt required[])
{
  DMLabel label;

  PetscFunctionBeginUser;
  PetscCall(DMGetLabel(dm, "Face Sets", &label));
  for (PetscInt i = 0; i < nrequired; ++i) {
    PetscInt local = 0, global = 0;

    if (label) PetscCall(DMLabelGetStratumSize(label, required[i], &local));
    PetscCallMPI(MPI_Allreduce(&local, &global, 1, MPIU_INT, MPI_SUM, PetscObjectComm((PetscObject)dm)));
    PetscCheck(global > 0, PetscObjectComm((PetscObject)dm), PETSC_ERR_ARG_WRONG,
               "%s mesh %s: expected a 'Face Sets' label with value %" PetscInt_FMT
               " (1 bottom, 2 right, 3 top, 4 left, higher values the scene's own), which the scene needs; it is "
               "missing",
               prefix, source, required[i]);
  }
  PetscFunctionReturn(0);
}

/* A cell whose Jacobian determinant is not positive at its first corner is inverted (its
   vertices out of order) or degenerate. */
static PetscErrorCode MeshCheckCells(DM dm, const char prefix[], const char source[])
{
  PetscInt  cStart, cEnd, dim, bad     = -1;
  PetscReal v0[3], J[9], invJ[9], detJ = 1, where[3] = {0, 0, 0}, worst = 1;

  PetscFunctionBeginUser;
  PetscCall(DMGetDimension(dm, &dim));
  PetscCall(DMGetCoordinatesLocalSetUp(dm));
  PetscCall(DMPlexGetHeightStratum(dm, 0, &cStart, &cEnd));
  for (PetscInt c = cStart; c < cEnd && bad < 0; ++c) {
    PetscCall(DMPlexComputeCellGeometryAffineFEM(dm, c, v0, J, invJ, &detJ));
    if (!(detJ > 0)) {
      bad   = c;
      worst = detJ;
      for (PetscInt d = 0; d < dim; ++d) where[d] = v0[d];
    }
  }
  {
    /* the first rank with such a cell names it */
    MPI_Comm    comm = PetscObjectComm((PetscObject)dm);
    PetscMPIInt rank, size, first;
    PetscReal   report[5] = {(PetscReal)bad, worst, where[0], where[1], where[2]};

    PetscCallMPI(MPI_Comm_rank(comm, &rank));
    PetscCallMPI(MPI_Comm_size(comm, &size));
    first = bad >= 0 ? rank : size;
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &first, 1, MPI_INT, MPI_MIN, comm));
    if (first == size) PetscFunctionReturn(0);
    PetscCallMPI(MPI_Bcast(report, 5, MPIU_REAL, first, comm));
    SETERRQ(comm, PETSC_ERR_ARG_WRONG,
            "%s mesh %s: cell %d with its first corner at (%g, %g, %g) is inverted or degenerate (Jacobian determinant "
            "%g)",
            prefix, source, (int)report[0], (double)report[2], (double)report[3], (double)report[4], (double)report[1]);
  }
  PetscFunctionReturn(0);
}

/* PETSc's box mesh takes zero cells per direction without a word (and then has no faces
   to label), and a box whose lower corner is above its upper one as an inverted mesh that
   runs. */
static PetscErrorCode MeshCheckBox(MPI_Comm comm, const char prefix[])
{
  char      option[256], lower_option[256], upper_option[256];
  PetscInt  faces[3], nfaces = 3, nlower = 3, nupper = 3;
  PetscReal lower[3] = {0, 0, 0}, upper[3] = {1, 1, 1};
  PetscBool set;

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(option, sizeof(option), "-%sdm_plex_box_faces", prefix));
  PetscCall(OptionsCheckIntegers(comm, NULL, option, "cells per direction, each at least 1"));
  PetscCall(PetscOptionsGetIntArray(NULL, NULL, option, faces, &nfaces, &set));
  for (PetscInt d = 0; set && d < nfaces; ++d)
    PetscCheck(faces[d] >= 1, comm, PETSC_ERR_ARG_OUTOFRANGE,
               "option %s: expected at least 1 cell in every direction, got %" PetscInt_FMT
               " in direction %" PetscInt_FMT,
               option, faces[d], d + 1);
  if (set) { /* PETSc builds the box, refined by -<prefix>dm_refine, on one rank: its points first */
    PetscInt  refine = 0;
    PetscReal points = 1;
    char      refine_option[256], source[512], value[128] = "";
    PetscCall(PetscSNPrintf(refine_option, sizeof(refine_option), "-%sdm_refine", prefix));
    PetscCall(PetscOptionsGetInt(NULL, NULL, refine_option, &refine, NULL));
    PetscCall(PetscOptionsGetString(NULL, NULL, option, value, sizeof(value), NULL));
    /* a box of n_1 x ... cells has about 2^dim points (cell, faces, edges, vertex) per vertex */
    for (PetscInt d = 0; d < nfaces; ++d)
      points *= 2.0 * ((PetscReal)faces[d] * PetscPowReal(2.0, (PetscReal)refine) + 1);
    PetscCall(PetscSNPrintf(source, sizeof(source), "option %s %s%s%s", option, value, refine ? " with " : "",
                            refine ? refine_option : ""));
    PetscCall(MemoryEstimateCheckMeshPoints(comm, source, points));
  }
  PetscCall(PetscSNPrintf(lower_option, sizeof(lower_option), "-%sdm_plex_box_lower", prefix));
  PetscCall(PetscSNPrintf(upper_option, sizeof(upper_option), "-%sdm_plex_box_upper", prefix));
  PetscCall(PetscOptionsGetRealArray(NULL, NULL, lower_option, lower, &nlower, NULL));
  PetscCall(PetscOptionsGetRealArray(NULL, NULL, upper_option, upper, &nupper, NULL));
  for (PetscInt d = 0; d < 3; ++d)
    PetscCheck(lower[d] < upper[d] && !PetscIsInfOrNanReal(lower[d]) && !PetscIsInfOrNanReal(upper[d]), comm,
               PETSC_ERR_ARG_OUTOFRANGE,
               "options %s and %s: expected a lower corner below the upper one in every direction, got %g and %g in "
               "direction %" PetscInt_FMT,
               lower_option, upper_option, (double)lower[d], (double)upper[d], d + 1);
  PetscFunctionReturn(0);
}

/* The mesh as the options give it, before it is distributed or refined, checked. */
static PetscErrorCode LoadChecked(MPI_Comm comm, const char prefix[], PetscInt dim, PetscInt nrequired,
                                  const PetscInt required[], DM *mesh, char filename[PETSC_MAX_PATH_LEN],
                                  PetscBool *from_file_)
{
  DM        dm;
  char      option[256];
  PetscBool from_file;

  PetscFunctionBeginUser;
  filename[0] = 0;
  PetscCall(MeshFromGeo(comm, prefix, dim));
  PetscCall(PetscSNPrintf(option, sizeof(option), "-%sdm_plex_filename", prefix));
  PetscCall(PetscOptionsGetString(NULL, NULL, option, filename, PETSC_MAX_PATH_LEN, &from_file));
  if (from_file) PetscCall(OptionsCheckReadableFile(comm, option, filename));
  if (from_file) {
    size_t len;
    PetscCall(PetscStrlen(filename, &len));
    if (len > 4 && !strcmp(filename + len - 4, ".msh")) PetscCall(MeshCheckGmshFile(comm, option, filename, dim));
  }

  if (!from_file) PetscCall(MeshCheckBox(comm, prefix));
  PetscCall(DMCreate(comm, &dm));
  PetscCall(DMSetType(dm, DMPLEX));
  PetscCall(PetscObjectSetOptionsPrefix((PetscObject)dm, prefix));
  {
    /* PT-Scotch unless -<prefix>petscpartitioner_type says otherwise (Debian's PETSc has no
       ParMETIS), for the split DMSetFromOptions makes of a box and for ours of a file below;
       read on one rank too, so that one options file serves every rank count */
    PetscPartitioner partitioner;
    PetscCall(DMPlexGetPartitioner(dm, &partitioner));
    PetscCall(PetscObjectSetOptionsPrefix((PetscObject)partitioner, prefix));
    PetscCall(PetscPartitionerSetType(partitioner, PETSCPARTITIONERPTSCOTCH));
    PetscCall(PetscPartitionerSetFromOptions(partitioner));
  }
  {
    PetscErrorCode ierr = DMSetFromOptions(dm);
    if (ierr) {
      PetscCall(ErrorReportingForget());
      SETERRQ(comm, PETSC_ERR_FILE_UNEXPECTED,
              "%s mesh %s: cannot build the mesh (expected a gmsh 2.2/4.1 .msh file or -%sdm_plex_box_* options)",
              prefix, from_file ? filename : "(box)", prefix);
    }
  }
  {
    PetscInt got;
    PetscCall(DMGetDimension(dm, &got));
    PetscCheck(!dim || got == dim, comm, PETSC_ERR_ARG_WRONG,
               "%s mesh %s: expected a %" PetscInt_FMT "D mesh for this scene, got a %" PetscInt_FMT "D one", prefix,
               from_file ? filename : "(box)", dim, got);
  }
  PetscCall(MeshCheckFaceSets(dm, prefix, from_file ? filename : "(box)", nrequired, required));
  PetscCall(MeshCheckCells(dm, prefix, from_file ? filename : "(box)"));
  *mesh       = dm;
  *from_file_ = from_file;
  PetscFunctionReturn(0);
}

PetscErrorCode MeshCountDofs(MPI_Comm comm, const char prefix[], PetscInt refine, PetscInt dim, PetscInt nrequired,
                             const PetscInt required[], const MeshFields *fields, PetscReal *dofs)
{
  DM        dm;
  char      filename[PETSC_MAX_PATH_LEN];
  PetscBool from_file;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_MESH, 0, 0, 0, 0));
  PetscCall(LoadChecked(comm, prefix, dim, nrequired, required, &dm, filename, &from_file));
  PetscCall(MemoryEstimateDofs(dm, refine, fields, dofs));
  PetscCall(DMDestroy(&dm));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_MESH, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode MeshCreate(MPI_Comm comm, const char prefix[], PetscInt refine, PetscInt dim, PetscInt nrequired,
                          const PetscInt required[], const MeshFields *fields, DM *mesh)
{
  DM          dm;
  char        filename[PETSC_MAX_PATH_LEN];
  PetscBool   from_file, distributed;
  PetscMPIInt size;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_MESH, 0, 0, 0, 0));
  PetscCall(LoadChecked(comm, prefix, dim, nrequired, required, &dm, filename, &from_file));

  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(DMPlexIsDistributed(dm, &distributed));
  if (size > 1 && !distributed) {
    DM parallel = NULL;

    /* PT-Scotch draws random numbers: from the same seed, the same mesh on the same ranks is
       split the same way in every run, which a checkpoint's vectors (stored in the
       partition's ordering) rely on */
    SCOTCH_randomSeed(1);
    SCOTCH_randomReset();
    PetscCall(DMPlexDistribute(dm, 0, NULL, &parallel));
    if (parallel) {
      PetscCall(DMDestroy(&dm));
      dm = parallel;
    }
  }
  {
    PetscReal dofs;
    PetscInt  mesh_dim;
    char      source[PETSC_MAX_PATH_LEN + 64];
    PetscCall(DMGetDimension(dm, &mesh_dim));
    PetscCall(MemoryEstimateDofs(dm, refine, fields, &dofs));
    PetscCall(PetscSNPrintf(source, sizeof(source), "%.*s mesh %s with -refine %" PetscInt_FMT,
                            (int)(strlen(prefix) - 1), prefix, from_file ? filename : "(box)", refine));
    PetscCall(MemoryEstimateAdd(comm, prefix, mesh_dim, dofs, source));
  }
  for (PetscInt r = 0; r < refine; ++r) {
    DM fine;

    PetscCall(DMRefine(dm, comm, &fine));
    PetscCall(DMDestroy(&dm));
    dm = fine;
  }
  PetscCall(PetscObjectSetName((PetscObject)dm, prefix));
  PetscCall(DMViewFromOptions(dm, NULL, "-dm_view"));
  *mesh = dm;
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_MESH, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode MeshLayoutSignature(DM dm, PetscReal *signature)
{
  IS              numbering;
  const PetscInt *global;
  PetscInt        cStart, cEnd, dim;
  PetscReal       local = 0;

  PetscFunctionBeginUser;
  PetscCall(DMGetDimension(dm, &dim));
  PetscCall(DMPlexGetHeightStratum(dm, 0, &cStart, &cEnd));
  PetscCall(DMPlexGetCellNumbering(dm, &numbering));
  PetscCall(ISGetIndices(numbering, &global));
  for (PetscInt c = cStart; c < cEnd; ++c) {
    PetscReal centroid[3] = {0, 0, 0}, volume;
    if (global[c - cStart] < 0) continue; /* owned elsewhere */
    PetscCall(DMPlexComputeCellGeometryFVM(dm, c, &volume, centroid, NULL));
    for (PetscInt d = 0; d < dim; ++d) local += (global[c - cStart] + 1) * (d + 1) * centroid[d];
  }
  PetscCall(ISRestoreIndices(numbering, &global));
  PetscCallMPI(MPI_Allreduce(&local, signature, 1, MPIU_REAL, MPIU_SUM, PetscObjectComm((PetscObject)dm)));
  PetscFunctionReturn(0);
}
