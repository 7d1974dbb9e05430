/* A run's set-up (run.h): the run options, the ranks' layout, the scene and its solvers,
   the coupling, the outputs, a restart; and the run's destruction. */
#include <time.h>
#include "run_impl.h"
#include "output_files.h"
#include "help.h"
#include "fem_ceed.h"
#include "options.h"
#include "logging.h"
#include "mesh.h"
#include "interrupt.h"
#include "rank_sync.h"
#include "pc_ilu_baij.h"

static PetscErrorCode RunParamsSetFromOptions(RunParams *p)
{
  char scenes[256], methods[256], help[300];

  PetscFunctionBeginUser;
  PetscCall(SceneListNames(scenes, sizeof(scenes)));
  PetscCall(CouplingListNames(methods, sizeof(methods)));
  PetscCall(PetscSNPrintf(help, sizeof(help), "Coupling method for scenes with fluid and structure: %s", methods));
  p->refine  = 0;
  p->dt      = 0.01;
  p->t_start = 0.0;
  p->t_final = 0.1;
  PetscCall(PetscStrncpy(p->coupling, "opt", sizeof(p->coupling)));
  PetscCall(OptionsDeclareUnit("-dt", UNIT_TIME));
  PetscCall(OptionsDeclareUnit("-t_start", UNIT_TIME));
  PetscCall(OptionsDeclareUnit("-t_final", UNIT_TIME));
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "fsiopt run options", "fsiopt");
  PetscCall(PetscOptionsString("-scene", scenes, NULL, p->scene, p->scene, sizeof(p->scene), NULL));
  PetscCall(PetscOptionsString("-coupling", help, NULL, p->coupling, p->coupling, sizeof(p->coupling), NULL));
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-refine", "uniform refinements of every mesh", 0, 10, &p->refine));
  PetscCall(OptionsPositiveReal(PetscOptionsObject, "-dt", "time step", &p->dt));
  PetscCall(OptionsNonNegativeReal(PetscOptionsObject, "-t_start", "initial time", &p->t_start));
  PetscCall(OptionsPositiveReal(PetscOptionsObject, "-t_final", "final time", &p->t_final));
  PetscCall(PetscSNPrintf(p->output_dir, sizeof(p->output_dir), "out/%s", p->scene));
  PetscCall(PetscOptionsString("-output_dir", "directory for summary.json and the other outputs (default out/<scene>)",
                               NULL, p->output_dir, p->output_dir, sizeof(p->output_dir), NULL));
  PetscOptionsEnd();
  PetscCall(CouplingCheckMethod(p->coupling));
  PetscCheck(p->t_final > p->t_start, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
             "option -t_final: expected a time after -t_start (%g), got %g", (double)p->t_start, (double)p->t_final);
  {
    const PetscReal ratio = (p->t_final - p->t_start) / p->dt;
    p->steps              = (PetscInt)PetscFloorReal(ratio + 0.5);
    PetscCheck(p->steps >= 1 && PetscAbsReal(ratio - p->steps) < 1e-6 * PetscMax(1.0, ratio), PETSC_COMM_WORLD,
               PETSC_ERR_ARG_OUTOFRANGE,
               "option -dt: expected a step that divides t_final - t_start = %g into whole steps, got %g",
               (double)(p->t_final - p->t_start), (double)p->dt);
  }
  PetscFunctionReturn(0);
}

/* -structure_ranks' default: the whole ranks the structure's share of the unknowns fills,
   floor(P n_s / (n_f + n_s)), the unknowns counted on the meshes as read (MeshCountDofs)
   before either side is made; 0 (both on every rank) where that share is less than a rank.
   On the current domain, every scene's default, a split lets the two sides' linearized
   solves overlap but not their nonlinear ones, and a structure rank with less than its
   share of work idles: on 2 ranks tube3d level 1 ran 24.3 s split and 22.2 s shared
   (docs/coupling-and-solvers.md). */
static PetscErrorCode SizedStructureRanks(Run run, PetscMPIInt size, PetscInt *K)
{
  Fluid      fluid;
  Structure  structure;
  MeshFields fields;
  PetscInt   nfaces, faces[2 * FSIOPT_MAX_BOUNDARIES];
  PetscReal  dofs[2];

  PetscFunctionBeginUser;
  PetscCall(FluidCreate(PETSC_COMM_WORLD, &fluid));
  PetscCall(FluidSetFromOptions(fluid));
  if (run->scene.fluid.n_fixed_mesh_faces) PetscCall(FluidEnableMeshMotion(fluid));
  PetscCall(FluidGetMeshFields(fluid, &fields));
  PetscCall(FluidDestroy(&fluid));
  PetscCall(SceneRequiredFaces(&run->scene.fluid, &nfaces, faces));
  PetscCall(MeshCountDofs(PETSC_COMM_WORLD, "fluid_", run->params.refine, run->scene.dim, nfaces, faces, &fields,
                          &dofs[0]));
  PetscCall(StructureCreate(PETSC_COMM_WORLD, &structure));
  PetscCall(StructureSetFromOptions(structure));
  PetscCall(StructureGetMeshFields(structure, &fields));
  PetscCall(StructureDestroy(&structure));
  PetscCall(SceneRequiredFaces(&run->scene.structure, &nfaces, faces));
  PetscCall(MeshCountDofs(PETSC_COMM_WORLD, "structure_", run->params.refine, run->scene.dim, nfaces, faces, &fields,
                          &dofs[1]));
  *K = 0;
  if (dofs[0] > 0 && dofs[1] > 0) *K = (PetscInt)PetscFloorReal(size * dofs[1] / (dofs[0] + dofs[1]));
  *K = PetscMin(PetscMax(*K, 0), size - 1);
  PetscFunctionReturn(0);
}

/* Fluid ranks first, then structure ranks (-structure_ranks K); K = 0, or one rank,
   puts both on every rank, one after the other. */
static PetscErrorCode SplitRanks(Run run)
{
  RunSummary *s = &run->summary;
  PetscMPIInt size, rank;
  PetscInt    K = 0;
  PetscBool   given;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  PetscCall(PetscOptionsHasName(NULL, NULL, "-structure_ranks", &given));
  if (!given && run->coupled && size > 1 && !run->help) PetscCall(SizedStructureRanks(run, size, &K));
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Parallel layout", "fsiopt");
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-structure_ranks",
                              "ranks of the structure, the rest go to the fluid (0: both on all ranks; default: the "
                              "whole ranks the structure's share of the unknowns fills, else 0)",
                              0, size - 1, &K));
  PetscOptionsEnd();
  run->fluid_comm     = PETSC_COMM_WORLD;
  run->structure_comm = PETSC_COMM_WORLD;
  s->fluid_ranks      = size;
  s->structure_ranks  = size;
  s->total_ranks      = size;
  if (!run->coupled || K == 0) PetscFunctionReturn(0);
  {
    const PetscMPIInt is_structure = rank >= size - K;
    MPI_Comm          sub;

    PetscCallMPI(MPI_Comm_split(PETSC_COMM_WORLD, is_structure, rank, &sub));
    run->fluid_comm     = is_structure ? MPI_COMM_NULL : sub;
    run->structure_comm = is_structure ? sub : MPI_COMM_NULL;
    s->fluid_ranks      = size - (PetscMPIInt)K;
    s->structure_ranks  = (PetscMPIInt)K;
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode FluidFromScene(Run run, DM *mesh)
{
  PetscInt   nfaces, faces[2 * FSIOPT_MAX_BOUNDARIES];
  MeshFields fields;

  PetscFunctionBeginUser;
  PetscCall(FluidCreate(run->fluid_comm, &run->fluid));
  PetscCall(FluidSetFromOptions(run->fluid));
  if (run->coupled) {
    ControlVariant variant;
    PetscCall(CouplingProblemGetControlVariant(&variant));
    PetscCall(FluidSetInterface(run->fluid, run->scene.fluid.interface_face,
                                variant == CONTROL_CONVECTIVE ? PETSC_TRUE : PETSC_FALSE));
    if (run->scene.fluid.n_fixed_mesh_faces) PetscCall(FluidEnableMeshMotion(run->fluid));
  }
  PetscCall(SceneRequiredFaces(&run->scene.fluid, &nfaces, faces));
  PetscCall(FluidGetMeshFields(run->fluid, &fields));
  PetscCall(MeshCreate(run->fluid_comm, "fluid_", run->params.refine, run->scene.dim, nfaces, faces, &fields, mesh));
  PetscCall(FluidSetUp(run->fluid, *mesh, &run->scene.fluid, run->params.t_start, run->params.dt));
  PetscCall(FluidGetInfo(run->fluid, &run->summary.dim, &run->summary.fluid_dofs));
  PetscFunctionReturn(0);
}

static PetscErrorCode StructureFromScene(Run run, DM *mesh)
{
  PetscInt   nfaces, faces[2 * FSIOPT_MAX_BOUNDARIES];
  MeshFields fields;

  PetscFunctionBeginUser;
  PetscCall(StructureCreate(run->structure_comm, &run->structure));
  PetscCall(StructureSetFromOptions(run->structure));
  PetscCall(SceneRequiredFaces(&run->scene.structure, &nfaces, faces));
  PetscCall(StructureGetMeshFields(run->structure, &fields));
  PetscCall(
    MeshCreate(run->structure_comm, "structure_", run->params.refine, run->scene.dim, nfaces, faces, &fields, mesh));
  PetscCall(StructureSetUp(run->structure, *mesh, &run->scene.structure, run->params.t_start, run->params.dt));
  PetscCall(StructureGetInfo(run->structure, &run->summary.dim, &run->summary.structure_dofs));
  PetscFunctionReturn(0);
}

/* The checkpoint options, and the state of a restart (else the initial outputs). */
/* -ceed_check_spaces: the libCEED bridge (src/ceed/) checked on this run's spaces */
static PetscErrorCode CheckCeedSpaces(Run run)
{
  PetscBool check = PETSC_FALSE;
  DM        dm;

  PetscFunctionBeginUser;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "libCEED operators", "fem");
  PetscCall(PetscOptionsBool("-ceed_check_spaces",
                             "assemble the mass and Laplacian of every finite-element space with libCEED and compare "
                             "them with PETSc's (stops above 1e-12 relative)",
                             NULL, check, &check, NULL));
  PetscOptionsEnd();
  if (!check) PetscFunctionReturn(0);
  if (run->fluid) {
    PetscCall(FluidGetDM(run->fluid, &dm));
    PetscCall(FEMCeedCheckSpaces(dm, "fluid", 1e-12));
  }
  if (run->structure) {
    PetscCall(StructureGetDM(run->structure, &dm));
    PetscCall(FEMCeedCheckSpaces(dm, "structure", 1e-12));
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckpointOrStart(Run run)
{
  PetscBool restartable = PETSC_TRUE, restart,
            separate = run->coupled && (run->fluid_comm != PETSC_COMM_WORLD || run->structure_comm != PETSC_COMM_WORLD);
  Probes      probes;
  FieldWriter fields;

  PetscFunctionBeginUser;
  if (run->coupling) PetscCall(CouplingIsRestartable(run->coupling, &restartable));
  PetscCall(StepOutputsGetProbes(run->outputs, &probes));
  PetscCall(StepOutputsGetFields(run->outputs, &fields));
  PetscCall(RunCheckpointSetFromOptions(&run->params, separate ? run->summary.structure_ranks : 0, restartable,
                                        &run->checkpoint));
  if (!run->help) PetscCall(OutputCheckViewerFiles(PETSC_COMM_WORLD, run->params.output_dir, run->checkpoint.file));
  restart = run->checkpoint.restarting && !run->help;
  if (run->checkpoint.possible) PetscCall(RunCheckpointSetLayouts(&run->checkpoint, run->fluid, run->structure));
  run->first_step = 1;
  if (restart) {
    PetscInt restart_step = 0;
    PetscCall(RunCheckpoint(run->checkpoint.restart, PETSC_TRUE, &restart_step, &run->params, &run->checkpoint,
                            &run->summary, run->fluid, run->structure, run->coupling, probes, fields, run->retry));
    run->first_step = restart_step + 1;
  }
  PetscCall(StepOutputsOpen(run->outputs));
  if (!restart) PetscCall(StepOutputsRecord(run->outputs, 0));
  PetscFunctionReturn(0);
}

/* When and where, for summary.json */
static PetscErrorCode RecordStart(RunSummary *s)
{
  const time_t now = time(NULL);
  struct tm    utc;

  PetscFunctionBeginUser;
  if (gmtime_r(&now, &utc)) (void)strftime(s->start_time, sizeof(s->start_time), "%Y-%m-%dT%H:%M:%SZ", &utc);
  PetscCall(PetscGetHostName(s->host, sizeof(s->host)));
  PetscFunctionReturn(0);
}

PetscErrorCode RunCheckRankSync(Run run, const char when[])
{
  DM dm;

  PetscFunctionBeginUser;
  if (run->fluid) PetscCall(FluidGetDM(run->fluid, &dm));
  if (run->fluid) PetscCall(RankSyncCheck((PetscObject)dm, "fluid", when));
  if (run->structure) PetscCall(StructureGetDM(run->structure, &dm));
  if (run->structure) PetscCall(RankSyncCheck((PetscObject)dm, "structure", when));
  PetscFunctionReturn(0);
}

PetscErrorCode RunCreate(Run *created)
{
  Run       run;
  PetscBool scene_given;
  DM        fluid_mesh = NULL, structure_mesh = NULL;

  PetscFunctionBeginUser;
  *created = NULL;
  PetscCall(PetscNew(&run));
  run->fluid_comm     = MPI_COMM_NULL;
  run->structure_comm = MPI_COMM_NULL;
  PetscCall(PetscTime(&run->start));
  PetscCall(RecordStart(&run->summary));
  run->stop_code = PETSC_ERR_NOT_CONVERGED;
  PetscCall(LoggingRegister());
  PetscCall(PCRegisterILUBAIJ());
  PetscCall(SceneRegisterAll());
  PetscCall(CouplingRegisterAll());
  PetscCall(OptionsCheckValuesGiven(PETSC_COMM_WORLD));
  run->help = OptionsHelpRequested();
  PetscCall(HelpListingBegin());
  PetscCall(HelpListingCaptureBegin());
  PetscCall(PetscOptionsGetString(NULL, NULL, "-scene", run->params.scene, sizeof(run->params.scene), &scene_given));
  if (!scene_given) {
    char names[256];
    PetscCall(SceneListNames(names, sizeof(names)));
    PetscCheck(run->help, PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG,
               "option -scene: expected a scene name (%s), or an options file that sets it", names);
    PetscCall(PetscPrintf(PETSC_COMM_WORLD,
                          "Scenes: %s. Add -scene <name> to -help to see the scene's and the solvers' options.\n",
                          names));
    PetscCall(HelpListingEnd(NULL));
    PetscCall(RunDestroy(&run));
    PetscFunctionReturn(0);
  }
  *created = run;

  PetscCall(PetscLogStagePush(FSIOPT_STAGE_SETUP));
  /* the scene first: it sets its defaults, -dt and -t_final among them */
  PetscCall(SceneCreate(run->params.scene, &run->scene));
  PetscCall(RunParamsSetFromOptions(&run->params));
  if (!run->help) PetscCall(OutputLockTake(PETSC_COMM_WORLD, run->params.output_dir));
  if (!run->help) PetscCall(RunCheckpointLock(&run->params));
  PetscCall(InterruptSetFromOptions());
  run->coupled = run->scene.has_fluid && run->scene.has_structure;
  PetscCall(InterruptCheckSetUp("options read"));
  PetscCall(SplitRanks(run));
  if (run->scene.has_fluid && run->fluid_comm != MPI_COMM_NULL) PetscCall(FluidFromScene(run, &fluid_mesh));
  if (run->scene.has_structure && run->structure_comm != MPI_COMM_NULL)
    PetscCall(StructureFromScene(run, &structure_mesh));
  PetscCall(InterruptCheckSetUp("meshes and solvers made"));
  if (run->coupled) {
    PetscCall(PetscLogEventBegin(FSIOPT_EVENT_INTERFACE, 0, 0, 0, 0));
    PetscCall(InterfaceCreate(PETSC_COMM_WORLD, fluid_mesh, run->scene.fluid.interface_face, structure_mesh,
                              run->scene.structure.interface_face, &run->itf));
    PetscCall(
      CouplingProblemCreate(PETSC_COMM_WORLD, run->fluid, run->structure, run->itf, &run->scene.fluid, &run->problem));
    PetscCall(CouplingCreate(run->params.coupling, run->problem, run->params.output_dir, run->params.t_start,
                             run->params.dt, &run->coupling));
    PetscCall(PetscLogEventEnd(FSIOPT_EVENT_INTERFACE, 0, 0, 0, 0));
  }
  PetscCall(StepOutputsCreate(&run->params, &run->scene, run->summary.dim, run->fluid, run->structure, run->itf,
                              run->problem, &run->outputs));
  PetscCall(StepRetryCreate(&run->params, run->fluid, run->structure, run->coupling, &run->retry));
  PetscCall(CheckCeedSpaces(run));
  PetscCall(ProgressCreate(PETSC_COMM_WORLD, &run->progress));
  PetscCall(InterruptCheckSetUp("coupling and outputs made"));
  PetscCall(CheckpointOrStart(run));
  PetscCall(InterruptCheckSetUp("initial state made"));
  PetscCall(RunCheckRankSync(run, "the set-up"));
  PetscCall(DMDestroy(&fluid_mesh));
  PetscCall(DMDestroy(&structure_mesh));
  PetscCall(PetscLogStagePop());
  PetscCall(HelpListingCaptureEnd());
  if (!run->help) PetscCall(OptionsCheckUnused(PETSC_COMM_WORLD, PETSC_FALSE));
  if (run->help) {
    /* every object has read its options by now: the listing is complete */
    PetscCall(HelpListingEnd(run->scene.units));
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "fsiopt: -help: the options above; no time step was run\n"));
    run->params.steps = 0;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode RunGetStop(Run run, PetscErrorCode *code, const char **reason)
{
  PetscFunctionBeginUser;
  *code   = run->stop_code;
  *reason = run->stop_reason[0] ? run->stop_reason : NULL;
  PetscFunctionReturn(0);
}

PetscErrorCode RunDestroy(Run *destroyed)
{
  Run run = *destroyed;

  PetscFunctionBeginUser;
  if (!run) PetscFunctionReturn(0);
  PetscCall(StepRetryDestroy(&run->retry));
  PetscCall(ProgressDestroy(&run->progress));
  PetscCall(CouplingDestroy(&run->coupling));
  PetscCall(StepOutputsDestroy(&run->outputs));
  PetscCall(CouplingProblemDestroy(&run->problem));
  PetscCall(InterfaceDestroy(&run->itf));
  PetscCall(FluidDestroy(&run->fluid));
  PetscCall(StructureDestroy(&run->structure));
  if (run->fluid_comm != PETSC_COMM_WORLD && run->fluid_comm != MPI_COMM_NULL)
    PetscCallMPI(MPI_Comm_free(&run->fluid_comm));
  if (run->structure_comm != PETSC_COMM_WORLD && run->structure_comm != MPI_COMM_NULL)
    PetscCallMPI(MPI_Comm_free(&run->structure_comm));
  PetscCall(SceneFinalize());
  PetscCall(CouplingFinalize());
  PetscCall(PetscFree(*destroyed));
  OutputLockRelease();
  PetscFunctionReturn(0);
}
