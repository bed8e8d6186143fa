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

/* ---- a whole config --------------------------------------------------------------------- */

/* A float as a JSON number in its shortest form; NULL when out of memory. */
static cJSON *number(float v) { return cJSON_CreateNumber(short_double(v)); }

/* obj[key] = item, taking it; 0 (and item deleted) when out of memory. */
static int add(cJSON *obj, const char *key, cJSON *item)
{
    if (!item) return 0;
    if (!cJSON_AddItemToObject(obj, key, item)) {
        cJSON_Delete(item);
        return 0;
    }
    return 1;
}

static int push(cJSON *array, cJSON *item)
{
    if (!item) return 0;
    if (!cJSON_AddItemToArray(array, item)) {
        cJSON_Delete(item);
        return 0;
    }
    return 1;
}

static cJSON *number_pair(double a, double b)
{
    cJSON *p = cJSON_CreateArray();
    if (p && (!push(p, cJSON_CreateNumber(a)) || !push(p, cJSON_CreateNumber(b)))) {
        cJSON_Delete(p);
        return NULL;
    }
    return p;
}

static cJSON *roles_object(const mm_config *c)
{
    cJSON *o = cJSON_CreateObject(), *axis = cJSON_CreateArray();
    const char *keys[] = {"hips", "root_bone", "facing_bone"};
    const char *values[] = {c->hips, c->root_bone, c->facing_bone};
    int ok = o && axis;
    for (int i = 0; ok && i < 3; ++i) ok = add(o, keys[i], cJSON_CreateString(values[i]));
    ok = ok && push(axis, number(c->forward_axis.x)) && push(axis, number(c->forward_axis.y)) &&
         push(axis, number(c->forward_axis.z));
    if (ok)
        ok = add(o, "forward_axis", axis);
    else
        cJSON_Delete(axis);
    const char *keys2[] = {"left_foot", "right_foot", "left_toe", "right_toe",
                           "left_hand", "right_hand", "head"};
    const char *values2[] = {c->left_foot, c->right_foot, c->left_toe, c->right_toe,
                             c->left_hand, c->right_hand, c->head};
    for (int i = 0; ok && i < 7; ++i) ok = add(o, keys2[i], cJSON_CreateString(values2[i]));
    if (!ok) {
        cJSON_Delete(o);
        return NULL;
    }
    return o;
}

static cJSON *features_object(const mm_config *c, const mm_config *d)
{
    cJSON *o = cJSON_CreateObject(), *bones = cJSON_CreateArray();
    int ok = o && bones;
    for (int i = 0; ok && i < c->bone_count; ++i) {
        const mm_config_bone *b = &c->bones[i];
        cJSON *bo = cJSON_CreateObject();
        ok = bo && add(bo, "name", cJSON_CreateString(b->name));
        if (ok && !(b->features & MM_MATCH_POSITION)) ok = add(bo, "position", cJSON_CreateFalse());
        if (ok && !(b->features & MM_MATCH_VELOCITY)) ok = add(bo, "velocity", cJSON_CreateFalse());
        if (ok && (b->features & MM_MATCH_POSITION))
            ok = add(bo, "position_weight", number(b->position_weight));
        if (ok && (b->features & MM_MATCH_VELOCITY))
            ok = add(bo, "velocity_weight", number(b->velocity_weight));
        if (ok)
            ok = push(bones, bo);
        else
            cJSON_Delete(bo);
    }
    if (ok)
        ok = add(o, "bones", bones);
    else
        cJSON_Delete(bones);
    int same_times = c->traj_count == d->traj_count;
    for (int i = 0; same_times && i < c->traj_count; ++i) same_times = c->traj_times[i] == d->traj_times[i];
    if (ok && !same_times) {
        cJSON *times = cJSON_CreateArray();
        ok = times != NULL;
        for (int i = 0; ok && i < c->traj_count; ++i) ok = push(times, number(c->traj_times[i]));
        if (ok)
            ok = add(o, "trajectory_times", times);
        else
            cJSON_Delete(times);
    }
    if (ok && c->root_velocity != d->root_velocity)
        ok = add(o, "root_velocity", cJSON_CreateBool(c->root_velocity));
    if (ok && c->body_velocity_weight != d->body_velocity_weight)
        ok = add(o, "body_velocity_weight", number(c->body_velocity_weight));
    if (ok && c->position_multiplier != d->position_multiplier)
        ok = add(o, "position_multiplier", number(c->position_multiplier));
    if (ok && c->angle_multiplier != d->angle_multiplier)
        ok = add(o, "angle_multiplier", number(c->angle_multiplier));
    if (!ok) {
        cJSON_Delete(o);
        return NULL;
    }
    return o;
}

static cJSON *gait_object(const mm_runtime_gait *g)
{
    static const char *const keys[] = {"forward_speed", "side_speed", "backward_speed", "velocity_halflife",
                                       "rotation_halflife"};
    const float values[] = {g->forward_speed, g->side_speed, g->backward_speed, g->velocity_halflife,
                            g->rotation_halflife};
    cJSON *o = cJSON_CreateObject();
    int ok = o != NULL;
    for (int k = 0; ok && k < 5; ++k)
        if (g->set & (1u << k)) ok = add(o, keys[k], number(values[k]));
    if (!ok) {
        cJSON_Delete(o);
        return NULL;
    }
    return o;
}

static cJSON *runtime_object(const mm_runtime_config *rt)
{
    static const char *const keys[] = {
        "pose_trajectory_ratio", "next_pose_favour",    "loop_anim_favour", "continuing_bias",
        "search_interval",       "transition_halflife", "idle_speed",       "sync_halflife"};
    const float values[] = {
        rt->pose_trajectory_ratio, rt->next_pose_favour,    rt->loop_anim_favour, rt->continuing_bias,
        rt->search_interval,       rt->transition_halflife, rt->idle_speed,       rt->sync_halflife};
    cJSON *o = cJSON_CreateObject();
    int ok = o != NULL;
    for (int k = 0; ok && k < 8; ++k)
        if (rt->set & (1u << k)) ok = add(o, keys[k], number(values[k]));
    if (ok && (rt->set & MM_RUNTIME_DISTANCE_MATCHING))
        ok = add(o, "distance_matching", cJSON_CreateBool(rt->distance_matching));
    if (ok && (rt->set & MM_RUNTIME_WARPING)) ok = add(o, "warping", cJSON_CreateBool(rt->warping));
    if (ok && (rt->set & MM_RUNTIME_CONTACT_FAVOUR))
        ok = add(o, "contact_favour", number(rt->contact_favour));
    if (ok && (rt->set & MM_RUNTIME_SPEED_ENVELOPE))
        ok = add(o, "speed_envelope", cJSON_CreateBool(rt->speed_envelope));
    const mm_runtime_gait *gaits[3] = {&rt->walk, &rt->run, &rt->crouch};
    static const char *const names[3] = {"walk", "run", "crouch"};
    for (int g = 0; ok && g < 3; ++g)
        if (gaits[g]->set) ok = add(o, names[g], gait_object(gaits[g]));
    if (!ok) {
        cJSON_Delete(o);
        return NULL;
    }
    return o;
}

static cJSON *clip_json(const mm_config *c, const mm_config_clip *k)
{
    cJSON *o = cJSON_CreateObject();
    int ok = o && add(o, "name", cJSON_CreateString(k->name)) && add(o, "file", cJSON_CreateString(k->file));
    if (ok && k->take[0]) ok = add(o, "take", cJSON_CreateString(k->take));
    if (ok && k->range_count > 0) {
        cJSON *ranges = cJSON_CreateArray();
        ok = ranges != NULL;
        for (int i = 0; ok && i < k->range_count; ++i)
            ok = push(ranges, number_pair(k->ranges[i].begin, k->ranges[i].end));
        if (ok)
            ok = add(o, "ranges", ranges);
        else
            cJSON_Delete(ranges);
    }
    if (ok && k->type == MM_CLIP_IDLE) ok = add(o, "type", cJSON_CreateString("idle"));
    if (ok && k->loop) ok = add(o, "loop", cJSON_CreateTrue());
    if (ok && k->mirror) ok = add(o, "mirror", cJSON_CreateTrue());
    if (ok && k->tag_range_count > 0) {
        cJSON *tags = cJSON_CreateObject();
        ok = tags != NULL;
        for (int i = 0; ok && i < k->tag_range_count; ++i) {
            const mm_config_tag_range *t = &k->tag_ranges[i];
            const char *name = c->tag_names[t->tag];
            cJSON *list = cJSON_GetObjectItemCaseSensitive(tags, name);
            if (!list && !(ok = add(tags, name, cJSON_CreateArray()))) break;
            list = cJSON_GetObjectItemCaseSensitive(tags, name);
            ok = push(list, number_pair(short_double(t->begin), short_double(t->end)));
        }
        if (ok)
            ok = add(o, "tags", tags);
        else
            cJSON_Delete(tags);
    }
    if (!ok) {
        cJSON_Delete(o);
        return NULL;
    }
    return o;
}

mm_result mm_config_save_json(const char *path, const mm_config *c, mm_error *err)
{
    mm__error_set_file(err, path);
    if (!path || !c)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "a path and a config are needed");
    mm_result r = mm_config_validate(c, err);
    if (r != MM_OK) return r;
    for (int i = 0; i < c->tag_count; ++i)
        if (!c->tag_names[i][0])
            return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "tags[%d] is empty", i);
    mm_config d;
    mm_config_defaults(&d);
    cJSON *root = cJSON_CreateObject();
    int ok = root != NULL;
    /* an interval of 1/N is written to 6 digits (0.0166667), which reads back as exactly 1/N */
    double rate = 1.0 / (double)c->interval, whole = floor(rate + 0.5);
    char text[32];
    snprintf(text, sizeof text, "%.6g", 1.0 / whole);
    double interval = fabs(rate - whole) <= 1e-5 * whole ? strtod(text, NULL) : short_double(c->interval);
    ok = ok && add(root, "interval", cJSON_CreateNumber(interval)) && add(root, "scale", number(c->scale));
    if (ok && (c->axes_up != d.axes_up || c->axes_forward != d.axes_forward)) {
        cJSON *o = cJSON_CreateObject();
        ok = o != NULL && mm_axis_name(c->axes_up) &&
             add(o, "up", cJSON_CreateString(mm_axis_name(c->axes_up)));
        if (ok && mm_axis_name(c->axes_forward))
            ok = add(o, "forward", cJSON_CreateString(mm_axis_name(c->axes_forward)));
        if (ok)
            ok = add(root, "axes", o);
        else
            cJSON_Delete(o);
    }
    ok = ok && add(root, "roles", roles_object(c));
    if (ok && c->root_smoothing != d.root_smoothing)
        ok = add(root, "root_smoothing", number(c->root_smoothing));
    if (ok && (c->contact_height != d.contact_height || c->contact_speed != d.contact_speed ||
               c->contact_min_time != d.contact_min_time ||
               c->contact_planted_tolerance != d.contact_planted_tolerance)) {
        cJSON *o = cJSON_CreateObject();
        ok = o != NULL;
        if (ok && c->contact_height != d.contact_height) ok = add(o, "height", number(c->contact_height));
        if (ok && c->contact_speed != d.contact_speed) ok = add(o, "speed", number(c->contact_speed));
        if (ok && c->contact_min_time != d.contact_min_time)
            ok = add(o, "min_time", number(c->contact_min_time));
        if (ok && c->contact_planted_tolerance != d.contact_planted_tolerance)
            ok = add(o, "planted_tolerance", number(c->contact_planted_tolerance));
        if (ok)
            ok = add(root, "contacts", o);
        else
            cJSON_Delete(o);
    }
    if (ok && (c->postures_detect != d.postures_detect || c->postures_pad != d.postures_pad)) {
        cJSON *o = cJSON_CreateObject();
        ok = o != NULL;
        if (ok && c->postures_detect != d.postures_detect)
            ok = add(o, "detect", cJSON_CreateBool(c->postures_detect));
        if (ok && c->postures_pad != d.postures_pad) ok = add(o, "pad", number(c->postures_pad));
        if (ok)
            ok = add(root, "postures", o);
        else
            cJSON_Delete(o);
    }
    if (ok && c->standing_make != d.standing_make) {
        cJSON *o = cJSON_CreateObject();
        ok = o != NULL && add(o, "make", cJSON_CreateBool(c->standing_make));
        if (ok)
            ok = add(root, "standing", o);
        else
            cJSON_Delete(o);
    }
    if (ok && c->idle_loop_make != d.idle_loop_make) {
        cJSON *o = cJSON_CreateObject();
        ok = o != NULL && add(o, "make", cJSON_CreateBool(c->idle_loop_make));
        if (ok)
            ok = add(root, "idle_loop", o);
        else
            cJSON_Delete(o);
    }
    ok = ok && add(root, "features", features_object(c, &d));
    int same_pairs = c->mirror_pair_count == d.mirror_pair_count;
    for (int i = 0; same_pairs && i < c->mirror_pair_count; ++i)
        same_pairs = strcmp(c->mirror_pairs[i].left, d.mirror_pairs[i].left) == 0 &&
                     strcmp(c->mirror_pairs[i].right, d.mirror_pairs[i].right) == 0;
    if (ok && !same_pairs) {
        cJSON *pairs = cJSON_CreateArray();
        ok = pairs != NULL;
        for (int i = 0; ok && i < c->mirror_pair_count; ++i) {
            const char *pair[2] = {c->mirror_pairs[i].left, c->mirror_pairs[i].right};
            ok = push(pairs, cJSON_CreateStringArray(pair, 2));
        }
        if (ok)
            ok = add(root, "mirror_pairs", pairs);
        else
            cJSON_Delete(pairs);
    }
    if (ok && c->tag_count > 0) {
        const char *names[MM_MAX_TAGS];
        for (int i = 0; i < c->tag_count; ++i) names[i] = c->tag_names[i];
        ok = add(root, "tags", cJSON_CreateStringArray(names, c->tag_count));
    }
    if (ok && (c->runtime.set || c->runtime.walk.set || c->runtime.run.set || c->runtime.crouch.set))
        ok = add(root, "runtime", runtime_object(&c->runtime));
    cJSON *clips = ok ? cJSON_CreateArray() : NULL;
    ok = ok && clips != NULL;
    for (int i = 0; ok && i < c->clip_count; ++i) ok = push(clips, clip_json(c, &c->clips[i]));
    if (ok)
        ok = add(root, "clips", clips);
    else
        cJSON_Delete(clips);
    if (ok && c->blend_count > 0) {
        cJSON *blends = cJSON_CreateArray();
        ok = blends != NULL;
        for (int i = 0; ok && i < c->blend_count; ++i) {
            const mm_config_blend *b = &c->blends[i];
            cJSON *o = cJSON_CreateObject();
            ok = o && add(o, "name", cJSON_CreateString(b->name)) &&
                 add(o, "left", cJSON_CreateString(c->clips[b->left].name)) &&
                 add(o, "right", cJSON_CreateString(c->clips[b->right].name)) &&
                 add(o, "weight", number(b->weight));
            if (ok)
                ok = push(blends, o);
            else
                cJSON_Delete(o);
        }
        if (ok)
            ok = add(root, "blend_clips", blends);
        else
            cJSON_Delete(blends);
    }
    if (!ok) return mm__config_doc_no_memory(root, NULL, err);
    return mm__config_doc_save(path, root, err);
}
