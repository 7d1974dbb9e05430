/* Harmonic or linear-elastic extension of the interface displacement (docs/design.md §2). The
   operator A lives on the reference mesh and never changes: it is assembled once on all
   dofs, and each extension is one solve with the factored free block,
     A_ff d_f = -A_fb d_b,
   with no finite-element evaluation per call. -mesh_motion_stiffening chi weights each
   cell by (|K|_mean / |K|)^chi (Jacobian-based stiffening, Stein, Tezduyar and Benney):
   the small cells next to a body then move nearly rigidly and the large ones far away
   absorb the deformation. -mesh_motion_incremental extends each step's increment from
   the mesh of the step's start instead, with A (and the weights) of that mesh: a body
   that rotates far (a flag's tip) is followed by small increments, where the total
   extension from the reference mesh shears the cells next to it. It costs an assembly
   and a factorization of A per step, and the mesh then depends on the path.
   -mesh_motion biharmonic solves Delta^2 d = 0 in the mixed form of Wick (2011): a second
   field w = -Delta d, tested by every vertex, so that besides d = g the normal derivative
   of d is zero on the boundary (a clamped plate): the cells next to a body follow it
   nearly rigidly, also around its corners, where a harmonic extension shears them. */
#include "motion.h"
#include "fem.h"
#include "fem_ceed.h"
#include "options.h"

#pragma GCC diagnostic ignored "-Wunused-parameter"

typedef enum {
  MOTION_HARMONIC,
  MOTION_ELASTIC,
  MOTION_BIHARMONIC
} MotionType;
static const char *const MotionTypes[] = {"harmonic", "elastic", "biharmonic", "MotionType", "MOTION_", NULL};

struct _p_MeshMotion {
  DM                dm, dm_all; /* Q1 vector field(s) with (without) the Dirichlet constraints */
  Mat               operator_all, operator_free; /* as assembled (incremental only); operator_compact's free block */
  Mat               operator_compact;            /* harmonic: operator_all's same-component part */
  IS                free_in_all;
  KSP               ksp;
  Vec               d, rhs, bc_local, bc_all, operator_bc_all;
  MotionType        type;
  PetscReal         stiffening;
  PetscBool         incremental;
  PetscBool         warm_start;                 /* a Krylov solver starts from the mesh in hand */
  Vec               coordinates_reference, start; /* incremental: the step's start d^{n-1}, coordinate layout */
  DM                dm_stiffness;                 /* a P0 field: each cell's weight */
  FEMCeedElasticity ceed;                         /* the operator by libCEED (not biharmonic) */
  PetscBool         use_ceed;                     /* -fem_backend ceed: the solver's operator is libCEED's */
  Vec               stiffness;
  DirichletDatum    datums[FSIOPT_MAX_BOUNDARIES];
  PetscReal         time;
};

/* the cell's weight, an auxiliary P0 field when stiffened */
#define WEIGHT (NfAux > 0 ? a[aOff[0]] : 1.0)

static void G3Harmonic(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                       const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[],
                       const PetscInt aOff_x[], const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[],
                       PetscReal t, PetscReal u_tShift, const PetscReal x[], PetscInt numConstants,
                       const PetscScalar constants[], PetscScalar g3[])
{
  for (PetscInt c = 0; c < dim; ++c)
    for (PetscInt d = 0; d < dim; ++d) g3[((c * dim + c) * dim + d) * dim + d] = WEIGHT;
}

/* linear elasticity with mu = lambda = 1 */
static void G3Elastic(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                      const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[],
                      const PetscInt aOff_x[], const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[],
                      PetscReal t, PetscReal u_tShift, const PetscReal x[], PetscInt numConstants,
                      const PetscScalar constants[], PetscScalar g3[])
{
  for (PetscInt c = 0; c < dim; ++c)
    for (PetscInt d = 0; d < dim; ++d) {
      g3[((c * dim + c) * dim + d) * dim + d] += WEIGHT;
      g3[((c * dim + d) * dim + d) * dim + c] += WEIGHT;
      g3[((c * dim + d) * dim + c) * dim + d] += WEIGHT;
    }
}

/* Biharmonic, mixed: tested by d's (interior) functions phi, (weight grad w, grad phi) = 0
   (G3Harmonic), so that -div(weight grad Delta d) = 0; by w's (all) functions psi,
   (grad d, grad psi) - (w, psi) = 0. Symmetric without weights; MUMPS' LU takes either. */
static void G3BiharmonicWD(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                           const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[],
                           const PetscInt aOff[], const PetscInt aOff_x[], const PetscScalar a[],
                           const PetscScalar a_t[], const PetscScalar a_x[], PetscReal t, PetscReal u_tShift,
                           const PetscReal x[], PetscInt numConstants, const PetscScalar constants[], PetscScalar g3[])
{
  for (PetscInt c = 0; c < dim; ++c)
    for (PetscInt d = 0; d < dim; ++d) g3[((c * dim + c) * dim + d) * dim + d] = 1.0;
}

static void G0BiharmonicWW(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                           const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[],
                           const PetscInt aOff[], const PetscInt aOff_x[], const PetscScalar a[],
                           const PetscScalar a_t[], const PetscScalar a_x[], PetscReal t, PetscReal u_tShift,
                           const PetscReal x[], PetscInt numConstants, const PetscScalar constants[], PetscScalar g0[])
{
  for (PetscInt c = 0; c < dim; ++c) g0[c * dim + c] = -1.0;
}

/* The cells' weights (|K|_mean / |K|)^chi on dm_all's present coordinates. */
static PetscErrorCode ComputeStiffness(MeshMotion mm)
{
  PetscSection section;
  PetscScalar *w;
  PetscReal    total = 0;
  PetscInt     cStart, cEnd, ncells;

  PetscFunctionBeginUser;
  PetscCall(DMGetLocalSection(mm->dm_stiffness, &section));
  PetscCall(DMPlexGetHeightStratum(mm->dm_all, 0, &cStart, &cEnd));
  PetscCall(VecGetArray(mm->stiffness, &w));
  for (PetscInt c = cStart; c < cEnd; ++c) { /* the volumes first, then their weights */
    PetscReal v;
    PetscInt  off;
    PetscCall(DMPlexComputeCellGeometryFVM(mm->dm_all, c, &v, NULL, NULL));
    PetscCall(PetscSectionGetOffset(section, c, &off));
    w[off] = v;
    total += v;
  }
  ncells = cEnd - cStart;
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &total, 1, MPIU_REAL, MPIU_SUM, PetscObjectComm((PetscObject)mm->dm_all)));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &ncells, 1, MPIU_INT, MPI_SUM, PetscObjectComm((PetscObject)mm->dm_all)));
  for (PetscInt c = cStart; c < cEnd; ++c) {
    PetscInt off;
    PetscCall(PetscSectionGetOffset(section, c, &off));
    w[off] = PetscPowReal(total / ncells / PetscRealPart(w[off]), mm->stiffening);
  }
  PetscCall(VecRestoreArray(mm->stiffness, &w));
  PetscFunctionReturn(0);
}

/* the weights, an auxiliary P0 field of the operator's DM */
static PetscErrorCode SetStiffness(MeshMotion mm)
{
  PetscFE displacement;

  PetscFunctionBeginUser;
  PetscCall(DMGetField(mm->dm_all, 0, NULL, (PetscObject *)&displacement));
  PetscCall(DMClone(mm->dm_all, &mm->dm_stiffness));
  PetscCall(FEMCreateField(mm->dm_stiffness, 0, "stiffness", 1, 0, displacement));
  PetscCall(DMCreateDS(mm->dm_stiffness));
  PetscCall(DMCreateLocalVector(mm->dm_stiffness, &mm->stiffness));
  PetscCall(ComputeStiffness(mm));
  PetscCall(DMSetAuxiliaryVec(mm->dm_all, NULL, 0, 0, mm->stiffness));
  PetscFunctionReturn(0);
}

/* -fem_backend_check: libCEED's operator against PETSc's */
static PetscErrorCode CheckBackends(MeshMotion mm)
{
  PetscBool check;
  Mat       petsc, ceed;
  Vec       zero;
  PetscReal difference;

  PetscFunctionBeginUser;
  PetscCall(FEMBackendGet(NULL, &check));
  if (!check || !mm->ceed) PetscFunctionReturn(0);
  PetscCall(DMCreateMatrix(mm->dm_all, &petsc));
  PetscCall(DMGetLocalVector(mm->dm_all, &zero));
  PetscCall(VecZeroEntries(zero));
  PetscCall(DMPlexSNESComputeJacobianFEM(mm->dm_all, zero, petsc, petsc, NULL));
  PetscCall(DMRestoreLocalVector(mm->dm_all, &zero));
  if (mm->stiffening > 0) PetscCall(FEMCeedElasticitySetCellValues(mm->ceed, mm->dm_stiffness, mm->stiffness));
  PetscCall(FEMCeedElasticityCreateMatrix(mm->ceed, &ceed));
  PetscCall(FEMCeedElasticityJacobian(mm->ceed, NULL, ceed));
  PetscCall(FEMCeedMatDifference(ceed, petsc, &difference));
  PetscCall(MatDestroy(&ceed));
  PetscCall(MatDestroy(&petsc));
  PetscCall(PetscPrintf(PetscObjectComm((PetscObject)mm->dm_all),
                        "fsiopt: backend check: mesh motion operator %.2e, libCEED relative to PETSc\n",
                        (double)difference));
  PetscCheck(difference <= 1e-12, PetscObjectComm((PetscObject)mm->dm_all), PETSC_ERR_PLIB,
             "option -fem_backend_check: the mesh motion's libCEED operator differs from PETSc's by %.2e, more than "
             "1e-12",
             (double)difference);
  PetscFunctionReturn(0);
}

/* the free block A_ff of the compact operator, in the pattern it had (a factorization then
   keeps its symbolic part) */
static PetscErrorCode ExtractFreeBlock(MeshMotion mm)
{
  PetscFunctionBeginUser;
  PetscCall(MatCreateSubMatrix(mm->operator_compact, mm->free_in_all, mm->free_in_all,
                               mm->operator_free ? MAT_REUSE_MATRIX : MAT_INITIAL_MATRIX, &mm->operator_free));
  PetscFunctionReturn(0);
}

/* A (and its free block) on dm_all's present coordinates */
static PetscErrorCode AssembleOperator(MeshMotion mm)
{
  Vec zero;

  PetscFunctionBeginUser;
  if (mm->use_ceed) {
    if (mm->stiffening > 0) PetscCall(FEMCeedElasticitySetCellValues(mm->ceed, mm->dm_stiffness, mm->stiffness));
    PetscCall(FEMCeedElasticityJacobian(mm->ceed, NULL, mm->operator_all));
  } else {
    PetscCall(DMGetLocalVector(mm->dm_all, &zero));
    PetscCall(VecZeroEntries(zero));
    PetscCall(MatZeroEntries(mm->operator_all));
    PetscCall(DMPlexSNESComputeJacobianFEM(mm->dm_all, zero, mm->operator_all, mm->operator_all, NULL));
    PetscCall(DMRestoreLocalVector(mm->dm_all, &zero));
  }
  /* the vector field's pattern holds couplings between components that the harmonic
     extension leaves zero: two thirds of its entries in 3D, read by every product and
     every multigrid level. The elastic one couples them; the biharmonic one has two fields */
  if (mm->type == MOTION_HARMONIC) {
    PetscInt dim;
    PetscCall(DMGetDimension(mm->dm_all, &dim));
    PetscCall(FEMMatrixSameComponentPart(mm->operator_all, dim,
                                         mm->operator_compact ? MAT_REUSE_MATRIX : MAT_INITIAL_MATRIX,
                                         &mm->operator_compact));
  } else if (!mm->operator_compact) {
    PetscCall(PetscObjectReference((PetscObject)mm->operator_all));
    mm->operator_compact = mm->operator_all;
  }
  if (mm->free_in_all) PetscCall(ExtractFreeBlock(mm));
  PetscFunctionReturn(0);
}

/* the displacement, and for the biharmonic extension w = -Delta d with d's quadrature */
static PetscErrorCode CreateFields(MeshMotion mm, DM dm)
{
  PetscFE displacement;

  PetscFunctionBeginUser;
  PetscCall(FEMCreateField(dm, 0, "mesh_displacement", -1, 1, NULL));
  if (mm->type != MOTION_BIHARMONIC) PetscFunctionReturn(0);
  PetscCall(DMGetField(dm, 0, NULL, (PetscObject *)&displacement));
  PetscCall(FEMCreateField(dm, 1, "mesh_displacement_laplacian", -1, 1, displacement));
  PetscFunctionReturn(0);
}

PetscErrorCode MeshMotionCreate(DM fluid, PetscInt interface_face, PetscInt nfixed, const PetscInt fixed_faces[],
                                MeshMotion *motion)
{
  MeshMotion  mm;
  PetscBool   warm_start_set = PETSC_FALSE;
  PhysicsData data;
  PetscDS     ds;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&mm));
  PetscOptionsBegin(PetscObjectComm((PetscObject)fluid), NULL, "Mesh motion", "mesh");
  PetscCall(PetscOptionsEnum("-mesh_motion", "Extension of the interface displacement into the fluid mesh", NULL,
                             MotionTypes, (PetscEnum)mm->type, (PetscEnum *)&mm->type, NULL));
  PetscCall(OptionsNonNegativeReal(PetscOptionsObject, "-mesh_motion_stiffening",
                                   "weight each cell by (mean cell size / its size)^chi: small cells near a body move "
                                   "rigidly (0: none)",
                                   &mm->stiffening));
  PetscCall(PetscOptionsBool("-mesh_motion_incremental",
                             "extend each step's increment from the mesh of the step's start, with the operator and "
                             "weights of that mesh (one assembly and factorization per step), instead of the total "
                             "displacement from the reference mesh",
                             NULL, mm->incremental, &mm->incremental, NULL));
  mm->warm_start = PETSC_TRUE;
  PetscCall(PetscOptionsBool("-mesh_motion_warm_start",
                             "an iterative mesh solver (-mesh_ksp_type other than preonly) starts from the "
                             "displacement of the mesh in hand, which checkpoints keep, so a restarted run repeats the "
                             "iterations",
                             NULL, mm->warm_start, &mm->warm_start, &warm_start_set));
  PetscOptionsEnd();
  /* a quadrature of its own: PETSc 3.18 caches cell geometry by quadrature on the cell
     IS that clones share, and this mesh does not move */
  PetscCall(DMClone(fluid, &mm->dm_all));
  PetscCall(CreateFields(mm, mm->dm_all));
  PetscCall(DMCreateDS(mm->dm_all));
  PetscCall(DMGetDS(mm->dm_all, &ds));
  if (mm->stiffening > 0) PetscCall(SetStiffness(mm));
  switch (mm->type) {
  case MOTION_HARMONIC:
    PetscCall(PetscDSSetJacobian(ds, 0, 0, NULL, NULL, NULL, G3Harmonic));
    break;
  case MOTION_ELASTIC:
    PetscCall(PetscDSSetJacobian(ds, 0, 0, NULL, NULL, NULL, G3Elastic));
    break;
  case MOTION_BIHARMONIC:
    PetscCall(PetscDSSetJacobian(ds, 0, 1, NULL, NULL, NULL, G3Harmonic));
    PetscCall(PetscDSSetJacobian(ds, 1, 0, NULL, NULL, NULL, G3BiharmonicWD));
    PetscCall(PetscDSSetJacobian(ds, 1, 1, G0BiharmonicWW, NULL, NULL, NULL));
    break;
  }
  {
    FEMBackend backend;
    PetscBool  check;
    PetscCall(FEMBackendGet(&backend, &check));
    if ((backend == FEM_BACKEND_CEED || check) && mm->type != MOTION_BIHARMONIC) {
      PetscCall(FEMCeedElasticityCreate(mm->dm_all, PETSC_FALSE, mm->stiffening > 0 ? FEM_CEED_CELLS_WEIGHT : FEM_CEED_CELLS_NONE,
                                         &mm->ceed));
      /* harmonic: P = c G; elastic (mu = lambda = 1): P = c (G + G^T + tr(G) I) */
      if (mm->type == MOTION_HARMONIC) PetscCall(FEMCeedElasticitySetForm(mm->ceed, 0.0, 1.0, 0.0, 0.0, 1.0));
      else PetscCall(FEMCeedElasticitySetForm(mm->ceed, 0.0, 1.0, 1.0, 1.0, 0.0));
      mm->use_ceed = backend == FEM_BACKEND_CEED ? PETSC_TRUE : PETSC_FALSE;
    }
    if (mm->use_ceed) PetscCall(FEMCeedElasticityCreateMatrix(mm->ceed, &mm->operator_all));
    else PetscCall(DMCreateMatrix(mm->dm_all, &mm->operator_all));
  }
  PetscCall(AssembleOperator(mm));
  PetscCall(CheckBackends(mm));
  /* the same field with the fixed faces and the interface constrained: its free dofs */
  PetscCall(DMClone(fluid, &mm->dm));
  PetscCall(CreateFields(mm, mm->dm));
  PetscCall(PetscMemzero(&data, sizeof(data)));
  data.n_dirichlet = nfixed + 1;
  for (PetscInt b = 0; b < nfixed; ++b) data.dirichlet_faces[b] = fixed_faces[b];
  data.dirichlet_faces[nfixed] = interface_face;
  for (PetscInt b = 0; b <= nfixed; ++b) data.dirichlet_fn[b] = FEMZero;
  PetscCall(DMCreateDS(mm->dm));
  PetscCall(FEMAddBoundaries(mm->dm, 0, &data, mm->datums, &mm->time));
  PetscCall(FEMFreeDofs(mm->dm, mm->dm_all, &mm->free_in_all));
  PetscCall(ExtractFreeBlock(mm));
  /* only the incremental motion assembles A again; the harmonic one's compact copy holds it */
  if (!mm->incremental) PetscCall(MatDestroy(&mm->operator_all));
  PetscCall(KSPCreate(PetscObjectComm((PetscObject)fluid), &mm->ksp));
  PetscCall(KSPSetOptionsPrefix(mm->ksp, "mesh_"));
  PetscCall(KSPSetOperators(mm->ksp, mm->operator_free, mm->operator_free));
  PetscCall(KSPSetType(mm->ksp, KSPPREONLY));
  {
    PC pc;
    PetscCall(KSPGetPC(mm->ksp, &pc));
    PetscCall(FEMDirectSolverDefaults("mesh_"));
    PetscCall(PCSetType(pc, PCLU));
    PetscCall(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
  }
  PetscCall(KSPSetFromOptions(mm->ksp));
  {
    PetscBool krylov;
    PetscCall(FEMSolverIsKrylov(mm->ksp, &krylov));
    PetscCheck(krylov || !warm_start_set || !mm->warm_start, PetscObjectComm((PetscObject)fluid), PETSC_ERR_ARG_INCOMP,
               "option -mesh_motion_warm_start: expected an iterative mesh solver (-mesh_ksp_type other than "
               "preonly); a factorization takes no first guess");
    mm->warm_start = (PetscBool)(mm->warm_start && krylov);
    if (mm->warm_start) PetscCall(KSPSetInitialGuessNonzero(mm->ksp, PETSC_TRUE));
  }
  PetscCall(KSPSetUp(mm->ksp));
  PetscCall(DMCreateGlobalVector(mm->dm, &mm->d));
  PetscCall(VecDuplicate(mm->d, &mm->rhs));
  PetscCall(DMCreateLocalVector(mm->dm, &mm->bc_local));
  PetscCall(DMCreateGlobalVector(mm->dm_all, &mm->bc_all));
  PetscCall(VecDuplicate(mm->bc_all, &mm->operator_bc_all));
  if (mm->incremental) {
    Vec coordinates;
    PetscCall(DMGetCoordinatesLocal(mm->dm_all, &coordinates));
    PetscCall(VecDuplicate(coordinates, &mm->coordinates_reference));
    PetscCall(VecCopy(coordinates, mm->coordinates_reference));
    PetscCall(VecDuplicate(coordinates, &mm->start));
    PetscCall(VecZeroEntries(mm->start));
  }
  *motion = mm;
  PetscFunctionReturn(0);
}

PetscErrorCode MeshMotionBeginStep(MeshMotion mm, Vec displacement)
{
  Vec coordinates;

  PetscFunctionBeginUser;
  if (!mm->incremental) PetscFunctionReturn(0);
  PetscCall(VecCopy(displacement, mm->start));
  PetscCall(VecDuplicate(mm->coordinates_reference, &coordinates));
  PetscCall(VecWAXPY(coordinates, 1.0, mm->coordinates_reference, displacement));
  PetscCall(DMSetCoordinatesLocal(mm->dm_all, coordinates));
  PetscCall(VecDestroy(&coordinates));
  PetscCall(FEMInvalidateGeometry(mm->dm_all));
  if (mm->stiffening > 0) PetscCall(ComputeStiffness(mm));
  PetscCall(AssembleOperator(mm));
  PetscFunctionReturn(0);
}

/* Between the motion's local layout and the coordinate layout, vertex by vertex: to_motion,
   motion = coordinates - start; else coordinates = motion + start (start NULL: 0). */
static PetscErrorCode Relayout(MeshMotion mm, PetscBool to_motion, const PetscScalar start[], const PetscScalar from[],
                               PetscScalar to[])
{
  PetscInt     dim, vStart, vEnd;
  PetscSection ls, cs;

  PetscFunctionBeginUser;
  PetscCall(DMGetDimension(mm->dm, &dim));
  PetscCall(DMPlexGetDepthStratum(mm->dm, 0, &vStart, &vEnd));
  PetscCall(DMGetLocalSection(mm->dm, &ls));
  PetscCall(DMGetCoordinateSection(mm->dm, &cs));
  for (PetscInt v = vStart; v < vEnd; ++v) {
    PetscInt off, coff;
    PetscCall(PetscSectionGetFieldOffset(ls, v, 0, &off));
    PetscCall(PetscSectionGetOffset(cs, v, &coff));
    for (PetscInt d = 0; d < dim; ++d) {
      const PetscScalar s = start ? start[coff + d] : 0.0;
      if (to_motion) to[off + d] = from[coff + d] - s;
      else to[coff + d] = from[off + d] + s;
    }
  }
  PetscFunctionReturn(0);
}

PetscErrorCode MeshMotionSolve(MeshMotion mm, Interface itf, Vec interface, Vec displacement)
{
  PetscInt           n, dim, vStart, vEnd;
  const PetscInt    *points;
  const PetscScalar *g;
  const PetscScalar *start = NULL;
  PetscScalar       *b;
  PetscSection       ls, cs;
  Vec                dlocal;
  KSPConvergedReason reason;
  PetscInt           its;

  PetscFunctionBeginUser;
  PetscCall(DMGetDimension(mm->dm, &dim));
  PetscCall(DMPlexGetDepthStratum(mm->dm, 0, &vStart, &vEnd));
  PetscCall(DMGetLocalSection(mm->dm, &ls));
  PetscCall(DMGetCoordinateSection(mm->dm, &cs));
  PetscCall(InterfaceGetFluidNodes(itf, &n, &points, NULL));
  /* the interface vertices' values, owners' first, then to every copy */
  PetscCall(VecZeroEntries(mm->bc_local));
  PetscCall(VecGetArrayRead(interface, &g));
  PetscCall(VecGetArray(mm->bc_local, &b));
  if (mm->incremental) PetscCall(VecGetArrayRead(mm->start, &start));
  for (PetscInt i = 0; i < n; ++i) {
    PetscInt off, coff;
    if (points[i] < vStart || points[i] >= vEnd) continue; /* edge nodes: the mesh is affine */
    PetscCall(PetscSectionGetFieldOffset(ls, points[i], 0, &off));
    PetscCall(PetscSectionGetOffset(cs, points[i], &coff));
    for (PetscInt d = 0; d < dim; ++d) b[off + d] = g[i * dim + d] - (start ? start[coff + d] : 0.0);
  }
  PetscCall(VecRestoreArray(mm->bc_local, &b));
  PetscCall(VecRestoreArrayRead(interface, &g));
  PetscCall(VecZeroEntries(mm->bc_all));
  PetscCall(DMLocalToGlobal(mm->dm_all, mm->bc_local, ADD_VALUES, mm->bc_all));
  PetscCall(DMGlobalToLocal(mm->dm_all, mm->bc_all, INSERT_VALUES, mm->bc_local));

  PetscCall(MatMult(mm->operator_compact, mm->bc_all, mm->operator_bc_all));
  {
    Vec free_part;
    PetscCall(VecGetSubVector(mm->operator_bc_all, mm->free_in_all, &free_part));
    PetscCall(VecCopy(free_part, mm->rhs));
    PetscCall(VecRestoreSubVector(mm->operator_bc_all, mm->free_in_all, &free_part));
  }
  PetscCall(VecScale(mm->rhs, -1.0));
  if (mm->warm_start) { /* not the solver's last answer: a restarted run has not got it */
    const PetscScalar *now;
    PetscScalar       *guess;
    PetscCall(DMGetLocalVector(mm->dm, &dlocal));
    PetscCall(VecGetArrayRead(displacement, &now));
    PetscCall(VecGetArray(dlocal, &guess));
    PetscCall(Relayout(mm, PETSC_TRUE, start, now, guess));
    PetscCall(VecRestoreArray(dlocal, &guess));
    PetscCall(VecRestoreArrayRead(displacement, &now));
    PetscCall(DMLocalToGlobal(mm->dm, dlocal, INSERT_VALUES, mm->d));
    PetscCall(DMRestoreLocalVector(mm->dm, &dlocal));
  }
  PetscCall(KSPSolve(mm->ksp, mm->rhs, mm->d));
  PetscCall(KSPGetConvergedReason(mm->ksp, &reason));
  PetscCall(KSPGetIterationNumber(mm->ksp, &its));
  if (reason == KSP_DIVERGED_DTOL && its == 0) {
    /* PETSc measures a first guess's residual against ||b||: with the interface back at its
       start (b at round-off, a wall at rest) the guess of a displaced mesh reads 1e5 ||b|| and
       diverges at once, where zero is the better start */
    PetscCall(VecZeroEntries(mm->d));
    PetscCall(KSPSolve(mm->ksp, mm->rhs, mm->d));
    PetscCall(KSPGetConvergedReason(mm->ksp, &reason));
  }
  PetscCheck(reason > 0, PetscObjectComm((PetscObject)mm->dm), PETSC_ERR_NOT_CONVERGED,
             "mesh motion solve failed: KSP reason %s", KSPConvergedReasons[reason]);
  PetscCall(DMGetLocalVector(mm->dm, &dlocal));
  PetscCall(VecZeroEntries(dlocal));
  PetscCall(DMGlobalToLocal(mm->dm, mm->d, INSERT_VALUES, dlocal));
  PetscCall(VecAXPY(dlocal, 1.0, mm->bc_local));
  PetscCall(VecGetArrayRead(dlocal, &g));
  PetscCall(VecGetArray(displacement, &b));
  PetscCall(Relayout(mm, PETSC_FALSE, start, g, b));
  PetscCall(VecRestoreArray(displacement, &b));
  PetscCall(VecRestoreArrayRead(dlocal, &g));
  if (start) PetscCall(VecRestoreArrayRead(mm->start, &start));
  PetscCall(DMRestoreLocalVector(mm->dm, &dlocal));
  PetscFunctionReturn(0);
}

PetscErrorCode MeshMotionDestroy(MeshMotion *motion)
{
  MeshMotion mm = *motion;

  PetscFunctionBeginUser;
  if (!mm) PetscFunctionReturn(0);
  PetscCall(VecDestroy(&mm->d));
  PetscCall(VecDestroy(&mm->bc_local));
  PetscCall(VecDestroy(&mm->rhs));
  PetscCall(VecDestroy(&mm->bc_all));
  PetscCall(VecDestroy(&mm->operator_bc_all));
  PetscCall(MatDestroy(&mm->operator_all));
  PetscCall(MatDestroy(&mm->operator_compact));
  PetscCall(FEMCeedElasticityDestroy(&mm->ceed));
  PetscCall(MatDestroy(&mm->operator_free));
  PetscCall(ISDestroy(&mm->free_in_all));
  PetscCall(KSPDestroy(&mm->ksp));
  PetscCall(DMDestroy(&mm->dm));
  PetscCall(DMDestroy(&mm->dm_all));
  PetscCall(VecDestroy(&mm->stiffness));
  PetscCall(DMDestroy(&mm->dm_stiffness));
  PetscCall(VecDestroy(&mm->coordinates_reference));
  PetscCall(VecDestroy(&mm->start));
  PetscCall(PetscFree(*motion));
  PetscFunctionReturn(0);
}
