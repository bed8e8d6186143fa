/* Desired paths in JSON (cJSON; mm/path_json.h). */
#include <mm/path_json.h>

#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "io/file.h"
#include "io/json_parse.h"

static mm_result pair(const cJSON *v, const char *what, int i, float out[2], mm_error *err)
{
    if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != 2)
        return mm_error_set(err, MM_ERR_SYNTAX, 0, 0, "points[%d].%s must be [x, z]", i, what);
    for (int k = 0; k < 2; ++k) {
        const cJSON *e = cJSON_GetArrayItem(v, k);
        if (!cJSON_IsNumber(e) || !isfinite(e->valuedouble) || fabs(e->valuedouble) > 1e7)
            return mm_error_set(err, MM_ERR_BAD_NUMBER, 0, 0, "points[%d].%s must hold two finite numbers", i,
                                what);
        out[k] = (float)e->valuedouble;
    }
    return MM_OK;
}

static mm_result parse_point(const cJSON *j, int i, mm_path_point *p, mm_error *err)
{
    static const char *const known[] = {"t", "position", "facing"};
    if (!cJSON_IsObject(j)) return mm_error_set(err, MM_ERR_SYNTAX, 0, 0, "points[%d] must be an object", i);
    for (const cJSON *it = j->child; it; it = it->next) {
        int ok = 0;
        for (size_t n = 0; n < sizeof known / sizeof known[0]; ++n) ok |= strcmp(it->string, known[n]) == 0;
        if (!ok)
            return mm_error_set(err, MM_ERR_UNKNOWN_KEYWORD, 0, 0, "points[%d].%s: unknown field", i,
                                it->string);
    }
    const cJSON *t = cJSON_GetObjectItemCaseSensitive(j, "t");
    if (!t) return mm_error_set(err, MM_ERR_SYNTAX, 0, 0, "points[%d].t is missing", i);
    if (!cJSON_IsNumber(t) || !isfinite(t->valuedouble) || fabs(t->valuedouble) > 1e7)
        return mm_error_set(err, MM_ERR_BAD_NUMBER, 0, 0, "points[%d].t must be a finite number", i);
    p->t = (float)t->valuedouble;
    const cJSON *position = cJSON_GetObjectItemCaseSensitive(j, "position");
    if (!position) return mm_error_set(err, MM_ERR_SYNTAX, 0, 0, "points[%d].position is missing", i);
    mm_result r = pair(position, "position", i, p->position, err);
    if (r != MM_OK) return r;
    const cJSON *facing = cJSON_GetObjectItemCaseSensitive(j, "facing");
    if (facing) {
        if ((r = pair(facing, "facing", i, p->facing, err)) != MM_OK) return r;
        float len = sqrtf(p->facing[0] * p->facing[0] + p->facing[1] * p->facing[1]);
        if (!(len > 1e-6f))
            return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0, "points[%d].facing must not be zero", i);
        p->facing[0] /= len;
        p->facing[1] /= len;
    }
    return MM_OK;
}

mm_result mm_path_parse_json(const char *text, size_t size, const char *name, mm_path *out, mm_error *err)
{
    if (!out) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no path given");
    memset(out, 0, sizeof *out);
    mm__error_set_file(err, name ? name : "<path>");
    if (!text || size == 0) return mm_error_set(err, MM_ERR_UNEXPECTED_EOF, 0, 0, "the path is empty");
    cJSON *root;
    mm_result r = mm__json_parse(text, size, &root, err);
    if (r != MM_OK) return r;
    const cJSON *points = cJSON_IsObject(root) ? cJSON_GetObjectItemCaseSensitive(root, "points") : NULL;
    if (!cJSON_IsObject(root))
        r = mm_error_set(err, MM_ERR_SYNTAX, 0, 0, "a path is an object {\"points\": [...]}");
    else if (!points || !cJSON_IsArray(points) || cJSON_GetArraySize(points) < 1)
        r = mm_error_set(err, MM_ERR_SYNTAX, 0, 0, "points: missing, empty, or not an array");
    for (const cJSON *it = root ? root->child : NULL; r == MM_OK && it; it = it->next)
        if (strcmp(it->string, "points") != 0)
            r = mm_error_set(err, MM_ERR_UNKNOWN_KEYWORD, 0, 0, "%s: unknown field", it->string);
    if (r == MM_OK) {
        int n = cJSON_GetArraySize(points);
        if ((r = mm_path_init(out, n, NULL)) != MM_OK)
            r = mm_error_set(err, r, 0, 0, "cannot hold %d points", n);
        int i = 0;
        for (const cJSON *p = points->child; r == MM_OK && p; p = p->next, ++i)
            r = parse_point(p, i, &out->points[i], err);
    }
    cJSON_Delete(root);
    if (r == MM_OK) r = mm_path_validate(out, err);
    if (r != MM_OK) mm_path_free(out);
    return r;
}

mm_result mm_path_load_json(const char *path, mm_path *out, mm_error *err)
{
    if (out) memset(out, 0, sizeof *out);
    char *text = NULL;
    size_t size = 0;
    mm_result r = mm__read_file(path, NULL, &text, &size, err);
    if (r != MM_OK) return r;
    r = mm_path_parse_json(text, size, path, out, err);
    free(text);
    return r;
}
