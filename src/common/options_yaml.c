/* A YAML options file, checked against what PETSc 3.18's reader (src/sys/objects/optionsyaml.c)
   does with it: it reads every document of the file, a mapping at the top; a mapping below
   becomes a prefix, a list one option of comma-separated values (a mapping in it holds one
   key and gives options too); it expands each alias and merge key ("<<", in order: a later
   key replaces what it merged), skips keys starting with "$$" and follows "$$x: !include
   file". Whatever would crash it, loop, print its banner, or read otherwise than YAML means
   is refused here, in one line. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <ctype.h>
#include <yaml.h>
#include "options_files.h"

#define PETSC_MAX_PREFIXES 25 /* MAXPREFIXES in PETSc 3.18's src/sys/objects/options.c */
/* Far above a real options file (tens of keys, a few anchors), far below what takes libyaml
   or PETSc seconds: libyaml looks each anchor and alias up among all anchors of the document,
   and PETSc sets an option for every copy an alias or merge key makes. */
#define MAX_ANCHORS  1000
#define MAX_ALIASES  10000
#define MAX_EXPANDED 100000 /* keys and values, once aliases and merge keys are expanded */
#define MAX_OPEN     (2 * PETSC_MAX_PREFIXES + 8)

#define STR(node)  ((const char *)(node)->data.scalar.value)
#define LINE(node) ((int)(node)->start_mark.line + 1)
#define MAP(node)  ((node)->data.mapping.pairs)
#define SEQ(node)  ((node)->data.sequence.items)

static const char *const include_why = "'!include' is not followed: PETSc opens its file relative to the working "
                                       "directory, not to this file; give that file with -options_file";

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

static int ParseFailed(Check *check, const char path[], yaml_parser_t *parser, const char *text)
{
  const size_t line = parser->problem_mark.line;

  if (parser->error == YAML_COMPOSER_ERROR && parser->context) /* "found duplicate anchor; first occurrence" */
    return CheckFail(check, "options file %s line %zu: not valid YAML: %s on line %zu, %s here", path, line + 1,
                     parser->context, parser->context_mark.line + 1, parser->problem ? parser->problem : "another");
  return CheckFail(check, "options file %s line %zu: not valid YAML: %s%s%s%s", path, line + 1,
                   parser->problem ? parser->problem : "parse error", parser->context ? " " : "",
                   parser->context ? parser->context : "", TabHint(text, line));
}

typedef struct {
  char *anchor;
  int   mapping, line, expect_key, redefined;
  char  key[64]; /* the last key of an open mapping */
} Open;

/* The events, before libyaml builds a document from them (its work grows with the square of
   the nesting and of the anchors): the nesting PETSc takes, the anchors, and an alias inside
   its own anchor's node, a loop that PETSc follows until its stack overflows. */
static int CheckEvents(Check *check, const char path[], const char *text, size_t n)
{
  yaml_parser_t parser;
  yaml_event_t  event;
  Open          open[MAX_OPEN];
  int           depth = 0, mappings = 0, anchors = 0, aliases = 0, failed = 0, done = 0;

  yaml_parser_initialize(&parser);
  yaml_parser_set_input_string(&parser, (const unsigned char *)text, n);
  while (!failed && !done) {
    const char *anchor = NULL, *key = "";
    int         line, is_key        = 0;
    if (!yaml_parser_parse(&parser, &event)) {
      failed = ParseFailed(check, path, &parser, text);
      break;
    }
    line = (int)event.start_mark.line + 1;
    if (event.type == YAML_STREAM_END_EVENT) done = 1;
    if (event.type == YAML_DOCUMENT_START_EVENT) anchors = aliases = 0; /* libyaml's are per document */
    if (event.type == YAML_SCALAR_EVENT) anchor = (const char *)event.data.scalar.anchor;
    if (event.type == YAML_SEQUENCE_START_EVENT) anchor = (const char *)event.data.sequence_start.anchor;
    if (event.type == YAML_MAPPING_START_EVENT) anchor = (const char *)event.data.mapping_start.anchor;
    if (depth && (event.type == YAML_SCALAR_EVENT || event.type == YAML_ALIAS_EVENT ||
                  event.type == YAML_SEQUENCE_START_EVENT || event.type == YAML_MAPPING_START_EVENT)) {
      Open *parent = &open[depth - 1];
      if (parent->mapping) {
        is_key             = parent->expect_key;
        parent->expect_key = !is_key;
      }
      if (is_key && event.type == YAML_SCALAR_EVENT)
        snprintf(parent->key, sizeof(parent->key), "%s", (const char *)event.data.scalar.value);
      key = parent->mapping ? parent->key : depth > 1 ? open[depth - 2].key : "";
    }
    if (anchor) {
      if (++anchors > MAX_ANCHORS)
        failed = CheckFail(check, "options file %s line %d: more than %d anchors (&name) in one document", path, line,
                           MAX_ANCHORS);
      for (int d = 0; d < depth; ++d)
        if (open[d].anchor && !strcmp(open[d].anchor, anchor)) open[d].redefined = 1;
    }
    if (event.type == YAML_ALIAS_EVENT) {
      const char *name = (const char *)event.data.alias.anchor;
      if (++aliases > MAX_ALIASES)
        failed = CheckFail(check, "options file %s line %d: more than %d aliases (*name) in one document", path, line,
                           MAX_ALIASES);
      for (int d = 0; d < depth && !failed; ++d)
        if (open[d].anchor && !open[d].redefined && !strcmp(open[d].anchor, name))
          failed = CheckFail(check,
                             "options file %s line %d: alias *%s refers to its own anchor: the %s of line %d holds it "
                             "(a loop)",
                             path, line, name, open[d].mapping ? "mapping" : "list", open[d].line);
    }
    if (event.type == YAML_SEQUENCE_START_EVENT && depth && !open[depth - 1].mapping)
      failed = CheckFail(check, "options file %s line %d: a list inside a list; expected values or mappings", path,
                         line);
    if (event.type == YAML_MAPPING_START_EVENT && mappings == PETSC_MAX_PREFIXES + 1)
      failed = CheckFail(check,
                         "options file %s line %d: key '%s' opens a mapping %d deep below the top; PETSc takes at most "
                         "%d",
                         path, line, key, PETSC_MAX_PREFIXES + 1, PETSC_MAX_PREFIXES);
    if (!failed && (event.type == YAML_SEQUENCE_START_EVENT || event.type == YAML_MAPPING_START_EVENT)) {
      /* with lists in lists refused and mappings bounded, MAX_OPEN is never reached */
      Open *o = &open[depth++];
      memset(o, 0, sizeof(*o));
      o->anchor     = anchor ? strdup(anchor) : NULL;
      o->mapping    = event.type == YAML_MAPPING_START_EVENT;
      o->expect_key = 1;
      o->line       = line;
      mappings += o->mapping;
    }
    if (event.type == YAML_SEQUENCE_END_EVENT || event.type == YAML_MAPPING_END_EVENT) {
      free(open[--depth].anchor);
      mappings -= open[depth].mapping;
    }
    yaml_event_delete(&event);
  }
  while (depth) free(open[--depth].anchor);
  yaml_parser_delete(&parser);
  return failed;
}

typedef struct {
  Check           *check;
  const char      *path;
  yaml_document_t *doc;
  unsigned char   *checked; /* per node: its shape was checked */
  long             work;    /* keys and values visited, expanded */
  size_t           bytes;
  char             prefix[PETSC_MAX_OPTION_NAME];
  size_t           prefix_length;
  int              depth;
} Reading;

static yaml_node_t *Node(Reading *r, yaml_node_item_t index)
{
  return yaml_document_get_node(r->doc, index);
}

static int IsInclude(const yaml_node_t *node)
{
  const char  *tag = (const char *)node->tag;
  const size_t n   = tag ? strlen(tag) : 0;
  return n >= 8 && !strcmp(tag + n - 8, "!include");
}

static int IsMerge(const char key[])
{
  return !strcmp(key, "<<");
}

static int IsSkipped(const char key[])
{
  return !strncmp(key, "$$", 2);
}

/* PETSc takes a prefix that starts with a letter, or below the top with a digit */
static int IsName(const char key[], int top)
{
  if (!(top ? isalpha((unsigned char)key[0]) : isalnum((unsigned char)key[0]))) return 0;
  for (const char *c = key; *c; ++c)
    if (!isalnum((unsigned char)*c) && *c != '_') return 0;
  return 1;
}

static const char *Kind(const yaml_node_t *node)
{
  return node->type == YAML_MAPPING_NODE ? "mapping" : node->type == YAML_SEQUENCE_NODE ? "list" : "single value";
}

typedef struct {
  const char *key;
  int         index, line;
} Key;

static int CompareKeys(const void *a, const void *b)
{
  const Key *x = a, *y = b;
  const int  c = strcmp(x->key, y->key);
  return c ? c : x->index - y->index;
}

/* YAML keeps the last of two equal keys without a word: one of them is a mistake. Sorted,
   not pairwise: a mapping may have a million keys. */
static int RepeatedKey(Reading *r, yaml_node_t *map)
{
  const int n     = (int)(MAP(map).top - MAP(map).start);
  Key      *keys  = malloc((size_t)(n ? n : 1) * sizeof(*keys));
  int       found = -1, first = -1;

  for (int i = 0; i < n; ++i) {
    yaml_node_t *key = Node(r, MAP(map).start[i].key);
    keys[i]          = (Key){STR(key), i, LINE(key)};
  }
  qsort(keys, (size_t)n, sizeof(*keys), CompareKeys);
  for (int i = 1; i < n; ++i)
    if (!strcmp(keys[i].key, keys[i - 1].key) && (found < 0 || keys[i].index < keys[found].index)) {
      found = i;
      for (first = i - 1; first > 0 && !strcmp(keys[first - 1].key, keys[i].key); --first) continue;
    }
  if (found >= 0)
    CheckFail(r->check, "options file %s line %d: key '%s' given again (first on line %d)", r->path, keys[found].line,
              keys[found].key, keys[first].line);
  free(keys);
  return found >= 0;
}

/* A mapping's merge key, if it has one */
static yaml_node_pair_t *MergePair(Reading *r, yaml_node_t *map)
{
  for (yaml_node_pair_t *pair = MAP(map).start; pair < MAP(map).top; ++pair)
    if (IsMerge(STR(Node(r, pair->key)))) return pair;
  return NULL;
}

/* The value a mapping gives key, its own or through its merge key (the mapping is checked) */
static int MergedValue(Reading *r, yaml_node_t *map, const char key[], yaml_node_t **value)
{
  yaml_node_pair_t *merge;

  for (yaml_node_pair_t *pair = MAP(map).start; pair < MAP(map).top; ++pair) {
    const char *name = STR(Node(r, pair->key));
    if (++r->work > MAX_EXPANDED)
      return CheckFail(r->check,
                       "options file %s line %d: more than %d keys and values once its aliases and merge keys are "
                       "expanded",
                       r->path, LINE(Node(r, pair->key)), MAX_EXPANDED);
    if (!strcmp(name, key)) {
      *value = Node(r, pair->value);
      return 0;
    }
  }
  merge = MergePair(r, map);
  return merge ? MergedValue(r, Node(r, merge->value), key, value) : 0;
}

static int CheckShape(Reading *r, yaml_node_t *node, int top);

static int CheckMappingShape(Reading *r, yaml_node_t *map, int top)
{
  yaml_node_t *merged = NULL, *first = NULL; /* the first key that gives options */

  for (yaml_node_pair_t *pair = MAP(map).start; pair < MAP(map).top; ++pair) {
    yaml_node_t *key = Node(r, pair->key);
    if (!key || key->type != YAML_SCALAR_NODE)
      return CheckFail(r->check, "options file %s line %d: expected a name as the key, found a %s", r->path,
                       LINE(key ? key : map), key ? Kind(key) : "mapping");
  }
  if (RepeatedKey(r, map)) return 1;
  for (yaml_node_pair_t *pair = MAP(map).start; pair < MAP(map).top; ++pair) {
    yaml_node_t *key = Node(r, pair->key), *value = Node(r, pair->value);
    const char  *name = STR(key);
    if (IsMerge(name)) {
      /* PETSc sets a mapping's keys in order: a key before the merge would lose to it */
      if (first)
        return CheckFail(r->check,
                         "options file %s line %d: the merge key '<<' comes after key '%s'; PETSc would let the merged "
                         "values replace the keys before it, YAML the other way round: put '<<' first",
                         r->path, LINE(key), STR(first));
      if (value->type != YAML_MAPPING_NODE)
        return CheckFail(r->check,
                         "options file %s line %d: the merge key '<<' takes one mapping (*name of one), found a %s%s",
                         r->path, LINE(key), Kind(value),
                         value->type == YAML_SEQUENCE_NODE ? " (PETSc lets the last of a list win, YAML the first)"
                                                           : "");
      merged = value;
    } else if (IsSkipped(name)) {
      if (IsInclude(value))
        return CheckFail(r->check, "options file %s line %d: %s", r->path, LINE(value), include_why);
      continue; /* PETSc reads nothing of it: a place to define anchors */
    } else if (!IsName(name, top))
      return CheckFail(r->check,
                       "options file %s line %d: key '%.40s' is not an option name (expected letters, digits and _, "
                       "starting with a letter%s)",
                       r->path, LINE(key), name, top ? "" : " or digit");
    else if (top && !strcmp(name, "options_file"))
      return CheckFail(r->check,
                       "options file %s line %d: a YAML file cannot include another (PETSc's YAML reader does not "
                       "follow options_file); give -options_file on the command line",
                       r->path, LINE(key));
    else {
      /* YAML replaces a merged value whole, PETSc only the options this key sets */
      yaml_node_t *before = NULL;
      if (!first) first = key;
      if (merged && MergedValue(r, merged, name, &before)) return 1;
      if (before && (before->type != YAML_SCALAR_NODE || value->type != YAML_SCALAR_NODE))
        return CheckFail(r->check,
                         "options file %s line %d: key '%s' replaces the %s that the merge key '<<' gives it (line "
                         "%d): YAML drops that %s, PETSc would keep its options; give '%s' in one place",
                         r->path, LINE(key), name, Kind(before), LINE(before), Kind(before), name);
    }
    if (CheckShape(r, value, 0)) return 1;
  }
  return 0;
}

static int CheckListShape(Reading *r, yaml_node_t *list)
{
  for (yaml_node_item_t *item = SEQ(list).start; item < SEQ(list).top; ++item) {
    yaml_node_t *element = Node(r, *item);
    if (element->type == YAML_SEQUENCE_NODE) /* through an alias: the events saw none */
      return CheckFail(r->check, "options file %s line %d: a list inside a list; expected values or mappings", r->path,
                       LINE(element));
    if (element->type == YAML_MAPPING_NODE) {
      yaml_node_t *key = MAP(element).top > MAP(element).start ? Node(r, MAP(element).start->key) : NULL;
      if (MAP(element).top - MAP(element).start > 1)
        return CheckFail(r->check,
                         "options file %s line %d: a mapping in a list holds one key: value (PETSc's rule), found %d",
                         r->path, LINE(element), (int)(MAP(element).top - MAP(element).start));
      if (key && key->type == YAML_SCALAR_NODE && IsMerge(STR(key)))
        return CheckFail(r->check, "options file %s line %d: PETSc takes no merge key '<<' in a list", r->path,
                         LINE(key));
      if (key && key->type == YAML_SCALAR_NODE && IsSkipped(STR(key))) continue;
    }
    if (CheckShape(r, element, 0)) return 1;
  }
  return 0;
}

/* Each node once: what PETSc's reader would refuse, or read otherwise than YAML */
static int CheckShape(Reading *r, yaml_node_t *node, int top)
{
  const long index = node - r->doc->nodes.start;

  if (r->checked[index]) return 0;
  r->checked[index] = 1;
  if (IsInclude(node)) return CheckFail(r->check, "options file %s line %d: %s", r->path, LINE(node), include_why);
  if (node->type == YAML_MAPPING_NODE) return CheckMappingShape(r, node, top);
  if (top)
    return CheckFail(r->check,
                     "options file %s line %d: expected a mapping of option names to values at the top, found "
                     "%s%.40s%s",
                     r->path, LINE(node), node->type == YAML_SEQUENCE_NODE ? "a list" : "the single value '",
                     node->type == YAML_SEQUENCE_NODE ? "" : STR(node), node->type == YAML_SEQUENCE_NODE ? "" : "'");
  if (node->type == YAML_SEQUENCE_NODE) return CheckListShape(r, node);
  return 0;
}

/* A prefix PETSc pushes, within its bounds */
static int Push(Reading *r, const char key[], int line)
{
  const size_t n = strlen(key);

  if (!r->depth && !isalpha((unsigned char)key[0])) /* a key merged into the top mapping */
    return CheckFail(r->check,
                     "options file %s line %d: key '%.40s' is not an option name at the top (expected a letter first)",
                     r->path, line, key);
  if (r->depth == PETSC_MAX_PREFIXES)
    return CheckFail(r->check,
                     "options file %s line %d: key '%s' opens a mapping %d deep below the top; PETSc takes at most %d",
                     r->path, line, key, PETSC_MAX_PREFIXES + 1, PETSC_MAX_PREFIXES);
  if (1 + r->prefix_length + n + 1 >= PETSC_MAX_OPTION_NAME)
    return CheckFail(r->check, "options file %s line %d: option names under key '%.40s...' pass PETSc's %d characters",
                     r->path, line, key, PETSC_MAX_OPTION_NAME - 1);
  snprintf(r->prefix + r->prefix_length, sizeof(r->prefix) - r->prefix_length, "%s_", key);
  r->prefix_length += n + 1;
  ++r->depth;
  return 0;
}

static void Pop(Reading *r, size_t length)
{
  r->prefix[r->prefix_length = length] = 0;
  --r->depth;
}

static int Set(Reading *r, const char key[], int line, long from, long to)
{
  char name[PETSC_MAX_OPTION_NAME];

  if (1 + r->prefix_length + strlen(key) >= PETSC_MAX_OPTION_NAME)
    return CheckFail(r->check, "options file %s line %d: option -%s%.40s... passes PETSc's %d characters", r->path,
                     line, r->prefix, key, PETSC_MAX_OPTION_NAME - 1);
  snprintf(name, sizeof(name), "%s%s", r->prefix, key);
  return CheckOption(r->check, r->path, name, line, 1, from, to);
}

static int Visit(Reading *r, yaml_node_t *node)
{
  if (++r->work > MAX_EXPANDED)
    return CheckFail(r->check,
                     "options file %s line %d: more than %d keys and values once its aliases and merge keys are "
                     "expanded",
                     r->path, LINE(node), MAX_EXPANDED);
  if (node->type == YAML_SCALAR_NODE && (r->bytes += node->data.scalar.length) > MAX_FILE_BYTES)
    return CheckFail(r->check,
                     "options file %s line %d: more than %d MiB of keys and values once its aliases are expanded",
                     r->path, LINE(node), MAX_FILE_BYTES >> 20);
  return 0;
}

/* The options PETSc sets from a mapping, in its order, aliases and merge keys expanded */
static int Expand(Reading *r, yaml_node_t *map)
{
  long from = 0, to = 0; /* when the merge key set its options */

  for (yaml_node_pair_t *pair = MAP(map).start; pair < MAP(map).top; ++pair) {
    yaml_node_t *key = Node(r, pair->key), *value = Node(r, pair->value);
    const char  *name   = STR(key);
    const size_t length = r->prefix_length;
    if (IsSkipped(name)) continue;
    if (Visit(r, key) || Visit(r, value)) return 1;
    if (IsMerge(name)) {
      from = r->check->time;
      if (Expand(r, value)) return 1;
      to = r->check->time;
    } else if (value->type == YAML_MAPPING_NODE) {
      if (Push(r, name, LINE(key)) || Expand(r, value)) return 1;
      Pop(r, length);
    } else {
      for (yaml_node_item_t *item = value->type == YAML_SEQUENCE_NODE ? SEQ(value).start : NULL;
           item && item < SEQ(value).top; ++item) {
        yaml_node_t *element = Node(r, *item);
        if (Visit(r, element)) return 1;
        if (element->type != YAML_MAPPING_NODE ||
            (MAP(element).top > MAP(element).start && IsSkipped(STR(Node(r, MAP(element).start->key)))))
          continue;
        if (Push(r, name, LINE(element)) || Expand(r, element)) return 1;
        Pop(r, length);
      }
      if (Set(r, name, LINE(key), from, to)) return 1;
    }
  }
  return 0;
}

static int CheckDocument(Check *check, const char path[], yaml_document_t *doc, yaml_node_t *root)
{
  Reading r = {.check = check, .path = path, .doc = doc};
  int     failed;

  r.checked = calloc((size_t)(doc->nodes.top - doc->nodes.start), 1);
  failed    = CheckShape(&r, root, 1) || Expand(&r, root);
  free(r.checked);
  return failed;
}

int CheckYAML(Check *check, const char path[], const char *text, size_t n)
{
  yaml_parser_t   parser;
  yaml_document_t doc;
  int             failed = 0, documents = 0;

  if (CheckEvents(check, path, text, n)) return 1;
  yaml_parser_initialize(&parser);
  yaml_parser_set_input_string(&parser, (const unsigned char *)text, n);
  while (!failed) {
    yaml_node_t *root;
    if (!yaml_parser_load(&parser, &doc)) {
      failed = ParseFailed(check, path, &parser, text);
      break;
    }
    if (!(root = yaml_document_get_root_node(&doc))) {
      yaml_document_delete(&doc);
      break;
    }
    /* PETSc skips an empty document and reads the ones after it */
    if (root->type != YAML_SCALAR_NODE || STR(root)[0]) {
      ++documents;
      failed = CheckDocument(check, path, &doc, root);
    }
    yaml_document_delete(&doc);
  }
  yaml_parser_delete(&parser);
  if (!failed && !documents)
    failed = CheckFail(check, "options file %s: no options in it (an empty YAML document)", path);
  return failed;
}
