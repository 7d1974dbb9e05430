#ifndef FSIOPT_OPTIONS_H
#define FSIOPT_OPTIONS_H
#include <petscsys.h>
#include "units.h"

/* Range-checked options: a bad value stops the run with one line naming the option. */
PetscErrorCode OptionsPositiveReal(PetscOptionItems *, const char opt[], const char text[], PetscReal *value);
PetscErrorCode OptionsNonNegativeReal(PetscOptionItems *, const char opt[], const char text[], PetscReal *value);
PetscErrorCode OptionsRealInRange(PetscOptionItems *, const char opt[], const char text[], PetscReal lo, PetscReal hi,
                                  PetscReal *value);
/* Refuses an integer option (or a comma-separated list of them) whose text names a value
   PetscInt cannot hold, or PETSc's words DEFAULT, DECIDE, DETERMINE; expected says what it
   takes. prefix may be NULL. */
PetscErrorCode OptionsCheckIntegers(MPI_Comm, const char prefix[], const char opt[], const char expected[]);
PetscErrorCode OptionsIntInRange(PetscOptionItems *, const char opt[], const char text[], PetscInt lo, PetscInt hi,
                                 PetscInt *value);
/* The names of a registry (scenes, coupling methods), comma separated, for messages and -help */
PetscErrorCode OptionsListNames(PetscFunctionList, char names[], size_t len);
/* Sets an option only when the user has not: how scenes give their defaults. */
PetscErrorCode OptionsSetDefault(const char opt[], const char value[]);
/* Before the first step: an option (command line, options file, YAML key, PETSC_OPTIONS)
   that nothing read stops the run, naming it and the nearest known option, unless
   -options_allow_unused; one that fsiopt reads in other set-ups (another scene, method or
   solver) is a warning. Defaults a scene or method set and did not read are neither.
   Viewers, convergence reasons and Jacobian tests, which PETSc reads inside its solves,
   are checked after the first step (after_first_step). */
PetscErrorCode OptionsCheckUnused(MPI_Comm, PetscBool after_first_step);
/* At the start: an option that takes a value given without one (PETSc would take it as not
   given, and the run would use the default) stops the run, naming it. */
PetscErrorCode OptionsCheckValuesGiven(MPI_Comm);
/* Whether the user asked for -help (the answer of the first call: a run's set-up sets -help
   for a while to learn the options in effect, help.h). */
PetscBool OptionsHelpRequested(void);
/* Fails with a one-line message when a file cannot be read. OptionsFileProblem (usable before
   PetscInitialize) returns 0 when the file is a readable, non-empty regular file. */
int            OptionsFileProblem(const char path[]);
const char    *OptionsFileProblemText(int problem);
PetscErrorCode OptionsCheckReadableFile(MPI_Comm, const char opt[], const char path[]);

/* Declared by the code that reads an option, for -help's listing: the unit of its value
   (shown in the scene's system of units) and the prefix of a group of options (a scene's
   own: listed under it, after the modules' groups, in the order declared). */
PetscErrorCode OptionsDeclareUnit(const char name[], UnitDimension);
PetscBool      OptionsDeclaredUnit(const char name[], UnitDimension *);
PetscErrorCode OptionsDeclareHelpGroup(const char prefix[]);
const char    *OptionsDeclaredHelpGroup(int i); /* NULL past the last */
/* Options whose names a run makes from its data (-fluid_boundary_NAME for each face set
   NAME of the mesh): fsiopt's own, listed by -help with the others, by their common prefix. */
PetscErrorCode OptionsDeclareFamily(const char prefix[]);
PetscBool      OptionsInDeclaredFamily(const char name[]);

/* Before PetscInitialize, which reads them: every options file of the run (petscrc files,
   PETSC_OPTIONS, -options_file, and the files they include) is a readable text file, valid
   YAML with a mapping at the top or PETSc's -name value lines, and includes no file that
   includes it. Returns 0, or 1 with one line in message naming the file and the line. */
int OptionsFilesCheck(int argc, char **argv, char message[], size_t len);
/* The length of the well-formed UTF-8 sequence at text (at most n bytes), 0 if it is not one
   (plain C: the options files are checked with it before PETSc starts, summary.json written) */
size_t UTF8SequenceLength(const unsigned char *text, size_t n);
#endif
