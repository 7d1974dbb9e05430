/* The grids -write_fields writes (fields_impl.h): the nodes and cells ParaView draws for a
   set of mesh cells (a whole mesh, or faces of a boundary). With -write_fields_nodes all a
   node is every mesh point that carries a Lagrange node of some field, so a degree-2 field
   keeps its edge, face and cell nodes: each cell is written as the cells of its once-refined
   lattice (4 in 2D, 8 in 3D, 2 for a face's edge), whose vertices are exactly the degree-2
   nodes. A degree-1 field has no value at an edge, face or cell centre; there it takes the
   mean of that point's vertices, which is its value (the midpoint of an edge, the centre of
   a quadrilateral or hexahedron). With `vertices` the nodes are the vertices and the cells
   the mesh's own: the fields' vertex values, smaller files. Nodes are numbered through a
   PetscSection over the node points and its global section, so each is written once, by
   the rank that owns it. */
#include <petscsf.h>
#include "fields_impl.h"

#define MAX_CORNERS 8  /* vertices of a hexahedron */
#define MAX_CLOSURE 27 /* points of a hexahedron's closure */

/* A cell's closure: each point with the set of the cell's vertices (bits, in the order the
   grid writes them) it spans. */
typedef struct {
  PetscInt n, point[MAX_CLOSURE], mask[MAX_CLOSURE];
  PetscInt ncorners, corner[MAX_CORNERS];
} Closure;

static PetscErrorCode ClosureGet(DM dm, PetscInt cell, DMPolytopeType ct, PetscInt vStart, PetscInt vEnd, Closure *c)
{
  PetscInt *closure = NULL, n;

  PetscFunctionBeginUser;
  c->n = c->ncorners = 0;
  PetscCall(DMPlexGetTransitiveClosure(dm, cell, PETSC_TRUE, &n, &closure));
  for (PetscInt i = 0; i < 2 * n; i += 2)
    if (closure[i] >= vStart && closure[i] < vEnd && c->ncorners < MAX_CORNERS) c->corner[c->ncorners++] = closure[i];
  /* DMPlex orients tetrahedra and hexahedra (a hexahedron's bottom face) the other way round
     from XDMF (VTK) */
  if ((ct == DM_POLYTOPE_HEXAHEDRON && c->ncorners == 8) || (ct == DM_POLYTOPE_TETRAHEDRON && c->ncorners == 4))
    PetscCall(DMPlexInvertCell(ct, c->corner));
  for (PetscInt i = 0; i < 2 * n && c->n < MAX_CLOSURE; i += 2) {
    PetscInt *sub = NULL, m, mask = 0;

    PetscCall(DMPlexGetTransitiveClosure(dm, closure[i], PETSC_TRUE, &m, &sub));
    for (PetscInt j = 0; j < 2 * m; j += 2)
      for (PetscInt k = 0; k < c->ncorners; ++k)
        if (sub[j] == c->corner[k]) mask |= 1 << k;
    PetscCall(DMPlexRestoreTransitiveClosure(dm, closure[i], PETSC_TRUE, &m, &sub));
    c->point[c->n]  = closure[i];
    c->mask[c->n++] = mask;
  }
  PetscCall(DMPlexRestoreTransitiveClosure(dm, cell, PETSC_TRUE, &n, &closure));
  PetscFunctionReturn(0);
}

static PetscInt ClosurePoint(const Closure *c, PetscInt mask)
{
  for (PetscInt i = 0; i < c->n; ++i)
    if (c->mask[i] == mask) return c->point[i];
  return -1;
}

/* The parameters of a tensor cell's corners in the order written (VTK's). */
static const PetscInt tensor_corner[3][8][3] = {
  {{0}, {1}},
  {{0, 0}, {1, 0}, {1, 1}, {0, 1}},
  {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}
};

/* The corners a lattice node (0, 1 or 2 per axis) spans: 1 = the middle of that axis. */
static PetscInt TensorNodeMask(PetscInt dim, const PetscInt node[])
{
  PetscInt mask = 0;

  for (PetscInt k = 0; k < (1 << dim); ++k) {
    PetscBool in = PETSC_TRUE;
    for (PetscInt d = 0; d < dim; ++d)
      if (node[d] != 1 && 2 * tensor_corner[dim - 1][k][d] != node[d]) in = PETSC_FALSE;
    if (in) mask |= 1 << k;
  }
  return mask;
}

/* The once-refined cells of a parent, as masks: translated copies of the parent for tensor
   cells; for simplices the corner copies and the inner cells, oriented in FixSimplex. */
static PetscInt RefinedMasks(DMPolytopeType ct, PetscInt masks[][MAX_CORNERS])
{
  static const PetscInt triangle[4][3] = {
    {1, 3, 5},
    {3, 2, 6},
    {5, 6, 4},
    {6, 5, 3}
  };
  static const PetscInt tetrahedron[8][4] = {
    {1, 3,  5,  9 },
    {3, 2,  6,  10},
    {5, 6,  4,  12},
    {9, 10, 12, 8 },
    {5, 10, 3,  9 },
    {5, 10, 9,  12},
    {5, 10, 12, 6 },
    {5, 10, 6,  3 }
  };
  PetscInt dim = ct == DM_POLYTOPE_SEGMENT ? 1 : ct == DM_POLYTOPE_QUADRILATERAL ? 2 : ct == DM_POLYTOPE_HEXAHEDRON ? 3 : 0;

  if (ct == DM_POLYTOPE_TRIANGLE) {
    for (PetscInt s = 0; s < 4; ++s)
      for (PetscInt k = 0; k < 3; ++k) masks[s][k] = triangle[s][k];
    return 4;
  }
  if (ct == DM_POLYTOPE_TETRAHEDRON) {
    for (PetscInt s = 0; s < 8; ++s)
      for (PetscInt k = 0; k < 4; ++k) masks[s][k] = tetrahedron[s][k];
    return 8;
  }
  for (PetscInt s = 0; s < (1 << dim); ++s)
    for (PetscInt k = 0; k < (1 << dim); ++k) {
      PetscInt node[3];
      for (PetscInt d = 0; d < dim; ++d) node[d] = ((s >> d) & 1) + tensor_corner[dim - 1][k][d];
      masks[s][k] = TensorNodeMask(dim, node);
    }
  return 1 << dim;
}

/* A refined simplex with the parent's orientation: its volume in barycentric parameters
   (the parent's corner k at the unit vector e_k, corner 0 at the origin) positive. */
static void FixSimplex(PetscInt n, PetscInt masks[])
{
  PetscReal x[4][3] = {{0}}, a[3][3], det;
  PetscInt  dim = n - 1;

  for (PetscInt i = 0; i < n; ++i)
    for (PetscInt d = 0; d < dim; ++d) {
      PetscInt count = 0;
      for (PetscInt k = 0; k < n; ++k) count += (masks[i] >> k) & 1;
      x[i][d] = ((masks[i] >> (d + 1)) & 1) / (PetscReal)count;
    }
  for (PetscInt i = 0; i < dim; ++i)
    for (PetscInt d = 0; d < dim; ++d) a[i][d] = x[i + 1][d] - x[0][d];
  det = dim == 2 ? a[0][0] * a[1][1] - a[0][1] * a[1][0]
                 : a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                     a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
  if (det < 0) {
    const PetscInt t = masks[0];
    masks[0]         = masks[1];
    masks[1]         = t;
  }
}

static PetscInt Corners(DMPolytopeType ct)
{
  switch (ct) {
  case DM_POLYTOPE_SEGMENT:
    return 2;
  case DM_POLYTOPE_TRIANGLE:
    return 3;
  case DM_POLYTOPE_QUADRILATERAL:
  case DM_POLYTOPE_TETRAHEDRON:
    return 4;
  case DM_POLYTOPE_HEXAHEDRON:
    return 8;
  default:
    return 0;
  }
}

/* Whether point p carries a node of the grid, and whether the fields' layout there is one
   node per point (all of a field's components, or none of them). */
static void NodeAt(const FieldsGridSources *src, PetscInt p, PetscBool vertex, PetscBool all, PetscBool *node,
                   PetscBool *bad)
{
  *node = vertex;
  for (PetscInt f = 0; f < src->nfields; ++f) {
    PetscInt ndof = 0, pStart, pEnd;
    if (!src->section[f] || PetscSectionGetChart(src->section[f], &pStart, &pEnd)) continue;
    if (p >= pStart && p < pEnd && PetscSectionGetFieldDof(src->section[f], p, src->number[f], &ndof)) ndof = -1;
    if (vertex ? ndof != src->nc[f] : ndof != 0 && ndof != src->nc[f]) *bad = PETSC_TRUE;
    if (all && ndof > 0) *node = PETSC_TRUE;
  }
}

/* Makes a per-point flag the same on every rank that has the point: the largest. */
static PetscErrorCode SyncFlags(DM dm, PetscInt pStart, PetscInt pEnd, PetscInt flag[])
{
  PetscSF   sf;
  PetscInt *root;

  PetscFunctionBeginUser;
  PetscCall(DMGetPointSF(dm, &sf));
  PetscCall(PetscMalloc1(pEnd - pStart, &root));
  PetscCall(PetscArraycpy(root, flag, pEnd - pStart));
  PetscCall(PetscSFReduceBegin(sf, MPIU_INT, flag, root, MPI_MAX));
  PetscCall(PetscSFReduceEnd(sf, MPIU_INT, flag, root, MPI_MAX));
  PetscCall(PetscSFBcastBegin(sf, MPIU_INT, root, flag, MPI_REPLACE));
  PetscCall(PetscSFBcastEnd(sf, MPIU_INT, root, flag, MPI_REPLACE));
  PetscCall(PetscFree(root));
  PetscFunctionReturn(0);
}

/* Concatenates every rank's n values on the root, in rank order. */
PetscErrorCode FieldsGatherOnRoot(MPI_Comm comm, PetscInt n, MPI_Datatype type, const void *send, void **recv,
                                  PetscInt *total)
{
  PetscMPIInt rank, size, mine = (PetscMPIInt)n, *counts = NULL, *displs = NULL, unit;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCallMPI(MPI_Type_size(type, &unit));
  *recv  = NULL;
  *total = 0;
  if (!rank) PetscCall(PetscMalloc2(size, &counts, size, &displs));
  PetscCallMPI(MPI_Gather(&mine, 1, MPI_INT, counts, 1, MPI_INT, 0, comm));
  for (PetscMPIInt r = 0; !rank && r < size; ++r) {
    displs[r] = (PetscMPIInt)*total;
    *total += counts[r];
  }
  if (!rank) PetscCall(PetscMalloc((size_t)PetscMax(*total, 1) * (size_t)unit, recv));
  PetscCallMPI(MPI_Gatherv(send, mine, type, *recv, counts, displs, type, 0, comm));
  if (!rank) PetscCall(PetscFree2(counts, displs));
  PetscFunctionReturn(0);
}

/* The grid's cells on this rank: the owned cells of the mesh, or the owned faces of the
   face sets (label values) given. */
PetscErrorCode FieldsGridCells(DM dm, const FieldsGridSources *src, PetscInt *n, PetscInt **cells)
{
  IS              numbering;
  const PetscInt *number;
  PetscInt        pStart, pEnd, cStart, cEnd;

  PetscFunctionBeginUser;
  PetscCall(DMPlexGetChart(dm, &pStart, &pEnd));
  PetscCall(DMPlexCreatePointNumbering(dm, &numbering));
  PetscCall(ISGetIndices(numbering, &number));
  PetscCall(DMPlexGetHeightStratum(dm, src->faces ? 1 : 0, &cStart, &cEnd));
  PetscCall(PetscMalloc1(cEnd - cStart, cells));
  *n = 0;
  for (PetscInt c = cStart; c < cEnd; ++c) {
    PetscBool in = src->faces ? PETSC_FALSE : PETSC_TRUE;
    if (number[c - pStart] < 0) continue;
    for (PetscInt k = 0; k < src->nfaces && !in; ++k) {
      PetscInt value;
      PetscCall(DMLabelGetValue(src->faces, c, &value));
      if (value == src->face_values[k]) in = PETSC_TRUE;
    }
    if (in) (*cells)[(*n)++] = c;
  }
  PetscCall(ISRestoreIndices(numbering, &number));
  PetscCall(ISDestroy(&numbering));
  PetscFunctionReturn(0);
}

PetscErrorCode FieldsGridSetUp(MPI_Comm comm, Part *P, const FieldsGridSources *src, PetscBool all)
{
  DM              dm     = src->dm;
  PetscInt        info[4] = {0, -1, 0, 0}, ncells = 0, nout = 0, *cells = NULL, *out = NULL, *flag = NULL, *global = NULL;
  PetscInt        pStart = 0, pEnd = 0, vStart = 0, vEnd = 0, total;
  PetscSection    nodes = NULL, numbers = NULL;
  PetscBool       bad = PETSC_FALSE;
  DMPolytopeType  ct  = DM_POLYTOPE_UNKNOWN;

  PetscFunctionBeginUser;
  if (dm) {
    PetscCall(DMGetCoordinateDim(dm, &info[0]));
    PetscCall(DMPlexGetChart(dm, &pStart, &pEnd));
    PetscCall(DMPlexGetDepthStratum(dm, 0, &vStart, &vEnd));
    PetscCall(FieldsGridCells(dm, src, &ncells, &cells));
    PetscCall(PetscCalloc1(pEnd - pStart, &flag));
    for (PetscInt i = 0; i < ncells; ++i) {
      DMPolytopeType cti;
      Closure        c;

      PetscCall(DMPlexGetCellType(dm, cells[i], &cti));
      if (i == 0) ct = cti;
      if (cti != ct || !Corners(ct)) bad = PETSC_TRUE;
      PetscCall(ClosureGet(dm, cells[i], ct, vStart, vEnd, &c));
      for (PetscInt k = 0; k < c.n; ++k) {
        PetscBool node;
        NodeAt(src, c.point[k], c.point[k] >= vStart && c.point[k] < vEnd, all, &node, &bad);
        if (node) flag[c.point[k] - pStart] = 1;
      }
    }
    if (ncells) info[1] = (PetscInt)ct;
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &bad, 1, MPIU_BOOL, MPI_LOR, comm));
  PetscCheck(!bad, comm, PETSC_ERR_SUP,
             "option -write_fields: the %s needs cells of one type (segments, triangles, quadrilaterals, tetrahedra, "
             "hexahedra) and Lagrange fields with one node per mesh point (degree 2 at most with -write_fields_nodes "
             "all; -write_fields_nodes vertices writes any degree's vertex values)",
             P->name);
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, info, 2, MPIU_INT, MPI_MAX, comm));
  P->dim = info[0];
  ct     = (DMPolytopeType)info[1];
  if (dm) {
    PetscCall(SyncFlags(dm, pStart, pEnd, flag));
    /* on the mesh's communicator: the global section numbers the nodes across its ranks */
    PetscCall(PetscSectionCreate(PetscObjectComm((PetscObject)dm), &nodes));
    PetscCall(PetscSectionSetChart(nodes, pStart, pEnd));
    for (PetscInt p = pStart; p < pEnd; ++p) {
      PetscCall(PetscSectionSetDof(nodes, p, flag[p - pStart]));
      if (flag[p - pStart] && (p < vStart || p >= vEnd)) info[2] = 1;
    }
    PetscCall(PetscSectionSetUp(nodes));
    {
      PetscSF sf;
      PetscCall(DMGetPointSF(dm, &sf));
      PetscCall(PetscSectionCreateGlobalSection(nodes, sf, PETSC_FALSE, PETSC_FALSE, &numbers));
    }
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &info[2], 1, MPIU_INT, MPI_MAX, comm));
  P->refined = info[2] ? PETSC_TRUE : PETSC_FALSE;
  P->nv       = Corners(ct); /* a refined cell has its parent's number of corners */
  P->polytope = ct;
  if (dm) {
    PetscInt masks[8][MAX_CORNERS], nsub = P->refined ? RefinedMasks(ct, masks) : 1;
    const PetscBool simplex = ct == DM_POLYTOPE_TRIANGLE || ct == DM_POLYTOPE_TETRAHEDRON;

    if (!P->refined)
      for (PetscInt k = 0; k < P->nv; ++k) masks[0][k] = 1 << k;
    else if (simplex)
      for (PetscInt s = 0; s < nsub; ++s) FixSimplex(P->nv, masks[s]);
    /* the owned nodes, with the vertices a degree-1 value there is the mean of */
    PetscCall(PetscMalloc1(pEnd - pStart, &P->own));
    PetscCall(PetscMalloc1(pEnd - pStart, &P->nvert));
    PetscCall(PetscMalloc1((pEnd - pStart) * MAX_CORNERS, &P->vert));
    PetscCall(PetscMalloc1(pEnd - pStart, &global));
    for (PetscInt p = pStart; p < pEnd; ++p) {
      PetscInt dof, off, *closure = NULL, n;

      PetscCall(PetscSectionGetDof(numbers, p, &dof));
      if (dof <= 0) continue;
      PetscCall(PetscSectionGetOffset(numbers, p, &off));
      P->own[P->nown]   = p;
      global[P->nown]   = off;
      P->nvert[P->nown] = 0;
      PetscCall(DMPlexGetTransitiveClosure(dm, p, PETSC_TRUE, &n, &closure));
      for (PetscInt i = 0; i < 2 * n; i += 2)
        if (closure[i] >= vStart && closure[i] < vEnd && P->nvert[P->nown] < MAX_CORNERS)
          P->vert[P->nown * MAX_CORNERS + P->nvert[P->nown]++] = closure[i];
      PetscCall(DMPlexRestoreTransitiveClosure(dm, p, PETSC_TRUE, &n, &closure));
      ++P->nown;
    }
    PetscCall(PetscMalloc1(ncells * nsub * P->nv, &out));
    for (PetscInt i = 0; i < ncells; ++i) {
      Closure c;
      PetscCall(ClosureGet(dm, cells[i], ct, vStart, vEnd, &c));
      for (PetscInt s = 0; s < nsub; ++s, ++nout)
        for (PetscInt k = 0; k < P->nv; ++k) {
          const PetscInt p = ClosurePoint(&c, masks[s][k]);
          PetscInt       off = -1, dof = 0;
          if (p >= 0) {
            PetscCall(PetscSectionGetDof(numbers, p, &dof));
            PetscCall(PetscSectionGetOffset(numbers, p, &off));
          }
          if (!dof) bad = PETSC_TRUE; /* a lattice node no field has */
          out[nout * P->nv + k] = dof > 0 ? off : -(off + 1);
        }
    }
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &bad, 1, MPIU_BOOL, MPI_LOR, comm));
  PetscCheck(!bad, comm, PETSC_ERR_SUP,
             "option -write_fields_nodes all: the %s's fields lack nodes of its refined cells; use -write_fields_nodes "
             "vertices",
             P->name);
  PetscCall(FieldsGatherOnRoot(comm, nout * P->nv, MPIU_INT, out, (void **)&P->cells, &total));
  P->ncells = P->nv ? total / P->nv : 0;
  PetscCall(FieldsGatherOnRoot(comm, P->nown, MPIU_INT, global, (void **)&P->index, &P->nnodes));
  PetscCallMPI(MPI_Bcast(&P->nnodes, 1, MPIU_INT, 0, comm));
  PetscCallMPI(MPI_Bcast(&P->ncells, 1, MPIU_INT, 0, comm));
  PetscCall(PetscSectionDestroy(&nodes));
  PetscCall(PetscSectionDestroy(&numbers));
  PetscCall(PetscFree(out));
  PetscCall(PetscFree(cells));
  PetscCall(PetscFree(flag));
  PetscCall(PetscFree(global));
  PetscFunctionReturn(0);
}

PetscErrorCode FieldsGridValue(const Part *P, PetscInt i, PetscSection s, PetscInt number, PetscInt nc,
                               const PetscScalar *a, PetscScalar v[])
{
  PetscInt ndof = 0, off, pStart, pEnd;

  PetscFunctionBeginUser;
  /* a section may cover only some points (the coordinates': the vertices) */
  PetscCall(PetscSectionGetChart(s, &pStart, &pEnd));
  if (P->own[i] >= pStart && P->own[i] < pEnd)
    PetscCall(number < 0 ? PetscSectionGetDof(s, P->own[i], &ndof) : PetscSectionGetFieldDof(s, P->own[i], number, &ndof));
  if (ndof >= nc) {
    PetscCall(number < 0 ? PetscSectionGetOffset(s, P->own[i], &off)
                         : PetscSectionGetFieldOffset(s, P->own[i], number, &off));
    for (PetscInt c = 0; c < nc; ++c) v[c] = a[off + c];
    PetscFunctionReturn(0);
  }
  for (PetscInt c = 0; c < nc; ++c) v[c] = 0;
  for (PetscInt k = 0; k < P->nvert[i]; ++k) {
    const PetscInt q = P->vert[i * MAX_CORNERS + k];
    PetscCall(number < 0 ? PetscSectionGetOffset(s, q, &off) : PetscSectionGetFieldOffset(s, q, number, &off));
    for (PetscInt c = 0; c < nc; ++c) v[c] += a[off + c] / P->nvert[i];
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FieldsGridDestroy(Part *P)
{
  PetscFunctionBeginUser;
  PetscCall(PetscFree(P->own));
  PetscCall(PetscFree(P->nvert));
  PetscCall(PetscFree(P->vert));
  PetscCall(PetscFree(P->index));
  PetscCall(PetscFree(P->cells));
  PetscFunctionReturn(0);
}
