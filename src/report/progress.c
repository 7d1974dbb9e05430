/* Progress lines (progress.h): a long run shows how far it is and when it will end. */
#include <time.h>
#include "progress.h"
#include "options.h"

struct _p_Progress {
  MPI_Comm         comm;
  PetscBool        quiet;
  PetscInt         interval; /* steps between lines; 0: by wall time */
  PetscReal        seconds;  /* wall time between lines when interval is 0 */
  const RunParams *params;
  PetscInt         first_step;
  PetscLogDouble   start, last_line;
  PetscInt         last_iterations; /* the coupling's total before this step */
};

PetscErrorCode ProgressCreate(MPI_Comm comm, Progress *progress)
{
  Progress p;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&p));
  p->comm    = comm;
  p->seconds = 2;
  PetscOptionsBegin(comm, NULL, "Progress lines while the run goes", "fsiopt");
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-progress_interval",
                              "a progress line every K steps (0: about every -progress_seconds of wall time)", 0,
                              PETSC_MAX_INT, &p->interval));
  PetscCall(OptionsPositiveReal(PetscOptionsObject, "-progress_seconds",
                                "with -progress_interval 0: wall time between progress lines, s", &p->seconds));
  PetscCall(
    PetscOptionsBool("-quiet", "print no progress lines (the final report only)", NULL, p->quiet, &p->quiet, NULL));
  PetscOptionsEnd();
  *progress = p;
  PetscFunctionReturn(0);
}

static PetscErrorCode Flush(MPI_Comm comm)
{
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (!rank) fflush(PETSC_STDOUT); /* a batch job's log is a file: lines must reach it as they are printed */
  PetscFunctionReturn(0);
}

PetscErrorCode ProgressStart(Progress p, const RunParams *params, PetscInt first_step, PetscInt fluid_dofs,
                             PetscInt structure_dofs, const char method[], PetscMPIInt structure_ranks)
{
  PetscInt    dofs[2] = {fluid_dofs, structure_dofs};
  PetscMPIInt size;
  char        sides[320] = "", layout[64] = "";

  PetscFunctionBeginUser;
  p->params     = params;
  p->first_step = first_step;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, dofs, 2, MPIU_INT, MPI_MAX, p->comm));
  PetscCallMPI(MPI_Comm_size(p->comm, &size));
  PetscCall(PetscTime(&p->start));
  p->last_line = p->start;
  if (p->quiet) PetscFunctionReturn(0);
  if (dofs[0] && dofs[1])
    PetscCall(PetscSNPrintf(sides, sizeof(sides),
                            "fluid %" PetscInt_FMT " and structure %" PetscInt_FMT " unknowns, coupling %s", dofs[0],
                            dofs[1], method));
  else
    PetscCall(PetscSNPrintf(sides, sizeof(sides), "%s %" PetscInt_FMT " unknowns", dofs[0] ? "fluid" : "structure",
                            dofs[0] ? dofs[0] : dofs[1]));
  if (structure_ranks > 0 && structure_ranks < size)
    PetscCall(PetscSNPrintf(layout, sizeof(layout), " (%d fluid | %d structure)", (int)(size - structure_ranks),
                            (int)structure_ranks));
  PetscCall(
    PetscPrintf(p->comm,
                "fsiopt: %s: %s on %d rank%s%s; steps %" PetscInt_FMT " to %" PetscInt_FMT " of dt %g (t = %g to %g)\n",
                params->scene, sides, (int)size, size > 1 ? "s" : "", layout, first_step, params->steps,
                (double)params->dt,
                (double)(params->t_start + (first_step - 1) * params->dt), (double)params->t_final));
  PetscCall(Flush(p->comm));
  PetscFunctionReturn(0);
}

static void Clock(PetscLogDouble seconds, char text[], size_t len)
{
  const long s = (long)(seconds + 0.5);

  if (s >= 3600) (void)PetscSNPrintf(text, len, "%ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
  else (void)PetscSNPrintf(text, len, "%ld:%02ld", s / 60, s % 60);
}

PetscErrorCode ProgressStep(Progress p, PetscInt step, Coupling coupling)
{
  PetscLogDouble now;
  PetscBool      due;
  CouplingStats  stats = {0};
  const PetscInt done = step - p->first_step + 1, left = p->params->steps - step;
  char           wall[32], eta[32], coupled[160] = "";

  PetscFunctionBeginUser;
  if (coupling) PetscCall(CouplingGetStats(coupling, &stats));
  PetscCall(PetscTime(&now));
  /* rank 0's clock decides: only rank 0 prints, and no rank waits for another */
  due = p->interval ? (step % p->interval == 0) : (now - p->last_line >= p->seconds);
  if (coupling && due)
    PetscCall(
      PetscSNPrintf(coupled, sizeof(coupled), ", coupling iterations %" PetscInt_FMT " (%.2f per step), jump %.2e",
                    stats.iterations - p->last_iterations, (double)stats.iterations / done, (double)stats.last_jump));
  p->last_iterations = stats.iterations;
  if (!due || p->quiet || step == p->params->steps) PetscFunctionReturn(0);
  p->last_line = now;
  Clock(now - p->start, wall, sizeof(wall));
  Clock((now - p->start) / done * left, eta, sizeof(eta));
  PetscCall(PetscPrintf(p->comm, "fsiopt: step %" PetscInt_FMT "/%" PetscInt_FMT ", t = %.6g%s, wall %s, ETA %s\n",
                        step, p->params->steps, (double)(p->params->t_start + step * p->params->dt), coupled, wall,
                        eta));
  PetscCall(Flush(p->comm));
  PetscFunctionReturn(0);
}

PetscErrorCode ProgressDestroy(Progress *progress)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(*progress));
  PetscFunctionReturn(0);
}
