/* Reading and writing the pieces of a checkpoint; what goes in it is each module's
   (FluidCheckpoint, StructureCheckpoint, CouplingCheckpoint, ProbesCheckpoint). */
#include <stdio.h>
#include "checkpoint.h"
#include "options.h"

/* Through a plain vector of the same layout: a vector with a DMPlex would go to the
   DM's own HDF5 layout (/fields, /vertex_fields), not this group. */
PetscErrorCode CheckpointVec(PetscViewer viewer, const char name[], Vec v, PetscBool load)
{
  Vec      plain;
  PetscInt n, N;

  PetscFunctionBeginUser;
  PetscCall(VecGetLocalSize(v, &n));
  PetscCall(VecGetSize(v, &N));
  PetscCall(VecCreateMPI(PetscObjectComm((PetscObject)v), n, N, &plain));
  PetscCall(PetscObjectSetName((PetscObject)plain, name));
  if (load) {
    PetscBool has;
    PetscCall(PetscViewerHDF5HasObject(viewer, (PetscObject)plain, &has));
    PetscCheck(has, PetscObjectComm((PetscObject)v), PETSC_ERR_FILE_UNEXPECTED, "option -restart: the checkpoint has no '%s': written by another scene or set-up", name);
    PetscCall(VecLoad(plain, viewer));
    PetscCall(VecCopy(plain, v));
  } else {
    PetscCall(VecCopy(v, plain));
    PetscCall(VecView(plain, viewer));
  }
  PetscCall(VecDestroy(&plain));
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckpointAttribute(PetscViewer viewer, const char name[], PetscDataType type, void *value, PetscBool load)
{
  PetscFunctionBeginUser;
  if (load) {
    PetscBool has;
    PetscCall(PetscViewerHDF5HasAttribute(viewer, NULL, name, &has));
    PetscCheck(has, PetscObjectComm((PetscObject)viewer), PETSC_ERR_FILE_UNEXPECTED, "option -restart: the checkpoint has no attribute '%s': not an fsiopt checkpoint of this set-up", name);
    PetscCall(PetscViewerHDF5ReadAttribute(viewer, NULL, name, type, NULL, value));
  } else PetscCall(PetscViewerHDF5WriteAttribute(viewer, NULL, name, type, value));
  PetscFunctionReturn(0);
}

PetscErrorCode CheckpointInt(PetscViewer viewer, const char name[], PetscInt *value, PetscBool load)
{
  PetscFunctionBeginUser;
  PetscCall(CheckpointAttribute(viewer, name, PETSC_INT, value, load));
  PetscFunctionReturn(0);
}

PetscErrorCode CheckpointReal(PetscViewer viewer, const char name[], PetscReal *value, PetscBool load)
{
  PetscFunctionBeginUser;
  PetscCall(CheckpointAttribute(viewer, name, PETSC_REAL, value, load));
  PetscFunctionReturn(0);
}

PetscErrorCode CheckpointLocalVec(PetscViewer viewer, const char name[], DM dm, Vec local, PetscBool load)
{
  Vec global;

  PetscFunctionBeginUser;
  PetscCall(DMGetGlobalVector(dm, &global));
  if (!load) PetscCall(DMLocalToGlobal(dm, local, INSERT_VALUES, global));
  PetscCall(CheckpointVec(viewer, name, global, load));
  if (load) PetscCall(DMGlobalToLocal(dm, global, INSERT_VALUES, local));
  PetscCall(DMRestoreGlobalVector(dm, &global));
  PetscFunctionReturn(0);
}

static PetscErrorCode TemporaryName(const char path[], char tmp[], size_t len)
{
  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(tmp, len, "%s.tmp", path));
  PetscFunctionReturn(0);
}

PetscErrorCode CheckpointOpen(MPI_Comm comm, const char path[], PetscBool load, PetscViewer *viewer)
{
  char tmp[PETSC_MAX_PATH_LEN];

  PetscFunctionBeginUser;
  if (load) {
    PetscCall(CheckReadableFile(comm, "-restart", path));
    {
      PetscErrorCode ierr;
      /* HDF5 would print its own diagnostic stack for a file that is not HDF5 */
      H5E_auto2_t report;
      void       *report_data;
      H5Eget_auto2(H5E_DEFAULT, &report, &report_data);
      H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
      ierr = PetscViewerHDF5Open(comm, path, FILE_MODE_READ, viewer);
      H5Eset_auto2(H5E_DEFAULT, report, report_data);
      if (ierr) {
        PetscCall(ErrorReportingForget());
        SETERRQ(comm, PETSC_ERR_FILE_UNEXPECTED, "option -restart %s: not an HDF5 file", path);
      }
    }
  } else {
    PetscCall(TemporaryName(path, tmp, sizeof(tmp)));
    PetscCall(PetscViewerHDF5Open(comm, tmp, FILE_MODE_WRITE, viewer));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode CheckpointClose(MPI_Comm comm, const char path[], PetscBool load, PetscViewer *viewer)
{
  char        tmp[PETSC_MAX_PATH_LEN];
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  PetscCall(PetscViewerDestroy(viewer));
  if (load) PetscFunctionReturn(0);
  PetscCall(TemporaryName(path, tmp, sizeof(tmp)));
  PetscCallMPI(MPI_Barrier(comm));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (!rank) PetscCheck(rename(tmp, path) == 0, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "option -checkpoint_file %s: cannot rename %s into place", path, tmp);
  PetscCallMPI(MPI_Barrier(comm));
  PetscFunctionReturn(0);
}
