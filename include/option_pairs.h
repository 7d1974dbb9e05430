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
#endif
