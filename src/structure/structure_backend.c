/* The structure's residual and Jacobian on the backend -fem_backend chose. PETSc: its
   pointwise integration of the whole weak form (structure_kernels.c), the reference.
   ceed: the volume terms (mass and stress, linear or St. Venant-Kirchhoff) by libCEED
   (src/ceed/ceed_elasticity.c) into a matrix of its own COO pattern; the scene's tractions
   by PETSc's integration on their faces, kept per time; the scene's volume loads by PETSc
   on a copy of the DM that holds nothing else. -fem_backend_check compares the two at the
   first steps. */
#include "structure_impl.h"
#include "logging.h"

/* the libCEED form follows the structure DM's constants */
static PetscErrorCode Synchronize(Structure s)
{
  PetscDS            ds;
  PetscInt           n;
  const PetscScalar *c;

  PetscFunctionBeginUser;
  PetscCall(DMGetDS(s->dm, &ds));
  PetscCall(PetscDSGetConstants(ds, &n, &c));
  PetscCall(FEMCeedElasticitySetForm(s->ceed, c[STRUCTURE_MASS], c[STRUCTURE_OPERATOR], c[STRUCTURE_MU],
                                     c[STRUCTURE_LAMBDA], 0.0));
  PetscFunctionReturn(0);
}

PetscErrorCode StructureOperatorResidual(Structure s, Vec xlocal, Vec F)
{
  Vec       flocal;
  PetscReal t;

  PetscFunctionBeginUser;
  if (!s->backend_ceed) {
    PetscCall(FEMResidual(s->dm, xlocal, F));
    PetscFunctionReturn(0);
  }
  PetscCall(Synchronize(s));
  t = s->time;
  PetscCall(DMGetLocalVector(s->dm, &flocal));
  PetscCall(FEMCeedElasticityResidual(s->ceed, xlocal, flocal));
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_BOUNDARY_TERMS, 0, 0, 0, 0));
  PetscCall(FEMBoundaryTerms(s->dm, t, xlocal, flocal, NULL, &s->tractions));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_BOUNDARY_TERMS, 0, 0, 0, 0));
  PetscCall(FEMLoadsAdd(s->dm, s->dm_loads, xlocal, flocal));
  PetscCall(VecZeroEntries(F));
  PetscCall(DMLocalToGlobal(s->dm, flocal, ADD_VALUES, F));
  PetscCall(DMRestoreLocalVector(s->dm, &flocal));
  PetscFunctionReturn(0);
}

static PetscErrorCode AssembleCeed(Structure s, Vec xlocal, Mat A)
{
  PetscFunctionBeginUser;
  PetscCall(Synchronize(s));
  PetscCall(FEMCeedElasticityJacobian(s->ceed, xlocal, A));
  PetscCall(MatAssemblyBegin(A, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(A, MAT_FINAL_ASSEMBLY));
  PetscFunctionReturn(0);
}

static PetscErrorCode Residual(SNES snes, Vec x, Vec F, void *ctx)
{
  Structure s = (Structure)ctx;
  Vec       xlocal;

  PetscFunctionBeginUser;
  (void)snes;
  PetscCall(DMGetLocalVector(s->dm, &xlocal));
  PetscCall(FEMGlobalToLocal(s->dm, x, xlocal));
  PetscCall(StructureOperatorResidual(s, xlocal, F));
  PetscCall(DMRestoreLocalVector(s->dm, &xlocal));
  PetscFunctionReturn(0);
}

/* St. Venant-Kirchhoff: the tangent factored after a solve is the first Newton Jacobian of
   the next solve, which starts from that solution (structure.c's TangentJacobian) */
static PetscErrorCode Jacobian(SNES snes, Vec x, Mat J, Mat P, void *ctx)
{
  Structure s    = (Structure)ctx;
  PetscBool same = PETSC_FALSE;
  Vec       xlocal;

  PetscFunctionBeginUser;
  (void)snes;
  PetscCall(DMGetLocalVector(s->dm, &xlocal));
  PetscCall(FEMGlobalToLocal(s->dm, x, xlocal));
  if (s->model == STRUCTURE_SVK && s->tangent_at) PetscCall(VecEqual(xlocal, s->tangent_at, &same));
  if (same) {
    PetscCall(DMRestoreLocalVector(s->dm, &xlocal));
    PetscFunctionReturn(0);
  }
  PetscCall(AssembleCeed(s, xlocal, s->ceed_jacobian));
  if (P != s->ceed_jacobian) PetscCall(MatCopy(s->ceed_jacobian, P, SAME_NONZERO_PATTERN));
  if (J != P && J != s->ceed_jacobian) PetscCall(MatCopy(s->ceed_jacobian, J, SAME_NONZERO_PATTERN));
  ++s->counts.factorizations;
  if (s->model == STRUCTURE_SVK) {
    if (!s->tangent_at) PetscCall(VecDuplicate(xlocal, &s->tangent_at));
    PetscCall(VecCopy(xlocal, s->tangent_at));
  }
  PetscCall(DMRestoreLocalVector(s->dm, &xlocal));
  PetscFunctionReturn(0);
}

/* -fem_backend_check: both backends' residual and Jacobian at eta (local) */
static PetscErrorCode CompareAt(Structure s, Vec xlocal, PetscReal *residual, PetscReal *jacobian)
{
  const PetscBool backend = s->backend_ceed;
  Vec             F_petsc, F_ceed;
  Mat             J_petsc, J_ceed;
  PetscReal       norm;

  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(s->eta, &F_petsc));
  PetscCall(VecDuplicate(s->eta, &F_ceed));
  s->backend_ceed = PETSC_FALSE;
  PetscCall(StructureOperatorResidual(s, xlocal, F_petsc));
  s->backend_ceed = PETSC_TRUE;
  PetscCall(StructureOperatorResidual(s, xlocal, F_ceed));
  s->backend_ceed = backend;
  PetscCall(VecAXPY(F_ceed, -1.0, F_petsc));
  PetscCall(VecNorm(F_ceed, NORM_2, residual));
  PetscCall(DMCreateMatrix(s->dm, &J_petsc));
  PetscCall(DMPlexSNESComputeJacobianFEM(s->dm, xlocal, J_petsc, J_petsc, NULL));
  PetscCall(FEMCeedElasticityCreateMatrix(s->ceed, &J_ceed));
  PetscCall(AssembleCeed(s, xlocal, J_ceed));
  {
    /* the residual's difference relative to R(0), the data, plus ||J||_F ||x|| / sqrt(N),
       the root mean square of a row's bound, a scale of the state's part before the
       assembly cancels it (near an equilibrium R(x) itself is mostly round-off) */
    Vec       zero, zlocal, F_zero;
    PetscReal data, jnorm, xnorm;
    PetscInt  N;
    PetscCall(VecDuplicate(F_petsc, &zero));
    PetscCall(VecDuplicate(F_petsc, &F_zero));
    PetscCall(VecZeroEntries(zero));
    PetscCall(DMGetLocalVector(s->dm, &zlocal));
    PetscCall(FEMGlobalToLocal(s->dm, zero, zlocal));
    s->backend_ceed = PETSC_FALSE;
    PetscCall(StructureOperatorResidual(s, zlocal, F_zero));
    s->backend_ceed = backend;
    PetscCall(DMRestoreLocalVector(s->dm, &zlocal));
    PetscCall(VecNorm(F_zero, NORM_2, &data));
    PetscCall(MatNorm(J_petsc, NORM_FROBENIUS, &jnorm));
    PetscCall(VecNorm(xlocal, NORM_2, &xnorm));
    PetscCall(VecGetSize(F_petsc, &N));
    norm = data + jnorm * xnorm / PetscSqrtReal((PetscReal)N);
    if (norm > 0) *residual /= norm; /* else both are zero */
    PetscCall(VecDestroy(&zero));
    PetscCall(VecDestroy(&F_zero));
  }
  PetscCall(FEMCeedMatDifference(J_ceed, J_petsc, jacobian));
  PetscCall(MatDestroy(&J_petsc));
  PetscCall(MatDestroy(&J_ceed));
  PetscCall(VecDestroy(&F_petsc));
  PetscCall(VecDestroy(&F_ceed));
  PetscFunctionReturn(0);
}

PetscErrorCode StructureBackendCheck(Structure s, PetscInt step)
{
  PetscBool   check;
  PetscReal   residual[2], jacobian[2];
  Vec         x, xlocal;
  PetscRandom random;

  PetscFunctionBeginUser;
  PetscCall(FEMBackendGet(NULL, &check));
  if (!check || !s->ceed || step > 3 || step == s->backend_checked_step) PetscFunctionReturn(0);
  s->backend_checked_step = step;
  PetscCall(CompareAt(s, s->eta_local, &residual[0], &jacobian[0]));
  PetscCall(VecDuplicate(s->eta, &x));
  PetscCall(DMGetLocalVector(s->dm, &xlocal));
  PetscCall(PetscRandomCreate(s->comm, &random));
  PetscCall(PetscRandomSetInterval(random, -1e-2, 1e-2)); /* strains of a percent: St. Venant-Kirchhoff's range */
  PetscCall(VecSetRandom(x, random));
  PetscCall(PetscRandomDestroy(&random));
  PetscCall(FEMGlobalToLocal(s->dm, x, xlocal));
  PetscCall(CompareAt(s, xlocal, &residual[1], &jacobian[1]));
  PetscCall(DMRestoreLocalVector(s->dm, &xlocal));
  PetscCall(VecDestroy(&x));
  PetscCall(PetscPrintf(s->comm,
                        "fsiopt: backend check: step %" PetscInt_FMT
                        ": structure residual %.2e (the step's start) %.2e (a random state), Jacobian %.2e %.2e, "
                        "libCEED relative to PETSc\n",
                        step, (double)residual[0], (double)residual[1], (double)jacobian[0], (double)jacobian[1]));
  for (PetscInt i = 0; i < 2; ++i)
    PetscCheck(residual[i] <= 1e-12 && jacobian[i] <= 1e-12, s->comm, PETSC_ERR_PLIB,
               "option -fem_backend_check: at step %" PetscInt_FMT
               " the structure's libCEED operators differ from PETSc's by %.2e (residual), %.2e (Jacobian), more "
               "than 1e-12",
               step, (double)residual[i], (double)jacobian[i]);
  PetscFunctionReturn(0);
}

PetscErrorCode StructureBackendSetUp(Structure s)
{
  FEMBackend backend;
  PetscBool  check;

  PetscFunctionBeginUser;
  PetscCall(FEMBackendGet(&backend, &check));
  if (backend != FEM_BACKEND_CEED && !check) PetscFunctionReturn(0);
  PetscCall(FEMCeedElasticityCreate(s->dm, s->model == STRUCTURE_SVK, PETSC_FALSE, &s->ceed));
  PetscCall(FEMLoadsCreate(s->dm, s->data.load_value_kernel, s->data.load_stress_kernel, NULL, &s->dm_loads));
  if (backend != FEM_BACKEND_CEED) PetscFunctionReturn(0); /* built for the check only */
  s->backend_ceed = PETSC_TRUE;
  PetscCall(FEMCeedElasticityCreateMatrix(s->ceed, &s->ceed_jacobian));
  PetscCall(SNESSetFunction(s->snes, NULL, Residual, s));
  PetscCall(SNESSetJacobian(s->snes, s->ceed_jacobian, s->ceed_jacobian, Jacobian, s));
  PetscFunctionReturn(0);
}

PetscErrorCode StructureBackendDestroy(Structure s)
{
  PetscFunctionBeginUser;
  PetscCall(FEMCeedElasticityDestroy(&s->ceed));
  PetscCall(MatDestroy(&s->ceed_jacobian));
  PetscCall(DMDestroy(&s->dm_loads));
  PetscCall(FEMTractionCacheDestroy(&s->tractions));
  PetscFunctionReturn(0);
}
