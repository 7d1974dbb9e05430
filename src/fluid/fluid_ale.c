/* The fluid on a moving mesh (ALE). Vertices move with the mesh displacement d; the mesh
   velocity z = (d^n - d^{n-1})/dt enters the convection as an auxiliary field. The
   seed's conservative step
     rho/dt [(u^n, v)_{Omega^n} - (u^{n-1}, v)_{Omega^{n-1}}] - rho ((div z) u^n, v) + ...
   is used with the div z term integrated exactly over the step, rho/dt [M(Omega^n) -
   M(Omega^{n-1})] u^n (Reynolds transport for mesh-bound basis functions), which leaves
     rho/dt M(Omega^{n-1}) (u^n - u^{n-1}) + rho (((u^n - z) . grad) u^n, v)_{Omega^n} + ...
   and satisfies the discrete geometric conservation law: a uniform flow stays uniform on
   any mesh motion. M(Omega^{n-1}) is formed once per step by the fluid's operators
   (fluid_operator.h) on a copy of the DM kept on the previous domain.
   BDF2 (-fluid_time_order 2) applies the same idea to d/dt (M u) - (dM/dt) u with both
   derivatives by the BDF2 formula:
     rho/(2 dt) [3 M^n u^n - 4 M^{n-1} u^{n-1} + M^{n-2} u^{n-2} - (3 M^n - 4 M^{n-1} + M^{n-2}) u^n]
       = rho/dt [(2 M^{n-1} - 1/2 M^{n-2}) u^n - 2 M^{n-1} u^{n-1} + 1/2 M^{n-2} u^{n-2}],
   again without M(Omega^n) and exact for a uniform flow, with z = (3 d^n - 4 d^{n-1} +
   d^{n-2})/(2 dt). */
#include "fluid_impl.h"
#include "fem.h"
#include "checkpoint.h"

struct _n_FluidALE {
  DM        dm_aux; /* the mesh velocity z, Q1 */
  Vec       z_local;
  Vec       coordinates_reference, displacement, displacement_old; /* coordinate layout */
  Vec       displacement_previous;                                 /* BDF2: d^{n-2} */
  PetscInt *corners, ncorners; /* per cell corner: cell, its vertex's and its dim edge neighbours' coordinate offsets */
  PetscReal corner_ratio;      /* the smallest corner area (volume) / its reference one, present mesh */
  PetscReal worst_corner_ratio, worst_corner_time; /* the smallest over the meshes steps ended on, and its time */
  PetscBool corner_ratio_of_step;                  /* corner_ratio is of a mesh a step of this run moved to */
  DM        dm_all;      /* the same fields and volume terms without constraints, on the old domain during a step */
  Vec       history_all; /* the history on all rows of dm_all (global) */
  Vec       all_local;
};

/* Copies vertex values between the coordinate layout and a Q1 field's local layout. */
static PetscErrorCode CopyVertexValues(DM dm, Vec from, PetscBool from_coordinate_layout, DM dm_field, Vec to,
                                       PetscReal scale)
{
  PetscSection       cs, fs;
  PetscInt           vStart, vEnd, dim;
  const PetscScalar *a;
  PetscScalar       *b;

  PetscFunctionBeginUser;
  PetscCall(DMGetDimension(dm, &dim));
  PetscCall(DMPlexGetDepthStratum(dm, 0, &vStart, &vEnd));
  PetscCall(DMGetCoordinateSection(dm, &cs));
  PetscCall(DMGetLocalSection(dm_field, &fs));
  PetscCall(VecGetArrayRead(from, &a));
  PetscCall(VecGetArray(to, &b));
  for (PetscInt v = vStart; v < vEnd; ++v) {
    PetscInt coff, foff;
    PetscCall(PetscSectionGetOffset(cs, v, &coff));
    PetscCall(PetscSectionGetOffset(fs, v, &foff));
    for (PetscInt d = 0; d < dim; ++d) {
      if (from_coordinate_layout) b[foff + d] = scale * a[coff + d];
      else b[coff + d] = scale * a[foff + d];
    }
  }
  PetscCall(VecRestoreArray(to, &b));
  PetscCall(VecRestoreArrayRead(from, &a));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidALEGetAll(Fluid f, DM *dm_all, Vec *history_all)
{
  PetscFunctionBeginUser;
  if (dm_all) *dm_all = f->ale->dm_all;
  if (history_all) *history_all = f->ale->history_all;
  PetscFunctionReturn(0);
}

PetscErrorCode FluidALEFreeRows(Fluid f, Vec all, Vec out)
{
  FluidALE ale = f->ale;

  PetscFunctionBeginUser;
  PetscCall(DMGlobalToLocal(ale->dm_all, all, INSERT_VALUES, ale->all_local));
  PetscCall(VecZeroEntries(out));
  PetscCall(DMLocalToGlobal(f->dm, ale->all_local, INSERT_VALUES, out));
  PetscFunctionReturn(0);
}

/* The scene's closed-form motion d(X, t) at the reference vertices, with the scene's context. */
static PetscErrorCode PrescribedDisplacement(Fluid f, FieldFn motion, PetscReal t, Vec displacement)
{
  FluidALE           ale = f->ale;
  PetscInt           n, dim;
  const PetscScalar *X;
  PetscScalar       *d;

  PetscFunctionBeginUser;
  PetscCall(DMGetDimension(f->dm, &dim));
  PetscCall(VecGetLocalSize(ale->coordinates_reference, &n));
  PetscCall(VecGetArrayRead(ale->coordinates_reference, &X));
  PetscCall(VecGetArray(displacement, &d));
  for (PetscInt i = 0; i < n; i += dim) {
    PetscReal x[3];
    for (PetscInt k = 0; k < dim; ++k) x[k] = PetscRealPart(X[i + k]);
    PetscCall(motion(dim, t, x, dim, &d[i], f->data.ctx));
  }
  PetscCall(VecRestoreArray(displacement, &d));
  PetscCall(VecRestoreArrayRead(ale->coordinates_reference, &X));
  PetscFunctionReturn(0);
}

/* The mesh velocity's field and the copy of the DM without constraints on which the old
   domains' mass acts on every dof, boundary values included; then the fluid's SNES
   evaluates through its operators, which add that mass. The mesh starts where the scene's
   motion puts it at the fluid's time. */
PetscErrorCode FluidALECreate(Fluid f, FluidALE *ale_out)
{
  FluidALE    ale;
  PetscObject velocity;
  Vec         coordinates;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&ale));
  *ale_out                = ale;
  ale->corner_ratio       = PETSC_MAX_REAL;
  ale->worst_corner_ratio = PETSC_MAX_REAL;
  PetscCall(DMGetField(f->dm, 0, NULL, &velocity));
  /* the mesh velocity: vertex values, as the (affine) coordinates */
  PetscCall(DMClone(f->dm, &ale->dm_aux));
  PetscCall(FEMCreateField(ale->dm_aux, 0, "mesh_velocity", -1, 1, (PetscFE)velocity));
  PetscCall(DMCreateDS(ale->dm_aux));
  PetscCall(DMCreateLocalVector(ale->dm_aux, &ale->z_local));
  PetscCall(VecZeroEntries(ale->z_local));
  PetscCall(DMSetAuxiliaryVec(f->dm, NULL, 0, 0, ale->z_local));
  PetscCall(DMGetCoordinatesLocalSetUp(f->dm));
  PetscCall(DMGetCoordinatesLocal(f->dm, &coordinates));
  PetscCall(VecDuplicate(coordinates, &ale->coordinates_reference));
  PetscCall(VecCopy(coordinates, ale->coordinates_reference));
  PetscCall(VecDuplicate(coordinates, &ale->displacement));
  PetscCall(VecDuplicate(coordinates, &ale->displacement_old));
  PetscCall(VecZeroEntries(ale->displacement));
  PetscCall(VecZeroEntries(ale->displacement_old));
  /* elements of its own: PETSc 3.18 caches cell geometry by quadrature on the cell IS that
     clones share, and this copy lives on the previous domain */
  PetscCall(DMClone(f->dm, &ale->dm_all));
  PetscCall(FluidSetVolumeWeakForm(f, ale->dm_all, NULL));
  PetscCall(DMSetAuxiliaryVec(ale->dm_all, NULL, 0, 0, ale->z_local)); /* for the body force's convection */
  PetscCall(DMCreateGlobalVector(ale->dm_all, &ale->history_all));
  PetscCall(DMCreateLocalVector(ale->dm_all, &ale->all_local));
  PetscCall(FluidSNESUseOperator(f));
  if (f->time_order == 2) {
    PetscCall(VecDuplicate(coordinates, &ale->displacement_previous));
    PetscCall(VecZeroEntries(ale->displacement_previous));
  }
  if (f->data.mesh_displacement) {
    /* the domain of t0, on which the initial state lives (else the first step's mesh
       velocity carries the whole of d(t0)) */
    PetscCall(PrescribedDisplacement(f, f->data.mesh_displacement, f->time, ale->displacement_old));
    PetscCall(FluidSetMeshDisplacement(f, ale->displacement_old));
    PetscCheck(!StepFailed(&f->failure), f->comm, PETSC_ERR_ARG_OUTOFRANGE, "the scene's mesh motion at t0 = %g: %s",
               (double)f->time, f->failure.reason);
  }
  PetscFunctionReturn(0);
}

/* a cell corner that keeps less of its reference area (volume) fails the step */
#define SMALLEST_CORNER_RATIO 1e-3

/* the mesh a step of this run ended on into the run's worst (not the start of a restart) */
static PetscErrorCode FoldCornerRatio(Fluid f)
{
  FluidALE ale = f->ale;

  PetscFunctionBeginUser;
  if (ale->corner_ratio_of_step && ale->corner_ratio >= SMALLEST_CORNER_RATIO &&
      ale->corner_ratio < ale->worst_corner_ratio) {
    ale->worst_corner_ratio = ale->corner_ratio;
    ale->worst_corner_time  = f->time;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FluidGetMeshQuality(Fluid f, PetscReal *worst_ratio, PetscReal *time)
{
  PetscFunctionBeginUser;
  *worst_ratio = -1;
  *time        = -1;
  if (!f->ale) PetscFunctionReturn(0); /* fixed */
  PetscCall(FoldCornerRatio(f));
  if (f->ale->worst_corner_ratio == PETSC_MAX_REAL) PetscFunctionReturn(0); /* no step */
  *worst_ratio = f->ale->worst_corner_ratio;
  *time        = f->ale->worst_corner_time;
  PetscFunctionReturn(0);
}

/* Before the time and the mesh move on: the old-domain mass of the fluid's operators (the
   solver's and the check's), the history term (rho/dt M(Omega^{n-1}) u^{n-1}, or BDF2's
   2 rho/dt M(Omega^{n-1}) u^{n-1} - 1/2 rho/dt M(Omega^{n-2}) u^{n-2}) by the solver's, and
   the displacements the mesh velocity needs. The displacements are kept, not the mass: a
   checkpoint restores them. */
PetscErrorCode FluidALEBeginStep(Fluid f)
{
  FluidALE        ale  = f->ale;
  const PetscBool bdf2 = FluidStepIsBDF2(f);
  Vec             coordinates;
  const PetscReal coefficient = f->rho / f->dt, old_coefficient = bdf2 ? 2.0 * coefficient : coefficient;
  const PetscReal older_coefficient = 0.5 * coefficient; /* BDF2: of M(Omega^{n-2}), subtracted */

  PetscFunctionBeginUser;
  PetscCall(FoldCornerRatio(f));
  ale->corner_ratio_of_step = PETSC_TRUE; /* the step moves the mesh */
  PetscCall(DMGetCoordinatesLocal(f->dm, &coordinates));
  if (bdf2) {
    Vec older;
    PetscCall(VecDuplicate(coordinates, &older));
    PetscCall(VecWAXPY(older, 1.0, ale->coordinates_reference, ale->displacement_old));
    PetscCall(DMSetCoordinatesLocal(ale->dm_all, older));
    PetscCall(VecDestroy(&older));
    PetscCall(FEMInvalidateGeometry(ale->dm_all));
    PetscCall(FluidOperatorOldDomain(f->op, 1, older_coefficient));
    PetscCall(FluidOperatorOldDomain(f->check, 1, older_coefficient));
  }
  PetscCall(DMSetCoordinatesLocal(ale->dm_all, coordinates));
  PetscCall(FEMInvalidateGeometry(ale->dm_all));
  PetscCall(FluidOperatorOldDomain(f->op, 0, old_coefficient));
  PetscCall(FluidOperatorOldDomain(f->check, 0, old_coefficient));
  PetscCall(FluidOperatorOldMassStep(f->op, bdf2, f->xlocal_old, f->xlocal_previous, ale->history_all));
  PetscCall(FluidOperatorOldMassStep(f->check, bdf2, f->xlocal_old, f->xlocal_previous, NULL));
  PetscCall(FluidALEFreeRows(f, ale->history_all, f->history));
  if (bdf2) PetscCall(VecCopy(ale->displacement_old, ale->displacement_previous));
  if (f->time_order == 2) PetscCall(VecCopy(f->xlocal_old, f->xlocal_previous));
  PetscCall(VecCopy(ale->displacement, ale->displacement_old));
  PetscCall(VecZeroEntries(ale->z_local));
  PetscFunctionReturn(0);
}

/* The corners of the cells: each vertex with the dim vertices it shares an edge with in
   its cell, as offsets into the local coordinates (quadrilaterals, triangles, hexahedra,
   tetrahedra: a vertex with another number of edge neighbours, a pyramid's apex, is left
   out). Found once; the mesh's topology never changes. */
static PetscErrorCode CellCornersSetUp(Fluid f)
{
  FluidALE     ale = f->ale;
  PetscSection section;
  PetscInt     cStart, cEnd, vStart, vEnd, eStart, eEnd, dim, n = 0;

  PetscFunctionBeginUser;
  PetscCall(DMGetDimension(f->dm, &dim));
  PetscCall(DMGetCoordinateSection(f->dm, &section));
  PetscCall(DMPlexGetHeightStratum(f->dm, 0, &cStart, &cEnd));
  PetscCall(DMPlexGetDepthStratum(f->dm, 0, &vStart, &vEnd));
  PetscCall(DMPlexGetDepthStratum(f->dm, 1, &eStart, &eEnd));
  PetscCall(PetscMalloc1((cEnd - cStart) * 8 * 5, &ale->corners)); /* at most 8 corners a cell */
  for (PetscInt c = cStart; c < cEnd; ++c) {
    PetscInt *closure = NULL, nclosure, verts[8], edges[12][2], nv = 0, ne = 0;

    PetscCall(DMPlexGetTransitiveClosure(f->dm, c, PETSC_TRUE, &nclosure, &closure));
    for (PetscInt i = 0; i < nclosure; ++i) {
      const PetscInt p = closure[2 * i];
      if (p >= vStart && p < vEnd && nv < 8) verts[nv++] = p;
      if (p >= eStart && p < eEnd && ne < 12) {
        const PetscInt *cone;
        PetscCall(DMPlexGetCone(f->dm, p, &cone));
        edges[ne][0] = cone[0];
        edges[ne][1] = cone[1];
        ++ne;
      }
    }
    PetscCall(DMPlexRestoreTransitiveClosure(f->dm, c, PETSC_TRUE, &nclosure, &closure));
    for (PetscInt i = 0; i < nv; ++i) {
      PetscInt *corner = &ale->corners[n * 5], k = 0;
      corner[0] = c;
      PetscCall(PetscSectionGetOffset(section, verts[i], &corner[1]));
      for (PetscInt e = 0; e < ne; ++e) {
        const PetscInt other = edges[e][0] == verts[i] ? edges[e][1] : edges[e][1] == verts[i] ? edges[e][0] : -1;
        if (other >= 0 && k < dim) PetscCall(PetscSectionGetOffset(section, other, &corner[2 + k]));
        if (other >= 0) ++k;
      }
      if (k == dim) ++n;
    }
  }
  ale->ncorners = n;
  PetscFunctionReturn(0);
}

/* the signed area (2D) or volume (3D) spanned by a corner's edges */
static PetscReal CornerVolume(PetscInt dim, const PetscScalar *x, const PetscInt corner[])
{
  PetscReal e[3][3] = {{0}};

  for (PetscInt k = 0; k < dim; ++k)
    for (PetscInt d = 0; d < dim; ++d) e[k][d] = PetscRealPart(x[corner[2 + k] + d] - x[corner[1] + d]);
  if (dim == 2) return e[0][0] * e[1][1] - e[0][1] * e[1][0];
  return e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) - e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
         e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
}

/* Every corner of every cell must keep its orientation and at least 1e-3 of its reference
   area (volume): otherwise the step fails, naming the cell, and the mesh stays as it was. */
static PetscErrorCode CheckCells(Fluid f, Vec coordinates)
{
  FluidALE           ale = f->ale;
  PetscInt           dim, bad = -1;
  PetscReal          worst = PETSC_MAX_REAL, where[4] = {-1, 0, 0, 0};
  const PetscScalar *X, *x;

  PetscFunctionBeginUser;
  PetscCall(DMGetDimension(f->dm, &dim));
  if (!ale->corners) PetscCall(CellCornersSetUp(f));
  PetscCall(VecGetArrayRead(ale->coordinates_reference, &X));
  PetscCall(VecGetArrayRead(coordinates, &x));
  for (PetscInt i = 0; i < ale->ncorners; ++i) {
    const PetscInt *corner = &ale->corners[i * 5];
    const PetscReal ratio  = CornerVolume(dim, x, corner) / CornerVolume(dim, X, corner);
    if (ratio < worst) {
      worst = ratio;
      if (worst < SMALLEST_CORNER_RATIO) bad = i;
    }
  }
  if (bad >= 0) {
    where[0] = (PetscReal)ale->corners[bad * 5];
    for (PetscInt d = 0; d < dim; ++d) where[1 + d] = PetscRealPart(x[ale->corners[bad * 5 + 1] + d]);
  }
  PetscCall(VecRestoreArrayRead(coordinates, &x));
  PetscCall(VecRestoreArrayRead(ale->coordinates_reference, &X));
  PetscCallMPI(MPI_Allreduce(&worst, &ale->corner_ratio, 1, MPIU_REAL, MPIU_MIN, f->comm));
  {
    PetscMPIInt rank, first, size, mine;
    PetscCallMPI(MPI_Comm_rank(f->comm, &rank));
    PetscCallMPI(MPI_Comm_size(f->comm, &size));
    mine = bad >= 0 ? rank : size;
    PetscCallMPI(MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, f->comm));
    if (first == size) PetscFunctionReturn(0);
    PetscCallMPI(MPI_Bcast(where, 4, MPIU_REAL, first, f->comm));
    PetscCall(StepFailureSet(&f->failure,
                             "fluid mesh inverted or degenerate at step %" PetscInt_FMT
                             " (t = %g): cell %d, corner at (%g, %g, %g), keeps less than 1e-3 of its reference %s: "
                             "the displacement is too large for this mesh (-mesh_motion biharmonic, a larger "
                             "-mesh_motion_stiffening or a finer mesh may help)",
                             f->step, (double)f->time, (int)where[0], (double)where[1], (double)where[2],
                             (double)where[3], dim == 2 ? "area" : "volume"));
    PetscFunctionReturn(0);
  }
}

PetscErrorCode FluidSetMeshDisplacement(Fluid f, Vec displacement)
{
  FluidALE ale = f->ale;
  Vec      coordinates, z_coordinate_layout;

  PetscFunctionBeginUser;
  PetscCheck(ale, f->comm, PETSC_ERR_ORDER,
             "fluid: the mesh of this fluid does not move (FluidEnableMeshMotion before FluidSetUp)");
  PetscCall(VecDuplicate(ale->coordinates_reference, &coordinates));
  PetscCall(VecWAXPY(coordinates, 1.0, ale->coordinates_reference, displacement));
  PetscCall(CheckCells(f, coordinates));
  if (StepFailed(&f->failure)) {
    PetscCall(VecDestroy(&coordinates));
    PetscFunctionReturn(0);
  }
  PetscCall(VecCopy(displacement, ale->displacement));
  PetscCall(DMSetCoordinatesLocal(f->dm, coordinates));
  PetscCall(FEMInvalidateGeometry(f->dm));
  PetscCall(VecDestroy(&coordinates));
  PetscCall(VecDuplicate(displacement, &z_coordinate_layout));
  PetscCall(VecWAXPY(z_coordinate_layout, -1.0, ale->displacement_old, displacement));
  if (FluidStepIsBDF2(f)) { /* 3/2 (d^n - d^{n-1}) - 1/2 (d^{n-1} - d^{n-2}) */
    PetscCall(VecScale(z_coordinate_layout, 1.5));
    PetscCall(VecAXPBYPCZ(z_coordinate_layout, -0.5, 0.5, 1.0, ale->displacement_old, ale->displacement_previous));
  }
  PetscCall(CopyVertexValues(f->dm, z_coordinate_layout, PETSC_TRUE, ale->dm_aux, ale->z_local, 1.0 / f->dt));
  PetscCall(VecDestroy(&z_coordinate_layout));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidGetMeshDisplacement(Fluid f, Vec *displacement)
{
  PetscFunctionBeginUser;
  *displacement = f->ale ? f->ale->displacement : NULL;
  PetscFunctionReturn(0);
}

PetscErrorCode FluidGetMeshVelocity(Fluid f, DM *dm, Vec *local)
{
  PetscFunctionBeginUser;
  *dm    = f->ale ? f->ale->dm_aux : NULL;
  *local = f->ale ? f->ale->z_local : NULL;
  PetscFunctionReturn(0);
}

PetscErrorCode FluidALEFollowScene(Fluid f)
{
  Vec d;

  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(f->ale->displacement, &d));
  PetscCall(PrescribedDisplacement(f, f->data.mesh_displacement, f->time, d));
  PetscCall(FluidSetMeshDisplacement(f, d));
  PetscCall(VecDestroy(&d));
  PetscFunctionReturn(0);
}

/* The displacements of the present mesh and, BDF2, of the one before it (the mesh velocity
   is not needed: the next step sets its own); loaded, the mesh moves there */
PetscErrorCode FluidALECheckpoint(Fluid f, Checkpoint cp, PetscBool load, PetscBool bdf2_state)
{
  FluidALE ale = f->ale;
  DM       cdm;

  PetscFunctionBeginUser;
  PetscCall(DMGetCoordinateDM(f->dm, &cdm));
  PetscCall(CheckpointLocalVec(cp, "mesh_displacement", cdm, ale->displacement, load));
  if (bdf2_state) PetscCall(CheckpointLocalVec(cp, "mesh_displacement_before", cdm, ale->displacement_old, load));
  if (load) {
    if (!bdf2_state) PetscCall(VecCopy(ale->displacement, ale->displacement_old));
    PetscCall(FluidSetMeshDisplacement(f, ale->displacement));
    ale->corner_ratio_of_step = PETSC_FALSE; /* a restart's start, or a retried step's, counted already */
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FluidALEDestroy(FluidALE *ale_out)
{
  FluidALE ale = *ale_out;

  PetscFunctionBeginUser;
  if (!ale) PetscFunctionReturn(0);
  PetscCall(VecDestroy(&ale->z_local));
  PetscCall(VecDestroy(&ale->coordinates_reference));
  PetscCall(PetscFree(ale->corners));
  PetscCall(VecDestroy(&ale->displacement));
  PetscCall(VecDestroy(&ale->displacement_old));
  PetscCall(VecDestroy(&ale->displacement_previous));
  PetscCall(VecDestroy(&ale->history_all));
  PetscCall(VecDestroy(&ale->all_local));
  PetscCall(DMDestroy(&ale->dm_all));
  PetscCall(DMDestroy(&ale->dm_aux));
  PetscCall(PetscFree(*ale_out));
  PetscFunctionReturn(0);
}
