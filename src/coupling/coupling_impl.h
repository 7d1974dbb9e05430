#ifndef FSIOPT_COUPLING_IMPL_H
#define FSIOPT_COUPLING_IMPL_H
#include "coupling.h"
#include "history.h"

/* A step's start from the values of the last M steps: the polynomial of degree K fitted to
   them by least squares (lower degree and fewer values while fewer are recorded). */
#define FSIOPT_EXTRAPOLATION_MAX        3
#define FSIOPT_EXTRAPOLATION_POINTS_MAX 8
typedef struct {
  Vec      past[FSIOPT_EXTRAPOLATION_POINTS_MAX]; /* newest first */
  PetscInt npast, degree, points;
} Extrapolation;
PetscErrorCode ExtrapolationCreate(Vec model, PetscInt degree, PetscInt points, Extrapolation *);
PetscErrorCode ExtrapolationRecord(Extrapolation *, Vec x);  /* x: the newest value */
PetscErrorCode ExtrapolationPredict(Extrapolation *, Vec x); /* x: the next step's start */
PetscErrorCode ExtrapolationDestroy(Extrapolation *);

/* What every coupling method shares; a method fills `ops` and keeps its own data. */
struct _p_Coupling {
  char            method[16];
  CouplingProblem problem;
  History         history;
  CouplingStats   stats;
  Vec             x; /* the scaled control, carried from step to step */
  Extrapolation   start;   /* the control each step starts from */
  PetscReal       tol;
  PetscInt        max_it;
  struct {
    PetscErrorCode (*step)(Coupling, PetscInt);
    PetscErrorCode (*destroy)(Coupling);
    const char *(*optimizer)(Coupling);
    PetscErrorCode (*resynchronize)(Coupling); /* after a checkpoint; NULL: the method cannot restart */
  } ops;
  void *data;
};

PetscErrorCode CouplingCreate_Opt(Coupling);
PetscErrorCode CouplingCreate_Partitioned(Coupling); /* dn, aitken, iqnils */
#endif
