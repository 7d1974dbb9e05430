/* The options database's string as pairs (option_pairs.h): summary.json's options and the
   restart fingerprint. */
#include "option_pairs.h"

/* A dash and a letter after a blank start an option's name (a negative number is a value). */
static PetscBool StartsOption(const char *c, const char *start)
{
  return c[0] == '-' && ((c[1] >= 'a' && c[1] <= 'z') || (c[1] >= 'A' && c[1] <= 'Z')) && (c == start || c[-1] == ' ')
         ? PETSC_TRUE
         : PETSC_FALSE;
}

void OptionPairsParse(const char *all, OptionPairs *pairs)
{
  pairs->n = 0;
  for (const char *c = all; *c && pairs->n < OPTION_PAIRS_MAX;) {
    const PetscInt i = pairs->n;
    while (*c == ' ') ++c;
    if (!*c) break;
    pairs->name[i] = c;
    while (*c && *c != ' ') ++c;
    pairs->name_len[i] = (size_t)(c - pairs->name[i]);
    while (*c == ' ') ++c;
    pairs->value[i] = c;
    while (*c && !StartsOption(c, pairs->value[i])) ++c;
    pairs->value_len[i] = (size_t)(c - pairs->value[i]);
    while (pairs->value_len[i] && pairs->value[i][pairs->value_len[i] - 1] == ' ') --pairs->value_len[i];
    pairs->n++;
  }
}
