#ifndef FSIOPT_OPTION_PAIRS_H
#define FSIOPT_OPTION_PAIRS_H
#include <petscsys.h>

/* PETSc's options database as one string (PetscOptionsGetAll: "-a 1 -b -c x y") read as
   name/value pairs pointing into it; a negative number is a value, not a name. */
#define OPTION_PAIRS_MAX 1024
typedef struct {
  PetscInt    n;
  const char *name[OPTION_PAIRS_MAX], *value[OPTION_PAIRS_MAX];
  size_t      name_len[OPTION_PAIRS_MAX], value_len[OPTION_PAIRS_MAX];
} OptionPairs;

void OptionPairsParse(const char *all, OptionPairs *);
/* Before PetscInitialize: an option given twice on the command line with different values
   (PETSc keeps the last without a word; an options file's value may be overridden once on
   the command line). Returns 0, or 1 with one line in message. -options_file may repeat. */
int  OptionsCommandLineCheck(int argc, char **argv, char message[], size_t len);
#endif
