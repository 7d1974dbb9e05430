#ifndef FSIOPT_RUN_IMPL_H
#define FSIOPT_RUN_IMPL_H
#include "run.h"
#include "fsiopt.h"
#include "scene.h"
#include "fluid.h"
#include "structure.h"
#include "interface.h"
#include "coupling.h"
#include "step_outputs.h"
#include "summary.h"
#include "run_checkpoint.h"
#include "step_retry.h"
#include "progress.h"

/* The objects of a run (setup.c), what the time loop did (advance.c), and the report
   (report.c). Fluid and structure are NULL on the ranks that do not hold them. */
struct _p_Run {
  RunParams           params;
  Scene               scene;
  RunSummary          summary;
  PetscBool           help, coupled;
  MPI_Comm            fluid_comm, structure_comm;
  Fluid               fluid;
  Structure           structure;
  Interface           itf;
  CouplingProblem     problem;
  Coupling            coupling;
  StepOutputs         outputs;
  StepRetry           retry;
  Progress            progress;
  RunCheckpointParams checkpoint;
  PetscInt            first_step;
  PetscLogDouble      start;
  /* how the time loop ended */
  const char    *failure;       /* the step that failed with the smallest dt, NULL: none */
  int            signal_caught; /* 0: none */
  char           stop_reason[2 * PETSC_MAX_PATH_LEN + 1024];
  PetscErrorCode stop_code;
};

/* -check_rank_sync on the fluid's and the structure's communicators (rank_sync.h) */
PetscErrorCode RunCheckRankSync(Run, const char when[]);
#endif
