/* The options files a run will read, checked before PetscInitialize: PETSc reads them inside
   it, answers a malformed one with its traceback banner and follows a file that includes
   itself until the stack overflows. Plain C only: nothing of PETSc exists yet; YAML files are
   checked in options_yaml.c. All of them count against PETSc's table of options. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <ctype.h>
#include <unistd.h>
#include <strings.h>
#include "options.h"
#include "options_files.h"

int CheckFail(Check *check, const char *format, ...)
{
  va_list args;

  va_start(args, format);
  vsnprintf(check->message, sizeof(check->message), format, args);
  va_end(args);
  return 1;
}

/* The rule of PETSc's PetscOptionsValidKey: what a token on the command line or in a plain
   file is, a name or a value (-1e-3 and -inf are values) */
static int IsOptionName(const char token[])
{
  char *end;

  if (token[0] != '-') return 0;
  if (token[1] == '-') ++token;
  if (!isalpha((unsigned char)token[1])) return 0;
  (void)strtod(token, &end);
  return end == token || *end == '_' || isalnum((unsigned char)*end);
}

int CheckOption(Check *check, const char path[], const char name[], int line, int unique, long from, long to)
{
  for (int i = 0; i < check->noptions; ++i) {
    CheckedOption *o = &check->options[i];
    if (strcasecmp(o->name, name)) continue; /* PETSc's names ignore case */
    if (unique && o->file == check->file && !(from <= o->time && o->time < to))
      return CheckFail(check, "options file %s line %d: option -%s given again (first on line %d)", path, line, name,
                       o->line);
    o->file = check->file;
    o->line = line;
    o->time = check->time++;
    return 0;
  }
  if (check->noptions == MAX_GIVEN_OPTIONS) {
    char where[4096 + 64] = "";
    if (path) snprintf(where, sizeof(where), "options file %s line %d: ", path, line);
    return CheckFail(check,
                     "%soption -%.60s: more than %d options given in all (files and command line); PETSc holds %d, "
                     "fsiopt's defaults among them",
                     where, name, MAX_GIVEN_OPTIONS, PETSC_MAX_OPTIONS);
  }
  check->options[check->noptions++] = (CheckedOption){strdup(name), check->file, line, check->time++};
  return 0;
}

static int EndsWith(const char s[], const char tail[])
{
  const size_t ls = strlen(s), lt = strlen(tail);
  return ls >= lt && !strcmp(s + ls - lt, tail);
}

/* PETSc reads a file as YAML by its name (or under -options_file_yaml) */
static int IsYAMLName(const char path[])
{
  return EndsWith(path, ".yaml") || EndsWith(path, ".yml");
}

size_t UTF8SequenceLength(const unsigned char *text, size_t n)
{
  size_t follow;

  if (text[0] < 0x80) return 1;
  if (text[0] >= 0xc2 && text[0] <= 0xdf) follow = 1;
  else if (text[0] >= 0xe0 && text[0] <= 0xef) follow = 2;
  else if (text[0] >= 0xf0 && text[0] <= 0xf4) follow = 3;
  else return 0;
  if (follow >= n) return 0;
  for (size_t k = 1; k <= follow; ++k)
    if ((text[k] & 0xc0) != 0x80) return 0;
  return follow + 1;
}

/* The line of the first byte that cannot be in a text file (NUL, other control characters,
   invalid UTF-8), or 0. */
static int BinaryLine(const unsigned char *text, size_t n)
{
  int line = 1;

  for (size_t i = 0, len; i < n; i += len) {
    const unsigned char c = text[i];
    if (c == '\n') ++line;
    if (c < 0x20 && c != '\n' && c != '\r' && c != '\t') return line;
    if (!(len = UTF8SequenceLength(text + i, n - i))) return line;
  }
  return 0;
}

static int ReadFile(Check *check, const char path[], const char origin[], char **text, size_t *n)
{
  const int problem = OptionsFileProblem(path);
  FILE     *fp;
  long      size;

  if (problem) return CheckFail(check, "%s %s: %s", origin, path, OptionsFileProblemText(problem));
  if (!(fp = fopen(path, "rb"))) return CheckFail(check, "%s %s: %s", origin, path, OptionsFileProblemText(1));
  fseek(fp, 0, SEEK_END);
  size = ftell(fp);
  fseek(fp, 0, SEEK_SET);
  if (size > MAX_FILE_BYTES) {
    fclose(fp);
    return CheckFail(check, "%s %s: %ld bytes, too large for an options file (at most %d)", origin, path, size,
                     MAX_FILE_BYTES);
  }
  *text = malloc((size_t)size + 1);
  *n    = fread(*text, 1, (size_t)size, fp);
  fclose(fp);
  (*text)[*n] = 0;
  return 0;
}

static int CheckFile(Check *check, const char path[], int yaml, const char origin[]);

/* PETSc compares these names ignoring case */
static int IsFileOption(const char name[])
{
  return !strcasecmp(name, "-options_file") || !strcasecmp(name, "-options_file_yaml");
}

/* PETSc sets no option of these, it acts on them */
static int IsAction(const char name[])
{
  return IsFileOption(name) || !strcasecmp(name, "-options_string_yaml") || !strcasecmp(name, "-prefix_push") ||
         !strcasecmp(name, "-prefix_pop");
}

/* The command line's options and PETSC_OPTIONS's, for the count of all options */
static int CheckArguments(Check *check, int argc, char **argv)
{
  for (int i = 0; i < argc; ++i)
    if (IsOptionName(argv[i]) && !IsAction(argv[i]) && CheckOption(check, NULL, argv[i] + 1, 0, 0, 0, 0)) return 1;
  return 0;
}

static int IsNumber(const char *token)
{
  char *end;
  (void)strtod(token, &end);
  return end != token && (!*end || isspace((unsigned char)*end));
}

/* PETSc's plain format: per line, -name [value] pairs or "alias -a -b", # starts a comment.
   An -options_file inside is followed, as PETSc would. */
static int CheckPlain(Check *check, const char path[], char *text)
{
  int line_number = 0;

  for (char *line = text, *next; line; line = next) {
    char *token, *save, *hash;
    int   expect_value = 0, after_alias = 0, tokens = 0;
    char  option[256] = "";

    ++line_number;
    next = strchr(line, '\n');
    if (next) *next++ = 0;
    if ((hash = strchr(line, '#'))) *hash = 0;
    for (token = strtok_r(line, " \t\r", &save); token; token = strtok_r(NULL, " \t\r", &save), ++tokens) {
      const int is_name = token[0] == '-' && !IsNumber(token);
      if (!tokens && !strcmp(token, "alias")) {
        after_alias = 1;
        continue;
      }
      if (after_alias) continue;
      if (is_name) {
        if (IsOptionName(token) && CheckOption(check, path, token + 1, line_number, 0, 0, 0)) return 1;
        snprintf(option, sizeof(option), "%s", token);
        expect_value = 1;
        continue;
      }
      if (!expect_value)
        return CheckFail(check, "options file %s line %d: expected -option [value], found '%.40s'%s", path, line_number,
                         token, tokens ? " after a value" : " (option names start with -)");
      expect_value = 0;
      if (IsFileOption(option))
        if (CheckFile(check, token, !strcasecmp(option, "-options_file_yaml") || IsYAMLName(token), path)) return 1;
    }
    if (expect_value && IsFileOption(option))
      return CheckFail(check, "options file %s line %d: option %s: expected a file name", path, line_number, option);
  }
  return 0;
}

static int CheckFile(Check *check, const char path[], int yaml, const char origin[])
{
  char   where[4096 + 64], *text = NULL, *real;
  size_t n = 0;
  int    failed, binary;

  if (check->depth) snprintf(where, sizeof(where), "options file %s includes", origin);
  else snprintf(where, sizeof(where), "%s", origin);
  if (ReadFile(check, path, where, &text, &n)) return 1;
  real = realpath(path, NULL);
  for (int d = 0; d < check->depth; ++d)
    if (real && !strcmp(real, check->stack[d])) {
      free(text);
      failed = d == check->depth - 1 ? CheckFail(check, "options file %s includes itself", path)
                                     : CheckFail(check, "options file %s includes %s, which includes it again (a loop)",
                                                 check->stack[d], origin);
      free(real);
      return failed;
    }
  if (check->depth == MAX_INCLUDE_DEPTH) {
    free(text);
    free(real);
    return CheckFail(check, "options file %s: included more than %d deep", path, MAX_INCLUDE_DEPTH);
  }
  if ((binary = BinaryLine((const unsigned char *)text, n)))
    failed = CheckFail(check, "options file %s line %d: binary bytes; expected a text file of options", path, binary);
  else {
    const int outer              = check->file;
    check->file                  = ++check->files;
    check->stack[check->depth++] = real;
    failed                       = yaml ? CheckYAML(check, path, text, n) : CheckPlain(check, path, text);
    --check->depth;
    check->file = outer;
  }
  free(text);
  free(real);
  return failed;
}

/* The files PETSc reads when it starts: the petscrc files (unless -skip_petscrc), those named
   in PETSC_OPTIONS, then those on the command line. */
int OptionsFilesCheck(int argc, char **argv, char message[], size_t len)
{
  Check       check   = {.depth = 0};
  int         skip_rc = 0, failed = 0;
  const char *home = getenv("HOME"), *env = getenv("PETSC_OPTIONS");
  char        rc[4096], *env_copy         = NULL;

  message[0] = 0;
  for (int i = 1; i < argc; ++i)
    if (!strcmp(argv[i], "-skip_petscrc")) skip_rc = 1;
  if (!skip_rc) {
    const char *local[] = {".petscrc", "petscrc"};
    if (home) {
      snprintf(rc, sizeof(rc), "%s/.petscrc", home);
      if (!access(rc, F_OK)) failed = CheckFile(&check, rc, 0, "the petscrc file");
    }
    for (int i = 0; i < 2 && !failed; ++i)
      if (!access(local[i], F_OK)) failed = CheckFile(&check, local[i], 0, "the petscrc file");
  }
  if (!failed && env) {
    char *save;
    env_copy = strdup(env);
    for (char *t = strtok_r(env_copy, " \t", &save); t && !failed; t = strtok_r(NULL, " \t", &save))
      if (IsFileOption(t)) {
        char *file = strtok_r(NULL, " \t", &save);
        if (!file) failed = CheckFail(&check, "environment variable PETSC_OPTIONS: option %s: expected a file name", t);
        else
          failed = CheckFile(&check, file, !strcasecmp(t, "-options_file_yaml") || IsYAMLName(file),
                             "environment variable PETSC_OPTIONS: option -options_file");
      } else failed = CheckArguments(&check, 1, &t);
    free(env_copy);
  }
  for (int i = 1; i < argc && !failed; ++i) {
    const int yaml_option = !strcasecmp(argv[i], "-options_file_yaml");
    char      origin[64];
    if (!IsFileOption(argv[i])) continue;
    if (i + 1 >= argc) failed = CheckFail(&check, "option %s: expected a file name", argv[i]);
    else {
      snprintf(origin, sizeof(origin), "option %s", argv[i]);
      failed = CheckFile(&check, argv[i + 1], yaml_option || IsYAMLName(argv[i + 1]), origin);
    }
  }
  if (!failed) failed = CheckArguments(&check, argc - 1, argv + 1);
  for (int i = 0; i < check.noptions; ++i) free(check.options[i].name);
  if (failed) snprintf(message, len, "%s", check.message);
  return failed;
}
