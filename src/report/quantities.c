/* What summary.json reports of a time series: the final value, or over the last `window`
   seconds the mean and amplitude as Turek and Hron define them for periodic signals,
   (max + min)/2 and (max - min)/2, and the frequency of the upward crossings of that mean
   (none when the amplitude is below 1e-5 of the values: a steady signal). */
#include "probes.h"

PetscErrorCode QuantityAnalyze(PetscInt n, const PetscReal t[], const PetscReal v[], PetscReal window, PetscReal *final,
                               PetscReal *mean, PetscReal *amplitude, PetscReal *frequency)
{
  PetscInt  first = n - 1, crossings = 0;
  PetscReal lo, hi, t_first = 0, t_last = 0;

  PetscFunctionBeginUser;
  *final = *mean = *amplitude = *frequency = -1;
  if (n < 1) PetscFunctionReturn(0);
  *final = v[n - 1];
  if (window <= 0) PetscFunctionReturn(0);
  while (first > 0 && t[first - 1] >= t[n - 1] - window * (1 + 1e-12)) --first;
  lo = hi = v[first];
  for (PetscInt i = first; i < n; ++i) {
    lo = PetscMin(lo, v[i]);
    hi = PetscMax(hi, v[i]);
  }
  *mean      = 0.5 * (hi + lo);
  *amplitude = 0.5 * (hi - lo);
  /* a steady signal's round-off crosses its mean at random: no frequency */
  if (*amplitude <= 1e-5 * PetscMax(PetscAbsReal(hi), PetscAbsReal(lo))) PetscFunctionReturn(0);
  for (PetscInt i = first; i + 1 < n; ++i) {
    const PetscReal a = v[i] - *mean, b = v[i + 1] - *mean;
    if (a < 0 && b >= 0) {
      const PetscReal tc = t[i] + (t[i + 1] - t[i]) * (-a) / (b - a);
      if (!crossings) t_first = tc;
      t_last = tc;
      ++crossings;
    }
  }
  if (crossings >= 2) *frequency = (crossings - 1) / (t_last - t_first);
  PetscFunctionReturn(0);
}
