/* The libCEED fluid's object, shared by ceed_fluid.c (volume terms), ceed_fluid_jacobian.c
   (the assembled Jacobian), ceed_fluid_faces.c (face terms) and ceed_fluid_matfree.c (the
   Jacobian without a matrix). */
#ifndef FSIOPT_CEED_FLUID_IMPL_H
#define FSIOPT_CEED_FLUID_IMPL_H
#include "fem_ceed.h"
#include "fluid_constants.h"
#include "qfunctions_fluid_context.h"

#define FEM_CEED_MAX_FACE_SETS 16

struct _n_FEMCeedFluid {
  Ceed                 ceed;
  DM                   dm;
  PetscFE              velocity_fe;
  FluidVolume          volume;
  CeedElemRestriction  r_u, r_p, r_q, r_z;
  CeedBasis            b_u, b_p, b_z;
  CeedVector           qdata, x, f, state, mesh_velocity;
  CeedQFunctionContext context;
  CeedQFunction        qf_residual, qf_stabilization, qf_block[3], qf_uu_transpose;
  CeedOperator         op_residual, op_stabilization, op_block[4];
  /* the velocity-velocity block's coefficients at the points (ceed_fluid_jacobian.c), the
     old domains' mass in them */
  CeedQFunction       qf_uu_coefficients;
  CeedOperator        op_uu_coefficients;
  CeedElemRestriction r_uu_coefficients;
  CeedVector          uu_coefficients;
  /* the matrix-free products of the last Jacobian, made at the first: operators of their own
     (see MassCreate), the transpose only changing the velocity-velocity block */
  CeedOperator op_apply[5], op_apply_uu_transpose; /* [4]: the old domains' mass */
  CeedVector   apply_state, apply_mesh_velocity, apply_qdata, apply_mass_weight;
  PetscBool    apply_old_mass;
  CeedOperator op_pressure_pattern; /* without a stabilization: the pressure-pressure block's pattern only */
  CeedSize    *counts;              /* of the COO pattern's blocks: the four volume ones, then the faces' */
  /* face terms: per set its faces, per group of a set a residual and a Jacobian operator */
  DM            dm_mesh_velocity;
  PetscInt      n_face_sets, n_face_ops;
  FEMCeedFaces  face_sets[FEM_CEED_MAX_FACE_SETS];
  CeedQFunction qf_face[2][2]; /* [backflow][Jacobian] */
  CeedOperator  face_residual[FEM_CEED_MAX_FACE_SETS * FEM_CEED_MAX_CELL_FACES],
    face_jacobian[FEM_CEED_MAX_FACE_SETS * FEM_CEED_MAX_CELL_FACES];
  /* moving meshes: the old domains' mass, weights per point of two domains and their sum */
  CeedElemRestriction r_x, r_w;
  CeedBasis           b_x;
  CeedVector          coordinates, domain_weight[2], mass_weight;
  CeedQFunction       qf_mass, qf_domain;
  CeedOperator        op_mass, op_domain;                /* the mass applied */
  FEMCeedGeometryKey  geometry;                          /* the coordinates qdata is of */
};

/* the Jacobian's block operators at the passive state, mesh velocity and geometry given;
   the pressure-pressure one only with a stabilization */
PetscErrorCode FEMCeedFluidBlockOperatorsCreate(FEMCeedFluid, CeedQFunction qf_uu, CeedVector state, CeedVector z,
                                                CeedVector qdata, CeedOperator ops[4]);
PetscErrorCode FEMCeedFluidMeshVelocitySet(FEMCeedFluid, Vec z);
/* what the volume operators read at the points besides the state: the geometry, the mesh
   velocity z, and whether the old domains' mass is in (refused on a fixed mesh) */
PetscErrorCode FEMCeedFluidPointsSet(FEMCeedFluid, Vec z, PetscBool old_mass);
/* the face sets' geometry follows the coordinates */
PetscErrorCode FEMCeedFluidFacesGeometry(FEMCeedFluid);
#endif
