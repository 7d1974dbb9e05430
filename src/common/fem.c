/* The finite-element pieces the fluid, the structure and the mesh motion share (fem.h):
   fields, boundary data and terms, the scenes' volume loads, residuals at a given state, the
   subproblems' SNES with counted Jacobians, geometry invalidation after a mesh move, error
   norms. */
#include <petsc/private/petscimpl.h> /* PetscObjectStateGet */
#include "fem.h"
#include "options.h"

/* PETSc fixes the signatures of pointwise kernels and callbacks; most use a few of their arguments. */
#pragma GCC diagnostic ignored "-Wunused-parameter"

PetscErrorCode FEMCreateField(DM dm, PetscInt field, const char name[], PetscInt Nc, PetscInt degree,
                              PetscFE quadrature_from)
{
  PetscFE   fe;
  PetscInt  dim;
  PetscBool simplex;

  PetscFunctionBeginUser;
  PetscCall(DMGetDimension(dm, &dim));
  PetscCall(DMPlexIsSimplex(dm, &simplex));
  if (Nc < 0) Nc = dim;
  /* k+1 Gauss points per direction: exact for mass terms on affine cells; the rest is O(h^{2k}). */
  PetscCall(PetscFECreateLagrange(PETSC_COMM_SELF, dim, Nc, simplex, degree, degree, &fe));
  PetscCall(PetscObjectSetName((PetscObject)fe, name));
  if (quadrature_from) PetscCall(PetscFECopyQuadrature(quadrature_from, fe));
  PetscCall(DMSetField(dm, field, NULL, (PetscObject)fe));
  PetscCall(PetscFEDestroy(&fe));
  PetscFunctionReturn(0);
}

static PetscErrorCode DirichletEvaluate(PetscInt dim, PetscReal t_ignored, const PetscReal x[], PetscInt Nc,
                                        PetscScalar *u, void *ctx)
{
  DirichletDatum *d = (DirichletDatum *)ctx;
  (void)t_ignored;
  return d->fn(dim, *d->time, x, Nc, u, d->ctx);
}

PetscErrorCode FEMAddBoundaries(DM dm, PetscInt field, const PhysicsData *data, DirichletDatum datums[],
                                const PetscReal *time)
{
  DMLabel label;
  PetscDS ds;
  char    name[64];

  PetscFunctionBeginUser;
  PetscCall(DMGetLabel(dm, "Face Sets", &label));
  PetscCall(DMGetDS(dm, &ds));
  for (PetscInt b = 0; b < data->n_dirichlet; ++b) {
    datums[b].fn   = data->dirichlet_fn[b];
    datums[b].ctx  = data->dirichlet_ctx[b] ? data->dirichlet_ctx[b] : data->ctx;
    datums[b].time = time;
    PetscCall(PetscSNPrintf(name, sizeof(name), "dirichlet_%" PetscInt_FMT, data->dirichlet_faces[b]));
    PetscCall(DMAddBoundary(dm, DM_BC_ESSENTIAL, name, label, 1, &data->dirichlet_faces[b], field, 0, NULL,
                            (void (*)(void))DirichletEvaluate, NULL, &datums[b], NULL));
  }
  for (PetscInt b = 0; b < data->n_traction; ++b) {
    PetscWeakForm bdwf;
    PetscInt      bd;

    PetscCall(PetscSNPrintf(name, sizeof(name), FEM_TRACTION_BOUNDARY "%" PetscInt_FMT, data->traction_faces[b]));
    PetscCall(DMAddBoundary(dm, DM_BC_NATURAL, name, label, 1, &data->traction_faces[b], field, 0, NULL, NULL, NULL,
                            NULL, &bd));
    /* Natural boundary terms live in the boundary's own weak form, not the volume one.
       Beware: PETSc 3.18 integrates them on reversed quadrilateral faces (top, left of a
       box) with mirrored basis values; only data constant along such a face are exact. */
    PetscCall(PetscDSGetBoundary(ds, bd, &bdwf, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL));
    if (data->traction_kernel[b])
      PetscCall(
        PetscWeakFormAddBdResidual(bdwf, label, data->traction_faces[b], field, 0, data->traction_kernel[b], NULL));
  }
  PetscFunctionReturn(0);
}

/* natural boundaries of dm's DS: their residual into flocal (tractions: the data ones only,
   or the others only) and their Jacobian into A (the others: the tractions have none) */
static PetscErrorCode NaturalBoundaries(DM dm, PetscReal t, PetscBool tractions, Vec xlocal, Vec flocal, Mat A)
{
  PetscDS  ds;
  PetscInt nb;

  PetscFunctionBeginUser;
  PetscCall(DMGetDS(dm, &ds));
  PetscCall(PetscDSGetNumBoundary(ds, &nb));
  for (PetscInt b = 0; b < nb; ++b) {
    PetscWeakForm           wf;
    DMBoundaryConditionType type;
    DMLabel                 label;
    const char             *name;
    PetscInt                nv, field;
    const PetscInt         *values;
    PetscBool               traction;

    PetscCall(PetscDSGetBoundary(ds, b, &wf, &type, &name, &label, &nv, &values, &field, NULL, NULL, NULL, NULL, NULL));
    if (type != DM_BC_NATURAL) continue;
    PetscCall(PetscStrncmp(name, FEM_TRACTION_BOUNDARY, sizeof(FEM_TRACTION_BOUNDARY) - 1, &traction));
    if (traction != tractions) continue;
    for (PetscInt v = 0; v < nv && flocal; ++v) {
      PetscFormKey key = {label, values[v], field, 0};
      PetscInt     n0, n1;
      void (**f0)(void), (**f1)(void);
      PetscCall(PetscWeakFormGetBdResidual(wf, label, values[v], field, 0, &n0, (void *)&f0, &n1, (void *)&f1));
      if (n0 || n1) PetscCall(DMPlexComputeBdResidualSingle(dm, t, wf, key, xlocal, NULL, flocal));
    }
    if (A && !traction)
      PetscCall(DMPlexComputeBdJacobianSingle(dm, t, wf, label, nv, values, field, xlocal, NULL, 0.0, A, A));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FEMBoundaryTerms(DM dm, PetscReal t, Vec xlocal, Vec flocal, Mat A, FEMTractionCache *cache)
{
  PetscFunctionBeginUser;
  if (flocal) PetscCall(FEMBoundaryTractions(dm, t, xlocal, flocal, cache));
  PetscCall(NaturalBoundaries(dm, t, PETSC_FALSE, xlocal, flocal, A));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMNaturalBoundaryResidual(DM dm, PetscReal t, Vec xlocal, Vec fglobal)
{
  Vec flocal;

  PetscFunctionBeginUser;
  PetscCall(DMGetLocalVector(dm, &flocal));
  PetscCall(VecZeroEntries(flocal));
  PetscCall(NaturalBoundaries(dm, t, PETSC_FALSE, xlocal, flocal, NULL));
  PetscCall(VecZeroEntries(fglobal));
  PetscCall(DMLocalToGlobal(dm, flocal, ADD_VALUES, fglobal));
  PetscCall(DMRestoreLocalVector(dm, &flocal));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMBoundaryTractions(DM dm, PetscReal t, Vec xlocal, Vec flocal, FEMTractionCache *cache)
{
  PetscFunctionBeginUser;
  {
    PetscDS            ds;
    PetscInt           n;
    const PetscScalar *constants;
    Vec                coordinates;
    PetscObjectId      id;
    PetscObjectState   state;
    PetscBool          same;

    PetscCall(DMGetDS(dm, &ds));
    PetscCall(PetscDSGetConstants(ds, &n, &constants));
    PetscCheck(n <= 64, PETSC_COMM_SELF, PETSC_ERR_SUP, "boundary terms: more than 64 constants");
    PetscCall(DMGetCoordinatesLocal(dm, &coordinates));
    PetscCall(PetscObjectGetId((PetscObject)coordinates, &id));
    PetscCall(PetscObjectStateGet((PetscObject)coordinates, &state));
    same = cache->values && n == cache->nconstants && id == cache->coordinates_id && state == cache->coordinates_state
           ? PETSC_TRUE
           : PETSC_FALSE;
    for (PetscInt i = 0; i < n && same; ++i) same = constants[i] == cache->constants[i] ? PETSC_TRUE : PETSC_FALSE;
    if (!same) {
      if (!cache->values) PetscCall(DMCreateLocalVector(dm, &cache->values));
      PetscCall(VecZeroEntries(cache->values));
      PetscCall(NaturalBoundaries(dm, t, PETSC_TRUE, xlocal, cache->values, NULL));
      cache->nconstants = n;
      PetscCall(PetscArraycpy(cache->constants, constants, n));
      cache->coordinates_id    = id;
      cache->coordinates_state = state;
    }
    PetscCall(VecAXPY(flocal, 1.0, cache->values));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FEMTractionCacheDestroy(FEMTractionCache *cache)
{
  PetscFunctionBeginUser;
  PetscCall(VecDestroy(&cache->values));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMLoadsCreate(DM dm, ResidualKernel f0, ResidualKernel f1, Vec aux, DM *dm_loads)
{
  PetscInt nf;
  PetscDS  ds;

  PetscFunctionBeginUser;
  *dm_loads = NULL;
  if (!f0 && !f1) PetscFunctionReturn(0);
  PetscCall(DMGetNumFields(dm, &nf));
  PetscCall(DMClone(dm, dm_loads));
  for (PetscInt i = 0; i < nf; ++i) {
    PetscObject field;
    PetscCall(DMGetField(dm, i, NULL, &field));
    PetscCall(DMSetField(*dm_loads, i, NULL, field));
  }
  PetscCall(DMCreateDS(*dm_loads));
  PetscCall(DMGetDS(*dm_loads, &ds));
  PetscCall(PetscDSSetResidual(ds, 0, f0, f1));
  if (aux) PetscCall(DMSetAuxiliaryVec(*dm_loads, NULL, 0, 0, aux));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMLoadsAdd(DM dm, DM dm_loads, Vec xlocal, Vec flocal)
{
  PetscDS            ds, loads;
  PetscInt           n;
  const PetscScalar *constants;
  Vec                coordinates, load_coordinates;

  PetscFunctionBeginUser;
  if (!dm_loads) PetscFunctionReturn(0);
  PetscCall(DMGetDS(dm, &ds));
  PetscCall(PetscDSGetConstants(ds, &n, &constants));
  PetscCall(DMGetDS(dm_loads, &loads));
  PetscCall(PetscDSSetConstants(loads, n, (PetscScalar *)constants));
  PetscCall(DMGetCoordinatesLocal(dm, &coordinates));
  PetscCall(DMGetCoordinatesLocal(dm_loads, &load_coordinates));
  if (coordinates != load_coordinates) {
    PetscCall(DMSetCoordinatesLocal(dm_loads, coordinates));
    PetscCall(FEMInvalidateGeometry(dm_loads));
  }
  PetscCall(DMPlexSNESComputeResidualFEM(dm_loads, xlocal, flocal, NULL));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMResidual(DM dm, Vec xlocal, Vec fglobal)
{
  Vec flocal;

  PetscFunctionBeginUser;
  PetscCall(DMGetLocalVector(dm, &flocal));
  PetscCall(VecZeroEntries(flocal));
  PetscCall(DMPlexSNESComputeResidualFEM(dm, xlocal, flocal, NULL));
  PetscCall(VecZeroEntries(fglobal));
  PetscCall(DMLocalToGlobal(dm, flocal, ADD_VALUES, fglobal));
  PetscCall(DMRestoreLocalVector(dm, &flocal));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMGlobalToLocal(DM dm, Vec xglobal, Vec xlocal)
{
  PetscFunctionBeginUser;
  PetscCall(VecZeroEntries(xlocal));
  PetscCall(DMGlobalToLocal(dm, xglobal, INSERT_VALUES, xlocal));
  PetscCall(DMPlexInsertBoundaryValues(dm, PETSC_TRUE, xlocal, 0.0, NULL, NULL, NULL));
  PetscFunctionReturn(0);
}

static PetscErrorCode InsertBoundaryValues(DM dm, Vec xlocal, void *ctx)
{
  PetscFunctionBeginUser;
  (void)ctx;
  PetscCall(DMPlexInsertBoundaryValues(dm, PETSC_TRUE, xlocal, 0.0, NULL, NULL, NULL));
  PetscFunctionReturn(0);
}

static PetscErrorCode CountedJacobian(DM dm, Vec xlocal, Mat J, Mat P, void *ctx)
{
  PetscInt *assemblies = (PetscInt *)ctx;

  PetscFunctionBeginUser;
  PetscCall(DMPlexSNESComputeJacobianFEM(dm, xlocal, J, P, NULL));
  ++(*assemblies);
  PetscFunctionReturn(0);
}

PetscErrorCode FEMZero(PetscInt dim, PetscReal t, const PetscReal x[], PetscInt Nc, PetscScalar *u, void *ctx)
{
  (void)dim;
  (void)t;
  (void)x;
  (void)ctx;
  for (PetscInt c = 0; c < Nc; ++c) u[c] = 0;
  return 0;
}

PetscErrorCode FEMDirectSolverDefaults(const char prefix[])
{
  char option[128];

  PetscFunctionBeginUser;
  /* MUMPS's workspace estimate (its default: 20 % above the analysis) fell short on 3 ranks
     for fsi3's mesh motion (INFOG(1) = -9, the factorization fails); 50 % held. The
     workspace is allocated, most of it never touched. */
  PetscCall(PetscSNPrintf(option, sizeof(option), "-%smat_mumps_icntl_14", prefix));
  PetscCall(OptionsSetDefault(option, "50"));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMCreateSNES(DM dm, const char prefix[], FEMJacobianPolicy policy, PetscInt *jacobian_assemblies,
                             SNES *snes)
{
  KSP ksp;
  PC  pc;

  PetscFunctionBeginUser;
  PetscCall(SNESCreate(PetscObjectComm((PetscObject)dm), snes));
  PetscCall(SNESSetOptionsPrefix(*snes, prefix));
  PetscCall(SNESSetDM(*snes, dm));
  PetscCall(DMPlexSetSNESLocalFEM(dm, NULL, NULL, NULL));
  PetscCall(DMSNESSetBoundaryLocal(dm, InsertBoundaryValues, NULL));
  PetscCall(DMSNESSetJacobianLocal(dm, CountedJacobian, jacobian_assemblies));
  /* MUMPS LU by default: it also solves with the transpose of the same factors. */
  PetscCall(SNESGetKSP(*snes, &ksp));
  PetscCall(KSPSetType(ksp, KSPPREONLY));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(FEMDirectSolverDefaults(prefix));
  PetscCall(PCSetType(pc, PCLU));
  PetscCall(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
  PetscCall(SNESSetTolerances(*snes, 1e-12, 1e-10, 1e-12, 50, PETSC_DEFAULT));
  if (policy == FEM_JACOBIAN_CONSTANT) PetscCall(SNESSetType(*snes, SNESKSPONLY));
  if (policy == FEM_JACOBIAN_ON_REQUEST) {
    /* Chord steps with factors from a nearby state: a backtracking search would stop at
       round-off (residuals of size rho/dt eps); the step tolerance ends them instead. */
    SNESLineSearch ls;
    PetscCall(SNESGetLineSearch(*snes, &ls));
    PetscCall(SNESLineSearchSetType(ls, SNESLINESEARCHBASIC));
  }
  if (policy != FEM_JACOBIAN_NEWTON) {
    /* -2: assemble at the next chance, then never again (until FEMUpdateJacobian asks). */
    PetscCall(SNESSetLagJacobian(*snes, -2));
    PetscCall(SNESSetLagJacobianPersists(*snes, PETSC_TRUE));
  }
  PetscCall(SNESSetFromOptions(*snes));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMSolveSteady(DM dm, const char prefix[], PetscInt *jacobian_assemblies, Vec x)
{
  SNES                snes;
  KSP                 ksp;
  PC                  pc;
  SNESConvergedReason reason;
  const PetscInt      assemblies = *jacobian_assemblies;

  PetscFunctionBeginUser;
  PetscCall(SNESCreate(PetscObjectComm((PetscObject)dm), &snes));
  PetscCall(SNESSetOptionsPrefix(snes, prefix));
  PetscCall(SNESSetDM(snes, dm));
  PetscCall(SNESGetKSP(snes, &ksp));
  PetscCall(KSPSetType(ksp, KSPPREONLY));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(FEMDirectSolverDefaults(prefix));
  PetscCall(PCSetType(pc, PCLU));
  PetscCall(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
  PetscCall(SNESSetTolerances(snes, 1e-12, 1e-10, 1e-12, 50, PETSC_DEFAULT));
  PetscCall(SNESSetFromOptions(snes));
  PetscCall(SNESSolve(snes, NULL, x));
  PetscCall(SNESGetConvergedReason(snes, &reason));
  PetscCheck(reason > 0, PetscObjectComm((PetscObject)dm), PETSC_ERR_NOT_CONVERGED, "%s solve failed: SNES reason %s",
             prefix, SNESConvergedReasons[reason]);
  PetscCall(SNESDestroy(&snes));
  *jacobian_assemblies = assemblies; /* the run's counters are for the time steps */
  PetscFunctionReturn(0);
}

PetscErrorCode FEMInvalidateGeometry(DM dm)
{
  PetscInt Nds, depth;

  PetscFunctionBeginUser;
  PetscCall(DMSetCoordinateField(dm, NULL));
  PetscCall(DMPlexGetDepth(dm, &depth));
  PetscCall(DMGetNumDS(dm, &Nds));
  /* every region: the whole mesh, or the cells of a label (value 1) a field is restricted to */
  for (PetscInt r = 0; r < Nds; ++r) {
    DMLabel  label;
    PetscDS  ds;
    PetscInt Nf;
    IS       cells = NULL;

    PetscCall(DMGetRegionNumDS(dm, r, &label, NULL, &ds));
    if (label) PetscCall(DMLabelGetStratumIS(label, 1, &cells));
    else {
      PetscCall(DMGetStratumIS(dm, "dim", depth, &cells));
      if (!cells) PetscCall(DMGetStratumIS(dm, "depth", depth, &cells));
    }
    if (!cells) continue;
    PetscCall(PetscDSGetNumFields(ds, &Nf));
    /* the geometry at each field's quadrature, and on affine cells (simplices) at the
       coordinate field's default quadrature, which PETSc uses there instead */
    for (PetscInt f = 0; f <= Nf; ++f) {
      PetscQuadrature quad = NULL;
      PetscObjectId   id;
      char            key[64];

      if (f < Nf) {
        PetscObject obj;
        PetscCall(PetscDSGetDiscretization(ds, f, &obj));
        PetscCall(PetscFEGetQuadrature((PetscFE)obj, &quad));
        PetscCall(PetscObjectReference((PetscObject)quad));
      } else {
        DMField  field;
        PetscInt degree;
        PetscCall(DMGetCoordinateField(dm, &field));
        if (!field) continue;
        PetscCall(DMFieldGetDegree(field, cells, NULL, &degree));
        if (degree <= 1) PetscCall(DMFieldCreateDefaultQuadrature(field, cells, &quad));
        if (!quad) continue;
      }
      PetscCall(PetscObjectGetId((PetscObject)quad, &id));
      /* the key of PETSc 3.18's DMSNESGetFEGeom (dmplexsnes.c), in both of its spellings */
      PetscCall(PetscSNPrintf(key, 33, "DMSNESGetFEGeom_%" PetscInt64_FMT "\n", id));
      PetscCall(PetscObjectCompose((PetscObject)cells, key, NULL));
      PetscCall(PetscSNPrintf(key, 33, "DMSNESGetFEGeom_%x\n", (unsigned)id));
      PetscCall(PetscObjectCompose((PetscObject)cells, key, NULL));
      PetscCall(PetscQuadratureDestroy(&quad));
    }
    PetscCall(ISDestroy(&cells));
  }
  PetscFunctionReturn(0);
}

/* SNESComputeJacobian sets the KSP's reuse flag from the SNES's preconditioner lag: ours
   comes after it. While set, PCSetUp skips, also in the nonlinear solves that follow (they
   reuse this Jacobian); the next full update clears it. */
static PetscErrorCode AssembleAt(SNES snes, Vec x, PetscBool reuse_preconditioner)
{
  Mat J, P;
  KSP ksp;

  PetscFunctionBeginUser;
  PetscCall(SNESSetUp(snes));
  PetscCall(SNESGetJacobian(snes, &J, &P, NULL, NULL));
  PetscCall(SNESComputeJacobian(snes, x, J, P));
  PetscCall(SNESGetKSP(snes, &ksp));
  PetscCall(KSPSetOperators(ksp, J, P));
  PetscCall(KSPSetReusePreconditioner(ksp, reuse_preconditioner));
  PetscCall(KSPSetUp(ksp));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMUpdateJacobian(SNES snes, Vec x, PetscBool reuse_preconditioner)
{
  PetscFunctionBeginUser;
  PetscCall(SNESSetLagJacobian(snes, -2));
  PetscCall(AssembleAt(snes, x, reuse_preconditioner));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMSolverIsKrylov(KSP ksp, PetscBool *krylov)
{
  PetscBool preonly;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectTypeCompare((PetscObject)ksp, KSPPREONLY, &preonly));
  *krylov = preonly ? PETSC_FALSE : PETSC_TRUE;
  PetscFunctionReturn(0);
}

PetscErrorCode FEMFactorJacobianAt(SNES snes, Vec x)
{
  PetscFunctionBeginUser;
  PetscCall(AssembleAt(snes, x, PETSC_FALSE));
  PetscFunctionReturn(0);
}

/* PETSc's objective kernels cannot carry a closure, so the closed forms being compared
   against, and their context, are held here for the duration of one FEMErrors call. */
static struct {
  FieldFn    exact[2];
  GradientFn gradient[2];
  void      *ctx;
  PetscReal  t;
} target;

#define OBJECTIVE_KERNELS(F) \
  static void ObjectiveValueError_##F(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], \
                                      const PetscInt uOff_x[], const PetscScalar u[], const PetscScalar u_t[], \
                                      const PetscScalar u_x[], const PetscInt aOff[], const PetscInt aOff_x[], \
                                      const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[], \
                                      PetscReal t, const PetscReal x[], PetscInt numConstants, \
                                      const PetscScalar constants[], PetscScalar obj[]) \
  { \
    PetscScalar    ue[3] = {0, 0, 0}; \
    const PetscInt Nc    = uOff[F + 1] - uOff[F]; \
    obj[0]               = 0; \
    if (!target.exact[F]) return; \
    (void)target.exact[F](dim, target.t, x, Nc, ue, target.ctx); \
    for (PetscInt c = 0; c < Nc; ++c) obj[0] += PetscSqr(u[uOff[F] + c] - ue[c]); \
  } \
  static void ObjectiveGradientError_##F(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], \
                                         const PetscInt uOff_x[], const PetscScalar u[], const PetscScalar u_t[], \
                                         const PetscScalar u_x[], const PetscInt aOff[], const PetscInt aOff_x[], \
                                         const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[], \
                                         PetscReal t, const PetscReal x[], PetscInt numConstants, \
                                         const PetscScalar constants[], PetscScalar obj[]) \
  { \
    PetscScalar    ge[9] = {0}; \
    const PetscInt Nc    = uOff[F + 1] - uOff[F]; \
    obj[0]               = 0; \
    if (!target.gradient[F]) return; \
    (void)target.gradient[F](dim, target.t, x, Nc, ge, target.ctx); \
    for (PetscInt i = 0; i < Nc * dim; ++i) obj[0] += PetscSqr(u_x[uOff_x[F] + i] - ge[i]); \
  }
OBJECTIVE_KERNELS(0)
OBJECTIVE_KERNELS(1)

PetscErrorCode FEMErrors(DM dm, Vec xglobal, PetscReal t, const FieldFn exact[], const GradientFn gradient[], void *ctx,
                         PetscReal l2[], PetscReal h1[])
{
  PetscDS     ds;
  PetscInt    Nf;
  PetscScalar integral[2] = {0, 0};

  PetscFunctionBeginUser;
  PetscCall(DMGetDS(dm, &ds));
  PetscCall(PetscDSGetNumFields(ds, &Nf));
  PetscCheck(Nf <= 2, PETSC_COMM_WORLD, PETSC_ERR_SUP, "error norms are implemented for at most two fields");
  target.t   = t;
  target.ctx = ctx;
  for (PetscInt f = 0; f < Nf; ++f) {
    target.exact[f]    = exact[f];
    target.gradient[f] = gradient ? gradient[f] : NULL;
  }
  for (PetscInt f = 0; f < Nf; ++f)
    PetscCall(PetscDSSetObjective(ds, f, f == 0 ? ObjectiveValueError_0 : ObjectiveValueError_1));
  PetscCall(DMPlexComputeIntegralFEM(dm, xglobal, integral, NULL));
  for (PetscInt f = 0; f < Nf; ++f) l2[f] = PetscSqrtReal(PetscRealPart(integral[f]));
  if (h1) {
    for (PetscInt f = 0; f < Nf; ++f)
      PetscCall(PetscDSSetObjective(ds, f, f == 0 ? ObjectiveGradientError_0 : ObjectiveGradientError_1));
    PetscCall(DMPlexComputeIntegralFEM(dm, xglobal, integral, NULL));
    for (PetscInt f = 0; f < Nf; ++f) h1[f] = PetscSqrtReal(PetscRealPart(integral[f]));
  }
  PetscCall(PetscMemzero(&target, sizeof(target)));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMFreeDofs(DM dm, DM dm_all, IS *is)
{
  PetscSection ls, gs, as;
  PetscInt     pStart, pEnd, n, rstart, k = 0, *idx;
  Vec          v;

  PetscFunctionBeginUser;
  PetscCall(DMGetLocalSection(dm, &ls));
  PetscCall(DMGetGlobalSection(dm, &gs));
  PetscCall(DMGetGlobalSection(dm_all, &as));
  PetscCall(PetscSectionGetChart(gs, &pStart, &pEnd));
  PetscCall(DMGetGlobalVector(dm, &v));
  PetscCall(VecGetLocalSize(v, &n));
  PetscCall(VecGetOwnershipRange(v, &rstart, NULL));
  PetscCall(DMRestoreGlobalVector(dm, &v));
  PetscCall(PetscMalloc1(n, &idx));
  for (PetscInt p = pStart; p < pEnd; ++p) {
    PetscInt        dof, cdof, goff, aoff, next = 0;
    const PetscInt *cidx = NULL;

    PetscCall(PetscSectionGetDof(gs, p, &dof));
    if (dof <= 0) continue; /* not owned here */
    PetscCall(PetscSectionGetOffset(gs, p, &goff));
    PetscCall(PetscSectionGetOffset(as, p, &aoff));
    PetscCall(PetscSectionGetDof(ls, p, &dof));
    PetscCall(PetscSectionGetConstraintDof(ls, p, &cdof));
    if (cdof) PetscCall(PetscSectionGetConstraintIndices(ls, p, &cidx));
    for (PetscInt d = 0, c = 0; d < dof; ++d) {
      if (c < cdof && cidx[c] == d) {
        ++c;
        continue;
      }
      idx[goff - rstart + next++] = aoff + d;
      ++k;
    }
  }
  PetscCheck(k == n, PETSC_COMM_SELF, PETSC_ERR_PLIB, "%" PetscInt_FMT " free dofs mapped, %" PetscInt_FMT " expected",
             k, n);
  PetscCall(ISCreateGeneral(PetscObjectComm((PetscObject)dm), n, idx, PETSC_OWN_POINTER, is));
  PetscFunctionReturn(0);
}
