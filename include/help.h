#ifndef FSIOPT_HELP_H
#define FSIOPT_HELP_H
#include <petscsys.h>

/* Under -help, fsiopt's own option lines are held back from PETSc's listing (Begin) and
   printed at its end grouped by prefix, with their units in the scene's system (End). */
PetscErrorCode HelpListingBegin(void);
PetscErrorCode HelpListingEnd(const char units[]);
#endif
