/* The error norms a scene with an exact solution reports (ErrorTable, fsiopt.h): the fluid
   and the structure each fill one, summary.json and the closing lines read them. */
#include "fsiopt.h"

PetscErrorCode ErrorTableAdd(ErrorTable *table, const char name[], PetscReal value)
{
  PetscFunctionBeginUser;
  PetscCheck(table->n < FSIOPT_MAX_ERRORS, PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "too many error norms");
  PetscCall(PetscStrncpy(table->name[table->n], name, sizeof(table->name[0])));
  table->value[table->n++] = value;
  PetscFunctionReturn(0);
}
