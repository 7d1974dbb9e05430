/* What a checkpoint belongs to (run_checkpoint.h): the options that define the discrete
   problem, as they were when it was written. A restart under others would compute another
   problem from the old history, so it is refused naming the first difference, unless
   -restart_change lists that option. Options that only say how the problem is solved,
   observed or ended may change; everything else in the options database is the problem. */
#include "run_checkpoint.h"
#include "option_pairs.h"
#include <stdlib.h>
#include <string.h>
#include <strings.h>

static const char *const may_change[] = {"-t_final",
                                         "-output_dir",
                                         "-checkpoint_every",
                                         "-checkpoint_file",
                                         "-restart",
                                         "-restart_change_dt",
                                         "-restart_change",
                                         "-dt",
                                         "-t_start", /* compared as a number on its own (run_checkpoint.c) */
                                         "-dt_min",
                                         "-quiet",
                                         "-write_fields",
                                         "-write_fields_interval",
                                         "-interrupt_test_step",
                                         "-interrupt_test_signal",
                                         "-interrupt_test_setup",
                                         "-interrupt_test_failure",
                                         "-options_allow_unused",
                                         "-help",
                                         "-log_view",
                                         "-info",
                                         "-quantities_window",
                                         "-probes_surface_force",
                                         "-progress_interval",
                                         "-progress_seconds",
                                         "-memory_per_node_gib",
                                         "-force",
                                         "-check_rank_sync",
                                         "-options_left",
                                         "-history",
                                         NULL};
/* parts of names: solvers, tolerances, monitors, backends and the coupling iteration's own
   settings (its inner solver, start, Jacobian reuse, acceleration); the method, its control,
   velocity, domain and Tikhonov weight are the problem */
static const char *const may_change_parts[] = {"monitor",
                                               "_view",
                                               "rtol",
                                               "atol",
                                               "stol",
                                               "_tol",
                                               "max_it",
                                               "max_funcs",
                                               "ksp_",
                                               "pc_",
                                               "snes_",
                                               "tao_",
                                               "mat_",
                                               "ceed",
                                               "fem_backend",
                                               "petscpartitioner",
                                               "malloc",
                                               "converged_reason",
                                               "coupling_inner",
                                               "coupling_chord",
                                               "coupling_secant",
                                               "coupling_explicit_jacobian",
                                               "coupling_jacobian",
                                               "coupling_predictor",
                                               "coupling_extrapolation",
                                               "coupling_start_correction",
                                               "coupling_iqn_",
                                               "coupling_imvj_",
                                               "coupling_omega",
                                               "coupling_stall",
                                               "coupling_test",
                                               NULL};

static PetscBool MayChange(const char *name, size_t len, const char change[])
{
  char buf[256];

  if (len >= sizeof(buf)) return PETSC_FALSE;
  memcpy(buf, name, len);
  buf[len] = 0;
  for (int i = 0; may_change[i]; ++i)
    if (!strcmp(buf, may_change[i])) return PETSC_TRUE;
  for (int i = 0; may_change_parts[i]; ++i)
    if (strstr(buf, may_change_parts[i])) return PETSC_TRUE;
  /* -restart_change a,b,-c: listed with or without the dash */
  for (const char *c = change; c && *c;) {
    const char *end = strchr(c, ',');
    size_t      n   = end ? (size_t)(end - c) : strlen(c);
    const char *w   = c[0] == '-' ? c + 1 : c;
    size_t      wn  = c[0] == '-' ? n - 1 : n;
    if (wn == len - 1 && !strncmp(w, buf + 1, wn)) return PETSC_TRUE;
    c = end ? end + 1 : NULL;
  }
  return PETSC_FALSE;
}

PetscErrorCode RunFingerprint(char text[], size_t len)
{
  char        *all;
  OptionPairs *pairs;
  size_t       used = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&pairs));
  PetscCall(PetscOptionsGetAll(NULL, &all));
  OptionPairsParse(all, pairs);
  text[0] = 0;
  for (PetscInt i = 0; i < pairs->n; ++i) {
    if (MayChange(pairs->name[i], pairs->name_len[i], NULL)) continue;
    PetscCheck(used + pairs->name_len[i] + pairs->value_len[i] + 3 < len, PETSC_COMM_SELF, PETSC_ERR_MEM,
               "the restart fingerprint needs more than %zu characters", len);
    used += (size_t)snprintf(text + used, len - used, "%.*s %.*s\n", (int)pairs->name_len[i], pairs->name[i],
                             (int)pairs->value_len[i], pairs->value[i]);
  }
  PetscCall(PetscFree(all));
  PetscCall(PetscFree(pairs));
  PetscFunctionReturn(0);
}

/* the value of name in a fingerprint ("name value\n" lines), NULL: absent */
static const char *Lookup(const char text[], const char *name, size_t name_len, size_t *value_len)
{
  for (const char *line = text; line && *line;) {
    const char *end = strchr(line, '\n');
    if (!strncmp(line, name, name_len) && (line[name_len] == ' ' || line[name_len] == '\n')) {
      const char *v = line[name_len] == ' ' ? line + name_len + 1 : line + name_len;
      *value_len    = (size_t)((end ? end : v + strlen(v)) - v);
      return v;
    }
    line = end ? end + 1 : NULL;
  }
  return NULL;
}

/* true, false or neither (-1), as PETSc reads a flag's value */
static int Truth(const char *v, size_t n)
{
  static const char *const yes[] = {"", "1", "true", "yes", "on"}, *const no[] = {"0", "false", "no", "off"};
  for (size_t i = 0; i < sizeof(yes) / sizeof(*yes); ++i)
    if (strlen(yes[i]) == n && !strncasecmp(v, yes[i], n)) return 1;
  for (size_t i = 0; i < sizeof(no) / sizeof(*no); ++i)
    if (strlen(no[i]) == n && !strncasecmp(v, no[i], n)) return 0;
  return -1;
}

/* the same value, also when written differently: "1.1" and "1.10", "2e3" and "2000", lists
   item by item, "true" and "1" */
static PetscBool SameValue(const char *a, size_t la, const char *b, size_t lb)
{
  if (la == lb && !strncmp(a, b, la)) return PETSC_TRUE;
  if (Truth(a, la) >= 0 && Truth(a, la) == Truth(b, lb)) return PETSC_TRUE;
  for (;;) {
    char        x[128], y[128], *ex, *ey;
    const char *ca = memchr(a, ',', la), *cb = memchr(b, ',', lb);
    size_t      na = ca ? (size_t)(ca - a) : la, nb = cb ? (size_t)(cb - b) : lb;
    double      u, v;
    if (!na || !nb || na >= sizeof(x) || nb >= sizeof(y) || !ca != !cb) return PETSC_FALSE;
    memcpy(x, a, na);
    x[na] = 0;
    memcpy(y, b, nb);
    y[nb] = 0;
    u     = strtod(x, &ex);
    v     = strtod(y, &ey);
    if (*ex || *ey || !(u == v || PetscAbsReal(u - v) <= 1e-14 * PetscMax(PetscAbsReal(u), PetscAbsReal(v))))
      return PETSC_FALSE;
    if (!ca) return PETSC_TRUE;
    a = ca + 1, la -= na + 1, b = cb + 1, lb -= nb + 1;
  }
}

static PetscErrorCode FirstDifference(const char a[], const char b[], const char change[], PetscBool *found,
                                      char name[], size_t nlen, char va[], char vb[], size_t vlen)
{
  PetscFunctionBeginUser;
  *found = PETSC_FALSE;
  for (const char *line = a; line && *line && !*found;) {
    const char *end = strchr(line, '\n'), *space = strchr(line, ' ');
    size_t      name_len, la, lb;
    const char *x, *y;
    if (!space || (end && space > end)) space = end ? end : line + strlen(line);
    name_len = (size_t)(space - line);
    x        = Lookup(a, line, name_len, &la);
    y        = Lookup(b, line, name_len, &lb);
    if (!MayChange(line, name_len, change) && (!y || !SameValue(x, la, y, lb))) {
      *found = PETSC_TRUE;
      snprintf(name, nlen, "%.*s", (int)name_len, line);
      snprintf(va, vlen, "%.*s", (int)la, x);
      if (y) snprintf(vb, vlen, "%.*s", (int)lb, y);
      else vb[0] = 0;
      if (!y) snprintf(vb, vlen, "%s", "\001"); /* absent */
    }
    line = end ? end + 1 : NULL;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode RunFingerprintCompare(const char path[], const char written[], const char mine[], const char change[])
{
  char      name[256], va[512], vb[512];
  PetscBool found;

  PetscFunctionBeginUser;
  PetscCall(FirstDifference(written, mine, change, &found, name, sizeof(name), va, vb, sizeof(va)));
  if (found) {
    const PetscBool absent = vb[0] == '\001' ? PETSC_TRUE : PETSC_FALSE;
    SETERRQ(PETSC_COMM_WORLD, PETSC_ERR_ARG_INCOMP,
            "option -restart %s: written with %s%s%s, this run has %s%s%s: a restart continues the problem it was "
            "written for (-restart_change %s lets it change)",
            path, name, va[0] ? " " : "", va, name, absent ? " at its default" : (vb[0] ? " " : ""), absent ? "" : vb,
            name + 1);
  }
  PetscCall(FirstDifference(mine, written, change, &found, name, sizeof(name), va, vb, sizeof(va)));
  if (found) /* only in this run */
    SETERRQ(PETSC_COMM_WORLD, PETSC_ERR_ARG_INCOMP,
            "option -restart %s: written with %s at its default, this run has %s%s%s: a restart continues the "
            "problem it was written for (-restart_change %s lets it change)",
            path, name, name, va[0] ? " " : "", va, name + 1);
  PetscFunctionReturn(0);
}
