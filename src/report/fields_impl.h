#ifndef FSIOPT_FIELDS_IMPL_H
#define FSIOPT_FIELDS_IMPL_H
/* The field writer's state, shared by fields.c (set-up, steps, XDMF) and
   fields_restart.c (the file opened, checkpoints, a restart's continuation of the file). */
#include "fields.h"
#include "checkpoint.h"
#include <petscviewerhdf5.h>

#define FIELDS_MAX 3 /* per grid: the fluid's velocity, pressure and mesh velocity */

/* One grid. Vertices are gathered on the root and put in the DM's global vertex order,
   so the topology is written once although the fluid's coordinates change every step. */
typedef struct {
  const char *name, *field[FIELDS_MAX];
  PetscBool   deform; /* geometry = coordinates + first field */
  PetscInt    nfields, nc[FIELDS_MAX];
  PetscInt    dim, nv, ncells, nvertices; /* the same on every rank */
  PetscInt    nown, *own;                 /* vertex points this rank owns */
  PetscInt   *index;                      /* root: global number of each gathered vertex */
  PetscInt   *cells;                      /* root: ncells x nv global vertex numbers, as written */
} Part;

struct _p_FieldWriter {
  MPI_Comm       comm;
  PetscMPIInt    rank;
  Fluid          fluid;
  Structure      structure;
  Part           part[2];
  PetscInt       interval, steps, nwritten, *written;
  PetscReal      t0, dt;
  char           dir[PETSC_MAX_PATH_LEN], path[PETSC_MAX_PATH_LEN], partial[PETSC_MAX_PATH_LEN];
  char           origin[128]; /* names this run in the files it writes and in its checkpoints */
  PetscBool      restarting;  /* the written steps and the source below come from a checkpoint */
  char           source[PETSC_MAX_PATH_LEN], source_origin[128];
  PetscViewer    viewer; /* root only; NULL until FieldWriterOpen */
  PetscBool      opened;
  PetscErrorCode write_error; /* root: the first failed write of the fields in progress */
  PetscLogEvent  event;
};

/* The datasets of a step's group: geometry (dim columns), then each field (vectors with
   3 columns, zero-padded in 2D: ParaView's XDMF vectors have three). k = 0 .. nfields. */
void FieldsDataset(const Part *, PetscInt k, const char **name, PetscInt *columns);
/* root: /origin and each grid's topology into a new file */
PetscErrorCode FieldsWriteHeader(FieldWriter, PetscViewer);
#endif
