#ifndef FSIOPT_CHECKSUM_H
#define FSIOPT_CHECKSUM_H
#include <stdint.h>
#include <petscvec.h>
#include <petscviewerhdf5.h>

/* The checksums of a checkpoint file (src/storage/checksum.c): a checksum of every dataset
   and attribute fsiopt writes there, recomputed from the values a restart reads; a file whose
   values changed after they were written is refused, naming the dataset or attribute.

   They are one table, the root's string attribute "checksums": a first line naming their
   kind (CHECKSUM_KIND), then a line per item, 16 hex digits and the item (on fluid |
   structure ranks each side's items in an attribute "checksums 1", "checksums 2" of its own):
     db7f87d61e074250 dataset /fluid/state
     088712be8a582fca attribute 'step' in /run
   One attribute: HDF5 spends about 25 us creating each attribute, which an attribute per item
   would have made three quarters of the checksums' cost.

   The kind: each value is an entry (index, bits) — a dataset's values their global indices
   and the 64 bits of their doubles; an attribute's one value index 0 and its integer as a
   64-bit two's complement, its double's bits, or a string's 64-bit FNV-1a hash — mixed by
   ChecksumEntry; an item's checksum is the sum of its entries' mod 2^64. The sum does not
   depend on how the ranks split a vector, and a change of any one value always changes it
   (ChecksumEntry is one-to-one in the bits for a given index). */
#define CHECKSUM_KIND "fsiopt-mix64-1"

uint64_t ChecksumEntry(uint64_t index, uint64_t bits);
uint64_t ChecksumInt(PetscInt);
uint64_t ChecksumReal(PetscReal);
uint64_t ChecksumString(const char[]);
/* of the vector's values by global index: this rank's share of the sum, and the sum
   (collective on the vector's communicator) */
PetscErrorCode ChecksumVecLocal(Vec, uint64_t *);
PetscErrorCode ChecksumVec(Vec, uint64_t *);

typedef struct _p_ChecksumTable *ChecksumTable;

/* Writing: a table filled item by item, written to the root of the file at its end (flushed
   first, on the viewer's ranks). */
PetscErrorCode ChecksumTableCreate(ChecksumTable *);
PetscErrorCode ChecksumTableDestroy(ChecksumTable *);
/* `item`: "dataset /group/name" or "attribute 'name' in /group" (ChecksumItem), with this
   rank's share of its checksum (a dataset's) or the whole of it, the same on every rank (an
   attribute's: `replicated`). Held until the table (or its part) is written, which sums the
   shares over the ranks that wrote them, all items in one reduction: one per item would be a
   synchronization of the ranks per dataset. */
PetscErrorCode ChecksumTableAdd(ChecksumTable, const char item[], uint64_t, PetscBool replicated);
/* A part of the file only some ranks write (CheckpointBeginPart): its items, those added
   from `first` (ChecksumTablePending when it began) on, flushed on the part's ranks (the
   viewer's) and written as the root's attribute "checksums <index>" (1, 2, ... for the parts
   in order) while they hold the file; the table's reader joins them to "checksums". */
PetscInt       ChecksumTablePending(ChecksumTable);
PetscErrorCode ChecksumTableWritePart(ChecksumTable, PetscViewer, PetscInt first, PetscInt index);
PetscErrorCode ChecksumTableWrite(ChecksumTable, PetscViewer);

/* Reading -restart `path`: the file's table, or NULL for a file an fsiopt without checksums
   wrote (its root has no attribute at all); a table of another kind, or a root whose
   attributes lack it, is refused in one line. Collective. */
PetscErrorCode ChecksumTableRead(PetscViewer, const char path[], ChecksumTable *);
/* The item's stored checksum against `computed`: an item the table lacks or whose checksum
   differs is refused in one line naming it. */
PetscErrorCode ChecksumTableCheck(ChecksumTable, MPI_Comm, const char path[], const char item[], uint64_t computed);

/* The table's name of a dataset or attribute `name` in `group` (an absolute path). */
PetscErrorCode ChecksumItem(const char group[], const char name[], PetscBool dataset, char item[], size_t len);
#endif
