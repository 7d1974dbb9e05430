/* PC "ilubaij": ILU on the operator copied to block AIJ (src/common/pc_ilu_baij.c). */
#pragma once
#include <petscpc.h>

PetscErrorCode PCRegisterILUBAIJ(void);
