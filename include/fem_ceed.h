#ifndef FSIOPT_FEM_CEED_H
#define FSIOPT_FEM_CEED_H
#include <petscdmplex.h>
#include <ceed.h>
#include <string.h>

/* libCEED, the fast backend of the finite-element operators (docs/design.md §5): the pieces of a
   CeedOperator taken from a DMPlex and its PetscFE, so that an operator integrates what
   PETSc's integration does, at the same quadrature points with the same basis values. */

/* A libCEED call checked: its error becomes a PETSc error with libCEED's message. */
/* Without a message on its Ceed the error was raised without one, as libCEED raises a failed
   allocation (its other such errors come from CeedInit, which is called with no Ceed). */
#define PetscCallCeed(ceed, call) \
  do { \
    if ((call) != CEED_ERROR_SUCCESS) { \
      const char *ceed_message = "(no message)"; \
      if (ceed) CeedGetErrorMessage(ceed, &ceed_message); \
      PetscCheck(!(ceed) || !strstr(ceed_message, "No error message"), PETSC_COMM_SELF, PETSC_ERR_MEM, \
                 "out of memory: a libCEED allocation failed"); \
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_LIB, "libCEED: %s", ceed_message); \
    } \
  } while (0)

/* -fem_backend: the operators by libCEED (the default) or PETSc's pointwise integration (the reference);
   -fem_backend_check: compare the two (check may be NULL); GetName: the backend's name, by
   which the solvers choose their operators */
typedef enum {
  FEM_BACKEND_PETSC,
  FEM_BACKEND_CEED
} FEMBackend;
PetscErrorCode FEMBackendGet(FEMBackend *, PetscBool *check);
PetscErrorCode FEMBackendGetName(const char **name, PetscBool *check);

/* The run's Ceed, of the backend -ceed (default /cpu/self/opt/blocked); made on first use. */
PetscErrorCode FEMCeedGet(Ceed *);

/* The element restriction of field `field` of dm's local vectors (DMPlexGetLocalOffsets:
   the nodes of each cell in closure order, components interlaced). */
PetscErrorCode FEMCeedRestriction(Ceed, DM dm, PetscInt field, CeedElemRestriction *);
/* The H1 basis of fe at fe's quadrature: the values and reference gradients PETSc tabulates
   (one scalar basis for every component), the same points and weights. */
PetscErrorCode FEMCeedBasis(Ceed, DM dm, PetscFE fe, CeedBasis *);
/* The cells' coordinates: their restriction and basis at fe's quadrature, and the local
   coordinate vector as a CeedVector. */
PetscErrorCode FEMCeedCoordinates(Ceed, DM dm, PetscFE fe, CeedElemRestriction *, CeedBasis *, CeedVector *);

/* The geometry at fe's quadrature points of every cell, for the operators' pointwise
   functions (qfunctions_geometry.h): [w |det A|, A^{-1}], 1 + dim^2 values per point, in a
   new restriction and vector. */
PetscErrorCode FEMCeedGeometry(Ceed, DM dm, PetscFE fe, CeedElemRestriction *r_q, CeedVector *qdata);
/* The same kept up to date: created at the first call, recomputed from dm's coordinates
   only when they changed since (the set-up operator is kept in the key) */
typedef struct {
  PetscObjectId       id;
  PetscObjectState    state;
  CeedElemRestriction r_x;
  CeedBasis           b_x;
  CeedVector          coordinates;
  CeedOperator        op;
} FEMCeedGeometryKey;
PetscErrorCode FEMCeedGeometryFollow(Ceed, DM dm, PetscFE fe, FEMCeedGeometryKey *, CeedElemRestriction *r_q,
                                     CeedVector *qdata);
PetscErrorCode FEMCeedGeometryKeyDestroy(Ceed, FEMCeedGeometryKey *);

/* A restriction of `size` values at each quadrature point of the cells of `cells` (points
   fastest, then components, then cells: the layout a caller may write), and a zeroed vector
   of it when values is not NULL */
PetscErrorCode FEMCeedPointRestriction(Ceed, CeedElemRestriction cells, CeedBasis basis, CeedInt size,
                                       CeedElemRestriction *points, CeedVector *values);
/* n zeroed CeedVectors of dm's local size */
PetscErrorCode FEMCeedLocalVectors(Ceed, DM dm, PetscInt n, CeedVector *vectors[]);

/* The faces of a face set (the values of label), for boundary operators (ceed_faces.c): as
   PETSc's boundary integration takes them, grouped by their local number k in the first
   supporting cell. Per group: the cells' restrictions of dm's field and of dm_aux's field 0
   (NULL: none), PETSc's face tabulations of face k as bases, and per face point
   [w |J_face|, n] (qdata, 1 + dim values, n outward), recomputed by Geometry when the
   coordinates changed. */
#define FEM_CEED_MAX_CELL_FACES 6
typedef struct {
  PetscInt            local_face;
  CeedInt             n;
  CeedElemRestriction r_u, r_z, r_q;
  CeedBasis           b_u, b_z;
  CeedVector          qdata;
} FEMCeedFaceGroup;
typedef struct _n_FEMCeedFaces {
  Ceed             ceed;
  DM               dm;
  PetscFE          fe;
  CeedInt          dim, nq;
  PetscInt         n, *group_of; /* the faces (points) and their local numbers */
  IS               points;
  PetscInt         n_groups;
  FEMCeedFaceGroup groups[FEM_CEED_MAX_CELL_FACES];
  PetscObjectId    coordinates_id;
  PetscObjectState coordinates_state;
} * FEMCeedFaces;
PetscErrorCode FEMCeedFacesCreate(DM dm, PetscFE fe, PetscInt field, DM dm_aux, DMLabel label, PetscInt nvalues,
                                  const PetscInt values[], FEMCeedFaces *);
PetscErrorCode FEMCeedFacesGeometry(FEMCeedFaces);
PetscErrorCode FEMCeedFacesDestroy(FEMCeedFaces *);
/* The vector mass of dm's field 0 on the faces of label's value (as PETSc's boundary
   integration of g0 = I), in a new AIJ matrix of dm's global size holding those entries only */
PetscErrorCode FEMCeedFaceMass(DM dm, DMLabel label, PetscInt value, Mat *A);

/* An AIJ matrix of dm's global size for MatSetPreallocationCOO (DMCreateMatrix's would leak
   its variable block sizes there, PETSc 3.18). */
PetscErrorCode FEMCeedCreateCOOMatrix(DM dm, Mat *);

/* Where a block's element matrices go, a run of elements at a time: values holds the
   entries offset .. offset + n - 1 of the block, in FEMCeedElementPattern's order. A run
   fits the cache, so the block's entries are never all in memory at once */
typedef struct {
  PetscErrorCode (*add)(void *ctx, CeedSize offset, CeedSize n, const CeedScalar *values);
  void *ctx;
} FEMCeedValuesSink;
/* the elements of a run: one gemm's, and what a sink receives at once (128 of a (Q1,Q1)
   fluid's velocity block, 590 kB) */
#define FEM_CEED_CHUNK_ELEMENTS 128

/* An operator's element matrices (ceed_element_matrices.c): the pattern, local rows and
   columns of every entry (PetscFree2 them), and the values in the same order */
PetscErrorCode FEMCeedElementPattern(Ceed, CeedOperator, CeedSize *count, CeedInt **rows, CeedInt **cols);
PetscErrorCode FEMCeedElementMatrices(Ceed, CeedOperator, FEMCeedValuesSink);

/* COO assembly of n operators (NULL ones skipped: absent blocks) into A: the pattern once
   (counts[b]: the entries of ops[b]), then the values per assembly; a block of the pattern
   whose operator is NULL in an assembly gets zeros. */
PetscErrorCode FEMCeedAssemblySetUp(Ceed, DM dm, PetscInt n, const CeedOperator ops[], Mat A, CeedSize counts[]);
PetscErrorCode FEMCeedAssemble(Ceed, PetscInt n, const CeedOperator ops[], const CeedSize counts[], Mat A);
/* the same, block b's values from custom[b].values where custom is not NULL and that
   function is set (in the order of FEMCeedElementPattern: element, input component, output
   component, input node, output node) */
typedef struct {
  PetscErrorCode (*values)(void *ctx, FEMCeedValuesSink);
  void *ctx;
} FEMCeedBlockValues;
PetscErrorCode FEMCeedAssembleBlocks(Ceed, PetscInt n, const CeedOperator ops[], const FEMCeedBlockValues custom[],
                                     const CeedSize counts[], Mat A);
/* One rank's pattern and assembly without COO (done: FALSE across ranks, or for a matrix
   whose pattern was not set up here): rows and columns global, negative ones dropped */
PetscErrorCode FEMCeedDirectSetUp(Mat A, PetscCount total, const PetscInt rows[], const PetscInt cols[],
                                  PetscBool *done);
PetscErrorCode FEMCeedDirectAssemble(Ceed, PetscInt n, const CeedOperator ops[], const FEMCeedBlockValues custom[],
                                     const CeedSize counts[], Mat A, PetscBool *done);

/* y = sum of ops[k] x (n >= 1) on PETSc local vectors, through the CeedVectors x and y that
   borrow their arrays */
PetscErrorCode FEMCeedApply(Ceed, PetscInt n, const CeedOperator ops[], CeedVector x, CeedVector y, Vec xlocal,
                            Vec ylocal);
/* a copy of a PETSc vector's values into a CeedVector of its size (passive inputs) */
PetscErrorCode FEMCeedVectorCopyFrom(Ceed, CeedVector target, Vec source);

/* A's values into B, a matrix of the same pattern (a duplicate, the Dirichlet fluid's), left
   assembled: MatCopy leaves a duplicate that was never assembled unassembled */
PetscErrorCode FEMCeedCopyMatrix(Mat A, Mat B);

/* ||ceed - petsc||_F / ||petsc||_F (ceed is overwritten by the difference) */
PetscErrorCode FEMCeedMatDifference(Mat ceed, Mat petsc, PetscReal *difference);

/* Vector stiffness forms on dm's field 0 (qfunctions_elasticity.h): m (u, v) + op c (P(grad u),
   grad v), P linear (h G + mu (G + G^T) + lambda tr(G) I) or St. Venant-Kirchhoff (svk),
   with per-cell values from a P0 field (FEMCeedElasticitySetCellValues): none; a weight c
   (else 1); or a material (rho_scale, mu, lambda, svk) of the cell, which then replaces mu,
   lambda and the model, and scales m. The Jacobian's state xlocal is read for St.
   Venant-Kirchhoff only (svk: some cell may be). The geometry follows dm's coordinates. */
typedef enum {
  FEM_CEED_CELLS_NONE     = 0,
  FEM_CEED_CELLS_WEIGHT   = 1,
  FEM_CEED_CELLS_MATERIAL = 4 /* its size */
} FEMCeedCellValues;
typedef struct _n_FEMCeedElasticity *FEMCeedElasticity;
PetscErrorCode FEMCeedElasticityCreate(DM dm, PetscBool svk, FEMCeedCellValues, FEMCeedElasticity *);
PetscErrorCode FEMCeedElasticitySetForm(FEMCeedElasticity, PetscScalar mass, PetscScalar op, PetscScalar mu,
                                        PetscScalar lambda, PetscScalar harmonic);
PetscErrorCode FEMCeedElasticitySetCellValues(FEMCeedElasticity, DM dm_cells, Vec values_local);
PetscErrorCode FEMCeedElasticityResidual(FEMCeedElasticity, Vec xlocal, Vec flocal);
PetscErrorCode FEMCeedElasticityCreateMatrix(FEMCeedElasticity, Mat *);
PetscErrorCode FEMCeedElasticityJacobian(FEMCeedElasticity, Vec xlocal, Mat);
PetscErrorCode FEMCeedElasticityDestroy(FEMCeedElasticity *);

/* -fem_backend_check, shared by the solvers: two operators of a solver, PETSc's (the
   reference) and another backend's, each giving R(x) into the global F at a local state with
   its boundary values and its Jacobian at such a state in a new matrix of its own (the
   solver's keep their values and factors); the titles name them in messages. */
typedef struct {
  DM dm;
  PetscErrorCode (*residual)(void *op, Vec xlocal, Vec F);
  PetscErrorCode (*jacobian)(void *op, Vec xlocal, Mat *A);
  void       *reference, *tested;
  const char *reference_title, *tested_title;
} FEMBackendPair;
#define FEM_BACKEND_CHECK_STEPS 3
#define FEM_BACKEND_CHECK_TOL   1e-12
/* both operators at the global state x (the step's start) and at a random state of entries in
   [-amplitude, amplitude]: one line naming `what` and the step, and an error above the tolerance */
PetscErrorCode FEMBackendCheckStep(const FEMBackendPair *, const char what[], PetscInt step, Vec x,
                                   PetscReal amplitude);

/* -ceed_check_spaces: every field of dm, its mass and Laplacian matrices assembled by libCEED
   (CeedOperatorLinearAssemble into the PETSc matrix by COO) against PETSc's; prints the
   relative differences and fails above tol. */
PetscErrorCode FEMCeedCheckSpaces(DM dm, const char name[], PetscReal tol);
/* The fluid's volume operators (the weak form of fluid_kernels.c) on dm (fields velocity,
   pressure), with the mesh velocity of dm_mesh_velocity's field 0 on moving meshes (NULL:
   fixed); constants as the fluid's PetscDS holds them (FLUID_*), a pressure stabilization
   operator only when they give it a tau > 0. The geometry follows dm's coordinates. */
typedef struct _n_FEMCeedFluid *FEMCeedFluid;
PetscErrorCode FEMCeedFluidCreate(DM dm, DM dm_mesh_velocity, const PetscScalar constants[], FEMCeedFluid *);
PetscErrorCode FEMCeedFluidSetConstants(FEMCeedFluid, const PetscScalar constants[]);
/* Face terms (qfunctions_fluid_faces.h) on the faces of the label's values: the backflow
   stabilization (backflow) or the interface's convective term; before CreateMatrix */
PetscErrorCode FEMCeedFluidAddFaces(FEMCeedFluid, DMLabel, PetscInt nvalues, const PetscInt values[],
                                    PetscBool backflow);
PetscBool      FEMCeedFluidHasFaces(FEMCeedFluid);
/* flocal = the volume residual at xlocal (zlocal: the mesh velocity's local vector, or NULL),
   with the old domains' mass term (below) when old_mass and the face terms when faces */
PetscErrorCode FEMCeedFluidResidual(FEMCeedFluid, Vec xlocal, Vec zlocal, PetscBool old_mass, PetscBool faces,
                                    Vec flocal);
/* A matrix of dm's global rows with the Jacobian's COO pattern, and the Jacobian at xlocal into it */
PetscErrorCode FEMCeedFluidCreateMatrix(FEMCeedFluid, Mat *);
PetscErrorCode FEMCeedFluidJacobian(FEMCeedFluid, Vec xlocal, Vec zlocal, PetscBool old_mass, Mat);
/* The volume Jacobian without a matrix: SetUp fixes its state (and mesh velocity, old-domain
   mass) as FEMCeedFluidJacobian's arguments do, and the present geometry and old-domain
   weights; Apply gives ylocal = J xlocal (or J^T xlocal), the matrix FEMCeedFluidJacobian
   would have assembled at SetUp */
PetscErrorCode FEMCeedFluidJacobianApplySetUp(FEMCeedFluid, Vec xlocal, Vec zlocal, PetscBool old_mass);
PetscErrorCode FEMCeedFluidJacobianApply(FEMCeedFluid, PetscBool transpose, Vec xlocal, Vec ylocal);
/* Moving meshes: the old domains' mass on the velocity, sum_q m_q phi_i phi_j with weights
   m = a0 w|det A|(domain 0) + a1 w|det A|(domain 1), each domain stored from the present
   coordinates of a DM of the same layout (mesh-bound basis functions: only the weights
   change); ylocal = M xlocal (pressure entries zero); with old_mass the Jacobian adds M. */
PetscErrorCode FEMCeedFluidMassDomain(FEMCeedFluid, DM dm_domain, PetscInt slot);
PetscErrorCode FEMCeedFluidMassWeights(FEMCeedFluid, PetscScalar a0, PetscScalar a1);
PetscErrorCode FEMCeedFluidMassApply(FEMCeedFluid, Vec xlocal, Vec ylocal);
PetscErrorCode FEMCeedFluidDestroy(FEMCeedFluid *);
#endif
