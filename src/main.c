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

static const char help[] = "fsiopt: fluid-structure interaction by optimization-based decoupling.\n"
                           "  fsiopt -options_file options/<scene>.yaml [options]   or   fsiopt -scene <name> [options]\n"
                           "Meshes: -fluid_dm_plex_* and -structure_dm_plex_* (box meshes, or gmsh files with *_dm_plex_filename).\n"
                           "Solvers: -fluid_snes_*, -fluid_ksp_*, -fluid_pc_*, -structure_snes_*, ...\n\n";

static const char *const coupling_methods[] = {"opt", "dn", "aitken", "iqnils"};

static PetscErrorCode RunParamsSetFromOptions(RunParams *p, PetscBool *scene_given)
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
  PetscCall(PetscOptionsString("-scene", names, NULL, p->scene, p->scene, sizeof(p->scene), scene_given));
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

static PetscErrorCode Run(void)
{
  RunParams   params;
  Scene       scene;
  RunSummary  summary;
  Fluid       fluid     = NULL;
  Structure   structure = NULL;
  PetscBool   scene_given, help;
  PetscLogDouble start, end;
  PetscMPIInt size;

  PetscFunctionBeginUser;
  PetscCall(PetscTime(&start));
  PetscCall(FsioptLogRegister());
  PetscCall(SceneRegisterAll());
  PetscCall(PetscMemzero(&params, sizeof(params)));
  PetscCall(PetscMemzero(&summary, sizeof(summary)));
  PetscCall(PetscOptionsHasHelp(NULL, &help));
  PetscCall(RunParamsSetFromOptions(&params, &scene_given));
  if (!scene_given) {
    char names[256];
    PetscCall(SceneListNames(names, sizeof(names)));
    PetscCheck(help, PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG, "option -scene: expected a scene name (%s), or an options file that sets it", names);
    PetscCall(PetscPrintf(PETSC_COMM_WORLD, "Scenes: %s. Add -scene <name> to -help to see the scene's and the solvers' options.\n", names));
    PetscFunctionReturn(0);
  }

  PetscCall(PetscLogStagePush(FSIOPT_STAGE_SETUP));
  PetscCall(SceneCreate(params.scene, &scene));
  if (scene.has_fluid) {
    PetscInt nfaces, faces[2 * FSIOPT_MAX_BOUNDARIES];
    DM       mesh;

    PetscCall(FluidCreate(PETSC_COMM_WORLD, &fluid));
    PetscCall(FluidSetFromOptions(fluid));
    PetscCall(SceneRequiredFaces(&scene.fluid, &nfaces, faces));
    PetscCall(MeshCreate(PETSC_COMM_WORLD, "fluid_", params.refine, nfaces, faces, &mesh));
    PetscCall(FluidSetUp(fluid, mesh, &scene.fluid, params.t_start, params.dt));
    PetscCall(DMDestroy(&mesh));
    PetscCall(FluidGetInfo(fluid, &summary.dim, &summary.fluid_dofs));
  }
  if (scene.has_structure) {
    PetscInt nfaces, faces[2 * FSIOPT_MAX_BOUNDARIES];
    DM       mesh;

    PetscCall(StructureCreate(PETSC_COMM_WORLD, &structure));
    PetscCall(StructureSetFromOptions(structure));
    PetscCall(SceneRequiredFaces(&scene.structure, &nfaces, faces));
    PetscCall(MeshCreate(PETSC_COMM_WORLD, "structure_", params.refine, nfaces, faces, &mesh));
    PetscCall(StructureSetUp(structure, mesh, &scene.structure, params.t_start, params.dt));
    PetscCall(DMDestroy(&mesh));
    PetscCall(StructureGetInfo(structure, &summary.dim, &summary.structure_dofs));
  }
  PetscCall(PetscLogStagePop());

  for (PetscInt step = 1; step <= params.steps; ++step) {
    if (fluid) {
      PetscCall(PetscLogStagePush(FSIOPT_STAGE_FLUID));
      PetscCall(FluidStep(fluid, step));
      PetscCall(PetscLogStagePop());
    }
    if (structure) {
      PetscCall(PetscLogStagePush(FSIOPT_STAGE_STRUCTURE));
      PetscCall(StructureStep(structure, step));
      PetscCall(PetscLogStagePop());
    }
  }

  PetscCall(PetscLogStagePush(FSIOPT_STAGE_OUTPUT));
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_ERRORS, 0, 0, 0, 0));
  if (fluid) PetscCall(FluidErrors(fluid, &summary.errors));
  if (structure) PetscCall(StructureErrors(structure, &summary.errors));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_ERRORS, 0, 0, 0, 0));
  if (fluid) PetscCall(FluidGetCounts(fluid, &summary.fluid));
  if (structure) PetscCall(StructureGetCounts(structure, &summary.structure));
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  PetscCall(PetscTime(&end));
  summary.params             = &params;
  summary.wall_time_s        = end - start;
  summary.work_factor        = -1;
  summary.max_interface_jump = -1;
  summary.converged          = PETSC_TRUE;
  summary.has_fluid          = scene.has_fluid;
  summary.has_structure      = scene.has_structure;
  summary.fluid_ranks        = scene.has_fluid ? size : 0;
  summary.structure_ranks    = scene.has_structure ? size : 0;
  PetscCall(SummaryWrite(PETSC_COMM_WORLD, params.output_dir, &summary));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "fsiopt: scene %s, %" PetscInt_FMT " steps to t = %g:", params.scene, params.steps, (double)params.t_final));
  for (PetscInt i = 0; i < summary.errors.n; ++i) PetscCall(PetscPrintf(PETSC_COMM_WORLD, " %s %.3e", summary.errors.name[i], (double)summary.errors.value[i]));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "\nfsiopt: outputs in %s/\n", params.output_dir));
  PetscCall(PetscLogStagePop());

  PetscCall(FluidDestroy(&fluid));
  PetscCall(StructureDestroy(&structure));
  PetscCall(SceneFinalize());
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
    if (size > 1) MPI_Abort(PETSC_COMM_WORLD, 1);
    PetscFinalize();
    return 1;
  }
  ierr = PetscFinalize();
  return ierr ? 1 : 0;
}
