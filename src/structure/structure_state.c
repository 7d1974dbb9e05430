/* The structure's state as others read and set it: its displacement and velocity (local
   vectors), the displacement at the nodes for probes, and, for a method that solves the
   coupled system at once (monolithic.c), its nonlinear system and a state set from outside. */
#include "structure_impl.h"

PetscErrorCode StructureGetDisplacementLocal(Structure s, Vec *eta_local)
{
  PetscFunctionBeginUser;
  *eta_local = s->eta_local;
  PetscFunctionReturn(0);
}

PetscErrorCode StructureGetVelocityLocal(Structure s, Vec *etadot_local)
{
  PetscFunctionBeginUser;
  *etadot_local = s->etadot_local;
  PetscFunctionReturn(0);
}

PetscErrorCode StructureRestoreVelocityLocal(Structure s, Vec *etadot_local)
{
  Vec global;

  PetscFunctionBeginUser;
  /* owners' values to the ghosts, through the space without constraints */
  PetscCall(DMGetGlobalVector(s->dm_free, &global));
  PetscCall(DMLocalToGlobal(s->dm_free, s->etadot_local, INSERT_VALUES, global));
  PetscCall(DMGlobalToLocal(s->dm_free, global, INSERT_VALUES, s->etadot_local));
  PetscCall(DMRestoreGlobalVector(s->dm_free, &global));
  *etadot_local = NULL;
  PetscFunctionReturn(0);
}

PetscErrorCode StructureCreateNodeVector(Structure s, Vec *v, PetscInt *nnodes, PetscReal **coords)
{
  PetscSection       global;
  PetscInt           dim, vStart, vEnd, rstart, n;
  Vec                coordinates;
  const PetscScalar *x;
  PetscSection       cs;

  PetscFunctionBeginUser;
  PetscCall(DMGetDimension(s->dm_free, &dim));
  PetscCall(DMCreateGlobalVector(s->dm_free, v));
  PetscCall(VecGetOwnershipRange(*v, &rstart, NULL));
  PetscCall(VecGetLocalSize(*v, &n));
  *nnodes = n / dim;
  PetscCall(PetscMalloc1(n, coords));
  for (PetscInt i = 0; i < n; ++i)
    (*coords)[i] = PETSC_MAX_REAL; /* a node inside an edge or a cell: no probe finds it */
  PetscCall(DMGetGlobalSection(s->dm_free, &global));
  PetscCall(DMPlexGetDepthStratum(s->dm_free, 0, &vStart, &vEnd));
  PetscCall(DMGetCoordinateSection(s->dm_free, &cs));
  PetscCall(DMGetCoordinatesLocal(s->dm_free, &coordinates));
  PetscCall(VecGetArrayRead(coordinates, &x));
  for (PetscInt v = vStart; v < vEnd; ++v) {
    PetscInt goff, coff;
    PetscCall(PetscSectionGetOffset(global, v, &goff));
    if (goff < 0) continue;
    PetscCall(PetscSectionGetOffset(cs, v, &coff));
    for (PetscInt d = 0; d < dim; ++d) (*coords)[goff - rstart + d] = PetscRealPart(x[coff + d]);
  }
  PetscCall(VecRestoreArrayRead(coordinates, &x));
  PetscFunctionReturn(0);
}

PetscErrorCode StructureGetNodeDisplacement(Structure s, Vec v)
{
  PetscFunctionBeginUser;
  PetscCall(DMLocalToGlobal(s->dm_free, s->eta_local, INSERT_VALUES, v));
  PetscFunctionReturn(0);
}

PetscErrorCode StructureGetNonlinearSystem(Structure s, SNES *snes, Vec *history, Vec *eta)
{
  PetscFunctionBeginUser;
  *snes    = s->snes;
  *history = s->history;
  if (eta) *eta = s->eta;
  PetscFunctionReturn(0);
}

PetscErrorCode StructureSetDisplacement(Structure s, Vec eta, Vec load)
{
  PetscFunctionBeginUser;
  PetscCall(VecCopy(eta, s->eta));
  PetscCall(FEMGlobalToLocal(s->dm, s->eta, s->eta_local));
  if (load) PetscCall(VecCopy(load, s->load));
  else PetscCall(VecZeroEntries(s->load));
  PetscFunctionReturn(0);
}
