/* A quantity given as a table of (t, value) rows in a CSV file (an inflow's flow rate over a
   cardiac cycle), interpolated linearly between rows and, when periodic, repeated with the
   period the table spans; expressions call it by name (expression.h). */
#ifndef FSIOPT_WAVEFORM_H
#define FSIOPT_WAVEFORM_H
#include <petscsys.h>

typedef struct _p_Waveform *Waveform;

/* Reads `path` (which `option` named) on the first rank: rows "t,value" (a first line that is
   not two numbers is a header), at least two, t strictly increasing. A file missing, empty,
   with a row that is not two numbers or out of order stops the run with one line naming the
   file and the line. Not periodic: [t_start, t_final] must lie within the table's span. */
PetscErrorCode WaveformLoad(MPI_Comm, const char option[], const char path[], PetscBool periodic, PetscReal t_start,
                            PetscReal t_final, Waveform *);
PetscReal      WaveformValue(Waveform, PetscReal t);
PetscErrorCode WaveformDestroy(Waveform *);
#endif
