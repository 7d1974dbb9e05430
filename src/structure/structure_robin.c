/* Robin supports of the wall (PhysicsData's robin_*): on the face set the traction
   -(k eta + c etadot), an elastic foundation of stiffness k and a dashpot c per unit area,
   the tissue around a vessel. The scheme's velocity is affine in eta^n (structure.c), so the
   term is k (eta, xi) + c (etadot, xi) on the face with

     order 0, 1:  etadot^n = (eta^n - eta^{n-1})/dt
     order 2:     the midpoint's average of both ends, k and c both averaged:
                  (k/2)(eta^n + eta^{n-1}) + c (eta^n - eta^{n-1})/dt, times 2 as the scheme is

   that is, s (eta^n, xi) on the left with s = k + c v (v = StructureVelocityCoefficient), and
   the part in eta^{n-1} in the step's history. Each face set's kernel reads its own s from
   the DS constants: face set b's at numConstants - 1 - b (the last ones), set by
   StructureRobinShifts for the evaluation at hand: s_b = op k_b + rate c_b. */
#include "structure_impl.h"

/* PETSc fixes the signatures of pointwise kernels; each uses a few of their arguments. */
#pragma GCC diagnostic ignored "-Wunused-parameter"

#define ROBIN_KERNELS(B) \
  static void RobinF0_##B(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[], \
                          const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], \
                          const PetscInt aOff[], const PetscInt aOff_x[], const PetscScalar a[], \
                          const PetscScalar a_t[], const PetscScalar a_x[], PetscReal t, const PetscReal x[], \
                          const PetscReal n[], PetscInt numConstants, const PetscScalar constants[], PetscScalar f0[]) \
  { \
    for (PetscInt c = 0; c < dim; ++c) f0[c] += constants[numConstants - 1 - (B)] * u[uOff[0] + c]; \
  } \
  static void RobinG0_##B(PetscInt dim, PetscInt Nf, PetscInt NfAux, const PetscInt uOff[], const PetscInt uOff_x[], \
                          const PetscScalar u[], const PetscScalar u_t[], const PetscScalar u_x[], \
                          const PetscInt aOff[], const PetscInt aOff_x[], const PetscScalar a[], \
                          const PetscScalar a_t[], const PetscScalar a_x[], PetscReal t, PetscReal u_tShift, \
                          const PetscReal x[], const PetscReal n[], PetscInt numConstants, \
                          const PetscScalar constants[], PetscScalar g0[]) \
  { \
    for (PetscInt c = 0; c < dim; ++c) g0[c * dim + c] += constants[numConstants - 1 - (B)]; \
  }
ROBIN_KERNELS(0)
ROBIN_KERNELS(1)
ROBIN_KERNELS(2)
ROBIN_KERNELS(3)
ROBIN_KERNELS(4)
ROBIN_KERNELS(5)
ROBIN_KERNELS(6)
ROBIN_KERNELS(7)

static const BdResidualKernel robin_f0[FSIOPT_MAX_BOUNDARIES] = {RobinF0_0, RobinF0_1, RobinF0_2, RobinF0_3,
                                                                 RobinF0_4, RobinF0_5, RobinF0_6, RobinF0_7};
typedef void (*BdJacobianKernel)(PetscInt, PetscInt, PetscInt, const PetscInt[], const PetscInt[], const PetscScalar[],
                                 const PetscScalar[], const PetscScalar[], const PetscInt[], const PetscInt[],
                                 const PetscScalar[], const PetscScalar[], const PetscScalar[], PetscReal, PetscReal,
                                 const PetscReal[], const PetscReal[], PetscInt, const PetscScalar[], PetscScalar[]);
static const BdJacobianKernel robin_g0[FSIOPT_MAX_BOUNDARIES] = {RobinG0_0, RobinG0_1, RobinG0_2, RobinG0_3,
                                                                 RobinG0_4, RobinG0_5, RobinG0_6, RobinG0_7};

PetscErrorCode StructureRobinAddBoundaries(Structure s)
{
  DMLabel label;
  PetscDS ds;

  PetscFunctionBeginUser;
  if (!s->data.n_robin) PetscFunctionReturn(0);
  PetscCall(DMGetLabel(s->dm, "Face Sets", &label));
  PetscCall(DMGetDS(s->dm, &ds));
  for (PetscInt b = 0; b < s->data.n_robin; ++b) {
    const PetscInt face = s->data.robin_faces[b];
    PetscWeakForm  wf;
    PetscInt       bd;
    char           name[64];

    /* not FEM_TRACTION_BOUNDARY's name: a term in eta, with a Jacobian, on every backend */
    PetscCall(PetscSNPrintf(name, sizeof(name), "robin_%" PetscInt_FMT, face));
    PetscCall(DMAddBoundary(s->dm, DM_BC_NATURAL, name, label, 1, &face, 0, 0, NULL, NULL, NULL, NULL, &bd));
    PetscCall(PetscDSGetBoundary(ds, bd, &wf, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL, NULL));
    PetscCall(PetscWeakFormAddBdResidual(wf, label, face, 0, 0, robin_f0[b], NULL));
    PetscCall(PetscWeakFormAddBdJacobian(wf, label, face, 0, 0, 0, robin_g0[b], NULL, NULL, NULL));
  }
  PetscFunctionReturn(0);
}

void StructureRobinShifts(Structure s, PetscReal op, PetscReal rate, PetscInt nconstants, PetscScalar constants[])
{
  for (PetscInt b = 0; b < s->data.n_robin; ++b)
    constants[nconstants - 1 - b] = op * s->data.robin_stiffness[b] + rate * s->data.robin_damping[b];
}
