/* Waveforms from CSV files (waveform.h): read on the first rank, checked row by row, handed to
   every rank; evaluated by bisection and linear interpolation. */
#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "waveform.h"
#include "options.h"

struct _p_Waveform {
  PetscInt   n;
  PetscReal *t, *v;
  PetscBool  periodic;
};

/* "t,value" or "t value": the two numbers of a line; 0 when it is not that */
static int ParseRow(const char line[], double *t, double *v)
{
  char *end;

  errno = 0;
  *t    = strtod(line, &end);
  if (end == line || errno) return 0;
  while (*end == ' ' || *end == '\t') ++end;
  if (*end == ',' || *end == ';') ++end;
  line = end;
  *v   = strtod(line, &end);
  if (end == line || errno) return 0;
  while (*end && isspace((unsigned char)*end)) ++end;
  return *end == 0;
}

/* rank 0: the rows into w, or a reason in why */
static void ReadRows(const char path[], Waveform w, char why[], size_t len)
{
  FILE  *fp = fopen(path, "r");
  char   line[1024];
  int    number = 0;
  size_t capacity = 0;

  why[0] = 0;
  if (!fp) {
    snprintf(why, len, "cannot be read (%s)", strerror(errno));
    return;
  }
  while (fgets(line, sizeof(line), fp)) {
    double t, v;
    char  *s = line;
    ++number;
    while (isspace((unsigned char)*s)) ++s;
    if (!*s || *s == '#') continue;
    if (!ParseRow(s, &t, &v)) {
      if (!w->n && number == 1) continue; /* a header */
      line[strcspn(line, "\r\n")] = 0;
      snprintf(why, len, "line %d: expected two numbers t,value; got \"%.60s\"", number, line);
      break;
    }
    if (w->n && t <= w->t[w->n - 1]) {
      snprintf(why, len, "line %d: t = %g does not come after the row before's t = %g (rows in increasing t)", number,
               t, (double)w->t[w->n - 1]);
      break;
    }
    if ((size_t)w->n == capacity) {
      capacity = capacity ? 2 * capacity : 64;
      w->t     = realloc(w->t, capacity * sizeof(PetscReal));
      w->v     = realloc(w->v, capacity * sizeof(PetscReal));
    }
    w->t[w->n]   = t;
    w->v[w->n++] = v;
  }
  fclose(fp);
  if (!why[0] && w->n < 2) snprintf(why, len, "has %s; expected at least two rows t,value", w->n ? "one row" : "no rows");
}

PetscErrorCode WaveformLoad(MPI_Comm comm, const char option[], const char path[], PetscBool periodic, PetscReal t_start,
                            PetscReal t_final, Waveform *waveform)
{
  Waveform    w;
  PetscMPIInt rank;
  char        why[256] = "";
  PetscInt    n        = 0;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(PetscNew(&w));
  w->periodic = periodic;
  if (!rank) {
    struct _p_Waveform rows = {0, NULL, NULL, periodic};
    ReadRows(path, &rows, why, sizeof(why));
    n = why[0] ? 0 : rows.n;
    PetscCall(PetscMalloc2(n, &w->t, n, &w->v));
    PetscCall(PetscArraycpy(w->t, rows.t, n));
    PetscCall(PetscArraycpy(w->v, rows.v, n));
    free(rows.t);
    free(rows.v);
  }
  PetscCallMPI(MPI_Bcast(why, sizeof(why), MPI_CHAR, 0, comm));
  if (why[0]) {
    PetscCall(PetscFree2(w->t, w->v));
    PetscCall(PetscFree(w));
    SETERRQ(comm, PETSC_ERR_FILE_UNEXPECTED, "option %s: the waveform file %s %s", option, path, why);
  }
  PetscCallMPI(MPI_Bcast(&n, 1, MPIU_INT, 0, comm));
  if (rank) PetscCall(PetscMalloc2(n, &w->t, n, &w->v));
  PetscCallMPI(MPI_Bcast(w->t, (PetscMPIInt)n, MPIU_REAL, 0, comm));
  PetscCallMPI(MPI_Bcast(w->v, (PetscMPIInt)n, MPIU_REAL, 0, comm));
  w->n = n;
  if (!periodic) {
    const PetscReal slack = 1e-12 * PetscMax(1.0, PetscAbsReal(t_final));
    if (t_start < w->t[0] - slack || t_final > w->t[n - 1] + slack) {
      const PetscReal first = w->t[0], last = w->t[n - 1];
      PetscCall(WaveformDestroy(&w));
      SETERRQ(comm, PETSC_ERR_ARG_OUTOFRANGE,
              "option %s: the waveform file %s spans t = %g to %g, not the run's %g to %g (or make it periodic)", option,
              path, (double)first, (double)last, (double)t_start, (double)t_final);
    }
  }
  *waveform = w;
  PetscFunctionReturn(0);
}

PetscReal WaveformValue(Waveform w, PetscReal t)
{
  const PetscReal first = w->t[0], last = w->t[w->n - 1];
  PetscInt        lo = 0, hi = w->n - 1;

  if (w->periodic) t = first + PetscFmodReal(PetscFmodReal(t - first, last - first) + (last - first), last - first);
  if (t <= first) return w->v[0];
  if (t >= last) return w->v[w->n - 1];
  while (hi - lo > 1) {
    const PetscInt mid = (lo + hi) / 2;
    if (w->t[mid] <= t) lo = mid;
    else hi = mid;
  }
  return w->v[lo] + (w->v[hi] - w->v[lo]) * (t - w->t[lo]) / (w->t[hi] - w->t[lo]);
}

PetscErrorCode WaveformDestroy(Waveform *waveform)
{
  PetscFunctionBeginUser;
  if (!*waveform) PetscFunctionReturn(0);
  PetscCall(PetscFree2((*waveform)->t, (*waveform)->v));
  PetscCall(PetscFree(*waveform));
  PetscFunctionReturn(0);
}
