/* Values of the fields at any points (-probes_fluid_velocity, -probes_fluid_pressure,
   -probes_structure_displacement, -probes_structure_velocity): each point located in the cell
   that holds it, on whichever rank owns that cell, and the field evaluated there by its own
   finite element (all its nodes, not only the vertices). The fluid's points are in the
   current configuration (the moving mesh), the structure's in the reference one. They become
   columns of probes.csv, each with its unit. */
#ifndef FSIOPT_POINT_VALUES_H
#define FSIOPT_POINT_VALUES_H
#include "fluid.h"
#include "structure.h"
#include "units.h"

typedef struct _p_PointValues *PointValues;

/* Reads the options on every rank of comm; fluid or structure NULL on a rank that holds none
   (-structure_ranks), or in a scene without one. *values NULL when no option asks for a point. */
PetscErrorCode PointValuesCreate(MPI_Comm, PetscInt dim, Fluid, Structure, PointValues *values);
/* The columns: n of them, their names ("u_x(1.5;0.5)") and units. */
PetscErrorCode PointValuesGetColumns(PointValues, PetscInt *n, const char *const **names, const UnitDimension **units);
/* The values of the columns now, on every rank; a point that left its mesh stops the run. */
PetscErrorCode PointValuesEvaluate(PointValues, PetscReal values[]);
PetscErrorCode PointValuesDestroy(PointValues *);
#endif
