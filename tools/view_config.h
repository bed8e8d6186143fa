/* view_config.h - the viewer's tuning saved into a config file as a person would edit it: only
 * the values changed since the tuning started (or was last saved) are written, each in place of
 * the number already in the file, or added to its object when the file does not have it (the
 * object made when missing); every other character of the file stays as it was (its layout,
 * its order, its "extends"). The result is checked by loading it as a config before it replaces
 * the file (through a temporary file in the same folder and a rename). */
#ifndef MM_TOOLS_VIEW_CONFIG_H
#define MM_TOOLS_VIEW_CONFIG_H

#include <stddef.h>

#include <mm/view.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Sets value_text (a JSON value: a number, true, false) at path in the JSON object text: path is
 * keys separated by '.', where a key "bones[NAME]" is the entry of the array "bones" whose "name"
 * is NAME. Returns a new text (malloc'd; the caller frees it), or NULL with a message in why (the
 * text is not an object, a path's array or entry is missing, out of memory). */
char *view_config_set(const char *text, const char *path, const char *value_text, char *why, size_t why_size);

/* Writes t's changed values (and the distance matching and warping switches, when changed) into
 * the config at path, then marks them saved. Returns the number of values written (0: nothing
 * changed, the file is left alone), or -1 with a message in why (the file is left alone). */
int view_config_save(const char *path, mm_view_tuning *t, char *why, size_t why_size);

#ifdef __cplusplus
}
#endif

#endif /* MM_TOOLS_VIEW_CONFIG_H */
