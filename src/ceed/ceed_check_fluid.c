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
  CeedElemRestriction  r_u, r_p, r_x, r_q;
  CeedBasis            b_u, b_p, b_x;
  CeedVector           coordinates, qdata, x, f;
  CeedQFunction        qf_setup, qf_residual;
  CeedQFunctionContext context;
  CeedOperator         op_setup, op_residual;
} FluidOperator;

static PetscErrorCode FluidOperatorCreate(DM dm, const FluidVolume *fv, FluidOperator *o)
{
  PetscFE       velocity, pressure;
  CeedInt       ncells, nq, nq_p, dim = fv->dim;
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
  PetscCall(FEMCeedCoordinates(ceed, dm, velocity, &o->r_x, &o->b_x, &o->coordinates));
  PetscCallCeed(ceed, CeedBasisGetNumQuadraturePoints(o->b_u, &nq));
  PetscCallCeed(ceed, CeedBasisGetNumQuadraturePoints(o->b_p, &nq_p));
  PetscCheck(nq == nq_p, PETSC_COMM_SELF, PETSC_ERR_SUP, "libCEED fluid: velocity and pressure need one quadrature");
  PetscCallCeed(ceed, CeedElemRestrictionGetNumElements(o->r_u, &ncells));
  PetscCallCeed(ceed, CeedElemRestrictionCreateStrided(ceed, ncells, nq, qsize, (CeedSize)ncells * nq * qsize,
                                                       CEED_STRIDES_BACKEND, &o->r_q));
  PetscCallCeed(ceed, CeedVectorCreate(ceed, (CeedSize)ncells * nq * qsize, &o->qdata));
  PetscCallCeed(ceed, CeedQFunctionContextCreate(ceed, &o->context));
  PetscCallCeed(ceed,
                CeedQFunctionContextSetData(o->context, CEED_MEM_HOST, CEED_COPY_VALUES, sizeof(*fv), (void *)fv));

  PetscCallCeed(ceed, CeedQFunctionCreateInterior(ceed, 1, SetupFluidGeometry, SetupFluidGeometry_loc, &o->qf_setup));
  PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_setup, "dx", dim * dim, CEED_EVAL_GRAD));
  PetscCallCeed(ceed, CeedQFunctionAddInput(o->qf_setup, "weight", 1, CEED_EVAL_WEIGHT));
  PetscCallCeed(ceed, CeedQFunctionAddOutput(o->qf_setup, "qdata", qsize, CEED_EVAL_NONE));
  PetscCallCeed(ceed, CeedQFunctionSetContext(o->qf_setup, o->context));
  PetscCallCeed(ceed, CeedOperatorCreate(ceed, o->qf_setup, NULL, NULL, &o->op_setup));
  PetscCallCeed(ceed, CeedOperatorSetField(o->op_setup, "dx", o->r_x, o->b_x, CEED_VECTOR_ACTIVE));
  PetscCallCeed(ceed, CeedOperatorSetField(o->op_setup, "weight", CEED_ELEMRESTRICTION_NONE, o->b_x, CEED_VECTOR_NONE));
  PetscCallCeed(ceed, CeedOperatorSetField(o->op_setup, "qdata", o->r_q, CEED_BASIS_NONE, CEED_VECTOR_ACTIVE));
  PetscCallCeed(ceed, CeedOperatorApply(o->op_setup, o->coordinates, o->qdata, CEED_REQUEST_IMMEDIATE));

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
  PetscCallCeed(ceed, CeedOperatorDestroy(&o->op_residual));
  PetscCallCeed(ceed, CeedOperatorDestroy(&o->op_setup));
  PetscCallCeed(ceed, CeedQFunctionDestroy(&o->qf_residual));
  PetscCallCeed(ceed, CeedQFunctionDestroy(&o->qf_setup));
  PetscCallCeed(ceed, CeedQFunctionContextDestroy(&o->context));
  PetscCallCeed(ceed, CeedVectorDestroy(&o->qdata));
  PetscCallCeed(ceed, CeedVectorDestroy(&o->coordinates));
  PetscCallCeed(ceed, CeedVectorDestroy(&o->x));
  PetscCallCeed(ceed, CeedVectorDestroy(&o->f));
  PetscCallCeed(ceed, CeedElemRestrictionDestroy(&o->r_q));
  PetscCallCeed(ceed, CeedElemRestrictionDestroy(&o->r_x));
  PetscCallCeed(ceed, CeedElemRestrictionDestroy(&o->r_p));
  PetscCallCeed(ceed, CeedElemRestrictionDestroy(&o->r_u));
  PetscCallCeed(ceed, CeedBasisDestroy(&o->b_x));
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
  PetscCallCeed(o->ceed, CeedVectorTakeArray(o->x, CEED_MEM_HOST, &xa));
  PetscCallCeed(o->ceed, CeedVectorTakeArray(o->f, CEED_MEM_HOST, &fa));
  PetscCall(VecRestoreArray(x, &xa));
  PetscCall(VecRestoreArray(f, &fa));
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
  PetscReal          norm, difference;
  PetscLogDouble     t0, t1, t2;

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
  fv = (FluidVolume){(CeedInt)dim, constants[FLUID_RHO], constants[FLUID_MU], constants[FLUID_MASS], 1, 1};

  /* the fields alone on a clone, with the volume kernels only: no data, no boundary conditions */
  PetscCall(DMGetField(fluid_dm, 0, NULL, &velocity));
  PetscCall(DMGetField(fluid_dm, 1, NULL, &pressure));
  PetscCall(DMClone(fluid_dm, &dm));
  PetscCall(DMSetField(dm, 0, NULL, velocity));
  PetscCall(DMSetField(dm, 1, NULL, pressure));
  PetscCall(DMCreateDS(dm));
  PetscCall(DMGetDS(dm, &ds));
  PetscCall(PetscDSSetResidual(ds, 0, FluidF0MassConvection, FluidF1Stress));
  PetscCall(PetscDSSetResidual(ds, 1, FluidF0Continuity, NULL));
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
  PetscCall(PetscPrintf(PETSC_COMM_SELF,
                        "fsiopt: libCEED check: fluid volume residual (Navier-Stokes, %" PetscInt_FMT
                        "D) at a random state: %.2e relative to PETSc's; per residual PETSc %.3g ms, libCEED %.3g ms "
                        "(%.1fx)\n",
                        dim, (double)difference, 1e3 * (t1 - t0) / repeats, 1e3 * (t2 - t1) / repeats,
                        (t1 - t0) / (t2 - t1)));
  PetscCall(FluidOperatorDestroy(&o));
  PetscCall(VecDestroy(&x));
  PetscCall(VecDestroy(&f_petsc));
  PetscCall(VecDestroy(&f_ceed));
  PetscCall(DMDestroy(&dm));
  PetscCheck(difference <= tol, PETSC_COMM_SELF, PETSC_ERR_PLIB,
             "libCEED check: the fluid volume residual differs from PETSc's by %.2e (more than %g)", (double)difference,
             (double)tol);
  PetscFunctionReturn(0);
}
