/* Velocity inlets given by a flow rate over a face set of any shape (flow_profile.h).
   Womersley's profiles, for the harmonic e^{i k w t} of the flow rate (w = 2 pi / period),
   alpha = R sqrt(k w / nu):
     3D tube of radius R:        s_k(r) = 1 - J0(L r/R) / J0(L),      L = alpha i^{3/2}
     2D channel, half-width R:   s_k(s) = 1 - cosh(l s/R) / cosh(l),  l = alpha sqrt(i)
   (the oscillating Poiseuille flows, Womersley 1955), k = 0 the parabola; each harmonic is
   scaled by its own integral over the face set, so the discrete flow rate of every harmonic
   is its share of Q. J0 by its power series: its terms, at most about e^alpha / alpha, and
   J0 itself, about e^{alpha/sqrt 2}, keep 1e-12 up to alpha = 60, which we require. */
#include "flow_profile.h"
#include <complex.h>

#define MAX_HARMONICS 64

struct _p_FlowProfile {
  char            option[160];
  FlowProfileKind kind;
  Expression      flow_rate;
  PetscReal       period;
  PetscInt        harmonics, dim;
  PetscReal       centroid[3], normal[3], tangent[3], radius; /* of the face set */
  double complex  coefficient[MAX_HARMONICS + 1];             /* Q's Fourier coefficients over the period */
  double complex  lambda[MAX_HARMONICS + 1];                  /* Womersley's L (3D) or l (2D) */
  double complex  integral[MAX_HARMONICS + 1];                /* of each shape over the face set */
};

static double complex BesselJ0(double complex z)
{
  const double complex w = -z * z / 4;
  double complex       term = 1, sum = 1;
  for (int m = 1; m < 400 && cabs(term) > 1e-17 * cabs(sum); ++m) {
    term *= w / ((double)m * m);
    sum += term;
  }
  return sum;
}

/* the shape of harmonic k at the point x: its distance r (3D) or offset s (2D) from the centroid */
static double complex Shape(const struct _p_FlowProfile *P, PetscInt k, const PetscReal x[])
{
  PetscReal d[3] = {0, 0, 0}, along = 0, r2 = 0, rho;

  for (PetscInt c = 0; c < P->dim; ++c) d[c] = x[c] - P->centroid[c];
  if (P->dim == 2) {
    for (PetscInt c = 0; c < 2; ++c) along += d[c] * P->tangent[c];
    r2 = along * along;
  } else {
    for (PetscInt c = 0; c < 3; ++c) along += d[c] * P->normal[c];
    for (PetscInt c = 0; c < 3; ++c) r2 += PetscSqr(d[c] - along * P->normal[c]);
  }
  rho = PetscSqrtReal(r2) / P->radius;
  if (P->kind == FLOW_PROFILE_PLUG) return 1;
  if (P->kind == FLOW_PROFILE_PARABOLIC || k == 0) return rho < 1 ? 1 - rho * rho : 0;
  if (P->dim == 2) return 1 - ccosh(P->lambda[k] * PetscMin(rho, 1.0)) / ccosh(P->lambda[k]);
  return 1 - BesselJ0(P->lambda[k] * PetscMin(rho, 1.0)) / BesselJ0(P->lambda[k]);
}

PetscErrorCode FlowProfileCreate(const char option[], FlowProfileKind kind, Expression flow_rate, PetscReal period,
                                 PetscInt harmonics, FlowProfile *profile)
{
  FlowProfile P;

  PetscFunctionBeginUser;
  PetscCall(PetscNew(&P));
  PetscCall(PetscStrncpy(P->option, option, sizeof(P->option)));
  P->kind      = kind;
  P->flow_rate = flow_rate;
  P->period    = period;
  P->harmonics = kind == FLOW_PROFILE_WOMERSLEY ? PetscMin(harmonics, MAX_HARMONICS) : 0;
  *profile     = P;
  PetscFunctionReturn(0);
}

PetscErrorCode FlowProfileDestroy(FlowProfile *profile)
{
  PetscFunctionBeginUser;
  if (!*profile) PetscFunctionReturn(0);
  PetscCall(ExpressionDestroy(&(*profile)->flow_rate));
  PetscCall(PetscFree(*profile));
  PetscFunctionReturn(0);
}

/* Calls fn(ctx, x, weight) at the quadrature points of every face of the set on this rank
   (Gauss, 24 points a direction, on each face's affine map: a Womersley profile's boundary
   layer, R/alpha thick, may be much thinner than a face) */
static PetscErrorCode ForEachPoint(DM dm, PetscInt face, void (*fn)(void *, const PetscReal[], PetscReal, const PetscReal[]),
                                   void *ctx)
{
  DMLabel         label;
  IS              stratum = NULL;
  const PetscInt *faces;
  PetscInt        n = 0, dim, fstart, fend;
  PetscQuadrature segment, quadrilateral, triangle;

  PetscFunctionBeginUser;
  PetscCall(DMGetDimension(dm, &dim));
  PetscCall(DMPlexGetHeightStratum(dm, 1, &fstart, &fend));
  PetscCall(DMGetLabel(dm, "Face Sets", &label));
  if (label) PetscCall(DMLabelGetStratumIS(label, face, &stratum));
  if (!stratum) PetscFunctionReturn(0);
  PetscCall(PetscDTGaussTensorQuadrature(1, 1, 24, -1.0, 1.0, &segment));
  PetscCall(PetscDTGaussTensorQuadrature(2, 1, 24, -1.0, 1.0, &quadrilateral));
  PetscCall(PetscDTStroudConicalQuadrature(2, 1, 24, -1.0, 1.0, &triangle));
  PetscCall(ISGetLocalSize(stratum, &n));
  PetscCall(ISGetIndices(stratum, &faces));
  for (PetscInt i = 0; i < n; ++i) {
    const PetscInt   f = faces[i];
    DMPolytopeType   type;
    PetscQuadrature  q;
    const PetscReal *xi, *w;
    PetscReal        v0[3], J[9], detJ, area, centroid[3], normal[3], cell_centroid[3], outward = 0;
    const PetscInt  *support;
    PetscInt         nq;

    if (f < fstart || f >= fend) continue;
    PetscCall(DMPlexGetCellType(dm, f, &type));
    q = type == DM_POLYTOPE_SEGMENT ? segment : type == DM_POLYTOPE_TRIANGLE ? triangle : quadrilateral;
    PetscCall(PetscQuadratureGetData(q, NULL, NULL, &nq, &xi, &w));
    PetscCall(DMPlexComputeCellGeometryFEM(dm, f, NULL, v0, J, NULL, &detJ));
    PetscCall(DMPlexComputeCellGeometryFVM(dm, f, &area, centroid, normal));
    PetscCall(DMPlexGetSupport(dm, f, &support));
    PetscCall(DMPlexComputeCellGeometryFVM(dm, support[0], NULL, cell_centroid, NULL));
    for (PetscInt d = 0; d < dim; ++d) outward += normal[d] * (centroid[d] - cell_centroid[d]);
    {
      PetscReal length = 0, unit[3] = {0, 0, 0}, total = 0;
      for (PetscInt d = 0; d < dim; ++d) length += normal[d] * normal[d];
      length = PetscSqrtReal(length) * (outward < 0 ? -1 : 1);
      for (PetscInt d = 0; d < dim; ++d) unit[d] = normal[d] / length;
      for (PetscInt p = 0; p < nq; ++p) total += w[p];
      for (PetscInt p = 0; p < nq; ++p) {
        PetscReal x[3] = {0, 0, 0};
        for (PetscInt d = 0; d < dim; ++d) {
          x[d] = v0[d];
          for (PetscInt e = 0; e < dim - 1; ++e) x[d] += J[d * dim + e] * (xi[p * (dim - 1) + e] + 1.0);
        }
        fn(ctx, x, area * w[p] / total, unit); /* the face's own area: exact for its affine map */
      }
    }
  }
  PetscCall(ISRestoreIndices(stratum, &faces));
  PetscCall(ISDestroy(&stratum));
  PetscCall(PetscQuadratureDestroy(&segment));
  PetscCall(PetscQuadratureDestroy(&quadrilateral));
  PetscCall(PetscQuadratureDestroy(&triangle));
  PetscFunctionReturn(0);
}

typedef struct {
  PetscInt           dim;
  PetscReal          sums[7]; /* area, area x centroid, area x normal */
  struct _p_FlowProfile *P;
  double complex     integral[MAX_HARMONICS + 1];
} Accumulator;

static void AddGeometry(void *ctx, const PetscReal x[], PetscReal weight, const PetscReal normal[])
{
  Accumulator *a = (Accumulator *)ctx;
  a->sums[0] += weight;
  for (PetscInt d = 0; d < a->dim; ++d) {
    a->sums[1 + d] += weight * x[d];
    a->sums[4 + d] += weight * normal[d];
  }
}

static void AddShapes(void *ctx, const PetscReal x[], PetscReal weight, const PetscReal normal[])
{
  Accumulator *a = (Accumulator *)ctx;
  (void)normal;
  for (PetscInt k = 0; k <= a->P->harmonics; ++k) a->integral[k] += weight * Shape(a->P, k, x);
}

/* -n times the real or imaginary part of shape k over its integral: what the fluid measures */
typedef struct {
  struct _p_FlowProfile *P;
  PetscInt               k;
  PetscBool              imaginary;
} ShapePart;

static PetscErrorCode ShapePartVelocity(PetscInt dim, PetscReal t, const PetscReal x[], PetscInt Nc, PetscScalar *u,
                                        void *ctx)
{
  const ShapePart     *s = (const ShapePart *)ctx;
  const double complex g = Shape(s->P, s->k, x) / s->P->integral[s->k];
  const PetscReal      v = s->imaginary ? cimag(g) : creal(g);

  (void)t;
  (void)Nc;
  for (PetscInt d = 0; d < dim; ++d) u[d] = -v * s->P->normal[d];
  return 0;
}

PetscErrorCode FlowProfileSetUp(DM dm, PetscInt face, PetscReal nu, const FluxMeasure *measure, void *profile)
{
  FlowProfile P = (FlowProfile)profile;
  Accumulator a;
  MPI_Comm    comm;
  PetscReal   length = 0, area;

  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)dm, &comm));
  PetscCall(DMGetDimension(dm, &P->dim));
  PetscCall(PetscMemzero(&a, sizeof(a)));
  a.dim = P->dim;
  a.P   = P;
  PetscCall(ForEachPoint(dm, face, AddGeometry, &a));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, a.sums, 7, MPIU_REAL, MPIU_SUM, comm));
  area = a.sums[0];
  PetscCheck(area > 0, comm, PETSC_ERR_ARG_WRONG, "option %s: the face set %" PetscInt_FMT " has no faces", P->option,
             face);
  for (PetscInt d = 0; d < P->dim; ++d) {
    P->centroid[d] = a.sums[1 + d] / area;
    length += PetscSqr(a.sums[4 + d]);
  }
  length = PetscSqrtReal(length);
  PetscCheck(length > 0.5 * area, comm, PETSC_ERR_ARG_WRONG,
             "option %s: the face set %" PetscInt_FMT " is not close to flat (its normals cancel: |int n| = %g of its "
             "area %g); a profile needs one direction",
             P->option, face, (double)length, (double)area);
  for (PetscInt d = 0; d < P->dim; ++d) P->normal[d] = a.sums[4 + d] / length;
  if (P->dim == 2) {
    P->tangent[0] = -P->normal[1];
    P->tangent[1] = P->normal[0];
    P->radius     = area / 2;
  } else P->radius = PetscSqrtReal(area / PETSC_PI);
  for (PetscInt k = 1; k <= P->harmonics; ++k) {
    const PetscReal alpha = P->radius * PetscSqrtReal(2 * PETSC_PI * k / P->period / nu);
    PetscCheck(alpha <= 60, comm, PETSC_ERR_ARG_OUTOFRANGE,
               "option %s: harmonic %" PetscInt_FMT " of the womersley profile has Womersley number %g, beyond the 60 "
               "its series keep to 1e-12; expected fewer harmonics (_harmonics) or a longer period (_period)",
               P->option, k, (double)alpha);
    P->lambda[k] = P->dim == 2 ? alpha * csqrt(I) : alpha * cexp(0.75 * I * PETSC_PI);
  }
  PetscCall(ForEachPoint(dm, face, AddShapes, &a));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, a.integral, 2 * (P->harmonics + 1), MPIU_REAL, MPIU_SUM, comm));
  for (PetscInt k = 0; k <= P->harmonics; ++k) P->integral[k] = a.integral[k];
  /* then by each shape's flow rate as the fluid interpolates and integrates it */
  for (PetscInt k = 0; k <= P->harmonics; ++k) {
    ShapePart real = {P, k, PETSC_FALSE}, imaginary = {P, k, PETSC_TRUE};
    PetscReal re, im = 0;
    PetscCall(measure->flux(measure->ctx, face, ShapePartVelocity, &real, &re));
    if (k) PetscCall(measure->flux(measure->ctx, face, ShapePartVelocity, &imaginary, &im));
    PetscCheck(PetscAbsReal(re) + PetscAbsReal(im) > 0.1, comm, PETSC_ERR_ARG_WRONG,
               "option %s: the mesh carries %g of the profile's flow rate through the face set %" PetscInt_FMT
               "; expected a face set its velocity nodes resolve",
               P->option, (double)(PetscAbsReal(re) + PetscAbsReal(im)), face);
    P->integral[k] *= -(re + I * im);
  }
  /* the flow rate's Fourier coefficients over one period: Q = sum_k Re(c_k e^{i k w t}) */
  if (P->kind == FLOW_PROFILE_WOMERSLEY) {
    const PetscInt samples = 32 * (P->harmonics + 1);
    for (PetscInt k = 0; k <= P->harmonics; ++k) P->coefficient[k] = 0;
    for (PetscInt j = 0; j < samples; ++j) {
      const PetscReal t = P->period * j / samples, origin[3] = {0, 0, 0};
      PetscScalar     q;
      ExpressionEvaluate(P->flow_rate, t, P->dim, origin, &q);
      for (PetscInt k = 0; k <= P->harmonics; ++k)
        P->coefficient[k] += (k ? 2.0 : 1.0) * q * cexp(-I * 2 * PETSC_PI * k * j / samples) / samples;
    }
  }
  PetscFunctionReturn(0);
}

PetscErrorCode FlowProfileVelocity(PetscInt dim, PetscReal t, const PetscReal x[], PetscInt Nc, PetscScalar *u,
                                   void *profile)
{
  const struct _p_FlowProfile *P     = (const struct _p_FlowProfile *)profile;
  PetscReal                    speed = 0;

  (void)Nc;
  if (P->kind == FLOW_PROFILE_WOMERSLEY) {
    const PetscReal omega = 2 * PETSC_PI / P->period;
    for (PetscInt k = 0; k <= P->harmonics; ++k)
      speed += creal(P->coefficient[k] * cexp(I * omega * k * t) * Shape(P, k, x) / P->integral[k]);
  } else {
    const PetscReal origin[3] = {0, 0, 0};
    PetscScalar     q;
    ExpressionEvaluate(P->flow_rate, t, dim, origin, &q);
    speed = q * creal(Shape(P, 0, x) / P->integral[0]);
  }
  for (PetscInt d = 0; d < dim; ++d) u[d] = -speed * P->normal[d]; /* Q > 0 flows in, against n */
  return 0;
}
