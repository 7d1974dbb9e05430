/* summary.json (summary.h): the counts, errors, quantities and options of a run,
   gathered from the solvers and the coupling onto rank 0 and written there atomically. */
#include <errno.h>
#include <string.h>
#include <unistd.h>
#include "summary.h"
#include "options.h"
#include "error_reporting.h"
#include "memory_estimate.h"
#include "option_pairs.h"
#include "output_files.h"
#include "logging.h"
#include "help.h"

extern const char fsiopt_version[]; /* build/version.c, made by make: git describe of the build */
#include <stdio.h>

/* A JSON string of the first n bytes of text (up to a NUL): a path or a message may hold any
   bytes, JSON only UTF-8 without raw control characters. A byte that is not UTF-8 becomes
   U+FFFD, so that the file stays readable and says that something was replaced. */
static void WriteEscaped(FILE *fp, const char *text, size_t n)
{
  const unsigned char *t = (const unsigned char *)text;

  fputc('"', fp);
  for (size_t i = 0, len; i < n && t[i]; i += len) {
    len = UTF8SequenceLength(t + i, n - i);
    if (!len) {
      fputs("\\ufffd", fp);
      len = 1;
    } else if (t[i] == '"' || t[i] == '\\') fprintf(fp, "\\%c", t[i]);
    else if (t[i] < 0x20) fprintf(fp, "\\u%04x", t[i]);
    else fwrite(t + i, 1, len, fp);
  }
  fputc('"', fp);
}

static void WriteStringOrNull(FILE *fp, const char key[], const char *value)
{
  fprintf(fp, "  \"%s\": ", key);
  if (value) WriteEscaped(fp, value, strlen(value));
  else fprintf(fp, "null");
  fprintf(fp, ",\n");
}

static void WriteNumberOrNull(FILE *fp, const char key[], PetscReal value, const char *sep)
{
  if (value < 0 || PetscIsInfOrNanReal(value)) fprintf(fp, "  \"%s\": null%s\n", key, sep);
  else fprintf(fp, "  \"%s\": %.10g%s\n", key, (double)value, sep);
}

/* "quantities": {"window_s": T, "<column>": {"final": v[, "mean": m, "amplitude": a, "frequency": f]}, ...} */
static void WriteQuantities(FILE *fp, const QuantityTable *q)
{
  fprintf(fp, "  \"quantities\": {");
  if (q->n) fprintf(fp, "\"window_s\": %.10g", (double)q->window);
  for (PetscInt i = 0; i < q->n; ++i) {
    fprintf(fp, ",\n    \"%s\": {\"final\": %.10e", q->name[i], (double)q->final[i]);
    if (q->window > 0) {
      fprintf(fp, ", \"mean\": %.10e, \"amplitude\": %.10e, \"frequency\": ", (double)q->mean[i],
              (double)q->amplitude[i]);
      if (q->frequency[i] > 0) fprintf(fp, "%.10e}", (double)q->frequency[i]);
      else fprintf(fp, "null}");
    } else fprintf(fp, "}");
  }
  fprintf(fp, "},\n");
}

static PetscInt FindGiven(const OptionPairs *given, const char name[])
{
  for (PetscInt i = 0; i < given->n; ++i)
    if (given->name_len[i] == strlen(name) && !strncmp(given->name[i], name, given->name_len[i])) return i;
  return -1;
}

static void WritePair(FILE *fp, PetscBool *first, const char *name, size_t name_len, const char *value,
                      size_t value_len)
{
  fprintf(fp, "%s\n    ", *first ? "" : ",");
  WriteEscaped(fp, name, name_len);
  fprintf(fp, ": ");
  WriteEscaped(fp, value, value_len);
  *first = PETSC_FALSE;
}

/* "options": every option in effect, as the objects read it while the run was set up
   (given or their default; help.h), and every given one; "options_given": those of the
   database (command line, options files, environment, the scene's defaults). Values as
   strings, "" for a flag without a value. */
static PetscErrorCode WriteOptions(FILE *fp)
{
  char        *all;
  OptionPairs *given;
  PetscInt     n;
  char *const *names, *const *values;
  PetscBool first = PETSC_TRUE;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&given));
  PetscCall(PetscOptionsGetAll(NULL, &all));
  OptionPairsParse(all, given);
  PetscCall(HelpListingGetCapturedOptions(&n, &names, &values));
  fprintf(fp, "  \"options\": {");
  for (PetscInt i = 0; i < n; ++i) {
    const PetscInt g = FindGiven(given, names[i]);
    size_t         len = strlen(names[i]), tail = strlen("mat_mumps_view_info");
    /* PETSc 3.18's MUMPS interface lists this flag with an uninitialized integer as its default */
    if (g < 0 && len >= tail && !strcmp(names[i] + len - tail, "mat_mumps_view_info")) continue;
    if (g >= 0) WritePair(fp, &first, given->name[g], given->name_len[g], given->value[g], given->value_len[g]);
    else WritePair(fp, &first, names[i], strlen(names[i]), values[i], strlen(values[i]));
  }
  for (PetscInt g = 0; g < given->n; ++g) {
    PetscBool read = PETSC_FALSE;
    for (PetscInt i = 0; i < n && !read; ++i)
      read = given->name_len[g] == strlen(names[i]) && !strncmp(given->name[g], names[i], given->name_len[g]);
    if (!read) WritePair(fp, &first, given->name[g], given->name_len[g], given->value[g], given->value_len[g]);
  }
  fprintf(fp, "},\n  \"options_given\": {");
  first = PETSC_TRUE;
  for (PetscInt g = 0; g < given->n; ++g)
    WritePair(fp, &first, given->name[g], given->name_len[g], given->value[g], given->value_len[g]);
  fprintf(fp, "}\n");
  PetscCall(PetscFree(all));
  PetscCall(PetscFree(given));
  PetscFunctionReturn(0);
}

static PetscErrorCode WriteOnRoot(const char dir[], const RunSummary *s)
{
  char             path[PETSC_MAX_PATH_LEN], tmp[PETSC_MAX_PATH_LEN];
  FILE            *fp;
  const RunParams *p = s->params;
  PetscReal        avg;

  PetscFunctionBeginUser;
  PetscCall(OutputMakeDirectories(dir));
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/summary.json", dir));
  PetscCall(PetscSNPrintf(tmp, sizeof(tmp), "%s/.summary.json.tmp", dir));
  fp = fopen(tmp, "w");
  PetscCheck(fp, PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "option -output_dir %s: cannot write %s", dir, tmp);
  avg = s->steps_done >= s->first_step ? (PetscReal)s->coupling_iterations / (s->steps_done - s->first_step + 1) : 0;
  fprintf(fp, "{\n");
  fprintf(fp, "  \"scene\": \"%s\",\n", p->scene);
  fprintf(fp, "  \"coupling\": \"%s\",\n", (s->has_fluid && s->has_structure) ? p->coupling : "none");
  if (s->optimizer) fprintf(fp, "  \"optimizer\": \"%s\",\n", s->optimizer);
  else fprintf(fp, "  \"optimizer\": null,\n");
  fprintf(fp, "  \"dim\": %d,\n", (int)s->dim);
  fprintf(fp, "  \"refine\": %d,\n", (int)p->refine);
  fprintf(fp, "  \"steps\": %d,\n", (int)p->steps);
  fprintf(fp, "  \"steps_done\": %d,\n", (int)s->steps_done);
  fprintf(fp, "  \"first_step\": %d,\n", (int)s->first_step);
  WriteStringOrNull(fp, "interrupted", s->interrupted);
  WriteStringOrNull(fp, "failure", s->failure);
  fprintf(fp, "  \"retried_steps\": %d,\n", (int)s->retried_steps);
  fprintf(fp, "  \"failed_attempts\": %d,\n", (int)s->failed_attempts);
  fprintf(fp, "  \"smallest_dt\": %.17g,\n", (double)s->smallest_dt);
  fprintf(fp, "  \"dt\": %.17g,\n", (double)p->dt);
  fprintf(fp, "  \"t_start\": %.17g,\n", (double)p->t_start);
  fprintf(fp, "  \"t_final\": %.17g,\n", (double)p->t_final);
  fprintf(fp, "  \"wall_time_s\": %.6f,\n", (double)s->wall_time_s);
  fprintf(fp, "  \"fluid_dofs\": %d,\n", (int)s->fluid_dofs);
  fprintf(fp, "  \"structure_dofs\": %d,\n", (int)s->structure_dofs);
  fprintf(fp, "  \"fluid_solves\": %d,\n", (int)s->fluid.nonlinear_solves);
  fprintf(fp, "  \"fluid_linear_solves\": %d,\n", (int)s->fluid.linear_solves);
  fprintf(fp, "  \"structure_solves\": %d,\n", (int)s->structure.nonlinear_solves);
  fprintf(fp, "  \"coupling_iterations\": %d,\n", (int)s->coupling_iterations);
  fprintf(fp, "  \"avg_coupling_iterations\": %.6g,\n", (double)avg);
  fprintf(fp, "  \"inner_iterations\": %d,\n", (int)s->inner_iterations);
  fprintf(fp, "  \"linearized_solves\": {\"forward\": %d, \"adjoint\": %d},\n", (int)s->forward_products,
          (int)s->adjoint_products);
  fprintf(fp, "  \"stalled_steps\": %d,\n", (int)s->stalled_steps);
  WriteNumberOrNull(fp, "work_factor", s->work_factor, ",");
  WriteNumberOrNull(fp, "max_interface_jump", s->max_interface_jump, ",");
  WriteNumberOrNull(fp, "worst_corner_ratio", s->worst_corner_ratio, ",");
  WriteNumberOrNull(fp, "worst_corner_time", s->worst_corner_time, ",");
  fprintf(fp, "  \"factorizations\": {\"fluid\": %d, \"structure\": %d},\n", (int)s->fluid.factorizations,
          (int)s->structure.factorizations);
  fprintf(fp, "  \"converged\": %s,\n", s->converged ? "true" : "false");
  fprintf(fp, "  \"errors\": {");
  for (PetscInt i = 0; i < s->errors.n; ++i)
    fprintf(fp, "%s\"%s\": %.10e", i ? ", " : "", s->errors.name[i], (double)s->errors.value[i]);
  fprintf(fp, "},\n");
  WriteQuantities(fp, &s->quantities);
  fprintf(fp, "  \"memory_gib\": {\"estimate\": %.4g, \"peak\": %.4g},\n", (double)(s->memory_estimate / 1073741824.0),
          (double)(s->peak_memory / 1073741824.0));
  fprintf(fp, "  \"ranks\": {\"fluid\": %d, \"structure\": %d, \"total\": %d},\n", (int)s->fluid_ranks,
          (int)s->structure_ranks, (int)s->total_ranks);
  WriteStringOrNull(fp, "version", fsiopt_version);
  WriteStringOrNull(fp, "units", s->units);
  WriteStringOrNull(fp, "start_time", s->start_time);
  WriteStringOrNull(fp, "host", s->host);
  PetscCall(WriteOptions(fp));
  fprintf(fp, "}\n");
  {
    int cause = 0;
    errno     = 0;
    if (ferror(fp) || fflush(fp) != 0) cause = errno ? errno : -1;
    if (fclose(fp) != 0 && !cause) cause = errno ? errno : -1;
    if (cause) {
      char why[256];
      (void)unlink(tmp); /* no stale temporary; summary.json of an earlier run, if any, stays */
      PetscCall(OutputWriteErrorText(tmp, cause, why, sizeof(why)));
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE, "cannot write %s (%s)", path, why);
    }
  }
  PetscCheck(rename(tmp, path) == 0, PETSC_COMM_SELF, PETSC_ERR_FILE_WRITE,
             "option -output_dir %s: cannot rename %s to %s", dir, tmp, path);
  PetscFunctionReturn(0);
}

/* Rank 0 writes; a failure stops every rank with rank 0's message, not rank 0 alone. */
PetscErrorCode SummaryWrite(MPI_Comm comm, const char dir[], const RunSummary *s)
{
  PetscMPIInt rank;
  char        message[1024] = "";

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (!rank && WriteOnRoot(dir, s)) {
    PetscCall(PetscStrncpy(message, ErrorReportingFirstMessage(), sizeof(message)));
    PetscCall(ErrorReportingForget());
  }
  PetscCallMPI(MPI_Bcast(message, sizeof(message), MPI_CHAR, 0, comm));
  PetscCheck(!message[0], comm, PETSC_ERR_FILE_WRITE, "%s", message);
  PetscFunctionReturn(0);
}

/* Rank 0 writes the summary; the structure's numbers live on the structure's ranks. */
static PetscErrorCode ShareWithAll(void *buffer, size_t bytes, PetscMPIInt root)
{
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Bcast(buffer, (int)bytes, MPI_BYTE, root, PETSC_COMM_WORLD));
  PetscFunctionReturn(0);
}

/* The errors against the scene's exact solution (none after a failed step: its state lies
   between two times), and the mesh quality and solver counts of each side. */
static PetscErrorCode GatherSolvers(RunSummary *s, PetscBool has_structure, Fluid fluid, Structure structure)
{
  ErrorTable  fluid_errors, structure_errors;
  PetscMPIInt size;

  PetscFunctionBeginUser;
  PetscCall(PetscMemzero(&fluid_errors, sizeof(fluid_errors)));
  PetscCall(PetscMemzero(&structure_errors, sizeof(structure_errors)));
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_ERRORS, 0, 0, 0, 0));
  if (fluid && !s->failure) PetscCall(FluidErrors(fluid, &fluid_errors));
  if (structure && !s->failure) PetscCall(StructureErrors(structure, &structure_errors));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_ERRORS, 0, 0, 0, 0));
  s->worst_corner_ratio = s->worst_corner_time = -1;
  if (fluid) PetscCall(FluidGetCounts(fluid, &s->fluid));
  if (fluid) PetscCall(FluidGetMeshQuality(fluid, &s->worst_corner_ratio, &s->worst_corner_time));
  PetscCall(ShareWithAll(&s->worst_corner_ratio, sizeof(s->worst_corner_ratio), 0));
  PetscCall(ShareWithAll(&s->worst_corner_time, sizeof(s->worst_corner_time), 0));
  if (structure) PetscCall(StructureGetCounts(structure, &s->structure));
  PetscCallMPI(MPI_Comm_size(PETSC_COMM_WORLD, &size));
  {
    /* rank 0 always holds the fluid (when there is one); the last rank always holds the structure */
    const PetscMPIInt structure_root = has_structure ? size - 1 : 0;
    PetscCall(ShareWithAll(&structure_errors, sizeof(structure_errors), structure_root));
    PetscCall(ShareWithAll(&s->structure, sizeof(s->structure), structure_root));
    PetscCall(ShareWithAll(&s->structure_dofs, sizeof(s->structure_dofs), structure_root));
    PetscCall(ShareWithAll(&s->dim, sizeof(s->dim), structure_root));
  }
  s->errors = fluid_errors;
  for (PetscInt i = 0; i < structure_errors.n; ++i)
    PetscCall(ErrorTableAdd(&s->errors, structure_errors.name[i], structure_errors.value[i]));
  PetscFunctionReturn(0);
}

PetscErrorCode SummaryGather(RunSummary *s, PetscBool has_fluid, PetscBool has_structure, Fluid fluid,
                             Structure structure, Coupling coupling)
{
  PetscFunctionBeginUser;
  PetscCall(GatherSolvers(s, has_structure, fluid, structure));
  PetscCall(MemoryEstimateGetTotals(&s->memory_estimate, &s->peak_memory));
  s->work_factor        = -1;
  s->max_interface_jump = -1;
  if (coupling) {
    CouplingStats stats;
    PetscInt      fluid_solves = s->fluid.nonlinear_solves;

    PetscCall(CouplingGetStats(coupling, &stats));
    PetscCall(CouplingGetOptimizer(coupling, &s->optimizer));
    PetscCall(ShareWithAll(&fluid_solves, sizeof(fluid_solves), 0));
    s->coupling_iterations = stats.iterations;
    s->inner_iterations    = stats.inner_iterations;
    s->forward_products    = stats.forward_products;
    s->adjoint_products    = stats.adjoint_products;
    s->max_interface_jump  = stats.max_jump;
    s->max_convergence_measure = stats.max_measure;
    s->convergence_measure     = stats.measure;
    s->stalled_steps       = stats.stalled_steps;
    /* seed eq. 6.5: a forward run with the traction known needs one fluid solve per step */
    s->work_factor = (PetscReal)(fluid_solves + 2 * stats.linearized_pairs) /
                     PetscMax(s->steps_done - s->first_step + 1, 1);
  }
  s->has_fluid     = has_fluid;
  s->has_structure = has_structure;
  if (!has_fluid) s->fluid_ranks = 0;
  if (!has_structure) s->structure_ranks = 0;
  PetscFunctionReturn(0);
}
