#include <signal.h>
#include "interrupt.h"

static volatile sig_atomic_t caught      = 0;
static PetscInt              test_step   = 0; /* -interrupt_test_step */
static int                   test_signal = SIGTERM;

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
  PetscCheck(sigaction(SIGINT, &action, NULL) == 0 && sigaction(SIGTERM, &action, NULL) == 0, PETSC_COMM_SELF,
             PETSC_ERR_SYS, "cannot install the SIGINT/SIGTERM handler");
  PetscFunctionReturn(0);
}

/* Tests need a signal that lands after a known step, on a loaded machine as on an idle one. */
PetscErrorCode InterruptSetFromOptions(void)
{
  const char *const names[]   = {"SIGTERM", "SIGINT", "SIGKILL"};
  const int         numbers[] = {SIGTERM, SIGINT, SIGKILL};
  PetscInt          which     = 0;

  PetscFunctionBeginUser;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Signals", "fsiopt");
  PetscCall(PetscOptionsInt("-interrupt_test_step",
                            "testing: the process sends itself -interrupt_test_signal after this step (0: never)", NULL,
                            test_step, &test_step, NULL));
  PetscCall(PetscOptionsEList("-interrupt_test_signal", "testing: the signal of -interrupt_test_step", NULL, names, 3,
                              names[which], &which, NULL));
  PetscOptionsEnd();
  test_signal = numbers[which];
  PetscFunctionReturn(0);
}

PetscErrorCode InterruptTestAfterStep(PetscInt step)
{
  PetscFunctionBeginUser;
  if (test_step > 0 && step == test_step)
    PetscCheck(raise(test_signal) == 0, PETSC_COMM_SELF, PETSC_ERR_SYS,
               "option -interrupt_test_step: cannot raise the signal");
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
