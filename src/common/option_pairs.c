/* The options database's string as pairs (option_pairs.h): summary.json's options and the
   restart fingerprint. */
#include "option_pairs.h"
#include <stdio.h>
#include <string.h>

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

int OptionsCommandLineCheck(int argc, char **argv, char message[], size_t len)
{
  for (int i = 1; i < argc; ++i) {
    const char *value_i = i + 1 < argc && !StartsOption(argv[i + 1], argv[i + 1]) ? argv[i + 1] : "";
    if (!StartsOption(argv[i], argv[i]) || !strcmp(argv[i], "-options_file")) continue;
    for (int j = i + 1; j < argc; ++j) {
      const char *value_j = j + 1 < argc && !StartsOption(argv[j + 1], argv[j + 1]) ? argv[j + 1] : "";
      if (strcmp(argv[i], argv[j]) || !StartsOption(argv[j], argv[j])) continue;
      if (strcmp(value_i, value_j)) {
        snprintf(message, len, "option %s: given twice on the command line (%s, then %s); give it once", argv[i],
                 value_i[0] ? value_i : "without a value", value_j[0] ? value_j : "without a value");
        return 1;
      }
    }
  }
  return 0;
}
