#include "logging.h"

PetscLogStage FSIOPT_STAGE_SETUP, FSIOPT_STAGE_FLUID, FSIOPT_STAGE_STRUCTURE, FSIOPT_STAGE_OUTPUT;
PetscLogEvent FSIOPT_EVENT_MESH, FSIOPT_EVENT_FLUID_SOLVE, FSIOPT_EVENT_STRUCTURE_SOLVE, FSIOPT_EVENT_ERRORS;

PetscErrorCode FsioptLogRegister(void)
{
  PetscClassId classid;

  PetscFunctionBeginUser;
  PetscCall(PetscClassIdRegister("fsiopt", &classid));
  PetscCall(PetscLogStageRegister("Setup", &FSIOPT_STAGE_SETUP));
  PetscCall(PetscLogStageRegister("Fluid", &FSIOPT_STAGE_FLUID));
  PetscCall(PetscLogStageRegister("Structure", &FSIOPT_STAGE_STRUCTURE));
  PetscCall(PetscLogStageRegister("Output", &FSIOPT_STAGE_OUTPUT));
  PetscCall(PetscLogEventRegister("MeshCreate", classid, &FSIOPT_EVENT_MESH));
  PetscCall(PetscLogEventRegister("FluidStep", classid, &FSIOPT_EVENT_FLUID_SOLVE));
  PetscCall(PetscLogEventRegister("StructureStep", classid, &FSIOPT_EVENT_STRUCTURE_SOLVE));
  PetscCall(PetscLogEventRegister("ErrorNorms", classid, &FSIOPT_EVENT_ERRORS));
  PetscFunctionReturn(0);
}
