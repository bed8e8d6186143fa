/* Writing into a config file: clip tag ranges and clips (the runtime tuning: src/tuning/).  The file is read
 * with cJSON, changed in place (every other field kept, in its order), printed with two-space indentation
 * (arrays of numbers on one line), checked by parsing it as a config, and written atomically. */
#define _POSIX_C_SOURCE 200809L
#include <mm/config_json.h>

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/config_doc.h"
#include "io/file.h"

/* ---- printing --------------------------------------------------------------------------- */

typedef struct text_buf {
    char *data;
    size_t size, capacity;
    int failed;
} text_buf;

static void put(text_buf *b, const char *s, size_t n)
{
    if (b->failed) return;
    if (b->size + n + 1 > b->capacity) {
        size_t cap = b->capacity ? b->capacity : 4096;
        while (b->size + n + 1 > cap) cap *= 2;
        char *p = (char *)realloc(b->data, cap);
        if (!p) {
            b->failed = 1;
            return;
        }
        b->data = p;
        b->capacity = cap;
    }
    memcpy(b->data + b->size, s, n);
    b->size += n;
    b->data[b->size] = 0;
}

static void puts_(text_buf *b, const char *s) { put(b, s, strlen(s)); }

static void put_indent(text_buf *b, int indent)
{
    for (int i = 0; i < indent; ++i) put(b, " ", 1);
}

static void put_string(text_buf *b, const char *s)
{
    put(b, "\"", 1);
    for (const unsigned char *p = (const unsigned char *)(s ? s : ""); *p; ++p) {
        char esc[8];
        switch (*p) {
        case '"':
            puts_(b, "\\\"");
            break;
        case '\\':
            puts_(b, "\\\\");
            break;
        case '\b':
            puts_(b, "\\b");
            break;
        case '\f':
            puts_(b, "\\f");
            break;
        case '\n':
            puts_(b, "\\n");
            break;
        case '\r':
            puts_(b, "\\r");
            break;
        case '\t':
            puts_(b, "\\t");
            break;
        default:
            if (*p < 0x20) {
                snprintf(esc, sizeof esc, "\\u%04x", *p);
                puts_(b, esc);
            } else {
                put(b, (const char *)p, 1);
            }
        }
    }
    put(b, "\"", 1);
}

/* The shortest decimal that reads back as the same double. */
static void put_number(text_buf *b, double v)
{
    char s[40];
    if (!isfinite(v)) {
        puts_(b, "null"); /* never valid in a config: the check after printing refuses it */
        return;
    }
    if (v == floor(v) && fabs(v) < 1e15) { /* whole numbers as integers (100, not 1e+02) */
        snprintf(s, sizeof s, "%.0f", v);
        puts_(b, s);
        return;
    }
    for (int digits = 1; digits <= 17; ++digits) {
        snprintf(s, sizeof s, "%.*g", digits, v);
        if (strtod(s, NULL) == v) break;
    }
    puts_(b, s);
}

/* Scalars, and arrays holding only scalars and such arrays, print on one line. */
static int is_flat(const cJSON *v)
{
    if (cJSON_IsObject(v)) return v->child == NULL;
    if (cJSON_IsArray(v))
        for (const cJSON *e = v->child; e; e = e->next)
            if (!is_flat(e)) return 0;
    return 1;
}

static void put_value(text_buf *b, const cJSON *v, int indent)
{
    if (cJSON_IsObject(v)) {
        if (!v->child) {
            puts_(b, "{}");
            return;
        }
        puts_(b, "{\n");
        for (const cJSON *e = v->child; e; e = e->next) {
            put_indent(b, indent + 2);
            put_string(b, e->string);
            puts_(b, ": ");
            put_value(b, e, indent + 2);
            puts_(b, e->next ? ",\n" : "\n");
        }
        put_indent(b, indent);
        puts_(b, "}");
    } else if (cJSON_IsArray(v)) {
        int flat = is_flat(v);
        puts_(b, flat ? "[" : "[\n");
        for (const cJSON *e = v->child; e; e = e->next) {
            if (!flat) put_indent(b, indent + 2);
            put_value(b, e, indent + 2);
            if (e->next) puts_(b, flat ? ", " : ",\n");
        }
        if (!flat && v->child) {
            puts_(b, "\n");
            put_indent(b, indent);
        }
        puts_(b, "]");
    } else if (cJSON_IsString(v)) {
        put_string(b, v->valuestring);
    } else if (cJSON_IsNumber(v)) {
        put_number(b, v->valuedouble);
    } else if (cJSON_IsBool(v)) {
        puts_(b, cJSON_IsTrue(v) ? "true" : "false");
    } else {
        puts_(b, "null");
    }
}

/* ---- editing ---------------------------------------------------------------------------- */

/* A float as the double of its shortest decimal form (0.6f is written 0.6, not 0.60000002). */
static double short_double(float f)
{
    char s[32];
    for (int digits = 1; digits <= 9; ++digits) {
        snprintf(s, sizeof s, "%.*g", digits, (double)f);
        if (strtof(s, NULL) == f) return strtod(s, NULL);
    }
    return (double)f;
}

/* Sets obj[key] to a number, in place when the key exists. 0: out of memory. */
int mm__json_set_number(cJSON *obj, const char *key, float value)
{
    cJSON *n = cJSON_CreateNumber(short_double(value));
    if (!n) return 0;
    if (cJSON_GetObjectItemCaseSensitive(obj, key))
        return cJSON_ReplaceItemInObjectCaseSensitive(obj, key, n);
    return cJSON_AddItemToObject(obj, key, n);
}

/* Sets obj[key] to true or false, in place when the key exists. 0: out of memory. */
int mm__json_set_bool(cJSON *obj, const char *key, bool value)
{
    cJSON *b = cJSON_CreateBool(value);
    if (!b) return 0;
    if (cJSON_GetObjectItemCaseSensitive(obj, key))
        return cJSON_ReplaceItemInObjectCaseSensitive(obj, key, b);
    return cJSON_AddItemToObject(obj, key, b);
}

/* obj[key] when it is an object; else a new object there (replacing what was). NULL: no memory. */
cJSON *mm__json_object_at(cJSON *obj, const char *key)
{
    cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (cJSON_IsObject(v)) return v;
    cJSON *o = cJSON_CreateObject();
    if (!o) return NULL;
    int ok = v ? cJSON_ReplaceItemInObjectCaseSensitive(obj, key, o) : cJSON_AddItemToObject(obj, key, o);
    if (!ok) {
        cJSON_Delete(o);
        return NULL;
    }
    return o;
}

/* The config file: its text checked as a config (errors name the file, and the line for JSON
 * syntax), and its JSON tree. */
mm_result mm__config_doc_load(const char *path, mm_config *cfg, cJSON **out_root, mm_error *err)
{
    *out_root = NULL;
    memset(cfg, 0, sizeof *cfg);
    mm_result r = mm_config_load_json(path, cfg, NULL, err);
    if (r != MM_OK) return r;
    char *text = NULL;
    size_t size = 0;
    r = mm__read_file(path, NULL, &text, &size, err);
    if (r == MM_OK) {
        *out_root = cJSON_ParseWithLength(text, size);
        if (!*out_root)
            r = mm_error_set(err, MM_ERR_SYNTAX, 0, 0, "not valid JSON");
        else if (!cJSON_IsObject(*out_root))
            r = mm_error_set(err, MM_ERR_SYNTAX, 0, 0, "the config must be an object");
    }
    free(text);
    if (r != MM_OK) {
        cJSON_Delete(*out_root);
        *out_root = NULL;
        mm_config_free(cfg);
    }
    return r;
}

/* Prints root, checks the result is a valid config and writes it atomically. Deletes root. */
mm_result mm__config_doc_save(const char *path, cJSON *root, mm_error *err)
{
    text_buf b = {NULL, 0, 0, 0};
    put_value(&b, root, 0);
    puts_(&b, "\n");
    cJSON_Delete(root);
    mm__error_set_file(err, path);
    if (b.failed) {
        free(b.data);
        return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    }
    mm_config check;
    memset(&check, 0, sizeof check);
    char dir[MM_PATH_MAX]; /* for a base config named by "extends" */
    const char *slash = strrchr(path, '/');
    if (slash)
        snprintf(dir, sizeof dir, "%.*s", (int)(slash - path), path);
    else
        snprintf(dir, sizeof dir, ".");
    mm_result r = mm_config_parse_json(b.data, b.size, path, dir, &check, err);
    mm_config_free(&check);
    if (r == MM_OK) r = mm__write_file_atomic(path, b.data, b.size, err);
    free(b.data);
    return r;
}

mm_result mm__config_doc_no_memory(cJSON *root, mm_config *cfg, mm_error *err)
{
    cJSON_Delete(root);
    mm_config_free(cfg);
    return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
}

/* ---- clip tags -------------------------------------------------------------------------- */

mm_result mm_config_save_clip_tags(const char *config_path, const char *clip_name, const char *tag,
                                   const float (*ranges)[2], int range_count, mm_error *err)
{
    mm__error_set_file(err, config_path);
    if (!config_path || !clip_name || !tag)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0,
                            "a config path, clip name and tag are needed");
    if (!tag[0] || strlen(tag) >= MM_TAG_NAME_MAX)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "tag '%s': names have 1 to %d characters",
                            tag, MM_TAG_NAME_MAX - 1);
    if (range_count < 0 || (range_count > 0 && !ranges))
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "tag '%s': %d ranges given", tag,
                            range_count);
    mm_config cfg;
    cJSON *root = NULL;
    mm_result r = mm__config_doc_load(config_path, &cfg, &root, err);
    if (r != MM_OK) return r;
    int clip = -1;
    for (int i = 0; i < cfg.clip_count && clip < 0; ++i)
        if (strcmp(cfg.clips[i].name, clip_name) == 0) clip = i;
    int declared = mm_config_tag_index(&cfg, tag) >= 0;
    /* a config that extends another lists its own clips after the base's */
    int inherited = cfg.clip_count - cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(root, "clips"));
    mm_config_free(&cfg);
    if (clip < 0) {
        cJSON_Delete(root);
        return mm_error_set(err, MM_ERR_NOT_FOUND, 0, 0, "clips: no clip named '%s'", clip_name);
    }
    if (clip < inherited) {
        cJSON_Delete(root);
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0,
                            "clips: '%s' comes from the config this one extends: edit that one", clip_name);
    }
    clip -= inherited;
    cJSON *item = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(root, "clips"), clip);
    if (range_count == 0) {
        cJSON *tags = cJSON_GetObjectItemCaseSensitive(item, "tags");
        if (cJSON_IsObject(tags)) cJSON_DeleteItemFromObjectCaseSensitive(tags, tag);
        return mm__config_doc_save(config_path, root, err);
    }
    if (!declared) { /* add the name to the top-level list */
        cJSON *names = cJSON_GetObjectItemCaseSensitive(root, "tags");
        if (!names) names = cJSON_AddArrayToObject(root, "tags");
        cJSON *s = cJSON_CreateString(tag);
        if (!names || !s || !cJSON_AddItemToArray(names, s)) {
            cJSON_Delete(s);
            return mm__config_doc_no_memory(root, NULL, err);
        }
    }
    cJSON *tags = mm__json_object_at(item, "tags");
    cJSON *list = cJSON_CreateArray();
    if (!tags || !list) {
        cJSON_Delete(list);
        return mm__config_doc_no_memory(root, NULL, err);
    }
    for (int i = 0; i < range_count; ++i) {
        cJSON *pair = cJSON_CreateArray();
        cJSON *b = cJSON_CreateNumber(short_double(ranges[i][0]));
        cJSON *e = cJSON_CreateNumber(short_double(ranges[i][1]));
        int ok = pair && b && e && cJSON_AddItemToArray(pair, b);
        if (ok) b = NULL;
        ok = ok && cJSON_AddItemToArray(pair, e);
        if (ok) e = NULL;
        ok = ok && cJSON_AddItemToArray(list, pair);
        if (!ok) {
            cJSON_Delete(b);
            cJSON_Delete(e);
            if (pair) cJSON_Delete(pair);
            cJSON_Delete(list);
            return mm__config_doc_no_memory(root, NULL, err);
        }
    }
    int ok = cJSON_GetObjectItemCaseSensitive(tags, tag)
                 ? cJSON_ReplaceItemInObjectCaseSensitive(tags, tag, list)
                 : cJSON_AddItemToObject(tags, tag, list);
    if (!ok) {
        cJSON_Delete(list);
        return mm__config_doc_no_memory(root, NULL, err);
    }
    return mm__config_doc_save(config_path, root, err);
}

/* ---- whole clips ------------------------------------------------------------------------ */

/* Appends a string to the array unless it is there. 0: no memory. */
static int add_name(cJSON *names, const char *name)
{
    for (const cJSON *e = names->child; e; e = e->next)
        if (cJSON_IsString(e) && strcmp(e->valuestring, name) == 0) return 1;
    cJSON *s = cJSON_CreateString(name);
    if (!s || !cJSON_AddItemToArray(names, s)) {
        cJSON_Delete(s);
        return 0;
    }
    return 1;
}

/* The clip object for c, or NULL when out of memory. */
static cJSON *clip_object(const mm_config_saved_clip *c)
{
    cJSON *o = cJSON_CreateObject();
    cJSON *ranges = cJSON_CreateArray();
    int ok = o && ranges && cJSON_AddStringToObject(o, "name", c->name) &&
             cJSON_AddStringToObject(o, "file", c->file);
    int n = c->range_count > 0 ? c->range_count : 1;
    for (int i = 0; ok && i < n; ++i) {
        cJSON *range =
            cJSON_CreateIntArray(c->range_count > 0 ? c->ranges[i] : (const int[2]){c->begin, c->end}, 2);
        ok = range && cJSON_AddItemToArray(ranges, range);
        if (!ok) cJSON_Delete(range);
    }
    ok = ok && cJSON_AddItemToObject(o, "ranges", ranges);
    if (ok) ranges = NULL;
    if (ok && c->type == MM_CLIP_IDLE) ok = cJSON_AddStringToObject(o, "type", "idle") != NULL;
    if (ok && c->mirror) ok = cJSON_AddTrueToObject(o, "mirror") != NULL;
    cJSON *tags = ok && c->tag_count > 0 ? cJSON_AddObjectToObject(o, "tags") : NULL;
    if (c->tag_count > 0 && !tags) ok = 0;
    for (int i = 0; ok && i < c->tag_count; ++i) {
        const mm_config_named_range *t = &c->tags[i];
        cJSON *list = cJSON_GetObjectItemCaseSensitive(tags, t->tag);
        if (!list) list = cJSON_AddArrayToObject(tags, t->tag);
        cJSON *pair = cJSON_CreateArray();
        ok = list && pair && cJSON_AddItemToArray(pair, cJSON_CreateNumber(short_double(t->begin))) &&
             cJSON_AddItemToArray(pair, cJSON_CreateNumber(short_double(t->end))) &&
             cJSON_AddItemToArray(list, pair);
        if (!ok) cJSON_Delete(pair);
    }
    cJSON_Delete(ranges);
    if (!ok) {
        cJSON_Delete(o);
        return NULL;
    }
    return o;
}

mm_result mm_config_save_clip(const char *config_path, const mm_config_saved_clip *clip, mm_error *err)
{
    mm__error_set_file(err, config_path);
    if (!config_path || !clip || !clip->name || !clip->name[0] || !clip->file || !clip->file[0])
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0,
                            "a config path and a clip name and file are needed");
    if (clip->tag_count < 0 || (clip->tag_count > 0 && !clip->tags))
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "clip '%s': %d tag ranges given", clip->name,
                            clip->tag_count);
    if (clip->range_count < 0 || (clip->range_count > 0 && !clip->ranges))
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "clip '%s': %d frame ranges given",
                            clip->name, clip->range_count);
    for (int i = 0; i < clip->tag_count; ++i)
        if (!clip->tags[i].tag[0])
            return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "clip '%s': tag range %d has no tag name",
                                clip->name, i);
    mm_config cfg;
    cJSON *root = NULL;
    mm_result r = mm__config_doc_load(config_path, &cfg, &root, err);
    if (r != MM_OK) return r;
    cJSON *clips = cJSON_GetObjectItemCaseSensitive(root, "clips");
    int own = cJSON_IsArray(clips) ? cJSON_GetArraySize(clips) : 0, inherited = cfg.clip_count - own, at = -1;
    for (int i = 0; i < cfg.clip_count && at < 0; ++i)
        if (strcmp(cfg.clips[i].name, clip->name) == 0) at = i;
    mm_config_free(&cfg);
    if (at >= 0 && at < inherited) {
        cJSON_Delete(root);
        return mm_error_set(err, MM_ERR_DUPLICATE_NAME, 0, 0,
                            "clips: '%s' is a clip of the config this one extends", clip->name);
    }
    if (!clips) clips = cJSON_AddArrayToObject(root, "clips");
    cJSON *names = cJSON_GetObjectItemCaseSensitive(root, "tags");
    if (!names && clip->tag_count > 0) names = cJSON_AddArrayToObject(root, "tags");
    cJSON *o = clip_object(clip);
    int ok = clips && o && (clip->tag_count == 0 || names);
    for (int i = 0; ok && i < clip->tag_count; ++i) ok = add_name(names, clip->tags[i].tag);
    if (ok && at >= 0) { /* the clip of that name is replaced */
        ok = cJSON_ReplaceItemInArray(clips, at - inherited, o);
    } else if (ok) {
        ok = cJSON_AddItemToArray(clips, o);
    }
    if (!ok) {
        cJSON_Delete(o);
        return mm__config_doc_no_memory(root, NULL, err);
    }
    return mm__config_doc_save(config_path, root, err);
}
