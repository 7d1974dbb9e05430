#include <signal.h>
#include "interrupt.h"

static volatile sig_atomic_t caught = 0;

static void Catch(int signum)
{
  caught = signum;
}

PetscErrorCode InterruptInstall(void)
{
  struct sigaction action;

  PetscFunctionBeginUser;
  memset(&action, 0, sizeof(action));
  action.sa_handler = Catch;
  action.sa_flags   = SA_RESETHAND; /* the second signal takes the default action */
  sigemptyset(&action.sa_mask);
  PetscCheck(sigaction(SIGINT, &action, NULL) == 0 && sigaction(SIGTERM, &action, NULL) == 0, PETSC_COMM_SELF, PETSC_ERR_SYS, "cannot install the SIGINT/SIGTERM handler");
  PetscFunctionReturn(0);
}

PetscErrorCode InterruptCheck(MPI_Comm comm, int *signum)
{
  int local = (int)caught;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Allreduce(&local, signum, 1, MPI_INT, MPI_MAX, comm));
  PetscFunctionReturn(0);
}

const char *InterruptName(int signum)
{
  return signum == SIGINT ? "SIGINT" : signum == SIGTERM ? "SIGTERM" : "a signal";
}
