#ifndef FSIOPT_FIELDS_H
#define FSIOPT_FIELDS_H
#include "fsiopt.h"
#include "fluid.h"
#include "structure.h"
#include "interface.h"
#include "coupling.h"

/* -write_fields: <output_dir>/fields.h5 and fields.xdmf, a time series ParaView opens:
   the fluid on its moving mesh (velocity, pressure and, where the mesh moves, the mesh
   velocity), the structure on its deformed mesh (displacement, velocity) and, with
   -write_fields_derived, derived fields (vorticity, Q-criterion, the wall's stress, the
   fluid walls' traction, normal and shear stress, the control's traction) on those grids
   and on "walls", the fluid's faces of -write_fields_walls. With -write_fields_nodes all
   (the default) every Lagrange node of a degree-2 field is written and each cell as its
   once-refined cells (fields_grid.c); with vertices, the vertex values on the mesh's cells.
   Written every -write_fields_interval steps, the first and the last step always; both
   files are .partial until FieldWriterFinish.
   fields.h5: attribute /origin (the run that wrote the file), /<grid>/topology (cells x
   nodes per cell, global node numbers), attributes "<dataset> unit" of /<grid>, and
   /<grid>/step_NNNNN/{geometry (nodes x dim), vectors (nodes x 3, z = 0 in 2D: ParaView's
   XDMF vectors have three components), tensors (nodes x 9), scalars (nodes)}, each step
   group with an attribute "time".
   A restart (-restart) continues the fields of the run that wrote the checkpoint: the new
   file starts with that run's steps up to the checkpoint's, so every step is listed once.
   All calls are collective on the communicator given to Create (PETSC_COMM_WORLD);
   fluid, structure, the interface and the coupling problem may be NULL on ranks (or in
   scenes) that do not hold them. Without -write_fields Create returns a NULL writer, which
   the other calls accept. */
typedef struct _p_FieldWriter *FieldWriter;

PetscErrorCode FieldWriterCreate(MPI_Comm, const RunParams *, const char units[], Fluid, Structure, Interface,
                                 CouplingProblem, FieldWriter *);
/* The steps written and where, to or from a checkpoint file (memory checkpoints: nothing). */
PetscErrorCode FieldWriterCheckpoint(FieldWriter, Checkpoint, PetscBool load);
/* Creates the .partial file: before step 0, or after a restart's checkpoint is loaded. */
PetscErrorCode FieldWriterOpen(FieldWriter);
PetscErrorCode FieldWriterWrite(FieldWriter, PetscInt step);
PetscErrorCode FieldWriterFinish(FieldWriter);
PetscErrorCode FieldWriterDestroy(FieldWriter *);
#endif
