#ifndef FSIOPT_FIELDS_H
#define FSIOPT_FIELDS_H
#include "fsiopt.h"
#include "fluid.h"
#include "structure.h"

/* -write_fields: <output_dir>/fields.h5 and fields.xdmf, a time series ParaView opens:
   the fluid on its moving mesh (velocity, pressure and, where the mesh moves, the mesh
   velocity at the vertices) and the structure on its deformed mesh (displacement).
   Written every -write_fields_interval steps, the first and the last step always; both
   files are .partial until FieldWriterFinish.
   fields.h5: attribute /origin (the run that wrote the file), /<grid>/topology (cells x
   vertices per cell, global vertex numbers) and /<grid>/step_NNNNN/{geometry (vertices x
   dim), velocity, mesh_velocity and displacement (vertices x 3, z = 0 in 2D: ParaView's
   XDMF vectors have three components), pressure (vertices)}, each step group with an
   attribute "time"; <grid> is "fluid" and/or "structure".
   A restart (-restart) continues the fields of the run that wrote the checkpoint: the new
   file starts with that run's steps up to the checkpoint's, so every step is listed once.
   All calls are collective on the communicator given to Create (PETSC_COMM_WORLD);
   fluid or structure may be NULL on ranks that do not hold them. Without -write_fields
   Create returns a NULL writer, which the other calls accept. */
typedef struct _p_FieldWriter *FieldWriter;

PetscErrorCode FieldWriterCreate(MPI_Comm, const RunParams *, Fluid, Structure, FieldWriter *);
/* The steps written and where, to or from a checkpoint file (memory checkpoints: nothing). */
PetscErrorCode FieldWriterCheckpoint(FieldWriter, Checkpoint, PetscBool load);
/* Creates the .partial file: before step 0, or after a restart's checkpoint is loaded. */
PetscErrorCode FieldWriterOpen(FieldWriter);
PetscErrorCode FieldWriterWrite(FieldWriter, PetscInt step);
PetscErrorCode FieldWriterFinish(FieldWriter);
PetscErrorCode FieldWriterDestroy(FieldWriter *);
#endif
