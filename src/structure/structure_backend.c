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
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_STRUCTURE_RESIDUAL, 0, 0, 0, 0));
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
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_STRUCTURE_RESIDUAL, 0, 0, 0, 0));
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
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_STRUCTURE_JACOBIAN, 0, 0, 0, 0));
  PetscCall(AssembleCeed(s, xlocal, s->ceed_jacobian));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_STRUCTURE_JACOBIAN, 0, 0, 0, 0));
  if (P != s->ceed_jacobian) PetscCall(FEMCeedCopyMatrix(s->ceed_jacobian, P));
  if (J != P && J != s->ceed_jacobian) PetscCall(FEMCeedCopyMatrix(s->ceed_jacobian, J));
  ++s->counts.factorizations;
  if (s->model == STRUCTURE_SVK) {
    if (!s->tangent_at) PetscCall(VecDuplicate(xlocal, &s->tangent_at));
    PetscCall(VecCopy(xlocal, s->tangent_at));
  }
  PetscCall(DMRestoreLocalVector(s->dm, &xlocal));
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckResidual(void *ctx, PetscBool ceed, Vec xlocal, Vec F)
{
  Structure       s       = (Structure)ctx;
  const PetscBool backend = s->backend_ceed;

  PetscFunctionBeginUser;
  s->backend_ceed = ceed;
  PetscCall(StructureOperatorResidual(s, xlocal, F));
  s->backend_ceed = backend;
  PetscFunctionReturn(0);
}

static PetscErrorCode CheckJacobians(void *ctx, Vec xlocal, Mat *petsc, Mat *ceed)
{
  Structure s = (Structure)ctx;

  PetscFunctionBeginUser;
  PetscCall(DMCreateMatrix(s->dm, petsc));
  PetscCall(DMPlexSNESComputeJacobianFEM(s->dm, xlocal, *petsc, *petsc, NULL));
  PetscCall(FEMCeedElasticityCreateMatrix(s->ceed, ceed));
  PetscCall(AssembleCeed(s, xlocal, *ceed));
  PetscFunctionReturn(0);
}

PetscErrorCode StructureBackendCheck(Structure s, PetscInt step)
{
  const FEMBackendPair pair = {s->dm, CheckResidual, CheckJacobians, s};
  PetscBool            check;

  PetscFunctionBeginUser;
  PetscCall(FEMBackendGet(NULL, &check));
  if (!check || !s->ceed || step > FEM_BACKEND_CHECK_STEPS || step == s->backend_checked_step) PetscFunctionReturn(0);
  s->backend_checked_step = step;
  /* a random state of strains of a percent: St. Venant-Kirchhoff's range */
  PetscCall(FEMBackendCheckStep(&pair, "structure", step, s->eta, 1e-2));
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
