/* Integrals over face sets of the fluid's discrete solution: the area (2D: length), the flow
   rate int u_h . n, int p_h, and the force -int sigma_h n with sigma_h = 2 mu D(u_h) - p_h I,
   n the fluid's outward normal. They serve the integrals of probes.csv (-integrals_*), the 0D
   outlets (fluid_outlets.c), and the body force as a boundary integral (-probes_surface_force):
   a check on the volume-weighted form of fluid_forces.c, which converges one order faster.
   The integration is our own: PETSc 3.18's boundary integration takes the supporting cell's
   Jacobian at the face quadrature read as cell points when the coordinates are of degree 1,
   which is right on affine cells only; on a moved quadrilateral its gradients are off by
   O(h) times the distortion. Here the cell's Jacobian is evaluated where PETSc's face
   tabulation places the face's quadrature points in the reference cell, and the area-weighted
   normal follows from it (Nanson: n dA = det J J^{-T} N dA_ref, N the reference face's):
   PETSc's face geometry of a non-affine face (a hexahedron's bilinear face) is ordered in the
   face's own orientation, not the cell's, and pairs the wrong points on a rotated face. */
#include "fluid_impl.h"
#include "fem.h"

/* The points of fe's face quadrature on the reference cell's face `face`, as
   PetscFEGetFaceTabulation places them (points[nq * dim]), the face's outward unit normal
   and the ratio of its area to the quadrature weights' sum. */
static PetscErrorCode ReferenceFacePoints(PetscFE fe, PetscInt face, PetscInt dim, PetscReal points[],
                                          PetscReal normal[3], PetscReal *scale)
{
  PetscDualSpace   space;
  PetscQuadrature  quadrature;
  DM               reference;
  const PetscInt  *faces;
  const PetscReal *xi;
  PetscReal        v0[3], J[9], detJ;
  PetscInt         nq;

  PetscFunctionBeginUser;
  PetscCall(PetscFEGetDualSpace(fe, &space));
  PetscCall(PetscDualSpaceGetDM(space, &reference));
  PetscCall(DMPlexGetCone(reference, 0, &faces));
  PetscCall(DMPlexComputeCellGeometryFEM(reference, faces[face], NULL, v0, J, NULL, &detJ));
  PetscCall(PetscFEGetFaceQuadrature(fe, &quadrature));
  PetscCall(PetscQuadratureGetData(quadrature, NULL, NULL, &nq, &xi, NULL));
  for (PetscInt q = 0; q < nq; ++q)
    for (PetscInt d = 0; d < dim; ++d) {
      points[q * dim + d] = v0[d];
      for (PetscInt e = 0; e < dim - 1; ++e) points[q * dim + d] += J[d * dim + e] * (xi[q * (dim - 1) + e] + 1.0);
    }
  {
    const PetscReal *w;
    PetscReal        area, centroid[3], cell_centroid[3], length = 0, outward = 0, sum = 0;
    PetscCall(PetscQuadratureGetData(quadrature, NULL, NULL, NULL, NULL, &w));
    PetscCall(DMPlexComputeCellGeometryFVM(reference, faces[face], &area, centroid, normal));
    PetscCall(DMPlexComputeCellGeometryFVM(reference, 0, NULL, cell_centroid, NULL));
    for (PetscInt d = 0; d < dim; ++d) {
      length += normal[d] * normal[d];
      outward += normal[d] * (centroid[d] - cell_centroid[d]);
    }
    length = PetscSqrtReal(length) * (outward < 0 ? -1.0 : 1.0);
    for (PetscInt d = 0; d < dim; ++d) normal[d] /= length;
    for (PetscInt q = 0; q < nq; ++q) sum += w[q];
    *scale = area / sum;
  }
  PetscFunctionReturn(0);
}

/* -(sigma_h n) of one quadrature point, with the scene's exact stress (the volume-form data
   of a manufactured solution, which the volume-weighted force subtracts too) */
static void Traction(Fluid f, PetscInt dim, const PetscScalar u[], const PetscScalar grad[], PetscScalar p,
                     const PetscReal x[], const PetscReal n[], PetscInt nconstants, const PetscScalar constants[],
                     PetscReal traction[])
{
  const PetscScalar mu        = constants[FLUID_MU];
  PetscScalar       data[9]   = {0, 0, 0, 0, 0, 0, 0, 0, 0};
  const PetscInt    uOff[2]   = {0, dim};
  const PetscInt    uOff_x[2] = {0, dim * dim};
  PetscScalar       fields[4], gradients[3 * 3 + 3];

  if (f->data.load_stress_kernel) {
    for (PetscInt c = 0; c < dim; ++c) fields[c] = u[c];
    fields[dim] = p;
    for (PetscInt i = 0; i < dim * dim; ++i) gradients[i] = grad[i];
    for (PetscInt i = 0; i < dim; ++i) gradients[dim * dim + i] = 0; /* the pressure's: unused */
    f->data.load_stress_kernel(dim, 2, 0, uOff, uOff_x, fields, NULL, gradients, NULL, NULL, NULL, NULL, NULL,
                               PetscRealPart(constants[FLUID_TIME]), x, nconstants, constants, data);
  }
  for (PetscInt c = 0; c < dim; ++c) {
    PetscScalar t = 0;
    for (PetscInt d = 0; d < dim; ++d) {
      const PetscScalar sigma = mu * (grad[c * dim + d] + grad[d * dim + c]) - (c == d ? p : 0.0);
      t += (sigma + data[c * dim + d]) * n[d];
    }
    traction[c] = -PetscRealPart(t);
  }
}

/* The faces (height 1) of the face sets `values` on this rank, sorted, each once. */
PetscErrorCode FluidFaceSetFaces(Fluid f, PetscInt n, const PetscInt values[], IS *faces)
{
  DMLabel  label;
  PetscInt fstart, fend, count = 0, *list = NULL;

  PetscFunctionBeginUser;
  PetscCall(DMGetLabel(f->dm, "Face Sets", &label));
  PetscCall(DMPlexGetHeightStratum(f->dm, 1, &fstart, &fend));
  for (PetscInt pass = 0; pass < 2; ++pass) {
    count = 0;
    for (PetscInt b = 0; b < n; ++b) {
      IS              stratum = NULL;
      const PetscInt *point;
      PetscInt        npoints = 0;

      if (label) PetscCall(DMLabelGetStratumIS(label, values[b], &stratum));
      if (!stratum) continue;
      PetscCall(ISGetLocalSize(stratum, &npoints));
      PetscCall(ISGetIndices(stratum, &point));
      for (PetscInt i = 0; i < npoints; ++i)
        if (point[i] >= fstart && point[i] < fend) {
          if (pass) list[count] = point[i];
          ++count;
        }
      PetscCall(ISRestoreIndices(stratum, &point));
      PetscCall(ISDestroy(&stratum));
    }
    if (!pass) PetscCall(PetscMalloc1(count, &list));
  }
  PetscCall(PetscSortRemoveDupsInt(&count, list));
  PetscCall(ISCreateGeneral(PETSC_COMM_SELF, count, list, PETSC_OWN_POINTER, faces));
  PetscFunctionReturn(0);
}

/* The integrals over `faces` (this rank's) of the state xlocal, summed over the fluid's ranks;
   with flux_local, also the flow rate's derivative dQ/du, int phi_i . n, added into it. */
PetscErrorCode FluidIntegrateFaces(Fluid f, Vec xlocal, IS faces, FluidFaceIntegral *integral, Vec flux_local)
{
  PetscDS            ds;
  PetscFE            fe[2];
  PetscSection       section;
  PetscInt           dim, n, nfields, total, nq, nq_pressure;
  const PetscScalar *constants;
  PetscInt           nconstants;
  PetscReal          sums[7] = {0, 0, 0, 0, 0, 0, 0}; /* area, flow rate, pressure, force, |wall shear| */

  PetscFunctionBeginUser;
  PetscCall(DMGetDimension(f->dm, &dim));
  PetscCall(DMGetDS(f->dm, &ds));
  PetscCall(PetscDSGetNumFields(ds, &nfields));
  PetscCheck(nfields == 2, f->comm, PETSC_ERR_PLIB, "fluid face integrals: expected velocity and pressure fields");
  PetscCall(PetscDSGetTotalDimension(ds, &total));
  PetscCall(PetscDSGetConstants(ds, &nconstants, &constants));
  for (PetscInt field = 0; field < 2; ++field) {
    PetscQuadrature quadrature;
    PetscCall(PetscDSGetDiscretization(ds, field, (PetscObject *)&fe[field]));
    PetscCall(FEMFacesMakeSharedObjects(f->dm, fe[field]));
    PetscCall(PetscFEGetFaceQuadrature(fe[field], &quadrature));
    PetscCall(PetscQuadratureGetData(quadrature, NULL, NULL, field ? &nq_pressure : &nq, NULL, NULL));
  }
  PetscCheck(nq == nq_pressure, f->comm, PETSC_ERR_SUP,
             "fluid face integrals: velocity and pressure need the same face quadrature");
  PetscCall(DMGetLocalSection(f->dm, &section));
  PetscCall(ISGetLocalSize(faces, &n));
  if (n) {
    const PetscInt  *face;
    const PetscReal *weights;
    PetscFEGeom     *geometry;
    PetscTabulation  T[2];
    PetscQuadrature  quadrature, cell_points[6] = {NULL, NULL, NULL, NULL, NULL, NULL}; /* per local face */
    PetscReal        reference_normal[6][3], reference_scale[6];
    PetscReal       *x, *J, *invJ, *detJ;
    PetscScalar     *element = NULL;

    PetscCall(PetscFEGetFaceQuadrature(fe[0], &quadrature));
    PetscCall(PetscQuadratureGetData(quadrature, NULL, NULL, NULL, NULL, &weights));
    PetscCall(PetscFEGetFaceTabulation(fe[0], 1, &T[0]));
    PetscCall(PetscFEGetFaceTabulation(fe[1], 1, &T[1]));
    PetscCall(FEMFaceGeometry(f->dm, fe[0], faces, &geometry)); /* each face's number in its cell */
    PetscCheck(total == T[0]->Nb + T[1]->Nb, PETSC_COMM_SELF, PETSC_ERR_PLIB, "fluid face integrals: closure size");
    PetscCall(PetscMalloc4(nq * dim, &x, nq * dim * dim, &J, nq * dim * dim, &invJ, nq, &detJ));
    if (flux_local) PetscCall(PetscMalloc1(total, &element));
    PetscCall(ISGetIndices(faces, &face));
    for (PetscInt e = 0; e < n; ++e) {
      const PetscInt  k = geometry->face[e][0], nb_u = T[0]->Nb, nb_p = T[1]->Nb;
      const PetscInt *support;
      PetscScalar    *coefficients = NULL;

      PetscCheck(k >= 0 && k < 6, PETSC_COMM_SELF, PETSC_ERR_PLIB, "fluid face integrals: local face %" PetscInt_FMT, k);
      if (!cell_points[k]) {
        PetscReal *points;
        PetscCall(PetscMalloc1(nq * dim, &points));
        PetscCall(ReferenceFacePoints(fe[0], k, dim, points, reference_normal[k], &reference_scale[k]));
        PetscCall(PetscQuadratureCreate(PETSC_COMM_SELF, &cell_points[k]));
        PetscCall(PetscQuadratureSetData(cell_points[k], dim, 1, nq, points, NULL));
      }
      PetscCall(DMPlexGetSupport(f->dm, face[e], &support));
      PetscCall(DMPlexComputeCellGeometryFEM(f->dm, support[0], cell_points[k], x, J, invJ, detJ));
      PetscCall(DMPlexVecGetClosure(f->dm, section, xlocal, support[0], NULL, &coefficients));
      if (element) PetscCall(PetscArrayzero(element, total));
      for (PetscInt q = 0; q < nq; ++q) {
        const PetscReal *Tu   = T[0]->T[0] + (k * nq + q) * nb_u * dim,
                        *Du   = T[0]->T[1] + (k * nq + q) * nb_u * dim * dim;
        const PetscReal *Tp   = T[1]->T[0] + (k * nq + q) * nb_p;
        const PetscReal *iJ   = &invJ[q * dim * dim];
        PetscScalar      u[3] = {0, 0, 0}, grad[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0}, p = 0;
        PetscReal        traction[3], normal[3] = {0, 0, 0}, length = 0, w;

        for (PetscInt d = 0; d < dim; ++d) { /* det J J^{-T} N */
          for (PetscInt r = 0; r < dim; ++r) normal[d] += iJ[r * dim + d] * reference_normal[k][r];
          normal[d] *= detJ[q];
          length += normal[d] * normal[d];
        }
        length = PetscSqrtReal(length);
        for (PetscInt d = 0; d < dim; ++d) normal[d] /= length;
        w = weights[q] * reference_scale[k] * length;

        for (PetscInt b = 0; b < nb_u; ++b)
          for (PetscInt c = 0; c < dim; ++c) {
            u[c] += coefficients[b] * Tu[b * dim + c];
            for (PetscInt d = 0; d < dim; ++d)
              for (PetscInt r = 0; r < dim; ++r)
                grad[c * dim + d] += coefficients[b] * Du[(b * dim + c) * dim + r] * invJ[q * dim * dim + r * dim + d];
          }
        for (PetscInt b = 0; b < nb_p; ++b) p += coefficients[nb_u + b] * Tp[b];
        Traction(f, dim, u, grad, p, &x[q * dim], normal, nconstants, constants, traction);
        sums[0] += w;
        for (PetscInt c = 0; c < dim; ++c) sums[1] += w * PetscRealPart(u[c]) * normal[c];
        sums[2] += w * PetscRealPart(p);
        for (PetscInt c = 0; c < dim; ++c) sums[3 + c] += w * traction[c];
        { /* the wall shear stress: the traction's part along the face, t - (t.n) n */
          PetscReal tn = 0, shear = 0;
          for (PetscInt c = 0; c < dim; ++c) tn += traction[c] * normal[c];
          for (PetscInt c = 0; c < dim; ++c) shear += PetscSqr(traction[c] - tn * normal[c]);
          sums[6] += w * PetscSqrtReal(shear);
        }
        for (PetscInt b = 0; b < nb_u && element; ++b)
          for (PetscInt c = 0; c < dim; ++c) element[b] += w * Tu[b * dim + c] * normal[c];
      }
      if (element) PetscCall(DMPlexVecSetClosure(f->dm, section, flux_local, support[0], element, ADD_VALUES));
      PetscCall(DMPlexVecRestoreClosure(f->dm, section, xlocal, support[0], NULL, &coefficients));
    }
    for (PetscInt k = 0; k < 6; ++k) PetscCall(PetscQuadratureDestroy(&cell_points[k]));
    PetscCall(ISRestoreIndices(faces, &face));
    PetscCall(PetscFree4(x, J, invJ, detJ));
    PetscCall(PetscFree(element));
    PetscCall(PetscFEGeomDestroy(&geometry));
  }
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sums, 7, MPIU_REAL, MPIU_SUM, f->comm));
  integral->area      = sums[0];
  integral->flow_rate = sums[1];
  integral->pressure  = sums[2];
  for (PetscInt c = 0; c < 3; ++c) integral->force[c] = sums[3 + c];
  integral->shear = sums[6];
  PetscFunctionReturn(0);
}

PetscErrorCode FluidFaceSetIntegral(Fluid f, PetscInt n, const PetscInt values[], FluidFaceIntegral *integral)
{
  IS faces;

  PetscFunctionBeginUser;
  PetscCall(FluidGlobalToLocal(f, f->x, f->xlocal_work));
  PetscCall(FluidFaceSetFaces(f, n, values, &faces));
  PetscCall(FluidIntegrateFaces(f, f->xlocal_work, faces, integral, NULL));
  PetscCall(ISDestroy(&faces));
  PetscFunctionReturn(0);
}

PetscErrorCode FluidInterpolatedFlux(void *ctx, PetscInt face, FieldFn fn, void *fn_ctx, PetscReal *flux)
{
  Fluid             f = (Fluid)ctx;
  Vec               x;
  IS                faces;
  FluidFaceIntegral integral;
  FieldFn           fns[2]  = {fn, FEMZero};
  void             *ctxs[2] = {fn_ctx, NULL};

  PetscFunctionBeginUser;
  PetscCall(DMGetLocalVector(f->dm, &x));
  PetscCall(VecZeroEntries(x));
  /* over every cell (a face's trace takes the face's nodes only): PETSc 3.18's projection
     onto a label of faces inserts nothing into a local vector here */
  PetscCall(DMProjectFunctionLocal(f->dm, f->time, fns, ctxs, INSERT_ALL_VALUES, x));
  PetscCall(FluidFaceSetFaces(f, 1, &face, &faces));
  PetscCall(FluidIntegrateFaces(f, x, faces, &integral, NULL));
  PetscCall(ISDestroy(&faces));
  PetscCall(DMRestoreLocalVector(f->dm, &x));
  *flux = integral.flow_rate;
  PetscFunctionReturn(0);
}

PetscErrorCode FluidBodyForceSurface(Fluid f, PetscReal force[3])
{
  FluidFaceIntegral integral;

  PetscFunctionBeginUser;
  PetscCheck(f->data.n_force_faces, f->comm, PETSC_ERR_ARG_WRONGSTATE,
             "the scene names no body faces for a fluid force");
  PetscCall(FluidFaceSetIntegral(f, f->data.n_force_faces, f->data.force_faces, &integral));
  for (PetscInt c = 0; c < 3; ++c) force[c] = integral.force[c];
  PetscFunctionReturn(0);
}
