/* A sparse J0 of the interface Jacobian by probing (Chan and Mathew 1992, "The interface
   probing technique in domain decomposition"; Curtis, Powell and Reid 1974 for the
   colouring). Where a step's response to a traction is local, J's 3 x 3 blocks fall fast
   with the distance between two interface nodes: at small time steps the wall answers as a
   mass and the fluid next to it as the mass of its first cells (tube3d, a pressure wave).
   J's blocks between each node and its neighbours within `rings` rings (nodes that share an
   interface face are one ring apart) then come from a few products: the nodes are coloured
   so that two nodes within 2 x rings rings of each other differ, and one product per colour
   and component, J sum_{j of colour c} e_(j,k), holds the column (j,k) of every node j of
   that colour in the rows of j's neighbours. The number of colours depends on the
   interface's connectivity, not on its size, if the colouring is good enough (below): the
   build's cost per control then does not grow with the mesh, where the dense J0 costs a
   product per control. The blocks it leaves out are the preconditioner's error: GMRES's
   iterations with it, against none and against the dense J0, are in
   docs/coupling-and-solvers.md.
   The colouring and the pattern are computed on every rank alike from the interface's
   whole graph (two integers per pair of neighbours). */
#include "problem_impl.h"
#include "fem.h"

#define PROBING_RECOLOUR_PASSES 50

struct _p_InterfaceProbing {
  PetscInt  dim, nlocal, nglobal, first; /* control nodes: this rank's, all, this rank's first */
  PetscInt  ncolors, *color;             /* by global control node */
  PetscInt *pattern_offset, *pattern;    /* this rank's nodes' neighbours (themselves too), global */
  Mat       units, images;               /* a build's work blocks, one width */
  MPI_Comm  comm;                        /* the ranks that hold controls (MPI_COMM_NULL elsewhere): J0's */
};

/* The global control node of each of this rank's interface nodes (-1: not a control), on
   every point of the fluid mesh that carries one, ghosts included: a local vector of a
   scalar space without constraints, as value + 1 (0: none). */
static PetscErrorCode ControlNodeIds(CouplingProblem P, PetscInt dim, PetscInt first, DM fluid, PetscInt degree,
                                     DM *dm_ids, Vec *ids)
{
  Vec                all, control, global;
  PetscSection       section;
  const PetscInt    *points;
  const PetscScalar *a;
  PetscScalar       *c, *v;
  PetscInt           n, nc;

  PetscFunctionBeginUser;
  PetscCall(InterfaceCreateVector(P->itf, &all));
  PetscCall(InterfaceCreateControlVector(P->itf, &control));
  PetscCall(VecGetLocalSize(control, &nc));
  PetscCall(VecGetArrayWrite(control, &c));
  for (PetscInt i = 0; i < nc; ++i) c[i] = first + i / dim + 1;
  PetscCall(VecRestoreArrayWrite(control, &c));
  PetscCall(InterfaceExtend(P->itf, control, all));
  PetscCall(DMClone(fluid, dm_ids));
  PetscCall(FEMCreateField(*dm_ids, 0, "probing_node", 1, degree, NULL));
  PetscCall(DMCreateDS(*dm_ids));
  PetscCall(DMGetLocalSection(*dm_ids, &section));
  PetscCall(DMCreateLocalVector(*dm_ids, ids));
  PetscCall(DMCreateGlobalVector(*dm_ids, &global));
  PetscCall(VecZeroEntries(*ids));
  PetscCall(InterfaceGetFluidNodes(P->itf, &n, &points, NULL));
  PetscCall(VecGetArrayRead(all, &a));
  PetscCall(VecGetArray(*ids, &v));
  for (PetscInt i = 0; i < n; ++i) {
    PetscInt off;
    PetscCall(PetscSectionGetOffset(section, points[i], &off));
    v[off] = a[i * dim];
  }
  PetscCall(VecRestoreArray(*ids, &v));
  PetscCall(VecRestoreArrayRead(all, &a));
  PetscCall(FEMSumOverRanks(*dm_ids, *ids, global)); /* the owner's value to every copy */
  PetscCall(VecDestroy(&global));
  PetscCall(VecDestroy(&all));
  PetscCall(VecDestroy(&control));
  PetscFunctionReturn(0);
}

/* This rank's pairs of control nodes that share an interface face, both ways */
static PetscErrorCode LocalPairs(CouplingProblem P, PetscInt dim, PetscInt first, PetscInt *npairs, PetscInt **pairs)
{
  DM           fluid, dm_ids;
  Vec          ids;
  PetscSection section;
  PetscFE      velocity;
  PetscSpace   space;
  PetscInt     degree, capacity = 0, count = 0, *list = NULL;
  DMLabel      label;
  IS           faces;

  PetscFunctionBeginUser;
  *npairs = 0;
  *pairs  = NULL;
  if (!P->fluid) PetscFunctionReturn(0);
  PetscCall(FluidGetDM(P->fluid, &fluid));
  PetscCall(DMGetField(fluid, 0, NULL, (PetscObject *)&velocity));
  PetscCall(PetscFEGetBasisSpace(velocity, &space));
  PetscCall(PetscSpaceGetDegree(space, &degree, NULL));
  PetscCall(ControlNodeIds(P, dim, first, fluid, degree, &dm_ids, &ids));
  PetscCall(DMGetLocalSection(dm_ids, &section));
  PetscCall(DMGetLabel(fluid, "Face Sets", &label));
  PetscCall(DMLabelGetStratumIS(label, P->fluid_data.interface_face, &faces));
  if (faces) {
    const PetscInt    *f;
    const PetscScalar *v;
    PetscInt           nf;
    PetscCall(ISGetLocalSize(faces, &nf));
    PetscCall(ISGetIndices(faces, &f));
    PetscCall(VecGetArrayRead(ids, &v));
    for (PetscInt i = 0; i < nf; ++i) {
      PetscInt *closure = NULL, nclosure, nodes[64], nn = 0, nsupport;
      PetscCall(DMPlexGetSupportSize(fluid, f[i], &nsupport));
      if (nsupport != 1) continue; /* a boundary face lives on its cell's rank only */
      PetscCall(DMPlexGetTransitiveClosure(fluid, f[i], PETSC_TRUE, &nclosure, &closure));
      for (PetscInt k = 0; k < nclosure; ++k) {
        PetscInt dof, off;
        PetscCall(PetscSectionGetDof(section, closure[2 * k], &dof));
        if (dof <= 0) continue;
        PetscCall(PetscSectionGetOffset(section, closure[2 * k], &off));
        if (PetscRealPart(v[off]) > 0.5 && nn < 64) nodes[nn++] = (PetscInt)(PetscRealPart(v[off]) + 0.5) - 1;
      }
      PetscCall(DMPlexRestoreTransitiveClosure(fluid, f[i], PETSC_TRUE, &nclosure, &closure));
      if (count + 2 * nn * nn > capacity) {
        capacity = 2 * (count + 2 * nn * nn) + 1024;
        PetscCall(PetscRealloc(capacity * sizeof(PetscInt), &list));
      }
      for (PetscInt a = 0; a < nn; ++a)
        for (PetscInt b = 0; b < nn; ++b)
          if (a != b) {
            list[count++] = nodes[a];
            list[count++] = nodes[b];
          }
    }
    PetscCall(VecRestoreArrayRead(ids, &v));
    PetscCall(ISRestoreIndices(faces, &f));
    PetscCall(ISDestroy(&faces));
  }
  PetscCall(VecDestroy(&ids));
  PetscCall(DMDestroy(&dm_ids));
  *npairs = count / 2;
  *pairs  = list;
  PetscFunctionReturn(0);
}

/* Every rank's pairs, on every rank, as the graph's adjacency (CSR, sorted, no repeats) */
static PetscErrorCode GatherGraph(MPI_Comm comm, PetscInt nnodes, PetscInt npairs, const PetscInt pairs[],
                                  PetscInt **offset, PetscInt **adjacency)
{
  PetscMPIInt size, mine = (PetscMPIInt)(2 * npairs), *counts, *displs;
  PetscInt   *all, total = 0, *degree;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(PetscMalloc2(size, &counts, size, &displs));
  PetscCallMPI(MPI_Allgather(&mine, 1, MPI_INT, counts, 1, MPI_INT, comm));
  for (PetscMPIInt r = 0; r < size; ++r) {
    displs[r] = (PetscMPIInt)total;
    total += counts[r];
  }
  PetscCall(PetscMalloc1(total + 1, &all));
  PetscCallMPI(MPI_Allgatherv(pairs, mine, MPIU_INT, all, counts, displs, MPIU_INT, comm));
  PetscCall(PetscCalloc1(nnodes + 1, &degree));
  PetscCall(PetscCalloc1(nnodes + 1, offset));
  for (PetscInt p = 0; p < total; p += 2) (*offset)[all[p] + 1]++;
  for (PetscInt v = 0; v < nnodes; ++v) (*offset)[v + 1] += (*offset)[v];
  PetscCall(PetscMalloc1((*offset)[nnodes] + 1, adjacency));
  for (PetscInt p = 0; p < total; p += 2) (*adjacency)[(*offset)[all[p]] + degree[all[p]]++] = all[p + 1];
  {
    /* sort and drop repeats (a pair of nodes shares up to two faces), compacting in place */
    PetscInt kept = 0;
    for (PetscInt v = 0; v < nnodes; ++v) {
      PetscInt start = (*offset)[v], n = degree[v];
      PetscCall(PetscSortRemoveDupsInt(&n, *adjacency + start));
      for (PetscInt k = 0; k < n; ++k) (*adjacency)[kept + k] = (*adjacency)[start + k];
      (*offset)[v] = kept;
      kept += n;
    }
    (*offset)[nnodes] = kept;
  }
  PetscCall(PetscFree(degree));
  PetscCall(PetscFree(all));
  PetscCall(PetscFree2(counts, displs));
  PetscFunctionReturn(0);
}

/* The nodes within `depth` rings of v (v itself first), by breadth-first search; `stamp` marks
   visits with the value `mark` */
static PetscErrorCode Ball(const PetscInt offset[], const PetscInt adjacency[], PetscInt v, PetscInt depth,
                           PetscInt mark, PetscInt stamp[], PetscInt *n, PetscInt queue[])
{
  PetscInt head = 0, level_end;

  PetscFunctionBeginUser;
  queue[0]  = v;
  stamp[v]  = mark;
  *n        = 1;
  level_end = 1;
  for (PetscInt level = 0; level < depth; ++level) {
    const PetscInt end = level_end;
    for (; head < end; ++head)
      for (PetscInt k = offset[queue[head]]; k < offset[queue[head] + 1]; ++k)
        if (stamp[adjacency[k]] != mark) {
          stamp[adjacency[k]] = mark;
          queue[(*n)++]       = adjacency[k];
        }
    level_end = *n;
  }
  PetscFunctionReturn(0);
}

/* The nodes in breadth-first order, each connected part from its lowest node (stamp: work,
   left at -2 for every node) */
static PetscErrorCode BreadthFirstOrder(PetscInt n, const PetscInt offset[], const PetscInt adjacency[],
                                        PetscInt order[], PetscInt stamp[])
{
  PetscInt head = 0, tail = 0;

  PetscFunctionBeginUser;
  for (PetscInt v = 0; v < n; ++v) stamp[v] = -1;
  for (PetscInt start = 0; start < n; ++start) {
    if (stamp[start] == -2) continue;
    stamp[start]  = -2;
    order[tail++] = start;
    for (; head < tail; ++head)
      for (PetscInt k = offset[order[head]]; k < offset[order[head] + 1]; ++k)
        if (stamp[adjacency[k]] != -2) {
          stamp[adjacency[k]] = -2;
          order[tail++]       = adjacency[k];
        }
  }
  PetscFunctionReturn(0);
}

/* Greedy colouring in `order`: each node takes the smallest colour no node within `distance`
   rings has (Ball's marks from `mark`, one per node) */
static PetscErrorCode GreedyColour(PetscInt n, const PetscInt offset[], const PetscInt adjacency[], PetscInt distance,
                                   const PetscInt order[], PetscInt mark, PetscInt stamp[], PetscInt queue[],
                                   PetscInt used[], PetscInt color[], PetscInt *ncolors)
{
  PetscInt m;

  PetscFunctionBeginUser;
  for (PetscInt v = 0; v < n; ++v) color[v] = -1;
  *ncolors = 0;
  for (PetscInt i = 0; i < n; ++i) {
    const PetscInt v = order[i];
    PetscCall(Ball(offset, adjacency, v, distance, mark + v, stamp, &m, queue));
    for (PetscInt k = 0; k <= m; ++k) used[k] = 0;
    for (PetscInt k = 1; k < m; ++k)
      if (color[queue[k]] >= 0 && color[queue[k]] <= m) used[color[queue[k]]] = 1;
    color[v] = 0;
    while (used[color[v]]) color[v]++;
    *ncolors = PetscMax(*ncolors, color[v] + 1);
  }
  PetscFunctionReturn(0);
}

PetscErrorCode CouplingProblemCreateProbing(CouplingProblem P, PetscInt rings, InterfaceProbing *probing)
{
  InterfaceProbing ip;
  Vec              control;
  PetscInt         npairs, *pairs, *offset, *adjacency, *stamp, *queue, *used, *order, *previous, n, rstart;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&ip));
  PetscCall(InterfaceCreateControlVector(P->itf, &control));
  PetscCall(VecGetBlockSize(control, &ip->dim)); /* the interface's dimension (interface.c) */
  PetscCall(VecGetLocalSize(control, &ip->nlocal));
  PetscCall(VecGetSize(control, &ip->nglobal));
  PetscCall(VecGetOwnershipRange(control, &rstart, NULL));
  ip->nlocal /= ip->dim;
  ip->nglobal /= ip->dim;
  ip->first = rstart / ip->dim;
  PetscCall(VecDestroy(&control));
  {
    /* J0 and its factors live on the ranks that hold controls: a parallel sparse LU with a rank
       that owns no row of it (a structure's own rank) waits for it in its solves */
    PetscMPIInt rank;
    PetscCallMPI(MPI_Comm_rank(P->comm, &rank));
    PetscCallMPI(MPI_Comm_split(P->comm, ip->nlocal > 0 ? 0 : MPI_UNDEFINED, rank, &ip->comm));
  }
  PetscCall(LocalPairs(P, ip->dim, ip->first, &npairs, &pairs));
  PetscCall(GatherGraph(P->comm, ip->nglobal, npairs, pairs, &offset, &adjacency));
  PetscCall(PetscFree(pairs));
  PetscCall(PetscMalloc1(ip->nglobal, &stamp));
  PetscCall(PetscMalloc1(ip->nglobal, &queue));
  PetscCall(PetscMalloc1(ip->nglobal + 1, &used));
  for (PetscInt v = 0; v < ip->nglobal; ++v) stamp[v] = -1;
  /* greedy colouring, the nodes first in breadth-first order (which does not depend on the
     mesh's numbering), then again and again with the colour classes in reverse order
     (Culberson's iterated greedy: never more colours, often fewer). tube3d levels 1-4, two
     rings: 28, 31, 33, 32 colours, where the first pass alone gave 30, 35, 40, 45 and PETSc's
     MatColoring of the rings' pattern at distance 2 (sl, lf, id) 31-45, 30-41, 33-44; 200
     passes gave no fewer than 50 */
  PetscCall(PetscMalloc1(ip->nglobal, &ip->color));
  PetscCall(PetscMalloc1(ip->nglobal, &order));
  PetscCall(PetscMalloc1(ip->nglobal, &previous));
  PetscCall(BreadthFirstOrder(ip->nglobal, offset, adjacency, order, stamp));
  PetscCall(GreedyColour(ip->nglobal, offset, adjacency, 2 * rings, order, ip->nglobal, stamp, queue, used, ip->color,
                         &ip->ncolors));
  for (PetscInt pass = 0; pass < PROBING_RECOLOUR_PASSES; ++pass) {
    PetscInt k = 0;
    PetscCall(PetscArraycpy(previous, order, ip->nglobal));
    for (PetscInt c = ip->ncolors - 1; c >= 0; --c)
      for (PetscInt i = 0; i < ip->nglobal; ++i)
        if (ip->color[previous[i]] == c) order[k++] = previous[i];
    PetscCall(GreedyColour(ip->nglobal, offset, adjacency, 2 * rings, order, (pass + 2) * ip->nglobal, stamp, queue,
                           used, ip->color, &ip->ncolors));
  }
  for (PetscInt v = 0; v < ip->nglobal; ++v) stamp[v] = -1; /* the marks below start afresh */
  PetscCall(PetscFree(previous));
  PetscCall(PetscFree(order));
  /* this rank's nodes' pattern: their neighbours within `rings` rings */
  PetscCall(PetscMalloc1(ip->nlocal + 1, &ip->pattern_offset));
  ip->pattern_offset[0] = 0;
  ip->pattern           = NULL;
  {
    PetscInt capacity = 0;
    for (PetscInt q = 0; q < ip->nlocal; ++q) {
      PetscCall(Ball(offset, adjacency, ip->first + q, rings, ip->nglobal + ip->first + q, stamp, &n, queue));
      if (ip->pattern_offset[q] + n > capacity) {
        capacity = 2 * (ip->pattern_offset[q] + n) + 64;
        PetscCall(PetscRealloc(capacity * sizeof(PetscInt), &ip->pattern));
      }
      PetscCall(PetscArraycpy(ip->pattern + ip->pattern_offset[q], queue, n));
      ip->pattern_offset[q + 1] = ip->pattern_offset[q] + n;
    }
  }
  PetscCall(PetscFree(stamp));
  PetscCall(PetscFree(queue));
  PetscCall(PetscFree(used));
  PetscCall(PetscFree(offset));
  PetscCall(PetscFree(adjacency));
  *probing = ip;
  PetscFunctionReturn(0);
}

PetscErrorCode InterfaceProbingGetColors(InterfaceProbing ip, PetscInt *ncolors)
{
  PetscFunctionBeginUser;
  *ncolors = ip->ncolors;
  PetscFunctionReturn(0);
}

PetscErrorCode InterfaceProbingCreateMatrix(InterfaceProbing ip, Mat *J0)
{
  const PetscInt dim = ip->dim, last = ip->first + ip->nlocal;
  PetscInt      *d_nnz, *o_nnz;

  PetscFunctionBeginUser;
  *J0 = NULL;
  if (ip->comm == MPI_COMM_NULL) PetscFunctionReturn(0);
  PetscCall(PetscCalloc2(ip->nlocal * dim, &d_nnz, ip->nlocal * dim, &o_nnz));
  for (PetscInt q = 0; q < ip->nlocal; ++q)
    for (PetscInt k = ip->pattern_offset[q]; k < ip->pattern_offset[q + 1]; ++k)
      for (PetscInt a = 0; a < dim; ++a) {
        if (ip->pattern[k] >= ip->first && ip->pattern[k] < last) d_nnz[q * dim + a] += dim;
        else o_nnz[q * dim + a] += dim;
      }
  PetscCall(MatCreateAIJ(ip->comm, ip->nlocal * dim, ip->nlocal * dim, ip->nglobal * dim, ip->nglobal * dim, 0, d_nnz, 0,
                         o_nnz, J0));
  PetscCall(MatSetBlockSize(*J0, dim));
  PetscCall(MatSetOption(*J0, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE));
  PetscCall(PetscFree2(d_nnz, o_nnz));
  PetscFunctionReturn(0);
}

/* J0's entries from products of J with the colours' unit loads, in multi-right-hand-side
   blocks of at most `block` columns, all of one width */
PetscErrorCode InterfaceProbingBuild(InterfaceProbing ip, Mat J, PetscInt block, Mat J0)
{
  const PetscInt dim = ip->dim, ncolumns = ip->ncolors * dim;
  const PetscInt nblocks = (ncolumns + block - 1) / block, width = (ncolumns + nblocks - 1) / nblocks;

  PetscFunctionBeginUser;
  if (!ip->units)
    PetscCall(MatCreateDense(PetscObjectComm((PetscObject)J), ip->nlocal * dim, PETSC_DECIDE, ip->nglobal * dim, width,
                             NULL, &ip->units));
  for (PetscInt first = 0; first < ncolumns; first += width) {
    const PetscScalar *image;
    PetscInt           lda, rstart;

    PetscCall(MatZeroEntries(ip->units));
    PetscCall(MatGetOwnershipRange(ip->units, &rstart, NULL));
    for (PetscInt q = 0; q < ip->nlocal; ++q)
      for (PetscInt k = 0; k < dim; ++k) {
        const PetscInt column = ip->color[ip->first + q] * dim + k;
        if (column >= first && column < first + width)
          PetscCall(MatSetValue(ip->units, rstart + q * dim + k, column - first, 1.0, INSERT_VALUES));
      }
    PetscCall(MatAssemblyBegin(ip->units, MAT_FINAL_ASSEMBLY));
    PetscCall(MatAssemblyEnd(ip->units, MAT_FINAL_ASSEMBLY));
    PetscCall(MatMatMult(J, ip->units, ip->images ? MAT_REUSE_MATRIX : MAT_INITIAL_MATRIX, PETSC_DEFAULT, &ip->images));
    PetscCall(MatDenseGetLDA(ip->images, &lda));
    PetscCall(MatDenseGetArrayRead(ip->images, &image));
    for (PetscInt q = 0; q < ip->nlocal; ++q)
      for (PetscInt p = ip->pattern_offset[q]; p < ip->pattern_offset[q + 1]; ++p) {
        const PetscInt j = ip->pattern[p];
        for (PetscInt k = 0; k < dim; ++k) {
          const PetscInt column = ip->color[j] * dim + k, col = j * dim + k;
          if (column < first || column >= first + width) continue;
          for (PetscInt a = 0; a < dim; ++a) {
            const PetscInt row = rstart + q * dim + a;
            PetscCall(MatSetValue(J0, row, col, image[(q * dim + a) + lda * (column - first)], INSERT_VALUES));
          }
        }
      }
    PetscCall(MatDenseRestoreArrayRead(ip->images, &image));
  }
  if (J0) {
    PetscCall(MatAssemblyBegin(J0, MAT_FINAL_ASSEMBLY));
    PetscCall(MatAssemblyEnd(J0, MAT_FINAL_ASSEMBLY));
  }
  PetscFunctionReturn(0);
}

PetscErrorCode InterfaceProbingDestroy(InterfaceProbing *probing)
{
  InterfaceProbing ip = *probing;

  PetscFunctionBeginUser;
  if (!ip) PetscFunctionReturn(0);
  PetscCall(PetscFree(ip->color));
  PetscCall(PetscFree(ip->pattern_offset));
  PetscCall(PetscFree(ip->pattern));
  PetscCall(MatDestroy(&ip->units));
  PetscCall(MatDestroy(&ip->images));
  if (ip->comm != MPI_COMM_NULL) PetscCallMPI(MPI_Comm_free(&ip->comm));
  PetscCall(PetscFree(*probing));
  PetscFunctionReturn(0);
}
