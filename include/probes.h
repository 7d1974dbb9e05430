#ifndef FSIOPT_PROBES_H
#define FSIOPT_PROBES_H
#include "fsiopt.h"
#include "interface.h"

/* probes.csv: t, then the structure displacement (each component) at interface points,
   a PartialFile until ProbesClose(complete). */
typedef struct _p_Probes *Probes;

PetscErrorCode ProbesCreate(MPI_Comm, Interface, PetscInt n, const PetscReal points[][3], const char dir[], Probes *);
PetscErrorCode ProbesRecord(Probes, PetscReal t, Vec interface_displacement);
PetscErrorCode ProbesClose(Probes *, PetscBool complete);
#endif
