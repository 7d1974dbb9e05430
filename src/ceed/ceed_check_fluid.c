/* -ceed_check_fluid: the fluid's volume residual (Navier-Stokes on a fixed mesh, the weak
   form of fluid_kernels.c) by a libCEED operator against PETSc's DMPlexSNESComputeResidualFEM
   at a random state, and the time of each: the first operator of issue 23, checked before
   any solver uses it. */
#include <petscds.h>
#include <petscsnes.h>
#include "fem_ceed.h"
#include "fluid.h"
#include "qfunctions_fluid.h"

typedef struct {
  Ceed                 ceed;
  CeedElemRestriction  r_u, r_p, r_q;
  CeedBasis            b_u, b_p;
  CeedVector           qdata, x, f;
  CeedQFunction        qf_residual;
  CeedQFunctionContext context;
  CeedOperator         op_residual;
  CeedVector           state;       /* the Jacobian's state u0, passive */
  CeedQFunction        qf_block[4]; /* velocity-velocity, velocity-pressure, pressure-velocity, pressure-pressure */
  CeedOperator         op_block[4]; /* pressure-pressure only with a pressure stabilization */
  CeedQFunction        qf_stabilization;
  CeedOperator         op_stabilization; /* its residual term, NULL without */
} FluidOperator;

/* -tau (grad p, grad q) on the active pressure: the residual's term or the Jacobian's block */
static PetscErrorCode StabilizationCreate(FluidOperator *o, CeedInt dim, CeedQFunction *qf, CeedOperator *op)
{
  Ceed ceed = o->ceed;

  PetscFunctionBeginUser;
  PetscCallCeed(ceed,
                CeedQFunctionCreateInterior(ceed, 1, FluidPressureStabilization, FluidPressureStabilization_loc, qf));
  PetscCallCeed(ceed, CeedQFunctionAddInput(*qf, "dp", dim, CEED_EVAL_GRAD));
  PetscCallCeed(ceed, CeedQFunctionAddInput(*qf, "qdata", 1 + dim * dim, CEED_EVAL_NONE));
  PetscCallCeed(ceed, CeedQFunctionAddOutput(*qf, "dq", dim, CEED_EVAL_GRAD));
  PetscCallCeed(ceed, CeedQFunctionSetContext(*qf, o->context));
  PetscCallCeed(ceed, CeedOperatorCreate(ceed, *qf, NULL, NULL, op));
  PetscCallCeed(ceed, CeedOperatorSetField(*op, "dp", o->r_p, o->b_p, CEED_VECTOR_ACTIVE));
  PetscCallCeed(ceed, CeedOperatorSetField(*op, "qdata", o->r_q, CEED_BASIS_NONE, o->qdata));
  PetscCallCeed(ceed, CeedOperatorSetField(*op, "dq", o->r_p, o->b_p, CEED_VECTOR_ACTIVE));
  PetscFunctionReturn(0);
}

static PetscErrorCode FluidOperatorCreate(DM dm, const FluidVolume *fv, FluidOperator *o)
{
  PetscFE       velocity, pressure;
  CeedInt       nq, nq_p, dim = fv->dim;
  const CeedInt qsize = 1 + dim * dim;
  PetscInt      n;
  Vec           local;

  PetscFunctionBeginUser;
  PetscCall(FEMCeedGet(&o->ceed));
  Ceed ceed = o->ceed;
  PetscCall(DMGetField(dm, 0, NULL, (PetscObject *)&velocity));
  PetscCall(DMGetField(dm, 1, NULL, (PetscObject *)&pressure));
  PetscCall(FEMCeedRestriction(ceed, dm, 0, &o->r_u));
  PetscCall(FEMCeedRestriction(ceed, dm, 1, &o->r_p));
  PetscCall(FEMCeedBasis(ceed, dm, velocity, &o->b_u));
  PetscCall(FEMCeedBasis(ceed, dm, pressure, &o->b_p));
  PetscCall(FEMCeedGeometry(ceed, dm, velocity, &o->r_q, &o->qdata));
  PetscCallCeed(ceed, CeedBasisGetNumQuadraturePoints(o->b_u, &nq));
  PetscCallCeed(ceed, CeedBasisGetNumQuadraturePoints(o->b_p, &nq_p));
  PetscCheck(nq == nq_p, PETSC_COMM_SELF, PETSC_ERR_SUP, "libCEED fluid: velocity and pressure need one quadrature");
  PetscCallCeed(ceed, CeedQFunctionContextCreate(ceed, &o->context));
  PetscCallCeed(ceed,
                CeedQFunctionContextSetData(o->context, CEED_MEM_HOST, CEED_COPY_VALUES, sizeof(*fv), (void *)fv));

  PetscCallCeed(ceed,
                CeedQFunctionCreateInterior(ceed, 1, FluidVolumeResidual, FluidVolumeResidual_loc, &o->qf_residual));
  PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_residual, "u", dim, CEED_EVAL_INTERP));
  PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_residual, "du", dim * dim, CEED_EVAL_GRAD));
  PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_residual, "p", 1, CEED_EVAL_INTERP));
  PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_residual, "qdata", qsize, CEED_EVAL_NONE));
  PetscCallCeed(ceed, CeedQFunctionAddOutput(o->qf_residual, "v", dim, CEED_EVAL_INTERP));
  PetscCallCeed(ceed, CeedQFunctionAddOutput(o->qf_residual, "dv", dim * dim, CEED_EVAL_GRAD));
  PetscCallCeed(ceed, CeedQFunctionAddOutput(o->qf_residual, "q", 1, CEED_EVAL_INTERP));
  PetscCallCeed(ceed, CeedQFunctionSetContext(o->qf_residual, o->context));
  PetscCallCeed(ceed, CeedOperatorCreate(ceed, o->qf_residual, NULL, NULL, &o->op_residual));
  PetscCallCeed(ceed, CeedOperatorSetField(o->op_residual, "u", o->r_u, o->b_u, CEED_VECTOR_ACTIVE));
  PetscCallCeed(ceed, CeedOperatorSetField(o->op_residual, "du", o->r_u, o->b_u, CEED_VECTOR_ACTIVE));
  PetscCallCeed(ceed, CeedOperatorSetField(o->op_residual, "p", o->r_p, o->b_p, CEED_VECTOR_ACTIVE));
  PetscCallCeed(ceed, CeedOperatorSetField(o->op_residual, "qdata", o->r_q, CEED_BASIS_NONE, o->qdata));
  PetscCallCeed(ceed, CeedOperatorSetField(o->op_residual, "v", o->r_u, o->b_u, CEED_VECTOR_ACTIVE));
  PetscCallCeed(ceed, CeedOperatorSetField(o->op_residual, "dv", o->r_u, o->b_u, CEED_VECTOR_ACTIVE));
  PetscCallCeed(ceed, CeedOperatorSetField(o->op_residual, "q", o->r_p, o->b_p, CEED_VECTOR_ACTIVE));
  if (fv->tau > 0) PetscCall(StabilizationCreate(o, dim, &o->qf_stabilization, &o->op_stabilization));
  PetscCall(DMGetLocalVector(dm, &local));
  PetscCall(VecGetLocalSize(local, &n));
  PetscCall(DMRestoreLocalVector(dm, &local));
  PetscCallCeed(ceed, CeedVectorCreate(ceed, n, &o->x));
  PetscCallCeed(ceed, CeedVectorCreate(ceed, n, &o->f));
  PetscFunctionReturn(0);
}

static PetscErrorCode FluidOperatorDestroy(FluidOperator *o)
{
  Ceed ceed = o->ceed;

  PetscFunctionBeginUser;
  for (PetscInt b = 0; b < 4; ++b) {
    PetscCallCeed(ceed, CeedOperatorDestroy(&o->op_block[b]));
    PetscCallCeed(ceed, CeedQFunctionDestroy(&o->qf_block[b]));
  }
  PetscCallCeed(ceed, CeedOperatorDestroy(&o->op_stabilization));
  PetscCallCeed(ceed, CeedQFunctionDestroy(&o->qf_stabilization));
  PetscCallCeed(ceed, CeedVectorDestroy(&o->state));
  PetscCallCeed(ceed, CeedOperatorDestroy(&o->op_residual));
  PetscCallCeed(ceed, CeedQFunctionDestroy(&o->qf_residual));
  PetscCallCeed(ceed, CeedQFunctionContextDestroy(&o->context));
  PetscCallCeed(ceed, CeedVectorDestroy(&o->qdata));
  PetscCallCeed(ceed, CeedVectorDestroy(&o->x));
  PetscCallCeed(ceed, CeedVectorDestroy(&o->f));
  PetscCallCeed(ceed, CeedElemRestrictionDestroy(&o->r_q));
  PetscCallCeed(ceed, CeedElemRestrictionDestroy(&o->r_p));
  PetscCallCeed(ceed, CeedElemRestrictionDestroy(&o->r_u));
  PetscCallCeed(ceed, CeedBasisDestroy(&o->b_p));
  PetscCallCeed(ceed, CeedBasisDestroy(&o->b_u));
  PetscFunctionReturn(0);
}

/* f = the residual of the local state x (local vectors of dm) */
static PetscErrorCode FluidOperatorApply(FluidOperator *o, Vec x, Vec f)
{
  PetscScalar *xa, *fa;

  PetscFunctionBeginUser;
  PetscCall(VecGetArray(x, &xa));
  PetscCall(VecGetArray(f, &fa));
  PetscCallCeed(o->ceed, CeedVectorSetArray(o->x, CEED_MEM_HOST, CEED_USE_POINTER, xa));
  PetscCallCeed(o->ceed, CeedVectorSetArray(o->f, CEED_MEM_HOST, CEED_USE_POINTER, fa));
  PetscCallCeed(o->ceed, CeedOperatorApply(o->op_residual, o->x, o->f, CEED_REQUEST_IMMEDIATE));
  if (o->op_stabilization)
    PetscCallCeed(o->ceed, CeedOperatorApplyAdd(o->op_stabilization, o->x, o->f, CEED_REQUEST_IMMEDIATE));
  PetscCallCeed(o->ceed, CeedVectorTakeArray(o->x, CEED_MEM_HOST, &xa));
  PetscCallCeed(o->ceed, CeedVectorTakeArray(o->f, CEED_MEM_HOST, &fa));
  PetscCall(VecRestoreArray(x, &xa));
  PetscCall(VecRestoreArray(f, &fa));
  PetscFunctionReturn(0);
}

/* The Jacobian's blocks at the local state x0, one operator each: libCEED assembles an
   operator with one active input and one active output restriction */
static PetscErrorCode FluidJacobianCreate(FluidOperator *o, const FluidVolume *fv, Vec x0)
{
  Ceed               ceed = o->ceed;
  const CeedInt      dim = fv->dim, qsize = 1 + dim * dim;
  const PetscScalar *x;
  PetscInt           n;

  PetscFunctionBeginUser;
  PetscCall(VecGetLocalSize(x0, &n));
  PetscCallCeed(ceed, CeedVectorCreate(ceed, n, &o->state));
  PetscCall(VecGetArrayRead(x0, &x));
  PetscCallCeed(ceed, CeedVectorSetArray(o->state, CEED_MEM_HOST, CEED_COPY_VALUES, (CeedScalar *)x));
  PetscCall(VecRestoreArrayRead(x0, &x));
  PetscCallCeed(ceed, CeedQFunctionCreateInterior(ceed, 1, FluidJacobianUU, FluidJacobianUU_loc, &o->qf_block[0]));
  PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_block[0], "w", dim, CEED_EVAL_INTERP));
  PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_block[0], "dw", dim * dim, CEED_EVAL_GRAD));
  PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_block[0], "u0", dim, CEED_EVAL_INTERP));
  PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_block[0], "du0", dim * dim, CEED_EVAL_GRAD));
  PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_block[0], "qdata", qsize, CEED_EVAL_NONE));
  PetscCallCeed(ceed, CeedQFunctionAddOutput(o->qf_block[0], "v", dim, CEED_EVAL_INTERP));
  PetscCallCeed(ceed, CeedQFunctionAddOutput(o->qf_block[0], "dv", dim * dim, CEED_EVAL_GRAD));
  PetscCallCeed(ceed, CeedQFunctionCreateInterior(ceed, 1, FluidJacobianUP, FluidJacobianUP_loc, &o->qf_block[1]));
  PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_block[1], "p", 1, CEED_EVAL_INTERP));
  PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_block[1], "qdata", qsize, CEED_EVAL_NONE));
  PetscCallCeed(ceed, CeedQFunctionAddOutput(o->qf_block[1], "dv", dim * dim, CEED_EVAL_GRAD));
  PetscCallCeed(ceed, CeedQFunctionCreateInterior(ceed, 1, FluidJacobianPU, FluidJacobianPU_loc, &o->qf_block[2]));
  PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_block[2], "du", dim * dim, CEED_EVAL_GRAD));
  PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_block[2], "qdata", qsize, CEED_EVAL_NONE));
  PetscCallCeed(ceed, CeedQFunctionAddOutput(o->qf_block[2], "q", 1, CEED_EVAL_INTERP));
  for (PetscInt b = 0; b < 3; ++b) {
    PetscCallCeed(ceed, CeedQFunctionSetContext(o->qf_block[b], o->context));
    PetscCallCeed(ceed, CeedOperatorCreate(ceed, o->qf_block[b], NULL, NULL, &o->op_block[b]));
  }
  PetscCallCeed(ceed, CeedOperatorSetField(o->op_block[0], "w", o->r_u, o->b_u, CEED_VECTOR_ACTIVE));
  PetscCallCeed(ceed, CeedOperatorSetField(o->op_block[0], "dw", o->r_u, o->b_u, CEED_VECTOR_ACTIVE));
  PetscCallCeed(ceed, CeedOperatorSetField(o->op_block[0], "u0", o->r_u, o->b_u, o->state));
  PetscCallCeed(ceed, CeedOperatorSetField(o->op_block[0], "du0", o->r_u, o->b_u, o->state));
  PetscCallCeed(ceed, CeedOperatorSetField(o->op_block[0], "qdata", o->r_q, CEED_BASIS_NONE, o->qdata));
  PetscCallCeed(ceed, CeedOperatorSetField(o->op_block[0], "v", o->r_u, o->b_u, CEED_VECTOR_ACTIVE));
  PetscCallCeed(ceed, CeedOperatorSetField(o->op_block[0], "dv", o->r_u, o->b_u, CEED_VECTOR_ACTIVE));
  PetscCallCeed(ceed, CeedOperatorSetField(o->op_block[1], "p", o->r_p, o->b_p, CEED_VECTOR_ACTIVE));
  PetscCallCeed(ceed, CeedOperatorSetField(o->op_block[1], "qdata", o->r_q, CEED_BASIS_NONE, o->qdata));
  PetscCallCeed(ceed, CeedOperatorSetField(o->op_block[1], "dv", o->r_u, o->b_u, CEED_VECTOR_ACTIVE));
  PetscCallCeed(ceed, CeedOperatorSetField(o->op_block[2], "du", o->r_u, o->b_u, CEED_VECTOR_ACTIVE));
  PetscCallCeed(ceed, CeedOperatorSetField(o->op_block[2], "qdata", o->r_q, CEED_BASIS_NONE, o->qdata));
  PetscCallCeed(ceed, CeedOperatorSetField(o->op_block[2], "q", o->r_p, o->b_p, CEED_VECTOR_ACTIVE));
  if (fv->tau > 0) PetscCall(StabilizationCreate(o, dim, &o->qf_block[3], &o->op_block[3]));
  PetscFunctionReturn(0);
}

/* PETSc's Jacobian and libCEED's at x0: their relative difference and times per assembly */
static PetscErrorCode CompareJacobians(DM dm, FluidOperator *o, const FluidVolume *fv, Vec x0, PetscInt repeats,
                                       PetscReal *difference, PetscLogDouble *petsc_s, PetscLogDouble *ceed_s)
{
  PetscDS        ds;
  Mat            petsc, ceed;
  CeedSize       counts[4];
  PetscLogDouble t0, t1, t2;

  PetscFunctionBeginUser;
  PetscCall(DMGetDS(dm, &ds));
  PetscCall(PetscDSSetJacobian(ds, 0, 0, FluidG0MassConvection, FluidG1Convection, NULL, FluidG3Viscous));
  PetscCall(PetscDSSetJacobian(ds, 0, 1, NULL, NULL, FluidG2Pressure, NULL));
  PetscCall(PetscDSSetJacobian(ds, 1, 0, NULL, FluidG1Continuity, NULL, NULL));
  if (fv->tau > 0) PetscCall(PetscDSSetJacobian(ds, 1, 1, NULL, NULL, NULL, FluidG3PressureStabilization));
  PetscCall(DMCreateMatrix(dm, &petsc));
  PetscCall(FluidJacobianCreate(o, fv, x0));
  PetscCall(FEMCeedCreateCOOMatrix(dm, &ceed));
  PetscCall(FEMCeedAssemblySetUp(o->ceed, dm, 4, o->op_block, ceed, counts));
  PetscCall(PetscTime(&t0));
  for (PetscInt r = 0; r < repeats; ++r) PetscCall(DMPlexSNESComputeJacobianFEM(dm, x0, petsc, petsc, NULL));
  PetscCall(PetscTime(&t1));
  for (PetscInt r = 0; r < repeats; ++r) PetscCall(FEMCeedAssemble(o->ceed, 4, o->op_block, counts, ceed));
  PetscCall(PetscTime(&t2));
  PetscCall(FEMCeedMatDifference(ceed, petsc, difference));
  *petsc_s = (t1 - t0) / repeats;
  *ceed_s  = (t2 - t1) / repeats;
  PetscCall(MatDestroy(&petsc));
  PetscCall(MatDestroy(&ceed));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedCheckFluidResidual(DM fluid_dm, PetscReal tol)
{
  DM                 dm;
  PetscDS            ds, fluid_ds;
  PetscObject        velocity, pressure;
  PetscInt           nconstants, dim, repeats = 10;
  const PetscScalar *fluid_constants;
  PetscScalar        constants[FLUID_NUM_CONSTANTS];
  FluidVolume        fv;
  FluidOperator      o = {0};
  Vec                x, f_petsc, f_ceed;
  PetscRandom        random;
  PetscReal          norm, difference, jacobian;
  PetscLogDouble     t0, t1, t2, petsc_jacobian_s = 0, ceed_jacobian_s = 0;

  PetscFunctionBeginUser;
  PetscCall(DMGetDS(fluid_dm, &fluid_ds));
  PetscCall(PetscDSGetConstants(fluid_ds, &nconstants, &fluid_constants));
  PetscCheck(nconstants >= FLUID_NUM_CONSTANTS, PETSC_COMM_SELF, PETSC_ERR_PLIB, "the fluid's constants are not set");
  PetscCall(DMGetDimension(fluid_dm, &dim));
  for (PetscInt i = 0; i < FLUID_NUM_CONSTANTS; ++i) constants[i] = fluid_constants[i];
  /* one backward-Euler step of Navier-Stokes with the fluid's density, viscosity and dt */
  constants[FLUID_MASS]       = constants[FLUID_RHO] / constants[FLUID_DT];
  constants[FLUID_OPERATOR]   = 1;
  constants[FLUID_CONVECTION] = 1;
  fv                          = (FluidVolume){(CeedInt)dim,
                                              constants[FLUID_RHO],
                                              constants[FLUID_MU],
                                              constants[FLUID_MASS],
                                              1,
                                              1,
                                              constants[FLUID_PRESSURE_STABILIZATION]};

  /* the fields alone on a clone, with the volume kernels only: no data, no boundary conditions */
  PetscCall(DMGetField(fluid_dm, 0, NULL, &velocity));
  PetscCall(DMGetField(fluid_dm, 1, NULL, &pressure));
  PetscCall(DMClone(fluid_dm, &dm));
  PetscCall(DMSetField(dm, 0, NULL, velocity));
  PetscCall(DMSetField(dm, 1, NULL, pressure));
  PetscCall(DMCreateDS(dm));
  PetscCall(DMGetDS(dm, &ds));
  PetscCall(PetscDSSetResidual(ds, 0, FluidF0MassConvection, FluidF1Stress));
  PetscCall(PetscDSSetResidual(ds, 1, FluidF0Continuity, fv.tau > 0 ? FluidF1PressureStabilization : NULL));
  PetscCall(PetscDSSetConstants(ds, FLUID_NUM_CONSTANTS, constants));

  PetscCall(DMCreateLocalVector(dm, &x));
  PetscCall(VecDuplicate(x, &f_petsc));
  PetscCall(VecDuplicate(x, &f_ceed));
  PetscCall(PetscRandomCreate(PETSC_COMM_SELF, &random));
  PetscCall(PetscRandomSetInterval(random, -1.0, 1.0));
  PetscCall(VecSetRandom(x, random));
  PetscCall(PetscRandomDestroy(&random));
  PetscCall(FluidOperatorCreate(dm, &fv, &o));

  PetscCall(PetscTime(&t0));
  for (PetscInt r = 0; r < repeats; ++r) {
    PetscCall(VecZeroEntries(f_petsc));
    PetscCall(DMPlexSNESComputeResidualFEM(dm, x, f_petsc, NULL));
  }
  PetscCall(PetscTime(&t1));
  for (PetscInt r = 0; r < repeats; ++r) PetscCall(FluidOperatorApply(&o, x, f_ceed));
  PetscCall(PetscTime(&t2));

  PetscCall(VecNorm(f_petsc, NORM_2, &norm));
  PetscCall(VecAXPY(f_ceed, -1.0, f_petsc));
  PetscCall(VecNorm(f_ceed, NORM_2, &difference));
  difference /= norm;
  PetscCall(CompareJacobians(dm, &o, &fv, x, 3, &jacobian, &petsc_jacobian_s, &ceed_jacobian_s));
  PetscCall(PetscPrintf(PETSC_COMM_SELF,
                        "fsiopt: libCEED check: fluid volume Jacobian (Navier-Stokes, %" PetscInt_FMT
                        "D%s) at a random state: %.2e relative to PETSc's; per assembly PETSc %.3g ms, libCEED %.3g ms "
                        "(%.1fx)\n",
                        dim, fv.tau > 0 ? ", pressure stabilization" : "", (double)jacobian, 1e3 * petsc_jacobian_s,
                        1e3 * ceed_jacobian_s, petsc_jacobian_s / ceed_jacobian_s));
  PetscCall(PetscPrintf(PETSC_COMM_SELF,
                        "fsiopt: libCEED check: fluid volume residual (Navier-Stokes, %" PetscInt_FMT
                        "D%s) at a random state: %.2e relative to PETSc's; per residual PETSc %.3g ms, libCEED %.3g ms "
                        "(%.1fx)\n",
                        dim, fv.tau > 0 ? ", pressure stabilization" : "", (double)difference,
                        1e3 * (t1 - t0) / repeats, 1e3 * (t2 - t1) / repeats, (t1 - t0) / (t2 - t1)));
  PetscCall(FluidOperatorDestroy(&o));
  PetscCall(VecDestroy(&x));
  PetscCall(VecDestroy(&f_petsc));
  PetscCall(VecDestroy(&f_ceed));
  PetscCall(DMDestroy(&dm));
  PetscCheck(jacobian <= tol, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "libCEED check: the fluid volume Jacobian differs from PETSc's by %.2e (more than %g)", (double)jacobian,
             (double)tol);
  PetscCheck(difference <= tol, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "libCEED check: the fluid volume residual differs from PETSc's by %.2e (more than %g)", (double)difference,
             (double)tol);
  PetscFunctionReturn(0);
}
