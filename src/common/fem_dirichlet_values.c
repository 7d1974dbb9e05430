/* The Dirichlet values of a DM, kept between calls. PETSc 3.18's DMPlexInsertBoundaryValues
   builds a label of the boundary's cells and projects at every call: on Turek-Hron fsi3 it
   took a fifth of a run, most of it at the fluid's every residual, because the mesh moves at
   every evaluation of the coupling. The values depend only on the time and on where the
   constrained nodes are, so they are projected again only when the time or the coordinates
   of a constrained point's closure (its vertices: the nodes of Lagrange elements on an
   affine or multilinear coordinate field lie where those put them) have changed. */
#include "fem.h"

struct _n_FEMDirichletValues {
  DM               dm; /* borrowed: the owner of the cache owns the DM */
  const PetscReal *time;
  Vec              values;   /* local: the projection of the last key */
  PetscInt         n_dofs;   /* the constrained local dofs */
  PetscInt        *dofs;
  PetscInt         n_coords; /* local coordinate entries of their closures, and their last values */
  PetscInt        *coord_offsets;
  PetscScalar     *coords;
  PetscReal        projected_time;
  PetscBool        valid;
};

PetscErrorCode FEMDirichletValuesCreate(DM dm, const PetscReal *time, FEMDirichletValues *out)
{
  FEMDirichletValues dv;
  PetscSection       section, coord_section;
  PetscInt           pStart, pEnd, cStart, cEnd, n_dofs = 0, n_coords = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&dv));
  dv->dm   = dm;
  dv->time = time;
  PetscCall(DMCreateLocalVector(dm, &dv->values));
  PetscCall(DMGetLocalSection(dm, &section));
  PetscCall(DMGetCoordinateSection(dm, &coord_section));
  PetscCall(PetscSectionGetChart(section, &pStart, &pEnd));
  PetscCall(PetscSectionGetChart(coord_section, &cStart, &cEnd)); /* the vertices, on an affine field */
  /* two passes: count, then fill */
  for (PetscInt pass = 0; pass < 2; ++pass) {
    n_dofs = n_coords = 0;
    for (PetscInt p = pStart; p < pEnd; ++p) {
      PetscInt        cdof, off, n_closure, *closure = NULL;
      const PetscInt *cind;

      PetscCall(PetscSectionGetConstraintDof(section, p, &cdof));
      if (!cdof) continue;
      if (pass) {
        PetscCall(PetscSectionGetOffset(section, p, &off));
        PetscCall(PetscSectionGetConstraintIndices(section, p, &cind));
        for (PetscInt k = 0; k < cdof; ++k) dv->dofs[n_dofs + k] = off + cind[k];
      }
      n_dofs += cdof;
      PetscCall(DMPlexGetTransitiveClosure(dm, p, PETSC_TRUE, &n_closure, &closure));
      for (PetscInt c = 0; c < n_closure; ++c) {
        PetscInt q = closure[2 * c], qdof = 0, qoff;
        if (q < cStart || q >= cEnd) continue;
        PetscCall(PetscSectionGetDof(coord_section, q, &qdof));
        if (!qdof) continue;
        if (pass) {
          PetscCall(PetscSectionGetOffset(coord_section, q, &qoff));
          for (PetscInt k = 0; k < qdof; ++k) dv->coord_offsets[n_coords + k] = qoff + k;
        }
        n_coords += qdof;
      }
      PetscCall(DMPlexRestoreTransitiveClosure(dm, p, PETSC_TRUE, &n_closure, &closure));
    }
    if (!pass) PetscCall(PetscMalloc3(n_dofs, &dv->dofs, n_coords, &dv->coord_offsets, n_coords, &dv->coords));
  }
  dv->n_dofs   = n_dofs;
  dv->n_coords = n_coords;
  *out         = dv;
  PetscFunctionReturn(0);
}

/* Did the time or a constrained point's closure move since the last projection? Records the
   new key. Local: each rank decides for its own dofs (the projection is local too). */
static PetscErrorCode KeyChanged(FEMDirichletValues dv, PetscBool *changed)
{
  Vec                coordinates;
  const PetscScalar *x;

  PetscFunctionBeginUser;
  *changed = !dv->valid || *dv->time != dv->projected_time ? PETSC_TRUE : PETSC_FALSE;
  PetscCall(DMGetCoordinatesLocal(dv->dm, &coordinates));
  PetscCall(VecGetArrayRead(coordinates, &x));
  for (PetscInt i = 0; i < dv->n_coords; ++i) {
    const PetscScalar xi = x[dv->coord_offsets[i]];
    if (!dv->valid || xi != dv->coords[i]) {
      *changed     = PETSC_TRUE;
      dv->coords[i] = xi;
    }
  }
  PetscCall(VecRestoreArrayRead(coordinates, &x));
  dv->projected_time = *dv->time;
  dv->valid          = PETSC_TRUE;
  PetscFunctionReturn(0);
}

PetscErrorCode FEMDirichletValuesGlobalToLocal(FEMDirichletValues dv, Vec xglobal, Vec xlocal)
{
  PetscBool          changed;
  const PetscScalar *b;
  PetscScalar       *a;

  PetscFunctionBeginUser;
  PetscCall(KeyChanged(dv, &changed));
  if (changed) {
    PetscCall(VecZeroEntries(dv->values));
    PetscCall(DMPlexInsertBoundaryValues(dv->dm, PETSC_TRUE, dv->values, 0.0, NULL, NULL, NULL));
  }
  PetscCall(DMGlobalToLocal(dv->dm, xglobal, INSERT_VALUES, xlocal));
  PetscCall(VecGetArray(xlocal, &a));
  PetscCall(VecGetArrayRead(dv->values, &b));
  for (PetscInt i = 0; i < dv->n_dofs; ++i) a[dv->dofs[i]] = b[dv->dofs[i]];
  PetscCall(VecRestoreArrayRead(dv->values, &b));
  PetscCall(VecRestoreArray(xlocal, &a));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMDirichletValuesDestroy(FEMDirichletValues *dv)
{
  PetscFunctionBeginUser;
  if (!*dv) PetscFunctionReturn(0);
  PetscCall(VecDestroy(&(*dv)->values));
  PetscCall(PetscFree3((*dv)->dofs, (*dv)->coord_offsets, (*dv)->coords));
  PetscCall(PetscFree(*dv));
  PetscFunctionReturn(0);
}
