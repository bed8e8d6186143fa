/* json_parse.h (private) - JSON text to a cJSON tree for the JSON readers (configs, input
 * scripts, scenes), a syntax error naming its line and column. */
#ifndef MM_IO_JSON_PARSE_H
#define MM_IO_JSON_PARSE_H

#include <stddef.h>

#include <cjson/cJSON.h>

#include <mm/result.h>

/* *out receives the tree (the caller deletes it). Empty text: MM_ERR_UNEXPECTED_EOF; invalid
 * JSON: MM_ERR_SYNTAX at the line and column where parsing stopped. */
mm_result mm__json_parse(const char *text, size_t size, cJSON **out, mm_error *err);

#endif
