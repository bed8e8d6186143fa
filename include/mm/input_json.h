/* mm/input_json.h - input scripts as JSON files (in the mm_build library, which uses cJSON).
 *
 *   {"keys": [{"t": 0.0, "stick": [0, 1], "gait": "walk"},
 *             {"t": 2.0, "stick": [1, 0], "gait": "run", "strafe": true, "facing": [0, 1]}]}
 *
 * "t" and "stick" are required; "gait" defaults to walk, "strafe" to false, "facing" is optional.
 * Unknown fields are errors; errors name the file and the key, e.g. "turn.json: keys[3].stick".
 *
 * Functions: mm_input_script_parse_json mm_input_script_load_json mm_input_script_write_json
 */
#ifndef MM_INPUT_JSON_H
#define MM_INPUT_JSON_H

#include <stddef.h>
#include <stdio.h>

#include "input.h"
#include "result.h"

#ifdef __cplusplus
extern "C" {
#endif

mm_result mm_input_script_parse_json(const char *text, size_t size, const char *name, mm_input_script *out,
                                     mm_error *err);
mm_result mm_input_script_load_json(const char *path, mm_input_script *out, mm_error *err);
/* Writes the script in the same form (numbers with %.9g in the C locale). */
mm_result mm_input_script_write_json(const mm_input_script *s, FILE *out);

#ifdef __cplusplus
}
#endif

#endif /* MM_INPUT_JSON_H */
