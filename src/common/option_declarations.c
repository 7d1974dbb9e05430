/* What an option's value is measured in, the option prefixes -help groups fsiopt's options
   by, and the families of options whose names a run makes (-fluid_boundary_NAME of a mesh's
   face sets): declared by the code that reads the options (a scene declares its own), looked
   up by -help's listing (report/help_listing.c), so a new scene or module edits no table there. */
#include <string.h>
#include "options.h"

#define MAX_UNITS  128
#define MAX_GROUPS 32

static struct {
  char          name[64];
  UnitDimension dimension;
} units[MAX_UNITS];
static char groups[MAX_GROUPS][64];
static char families[MAX_GROUPS][64];
static int  n_units = 0, n_groups = 0, n_families = 0;

PetscErrorCode OptionsDeclareUnit(const char name[], UnitDimension dimension)
{
  PetscFunctionBeginUser;
  for (int i = 0; i < n_units; ++i)
    if (!strcmp(units[i].name, name)) {
      units[i].dimension = dimension;
      PetscFunctionReturn(0);
    }
  PetscCheck(n_units < MAX_UNITS && strlen(name) < sizeof(units[0].name), PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "option %s: no room to declare its unit (at most %d options of names under %d characters)", name,
             MAX_UNITS, (int)sizeof(units[0].name));
  PetscCall(PetscStrncpy(units[n_units].name, name, sizeof(units[0].name)));
  units[n_units++].dimension = dimension;
  PetscFunctionReturn(0);
}

PetscBool OptionsDeclaredUnit(const char name[], UnitDimension *dimension)
{
  for (int i = 0; i < n_units; ++i)
    if (!strcmp(units[i].name, name)) {
      *dimension = units[i].dimension;
      return PETSC_TRUE;
    }
  return PETSC_FALSE;
}

/* prefix into a table of prefixes, once */
static PetscErrorCode AddPrefix(char table[][64], int *n, const char what[], const char prefix[])
{
  PetscFunctionBeginUser;
  for (int i = 0; i < *n; ++i)
    if (!strcmp(table[i], prefix)) PetscFunctionReturn(0);
  PetscCheck(*n < MAX_GROUPS && strlen(prefix) < 64, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "option %s %s: no room to declare it (at most %d, each under 64 characters)", what, prefix, MAX_GROUPS);
  PetscCall(PetscStrncpy(table[(*n)++], prefix, 64));
  PetscFunctionReturn(0);
}

PetscErrorCode OptionsDeclareHelpGroup(const char prefix[])
{
  PetscFunctionBeginUser;
  PetscCall(AddPrefix(groups, &n_groups, "prefix", prefix));
  PetscFunctionReturn(0);
}

const char *OptionsDeclaredHelpGroup(int i)
{
  return i >= 0 && i < n_groups ? groups[i] : NULL;
}

PetscErrorCode OptionsDeclareFamily(const char prefix[])
{
  PetscFunctionBeginUser;
  PetscCall(AddPrefix(families, &n_families, "family", prefix));
  PetscFunctionReturn(0);
}

PetscBool OptionsInDeclaredFamily(const char name[])
{
  for (int i = 0; i < n_families; ++i)
    if (!strncmp(name, families[i], strlen(families[i]))) return PETSC_TRUE;
  return PETSC_FALSE;
}
