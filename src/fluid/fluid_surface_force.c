/* The force of the fluid on a body as the boundary integral of sigma n of the discrete
   solution, F_c = -int_body (sigma_h n)_c with sigma_h = 2 mu D(u_h) - p_h I and n the
   fluid's outward normal: a check on the volume-weighted form of fluid_forces.c, which
   converges one order faster (-probes_surface_force).
   The integration is our own: PETSc 3.18's boundary integration takes the supporting cell's
   Jacobian at the face quadrature read as cell points when the coordinates are of degree 1,
   which is right on affine cells only; on a moved quadrilateral its gradients are off by
   O(h) times the distortion. Here the cell's Jacobian is evaluated where PETSc's face
   tabulation places the face's quadrature points in the reference cell. */
#include "fluid_impl.h"
#include "fem.h"

/* The points of fe's face quadrature on the reference cell's face `face`, as
   PetscFEGetFaceTabulation places them (points[nq * dim]). */
static PetscErrorCode ReferenceFacePoints(PetscFE fe, PetscInt face, PetscInt dim, PetscReal points[])
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

PetscErrorCode FluidBodyForceSurface(Fluid f, PetscReal force[3])
{
  PetscDS            ds;
  PetscFE            fe[2];
  PetscSection       section;
  IS                 faces;
  PetscInt           dim, n, nfields, total, nq, nq_pressure;
  const PetscScalar *constants;
  PetscInt           nconstants;

  PetscFunctionBeginUser;
  PetscCheck(f->data.n_force_faces, f->comm, PETSC_ERR_ARG_WRONGSTATE,
             "the scene names no body faces for a fluid force");
  PetscCall(DMGetDimension(f->dm, &dim));
  PetscCall(DMGetDS(f->dm, &ds));
  PetscCall(PetscDSGetNumFields(ds, &nfields));
  PetscCheck(nfields == 2, f->comm, PETSC_ERR_PLIB, "fluid surface force: expected velocity and pressure fields");
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
             "fluid surface force: velocity and pressure need the same face quadrature");
  PetscCall(DMGetLocalSection(f->dm, &section));
  PetscCall(FluidGlobalToLocal(f, f->x, f->xlocal_work));
  PetscCall(FluidBodyFaces(f, &faces));
  PetscCall(ISGetLocalSize(faces, &n));
  for (PetscInt c = 0; c < 3; ++c) force[c] = 0;
  if (n) {
    const PetscInt  *face;
    const PetscReal *weights;
    PetscFEGeom     *geometry;
    PetscTabulation  T[2];
    PetscQuadrature  quadrature, cell_points[6] = {NULL, NULL, NULL, NULL, NULL, NULL}; /* per local face */
    PetscReal       *x, *J, *invJ, *detJ;
    PetscInt         every;

    PetscCall(PetscFEGetFaceQuadrature(fe[0], &quadrature));
    PetscCall(PetscQuadratureGetData(quadrature, NULL, NULL, NULL, NULL, &weights));
    PetscCall(PetscFEGetFaceTabulation(fe[0], 1, &T[0]));
    PetscCall(PetscFEGetFaceTabulation(fe[1], 1, &T[1]));
    PetscCall(FEMFaceGeometry(f->dm, fe[0], faces, &geometry)); /* the normals, the faces' |J| */
    every = !geometry->isAffine && geometry->numPoints == nq;
    PetscCheck(total == T[0]->Nb + T[1]->Nb, PETSC_COMM_SELF, PETSC_ERR_PLIB, "fluid surface force: closure size");
    PetscCall(PetscMalloc4(nq * dim, &x, nq * dim * dim, &J, nq * dim * dim, &invJ, nq, &detJ));
    PetscCall(ISGetIndices(faces, &face));
    for (PetscInt e = 0; e < n; ++e) {
      const PetscInt  k = geometry->face[e][0], nb_u = T[0]->Nb, nb_p = T[1]->Nb;
      const PetscInt *support;
      PetscScalar    *coefficients = NULL;

      PetscCheck(k >= 0 && k < 6, PETSC_COMM_SELF, PETSC_ERR_PLIB, "fluid surface force: local face %" PetscInt_FMT, k);
      if (!cell_points[k]) {
        PetscReal *points;
        PetscCall(PetscMalloc1(nq * dim, &points));
        PetscCall(ReferenceFacePoints(fe[0], k, dim, points));
        PetscCall(PetscQuadratureCreate(PETSC_COMM_SELF, &cell_points[k]));
        PetscCall(PetscQuadratureSetData(cell_points[k], dim, 1, nq, points, NULL));
      }
      PetscCall(DMPlexGetSupport(f->dm, face[e], &support));
      PetscCall(DMPlexComputeCellGeometryFEM(f->dm, support[0], cell_points[k], x, J, invJ, detJ));
      PetscCall(DMPlexVecGetClosure(f->dm, section, f->xlocal_work, support[0], NULL, &coefficients));
      for (PetscInt q = 0; q < nq; ++q) {
        const PetscInt   g    = e * geometry->numPoints + (every ? q : 0);
        const PetscReal *Tu   = T[0]->T[0] + (k * nq + q) * nb_u * dim,
                        *Du   = T[0]->T[1] + (k * nq + q) * nb_u * dim * dim;
        const PetscReal *Tp   = T[1]->T[0] + (k * nq + q) * nb_p;
        PetscScalar      u[3] = {0, 0, 0}, grad[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0}, p = 0;
        PetscReal        traction[3];

        for (PetscInt b = 0; b < nb_u; ++b)
          for (PetscInt c = 0; c < dim; ++c) {
            u[c] += coefficients[b] * Tu[b * dim + c];
            for (PetscInt d = 0; d < dim; ++d)
              for (PetscInt r = 0; r < dim; ++r)
                grad[c * dim + d] += coefficients[b] * Du[(b * dim + c) * dim + r] * invJ[q * dim * dim + r * dim + d];
          }
        for (PetscInt b = 0; b < nb_p; ++b) p += coefficients[nb_u + b] * Tp[b];
        Traction(f, dim, u, grad, p, &x[q * dim], &geometry->n[g * dim], nconstants, constants, traction);
        for (PetscInt c = 0; c < dim; ++c) force[c] += weights[q] * geometry->detJ[g] * traction[c];
      }
      PetscCall(DMPlexVecRestoreClosure(f->dm, section, f->xlocal_work, support[0], NULL, &coefficients));
    }
    for (PetscInt k = 0; k < 6; ++k) PetscCall(PetscQuadratureDestroy(&cell_points[k]));
    PetscCall(ISRestoreIndices(faces, &face));
    PetscCall(PetscFree4(x, J, invJ, detJ));
    PetscCall(PetscFEGeomDestroy(&geometry));
  }
  PetscCall(ISDestroy(&faces));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, force, 3, MPIU_REAL, MPIU_SUM, f->comm));
  PetscFunctionReturn(0);
}
