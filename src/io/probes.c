#include "probes.h"
#include "output.h"

struct _p_Probes {
  MPI_Comm   comm;
  PetscInt   n, dim;
  VecScatter to_zero;
  Vec        values; /* on rank 0: n * dim */
  PartialFile file;
};

PetscErrorCode ProbesCreate(MPI_Comm comm, Interface itf, PetscInt n, const PetscReal points[][3], const char dir[], Probes *probes)
{
  Probes           P;
  PetscInt         nlocal, dim, start, *index;
  const PetscReal *coords;
  Vec              all;
  IS               from;
  PetscMPIInt      rank;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&P));
  P->comm = comm;
  P->n    = n;
  PetscCall(InterfaceCreateVector(itf, &all));
  PetscCall(VecGetBlockSize(all, &dim));
  P->dim = dim;
  PetscCall(VecGetOwnershipRange(all, &start, NULL));
  PetscCall(InterfaceGetFluidNodes(itf, &nlocal, NULL, &coords));
  PetscCall(PetscMalloc1(n * dim, &index));
  for (PetscInt p = 0; p < n; ++p) {
    PetscInt found = -1;
    for (PetscInt i = 0; i < nlocal && found < 0; ++i) {
      PetscReal dist = 0;
      for (PetscInt d = 0; d < dim; ++d) dist = PetscMax(dist, PetscAbsReal(coords[i * dim + d] - points[p][d]));
      if (dist < 1e-6) found = start + i * dim; /* gmsh places nodes on arcs to about 1e-9 */
    }
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &found, 1, MPIU_INT, MPI_MAX, comm));
    PetscCheck(found >= 0, comm, PETSC_ERR_ARG_WRONG, "probe (%g, %g, %g): not a node of the fluid-structure interface", (double)points[p][0], (double)points[p][1], (double)(dim == 3 ? points[p][2] : 0));
    for (PetscInt d = 0; d < dim; ++d) index[p * dim + d] = found + d;
  }
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(VecCreateSeq(PETSC_COMM_SELF, rank ? 0 : n * dim, &P->values));
  PetscCall(ISCreateGeneral(comm, rank ? 0 : n * dim, index, PETSC_COPY_VALUES, &from));
  PetscCall(VecScatterCreate(all, from, P->values, NULL, &P->to_zero));
  PetscCall(ISDestroy(&from));
  PetscCall(PetscFree(index));
  PetscCall(VecDestroy(&all));
  PetscCall(PartialFileOpen(comm, dir, "probes.csv", &P->file));
  PetscCall(PetscFPrintf(comm, P->file.fp, "t"));
  for (PetscInt p = 0; p < n; ++p)
    for (PetscInt d = 0; d < dim; ++d) {
      if (dim == 3) PetscCall(PetscFPrintf(comm, P->file.fp, ",d%c(%g;%g;%g)", "xyz"[d], (double)points[p][0], (double)points[p][1], (double)points[p][2]));
      else PetscCall(PetscFPrintf(comm, P->file.fp, ",d%c(%g;%g)", "xyz"[d], (double)points[p][0], (double)points[p][1]));
    }
  PetscCall(PetscFPrintf(comm, P->file.fp, "\n"));
  *probes = P;
  PetscFunctionReturn(0);
}

PetscErrorCode ProbesRecord(Probes P, PetscReal t, Vec displacement)
{
  const PetscScalar *v;
  PetscMPIInt        rank;

  PetscFunctionBeginUser;
  PetscCall(VecScatterBegin(P->to_zero, displacement, P->values, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(P->to_zero, displacement, P->values, INSERT_VALUES, SCATTER_FORWARD));
  PetscCallMPI(MPI_Comm_rank(P->comm, &rank));
  PetscCall(PetscFPrintf(P->comm, P->file.fp, "%.10g", (double)t));
  PetscCall(VecGetArrayRead(P->values, &v));
  if (!rank)
    for (PetscInt i = 0; i < P->n * P->dim; ++i) PetscCall(PetscFPrintf(PETSC_COMM_SELF, P->file.fp, ",%.12e", (double)PetscRealPart(v[i])));
  PetscCall(VecRestoreArrayRead(P->values, &v));
  PetscCall(PetscFPrintf(P->comm, P->file.fp, "\n"));
  PetscFunctionReturn(0);
}

PetscErrorCode ProbesClose(Probes *probes, PetscBool complete)
{
  Probes P = *probes;

  PetscFunctionBeginUser;
  if (!P) PetscFunctionReturn(0);
  PetscCall(PartialFileClose(&P->file, complete));
  PetscCall(VecScatterDestroy(&P->to_zero));
  PetscCall(VecDestroy(&P->values));
  PetscCall(PetscFree(*probes));
  PetscFunctionReturn(0);
}
