/* Editing a config file in place (private to the build library): the file read as a checked config
 * and as a JSON tree, values set in the tree, and the tree written back atomically after checking
 * it parses as a config. Used by src/io/config_save.c and src/tuning/. */
#ifndef MM_IO_CONFIG_DOC_H
#define MM_IO_CONFIG_DOC_H

#include <cjson/cJSON.h>
#include <stdbool.h>

#include <mm/config.h>

/* The config file: its text checked as a config (errors name the file, and the line for JSON
 * syntax), and its JSON tree. */
mm_result mm__config_doc_load(const char *path, mm_config *cfg, cJSON **out_root, mm_error *err);
/* Prints root, checks the result is a valid config and writes it atomically. Deletes root. */
mm_result mm__config_doc_save(const char *path, cJSON *root, mm_error *err);
/* Deletes root and cfg and reports running out of memory. */
mm_result mm__config_doc_no_memory(cJSON *root, mm_config *cfg, mm_error *err);
/* obj[key] set to a number (its shortest decimal form) or a bool, in place when the key exists.
 * 0: out of memory. */
int mm__json_set_number(cJSON *obj, const char *key, float value);
int mm__json_set_bool(cJSON *obj, const char *key, bool value);
/* obj[key] when it is an object; else a new object there (replacing what was). NULL: no memory. */
cJSON *mm__json_object_at(cJSON *obj, const char *key);

#endif
