/* Options as fsiopt reads them (options.h): range-checked values, scene defaults the user
   overrides, readable files, and the check of options nothing read. */
#include <float.h>
#include <ctype.h>
#include <errno.h>
#include <strings.h>
#include "options.h"
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

PetscErrorCode OptionsPositiveReal(PetscOptionItems *PetscOptionsObject, const char opt[], const char text[],
                                   PetscReal *value)
{
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsReal(opt, text, NULL, *value, value, NULL));
  PetscCheck(*value > 0 && !PetscIsInfOrNanReal(*value), PetscOptionsObject->comm, PETSC_ERR_ARG_OUTOFRANGE,
             "option %s: expected a positive number (%s), got %g", opt, text, (double)*value);
  /* below the smallest normal double its reciprocal overflows and products with it lose their
     digits (channel2d's fluid density 1e-320: 7 times the coupling iterations) */
  PetscCheck(*value >= DBL_MIN, PetscOptionsObject->comm, PETSC_ERR_ARG_OUTOFRANGE,
             "option %s: expected a positive number of at least %g (%s), got %g: a subnormal number", opt, DBL_MIN,
             text, (double)*value);
  PetscFunctionReturn(0);
}

PetscErrorCode OptionsNonNegativeReal(PetscOptionItems *PetscOptionsObject, const char opt[], const char text[],
                                      PetscReal *value)
{
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsReal(opt, text, NULL, *value, value, NULL));
  PetscCheck(*value >= 0 && !PetscIsInfOrNanReal(*value), PetscOptionsObject->comm, PETSC_ERR_ARG_OUTOFRANGE,
             "option %s: expected a number >= 0 (%s), got %g", opt, text, (double)*value);
  PetscFunctionReturn(0);
}

PetscErrorCode OptionsRealInRange(PetscOptionItems *PetscOptionsObject, const char opt[], const char text[],
                                  PetscReal lo, PetscReal hi, PetscReal *value)
{
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsReal(opt, text, NULL, *value, value, NULL));
  PetscCheck(*value > lo && *value < hi, PetscOptionsObject->comm, PETSC_ERR_ARG_OUTOFRANGE,
             "option %s: expected a number in (%g, %g) (%s), got %g", opt, (double)lo, (double)hi, text,
             (double)*value);
  PetscFunctionReturn(0);
}

/* PETSc reads an integer option by strtoll and a cast to PetscInt, so 2^32 + 1 becomes 1, and
   takes its words DEFAULT, DECIDE, DETERMINE as -2, -1, -1: refused here before it reads. */
PetscErrorCode OptionsCheckIntegers(MPI_Comm comm, const char prefix[], const char opt[], const char expected[])
{
  char      text[1024], *token, *rest;
  PetscBool set;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetString(NULL, prefix, opt, text, sizeof(text), &set));
  if (!set) PetscFunctionReturn(0);
  for (token = strtok_r(text, ",", &rest); token; token = strtok_r(NULL, ",", &rest)) {
    const char *words[] = {"DEFAULT", "DECIDE", "DETERMINE", "PETSC_DEFAULT", "PETSC_DECIDE", "PETSC_DETERMINE"};
    char       *end;
    long long   v;

    while (isspace((unsigned char)*token)) ++token;
    for (size_t k = 0; k < sizeof(words) / sizeof(words[0]); ++k)
      PetscCheck(strcasecmp(token, words[k]), comm, PETSC_ERR_ARG_WRONG,
                 "option -%s%s: expected %s, got %s (PETSc's word for a value it chooses, which has no meaning here)",
                 prefix ? prefix : "", opt + 1, expected, token);
    errno = 0;
    v     = strtoll(token, &end, 10);
    while (isspace((unsigned char)*end)) ++end;
    if (end == token || *end) continue; /* not a plain integer: PETSc's own message names it */
    PetscCheck(errno != ERANGE && v >= PETSC_MIN_INT && v <= PETSC_MAX_INT, comm, PETSC_ERR_ARG_OUTOFRANGE,
               "option -%s%s: %s does not fit fsiopt's integers (%" PetscInt_FMT " to %" PetscInt_FMT "); expected %s",
               prefix ? prefix : "", opt + 1, token, (PetscInt)PETSC_MIN_INT, (PetscInt)PETSC_MAX_INT, expected);
  }
  PetscFunctionReturn(0);
}

PetscErrorCode OptionsIntInRange(PetscOptionItems *PetscOptionsObject, const char opt[], const char text[], PetscInt lo,
                                 PetscInt hi, PetscInt *value)
{
  char expected[128];

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(expected, sizeof(expected), "an integer in [%" PetscInt_FMT ", %" PetscInt_FMT "]", lo, hi));
  PetscCall(OptionsCheckIntegers(PetscOptionsObject->comm, PetscOptionsObject->prefix, opt, expected));
  PetscCall(PetscOptionsInt(opt, text, NULL, *value, value, NULL));
  PetscCheck(*value >= lo && *value <= hi, PetscOptionsObject->comm, PETSC_ERR_ARG_OUTOFRANGE,
             "option %s: expected an integer in [%" PetscInt_FMT ", %" PetscInt_FMT "] (%s), got %" PetscInt_FMT, opt,
             lo, hi, text, *value);
  PetscFunctionReturn(0);
}

static PetscErrorCode RecordDefault(const char[]);

PetscErrorCode OptionsListNames(PetscFunctionList list, char names[], size_t len)
{
  const char **entries;
  int          n;

  PetscFunctionBeginUser;
  PetscCall(PetscFunctionListGet(list, &entries, &n));
  names[0] = 0;
  for (int i = 0; i < n; ++i) {
    if (!entries[i] || !entries[i][0]) continue; /* PETSc 3.18 counts one entry more than it fills */
    if (names[0]) PetscCall(PetscStrlcat(names, ", ", len));
    PetscCall(PetscStrlcat(names, entries[i], len));
  }
  PetscCall(PetscFree(entries));
  PetscFunctionReturn(0);
}

PetscErrorCode OptionsSetDefault(const char opt[], const char value[])
{
  PetscBool set, used;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsUsed(NULL, opt, &used));
  PetscCall(PetscOptionsHasName(NULL, NULL, opt, &set));
  if (set && !used) {
    /* looking marked the user's option as read: set it again, unread, so that a set-up
       that does not read it is told (OptionsCheckUnused) */
    const char *value_now;
    char       *copy = NULL;
    PetscCall(PetscOptionsFindPair(NULL, NULL, opt, &value_now, &set));
    if (value_now) PetscCall(PetscStrallocpy(value_now, &copy));
    PetscCall(PetscOptionsClearValue(NULL, opt));
    PetscCall(PetscOptionsSetValue(NULL, opt, copy));
    PetscCall(PetscFree(copy));
  }
  if (set) PetscFunctionReturn(0);
  PetscCall(PetscOptionsSetValue(NULL, opt, value));
  PetscCall(RecordDefault(opt));
  PetscFunctionReturn(0);
}

int OptionsFileProblem(const char path[])
{
  struct stat st;
  FILE       *fp;

  if (stat(path, &st)) return 1;
  if (!S_ISREG(st.st_mode)) return 2;
  if (!(fp = fopen(path, "r"))) return 1;
  fclose(fp);
  return st.st_size > 0 ? 0 : 3;
}

const char *OptionsFileProblemText(int problem)
{
  switch (problem) {
  case 1:
    return "cannot open the file for reading";
  case 2:
    return "expected a regular file";
  case 3:
    return "the file is empty";
  default:
    return "no problem";
  }
}

PetscErrorCode OptionsCheckReadableFile(MPI_Comm comm, const char opt[], const char path[])
{
  const int problem = OptionsFileProblem(path);

  PetscFunctionBeginUser;
  PetscCheck(!problem, comm, PETSC_ERR_FILE_OPEN, "option %s %s: %s", opt, path, OptionsFileProblemText(problem));
  PetscFunctionReturn(0);
}

/* Options OptionsSetDefault put in the database because the user had not: a set-up that
   does not read one of them (a scene's opt settings under -coupling aitken) was not
   given it. */
#define OPTIONS_MAX_DEFAULTS 256
static char    *set_defaults[OPTIONS_MAX_DEFAULTS];
static PetscInt n_set_defaults = 0;

static PetscErrorCode ForgetDefaults(void)
{
  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < n_set_defaults; ++i) PetscCall(PetscFree(set_defaults[i]));
  n_set_defaults = 0;
  PetscFunctionReturn(0);
}

static PetscErrorCode RecordDefault(const char opt[])
{
  PetscFunctionBeginUser;
  if (n_set_defaults == 0) PetscCall(PetscRegisterFinalize(ForgetDefaults));
  if (n_set_defaults == OPTIONS_MAX_DEFAULTS)
    PetscFunctionReturn(0); /* the check then reports it: a false alarm, not a miss */
  PetscCall(PetscStrallocpy(opt[0] == '-' ? opt + 1 : opt, &set_defaults[n_set_defaults++]));
  PetscFunctionReturn(0);
}

static PetscBool IsDefault(const char name[])
{
  for (PetscInt i = 0; i < n_set_defaults; ++i)
    if (!strcmp(set_defaults[i], name)) return PETSC_TRUE;
  return PETSC_FALSE;
}

/* Levenshtein distance, for the suggestion of the nearest known option */
static size_t EditDistance(const char *a, const char *b)
{
  size_t la = strlen(a), lb = strlen(b), row[256];

  if (lb >= sizeof(row) / sizeof(row[0])) return (size_t)-1;
  for (size_t j = 0; j <= lb; ++j) row[j] = j;
  for (size_t i = 1; i <= la; ++i) {
    size_t diagonal = row[0];
    row[0]          = i;
    for (size_t j = 1; j <= lb; ++j) {
      const size_t above = row[j],
                   best  = PetscMin(PetscMin(row[j] + 1, row[j - 1] + 1), diagonal + (a[i - 1] != b[j - 1]));
      diagonal           = above;
      row[j]             = best;
    }
  }
  return row[lb];
}

/* fsiopt's own options (build/known_options.c, made by make from the string literals of
   src/), and the PETSc solver options users most often give, under fsiopt's prefixes. */
extern const char *const fsiopt_known_options[];
static const char *const solver_prefixes[] =
  {"fluid_", "structure_", "mesh_", "fluid_dirichlet_", "tao_brgn_subsolver_tao_bnk_", "", NULL};
static const char *const solver_options[] = {"snes_type",
                                             "snes_rtol",
                                             "snes_atol",
                                             "snes_stol",
                                             "snes_max_it",
                                             "snes_monitor",
                                             "snes_converged_reason",
                                             "snes_linesearch_type",
                                             "snes_lag_jacobian",
                                             "snes_test_jacobian",
                                             "ksp_type",
                                             "ksp_rtol",
                                             "ksp_atol",
                                             "ksp_max_it",
                                             "ksp_monitor",
                                             "ksp_converged_reason",
                                             "ksp_view",
                                             "ksp_gmres_restart",
                                             "pc_type",
                                             "pc_factor_mat_solver_type",
                                             "pc_fieldsplit_type",
                                             "pc_gamg_type",
                                             "pc_hypre_type",
                                             "snes_view",
                                             "tao_type",
                                             "tao_monitor",
                                             "tao_view",
                                             "tao_ls_type",
                                             "log_view",
                                             "options_left",
                                             "malloc_debug",
                                             "malloc_dump",
                                             "info",
                                             NULL};

static void Nearest(const char name[], char best[], size_t len)
{
  size_t best_d = (size_t)-1;
  char   candidate[256];

  best[0] = 0;
  for (const char *const *k = fsiopt_known_options; *k; ++k) {
    const size_t d = EditDistance(name, *k + 1);
    if (d < best_d) {
      best_d = d;
      (void)PetscStrncpy(best, *k, len);
    }
  }
  for (const char *const *p = solver_prefixes; *p; ++p)
    for (const char *const *o = solver_options; *o; ++o) {
      (void)PetscSNPrintf(candidate, sizeof(candidate), "%s%s", *p, *o);
      const size_t d = EditDistance(name, candidate);
      if (d < best_d) {
        best_d = d;
        (void)PetscSNPrintf(best, len, "-%s", candidate);
      }
    }
  /* a suggestion only when it is near: a few letters, not a different word */
  if (best_d > PetscMax(2, strlen(name) / 4)) best[0] = 0;
}

static PetscBool IsKnown(const char name[])
{
  for (const char *const *k = fsiopt_known_options; *k; ++k)
    if (!strcmp(*k + 1, name)) return PETSC_TRUE;
  return PETSC_FALSE;
}

/* PETSc reads these in PetscFinalize, after the check */
static PetscBool IsReadAtExit(const char name[])
{
  return !strcmp(name, "options_left") || !strcmp(name, "options_view") ? PETSC_TRUE : PETSC_FALSE;
}

/* Viewers, convergence reasons and Jacobian tests PETSc reads inside its solves, not when
   the solver is set up, and the options of the solvers a preconditioner makes when it is
   first set up (a field split's, a multigrid's levels, a block preconditioner's blocks):
   the first check lets them wait for the first step. */
static PetscBool IsReadInSolves(const char name[])
{
  /* mat_<package>_: a factorization package reads its options at the first factorization;
     mat_mffd_: the differences operator of -coupling_snes_mf_operator, at the first solve */
  const char *const lazy[] = {"_view",        "converged_reason", "test_jacobian", "_monitor",   "fieldsplit_",
                              "mg_levels_",   "mg_coarse_",       "sub_",          "mat_mumps_", "mat_superlu_",
                              "mat_umfpack_", "mat_klu_",         "mat_mffd_",     NULL};

  for (const char *const *l = lazy; *l; ++l)
    if (strstr(name, *l)) return PETSC_TRUE;
  return PETSC_FALSE;
}

/* the options fsiopt reads as numbers, names or strings (build/known_options.c) */
extern const char *const fsiopt_value_options[];

PetscBool OptionsHelpRequested(void)
{
  static int asked = -1; /* the answer of the first call, before a capture sets -help */

  if (asked < 0) {
    PetscBool help = PETSC_FALSE;
    (void)PetscOptionsHasHelp(NULL, &help);
    asked = help ? 1 : 0;
  }
  return asked ? PETSC_TRUE : PETSC_FALSE;
}

/* An option fsiopt reads as a value, or a solver option of the list above that takes one
   (a literal of src/ that fsiopt only passes on, a PETSc flag among them, is not checked) */
static PetscBool TakesValue(const char name[])
{
  char candidate[256];

  for (const char *const *v = fsiopt_value_options; *v; ++v)
    if (!strcmp(*v, name)) return PETSC_TRUE;
  for (const char *const *p = solver_prefixes; *p; ++p)
    for (const char *const *o = solver_options; *o; ++o) {
      if (IsReadInSolves(*o) || !strcmp(*o, "log_view") || !strcmp(*o, "options_left") || !strncmp(*o, "malloc", 6) ||
          !strcmp(*o, "info"))
        continue;
      (void)PetscSNPrintf(candidate, sizeof(candidate), "-%s%s", *p, *o);
      if (!strcmp(candidate, name)) return PETSC_TRUE;
    }
  return PETSC_FALSE;
}

/* PETSc reads an option given without its value as not given: "-fluid_density" alone, or a
   YAML key with nothing after the colon, would run with the default. Read from the whole
   table, which marks no option as used. */
PetscErrorCode OptionsCheckValuesGiven(MPI_Comm comm)
{
  char *all, *token, *save, *name = NULL, missing[1024] = "";

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetAll(NULL, &all));
  for (token = strtok_r(all, " ", &save);; token = strtok_r(NULL, " ", &save)) {
    const PetscBool is_name = token && token[0] == '-' && isalpha((unsigned char)token[1]) ? PETSC_TRUE : PETSC_FALSE;
    if (name && (!token || is_name) && TakesValue(name)) {
      PetscCall(PetscStrlcat(missing, missing[0] ? ", " : "", sizeof(missing)));
      PetscCall(PetscStrlcat(missing, name, sizeof(missing)));
    }
    if (!token) break;
    name = is_name ? token : NULL;
  }
  PetscCall(PetscFree(all));
  PetscCheck(!missing[0], comm, PETSC_ERR_ARG_WRONG, "option%s %s: expected a value after the name",
             strchr(missing, ',') ? "s" : "", missing);
  PetscFunctionReturn(0);
}

/* A viewer or test waits for the first step only under a prefix some solver has: one
   under none (-fluidd_snes_monitor) cannot be read later either, and is refused at once. */
static PetscBool IsDeferred(const char name[])
{
  const char *const objects[] = {"snes_", "ksp_", "pc_", "tao_", "dm_", "mat_", "vec_", NULL};

  if (!IsReadInSolves(name)) return PETSC_FALSE;
  for (const char *const *p = solver_prefixes; **p; ++p)
    if (!strncmp(name, *p, strlen(*p))) return PETSC_TRUE;
  /* the coupling's Newton-Krylov solver (opt_newton_krylov.c) */
  if (!strncmp(name, "coupling_", 9)) return PETSC_TRUE;
  for (const char *const *o = objects; *o; ++o)
    if (!strncmp(name, *o, strlen(*o))) return PETSC_TRUE;
  return PETSC_FALSE;
}

/* the longest of fsiopt's solver prefixes that name starts with ("" for none) */
static void SolverPrefix(const char name[], char prefix[], size_t len)
{
  size_t best = 0;

  (void)PetscStrncpy(prefix, "", len);
  for (const char *const *p = solver_prefixes; **p; ++p)
    if (!strncmp(name, *p, strlen(*p)) && strlen(*p) > best) {
      best = strlen(*p);
      (void)PetscStrncpy(prefix, *p, len);
    }
}

/* read[i]: names[i], left unread on this rank, was read on another: a run that splits its
   ranks between the fluid and the structure (-structure_ranks) reads each side's options on
   that side's ranks only */
static PetscErrorCode ReadOnAnotherRank(MPI_Comm comm, PetscInt n, char **names, PetscBool read[])
{
  PetscMPIInt size, length = 0, *lengths, *offsets;
  char       *mine, *all;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  for (PetscInt i = 0; i < n; ++i) read[i] = PETSC_FALSE;
  if (size == 1) PetscFunctionReturn(0);
  for (PetscInt i = 0; i < n; ++i) length += (PetscMPIInt)strlen(names[i]) + 1;
  PetscCall(PetscMalloc3(length + 1, &mine, size, &lengths, size + 1, &offsets));
  mine[0] = 0;
  for (PetscInt i = 0; i < n; ++i) {
    PetscCall(PetscStrlcat(mine, names[i], length + 1));
    PetscCall(PetscStrlcat(mine, "\n", length + 1));
  }
  PetscCallMPI(MPI_Allgather(&length, 1, MPI_INT, lengths, 1, MPI_INT, comm));
  offsets[0] = 0;
  for (PetscMPIInt r = 0; r < size; ++r) offsets[r + 1] = offsets[r] + lengths[r];
  PetscCall(PetscMalloc1(offsets[size] + 1, &all));
  PetscCallMPI(MPI_Allgatherv(mine, length, MPI_CHAR, all, lengths, offsets, MPI_CHAR, comm));
  for (PetscInt i = 0; i < n; ++i) {
    const size_t len = strlen(names[i]);
    for (PetscMPIInt r = 0; r < size && !read[i]; ++r) {
      PetscBool left = PETSC_FALSE; /* names[i] among rank r's unread options */
      for (PetscMPIInt at = offsets[r]; at < offsets[r + 1] && !left;) {
        PetscMPIInt end = at;
        while (end < offsets[r + 1] && all[end] != '\n') ++end;
        left = (size_t)(end - at) == len && !strncmp(all + at, names[i], len) ? PETSC_TRUE : PETSC_FALSE;
        at   = end + 1;
      }
      read[i] = left ? PETSC_FALSE : PETSC_TRUE;
    }
  }
  PetscCall(PetscFree(all));
  PetscCall(PetscFree3(mine, lengths, offsets));
  PetscFunctionReturn(0);
}

PetscErrorCode OptionsCheckUnused(MPI_Comm comm, PetscBool after_first_step)
{
  PetscBool *elsewhere;
  PetscInt  n;
  char    **names, **values, unknown[1024] = "", nearest[1024] = "", unread[1024] = "";
  char      exact_prefix[64] = "";
  PetscInt  n_unknown = 0, n_suggested = 0, n_exact = 0;
  PetscBool allow = PETSC_FALSE;

  PetscFunctionBeginUser;
  if (!after_first_step) {
    PetscOptionsBegin(comm, NULL, "Options nothing reads", "fsiopt");
    PetscCall(
      PetscOptionsBool("-options_allow_unused",
                       "an option that nothing reads is a warning, not an error (for options meant for other tools)",
                       NULL, allow, &allow, NULL));
    PetscOptionsEnd();
  } else PetscCall(PetscOptionsGetBool(NULL, NULL, "-options_allow_unused", &allow, NULL));
  PetscCall(PetscOptionsLeftGet(NULL, &n, &names, &values));
  PetscCall(PetscMalloc1(n + 1, &elsewhere));
  PetscCall(ReadOnAnotherRank(comm, n, names, elsewhere));
  for (PetscInt i = 0; i < n; ++i) {
    char suggestion[256];

    if (elsewhere[i] || IsDefault(names[i]) || IsReadAtExit(names[i]) || IsDeferred(names[i]) != after_first_step)
      continue;
    if (IsKnown(names[i])) {
      PetscCall(PetscStrlcat(unread, unread[0] ? ", -" : "-", sizeof(unread)));
      PetscCall(PetscStrlcat(unread, names[i], sizeof(unread)));
      continue;
    }
    PetscCall(PetscStrlcat(unknown, n_unknown++ ? ", -" : "-", sizeof(unknown)));
    PetscCall(PetscStrlcat(unknown, names[i], sizeof(unknown)));
    Nearest(names[i], suggestion, sizeof(suggestion));
    if (!strcmp(suggestion + 1, names[i])) { /* a solver option of a solver this set-up lacks */
      if (!n_exact++) SolverPrefix(names[i], exact_prefix, sizeof(exact_prefix));
    } else if (suggestion[0]) {
      PetscCall(PetscStrlcat(nearest, n_suggested++ ? ", " : "", sizeof(nearest)));
      PetscCall(PetscStrlcat(nearest, suggestion, sizeof(nearest)));
    }
  }
  PetscCall(PetscOptionsLeftRestore(NULL, &n, &names, &values));
  PetscCall(PetscFree(elsewhere));
  if (unread[0])
    PetscCall(PetscPrintf(comm,
                          "fsiopt: warning: option%s %s: not read by this set-up (%s to another scene, coupling method "
                          "or solver)\n",
                          strchr(unread, ',') ? "s" : "", unread, strchr(unread, ',') ? "they belong" : "it belongs"));
  if (!n_unknown) PetscFunctionReturn(0);
  {
    char        message[3072];
    const char *pronoun     = n_unknown > 1 ? "them" : "it";
    char        absent[128] = "";
    if (n_exact)
      PetscCall(
        PetscSNPrintf(absent, sizeof(absent), " (this set-up has no solver with the prefix -%s)", exact_prefix));
    PetscCall(PetscSNPrintf(message, sizeof(message), "option%s %s: nothing %s %s%s%s%s%s%s", n_unknown > 1 ? "s" : "",
                            unknown, after_first_step ? "read" : "reads", pronoun,
                            after_first_step
                              ? " in the first step, where the solvers read their viewers, tests and inner solvers"
                              : "",
                            absent, n_suggested ? " (the nearest known: " : "", nearest, n_suggested ? ")" : ""));
    if (allow) PetscCall(PetscPrintf(comm, "fsiopt: warning: %s; let through by -options_allow_unused\n", message));
    else SETERRQ(comm, PETSC_ERR_ARG_WRONG, "%s; -options_allow_unused lets %s through", message, pronoun);
  }
  PetscFunctionReturn(0);
}
