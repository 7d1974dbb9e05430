#ifndef FSIOPT_INTERFACE_H
#define FSIOPT_INTERFACE_H
#include "fsiopt.h"

/* The conforming fluid-structure interface (docs/design.md §3, "a matrix view").

   An interface vector holds one value per interface node and component, laid out on
   the parent communicator in the fluid's ownership and order (the fluid numbers the
   interface). The structure's own interface nodes are matched to the fluid's by their
   coordinates, and a VecScatter on the parent communicator moves values between the
   two orderings, so the fluid and the structure may live on different ranks.

   The control space is the trace of the fluid's velocity test space: the interface
   nodes where the fluid velocity is free. Controls and interface velocity jumps are
   vectors over those nodes only ("control vectors").

   Every function is collective on the parent communicator; a rank that holds no fluid
   (or no structure) passes NULL for that side's vectors. */
typedef struct _p_Interface *Interface;

/* how the interface mass becomes the diagonal weight of the objective (-coupling_interface_lumping) */
typedef enum {
  INTERFACE_LUMPING_AUTO,
  INTERFACE_LUMPING_ROW_SUM,
  INTERFACE_LUMPING_HRZ
} InterfaceLumping;
extern const char *const InterfaceLumpings[];

PetscErrorCode InterfaceCreate(MPI_Comm comm, DM fluid, PetscInt fluid_face, DM structure, PetscInt structure_face,
                               Interface *);
PetscErrorCode InterfaceDestroy(Interface *);

PetscErrorCode InterfaceCreateVector(Interface, Vec *);        /* all interface nodes */
PetscErrorCode InterfaceCreateControlVector(Interface, Vec *); /* fluid-free nodes */
/* The interface mass matrix (vector-valued, all interface nodes): (M g)_i = (g, phi_i)_Gamma. */
PetscErrorCode InterfaceGetMass(Interface, Mat *);
/* The lumped interface mass on the control nodes (a diagonal L2 weight): its row sums, or its
   diagonal scaled to the same total where row sums vanish (-coupling_interface_lumping). */
PetscErrorCode InterfaceGetLumpedControlMass(Interface, Vec *);

/* control <-> interface: restriction to the control nodes and zero extension */
PetscErrorCode InterfaceRestrict(Interface, Vec all, Vec control);
PetscErrorCode InterfaceExtend(Interface, Vec control, Vec all);

/* Velocity traces from local vectors (field 0, boundary values included as they are
   in the local vector) and their adjoints: spreading interface values into the free
   rows of a global vector (insert; constrained nodes are dropped). */
PetscErrorCode InterfaceFluidTrace(Interface, Vec fluid_local, Vec all);
PetscErrorCode InterfaceFluidSpread(Interface, Vec all, Vec fluid_global);
/* The adjoint of the spreading: the free interface rows of a fluid global vector (a
   load, e.g. a reaction) as an interface vector; 0 at constrained nodes. */
PetscErrorCode InterfaceFluidGather(Interface, Vec fluid_global, Vec all);
/* The fluid's free interface rows (global indices, this rank's), every component. */
PetscErrorCode InterfaceGetFluidRows(Interface, IS *rows);
PetscErrorCode InterfaceStructureTrace(Interface, Vec structure_local, Vec all);
PetscErrorCode InterfaceStructureSpread(Interface, Vec all, Vec structure_global);
/* Overwrites the structure's owned interface values (all components) in a local vector. */
PetscErrorCode InterfaceStructureInsertLocal(Interface, Vec all, Vec structure_local);

/* Interpolates a closed form (with its context) at the interface nodes at time t. */
PetscErrorCode InterfaceInterpolate(Interface, FieldFn, void *ctx, PetscReal t, Vec all);
/* This rank's interface nodes in the order of its part of an interface vector: the
   fluid mesh points carrying them and their reference coordinates. */
PetscErrorCode InterfaceGetFluidNodes(Interface, PetscInt *n, const PetscInt **points, const PetscReal **coords);
#endif
