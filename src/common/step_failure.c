/* Why a solve inside a time step failed (StepFailure, fsiopt.h), recorded so that the
   time loop can retry the step with a smaller dt. */
#include <stdarg.h>
#include "fsiopt.h"

PetscErrorCode StepFailureSet(StepFailure *failure, const char format[], ...)
{
  va_list args;
  size_t  written;

  PetscFunctionBeginUser;
  va_start(args, format);
  PetscCall(PetscVSNPrintf(failure->reason, sizeof(failure->reason), format, &written, args));
  va_end(args);
  PetscFunctionReturn(0);
}
