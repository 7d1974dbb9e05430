#ifndef FSIOPT_STEP_OUTPUTS_H
#define FSIOPT_STEP_OUTPUTS_H
#include "fsiopt.h"
#include "scene.h"
#include "fluid.h"
#include "structure.h"
#include "interface.h"
#include "coupling.h"
#include "probes.h"
#include "fields.h"
/* What a run writes at each step it completes (probes.csv, the fields of -write_fields),
   behind one object, so that a new per-step output is added here and nowhere else.
   history.csv is the coupling method's (coupling.c), summary.json the report's. */
typedef struct _p_StepOutputs *StepOutputs;
/* fluid, structure, itf and problem may be NULL where the scene or the rank has none */
PetscErrorCode StepOutputsCreate(const RunParams *, const Scene *, PetscInt dim, Fluid, Structure, Interface,
                                 CouplingProblem, StepOutputs *);
/* the state at the end of `step` (0: the initial state) */
PetscErrorCode StepOutputsRecord(StepOutputs, PetscInt step);
PetscErrorCode StepOutputsGetProbes(StepOutputs, Probes *);      /* for checkpoints; may be NULL */
PetscErrorCode StepOutputsGetFields(StepOutputs, FieldWriter *); /* for checkpoints; NULL without -write_fields */
/* the files a restart continues, once its checkpoint is loaded; else new ones, before step 0 */
PetscErrorCode StepOutputsOpen(StepOutputs);
/* completes the files under their final names; the quantities of summary.json */
PetscErrorCode StepOutputsFinish(StepOutputs, QuantityTable *);
PetscErrorCode StepOutputsDestroy(StepOutputs *); /* leaves unfinished files as .partial */
#endif
