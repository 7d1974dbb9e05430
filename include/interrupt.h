#ifndef FSIOPT_INTERRUPT_H
#define FSIOPT_INTERRUPT_H
#include <petscsys.h>

/* SIGINT and SIGTERM end a run after the step in progress: the outputs are completed up
   to that step, summary.json says converged: false and names the signal, and the run
   exits non-zero. A second signal of the same kind stops the process at once. */
PetscErrorCode InterruptInstall(void);
/* The signal any rank has received since the start (0: none); collective. */
PetscErrorCode InterruptCheck(MPI_Comm, int *signum);
const char    *InterruptName(int signum);
#endif
