/* One-line error reporting (error_reporting.h): the first message of an error, the one that
   names its cause, is kept in place of PETSc's traceback banner, with the option named
   where PETSc's message names only its value; and the error of the first rank that failed
   shared by all ranks. */
#include "error_reporting.h"
#include "option_pairs.h"
#include "memory_estimate.h"
#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The first message names the cause; PetscCall repeats it up the stack. */
static char     first_message[1024];
static MPI_Comm first_comm = MPI_COMM_NULL;

/* PETSc's reading of a value names the value, not the option: "Input string water has no
   numeric value". The options whose value it is, from the database. */
static PetscBool NameTheOption(const char *mess, char out[], size_t len)
{
  static const struct {
    const char *before, *after, *expected;
  } forms[] = {
    {"Input string ",           " has no numeric value", "a number"               },
    {"Input string ",           " has no integer value", "an integer (no . in it)"},
    {"Unknown logical value: ", "",                      "true or false"          },
  };
  for (size_t f = 0; f < sizeof(forms) / sizeof(*forms); ++f) {
    const size_t nb = strlen(forms[f].before);
    const char  *value, *end;
    char        *all = NULL, names[512] = "";
    OptionPairs *pairs;
    size_t       nv;

    if (strncmp(mess, forms[f].before, nb)) continue;
    value = mess + nb;
    end   = forms[f].after[0] ? strstr(value, forms[f].after) : value + strlen(value);
    if (!end) continue;
    nv = (size_t)(end - value);
    if (PetscOptionsGetAll(NULL, &all) || !(pairs = (OptionPairs *)calloc(1, sizeof(*pairs)))) {
      PetscFree(all);
      return PETSC_FALSE;
    }
    OptionPairsParse(all, pairs);
    for (PetscInt i = 0; i < pairs->n; ++i) {
      /* a list is read item by item: "0.1,0.2" holds "0.1" */
      const char *v     = pairs->value[i];
      PetscBool   holds = pairs->value_len[i] == nv && !strncmp(v, value, nv) ? PETSC_TRUE : PETSC_FALSE;
      for (const char *c = v; !holds && c < v + pairs->value_len[i]; ++c)
        if ((c == v || c[-1] == ',') && !strncmp(c, value, nv) && (c + nv == v + pairs->value_len[i] || c[nv] == ','))
          holds = PETSC_TRUE;
      if (holds && strlen(names) + pairs->name_len[i] + 6 < sizeof(names)) {
        if (names[0]) strcat(names, " or ");
        strncat(names, pairs->name[i], pairs->name_len[i]);
      }
    }
    free(pairs);
    PetscFree(all);
    if (!names[0]) return PETSC_FALSE;
    snprintf(out, len, "option %s: expected %s, got '%.*s'", names, forms[f].expected, (int)nv, value);
    return PETSC_TRUE;
  }
  return PETSC_FALSE;
}

/* An allocation that failed says so (PETSc's malloc, MUMPS's workspace, rather than only the
   library's function), with the estimate the run was admitted by and what to change. */
static void OutOfMemory(char out[], size_t len, const char what[])
{
  snprintf(out, len,
           "out of memory: %s; this rank's estimate was %.3g GiB (memory_gib in summary.json of a run that "
           "completes): use more nodes, fewer cells, or the iterative solvers of options/solvers/",
           what, (double)(MemoryEstimateThisRank() / 1073741824.0));
}

static PetscBool NameTheMemory(int n, const char *func, const char *mess, char out[], size_t len)
{
  static const char *const mumps_memory[] = {"INFOG(1)=-8", "INFOG(1)=-9", "INFOG(1)=-13", "INFOG(1)=-14",
                                             "INFOG(1)=-15", "INFOG(1)=-17", "INFOG(1)=-19", "INFOG(1)=-20"};
  const char              *what           = NULL;
  char                     where[512];

  if (n == PETSC_ERR_MEM || (func && (!strcmp(func, "PetscMallocAlign") || !strcmp(func, "PetscReallocAlign"))))
    what = "an allocation failed";
  for (size_t i = 0; !what && mess && i < sizeof(mumps_memory) / sizeof(*mumps_memory); ++i) {
    const char *at = strstr(mess, mumps_memory[i]);
    if (at && !isdigit((unsigned char)at[strlen(mumps_memory[i])])) what = "MUMPS's workspace could not be allocated";
  }
  if (!what) return PETSC_FALSE;
  snprintf(where, sizeof(where), "%s (%s in %s())", what, mess && mess[0] ? mess : "PETSc error", func ? func : "?");
  OutOfMemory(out, len, where);
  return PETSC_TRUE;
}

static PetscErrorCode RecordFirstMessage(MPI_Comm comm, int line, const char *func, const char *file, PetscErrorCode n,
                                         PetscErrorType p, const char *mess, void *ctx)
{
  (void)ctx;
  if (p == PETSC_ERROR_INITIAL && !first_message[0]) {
    /* our own checks name the option or file; an error raised inside PETSc says where.
       Ours are compiled as src/... (the Makefile's paths); Debian's PETSc as ./src/... */
    const PetscBool ours = file && strncmp(file, "src/", 4) == 0 ? PETSC_TRUE : PETSC_FALSE;
    first_comm           = comm;
    if (mess && ours && !strncmp(mess, "out of memory: ", 15)) OutOfMemory(first_message, sizeof(first_message), mess + 15);
    else if (mess && mess[0] && ours) PetscSNPrintf(first_message, sizeof(first_message), "%s", mess);
    else if (NameTheMemory((int)n, func, mess, first_message, sizeof(first_message))) (void)0;
    else if (!(mess && NameTheOption(mess, first_message, sizeof(first_message))))
      PetscSNPrintf(first_message, sizeof(first_message), "%s (PETSc error %d in %s() at %s:%d)",
                    mess && mess[0] ? mess : "PETSc error", (int)n, func, file, line);
  }
  return n;
}

MPI_Comm ErrorReportingFirstComm(void)
{
  return first_comm;
}

PetscErrorCode ErrorReportingForget(void)
{
  first_message[0] = 0;
  first_comm       = MPI_COMM_NULL;
  return 0;
}

PetscErrorCode ErrorReportingAgree(MPI_Comm comm, PetscErrorCode ierr)
{
  PetscMPIInt rank, size, mine, first;
  int         code = (int)ierr;
  char        message[sizeof(first_message)];

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  mine = ierr ? rank : size;
  PetscCallMPI(MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm));
  if (first == size) PetscFunctionReturn(0);
  PetscCall(PetscStrncpy(message, ErrorReportingFirstMessage(), sizeof(message)));
  PetscCallMPI(MPI_Bcast(message, (PetscMPIInt)sizeof(message), MPI_CHAR, first, comm));
  PetscCallMPI(MPI_Bcast(&code, 1, MPI_INT, first, comm));
  PetscCall(ErrorReportingForget());
  SETERRQ(comm, (PetscErrorCode)code, "%s", message);
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
