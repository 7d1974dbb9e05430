#ifndef FSIOPT_INTERFACE_IMPL_H
#define FSIOPT_INTERFACE_IMPL_H
/* What the files of the interface share: the object, and the node matching by coordinates
   (interface_match.c) that InterfaceCreate (interface.c) starts with. */
#include "interface.h"
#include "fem_ceed.h"

/* The interface nodes one rank owns on one side, in increasing point number. */
typedef struct {
  PetscInt   n;
  PetscInt  *point;  /* DMPlex point carrying the node */
  PetscReal *coords; /* n * dim */
  PetscInt  *local;  /* offset of component 0 of field 0 in the local vector */
  PetscInt  *global; /* index of component 0 in the global vector; -1 when constrained */
} Side;

struct _p_Interface {
  MPI_Comm   comm;
  PetscInt   dim;
  Side       fluid, structure;
  PetscInt   ncontrol, *control; /* fluid nodes (indices into `fluid`) with a free velocity */
  Vec        all, structure_all, control_template;
  VecScatter structure_to_fluid;
  Mat        mass;
  Vec        lumped_control;
};

PetscErrorCode InterfaceSideDestroy(Side *);
/* the nodes of face set `face` this rank owns, in increasing point number (name: the side, for messages) */
PetscErrorCode InterfaceSideCollect(DM, PetscInt face, const char name[], Side *);
/* pairs every fluid node with the structure node at its coordinates (within rtol of the
   interface's size), or stops naming the first that has none */
PetscErrorCode InterfaceMatch(Interface, PetscReal rtol, PetscInt fluid_face, PetscInt structure_face);
#endif
