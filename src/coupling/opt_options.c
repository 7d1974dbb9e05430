/* -coupling opt's options: its defaults (each the fastest measured at the scene's accuracy,
   docs/coupling-and-solvers.md), read from the options database and checked together. The
   inner method's default depends on the fluid's solver, so this reads it from the problem. */
#include "opt_impl.h"
#include "options.h"

/* the rings of the probed J0 with an iterative fluid */
#define OPT_DEFAULT_PROBING_RINGS 2

/* The defaults that do not depend on the fluid's solver, and the coupling tolerance. */
static PetscErrorCode OptOptionsTolerances(PetscOptionItems *PetscOptionsObject, Opt *opt)
{
  PetscFunctionBeginUser;
  opt->stall_its            = 5;
  opt->test_taylor_step     = 1;
  opt->tol                  = 1e-10;
  opt->krylov_jump_fraction = 0.5;
  /* tube3d, iterative solvers, 2 steps: 0.01 halves the fluid's Krylov iterations (2842 ->
     1460) at the same Gauss-Newton and GMRES iterations; 0.1 gains little more and moves
     the probes by 4e-5 relative (docs/coupling-and-solvers.md). With LU it changes nothing. */
  opt->inexact_products  = 0.01;
  /* tube3d levels 1-3 with the iterative-ilu files: the step that lands within the tolerance
     needs products about ten times as accurate as the others to make LU's iterations
     (docs/coupling-and-solvers.md) */
  opt->inexact_products_last = 0.001;
  opt->chord_contraction = 0.5;
  /* from rest at dt = 1e-6 on channel2d the absolute 1e-4 accepts every start and the wall does
     not move (probe error 100 %); 1e-3 of the wall's velocity meets a tight run's probes there,
     costs nothing on channel2d's pulse, tube3d or the MMS scenes and 3 of 60 iterations on
     fsi1 (docs/coupling-and-solvers.md); 1e-2 left 0.6 % */
  opt->tol_relative = 1e-3;
  PetscCall(OptionsDeclareUnit("-coupling_tol", UNIT_JUMP));
  PetscCall(OptionsPositiveReal(PetscOptionsObject, "-coupling_tol",
                                "stop when ||u - v_s||_{L2(Gamma_I)} falls below this", &opt->tol));
  PetscCall(
    OptionsNonNegativeReal(PetscOptionsObject, "-coupling_tol_relative",
                           "and below this fraction (dimensionless) of the largest wall velocity of the run so far, "
                           "||v_s||_{L2(Gamma_I)} (the tighter of the two: a run from rest is not accepted at its "
                           "start; 0: the absolute test alone)",
                           &opt->tol_relative));
  PetscFunctionReturn(0);
}

/* The explicit Jacobian and the inner method: both defaults follow the fluid's solver. */
static PetscErrorCode OptOptionsInner(PetscOptionItems *PetscOptionsObject, Coupling C, PetscBool fluid_krylov)
{
  Opt *opt = (Opt *)C->data;

  PetscFunctionBeginUser;
  /* with the fluid factored, J0's columns are triangular solves in blocks of 32 (tube3d level
     1: 1024 controls, 32 block solves); with a fluid whose solves iterate each column is a
     Krylov solve, so J0 is probed there: a few products whatever the mesh, and GMRES
     preconditioned by it (tube3d levels 2-4, docs/coupling-and-solvers.md). A recycled
     preconditioner, when asked for, takes J0's place. */
  {
    PetscBool recycle;
    PetscCall(PetscOptionsHasName(NULL, NULL, "-coupling_inner_recycle", &recycle));
    opt->rebuild_every = fluid_krylov && recycle ? 0 : 50;
    opt->probing_rings = fluid_krylov ? OPT_DEFAULT_PROBING_RINGS : 0;
  }
  PetscCall(
    OptionsIntInRange(PetscOptionsObject, "-coupling_explicit_jacobian",
                      "build the explicit Jacobian J0 (the chord steps' matrix, the Krylov methods' preconditioner) "
                      "every K steps, and when a step contracts the jump by less than -coupling_chord_contraction "
                      "(0: none, Kuberry 2015's plain CGLS); default 50 (0 with an iterative fluid and "
                      "-coupling_inner_recycle)",
                      0, 1000000, &opt->rebuild_every));
  {
    /* The default is the fastest inner solver measured at the scene's accuracy
       (docs/coupling-and-solvers.md): with the fluid factored and an explicit J0 in hand,
       chord steps (with the fitted start: channel2d's pulse 1.6x, tube3d 3.9x, fsi3's swing 2.2x
       faster than cgls); with a fluid whose linear solves iterate, gmres, the only one that ties
       the products' Krylov tolerances to the coupling's (cgls was 9x slower on tube3d level 1).
       cgls (TAO Gauss-Newton) is Kuberry 2015's method. */
    PetscInt  inner;
    PetscBool tao_given;
    /* a TAO optimizer or a Tikhonov term asks for the least-squares problem: TAO's own */
    PetscCall(PetscOptionsHasName(NULL, NULL, "-tao_type", &tao_given));
    PetscCall(CouplingProblemGetTikhonov(C->problem, &opt->tikhonov));
    inner = tao_given || opt->tikhonov > 0 ? OPT_INNER_CGLS
          : !fluid_krylov && opt->rebuild_every > 0 ? OPT_INNER_CHORD
                                                    : OPT_INNER_GMRES;
    PetscCall(PetscOptionsEList("-coupling_inner",
                                "the step of an iteration: cgls (TAO Gauss-Newton, CG on J^T J), or Newton on the "
                                "square system J h = -F by gmres or bicgstab (right-preconditioned by the explicit J0, "
                                "no adjoint solve), or chord (h = -J0^-1 F, no linearized solve); default chord with a "
                                "factored fluid and an explicit J0, gmres otherwise, cgls with -tao_type or "
                                "-coupling_tikhonov",
                                NULL, OptInnerNames, 4, OptInnerNames[inner], &inner, NULL));
    opt->inner_type = (OptInner)inner;
  }
  /* With J0 in hand a Newton mode corrects it by secant updates and corrects the start by it:
     tube3d 6 % faster, channel2d's work factor 1.51 instead of 1.68 (docs/coupling-and-solvers.md) */
  if (opt->inner_type != OPT_INNER_CGLS && opt->rebuild_every > 0) {
    opt->secants          = 20;
    opt->start_correction = PETSC_TRUE;
  }
  opt->build_block = 32;
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-coupling_explicit_jacobian_block",
                              "build that J from products J [e_j ...] of at most this many columns (all blocks of one "
                              "width), one multi-right-hand-side solve each (1: one solve per control)",
                              1, 100000, &opt->build_block));
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-coupling_explicit_jacobian_probing",
                              "build that J sparse, by probing: its blocks between interface nodes within R rings of "
                              "each other (nodes sharing an interface face are one ring apart), from one product per "
                              "colour and component of a colouring of the nodes (a number set by the interface's "
                              "connectivity, not its size), factored by -coupling_explicit_jacobian_pc_type (MUMPS LU) (0: dense, one "
                              "product per control); default 0 with a factored fluid, 2 with an iterative one",
                              0, 4, &opt->probing_rings));
  opt->probing_rtol = 1e-4;
  PetscCall(OptionsRealInRange(PetscOptionsObject, "-coupling_explicit_jacobian_probing_rtol",
                               "the probing products' relative tolerance of iterative subproblem solves (a "
                               "preconditioner's entries need a few digits; a factored solve is exact)",
                               1e-14, 0.1, &opt->probing_rtol));
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-coupling_explicit_jacobian_rebuild_its",
                              "also rebuild that J after a Gauss-Newton iteration whose CG needed more than N "
                              "iterations (0: only every K steps)",
                              0, 1000000, &opt->rebuild_inner));
  PetscCall(
    OptionsIntInRange(PetscOptionsObject, "-coupling_stall_its",
                      "stop a step as stalled when the objective has not improved by 1% over this many iterations", 1,
                      1000, &opt->stall_its));
  PetscFunctionReturn(0);
}

/* The Newton-Krylov modes' knobs (listed by -help whatever the mode), the start, the derivative checks. */
static PetscErrorCode OptOptionsNewtonKrylov(PetscOptionItems *PetscOptionsObject, Opt *opt)
{
  PetscFunctionBeginUser;
  if (opt->inner_type != OPT_INNER_CGLS || OptionsHelpRequested()) {
    PetscCall(
      OptionsRealInRange(PetscOptionsObject, "-coupling_inner_jump_fraction",
                         "gmres, bicgstab: stop the Krylov method when the linearized jump ||F + J h|| is below "
                         "this fraction of -coupling_tol, or below the forcing term x ||F|| (-coupling_snes_ksp_ew, "
                         "on by default without -coupling_inner_recycle)",
                         1e-12, 1.0, &opt->krylov_jump_fraction));
    PetscCall(OptionsNonNegativeReal(PetscOptionsObject, "-coupling_inexact_products",
                                     "gmres, bicgstab: theta of the relaxed products: the product at Krylov residual r "
                                     "solves its linearized problems to the relative tolerance theta x (the Krylov "
                                     "method's absolute tolerance) / ||r||, at most 0.1 (0: each solver's own rtol)",
                                     &opt->inexact_products));
    PetscCall(OptionsNonNegativeReal(PetscOptionsObject, "-coupling_inexact_products_last",
                                     "gmres, bicgstab: theta of the relaxed products in a Gauss-Newton step expected "
                                     "to be the last (its jump, shrunk once more by the last iteration's ratio, within "
                                     "10 x -coupling_tol); the smaller of it and -coupling_inexact_products applies",
                                     &opt->inexact_products_last));
    PetscCall(OptionsRealInRange(PetscOptionsObject, "-coupling_chord_contraction",
                                 "chord: rebuild the explicit J0 after an iteration that shrank the jump by less than "
                                 "this factor",
                                 0.0, 1.0, &opt->chord_contraction));
    PetscCall(OptionsIntInRange(PetscOptionsObject, "-coupling_inner_recycle",
                                "gmres, bicgstab: precondition each Krylov solve by the products J h of this step's "
                                "and the last K steps' solves: J^-1 on their span (0: no preconditioner)",
                                0, 1000, &opt->recycle_steps));
    opt->recycle_stretch = 1.0;
    opt->recycle_columns = 50;
    PetscCall(OptionsIntInRange(PetscOptionsObject, "-coupling_inner_recycle_columns",
                                "gmres, bicgstab: keep at most this many of those products, the newest", 1, 10000,
                                &opt->recycle_columns));
    opt->recycle_filter = 1e-8;
    PetscCall(OptionsRealInRange(PetscOptionsObject, "-coupling_inner_recycle_filter",
                                 "gmres, bicgstab: drop a product whose part orthogonal to the newer ones is below "
                                 "this fraction of its norm (as -coupling_iqn_filter does)",
                                 0.0, 1.0, &opt->recycle_filter));
    PetscCall(OptionsIntInRange(PetscOptionsObject, "-coupling_secant_updates",
                                "correct the explicit J0^-1 after each iteration by Broyden's secant update from its "
                                "step and the change of F, carried across steps; after K of them they start again from "
                                "J0^-1 (0: none)",
                                0, 64, &opt->secants));
  }
  PetscCall(PetscOptionsBool("-coupling_start_correction",
                             "extrapolate the next step's start from the accepted controls corrected by the chord step "
                             "-J0^-1 F of their state (needs -coupling_explicit_jacobian; no extra solve)",
                             NULL, opt->start_correction, &opt->start_correction, NULL));
  PetscCall(PetscOptionsBool("-coupling_test_adjoint", "At the first step, check <J h, r> = <h, J^T r> for random h, r",
                             NULL, opt->test_adjoint, &opt->test_adjoint, NULL));
  PetscCall(PetscOptionsBool("-coupling_test_taylor",
                             "At the start of a step (-coupling_test_taylor_step), print the Taylor remainders "
                             "||F(x+th) - F(x) - t J h|| for halving t",
                             NULL, opt->test_taylor, &opt->test_taylor, NULL));
  PetscCall(OptionsIntInRange(PetscOptionsObject, "-coupling_test_taylor_step",
                              "the step at whose start the Taylor test runs; from step 2 on along the start's change "
                              "from the last step's control, a smooth direction (at step 1 a random one)",
                              1, PETSC_MAX_INT, &opt->test_taylor_step));
  PetscFunctionReturn(0);
}

PetscErrorCode OptSetFromOptions(Coupling C, PetscBool *fluid_krylov)
{
  Opt *opt = (Opt *)C->data;

  PetscFunctionBeginUser;
  PetscCall(CouplingProblemFluidSolverIsKrylov(C->problem, fluid_krylov));
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Optimization-based coupling", "coupling");
  PetscCall(OptOptionsTolerances(PetscOptionsObject, opt));
  PetscCall(OptOptionsInner(PetscOptionsObject, C, *fluid_krylov));
  PetscCall(OptOptionsNewtonKrylov(PetscOptionsObject, opt));
  PetscOptionsEnd();
  PetscCheck(!opt->start_correction || opt->rebuild_every > 0, PETSC_COMM_WORLD, PETSC_ERR_ARG_INCOMP,
             "option -coupling_start_correction: the correction solves with the explicit J0; expected "
             "-coupling_explicit_jacobian K > 0");
  PetscFunctionReturn(0);
}
