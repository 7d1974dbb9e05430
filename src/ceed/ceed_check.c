/* -ceed_check_spaces (fem_ceed.h): the bridge of ceed_space.c checked where it matters, in
   assembled matrices. A wrong node order, basis, quadrature or geometry changes them. */
#include <petscds.h>
#include <petscsnes.h>
#include "fem_ceed.h"
#include "fem.h"
#include "qfunctions_check.h"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-parameter"
static void IdentityMass(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                         const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[],
                         const PetscInt aOff_x[], const PetscScalar a[], const PetscScalar a_t[],
                         const PetscScalar a_x[], PetscReal t, PetscReal u_tShift, const PetscReal x[],
                         PetscInt numConstants, const PetscScalar constants[], PetscScalar g0[])
{
  const PetscInt nc = uOff[1] - uOff[0];
  for (PetscInt c = 0; c < nc; ++c) g0[c * nc + c] = 1;
}

static void IdentityLaplacian(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                              const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[],
                              const PetscInt aOff[], const PetscInt aOff_x[], const PetscScalar a[],
                              const PetscScalar a_t[], const PetscScalar a_x[], PetscReal t, PetscReal u_tShift,
                              const PetscReal x[], PetscInt numConstants, const PetscScalar constants[],
                              PetscScalar g3[])
{
  const PetscInt nc = uOff[1] - uOff[0];
  for (PetscInt c = 0; c < nc; ++c)
    for (PetscInt d = 0; d < dim; ++d) g3[((c * nc + c) * dim + d) * dim + d] = 1;
}
#pragma GCC diagnostic pop

typedef enum {
  MASS,
  LAPLACIAN
} CheckKind;

/* The libCEED operator of the kind on dm's one field fe, assembled into A by COO */
static PetscErrorCode AssembleWithCeed(DM dm, PetscFE fe, CheckKind kind, Mat A)
{
  Ceed                 ceed;
  CeedElemRestriction  r_u, r_q = NULL;
  CeedBasis            b_u;
  CeedVector           qdata = NULL;
  CeedQFunction        qf_apply;
  CeedQFunctionContext context;
  CeedOperator         op_apply;
  PetscInt             dim, ncomp;
  SpaceShape           shape;

  PetscFunctionBeginUser;
  PetscCall(FEMCeedGet(&ceed));
  PetscCall(DMGetDimension(dm, &dim));
  PetscCall(PetscFEGetNumComponents(fe, &ncomp));
  shape.dim           = (CeedInt)dim;
  shape.ncomp         = (CeedInt)ncomp;
  const CeedInt qsize = 1 + shape.dim * shape.dim;
  PetscCall(FEMCeedRestriction(ceed, dm, 0, &r_u));
  PetscCall(FEMCeedBasis(ceed, dm, fe, &b_u));
  PetscCall(FEMCeedGeometry(ceed, dm, fe, &r_q, &qdata));
  PetscCallCeed(ceed, CeedQFunctionContextCreate(ceed, &context));
  PetscCallCeed(ceed, CeedQFunctionContextSetData(context, CEED_MEM_HOST, CEED_COPY_VALUES, sizeof(shape), &shape));
  if (kind == MASS) PetscCallCeed(ceed, CeedQFunctionCreateInterior(ceed, 1, ApplyMass, ApplyMass_loc, &qf_apply));
  else PetscCallCeed(ceed, CeedQFunctionCreateInterior(ceed, 1, ApplyLaplacian, ApplyLaplacian_loc, &qf_apply));
  const CeedEvalMode mode = kind == MASS ? CEED_EVAL_INTERP : CEED_EVAL_GRAD;
  const CeedInt      size = kind == MASS ? shape.ncomp : shape.ncomp * shape.dim;
  PetscCallCeed(ceed, CeedQFunctionAddInput(qf_apply, "u", size, mode));
  PetscCallCeed(ceed, CeedQFunctionAddInput(qf_apply, "qdata", qsize, CEED_EVAL_NONE));
  PetscCallCeed(ceed, CeedQFunctionAddOutput(qf_apply, "v", size, mode));
  PetscCallCeed(ceed, CeedQFunctionSetContext(qf_apply, context));

  PetscCallCeed(ceed, CeedOperatorCreate(ceed, qf_apply, NULL, NULL, &op_apply));
  PetscCallCeed(ceed, CeedOperatorSetField(op_apply, "u", r_u, b_u, CEED_VECTOR_ACTIVE));
  PetscCallCeed(ceed, CeedOperatorSetField(op_apply, "qdata", r_q, CEED_BASIS_NONE, qdata));
  PetscCallCeed(ceed, CeedOperatorSetField(op_apply, "v", r_u, b_u, CEED_VECTOR_ACTIVE));

  {
    CeedSize count;
    PetscCall(FEMCeedAssemblySetUp(ceed, dm, 1, &op_apply, A, &count));
    PetscCall(FEMCeedAssemble(ceed, 1, &op_apply, &count, A));
  }
  PetscCallCeed(ceed, CeedOperatorDestroy(&op_apply));
  PetscCallCeed(ceed, CeedQFunctionDestroy(&qf_apply));
  PetscCallCeed(ceed, CeedQFunctionContextDestroy(&context));
  PetscCallCeed(ceed, CeedVectorDestroy(&qdata));
  PetscCallCeed(ceed, CeedElemRestrictionDestroy(&r_q));
  PetscCallCeed(ceed, CeedElemRestrictionDestroy(&r_u));
  PetscCallCeed(ceed, CeedBasisDestroy(&b_u));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedMatDifference(Mat ceed, Mat petsc, PetscReal *difference)
{
  PetscReal norm;

  PetscFunctionBeginUser;
  PetscCall(MatNorm(petsc, NORM_FROBENIUS, &norm));
  PetscCall(MatAXPY(ceed, -1.0, petsc, DIFFERENT_NONZERO_PATTERN));
  PetscCall(MatNorm(ceed, NORM_FROBENIUS, difference));
  *difference /= norm;
  PetscFunctionReturn(0);
}

/* ||A_ceed - A_petsc||_F / ||A_petsc||_F for the kind on dm's one field */
static PetscErrorCode Compare(DM dm, PetscFE fe, CheckKind kind, PetscReal *difference)
{
  PetscDS ds;
  Mat     petsc, ceed;
  Vec     zero;

  PetscFunctionBeginUser;
  PetscCall(DMGetDS(dm, &ds));
  PetscCall(PetscDSSetJacobian(ds, 0, 0, kind == MASS ? IdentityMass : NULL, NULL, NULL,
                               kind == LAPLACIAN ? IdentityLaplacian : NULL));
  PetscCall(DMCreateMatrix(dm, &petsc));
  PetscCall(DMGetLocalVector(dm, &zero));
  PetscCall(VecZeroEntries(zero));
  PetscCall(DMPlexSNESComputeJacobianFEM(dm, zero, petsc, petsc, NULL));
  PetscCall(DMRestoreLocalVector(dm, &zero));
  PetscCall(FEMCeedCreateCOOMatrix(dm, &ceed));
  PetscCall(AssembleWithCeed(dm, fe, kind, ceed));
  PetscCall(FEMCeedMatDifference(ceed, petsc, difference));
  PetscCall(MatDestroy(&petsc));
  PetscCall(MatDestroy(&ceed));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCeedCheckSpaces(DM dm, const char name[], PetscReal tol)
{
  PetscInt nfields;

  PetscFunctionBeginUser;
  PetscCall(DMGetNumFields(dm, &nfields));
  for (PetscInt f = 0; f < nfields; ++f) {
    PetscObject    field;
    PetscClassId   id;
    DM             one;
    PetscReal      mass, laplacian;
    PetscInt       ncomp, dim, start;
    DMPolytopeType type;
    const char    *field_name;
    char           label[64];

    PetscCall(DMGetField(dm, f, NULL, &field));
    PetscCall(PetscObjectGetClassId(field, &id));
    if (id != PETSCFE_CLASSID) continue;
    PetscCall(PetscObjectGetName(field, &field_name));
    PetscCall(PetscStrncpy(label, field_name, sizeof(label))); /* the clones below may rename the field */
    /* the field alone, without boundary conditions (every node free), and a fresh weak form
       for each matrix: PetscDSSetJacobian keeps a kernel it is given NULL for */
    for (CheckKind kind = MASS; kind <= LAPLACIAN; ++kind) {
      PetscCall(DMClone(dm, &one));
      PetscCall(DMSetField(one, 0, NULL, field));
      PetscCall(DMCreateDS(one));
      PetscCall(Compare(one, (PetscFE)field, kind, kind == MASS ? &mass : &laplacian));
      PetscCall(DMDestroy(&one));
    }
    PetscCall(PetscFEGetNumComponents((PetscFE)field, &ncomp));
    PetscCall(DMGetDimension(dm, &dim));
    PetscCall(DMPlexGetHeightStratum(dm, 0, &start, NULL));
    PetscCall(DMPlexGetCellType(dm, start, &type));
    PetscCall(PetscPrintf(PetscObjectComm((PetscObject)dm),
                          "fsiopt: libCEED check: %s field %" PetscInt_FMT " (%s, %" PetscInt_FMT
                          " components, %" PetscInt_FMT "D %s cells): mass %.2e, Laplacian %.2e relative to PETSc's\n",
                          name, f, label, ncomp, dim, DMPolytopeTypes[type], (double)mass, (double)laplacian));
    PetscCheck(mass <= tol && laplacian <= tol, PetscObjectComm((PetscObject)dm), PETSC_ERR_PLIB,
               "libCEED check: %s field %" PetscInt_FMT
               ": mass %.2e, Laplacian %.2e differ from PETSc's by more than %g",
               name, f, (double)mass, (double)laplacian, (double)tol);
  }
  PetscFunctionReturn(0);
}

/* both operators at the global state x: the residuals' difference relative to R(0) (the
   data) plus ||J||_F ||x|| / sqrt(N), the root mean square of a row's bound of the state's
   part before the assembly cancels it (near an equilibrium R(x) itself is mostly
   round-off); the Jacobians' in the Frobenius norm */
static PetscErrorCode CompareAt(const FEMBackendPair *pair, Vec x, PetscReal *residual, PetscReal *jacobian)
{
  Vec       xlocal, zero, F_reference, F_tested, F_zero;
  Mat       J_reference, J_tested;
  PetscReal data, jnorm, xnorm, scale;
  PetscInt  N;

  PetscFunctionBeginUser;
  PetscCall(DMGetLocalVector(pair->dm, &xlocal));
  PetscCall(VecDuplicate(x, &F_reference));
  PetscCall(VecDuplicate(x, &F_tested));
  PetscCall(VecDuplicate(x, &F_zero));
  PetscCall(VecDuplicate(x, &zero));
  PetscCall(VecZeroEntries(zero));
  PetscCall(FEMGlobalToLocal(pair->dm, zero, xlocal));
  PetscCall(pair->residual(pair->reference, xlocal, F_zero));
  PetscCall(FEMGlobalToLocal(pair->dm, x, xlocal));
  PetscCall(pair->residual(pair->reference, xlocal, F_reference));
  PetscCall(pair->residual(pair->tested, xlocal, F_tested));
  PetscCall(pair->jacobian(pair->reference, xlocal, &J_reference));
  PetscCall(pair->jacobian(pair->tested, xlocal, &J_tested));
  PetscCall(VecAXPY(F_tested, -1.0, F_reference));
  PetscCall(VecNorm(F_tested, NORM_2, residual));
  PetscCall(VecNorm(F_zero, NORM_2, &data));
  PetscCall(MatNorm(J_reference, NORM_FROBENIUS, &jnorm));
  PetscCall(VecNorm(xlocal, NORM_2, &xnorm));
  PetscCall(VecGetSize(x, &N));
  scale = data + jnorm * xnorm / PetscSqrtReal((PetscReal)N);
  if (scale > 0) *residual /= scale; /* else both are zero */
  PetscCall(FEMCeedMatDifference(J_tested, J_reference, jacobian));
  PetscCall(MatDestroy(&J_reference));
  PetscCall(MatDestroy(&J_tested));
  PetscCall(VecDestroy(&F_reference));
  PetscCall(VecDestroy(&F_tested));
  PetscCall(VecDestroy(&F_zero));
  PetscCall(VecDestroy(&zero));
  PetscCall(DMRestoreLocalVector(pair->dm, &xlocal));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMBackendCheckStep(const FEMBackendPair *pair, const char what[], PetscInt step, Vec x,
                                   PetscReal amplitude)
{
  PetscReal   residual[2], jacobian[2];
  Vec         random_state;
  PetscRandom random;
  MPI_Comm    comm = PetscObjectComm((PetscObject)x);

  PetscFunctionBeginUser;
  PetscCall(CompareAt(pair, x, &residual[0], &jacobian[0]));
  PetscCall(VecDuplicate(x, &random_state));
  PetscCall(PetscRandomCreate(comm, &random));
  PetscCall(PetscRandomSetInterval(random, -amplitude, amplitude));
  PetscCall(VecSetRandom(random_state, random));
  PetscCall(PetscRandomDestroy(&random));
  PetscCall(CompareAt(pair, random_state, &residual[1], &jacobian[1]));
  PetscCall(VecDestroy(&random_state));
  PetscCall(PetscPrintf(comm,
                        "fsiopt: backend check: step %" PetscInt_FMT
                        ": %s residual %.2e (the step's start) %.2e (a random state), Jacobian %.2e %.2e, %s "
                        "relative to %s\n",
                        step, what, (double)residual[0], (double)residual[1], (double)jacobian[0],
                        (double)jacobian[1], pair->tested_title, pair->reference_title));
  for (PetscInt i = 0; i < 2; ++i)
    PetscCheck(residual[i] <= FEM_BACKEND_CHECK_TOL && jacobian[i] <= FEM_BACKEND_CHECK_TOL, comm, PETSC_ERR_PLIB,
               "option -fem_backend_check: at step %" PetscInt_FMT
               " the %s's %s operators differ from %s's by %.2e (residual), %.2e (Jacobian), more than %g",
               step, what, pair->tested_title, pair->reference_title, (double)residual[i], (double)jacobian[i],
               FEM_BACKEND_CHECK_TOL);
  PetscFunctionReturn(0);
}
