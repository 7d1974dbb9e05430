/* A gmsh geometry (.geo) given where a mesh file is expected (-PREFIXdm_plex_filename), meshed
   by gmsh before anything reads it (mesh.h): the mesh is written beside the .geo with the
   extension .msh (MSH 2.2, as `make` writes meshes/), or -NAME-setnumber-NAME-VALUE....msh
   with -PREFIXgeo_setnumber NAME,VALUE,... passed on as gmsh's -setnumber; kept and reused
   while newer than the .geo and the files it includes. gmsh runs on the first rank; its last line of output names what
   went wrong. The dimension is the scene's, or the .geo's first line's (// gmsh -2). */
#include "mesh.h"
#include "options.h"
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <fcntl.h>
#include <unistd.h>

extern char **environ;

/* rank 0: runs gmsh; 0 on success, else its last line of output in message */
static int RunGmsh(const char geo[], const char msh[], PetscInt dim, PetscInt nset, char *const set[], char message[],
                   size_t len)
{
  char                       log[PETSC_MAX_PATH_LEN + 8], dimension[16], *argv[64];
  int                        argc = 0, status = 0, fd;
  pid_t                      pid;
  posix_spawn_file_actions_t actions;
  FILE                      *fp;

  snprintf(log, sizeof(log), "%.4000s.log", msh);
  snprintf(dimension, sizeof(dimension), "-%d", (int)dim);
  argv[argc++] = (char *)"gmsh";
  argv[argc++] = dimension;
  argv[argc++] = (char *)"-format";
  argv[argc++] = (char *)"msh22";
  argv[argc++] = (char *)"-v";
  argv[argc++] = (char *)"2";
  for (PetscInt i = 0; i + 1 < nset && argc < 56; i += 2) {
    argv[argc++] = (char *)"-setnumber";
    argv[argc++] = set[i];
    argv[argc++] = set[i + 1];
  }
  argv[argc++] = (char *)"-o";
  argv[argc++] = (char *)msh;
  argv[argc++] = (char *)geo;
  argv[argc]   = NULL;
  fd           = open(log, O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd < 0) {
    snprintf(message, len, "cannot write %.400s", log);
    return 1;
  }
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fd, 1);
  posix_spawn_file_actions_adddup2(&actions, fd, 2);
  if (posix_spawnp(&pid, "gmsh", &actions, NULL, argv, environ)) {
    posix_spawn_file_actions_destroy(&actions);
    close(fd);
    snprintf(message, len, "gmsh is not on the PATH (make deps installs it)");
    return 1;
  }
  posix_spawn_file_actions_destroy(&actions);
  close(fd);
  if (waitpid(pid, &status, 0) < 0 || !WIFEXITED(status) || WEXITSTATUS(status)) {
    char line[512] = "";
    message[0]     = 0;
    if ((fp = fopen(log, "r"))) {
      while (fgets(line, sizeof(line), fp))
        if (line[0] != '\n') snprintf(message, len, "%s", line);
      fclose(fp);
    }
    if (message[0] && message[strlen(message) - 1] == '\n') message[strlen(message) - 1] = 0;
    if (!message[0]) snprintf(message, len, "gmsh failed");
    unlink(msh); /* no half-written mesh is reused; the reason is in the message */
    unlink(log);
    return 1;
  }
  unlink(log);
  return 0;
}

/* the newest modification time of the .geo and of the files it includes (Include "F";) */
static time_t GeoTime(const char geo[])
{
  struct stat st;
  time_t      newest = 0;
  FILE       *fp;
  char        line[1024], dir[PETSC_MAX_PATH_LEN];
  const char *slash = strrchr(geo, '/');

  if (stat(geo, &st)) return 0;
  newest = st.st_mtime;
  snprintf(dir, sizeof(dir), "%.*s", slash ? (int)(slash - geo + 1) : 0, geo);
  if (!(fp = fopen(geo, "r"))) return newest;
  while (fgets(line, sizeof(line), fp)) {
    char name[512], path[PETSC_MAX_PATH_LEN + 512];
    if (sscanf(line, " Include \"%511[^\"]\"", name) != 1) continue;
    snprintf(path, sizeof(path), "%s%s", name[0] == '/' ? "" : dir, name);
    if (!stat(path, &st) && st.st_mtime > newest) newest = st.st_mtime;
  }
  fclose(fp);
  return newest;
}

/* A relative mesh path that the working directory lacks is the repository's (the one fsiopt
   was built in: FSIOPT_ROOT), so that the options files' meshes/... paths work from any directory. */
static PetscErrorCode ResolveFromRoot(const char option[])
{
  char      path[PETSC_MAX_PATH_LEN], rooted[2 * PETSC_MAX_PATH_LEN];
  PetscBool given;

  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetString(NULL, NULL, option, path, sizeof(path), &given));
  if (!given || !path[0] || path[0] == '/' || !access(path, F_OK)) PetscFunctionReturn(0);
  PetscCall(PetscSNPrintf(rooted, sizeof(rooted), "%s/%s", FSIOPT_ROOT, path));
  if (access(rooted, F_OK)) PetscFunctionReturn(0); /* the reader names the path as given */
  PetscCall(PetscOptionsSetValue(NULL, option, rooted));
  PetscFunctionReturn(0);
}

PetscErrorCode MeshFromGeo(MPI_Comm comm, const char prefix[], PetscInt dim)
{
  char        option[128], set_option[128], geo[PETSC_MAX_PATH_LEN] = "", msh[PETSC_MAX_PATH_LEN], message[512] = "";
  char       *set[16];
  PetscInt    nset = 16;
  size_t      len;
  PetscBool   given, has_set;
  PetscMPIInt rank;
  int         failed = 0;

  PetscFunctionBeginUser;
  PetscCall(PetscSNPrintf(option, sizeof(option), "-%sdm_plex_filename", prefix));
  PetscCall(ResolveFromRoot(option));
  PetscCall(PetscOptionsGetString(NULL, NULL, option, geo, sizeof(geo), &given));
  PetscCall(PetscStrlen(geo, &len));
  if (!given || len < 5 || strcmp(geo + len - 4, ".geo")) PetscFunctionReturn(0);
  PetscCall(OptionsCheckReadableFile(comm, option, geo));
  PetscCall(PetscSNPrintf(set_option, sizeof(set_option), "-%sgeo_setnumber", prefix));
  PetscCall(PetscOptionsGetStringArray(NULL, NULL, set_option, set, &nset, &has_set));
  if (!has_set) nset = 0;
  PetscCheck(nset % 2 == 0, comm, PETSC_ERR_ARG_WRONG,
             "option %s: expected pairs NAME,VALUE of the geometry's numbers (gmsh -setnumber)", set_option);
  if (dim < 2) { /* the scene takes any: the .geo's first line, // gmsh -2 or -3, as meshes/ writes them */
    FILE *fp = fopen(geo, "r");
    int   d  = 3;
    if (fp && fscanf(fp, "// gmsh -%d", &d) != 1) d = 3;
    if (fp) fclose(fp);
    dim = d == 2 ? 2 : 3;
  }
  PetscCall(PetscStrncpy(msh, geo, len - 3));
  msh[len - 4] = 0;
  for (PetscInt i = 0; i < nset; ++i) {
    PetscCall(PetscStrlcat(msh, "-", sizeof(msh)));
    PetscCall(PetscStrlcat(msh, set[i], sizeof(msh)));
  }
  PetscCall(PetscStrlcat(msh, ".msh", sizeof(msh)));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (!rank) {
    struct stat m;
    if (stat(msh, &m) || m.st_mtime < GeoTime(geo))
      failed = RunGmsh(geo, msh, dim, nset, set, message, sizeof(message));
  }
  for (PetscInt i = 0; i < nset; ++i) PetscCall(PetscFree(set[i]));
  PetscCallMPI(MPI_Bcast(&failed, 1, MPI_INT, 0, comm));
  PetscCallMPI(MPI_Bcast(message, sizeof(message), MPI_CHAR, 0, comm));
  PetscCheck(!failed, comm, PETSC_ERR_FILE_UNEXPECTED, "option %s: gmsh could not mesh %s: %s", option, geo, message);
  PetscCall(PetscOptionsSetValue(NULL, option, msh));
  PetscFunctionReturn(0);
}
