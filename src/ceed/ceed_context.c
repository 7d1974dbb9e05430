/* The run's choice of operator backend (-fem_backend), and its Ceed: one per process, of
   the libCEED backend the user chose, destroyed at PetscFinalize. */
#include "fem_ceed.h"

static const char *const FEMBackends[] = {"petsc", "ceed", "FEMBackend", "FEM_BACKEND_", NULL};

static struct {
  PetscBool  read;
  FEMBackend backend;
  PetscBool  check;
  char       resource[PETSC_MAX_PATH_LEN];
} choice = {PETSC_FALSE, FEM_BACKEND_CEED, PETSC_FALSE,
            "/cpu/self/opt/blocked"}; /* ceed: the whole suite passes with it */

/* the three options of the operators, read once (the fluid reads them early, so that -help lists them) */
static PetscErrorCode ReadChoice(void)
{
  PetscFunctionBeginUser;
  if (choice.read) PetscFunctionReturn(0);
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Finite-element operators", "fem");
  PetscCall(PetscOptionsEnum("-fem_backend",
                             "finite-element operators of the fluid, the structure and the mesh motion: ceed "
                             "(libCEED, the fast path) or petsc (PETSc's pointwise integration, the reference)",
                             NULL, FEMBackends, (PetscEnum)choice.backend, (PetscEnum *)&choice.backend, NULL));
  PetscCall(PetscOptionsBool("-fem_backend_check",
                             "compare the fluid's residual and Jacobian of both backends at the start of the first "
                             "three steps, at the step's state and at a random one (stops above 1e-12 relative)",
                             NULL, choice.check, &choice.check, NULL));
  PetscCall(PetscOptionsString("-ceed", "libCEED backend of the finite-element operators", NULL, choice.resource,
                               choice.resource, sizeof(choice.resource), NULL));
  PetscOptionsEnd();
  choice.read = PETSC_TRUE;
  PetscFunctionReturn(0);
}

PetscErrorCode FEMBackendGet(FEMBackend *backend, PetscBool *check)
{
  PetscFunctionBeginUser;
  PetscCall(ReadChoice());
  if (backend) *backend = choice.backend;
  if (check) *check = choice.check;
  PetscFunctionReturn(0);
}

PetscErrorCode FEMBackendGetName(const char **name, PetscBool *check)
{
  FEMBackend backend = FEM_BACKEND_CEED;

  PetscFunctionBeginUser;
  PetscCall(FEMBackendGet(&backend, check));
  *name = FEMBackends[backend];
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
  char      known[1024] = "";
  PetscBool found       = PETSC_FALSE;

  PetscFunctionBeginUser;
  if (run_ceed) {
    *ceed = run_ceed;
    PetscFunctionReturn(0);
  }
  PetscCall(ReadChoice());
  for (const char *const *b = cpu_backends; *b; ++b) {
    PetscCall(PetscStrlcat(known, known[0] ? ", " : "", sizeof(known)));
    PetscCall(PetscStrlcat(known, *b, sizeof(known)));
    found = found || !strcmp(choice.resource, *b);
  }
  PetscCheck(found, PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG, "option -ceed %s: expected one of %s", choice.resource,
             known);
  /* an error libCEED raises without a Ceed (a failed allocation) takes the handler this names,
     and its default aborts with a backtrace: returned instead, it reaches PetscCallCeed */
  if (setenv("CEED_ERROR_HANDLER", "return", 0)) SETERRQ(PETSC_COMM_SELF, PETSC_ERR_SYS, "setenv CEED_ERROR_HANDLER failed");
  PetscCallCeed(NULL, CeedInit(choice.resource, &run_ceed));
  PetscCallCeed(run_ceed, CeedSetErrorHandler(run_ceed, CeedErrorStore));
  PetscCall(PetscRegisterFinalize(DestroyCeed));
  *ceed = run_ceed;
  PetscFunctionReturn(0);
}
