/* The per-step outputs of a run (outputs.h): probes.csv and the fields. */
#include "outputs.h"
#include "fields.h"
#include "logging.h"

struct _p_Outputs {
  const RunParams *params;
  const Scene     *scene;
  Fluid            fluid;
  Structure        structure;
  CouplingProblem  problem;
  Probes           probes;
  Vec              displacement; /* of the probed nodes */
  FieldWriter      fields;
};

/* probes.csv: the displacement at the scene's probe points (on the interface of a coupled
   run, in the structure of a structure alone) and the force on the fluid's body faces. */
static PetscErrorCode ProbesSetUp(Outputs out, PetscInt dim, Interface itf)
{
  const char  *force_names[] = {"drag", "lift", "force_z"};
  const Scene *scene         = out->scene;
  PetscInt     nforce = scene->has_fluid && scene->fluid.n_force_faces ? dim : 0, nodes = 0;
  PetscReal   *coords = NULL;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &dim, 1, MPIU_INT, MPI_MAX, PETSC_COMM_WORLD));
  if (!scene->n_probes && !nforce) PetscFunctionReturn(0);
  if (scene->n_probes && itf) {
    const PetscReal *interface_coords;
    PetscCall(InterfaceCreateVector(itf, &out->displacement));
    PetscCall(InterfaceGetFluidNodes(itf, &nodes, NULL, &interface_coords));
    PetscCall(PetscMalloc1(nodes * dim, &coords));
    PetscCall(PetscArraycpy(coords, interface_coords, nodes * dim));
  } else if (scene->n_probes && out->structure && !scene->has_fluid)
    PetscCall(StructureCreateNodeVector(out->structure, &out->displacement, &nodes, &coords));
  PetscCall(ProbesCreate(PETSC_COMM_WORLD, dim, nodes, coords, out->displacement ? scene->n_probes : 0, scene->probes,
                         nforce, force_names, scene->units, out->params->output_dir, &out->probes));
  PetscCall(PetscFree(coords));
  PetscFunctionReturn(0);
}

PetscErrorCode OutputsCreate(const RunParams *params, const Scene *scene, PetscInt dim, Fluid fluid,
                             Structure structure, Interface itf, CouplingProblem problem, Outputs *outputs)
{
  Outputs out;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&out));
  out->params    = params;
  out->scene     = scene;
  out->fluid     = fluid;
  out->structure = structure;
  out->problem   = problem;
  PetscCall(ProbesSetUp(out, dim, itf));
  PetscCall(FieldWriterCreate(PETSC_COMM_WORLD, params, fluid, structure, &out->fields));
  *outputs = out;
  PetscFunctionReturn(0);
}

static PetscErrorCode RecordProbes(Outputs out, PetscReal t)
{
  PetscReal force[3] = {0, 0, 0};

  PetscFunctionBeginUser;
  if (!out->probes) PetscFunctionReturn(0);
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_PROBES, 0, 0, 0, 0));
  if (out->fluid && out->scene->fluid.n_force_faces) PetscCall(FluidBodyForce(out->fluid, force));
  if (out->displacement && out->problem)
    PetscCall(CouplingProblemInterfaceDisplacement(out->problem, out->displacement));
  else if (out->displacement) PetscCall(StructureGetNodeDisplacement(out->structure, out->displacement));
  PetscCall(ProbesRecord(out->probes, t, out->displacement, force));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_PROBES, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

PetscErrorCode OutputsRecord(Outputs out, PetscInt step)
{
  PetscFunctionBeginUser;
  PetscCall(RecordProbes(out, out->params->t_start + step * out->params->dt));
  PetscCall(FieldWriterWrite(out->fields, step));
  PetscFunctionReturn(0);
}

PetscErrorCode OutputsGetProbes(Outputs out, Probes *probes)
{
  PetscFunctionBeginUser;
  *probes = out->probes;
  PetscFunctionReturn(0);
}

PetscErrorCode OutputsGetFields(Outputs out, FieldWriter *fields)
{
  PetscFunctionBeginUser;
  *fields = out->fields;
  PetscFunctionReturn(0);
}

PetscErrorCode OutputsOpen(Outputs out)
{
  PetscFunctionBeginUser;
  PetscCall(FieldWriterOpen(out->fields));
  PetscFunctionReturn(0);
}

PetscErrorCode OutputsFinish(Outputs out, QuantityTable *quantities)
{
  PetscFunctionBeginUser;
  if (out->probes) {
    PetscCall(ProbesQuantities(out->probes, quantities));
    PetscCall(ProbesClose(&out->probes, PETSC_TRUE));
  }
  PetscCall(FieldWriterFinish(out->fields));
  PetscFunctionReturn(0);
}

PetscErrorCode OutputsDestroy(Outputs *outputs)
{
  Outputs out = *outputs;

  PetscFunctionBeginUser;
  if (!out) PetscFunctionReturn(0);
  PetscCall(ProbesClose(&out->probes, PETSC_FALSE));
  PetscCall(FieldWriterDestroy(&out->fields));
  PetscCall(VecDestroy(&out->displacement));
  PetscCall(PetscFree(*outputs));
  PetscFunctionReturn(0);
}
