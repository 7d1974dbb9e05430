#ifndef FSIOPT_INTERRUPT_H
#define FSIOPT_INTERRUPT_H
#include <petscsys.h>

/* SIGINT, SIGTERM and SIGHUP end a run after the step in progress: the outputs are
   completed up to that step, summary.json says converged: false and names the signal, and
   the run exits non-zero. A second signal of the same kind stops the process at once.
   SIGUSR1 (what batch systems send before a time limit) asks for a checkpoint after the
   step in progress; the run goes on. */
PetscErrorCode InterruptInstall(void);
/* -interrupt_test_step K, -interrupt_test_signal: a signal the process sends itself after
   step K's outputs (and before the interrupt check of that step), for deterministic tests */
PetscErrorCode InterruptSetFromOptions(void);
PetscErrorCode InterruptTestAfterStep(PetscInt step);
/* The stopping signal any rank has received since the start (0: none), and whether any
   rank received a SIGUSR1 since the last check; collective. */
PetscErrorCode InterruptCheck(MPI_Comm, int *signum, PetscBool *checkpoint);
/* The stopping signal any rank has received since the start (0: none), leaving SIGUSR1's
   requests to InterruptCheck; collective. A failed step asks before it retries. */
PetscErrorCode InterruptStopPending(MPI_Comm, int *signum);
/* -interrupt_test_failure: the signal of -interrupt_test_signal when a step first fails */
PetscErrorCode InterruptTestAfterFailure(void);
const char    *InterruptName(int signum);
/* Installed at the start (main), the handlers hold a stop that comes during the set-up until
   the next of these checks, which end the run with one line (collective on every rank;
   `where`: the part of the set-up done). */
PetscErrorCode InterruptCheckSetUp(const char where[]);
#endif
