#ifndef FSIOPT_ERROR_REPORTING_H
#define FSIOPT_ERROR_REPORTING_H
#include <petscsys.h>

/* One-line error reporting instead of PETSc's traceback banner. */
PetscErrorCode ErrorReportingPush(void);
const char    *ErrorReportingFirstMessage(void);
/* the communicator the first error was raised on */
MPI_Comm ErrorReportingFirstComm(void);
/* Drops the recorded message, so that a caller can replace a library's message by its own. */
PetscErrorCode ErrorReportingForget(void);
/* After work only some ranks of comm did (ierr there, 0 elsewhere): collective; every rank
   returns the error of the lowest rank that failed, with its message. */
PetscErrorCode ErrorReportingAgree(MPI_Comm comm, PetscErrorCode ierr);
#endif
