#ifndef FSIOPT_FEM_H
#define FSIOPT_FEM_H
#include "fsiopt.h"

/* The pieces the fluid and structure solvers share: fields, boundary data, residual
   evaluation on a given state, counted Jacobians and error norms. */

/* Entries (global rows and columns) every Jacobian of dm must hold beyond the weak form's
   stencil (fem_matrix_pattern.c): in the pattern of the matrices the backends make, zero
   after each assembly, for the caller to add to. */
PetscErrorCode FEMAddExtraPattern(DM dm, PetscInt n, const PetscInt rows[], const PetscInt cols[]);
PetscErrorCode FEMGetExtraPattern(DM dm, PetscInt *n, const PetscInt **rows, const PetscInt **cols);
/* the entries of A (dofs in groups of bs components) that couple a component with itself */
PetscErrorCode FEMMatrixSameComponentPart(Mat A, PetscInt bs, MatReuse reuse, Mat *B);
PetscErrorCode FEMCreateField(DM dm, PetscInt field, const char name[], PetscInt Nc, PetscInt degree,
                              PetscFE quadrature_from);
/* Registers the essential and natural boundaries of `data` on field `field`.
   `datums` must live as long as the DM; `time` is the solver's current time. */
PetscErrorCode FEMAddBoundaries(DM dm, PetscInt field, const PhysicsData *data, DirichletDatum datums[],
                                const PetscReal *time);
/* The names FEMAddBoundaries gives the natural boundaries of the scene's tractions, which
   depend on x, t and the constants only (PhysicsData.traction_kernel). */
#define FEM_TRACTION_BOUNDARY "traction_"
/* The natural-boundary terms of dm's weak form at the local state xlocal, added into flocal
   (residual, may be NULL) and into A (Jacobian, before its final assembly; may be NULL), by
   PETSc's integration on their faces only. The tractions' part is kept in `cache` and
   recomputed only when dm's constants or coordinates change (cache may be NULL without flocal). */
typedef struct {
  Vec              values; /* local */
  PetscInt         nconstants;
  PetscScalar      constants[64];
  PetscObjectId    coordinates_id;
  PetscObjectState coordinates_state;
} FEMTractionCache;
PetscErrorCode FEMBoundaryTerms(DM dm, PetscReal t, Vec xlocal, Vec flocal, Mat A, FEMTractionCache *cache);
/* the other natural-boundary terms alone (not the tractions), their residual at xlocal into
   the global fglobal, which is zeroed first */
PetscErrorCode FEMNaturalBoundaryResidual(DM dm, PetscReal t, Vec xlocal, Vec fglobal);
/* the tractions' part alone (where the other terms have libCEED face operators) */
PetscErrorCode FEMBoundaryTractions(DM dm, PetscReal t, Vec xlocal, Vec flocal, FEMTractionCache *cache);
PetscErrorCode FEMTractionCacheDestroy(FEMTractionCache *);
/* PETSc's face geometry of the faces `points` for fe's face quadrature, as its boundary
   integration computes it (an affine face: one normal and |J| at its centre); the objects
   PETSc creates lazily for face integrals, made on every rank of dm first (ceed_faces.c). */
PetscErrorCode FEMFaceGeometry(DM dm, PetscFE fe, IS points, PetscFEGeom **geometry);
PetscErrorCode FEMFacesMakeSharedObjects(DM dm, PetscFE fe);
/* The scene's volume loads (f0, f1 on field 0) alone, on a copy of dm with its fields (and
   the auxiliary field aux when given), for the operators of the libCEED backend; NULL
   when there are none. FEMLoadsAdd adds them at xlocal into flocal, with dm's present
   constants and coordinates. */
PetscErrorCode FEMLoadsCreate(DM dm, ResidualKernel f0, ResidualKernel f1, Vec aux, DM *dm_loads);
PetscErrorCode FEMLoadsAdd(DM dm, DM dm_loads, Vec xlocal, Vec flocal);
/* The zero field: homogeneous Dirichlet data. */
PetscErrorCode FEMZero(PetscInt dim, PetscReal t, const PetscReal x[], PetscInt Nc, PetscScalar *u, void *ctx);
/* Residual of the DM's weak form at the local state xlocal (boundary values already in it). */
PetscErrorCode FEMResidual(DM dm, Vec xlocal, Vec fglobal);
/* Global state to local state with the boundary values of the current time. */
PetscErrorCode FEMGlobalToLocal(DM dm, Vec xglobal, Vec xlocal);
/* The same with the Dirichlet values kept until *time or the constrained points' coordinates
   change (fem_dirichlet_values.c). */
typedef struct _n_FEMDirichletValues *FEMDirichletValues;
PetscErrorCode FEMDirichletValuesCreate(DM dm, const PetscReal *time, FEMDirichletValues *dv);
PetscErrorCode FEMDirichletValuesGlobalToLocal(FEMDirichletValues dv, Vec xglobal, Vec xlocal);
PetscErrorCode FEMDirichletValuesDestroy(FEMDirichletValues *dv);
/* The SNES of one subproblem: boundary insertion at the solver's time, a Jacobian that
   counts its assemblies (= LU factorizations), MUMPS LU by default, and with
   the policy's Jacobian updates (see FEMJacobianPolicy).
   Options under `prefix` override all of it. */
typedef enum {
  FEM_JACOBIAN_NEWTON,    /* assembled and factored at every Newton iteration */
  FEM_JACOBIAN_CONSTANT,  /* assembled and factored once per run: one linear solve per step */
  FEM_JACOBIAN_ON_REQUEST /* assembled and factored by FEMUpdateJacobian only; solves reuse the factors */
} FEMJacobianPolicy;
/* The defaults of a MUMPS LU under `prefix` (a user's option overrides them) */
PetscErrorCode FEMDirectSolverDefaults(const char prefix[]);
PetscErrorCode FEMCreateSNES(DM dm, const char prefix[], FEMJacobianPolicy, PetscInt *jacobian_assemblies, SNES *snes);
/* Solves R(x) = 0 once with a SNES of its own (options under `prefix`), e.g. an initial
   projection; its factorizations are not added to the run's counter. */
PetscErrorCode FEMSolveSteady(DM dm, const char prefix[], PetscInt *jacobian_assemblies, Vec x);
/* After the coordinates moved: PETSc 3.18 keeps the cell geometry of residual and
   Jacobian assembly composed on the cell IS, and the coordinate field cached on the DM. */
PetscErrorCode FEMInvalidateGeometry(DM dm);
/* A solve with A or A^T, the factors the SNES holds (no new factorization). */
PetscErrorCode FEMLinearSolve(SNES snes, Vec rhs, Vec x, PetscBool transpose);
/* An inexact product's relative tolerance for the linearized solves that follow (0: each
   solver's own -*_ksp_rtol); a solve takes the larger of the two. */
PetscErrorCode FEMSetLinearizedRtol(PetscReal rtol);
PetscErrorCode FEMLinearSolveBlock(SNES snes, Mat rhs, Mat x);
/* Assembles the Jacobian at x and factors it now (FEM_JACOBIAN_ON_REQUEST); with
   reuse_preconditioner (a Krylov solver) the preconditioner of the last full update stays. */
PetscErrorCode FEMUpdateJacobian(SNES snes, Vec x, PetscBool reuse_preconditioner);
/* Whether a linear solver iterates (not preonly: a factorization, the default) */
PetscErrorCode FEMSolverIsKrylov(KSP ksp, PetscBool *krylov);
/* The same for a Newton SNES after its solve: the linear solves that follow use the
   tangent at x; its next solve assembles afresh. */
PetscErrorCode FEMFactorJacobianAt(SNES snes, Vec x);
/* The free (unconstrained) dofs of dm, in dm's global order, as global indices of dm_all:
   a clone with the same fields and no constraints. */
PetscErrorCode FEMFreeDofs(DM dm, DM dm_all, IS *is);
/* Per field: L2 error and L2 error of the gradient against closed forms at time t, called
   with ctx (a NULL closed form gives 0; h1 may be NULL). At most two fields. */
PetscErrorCode FEMErrors(DM dm, Vec xglobal, PetscReal t, const FieldFn exact[], const GradientFn gradient[], void *ctx,
                         PetscReal l2[], PetscReal h1[]);

/* Nodal values of a pointwise function (a ResidualKernel's signature: the field's values
   and gradients, the DM's constants and auxiliary fields in, nc values out) in a continuous
   Lagrange space of the given degree on dm's mesh: each cell's values at the nodes, averaged
   over the cells that share a node (fem_nodal_average.c). Compute returns a local vector of
   the object's, valid until the next Compute. */
typedef struct _n_FEMNodalAverage *FEMNodalAverage;
/* A local vector's contributions from each rank's cells summed at every point, the sums
   back in the local vector on every rank that has the point (global: work space). */
PetscErrorCode FEMSumOverRanks(DM dm, Vec local, Vec global);
PetscErrorCode FEMNodalAverageCreate(DM dm, PetscInt degree, PetscInt nc, const char name[], ResidualKernel,
                                     FEMNodalAverage *);
PetscErrorCode FEMNodalAverageCompute(FEMNodalAverage, Vec local_field, PetscReal t, Vec *value);
PetscErrorCode FEMNodalAverageValue(FEMNodalAverage, Vec *value); /* the last Compute's */
PetscErrorCode FEMNodalAverageGetSection(FEMNodalAverage, PetscSection *);
PetscErrorCode FEMNodalAverageDestroy(FEMNodalAverage *);
#endif
