/* fsiopt: fluid-structure interaction by optimization-based decoupling.
   main reads like the table of contents: options, scene, meshes, solvers, time loop,
   report. */
#include <stdio.h>
#include "fsiopt.h"
#include "options.h"
#include "logging.h"
#include "scene.h"
#include "mesh.h"
#include "fluid.h"
#include "structure.h"
#include "summary.h"
#include "interface.h"
#include "coupling.h"
#include "probes.h"
#include "fields.h"
#include "interrupt.h"
#include "run_checkpoint.h"
#include "step_retry.h"

static const char help[] = "fsiopt: fluid-structure interaction by optimization-based decoupling.\n"
                           "  fsiopt -options_file options/<scene>.yaml [options]   or   fsiopt -scene <name> [options]\n"
                           "Meshes: -fluid_dm_plex_* and -structure_dm_plex_* (box meshes, or gmsh files with *_dm_plex_filename).\n"
                           "Solvers: -fluid_snes_*, -fluid_ksp_*, -fluid_pc_*, -structure_snes_*, ...\n\n";

static const char *const coupling_methods[] = {"opt", "dn", "aitken", "iqnils"};

static PetscErrorCode RunParamsSetFromOptions(RunParams *p)
{
  char     names[256];
  PetscInt coupling = 0;

  PetscFunctionBeginUser;
  PetscCall(SceneListNames(names, sizeof(names)));
  p->refine  = 0;
  p->dt      = 0.01;
  p->t_start = 0.0;
  p->t_final = 0.1;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "fsiopt run options", "fsiopt");
  PetscCall(PetscOptionsString("-scene", names, NULL, p->scene, p->scene, sizeof(p->scene), NULL));
  PetscCall(PetscOptionsEList("-coupling", "Coupling method (for scenes with fluid and structure)", NULL, coupling_methods, 4, coupling_methods[0], &coupling, NULL));
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-refine", "uniform refinements of every mesh", 0, 10, &p->refine));
  PetscCall(OptionsPositiveReal(PetscOptionsObject, "-dt", "time step", &p->dt));
  PetscCall(OptionsNonNegativeReal(PetscOptionsObject, "-t_start", "initial time", &p->t_start));
  PetscCall(OptionsPositiveReal(PetscOptionsObject, "-t_final", "final time", &p->t_final));
  PetscCall(PetscSNPrintf(p->output_dir, sizeof(p->output_dir), "out/%s", p->scene));
  PetscCall(PetscOptionsString("-output_dir", "directory for summary.json and the other outputs (default out/<scene>)", NULL, p->output_dir, p->output_dir, sizeof(p->output_dir), NULL));
  PetscOptionsEnd();
  PetscCall(PetscStrncpy(p->coupling, coupling_methods[coupling], sizeof(p->coupling)));
  PetscCheck(p->t_final > p->t_start, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE, "option -t_final: expected a time after -t_start (%g), got %g", (double)p->t_start, (double)p->t_final);
  {
    const PetscReal ratio = (p->t_final - p->t_start) / p->dt;
    p->steps              = (PetscInt)PetscFloorReal(ratio + 0.5);
    PetscCheck(p->steps >= 1 && PetscAbsReal(ratio - p->steps) < 1e-6 * PetscMax(1.0, ratio), PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE, "option -dt: expected a step that divides t_final - t_start = %g into whole steps, got %g", (double)(p->t_final - p->t_start), (double)p->dt);
  }
  PetscFunctionReturn(0);
}

/* Fluid ranks first, then structure ranks (-structure_ranks K); K = 0, or one rank,
   puts both on every rank, one after the other. */
static PetscErrorCode SplitRanks(PetscBool coupled, MPI_Comm *fluid_comm, MPI_Comm *structure_comm, PetscMPIInt *fluid_ranks, PetscMPIInt *structure_ranks)
{
  PetscMPIInt size, rank;
  PetscInt    K = 0;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Parallel layout", "fsiopt");
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-structure_ranks", "ranks of the structure, the rest go to the fluid (0: both on all ranks)", 0, size - 1, &K));
  PetscOptionsEnd();
  *fluid_comm      = PETSC_COMM_WORLD;
  *structure_comm  = PETSC_COMM_WORLD;
  *fluid_ranks     = size;
  *structure_ranks = size;
  if (!coupled || K == 0) PetscFunctionReturn(0);
  {
    const PetscMPIInt is_structure = rank >= size - K;
    MPI_Comm          sub;

    PetscCallMPI(MPI_Comm_split(PETSC_COMM_WORLD, is_structure, rank, &sub));
    *fluid_comm      = is_structure ? MPI_COMM_NULL : sub;
    *structure_comm  = is_structure ? sub : MPI_COMM_NULL;
    *fluid_ranks     = size - (PetscMPIInt)K;
    *structure_ranks = (PetscMPIInt)K;
  }
  PetscFunctionReturn(0);
}

/* Rank 0 writes the summary; the structure's numbers live on the structure's ranks. */
static PetscErrorCode ShareWithAll(void *buffer, size_t bytes, PetscMPIInt root)
{
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Bcast(buffer, (int)bytes, MPI_BYTE, root, PETSC_COMM_WORLD));
  PetscFunctionReturn(0);
}

/* probes.csv: the displacement at the scene's probe points (on the interface of a coupled
   run, in the structure of a structure alone) and the force on the fluid's body faces. */
static PetscErrorCode ProbesSetUp(const Scene *scene, PetscInt dim, Structure structure, Interface itf, const char dir[], Probes *probes, Vec *displacement)
{
  const char *force_names[] = {"drag", "lift", "force_z"};
  PetscInt    nforce = scene->has_fluid && scene->fluid.n_force_faces ? dim : 0, nodes = 0;
  PetscReal  *coords = NULL;

  PetscFunctionBeginUser;
  *probes       = NULL;
  *displacement = NULL;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &dim, 1, MPIU_INT, MPI_MAX, PETSC_COMM_WORLD));
  if (!scene->n_probes && !nforce) PetscFunctionReturn(0);
  if (scene->n_probes && itf) {
    const PetscReal *interface_coords;
    PetscCall(InterfaceCreateVector(itf, displacement));
    PetscCall(InterfaceGetFluidNodes(itf, &nodes, NULL, &interface_coords));
    PetscCall(PetscMalloc1(nodes * dim, &coords));
    PetscCall(PetscArraycpy(coords, interface_coords, nodes * dim));
  } else if (scene->n_probes && structure && !scene->has_fluid) PetscCall(StructureCreateNodeVector(structure, displacement, &nodes, &coords));
  PetscCall(ProbesCreate(PETSC_COMM_WORLD, dim, nodes, coords, *displacement ? scene->n_probes : 0, scene->probes, nforce, force_names, dir, probes));
  PetscCall(PetscFree(coords));
  PetscFunctionReturn(0);
}

static PetscErrorCode RecordProbes(Probes probes, PetscReal t, const Scene *scene, Fluid fluid, Structure structure, CouplingProblem problem, Vec displacement)
{
  PetscReal force[3] = {0, 0, 0};

  PetscFunctionBeginUser;
  if (!probes) PetscFunctionReturn(0);
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_PROBES, 0, 0, 0, 0));
  if (fluid && scene->fluid.n_force_faces) PetscCall(FluidBodyForce(fluid, force));
  if (displacement && problem) PetscCall(CouplingProblemInterfaceDisplacement(problem, displacement));
  else if (displacement) PetscCall(StructureGetNodeDisplacement(structure, displacement));
  PetscCall(ProbesRecord(probes, t, displacement, force));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_PROBES, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

/* Set when every rank stops on the same error (an interrupt): no abort is needed to end them. */
static PetscBool collective_stop = PETSC_FALSE;

static PetscErrorCode Run(void)
{
  RunParams       params;
  Scene           scene;
  RunSummary      summary;
  Fluid           fluid     = NULL;
  Structure       structure = NULL;
  Interface       itf       = NULL;
  CouplingProblem problem   = NULL;
  Coupling        coupling  = NULL;
  Probes          probes    = NULL;
  FieldWriter     fields    = NULL;
  Vec             probed_displacement = NULL;
  StepRetry       retry = NULL;
  StepRetryStats  retry_stats;
  const char     *failure = NULL;
  char            stop_reason[2 * PETSC_MAX_PATH_LEN + 1024] = ""; /* the run's last word, after the clean-up */
  PetscErrorCode  stop_code = PETSC_ERR_NOT_CONVERGED;
  PetscBool       scene_given, help, coupled;
  int             signal_caught = 0;
  RunCheckpointParams checkpoint;
  PetscInt         first_step = 1;
  PetscLogDouble  start, end;
  PetscMPIInt     size;
  MPI_Comm        fluid_comm, structure_comm;
  DM              fluid_mesh = NULL, structure_mesh = NULL;
  ErrorTable      fluid_errors, structure_errors;

  PetscFunctionBeginUser;
  PetscCall(PetscTime(&start));
  PetscCall(FsioptLogRegister());
  PetscCall(SceneRegisterAll());
  PetscCall(PetscMemzero(&params, sizeof(params)));
  PetscCall(PetscMemzero(&summary, sizeof(summary)));
  PetscCall(PetscMemzero(&fluid_errors, sizeof(fluid_errors)));
  PetscCall(PetscMemzero(&structure_errors, sizeof(structure_errors)));
  PetscCall(PetscOptionsHasHelp(NULL, &help));
  PetscCall(PetscOptionsGetString(NULL, NULL, "-scene", params.scene, sizeof(params.scene), &scene_given));
  if (!scene_given) {
    char names[256];
    PetscCall(SceneListNames(names, sizeof(names)));
    PetscCheck(help, PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG, "option -scene: expected a scene name (%s), or an options file that sets it", names);
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "Scenes: %s. Add -scene <name> to -help to see the scene's and the solvers' options.\n", names));
    PetscFunctionReturn(0);
  }

  PetscCall(PetscLogStagePush(FSIOPT_STAGE_SETUP));
  /* the scene first: it sets its defaults, -dt and -t_final among them */
  PetscCall(SceneCreate(params.scene, &scene));
  PetscCall(RunParamsSetFromOptions(&params));
  PetscCall(InterruptSetFromOptions());
  coupled = scene.has_fluid && scene.has_structure;
  PetscCall(SplitRanks(coupled, &fluid_comm, &structure_comm, &summary.fluid_ranks, &summary.structure_ranks));
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &summary.total_ranks));
  if (scene.has_fluid && fluid_comm != MPI_COMM_NULL) {
    PetscInt nfaces, faces[2 * FSIOPT_MAX_BOUNDARIES];

    PetscCall(FluidCreate(fluid_comm, &fluid));
    PetscCall(FluidSetFromOptions(fluid));
    if (coupled) {
      ControlVariant variant;
      PetscCall(CouplingProblemGetControlVariant(&variant));
      PetscCall(FluidSetInterface(fluid, scene.fluid.interface_face, variant == CONTROL_CONVECTIVE ? PETSC_TRUE : PETSC_FALSE));
      if (scene.fluid.n_fixed_mesh_faces) PetscCall(FluidEnableMeshMotion(fluid));
    }
    PetscCall(SceneRequiredFaces(&scene.fluid, &nfaces, faces));
    PetscCall(MeshCreate(fluid_comm, "fluid_", params.refine, scene.dim, nfaces, faces, &fluid_mesh));
    PetscCall(FluidSetUp(fluid, fluid_mesh, &scene.fluid, params.t_start, params.dt));
    PetscCall(FluidGetInfo(fluid, &summary.dim, &summary.fluid_dofs));
  }
  if (scene.has_structure && structure_comm != MPI_COMM_NULL) {
    PetscInt nfaces, faces[2 * FSIOPT_MAX_BOUNDARIES];

    PetscCall(StructureCreate(structure_comm, &structure));
    PetscCall(StructureSetFromOptions(structure));
    PetscCall(SceneRequiredFaces(&scene.structure, &nfaces, faces));
    PetscCall(MeshCreate(structure_comm, "structure_", params.refine, scene.dim, nfaces, faces, &structure_mesh));
    PetscCall(StructureSetUp(structure, structure_mesh, &scene.structure, params.t_start, params.dt));
    PetscCall(StructureGetInfo(structure, &summary.dim, &summary.structure_dofs));
  }
  if (coupled) {
    PetscCall(PetscLogEventBegin(FSIOPT_EVENT_INTERFACE, 0, 0, 0, 0));
    PetscCall(InterfaceCreate(PETSC_COMM_WORLD, fluid_mesh, scene.fluid.interface_face, structure_mesh, scene.structure.interface_face, &itf));
    PetscCall(CouplingProblemCreate(PETSC_COMM_WORLD, fluid, structure, itf, &scene.fluid, &problem));
    PetscCall(CouplingCreate(params.coupling, problem, params.output_dir, params.t_start, params.dt, &coupling));
    PetscCall(PetscLogEventEnd(FSIOPT_EVENT_INTERFACE, 0, 0, 0, 0));
  }
  PetscCall(ProbesSetUp(&scene, summary.dim, structure, itf, params.output_dir, &probes, &probed_displacement));
  PetscCall(FieldWriterCreate(PETSC_COMM_WORLD, &params, fluid, structure, &fields));
  PetscCall(StepRetryCreate(&params, fluid, structure, coupling, &retry));
  {
    PetscBool restartable = PETSC_TRUE;
    if (coupling) PetscCall(CouplingIsRestartable(coupling, &restartable));
    PetscCall(RunCheckpointSetFromOptions(&params, coupled && (fluid_comm != PETSC_COMM_WORLD || structure_comm != PETSC_COMM_WORLD), fields ? PETSC_TRUE : PETSC_FALSE, restartable, &checkpoint));
  }
  if (checkpoint.restarting && !help) {
    PetscInt restart_step = 0;
    PetscCall(RunCheckpoint(checkpoint.restart, PETSC_TRUE, &restart_step, &params, &summary, fluid, structure, coupling, probes));
    first_step = restart_step + 1;
  } else {
    PetscCall(RecordProbes(probes, params.t_start, &scene, fluid, structure, problem, probed_displacement));
    PetscCall(FieldWriterWrite(fields, 0));
  }
  PetscCall(DMDestroy(&fluid_mesh));
  PetscCall(DMDestroy(&structure_mesh));
  PetscCall(PetscLogStagePop());
  if (help) {
    /* every object has read its options by now: the listing is complete */
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "fsiopt: -help: the options above; no time step was run\n"));
    params.steps = 0;
  }

  PetscCall(InterruptInstall());
  summary.steps_done = params.steps;
  summary.first_step = first_step;
  for (PetscInt step = first_step; step <= params.steps; ++step) {
    PetscCall(StepRetryAdvance(retry, step, &failure));
    if (failure) {
      /* the outputs end with the last step completed; the last checkpoint stays */
      summary.steps_done = step - 1;
      summary.failure    = failure;
      break;
    }
    PetscCall(RecordProbes(probes, params.t_start + step * params.dt, &scene, fluid, structure, problem, probed_displacement));
    PetscCall(FieldWriterWrite(fields, step));
    PetscCall(InterruptTestAfterStep(step));
    PetscCall(InterruptCheck(PETSC_COMM_WORLD, &signal_caught));
    /* an interrupted run leaves a checkpoint of its last step when its set-up can */
    if ((checkpoint.every && step % checkpoint.every == 0) || (signal_caught && checkpoint.possible && step < params.steps)) {
      PetscInt saved = step;
      PetscCall(PetscLogEventBegin(FSIOPT_EVENT_CHECKPOINT, 0, 0, 0, 0));
      PetscCall(RunCheckpoint(checkpoint.file, PETSC_FALSE, &saved, &params, &summary, fluid, structure, coupling, probes));
      PetscCall(PetscLogEventEnd(FSIOPT_EVENT_CHECKPOINT, 0, 0, 0, 0));
      checkpoint.last = step;
    }
    if (signal_caught) {
      summary.steps_done  = step;
      summary.interrupted = InterruptName(signal_caught);
      break;
    }
  }

  if (help) goto cleanup;
  PetscCall(StepRetryGetStats(retry, &retry_stats));
  summary.retried_steps   = retry_stats.retried_steps;
  summary.failed_attempts = retry_stats.failed_attempts;
  summary.smallest_dt     = retry_stats.smallest_dt;
  PetscCall(PetscLogStagePush(FSIOPT_STAGE_OUTPUT));
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_ERRORS, 0, 0, 0, 0));
  /* a failed step leaves a state between two times: no error to report */
  if (fluid && !failure) PetscCall(FluidErrors(fluid, &fluid_errors));
  if (structure && !failure) PetscCall(StructureErrors(structure, &structure_errors));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_ERRORS, 0, 0, 0, 0));
  summary.worst_corner_ratio = summary.worst_corner_time = -1;
  if (fluid) PetscCall(FluidGetCounts(fluid, &summary.fluid));
  if (fluid) PetscCall(FluidGetMeshQuality(fluid, &summary.worst_corner_ratio, &summary.worst_corner_time));
  PetscCall(ShareWithAll(&summary.worst_corner_ratio, sizeof(summary.worst_corner_ratio), 0));
  PetscCall(ShareWithAll(&summary.worst_corner_time, sizeof(summary.worst_corner_time), 0));
  if (structure) PetscCall(StructureGetCounts(structure, &summary.structure));
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  {
    /* rank 0 always holds the fluid (when there is one); the last rank always holds the structure */
    const PetscMPIInt structure_root = scene.has_structure ? size - 1 : 0;
    PetscCall(ShareWithAll(&structure_errors, sizeof(structure_errors), structure_root));
    PetscCall(ShareWithAll(&summary.structure, sizeof(summary.structure), structure_root));
    PetscCall(ShareWithAll(&summary.structure_dofs, sizeof(summary.structure_dofs), structure_root));
    PetscCall(ShareWithAll(&summary.dim, sizeof(summary.dim), structure_root));
  }
  summary.errors = fluid_errors;
  for (PetscInt i = 0; i < structure_errors.n; ++i) PetscCall(ErrorTableAdd(&summary.errors, structure_errors.name[i], structure_errors.value[i]));
  summary.work_factor        = -1;
  summary.max_interface_jump = -1;
  if (coupling) {
    CouplingStats stats;
    PetscInt      fluid_solves = summary.fluid.nonlinear_solves;

    PetscCall(CouplingFinish(coupling));
    PetscCall(CouplingGetStats(coupling, &stats));
    PetscCall(CouplingGetOptimizer(coupling, &summary.optimizer));
    PetscCall(ShareWithAll(&fluid_solves, sizeof(fluid_solves), 0));
    summary.coupling_iterations = stats.iterations;
    summary.inner_iterations    = stats.inner_iterations;
    summary.max_interface_jump  = stats.max_jump;
    summary.stalled_steps       = stats.stalled_steps;
    /* seed eq. 6.5: a forward run with the traction known needs one fluid solve per step */
    summary.work_factor = (PetscReal)(fluid_solves + 2 * stats.linearized_pairs) / PetscMax(summary.steps_done - first_step + 1, 1);
  }
  if (probes) {
    PetscCall(ProbesQuantities(probes, &summary.quantities));
    PetscCall(ProbesClose(&probes, PETSC_TRUE));
  }
  PetscCall(PetscTime(&end));
  summary.params        = &params;
  summary.wall_time_s   = end - start;
  summary.converged     = summary.stalled_steps == 0 && !signal_caught && !failure ? PETSC_TRUE : PETSC_FALSE;
  summary.has_fluid     = scene.has_fluid;
  summary.has_structure = scene.has_structure;
  if (!scene.has_fluid) summary.fluid_ranks = 0;
  if (!scene.has_structure) summary.structure_ranks = 0;
  PetscCall(FieldWriterFinish(fields));
  PetscCall(SummaryWrite(PETSC_COMM_WORLD, params.output_dir, &summary));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "fsiopt: scene %s, %" PetscInt_FMT " steps to t = %g:", params.scene, params.steps, (double)params.t_final));
  for (PetscInt i = 0; i < summary.errors.n; ++i) PetscCall(PetscPrintf(PETSC_COMM_WORLD, " %s %.3e", summary.errors.name[i], (double)summary.errors.value[i]));
  if (coupling) PetscCall(PetscPrintf(PETSC_COMM_WORLD, "\nfsiopt: %" PetscInt_FMT " coupling iterations (%.2f per step), %" PetscInt_FMT " inner, max interface jump %.3e, work factor %.2f", summary.coupling_iterations, (double)summary.coupling_iterations / PetscMax(summary.steps_done - first_step + 1, 1), summary.inner_iterations, (double)summary.max_interface_jump, (double)summary.work_factor));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "\nfsiopt: outputs in %s/\n", params.output_dir));
  PetscCall(PetscLogStagePop());
  /* the run ends with an error after everything is freed, on every rank at once */
  collective_stop = signal_caught || failure ? PETSC_TRUE : PETSC_FALSE;
  if (failure) {
    char restart[PETSC_MAX_PATH_LEN + 64] = "";
    if (checkpoint.last >= 0) PetscCall(PetscSNPrintf(restart, sizeof(restart), "; the last checkpoint (step %" PetscInt_FMT ") is %s", checkpoint.last, checkpoint.file));
    PetscCall(PetscSNPrintf(stop_reason, sizeof(stop_reason), "%s; the outputs in %s/ go to step %" PetscInt_FMT "%s", failure, params.output_dir, summary.steps_done, restart));
  } else if (signal_caught) {
    char restart[PETSC_MAX_PATH_LEN + 64] = "";
    stop_code = PETSC_ERR_SIG;
    if (checkpoint.last == summary.steps_done) PetscCall(PetscSNPrintf(restart, sizeof(restart), "; go on with -restart %s", checkpoint.file));
    PetscCall(PetscSNPrintf(stop_reason, sizeof(stop_reason), "interrupted by %s after step %" PetscInt_FMT " of %" PetscInt_FMT " (t = %g); the outputs in %s/ go to that step%s", summary.interrupted, summary.steps_done, params.steps, (double)(params.t_start + summary.steps_done * params.dt), params.output_dir, restart));
  }

cleanup:
  PetscCall(StepRetryDestroy(&retry));
  PetscCall(CouplingDestroy(&coupling));
  PetscCall(ProbesClose(&probes, PETSC_FALSE));
  PetscCall(FieldWriterDestroy(&fields));
  PetscCall(VecDestroy(&probed_displacement));
  PetscCall(CouplingProblemDestroy(&problem));
  PetscCall(InterfaceDestroy(&itf));
  PetscCall(FluidDestroy(&fluid));
  PetscCall(StructureDestroy(&structure));
  if (fluid_comm != PETSC_COMM_WORLD && fluid_comm != MPI_COMM_NULL) PetscCallMPI(MPI_Comm_free(&fluid_comm));
  if (structure_comm != PETSC_COMM_WORLD && structure_comm != MPI_COMM_NULL) PetscCallMPI(MPI_Comm_free(&structure_comm));
  PetscCall(SceneFinalize());
  PetscCheck(!stop_reason[0], PETSC_COMM_WORLD, stop_code, "%s", stop_reason);
  PetscFunctionReturn(0);
}

/* PETSc reads options files inside PetscInitialize and answers a missing one with its
   traceback banner; check them first so the user gets one line instead. */
static int CheckOptionsFiles(int argc, char **argv)
{
  for (int i = 1; i < argc; ++i) {
    if (strcmp(argv[i], "-options_file") && strcmp(argv[i], "-options_file_yaml")) continue;
    if (i + 1 >= argc) {
      fprintf(stderr, "fsiopt: error: option %s: expected a file name\n", argv[i]);
      return 1;
    }
    const int problem = FileProblem(argv[i + 1]);
    if (problem) {
      fprintf(stderr, "fsiopt: error: option %s %s: %s\n", argv[i], argv[i + 1], FileProblemText(problem));
      return 1;
    }
  }
  return 0;
}

int main(int argc, char **argv)
{
  PetscErrorCode ierr;

  if (CheckOptionsFiles(argc, argv)) return 1;
  ierr = PetscInitialize(&argc, &argv, NULL, help);
  if (ierr) return 1;
  ierr = ErrorReportingPush();
  if (!ierr) ierr = Run();
  if (ierr) {
    PetscMPIInt rank, size;
    MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
    MPI_Comm_size(PETSC_COMM_WORLD, &size);
    if (!rank) fprintf(stderr, "fsiopt: error: %s\n", ErrorReportingFirstMessage());
    fflush(stderr);
    /* On one rank finish cleanly; on several, a rank that did not fail may wait in a
       collective call, and only an abort is sure not to hang. */
    if (size > 1 && !collective_stop) MPI_Abort(PETSC_COMM_WORLD, 1);
    PetscFinalize();
    return 1;
  }
  ierr = PetscPopErrorHandler();
  if (!ierr) ierr = PetscFinalize();
  return ierr ? 1 : 0;
}
