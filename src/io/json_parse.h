/* json_parse.h (private) - strict JSON text to a cJSON tree for the JSON readers (configs, input
 * scripts, scenes): a syntax error, a key given twice in one object, or text after the value is
 * refused at its line and column. The readers' meaning errors (wrong type, out of range, unknown
 * field) name a field path; mm__json_where finds that path's line and column in the text, and the
 * text of a number as written. Everything is linear in the size of the text. */
#ifndef MM_IO_JSON_PARSE_H
#define MM_IO_JSON_PARSE_H

#include <stddef.h>

#include <cjson/cJSON.h>

#include <mm/result.h>

/* *out receives the tree (the caller deletes it). Empty text: MM_ERR_UNEXPECTED_EOF; invalid
 * JSON (RFC 8259 exactly: no leading +, leading zeros, bare dots, control characters in strings
 * or whitespace other than space, tab, CR and LF): MM_ERR_SYNTAX at the line and column where it
 * stops; a key given twice in one object: MM_ERR_DUPLICATE_NAME at the second, naming the first's
 * line; text after the value: MM_ERR_SYNTAX there. */
mm_result mm__json_parse(const char *text, size_t size, cJSON **out, mm_error *err);

/* Where each value of a parsed tree is in its text: what mm__json_parse_where records. A chain of
 * them (next) covers a tree merged from several files (a config and the ones it extends). */
typedef struct mm__json_where mm__json_where;

/* mm__json_parse that also records, when *where is given, each value's line and column (and a
 * copy of the text, for the numbers as written) under the name file; *where is NULL on failure
 * and is freed with mm__json_where_free. */
mm_result mm__json_parse_where(const char *text, size_t size, const char *file, cJSON **out,
                               mm__json_where **where, mm_error *err);
/* Appends tail to the chain head (either may be NULL); returns the chain. */
mm__json_where *mm__json_where_join(mm__json_where *head, mm__json_where *tail);
void mm__json_where_free(mm__json_where *where);

/* The line and column of node's value and the file it was read from; 0 when node is unknown. */
int mm__json_where_at(const mm__json_where *where, const cJSON *node, int *line, int *column,
                      const char **file);
/* The number node as written in its text (*length characters, not terminated); NULL if unknown. */
const char *mm__json_number_text(const mm__json_where *where, const cJSON *node, size_t *length);

/* The deepest node of root that the field path at the start of message leads to ("clips[3].name
 * is missing" -> clips[3]; "runtime.walk.side_speed: ..." -> that number); root itself when the
 * message starts with no path. */
const cJSON *mm__json_path_node(const cJSON *root, const char *message);

/* When err has no line yet: the line and column (and file) of the node its message's field path
 * leads to in root. Returns err->code. */
mm_result mm__json_locate_error(const cJSON *root, const mm__json_where *where, mm_error *err);

#endif
