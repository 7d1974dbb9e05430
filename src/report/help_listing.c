/* -help: PETSc prints each object's options as the object reads them, so fsiopt's own are
   scattered between the solvers'. Their lines are held back and printed first, grouped by
   prefix, with the unit each value has in the scene's system, the checks of internals apart;
   PETSc's own listing follows under -help all and is left out under -help. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include "help.h"
#include "units.h"
#include "options.h"

extern const char *const fsiopt_known_options[];

#define MAX_HELD 512
static PetscErrorCode (*petsc_help_printf)(MPI_Comm, const char[], ...) = NULL;
static char    *held[MAX_HELD], pending_header[256], partial[4096];
static int      n_held = 0;
static MPI_Comm help_comm;
/* -help all: PETSc's lines, kept in order to follow fsiopt's */
static PetscBool list_petsc = PETSC_FALSE;
static char     *petsc_text = NULL;
static size_t    petsc_len = 0, petsc_size = 0;

void HelpListingSetPETSc(PetscBool all)
{
  list_petsc = all;
}

static PetscErrorCode KeepPETScLine(const char line[])
{
  const size_t n = strlen(line);

  PetscFunctionBeginUser;
  if (!list_petsc) PetscFunctionReturn(0);
  if (petsc_len + n + 1 > petsc_size) {
    char *grown;
    petsc_size = 2 * (petsc_size + n + 1);
    PetscCall(PetscMalloc1(petsc_size, &grown));
    if (petsc_text) PetscCall(PetscMemcpy(grown, petsc_text, petsc_len + 1));
    PetscCall(PetscFree(petsc_text));
    petsc_text = grown;
  }
  PetscCall(PetscMemcpy(petsc_text + petsc_len, line, n + 1));
  petsc_len += n;
  PetscFunctionReturn(0);
}

static PetscBool IsOwn(const char line[])
{
  char name[256];
  int  n = 0;

  if (strncmp(line, "  -", 3)) return PETSC_FALSE;
  while (line[2 + n] && line[2 + n] != ' ' && line[2 + n] != ':' && line[2 + n] != '\n' && n < 255) {
    name[n] = line[2 + n];
    ++n;
  }
  name[n] = 0;
  for (const char *const *k = fsiopt_known_options; *k; ++k)
    if (!strcmp(*k, name)) return PETSC_TRUE;
  return OptionsInDeclaredFamily(name);
}

/* Capture: the options every object read while the run was set up, with the values they
   took (given or default), parsed from the lines "  -name <now value : formerly default>". */
#define MAX_CAPTURED 2048
static PetscBool capturing = PETSC_FALSE;
static char     *captured_name[MAX_CAPTURED], *captured_value[MAX_CAPTURED];
static PetscInt  n_captured = 0;

static PetscErrorCode Captured(const char name[], const char value[])
{
  PetscFunctionBeginUser;
  if (n_captured == MAX_CAPTURED) PetscFunctionReturn(0);
  for (PetscInt i = 0; i < n_captured; ++i)
    if (!strcmp(captured_name[i], name)) PetscFunctionReturn(0);
  PetscCall(PetscStrallocpy(name, &captured_name[n_captured]));
  PetscCall(PetscStrallocpy(value, &captured_value[n_captured++]));
  PetscFunctionReturn(0);
}

/* printable UTF-8 (summary.json is UTF-8): no control characters, whole sequences only */
static PetscBool IsText(const char text[])
{
  for (const unsigned char *c = (const unsigned char *)text; *c;) {
    const int extra = *c < 0x80 ? 0 : (*c & 0xe0) == 0xc0 ? 1 : (*c & 0xf0) == 0xe0 ? 2 : (*c & 0xf8) == 0xf0 ? 3 : -1;
    if (*c < 0x20 || *c == 0x7f || extra < 0 || (extra == 1 && *c < 0xc2)) return PETSC_FALSE;
    ++c;
    for (int k = 0; k < extra; ++k, ++c)
      if ((*c & 0xc0) != 0x80) return PETSC_FALSE;
  }
  return PETSC_TRUE;
}

static PetscErrorCode CaptureLine(const char line[])
{
  const char *name = line + 2, *open, *end;
  char        value[1024], option[256];
  size_t      name_len;

  PetscFunctionBeginUser;
  if (strncmp(line, "  -", 3) || n_captured == MAX_CAPTURED) PetscFunctionReturn(0);
  name_len = strcspn(name, " :\n");
  open     = name + name_len;
  if (*open == ':') ++open;
  if (strncmp(open, " <", 2)) PetscFunctionReturn(0); /* a viewer's forms, a text: no value */
  open += 2;
  if (!strncmp(open, "now ", 4)) open += 4;
  end = strstr(open, " : ");
  if (!end || (strchr(open, '>') && strchr(open, '>') < end && strncmp(open, "<unspecified>", 13)))
    end = strchr(open, '>');
  if (!end) PetscFunctionReturn(0);
  PetscCall(PetscStrncpy(value, open, PetscMin(sizeof(value), (size_t)(end - open + 1))));
  if (!strcmp(value, "<unspecified>")) PetscFunctionReturn(0);
  /* PETSc 3.18 prints an uninitialized buffer as the default of -<prefix>dm_plex_boundary_label:
     bytes that are no text (a run's summary.json was then no UTF-8, and a test read none) */
  if (!IsText(value)) PetscFunctionReturn(0);
  PetscCall(PetscStrncpy(option, name, PetscMin(sizeof(option), name_len + 1)));
  PetscCall(Captured(option, value));
  PetscFunctionReturn(0);
}

/* One complete line: fsiopt's kept, a header kept until a line of its block is printed. */
static PetscErrorCode Line(const char line[])
{
  PetscFunctionBeginUser;
  if (capturing) PetscCall(CaptureLine(line));
  else if (IsOwn(line)) {
    if (n_held < MAX_HELD) PetscCall(PetscStrallocpy(line, &held[n_held++]));
  } else if (!strncmp(line, "-----", 5)) {
    PetscCall(PetscStrncpy(pending_header, line, sizeof(pending_header)));
  } else if (pending_header[0] && line[0] != ' ' && strlen(line) > 1 && line[strlen(line) - 2] == ':') {
    PetscCall(PetscStrlcat(pending_header, line, sizeof(pending_header)));
  } else {
    if (pending_header[0]) PetscCall(KeepPETScLine(pending_header));
    pending_header[0] = 0;
    PetscCall(KeepPETScLine(line));
  }
  PetscFunctionReturn(0);
}

static PetscErrorCode Collect(MPI_Comm comm, const char format[], ...)
{
  va_list args;
  size_t  used = strlen(partial);
  char   *start, *end;

  PetscFunctionBeginUser;
  help_comm = comm;
  va_start(args, format);
  vsnprintf(partial + used, sizeof(partial) - used, format, args);
  va_end(args);
  for (start = partial; (end = strchr(start, '\n'));) {
    const char saved = end[1];
    end[1]           = 0;
    PetscCall(Line(start));
    end[1] = saved;
    start  = end + 1;
  }
  memmove(partial, start, strlen(start) + 1);
  PetscFunctionReturn(0);
}

/* PETSc prints the choices of a type (PetscFunctionListPrintTypes) with fprintf to the C
   library's stdout, not through PetscHelpPrintf: glibc lets stdout be reassigned, so those
   lines go to memory during the capture while PETSc's PETSC_STDOUT (PetscPrintf) still
   writes where it did. */
static FILE  *real_stdout = NULL, *type_lines = NULL;
static char  *type_text = NULL;
static size_t type_len  = 0;

void HelpListingCaptureAbandon(void)
{
  if (!real_stdout) return;
  fclose(type_lines);
  free(type_text);
  stdout      = real_stdout;
  real_stdout = NULL;
}

static PetscErrorCode DivertStdout(void)
{
  PetscFunctionBeginUser;
  fflush(stdout);
  PetscCheck(type_lines = open_memstream(&type_text, &type_len), PETSC_COMM_SELF, PETSC_ERR_MEM,
             "cannot open a memory stream");
  real_stdout = stdout;
  stdout      = type_lines;
  PetscFunctionReturn(0);
}

/* after the listing: what objects still print at their destruction (-log_view's viewers) */
static PetscErrorCode Discard(MPI_Comm comm, const char format[], ...)
{
  (void)comm;
  (void)format;
  return 0;
}

PetscErrorCode HelpListingBegin(void)
{
  PetscFunctionBeginUser;
  if (!OptionsHelpRequested() || petsc_help_printf) PetscFunctionReturn(0);
  petsc_help_printf = PetscHelpPrintf;
  PetscHelpPrintf   = Collect;
  help_comm         = PETSC_COMM_WORLD;
  PetscCall(DivertStdout());
  PetscFunctionReturn(0);
}

/* the modules' prefixes, in the order printed; an option under none is the run's; the scenes'
   prefixes (OptionsDeclareHelpGroup) follow, the checks of internals (TESTING) last */
#define TESTING "checks"
static const char *const module_groups[] = {"", "fluid_", "structure_", "coupling_", "tao_", "mesh_", "checkpoint_"};
#define N_MODULE_GROUPS ((int)(sizeof(module_groups) / sizeof(module_groups[0])))

/* the i-th group in the order printed; NULL past the last */
static const char *Group(int i)
{
  int declared = 0;

  if (i < N_MODULE_GROUPS) return module_groups[i];
  while (OptionsDeclaredHelpGroup(declared)) ++declared;
  if (i < N_MODULE_GROUPS + declared) return OptionsDeclaredHelpGroup(i - N_MODULE_GROUPS);
  return i == N_MODULE_GROUPS + declared ? TESTING : NULL;
}

/* a check of the code's internals or a fault injection: derivative tests, backend and rank
   comparisons, signals sent by the run to itself */
static PetscBool IsCheck(const char line[])
{
  char name[128];
  int  n = 0;

  while (line[2 + n] && line[2 + n] != ' ' && line[2 + n] != ':' && n < 127) {
    name[n] = line[2 + n];
    ++n;
  }
  name[n] = 0;
  return (strstr(name, "_test_") || (strstr(name, "check") && !strstr(name, "checkpoint"))) ? PETSC_TRUE : PETSC_FALSE;
}

static PetscBool InGroup(const char line[], const char group[])
{
  if (!strcmp(group, TESTING)) return IsCheck(line);
  if (IsCheck(line)) return PETSC_FALSE;
  if (group[0]) return !strncmp(line + 3, group, strlen(group)) ? PETSC_TRUE : PETSC_FALSE;
  for (int i = 1; Group(i); ++i)
    if (strcmp(Group(i), TESTING) && !strncmp(line + 3, Group(i), strlen(Group(i)))) return PETSC_FALSE;
  return PETSC_TRUE;
}

static const char *GroupTitle(const char group[])
{
  if (!group[0]) return "the run (no prefix)";
  if (!strcmp(group, TESTING)) return "checks of the code and fault injection (for testing, not for production runs)";
  return group;
}

PetscErrorCode HelpListingEnd(const char units[])
{
  PetscFunctionBeginUser;
  if (!petsc_help_printf) PetscFunctionReturn(0);
  if (partial[0]) PetscCall(Line(partial));
  fflush(type_lines);
  if (type_text) PetscCall(KeepPETScLine(type_text)); /* the types' choices, printed to stdout */
  HelpListingCaptureAbandon();
  PetscHelpPrintf   = petsc_help_printf;
  petsc_help_printf = NULL;
  PetscCall(PetscHelpPrintf(help_comm, "fsiopt: fluid-structure interaction by optimization-based decoupling.\n"
                                       "  fsiopt -options_file options/<scene>.yaml [options]   or   fsiopt -scene "
                                       "<name> [options]\n"));
  if (!units) units = "nondimensional";
  if (n_held)
    PetscCall(PetscHelpPrintf(help_comm, "fsiopt's options, by prefix, -name <value>: what it is [unit] (values in %s%s):\n",
                              units, strcmp(units, "nondimensional") ? " units" : " form"));
  for (int i = 0; Group(i); ++i) {
    const char *g   = Group(i);
    PetscBool   any = PETSC_FALSE;
    for (int j = 0; j < n_held; ++j) {
      char          *line = held[j], *tail, name[128];
      const char    *unit = NULL;
      UnitDimension  dimension;
      size_t         n = strcspn(line + 2, " :\n");
      if (!InGroup(line, g)) continue;
      if (!any) PetscCall(PetscHelpPrintf(help_comm, " %s\n", GroupTitle(g)));
      any = PETSC_TRUE;
      if (n < sizeof(name)) {
        memcpy(name, line + 2, n);
        name[n] = 0;
        if (OptionsDeclaredUnit(name, &dimension)) unit = UnitName(units, dimension);
      }
      if ((tail = strstr(line, " (None)\n"))) *tail = 0; /* PETSc names a manual page here; ours have none */
      else if ((tail = strrchr(line, '\n'))) *tail = 0;
      if (unit && strlen(line) > strlen(unit) && !strcmp(line + strlen(line) - strlen(unit), unit))
        unit = NULL; /* the text ends with it */
      PetscCall(PetscHelpPrintf(help_comm, "%s%s%s%s\n", line, unit ? " [" : "", unit ? unit : "", unit ? "]" : ""));
    }
  }
  for (int i = 0; i < n_held; ++i) PetscCall(PetscFree(held[i]));
  n_held = 0;
  if (list_petsc) {
    PetscCall(PetscHelpPrintf(help_comm, "PETSc's options of the objects this set-up made:\n"));
    if (petsc_text) PetscCall(PetscHelpPrintf(help_comm, "%s", petsc_text));
  } else
    PetscCall(PetscHelpPrintf(help_comm, "PETSc's options of the solvers, meshes and viewers this set-up made "
                                         "(-fluid_ksp_type, -structure_pc_type, ...): -help all\n"));
  PetscCall(PetscFree(petsc_text));
  petsc_len = petsc_size = 0;
  if (!list_petsc) PetscHelpPrintf = Discard;
  PetscFunctionReturn(0);
}

static PetscErrorCode ForgetCaptured(void)
{
  PetscFunctionBeginUser;
  for (PetscInt i = 0; i < n_captured; ++i) {
    PetscCall(PetscFree(captured_name[i]));
    PetscCall(PetscFree(captured_value[i]));
  }
  n_captured = 0;
  PetscFunctionReturn(0);
}

PetscErrorCode HelpListingCaptureBegin(void)
{
  PetscFunctionBeginUser;
  if (OptionsHelpRequested() || petsc_help_printf) PetscFunctionReturn(0);
  PetscCall(DivertStdout());
  /* PETSc objects print the options they read, with the values they took, only under
     -help: set it for the set-up, and keep what they print instead of printing it */
  PetscCall(PetscOptionsSetValue(NULL, "-help", NULL));
  PetscCall(PetscRegisterFinalize(ForgetCaptured));
  petsc_help_printf = PetscHelpPrintf;
  PetscHelpPrintf   = Collect;
  capturing         = PETSC_TRUE;
  PetscFunctionReturn(0);
}

/* Objects that live on some ranks only (the structure's, with -structure_ranks) print
   their options there: rank 0, which writes summary.json, gathers them. */
static PetscErrorCode GatherOnFirstRank(MPI_Comm comm)
{
  PetscMPIInt rank, size, mine = 0, *lengths = NULL, *offsets = NULL;
  char       *packed, *all = NULL;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  if (size == 1) PetscFunctionReturn(0);
  for (PetscInt i = 0; i < n_captured; ++i)
    mine += (PetscMPIInt)(strlen(captured_name[i]) + strlen(captured_value[i]) + 2);
  PetscCall(PetscMalloc1(mine + 1, &packed));
  for (PetscInt i = 0, at = 0; i < n_captured; ++i) {
    at += sprintf(packed + at, "%s", captured_name[i]) + 1;
    at += sprintf(packed + at, "%s", captured_value[i]) + 1;
  }
  if (!rank) PetscCall(PetscMalloc2(size, &lengths, size + 1, &offsets));
  PetscCallMPI(MPI_Gather(&mine, 1, MPI_INT, lengths, 1, MPI_INT, 0, comm));
  if (!rank) {
    offsets[0] = 0;
    for (PetscMPIInt r = 0; r < size; ++r) offsets[r + 1] = offsets[r] + lengths[r];
    PetscCall(PetscMalloc1(offsets[size] + 1, &all));
  }
  PetscCallMPI(MPI_Gatherv(packed, mine, MPI_CHAR, all, lengths, offsets, MPI_CHAR, 0, comm));
  if (!rank)
    for (char *c = all + lengths[0]; c < all + offsets[size];) {
      const char *name = c, *value = c + strlen(c) + 1;
      PetscCall(Captured(name, value));
      c = (char *)value + strlen(value) + 1;
    }
  PetscCall(PetscFree(packed));
  if (!rank) PetscCall(PetscFree2(lengths, offsets));
  PetscCall(PetscFree(all));
  PetscFunctionReturn(0);
}

PetscErrorCode HelpListingCaptureEnd(void)
{
  PetscFunctionBeginUser;
  if (!capturing) PetscFunctionReturn(0);
  if (partial[0]) PetscCall(CaptureLine(partial));
  fflush(type_lines);
  for (char *line = type_text, *next; line && *line; line = next) {
    next = strchr(line, '\n');
    if (next) *next++ = 0;
    PetscCall(CaptureLine(line));
  }
  HelpListingCaptureAbandon();
  partial[0]        = 0;
  PetscHelpPrintf   = petsc_help_printf;
  petsc_help_printf = NULL;
  capturing         = PETSC_FALSE;
  PetscCall(PetscOptionsClearValue(NULL, "-help"));
  PetscCall(GatherOnFirstRank(PETSC_COMM_WORLD));
  PetscFunctionReturn(0);
}

PetscErrorCode HelpListingGetCapturedOptions(PetscInt *n, char *const **names, char *const **values)
{
  PetscFunctionBeginUser;
  *n      = n_captured;
  *names  = captured_name;
  *values = captured_value;
  PetscFunctionReturn(0);
}
