/* fsiopt: fluid-structure interaction by optimization-based decoupling.
   main reads like the table of contents: a run is set up (src/run/setup.c), advanced
   (advance.c) and reported (report.c); errors end it with one line. */
#include <signal.h>
#include <string.h>
#include <sys/resource.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <unistd.h>
#include "run.h"
#include "checkpoint.h"
#include "options.h"
#include "error_reporting.h"
#include "output_files.h"
#include "help.h"
#include "interrupt.h"

static const char
  usage[] = "fsiopt: fluid-structure interaction by optimization-based decoupling.\n"
           "  fsiopt -options_file options/<scene>.yaml [options]   or   fsiopt -scene <name> [options]\n"
           "Meshes: -fluid_dm_plex_* and -structure_dm_plex_* (box meshes, or gmsh files with *_dm_plex_filename).\n"
           "Solvers: -fluid_snes_*, -fluid_ksp_*, -fluid_pc_*, -structure_snes_*, ...\n\n";

/* Set when every rank stops on the same error (a failed step, an interrupt): no abort is
   needed to end them. */
static PetscBool collective_stop = PETSC_FALSE;

static PetscErrorCode RunMain(void)
{
  Run            run;
  PetscErrorCode code;
  const char    *why;
  char           stop[2 * PETSC_MAX_PATH_LEN + 1024] = "";

  PetscFunctionBeginUser;
  PetscCall(RunCreate(&run));
  if (!run) PetscFunctionReturn(0);
  PetscCall(RunAdvance(run));
  PetscCall(RunReport(run));
  PetscCall(RunGetStop(run, &code, &why));
  if (why) PetscCall(PetscStrncpy(stop, why, sizeof(stop)));
  collective_stop = why ? PETSC_TRUE : PETSC_FALSE;
  PetscCall(RunDestroy(&run));
  PetscCheck(!stop[0], PETSC_COMM_WORLD, code, "%s", stop);
  PetscFunctionReturn(0);
}

/* Ranks that stop on an error meet here; a rank that did not fail never comes. */
static MPI_Comm error_comm = MPI_COMM_NULL;

/* Whether every rank stopped on the error (the same check on all of them, or a stop they
   agreed on): a barrier of the failed ranks that completes within a few seconds. */
static PetscBool EveryRankStopped(MPI_Comm comm)
{
  MPI_Request     barrier;
  int             done  = 0;
  struct timespec pause = {0, 10000000}; /* 10 ms */

  if (comm == MPI_COMM_NULL || MPI_Ibarrier(comm, &barrier) != MPI_SUCCESS) return PETSC_FALSE;
  for (int waited = 0; waited < 300 && !done; ++waited) { /* 3 s */
    if (MPI_Test(&barrier, &done, MPI_STATUS_IGNORE) != MPI_SUCCESS) return PETSC_FALSE;
    if (!done) nanosleep(&pause, NULL);
  }
  return done ? PETSC_TRUE : PETSC_FALSE;
}

/* Whether this process is the job's first rank, before MPI runs: the launcher says (Open MPI,
   or a PMI launcher such as srun); without one it is the only rank. */
static int FirstRank(void)
{
  const char *rank = getenv("OMPI_COMM_WORLD_RANK") ? getenv("OMPI_COMM_WORLD_RANK") : getenv("PMI_RANK");

  return !rank || !strcmp(rank, "0");
}

/* On the first rank only: PETSc reads the options files there and hands their options to the
   others, so a file the other ranks cannot see (a node's local disk) serves the run, and a
   rank that failed alone would end it with no line at all (MPI is not running yet, so it
   could not say so to the first; the launcher says which rank we are). */
static int CheckOptionsFiles(int argc, char **argv)
{
  char message[8192];

  if (!FirstRank()) return 0;
  if (!OptionsFilesCheck(argc, argv, message, sizeof(message))) return 0;
  fprintf(stderr, "fsiopt: error: %s\n", message);
  return 1;
}

/* Under an address-space limit (ulimit -v) below what a run needs to start, OpenBLAS's first
   call waits forever for the buffers it reserves (and MPI's start-up fails with its own
   lines): one line instead. 400 MiB hung in OpenBLAS on channel2d, 512 MiB started it. */
#define MIN_ADDRESS_SPACE_MIB 512

static int CheckAddressSpace(void)
{
  struct rlimit limit;

  if (getrlimit(RLIMIT_AS, &limit) || limit.rlim_cur == RLIM_INFINITY ||
      limit.rlim_cur >= (rlim_t)MIN_ADDRESS_SPACE_MIB << 20)
    return 0;
  if (FirstRank())
    fprintf(stderr,
            "fsiopt: error: the address-space limit (ulimit -v) is %lu MiB; fsiopt needs at least %d MiB to start (MPI, "
            "BLAS and PETSc reserve that much), more for its meshes and factors\n",
            (unsigned long)(limit.rlim_cur >> 20), MIN_ADDRESS_SPACE_MIB);
  return 1;
}

/* -help [all] on the command line, taken out of it: PETSc would print its banner and its
   general options during PetscInitialize, before fsiopt's, and a reader that stops early
   (fsiopt -help | head) could meet PETSc's signal handler there. Returns 0 (none), 1
   (fsiopt's options) or 2 (and PETSc's). "-help intro" stays PETSc's. */
static int TakeHelp(int *argc, char **argv)
{
  int mode = 0, out = 1;

  for (int i = 1; i < *argc; ++i) {
    if (!strcmp(argv[i], "-help") || !strcmp(argv[i], "--help")) {
      const char *value = i + 1 < *argc ? argv[i + 1] : NULL;
      if (value && !strcmp(value, "intro")) return 0;
      mode = 1;
      if (value && (!strcmp(value, "all") || !strcmp(value, "petsc"))) {
        mode = 2;
        ++i;
      }
      continue;
    }
    argv[out++] = argv[i];
  }
  if (mode) {
    *argc       = out;
    argv[*argc] = NULL;
  }
  return mode;
}

int main(int argc, char **argv)
{
  PetscErrorCode ierr;
  int            help;

  if (CheckAddressSpace() || CheckOptionsFiles(argc, argv)) return 1;
  help = TakeHelp(&argc, argv);
  /* the listing's reader may go away: its writes then fail quietly, and the set-up, which
     runs no step, ends as usual */
  if (help) signal(SIGPIPE, SIG_IGN);
  /* PT-Scotch's threads split a mesh differently from run to run; a checkpoint's vectors,
     stored in the partition's ordering, need the same split at the restart (mesh.c) */
  setenv("SCOTCH_PTHREAD_NUMBER", "1", 1);
  /* MPI-IO (the checkpoints' HDF5) through ROMIO (any Open MPI version's) unless the user chose: Open MPI's OMPIO
     prints its own line on a failed write, and its shared-file-pointer component leaves
     semaphores behind when a writing run is killed */
  setenv("OMPI_MCA_io", "^ompio", 0);
  ierr = PetscInitialize(&argc, &argv, NULL, usage);
  if (ierr) return 1;
  if (help) {
    if (PetscOptionsSetValue(NULL, "-help", NULL)) return 1;
    HelpListingSetPETSc(help == 2 ? PETSC_TRUE : PETSC_FALSE);
  }
  /* a stop during the set-up ends it with one line (PETSc's own handler would catch SIGHUP
     with its banner, and SIGTERM and SIGINT would kill the run without a word) */
  if (InterruptInstall()) return 1;
  if (help) signal(SIGPIPE, SIG_IGN);
  MPI_Comm_dup(PETSC_COMM_WORLD, &error_comm);
  ierr = ErrorReportingPush();
  if (!ierr) ierr = RunMain();
  if (ierr) {
    PetscMPIInt rank, size;
    PetscBool   every_rank = PETSC_TRUE;
    MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
    MPI_Comm_size(PETSC_COMM_WORLD, &size);
    HelpListingCaptureAbandon();
    if (size > 1 && !collective_stop) every_rank = EveryRankStopped(error_comm);
    OutputRemoveSetUpFiles();
    if (every_rank) OutputLockRelease();
    if (!every_rank) {
      /* the others wait in a call this rank will not make: it says why and ends the job
         (the launcher stops the other ranks). An error every rank of a subcommunicator
         raised (the structure's ranks of a split run) is said by its first rank only. */
      MPI_Comm    comm      = ErrorReportingFirstComm();
      PetscMPIInt comm_rank = 0, comm_size = 1;
      if (comm != MPI_COMM_NULL && MPI_Comm_size(comm, &comm_size) == MPI_SUCCESS && comm_size > 1 &&
          EveryRankStopped(comm))
        MPI_Comm_rank(comm, &comm_rank);
      if (!comm_rank) fprintf(stderr, "fsiopt: error: rank %d: %s\n", (int)rank, ErrorReportingFirstMessage());
      OutputLockReleaseForJob();
      fflush(stderr);
      fflush(stdout);
      _exit(1);
    }
    if (!rank) fprintf(stderr, "fsiopt: error: %s\n", ErrorReportingFirstMessage());
    fflush(stderr);
    if (OutputHDF5Failed()) {
      fflush(stdout);
      _exit(1);
    }
    PetscFinalize();
    return 1;
  }
  ierr = PetscPopErrorHandler();
  if (!ierr) ierr = PetscFinalize();
  return ierr ? 1 : 0;
}
