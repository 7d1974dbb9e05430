/* Signals a run answers between steps (interrupt.h): SIGINT, SIGTERM, SIGHUP, the ones batch
   systems and resource limits send before a kill (SIGUSR2, SIGALRM, SIGQUIT, SIGXCPU) and a
   closed pipe end it after the step in progress, SIGUSR1 asks for a checkpoint, SIGXFSZ (a
   file-size limit) is ignored so that the write it stopped fails and is reported as such;
   and the -interrupt_test_* options that raise them at a given step for the tests. */
#include <signal.h>
#include "interrupt.h"
#include "options.h"

/* The signals a run knows by name: those that end it after its step as SIGTERM does, and the
   others -interrupt_test_signal may raise. */
static const struct {
  const char *name;
  int         number;
  PetscBool   stops;
} known[] = {
  {"SIGTERM", SIGTERM, PETSC_TRUE },
  {"SIGINT",  SIGINT,  PETSC_TRUE },
  {"SIGKILL", SIGKILL, PETSC_FALSE},
  {"SIGHUP",  SIGHUP,  PETSC_TRUE },
  {"SIGUSR1", SIGUSR1, PETSC_FALSE},
  {"SIGPIPE", SIGPIPE, PETSC_FALSE},
  {"SIGUSR2", SIGUSR2, PETSC_TRUE },
  {"SIGALRM", SIGALRM, PETSC_TRUE },
  {"SIGQUIT", SIGQUIT, PETSC_TRUE },
  {"SIGXCPU", SIGXCPU, PETSC_TRUE },
  {"SIGXFSZ", SIGXFSZ, PETSC_FALSE}
};

static volatile sig_atomic_t caught      = 0;
static volatile sig_atomic_t requests    = 0; /* SIGUSR1s received */
static int                   answered    = 0; /* of those, the ones InterruptCheck has reported */
static PetscInt              test_step   = 0; /* -interrupt_test_step */
static int                   test_signal = SIGTERM;
static PetscBool             test_failure = PETSC_FALSE; /* -interrupt_test_failure, until it fires */

static void Catch(int signum)
{
  caught = signum;
}

/* every write to the closed pipe raises it again: the first one stops the run, the rest
   leave the writes failing quietly while the run writes its checkpoint and outputs */
static void CatchPipe(int signum)
{
  if (!caught) caught = signum;
}

static void CatchCheckpointRequest(int signum)
{
  (void)signum;
  requests = requests + 1;
}

PetscErrorCode InterruptInstall(void)
{
  struct sigaction action;

  PetscFunctionBeginUser;
  memset(&action, 0, sizeof(action));
  action.sa_handler = Catch;
  action.sa_flags   = SA_RESETHAND; /* the second signal takes the default action */
  sigemptyset(&action.sa_mask);
  /* SIGHUP: the terminal or the batch system's session went away; SIGUSR2, SIGALRM: a batch
     system's warning before its kill; SIGQUIT: a user's; SIGXCPU: the CPU-time limit, whose
     SIGKILL follows: all as a SIGTERM */
  for (size_t i = 0; i < PETSC_STATIC_ARRAY_LENGTH(known); ++i)
    PetscCheck(!known[i].stops || sigaction(known[i].number, &action, NULL) == 0, PETSC_COMM_SELF, PETSC_ERR_SYS,
               "cannot install the handler of %s", known[i].name);
  /* SIGXFSZ: a write past the file-size limit then fails with EFBIG, which the writers report */
  memset(&action, 0, sizeof(action));
  action.sa_handler = SIG_IGN;
  sigemptyset(&action.sa_mask);
  PetscCheck(sigaction(SIGXFSZ, &action, NULL) == 0, PETSC_COMM_SELF, PETSC_ERR_SYS, "cannot ignore SIGXFSZ");
  /* SIGPIPE: whatever read the standard output went away (tee, a log reader), which would
     otherwise end the run at its next line without a checkpoint */
  memset(&action, 0, sizeof(action));
  action.sa_handler = CatchPipe;
  sigemptyset(&action.sa_mask);
  PetscCheck(sigaction(SIGPIPE, &action, NULL) == 0, PETSC_COMM_SELF, PETSC_ERR_SYS,
             "cannot install the SIGPIPE handler");
  memset(&action, 0, sizeof(action));
  action.sa_handler = CatchCheckpointRequest; /* every SIGUSR1 asks again */
  sigemptyset(&action.sa_mask);
  PetscCheck(sigaction(SIGUSR1, &action, NULL) == 0, PETSC_COMM_SELF, PETSC_ERR_SYS,
             "cannot install the SIGUSR1 handler");
  PetscFunctionReturn(0);
}

/* Tests need a signal that lands after a known step, on a loaded machine as on an idle one. */
PetscErrorCode InterruptSetFromOptions(void)
{
  const char *names[PETSC_STATIC_ARRAY_LENGTH(known)];
  PetscInt    which = 0;
  PetscBool         in_setup  = PETSC_FALSE;

  PetscFunctionBeginUser;
  for (size_t i = 0; i < PETSC_STATIC_ARRAY_LENGTH(known); ++i) names[i] = known[i].name;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Signals", "fsiopt");
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-interrupt_test_step",
                              "testing: the process sends itself -interrupt_test_signal after this step (0: never)", 0,
                              PETSC_MAX_INT, &test_step));
  PetscCall(PetscOptionsEList("-interrupt_test_signal", "testing: the signal of -interrupt_test_step", NULL, names,
                              (PetscInt)PETSC_STATIC_ARRAY_LENGTH(names), names[which], &which, NULL));
  PetscCall(PetscOptionsBool("-interrupt_test_failure",
                             "testing: the process sends itself -interrupt_test_signal when a step first fails", NULL,
                             test_failure, &test_failure, NULL));
  PetscCall(PetscOptionsBool("-interrupt_test_setup",
                             "testing: the process sends itself -interrupt_test_signal during its set-up", NULL,
                             in_setup, &in_setup, NULL));
  PetscOptionsEnd();
  test_signal = known[which].number;
  if (in_setup)
    PetscCheck(raise(test_signal) == 0, PETSC_COMM_SELF, PETSC_ERR_SYS,
               "option -interrupt_test_setup: cannot raise the signal");
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

PetscErrorCode InterruptTestAfterFailure(void)
{
  PetscFunctionBeginUser;
  if (!test_failure) PetscFunctionReturn(0);
  test_failure = PETSC_FALSE;
  PetscCheck(raise(test_signal) == 0, PETSC_COMM_SELF, PETSC_ERR_SYS,
             "option -interrupt_test_failure: cannot raise the signal");
  PetscFunctionReturn(0);
}

PetscErrorCode InterruptStopPending(MPI_Comm comm, int *signum)
{
  int local = (int)caught;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Allreduce(&local, signum, 1, MPI_INT, MPI_MAX, comm));
  PetscFunctionReturn(0);
}

PetscErrorCode InterruptCheck(MPI_Comm comm, int *signum, PetscBool *checkpoint)
{
  const int seen     = (int)requests;
  int       local[2] = {(int)caught, seen > answered}, any[2];

  PetscFunctionBeginUser;
  answered = seen;
  PetscCallMPI(MPI_Allreduce(local, any, 2, MPI_INT, MPI_MAX, comm));
  *signum     = any[0];
  *checkpoint = any[1] ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(0);
}

PetscErrorCode InterruptCheckSetUp(const char where[])
{
  int signum = 0, any = 0;

  PetscFunctionBeginUser;
  signum = (int)caught;
  PetscCallMPI(MPI_Allreduce(&signum, &any, 1, MPI_INT, MPI_MAX, PETSC_COMM_WORLD));
  PetscCheck(!any, PETSC_COMM_WORLD, PETSC_ERR_USER, "stopped by %s during the set-up (%s); no step was run",
             InterruptName(any), where);
  PetscFunctionReturn(0);
}

const char *InterruptName(int signum)
{
  for (size_t i = 0; i < PETSC_STATIC_ARRAY_LENGTH(known); ++i)
    if (known[i].number == signum) return known[i].name;
  return "a signal";
}
