/* The options files a run will read, checked before PetscInitialize: PETSc reads them inside
   it, answers a malformed one with its traceback banner and follows a file that includes
   itself until the stack overflows. Plain C and libyaml only: nothing of PETSc exists yet. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <ctype.h>
#include <unistd.h>
#include <yaml.h>
#include "options.h"

#define MAX_INCLUDE_DEPTH 16
#define MAX_FILE_BYTES    (16 << 20)

typedef struct {
  char        message[2 * 4096];
  const char *stack[MAX_INCLUDE_DEPTH]; /* the real paths of the files being read, outermost first */
  int         depth;
} Check;

static int Fail(Check *check, const char *format, ...) __attribute__((format(printf, 2, 3)));

static int Fail(Check *check, const char *format, ...)
{
  va_list args;

  va_start(args, format);
  vsnprintf(check->message, sizeof(check->message), format, args);
  va_end(args);
  return 1;
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

/* The line of the first byte that cannot be in a text file (NUL, other control characters,
   invalid UTF-8), or 0. */
static int BinaryLine(const unsigned char *text, size_t n)
{
  int line = 1;

  for (size_t i = 0; i < n; ++i) {
    const unsigned char c = text[i];
    size_t              follow;
    if (c == '\n') ++line;
    if (c < 0x80) {
      if (c < 0x20 && c != '\n' && c != '\r' && c != '\t') return line;
      continue;
    }
    if (c >= 0xc2 && c <= 0xdf) follow = 1;
    else if (c >= 0xe0 && c <= 0xef) follow = 2;
    else if (c >= 0xf0 && c <= 0xf4) follow = 3;
    else return line;
    for (size_t k = 1; k <= follow; ++k)
      if (i + k >= n || (text[i + k] & 0xc0) != 0x80) return line;
    i += follow;
  }
  return 0;
}

static int ReadFile(Check *check, const char path[], const char origin[], char **text, size_t *n)
{
  const int problem = OptionsFileProblem(path);
  FILE     *fp;
  long      size;

  if (problem) return Fail(check, "%s %s: %s", origin, path, OptionsFileProblemText(problem));
  if (!(fp = fopen(path, "rb"))) return Fail(check, "%s %s: %s", origin, path, OptionsFileProblemText(1));
  fseek(fp, 0, SEEK_END);
  size = ftell(fp);
  fseek(fp, 0, SEEK_SET);
  if (size > MAX_FILE_BYTES) {
    fclose(fp);
    return Fail(check, "%s %s: %ld bytes, too large for an options file (at most %d)", origin, path, size,
                MAX_FILE_BYTES);
  }
  *text = malloc((size_t)size + 1);
  *n    = fread(*text, 1, (size_t)size, fp);
  fclose(fp);
  (*text)[*n] = 0;
  return 0;
}

/* PETSc's YAML reader takes a mapping at the top; below, mappings (prefixes), scalars and
   sequences of scalars or mappings. It includes no other file. */
static int CheckYAMLNode(Check *check, const char path[], yaml_document_t *doc, yaml_node_t *node, int top)
{
  const int line = (int)node->start_mark.line + 1;

  switch (node->type) {
  case YAML_MAPPING_NODE:
    for (yaml_node_pair_t *pair = node->data.mapping.pairs.start; pair < node->data.mapping.pairs.top; ++pair) {
      yaml_node_t *key = yaml_document_get_node(doc, pair->key), *value = yaml_document_get_node(doc, pair->value);
      if (!key || key->type != YAML_SCALAR_NODE)
        return Fail(check, "options file %s line %d: expected a name as the key, found a %s", path,
                    key ? (int)key->start_mark.line + 1 : line,
                    key && key->type == YAML_SEQUENCE_NODE ? "list" : "mapping");
      if (top && !strcmp((const char *)key->data.scalar.value, "options_file"))
        return Fail(check,
                    "options file %s line %d: a YAML file cannot include another (PETSc's YAML reader does not follow "
                    "options_file); give -options_file on the command line",
                    path, (int)key->start_mark.line + 1);
      /* YAML keeps the last of two equal keys without a word: one of them is a mistake */
      for (yaml_node_pair_t *earlier = node->data.mapping.pairs.start; earlier < pair; ++earlier) {
        yaml_node_t *other = yaml_document_get_node(doc, earlier->key);
        if (other && other->type == YAML_SCALAR_NODE &&
            !strcmp((const char *)other->data.scalar.value, (const char *)key->data.scalar.value))
          return Fail(check, "options file %s line %d: key '%s' given again (first on line %d)", path,
                      (int)key->start_mark.line + 1, (const char *)key->data.scalar.value,
                      (int)other->start_mark.line + 1);
      }
      if (value && CheckYAMLNode(check, path, doc, value, 0)) return 1;
    }
    return 0;
  case YAML_SEQUENCE_NODE:
    if (top)
      return Fail(check,
                  "options file %s line %d: expected a mapping of option names to values at the top, found a list",
                  path, line);
    for (yaml_node_item_t *item = node->data.sequence.items.start; item < node->data.sequence.items.top; ++item) {
      yaml_node_t *element = yaml_document_get_node(doc, *item);
      if (element && element->type == YAML_SEQUENCE_NODE)
        return Fail(check, "options file %s line %d: a list inside a list; expected values or mappings", path,
                    (int)element->start_mark.line + 1);
      if (element && element->type == YAML_MAPPING_NODE && CheckYAMLNode(check, path, doc, element, 0)) return 1;
    }
    return 0;
  default:
    if (top)
      return Fail(check,
                  "options file %s line %d: expected a mapping of option names to values, found the single value "
                  "'%.40s'",
                  path, line, (const char *)node->data.scalar.value);
    return 0;
  }
}

/* A tab before the first character of the line the parser stopped on: say so, YAML's own
   message ("found character that cannot start any token") does not. */
static const char *TabHint(const char *text, size_t line)
{
  const char *c = text;

  for (size_t l = 0; l < line && c; ++l) {
    c = strchr(c, '\n');
    if (c) ++c;
  }
  if (!c) return "";
  for (; *c == ' ' || *c == '\t'; ++c)
    if (*c == '\t') return " (a tab indents this line: YAML indents with spaces)";
  return "";
}

static int CheckYAML(Check *check, const char path[], const char *text, size_t n)
{
  yaml_parser_t   parser;
  yaml_document_t doc;
  yaml_node_t    *root;
  int             failed = 0;

  yaml_parser_initialize(&parser);
  yaml_parser_set_input_string(&parser, (const unsigned char *)text, n);
  if (!yaml_parser_load(&parser, &doc)) {
    const size_t line = parser.problem_mark.line;
    failed            = Fail(check, "options file %s line %zu: not valid YAML: %s%s%s%s", path, line + 1,
                  parser.problem ? parser.problem : "parse error", parser.context ? " " : "",
                  parser.context ? parser.context : "", TabHint(text, line));
    yaml_parser_delete(&parser);
    return failed;
  }
  root = yaml_document_get_root_node(&doc);
  if (!root) failed = Fail(check, "options file %s: no options in it (an empty YAML document)", path);
  else failed = CheckYAMLNode(check, path, &doc, root, 1);
  yaml_document_delete(&doc);
  yaml_parser_delete(&parser);
  return failed;
}

static int CheckFile(Check *check, const char path[], int yaml, const char origin[]);

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
        snprintf(option, sizeof(option), "%s", token);
        expect_value = 1;
        continue;
      }
      if (!expect_value)
        return Fail(check, "options file %s line %d: expected -option [value], found '%.40s'%s", path, line_number,
                    token, tokens ? " after a value" : " (option names start with -)");
      expect_value = 0;
      if (!strcmp(option, "-options_file") || !strcmp(option, "-options_file_yaml"))
        if (CheckFile(check, token, !strcmp(option, "-options_file_yaml") || IsYAMLName(token), path)) return 1;
    }
    if (expect_value && (!strcmp(option, "-options_file") || !strcmp(option, "-options_file_yaml")))
      return Fail(check, "options file %s line %d: option %s: expected a file name", path, line_number, option);
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
      failed = d == check->depth - 1
               ? Fail(check, "options file %s includes itself", path)
               : Fail(check, "options file %s includes %s, which includes it again (a loop)", check->stack[d], origin);
      free(real);
      return failed;
    }
  if (check->depth == MAX_INCLUDE_DEPTH) {
    free(text);
    free(real);
    return Fail(check, "options file %s: included more than %d deep", path, MAX_INCLUDE_DEPTH);
  }
  if ((binary = BinaryLine((const unsigned char *)text, n)))
    failed = Fail(check, "options file %s line %d: binary bytes; expected a text file of options", path, binary);
  else {
    check->stack[check->depth++] = real;
    failed                       = yaml ? CheckYAML(check, path, text, n) : CheckPlain(check, path, text);
    --check->depth;
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
      if (!strcmp(t, "-options_file") || !strcmp(t, "-options_file_yaml")) {
        char *file = strtok_r(NULL, " \t", &save);
        if (!file) failed = Fail(&check, "environment variable PETSC_OPTIONS: option %s: expected a file name", t);
        else
          failed = CheckFile(&check, file, !strcmp(t, "-options_file_yaml") || IsYAMLName(file),
                             "environment variable PETSC_OPTIONS: option -options_file");
      }
    free(env_copy);
  }
  for (int i = 1; i < argc && !failed; ++i) {
    const int yaml_option = !strcmp(argv[i], "-options_file_yaml");
    char      origin[64];
    if (strcmp(argv[i], "-options_file") && !yaml_option) continue;
    if (i + 1 >= argc) failed = Fail(&check, "option %s: expected a file name", argv[i]);
    else {
      snprintf(origin, sizeof(origin), "option %s", argv[i]);
      failed = CheckFile(&check, argv[i + 1], yaml_option || IsYAMLName(argv[i + 1]), origin);
    }
  }
  if (failed) snprintf(message, len, "%s", check.message);
  return failed;
}
