/* The fluid on a moving mesh (ALE). Vertices move with the mesh displacement d; the mesh
   velocity z = (d^n - d^{n-1})/dt enters the convection as an auxiliary field. The
   seed's conservative step
     rho/dt [(u^n, v)_{Omega^n} - (u^{n-1}, v)_{Omega^{n-1}}] - rho ((div z) u^n, v) + ...
   is used with the div z term integrated exactly over the step, rho/dt [M(Omega^n) -
   M(Omega^{n-1})] u^n (Reynolds transport for mesh-bound basis functions), which leaves
     rho/dt M(Omega^{n-1}) (u^n - u^{n-1}) + rho (((u^n - z) . grad) u^n, v)_{Omega^n} + ...
   and satisfies the discrete geometric conservation law: a uniform flow stays uniform on
   any mesh motion. M(Omega^{n-1}) is a matrix assembled once per step on a copy of the
   DM kept on the previous domain.
   BDF2 (-fluid_time_order 2) applies the same idea to d/dt (M u) - (dM/dt) u with both
   derivatives by the BDF2 formula:
     rho/(2 dt) [3 M^n u^n - 4 M^{n-1} u^{n-1} + M^{n-2} u^{n-2} - (3 M^n - 4 M^{n-1} + M^{n-2}) u^n]
       = rho/dt [(2 M^{n-1} - 1/2 M^{n-2}) u^n - 2 M^{n-1} u^{n-1} + 1/2 M^{n-2} u^{n-2}],
   again without M(Omega^n) and exact for a uniform flow, with z = (3 d^n - 4 d^{n-1} +
   d^{n-2})/(2 dt). */
#include "fluid_impl.h"
#include "fem.h"

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

/* coefficient M on dm_all's present coordinates, every dof, once per step (FluidALEBeginStep). Assembled here rather than through
   DMPlexSNESComputeJacobianFEM, whose generic element loop (every component pair of the
   vector basis, with the g1..g3 slots) costs as much as the full Navier-Stokes Jacobian:
   the mass needs only sum_q w_q |J_q| phi_i . phi_j on the velocity block. */
static PetscErrorCode AssembleMass(Fluid f, Mat target, PetscReal coefficient)
{
  PetscDS          ds;
  PetscFE          fe;
  PetscQuadrature  quad;
  PetscTabulation  T;
  const PetscReal *weights;
  PetscReal       *v, *J, *invJ, *detJ;
  PetscScalar     *element;
  PetscInt         dim, Nq, Nb, Nc, totDim, cStart, cEnd;

  PetscFunctionBeginUser;
  PetscCall(DMGetDimension(f->dm_all, &dim));
  PetscCall(DMGetDS(f->dm_all, &ds));
  PetscCall(PetscDSGetTotalDimension(ds, &totDim));
  PetscCall(PetscDSGetDiscretization(ds, 0, (PetscObject *)&fe));
  PetscCall(PetscFEGetQuadrature(fe, &quad));
  PetscCall(PetscQuadratureGetData(quad, NULL, NULL, &Nq, NULL, &weights));
  PetscCall(PetscFEGetDimension(fe, &Nb));
  PetscCall(PetscFEGetNumComponents(fe, &Nc));
  PetscCall(PetscFEGetCellTabulation(fe, 0, &T));
  PetscCall(
    PetscMalloc5(Nq * dim, &v, Nq * dim * dim, &J, Nq * dim * dim, &invJ, Nq, &detJ, totDim * totDim, &element));
  PetscCall(DMPlexGetHeightStratum(f->dm_all, 0, &cStart, &cEnd));
  PetscCall(MatZeroEntries(target));
  for (PetscInt cell = cStart; cell < cEnd; ++cell) {
    PetscCall(DMPlexComputeCellGeometryFEM(f->dm_all, cell, quad, v, J, invJ, detJ));
    PetscCall(PetscArrayzero(element, totDim * totDim));
    for (PetscInt q = 0; q < Nq; ++q) {
      const PetscReal *phi = &T->T[0][q * Nb * Nc];
      const PetscReal  wq  = coefficient * weights[q] * detJ[q];
      for (PetscInt i = 0; i < Nb; ++i)
        for (PetscInt j = 0; j < Nb; ++j) {
          PetscReal dot = 0;
          for (PetscInt c = 0; c < Nc; ++c) dot += phi[i * Nc + c] * phi[j * Nc + c];
          element[i * totDim + j] += wq * dot;
        }
    }
    PetscCall(DMPlexMatSetClosure(f->dm_all, NULL, NULL, target, cell, element, ADD_VALUES));
  }
  PetscCall(MatAssemblyBegin(target, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(target, MAT_FINAL_ASSEMBLY));
  PetscCall(PetscFree5(v, J, invJ, detJ, element));
  PetscFunctionReturn(0);
}

/* out = the free rows of a global vector of dm_all */
static PetscErrorCode FreeRows(Fluid f, Vec all, Vec out)
{
  PetscFunctionBeginUser;
  PetscCall(DMGlobalToLocal(f->dm_all, all, INSERT_VALUES, f->all_local));
  PetscCall(VecZeroEntries(out));
  PetscCall(DMLocalToGlobal(f->dm, f->all_local, INSERT_VALUES, out));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidOldMassMultAll(Fluid f, Vec xlocal, Vec yall, PetscBool add)
{
  PetscFunctionBeginUser;
  if (f->backend_ceed) {
    Vec ylocal;
    PetscCall(DMGetLocalVector(f->dm_all, &ylocal));
    PetscCall(FEMCeedFluidMassApply(f->ceed, xlocal, ylocal));
    if (!add) PetscCall(VecZeroEntries(yall));
    PetscCall(DMLocalToGlobal(f->dm_all, ylocal, ADD_VALUES, yall));
    PetscCall(DMRestoreLocalVector(f->dm_all, &ylocal));
    PetscFunctionReturn(0);
  }
  if (!f->mass_old_all) { /* before the backend is set up (an initial projection): no step, no mass */
    if (!add) PetscCall(VecZeroEntries(yall));
    PetscFunctionReturn(0);
  }
  PetscCall(DMLocalToGlobal(f->dm_all, xlocal, INSERT_VALUES, f->all_x));
  if (add) PetscCall(MatMultAdd(f->mass_old_all, f->all_x, yall, yall));
  else PetscCall(MatMult(f->mass_old_all, f->all_x, yall));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidOldMassMult(Fluid f, Vec xlocal, Vec out)
{
  PetscFunctionBeginUser;
  PetscCall(FluidOldMassMultAll(f, xlocal, f->all_y, PETSC_FALSE));
  PetscCall(FreeRows(f, f->all_y, out));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidALESetUp(Fluid f)
{
  PetscObject velocity;
  Vec         coordinates;
  FEMBackend  backend;
  PetscBool   check;

  PetscFunctionBeginUser;
  PetscCall(DMGetField(f->dm, 0, NULL, &velocity));
  /* the mesh velocity: vertex values, as the (affine) coordinates */
  PetscCall(DMClone(f->dm, &f->dm_aux));
  PetscCall(FEMCreateField(f->dm_aux, 0, "mesh_velocity", -1, 1, (PetscFE)velocity));
  PetscCall(DMCreateDS(f->dm_aux));
  PetscCall(DMCreateLocalVector(f->dm_aux, &f->z_local));
  PetscCall(VecZeroEntries(f->z_local));
  PetscCall(DMSetAuxiliaryVec(f->dm, NULL, 0, 0, f->z_local));
  PetscCall(DMGetCoordinatesLocalSetUp(f->dm));
  PetscCall(DMGetCoordinatesLocal(f->dm, &coordinates));
  PetscCall(VecDuplicate(coordinates, &f->coordinates_reference));
  PetscCall(VecCopy(coordinates, f->coordinates_reference));
  PetscCall(VecDuplicate(coordinates, &f->displacement));
  PetscCall(VecDuplicate(coordinates, &f->displacement_old));
  PetscCall(VecZeroEntries(f->displacement));
  PetscCall(VecZeroEntries(f->displacement_old));
  /* the old-domain mass on every dof, boundary values included, on a copy of the DM
     without constraints; elements of its own: PETSc 3.18 caches cell geometry by
     quadrature on the cell IS that clones share, and this copy lives on the previous domain */
  PetscCall(DMClone(f->dm, &f->dm_all));
  PetscCall(FluidSetVolumeWeakForm(f, f->dm_all, NULL));
  PetscCall(DMSetAuxiliaryVec(f->dm_all, NULL, 0, 0, f->z_local)); /* for the body force's convection */
  PetscCall(DMCreateGlobalVector(f->dm_all, &f->all_x));
  PetscCall(VecDuplicate(f->all_x, &f->all_y));
  PetscCall(DMCreateLocalVector(f->dm_all, &f->all_local));
  PetscCall(VecDuplicate(f->all_x, &f->history_all));
  PetscCall(DMCreateGlobalVector(f->dm, &f->work));
  PetscCall(SNESSetFunction(f->snes, NULL, FluidSNESResidual, f));
  PetscCall(SNESSetJacobian(f->snes, NULL, NULL, FluidSNESJacobian, f));
  if (f->time_order == 2) {
    PetscCall(VecDuplicate(coordinates, &f->displacement_previous));
    PetscCall(VecZeroEntries(f->displacement_previous));
  }
  /* the old domains' mass matrices of PETSc's backend (libCEED's keeps weights per point) */
  PetscCall(FEMBackendGet(&backend, &check));
  if (backend == FEM_BACKEND_CEED && !check) PetscFunctionReturn(0);
  PetscCall(DMCreateMatrix(f->dm_all, &f->mass_old_all));
  PetscCall(MatAssemblyBegin(f->mass_old_all, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(f->mass_old_all, MAT_FINAL_ASSEMBLY));
  if (f->time_order == 2) PetscCall(MatDuplicate(f->mass_old_all, MAT_DO_NOT_COPY_VALUES, &f->mass_older_all));
  PetscCall(FEMFreeDofs(f->dm, f->dm_all, &f->free_in_all));
  PetscCall(MatCreateSubMatrix(f->mass_old_all, f->free_in_all, f->free_in_all, MAT_INITIAL_MATRIX, &f->mass_old));
  PetscFunctionReturn(0);
}

/* a cell corner that keeps less of its reference area (volume) fails the step */
#define SMALLEST_CORNER_RATIO 1e-3

/* the mesh a step of this run ended on into the run's worst (not the start of a restart) */
static PetscErrorCode FoldCornerRatio(Fluid f)
{
  PetscFunctionBeginUser;
  if (f->corner_ratio_of_step && f->corner_ratio >= SMALLEST_CORNER_RATIO && f->corner_ratio < f->worst_corner_ratio) {
    f->worst_corner_ratio = f->corner_ratio;
    f->worst_corner_time  = f->time;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FluidGetMeshQuality(Fluid f, PetscReal *worst_ratio, PetscReal *time)
{
  PetscFunctionBeginUser;
  *worst_ratio = -1;
  *time        = -1;
  PetscCall(FoldCornerRatio(f));
  if (f->worst_corner_ratio == PETSC_MAX_REAL) PetscFunctionReturn(0); /* fixed, or no step */
  *worst_ratio = f->worst_corner_ratio;
  *time        = f->worst_corner_time;
  PetscFunctionReturn(0);
}

/* Before the time and the mesh move on: the old-domain mass, the history term (rho/dt
   M(Omega^{n-1}) u^{n-1}, or BDF2's 2 rho/dt M(Omega^{n-1}) u^{n-1} - 1/2 rho/dt
   M(Omega^{n-2}) u^{n-2}), and the displacements the mesh velocity needs. The
   displacements are kept, not the matrices: a checkpoint restores them. */
PetscErrorCode FluidALEBeginStep(Fluid f)
{
  const PetscBool bdf2 = FluidStepIsBDF2(f);
  Vec             coordinates;
  const PetscReal coefficient = f->rho / f->dt, old_coefficient = bdf2 ? 2.0 * coefficient : coefficient;
  const PetscReal older_coefficient = 0.5 * coefficient; /* BDF2: of M(Omega^{n-2}), subtracted */

  PetscFunctionBeginUser;
  PetscCall(FoldCornerRatio(f));
  f->corner_ratio_of_step = PETSC_TRUE; /* the step moves the mesh */
  PetscCall(DMGetCoordinatesLocal(f->dm, &coordinates));
  if (bdf2) {
    Vec older;
    PetscCall(VecDuplicate(coordinates, &older));
    PetscCall(VecWAXPY(older, 1.0, f->coordinates_reference, f->displacement_old));
    PetscCall(DMSetCoordinatesLocal(f->dm_all, older));
    PetscCall(VecDestroy(&older));
    PetscCall(FEMInvalidateGeometry(f->dm_all));
    if (f->mass_older_all) PetscCall(AssembleMass(f, f->mass_older_all, older_coefficient));
    if (f->ceed) PetscCall(FEMCeedFluidMassDomain(f->ceed, f->dm_all, 1));
  }
  PetscCall(DMSetCoordinatesLocal(f->dm_all, coordinates));
  PetscCall(FEMInvalidateGeometry(f->dm_all));
  if (f->mass_old_all) { /* PETSc's matrices (also kept beside libCEED's for -fem_backend_check) */
    PetscCall(AssembleMass(f, f->mass_old_all, old_coefficient));
    if (!f->backend_ceed) {
      PetscCall(DMLocalToGlobal(f->dm_all, f->xlocal_old, INSERT_VALUES, f->all_x));
      PetscCall(MatMult(f->mass_old_all, f->all_x, f->history_all));
      if (bdf2) {
        PetscCall(DMLocalToGlobal(f->dm_all, f->xlocal_previous, INSERT_VALUES, f->all_x));
        PetscCall(MatMult(f->mass_older_all, f->all_x, f->all_y));
        PetscCall(VecAXPY(f->history_all, -1.0, f->all_y));
      }
    }
    if (bdf2) PetscCall(MatAXPY(f->mass_old_all, -1.0, f->mass_older_all, SAME_NONZERO_PATTERN));
    PetscCall(MatCreateSubMatrix(f->mass_old_all, f->free_in_all, f->free_in_all, MAT_REUSE_MATRIX, &f->mass_old));
  }
  if (f->ceed) { /* libCEED's weights: the history's parts, then their sum for the step */
    PetscCall(FEMCeedFluidMassDomain(f->ceed, f->dm_all, 0));
    if (f->backend_ceed) {
      PetscCall(FEMCeedFluidMassWeights(f->ceed, old_coefficient, 0.0));
      PetscCall(FluidOldMassMultAll(f, f->xlocal_old, f->history_all, PETSC_FALSE));
      if (bdf2) {
        PetscCall(FEMCeedFluidMassWeights(f->ceed, 0.0, -older_coefficient));
        PetscCall(FluidOldMassMultAll(f, f->xlocal_previous, f->history_all, PETSC_TRUE));
      }
    }
    PetscCall(FEMCeedFluidMassWeights(f->ceed, old_coefficient, bdf2 ? -older_coefficient : 0.0));
  }
  PetscCall(FreeRows(f, f->history_all, f->history));
  if (bdf2) PetscCall(VecCopy(f->displacement_old, f->displacement_previous));
  if (f->time_order == 2) PetscCall(VecCopy(f->xlocal_old, f->xlocal_previous));
  PetscCall(VecCopy(f->displacement, f->displacement_old));
  PetscCall(VecZeroEntries(f->z_local));
  PetscFunctionReturn(0);
}

/* The corners of the cells: each vertex with the dim vertices it shares an edge with in
   its cell, as offsets into the local coordinates (quadrilaterals, triangles, hexahedra,
   tetrahedra: a vertex with another number of edge neighbours, a pyramid's apex, is left
   out). Found once; the mesh's topology never changes. */
static PetscErrorCode CellCornersSetUp(Fluid f)
{
  PetscSection section;
  PetscInt     cStart, cEnd, vStart, vEnd, eStart, eEnd, dim, n = 0;

  PetscFunctionBeginUser;
  PetscCall(DMGetDimension(f->dm, &dim));
  PetscCall(DMGetCoordinateSection(f->dm, &section));
  PetscCall(DMPlexGetHeightStratum(f->dm, 0, &cStart, &cEnd));
  PetscCall(DMPlexGetDepthStratum(f->dm, 0, &vStart, &vEnd));
  PetscCall(DMPlexGetDepthStratum(f->dm, 1, &eStart, &eEnd));
  PetscCall(PetscMalloc1((cEnd - cStart) * 8 * 5, &f->corners)); /* at most 8 corners a cell */
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
      PetscInt *corner = &f->corners[n * 5], k = 0;
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
  f->ncorners = n;
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
  PetscInt           dim, bad = -1;
  PetscReal          worst = PETSC_MAX_REAL, where[4] = {-1, 0, 0, 0};
  const PetscScalar *X, *x;

  PetscFunctionBeginUser;
  PetscCall(DMGetDimension(f->dm, &dim));
  if (!f->corners) PetscCall(CellCornersSetUp(f));
  PetscCall(VecGetArrayRead(f->coordinates_reference, &X));
  PetscCall(VecGetArrayRead(coordinates, &x));
  for (PetscInt i = 0; i < f->ncorners; ++i) {
    const PetscInt *corner = &f->corners[i * 5];
    const PetscReal ratio  = CornerVolume(dim, x, corner) / CornerVolume(dim, X, corner);
    if (ratio < worst) {
      worst = ratio;
      if (worst < SMALLEST_CORNER_RATIO) bad = i;
    }
  }
  if (bad >= 0) {
    where[0] = (PetscReal)f->corners[bad * 5];
    for (PetscInt d = 0; d < dim; ++d) where[1 + d] = PetscRealPart(x[f->corners[bad * 5 + 1] + d]);
  }
  PetscCall(VecRestoreArrayRead(coordinates, &x));
  PetscCall(VecRestoreArrayRead(f->coordinates_reference, &X));
  PetscCallMPI(MPI_Allreduce(&worst, &f->corner_ratio, 1, MPIU_REAL, MPIU_MIN, f->comm));
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
  Vec coordinates, z_coordinate_layout;

  PetscFunctionBeginUser;
  PetscCheck(f->moving, f->comm, PETSC_ERR_ORDER,
             "fluid: the mesh of this fluid does not move (FluidEnableMeshMotion before FluidSetUp)");
  PetscCall(VecDuplicate(f->coordinates_reference, &coordinates));
  PetscCall(VecWAXPY(coordinates, 1.0, f->coordinates_reference, displacement));
  PetscCall(CheckCells(f, coordinates));
  if (StepFailed(&f->failure)) {
    PetscCall(VecDestroy(&coordinates));
    PetscFunctionReturn(0);
  }
  PetscCall(VecCopy(displacement, f->displacement));
  PetscCall(DMSetCoordinatesLocal(f->dm, coordinates));
  PetscCall(FEMInvalidateGeometry(f->dm));
  PetscCall(VecDestroy(&coordinates));
  PetscCall(VecDuplicate(displacement, &z_coordinate_layout));
  PetscCall(VecWAXPY(z_coordinate_layout, -1.0, f->displacement_old, displacement));
  if (FluidStepIsBDF2(f)) { /* 3/2 (d^n - d^{n-1}) - 1/2 (d^{n-1} - d^{n-2}) */
    PetscCall(VecScale(z_coordinate_layout, 1.5));
    PetscCall(VecAXPBYPCZ(z_coordinate_layout, -0.5, 0.5, 1.0, f->displacement_old, f->displacement_previous));
  }
  PetscCall(CopyVertexValues(f->dm, z_coordinate_layout, PETSC_TRUE, f->dm_aux, f->z_local, 1.0 / f->dt));
  PetscCall(VecDestroy(&z_coordinate_layout));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidGetMeshDisplacement(Fluid f, Vec *displacement)
{
  PetscFunctionBeginUser;
  *displacement = f->displacement;
  PetscFunctionReturn(0);
}

PetscErrorCode FluidGetMeshVelocity(Fluid f, DM *dm, Vec *local)
{
  PetscFunctionBeginUser;
  *dm    = f->moving ? f->dm_aux : NULL;
  *local = f->moving ? f->z_local : NULL;
  PetscFunctionReturn(0);
}

/* The scene's closed-form motion d(X, t) at the reference vertices, with the scene's context. */
PetscErrorCode FluidPrescribedDisplacement(Fluid f, FieldFn motion, PetscReal t, Vec displacement)
{
  PetscInt           n, dim;
  const PetscScalar *X;
  PetscScalar       *d;

  PetscFunctionBeginUser;
  PetscCall(DMGetDimension(f->dm, &dim));
  PetscCall(VecGetLocalSize(f->coordinates_reference, &n));
  PetscCall(VecGetArrayRead(f->coordinates_reference, &X));
  PetscCall(VecGetArray(displacement, &d));
  for (PetscInt i = 0; i < n; i += dim) {
    PetscReal x[3];
    for (PetscInt k = 0; k < dim; ++k) x[k] = PetscRealPart(X[i + k]);
    PetscCall(motion(dim, t, x, dim, &d[i], f->data.ctx));
  }
  PetscCall(VecRestoreArray(displacement, &d));
  PetscCall(VecRestoreArrayRead(f->coordinates_reference, &X));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidALEDestroy(Fluid f)
{
  PetscFunctionBeginUser;
  PetscCall(VecDestroy(&f->z_local));
  PetscCall(VecDestroy(&f->coordinates_reference));
  PetscCall(PetscFree(f->corners));
  PetscCall(VecDestroy(&f->displacement));
  PetscCall(VecDestroy(&f->displacement_old));
  PetscCall(VecDestroy(&f->displacement_previous));
  PetscCall(MatDestroy(&f->mass_old));
  PetscCall(MatDestroy(&f->mass_older_all));
  PetscCall(VecDestroy(&f->history_all));
  PetscCall(ISDestroy(&f->free_in_all));
  PetscCall(MatDestroy(&f->mass_old_all));
  PetscCall(VecDestroy(&f->all_x));
  PetscCall(VecDestroy(&f->all_y));
  PetscCall(VecDestroy(&f->all_local));
  PetscCall(DMDestroy(&f->dm_all));
  PetscCall(VecDestroy(&f->work));
  PetscCall(DMDestroy(&f->dm_aux));
  PetscFunctionReturn(0);
}
