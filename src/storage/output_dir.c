/* The output directory (output_files.h): made with its parents, and owned by one run through
   a lock file <output_dir>/.fsiopt.lock with the pid, host and start time of the run that
   writes there; and the same lock for another path the run writes (its checkpoint file,
   <file>.lock). Two runs writing into one directory, or one checkpoint file, would
   interleave and overwrite each other's files. */
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

/* A run's locks: its output directory's, then its checkpoint file's (OutputLockTakeFile). */
#define MAX_LOCKS 2
typedef struct {
  char path[PETSC_MAX_PATH_LEN];
  int  held;  /* rank 0: this process made the lock */
  int  known; /* every rank: path names the job's lock */
} Lock;
static Lock locks[MAX_LOCKS];
static int  nlocks = 0;
static char created_dir[PETSC_MAX_PATH_LEN]; /* made for this run: removed again if left empty */

/* What a lock guards, for its messages: the option and its value, what the value names, and
   how a live holder relates to it ("in use by", "in the output directory of"). */
typedef struct {
  const char *option, *value, *noun, *relation;
} Guarded;

typedef enum {
  LOCK_TAKE,  /* create it; a dead run's is taken over with a notice */
  LOCK_CHECK, /* another live run's refused, a dead run's removed with a notice; none created */
  LOCK_PEEK   /* another live run's refused; a dead run's left as it is, for its path's next owner */
} LockMode;

/* rank 0: whether the lock file `path` lets this run go on (0; with LOCK_TAKE: created), or
   why not (message; -1: it cannot be created, 1: refused) */
static int TryLock(const char path[], const Guarded *g, LockMode mode, char message[], size_t len)
{
  char host[256] = "", content[512];
  int  fd;

  (void)gethostname(host, sizeof(host) - 1);
  for (int attempt = 0; attempt < 3; ++attempt) {
    FILE *fp;
    long  pid             = 0;
    char  owner_host[256] = "", started[64] = "";

    if (mode != LOCK_TAKE && access(path, F_OK) != 0) return 0; /* nobody holds it */
    fd = mode == LOCK_TAKE ? open(path, O_WRONLY | O_CREAT | O_EXCL, 0644) : -1;
    if (fd >= 0) {
      time_t    now = time(NULL);
      struct tm tm;
      char      stamp[64];
      (void)strftime(stamp, sizeof(stamp), "%Y-%m-%dT%H:%M:%S", localtime_r(&now, &tm));
      (void)snprintf(content, sizeof(content), "%ld %s %s\n", (long)getpid(), host, stamp);
      if (write(fd, content, strlen(content)) != (ssize_t)strlen(content) || close(fd) != 0) {
        (void)unlink(path);
        (void)snprintf(message, len, "option %s %s: cannot write its lock file %s (%s)", g->option, g->value, path,
                       strerror(errno));
        return 1;
      }
      return 0;
    }
    if (mode == LOCK_TAKE && errno != EEXIST) {
      (void)snprintf(message, len, "option %s %s: cannot create its lock file %s (%s)", g->option, g->value, path,
                     strerror(errno));
      return -1;
    }
    fp = fopen(path, "r");
    if (fp) {
      if (fscanf(fp, "%ld %255s %63s", &pid, owner_host, started) < 2) pid = 0;
      fclose(fp);
    }
    if (pid > 0 && !strcmp(owner_host, host) && kill((pid_t)pid, 0) != 0 && errno == ESRCH) {
      /* its run ended without releasing it (killed): the path is free */
      if (mode == LOCK_PEEK) return 0;
      /* stderr: stdout is the -help listing's capture during the set-up */
      fprintf(stderr, "fsiopt: %s %s: taking over the lock of run %ld (started %s), which no longer runs\n", g->noun,
              g->value, pid, started[0] ? started : "?");
      (void)unlink(path);
      continue;
    }
    if (pid > 0)
      (void)snprintf(message, len, "option %s %s: %s run %ld on %s (started %s; its lock %s): give each run its own %s",
                     g->option, g->value, g->relation, pid, owner_host, started[0] ? started : "?", path, g->option);
    else
      (void)snprintf(message, len, "option %s %s: the lock file %s is unreadable; remove it if no run uses %s",
                     g->option, g->value, path, g->value);
    return 1;
  }
  (void)snprintf(message, len, "option %s %s: another run keeps taking its lock %s", g->option, g->value, path);
  return 1;
}

/* rank 0's verdict (refused: 0 or 1, message) on every rank, refused there with one line */
static PetscErrorCode Agree(MPI_Comm comm, int refused, char message[], size_t len)
{
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Bcast(&refused, 1, MPI_INT, 0, comm));
  PetscCallMPI(MPI_Bcast(message, (PetscMPIInt)len, MPI_CHAR, 0, comm));
  PetscCheck(!refused, comm, PETSC_ERR_FILE_OPEN, "%s", message);
  PetscFunctionReturn(0);
}

/* Every rank: lock `path` (which rank 0 has created) is the run's, to be released at its end. */
static PetscErrorCode Register(MPI_Comm comm, const char path[])
{
  PetscMPIInt rank;

  PetscFunctionBeginUser;
  PetscCheck(nlocks < MAX_LOCKS, PETSC_COMM_SELF, PETSC_ERR_PLIB, "a run holds at most %d locks", MAX_LOCKS);
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(PetscStrncpy(locks[nlocks].path, path, sizeof(locks[nlocks].path)));
  locks[nlocks].held  = !rank;
  locks[nlocks].known = 1;
  ++nlocks;
  PetscFunctionReturn(0);
}

PetscErrorCode OutputLockTake(MPI_Comm comm, const char dir[])
{
  PetscMPIInt   rank;
  char          message[3 * PETSC_MAX_PATH_LEN + 512] = "", path[PETSC_MAX_PATH_LEN];
  int           refused                               = 0;
  const Guarded g = {"-output_dir", dir, "output directory", "in use by"};

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s/.fsiopt.lock", dir));
  if (!rank) {
    PetscBool exists;
    PetscCall(PetscTestDirectory(dir, 'w', &exists));
    if (!exists) {
      PetscCall(PetscStrncpy(created_dir, dir, sizeof(created_dir)));
      refused = OutputMakeDirectoriesWhy(dir, message, sizeof(message));
    }
    if (!refused) refused = TryLock(path, &g, LOCK_TAKE, message, sizeof(message)) != 0;
  }
  PetscCall(Agree(comm, refused, message, sizeof(message)));
  PetscCallMPI(MPI_Bcast(created_dir, sizeof(created_dir), MPI_CHAR, 0, comm));
  PetscCall(Register(comm, path));
  PetscFunctionReturn(0);
}

PetscErrorCode OutputLockTakeFile(MPI_Comm comm, const char option[], const char file[], const char noun[],
                                  PetscBool in_output_dir)
{
  PetscMPIInt   rank;
  char          message[3 * PETSC_MAX_PATH_LEN + 512] = "", path[PETSC_MAX_PATH_LEN], dir_lock[PETSC_MAX_PATH_LEN];
  int           refused = 0, created = 0;
  const Guarded g = {option, file, noun, "in use by"}, owner = {option, file, noun, "in the output directory of"};
  const char   *slash = strrchr(file, '/');

  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCall(PetscSNPrintf(path, sizeof(path), "%s.lock", file));
  if (slash) PetscCall(PetscSNPrintf(dir_lock, sizeof(dir_lock), "%.*s/.fsiopt.lock", (int)(slash - file), file));
  else PetscCall(PetscStrncpy(dir_lock, ".fsiopt.lock", sizeof(dir_lock)));
  if (!rank) {
    if (in_output_dir) refused = TryLock(path, &g, LOCK_CHECK, message, sizeof(message));
    else {
      refused = TryLock(path, &g, LOCK_TAKE, message, sizeof(message));
      created = !refused;
      /* not creatable (no such directory): the run's check of the file says why it cannot
         write there, if it ever writes it */
      if (refused == -1) refused = 0;
      /* a run whose -output_dir holds the file writes it without a lock of its own (its
         directory's covers it) and looks for this one after taking its directory's; this
         one taken first and the directory's looked at second, of two runs starting
         together at least one sees the other */
      if (!refused) refused = TryLock(dir_lock, &owner, LOCK_PEEK, message, sizeof(message));
    }
  }
  PetscCallMPI(MPI_Bcast(&created, 1, MPI_INT, 0, comm));
  if (created) PetscCall(Register(comm, path)); /* before a refusal: released on its error path */
  PetscCall(Agree(comm, refused != 0, message, sizeof(message)));
  PetscFunctionReturn(0);
}

/* every lock before the directory, which may hold one of them */
static void ReleaseAll(int every_rank)
{
  for (int i = 0; i < nlocks; ++i) {
    if (locks[i].held || (every_rank && locks[i].known)) (void)unlink(locks[i].path);
    locks[i].held = locks[i].known = 0;
  }
  nlocks = 0;
  if (created_dir[0]) (void)rmdir(created_dir); /* only when the run left nothing in it */
  created_dir[0] = 0;
}

void OutputLockReleaseForJob(void)
{
  ReleaseAll(1);
}

void OutputLockRelease(void)
{
  ReleaseAll(0);
}
