#ifndef FSIOPT_ACCELERATION_H
#define FSIOPT_ACCELERATION_H
#include "coupling_impl.h"

/* The partitioned family (partitioned.c) iterates u_{k+1} = update(u_k, S(u_k), r_k) with
   S one Dirichlet-Neumann sweep and r_k = S(u_k) - u_k. What `update` does is the
   acceleration, one file each (the shape of preCICE's acceleration module):
     acceleration_constant.c  dn      u + omega r, omega fixed
     acceleration_aitken.c    aitken  Aitken's dynamic relaxation, the seed's reference
     acceleration_iqnils.c    iqnils  interface quasi-Newton, least-squares inverse Jacobian
     acceleration_iqnimvj.c   iqnimvj interface quasi-Newton, multi-vector inverse Jacobian
   (the last two share their columns and QR: acceleration_iqn.c) */
typedef struct _p_Acceleration *Acceleration;
struct _p_Acceleration {
  PetscReal omega;     /* the relaxation of a step without a model (-coupling_omega); aitken: the one in use */
  PetscInt  model_its; /* the first iterations build a model: the divergence test waits for them */
  struct {
    PetscErrorCode (*setup)(Acceleration, Vec model);          /* its options and work vectors */
    PetscErrorCode (*begin_step)(Acceleration, PetscInt step); /* may be NULL */
    PetscErrorCode (*update)(Acceleration, PetscInt step, PetscInt k, Vec u, Vec sweep, Vec r); /* u_k -> u_{k+1} */
    PetscErrorCode (*reset)(
      Acceleration); /* forget what was learnt with another dt or before a checkpoint; may be NULL */
    PetscErrorCode (*destroy)(Acceleration); /* may be NULL */
  } ops;
  void *data;
};

/* The partitioned method with acceleration `acc` (whose ops and defaults are set). */
PetscErrorCode CouplingCreate_Partitioned(Coupling, Acceleration acc);
#endif
