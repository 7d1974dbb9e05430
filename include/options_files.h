#ifndef FSIOPT_OPTIONS_FILES_H
#define FSIOPT_OPTIONS_FILES_H
/* Shared by the check of options files (options_files.c) and of YAML ones (options_yaml.c),
   both run before PetscInitialize: plain C and libyaml. */
#include <stddef.h>
#include <petscsys.h> /* PETSC_MAX_OPTION_NAME: only the macro, nothing of PETSc runs yet */

/* PETSc 3.18 keeps at most 512 options (MAXOPTIONS in src/sys/objects/options.c) and
   answers the next with its banner, or fsiopt's set-up with an error; the scenes' and
   methods' defaults take up to 256 of them (OPTIONS_MAX_DEFAULTS in options.c) */
#define PETSC_MAX_OPTIONS 512
#define MAX_GIVEN_OPTIONS (PETSC_MAX_OPTIONS - 256)
#define MAX_INCLUDE_DEPTH 16
#define MAX_FILE_BYTES    (16 << 20)

typedef struct {
  char *name; /* without the leading '-' */
  int   file, line;
  long  time; /* when it was last set, counting every option set */
} CheckedOption;

typedef struct {
  char          message[2 * 4096];
  const char   *stack[MAX_INCLUDE_DEPTH]; /* the real paths of the files being read, outermost first */
  int           depth;
  int           file; /* which file is being read (each one read gets a number) */
  int           files;
  long          time;
  CheckedOption options[MAX_GIVEN_OPTIONS]; /* the options given, from every source */
  int           noptions;
} Check;

int CheckFail(Check *check, const char *format, ...) __attribute__((format(printf, 2, 3)));
/* Records an option of the current file, at line. unique: the file is YAML, where an option
   may be set once, unless the earlier setting was made at a time in [from, to) (the mapping's
   merge key that the key overrides). Fails past MAX_GIVEN_OPTIONS. */
int CheckOption(Check *check, const char path[], const char name[], int line, int unique, long from, long to);
int CheckYAML(Check *check, const char path[], const char *text, size_t n);
#endif
