/* Face sets and regions by name (mesh.h): the names of a gmsh file's physical groups
   ($PhysicalNames), so that an options file can name a face set or a region as the geometry
   does, read on the first rank and handed to all (a file without names has none; ASCII files
   of format 2.2 and 4.1), or the sides of a 2D box. */
#include "mesh.h"
#include "options.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* rank 0: the groups of dimension dim, at most max of them */
static int ReadNames(const char path[], PetscInt dim, PetscInt max, MeshPhysicalName names[])
{
  FILE *fp = fopen(path, "r");
  char  line[512];
  int   n = 0, count = 0;

  if (!fp) return 0;
  while (fgets(line, sizeof(line), fp))
    if (!strncmp(line, "$PhysicalNames", 14)) break;
  if (!feof(fp) && fscanf(fp, "%d", &count) == 1) {
    for (int i = 0; i < count && n < max; ++i) {
      int  d, tag;
      char quoted[256];
      if (fscanf(fp, "%d %d %255s", &d, &tag, quoted) != 3) break;
      if (d != dim) continue;
      names[n].value = tag;
      /* "inlet" -> inlet */
      PetscStrncpy(names[n].name, quoted[0] == '"' ? quoted + 1 : quoted, sizeof(names[n].name));
      if (strlen(names[n].name) && names[n].name[strlen(names[n].name) - 1] == '"')
        names[n].name[strlen(names[n].name) - 1] = 0;
      ++n;
    }
  }
  fclose(fp);
  return n;
}

PetscErrorCode MeshGmshPhysicalNames(MPI_Comm comm, const char path[], PetscInt dim, PetscInt max, PetscInt *n,
                                     MeshPhysicalName names[])
{
  PetscMPIInt rank;
  int         found = 0;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (!rank) found = ReadNames(path, dim, max, names);
  PetscCallMPI(MPI_Bcast(&found, 1, MPI_INT, 0, comm));
  PetscCallMPI(MPI_Bcast(names, (PetscMPIInt)(found * sizeof(MeshPhysicalName)), MPI_BYTE, 0, comm));
  *n = found;
  PetscFunctionReturn(0);
}

PetscErrorCode MeshFaceSetNames(MPI_Comm comm, const char prefix[], PetscInt dim, PetscInt max, PetscInt *n,
                                MeshPhysicalName sets[])
{
  char      option[64], path[PETSC_MAX_PATH_LEN];
  PetscBool file;

  PetscFunctionBeginUser;
  PetscCall(MeshFromGeo(comm, prefix, dim));
  PetscCall(PetscSNPrintf(option, sizeof(option), "-%sdm_plex_filename", prefix));
  PetscCall(PetscOptionsGetString(NULL, NULL, option, path, sizeof(path), &file));
  *n = 0;
  /* before its names are read: a device or a FIFO would be read forever, a directory as empty */
  if (file) PetscCall(OptionsCheckReadableFile(comm, option, path));
  if (file) PetscCall(MeshGmshPhysicalNames(comm, path, dim - 1, max, n, sets));
  else if (dim == 2 && max >= 4) {
    const char *box[] = {"bottom", "right", "top", "left"}; /* FACE_BOTTOM, ... */
    for (PetscInt i = 0; i < 4; ++i) {
      PetscCall(PetscStrncpy(sets[i].name, box[i], sizeof(sets[i].name)));
      sets[i].value = i + 1;
    }
    *n = 4;
  }
  PetscFunctionReturn(0);
}

PetscErrorCode MeshFaceSetFind(PetscInt n, const MeshPhysicalName sets[], const char text[], PetscInt *value)
{
  char *end;
  long  number;

  PetscFunctionBeginUser;
  *value = -1;
  for (PetscInt i = 0; i < n && *value < 0; ++i)
    if (!strcmp(sets[i].name, text)) *value = sets[i].value;
  if (*value >= 0 || !text[0]) PetscFunctionReturn(0);
  number = strtol(text, &end, 10);
  if (!*end && number > 0 && number < PETSC_MAX_INT) *value = (PetscInt)number;
  PetscFunctionReturn(0);
}
