#ifndef FSIOPT_PROBES_H
#define FSIOPT_PROBES_H
#include "fsiopt.h"
#include <petscviewer.h>
#include "units.h"

/* probes.csv: t, the displacement (each component) at mesh nodes, then scalar columns the
   caller computes (a body's drag and lift); a PartialFile until ProbesClose(complete).
   Rank 0 keeps the series for the quantities of summary.json. */
typedef struct _p_Probes *Probes;

#define FSIOPT_MAX_QUANTITIES 64
/* Over the window of the run's last `window` seconds: the final value, and mean = (max +
   min)/2, amplitude = (max - min)/2 and the frequency of the upward crossings of the mean
   (Turek & Hron's definitions for periodic signals; negative: does not apply). */
typedef struct {
  PetscInt  n;
  PetscReal window;
  char      name[FSIOPT_MAX_QUANTITIES][48];
  PetscReal final[FSIOPT_MAX_QUANTITIES], mean[FSIOPT_MAX_QUANTITIES], amplitude[FSIOPT_MAX_QUANTITIES],
    frequency[FSIOPT_MAX_QUANTITIES];
} QuantityTable;

/* The file `name` in dir; `nodes` local nodes with coordinates coords[nodes*dim], whose displacements are the blocks
   of size dim of the vectors ProbesRecord gets (NULL when there are no points); then nextra columns of the
   caller, each with its unit (extra_units NULL: forces). */
PetscErrorCode ProbesCreate(MPI_Comm, PetscInt dim, PetscInt nodes, const PetscReal coords[], PetscInt npoints,
                            const PetscReal points[][3], PetscInt nextra, const char *const extra_names[],
                            const UnitDimension extra_units[], const char units[], const char dir[], const char name[],
                            Probes *);
PetscErrorCode ProbesRecord(Probes, PetscReal t, Vec displacement, const PetscReal extra[]);
/* The quantities of every column, on rank 0 (window from -quantities_window), appended to
   the table's first table->n. */
PetscErrorCode ProbesQuantities(Probes, QuantityTable *);
PetscErrorCode ProbesClose(Probes *, PetscBool complete);
PetscErrorCode ProbesCheckpoint(Probes, Checkpoint, PetscBool load); /* checkpoint.h */

/* quantities.c: the analysis of one series */
PetscErrorCode QuantityAnalyze(PetscInt n, const PetscReal t[], const PetscReal v[], PetscReal window, PetscReal *final,
                               PetscReal *mean, PetscReal *amplitude, PetscReal *frequency);
#endif
