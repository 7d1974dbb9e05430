/* The run's checkpoint: which options, and which modules' states, in one HDF5 file. */
#include "run_checkpoint.h"
#include "checkpoint.h"
#include "options.h"

PetscErrorCode RunCheckpointSetFromOptions(const RunParams *params, PetscBool separate_ranks, PetscBool restartable,
                                           RunCheckpointParams *cp)
{
  PetscFunctionBeginUser;
  cp->every      = 0;
  cp->last       = -1;
  cp->restart[0] = 0;
  PetscCall(PetscSNPrintf(cp->file, sizeof(cp->file), "%s/checkpoint.h5", params->output_dir));
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Checkpoints and restarts", "fsiopt");
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-checkpoint_every", "write the state every K steps (0: never)", 0,
                              PETSC_MAX_INT, &cp->every));
  PetscCall(PetscOptionsString("-checkpoint_file", "where (HDF5; written to FILE.tmp, then renamed)", NULL, cp->file,
                               cp->file, sizeof(cp->file), NULL));
  PetscCall(PetscOptionsString("-restart", "continue from this checkpoint", NULL, cp->restart, cp->restart,
                               sizeof(cp->restart), &cp->restarting));
  PetscOptionsEnd();
  PetscCheck(!(cp->every || cp->restarting) || !separate_ranks, PETSC_COMM_WORLD, PETSC_ERR_SUP,
             "option %s: checkpoints need fluid and structure on the same ranks (-structure_ranks 0)",
             cp->restarting ? "-restart" : "-checkpoint_every");
  cp->possible = !separate_ranks && restartable ? PETSC_TRUE : PETSC_FALSE;
  PetscFunctionReturn(0);
}

PetscErrorCode RunCheckpoint(const char path[], PetscBool load, PetscInt *step, const RunParams *params,
                             const RunSummary *summary, Fluid fluid, Structure structure, Coupling coupling,
                             Probes probes, FieldWriter fields)
{
  Checkpoint cp;
  PetscReal  dt         = params->dt;
  PetscInt   fluid_dofs = summary->fluid_dofs, structure_dofs = summary->structure_dofs, ranks = summary->total_ranks;

  PetscFunctionBeginUser;
  PetscCall(CheckpointOpen(PETSC_COMM_WORLD, path, load, &cp));
  PetscCall(CheckpointPushGroup(cp, "/run"));
  PetscCall(CheckpointInt(cp, "step", step, load));
  PetscCall(CheckpointReal(cp, "dt", &dt, load));
  PetscCall(CheckpointInt(cp, "fluid_dofs", &fluid_dofs, load));
  PetscCall(CheckpointInt(cp, "structure_dofs", &structure_dofs, load));
  PetscCall(CheckpointInt(cp, "ranks", &ranks, load));
  PetscCall(CheckpointPopGroup(cp));
  if (load) {
    PetscCheck(PetscAbsReal(dt - params->dt) <= 1e-12 * params->dt, PETSC_COMM_WORLD, PETSC_ERR_ARG_INCOMP,
               "option -restart %s: written with dt = %g, this run has -dt %g", path, (double)dt, (double)params->dt);
    PetscCheck(fluid_dofs == summary->fluid_dofs && structure_dofs == summary->structure_dofs, PETSC_COMM_WORLD,
               PETSC_ERR_ARG_INCOMP,
               "option -restart %s: written for %" PetscInt_FMT " fluid and %" PetscInt_FMT
               " structure unknowns, this run has %" PetscInt_FMT " and %" PetscInt_FMT " (another scene or mesh)",
               path, fluid_dofs, structure_dofs, summary->fluid_dofs, summary->structure_dofs);
    PetscCheck(ranks == summary->total_ranks, PETSC_COMM_WORLD, PETSC_ERR_ARG_INCOMP,
               "option -restart %s: written on %" PetscInt_FMT
               " ranks, this run has %d (the meshes' distribution must be the same)",
               path, ranks, (int)summary->total_ranks);
    PetscCheck(*step >= 0 && *step < params->steps, PETSC_COMM_WORLD, PETSC_ERR_ARG_INCOMP,
               "option -restart %s: it ends step %" PetscInt_FMT
               ", expected a step before this run's last (%" PetscInt_FMT ")",
               path, *step, params->steps);
  }
  if (fluid) PetscCall(FluidCheckpoint(fluid, cp, load));
  if (structure) PetscCall(StructureCheckpoint(structure, cp, load));
  if (coupling) PetscCall(CouplingCheckpoint(coupling, cp, load));
  if (probes) PetscCall(ProbesCheckpoint(probes, cp, load));
  PetscCall(FieldWriterCheckpoint(fields, cp, load));
  PetscCall(CheckpointClose(PETSC_COMM_WORLD, path, load, &cp));
  PetscFunctionReturn(0);
}
