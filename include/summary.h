#ifndef FSIOPT_SUMMARY_H
#define FSIOPT_SUMMARY_H
#include "fsiopt.h"
#include "probes.h"
#include "fluid.h"
#include "structure.h"
#include "coupling.h"

/* Everything summary.json reports (docs/design.md §6). Negative values mean "does not apply"
   and are written as null. */
typedef struct {
  const RunParams *params;
  const char      *optimizer; /* NULL: none */
  PetscInt         dim, fluid_dofs, structure_dofs;
  PetscReal        wall_time_s;
  SolverCounts     fluid, structure;
  PetscInt         coupling_iterations, inner_iterations, stalled_steps;
  PetscInt         forward_products, adjoint_products;
  PetscReal        work_factor, max_interface_jump;
  PetscReal        max_convergence_measure; /* the method's own measure's largest final value */
  const char      *convergence_measure;     /* what it is, with the tolerance (CouplingStats.measure) */
  PetscReal        worst_corner_ratio, worst_corner_time; /* moving fluid meshes (FluidGetMeshQuality) */
  PetscBool        converged, has_fluid, has_structure;
  PetscInt         steps_done;  /* fewer than params->steps when interrupted */
  PetscInt         first_step;  /* 1, or the step after the checkpoint of a restart: the counts are this run's */
  const char      *interrupted; /* the signal that ended the run early, NULL: none */
  const char      *failure;     /* the step that failed with the smallest dt allowed, NULL: none */
  PetscInt         retried_steps, failed_attempts;
  PetscReal        smallest_dt;
  PetscReal        memory_estimate, peak_memory; /* bytes, summed over the ranks (memory_estimate.h) */
  ErrorTable       errors;
  QuantityTable    quantities;
  PetscMPIInt      fluid_ranks, structure_ranks, total_ranks;
  const char      *units;          /* the scene's */
  char             start_time[32]; /* UTC, ISO 8601 */
  char             host[256];
} RunSummary;

/* Fills the counts, errors, ranks and quantities of coupling and solvers (collective; fluid,
   structure, coupling may be NULL where the scene or the rank has none). s->failure,
   s->steps_done, s->first_step and the retry counts are the time loop's. */
PetscErrorCode SummaryGather(RunSummary *s, PetscBool has_fluid, PetscBool has_structure, Fluid, Structure, Coupling);
/* Writes <dir>/summary.json atomically (a temporary file renamed into place). */
PetscErrorCode SummaryWrite(MPI_Comm, const char dir[], const RunSummary *);
#endif
