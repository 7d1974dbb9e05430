/* The names the general scene's expressions may use besides x, y, z, t: the waveforms read
   from files (-waveform_NAME FILE: a function NAME(t)) and the parameters
   (-parameter_NAME VALUE: a number NAME). */
#ifndef FSIOPT_GENERAL_SYMBOLS_H
#define FSIOPT_GENERAL_SYMBOLS_H
#include "expression.h"

/* reads the options; the symbols live until GeneralSymbolsDestroy */
PetscErrorCode GeneralSymbolsLoad(const ExpressionSymbols **);
PetscErrorCode GeneralSymbolsDestroy(void);
#endif
