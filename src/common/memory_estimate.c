/* A run's memory, estimated before its meshes are refined, so that a -refine the machine
   cannot hold is refused at once instead of swapping or being killed an hour later. */
#include <stdio.h>
#include <string.h>
#include <sys/resource.h>
#include "memory_estimate.h"
#include "options.h"

/* Bytes per unknown of a subproblem solved by sparse LU (MUMPS), matrices, vectors and mesh
   included, as a power law in the unknowns: nested-dissection fill grows like log N per
   unknown in 2D and like N^(1/3) in 3D. Fitted to the peak resident memory of channel2d,
   turek-hron fsi3 and tube3d on one rank (scripts/memory_estimate.py prints estimate and
   measurement side by side); the 3D exponent is the theoretical one, above the fit, so that
   larger runs are not underestimated. */
static const PetscReal lu_bytes_per_dof[4] = {0, 2.0e3, 8.0e3, 3.4e4}; /* at reference_dofs */
static const PetscReal lu_exponent[4]      = {0, 0.1, 0.15, 1.0 / 3.0};
static const PetscReal reference_dofs      = 5.0e4;
/* Krylov solvers with incomplete or multigrid preconditioners: linear in the unknowns,
   matrices (the fluid's explicit transpose and its field split's blocks included), GAMG's
   hierarchies, vectors and mesh. Above the peaks of channel2d (-refine 1, 2: 3.9e3 and
   5.8e3 bytes per unknown) and tube3d (levels 1-4: 8.4e3 to 13.4e3) with the solver files
   of options/solvers/ (scripts/memory_estimate.py) */
static const PetscReal iterative_bytes_per_dof[4] = {0, 8.0e3, 8.0e3, 1.6e4};
/* PETSc, MPI, HDF5 and libCEED themselves, per rank */
static const PetscReal rank_baseline_bytes = 9.0e7;

static PetscReal promised       = 0; /* this rank's estimate so far, bytes */
static PetscBool baseline_added = PETSC_FALSE;

PetscErrorCode MemoryEstimateDofs(DM coarse, PetscInt refine, const MeshFields *fields, PetscReal *dofs)
{
  PetscInt  dim, depth, cStart, cEnd;
  PetscReal n[4] = {0, 0, 0, 0}, local = 0;
  PetscBool simplex = PETSC_FALSE;

  PetscFunctionBeginUser;
  PetscCall(DMGetDimension(coarse, &dim));
  PetscCall(DMPlexGetDepth(coarse, &depth));
  PetscCall(DMPlexGetHeightStratum(coarse, 0, &cStart, &cEnd));
  {
    PetscInt interpolated = depth == dim, all;
    PetscCallMPI(MPI_Allreduce(&interpolated, &all, 1, MPIU_INT, MPI_MIN, PetscObjectComm((PetscObject)coarse)));
    if (!all) {
      *dofs = -1;
      PetscFunctionReturn(0);
    }
  }
  for (PetscInt d = 0; d <= dim; ++d) {
    PetscInt start, end;
    PetscCall(DMPlexGetDepthStratum(coarse, d, &start, &end));
    n[d] = (PetscReal)(end - start);
  }
  if (cEnd > cStart) {
    DMPolytopeType ct;
    PetscCall(DMPlexGetCellType(coarse, cStart, &ct));
    simplex = (ct == DM_POLYTOPE_TRIANGLE || ct == DM_POLYTOPE_TETRAHEDRON) ? PETSC_TRUE : PETSC_FALSE;
  }
  /* what one uniform refinement adds: every edge gets a vertex, every quadrilateral face a
     vertex and four edges, every cell its interior points */
  for (PetscInt r = 0; r < refine; ++r) {
    PetscReal v = n[0], e = n[1], f = n[2], c = n[3];
    if (dim == 2 && simplex) {
      n[0] = v + e;
      n[1] = 2 * e + 3 * f;
      n[2] = 4 * f;
    } else if (dim == 2) {
      n[0] = v + e + f;
      n[1] = 2 * e + 4 * f;
      n[2] = 4 * f;
    } else if (dim == 3 && simplex) {
      n[0] = v + e;
      n[1] = 2 * e + 3 * f + c;
      n[2] = 4 * f + 8 * c;
      n[3] = 8 * c;
    } else if (dim == 3) {
      n[0] = v + e + f + c;
      n[1] = 2 * e + 4 * f + 6 * c;
      n[2] = 4 * f + 12 * c;
      n[3] = 8 * c;
    } else {
      n[0] = v + e;
      n[1] = 2 * e;
    }
  }
  /* Lagrange nodes of degree k inside a point of dimension j: (k-1)^j on tensor cells,
     binomial(k-1, j) on simplices */
  for (PetscInt i = 0; i < fields->n; ++i) {
    const PetscInt k = fields->degree[i];
    for (PetscInt j = 0; j <= dim; ++j) {
      PetscReal w = 1;
      if (simplex) {
        for (PetscInt m = 0; m < j; ++m) w *= (PetscReal)(k - 1 - m) / (m + 1);
        if (k - 1 < j) w = 0;
      } else w = PetscPowRealInt((PetscReal)(k - 1), j);
      local += (fields->components[i] < 0 ? dim : fields->components[i]) * w * n[j];
    }
  }
  PetscCallMPI(MPI_Allreduce(&local, dofs, 1, MPIU_REAL, MPIU_SUM, PetscObjectComm((PetscObject)coarse)));
  PetscFunctionReturn(0);
}

/* What the node has: the memory the kernel calls available, and below it the cgroup's limit
   (a batch job's allocation) when there is one. */
static PetscReal NodeAvailableBytes(void)
{
  PetscReal available = -1;
  FILE     *fp        = fopen("/proc/meminfo", "r");
  char      line[256];

  if (fp) {
    while (fgets(line, sizeof(line), fp)) {
      double kib;
      if (sscanf(line, "MemAvailable: %lf kB", &kib) == 1) available = 1024.0 * kib;
    }
    fclose(fp);
  }
  fp = fopen("/sys/fs/cgroup/memory.max", "r");
  if (fp) {
    double limit, used = 0;
    if (fscanf(fp, "%lf", &limit) == 1) { /* "max": no limit */
      FILE *cur = fopen("/sys/fs/cgroup/memory.current", "r");
      if (cur) {
        if (fscanf(cur, "%lf", &used) != 1) used = 0;
        fclose(cur);
      }
      if (available < 0 || limit - used < available) available = limit - used;
    }
    fclose(fp);
  }
  return available;
}

static PetscReal SubproblemBytes(const char prefix[], PetscInt dim, PetscReal dofs, PetscBool *direct)
{
  char      option[64], pc[64] = "";
  PetscBool set = PETSC_FALSE;

  (void)PetscSNPrintf(option, sizeof(option), "-%spc_type", prefix);
  (void)PetscOptionsGetString(NULL, NULL, option, pc, sizeof(pc), &set);
  *direct = (!set || !strcmp(pc, "lu") || !strcmp(pc, "cholesky")) ? PETSC_TRUE : PETSC_FALSE;
  if (!*direct) return dofs * iterative_bytes_per_dof[dim];
  return dofs * lu_bytes_per_dof[dim] * PetscPowReal(PetscMax(dofs, 1.0) / reference_dofs, lu_exponent[dim]);
}

/* -force and -memory_per_node_gib, which both checks obey */
static PetscErrorCode ReadNodeLimit(MPI_Comm comm, PetscBool *force, PetscReal *node_gib)
{
  PetscFunctionBeginUser;
  PetscOptionsBegin(comm, NULL, "Memory estimate", "fsiopt");
  PetscCall(PetscOptionsBool("-force", "run even when the estimated memory exceeds what a node has", NULL, *force,
                             force, NULL));
  PetscCall(OptionsNonNegativeReal(PetscOptionsObject, "-memory_per_node_gib",
                                   "memory a node may use, GiB (0: what the node has available)", node_gib));
  PetscOptionsEnd();
  PetscFunctionReturn(0);
}

PetscErrorCode MemoryEstimateAdd(MPI_Comm comm, const char prefix[], PetscInt dim, PetscReal dofs, const char source[])
{
  PetscBool   force    = PETSC_FALSE, direct;
  PetscReal   node_gib = 0, bytes, node_need, node_has, worst[2];
  PetscMPIInt size, node_size, rank;
  MPI_Comm    node;
  char        host[256];

  PetscFunctionBeginUser;
  if (dofs < 0 || dim < 1 || dim > 3) PetscFunctionReturn(0);
  PetscCall(ReadNodeLimit(comm, &force, &node_gib));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  bytes = SubproblemBytes(prefix, dim, dofs, &direct);
  promised += bytes / size;
  if (!baseline_added) promised += rank_baseline_bytes;
  baseline_added = PETSC_TRUE;

  PetscCallMPI(MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node));
  PetscCallMPI(MPI_Comm_size(node, &node_size));
  PetscCallMPI(MPI_Comm_rank(node, &rank));
  PetscCallMPI(MPI_Allreduce(&promised, &node_need, 1, MPIU_REAL, MPIU_SUM, node));
  node_has = node_gib > 0 ? node_gib * 1073741824.0 : NodeAvailableBytes();
  PetscCallMPI(MPI_Bcast(&node_has, 1, MPIU_REAL, 0, node));
  PetscCallMPI(MPI_Comm_free(&node));
  /* the node that is shortest of memory, relative to its need, speaks */
  {
    struct {
      double ratio;
      int    rank;
    } mine, first;
    PetscMPIInt world_rank;
    PetscReal   report[3];

    PetscCallMPI(MPI_Comm_rank(comm, &world_rank));
    mine.ratio = node_has > 0 ? node_need / node_has : 0;
    mine.rank  = world_rank;
    PetscCallMPI(MPI_Allreduce(&mine, &first, 1, MPI_DOUBLE_INT, MPI_MAXLOC, comm));
    if (first.ratio <= 1) PetscFunctionReturn(0);
    report[0] = node_need;
    report[1] = node_has;
    report[2] = node_size;
    PetscCall(PetscGetHostName(host, sizeof(host)));
    PetscCallMPI(MPI_Bcast(report, 3, MPIU_REAL, first.rank, comm));
    PetscCallMPI(MPI_Bcast(host, sizeof(host), MPI_CHAR, first.rank, comm));
    worst[0] = report[0] / 1073741824.0;
    worst[1] = report[1] / 1073741824.0;
    if (force) {
      PetscCall(PetscPrintf(comm,
                            "fsiopt: notice: -force: %s: estimated memory %.3g GiB for the %d rank(s) on %s, which has "
                            "%.3g GiB\n",
                            source, (double)worst[0], (int)report[2], host, (double)worst[1]));
      PetscFunctionReturn(0);
    }
    SETERRQ(comm, PETSC_ERR_MEM,
            "%s: estimated memory %.3g GiB for the %d rank(s) on %s (%.3g million unknowns on this mesh, %s), more "
            "than the %.3g GiB it has%s; use fewer refinements or more nodes, or add -force",
            source, (double)worst[0], (int)report[2], host, (double)(dofs / 1e6),
            direct ? "LU factors" : "Krylov solvers", (double)worst[1],
            node_gib > 0 ? " (-memory_per_node_gib)" : " available");
  }
  PetscFunctionReturn(0);
}

PetscErrorCode MemoryEstimateGetTotals(PetscReal *estimate, PetscReal *peak)
{
  struct rusage usage;
  PetscReal     mine[2] = {promised, 0}, sum[2];

  PetscFunctionBeginUser;
  if (getrusage(RUSAGE_SELF, &usage) == 0) mine[1] = 1024.0 * (PetscReal)usage.ru_maxrss;
  PetscCallMPI(MPI_Allreduce(mine, sum, 2, MPIU_REAL, MPIU_SUM, PETSC_COMM_WORLD));
  *estimate = sum[0];
  *peak     = sum[1];
  PetscFunctionReturn(0);
}

/* Peak resident bytes per mesh point (cell, face, edge, vertex) while DMPlex builds a box on one
   rank and labels its faces: channel2d's fluid box of 2000 x 2000 cells (16.0 million points)
   peaked at 1.96 GB, 117 bytes per point above the run's baseline. */
static const PetscReal box_bytes_per_point = 120.0;

PetscErrorCode MemoryEstimateCheckMeshPoints(MPI_Comm comm, const char source[], PetscReal points)
{
  PetscBool force    = PETSC_FALSE;
  PetscReal node_gib = 0, has, need = points * box_bytes_per_point; /* the baseline is MemoryEstimateAdd's */

  PetscFunctionBeginUser;
  PetscCheck(points <= (PetscReal)PETSC_MAX_INT, comm, PETSC_ERR_ARG_OUTOFRANGE,
             "%s: %.3g mesh points (cells, faces, edges, vertices), more than PETSc's integers number (at most %d)",
             source, (double)points, (int)PETSC_MAX_INT);
  PetscCall(ReadNodeLimit(comm, &force, &node_gib));
  has = node_gib > 0 ? node_gib * 1073741824.0 : NodeAvailableBytes();
  PetscCallMPI(MPI_Bcast(&has, 1, MPIU_REAL, 0, comm));
  PetscCheck(force || has <= 0 || need <= has, comm, PETSC_ERR_MEM,
             "%s: building it on one rank takes about %.3g GiB (%.3g million mesh points), more than the %.3g GiB "
             "available%s; use fewer cells, or add -force",
             source, (double)(need / 1073741824.0), (double)(points / 1e6), (double)(has / 1073741824.0),
             node_gib > 0 ? " (-memory_per_node_gib)" : "");
  PetscFunctionReturn(0);
}

PetscReal MemoryEstimateThisRank(void)
{
  return promised;
}
