#ifndef FSIOPT_HELP_H
#define FSIOPT_HELP_H
#include <petscsys.h>

/* Under -help, fsiopt's own option lines are held back from PETSc's listing (Begin) and
   printed at its end grouped by prefix, with their units in the scene's system (End). */
PetscErrorCode HelpListingBegin(void);
/* -help all (main.c, from the command line): PETSc's own lines follow fsiopt's */
void           HelpListingSetPETSc(PetscBool all);
PetscErrorCode HelpListingEnd(const char units[]);
/* Around a run's set-up without -help: the options every object reads, with the values
   they take (given or default), for summary.json (HelpListingGetCapturedOptions: n pairs,
   in the order read; names with their dash). */
PetscErrorCode HelpListingCaptureBegin(void);
PetscErrorCode HelpListingCaptureEnd(void);
/* main's error path (no PETSc call): stdout as it was */
void           HelpListingCaptureAbandon(void);
PetscErrorCode HelpListingGetCapturedOptions(PetscInt *n, char *const **names, char *const **values);
#endif
