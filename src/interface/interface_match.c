/* The interface's nodes, side by side: a conforming interface shares its nodes, so the
   fluid's and the structure's are paired by their coordinates; a mesh whose nodes do not
   meet is named with its first unmatched node. */
#include "interface_impl.h"

PetscErrorCode InterfaceSideDestroy(Side *s)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree4(s->point, s->coords, s->local, s->global));
  PetscFunctionReturn(0);
}

/* The node of a Lagrange element of degree <= 2 sits at the centre of its point's vertices. */
static PetscErrorCode PointCentre(DM dm, PetscInt p, PetscInt dim, PetscReal x[])
{
  PetscInt           ncl, *cl = NULL, vStart, vEnd, nv = 0;
  PetscSection       cs;
  Vec                coordinates;
  const PetscScalar *c;

  PetscFunctionBeginUser;
  PetscCall(DMPlexGetDepthStratum(dm, 0, &vStart, &vEnd));
  PetscCall(DMGetCoordinateSection(dm, &cs));
  PetscCall(DMGetCoordinatesLocal(dm, &coordinates));
  PetscCall(VecGetArrayRead(coordinates, &c));
  for (PetscInt d = 0; d < dim; ++d) x[d] = 0;
  PetscCall(DMPlexGetTransitiveClosure(dm, p, PETSC_TRUE, &ncl, &cl));
  for (PetscInt i = 0; i < ncl; ++i) {
    const PetscInt q = cl[2 * i];
    PetscInt       off;

    if (q < vStart || q >= vEnd) continue;
    PetscCall(PetscSectionGetOffset(cs, q, &off));
    for (PetscInt d = 0; d < dim; ++d) x[d] += PetscRealPart(c[off + d]);
    ++nv;
  }
  PetscCall(DMPlexRestoreTransitiveClosure(dm, p, PETSC_TRUE, &ncl, &cl));
  PetscCall(VecRestoreArrayRead(coordinates, &c));
  for (PetscInt d = 0; d < dim; ++d) x[d] /= nv;
  PetscFunctionReturn(0);
}

PetscErrorCode InterfaceSideCollect(DM dm, PetscInt face, const char name[], Side *side)
{
  DMLabel         label;
  IS              faces = NULL;
  PetscSection    ls, gs;
  PetscInt        pStart, pEnd, nfaces = 0, dim;
  const PetscInt *fidx = NULL;
  PetscBool      *mark;

  PetscFunctionBeginUser;
  PetscCall(DMGetDimension(dm, &dim));
  PetscCall(DMGetCoordinatesLocalSetUp(dm));
  PetscCall(DMGetLabel(dm, "Face Sets", &label));
  PetscCall(DMGetLocalSection(dm, &ls));
  PetscCall(DMGetGlobalSection(dm, &gs));
  PetscCall(DMPlexGetChart(dm, &pStart, &pEnd));
  PetscCall(PetscCalloc1(pEnd - pStart, &mark));
  if (label) PetscCall(DMLabelGetStratumIS(label, face, &faces));
  if (faces) {
    PetscCall(ISGetLocalSize(faces, &nfaces));
    PetscCall(ISGetIndices(faces, &fidx));
  }
  for (PetscInt f = 0; f < nfaces; ++f) {
    PetscInt ncl, *cl = NULL;

    PetscCall(DMPlexGetTransitiveClosure(dm, fidx[f], PETSC_TRUE, &ncl, &cl));
    for (PetscInt i = 0; i < ncl; ++i) mark[cl[2 * i] - pStart] = PETSC_TRUE;
    PetscCall(DMPlexRestoreTransitiveClosure(dm, fidx[f], PETSC_TRUE, &ncl, &cl));
  }
  if (faces) {
    PetscCall(ISRestoreIndices(faces, &fidx));
    PetscCall(ISDestroy(&faces));
  }
  side->n = 0;
  for (PetscInt pass = 0; pass < 2; ++pass) {
    PetscInt n = 0;

    for (PetscInt p = pStart; p < pEnd; ++p) {
      PetscInt ndof, cdof, gdof, off, goff;

      if (!mark[p - pStart]) continue;
      PetscCall(PetscSectionGetFieldDof(ls, p, 0, &ndof));
      if (!ndof) continue;
      PetscCall(PetscSectionGetDof(gs, p, &gdof));
      if (gdof < 0) continue; /* a ghost: its owner lists it */
      PetscCheck(ndof == dim, PETSC_COMM_SELF, PETSC_ERR_SUP,
                 "%s interface: expected one velocity node per mesh point (polynomial degree at most 2), got "
                 "%" PetscInt_FMT " dofs",
                 name, ndof);
      PetscCall(PetscSectionGetFieldConstraintDof(ls, p, 0, &cdof));
      PetscCheck(cdof == 0 || cdof == ndof, PETSC_COMM_SELF, PETSC_ERR_SUP,
                 "%s interface: a node with some components constrained and others free is not supported", name);
      if (pass == 1) {
        PetscCall(PetscSectionGetFieldOffset(ls, p, 0, &off));
        PetscCall(PetscSectionGetOffset(gs, p, &goff));
        side->point[n]  = p;
        side->local[n]  = off;
        side->global[n] = cdof ? -1 : goff;
        PetscCall(PointCentre(dm, p, dim, &side->coords[n * dim]));
      }
      ++n;
    }
    if (pass == 0) {
      side->n = n;
      PetscCall(PetscMalloc4(n, &side->point, n * dim, &side->coords, n, &side->local, n, &side->global));
    }
  }
  PetscCall(PetscFree(mark));
  PetscFunctionReturn(0);
}

/* One line naming the first fluid node without a structure partner, on every rank. */
static PetscErrorCode ReportUnmatched(MPI_Comm comm, PetscInt dim, const PetscReal *x_or_null, PetscInt fluid_face,
                                      PetscInt structure_face)
{
  PetscMPIInt rank, size, bad, first;
  PetscReal   x[3] = {0, 0, 0};

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  bad = x_or_null ? rank : size;
  PetscCallMPI(MPI_Allreduce(&bad, &first, 1, MPI_INT, MPI_MIN, comm));
  if (first == size) PetscFunctionReturn(0);
  if (rank == first)
    for (PetscInt d = 0; d < dim; ++d) x[d] = x_or_null[d];
  PetscCallMPI(MPI_Bcast(x, 3, MPIU_REAL, first, comm));
  SETERRQ(comm, PETSC_ERR_ARG_INCOMP,
          "interface: the meshes do not conform: fluid node (%g, %g, %g) on face set %" PetscInt_FMT
          " has no structure node on face set %" PetscInt_FMT " within the tolerance (-coupling_interface_tol)",
          (double)x[0], (double)x[1], (double)x[2], fluid_face, structure_face);
}

PetscErrorCode InterfaceMatch(Interface itf, PetscReal rtol, PetscInt fluid_face, PetscInt structure_face)
{
  const PetscInt dim = itf->dim;
  PetscMPIInt    size, nmine, *counts, *displs;
  PetscInt       nstruct = 0, nfluid_total, *perm, *from, *to;
  PetscReal     *coords, *xs, lo[3] = {PETSC_MAX_REAL, PETSC_MAX_REAL, PETSC_MAX_REAL},
                          hi[3] = {PETSC_MIN_REAL, PETSC_MIN_REAL, PETSC_MIN_REAL}, diam = 0, tol;
  const PetscReal *unmatched = NULL;
  IS               isfrom, isto;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(itf->comm, &size));
  PetscCall(PetscMalloc2(size, &counts, size + 1, &displs));
  nmine = (PetscMPIInt)(itf->structure.n * dim);
  PetscCallMPI(MPI_Allgather(&nmine, 1, MPI_INT, counts, 1, MPI_INT, itf->comm));
  displs[0] = 0;
  for (PetscMPIInt r = 0; r < size; ++r) displs[r + 1] = displs[r] + counts[r];
  nstruct = displs[size] / dim;
  PetscCall(PetscMalloc3(nstruct * dim, &coords, nstruct, &xs, nstruct, &perm));
  PetscCallMPI(MPI_Allgatherv(itf->structure.coords, nmine, MPIU_REAL, coords, counts, displs, MPIU_REAL, itf->comm));
  PetscCallMPI(MPI_Allreduce(&itf->fluid.n, &nfluid_total, 1, MPIU_INT, MPI_SUM, itf->comm));
  PetscCheck(nfluid_total > 0, itf->comm, PETSC_ERR_ARG_WRONG,
             "interface: the fluid mesh has no node on face set %" PetscInt_FMT, fluid_face);
  PetscCheck(nfluid_total == nstruct, itf->comm, PETSC_ERR_ARG_INCOMP,
             "interface: the meshes do not conform: the fluid has %" PetscInt_FMT " nodes on face set %" PetscInt_FMT
             ", the structure %" PetscInt_FMT " on face set %" PetscInt_FMT,
             nfluid_total, fluid_face, nstruct, structure_face);
  for (PetscInt i = 0; i < nstruct; ++i) {
    for (PetscInt d = 0; d < dim; ++d) {
      lo[d] = PetscMin(lo[d], coords[i * dim + d]);
      hi[d] = PetscMax(hi[d], coords[i * dim + d]);
    }
    xs[i]   = coords[i * dim];
    perm[i] = i;
  }
  for (PetscInt d = 0; d < dim; ++d) diam = PetscMax(diam, hi[d] - lo[d]);
  tol = rtol * PetscMax(diam, 1e-300);
  PetscCall(PetscSortRealWithPermutation(nstruct, xs, perm));
  PetscCall(PetscMalloc1(itf->fluid.n * dim, &from));
  PetscCall(PetscMalloc1(itf->fluid.n * dim, &to));
  {
    PetscInt fstart;
    PetscCall(VecGetOwnershipRange(itf->all, &fstart, NULL));
    for (PetscInt i = 0; i < itf->fluid.n && !unmatched; ++i) {
      const PetscReal *x = &itf->fluid.coords[i * dim];
      PetscInt         a = 0, b = nstruct, found = -1;

      /* first structure node with x >= x_fluid - tol */
      while (a < b) {
        const PetscInt m = (a + b) / 2;
        if (coords[perm[m] * dim] < x[0] - tol) a = m + 1;
        else b = m;
      }
      for (PetscInt k = a; k < nstruct && coords[perm[k] * dim] <= x[0] + tol; ++k) {
        PetscReal dist = 0;
        for (PetscInt d = 0; d < dim; ++d) dist = PetscMax(dist, PetscAbsReal(coords[perm[k] * dim + d] - x[d]));
        if (dist <= tol) {
          found = perm[k];
          break;
        }
      }
      if (found < 0) unmatched = x;
      for (PetscInt c = 0; c < dim; ++c) {
        from[i * dim + c] = found * dim +
                            c; /* structure nodes are gathered in rank order: the gathered index is the global one */
        to[i * dim + c] = fstart + i * dim + c;
      }
    }
  }
  PetscCall(ReportUnmatched(itf->comm, dim, unmatched, fluid_face, structure_face));
  PetscCall(ISCreateGeneral(itf->comm, itf->fluid.n * dim, from, PETSC_OWN_POINTER, &isfrom));
  PetscCall(ISCreateGeneral(itf->comm, itf->fluid.n * dim, to, PETSC_OWN_POINTER, &isto));
  PetscCall(VecScatterCreate(itf->structure_all, isfrom, itf->all, isto, &itf->structure_to_fluid));
  PetscCall(ISDestroy(&isfrom));
  PetscCall(ISDestroy(&isto));
  PetscCall(PetscFree3(coords, xs, perm));
  PetscCall(PetscFree2(counts, displs));
  PetscFunctionReturn(0);
}
