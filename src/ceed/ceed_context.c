/* The run's choice of operator backend (-fem_backend), and its Ceed: one per process, of
   the libCEED backend the user chose, destroyed at PetscFinalize. */
#include "fem_ceed.h"

const char *const FEMBackends[] = {"petsc", "ceed", "FEMBackend", "FEM_BACKEND_", NULL};

PetscErrorCode FEMBackendGet(FEMBackend *backend)
{
  static PetscBool  read   = PETSC_FALSE;
  static FEMBackend chosen = FEM_BACKEND_PETSC;

  PetscFunctionBeginUser;
  if (!read) {
    PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Finite-element operators", "fem");
    PetscCall(PetscOptionsEnum("-fem_backend",
                               "operators of the fluid: petsc (PETSc's pointwise integration, the reference) or "
                               "ceed (libCEED, the fast path)",
                               NULL, FEMBackends, (PetscEnum)chosen, (PetscEnum *)&chosen, NULL));
    PetscOptionsEnd();
    read = PETSC_TRUE;
  }
  *backend = chosen;
  PetscFunctionReturn(0);
}

static Ceed run_ceed = NULL;

static PetscErrorCode DestroyCeed(void)
{
  PetscFunctionBeginUser;
  if (run_ceed) PetscCallCeed(NULL, CeedDestroy(&run_ceed));
  run_ceed = NULL;
  PetscFunctionReturn(0);
}

/* The CPU backends of the PyPI build of libCEED the Makefile installs that run here: a
   resource libCEED does not have makes it abort the process rather than return an error, so
   the choice is checked first. Its /cpu/self/avx/blocked initializes but dies of SIGILL in
   its first tensor contraction on this machine's CPU (which has AVX2 and FMA): that build
   needs a newer instruction set, and is left out. */
static const char *const cpu_backends[] = {"/cpu/self/opt/blocked", "/cpu/self/ref/serial", NULL};

PetscErrorCode FEMCeedGet(Ceed *ceed)
{
  char      resource[PETSC_MAX_PATH_LEN] = "/cpu/self/opt/blocked", known[1024] = "";
  PetscBool found = PETSC_FALSE;

  PetscFunctionBeginUser;
  if (run_ceed) {
    *ceed = run_ceed;
    PetscFunctionReturn(0);
  }
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "libCEED operators", "fem");
  PetscCall(PetscOptionsString("-ceed", "libCEED backend of the finite-element operators", NULL, resource, resource,
                               sizeof(resource), NULL));
  PetscOptionsEnd();
  for (const char *const *b = cpu_backends; *b; ++b) {
    PetscCall(PetscStrlcat(known, known[0] ? ", " : "", sizeof(known)));
    PetscCall(PetscStrlcat(known, *b, sizeof(known)));
    found = found || !strcmp(resource, *b);
  }
  PetscCheck(found, PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG, "option -ceed %s: expected one of %s", resource, known);
  PetscCallCeed(NULL, CeedInit(resource, &run_ceed));
  PetscCallCeed(run_ceed, CeedSetErrorHandler(run_ceed, CeedErrorStore));
  PetscCall(PetscRegisterFinalize(DestroyCeed));
  *ceed = run_ceed;
  PetscFunctionReturn(0);
}
