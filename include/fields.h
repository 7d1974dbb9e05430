#ifndef FSIOPT_FIELDS_H
#define FSIOPT_FIELDS_H
#include "fsiopt.h"
#include "fluid.h"
#include "structure.h"

/* -write_fields: <output_dir>/fields.h5 and fields.xdmf, a time series ParaView opens:
   the fluid on its moving mesh (velocity, pressure at the vertices) and the structure on
   its deformed mesh (displacement). Written every -write_fields_interval steps, the first
   and the last step always; both files are .partial until FieldWriterFinish.
   fields.h5: /<grid>/topology (cells x vertices per cell, global vertex numbers) and
   /<grid>/step_NNNNN/{geometry (vertices x dim), velocity and displacement (vertices x 3,
   z = 0 in 2D: ParaView's XDMF vectors have three components), pressure (vertices)},
   each step group with an attribute "time"; <grid> is "fluid" and/or "structure".
   All calls are collective on the communicator given to Create (PETSC_COMM_WORLD);
   fluid or structure may be NULL on ranks that do not hold them. Without -write_fields
   Create returns a NULL writer, which the other calls accept. */
typedef struct _p_FieldWriter *FieldWriter;

PetscErrorCode FieldWriterCreate(MPI_Comm, const RunParams *, Fluid, Structure, FieldWriter *);
PetscErrorCode FieldWriterWrite(FieldWriter, PetscInt step);
PetscErrorCode FieldWriterFinish(FieldWriter);
PetscErrorCode FieldWriterDestroy(FieldWriter *);
#endif
