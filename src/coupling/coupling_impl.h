#ifndef FSIOPT_COUPLING_IMPL_H
#define FSIOPT_COUPLING_IMPL_H
#include "coupling.h"
#include "history.h"

/* What every coupling method shares; a method fills `ops` and keeps its own data. */
struct _p_Coupling {
  char            method[16];
  CouplingProblem problem;
  History         history;
  CouplingStats   stats;
  Vec             x; /* the scaled control, carried from step to step */
#define FSIOPT_EXTRAPOLATION_MAX 3
  Vec             past[FSIOPT_EXTRAPOLATION_MAX + 1]; /* x^{n-1}, x^{n-2}, ... for the extrapolated start */
  PetscInt        npast, extrapolation;
  PetscReal       tol;
  PetscInt        max_it;
  struct {
    PetscErrorCode (*step)(Coupling, PetscInt);
    PetscErrorCode (*destroy)(Coupling);
    const char *(*optimizer)(Coupling);
  } ops;
  void *data;
};

PetscErrorCode CouplingCreate_Opt(Coupling);
PetscErrorCode CouplingCreate_Partitioned(Coupling); /* dn, aitken, iqnils */
#endif
