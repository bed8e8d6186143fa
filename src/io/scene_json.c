/* Scenes in JSON (cJSON). */
#include <mm/scene_json.h>

#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "io/json_parse.h"
#include "io/file.h"
#include "io/text.h"

#define FAIL(code, ...) mm_error_set(err, code, 0, 0, __VA_ARGS__)

static mm_result check_keys(const cJSON *obj, const char *where, const char *const *keys, size_t count,
                            mm_error *err)
{
    for (const cJSON *it = obj->child; it; it = it->next) {
        int ok = 0;
        for (size_t k = 0; k < count; ++k) ok |= strcmp(it->string, keys[k]) == 0;
        if (!ok)
            return FAIL(MM_ERR_UNKNOWN_KEYWORD, "%s%s%s: unknown field", where, where[0] ? "." : "",
                        it->string);
    }
    return MM_OK;
}

/* A finite number within MM_SCENE_MAX_EXTENT (limit) into *out. */
static mm_result number(const cJSON *v, const char *what, double limit, double *out, mm_error *err)
{
    if (!cJSON_IsNumber(v) || !isfinite(v->valuedouble))
        return FAIL(MM_ERR_BAD_NUMBER, "%s must be a finite number", what);
    if (fabs(v->valuedouble) > limit)
        return FAIL(MM_ERR_OUT_OF_RANGE, "%s is %g (at most %g in magnitude)", what, v->valuedouble, limit);
    *out = v->valuedouble;
    return MM_OK;
}

static mm_result vec3(const cJSON *v, const char *what, mm_vec3 *out, mm_error *err)
{
    if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != 3)
        return FAIL(MM_ERR_SYNTAX, "%s must be an array of 3 numbers", what);
    double x[3];
    char item[96];
    const cJSON *e = v->child;
    for (int i = 0; i < 3; ++i, e = e->next) {
        snprintf(item, sizeof item, "%s[%d]", what, i);
        mm_result r = number(e, item, MM_SCENE_MAX_EXTENT, &x[i], err);
        if (r != MM_OK) return r;
    }
    /* + 0: -0 reads as 0, as it is written */
    *out = mm_vec3_make((float)x[0] + 0.0f, (float)x[1] + 0.0f, (float)x[2] + 0.0f);
    return MM_OK;
}

static mm_result parse_box(const cJSON *j, int i, mm_scene *s, mm_error *err)
{
    static const char *const keys[] = {"position", "size", "yaw"};
    char where[64], what[96];
    snprintf(where, sizeof where, "boxes[%d]", i);
    if (!cJSON_IsObject(j)) return FAIL(MM_ERR_SYNTAX, "%s must be an object", where);
    mm_result r = check_keys(j, where, keys, 3, err);
    if (r != MM_OK) return r;
    mm_vec3 position, size;
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(j, "position");
    snprintf(what, sizeof what, "%s.position", where);
    if (!v) return FAIL(MM_ERR_SYNTAX, "%s is missing", what);
    if ((r = vec3(v, what, &position, err)) != MM_OK) return r;
    v = cJSON_GetObjectItemCaseSensitive(j, "size");
    snprintf(what, sizeof what, "%s.size", where);
    if (!v) return FAIL(MM_ERR_SYNTAX, "%s is missing", what);
    if ((r = vec3(v, what, &size, err)) != MM_OK) return r;
    const float sz[3] = {size.x, size.y, size.z};
    for (int k = 0; k < 3; ++k)
        if (sz[k] < 0.0f) return FAIL(MM_ERR_OUT_OF_RANGE, "%s.size[%d] must not be negative", where, k);
    double yaw = 0.0;
    v = cJSON_GetObjectItemCaseSensitive(j, "yaw");
    snprintf(what, sizeof what, "%s.yaw", where);
    if (v && (r = number(v, what, 36000.0, &yaw, err)) != MM_OK) return r;
    r = mm_scene_add_box(s, position, size, (float)(yaw * MM_DEG_TO_RAD) + 0.0f);
    if (r != MM_OK) return FAIL(r, "%s: %s", where, mm_result_str(r));
    return MM_OK;
}

mm_result mm_scene_parse_json(const char *text, size_t size, const char *name, mm_scene *out, mm_error *err)
{
    if (!out) return FAIL(MM_ERR_INVALID_ARGUMENT, "no scene given");
    mm_scene_init(out, 0.0f);
    mm__error_set_file(err, name ? name : "<scene>");
    if (!text || size == 0) return FAIL(MM_ERR_UNEXPECTED_EOF, "the scene is empty");
    cJSON *root;
    mm__json_where *where = NULL;
    mm_result parsed = mm__json_parse_where(text, size, NULL, &root, &where, err);
    if (parsed != MM_OK) return parsed;
    static const char *const keys[] = {"ground", "boxes"};
    mm_result r = MM_OK;
    if (!cJSON_IsObject(root))
        r = FAIL(MM_ERR_SYNTAX, "a scene is an object {\"ground\": 0, \"boxes\": [...]}");
    else
        r = check_keys(root, "", keys, 2, err);
    const cJSON *ground = r == MM_OK ? cJSON_GetObjectItemCaseSensitive(root, "ground") : NULL;
    if (ground) {
        double g = 0.0;
        r = number(ground, "ground", MM_SCENE_MAX_EXTENT, &g, err);
        out->ground = (float)g + 0.0f;
    }
    const cJSON *boxes = r == MM_OK ? cJSON_GetObjectItemCaseSensitive(root, "boxes") : NULL;
    if (boxes) {
        int n = cJSON_GetArraySize(boxes);
        if (!cJSON_IsArray(boxes))
            r = FAIL(MM_ERR_SYNTAX, "boxes must be an array of objects");
        else if (n > MM_SCENE_MAX_BOXES)
            r = FAIL(MM_ERR_LIMIT, "boxes: %d boxes (at most %d)", n, MM_SCENE_MAX_BOXES);
        int i = 0;
        for (const cJSON *b = boxes->child; r == MM_OK && b; b = b->next, ++i) r = parse_box(b, i, out, err);
    }
    /* a meaning error names a field path: its value's line and column are added */
    if (r != MM_OK) mm__json_locate_error(root, where, err);
    cJSON_Delete(root);
    mm__json_where_free(where);
    if (r != MM_OK) mm_scene_init(out, 0.0f);
    return r;
}

mm_result mm_scene_load_json(const char *path, mm_scene *out, mm_error *err)
{
    if (out) mm_scene_init(out, 0.0f);
    char *text = NULL;
    size_t size = 0;
    mm_result r = mm__read_file(path, NULL, &text, &size, err);
    if (r != MM_OK) return r;
    r = mm_scene_parse_json(text, size, path, out, err);
    free(text);
    return r;
}

mm_result mm_scene_write_json(const mm_scene *scene, FILE *out)
{
    if (!scene || !out || scene->box_count < 0 || scene->box_count > MM_SCENE_MAX_BOXES)
        return MM_ERR_INVALID_ARGUMENT;
    char v[7][64];
    mm__format_number(v[0], sizeof v[0], scene->ground, 9);
    fprintf(out, "{\"ground\": %s, \"boxes\": [", v[0]);
    for (int i = 0; i < scene->box_count; ++i) {
        const mm_scene_box *b = &scene->boxes[i];
        const float f[6] = {b->position.x, b->position.y, b->position.z, b->size.x, b->size.y, b->size.z};
        for (int k = 0; k < 6; ++k) mm__format_number(v[k], sizeof v[k], f[k], 9);
        /* degrees to 17 digits: converting back to radians gives the same float */
        mm__format_number(v[6], sizeof v[6], (double)b->yaw * MM_RAD_TO_DEG, 17);
        fprintf(out, "%s\n  {\"position\": [%s, %s, %s], \"size\": [%s, %s, %s], \"yaw\": %s}", i ? "," : "",
                v[0], v[1], v[2], v[3], v[4], v[5], v[6]);
    }
    fputs(scene->box_count ? "\n]}\n" : "]}\n", out);
    return ferror(out) ? MM_ERR_IO : MM_OK;
}
