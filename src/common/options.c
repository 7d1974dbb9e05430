#include "options.h"
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

PetscErrorCode OptionsPositiveReal(PetscOptionItems *PetscOptionsObject, const char opt[], const char text[], PetscReal *value)
{
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsReal(opt, text, NULL, *value, value, NULL));
  PetscCheck(*value > 0 && !PetscIsInfOrNanReal(*value), PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE, "option %s: expected a positive number (%s), got %g", opt, text, (double)*value);
  PetscFunctionReturn(0);
}

PetscErrorCode OptionsNonNegativeReal(PetscOptionItems *PetscOptionsObject, const char opt[], const char text[], PetscReal *value)
{
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsReal(opt, text, NULL, *value, value, NULL));
  PetscCheck(*value >= 0 && !PetscIsInfOrNanReal(*value), PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE, "option %s: expected a number >= 0 (%s), got %g", opt, text, (double)*value);
  PetscFunctionReturn(0);
}

PetscErrorCode OptionsRealInRange(PetscOptionItems *PetscOptionsObject, const char opt[], const char text[], PetscReal lo, PetscReal hi, PetscReal *value)
{
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsReal(opt, text, NULL, *value, value, NULL));
  PetscCheck(*value > lo && *value < hi, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE, "option %s: expected a number in (%g, %g) (%s), got %g", opt, (double)lo, (double)hi, text, (double)*value);
  PetscFunctionReturn(0);
}

PetscErrorCode OptionsIntInRange(PetscOptionItems *PetscOptionsObject, const char opt[], const char text[], PetscInt lo, PetscInt hi, PetscInt *value)
{
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsInt(opt, text, NULL, *value, value, NULL));
  PetscCheck(*value >= lo && *value <= hi, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE, "option %s: expected an integer in [%" PetscInt_FMT ", %" PetscInt_FMT "] (%s), got %" PetscInt_FMT, opt, lo, hi, text, *value);
  PetscFunctionReturn(0);
}

PetscErrorCode OptionsSetDefault(const char opt[], const char value[])
{
  PetscBool set;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsHasName(NULL, NULL, opt, &set));
  if (!set) PetscCall(PetscOptionsSetValue(NULL, opt, value));
  PetscFunctionReturn(0);
}

int FileProblem(const char path[])
{
  struct stat st;
  FILE       *fp;

  if (stat(path, &st)) return 1;
  if (!S_ISREG(st.st_mode)) return 2;
  if (!(fp = fopen(path, "r"))) return 1;
  fclose(fp);
  return st.st_size > 0 ? 0 : 3;
}

const char *FileProblemText(int problem)
{
  switch (problem) {
  case 1:
    return "cannot open the file for reading";
  case 2:
    return "expected a regular file";
  case 3:
    return "the file is empty";
  default:
    return "no problem";
  }
}

PetscErrorCode CheckReadableFile(MPI_Comm comm, const char opt[], const char path[])
{
  const int problem = FileProblem(path);

  PetscFunctionBeginUser;
  PetscCheck(!problem, comm, PETSC_ERR_FILE_OPEN, "option %s %s: %s", opt, path, FileProblemText(problem));
  PetscFunctionReturn(0);
}

/* The first message of an error is the one that names the cause; PetscCall repeats it up the stack. */
static char first_message[1024];

static PetscErrorCode RecordFirstMessage(MPI_Comm comm, int line, const char *func, const char *file, PetscErrorCode n, PetscErrorType p, const char *mess, void *ctx)
{
  (void)comm;
  (void)ctx;
  if (p == PETSC_ERROR_INITIAL && !first_message[0]) {
    /* our own checks name the option or file; an error raised inside PETSc says where.
       Ours are compiled as src/... (the Makefile's paths); Debian's PETSc as ./src/... */
    const PetscBool ours = file && strncmp(file, "src/", 4) == 0 ? PETSC_TRUE : PETSC_FALSE;
    if (mess && mess[0] && ours) PetscSNPrintf(first_message, sizeof(first_message), "%s", mess);
    else PetscSNPrintf(first_message, sizeof(first_message), "%s (PETSc error %d in %s() at %s:%d)", mess && mess[0] ? mess : "PETSc error", (int)n, func, file, line);
  }
  return n;
}

PetscErrorCode ErrorReportingForget(void)
{
  first_message[0] = 0;
  return 0;
}

PetscErrorCode ErrorReportingPush(void)
{
  PetscFunctionBeginUser;
  PetscCall(PetscPushErrorHandler(RecordFirstMessage, NULL));
  PetscFunctionReturn(0);
}

const char *ErrorReportingFirstMessage(void)
{
  return first_message[0] ? first_message : "unknown error";
}
