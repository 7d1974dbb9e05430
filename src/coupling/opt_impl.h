#ifndef FSIOPT_OPT_IMPL_H
#define FSIOPT_OPT_IMPL_H
/* What the two inner solvers of -coupling opt share: opt.c (TAO: Gauss-Newton with CG on
   the normal equations, and the optimizers that see only the objective) and
   opt_newton_krylov.c (SNES: Newton on the square system F(x) = 0, a Krylov method on J
   itself). Both stop on the interface jump with the same test. */
#include "coupling_impl.h"
#include "checkpoint.h"
#include "explicit_jacobian.h"
#include "acceleration_iqn.h"
#include <petsctao.h>
#include <petscsnes.h>

typedef enum {
  OPT_INNER_CGLS, /* TAO's brgn (or another TAO type): CG on J^T J, a forward and an adjoint solve per iteration */
  OPT_INNER_GMRES,
  OPT_INNER_BICGSTAB,
  OPT_INNER_CHORD /* h = -J0^{-1} F: no linearized solve at all */
} OptInner;
extern const char *const OptInnerNames[];

typedef enum {
  OPT_CONTINUE,
  OPT_CONVERGED, /* below the tolerance, or stalled (Opt.stalled) */
  OPT_DIVERGED,  /* the jump grew 1000-fold, or is not a number */
  OPT_MAX_IT,
  OPT_FAILED /* a subproblem failed */
} OptVerdict;

typedef struct {
  OptInner   inner_type;
  Tao        tao, inner; /* inner: the Tao that iterates (brgn's subsolver, or tao) */
  SNES       snes;       /* the Newton-Krylov solver (inner_type != OPT_INNER_CGLS) */
  Vec        F;
  Mat        J;
  PetscReal  tikhonov, tol; /* -coupling_tikhonov, -coupling_tol */
  PetscReal  tol_relative;  /* -coupling_tol_relative */
  PetscReal  velocity_scale; /* the largest ||v_s||_L2(Gamma_I) of the accepted states so far (checkpointed) */
  PetscReal  last_velocity;  /* ||v_s|| of the last iterate tested */
  PetscInt   step, stall_its, inner_seen;
  PetscReal *objectives; /* this step's, by iteration */
  PetscBool  stalled, test_adjoint, test_taylor;
  PetscInt   test_taylor_step; /* -coupling_test_taylor_step */
  PetscReal  last_jump, first_jump;
  PetscReal  last_tol; /* the tolerance the last iteration was held to */
  /* the explicit-Jacobian preconditioner of the inner Krylov method (explicit_jacobian.c) */
  ExplicitJacobian explicit_jacobian;
  PetscInt         rebuild_every, build_block;
  PetscInt         probing_rings;  /* -coupling_explicit_jacobian_probing: 0 dense, else J0 by probing */
  PetscInt         probing_colors; /* the colouring's (0: dense) */
  PetscReal        probing_rtol;   /* -coupling_explicit_jacobian_probing_rtol */
  PetscInt         rebuild_inner; /* and when a Gauss-Newton iteration's CG needed more than this */
  PetscInt         last_iteration;
  PetscInt         linearized_iterations; /* this step's iterations that solved linearized problems */
  OptVerdict       verdict;
  /* opt_newton_krylov.c */
  Mat       J_newton;               /* J at x_linearization; the explicit J0's columns on fresh fluid factors */
  Vec       x_linearization;        /* that point */
  PetscBool linearization_current;  /* the problem's factors are those of x_linearization */
  PetscReal krylov_jump_fraction;   /* the Krylov method stops when the predicted jump is below this x tol */
  PetscReal inexact_products;       /* theta of the relaxed product tolerance; 0: exact products */
  PetscReal inexact_products_last;  /* theta for a Gauss-Newton step expected to be the last */
  PetscReal fnorm, fnorm_previous;  /* ||F|| at this Gauss-Newton iterate and the one before (0: none) */
  PetscBool forcing_first_adaptive; /* the first Krylov solve of a step aims at gamma C ||F_0|| */
  PetscReal quadratic_constant;     /* C in ||F_1|| = C ||F_0||^2, measured on the last step (0: none) */
  PetscReal chord_contraction;      /* a chord step that shrinks the jump less than this rebuilds J0 */
  PetscBool start_correction;       /* -coupling_start_correction */
  PetscInt  secants;                /* -coupling_secant_updates */
  Vec       x_previous, F_previous; /* the last iterate and its F, for the secant update */
  Vec       correction;
  /* opt_krylov_recycle.c: earlier products precondition each Krylov solve */
  PetscInt   recycle_steps;   /* -coupling_inner_recycle: of this many steps back (0: none) */
  PetscInt   recycle_columns; /* -coupling_inner_recycle_columns */
  PetscReal  recycle_filter;  /* -coupling_inner_recycle_filter */
  IQNColumns recycled;        /* V: the products J h, W: their h */
  Vec       *recycle_W;       /* the kept columns' h (recycled.kept of them), fixed for the solve in progress */
  PetscReal  recycle_scale;   /* ||W|| / ||V|| of those: J^-1's size off their span */
  PetscReal  recycle_stretch; /* <= 1: scale ||r|| / ||P r|| of the last application; 1 without one */
} Opt;

/* F(x), called in the optimizer's stage */
PetscErrorCode OptResidual(Coupling, Vec x, Vec F);
/* opt_options.c: the options and their measured defaults; whether the fluid's solves iterate */
PetscErrorCode OptSetFromOptions(Coupling, PetscBool *fluid_krylov);
/* The stopping test of an iteration (docs/design.md §3): writes its history row, counts its inner
   iterations (the solver's running total `inner_total`) and decides. */
PetscErrorCode OptTestIteration(Coupling, PetscInt its, PetscReal objective, PetscInt inner_total, OptVerdict *);

/* The explicit J0 of J (dense, or probed) as ksp's preconditioner */
PetscErrorCode OptExplicitJacobianCreate(Coupling, Mat J, PetscBool normal_equations, KSP ksp);

/* opt_krylov_recycle.c */
PetscErrorCode OptRecycleSetUp(Coupling, KSP);
PetscErrorCode OptRecycleRecord(Opt *, Vec h, Vec Jh);
/* drops the kept products: after a checkpoint file (in the run that writes it as in the run
   that restarts from it, which go on identically) and after a new dt (J scales with it) */
PetscErrorCode OptRecycleForget(Opt *);
PetscErrorCode OptRecycleDestroy(Opt *);

/* opt_newton_krylov.c */
PetscErrorCode OptNewtonKrylovSetUp(Coupling);
PetscErrorCode OptNewtonKrylovSolve(Coupling, const char **reason);
PetscErrorCode OptNewtonKrylovDestroy(Coupling);
#endif
