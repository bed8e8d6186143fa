/* mm/path_json.h - desired paths (mm/drive.h) as JSON files (in the mm_build library, which uses
 * cJSON).
 *
 *   {"points": [{"t": 0.0, "position": [0, 0], "facing": [0, 1]},
 *               {"t": 4.0, "position": [0, 5]},
 *               {"t": 8.0, "position": [5, 5], "facing": [1, 0]}]}
 *
 * Seconds, metres, the world's ground plane (x, z); linear between points. "t" and "position" are
 * required, times increasing; "facing" is a direction of any length but zero, optional (without
 * it: along the path). Unknown fields are errors; errors name the file and the point, e.g.
 * "path.json: points[2].position".
 *
 * Functions: mm_path_parse_json mm_path_load_json
 */
#ifndef MM_PATH_JSON_H
#define MM_PATH_JSON_H

#include <stddef.h>

#include "drive.h"
#include "result.h"

#ifdef __cplusplus
extern "C" {
#endif

mm_result mm_path_parse_json(const char *text, size_t size, const char *name, mm_path *out, mm_error *err);
mm_result mm_path_load_json(const char *path, mm_path *out, mm_error *err);

#ifdef __cplusplus
}
#endif

#endif /* MM_PATH_JSON_H */
