/* Harmonic or linear-elastic extension of the interface displacement (DESIGN §2). */
#include "motion.h"
#include "fem.h"
#include "options.h"

#pragma GCC diagnostic ignored "-Wunused-parameter"

typedef enum { MOTION_HARMONIC, MOTION_ELASTIC } MotionType;
static const char *const MotionTypes[] = {"harmonic", "elastic", "MotionType", "MOTION_", NULL};

struct _p_MeshMotion {
  DM             dm, dm_free; /* Q1 vector field with (without) the Dirichlet constraints */
  SNES           snes;
  Vec            d, bc_local, free_global;
  PetscInt       factorizations;
  MotionType     type;
  DirichletDatum datums[FSIOPT_MAX_BOUNDARIES];
  PetscReal      time;
};

static void F1Harmonic(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[], const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[], const PetscInt aOff_x[], const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[], PetscReal t, const PetscReal x[], PetscInt numConstants, const PetscScalar constants[], PetscScalar f1[])
{
  for (PetscInt i = 0; i < dim * dim; ++i) f1[i] = u_x[i];
}

static void G3Harmonic(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[], const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[], const PetscInt aOff_x[], const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[], PetscReal t, PetscReal u_tShift, const PetscReal x[], PetscInt numConstants, const PetscScalar constants[], PetscScalar g3[])
{
  for (PetscInt c = 0; c < dim; ++c)
    for (PetscInt d = 0; d < dim; ++d) g3[((c * dim + c) * dim + d) * dim + d] = 1.0;
}

/* linear elasticity with mu = lambda = 1 */
static void F1Elastic(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[], const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[], const PetscInt aOff_x[], const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[], PetscReal t, const PetscReal x[], PetscInt numConstants, const PetscScalar constants[], PetscScalar f1[])
{
  PetscScalar divergence = 0;
  for (PetscInt d = 0; d < dim; ++d) divergence += u_x[d * dim + d];
  for (PetscInt c = 0; c < dim; ++c)
    for (PetscInt d = 0; d < dim; ++d) f1[c * dim + d] = u_x[c * dim + d] + u_x[d * dim + c] + (c == d ? divergence : 0.0);
}

static void G3Elastic(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[], const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[], const PetscInt aOff_x[], const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[], PetscReal t, PetscReal u_tShift, const PetscReal x[], PetscInt numConstants, const PetscScalar constants[], PetscScalar g3[])
{
  for (PetscInt c = 0; c < dim; ++c)
    for (PetscInt d = 0; d < dim; ++d) {
      g3[((c * dim + c) * dim + d) * dim + d] += 1.0;
      g3[((c * dim + d) * dim + d) * dim + c] += 1.0;
      g3[((c * dim + d) * dim + c) * dim + d] += 1.0;
    }
}

static PetscErrorCode Zero(PetscInt dim, PetscReal t, const PetscReal x[], PetscInt Nc, PetscScalar *u, void *ctx)
{
  for (PetscInt c = 0; c < Nc; ++c) u[c] = 0;
  return 0;
}

/* zero on every constrained dof, then the interface displacement where it is given */
static PetscErrorCode InsertBoundary(DM dm, Vec xlocal, void *ctx)
{
  MeshMotion mm = (MeshMotion)ctx;

  PetscFunctionBeginUser;
  PetscCall(DMPlexInsertBoundaryValues(dm, PETSC_TRUE, xlocal, 0.0, NULL, NULL, NULL));
  PetscCall(VecAXPY(xlocal, 1.0, mm->bc_local));
  PetscFunctionReturn(0);
}

PetscErrorCode MeshMotionCreate(DM fluid, PetscInt interface_face, PetscInt nfixed, const PetscInt fixed_faces[], MeshMotion *motion)
{
  MeshMotion  mm;
  PhysicsData data;
  PetscDS     ds;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&mm));
  PetscOptionsBegin(PetscObjectComm((PetscObject)fluid), NULL, "Mesh motion", "mesh");
  PetscCall(PetscOptionsEnum("-mesh_motion", "Extension of the interface displacement into the fluid mesh", NULL, MotionTypes, (PetscEnum)mm->type, (PetscEnum *)&mm->type, NULL));
  PetscOptionsEnd();
  PetscCall(DMClone(fluid, &mm->dm_free));
  /* a quadrature of its own: PETSc 3.18 caches cell geometry by quadrature on the cell
     IS that clones share, and this mesh does not move */
  PetscCall(FEMCreateField(mm->dm_free, 0, "mesh_displacement", -1, 1, NULL));
  PetscCall(DMCreateDS(mm->dm_free));
  PetscCall(DMClone(fluid, &mm->dm));
  PetscCall(FEMCreateField(mm->dm, 0, "mesh_displacement", -1, 1, NULL));
  PetscCall(DMCreateDS(mm->dm));
  PetscCall(DMGetDS(mm->dm, &ds));
  if (mm->type == MOTION_HARMONIC) {
    PetscCall(PetscDSSetResidual(ds, 0, NULL, F1Harmonic));
    PetscCall(PetscDSSetJacobian(ds, 0, 0, NULL, NULL, NULL, G3Harmonic));
  } else {
    PetscCall(PetscDSSetResidual(ds, 0, NULL, F1Elastic));
    PetscCall(PetscDSSetJacobian(ds, 0, 0, NULL, NULL, NULL, G3Elastic));
  }
  PetscCall(PetscMemzero(&data, sizeof(data)));
  data.n_dirichlet = nfixed + 1;
  for (PetscInt b = 0; b < nfixed; ++b) data.dirichlet_faces[b] = fixed_faces[b];
  data.dirichlet_faces[nfixed] = interface_face;
  for (PetscInt b = 0; b <= nfixed; ++b) data.dirichlet_fn[b] = Zero;
  PetscCall(FEMAddBoundaries(mm->dm, 0, &data, mm->datums, &mm->time));
  PetscCall(FEMCreateSNES(mm->dm, "mesh_", FEM_JACOBIAN_CONSTANT, &mm->factorizations, &mm->snes));
  PetscCall(DMSNESSetBoundaryLocal(mm->dm, InsertBoundary, mm));
  PetscCall(DMCreateGlobalVector(mm->dm, &mm->d));
  PetscCall(VecZeroEntries(mm->d));
  PetscCall(DMCreateLocalVector(mm->dm, &mm->bc_local));
  PetscCall(DMCreateGlobalVector(mm->dm_free, &mm->free_global));
  *motion = mm;
  PetscFunctionReturn(0);
}

PetscErrorCode MeshMotionSolve(MeshMotion mm, Interface itf, Vec interface, Vec displacement)
{
  PetscInt           n, dim, vStart, vEnd;
  const PetscInt    *points;
  const PetscScalar *g;
  PetscScalar       *b;
  PetscSection       ls, cs;
  Vec                dlocal;
  SNESConvergedReason reason;

  PetscFunctionBeginUser;
  PetscCall(DMGetDimension(mm->dm, &dim));
  PetscCall(DMPlexGetDepthStratum(mm->dm, 0, &vStart, &vEnd));
  PetscCall(DMGetLocalSection(mm->dm, &ls));
  PetscCall(InterfaceGetFluidNodes(itf, &n, &points, NULL));
  /* the interface vertices' values, owners' first, then to every copy */
  PetscCall(VecZeroEntries(mm->bc_local));
  PetscCall(VecGetArrayRead(interface, &g));
  PetscCall(VecGetArray(mm->bc_local, &b));
  for (PetscInt i = 0; i < n; ++i) {
    PetscInt off;
    if (points[i] < vStart || points[i] >= vEnd) continue; /* edge nodes: the mesh is affine */
    PetscCall(PetscSectionGetOffset(ls, points[i], &off));
    for (PetscInt d = 0; d < dim; ++d) b[off + d] = g[i * dim + d];
  }
  PetscCall(VecRestoreArray(mm->bc_local, &b));
  PetscCall(VecRestoreArrayRead(interface, &g));
  PetscCall(VecZeroEntries(mm->free_global));
  PetscCall(DMLocalToGlobal(mm->dm_free, mm->bc_local, ADD_VALUES, mm->free_global));
  PetscCall(DMGlobalToLocal(mm->dm_free, mm->free_global, INSERT_VALUES, mm->bc_local));

  PetscCall(FEMInvalidateGeometry(mm->dm));
  PetscCall(SNESSolve(mm->snes, NULL, mm->d));
  PetscCall(SNESGetConvergedReason(mm->snes, &reason));
  PetscCheck(reason > 0, PetscObjectComm((PetscObject)mm->dm), PETSC_ERR_NOT_CONVERGED, "mesh motion solve failed: SNES reason %s", SNESConvergedReasons[reason]);
  PetscCall(DMGetLocalVector(mm->dm, &dlocal));
  PetscCall(VecZeroEntries(dlocal));
  PetscCall(DMGlobalToLocal(mm->dm, mm->d, INSERT_VALUES, dlocal));
  PetscCall(InsertBoundary(mm->dm, dlocal, mm));
  PetscCall(DMGetCoordinateSection(mm->dm, &cs));
  PetscCall(VecGetArrayRead(dlocal, &g));
  PetscCall(VecGetArray(displacement, &b));
  for (PetscInt v = vStart; v < vEnd; ++v) {
    PetscInt off, coff;
    PetscCall(PetscSectionGetOffset(ls, v, &off));
    PetscCall(PetscSectionGetOffset(cs, v, &coff));
    for (PetscInt d = 0; d < dim; ++d) b[coff + d] = g[off + d];
  }
  PetscCall(VecRestoreArray(displacement, &b));
  PetscCall(VecRestoreArrayRead(dlocal, &g));
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
  PetscCall(VecDestroy(&mm->free_global));
  PetscCall(SNESDestroy(&mm->snes));
  PetscCall(DMDestroy(&mm->dm));
  PetscCall(DMDestroy(&mm->dm_free));
  PetscCall(PetscFree(*motion));
  PetscFunctionReturn(0);
}
