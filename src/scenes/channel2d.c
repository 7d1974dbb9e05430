/* Scene channel2d (seed §3.6.1, §4.10): the haemodynamic channel. Fluid [0,6]x[0,1],
   wall [0,6]x[1,1.1] on top of it; a pressure pulse enters at x = 0 as the traction
   b(t) = (A (1 - cos(2 pi t / T_b)), 0) for t <= T_b (A = 1e3 dyn/cm^2, T_b = 0.025 s),
   the outlet x = 6 is traction-free, the bottom is a no-slip wall, the wall's ends are
   clamped and its top is traction-free. cgs units; rho = 1, mu = 0.035, rho_s = 1.1,
   E = 3e6, nu_s = 0.3 (our reading of the numbers the seed's text lost, docs/design.md §4).
   The fluid mesh follows the wall (harmonic extension, fixed on the other three sides).
   The scene's defaults are the seed's run, dt = 1e-4 to T = 0.1 with the linear wall
   (options/channel2d.yaml), and the solver settings that every run of it shares (the St.
   Venant-Kirchhoff wall of options/channel2d-svk.yaml too), each with its reason below. */
#include "scene.h"
#include "fluid.h"
#include "options.h"
#include "fem.h"

#pragma GCC diagnostic ignored "-Wunused-parameter"

enum {
  INLET_AMPLITUDE = FLUID_NUM_CONSTANTS,
  INLET_DURATION
};

/* the traction on the inlet: constant along it, so PETSc's face integration is exact */
static void InletTraction(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                          const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[],
                          const PetscInt aOff[], const PetscInt aOff_x[], const PetscScalar a[],
                          const PetscScalar a_t[], const PetscScalar a_x[], PetscReal t, const PetscReal x[],
                          const PetscReal n[], PetscInt numConstants, const PetscScalar constants[], PetscScalar f0[])
{
  const PetscReal time = PetscRealPart(constants[FLUID_TIME]), T = PetscRealPart(constants[INLET_DURATION]);
  const PetscReal b = time <= T
                      ? PetscRealPart(constants[INLET_AMPLITUDE]) * (1.0 - PetscCosReal(2.0 * PETSC_PI * time / T))
                      : 0.0;

  f0[0] -= constants[FLUID_LOAD] * b;
}

PetscErrorCode SceneCreate_Channel2D(Scene *scene)
{
  PhysicsData *fluid     = &scene->fluid;
  PetscReal    amplitude = 1e3, duration = 0.025;

  PetscFunctionBeginUser;
  scene->dim   = 2;
  scene->units = "cgs";
  PetscCall(OptionsDeclareHelpGroup("channel_"));
  PetscCall(OptionsDeclareUnit("-channel_inlet_amplitude", UNIT_PRESSURE));
  PetscCall(OptionsDeclareUnit("-channel_inlet_duration", UNIT_TIME));
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Scene channel2d: the haemodynamic channel of Kuberry 2015", "scene");
  PetscCall(OptionsNonNegativeReal(PetscOptionsObject, "-channel_inlet_amplitude",
                                   "amplitude A of the inlet traction pulse A (1 - cos(2 pi t/T)), dyn/cm^2",
                                   &amplitude));
  PetscCall(
    OptionsPositiveReal(PetscOptionsObject, "-channel_inlet_duration", "duration T of the inlet pulse, s", &duration));
  PetscOptionsEnd();
  PetscCall(OptionsSetDefault("-fluid_dm_plex_simplex", "0"));
  PetscCall(OptionsSetDefault("-fluid_dm_plex_box_lower", "0,0"));
  PetscCall(OptionsSetDefault("-fluid_dm_plex_box_upper", "6,1"));
  PetscCall(OptionsSetDefault("-fluid_dm_plex_box_faces", "30,10"));
  PetscCall(OptionsSetDefault("-structure_dm_plex_simplex", "0"));
  PetscCall(OptionsSetDefault("-structure_dm_plex_box_lower", "0,1"));
  PetscCall(OptionsSetDefault("-structure_dm_plex_box_upper", "6,1.1"));
  PetscCall(OptionsSetDefault("-structure_dm_plex_box_faces", "30,1"));
  PetscCall(OptionsSetDefault("-fluid_density", "1.0"));
  PetscCall(OptionsSetDefault("-fluid_viscosity", "0.035"));
  PetscCall(OptionsSetDefault("-structure_density", "1.1"));
  PetscCall(OptionsSetDefault("-structure_youngs_modulus", "3e6"));
  PetscCall(OptionsSetDefault("-structure_poisson_ratio", "0.3"));

  PetscCall(OptionsSetDefault("-dt", "1e-4"));
  PetscCall(OptionsSetDefault("-t_final", "0.1"));
  /* the linear wall's first-order scheme; channel2d-svk.yaml: the midpoint one */
  PetscCall(OptionsSetDefault("-structure_time_order", "1"));
  /* -coupling opt on the interface traction (with its regime's inner solver: chord steps on
     an explicit J0 with the fluid factored), to the seed's tolerance on ||u - v_s||_{L2(Gamma_I)}
     (about 4e-6 of its size at the peak); the fluid is refactored every 10th iteration */
  PetscCall(OptionsSetDefault("-coupling_tol", "1e-4"));
  PetscCall(OptionsSetDefault("-coupling_jacobian_lag", "10"));
  /* with -coupling_inner cgls: inexact Gauss-Newton, the inner CG stops at 1e-4 of its start.
     The same Gauss-Newton iterations as at 1e-10, with half the CG iterations (first 300 steps) */
  PetscCall(OptionsSetDefault("-tao_brgn_subsolver_tao_bnk_ksp_rtol", "1e-4"));
  /* the structure solves first and the fluid runs on the mesh of this very iterate: with the
     seed's lagged domain (-coupling_domain lagged) the first Gauss-Newton step of every time
     step is spent on the domain's own move (1.9 instead of 1.0 iterations per step) */
  PetscCall(OptionsSetDefault("-coupling_domain", "current"));
  /* each step starts from the control extrapolated by the quadratic fitted (least squares) to
     the last twelve, or by the linear recurrence of order 6 fitted to them where that predicted
     the last control better: the fit damps the error of controls accepted at the tolerance,
     which the quadratic through three amplifies threefold */
  PetscCall(OptionsSetDefault("-coupling_extrapolation", "2"));
  PetscCall(OptionsSetDefault("-coupling_extrapolation_points", "12"));
  PetscCall(OptionsSetDefault("-coupling_extrapolation_recurrence", "6"));
  /* the fluid's Newton solves stop at 1e-7 of the first residual and at 1e-8 of the
     right-hand side: the predicted starts of later iterations are close */
  PetscCall(OptionsSetDefault("-fluid_snes_rtol", "1e-7"));
  PetscCall(OptionsSetDefault("-fluid_rhs_rtol", "1e-8"));
  /* -1/2 rho ((u-z).n)_- (u, v) on the inlet and outlet: without it the flow that returns
     through the traction-free inlet after the pulse feeds an instability (t > 0.033) */
  PetscCall(OptionsSetDefault("-fluid_backflow_stabilization", "1"));

  scene->has_fluid           = PETSC_TRUE;
  fluid->n_dirichlet         = 1;
  fluid->dirichlet_faces[0]  = FACE_BOTTOM;
  fluid->dirichlet_fn[0]     = FEMZero;
  fluid->n_traction          = 2;
  fluid->traction_faces[0]   = FACE_LEFT;
  fluid->traction_kernel[0]  = InletTraction;
  fluid->traction_faces[1]   = FACE_RIGHT; /* traction-free outlet */
  fluid->interface_face      = FACE_TOP;
  fluid->n_fixed_mesh_faces  = 3;
  fluid->fixed_mesh_faces[0] = FACE_BOTTOM;
  fluid->fixed_mesh_faces[1] = FACE_LEFT;
  fluid->fixed_mesh_faces[2] = FACE_RIGHT;
  fluid->n_extra             = 2;
  fluid->extra[0]            = amplitude;
  fluid->extra[1]            = duration;

  /* the wall: ends clamped, top traction-free, bottom on the fluid */
  PetscCall(SceneClampedWall(scene));

  /* the vertical displacement of the seed's three interface points */
  scene->n_probes = 3;
  for (PetscInt i = 0; i < 3; ++i) {
    scene->probes[i][0] = 1.5 * (i + 1);
    scene->probes[i][1] = 1.0;
  }
  PetscFunctionReturn(0);
}
