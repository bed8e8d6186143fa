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

/* What boxes, ramps and stairs share, of the object `where`: position and size (metres, no size
 * negative) and yaw (degrees, 0 when left out). keys: the object's allowed keys. */
static mm_result parse_placement(const cJSON *j, const char *where, const char *const *keys, int key_count,
                                 mm_vec3 *position, mm_vec3 *size, double *yaw, mm_error *err)
{
    char what[96];
    if (!cJSON_IsObject(j)) return FAIL(MM_ERR_SYNTAX, "%s must be an object", where);
    mm_result r = check_keys(j, where, keys, key_count, err);
    if (r != MM_OK) return r;
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(j, "position");
    snprintf(what, sizeof what, "%s.position", where);
    if (!v) return FAIL(MM_ERR_SYNTAX, "%s is missing", what);
    if ((r = vec3(v, what, position, err)) != MM_OK) return r;
    v = cJSON_GetObjectItemCaseSensitive(j, "size");
    snprintf(what, sizeof what, "%s.size", where);
    if (!v) return FAIL(MM_ERR_SYNTAX, "%s is missing", what);
    if ((r = vec3(v, what, size, err)) != MM_OK) return r;
    const float sz[3] = {size->x, size->y, size->z};
    for (int k = 0; k < 3; ++k)
        if (sz[k] < 0.0f) return FAIL(MM_ERR_OUT_OF_RANGE, "%s.size[%d] must not be negative", where, k);
    *yaw = 0.0;
    v = cJSON_GetObjectItemCaseSensitive(j, "yaw");
    snprintf(what, sizeof what, "%s.yaw", where);
    if (v && (r = number(v, what, 36000.0, yaw, err)) != MM_OK) return r;
    return MM_OK;
}

static mm_result parse_box(const cJSON *j, int i, mm_scene *s, mm_error *err)
{
    static const char *const keys[] = {"position", "size", "yaw"};
    char where[64];
    snprintf(where, sizeof where, "boxes[%d]", i);
    mm_vec3 position, size;
    double yaw;
    mm_result r = parse_placement(j, where, keys, 3, &position, &size, &yaw, err);
    if (r != MM_OK) return r;
    r = mm_scene_add_box(s, position, size, (float)(yaw * MM_DEG_TO_RAD) + 0.0f);
    if (r != MM_OK) return FAIL(r, "%s: %s", where, mm_result_str(r));
    return MM_OK;
}

/* A ramp or a flight of stairs: position, size, yaw (degrees) and, for stairs, steps. */
static mm_result parse_terrain_solid(const cJSON *j, const char *list, int i, bool stairs, mm_scene *s,
                                     mm_error *err)
{
    static const char *const keys[] = {"position", "size", "yaw", "steps"};
    char where[64], what[96];
    snprintf(where, sizeof where, "%s[%d]", list, i);
    mm_vec3 position, size;
    double yaw, steps = 0.0;
    mm_result r = parse_placement(j, where, keys, stairs ? 4 : 3, &position, &size, &yaw, err);
    if (r != MM_OK) return r;
    if (!(size.z > 0.0f))
        return FAIL(MM_ERR_OUT_OF_RANGE, "%s.size[2] (its length) must be more than 0", where);
    if (stairs) {
        const cJSON *v = cJSON_GetObjectItemCaseSensitive(j, "steps");
        snprintf(what, sizeof what, "%s.steps", where);
        if (!v) return FAIL(MM_ERR_SYNTAX, "%s is missing", what);
        if ((r = number(v, what, MM_SCENE_MAX_STEPS, &steps, err)) != MM_OK) return r;
        if (steps < 1.0 || steps != floor(steps))
            return FAIL(MM_ERR_OUT_OF_RANGE, "%s must be a whole number from 1 to %d", what,
                        MM_SCENE_MAX_STEPS);
    }
    float radians = (float)(yaw * MM_DEG_TO_RAD) + 0.0f;
    r = stairs ? mm_scene_add_stairs(s, position, size, radians, (int)steps)
               : mm_scene_add_ramp(s, position, size, radians);
    if (r != MM_OK) return FAIL(r, "%s: %s", where, mm_result_str(r));
    return MM_OK;
}

/* The folder part of path (up to and with its last '/'), or "" (the current folder). */
static void folder_of(const char *path, char *out, size_t size)
{
    const char *slash = path ? strrchr(path, '/') : NULL;
    size_t n = slash ? (size_t)(slash - path + 1) : 0;
    if (n >= size) n = 0;
    memcpy(out, path, n);
    out[n] = 0;
}

/* Skips blanks and '#' comments in a PGM header. */
static size_t pgm_skip(const unsigned char *t, size_t n, size_t i)
{
    while (i < n) {
        if (t[i] == '#')
            while (i < n && t[i] != '\n') ++i;
        else if (t[i] == ' ' || t[i] == '\t' || t[i] == '\r' || t[i] == '\n')
            ++i;
        else
            break;
    }
    return i;
}

static bool pgm_int(const unsigned char *t, size_t n, size_t *i, long *out)
{
    *i = pgm_skip(t, n, *i);
    long v = 0;
    size_t start = *i;
    while (*i < n && t[*i] >= '0' && t[*i] <= '9' && v < 1000000) v = v * 10 + (t[(*i)++] - '0');
    *out = v;
    return *i > start;
}

/* A PGM image (P2 text or P5 binary, 8 or 16 bits) as heights: grey / maxval * scale, row 0 at
 * the field's origin.z. */
static mm_result load_pgm(const char *path, const char *what, float scale, float *heights, int *columns,
                          int *rows, mm_error *err)
{
    char *text = NULL;
    size_t size = 0;
    mm_error read_err;
    if (mm__read_file(path, NULL, &text, &size, &read_err) != MM_OK)
        return FAIL(MM_ERR_IO, "%s: cannot read the height map %s", what, path);
    const unsigned char *t = (const unsigned char *)text;
    mm_result r = MM_OK;
    long w = 0, h = 0, maxval = 0;
    size_t i = 2;
    bool binary = size > 2 && t[0] == 'P' && t[1] == '5', plain = size > 2 && t[0] == 'P' && t[1] == '2';
    if (!binary && !plain)
        r = FAIL(MM_ERR_SYNTAX, "%s: %s is not a PGM image (P2 or P5)", what, path);
    else if (!pgm_int(t, size, &i, &w) || !pgm_int(t, size, &i, &h) || !pgm_int(t, size, &i, &maxval) ||
             maxval < 1 || maxval > 65535)
        r = FAIL(MM_ERR_SYNTAX, "%s: %s has a bad PGM header", what, path);
    else if (w < 2 || h < 2)
        r = FAIL(MM_ERR_OUT_OF_RANGE, "%s: %s is %ldx%ld (at least 2x2)", what, path, w, h);
    else if (w * h > MM_SCENE_MAX_FIELD_SAMPLES)
        r = FAIL(MM_ERR_LIMIT, "%s: %s has %ld samples (at most %d)", what, path, w * h,
                 MM_SCENE_MAX_FIELD_SAMPLES);
    if (r == MM_OK) {
        int bytes = maxval > 255 ? 2 : 1;
        ++i; /* the one blank after maxval (P5) */
        for (long k = 0; r == MM_OK && k < w * h; ++k) {
            long v = 0;
            if (plain) {
                if (!pgm_int(t, size, &i, &v) || v > maxval)
                    r = FAIL(MM_ERR_SYNTAX, "%s: %s: sample %ld is missing or above maxval", what, path, k);
            } else if (i + (size_t)bytes > size) {
                r = FAIL(MM_ERR_UNEXPECTED_EOF, "%s: %s ends after %ld of %ld samples", what, path, k, w * h);
            } else {
                v = bytes == 2 ? (long)t[i] << 8 | t[i + 1] : t[i];
                i += (size_t)bytes;
            }
            heights[k] = (float)((double)v / (double)maxval * scale);
        }
    }
    free(text);
    *columns = (int)w;
    *rows = (int)h;
    return r;
}

/* The height field: origin, spacing, and heights given inline (columns, rows, heights) or as a PGM
 * image (image, height_scale). */
static mm_result parse_field(const cJSON *j, const char *name, mm_scene *s, mm_error *err)
{
    static const char *const keys[] = {"origin",  "spacing", "columns",     "rows",
                                       "heights", "image",   "height_scale"};
    static float heights[MM_SCENE_MAX_FIELD_SAMPLES]; /* large: kept off the stack */
    if (!cJSON_IsObject(j)) return FAIL(MM_ERR_SYNTAX, "field must be an object");
    mm_result r = check_keys(j, "field", keys, 7, err);
    if (r != MM_OK) return r;
    mm_vec3 origin = {0, 0, 0};
    double spacing = 0.0, columns = 0.0, rows = 0.0;
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(j, "origin");
    if (v && (r = vec3(v, "field.origin", &origin, err)) != MM_OK) return r;
    v = cJSON_GetObjectItemCaseSensitive(j, "spacing");
    if (!v) return FAIL(MM_ERR_SYNTAX, "field.spacing is missing");
    if ((r = number(v, "field.spacing", MM_SCENE_MAX_EXTENT, &spacing, err)) != MM_OK) return r;
    if (!(spacing > 0.0)) return FAIL(MM_ERR_OUT_OF_RANGE, "field.spacing must be more than 0");
    const cJSON *image = cJSON_GetObjectItemCaseSensitive(j, "image");
    const cJSON *list = cJSON_GetObjectItemCaseSensitive(j, "heights");
    int nc = 0, nr = 0;
    if (image) {
        if (list || cJSON_GetObjectItemCaseSensitive(j, "columns") ||
            cJSON_GetObjectItemCaseSensitive(j, "rows"))
            return FAIL(MM_ERR_SYNTAX, "field: give either image or columns, rows and heights");
        if (!cJSON_IsString(image)) return FAIL(MM_ERR_SYNTAX, "field.image must be a file name");
        double scale = 1.0;
        v = cJSON_GetObjectItemCaseSensitive(j, "height_scale");
        if (!v) return FAIL(MM_ERR_SYNTAX, "field.height_scale is missing (metres at the image's white)");
        if ((r = number(v, "field.height_scale", MM_SCENE_MAX_EXTENT, &scale, err)) != MM_OK) return r;
        char path[1024];
        folder_of(image->valuestring[0] == '/' ? NULL : name, path, sizeof path);
        if (strlen(path) + strlen(image->valuestring) + 1 > sizeof path)
            return FAIL(MM_ERR_OUT_OF_RANGE, "field.image: the path is too long");
        strcat(path, image->valuestring);
        if ((r = load_pgm(path, "field.image", (float)scale, heights, &nc, &nr, err)) != MM_OK) return r;
    } else {
        if (cJSON_GetObjectItemCaseSensitive(j, "height_scale"))
            return FAIL(MM_ERR_SYNTAX, "field.height_scale goes with field.image");
        v = cJSON_GetObjectItemCaseSensitive(j, "columns");
        if (!v) return FAIL(MM_ERR_SYNTAX, "field.columns is missing");
        if ((r = number(v, "field.columns", MM_SCENE_MAX_FIELD_SAMPLES, &columns, err)) != MM_OK) return r;
        v = cJSON_GetObjectItemCaseSensitive(j, "rows");
        if (!v) return FAIL(MM_ERR_SYNTAX, "field.rows is missing");
        if ((r = number(v, "field.rows", MM_SCENE_MAX_FIELD_SAMPLES, &rows, err)) != MM_OK) return r;
        if (columns < 2 || rows < 2 || columns != floor(columns) || rows != floor(rows))
            return FAIL(MM_ERR_OUT_OF_RANGE, "field.columns and field.rows must be whole numbers from 2");
        if (columns * rows > MM_SCENE_MAX_FIELD_SAMPLES)
            return FAIL(MM_ERR_LIMIT, "field: %g samples (at most %d)", columns * rows,
                        MM_SCENE_MAX_FIELD_SAMPLES);
        nc = (int)columns, nr = (int)rows;
        if (!list) return FAIL(MM_ERR_SYNTAX, "field.heights is missing");
        if (!cJSON_IsArray(list) || cJSON_GetArraySize(list) != nc * nr)
            return FAIL(MM_ERR_SYNTAX, "field.heights must be an array of columns * rows = %d numbers",
                        nc * nr);
        int k = 0;
        char what[64];
        for (const cJSON *e = list->child; e; e = e->next, ++k) {
            double h = 0.0;
            snprintf(what, sizeof what, "field.heights[%d]", k);
            if ((r = number(e, what, MM_SCENE_MAX_EXTENT, &h, err)) != MM_OK) return r;
            heights[k] = (float)h + 0.0f;
        }
    }
    r = mm_scene_set_field(s, origin, (float)spacing, nc, nr, heights);
    if (r != MM_OK) return FAIL(r, "field: %s", mm_result_str(r));
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
    static const char *const keys[] = {"ground", "boxes", "ramps", "stairs", "field"};
    mm_result r = MM_OK;
    if (!cJSON_IsObject(root))
        r = FAIL(MM_ERR_SYNTAX, "a scene is an object {\"ground\": 0, \"boxes\": [...]}");
    else
        r = check_keys(root, "", keys, 5, err);
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
    static const char *const lists[2] = {"ramps", "stairs"};
    static const int limits[2] = {MM_SCENE_MAX_RAMPS, MM_SCENE_MAX_STAIRS};
    for (int l = 0; l < 2 && r == MM_OK; ++l) {
        const cJSON *items = cJSON_GetObjectItemCaseSensitive(root, lists[l]);
        if (!items) continue;
        int n = cJSON_GetArraySize(items);
        if (!cJSON_IsArray(items))
            r = FAIL(MM_ERR_SYNTAX, "%s must be an array of objects", lists[l]);
        else if (n > limits[l])
            r = FAIL(MM_ERR_LIMIT, "%s: %d given (at most %d)", lists[l], n, limits[l]);
        int i = 0;
        for (const cJSON *b = items->child; r == MM_OK && b; b = b->next, ++i)
            r = parse_terrain_solid(b, lists[l], i, l == 1, out, err);
    }
    const cJSON *field = r == MM_OK ? cJSON_GetObjectItemCaseSensitive(root, "field") : NULL;
    if (field) r = parse_field(field, name, out, err);
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
    if (!scene || !out || scene->box_count < 0 || scene->box_count > MM_SCENE_MAX_BOXES ||
        scene->ramp_count < 0 || scene->ramp_count > MM_SCENE_MAX_RAMPS || scene->stairs_count < 0 ||
        scene->stairs_count > MM_SCENE_MAX_STAIRS)
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
    fputs(scene->box_count ? "\n]" : "]", out);
    for (int l = 0; l < 2; ++l) {
        int n = l ? scene->stairs_count : scene->ramp_count;
        if (!n) continue;
        fprintf(out, ",\n \"%s\": [", l ? "stairs" : "ramps");
        for (int i = 0; i < n; ++i) {
            mm_vec3 p = l ? scene->stairs[i].position : scene->ramps[i].position;
            mm_vec3 sz = l ? scene->stairs[i].size : scene->ramps[i].size;
            float yaw = l ? scene->stairs[i].yaw : scene->ramps[i].yaw;
            const float f[6] = {p.x, p.y, p.z, sz.x, sz.y, sz.z};
            for (int k = 0; k < 6; ++k) mm__format_number(v[k], sizeof v[k], f[k], 9);
            mm__format_number(v[6], sizeof v[6], (double)yaw * MM_RAD_TO_DEG, 17);
            fprintf(out, "%s\n  {\"position\": [%s, %s, %s], \"size\": [%s, %s, %s], \"yaw\": %s",
                    i ? "," : "", v[0], v[1], v[2], v[3], v[4], v[5], v[6]);
            if (l) fprintf(out, ", \"steps\": %d", scene->stairs[i].steps);
            fputs("}", out);
        }
        fputs("\n]", out);
    }
    const mm_scene_field *f = &scene->field;
    if (f->columns >= 2 && f->rows >= 2 && f->columns * f->rows <= MM_SCENE_MAX_FIELD_SAMPLES) {
        const float o[4] = {f->origin.x, f->origin.y, f->origin.z, f->spacing};
        for (int k = 0; k < 4; ++k) mm__format_number(v[k], sizeof v[k], o[k], 9);
        fprintf(out,
                ",\n \"field\": {\"origin\": [%s, %s, %s], \"spacing\": %s, \"columns\": %d, \"rows\": %d,\n "
                " \"heights\": [",
                v[0], v[1], v[2], v[3], f->columns, f->rows);
        for (int i = 0; i < f->columns * f->rows; ++i) {
            mm__format_number(v[0], sizeof v[0], f->heights[i], 9);
            fprintf(out, "%s%s", i == 0 ? "" : i % f->columns == 0 ? ",\n   " : ", ", v[0]);
        }
        fputs("]}", out);
    }
    fputs("}\n", out);
    return ferror(out) ? MM_ERR_IO : MM_OK;
}
