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
