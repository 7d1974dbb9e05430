/* The structure's operators on libCEED (-fem_backend ceed, the default): the volume terms
   (mass and stress, linear or St. Venant-Kirchhoff) by libCEED (src/ceed/ceed_elasticity.c)
   into a matrix of its own COO pattern; the scene's tractions by PETSc's integration on their
   faces, kept per time; the scene's volume loads by PETSc on a copy of the DM that holds
   nothing else. */
#include "structure_impl.h"
#include "fem_ceed.h"
#include "logging.h"

typedef struct {
  FEMCeedElasticity ceed;
  Mat               jacobian; /* of its COO pattern: the solver's matrix (NULL for the check) */
  DM                dm_loads; /* the scene's volume loads alone, NULL without */
  FEMTractionCache  tractions;
} OperatorCeed;

/* the libCEED form follows the structure DM's constants */
static PetscErrorCode Synchronize(StructureOperator op)
{
  OperatorCeed      *c = (OperatorCeed *)op->data;
  PetscDS            ds;
  PetscInt           n;
  const PetscScalar *k;

  PetscFunctionBeginUser;
  PetscCall(DMGetDS(op->structure->dm, &ds));
  PetscCall(PetscDSGetConstants(ds, &n, &k));
  PetscCall(FEMCeedElasticitySetForm(c->ceed, k[STRUCTURE_MASS], k[STRUCTURE_OPERATOR], k[STRUCTURE_MU],
                                     k[STRUCTURE_LAMBDA], 0.0));
  PetscFunctionReturn(0);
}

static PetscErrorCode Residual(StructureOperator op, Vec xlocal, Vec F)
{
  OperatorCeed *c = (OperatorCeed *)op->data;
  Structure     s = op->structure;
  Vec           flocal;
  PetscReal     t;

  PetscFunctionBeginUser;
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_STRUCTURE_RESIDUAL, 0, 0, 0, 0));
  PetscCall(Synchronize(op));
  t = s->time;
  PetscCall(DMGetLocalVector(s->dm, &flocal));
  PetscCall(FEMCeedElasticityResidual(c->ceed, xlocal, flocal));
  PetscCall(PetscLogEventBegin(FSIOPT_EVENT_BOUNDARY_TERMS, 0, 0, 0, 0));
  PetscCall(FEMBoundaryTerms(s->dm, t, xlocal, flocal, NULL, &c->tractions));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_BOUNDARY_TERMS, 0, 0, 0, 0));
  PetscCall(FEMLoadsAdd(s->dm, c->dm_loads, xlocal, flocal));
  PetscCall(VecZeroEntries(F));
  PetscCall(DMLocalToGlobal(s->dm, flocal, ADD_VALUES, F));
  PetscCall(DMRestoreLocalVector(s->dm, &flocal));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_STRUCTURE_RESIDUAL, 0, 0, 0, 0));
  PetscFunctionReturn(0);
}

static PetscErrorCode Assemble(StructureOperator op, Vec xlocal, Mat A)
{
  OperatorCeed *c = (OperatorCeed *)op->data;

  PetscFunctionBeginUser;
  PetscCall(Synchronize(op));
  PetscCall(FEMCeedElasticityJacobian(c->ceed, xlocal, A));
  if (op->structure->data.n_robin) PetscCall(FEMBoundaryTerms(op->structure->dm, op->structure->time, xlocal, NULL, A, NULL));
  PetscCall(MatAssemblyBegin(A, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(A, MAT_FINAL_ASSEMBLY));
  PetscFunctionReturn(0);
}

static PetscErrorCode JacobianMatrix(StructureOperator op, Vec xlocal, Mat *A)
{
  OperatorCeed *c = (OperatorCeed *)op->data;

  PetscFunctionBeginUser;
  PetscCall(FEMCeedElasticityCreateMatrix(c->ceed, A));
  PetscCall(Assemble(op, xlocal, *A));
  PetscFunctionReturn(0);
}

static PetscErrorCode SNESResidual(SNES snes, Vec x, Vec F, void *ctx)
{
  StructureOperator op = (StructureOperator)ctx;
  Structure         s  = op->structure;
  Vec               xlocal;

  PetscFunctionBeginUser;
  (void)snes;
  PetscCall(DMGetLocalVector(s->dm, &xlocal));
  PetscCall(FEMGlobalToLocal(s->dm, x, xlocal));
  PetscCall(Residual(op, xlocal, F));
  PetscCall(DMRestoreLocalVector(s->dm, &xlocal));
  PetscFunctionReturn(0);
}

/* St. Venant-Kirchhoff: the tangent factored after a solve is the first Newton Jacobian of
   the next solve, which starts from that solution (structure.c) */
static PetscErrorCode SNESJacobian(SNES snes, Vec x, Mat J, Mat P, void *ctx)
{
  StructureOperator op   = (StructureOperator)ctx;
  OperatorCeed     *c    = (OperatorCeed *)op->data;
  Structure         s    = op->structure;
  PetscBool         same = PETSC_FALSE;
  Vec               xlocal;

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
  PetscCall(Assemble(op, xlocal, c->jacobian));
  PetscCall(PetscLogEventEnd(FSIOPT_EVENT_STRUCTURE_JACOBIAN, 0, 0, 0, 0));
  if (P != c->jacobian) PetscCall(FEMCeedCopyMatrix(c->jacobian, P));
  if (J != P && J != c->jacobian) PetscCall(FEMCeedCopyMatrix(c->jacobian, J));
  ++s->counts.factorizations;
  if (s->model == STRUCTURE_SVK) {
    if (!s->tangent_at) PetscCall(VecDuplicate(xlocal, &s->tangent_at));
    PetscCall(VecCopy(xlocal, s->tangent_at));
  }
  PetscCall(DMRestoreLocalVector(s->dm, &xlocal));
  PetscFunctionReturn(0);
}

static PetscErrorCode Destroy(StructureOperator op)
{
  OperatorCeed *c = (OperatorCeed *)op->data;

  PetscFunctionBeginUser;
  PetscCall(FEMCeedElasticityDestroy(&c->ceed));
  PetscCall(MatDestroy(&c->jacobian));
  PetscCall(DMDestroy(&c->dm_loads));
  PetscCall(FEMTractionCacheDestroy(&c->tractions));
  PetscCall(PetscFree(op->data));
  PetscFunctionReturn(0);
}

/* The solver's: its matrix and its callbacks on the SNES, in place of DMPlex's */
PetscErrorCode StructureOperatorCreate_Ceed(Structure s, StructureOperatorUse use, StructureOperator op)
{
  OperatorCeed *c;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&c));
  op->data                = c;
  op->ops.residual        = Residual;
  op->ops.jacobian_matrix = JacobianMatrix;
  op->ops.destroy         = Destroy;
  PetscCall(FEMCeedElasticityCreate(s->dm, s->model == STRUCTURE_SVK,
                                    s->material ? FEM_CEED_CELLS_MATERIAL : FEM_CEED_CELLS_NONE, &c->ceed));
  if (s->material) PetscCall(FEMCeedElasticitySetCellValues(c->ceed, s->dm_material, s->material));
  PetscCall(FEMLoadsCreate(s->dm, s->data.load_value_kernel, s->data.load_stress_kernel, NULL, &c->dm_loads));
  if (use != STRUCTURE_OPERATOR_SOLVER) PetscFunctionReturn(0);
  PetscCall(FEMCeedElasticityCreateMatrix(c->ceed, &c->jacobian));
  PetscCall(SNESSetFunction(s->snes, NULL, SNESResidual, op));
  PetscCall(SNESSetJacobian(s->snes, c->jacobian, c->jacobian, SNESJacobian, op));
  PetscFunctionReturn(0);
}
