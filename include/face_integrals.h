/* Integrals over the fluid's face sets as columns of probes.csv (-integrals_flow_rate,
   -integrals_mean_pressure, -integrals_force: face sets by name or number), over its regions
   (-integrals_region_volume, _mean_pressure, _kinetic_energy: by name, number or all), and the state of
   the fluid's 0D outlets (the outlet pressure of each), each column with its unit. */
#ifndef FSIOPT_FACE_INTEGRALS_H
#define FSIOPT_FACE_INTEGRALS_H
#include "fluid.h"
#include "units.h"

typedef struct _p_FaceIntegrals *FaceIntegrals;

/* Reads the options on every rank of comm; fluid NULL on a rank that holds none, or in a
   scene without one. *integrals NULL when nothing is asked and the fluid has no 0D outlet. */
PetscErrorCode FaceIntegralsCreate(MPI_Comm, PetscInt dim, Fluid, FaceIntegrals *integrals);
PetscErrorCode FaceIntegralsGetColumns(FaceIntegrals, PetscInt *n, const char *const **names,
                                       const UnitDimension **units);
/* The values of the columns now, on every rank of comm. */
PetscErrorCode FaceIntegralsEvaluate(FaceIntegrals, PetscReal values[]);
PetscErrorCode FaceIntegralsDestroy(FaceIntegrals *);
#endif
