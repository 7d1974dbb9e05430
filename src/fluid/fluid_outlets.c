/* The fluid's 0D outlets (PhysicsData.outlets): on an outlet's face set the traction -p n with
   p = R_p Q + P_c, Q = int u.n the flow rate out, and the capacitor's pressure P_c of the
   three-element Windkessel C dP_c/dt = Q - (P_c - P_d)/R_d by backward Euler over the step,
       P_c^{n+1} = (P_c^n + dt/C (Q^{n+1} + P_d/R_d)) / (1 + dt/(R_d C)),
   or P_c = P_d for a resistance (C = 0). Implicit in the step: every residual of the fluid's
   Newton iteration takes Q of its own iterate, so a converged fluid solve satisfies the 0D
   model at the new time and every solve of the coupling's loop sees the same outlet. The
   Jacobian gets the model's rank-one term dp/dQ b b^T, b_i = int phi_i . n: a dense block
   over the outlet's velocity nodes, which Newton needs (without it a resistance of a few
   times the channel's own multiplies the Newton iterations) and which fills the matrix by
   the square of an outlet's node count.
   P_c^n advances when the next step begins from the state the last one accepted, and is
   checkpointed with it. */
#include "fluid_impl.h"
#include "checkpoint.h"

#pragma GCC diagnostic ignored "-Wunused-parameter"

struct _n_FluidOutlets {
  PetscInt  n;
  IS        faces[FSIOPT_MAX_OUTLETS];
  /* the dense block's pattern: this rank's rows (global numbers of the outlet's free velocity
     dofs it owns), the columns (every rank's rows, in rank order) and their layout */
  PetscInt    nrows[FSIOPT_MAX_OUTLETS], ncols[FSIOPT_MAX_OUTLETS], *rows[FSIOPT_MAX_OUTLETS], *cols[FSIOPT_MAX_OUTLETS];
  PetscMPIInt *counts[FSIOPT_MAX_OUTLETS], *displs[FSIOPT_MAX_OUTLETS];
  PetscReal capacitor[FSIOPT_MAX_OUTLETS]; /* P_c at the time of the fluid's state f->x */
  PetscReal pressure[FSIOPT_MAX_OUTLETS];  /* p of the last residual's iterate */
  PetscBool stepped;                       /* a step has solved since `capacitor` was brought to f->x */
  PetscReal step_dt;                       /* that step's dt */
};

/* P_c at the end of a step of length dt from P_c = pc with the outflow q */
static PetscReal CapacitorAfter(const OutletModel *m, PetscReal pc, PetscReal q, PetscReal dt)
{
  if (m->capacitance <= 0) return m->distal_pressure;
  return (pc + dt / m->capacitance * (q + m->distal_pressure / m->distal_resistance)) /
         (1 + dt / (m->distal_resistance * m->capacitance));
}

/* The free velocity dofs in the closure of the outlet's faces: its block's pattern, kept with
   the DM for the matrices the backends make */
static PetscErrorCode BlockPattern(Fluid f, FluidOutlets o, PetscInt k)
{
  PetscSection       section;
  Vec                marks_local, marks;
  const PetscInt    *face;
  const PetscScalar *m;
  PetscScalar       *ml;
  PetscInt           nfaces, start, n, count = 0, *pairs_rows, *pairs_cols;
  PetscMPIInt        size, mine;

  PetscFunctionBeginUser;
  PetscCall(DMGetLocalSection(f->dm, &section));
  PetscCall(DMGetLocalVector(f->dm, &marks_local));
  PetscCall(DMGetGlobalVector(f->dm, &marks));
  PetscCall(VecZeroEntries(marks_local));
  PetscCall(VecZeroEntries(marks));
  PetscCall(ISGetLocalSize(o->faces[k], &nfaces));
  PetscCall(ISGetIndices(o->faces[k], &face));
  PetscCall(VecGetArray(marks_local, &ml));
  for (PetscInt e = 0; e < nfaces; ++e) {
    PetscInt *closure = NULL, nclosure;
    PetscCall(DMPlexGetTransitiveClosure(f->dm, face[e], PETSC_TRUE, &nclosure, &closure));
    for (PetscInt c = 0; c < nclosure; ++c) {
      PetscInt ndof, off;
      PetscCall(PetscSectionGetFieldDof(section, closure[2 * c], 0, &ndof));
      PetscCall(PetscSectionGetFieldOffset(section, closure[2 * c], 0, &off));
      for (PetscInt d = 0; d < ndof; ++d) ml[off + d] = 1.0;
    }
    PetscCall(DMPlexRestoreTransitiveClosure(f->dm, face[e], PETSC_TRUE, &nclosure, &closure));
  }
  PetscCall(VecRestoreArray(marks_local, &ml));
  PetscCall(ISRestoreIndices(o->faces[k], &face));
  PetscCall(DMLocalToGlobal(f->dm, marks_local, ADD_VALUES, marks));
  PetscCall(VecGetOwnershipRange(marks, &start, NULL));
  PetscCall(VecGetLocalSize(marks, &n));
  PetscCall(VecGetArrayRead(marks, &m));
  for (PetscInt i = 0; i < n; ++i) count += m[i] != 0.0;
  PetscCall(PetscMalloc1(count + 1, &o->rows[k]));
  o->nrows[k] = 0;
  for (PetscInt i = 0; i < n; ++i)
    if (m[i] != 0.0) o->rows[k][o->nrows[k]++] = start + i;
  PetscCall(VecRestoreArrayRead(marks, &m));
  PetscCall(DMRestoreGlobalVector(f->dm, &marks));
  PetscCall(DMRestoreLocalVector(f->dm, &marks_local));
  PetscCallMPI(MPI_Comm_size(f->comm, &size));
  PetscCall(PetscMalloc2(size, &o->counts[k], size, &o->displs[k]));
  mine = (PetscMPIInt)o->nrows[k];
  PetscCallMPI(MPI_Allgather(&mine, 1, MPI_INT, o->counts[k], 1, MPI_INT, f->comm));
  o->ncols[k] = 0;
  for (PetscMPIInt r = 0; r < size; ++r) {
    o->displs[k][r] = (PetscMPIInt)o->ncols[k];
    o->ncols[k] += o->counts[k][r];
  }
  PetscCall(PetscMalloc1(o->ncols[k] + 1, &o->cols[k]));
  PetscCallMPI(MPI_Allgatherv(o->rows[k], mine, MPIU_INT, o->cols[k], o->counts[k], o->displs[k], MPIU_INT, f->comm));
  PetscCall(PetscMalloc2(o->nrows[k] * o->ncols[k] + 1, &pairs_rows, o->nrows[k] * o->ncols[k] + 1, &pairs_cols));
  for (PetscInt i = 0; i < o->nrows[k]; ++i)
    for (PetscInt j = 0; j < o->ncols[k]; ++j) {
      pairs_rows[i * o->ncols[k] + j] = o->rows[k][i];
      pairs_cols[i * o->ncols[k] + j] = o->cols[k][j];
    }
  PetscCall(FEMAddExtraPattern(f->dm, o->nrows[k] * o->ncols[k], pairs_rows, pairs_cols));
  PetscCall(PetscFree2(pairs_rows, pairs_cols));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidOutletsCreate(Fluid f)
{
  FluidOutlets o;

  PetscFunctionBeginUser;
  if (!f->data.n_outlets) PetscFunctionReturn(0);
  PetscCall(PetscNew(&o));
  o->n = f->data.n_outlets;
  for (PetscInt k = 0; k < o->n; ++k) {
    const OutletModel *m = &f->data.outlets[k];
    PetscCall(FluidFaceSetFaces(f, 1, &m->face, &o->faces[k]));
    PetscCall(BlockPattern(f, o, k));
    o->capacitor[k] = m->distal_pressure; /* at rest */
    o->pressure[k]  = m->distal_pressure;
  }
  f->outlets = o;
  PetscFunctionReturn(0);
}

PetscErrorCode FluidOutletsDestroy(FluidOutlets *outlets)
{
  PetscFunctionBeginUser;
  if (!*outlets) PetscFunctionReturn(0);
  for (PetscInt k = 0; k < (*outlets)->n; ++k) {
    PetscCall(ISDestroy(&(*outlets)->faces[k]));
    PetscCall(PetscFree((*outlets)->rows[k]));
    PetscCall(PetscFree((*outlets)->cols[k]));
    PetscCall(PetscFree2((*outlets)->counts[k], (*outlets)->displs[k]));
  }
  PetscCall(PetscFree(*outlets));
  PetscFunctionReturn(0);
}

PetscInt FluidOutletsGetPressures(Fluid f, PetscScalar constants[])
{
  if (!f->outlets) return 0;
  for (PetscInt k = 0; k < f->outlets->n; ++k) constants[f->outlets->n - 1 - k] = f->outlets->pressure[k];
  return f->outlets->n;
}

/* the flow rates of the local state xlocal */
static PetscErrorCode FlowRates(Fluid f, Vec xlocal, PetscReal q[])
{
  PetscFunctionBeginUser;
  for (PetscInt k = 0; k < f->outlets->n; ++k) {
    FluidFaceIntegral integral;
    PetscCall(FluidIntegrateFaces(f, xlocal, f->outlets->faces[k], &integral, NULL));
    q[k] = integral.flow_rate;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FluidOutletsSetIterate(Fluid f, Vec xlocal)
{
  FluidOutlets       o = f->outlets;
  PetscDS            ds;
  PetscInt           n;
  const PetscScalar *constants;
  PetscScalar        c[FLUID_MAX_CONSTANTS];
  PetscReal          q[FSIOPT_MAX_OUTLETS];

  PetscFunctionBeginUser;
  if (!o) PetscFunctionReturn(0);
  PetscCall(FlowRates(f, xlocal, q));
  for (PetscInt k = 0; k < o->n; ++k) {
    const OutletModel *m = &f->data.outlets[k];
    o->pressure[k]       = m->proximal_resistance * q[k] + CapacitorAfter(m, o->capacitor[k], q[k], f->dt);
  }
  o->stepped = PETSC_TRUE;
  o->step_dt = f->dt;
  PetscCall(DMGetDS(f->dm, &ds));
  PetscCall(PetscDSGetConstants(ds, &n, &constants));
  PetscCall(PetscArraycpy(c, constants, n));
  (void)FluidOutletsGetPressures(f, &c[n - o->n]);
  PetscCall(PetscDSSetConstants(ds, n, c));
  PetscFunctionReturn(0);
}

/* P_c at the time of f->x */
static PetscErrorCode CapacitorsAtState(Fluid f, PetscReal q[], PetscReal pc[])
{
  FluidOutlets o = f->outlets;

  PetscFunctionBeginUser;
  PetscCall(FluidGlobalToLocal(f, f->x, f->xlocal_work));
  PetscCall(FlowRates(f, f->xlocal_work, q));
  for (PetscInt k = 0; k < o->n; ++k)
    pc[k] = o->stepped ? CapacitorAfter(&f->data.outlets[k], o->capacitor[k], q[k], o->step_dt) : o->capacitor[k];
  PetscFunctionReturn(0);
}

/* dp/dQ of the outlet over a step of dt */
static PetscReal PressureSlope(const OutletModel *m, PetscReal dt)
{
  const PetscReal slope = m->proximal_resistance;
  if (m->capacitance <= 0) return slope;
  return slope + dt * m->distal_resistance / (m->distal_resistance * m->capacitance + dt);
}

PetscErrorCode FluidOutletsAddJacobian(Fluid f, Vec xlocal, Mat P, Mat J)
{
  FluidOutlets o = f->outlets;
  Vec          flux_local, flux;
  Mat          targets[2] = {P, J};

  PetscFunctionBeginUser;
  if (!o) PetscFunctionReturn(0);
  PetscCall(DMGetLocalVector(f->dm, &flux_local));
  PetscCall(DMGetGlobalVector(f->dm, &flux));
  for (PetscInt m = 0; m < 2; ++m) /* PETSc's stencil lacks them */
    if (targets[m]) PetscCall(MatSetOption(targets[m], MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_FALSE));
  for (PetscInt k = 0; k < o->n; ++k) {
    FluidFaceIntegral  integral;
    const PetscScalar *b;
    PetscScalar       *mine, *all, *block;
    PetscInt           start;
    const PetscReal    slope = PressureSlope(&f->data.outlets[k], f->dt);

    PetscCall(VecZeroEntries(flux_local));
    PetscCall(VecZeroEntries(flux));
    PetscCall(FluidIntegrateFaces(f, xlocal, o->faces[k], &integral, flux_local));
    PetscCall(DMLocalToGlobal(f->dm, flux_local, ADD_VALUES, flux));
    PetscCall(VecGetOwnershipRange(flux, &start, NULL));
    PetscCall(PetscMalloc3(o->nrows[k] + 1, &mine, o->ncols[k] + 1, &all, o->nrows[k] * o->ncols[k] + 1, &block));
    PetscCall(VecGetArrayRead(flux, &b));
    for (PetscInt i = 0; i < o->nrows[k]; ++i) mine[i] = b[o->rows[k][i] - start];
    PetscCall(VecRestoreArrayRead(flux, &b));
    PetscCallMPI(MPI_Allgatherv(mine, (PetscMPIInt)o->nrows[k], MPIU_SCALAR, all, o->counts[k], o->displs[k],
                                MPIU_SCALAR, f->comm));
    for (PetscInt i = 0; i < o->nrows[k]; ++i)
      for (PetscInt j = 0; j < o->ncols[k]; ++j) block[i * o->ncols[k] + j] = slope * mine[i] * all[j];
    for (PetscInt m = 0; m < 2; ++m)
      if (targets[m])
        PetscCall(MatSetValues(targets[m], o->nrows[k], o->rows[k], o->ncols[k], o->cols[k], block, ADD_VALUES));
    PetscCall(PetscFree3(mine, all, block));
  }
  for (PetscInt m = 0; m < 2; ++m)
    if (targets[m]) {
      PetscCall(MatAssemblyBegin(targets[m], MAT_FINAL_ASSEMBLY));
      PetscCall(MatAssemblyEnd(targets[m], MAT_FINAL_ASSEMBLY));
    }
  PetscCall(DMRestoreGlobalVector(f->dm, &flux));
  PetscCall(DMRestoreLocalVector(f->dm, &flux_local));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidOutletsBeginStep(Fluid f)
{
  PetscReal q[FSIOPT_MAX_OUTLETS];

  PetscFunctionBeginUser;
  if (!f->outlets) PetscFunctionReturn(0);
  PetscCall(CapacitorsAtState(f, q, f->outlets->capacitor));
  f->outlets->stepped = PETSC_FALSE;
  PetscFunctionReturn(0);
}

PetscErrorCode FluidGetOutletState(Fluid f, PetscReal q[], PetscReal p[])
{
  PetscReal pc[FSIOPT_MAX_OUTLETS];

  PetscFunctionBeginUser;
  if (!f->outlets) PetscFunctionReturn(0);
  PetscCall(CapacitorsAtState(f, q, pc));
  for (PetscInt k = 0; k < f->outlets->n; ++k) p[k] = f->data.outlets[k].proximal_resistance * q[k] + pc[k];
  PetscFunctionReturn(0);
}

PetscErrorCode FluidOutletsCheckpoint(Fluid f, Checkpoint cp, PetscBool load)
{
  FluidOutlets o = f->outlets;
  PetscReal    q[FSIOPT_MAX_OUTLETS], pc[FSIOPT_MAX_OUTLETS];

  PetscFunctionBeginUser;
  if (!o) PetscFunctionReturn(0);
  if (!load) PetscCall(CapacitorsAtState(f, q, pc));
  for (PetscInt k = 0; k < o->n; ++k) {
    char name[96];
    PetscCall(PetscSNPrintf(name, sizeof(name), "outlet_capacitor_pressure_%s", f->data.outlets[k].name));
    PetscCall(CheckpointReal(cp, name, &pc[k], load));
  }
  if (load) {
    PetscCall(PetscArraycpy(o->capacitor, pc, o->n));
    o->stepped = PETSC_FALSE;
  }
  PetscFunctionReturn(0);
}

/* -load (-p_k n), p_k the last constant but k */
static inline void OutletTraction(PetscInt k, PetscInt dim, const PetscReal n[], PetscInt nconstants,
                                  const PetscScalar constants[], PetscScalar f0[])
{
  const PetscScalar p = constants[nconstants - 1 - k];
  for (PetscInt d = 0; d < dim; ++d) f0[d] += constants[FLUID_LOAD] * p * n[d];
}

#define OUTLET_KERNEL(K) \
  static void FluidOutletTraction##K(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], \
                                     const PetscInt uOff_x[], const PetscScalar u[], const PetscScalar u_t[], \
                                     const PetscScalar u_x[], const PetscInt aOff[], const PetscInt aOff_x[], \
                                     const PetscScalar a[], const PetscScalar a_t[], const PetscScalar a_x[], \
                                     PetscReal t, const PetscReal x[], const PetscReal n[], PetscInt numConstants, \
                                     const PetscScalar constants[], PetscScalar f0[]) \
  { \
    OutletTraction(K, dim, n, numConstants, constants, f0); \
  }
OUTLET_KERNEL(0)
OUTLET_KERNEL(1)
OUTLET_KERNEL(2)
OUTLET_KERNEL(3)
OUTLET_KERNEL(4)
OUTLET_KERNEL(5)
OUTLET_KERNEL(6)
OUTLET_KERNEL(7)

BdResidualKernel FluidOutletKernel(PetscInt k)
{
  static const BdResidualKernel kernels[FSIOPT_MAX_OUTLETS] = {
    FluidOutletTraction0, FluidOutletTraction1, FluidOutletTraction2, FluidOutletTraction3,
    FluidOutletTraction4, FluidOutletTraction5, FluidOutletTraction6, FluidOutletTraction7};
  return k >= 0 && k < FSIOPT_MAX_OUTLETS ? kernels[k] : NULL;
}
