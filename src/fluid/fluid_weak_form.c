/* The fluid's weak form on its DM: the PetscDS constants, the volume kernels (Navier-Stokes
   or Stokes, the pressure stabilization of equal-order pairs), the boundary terms
   (backflow, the convective interface term) and the Stokes projection of an exact
   solution; the kernels themselves are in fluid_kernels.c. */
#include "fluid_impl.h"
#include "fem.h"

/* PETSc fixes the signatures of pointwise kernels; the projection kernel uses a few of their arguments. */
#pragma GCC diagnostic ignored "-Wunused-parameter"

PetscErrorCode FluidSetConstants(Fluid f, PetscReal mass, PetscReal op, PetscReal load)
{
  PetscFunctionBeginUser;
  PetscCall(FluidSetConstantsFull(f, mass, op, load, f->model == FLUID_NAVIER_STOKES ? 1.0 : 0.0, 0.0));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidSetConstantsFull(Fluid f, PetscReal mass, PetscReal op, PetscReal load, PetscReal convection,
                                     PetscReal projection)
{
  PetscDS     ds;
  PetscScalar c[FLUID_MAX_CONSTANTS];
  PetscInt    n = FLUID_NUM_CONSTANTS + f->data.n_extra;

  PetscFunctionBeginUser;
  c[FLUID_RHO]                    = f->rho;
  c[FLUID_MU]                     = f->mu;
  c[FLUID_MASS]                   = mass;
  c[FLUID_OPERATOR]               = op;
  c[FLUID_LOAD]                   = load;
  c[FLUID_TIME]                   = f->time;
  c[FLUID_DT]                     = f->dt;
  c[FLUID_CONVECTION]             = convection;
  c[FLUID_PROJECTION]             = projection;
  c[FLUID_PRESSURE_STABILIZATION] = f->pressure_tau;
  for (PetscInt i = 0; i < f->data.n_extra; ++i) c[FLUID_NUM_CONSTANTS + i] = f->data.extra[i];
  PetscCall(DMGetDS(f->dm, &ds));
  n += FluidOutletsGetPressures(f, &c[n]);
  PetscCall(PetscDSSetConstants(ds, n, c));
  PetscFunctionReturn(0);
}

/* Fields and volume kernels on dm (the solver's DM, or a copy of it without boundary
   conditions), on the cells of `region` (value 1) only when given. */
PetscErrorCode FluidSetVolumeWeakForm(Fluid f, DM dm, DMLabel region)
{
  PetscDS       ds;
  PetscWeakForm wf;
  PetscFE       velocity, pressure;

  PetscFunctionBeginUser;
  PetscCall(FEMCreateField(dm, 0, "velocity", -1, f->velocity_degree, NULL));
  PetscCall(DMGetField(dm, 0, NULL, (PetscObject *)&velocity));
  PetscCall(FEMCreateField(dm, 1, "pressure", 1, f->pressure_degree, velocity));
  if (region) {
    /* held while DMSetField replaces the field by itself on the region */
    PetscCall(DMGetField(dm, 1, NULL, (PetscObject *)&pressure));
    PetscCall(PetscObjectReference((PetscObject)velocity));
    PetscCall(PetscObjectReference((PetscObject)pressure));
    PetscCall(DMSetField(dm, 0, region, (PetscObject)velocity));
    PetscCall(DMSetField(dm, 1, region, (PetscObject)pressure));
    PetscCall(PetscFEDestroy(&velocity));
    PetscCall(PetscFEDestroy(&pressure));
    PetscCall(DMGetField(dm, 0, NULL, (PetscObject *)&velocity));
  }
  PetscCall(DMCreateDS(dm));
  if (region) PetscCall(DMGetRegionDS(dm, region, NULL, &ds));
  else PetscCall(DMGetDS(dm, &ds));
  /* the kernels under the region's key: PETSc looks a region's kernels up by its label */
  PetscCall(PetscDSGetWeakForm(ds, &wf));
  {
    const PetscInt value = region ? 1 : 0;
    if (f->model == FLUID_NAVIER_STOKES) {
      PetscCall(PetscWeakFormAddResidual(wf, region, value, 0, 0, FluidF0MassConvection, FluidF1Stress));
      PetscCall(PetscWeakFormAddJacobian(wf, region, value, 0, 0, 0, FluidG0MassConvection, FluidG1Convection, NULL,
                                         FluidG3Viscous));
    } else {
      PetscCall(PetscWeakFormAddResidual(wf, region, value, 0, 0, FluidF0MassStokes, FluidF1Stress));
      PetscCall(PetscWeakFormAddJacobian(wf, region, value, 0, 0, 0, FluidG0MassStokes, NULL, NULL, FluidG3Viscous));
    }
    PetscCall(PetscWeakFormAddResidual(wf, region, value, 1, 0, FluidF0Continuity,
                                       f->pressure_stabilization > 0 ? FluidF1PressureStabilization : NULL));
    if (f->pressure_stabilization > 0)
      PetscCall(PetscWeakFormAddJacobian(wf, region, value, 1, 1, 0, NULL, NULL, NULL, FluidG3PressureStabilization));
    PetscCall(PetscWeakFormAddJacobian(wf, region, value, 0, 1, 0, NULL, NULL, FluidG2Pressure, NULL));
    PetscCall(PetscWeakFormAddJacobian(wf, region, value, 1, 0, 0, NULL, FluidG1Continuity, NULL, NULL));
    if (f->data.load_value_kernel || f->data.load_stress_kernel)
      PetscCall(
        PetscWeakFormAddResidual(wf, region, value, 0, 0, f->data.load_value_kernel, f->data.load_stress_kernel));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FluidSetUpWeakForm(Fluid f)
{
  PetscDS ds;

  PetscFunctionBeginUser;
  PetscCall(FluidSetVolumeWeakForm(f, f->dm, NULL));
  PetscCall(DMGetDS(f->dm, &ds));
  PetscCall(FEMAddBoundaries(f->dm, 0, &f->data, f->datums, &f->time));
  /* a listed face set that is no traction boundary would get nothing: refused, not ignored */
  for (PetscInt i = 0; i < f->n_backflow_faces && f->backflow_faces_given; ++i) {
    PetscBool traction = PETSC_FALSE;
    char      list[128] = "";
    for (PetscInt b = 0; b < f->data.n_traction; ++b) {
      char number[24];
      traction = traction || f->backflow_faces[i] == f->data.traction_faces[b] ? PETSC_TRUE : PETSC_FALSE;
      PetscCall(PetscSNPrintf(number, sizeof(number), "%s%" PetscInt_FMT, b ? ", " : "", f->data.traction_faces[b]));
      PetscCall(PetscStrlcat(list, number, sizeof(list)));
    }
    PetscCheck(traction, PetscObjectComm((PetscObject)f->dm), PETSC_ERR_ARG_WRONG,
               "option -fluid_backflow_faces: face set %" PetscInt_FMT
               " is not one of the fluid's traction boundaries (%s)",
               f->backflow_faces[i], list[0] ? list : "it has none");
  }
  if (f->backflow && f->model == FLUID_NAVIER_STOKES) {
    DMLabel label;
    PetscCall(DMGetLabel(f->dm, "Face Sets", &label));
    for (PetscInt b = 0; b < f->data.n_traction; ++b) {
      PetscWeakForm bdwf;
      PetscInt      bd;
      char          name[64];
      PetscBool     listed = f->backflow_faces_given ? PETSC_FALSE : PETSC_TRUE;

      for (PetscInt i = 0; i < f->n_backflow_faces && f->backflow_faces_given; ++i)
        listed = listed || f->backflow_faces[i] == f->data.traction_faces[b];
      if (!listed) continue;
      PetscCall(PetscSNPrintf(name, sizeof(name), "backflow_%" PetscInt_FMT, f->data.traction_faces[b]));
      PetscCall(DMAddBoundary(f->dm, DM_BC_NATURAL, name, label, 1, &f->data.traction_faces[b], 0, 0, NULL, NULL, NULL,
                              NULL, &bd));
      PetscCall(PetscDSGetBoundary(ds, bd, &bdwf, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL));
      PetscCall(PetscWeakFormAddBdResidual(bdwf, label, f->data.traction_faces[b], 0, 0, FluidF0Backflow, NULL));
      PetscCall(
        PetscWeakFormAddBdJacobian(bdwf, label, f->data.traction_faces[b], 0, 0, 0, FluidG0Backflow, NULL, NULL, NULL));
    }
  }
  if (f->interface_face && f->interface_convective_term && f->model == FLUID_NAVIER_STOKES) {
    DMLabel       label;
    PetscWeakForm bdwf;
    PetscInt      bd;

    PetscCall(DMGetLabel(f->dm, "Face Sets", &label));
    PetscCall(DMAddBoundary(f->dm, DM_BC_NATURAL, "interface_convection", label, 1, &f->interface_face, 0, 0, NULL,
                            NULL, NULL, NULL, &bd));
    PetscCall(PetscDSGetBoundary(ds, bd, &bdwf, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL));
    PetscCall(PetscWeakFormAddBdResidual(bdwf, label, f->interface_face, 0, 0, FluidF0InterfaceConvection, NULL));
    PetscCall(PetscWeakFormAddBdJacobian(bdwf, label, f->interface_face, 0, 0, 0, FluidG0InterfaceConvection, NULL,
                                         NULL, NULL));
  }
  PetscFunctionReturn(0);
}

/* The Stokes projection of the exact solution: a(u_h, v) - (p_h, div v) = (sigma_ex, grad v),
   (q, div u_h) = 0, with the Dirichlet data at t0 and sigma_ex n on the other sides. It is
   discretely divergence free, so a first step with a tiny dt does not see an O(h^k/dt)
   pressure from the divergence of an interpolant. The kernel reads the closed forms here. */
static struct {
  FieldFn    pressure;
  GradientFn gradient;
  void      *ctx;
  PetscReal  t;
} projection_target;

static void ProjectionStress(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                             const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[],
                             const PetscInt aOff[], const PetscInt aOff_x[], const PetscScalar a[],
                             const PetscScalar a_t[], const PetscScalar a_x[], PetscReal t, const PetscReal x[],
                             PetscInt numConstants, const PetscScalar constants[], PetscScalar f1[])
{
  PetscScalar g[9] = {0}, p = 0;

  if (constants[FLUID_PROJECTION] == 0.0) return;
  (void)projection_target.gradient(dim, projection_target.t, x, dim, g, projection_target.ctx);
  (void)projection_target.pressure(dim, projection_target.t, x, 1, &p, projection_target.ctx);
  for (PetscInt c = 0; c < dim; ++c)
    for (PetscInt d = 0; d < dim; ++d)
      f1[c * dim + d] -= constants[FLUID_MU] * (g[c * dim + d] + g[d * dim + c]) - (c == d ? p : 0.0);
}

PetscErrorCode FluidProjectExact(Fluid f)
{
  PetscDS       ds;
  PetscWeakForm wf;

  PetscFunctionBeginUser;
  PetscCall(DMGetDS(f->dm, &ds));
  PetscCall(PetscDSGetWeakForm(ds, &wf));
  PetscCall(PetscWeakFormAddResidual(wf, NULL, 0, 0, 0, NULL, ProjectionStress));
  projection_target.pressure = f->data.exact[1];
  projection_target.gradient = f->data.exact_gradient[0];
  projection_target.ctx      = f->data.ctx;
  projection_target.t        = f->time;
  PetscCall(FluidSetConstantsFull(f, 0.0, 1.0, 0.0, 0.0, 1.0));
  PetscCall(FEMSolveSteady(f->dm, "fluid_projection_", &f->counts.factorizations, f->x));
  PetscFunctionReturn(0);
}

/* tau of the size of the Schur complement B (rho/dt M + mu K)^{-1} B^T at the mesh scale */
PetscErrorCode FluidSetPressureStabilization(Fluid f)
{
  const PetscReal h = f->cell_size;

  PetscFunctionBeginUser;
  if (f->pressure_stabilization > 0)
    f->pressure_tau = f->pressure_stabilization * h * h / (f->rho * h * h / f->dt + f->mu);
  PetscFunctionReturn(0);
}
