/* The run's checkpoint: which options, and which modules' states, in one HDF5 file. */
#include <errno.h>
#include <fcntl.h>
#include <libgen.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include "run_checkpoint.h"
#include "checkpoint.h"
#include "options.h"
#include "output_files.h"
#include "mesh.h"

/* Before the first step: a checkpoint that cannot be written would stop the run at its
   first checkpoint (or at a SIGTERM's), hours in. */
static PetscErrorCode CheckWritable(const char path[], const char output_dir[], PetscBool scheduled)
{
  PetscMPIInt rank;
  int         cause = 0, directory = 0;
  const char *clash = NULL;
  char        tmp[PETSC_MAX_PATH_LEN];

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  if (!rank) {
    struct stat st;
    int         fd;
    PetscBool   owned;
    /* the checkpoint is written beside the file and renamed over it: over a device (/dev/null)
       or a FIFO that would replace the device's node */
    directory = !stat(path, &st) && !S_ISREG(st.st_mode);
    owned     = OutputDirHolds(path, output_dir, &clash);
    /* a killed run's temporary in the directory this run owns goes; elsewhere another run
       may be writing it */
    PetscCall(PetscSNPrintf(tmp, sizeof(tmp), "%s.tmp", path));
    if (owned && !clash && !directory && !access(tmp, F_OK) && !unlink(tmp))
      PetscCall(PetscPrintf(PETSC_COMM_SELF, "fsiopt: removed %s, a killed run's unfinished checkpoint\n", tmp));
    PetscCall(PetscSNPrintf(tmp, sizeof(tmp), "%s.probe.%d", path, (int)getpid()));
    fd = directory || clash ? -1 : open(tmp, O_WRONLY | O_CREAT | O_EXCL, 0644);
    if (fd < 0) cause = errno;
    else {
      (void)close(fd);
      (void)unlink(tmp);
    }
  }
  PetscCallMPI(MPI_Bcast(&directory, 1, MPI_INT, 0, PETSC_COMM_WORLD));
  PetscCheck(!directory, PETSC_COMM_WORLD, PETSC_ERR_FILE_OPEN,
             "option -checkpoint_file %s: a directory, device or FIFO; expected the name of a regular file (written "
             "beside it and renamed over it)",
             path);
  cause = clash ? -1 : cause;
  PetscCallMPI(MPI_Bcast(&cause, 1, MPI_INT, 0, PETSC_COMM_WORLD));
  PetscCheck(cause != -1, PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG,
             "option -checkpoint_file %s: the name of a file the run writes in -output_dir %s; choose another name",
             path, output_dir);
  PetscCheck(!cause, PETSC_COMM_WORLD, PETSC_ERR_FILE_OPEN, "option -checkpoint_file %s: cannot write there (%s)", path,
             strerror(cause));
  if (scheduled) { /* every rank opens the checkpoint (MPI-IO): a directory only the first rank's
                     node sees would fail the first checkpoint, hours in */
    char        copy[PETSC_MAX_PATH_LEN];
    const char *dir;
    PetscMPIInt size, first, mine;
    PetscCall(PetscStrncpy(copy, path, sizeof(copy)));
    dir = dirname(copy);
    PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
    cause = access(dir, W_OK | X_OK) ? errno : 0;
    mine  = cause ? rank : size;
    PetscCallMPI(MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, PETSC_COMM_WORLD));
    if (first < size) {
      PetscCallMPI(MPI_Bcast(&cause, 1, MPI_INT, first, PETSC_COMM_WORLD));
      SETERRQ(PETSC_COMM_WORLD, PETSC_ERR_FILE_OPEN,
              "option -checkpoint_file %s: rank %d cannot write in %s (%s); every rank writes the checkpoint: put it "
              "on a file system all the run's nodes share",
              path, (int)first, dir, strerror(cause));
    }
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode DefaultFile(const RunParams *params, char file[], size_t len)
{
  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(file, len, "%s/checkpoint.h5", params->output_dir));
  PetscFunctionReturn(0);
}

PetscErrorCode RunCheckpointLock(const RunParams *params)
{
  char        file[PETSC_MAX_PATH_LEN];
  const char *clash;
  PetscBool   own;

  PetscFunctionBeginUser;
  PetscCall(DefaultFile(params, file, sizeof(file)));
  PetscCall(PetscOptionsGetString(NULL, NULL, "-checkpoint_file", file, sizeof(file), NULL));
  own = OutputDirHolds(file, params->output_dir, &clash);
  PetscCall(OutputLockTakeFile(PETSC_COMM_WORLD, "-checkpoint_file", file, "checkpoint file", own));
  PetscFunctionReturn(0);
}

PetscErrorCode RunCheckpointSetFromOptions(const RunParams *params, PetscInt structure_ranks, PetscBool restartable,
                                           RunCheckpointParams *cp)
{
  PetscFunctionBeginUser;
  cp->every           = 0;
  cp->structure_ranks = structure_ranks;
  cp->last            = -1;
  cp->restart[0]      = 0;
  cp->change_dt       = PETSC_FALSE;
  cp->change[0]       = 0;
  PetscCall(DefaultFile(params, cp->file, sizeof(cp->file)));
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Checkpoints and restarts", "fsiopt");
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-checkpoint_every", "write the state every K steps (0: never)", 0,
                              PETSC_MAX_INT, &cp->every));
  PetscCall(PetscOptionsString("-checkpoint_file", "where (HDF5; written to FILE.tmp, then renamed)", NULL, cp->file,
                               cp->file, sizeof(cp->file), NULL));
  PetscCall(PetscOptionsString("-restart", "continue from this checkpoint", NULL, cp->restart, cp->restart,
                               sizeof(cp->restart), &cp->restarting));
  PetscCall(
    PetscOptionsBool("-restart_change_dt",
                     "the -restart checkpoint may have been written with another dt: go on at -dt from its time "
                     "(a whole number of steps of -dt after -t_start) as a retried step does (BDF2 starts with "
                     "one backward-Euler step, the extrapolated start is dropped)",
                     NULL, cp->change_dt, &cp->change_dt, NULL));
  PetscCall(
    PetscOptionsString("-restart_change",
                       "options (a,b,...) that define the problem and may differ from the -restart checkpoint's "
                       "(a restart otherwise refuses any: it would compute another problem from the old history)",
                       NULL, cp->change, cp->change, sizeof(cp->change), NULL));
  PetscOptionsEnd();
  PetscCheck(!cp->change_dt || cp->restarting, PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG,
             "option -restart_change_dt: expected with -restart FILE");
  PetscCheck(!cp->change[0] || cp->restarting, PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG,
             "option -restart_change: expected with -restart FILE");
  cp->possible = restartable;
  /* with -checkpoint_every, and for the checkpoint a SIGTERM or SIGUSR1 writes */
  if ((cp->every || cp->possible) && !OptionsHelpRequested())
    PetscCall(CheckWritable(cp->file, params->output_dir, cp->every ? PETSC_TRUE : PETSC_FALSE));
  PetscFunctionReturn(0);
}

/* The step of this run's dt that ends at the checkpoint's time (written with dt_written). */
static PetscErrorCode StepAtNewTimeStep(const char path[], PetscInt step_written, PetscReal dt_written,
                                        const RunParams *params, PetscInt *step)
{
  const PetscReal elapsed = step_written * dt_written, ratio = elapsed / params->dt;

  PetscFunctionBeginUser;
  *step = (PetscInt)PetscFloorReal(ratio + 0.5);
  PetscCheck(PetscAbsReal(ratio - *step) < 1e-6 * PetscMax(1.0, ratio), PETSC_COMM_WORLD, PETSC_ERR_ARG_INCOMP,
             "option -restart_change_dt: the checkpoint %s ends at t = %g, %g after -t_start, which is not a whole "
             "number of steps of -dt %g",
             path, (double)(params->t_start + elapsed), (double)elapsed, (double)params->dt);
  PetscFunctionReturn(0);
}

PetscErrorCode RunCheckpointSetLayouts(RunCheckpointParams *cp, Fluid fluid, Structure structure)
{
  DM dm;

  PetscFunctionBeginUser;
  /* on fluid | structure ranks, each side's from its ranks */
  cp->layouts[0] = cp->layouts[1] = PETSC_MIN_REAL;
  if (fluid) {
    PetscCall(FluidGetDM(fluid, &dm));
    PetscCall(MeshLayoutSignature(dm, &cp->layouts[0]));
  }
  if (structure) {
    PetscCall(StructureGetDM(structure, &dm));
    PetscCall(MeshLayoutSignature(dm, &cp->layouts[1]));
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, cp->layouts, 2, MPIU_REAL, MPIU_MAX, PETSC_COMM_WORLD));
  for (PetscInt k = 0; k < 2; ++k)
    if (cp->layouts[k] == PETSC_MIN_REAL) cp->layouts[k] = 0;
  PetscFunctionReturn(0);
}

/* The meshes' splits and numberings, which the vectors of the file are stored in: a restart
   must have the same (the same mesh, ranks and partitioner). */
static PetscErrorCode CheckpointLayouts(Checkpoint cp, const char path[], PetscBool load,
                                        const RunCheckpointParams *cpp)
{
  const char *names[2] = {"fluid_layout", "structure_layout"};

  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < 2; ++k) {
    PetscReal written = cpp->layouts[k];
    PetscCall(CheckpointReal(cp, names[k], &written, load));
    PetscCheck(PetscAbsReal(written - cpp->layouts[k]) <= 1e-10 * PetscMax(1.0, PetscAbsReal(cpp->layouts[k])),
               PETSC_COMM_WORLD, PETSC_ERR_ARG_INCOMP,
               "option -restart %s: written with another split or numbering of the %s mesh on these ranks (another "
               "mesh, partitioner or PETSc); restart with the set-up that wrote it",
               path, k ? "structure" : "fluid");
  }
  PetscFunctionReturn(0);
}

/* The split of the ranks the states are stored from; a checkpoint without it was written
   before a split could write one, on every rank. */
static PetscErrorCode CheckpointStructureRanks(Checkpoint cp, const char path[], PetscBool load,
                                               const RunCheckpointParams *cpp)
{
  PetscInt  written = cpp->structure_ranks;
  PetscBool has     = PETSC_TRUE;

  PetscFunctionBeginUser;
  if (load) PetscCall(CheckpointHasAttribute(cp, "structure_ranks", &has));
  if (has) PetscCall(CheckpointInt(cp, "structure_ranks", &written, load));
  else written = 0;
  PetscCheck(written == cpp->structure_ranks, PETSC_COMM_WORLD, PETSC_ERR_ARG_INCOMP,
             "option -restart %s: written with -structure_ranks %" PetscInt_FMT ", this run has %" PetscInt_FMT
             " (restart on the layout that wrote it: add -structure_ranks %" PetscInt_FMT ")",
             path, written, cpp->structure_ranks, written);
  PetscFunctionReturn(0);
}

/* The times the modules' groups record against the step /run records: each was written
   from the same state, so they agree to round-off (each module adds its dt step by step).
   A checksum does not see a file whose values were changed with their checksums, or one an
   fsiopt without checksums wrote and that was damaged since; disagreeing times are refused
   before the state is read. */
static PetscErrorCode CheckpointTimesAgree(Checkpoint cp, const char path[], PetscInt step, PetscReal dt,
                                           PetscReal t_start)
{
  const char *groups[2] = {"/fluid", "/structure"};
  PetscReal   t         = t_start + step * dt;

  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < 2; ++k) {
    PetscBool group, has_time, has_step = PETSC_FALSE;
    PetscReal time        = t;
    PetscInt  module_step = step;
    PetscCall(CheckpointHasGroup(cp, groups[k], &group));
    if (!group) continue;
    PetscCall(CheckpointPushGroup(cp, groups[k]));
    PetscCall(CheckpointHasAttribute(cp, "time", &has_time));
    if (has_time) PetscCall(CheckpointReal(cp, "time", &time, PETSC_TRUE));
    if (!k) PetscCall(CheckpointHasAttribute(cp, "step", &has_step));
    if (has_step) PetscCall(CheckpointInt(cp, "step", &module_step, PETSC_TRUE));
    PetscCall(CheckpointPopGroup(cp));
    PetscCheck(module_step == step, PETSC_COMM_WORLD, PETSC_ERR_FILE_UNEXPECTED,
               "option -restart %s: its attributes disagree: step %" PetscInt_FMT " in /run, %" PetscInt_FMT
               " in %s (damaged)",
               path, step, module_step, groups[k]);
    /* a millionth of a step: far above the round-off of a sum of steps, far below a step */
    PetscCheck(PetscAbsReal(time - t) <= 1e-6 * dt + 1e-12 * PetscAbsReal(t), PETSC_COMM_WORLD,
               PETSC_ERR_FILE_UNEXPECTED,
               "option -restart %s: its attributes disagree: time in %s is %.16g, step %" PetscInt_FMT
               " in /run ends at t = t_start + step dt = %.16g (damaged)",
               path, groups[k], (double)time, step, (double)t);
  }
  PetscFunctionReturn(0);
}

#define FINGERPRINT_LEN 65536

/* On fluid | structure ranks each side's state is a part of the file its ranks write alone. */
static PetscErrorCode ModulesCheckpoint(Checkpoint cp, PetscBool load, Fluid fluid, Structure structure,
                                        Coupling coupling, Probes probes, FieldWriter fields)
{
  DM dm;

  PetscFunctionBeginUser;
  if (fluid) PetscCall(FluidGetDM(fluid, &dm));
  PetscCall(CheckpointBeginPart(cp, fluid ? PetscObjectComm((PetscObject)dm) : MPI_COMM_NULL));
  PetscCall(CheckpointEndPart(cp, fluid ? FluidCheckpoint(fluid, cp, load) : 0));
  if (structure) PetscCall(StructureGetDM(structure, &dm));
  PetscCall(CheckpointBeginPart(cp, structure ? PetscObjectComm((PetscObject)dm) : MPI_COMM_NULL));
  PetscCall(CheckpointEndPart(cp, structure ? StructureCheckpoint(structure, cp, load) : 0));
  if (coupling) PetscCall(CouplingCheckpoint(coupling, cp, load));
  if (probes) PetscCall(ProbesCheckpoint(probes, cp, load));
  PetscCall(FieldWriterCheckpoint(fields, cp, load));
  PetscFunctionReturn(0);
}

PetscErrorCode RunCheckpoint(const char path[], PetscBool load, PetscInt *step, const RunParams *params,
                             const RunCheckpointParams *cpp, const RunSummary *summary, Fluid fluid,
                             Structure structure, Coupling coupling, Probes probes, FieldWriter fields, StepRetry retry)
{
  Checkpoint cp;
  PetscReal  dt = params->dt, t_start = params->t_start;
  PetscInt   dofs[2] = {summary->fluid_dofs, summary->structure_dofs}, fluid_dofs, structure_dofs,
           ranks = summary->total_ranks;
  PetscBool  has_fingerprint = PETSC_TRUE, other_dt, unchecked;
  char      *fingerprint, *written;

  PetscFunctionBeginUser;
  /* on fluid | structure ranks each side counts its own */
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, dofs, 2, MPIU_INT, MPI_MAX, PETSC_COMM_WORLD));
  fluid_dofs     = dofs[0];
  structure_dofs = dofs[1];
  PetscCall(CheckpointOpen(PETSC_COMM_WORLD, path, load, &cp));
  PetscCall(CheckpointPushGroup(cp, "/run"));
  PetscCall(CheckpointInt(cp, "step", step, load));
  PetscCall(CheckpointReal(cp, "dt", &dt, load));
  PetscCheck(!load || (PetscIsNormalReal(dt) && dt > 0), PETSC_COMM_WORLD, PETSC_ERR_FILE_UNEXPECTED,
             "option -restart %s: its time step dt = %g is not a positive number (damaged)", path, (double)dt);
  PetscCall(CheckpointReal(cp, "t_start", &t_start, load));
  PetscCheck(!load || !PetscIsInfOrNanReal(t_start), PETSC_COMM_WORLD, PETSC_ERR_FILE_UNEXPECTED,
             "option -restart %s: its t_start is not a number (damaged)", path);
  PetscCall(CheckpointInt(cp, "fluid_dofs", &fluid_dofs, load));
  PetscCall(CheckpointInt(cp, "structure_dofs", &structure_dofs, load));
  PetscCall(CheckpointInt(cp, "ranks", &ranks, load));
  PetscCall(CheckpointStructureRanks(cp, path, load, cpp));
  PetscCall(CheckpointLayouts(cp, path, load, cpp));
  PetscCall(PetscMalloc2(FINGERPRINT_LEN, &fingerprint, FINGERPRINT_LEN, &written));
  PetscCall(RunFingerprint(fingerprint, FINGERPRINT_LEN));
  PetscCall(PetscStrncpy(written, fingerprint, FINGERPRINT_LEN));
  if (load) PetscCall(CheckpointHasAttribute(cp, "problem_options", &has_fingerprint));
  PetscCheck(has_fingerprint, PETSC_COMM_WORLD, PETSC_ERR_FILE_UNEXPECTED,
             "option -restart %s: the checkpoint does not record the options of the problem it belongs to "
             "(attribute problem_options of /run; damaged, or written by an older fsiopt): nothing to check a "
             "restart against",
             path);
  PetscCall(CheckpointString(cp, "problem_options", written, FINGERPRINT_LEN, load));
  PetscCall(CheckpointPopGroup(cp));
  if (load) PetscCall(CheckpointTimesAgree(cp, path, *step, dt, t_start));
  other_dt = load && PetscAbsReal(dt - params->dt) > 1e-12 * params->dt ? PETSC_TRUE : PETSC_FALSE;
  if (load) {
    PetscCheck(!other_dt || cpp->change_dt, PETSC_COMM_WORLD, PETSC_ERR_ARG_INCOMP,
               "option -restart %s: written with dt = %g, this run has -dt %g (add -restart_change_dt to go on at "
               "the new dt)",
               path, (double)dt, (double)params->dt);
    PetscCheck(PetscAbsReal(t_start - params->t_start) <= 1e-12 * PetscMax(1.0, PetscAbsReal(t_start)),
               PETSC_COMM_WORLD, PETSC_ERR_ARG_INCOMP,
               "option -restart %s: written with t_start = %g, this run has -t_start %g", path, (double)t_start,
               (double)params->t_start);
    PetscCheck(!other_dt || !fields, PETSC_COMM_WORLD, PETSC_ERR_ARG_INCOMP,
               "option -restart_change_dt: not with -write_fields (the fields written are listed by steps of the "
               "checkpoint's dt %g)",
               (double)dt);
    PetscCheck(fluid_dofs == dofs[0] && structure_dofs == dofs[1], PETSC_COMM_WORLD,
               PETSC_ERR_ARG_INCOMP,
               "option -restart %s: written for %" PetscInt_FMT " fluid and %" PetscInt_FMT
               " structure unknowns, this run has %" PetscInt_FMT " and %" PetscInt_FMT " (another scene or mesh)",
               path, fluid_dofs, structure_dofs, dofs[0], dofs[1]);
    PetscCheck(ranks == summary->total_ranks, PETSC_COMM_WORLD, PETSC_ERR_ARG_INCOMP,
               "option -restart %s: written on %" PetscInt_FMT
               " ranks, this run has %d (the meshes' distribution must be the same)",
               path, ranks, (int)summary->total_ranks);
    PetscCall(RunFingerprintCompare(path, written, fingerprint, cpp->change));
    if (other_dt) PetscCall(StepAtNewTimeStep(path, *step, dt, params, step));
    PetscCheck(*step >= 0 && *step < params->steps, PETSC_COMM_WORLD, PETSC_ERR_ARG_INCOMP,
               "option -restart %s: it ends step %" PetscInt_FMT
               ", expected a step before this run's last (%" PetscInt_FMT ")",
               path, *step, params->steps);
  }
  /* the modules' states belong to the checkpoint's dt; the next step leaves it as a retried step does */
  if (other_dt) PetscCall(StepRetrySetTimeStep(retry, dt));
  if (load) PetscCall(ModulesCheckpoint(cp, PETSC_TRUE, fluid, structure, coupling, probes, fields));
  else {
    /* a write that fails (a full disk) closes the file before it returns the error */
    PetscErrorCode ierr;
    PetscCall(PetscPushErrorHandler(PetscReturnErrorHandler, NULL));
    ierr = ModulesCheckpoint(cp, PETSC_FALSE, fluid, structure, coupling, probes, fields);
    if (ierr) (void)CheckpointDestroy(&cp);
    PetscCall(PetscPopErrorHandler());
    if (ierr) {
      PetscCall(PetscFree2(fingerprint, written));
      return ierr;
    }
  }
  unchecked = load && !CheckpointHasChecksums(cp);
  PetscCall(CheckpointClose(PETSC_COMM_WORLD, path, load, &cp));
  PetscCall(PetscFree2(fingerprint, written));
  /* accepted: refusing would end the runs whose last checkpoint an fsiopt without checksums
     wrote; the file's damage shows only if it breaks the checks of type, shape and times */
  if (unchecked)
    PetscCall(PetscPrintf(PETSC_COMM_WORLD,
                          "fsiopt: warning: option -restart %s: the checkpoint has no checksums (written by an fsiopt "
                          "without them): its values are read unchecked\n",
                          path));
  if (other_dt) {
    PetscCall(StepRetrySetTimeStep(retry, params->dt));
    PetscCall(PetscPrintf(PETSC_COMM_WORLD,
                          "fsiopt: -restart_change_dt: the checkpoint's dt %g becomes -dt %g at step %" PetscInt_FMT
                          " (t = %g)\n",
                          (double)dt, (double)params->dt, *step, (double)(params->t_start + *step * params->dt)));
  }
  PetscFunctionReturn(0);
}
