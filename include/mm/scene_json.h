/* mm/scene_json.h - scenes as JSON files (in the mm_build library, which uses cJSON).
 *
 *   {"ground": 0.0,
 *    "boxes": [{"position": [0, 0, 3], "size": [4, 1, 0.4], "yaw": 90}]}
 *
 * "ground" (metres, default 0) and "boxes" (default []) are optional. Each box needs "position",
 * the centre of its BOTTOM face in metres (a box standing on the ground has y == ground), and
 * "size", its full extents along its own x, y, z in metres (each >= 0); "yaw" is in DEGREES
 * about +Y (default 0; converted to radians in mm_scene). At most MM_SCENE_MAX_BOXES boxes; every
 * number finite and within MM_SCENE_MAX_EXTENT. Unknown fields are errors; errors name the file
 * (err->file) and the field path, e.g. "boxes[2].size[1] must not be negative". The format is
 * described in docs/scene.md.
 *
 * Terrain (docs/scene.md, "Terrain"): "ramps" and "stairs" (arrays of {"position", "size", "yaw"},
 * stairs with "steps") and "field" ({"origin", "spacing", "columns", "rows", "heights"}, or
 * {"origin", "spacing", "image": "map.pgm", "height_scale"} with a PGM height map relative to the
 * scene file's folder).
 *
 * Functions: mm_scene_parse_json mm_scene_load_json mm_scene_write_json
 */
#ifndef MM_SCENE_JSON_H
#define MM_SCENE_JSON_H

#include <stddef.h>
#include <stdio.h>

#include "result.h"
#include "scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Parses JSON text (size bytes; need not be zero-terminated) into out; name is used in errors. */
mm_result mm_scene_parse_json(const char *text, size_t size, const char *name, mm_scene *out, mm_error *err);
/* Reads and parses a scene file. */
mm_result mm_scene_load_json(const char *path, mm_scene *out, mm_error *err);
/* Writes the scene in the same form (yaw in degrees; numbers in the C locale, precise enough
 * that reading it back gives the same floats). */
mm_result mm_scene_write_json(const mm_scene *scene, FILE *out);

#ifdef __cplusplus
}
#endif

#endif /* MM_SCENE_JSON_H */
