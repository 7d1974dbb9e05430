#ifndef FSIOPT_FIELDS_IMPL_H
#define FSIOPT_FIELDS_IMPL_H
/* The field writer's state, shared by fields.c (set-up, steps, XDMF) and
   fields_restart.c (the file opened, checkpoints, a restart's continuation of the file). */
#include "fields.h"
#include "checkpoint.h"
#include "memory_estimate.h"
#include <petscviewerhdf5.h>

#define FIELDS_MAX    8 /* per grid: the fluid's velocity, pressure, mesh velocity and derived fields */
#define FIELD_SOURCES 3 /* the arrays a written field is computed from */

/* How a written field comes from the values its sources give at a node (fields_derived.c). */
typedef enum {
  FIELD_COPY,
  FIELD_VORTICITY,         /* from grad u: curl u (a scalar in 2D) */
  FIELD_Q_CRITERION,       /* from grad u: (|W|^2 - |S|^2)/2 */
  FIELD_VON_MISES,         /* from the Cauchy stress (3 x 3) */
  FIELD_TRACTION,          /* from grad u, p, n: sigma n, n out of the fluid */
  FIELD_NORMAL_STRESS,     /* n . sigma n */
  FIELD_WALL_SHEAR_STRESS, /* (n . sigma n) n - sigma n: the fluid's shear on the wall */
} FieldTransform;

/* One grid (fields_grid.c): its nodes are mesh points, gathered on the root in the order of
   their global numbers, so the topology is written once although the fluid's coordinates
   change every step. */
typedef struct {
  const char    *name, *field[FIELDS_MAX];
  const char    *unit[FIELDS_MAX]; /* NULL: nondimensional */
  PetscBool      deform;           /* geometry = coordinates + first field */
  PetscInt       nfields, nc[FIELDS_MAX]; /* 1, dim (a vector; -1 until set up) or 9 (a tensor) */
  FieldTransform transform[FIELDS_MAX];
  PetscInt       nsources[FIELDS_MAX], source_nc[FIELDS_MAX][FIELD_SOURCES]; /* 0: one, the field's nc */
  PetscInt       dim, nv, ncells, nnodes; /* the same on every rank */
  DMPolytopeType polytope;                /* of the mesh's cells (or faces) */
  PetscBool      refined;                 /* each written as its once-refined lattice */
  PetscInt       nown, *own;              /* node points this rank owns */
  PetscInt      *nvert, *vert;            /* each's vertices (8 slots each): a degree-1 value is their mean */
  PetscInt      *index;                   /* root: global number of each gathered node */
  PetscInt      *cells;                   /* root: ncells x nv global node numbers, as written */
} Part;

/* What a grid is made of on this rank: the mesh (NULL: none of it here), the cells (all,
   or the faces of the given face sets) and the layout of the fields it carries. */
typedef struct {
  DM           dm;
  DMLabel      faces; /* NULL: the mesh's cells */
  PetscInt     nfaces, face_values[16];
  PetscInt     nfields;
  PetscSection section[FIELDS_MAX]; /* NULL: a field that has no layout to check */
  PetscInt     number[FIELDS_MAX], nc[FIELDS_MAX];
} FieldsGridSources;

PetscErrorCode FieldsGridSetUp(MPI_Comm, Part *, const FieldsGridSources *, PetscBool all_nodes);
/* The nc values at own node i of a field (number: its field in section s, -1 for a section
   of one field such as the coordinates') in the local array a. */
PetscErrorCode FieldsGridValue(const Part *, PetscInt i, PetscSection s, PetscInt number, PetscInt nc,
                               const PetscScalar *a, PetscScalar v[]);
PetscErrorCode FieldsGridDestroy(Part *);
/* The grid's cells (or faces) this rank owns; the caller frees them. */
PetscErrorCode FieldsGridCells(DM, const FieldsGridSources *, PetscInt *n, PetscInt **cells);
PetscErrorCode FieldsGatherOnRoot(MPI_Comm, PetscInt n, MPI_Datatype, const void *send, void **recv, PetscInt *total);

typedef struct _n_FieldsDerived *FieldsDerived;

struct _p_FieldWriter {
  MPI_Comm       comm;
  PetscMPIInt    rank;
  Fluid          fluid;
  Structure      structure;
  Interface      itf;     /* coupled scenes: the interface and the problem whose control */
  CouplingProblem problem; /* -write_fields_derived interface_traction writes; else NULL */
  Part           part[3]; /* fluid, structure, the fluid's walls */
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
  const char    *units; /* the scene's system (units.h) */
  PetscBool      all_nodes;
  FieldsDerived  derived;
};

/* Where a grid's fields live on this rank when written: per field and source, a local
   vector with its section and the field's number there (-1: a section of one field). */
typedef struct {
  FieldsGridSources grid; /* the grid's mesh and cells */
  PetscSection      section[FIELDS_MAX][FIELD_SOURCES];
  PetscInt          number[FIELDS_MAX][FIELD_SOURCES];
  Vec               local[FIELDS_MAX][FIELD_SOURCES];
  Vec               borrowed; /* the fluid's local solution, returned by FieldsWriterSourcesRestore */
  PetscReal         mu;       /* the fluid's viscosity, for the walls' stresses */
} Sources;

/* fields.c: a grid's sources on this rank (values = PETSC_FALSE: their layout only) */
PetscErrorCode FieldsWriterSources(FieldWriter, PetscInt part, PetscBool values, Sources *);
PetscErrorCode FieldsWriterSourcesRestore(Sources *);

/* fields_derived.c: -write_fields_derived and -write_fields_walls. Create adds the fields
   asked for to the grids (and the walls' grid, part[2]); Sources fills in theirs, computing
   them when values is true. */
PetscErrorCode FieldsDerivedCreate(FieldWriter);
PetscErrorCode FieldsDerivedSources(FieldWriter, PetscInt part, PetscBool values, Sources *);
void           FieldsTransform(FieldTransform, PetscInt dim, PetscReal mu, const PetscScalar in[], PetscScalar out[]);
PetscErrorCode FieldsDerivedDestroy(FieldsDerived *);

/* The datasets of a step's group: geometry (dim columns), then each field (vectors with
   3 columns, zero-padded in 2D: ParaView's XDMF vectors have three). k = 0 .. nfields. */
void FieldsDataset(const Part *, PetscInt k, const char **name, PetscInt *columns);
/* root: /origin and each grid's topology into a new file */
PetscErrorCode FieldsWriteHeader(FieldWriter, PetscViewer);
#endif
