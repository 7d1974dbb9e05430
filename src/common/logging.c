/* fsiopt's PETSc log stages and events (logging.h), registered once at start-up, so that
   -log_view splits a run by physics and by task. */
#include "logging.h"

PetscLogStage FSIOPT_STAGE_SETUP, FSIOPT_STAGE_FLUID, FSIOPT_STAGE_STRUCTURE, FSIOPT_STAGE_OUTPUT,
  FSIOPT_STAGE_OPTIMIZER, FSIOPT_STAGE_SENSITIVITY, FSIOPT_STAGE_ADJOINT, FSIOPT_STAGE_MESH_MOTION;
PetscLogEvent FSIOPT_EVENT_MESH, FSIOPT_EVENT_FLUID_SOLVE, FSIOPT_EVENT_STRUCTURE_SOLVE, FSIOPT_EVENT_ERRORS,
  FSIOPT_EVENT_SENSITIVITY, FSIOPT_EVENT_ADJOINT, FSIOPT_EVENT_INTERFACE, FSIOPT_EVENT_PROBES, FSIOPT_EVENT_CHECKPOINT,
  FSIOPT_EVENT_STEP_START, FSIOPT_EVENT_CEED_RESIDUAL, FSIOPT_EVENT_CEED_JACOBIAN, FSIOPT_EVENT_CEED_LINEARIZE,
  FSIOPT_EVENT_CEED_ELEMENT_MATRICES, FSIOPT_EVENT_BOUNDARY_TERMS, FSIOPT_EVENT_FLUID_RESIDUAL,
  FSIOPT_EVENT_FLUID_JACOBIAN, FSIOPT_EVENT_STRUCTURE_RESIDUAL, FSIOPT_EVENT_STRUCTURE_JACOBIAN,
  FSIOPT_EVENT_FLUID_MATFREE, FSIOPT_EVENT_FLUID_LINEAR, FSIOPT_EVENT_STRUCTURE_LINEAR, FSIOPT_EVENT_CHECKSUM;

PetscErrorCode LoggingRegister(void)
{
  PetscClassId classid;

  PetscFunctionBeginUser;
  PetscCall(PetscClassIdRegister("fsiopt", &classid));
  PetscCall(PetscLogStageRegister("Setup", &FSIOPT_STAGE_SETUP));
  PetscCall(PetscLogStageRegister("Fluid", &FSIOPT_STAGE_FLUID));
  PetscCall(PetscLogStageRegister("Structure", &FSIOPT_STAGE_STRUCTURE));
  PetscCall(PetscLogStageRegister("Output", &FSIOPT_STAGE_OUTPUT));
  PetscCall(PetscLogStageRegister("Optimizer", &FSIOPT_STAGE_OPTIMIZER));
  PetscCall(PetscLogStageRegister("Sensitivity", &FSIOPT_STAGE_SENSITIVITY));
  PetscCall(PetscLogStageRegister("Adjoint", &FSIOPT_STAGE_ADJOINT));
  PetscCall(PetscLogStageRegister("MeshMotion", &FSIOPT_STAGE_MESH_MOTION));
  PetscCall(PetscLogEventRegister("MeshCreate", classid, &FSIOPT_EVENT_MESH));
  PetscCall(PetscLogEventRegister("FluidStep", classid, &FSIOPT_EVENT_FLUID_SOLVE));
  PetscCall(PetscLogEventRegister("StructureStep", classid, &FSIOPT_EVENT_STRUCTURE_SOLVE));
  PetscCall(PetscLogEventRegister("ErrorNorms", classid, &FSIOPT_EVENT_ERRORS));
  PetscCall(PetscLogEventRegister("SensitivityProd", classid, &FSIOPT_EVENT_SENSITIVITY));
  PetscCall(PetscLogEventRegister("AdjointProd", classid, &FSIOPT_EVENT_ADJOINT));
  PetscCall(PetscLogEventRegister("InterfaceSetUp", classid, &FSIOPT_EVENT_INTERFACE));
  PetscCall(PetscLogEventRegister("ProbesForces", classid, &FSIOPT_EVENT_PROBES));
  PetscCall(PetscLogEventRegister("Checkpoint", classid, &FSIOPT_EVENT_CHECKPOINT));
  /* inside Checkpoint (and a restart's read): the checksums' share of a checkpoint's cost */
  PetscCall(PetscLogEventRegister("Checksum", classid, &FSIOPT_EVENT_CHECKSUM));
  PetscCall(PetscLogEventRegister("StepStartKeep", classid, &FSIOPT_EVENT_STEP_START));
  PetscCall(PetscLogEventRegister("CeedResidual", classid, &FSIOPT_EVENT_CEED_RESIDUAL));
  PetscCall(PetscLogEventRegister("CeedJacobian", classid, &FSIOPT_EVENT_CEED_JACOBIAN));
  /* inside CeedJacobian: the pointwise data at each point (libCEED's linearization of a
     pointwise function, D, or the fluid velocity block's coefficients), and the element
     matrices formed from it */
  PetscCall(PetscLogEventRegister("CeedLinearize", classid, &FSIOPT_EVENT_CEED_LINEARIZE));
  PetscCall(PetscLogEventRegister("CeedElemMats", classid, &FSIOPT_EVENT_CEED_ELEMENT_MATRICES));
  PetscCall(PetscLogEventRegister("BoundaryTerms", classid, &FSIOPT_EVENT_BOUNDARY_TERMS));
  /* the whole operator of libCEED's backend: volume, boundary terms, loads, assembly */
  PetscCall(PetscLogEventRegister("FluidResidual", classid, &FSIOPT_EVENT_FLUID_RESIDUAL));
  PetscCall(PetscLogEventRegister("FluidJacobian", classid, &FSIOPT_EVENT_FLUID_JACOBIAN));
  PetscCall(PetscLogEventRegister("StructResidual", classid, &FSIOPT_EVENT_STRUCTURE_RESIDUAL));
  PetscCall(PetscLogEventRegister("StructJacobian", classid, &FSIOPT_EVENT_STRUCTURE_JACOBIAN));
  PetscCall(PetscLogEventRegister("FluidMatFreeMult", classid, &FSIOPT_EVENT_FLUID_MATFREE));
  /* the linearized solves on factors in hand (sensitivity, adjoint, predictor): what separate
     fluid and structure ranks can do at the same time (scripts/strong_scaling.py's ideal) */
  PetscCall(PetscLogEventRegister("FluidLinSolve", classid, &FSIOPT_EVENT_FLUID_LINEAR));
  PetscCall(PetscLogEventRegister("StructLinSolve", classid, &FSIOPT_EVENT_STRUCTURE_LINEAR));
  /* -log_view names a stage after rank 0's record of it: with -structure_ranks, rank 0
     (a fluid rank) would otherwise never enter Structure, and the line would be nameless */
  for (PetscLogStage stage = FSIOPT_STAGE_SETUP; stage <= FSIOPT_STAGE_MESH_MOTION; ++stage) {
    PetscCall(PetscLogStagePush(stage));
    PetscCall(PetscLogStagePop());
  }
  PetscFunctionReturn(0);
}
