/* A gmsh .msh file read by us before PETSc reads it (mesh.h): PETSc's reader trusts the
   file, and a cell that names a node the file does not have gave a mesh that ran to a
   wrong answer. Checked: the declared counts, node tags that exist and are unique, element
   types fsiopt meshes with, cells of the scene's dimension, and no two nodes of the cells at
   one point (a crack the mesh generator left: the two sides would not be connected).
   ASCII files of format 2.2 and 4.1; other gmsh files (binary, other versions) are left to
   PETSc's reader, and a file without a $MeshFormat header is refused. */
#include "mesh.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
  long   tag;
  double x[3];
  int    used;
} Node;

/* nodes of a gmsh element type, and its dimension; 0 nodes: not a type fsiopt meshes with */
static int ElementType(int type, int *dim)
{
  static const int nodes[] = {0, 2, 3, 4, 4, 8, 6, 5, 3, 6, 9, 10, 27, 18, 14, 1, 8, 20};
  static const int dims[]  = {0, 1, 2, 2, 3, 3, 3, 3, 1, 2, 2, 3, 3, 3, 3, 0, 2, 3};
  if (type < 1 || type > 17 || type == 6 || type == 7 || type == 13 || type == 14) return 0; /* prisms, pyramids */
  *dim = dims[type];
  return nodes[type];
}

static int CompareTags(const void *a, const void *b)
{
  const long p = ((const Node *)a)->tag, q = ((const Node *)b)->tag;
  return p < q ? -1 : p > q;
}

static int ComparePoints(const void *a, const void *b)
{
  const Node *p = *(Node *const *)a, *q = *(Node *const *)b;
  for (int d = 0; d < 3; ++d)
    if (p->x[d] != q->x[d]) return p->x[d] < q->x[d] ? -1 : 1;
  return 0;
}

static Node *FindNode(Node *nodes, long n, long tag)
{
  Node key;
  key.tag = tag;
  return bsearch(&key, nodes, (size_t)n, sizeof(Node), CompareTags);
}

/* advances fp to the line after `header`; 0: not found */
static int Seek(FILE *fp, const char header[])
{
  char line[512];
  rewind(fp);
  while (fgets(line, sizeof(line), fp))
    if (!strncmp(line, header, strlen(header))) return 1;
  return 0;
}

/* A declared count the file cannot hold (each node or element takes a line of at least a few
   bytes) or PETSc's integers cannot number: refused before anything is allocated for it. */
static int CountTooLarge(const char section[], const char what[], long declared, long file_bytes, char why[], size_t len)
{
  const long fit = file_bytes / 6; /* "1 0 0\n": the shortest line a node or an element takes */

  if (declared > PETSC_MAX_INT)
    snprintf(why, len, "its %s section declares %ld %s, more than PETSc's integers number (at most %d)", section,
             declared, what, (int)PETSC_MAX_INT);
  else if (declared > fit)
    snprintf(why, len, "its %s section declares %ld %s, more than its %ld bytes can hold (a count is wrong)", section,
             declared, what, file_bytes);
  else return 0;
  return 1;
}

/* The $Nodes section into *nodes (sorted by tag, tags positive and unique); 1 and why set on a fault. */
static int ReadNodes(FILE *fp, double version, long file_bytes, Node **nodes_out, long *nnodes_out, char why[],
                     size_t len)
{
  long  nnodes = 0, read = 0;
  Node *nodes  = NULL;

  if (!Seek(fp, "$Nodes")) {
    snprintf(why, len, "it has no $Nodes section");
    return 1;
  }
  if (version == 2.2) {
    if (fscanf(fp, "%ld", &nnodes) != 1 || nnodes <= 0) {
      snprintf(why, len, "its $Nodes section does not start with a positive node count");
      return 1;
    }
    if (CountTooLarge("$Nodes", "nodes", nnodes, file_bytes, why, len)) return 1;
    if (!(nodes = calloc((size_t)nnodes, sizeof(Node)))) {
      snprintf(why, len, "its %ld nodes do not fit in memory", nnodes);
      return 1;
    }
    for (; read < nnodes; ++read)
      if (fscanf(fp, "%ld %lf %lf %lf", &nodes[read].tag, &nodes[read].x[0], &nodes[read].x[1], &nodes[read].x[2]) != 4)
        break;
  } else {
    long blocks, minTag, maxTag;
    if (fscanf(fp, "%ld %ld %ld %ld", &blocks, &nnodes, &minTag, &maxTag) != 4 || nnodes <= 0) {
      snprintf(why, len, "its $Nodes section does not start with its block and node counts");
      return 1;
    }
    if (CountTooLarge("$Nodes", "nodes", nnodes, file_bytes, why, len) ||
        CountTooLarge("$Nodes", "node blocks", blocks, file_bytes, why, len))
      return 1;
    if (!(nodes = calloc((size_t)nnodes, sizeof(Node)))) {
      snprintf(why, len, "its %ld nodes do not fit in memory", nnodes);
      return 1;
    }
    for (long b = 0; b < blocks && read <= nnodes; ++b) {
      int  edim, etag, parametric;
      long inblock;
      if (fscanf(fp, "%d %d %d %ld", &edim, &etag, &parametric, &inblock) != 4 || parametric || inblock < 0 ||
          read + inblock > nnodes) {
        read = -1;
        break;
      }
      for (long i = 0; i < inblock; ++i)
        if (fscanf(fp, "%ld", &nodes[read + i].tag) != 1) inblock = -1;
      for (long i = 0; i < inblock; ++i)
        if (fscanf(fp, "%lf %lf %lf", &nodes[read + i].x[0], &nodes[read + i].x[1], &nodes[read + i].x[2]) != 3)
          inblock = -1;
      if (inblock < 0) {
        read = -1;
        break;
      }
      read += inblock;
    }
  }
  *nodes_out  = nodes;
  *nnodes_out = nnodes;
  if (read != nnodes) {
    snprintf(why, len, "its $Nodes section declares %ld nodes but %s", nnodes,
             read < 0 ? "a node block is malformed" : "has fewer (the file is truncated or a count is wrong)");
    return 1;
  }
  qsort(nodes, (size_t)nnodes, sizeof(Node), CompareTags);
  for (long i = 0; i < nnodes; ++i) {
    if (nodes[i].tag <= 0) {
      snprintf(why, len, "it has node %ld (node tags start at 1)", nodes[i].tag);
      return 1;
    }
    if (i && nodes[i].tag == nodes[i - 1].tag) {
      snprintf(why, len, "node %ld is listed twice in $Nodes", nodes[i].tag);
      return 1;
    }
  }
  return 0;
}

/* One element's type and nodes (fp after its tag): a type fsiopt meshes with, of at most the
   scene's dimension, distinct nodes that $Nodes has; marks the nodes of cells. */
static int CheckElement(FILE *fp, double version, long tag, int type, int dim, Node *nodes, long nnodes, int *top,
                        char why[], size_t len)
{
  int  edim = 0, count;
  long node, element_nodes[27];

  if (version == 2.2) {
    int ntags, t;
    if (fscanf(fp, "%d %d", &type, &ntags) != 2 || ntags < 0) {
      snprintf(why, len, "element %ld is malformed", tag);
      return 1;
    }
    for (int k = 0; k < ntags; ++k)
      if (fscanf(fp, "%d", &t) != 1) {
        snprintf(why, len, "element %ld is malformed", tag);
        return 1;
      }
  }
  count = ElementType(type, &edim);
  if (!count) {
    snprintf(why, len,
             "element %ld has gmsh type %d, which fsiopt does not mesh with (lines, triangles, "
             "quadrilaterals, tetrahedra, hexahedra and points, linear or quadratic)",
             tag, type);
    return 1;
  }
  if (edim > dim && dim > 0) {
    snprintf(why, len, "element %ld is %dD (gmsh type %d) in a mesh for a %dD scene", tag, edim, type, dim);
    return 1;
  }
  if (edim > *top) *top = edim;
  for (int k = 0; k < count; ++k) {
    Node *n;
    if (fscanf(fp, "%ld", &node) != 1) {
      snprintf(why, len, "element %ld has fewer nodes than its type %d needs", tag, type);
      return 1;
    }
    element_nodes[k] = node;
    for (int j = 0; j < k; ++j)
      if (element_nodes[j] == node) {
        snprintf(why, len, "element %ld names node %ld twice (a collapsed cell)", tag, node);
        return 1;
      }
    n = FindNode(nodes, nnodes, node);
    if (!n) {
      snprintf(why, len, "element %ld refers to node %ld, which $Nodes does not have", tag, node);
      return 1;
    }
    if (edim == (dim > 0 ? dim : edim)) n->used = 1;
  }
  return 0;
}

/* The $Elements section: its counts, each element, and cells of the scene's dimension. */
static int CheckElements(FILE *fp, double version, long file_bytes, int dim, Node *nodes, long nnodes, char why[],
                         size_t len)
{
  long nelem = 0, seen = 0, blocks = 1, minTag, maxTag;
  int  top = 0;

  if (!Seek(fp, "$Elements")) {
    snprintf(why, len, "it has no $Elements section");
    return 1;
  }
  if (version == 2.2 ? fscanf(fp, "%ld", &nelem) != 1
                     : fscanf(fp, "%ld %ld %ld %ld", &blocks, &nelem, &minTag, &maxTag) != 4) {
    snprintf(why, len, "its $Elements section does not start with its counts");
    return 1;
  }
  if (CountTooLarge("$Elements", "elements", nelem, file_bytes, why, len) ||
      CountTooLarge("$Elements", "element blocks", blocks, file_bytes, why, len))
    return 1;
  for (long b = 0; b < blocks; ++b) {
    int  type    = 0;
    long inblock = nelem;
    if (version == 4.1) {
      int entity_dim, entity_tag;
      if (fscanf(fp, "%d %d %d %ld", &entity_dim, &entity_tag, &type, &inblock) != 4) {
        snprintf(why, len, "an element block of $Elements is malformed");
        return 1;
      }
    }
    for (long e = 0; e < inblock; ++e, ++seen) {
      long tag;
      if (fscanf(fp, "%ld", &tag) != 1) {
        snprintf(why, len,
                 "its $Elements section declares %ld elements but has fewer (the file is truncated or a "
                 "count is wrong)",
                 nelem);
        return 1;
      }
      if (CheckElement(fp, version, tag, type, dim, nodes, nnodes, &top, why, len)) return 1;
    }
  }
  if (seen != nelem) {
    snprintf(why, len, "its $Elements section declares %ld elements but its blocks hold %ld", nelem, seen);
    return 1;
  }
  if (dim > 0 && top < dim) {
    snprintf(why, len, "it has no %dD cells (its highest elements are %dD)", dim, top);
    return 1;
  }
  return 0;
}

/* A crack: two nodes of the cells at one point. */
static int CheckCracks(Node *nodes, long nnodes, char why[], size_t len)
{
  Node **used = malloc((size_t)nnodes * sizeof(Node *));
  long   n = 0;
  int    result = 0;

  for (long i = 0; i < nnodes; ++i)
    if (nodes[i].used) used[n++] = &nodes[i];
  qsort(used, (size_t)n, sizeof(Node *), ComparePoints);
  for (long i = 1; i < n && !result; ++i)
    if (!ComparePoints(&used[i], &used[i - 1])) {
      snprintf(why, len,
               "nodes %ld and %ld are at the same point (%g, %g, %g): a crack or a duplicated node (merge "
               "them, e.g. gmsh's Coherence)",
               used[i - 1]->tag, used[i]->tag, used[i]->x[0], used[i]->x[1], used[i]->x[2]);
      result = 1;
    }
  free(used);
  return result;
}

/* The checks; returns 0 and leaves why empty when the file is fine or not ours to check. */
static int Check(const char path[], int dim, char why[], size_t len)
{
  FILE  *fp = fopen(path, "r");
  double version;
  int    binary = 0, datasize, result = 1;
  long   nnodes = 0;
  Node  *nodes  = NULL;

  why[0] = 0;
  if (!fp) return 0; /* OptionsCheckReadableFile reports it */
  /* PETSc's reader crashes on a file that is not gmsh's at all */
  if (!Seek(fp, "$MeshFormat") || fscanf(fp, "%lf %d %d", &version, &binary, &datasize) != 3)
    snprintf(why, len, "not a gmsh mesh (no readable $MeshFormat section)");
  else if (binary || (version != 2.2 && version != 4.1)) result = 0;
  else {
    long bytes;
    (void)fseek(fp, 0, SEEK_END);
    bytes = ftell(fp);
    rewind(fp);
    result = ReadNodes(fp, version, bytes, &nodes, &nnodes, why, len) ||
             CheckElements(fp, version, bytes, dim, nodes, nnodes, why, len) || CheckCracks(nodes, nnodes, why, len);
  }
  free(nodes);
  fclose(fp);
  return result;
}

PetscErrorCode MeshCheckGmshFile(MPI_Comm comm, const char option[], const char path[], PetscInt dim)
{
  PetscMPIInt rank;
  char        why[512] = "";
  int         bad      = 0;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (!rank) bad = Check(path, (int)dim, why, sizeof(why));
  PetscCallMPI(MPI_Bcast(&bad, 1, MPI_INT, 0, comm));
  PetscCallMPI(MPI_Bcast(why, sizeof(why), MPI_CHAR, 0, comm));
  PetscCheck(!bad, comm, PETSC_ERR_FILE_UNEXPECTED, "option %s %s: %s", option, path, why);
  PetscFunctionReturn(0);
}
