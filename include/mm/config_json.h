/* mm/config_json.h - database configs as JSON files (the mm_build library, which uses cJSON).
 *
 * The format is documented field by field in docs/config.md, generated from the same table that
 * `mm config explain` prints (mm_config_field_docs). Unknown fields are errors (a typo must not
 * silently fall back to a default). Errors name the file and the field path, e.g.
 * "lafan1.json: clips[2].ranges[0]: [900, 100) is empty".
 *
 * Paths of clip files are resolved (mm_config_resolve_path): absolute paths as they are;
 * relative ones against the config file's folder, then cfg->data_dir (if set), then $MM_DATA_DIR.
 *
 * Functions: mm_config_parse_json mm_config_load_json mm_config_field_docs
 *            mm_config_resolve_path mm_config_import_takes mm_config_load_sources mm_config_free_sources
 *            mm_config_save_clip_tags mm_config_save_clip mm_config_save_json
 */
#ifndef MM_CONFIG_JSON_H
#define MM_CONFIG_JSON_H

#include <stddef.h>

#include "clip.h"
#include "config.h"
#include "import.h"
#include "database.h"
#include "result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Parses JSON text into cfg (defaults first, then the fields present). name is used in errors
 * and base_dir for relative paths (may be NULL). */
mm_result mm_config_parse_json(const char *text, size_t size, const char *name, const char *base_dir,
                               mm_config *cfg, mm_error *err);
/* Reads and parses a config file; base_dir is the file's folder. out_text (may be NULL)
 * receives the file's text (malloc'd, zero-terminated) for embedding in a database. */
mm_result mm_config_load_json(const char *path, mm_config *cfg, char **out_text, mm_error *err);

typedef struct mm_config_field_doc {
    const char *path;     /* "features.bones[].position_weight" */
    const char *type;     /* "number", "string", "bool", "[number]", ... */
    const char *unit;     /* "s", "m", "m/s", "" */
    const char *fallback; /* default value as text */
    const char *help;     /* meaning, one paragraph */
} mm_config_field_doc;

/* The documentation of every field, in file order; *count receives the number. */
const mm_config_field_doc *mm_config_field_docs(int *count);

/* Resolves a clip's file path into out (size bytes). Returns MM_ERR_NOT_FOUND (err names the
 * places looked at) when no file exists there. */
mm_result mm_config_resolve_path(const mm_config *cfg, const char *file, char *out, size_t size,
                                 mm_error *err);

/* Imports every take of the file at path as the build reads it (mm_import_clips): turned from the
 * config's axes to +Y up, +Z forward (mm_axes_turn, mm_clip_turn), then in metres by cfg->scale
 * (0: detected from the body's height along +Y after the turn). err names the file. */
mm_result mm_config_import_takes(const mm_config *cfg, const char *path, mm_clip_list *out, mm_error *err);

/* Loads the source of every config clip through mm_config_import_takes (BVH with mm's reader, FBX,
 * glTF and Collada through assimp when built with it; the clip's take, or the file's first). A file
 * and take used by several clips is read once. *out_clips is an array of cfg->clip_count clips. */
mm_result mm_config_load_sources(const mm_config *cfg, mm_clip **out_clips, mm_error *err);
void mm_config_free_sources(const mm_config *cfg, mm_clip *clips);

/* Saving tuned values back into a config file. The file is read and changed in place: every
 * other field keeps its value and order (the file is re-printed with two-space indentation,
 * arrays of numbers on one line, numbers in their shortest form), the result is checked as a
 * config, and written atomically (a temporary file and a rename: a failure leaves the file as it
 * was). Errors name the file (err->file) and the field or clip. */

/* Replaces the tag ranges [begin, end] (seconds from the start of the source file) of tag in the
 * config clip named clip_name (its name as the config gives it, or the one derived from its file)
 * with ranges[0..range_count-1]; range_count 0 removes the tag from the clip. A tag not yet in
 * the top-level `tags` list is added to it. */
mm_result mm_config_save_clip_tags(const char *config_path, const char *clip_name, const char *tag,
                                   const float (*ranges)[2], int range_count, mm_error *err);

/* A tag range by name: [begin, end] seconds from the start of the source file (begin == end tags
 * the one frame at that time). */
typedef struct mm_config_named_range {
    char tag[MM_TAG_NAME_MAX];
    float begin, end;
} mm_config_named_range;

/* A clip as mm_config_save_clip writes it: frame ranges of file, either the list `ranges`
 * (range_count of them) or, when range_count is 0, the one range [begin, end). */
typedef struct mm_config_saved_clip {
    const char *name;
    const char *file; /* as the config should name it (e.g. "lafan1/obstacles1_subject1.bvh") */
    int begin, end;   /* source frames, half-open */
    const int (*ranges)[2];
    int range_count;
    mm_clip_type type;
    bool mirror;
    const mm_config_named_range *tags;
    int tag_count;
} mm_config_saved_clip;

/* Adds a clip to the config file (at the end of its own `clips`), or replaces the clip of that
 * name, so that writing the same clips again changes nothing; tag names not yet listed are added
 * to `tags`. A name belonging to a clip of the config this one extends is MM_ERR_DUPLICATE_NAME. */
mm_result mm_config_save_clip(const char *config_path, const mm_config_saved_clip *clip, mm_error *err);

/* Writes cfg as a new config file at path (replacing any file there, atomically): interval,
 * scale, roles, features.bones and clips always; every other field where it differs from
 * mm_config_defaults (the runtime object: the fields set). Reading the file back gives cfg (its
 * clips, tags and values, floats in their shortest form). cfg is validated first
 * (mm_config_validate). */
mm_result mm_config_save_json(const char *path, const mm_config *cfg, mm_error *err);

#ifdef __cplusplus
}
#endif

#endif /* MM_CONFIG_JSON_H */
