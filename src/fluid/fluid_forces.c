/* The force of the fluid on a body (drag and lift), in the volume-weighted form: with w
   the field equal to e_c at the body's velocity nodes and 0 at the others,
     F_c = -R_volume(u^n, p^n; w) = - int_Omega rho (u_t + ((u - z).grad) u) . w + sigma : grad w,
   which equals the boundary integral of sigma n over the body (n out of the body) for the
   exact solution, and converges faster than the boundary integral of the discrete
   pressure and velocity gradient traces (it is the flux the discrete equations balance). R_volume
   is the residual of the volume terms on every dof, constrained ones included: it is
   evaluated on dm_all, a copy of the fluid's DM without boundary conditions. */
#include "fluid_impl.h"
#include "fem.h"

PetscErrorCode FluidUnconstrainedSetUp(Fluid f)
{
  PetscFunctionBeginUser;
  if (f->dm_all) PetscFunctionReturn(0);
  PetscCall(DMClone(f->dm, &f->dm_all));
  /* elements of its own: PETSc 3.18 caches cell geometry by quadrature on the cell IS
     that clones share, and this copy may live on another domain than the fluid's DM */
  PetscCall(FluidSetVolumeWeakForm(f, f->dm_all));
  if (f->z_local) PetscCall(DMSetAuxiliaryVec(f->dm_all, NULL, 0, 0, f->z_local));
  PetscCall(DMCreateGlobalVector(f->dm_all, &f->all_x));
  PetscCall(VecDuplicate(f->all_x, &f->all_y));
  PetscCall(DMCreateLocalVector(f->dm_all, &f->all_local));
  PetscCall(DMCreateLocalVector(f->dm, &f->xlocal_work));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidForcesSetUp(Fluid f)
{
  DMLabel      label;
  PetscSection local, global;
  PetscInt     dim, n = 0, capacity = 0;

  PetscFunctionBeginUser;
  if (!f->data.n_force_faces) PetscFunctionReturn(0);
  PetscCall(FluidUnconstrainedSetUp(f));
  PetscCall(DMGetDimension(f->dm_all, &dim));
  PetscCall(DMGetLabel(f->dm_all, "Face Sets", &label));
  PetscCall(DMGetLocalSection(f->dm_all, &local));
  PetscCall(DMGetGlobalSection(f->dm_all, &global));
  {
    /* the points in the closure of the body's faces, each once */
    PetscInt *list = NULL;

    for (PetscInt pass = 0; pass < 2; ++pass) {
      capacity = 0;
      for (PetscInt b = 0; b < f->data.n_force_faces; ++b) {
        IS              faces;
        const PetscInt *face;
        PetscInt        nfaces = 0;

        PetscCall(DMLabelGetStratumIS(label, f->data.force_faces[b], &faces));
        if (!faces) continue;
        PetscCall(ISGetLocalSize(faces, &nfaces));
        PetscCall(ISGetIndices(faces, &face));
        for (PetscInt i = 0; i < nfaces; ++i) {
          PetscInt *closure = NULL, nclosure;
          PetscCall(DMPlexGetTransitiveClosure(f->dm_all, face[i], PETSC_TRUE, &nclosure, &closure));
          for (PetscInt k = 0; k < nclosure; ++k, ++capacity)
            if (pass) list[capacity] = closure[2 * k];
          PetscCall(DMPlexRestoreTransitiveClosure(f->dm_all, face[i], PETSC_TRUE, &nclosure, &closure));
        }
        PetscCall(ISRestoreIndices(faces, &face));
        PetscCall(ISDestroy(&faces));
      }
      if (!pass) PetscCall(PetscMalloc1(capacity, &list));
    }
    PetscCall(PetscSortRemoveDupsInt(&capacity, list));
    /* Q_k has at most (k-1)^(d-1) nodes on a face; count the dofs first */
    for (PetscInt i = 0; i < capacity; ++i) {
      PetscInt ndof, goff;
      PetscCall(PetscSectionGetOffset(global, list[i], &goff));
      if (goff < 0) continue; /* another rank owns it */
      PetscCall(PetscSectionGetFieldDof(local, list[i], 0, &ndof));
      n += ndof / dim;
    }
    PetscCall(PetscMalloc1(n, &f->force_rows));
    n = 0;
    for (PetscInt i = 0; i < capacity; ++i) {
      PetscInt ndof, loff, goff;
      PetscCall(PetscSectionGetOffset(global, list[i], &goff));
      if (goff < 0) continue;
      PetscCall(PetscSectionGetFieldDof(local, list[i], 0, &ndof));
      PetscCall(PetscSectionGetFieldOffset(local, list[i], 0, &loff));
      for (PetscInt node = 0; node < ndof / dim; ++node) f->force_rows[n++] = loff + node * dim;
    }
    PetscCall(PetscFree(list));
  }
  f->n_force_rows = n;
  PetscFunctionReturn(0);
}

/* The constants of the fluid's weak form, with mass, op and load set as asked (< 0: unchanged). */
static PetscErrorCode CopyConstants(Fluid f, PetscReal mass, PetscReal op, PetscReal load)
{
  PetscDS            ds, ds_all;
  const PetscScalar *constants;
  PetscScalar        copy[FLUID_NUM_CONSTANTS + FSIOPT_MAX_EXTRA];
  PetscInt           n;

  PetscFunctionBeginUser;
  PetscCall(DMGetDS(f->dm, &ds));
  PetscCall(DMGetDS(f->dm_all, &ds_all));
  PetscCall(PetscDSGetConstants(ds, &n, &constants));
  PetscCall(PetscArraycpy(copy, constants, n));
  if (mass >= 0) copy[FLUID_MASS] = mass;
  if (op >= 0) copy[FLUID_OPERATOR] = op;
  if (load >= 0) copy[FLUID_LOAD] = load;
  PetscCall(PetscDSSetConstants(ds_all, n, copy));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidBodyForce(Fluid f, PetscReal force[3])
{
  PetscInt           dim;
  const PetscScalar *r;
  PetscReal          sum[3] = {0, 0, 0};
  Vec                residual = f->all_y, old;

  PetscFunctionBeginUser;
  PetscCheck(f->data.n_force_faces, f->comm, PETSC_ERR_ARG_WRONGSTATE, "the scene names no body faces for a fluid force");
  PetscCall(DMGetDimension(f->dm, &dim));
  if (f->moving) {
    Vec coordinates;
    PetscCall(DMGetCoordinatesLocal(f->dm, &coordinates));
    PetscCall(DMSetCoordinatesLocal(f->dm_all, coordinates));
    PetscCall(FEMInvalidateGeometry(f->dm_all));
  }
  PetscCall(FEMGlobalToLocal(f->dm, f->x, f->xlocal_work));
  /* the initial state has no time derivative to go with it: its force is the steady one */
  PetscCall(CopyConstants(f, f->step == 0 ? 0.0 : -1, -1, -1));
  PetscCall(FEMResidual(f->dm_all, f->xlocal_work, residual));
  PetscCall(DMGetGlobalVector(f->dm_all, &old));
  if (f->step == 0) { /* nothing to add */
  } else if (f->moving) {
    /* rho/dt M(Omega^{n-1}) (u^n - u^{n-1}): the mass term of a moving mesh */
    PetscCall(DMLocalToGlobal(f->dm_all, f->xlocal_work, INSERT_VALUES, f->all_x));
    PetscCall(DMLocalToGlobal(f->dm_all, f->xlocal_old, INSERT_VALUES, old));
    PetscCall(VecAXPY(f->all_x, -1.0, old));
    PetscCall(MatMultAdd(f->mass_old_all, f->all_x, residual, residual));
  } else if (!f->steady) {
    /* minus the history term rho/dt (u^{n-1}, w) */
    PetscCall(CopyConstants(f, -1, 0.0, 0.0));
    PetscCall(FEMResidual(f->dm_all, f->xlocal_old, old));
    PetscCall(VecAXPY(residual, -1.0, old));
  }
  PetscCall(DMRestoreGlobalVector(f->dm_all, &old));
  PetscCall(DMGlobalToLocal(f->dm_all, residual, INSERT_VALUES, f->all_local));
  PetscCall(VecGetArrayRead(f->all_local, &r));
  for (PetscInt i = 0; i < f->n_force_rows; ++i)
    for (PetscInt c = 0; c < dim; ++c) sum[c] -= PetscRealPart(r[f->force_rows[i] + c]);
  PetscCall(VecRestoreArrayRead(f->all_local, &r));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sum, 3, MPIU_REAL, MPIU_SUM, f->comm));
  for (PetscInt c = 0; c < 3; ++c) force[c] = sum[c];
  PetscFunctionReturn(0);
}

PetscErrorCode FluidForcesDestroy(Fluid f)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(f->force_rows));
  PetscCall(VecDestroy(&f->all_x));
  PetscCall(VecDestroy(&f->all_y));
  PetscCall(VecDestroy(&f->all_local));
  PetscCall(VecDestroy(&f->xlocal_work));
  PetscCall(DMDestroy(&f->dm_all));
  PetscFunctionReturn(0);
}
