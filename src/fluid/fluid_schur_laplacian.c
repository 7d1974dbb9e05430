/* A sparse stand-in for the Schur complement of the fluid's field split
   (-fluid_schur_pressure_laplacian): -(tau + 1/m) (grad p, grad q) on the pressure space, m
   the step's mass coefficient (rho/dt, 3/2 rho/dt with BDF2) and tau the pressure
   stabilization's, with Dirichlet rows where the velocity is free (traction, pressure, open
   and outlet faces, and the interface, whose traction the coupling gives).

   Why: at the small time steps of a pressure wave the velocity block is about m M, so the
   Schur complement -tau K - B A^-1 B^T is about -(tau K + B (m M)^-1 B^T), a pressure
   Laplacian scaled by tau + 1/m, whose pressure is fixed where a traction is given. selfp's
   B diag(A)^-1 B^T is one too, with the stencil of B B^T (twice as wide as K's) and no
   coarse hierarchy from GAMG. Where viscosity or convection dominate the velocity block
   (steady flows, large dt) it is no such Laplacian: the option is refused for steady fluids.
   Measured on tube3d it stands for the Schur complement less well than selfp: 1.6x the
   FGMRES iterations at about a quarter of the cost per application, slower overall
   (docs/coupling-and-solvers.md); it stays an option to measure on other flows. */
#include "fluid.h"
#include "fluid_impl.h"

#pragma GCC diagnostic ignored "-Wunused-parameter" /* PETSc's pointwise signature */

/* -(grad p, grad q) scaled by constants[0] */
static void G3NegativeLaplacian(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[],
                                const PetscInt uOff_x[], const PetscScalar u[], const PetscScalar u_t[],
                                const PetscScalar u_x[], const PetscInt aOff[], const PetscInt aOff_x[],
                                const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[], PetscReal t,
                                PetscReal u_tShift, const PetscReal x[], PetscInt numConstants,
                                const PetscScalar constants[], PetscScalar g3[])
{
  for (PetscInt d = 0; d < dim; ++d) g3[d * dim + d] = -constants[0];
}

/* the pressure dofs this rank owns on the faces where the velocity is free, in dm's numbering */
static PetscErrorCode FreeVelocityRows(Fluid f, DM dm, PetscInt *n, PetscInt **rows)
{
  DMLabel      label;
  PetscSection global;
  PetscInt     faces[FSIOPT_MAX_BOUNDARIES + 1], n_faces = 0, count = 0;
  PetscInt    *found = NULL;

  PetscFunctionBeginUser;
  for (PetscInt b = 0; b < f->data.n_traction; ++b) faces[n_faces++] = f->data.traction_faces[b];
  if (f->interface_face) faces[n_faces++] = f->interface_face;
  PetscCall(DMGetLabel(dm, "Face Sets", &label));
  PetscCall(DMGetGlobalSection(dm, &global));
  for (PetscInt pass = 0; pass < 2; ++pass) {
    count = 0;
    for (PetscInt k = 0; k < n_faces && label; ++k) {
      IS              points;
      const PetscInt *face;
      PetscInt        n_points;

      PetscCall(DMLabelGetStratumIS(label, faces[k], &points));
      if (!points) continue;
      PetscCall(ISGetLocalSize(points, &n_points));
      PetscCall(ISGetIndices(points, &face));
      for (PetscInt i = 0; i < n_points; ++i) {
        PetscInt *closure = NULL, n_closure;

        PetscCall(DMPlexGetTransitiveClosure(dm, face[i], PETSC_TRUE, &n_closure, &closure));
        for (PetscInt c = 0; c < n_closure; ++c) {
          PetscInt dof, off;

          PetscCall(PetscSectionGetDof(global, closure[2 * c], &dof));
          PetscCall(PetscSectionGetOffset(global, closure[2 * c], &off));
          if (dof <= 0) continue; /* another rank's point: negative */
          for (PetscInt d = 0; d < dof; ++d, ++count)
            if (pass) found[count] = off + d;
        }
        PetscCall(DMPlexRestoreTransitiveClosure(dm, face[i], PETSC_TRUE, &n_closure, &closure));
      }
      PetscCall(ISRestoreIndices(points, &face));
      PetscCall(ISDestroy(&points));
    }
    if (!pass) PetscCall(PetscMalloc1(count, &found));
  }
  PetscCall(PetscSortRemoveDupsInt(&count, found));
  *n    = count;
  *rows = found;
  PetscFunctionReturn(0);
}

PetscErrorCode FluidSchurLaplacianSetUp(Fluid f)
{
  KSP       ksp;
  PC        pc;
  PetscBool fieldsplit;
  DM        dm;
  PetscFE   pressure;
  PetscDS   ds;
  Vec       zero, diagonal;
  PetscInt  n_rows = 0, *rows = NULL, n_split, local;
  IS       *splits;
  PetscReal one = 1;

  PetscFunctionBeginUser;
  if (!f->schur_laplacian.use) PetscFunctionReturn(0);
  PetscCheck(!f->steady && f->model == FLUID_NAVIER_STOKES, f->comm, PETSC_ERR_ARG_INCOMP,
             "option -fluid_schur_pressure_laplacian: the Schur complement of a steady or Stokes fluid is no "
             "pressure Laplacian; expected a time-dependent Navier-Stokes fluid");
  PetscCall(SNESGetKSP(f->snes, &ksp));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PetscObjectTypeCompare((PetscObject)pc, PCFIELDSPLIT, &fieldsplit));
  if (fieldsplit) {
    PCCompositeType type;
    PetscCall(PCFieldSplitGetType(pc, &type));
    fieldsplit = type == PC_COMPOSITE_SCHUR ? PETSC_TRUE : PETSC_FALSE;
  }
  PetscCheck(fieldsplit, f->comm, PETSC_ERR_ARG_INCOMP,
             "option -fluid_schur_pressure_laplacian: expected -fluid_pc_type fieldsplit with "
             "-fluid_pc_fieldsplit_type schur (options/solvers/fluid-schur-gamg.yaml)");
  PetscCall(DMGetField(f->dm, 1, NULL, (PetscObject *)&pressure));
  PetscCall(DMClone(f->dm, &dm));
  PetscCall(DMSetField(dm, 0, NULL, (PetscObject)pressure));
  PetscCall(DMCreateDS(dm));
  PetscCall(DMGetDS(dm, &ds));
  PetscCall(PetscDSSetJacobian(ds, 0, 0, NULL, NULL, NULL, G3NegativeLaplacian));
  PetscCall(PetscDSSetConstants(ds, 1, &one));
  PetscCall(DMCreateMatrix(dm, &f->schur_laplacian.matrix));
  PetscCall(PetscObjectSetName((PetscObject)f->schur_laplacian.matrix, "fluid_schur_pressure_laplacian"));
  PetscCall(DMGetLocalVector(dm, &zero));
  PetscCall(VecZeroEntries(zero));
  PetscCall(DMPlexSNESComputeJacobianFEM(dm, zero, f->schur_laplacian.matrix, f->schur_laplacian.matrix, NULL));
  PetscCall(DMRestoreLocalVector(dm, &zero));
  /* the split's pressure block is numbered as this DM: the same points in the same order */
  PetscCall(DMCreateFieldIS(f->dm, &n_split, NULL, &splits));
  PetscCall(ISGetLocalSize(splits[1], &local));
  for (PetscInt k = 0; k < n_split; ++k) PetscCall(ISDestroy(&splits[k]));
  PetscCall(PetscFree(splits));
  {
    PetscInt rows_here;
    PetscCall(MatGetLocalSize(f->schur_laplacian.matrix, &rows_here, NULL));
    PetscCheck(rows_here == local, PETSC_COMM_SELF, PETSC_ERR_ARG_INCOMP,
               "option -fluid_schur_pressure_laplacian: the pressure has constrained values (%" PetscInt_FMT
               " free of %" PetscInt_FMT "); expected a pressure without Dirichlet conditions",
               local, rows_here);
  }
  PetscCall(FreeVelocityRows(f, dm, &n_rows, &rows));
  PetscCall(MatCreateVecs(f->schur_laplacian.matrix, &diagonal, NULL));
  PetscCall(MatGetDiagonal(f->schur_laplacian.matrix, diagonal));
  PetscCall(MatZeroRowsColumns(f->schur_laplacian.matrix, n_rows, rows, -1.0, NULL, NULL));
  PetscCall(MatDiagonalSet(f->schur_laplacian.matrix, diagonal, INSERT_VALUES)); /* each row keeps its own */
  PetscCall(VecDestroy(&diagonal));
  PetscCall(PetscFree(rows));
  PetscCall(DMDestroy(&dm));
  f->schur_laplacian.scale = 1;
  PetscCall(PCFieldSplitSetSchurPre(pc, PC_FIELDSPLIT_SCHUR_PRE_USER, f->schur_laplacian.matrix));
  /* the transposed solves' split (fem_linear_solve.c) takes it too: the matrix is symmetric */
  PetscCall(PetscObjectCompose((PetscObject)f->snes, "fsiopt_schur_preconditioning_matrix",
                               (PetscObject)f->schur_laplacian.matrix));
  PetscFunctionReturn(0);
}

/* scaled by tau + 1/m of the step: a new dt, or BDF2's first step after backward Euler */
PetscErrorCode FluidSchurLaplacianBeginStep(Fluid f)
{
  PetscReal scale;

  PetscFunctionBeginUser;
  if (!f->schur_laplacian.matrix) PetscFunctionReturn(0);
  scale = f->pressure_tau + 1.0 / f->mass_coefficient;
  if (scale == f->schur_laplacian.scale) PetscFunctionReturn(0);
  PetscCall(MatScale(f->schur_laplacian.matrix, scale / f->schur_laplacian.scale));
  f->schur_laplacian.scale = scale;
  PetscFunctionReturn(0);
}
