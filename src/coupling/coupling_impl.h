#ifndef FSIOPT_COUPLING_IMPL_H
#define FSIOPT_COUPLING_IMPL_H
#include "coupling.h"
#include "history.h"

/* A step's start from the values of the last M steps: the polynomial of degree K fitted to
   them by least squares (lower degree and fewer values while fewer are recorded). */
#define FSIOPT_EXTRAPOLATION_MAX        3
#define FSIOPT_EXTRAPOLATION_POINTS_MAX 16
typedef struct {
  Vec      past[FSIOPT_EXTRAPOLATION_POINTS_MAX]; /* newest first */
  PetscInt npast, degree, points;
  PetscInt ar_order;                            /* > 0: also the fitted linear recurrence of this order */
  PetscInt ar_from;                             /* fitted once this many values are recorded (>= 4) */
  PetscInt predictions, recurrence_predictions; /* how often the recurrence was chosen */
} Extrapolation;
PetscErrorCode ExtrapolationCreate(Vec model, PetscInt degree, PetscInt points, Extrapolation *);
PetscErrorCode ExtrapolationRecord(Extrapolation *, Vec x);  /* x: the newest value */
PetscErrorCode ExtrapolationPredict(Extrapolation *, Vec x); /* x: the next step's start */
PetscErrorCode ExtrapolationDestroy(Extrapolation *);
PetscErrorCode ExtrapolationCheckpoint(Extrapolation *, Checkpoint, const char name[], PetscBool load);

/* What a method's iteration reports to the step skeleton (CouplingStep, coupling.c), which
   begins the step, collects the subproblems' failures, counts and ends the step. */
typedef struct {
  PetscInt  iterations;       /* this step's coupling iterations (a failed attempt's too) */
  PetscInt  linearized_pairs; /* of which solved the linearized and adjoint problems */
  PetscReal jump;             /* the step's final interface jump, for the run's largest */
  PetscReal measure;          /* the final value of what the method's tolerance bounds (C->measure) */
  PetscBool stalled;          /* stopped short of the tolerance without failing */
} CouplingIterations;

/* What every coupling method shares; a method fills `ops` and keeps its own data. */
struct _p_Coupling {
  char            method[16];
  CouplingProblem problem;
  History         history;
  CouplingStats   stats;
  Vec             x;     /* the scaled control, carried from step to step */
  Extrapolation   start; /* the control each step starts from */
  PetscReal       dt;
  PetscInt        max_it;
  StepFailure     failure; /* of the step in progress */
  char            measure[128]; /* what the method's tolerance bounds, for the closing lines */
  char            setting[160]; /* how the method iterates, for the first line (chosen by regime) */
  struct {
    PetscErrorCode (*setup)(Coupling); /* the method's options and solvers, after the common ones */
    /* iterate one step to convergence from C->x, after CouplingProblemBeginStep and
       before CouplingProblemEndStep; a failure goes to C->failure */
    PetscErrorCode (*iterate)(Coupling, PetscInt step, CouplingIterations *);
    PetscErrorCode (*destroy)(Coupling);
    const char *(*optimizer)(Coupling);
    /* after a checkpoint file or a new dt: drop what was built from the steps before */
    PetscErrorCode (*resynchronize)(Coupling);
    PetscErrorCode (*checkpoint)(Coupling, Checkpoint, PetscBool load); /* the method's own state; may be NULL */
    /* after the step is accepted and its state final: may change C->x, the control the next
       step's start is extrapolated from (never the state); may be NULL */
    PetscErrorCode (*end_step)(Coupling);
    PetscBool restartable; /* its state is all in checkpoint files */
  } ops;
  void *data;
};

#endif
