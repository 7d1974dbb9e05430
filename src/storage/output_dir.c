/* The output directory (output_files.h): made with its parents, and owned by one run through
   a lock file <output_dir>/.fsiopt.lock with the pid, host and start time of the run that
   writes there. Two runs writing into one directory would interleave and overwrite each
   other's files. */
#include "output_files.h"
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

int OutputMakeDirectoriesWhy(const char dir[], char why[], size_t len)
{
  char        path[PETSC_MAX_PATH_LEN];
  struct stat st;

  why[0] = 0;
  (void)snprintf(path, sizeof(path), "%s", dir);
  for (char *c = path + 1;; ++c) {
    const char at = *c;
    if (at && at != '/') continue;
    *c = 0;
    /* an existing directory may be read-only above the one we write in */
    if (mkdir(path, 0777) && errno != EEXIST) {
      (void)snprintf(why, len, "option -output_dir %s: cannot create %s (%s)", dir, path, strerror(errno));
      return 1;
    }
    if (stat(path, &st) || !S_ISDIR(st.st_mode)) {
      (void)snprintf(why, len, "option -output_dir %s: %s is not a directory", dir, path);
      return 1;
    }
    *c = at;
    if (!at) break;
  }
  if (access(path, W_OK | X_OK)) {
    (void)snprintf(why, len, "option -output_dir %s: cannot write there (%s)", dir, strerror(errno));
    return 1;
  }
  return 0;
}

PetscErrorCode OutputMakeDirectories(const char dir[])
{
  char why[2 * PETSC_MAX_PATH_LEN + 128];

  PetscFunctionBeginUser;
  PetscCheck(!OutputMakeDirectoriesWhy(dir, why, sizeof(why)), PETSC_COMM_SELF, PETSC_ERR_FILE_OPEN, "%s", why);
  PetscFunctionReturn(0);
}

static char lock_path[PETSC_MAX_PATH_LEN];
static char created_dir[PETSC_MAX_PATH_LEN]; /* made for this run: removed again if left empty */
static int  held  = 0;                       /* rank 0: this process made the lock */
static int  known = 0;                       /* every rank: lock_path names the job's lock */

/* rank 0: take the lock or say why not (message; 0 taken) */
static int TryLock(const char dir[], char message[], size_t len)
{
  char host[256] = "", content[512];
  int  fd;

  (void)gethostname(host, sizeof(host) - 1);
  (void)snprintf(lock_path, sizeof(lock_path), "%s/.fsiopt.lock", dir);
  for (int attempt = 0; attempt < 3; ++attempt) {
    FILE *fp;
    long  pid             = 0;
    char  owner_host[256] = "", started[64] = "";

    fd = open(lock_path, O_WRONLY | O_CREAT | O_EXCL, 0644);
    if (fd >= 0) {
      time_t    now = time(NULL);
      struct tm tm;
      char      stamp[64];
      (void)strftime(stamp, sizeof(stamp), "%Y-%m-%dT%H:%M:%S", localtime_r(&now, &tm));
      (void)snprintf(content, sizeof(content), "%ld %s %s\n", (long)getpid(), host, stamp);
      if (write(fd, content, strlen(content)) != (ssize_t)strlen(content) || close(fd) != 0) {
        (void)unlink(lock_path);
        (void)snprintf(message, len, "option -output_dir %s: cannot write its lock file %s (%s)", dir, lock_path,
                       strerror(errno));
        return 1;
      }
      held = 1;
      return 0;
    }
    if (errno != EEXIST) {
      (void)snprintf(message, len, "option -output_dir %s: cannot create its lock file %s (%s)", dir, lock_path,
                     strerror(errno));
      return 1;
    }
    fp = fopen(lock_path, "r");
    if (fp) {
      if (fscanf(fp, "%ld %255s %63s", &pid, owner_host, started) < 2) pid = 0;
      fclose(fp);
    }
    if (pid > 0 && !strcmp(owner_host, host) && kill((pid_t)pid, 0) != 0 && errno == ESRCH) {
      /* its run ended without releasing it (killed): the directory is free */
      /* stderr: stdout is the -help listing's capture during the set-up */
      fprintf(stderr,
              "fsiopt: output directory %s: taking over the lock of run %ld (started %s), which no longer runs\n", dir,
              pid, started[0] ? started : "?");
      (void)unlink(lock_path);
      continue;
    }
    if (pid > 0)
      (void)snprintf(message, len,
                     "option -output_dir %s: in use by run %ld on %s (started %s; its lock %s): give each run its own "
                     "-output_dir",
                     dir, pid, owner_host, started[0] ? started : "?", lock_path);
    else
      (void)snprintf(message, len, "option -output_dir %s: its lock file %s is unreadable; remove it if no run uses %s",
                     dir, lock_path, dir);
    return 1;
  }
  (void)snprintf(message, len, "option -output_dir %s: another run keeps taking its lock %s", dir, lock_path);
  return 1;
}

PetscErrorCode OutputLockTake(MPI_Comm comm, const char dir[])
{
  PetscMPIInt rank;
  char        message[2 * PETSC_MAX_PATH_LEN + 512] = "";
  int         refused                               = 0;

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  if (!rank) {
    PetscBool exists;
    PetscCall(PetscTestDirectory(dir, 'w', &exists));
    if (!exists) {
      PetscCall(PetscStrncpy(created_dir, dir, sizeof(created_dir)));
      refused = OutputMakeDirectoriesWhy(dir, message, sizeof(message));
    }
    if (!refused) refused = TryLock(dir, message, sizeof(message));
  }
  PetscCallMPI(MPI_Bcast(&refused, 1, MPI_INT, 0, comm));
  PetscCallMPI(MPI_Bcast(message, sizeof(message), MPI_CHAR, 0, comm));
  PetscCheck(!refused, comm, PETSC_ERR_FILE_OPEN, "%s", message);
  PetscCallMPI(MPI_Bcast(lock_path, sizeof(lock_path), MPI_CHAR, 0, comm));
  PetscCallMPI(MPI_Bcast(created_dir, sizeof(created_dir), MPI_CHAR, 0, comm));
  known = 1;
  PetscFunctionReturn(0);
}

void OutputLockReleaseForJob(void)
{
  if (known) (void)unlink(lock_path);
  known = held = 0;
  if (created_dir[0]) (void)rmdir(created_dir);
  created_dir[0] = 0;
}

void OutputLockRelease(void)
{
  if (held) (void)unlink(lock_path);
  held = known = 0;
  if (created_dir[0]) (void)rmdir(created_dir); /* only when the run left nothing in it */
  created_dir[0] = 0;
}
