#ifndef FSIOPT_FEM_CEED_H
#define FSIOPT_FEM_CEED_H
#include <petscdmplex.h>
#include <ceed.h>

/* libCEED, the fast backend of the finite-element operators (DESIGN §5): the pieces of a
   CeedOperator taken from a DMPlex and its PetscFE, so that an operator integrates what
   PETSc's integration does, at the same quadrature points with the same basis values. */

/* A libCEED call checked: its error becomes a PETSc error with libCEED's message. */
#define PetscCallCeed(ceed, call) \
  do { \
    if ((call) != CEED_ERROR_SUCCESS) { \
      const char *ceed_message = "(no message)"; \
      if (ceed) CeedGetErrorMessage(ceed, &ceed_message); \
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_LIB, "libCEED: %s", ceed_message); \
    } \
  } while (0)

/* The run's Ceed, of the backend -ceed (default /cpu/self/opt/blocked); made on first use. */
PetscErrorCode FEMCeedGet(Ceed *);

/* The element restriction of field `field` of dm's local vectors (DMPlexGetLocalOffsets:
   the nodes of each cell in closure order, components interlaced). */
PetscErrorCode FEMCeedRestriction(Ceed, DM dm, PetscInt field, CeedElemRestriction *);
/* The H1 basis of fe at fe's quadrature: the values and reference gradients PETSc tabulates
   (one scalar basis for every component), the same points and weights. */
PetscErrorCode FEMCeedBasis(Ceed, DM dm, PetscFE fe, CeedBasis *);
/* The cells' coordinates: their restriction and basis at fe's quadrature, and the local
   coordinate vector as a CeedVector. */
PetscErrorCode FEMCeedCoordinates(Ceed, DM dm, PetscFE fe, CeedElemRestriction *, CeedBasis *, CeedVector *);

/* The geometry at fe's quadrature points of every cell, for the operators' pointwise
   functions (qfunctions_geometry.h): [w |det A|, A^{-1}], 1 + dim^2 values per point. */
PetscErrorCode FEMCeedGeometry(Ceed, DM dm, PetscFE fe, CeedElemRestriction *r_q, CeedVector *qdata);

/* An AIJ matrix of dm's global size for MatSetPreallocationCOO (DMCreateMatrix's would leak
   its variable block sizes there, PETSc 3.18). */
PetscErrorCode FEMCeedCreateCOOMatrix(DM dm, Mat *);

/* COO assembly of n operators (NULL ones skipped: absent blocks) into A: the pattern once
   (counts[b]: the entries of ops[b]), then the values per assembly. */
PetscErrorCode FEMCeedAssemblySetUp(Ceed, DM dm, PetscInt n, const CeedOperator ops[], Mat A, CeedSize counts[]);
PetscErrorCode FEMCeedAssemble(Ceed, PetscInt n, const CeedOperator ops[], const CeedSize counts[], Mat A);

/* ||ceed - petsc||_F / ||petsc||_F (ceed is overwritten by the difference) */
PetscErrorCode FEMCeedMatDifference(Mat ceed, Mat petsc, PetscReal *difference);

/* -ceed_check_spaces: every field of dm, its mass and Laplacian matrices assembled by libCEED
   (CeedOperatorLinearAssemble into the PETSc matrix by COO) against PETSc's; prints the
   relative differences and fails above tol. */
PetscErrorCode FEMCeedCheckSpaces(DM dm, const char name[], PetscReal tol);
/* -ceed_check_fluid: the fluid's volume residual (Navier-Stokes, fixed mesh, the weak form of
   fluid_kernels.c) by libCEED against PETSc's at a random state on each rank's cells, and
   the time of each per residual; fails above tol. */
PetscErrorCode FEMCeedCheckFluidResidual(DM fluid_dm, PetscReal tol);
#endif
