#include "mesh.h"
#include "options.h"
#include "logging.h"

static PetscErrorCode MeshCheckFaceSets(DM dm, const char prefix[], const char source[], PetscInt nrequired, const PetscInt required[])
{
  DMLabel label;

  PetscFunctionBeginUser;
  PetscCall(DMGetLabel(dm, "Face Sets", &label));
  for (PetscInt i = 0; i < nrequired; ++i) {
    PetscInt local = 0, global = 0;

    if (label) PetscCall(DMLabelGetStratumSize(label, required[i], &local));
    PetscCallMPI(MPI_Allreduce(&local, &global, 1, MPIU_INT, MPI_SUM, PetscObjectComm((PetscObject)dm)));
    PetscCheck(global > 0, PetscObjectComm((PetscObject)dm), PETSC_ERR_ARG_WRONG, "%s mesh %s: expected a 'Face Sets' label with value %" PetscInt_FMT " (1 bottom, 2 right, 3 top, 4 left, higher values the scene's own), which the scene needs; it is missing", prefix, source, required[i]);
  }
  PetscFunctionReturn(0);
}

PetscErrorCode MeshCreate(MPI_Comm comm, const char prefix[], PetscInt refine, PetscInt nrequired, const PetscInt required[], DM *mesh)
{
  DM          dm;
  char        option[256], filename[PETSC_MAX_PATH_LEN] = "";
  PetscBool   from_file, distributed;
  PetscMPIInt size;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_MESH, 0, 0, 0, 0));
  PetscCall(PetscSNPrintf(option, sizeof(option), "-%sdm_plex_filename", prefix));
  PetscCall(PetscOptionsGetString(NULL, NULL, option, filename, sizeof(filename), &from_file));
  if (from_file) PetscCall(CheckReadableFile(comm, option, filename));

  PetscCall(DMCreate(comm, &dm));
  PetscCall(DMSetType(dm, DMPLEX));
  PetscCall(PetscObjectSetOptionsPrefix((PetscObject)dm, prefix));
  {
    PetscErrorCode ierr = DMSetFromOptions(dm);
    if (ierr) {
      PetscCall(ErrorReportingForget());
      SETERRQ(comm, PETSC_ERR_FILE_UNEXPECTED, "%s mesh %s: cannot build the mesh (expected a gmsh 2.2/4.1 .msh file or -%sdm_plex_box_* options)", prefix, from_file ? filename : "(box)", prefix);
    }
  }
  PetscCall(MeshCheckFaceSets(dm, prefix, from_file ? filename : "(box)", nrequired, required));

  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(DMPlexIsDistributed(dm, &distributed));
  if (size > 1 && !distributed) {
    DM               parallel = NULL;
    PetscPartitioner partitioner;

    /* PT-Scotch unless -<prefix>petscpartitioner_type says otherwise (Debian's PETSc has
       no ParMETIS) */
    PetscCall(DMPlexGetPartitioner(dm, &partitioner));
    PetscCall(PetscPartitionerSetType(partitioner, PETSCPARTITIONERPTSCOTCH));
    PetscCall(PetscPartitionerSetFromOptions(partitioner));
    PetscCall(DMPlexDistribute(dm, 0, NULL, &parallel));
    if (parallel) {
      PetscCall(DMDestroy(&dm));
      dm = parallel;
    }
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
