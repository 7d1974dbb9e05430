/* Conforming interface maps: nodes by coordinates, the interface mass matrix, traces
   and their adjoints, and the transfer between the fluid's and the structure's
   orderings on the parent communicator. */
#include "interface_impl.h"
#include "options.h"

#pragma GCC diagnostic ignored "-Wunused-parameter"

const char *const InterfaceLumpings[] = {"auto", "row-sum", "hrz", "InterfaceLumping", "INTERFACE_LUMPING_", NULL};

static void MassG0(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[],
                   const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], const PetscInt aOff[],
                   const PetscInt aOff_x[], const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[],
                   PetscReal t, PetscReal u_tShift, const PetscReal x[], const PetscReal n[], PetscInt numConstants,
                   const PetscScalar constants[], PetscScalar g0[])
{
  for (PetscInt c = 0; c < dim; ++c) g0[c * dim + c] = 1.0;
}

/* The interface mass matrix, assembled as a boundary bilinear form on the fluid's velocity
   space without constraints (test and trial functions share PETSc's face tabulation, so
   reversed faces are integrated exactly), then restricted to the interface rows. */
static PetscErrorCode InterfaceAssembleMass(Interface itf, DM fluid, PetscInt face)
{
  Mat mass_fluid = NULL;

  PetscFunctionBeginUser;
  if (fluid) {
    DM            dm;
    PetscObject   fe;
    PetscDS       ds;
    PetscWeakForm wf;
    DMLabel       label;
    PetscInt      bd, *rows;
    PetscSection  gs;
    Mat           full = NULL;
    Vec           zero = NULL;
    IS            is;
    FEMBackend    backend;
    PetscBool     check;

    PetscCall(DMClone(fluid, &dm));
    PetscCall(DMGetField(fluid, 0, NULL, &fe));
    PetscCall(DMSetField(dm, 0, NULL, fe));
    PetscCall(DMCreateDS(dm));
    PetscCall(DMGetLabel(dm, "Face Sets", &label));
    PetscCall(DMAddBoundary(dm, DM_BC_NATURAL, "interface", label, 1, &face, 0, 0, NULL, NULL, NULL, NULL, &bd));
    PetscCall(DMGetDS(dm, &ds));
    PetscCall(PetscDSGetBoundary(ds, bd, &wf, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL));
    PetscCall(PetscWeakFormAddBdJacobian(wf, label, face, 0, 0, 0, MassG0, NULL, NULL, NULL));
    PetscCall(FEMBackendGet(&backend, &check));
    /* libCEED's face operator: a matrix of the faces' entries only; PETSc's integration
       preallocates the whole velocity matrix first (11 s of tube3d level 2's set-up) */
    if (backend == FEM_BACKEND_CEED || check) PetscCall(FEMCeedFaceMass(dm, label, face, &full));
    if (backend == FEM_BACKEND_PETSC || check) {
      Mat petsc;
      PetscCall(DMCreateMatrix(dm, &petsc));
      PetscCall(DMCreateLocalVector(dm, &zero));
      PetscCall(VecZeroEntries(zero));
      /* the faces alone: the whole-mesh Jacobian would visit every cell for nothing */
      PetscCall(DMPlexComputeBdJacobianSingle(dm, 0.0, wf, label, 1, &face, 0, zero, NULL, 0.0, petsc, petsc));
      PetscCall(MatAssemblyBegin(petsc, MAT_FINAL_ASSEMBLY));
      PetscCall(MatAssemblyEnd(petsc, MAT_FINAL_ASSEMBLY));
      if (full) {
        PetscReal difference;
        Mat       copy;
        PetscCall(MatDuplicate(full, MAT_COPY_VALUES, &copy));
        PetscCall(FEMCeedMatDifference(copy, petsc, &difference));
        PetscCall(PetscPrintf(PetscObjectComm((PetscObject)dm),
                              "fsiopt: backend check: interface mass %.2e, libCEED relative to PETSc\n",
                              (double)difference));
        PetscCheck(difference <= FEM_BACKEND_CHECK_TOL, PetscObjectComm((PetscObject)dm), PETSC_ERR_PLIB,
                   "-fem_backend_check: the interface mass differs from PETSc's by %.1e, above %.0e",
                   (double)difference, (double)FEM_BACKEND_CHECK_TOL);
        PetscCall(MatDestroy(&copy));
        if (backend == FEM_BACKEND_PETSC) { /* the backend's own */
          PetscCall(MatDestroy(&full));
          full = petsc;
        } else PetscCall(MatDestroy(&petsc));
      } else full = petsc;
    }
    PetscCall(DMGetGlobalSection(dm, &gs));
    PetscCall(PetscMalloc1(itf->fluid.n * itf->dim, &rows));
    for (PetscInt i = 0; i < itf->fluid.n; ++i) {
      PetscInt goff;
      PetscCall(PetscSectionGetOffset(gs, itf->fluid.point[i], &goff));
      for (PetscInt c = 0; c < itf->dim; ++c) rows[i * itf->dim + c] = goff + c;
    }
    PetscCall(ISCreateGeneral(PetscObjectComm((PetscObject)dm), itf->fluid.n * itf->dim, rows, PETSC_OWN_POINTER, &is));
    PetscCall(MatCreateSubMatrix(full, is, is, MAT_INITIAL_MATRIX, &mass_fluid));
    PetscCall(ISDestroy(&is));
    PetscCall(MatDestroy(&full));
    PetscCall(VecDestroy(&zero));
    PetscCall(DMDestroy(&dm));
  }
  {
    PetscMPIInt cmp = MPI_UNEQUAL;
    if (fluid) PetscCallMPI(MPI_Comm_compare(PetscObjectComm((PetscObject)fluid), itf->comm, &cmp));
    if (fluid && (cmp == MPI_IDENT || cmp == MPI_CONGRUENT)) {
      itf->mass = mass_fluid;
      PetscFunctionReturn(0);
    }
  }
  /* The fluid has its own ranks, the first of the parent communicator: the same global
     numbering holds there, so the rows move over as they are. */
  {
    PetscInt n, N, rstart, rend;

    PetscCall(VecGetLocalSize(itf->all, &n));
    PetscCall(VecGetSize(itf->all, &N));
    PetscCall(MatCreateAIJ(itf->comm, n, n, N, N, 27, NULL, 27, NULL, &itf->mass));
    PetscCall(MatSetOption(itf->mass, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_FALSE));
    PetscCall(VecGetOwnershipRange(itf->all, &rstart, &rend));
    if (mass_fluid) {
      PetscInt fstart, fend;
      PetscCall(MatGetOwnershipRange(mass_fluid, &fstart, &fend));
      PetscCheck(fstart == rstart && fend == rend, PETSC_COMM_SELF, PETSC_ERR_PLIB,
                 "interface: fluid ranks must come first in the parent communicator");
      for (PetscInt r = fstart; r < fend; ++r) {
        PetscInt           ncols;
        const PetscInt    *cols;
        const PetscScalar *vals;
        PetscCall(MatGetRow(mass_fluid, r, &ncols, &cols, &vals));
        PetscCall(MatSetValues(itf->mass, 1, &r, ncols, cols, vals, INSERT_VALUES));
        PetscCall(MatRestoreRow(mass_fluid, r, &ncols, &cols, &vals));
      }
    }
    PetscCall(MatAssemblyBegin(itf->mass, MAT_FINAL_ASSEMBLY));
    PetscCall(MatAssemblyEnd(itf->mass, MAT_FINAL_ASSEMBLY));
    PetscCall(MatDestroy(&mass_fluid));
  }
  PetscFunctionReturn(0);
}

/* The diagonal weight of the least-squares objective. Row sums are the usual lumping but
   vanish at the vertices of P2 triangles (the traces of P2 tetrahedra); the scaled diagonal
   (Hinton-Rock-Zienkiewicz) is positive for every Lagrange element and keeps the total mass.
   With one element type on the interface, the global scale equals HRZ's per-element one. */
static PetscErrorCode InterfaceLumpMass(Interface itf, InterfaceLumping lumping)
{
  Vec       ones, lumped;
  PetscReal smallest, total, diagonal_total;

  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(itf->all, &ones));
  PetscCall(VecDuplicate(itf->all, &lumped));
  PetscCall(VecSet(ones, 1.0));
  PetscCall(MatMult(itf->mass, ones, lumped));
  PetscCall(VecMin(lumped, NULL, &smallest));
  /* relative to the largest entry: round-off leaves +-1e-18 where the row sum is zero */
  {
    PetscReal largest;
    PetscCall(VecMax(lumped, NULL, &largest));
    if (smallest <= 1e-12 * largest) {
      PetscCheck(lumping != INTERFACE_LUMPING_ROW_SUM, itf->comm, PETSC_ERR_ARG_INCOMP,
                 "option -coupling_interface_lumping: the row sums of the interface mass have a non-positive entry "
                 "(%g), as at the vertices of P2 triangles; expected hrz or auto for this element",
                 (double)smallest);
      lumping = INTERFACE_LUMPING_HRZ;
    }
  }
  if (lumping == INTERFACE_LUMPING_HRZ) {
    PetscCall(VecSum(lumped, &total));
    PetscCall(MatGetDiagonal(itf->mass, lumped));
    PetscCall(VecSum(lumped, &diagonal_total));
    PetscCall(VecScale(lumped, total / diagonal_total));
  }
  PetscCall(VecDuplicate(itf->control_template, &itf->lumped_control));
  PetscCall(InterfaceRestrict(itf, lumped, itf->lumped_control));
  PetscCall(VecDestroy(&ones));
  PetscCall(VecDestroy(&lumped));
  PetscFunctionReturn(0);
}

PetscErrorCode InterfaceCreate(MPI_Comm comm, DM fluid, PetscInt fluid_face, DM structure, PetscInt structure_face,
                               Interface *interface)
{
  Interface        itf;
  PetscInt         dim_local = 0, dim;
  PetscReal        rtol      = 1e-8;
  InterfaceLumping lumping   = INTERFACE_LUMPING_AUTO;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&itf));
  itf->comm = comm;
  if (fluid) PetscCall(DMGetDimension(fluid, &dim_local));
  else if (structure) PetscCall(DMGetDimension(structure, &dim_local));
  PetscCallMPI(MPI_Allreduce(&dim_local, &dim, 1, MPIU_INT, MPI_MAX, comm));
  itf->dim = dim;
  PetscOptionsBegin(comm, NULL, "Interface options", "coupling");
  PetscCall(OptionsRealInRange(PetscOptionsObject, "-coupling_interface_tol",
                               "tolerance of the interface node matching, relative to the interface's extent", 0.0, 1.0,
                               &rtol));
  PetscCall(PetscOptionsEnum("-coupling_interface_lumping",
                             "diagonal weight of the least-squares objective: the interface mass's row sums, its "
                             "diagonal scaled to the same total (positive for P2 triangles, whose vertex row sums "
                             "vanish), or auto (row sums where all are positive, else the scaled diagonal)",
                             NULL, InterfaceLumpings, (PetscEnum)lumping, (PetscEnum *)&lumping, NULL));
  PetscOptionsEnd();
  if (fluid) PetscCall(InterfaceSideCollect(fluid, fluid_face, "fluid", &itf->fluid));
  if (structure) PetscCall(InterfaceSideCollect(structure, structure_face, "structure", &itf->structure));

  PetscCall(VecCreateMPI(comm, itf->fluid.n * dim, PETSC_DETERMINE, &itf->all));
  PetscCall(VecSetBlockSize(itf->all, dim));
  PetscCall(VecCreateMPI(comm, itf->structure.n * dim, PETSC_DETERMINE, &itf->structure_all));
  PetscCall(VecSetBlockSize(itf->structure_all, dim));
  PetscCall(PetscMalloc1(itf->fluid.n, &itf->control));
  for (PetscInt i = 0; i < itf->fluid.n; ++i)
    if (itf->fluid.global[i] >= 0) itf->control[itf->ncontrol++] = i;
  PetscCall(VecCreateMPI(comm, itf->ncontrol * dim, PETSC_DETERMINE, &itf->control_template));
  PetscCall(VecSetBlockSize(itf->control_template, dim));
  {
    PetscInt N;
    PetscCall(VecGetSize(itf->control_template, &N));
    PetscCheck(N > 0, comm, PETSC_ERR_ARG_WRONG,
               "interface: every fluid velocity node on face set %" PetscInt_FMT
               " is constrained by a Dirichlet condition: there is nothing to control",
               fluid_face);
  }
  PetscCall(InterfaceMatch(itf, rtol, fluid_face, structure_face));
  PetscCall(InterfaceAssembleMass(itf, fluid, fluid_face));
  PetscCall(InterfaceLumpMass(itf, lumping));
  *interface = itf;
  PetscFunctionReturn(0);
}

PetscErrorCode InterfaceDestroy(Interface *interface)
{
  Interface itf = *interface;

  PetscFunctionBeginUser;
  if (!itf) PetscFunctionReturn(0);
  PetscCall(InterfaceSideDestroy(&itf->fluid));
  PetscCall(InterfaceSideDestroy(&itf->structure));
  PetscCall(PetscFree(itf->control));
  PetscCall(VecDestroy(&itf->all));
  PetscCall(VecDestroy(&itf->structure_all));
  PetscCall(VecDestroy(&itf->control_template));
  PetscCall(VecDestroy(&itf->lumped_control));
  PetscCall(VecScatterDestroy(&itf->structure_to_fluid));
  PetscCall(MatDestroy(&itf->mass));
  PetscCall(PetscFree(*interface));
  PetscFunctionReturn(0);
}

PetscErrorCode InterfaceCreateVector(Interface itf, Vec *v)
{
  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(itf->all, v));
  PetscFunctionReturn(0);
}

PetscErrorCode InterfaceCreateControlVector(Interface itf, Vec *v)
{
  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(itf->control_template, v));
  PetscFunctionReturn(0);
}

PetscErrorCode InterfaceGetMass(Interface itf, Mat *mass)
{
  PetscFunctionBeginUser;
  *mass = itf->mass;
  PetscFunctionReturn(0);
}

PetscErrorCode InterfaceGetLumpedControlMass(Interface itf, Vec *lumped)
{
  PetscFunctionBeginUser;
  *lumped = itf->lumped_control;
  PetscFunctionReturn(0);
}

PetscErrorCode InterfaceRestrict(Interface itf, Vec all, Vec control)
{
  const PetscScalar *a;
  PetscScalar       *c;

  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(all, &a));
  PetscCall(VecGetArrayWrite(control, &c));
  for (PetscInt i = 0; i < itf->ncontrol; ++i)
    for (PetscInt d = 0; d < itf->dim; ++d) c[i * itf->dim + d] = a[itf->control[i] * itf->dim + d];
  PetscCall(VecRestoreArrayWrite(control, &c));
  PetscCall(VecRestoreArrayRead(all, &a));
  PetscFunctionReturn(0);
}

PetscErrorCode InterfaceExtend(Interface itf, Vec control, Vec all)
{
  const PetscScalar *c;
  PetscScalar       *a;

  PetscFunctionBeginUser;
  PetscCall(VecZeroEntries(all));
  PetscCall(VecGetArrayRead(control, &c));
  PetscCall(VecGetArray(all, &a));
  for (PetscInt i = 0; i < itf->ncontrol; ++i)
    for (PetscInt d = 0; d < itf->dim; ++d) a[itf->control[i] * itf->dim + d] = c[i * itf->dim + d];
  PetscCall(VecRestoreArray(all, &a));
  PetscCall(VecRestoreArrayRead(control, &c));
  PetscFunctionReturn(0);
}

static PetscErrorCode SideTrace(const Side *side, PetscInt dim, Vec local, Vec out)
{
  const PetscScalar *l;
  PetscScalar       *o;

  PetscFunctionBeginUser;
  PetscCall(VecGetArrayWrite(out, &o));
  if (side->n) PetscCall(VecGetArrayRead(local, &l));
  for (PetscInt i = 0; i < side->n; ++i)
    for (PetscInt d = 0; d < dim; ++d) o[i * dim + d] = l[side->local[i] + d];
  if (side->n) PetscCall(VecRestoreArrayRead(local, &l));
  PetscCall(VecRestoreArrayWrite(out, &o));
  PetscFunctionReturn(0);
}

static PetscErrorCode SideSpread(const Side *side, PetscInt dim, Vec in, Vec global)
{
  const PetscScalar *a;
  PetscScalar       *g;
  PetscInt           rstart;

  PetscFunctionBeginUser;
  if (!global) PetscFunctionReturn(0);
  PetscCall(VecGetOwnershipRange(global, &rstart, NULL));
  PetscCall(VecGetArrayRead(in, &a));
  PetscCall(VecGetArray(global, &g));
  for (PetscInt i = 0; i < side->n; ++i) {
    if (side->global[i] < 0) continue;
    for (PetscInt d = 0; d < dim; ++d) g[side->global[i] - rstart + d] = a[i * dim + d];
  }
  PetscCall(VecRestoreArray(global, &g));
  PetscCall(VecRestoreArrayRead(in, &a));
  PetscFunctionReturn(0);
}

PetscErrorCode InterfaceFluidTrace(Interface itf, Vec fluid_local, Vec all)
{
  PetscFunctionBeginUser;
  PetscCall(SideTrace(&itf->fluid, itf->dim, fluid_local, all));
  PetscFunctionReturn(0);
}

PetscErrorCode InterfaceFluidSpread(Interface itf, Vec all, Vec fluid_global)
{
  PetscFunctionBeginUser;
  PetscCall(SideSpread(&itf->fluid, itf->dim, all, fluid_global));
  PetscFunctionReturn(0);
}

PetscErrorCode InterfaceStructureTrace(Interface itf, Vec structure_local, Vec all)
{
  PetscFunctionBeginUser;
  PetscCall(SideTrace(&itf->structure, itf->dim, structure_local, itf->structure_all));
  PetscCall(VecScatterBegin(itf->structure_to_fluid, itf->structure_all, all, INSERT_VALUES, SCATTER_FORWARD));
  PetscCall(VecScatterEnd(itf->structure_to_fluid, itf->structure_all, all, INSERT_VALUES, SCATTER_FORWARD));
  PetscFunctionReturn(0);
}

PetscErrorCode InterfaceStructureSpread(Interface itf, Vec all, Vec structure_global)
{
  PetscFunctionBeginUser;
  PetscCall(VecScatterBegin(itf->structure_to_fluid, all, itf->structure_all, INSERT_VALUES, SCATTER_REVERSE));
  PetscCall(VecScatterEnd(itf->structure_to_fluid, all, itf->structure_all, INSERT_VALUES, SCATTER_REVERSE));
  PetscCall(SideSpread(&itf->structure, itf->dim, itf->structure_all, structure_global));
  PetscFunctionReturn(0);
}

PetscErrorCode InterfaceInterpolate(Interface itf, FieldFn fn, void *ctx, PetscReal t, Vec all)
{
  PetscScalar *a;

  PetscFunctionBeginUser;
  PetscCall(VecGetArrayWrite(all, &a));
  for (PetscInt i = 0; i < itf->fluid.n; ++i)
    PetscCall(fn(itf->dim, t, &itf->fluid.coords[i * itf->dim], itf->dim, &a[i * itf->dim], ctx));
  PetscCall(VecRestoreArrayWrite(all, &a));
  PetscFunctionReturn(0);
}

PetscErrorCode InterfaceStructureInsertLocal(Interface itf, Vec all, Vec structure_local)
{
  PetscScalar       *l;
  const PetscScalar *a;

  PetscFunctionBeginUser;
  PetscCall(VecScatterBegin(itf->structure_to_fluid, all, itf->structure_all, INSERT_VALUES, SCATTER_REVERSE));
  PetscCall(VecScatterEnd(itf->structure_to_fluid, all, itf->structure_all, INSERT_VALUES, SCATTER_REVERSE));
  if (!itf->structure.n) PetscFunctionReturn(0);
  PetscCall(VecGetArrayRead(itf->structure_all, &a));
  PetscCall(VecGetArray(structure_local, &l));
  for (PetscInt i = 0; i < itf->structure.n; ++i)
    for (PetscInt d = 0; d < itf->dim; ++d) l[itf->structure.local[i] + d] = a[i * itf->dim + d];
  PetscCall(VecRestoreArray(structure_local, &l));
  PetscCall(VecRestoreArrayRead(itf->structure_all, &a));
  PetscFunctionReturn(0);
}

PetscErrorCode InterfaceGetFluidNodes(Interface itf, PetscInt *n, const PetscInt **points, const PetscReal **coords)
{
  PetscFunctionBeginUser;
  if (n) *n = itf->fluid.n;
  if (points) *points = itf->fluid.point;
  if (coords) *coords = itf->fluid.coords;
  PetscFunctionReturn(0);
}

PetscErrorCode InterfaceGetFluidRows(Interface itf, IS *rows)
{
  const Side *side = &itf->fluid;
  PetscInt   *idx, n = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscMalloc1(side->n * itf->dim, &idx));
  for (PetscInt i = 0; i < side->n; ++i) {
    if (side->global[i] < 0) continue;
    for (PetscInt d = 0; d < itf->dim; ++d) idx[n++] = side->global[i] + d;
  }
  PetscCall(ISCreateGeneral(PETSC_COMM_SELF, n, idx, PETSC_OWN_POINTER, rows));
  PetscFunctionReturn(0);
}

PetscErrorCode InterfaceFluidGather(Interface itf, Vec fluid_global, Vec all)
{
  const Side        *side = &itf->fluid;
  const PetscScalar *g;
  PetscScalar       *a;
  PetscInt           rstart;

  PetscFunctionBeginUser;
  PetscCall(VecZeroEntries(all));
  if (!fluid_global) PetscFunctionReturn(0);
  PetscCall(VecGetOwnershipRange(fluid_global, &rstart, NULL));
  PetscCall(VecGetArrayRead(fluid_global, &g));
  PetscCall(VecGetArray(all, &a));
  for (PetscInt i = 0; i < side->n; ++i) {
    if (side->global[i] < 0) continue;
    for (PetscInt d = 0; d < itf->dim; ++d) a[i * itf->dim + d] = g[side->global[i] - rstart + d];
  }
  PetscCall(VecRestoreArray(all, &a));
  PetscCall(VecRestoreArrayRead(fluid_global, &g));
  PetscFunctionReturn(0);
}
