/* The general scene's waveforms and parameters (general_symbols.h). PETSc's pointwise
   kernels take no context, so the expressions that use these live in general.c's file-level
   tables, and so do the symbols here, for the run's length. */
#include "general_symbols.h"
#include "options.h"
#include "waveform.h"

#include <ctype.h>

#define MAX_SYMBOLS 16
static Waveform           waveforms[MAX_SYMBOLS];
static char               function_names[MAX_SYMBOLS][64];
static ExpressionFunction functions[MAX_SYMBOLS];
static char               parameter_text[MAX_SYMBOLS][64];
static const char        *parameter_names[MAX_SYMBOLS];
static double             parameter_values[MAX_SYMBOLS];
static ExpressionSymbols  symbols;

static PetscReal WaveformAt(void *waveform, PetscReal t)
{
  return WaveformValue((Waveform)waveform, t);
}

/* the NAMEs of the options -FAMILYNAME given (not those ending in `skip`) */
static PetscErrorCode FamilyNames(const char family[], const char skip[], PetscInt *count, char names[][64])
{
  PetscInt     n;
  char       **left, **values;
  const size_t length = strlen(family);

  PetscFunctionBeginUser;
  *count = 0;
  PetscCall(PetscOptionsLeftGet(NULL, &n, &left, &values));
  for (PetscInt i = 0; i < n; ++i) {
    const size_t all = strlen(left[i]);
    PetscBool    ours;
    PetscCall(PetscStrncmp(left[i], family, length, &ours));
    if (!ours || (skip && all > strlen(skip) && !strcmp(left[i] + all - strlen(skip), skip))) continue;
    if (*count == MAX_SYMBOLS) {
      PetscCall(PetscOptionsLeftRestore(NULL, &n, &left, &values));
      SETERRQ(PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE, "options -%sNAME: at most %d", family, MAX_SYMBOLS);
    }
    PetscCall(PetscStrncpy(names[(*count)++], left[i] + length, 64));
  }
  PetscCall(PetscOptionsLeftRestore(NULL, &n, &left, &values));
  for (PetscInt k = 0; k < *count; ++k)
    for (const char *c = names[k]; *c; ++c)
      PetscCheck(isalnum((unsigned char)*c) || *c == '_', PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG,
                 "option -%s%s: the name is letters, digits and _ (the expressions use it)", family, names[k]);
  PetscFunctionReturn(0);
}

/* -waveform_NAME FILE, -waveform_NAME_extend periodic|none: the functions NAME(t) */
static PetscErrorCode LoadWaveforms(void)
{
  const char *const extends[] = {"periodic", "none", NULL};
  PetscReal         t_start = 0, t_final;

  PetscFunctionBeginUser;
  PetscCall(OptionsDeclareFamily("-waveform_"));
  PetscCall(FamilyNames("waveform_", "_extend", &symbols.nfunctions, function_names));
  PetscCall(PetscOptionsGetReal(NULL, NULL, "-t_start", &t_start, NULL));
  t_final = t_start;
  PetscCall(PetscOptionsGetReal(NULL, NULL, "-t_final", &t_final, NULL));
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Scene general: waveforms", "scene");
  for (PetscInt w = 0; w < symbols.nfunctions; ++w) {
    char     option[96], extend_option[112], path[PETSC_MAX_PATH_LEN];
    PetscInt extend = 0;
    PetscCall(PetscSNPrintf(option, sizeof(option), "-waveform_%s", function_names[w]));
    PetscCall(PetscSNPrintf(extend_option, sizeof(extend_option), "%s_extend", option));
    PetscCall(PetscOptionsString(option, "a CSV file of rows t,value: the function of t the expressions call by this name",
                                 NULL, "", path, sizeof(path), NULL));
    PetscCall(PetscOptionsEList(extend_option, "beyond the file's rows: repeat them with the period they span, or none",
                                NULL, extends, 2, extends[0], &extend, NULL));
    PetscCall(WaveformLoad(PETSC_COMM_WORLD, option, path, extend == 0 ? PETSC_TRUE : PETSC_FALSE, t_start, t_final,
                           &waveforms[w]));
    functions[w].name = function_names[w];
    functions[w].fn   = WaveformAt;
    functions[w].ctx  = waveforms[w];
  }
  PetscOptionsEnd();
  PetscFunctionReturn(0);
}

/* -parameter_NAME VALUE: the numbers NAME */
static PetscErrorCode LoadParameters(void)
{
  const char *const reserved[] = {"x", "y", "z", "t", "pi", "_pi", "_e"};

  PetscFunctionBeginUser;
  PetscCall(OptionsDeclareFamily("-parameter_"));
  PetscCall(FamilyNames("parameter_", NULL, &symbols.nparameters, parameter_text));
  PetscOptionsBegin(PETSC_COMM_WORLD, NULL, "Scene general: parameters", "scene");
  for (PetscInt p = 0; p < symbols.nparameters; ++p) {
    char      option[96];
    PetscReal value = 0;
    PetscBool given;
    PetscCall(PetscSNPrintf(option, sizeof(option), "-parameter_%s", parameter_text[p]));
    for (size_t r = 0; r < sizeof(reserved) / sizeof(reserved[0]); ++r)
      PetscCheck(strcmp(parameter_text[p], reserved[r]), PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG,
                 "option %s: %s is a name of every expression already", option, reserved[r]);
    for (PetscInt w = 0; w < symbols.nfunctions; ++w)
      PetscCheck(strcmp(parameter_text[p], function_names[w]), PETSC_COMM_WORLD, PETSC_ERR_ARG_WRONG,
                 "option %s: -waveform_%s has that name", option, function_names[w]);
    PetscCall(PetscOptionsReal(option, "a number the expressions use by this name", NULL, value, &value, &given));
    PetscCheck(PetscIsNormalReal(value) || value == 0, PETSC_COMM_WORLD, PETSC_ERR_ARG_OUTOFRANGE,
               "option %s: expected a finite number", option);
    parameter_names[p]  = parameter_text[p];
    parameter_values[p] = value;
  }
  PetscOptionsEnd();
  PetscFunctionReturn(0);
}

PetscErrorCode GeneralSymbolsLoad(const ExpressionSymbols **loaded)
{
  PetscFunctionBeginUser;
  PetscCall(GeneralSymbolsDestroy());
  symbols.functions        = functions;
  symbols.parameter_names  = parameter_names;
  symbols.parameter_values = parameter_values;
  PetscCall(LoadWaveforms());
  PetscCall(LoadParameters());
  *loaded = &symbols;
  PetscFunctionReturn(0);
}

PetscErrorCode GeneralSymbolsDestroy(void)
{
  PetscFunctionBeginUser;
  for (PetscInt w = 0; w < symbols.nfunctions; ++w) PetscCall(WaveformDestroy(&waveforms[w]));
  symbols.nfunctions  = 0;
  symbols.nparameters = 0;
  PetscFunctionReturn(0);
}
