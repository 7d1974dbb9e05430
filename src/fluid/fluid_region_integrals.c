/* Integrals over a region of the fluid (a "Cell Sets" value, or every cell) on its current
   mesh: its volume (2D: area), int p and the kinetic energy int rho |u|^2 / 2, from the
   fields' own elements at their quadrature points. Only when probes.csv asks for them. */
#include "fluid_impl.h"

PetscErrorCode FluidRegionIntegral(Fluid f, PetscInt region, FluidRegionIntegrals *integral)
{
  PetscFE          fe[2];
  PetscQuadrature  quadrature;
  PetscTabulation  T[2];
  PetscSection     section;
  DMLabel          cells;
  IS               is = NULL;
  const PetscInt  *list = NULL;
  const PetscReal *points, *weights;
  PetscReal       *v0, *J, *invJ, *detJ, sums[3] = {0, 0, 0};
  PetscInt         dim, nq, Nb[2], Nc[2], cStart, cEnd, n;

  PetscFunctionBeginUser;
  PetscCall(FluidGlobalToLocal(f, f->x, f->xlocal_work));
  PetscCall(DMGetDimension(f->dm, &dim));
  PetscCall(DMGetLocalSection(f->dm, &section));
  for (PetscInt k = 0; k < 2; ++k) {
    PetscCall(DMGetField(f->dm, k, NULL, (PetscObject *)&fe[k]));
    PetscCall(PetscFEGetDimension(fe[k], &Nb[k]));
    PetscCall(PetscFEGetNumComponents(fe[k], &Nc[k]));
  }
  PetscCall(PetscFEGetQuadrature(fe[0], &quadrature));
  PetscCall(PetscQuadratureGetData(quadrature, NULL, NULL, &nq, &points, &weights));
  for (PetscInt k = 0; k < 2; ++k) PetscCall(PetscFECreateTabulation(fe[k], 1, nq, points, 0, &T[k]));
  PetscCall(PetscMalloc4(dim, &v0, dim * dim * nq, &J, dim * dim * nq, &invJ, nq, &detJ));
  PetscCall(DMPlexGetHeightStratum(f->dm, 0, &cStart, &cEnd));
  n = cEnd - cStart;
  if (region >= 0) {
    PetscCall(DMGetLabel(f->dm, "Cell Sets", &cells));
    n = 0;
    if (cells) PetscCall(DMLabelGetStratumIS(cells, region, &is));
    if (is) PetscCall(ISGetLocalSize(is, &n));
    if (is) PetscCall(ISGetIndices(is, &list));
  }
  for (PetscInt i = 0; i < n; ++i) {
    const PetscInt c = list ? list[i] : cStart + i;
    PetscScalar   *values = NULL;
    PetscInt       size;
    if (c < cStart || c >= cEnd) continue;
    PetscCall(DMPlexComputeCellGeometryFEM(f->dm, c, quadrature, v0, J, invJ, detJ));
    PetscCall(DMPlexVecGetClosure(f->dm, section, f->xlocal_work, c, &size, &values));
    for (PetscInt q = 0; q < nq; ++q) {
      const PetscReal w = weights[q] * detJ[q];
      PetscReal       u2 = 0, p = 0;
      for (PetscInt d = 0; d < Nc[0]; ++d) {
        PetscReal u = 0;
        for (PetscInt b = 0; b < Nb[0]; ++b) u += PetscRealPart(values[b]) * T[0]->T[0][(q * Nb[0] + b) * Nc[0] + d];
        u2 += u * u;
      }
      for (PetscInt b = 0; b < Nb[1]; ++b) p += PetscRealPart(values[Nb[0] + b]) * T[1]->T[0][q * Nb[1] + b];
      sums[0] += w;
      sums[1] += w * p;
      sums[2] += w * 0.5 * f->rho * u2;
    }
    PetscCall(DMPlexVecRestoreClosure(f->dm, section, f->xlocal_work, c, &size, &values));
  }
  if (is) PetscCall(ISRestoreIndices(is, &list));
  PetscCall(ISDestroy(&is));
  PetscCall(PetscFree4(v0, J, invJ, detJ));
  for (PetscInt k = 0; k < 2; ++k) PetscCall(PetscTabulationDestroy(&T[k]));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sums, 3, MPIU_REAL, MPIU_SUM, f->comm));
  integral->volume   = sums[0];
  integral->pressure = sums[1];
  integral->kinetic  = sums[2];
  PetscFunctionReturn(0);
}
