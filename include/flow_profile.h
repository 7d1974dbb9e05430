/* A velocity inlet given by its flow rate Q(t) through a face set of any shape (flow_profile.c):
   the velocity -n Q(t) s(x) / int s over the face set, n its mean outward normal, with the
   shape s a plug (1), a parabola (1 - (r/R)^2: r the distance from the face set's centroid
   across it, R its equivalent radius sqrt(A/pi), or its half-length in 2D), or Womersley's
   profiles of a periodic Q, harmonic by harmonic (a tube of radius R in 3D, a channel of
   half-width R in 2D). Each shape is scaled by its flow rate as the fluid interpolates and
   integrates it, so the discrete inflow is Q(t) (Womersley's: its harmonics' sum) whatever
   the mesh resolves of the profile. */
#ifndef FSIOPT_FLOW_PROFILE_H
#define FSIOPT_FLOW_PROFILE_H
#include "fsiopt.h"
#include "expression.h"

typedef enum {
  FLOW_PROFILE_PLUG,
  FLOW_PROFILE_PARABOLIC,
  FLOW_PROFILE_WOMERSLEY
} FlowProfileKind;

typedef struct _p_FlowProfile *FlowProfile;

/* option: the inlet's, for messages; flow_rate: an expression in t (its own, the profile destroys it); period: Womersley's
   (the flow rate's Fourier series over it, `harmonics` of them), ignored by the others. */
PetscErrorCode FlowProfileCreate(const char option[], FlowProfileKind, Expression flow_rate, PetscReal period,
                                 PetscInt harmonics, FlowProfile *);
/* The geometry of the face set `face` of dm, the kinematic viscosity nu (Womersley's), and
   each shape's flow rate as the fluid interpolates it, which the profile is scaled by:
   PhysicsData.dirichlet_setup; collective. */
PetscErrorCode FlowProfileSetUp(DM dm, PetscInt face, PetscReal nu, const FluxMeasure *, void *profile);
/* the velocity at (t, x): a FieldFn with the profile as its ctx */
PetscErrorCode FlowProfileVelocity(PetscInt dim, PetscReal t, const PetscReal x[], PetscInt Nc, PetscScalar *u,
                                   void *profile);
PetscErrorCode FlowProfileDestroy(FlowProfile *);
#endif
