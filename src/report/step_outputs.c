/* The per-step outputs of a run (step_outputs.h): probes.csv and the fields. */
#include "step_outputs.h"
#include "fields.h"
#include "logging.h"
#include "point_values.h"
#include "face_integrals.h"

struct _p_StepOutputs {
  const RunParams *params;
  const Scene     *scene;
  Fluid            fluid;
  Structure        structure;
  CouplingProblem  problem;
  Probes           probes;
  Probes           surface;      /* force_surface.csv (-probes_surface_force) */
  Vec              displacement; /* of the probed nodes */
  PointValues      points;       /* -probes_fluid_velocity, ...: after the force columns */
  FaceIntegrals    integrals;    /* -integrals_flow_rate, ..., the 0D outlets: after the points' columns */
  PetscInt         nforce, npoint_columns;
  FieldWriter      fields;
};

/* probes.csv: the displacement at the scene's probe points (on the interface of a coupled
   run, in the structure of a structure alone) and the force on the fluid's body faces. */
static PetscErrorCode ProbesSetUp(StepOutputs out, PetscInt dim, Interface itf)
{
  const char          *force_names[] = {"drag", "lift", "force_z"};
  const Scene         *scene         = out->scene;
  const char *const   *point_names;
  const char *const   *integral_names;
  const UnitDimension *point_units;
  const UnitDimension *integral_units;
  const char          *names[FSIOPT_MAX_QUANTITIES];
  UnitDimension        units[FSIOPT_MAX_QUANTITIES];
  PetscInt             nforce = scene->has_fluid && scene->fluid.n_force_faces ? dim : 0, nodes = 0, npoint_columns,
                       nintegrals;
  PetscReal           *coords = NULL;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &dim, 1, MPIU_INT, MPI_MAX, PETSC_COMM_WORLD));
  PetscCall(PointValuesCreate(PETSC_COMM_WORLD, dim, out->fluid, out->structure, &out->points));
  PetscCall(PointValuesGetColumns(out->points, &npoint_columns, &point_names, &point_units));
  PetscCall(FaceIntegralsCreate(PETSC_COMM_WORLD, dim, out->fluid, &out->integrals));
  PetscCall(FaceIntegralsGetColumns(out->integrals, &nintegrals, &integral_names, &integral_units));
  PetscCheck(nforce + npoint_columns + nintegrals <= FSIOPT_MAX_QUANTITIES, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
             "options -probes_fluid_velocity, ..., -integrals_*: at most %d columns of probes.csv besides the scene's, "
             "asked for %" PetscInt_FMT,
             FSIOPT_MAX_QUANTITIES - (int)nforce, npoint_columns + nintegrals);
  for (PetscInt c = 0; c < nforce; ++c) {
    names[c] = force_names[c];
    units[c] = dim == 2 ? UNIT_FORCE_PER_DEPTH : UNIT_FORCE; /* a 2D body's force is per unit depth */
  }
  for (PetscInt c = 0; c < npoint_columns; ++c) {
    names[nforce + c] = point_names[c];
    units[nforce + c] = point_units[c];
  }
  for (PetscInt c = 0; c < nintegrals; ++c) {
    names[nforce + npoint_columns + c] = integral_names[c];
    units[nforce + npoint_columns + c] = integral_units[c];
  }
  out->nforce         = nforce;
  out->npoint_columns = npoint_columns;
  if (!scene->n_probes && !nforce && !npoint_columns && !nintegrals) PetscFunctionReturn(0);
  if (scene->n_probes && itf) {
    const PetscReal *interface_coords;
    PetscCall(InterfaceCreateVector(itf, &out->displacement));
    PetscCall(InterfaceGetFluidNodes(itf, &nodes, NULL, &interface_coords));
    PetscCall(PetscMalloc1(nodes * dim, &coords));
    PetscCall(PetscArraycpy(coords, interface_coords, nodes * dim));
  } else if (scene->n_probes && out->structure && !scene->has_fluid)
    PetscCall(StructureCreateNodeVector(out->structure, &out->displacement, &nodes, &coords));
  PetscCall(ProbesCreate(PETSC_COMM_WORLD, dim, nodes, coords, out->displacement ? scene->n_probes : 0, scene->probes,
                         nforce + npoint_columns + nintegrals, names, units, scene->units, out->params->output_dir, "probes.csv",
                         &out->probes));
  PetscCall(PetscFree(coords));
  PetscFunctionReturn(0);
}

/* force_surface.csv: the body force as the boundary integral of sigma n, beside probes.csv's
   volume-weighted one. A check, not restored on restart: its series starts at the run's
   first step. */
static PetscErrorCode SurfaceForceSetUp(StepOutputs out, PetscInt dim)
{
  const char  *names[] = {"drag_surface", "lift_surface", "force_z_surface"};
  const Scene *scene   = out->scene;
  PetscBool    surface = PETSC_FALSE, set;

  PetscFunctionBeginUser;
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Probes and the quantities of summary.json", "probes");
  PetscCall(
    PetscOptionsBool("-probes_surface_force",
                     "also write force_surface.csv: the body's force as the boundary integral of sigma n of the "
                     "discrete solution (a check on probes.csv's volume-weighted drag and lift; from the run's "
                     "first step, not restored on restart)",
                     NULL, surface, &surface, &set));
  PetscOptionsEnd();
  if (!surface) PetscFunctionReturn(0);
  PetscCheck(scene->has_fluid && scene->fluid.n_force_faces, PETSC_COMM_WORLD, PETSC_ERR_ARG_INCOMP,
             "option -probes_surface_force: scene %s has no body whose force the fluid reports", scene->name);
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &dim, 1, MPIU_INT, MPI_MAX, PETSC_COMM_WORLD));
  PetscCall(ProbesCreate(PETSC_COMM_WORLD, dim, 0, NULL, 0, NULL, dim, names, NULL, scene->units, out->params->output_dir,
                         "force_surface.csv", &out->surface));
  PetscFunctionReturn(0);
}

PetscErrorCode StepOutputsCreate(const RunParams *params, const Scene *scene, PetscInt dim, Fluid fluid,
                                 Structure structure, Interface itf, CouplingProblem problem, StepOutputs *outputs)
{
  StepOutputs out;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&out));
  out->params    = params;
  out->scene     = scene;
  out->fluid     = fluid;
  out->structure = structure;
  out->problem   = problem;
  PetscCall(ProbesSetUp(out, dim, itf));
  PetscCall(SurfaceForceSetUp(out, dim));
  PetscCall(FieldWriterCreate(PETSC_COMM_WORLD, params, scene->units, fluid, structure, itf, problem,
                              &out->fields));
  *outputs = out;
  PetscFunctionReturn(0);
}

static PetscErrorCode RecordProbes(StepOutputs out, PetscReal t)
{
  PetscReal force[3] = {0, 0, 0}, extra[FSIOPT_MAX_QUANTITIES];

  PetscFunctionBeginUser;
  if (!out->probes) PetscFunctionReturn(0);
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_PROBES, 0, 0, 0, 0));
  if (out->fluid && out->scene->fluid.n_force_faces) PetscCall(FluidBodyForce(out->fluid, force));
  for (PetscInt c = 0; c < out->nforce; ++c) extra[c] = force[c];
  if (out->points) PetscCall(PointValuesEvaluate(out->points, &extra[out->nforce]));
  if (out->integrals) PetscCall(FaceIntegralsEvaluate(out->integrals, &extra[out->nforce + out->npoint_columns]));
  if (out->displacement && out->problem)
    PetscCall(CouplingProblemInterfaceDisplacement(out->problem, out->displacement));
  else if (out->displacement) PetscCall(StructureGetNodeDisplacement(out->structure, out->displacement));
  PetscCall(ProbesRecord(out->probes, t, out->displacement, extra));
  if (out->surface) {
    PetscCall(FluidBodyForceSurface(out->fluid, force));
    PetscCall(ProbesRecord(out->surface, t, NULL, force));
  }
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_PROBES, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode StepOutputsRecord(StepOutputs out, PetscInt step)
{
  PetscFunctionBeginUser;
  PetscCall(RecordProbes(out, out->params->t_start + step * out->params->dt));
  PetscCall(FieldWriterWrite(out->fields, step));
  PetscFunctionReturn(0);
}

PetscErrorCode StepOutputsGetProbes(StepOutputs out, Probes *probes)
{
  PetscFunctionBeginUser;
  *probes = out->probes;
  PetscFunctionReturn(0);
}

PetscErrorCode StepOutputsGetFields(StepOutputs out, FieldWriter *fields)
{
  PetscFunctionBeginUser;
  *fields = out->fields;
  PetscFunctionReturn(0);
}

PetscErrorCode StepOutputsOpen(StepOutputs out)
{
  PetscFunctionBeginUser;
  PetscCall(FieldWriterOpen(out->fields));
  PetscFunctionReturn(0);
}

PetscErrorCode StepOutputsFinish(StepOutputs out, QuantityTable *quantities)
{
  PetscFunctionBeginUser;
  quantities->n = 0;
  if (out->probes) {
    PetscCall(ProbesQuantities(out->probes, quantities));
    PetscCall(ProbesClose(&out->probes, PETSC_TRUE));
  }
  if (out->surface) {
    PetscCall(ProbesQuantities(out->surface, quantities));
    PetscCall(ProbesClose(&out->surface, PETSC_TRUE));
  }
  PetscCall(FieldWriterFinish(out->fields));
  PetscFunctionReturn(0);
}

PetscErrorCode StepOutputsDestroy(StepOutputs *outputs)
{
  StepOutputs out = *outputs;

  PetscFunctionBeginUser;
  if (!out) PetscFunctionReturn(0);
  PetscCall(ProbesClose(&out->probes, PETSC_FALSE));
  PetscCall(ProbesClose(&out->surface, PETSC_FALSE));
  PetscCall(FieldWriterDestroy(&out->fields));
  PetscCall(VecDestroy(&out->displacement));
  PetscCall(PointValuesDestroy(&out->points));
  PetscCall(FaceIntegralsDestroy(&out->integrals));
  PetscCall(PetscFree(*outputs));
  PetscFunctionReturn(0);
}
