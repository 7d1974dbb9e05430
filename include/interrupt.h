#ifndef FSIOPT_INTERRUPT_H
#define FSIOPT_INTERRUPT_H
#include <petscsys.h>

/* SIGINT and SIGTERM end a run after the step in progress: the outputs are completed up
   to that step, summary.json says converged: false and names the signal, and the run
   exits non-zero. A second signal of the same kind stops the process at once. */
PetscErrorCode InterruptInstall(void);
/* -interrupt_test_step K, -interrupt_test_signal: a signal the process sends itself after
   step K's outputs (and before the interrupt check of that step), for deterministic tests */
PetscErrorCode InterruptSetFromOptions(void);
PetscErrorCode InterruptTestAfterStep(PetscInt step);
/* The signal any rank has received since the start (0: none); collective. */
PetscErrorCode InterruptCheck(MPI_Comm, int *signum);
const char    *InterruptName(int signum);
#endif
