/* Files PETSc writes on request (output_files.h): a viewer option's "type:FILE[:format[:mode]]"
   or -log_view's ":FILE". PETSc writes them at the end of a solve or of the run, so one that
   names a file of the run's own (its outputs in -output_dir, its checkpoint) would replace it,
   or be replaced by it, and one in a directory that is not there would fail with PETSc's
   banner, only after the last step. They are checked before the first. */
#include <errno.h>
#include <libgen.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "output_files.h"
#include "option_pairs.h"

/* The real path of the directory a file would be in (the file need not exist), or 0 */
static int ParentReal(const char file[], char real[PATH_MAX])
{
  char copy[PATH_MAX];

  (void)snprintf(copy, sizeof(copy), "%s", file);
  return realpath(dirname(copy), real) != NULL;
}

static int StartsWith(const char s[], const char head[])
{
  return !strncmp(s, head, strlen(head));
}

PetscBool OutputDirHolds(const char file[], const char output_dir[], const char **clash)
{
  char        dir[PATH_MAX], out[PATH_MAX], copy[PATH_MAX];
  const char *base;

  *clash = NULL;
  if (!ParentReal(file, dir) || !realpath(output_dir, out) || strcmp(dir, out)) return PETSC_FALSE;
  (void)snprintf(copy, sizeof(copy), "%s", file);
  base = basename(copy);
  for (int i = 0; OutputFileNames[i] && !*clash; ++i)
    if (StartsWith(base, OutputFileNames[i])) *clash = OutputFileNames[i];
  return PETSC_TRUE;
}

/* Rank 0: the run's own file that `file` would overwrite (a name of OutputFileNames in
   output_dir, or the checkpoint), else NULL. */
static const char *OwnFile(const char file[], const char output_dir[], const char checkpoint[])
{
  const char *clash;

  if (checkpoint && checkpoint[0]) {
    char dir[PATH_MAX], cp_dir[PATH_MAX], copy[PATH_MAX], cp_copy[PATH_MAX];
    (void)snprintf(copy, sizeof(copy), "%s", file);
    (void)snprintf(cp_copy, sizeof(cp_copy), "%s", checkpoint);
    if (ParentReal(file, dir) && ParentReal(checkpoint, cp_dir) && !strcmp(dir, cp_dir) &&
        StartsWith(basename(copy), basename(cp_copy)))
      return "checkpoint (-checkpoint_file)";
  }
  (void)OutputDirHolds(file, output_dir, &clash);
  return clash;
}

/* The viewer types that write a file named after the colon (draw and socket viewers name a
   display or a host there) */
static int WritesFile(const char type[])
{
  static const char *const types[] = {"", "ascii", "binary", "hdf5", "vtk", NULL};

  for (int i = 0; types[i]; ++i)
    if (!strcmp(type, types[i])) return 1;
  return 0;
}

/* Whether a file could be written there (its directory exists and takes files); errno says why not */
static int Writable(const char file[])
{
  char copy[PATH_MAX];

  (void)snprintf(copy, sizeof(copy), "%s", file);
  return access(dirname(copy), W_OK | X_OK) == 0;
}

PetscErrorCode OutputCheckViewerFiles(MPI_Comm comm, const char output_dir[], const char checkpoint[])
{
  PetscMPIInt rank;
  char        message[2 * PETSC_MAX_PATH_LEN + 256] = "";

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (!rank) {
    char        *all;
    OptionPairs *pairs;
    PetscCall(PetscNew(&pairs));
    PetscCall(PetscOptionsGetAll(NULL, &all));
    OptionPairsParse(all, pairs);
    for (PetscInt i = 0; i < pairs->n && !message[0]; ++i) {
      char        value[PATH_MAX], *file, *end;
      const char *own;
      (void)snprintf(value, sizeof(value), "%.*s", (int)pairs->value_len[i], pairs->value[i]);
      if (!(file = strchr(value, ':'))) continue; /* a viewer type alone writes to the screen */
      /* a viewer's type is one word (ascii, binary, hdf5, ...) or none: an expression's ": " is no file */
      if (strspn(value, "abcdefghijklmnopqrstuvwxyz0123456789_") != (size_t)(file - value)) continue;
      *file++ = 0;
      if ((end = strchr(file, ':'))) *end = 0;
      if (!file[0]) continue;
      if ((own = OwnFile(file, output_dir, checkpoint)))
        (void)snprintf(message, sizeof(message),
                       "option %.*s: PETSc would write %s over the run's own %s; choose another file name",
                       (int)pairs->name_len[i], pairs->name[i], file, own);
      else if (WritesFile(value) && !Writable(file))
        (void)snprintf(message, sizeof(message), "option %.*s: PETSc could not write %s (%s)",
                       (int)pairs->name_len[i], pairs->name[i], file, strerror(errno));
    }
    PetscCall(PetscFree(all));
    PetscCall(PetscFree(pairs));
  }
  PetscCallMPI(MPI_Bcast(message, sizeof(message), MPI_CHAR, 0, comm));
  PetscCheck(!message[0], comm, PETSC_ERR_ARG_WRONG, "%s", message);
  PetscFunctionReturn(0);
}
