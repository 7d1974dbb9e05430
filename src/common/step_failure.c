/* Why a solve inside a time step failed (StepFailure, fsiopt.h), recorded so that the
   time loop can retry the step with a smaller dt; and the failure no smaller dt mends, a
   factorization out of memory. */
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

/* MUMPS that cannot allocate its factors fails the factorization quietly: the linear solve
   then fails, and a retried step would factor a matrix of the same size again. */
PetscErrorCode StepFailureCheckMemory(SNES snes, const char solver[])
{
  KSP            ksp;
  PC             pc;
  PCFailedReason reason = PC_NOERROR;
  PetscBool      out_of_memory;
  MPI_Comm       comm;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)snes, &comm));
  PetscCall(SNESGetKSP(snes, &ksp));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PCGetFailedReasonRank(pc, &reason));
  out_of_memory = reason == PC_FACTOR_OUTMEMORY ? PETSC_TRUE : PETSC_FALSE;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &out_of_memory, 1, MPIU_BOOL, MPI_LOR, comm));
  PetscCheck(!out_of_memory, comm, PETSC_ERR_MEM, "out of memory: the %s's factorization could not allocate its factors",
             solver);
  PetscFunctionReturn(0);
}
