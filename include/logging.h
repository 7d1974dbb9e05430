#ifndef FSIOPT_LOGGING_H
#define FSIOPT_LOGGING_H
#include <petsclog.h>

/* Stages and events, so that -log_view splits a run by physics and by task. */
extern PetscLogStage FSIOPT_STAGE_SETUP, FSIOPT_STAGE_FLUID, FSIOPT_STAGE_STRUCTURE, FSIOPT_STAGE_OUTPUT;
extern PetscLogEvent FSIOPT_EVENT_MESH, FSIOPT_EVENT_FLUID_SOLVE, FSIOPT_EVENT_STRUCTURE_SOLVE, FSIOPT_EVENT_ERRORS;

PetscErrorCode FsioptLogRegister(void);
#endif
