/* Entries beyond the weak form's stencil that every Jacobian of a DM must hold (fem.h): a
   0D outlet's dense block couples every velocity node of its face set. Kept with the DM, so
   that whichever backend makes the matrix puts them in its pattern: libCEED's COO pattern
   (ceed_assembly.c) is fixed once made, and an entry outside it cannot be added later. */
#include "fem.h"

typedef struct {
  PetscInt  n;
  PetscInt *rows, *cols;
} ExtraPattern;

static PetscErrorCode ExtraPatternDestroy(void *ctx)
{
  ExtraPattern *p = (ExtraPattern *)ctx;

  PetscFunctionBeginUser;
  PetscCall(PetscFree2(p->rows, p->cols));
  PetscCall(PetscFree(p));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMAddExtraPattern(DM dm, PetscInt n, const PetscInt rows[], const PetscInt cols[])
{
  PetscContainer container;
  ExtraPattern  *p;
  PetscInt      *r, *c, old = 0;
  const PetscInt *old_rows = NULL, *old_cols = NULL;

  PetscFunctionBeginUser;
  PetscCall(FEMGetExtraPattern(dm, &old, &old_rows, &old_cols));
  PetscCall(PetscMalloc2(old + n, &r, old + n, &c));
  PetscCall(PetscArraycpy(r, old_rows, old));
  PetscCall(PetscArraycpy(c, old_cols, old));
  PetscCall(PetscArraycpy(r + old, rows, n));
  PetscCall(PetscArraycpy(c + old, cols, n));
  PetscCall(PetscNew(&p));
  p->n    = old + n;
  p->rows = r;
  p->cols = c;
  PetscCall(PetscContainerCreate(PETSC_COMM_SELF, &container));
  PetscCall(PetscContainerSetPointer(container, p));
  PetscCall(PetscContainerSetUserDestroy(container, ExtraPatternDestroy));
  PetscCall(PetscObjectCompose((PetscObject)dm, "fsiopt_extra_pattern", (PetscObject)container));
  PetscCall(PetscContainerDestroy(&container));
  PetscFunctionReturn(0);
}

PetscErrorCode FEMGetExtraPattern(DM dm, PetscInt *n, const PetscInt **rows, const PetscInt **cols)
{
  PetscContainer container;
  ExtraPattern  *p;

  PetscFunctionBeginUser;
  *n = 0;
  if (rows) *rows = NULL;
  if (cols) *cols = NULL;
  PetscCall(PetscObjectQuery((PetscObject)dm, "fsiopt_extra_pattern", (PetscObject *)&container));
  if (!container) PetscFunctionReturn(0);
  PetscCall(PetscContainerGetPointer(container, (void **)&p));
  *n = p->n;
  if (rows) *rows = p->rows;
  if (cols) *cols = p->cols;
  PetscFunctionReturn(0);
}
