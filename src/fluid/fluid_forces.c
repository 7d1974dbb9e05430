/* The force of the fluid on a body (drag and lift), in the volume-weighted form: with w
   the field equal to e_c at the body's velocity nodes and 0 at the others,
     F_c = -R_volume(u^n, p^n; w) = - int_Omega rho (u_t + ((u - z).grad) u) . w + sigma : grad w,
   which equals the boundary integral of sigma n over the body (n out of the body) for the
   exact solution, and converges faster than the boundary integral of the discrete
   pressure and velocity gradient traces (it is the flux the discrete equations balance).
   w vanishes outside the cells that touch the body, so on a fixed mesh R_volume is
   evaluated there only: on dm_force, a copy of the fluid's DM whose fields live on those
   cells and carry no boundary conditions (the body's rows are constrained in the fluid's
   own DM). On a moving mesh it is evaluated on every cell of dm_all, the ALE's copy without
   constraints, by the fluid's operator: PETSc 3.18 caches a region's cell geometry on an
   index set we cannot reach to invalidate when the mesh moves. */
#include "fluid_impl.h"
#include "fem.h"

struct _n_FluidForces {
  DM       dm_force;                  /* fixed meshes: the fields on the cells that touch the body */
  Vec      force_x, force_residual;   /* its local vectors */
  PetscInt n_force_copy, *force_copy; /* per point: its offset in dm_force, in dm, its dofs */
  PetscInt n_force_rows, *force_rows; /* the body's velocity nodes (first component): in dm_force's local
                                         array; on a moving mesh the owned ones in dm_all's global array */
  Vec      all;                       /* moving meshes: the volume residual on dm_all's global rows */
};

PetscErrorCode FluidBodyFaces(Fluid f, IS *faces)
{
  PetscFunctionBeginUser;
  PetscCall(FluidFaceSetFaces(f, f->data.n_force_faces, f->data.force_faces, faces));
  PetscFunctionReturn(0);
}

/* The points in the closure of the body's faces, sorted, each once. */
static PetscErrorCode BodyPoints(Fluid f, PetscInt *n, PetscInt **points)
{
  IS              faces;
  const PetscInt *face;
  PetscInt        nfaces, count = 0, *list = NULL;

  PetscFunctionBeginUser;
  PetscCall(FluidBodyFaces(f, &faces));
  PetscCall(ISGetLocalSize(faces, &nfaces));
  PetscCall(ISGetIndices(faces, &face));
  for (PetscInt pass = 0; pass < 2; ++pass) {
    count = 0;
    for (PetscInt i = 0; i < nfaces; ++i) {
      PetscInt *closure = NULL, nclosure;
      PetscCall(DMPlexGetTransitiveClosure(f->dm, face[i], PETSC_TRUE, &nclosure, &closure));
      for (PetscInt k = 0; k < nclosure; ++k, ++count)
        if (pass) list[count] = closure[2 * k];
      PetscCall(DMPlexRestoreTransitiveClosure(f->dm, face[i], PETSC_TRUE, &nclosure, &closure));
    }
    if (!pass) PetscCall(PetscMalloc1(count, &list));
  }
  PetscCall(ISRestoreIndices(faces, &face));
  PetscCall(ISDestroy(&faces));
  PetscCall(PetscSortRemoveDupsInt(&count, list));
  *n      = count;
  *points = list;
  PetscFunctionReturn(0);
}

/* The first component of every velocity node of the body points: offset(p) + node * dim,
   with offset(p) the point's offset in `offsets` less `shift` (velocity comes first among a
   point's dofs); points with a negative offset (owned by another rank) are left out. */
static PetscErrorCode VelocityRows(PetscInt nbody, const PetscInt body[], PetscInt dim, PetscSection dofs,
                                   PetscSection offsets, PetscInt shift, PetscInt *n, PetscInt **rows)
{
  PetscFunctionBeginUser;
  for (PetscInt pass = 0; pass < 2; ++pass) {
    *n = 0;
    for (PetscInt i = 0; i < nbody; ++i) {
      PetscInt ndof, off;
      PetscCall(PetscSectionGetOffset(offsets, body[i], &off));
      if (off < 0) continue;
      PetscCall(PetscSectionGetFieldDof(dofs, body[i], 0, &ndof));
      for (PetscInt node = 0; node < ndof / dim; ++node, ++*n)
        if (pass) (*rows)[*n] = off - shift + node * dim;
    }
    if (!pass) PetscCall(PetscMalloc1(*n, rows));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FluidForcesCreate(Fluid f, FluidForces *forces)
{
  FluidForces  fo;
  DMLabel      band;
  PetscSection local, local_force;
  PetscInt     dim, nbody = 0, *body = NULL, cStart, cEnd, pStart, pEnd;

  PetscFunctionBeginUser;
  *forces = NULL;
  if (!f->data.n_force_faces) PetscFunctionReturn(0);
  PetscCall(PetscNew(&fo));
  *forces = fo;
  PetscCall(DMGetDimension(f->dm, &dim));
  PetscCall(BodyPoints(f, &nbody, &body));
  if (f->moving) {
    PetscSection global_all;
    PetscInt     rstart;
    DM           dm_all;

    /* the owned body nodes in dm_all's global array */
    PetscCall(FluidALEGetAll(f, &dm_all, NULL));
    PetscCall(DMCreateGlobalVector(dm_all, &fo->all));
    PetscCall(DMGetGlobalSection(dm_all, &global_all));
    PetscCall(DMGetLocalSection(dm_all, &local));
    PetscCall(VecGetOwnershipRange(fo->all, &rstart, NULL));
    PetscCall(VelocityRows(nbody, body, dim, local, global_all, rstart, &fo->n_force_rows, &fo->force_rows));
    PetscCall(PetscFree(body));
    PetscFunctionReturn(0);
  }
  /* the band: every cell with a body point in its closure */
  PetscCall(DMClone(f->dm, &fo->dm_force));
  PetscCall(DMCreateLabel(fo->dm_force, "force_band"));
  PetscCall(DMGetLabel(fo->dm_force, "force_band", &band));
  PetscCall(DMPlexGetHeightStratum(f->dm, 0, &cStart, &cEnd));
  for (PetscInt i = 0; i < nbody; ++i) {
    PetscInt *star = NULL, nstar;
    PetscCall(DMPlexGetTransitiveClosure(f->dm, body[i], PETSC_FALSE, &nstar, &star));
    for (PetscInt k = 0; k < nstar; ++k)
      if (star[2 * k] >= cStart && star[2 * k] < cEnd) PetscCall(DMLabelSetValue(band, star[2 * k], 1));
    PetscCall(DMPlexRestoreTransitiveClosure(f->dm, body[i], PETSC_FALSE, &nstar, &star));
  }
  /* fields on a label live on its points: the cells' closures too */
  PetscCall(DMPlexLabelComplete(fo->dm_force, band));
  PetscCall(FluidSetVolumeWeakForm(f, fo->dm_force, band));
  PetscCall(DMCreateLocalVector(fo->dm_force, &fo->force_x));
  PetscCall(VecDuplicate(fo->force_x, &fo->force_residual));
  /* the band's dofs in the fluid's local layout: per point the same dofs in the same order */
  PetscCall(DMGetLocalSection(f->dm, &local));
  PetscCall(DMGetLocalSection(fo->dm_force, &local_force));
  PetscCall(PetscSectionGetChart(local_force, &pStart, &pEnd));
  PetscCall(PetscMalloc1(3 * (pEnd - pStart), &fo->force_copy));
  for (PetscInt p = pStart; p < pEnd; ++p) {
    PetscInt ndof, off_force, off, ndof_fluid;
    PetscCall(PetscSectionGetDof(local_force, p, &ndof));
    if (!ndof) continue;
    PetscCall(PetscSectionGetOffset(local_force, p, &off_force));
    PetscCall(PetscSectionGetOffset(local, p, &off));
    PetscCall(PetscSectionGetDof(local, p, &ndof_fluid));
    PetscCheck(ndof == ndof_fluid, f->comm, PETSC_ERR_PLIB,
               "fluid forces: point %" PetscInt_FMT " has %" PetscInt_FMT " dofs in the band, %" PetscInt_FMT
               " in the fluid",
               p, ndof, ndof_fluid);
    fo->force_copy[3 * fo->n_force_copy]     = off_force;
    fo->force_copy[3 * fo->n_force_copy + 1] = off;
    fo->force_copy[3 * fo->n_force_copy + 2] = ndof;
    fo->n_force_copy++;
  }
  /* the body's velocity nodes: every local copy in the band (each rank adds its own cells'
     contributions) */
  PetscCall(VelocityRows(nbody, body, dim, local_force, local_force, 0, &fo->n_force_rows, &fo->force_rows));
  PetscCall(PetscFree(body));
  PetscFunctionReturn(0);
}

/* The constants of dm (dm_force's band, or dm_all): the fluid's, with mass, op and load set
   as asked (< 0: unchanged). */
static PetscErrorCode SetConstants(Fluid f, DM dm, PetscReal mass, PetscReal op, PetscReal load)
{
  PetscDS            ds, ds_force;
  DMLabel            band;
  const PetscScalar *constants;
  PetscScalar        copy[FLUID_MAX_CONSTANTS];
  PetscInt           n;

  PetscFunctionBeginUser;
  PetscCall(DMGetDS(f->dm, &ds));
  PetscCall(DMGetLabel(dm, "force_band", &band));
  if (band) PetscCall(DMGetRegionDS(dm, band, NULL, &ds_force));
  else PetscCall(DMGetDS(dm, &ds_force));
  PetscCall(PetscDSGetConstants(ds, &n, &constants));
  PetscCall(PetscArraycpy(copy, constants, n));
  if (mass >= 0) copy[FLUID_MASS] = mass;
  if (op >= 0) copy[FLUID_OPERATOR] = op;
  if (load >= 0) copy[FLUID_LOAD] = load;
  PetscCall(PetscDSSetConstants(ds_force, n, copy));
  PetscFunctionReturn(0);
}

/* The band's residual at the fluid's local state xlocal, summed over the body's rows. */
static PetscErrorCode BandSum(Fluid f, Vec xlocal, PetscReal sum[3])
{
  FluidForces        fo = f->forces;
  const PetscScalar *x, *r;
  PetscScalar       *xb;
  PetscInt           dim;

  PetscFunctionBeginUser;
  PetscCall(DMGetDimension(f->dm, &dim));
  PetscCall(VecGetArrayRead(xlocal, &x));
  PetscCall(VecGetArray(fo->force_x, &xb));
  for (PetscInt i = 0; i < fo->n_force_copy; ++i)
    PetscCall(PetscArraycpy(&xb[fo->force_copy[3 * i]], &x[fo->force_copy[3 * i + 1]], fo->force_copy[3 * i + 2]));
  PetscCall(VecRestoreArray(fo->force_x, &xb));
  PetscCall(VecRestoreArrayRead(xlocal, &x));
  PetscCall(VecZeroEntries(fo->force_residual));
  {
    /* PETSc integrates the band on the ranks with band cells only and would create the
       coordinate field there alone (-check_rank_sync; FEMFacesMakeSharedObjects) */
    DMField coordinates;
    PetscCall(DMGetCoordinateField(fo->dm_force, &coordinates));
  }
  PetscCall(DMPlexSNESComputeResidualFEM(fo->dm_force, fo->force_x, fo->force_residual, NULL));
  PetscCall(VecGetArrayRead(fo->force_residual, &r));
  for (PetscInt i = 0; i < fo->n_force_rows; ++i)
    for (PetscInt c = 0; c < dim; ++c) sum[c] += PetscRealPart(r[fo->force_rows[i] + c]);
  PetscCall(VecRestoreArrayRead(fo->force_residual, &r));
  PetscFunctionReturn(0);
}

/* On a moving mesh: every cell's volume residual plus the time derivative's part, the old
   domains' mass times u^n minus the history (rho/dt M(Omega^{n-1}) (u^n - u^{n-1}) for
   backward Euler; fluid_ale.c), summed over the owned body rows. */
static PetscErrorCode MovingSum(Fluid f, PetscReal sum[3])
{
  FluidForces        fo = f->forces;
  const PetscScalar *r;
  Vec                coordinates, history_all;
  PetscInt           dim;
  DM                 dm_all;

  PetscFunctionBeginUser;
  PetscCall(DMGetDimension(f->dm, &dim));
  PetscCall(FluidALEGetAll(f, &dm_all, &history_all));
  PetscCall(DMGetCoordinatesLocal(f->dm, &coordinates));
  PetscCall(DMSetCoordinatesLocal(dm_all, coordinates)); /* the next step puts back the old ones */
  PetscCall(FEMInvalidateGeometry(dm_all));
  PetscCall(FluidOperatorResidualAll(f->op, f->xlocal_work, f->step > 0, fo->all));
  if (f->step > 0) PetscCall(VecAXPY(fo->all, -1.0, history_all));
  PetscCall(VecGetArrayRead(fo->all, &r));
  for (PetscInt i = 0; i < fo->n_force_rows; ++i)
    for (PetscInt c = 0; c < dim; ++c) sum[c] += PetscRealPart(r[fo->force_rows[i] + c]);
  PetscCall(VecRestoreArrayRead(fo->all, &r));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidBodyForce(Fluid f, PetscReal force[3])
{
  PetscReal now[3] = {0, 0, 0}, before[3] = {0, 0, 0};
  DM        dm;

  PetscFunctionBeginUser;
  PetscCheck(f->data.n_force_faces, f->comm, PETSC_ERR_ARG_WRONGSTATE,
             "the scene names no body faces for a fluid force");
  if (f->moving) PetscCall(FluidALEGetAll(f, &dm, NULL));
  else dm = f->forces->dm_force;
  PetscCall(FluidGlobalToLocal(f, f->x, f->xlocal_work));
  /* the initial state has no time derivative to go with it: its force is the steady one */
  PetscCall(SetConstants(f, dm, f->step == 0 ? 0.0 : -1, -1, -1));
  if (f->moving) PetscCall(MovingSum(f, now));
  else {
    PetscCall(BandSum(f, f->xlocal_work, now));
    if (f->step > 0 && !f->steady) {
      /* minus the history term rho/dt (u^{n-1}, w) */
      PetscCall(SetConstants(f, dm, -1, 0.0, 0.0));
      PetscCall(BandSum(f, f->xlocal_old, before));
    }
  }
  for (PetscInt c = 0; c < 3; ++c) force[c] = -(now[c] - before[c]);
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, force, 3, MPIU_REAL, MPIU_SUM, f->comm));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidForcesDestroy(FluidForces *forces)
{
  FluidForces fo = *forces;

  PetscFunctionBeginUser;
  if (!fo) PetscFunctionReturn(0);
  PetscCall(PetscFree(fo->force_copy));
  PetscCall(PetscFree(fo->force_rows));
  PetscCall(VecDestroy(&fo->force_x));
  PetscCall(VecDestroy(&fo->force_residual));
  PetscCall(VecDestroy(&fo->all));
  PetscCall(DMDestroy(&fo->dm_force));
  PetscCall(PetscFree(*forces));
  PetscFunctionReturn(0);
}
