/* A run's searches as JSON lines, read back and replayed (mm/trace.h, docs/viewer.md). */
#include <mm/trace.h>

#include <cjson/cJSON.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include <mm/drive.h>
#include <mm/input_json.h>
#include <mm/moves.h>
#include <mm/path_json.h>
#include <mm/scene_json.h>
#include <mm/search.h>

#include "io/file.h"
#include "io/json_parse.h"
#include "io/text.h"

#define TRACE_FORMAT       "mm-trace"
#define FLOAT_DIGITS       9  /* a float's shortest round trip */
#define DOUBLE_DIGITS      17 /* a double's */
#define TRACE_LINE_ROOM    4096
#define TRACE_MAX_LINES    100000000L /* lines a trace may have */
#define TRACE_INITIAL_CAP  64
#define TRACE_CONTACT_TERM 6 /* "contact_favour" in mm_trace_term_names */

const char *const mm_trace_term_names[MM_TRACE_TERM_COUNT] = {
    "pose_position", "pose_velocity",  "root_velocity",    "traj_position",  "traj_direction",
    "loop_favour",   "contact_favour", "next_pose_favour", "continuing_bias"};

void mm_trace_run_defaults(mm_trace_run *run)
{
    memset(run, 0, sizeof *run);
    run->fps = 60.0;
    run->random_seed = -1;
    run->distance_matching = run->warping = run->transition_mode = -1;
    run->crossfade_time = -1.0;
    run->top_k = MM_TRACE_DEFAULT_K;
}

uint64_t mm_trace_db_checksum(const mm_database *db)
{
    uint64_t c = 0; /* the file header's checksum field, at offset 16 (docs/format.md) */
    if (db && db->data && db->size >= 24) memcpy(&c, (const unsigned char *)db->data + 16, sizeof c);
    return c;
}

mm_result mm_trace_run_set_input_file(mm_trace_run *run, const char *path, mm_error *err)
{
    if (!run || !path) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "trace: no input file");
    char *text = NULL;
    size_t size = 0;
    mm_result r = mm__read_file(path, NULL, &text, &size, err);
    if (r != MM_OK) return r;
    free(run->input_text);
    run->input_text = text; /* mm__read_file terminates it */
    snprintf(run->input_path, sizeof run->input_path, "%s", path);
    return MM_OK;
}

void mm_trace_run_free(mm_trace_run *run)
{
    if (!run) return;
    free(run->input_text);
    run->input_text = NULL;
}

/* ---- writing: one line at a time into a growing buffer ------------------------------------- */

typedef struct line_text {
    char *data;
    size_t length, room;
    int failed;
} line_text;

static void put(line_text *b, const char *s, size_t n)
{
    if (b->failed) return;
    if (b->length + n + 1 > b->room) {
        size_t room = b->room ? b->room : TRACE_LINE_ROOM;
        while (room < b->length + n + 1) room *= 2;
        char *grown = (char *)realloc(b->data, room);
        if (!grown) {
            b->failed = 1;
            return;
        }
        b->data = grown, b->room = room;
    }
    memcpy(b->data + b->length, s, n);
    b->length += n;
    b->data[b->length] = 0;
}

static void puts_text(line_text *b, const char *s) { put(b, s, strlen(s)); }

static void putf(line_text *b, const char *fmt, ...)
{
    char buf[256];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    if (n < 0 || (size_t)n >= sizeof buf) {
        b->failed = 1;
        return;
    }
    put(b, buf, (size_t)n);
}

/* A number as JSON (not finite: null). */
static void put_number(line_text *b, double v, int digits)
{
    char buf[64];
    if (!isfinite(v)) {
        puts_text(b, "null");
        return;
    }
    put(b, buf, (size_t)mm__format_number(buf, sizeof buf, v, digits));
}

/* A JSON string. */
static void put_string(line_text *b, const char *s)
{
    put(b, "\"", 1);
    for (const unsigned char *p = (const unsigned char *)s; *p; ++p) {
        if (*p == '"' || *p == '\\') {
            char e[2] = {'\\', (char)*p};
            put(b, e, 2);
        } else if (*p == '\n') {
            put(b, "\\n", 2);
        } else if (*p == '\t') {
            put(b, "\\t", 2);
        } else if (*p == '\r') {
            put(b, "\\r", 2);
        } else if (*p < 0x20) {
            putf(b, "\\u%04x", *p);
        } else {
            put(b, (const char *)p, 1);
        }
    }
    put(b, "\"", 1);
}

static void put_switch(line_text *b, const char *name, int value)
{
    putf(b, ",\"%s\":%s", name, value < 0 ? "null" : value ? "true" : "false");
}

static mm_result write_line(FILE *out, line_text *b)
{
    mm_result r = MM_OK;
    if (b->failed)
        r = MM_ERR_OUT_OF_MEMORY;
    else if (fwrite(b->data, 1, b->length, out) != b->length || fputc('\n', out) == EOF)
        r = MM_ERR_IO;
    free(b->data);
    return r;
}

static void header_line(line_text *b, const mm_trace_run *run, int dims)
{
    putf(b, "{\"type\":\"header\",\"format\":\"%s\",\"version\":%d,\"database\":{\"path\":", TRACE_FORMAT,
         MM_TRACE_VERSION);
    put_string(b, run->db_path);
    putf(b, ",\"checksum\":\"%016llx\",\"bytes\":%llu,\"frames\":%d,\"dims\":%d},\"fps\":",
         (unsigned long long)run->db_checksum, (unsigned long long)run->db_size, run->db_frames, dims);
    put_number(b, run->fps, DOUBLE_DIGITS);
    putf(b, ",\"ticks\":%d,\"input\":{", run->ticks);
    if (run->path_file[0]) {
        puts_text(b, "\"kind\":\"path\",\"path\":");
        put_string(b, run->path_file);
    } else if (run->random_seed >= 0) {
        putf(b, "\"kind\":\"random\",\"seed\":%ld,\"seconds\":", run->random_seed);
        put_number(b, run->random_seconds, DOUBLE_DIGITS);
    } else {
        puts_text(b, "\"kind\":\"script\",\"path\":");
        put_string(b, run->input_path);
        puts_text(b, ",\"text\":");
        put_string(b, run->input_text ? run->input_text : "");
    }
    puts_text(b, "},\"scene\":");
    if (run->scene_path[0])
        put_string(b, run->scene_path);
    else
        puts_text(b, "null");
    put_switch(b, "distance_matching", run->distance_matching);
    put_switch(b, "warping", run->warping);
    putf(b, ",\"transition\":%s",
         run->transition_mode < 0                          ? "null"
         : run->transition_mode == MM_TRANSITION_CROSSFADE ? "\"crossfade\""
                                                           : "\"inertialize\"");
    puts_text(b, ",\"crossfade_time\":");
    if (run->crossfade_time < 0)
        puts_text(b, "null");
    else
        put_number(b, run->crossfade_time, DOUBLE_DIGITS);
    putf(b, ",\"top_k\":%d,\"tick_lines\":%s,\"terms\":[", run->top_k, run->tick_lines ? "true" : "false");
    for (int k = 0; k < MM_TRACE_TERM_COUNT; ++k) {
        if (k) puts_text(b, ",");
        put_string(b, mm_trace_term_names[k]);
    }
    puts_text(b, "]}");
}

mm_result mm_trace_write_header(FILE *out, const mm_trace_run *run, const mm_database *db)
{
    if (!out || !run || !db) return MM_ERR_INVALID_ARGUMENT;
    line_text b = {0};
    header_line(&b, run, db->dims);
    return write_line(out, &b);
}

/* A candidate's terms in mm_trace_term_names order. */
static void candidate_terms(const mm_candidate *k, float terms[MM_TRACE_TERM_COUNT])
{
    const float all[MM_TRACE_TERM_COUNT] = {
        k->terms.pose_position, k->terms.pose_velocity,  k->terms.root_velocity,
        k->terms.traj_position, k->terms.traj_direction, k->loop_favour,
        k->contact_favour,      k->next_pose_favour,     k->continuing_bias};
    memcpy(terms, all, sizeof all);
}

static void search_line(line_text *b, const mm_trace_run *run, const mm_character *c, int tick, double t,
                        bool transition)
{
    const mm_database *db = c->db;
    putf(b, "{\"type\":\"search\",\"tick\":%d,\"t\":", tick);
    put_number(b, t, DOUBLE_DIGITS);
    putf(b, ",\"frame_before\":%d,\"winner\":%d,\"transition\":%s,\"choice\":%d,\"query\":[",
         c->last_params.current_frame, c->frame, transition ? "true" : "false", c->last_choice.frame);
    for (int d = 0; d < db->dims; ++d) {
        if (d) puts_text(b, ",");
        put_number(b, c->query[d], FLOAT_DIGITS);
    }
    puts_text(b, "],\"candidates\":[");
    mm_candidate found[MM_TRACE_MAX_K];
    int k = run->top_k < 1 ? 1 : run->top_k > MM_TRACE_MAX_K ? MM_TRACE_MAX_K : run->top_k;
    int n = mm_character_candidates(c, found, k);
    for (int i = 0; i < n; ++i) {
        putf(b, "%s{\"frame\":%d,\"clip\":%d,\"cost\":", i ? "," : "", found[i].frame, found[i].clip);
        put_number(b, found[i].cost, FLOAT_DIGITS);
        puts_text(b, ",\"terms\":{");
        float terms[MM_TRACE_TERM_COUNT];
        candidate_terms(&found[i], terms);
        for (int j = 0; j < MM_TRACE_TERM_COUNT; ++j) {
            putf(b, "%s\"%s\":", j ? "," : "", mm_trace_term_names[j]);
            put_number(b, terms[j], FLOAT_DIGITS);
        }
        puts_text(b, "}}");
    }
    puts_text(b, "]}");
}

static void put_vec(line_text *b, const float *v, int n)
{
    puts_text(b, "[");
    for (int i = 0; i < n; ++i) {
        if (i) puts_text(b, ",");
        put_number(b, v[i], FLOAT_DIGITS);
    }
    puts_text(b, "]");
}

static void tick_line(line_text *b, const mm_character *c, int tick, double t)
{
    const mm_database *db = c->db;
    putf(b, "{\"type\":\"tick\",\"tick\":%d,\"t\":", tick);
    put_number(b, t, DOUBLE_DIGITS);
    putf(b, ",\"clip\":%d,\"frame\":%d,\"fraction\":", db->frame_clip[c->frame], c->frame);
    put_number(b, c->frame_fraction, DOUBLE_DIGITS);
    const float position[3] = {c->root.translation.x, c->root.translation.y, c->root.translation.z};
    const float facing[4] = {c->root.rotation.x, c->root.rotation.y, c->root.rotation.z, c->root.rotation.w};
    puts_text(b, ",\"root\":{\"position\":");
    put_vec(b, position, 3);
    puts_text(b, ",\"facing\":");
    put_vec(b, facing, 4);
    puts_text(b, "},\"feet\":[");
    unsigned label = db->contacts[c->frame];
    const unsigned heel[2] = {MM_CONTACT_LEFT_HEEL, MM_CONTACT_RIGHT_HEEL},
                   toe[2] = {MM_CONTACT_LEFT_TOE, MM_CONTACT_RIGHT_TOE};
    for (int k = 0; k < 2; ++k) {
        const float lock[3] = {c->foot_lock[k].x, c->foot_lock[k].y, c->foot_lock[k].z};
        putf(b, "%s{\"heel\":%s,\"toe\":%s,\"locked\":%s,\"lock\":", k ? "," : "",
             label & heel[k] ? "true" : "false", label & toe[k] ? "true" : "false",
             c->foot_locked[k] ? "true" : "false");
        put_vec(b, lock, 3);
        puts_text(b, "}");
    }
    puts_text(b, "]}");
}

mm_result mm_trace_write_tick(FILE *out, const mm_trace_run *run, const mm_character *c, int tick, double t,
                              int searches_before, int transitions_before)
{
    if (!out || !run || !c || !c->state) return MM_ERR_INVALID_ARGUMENT;
    mm_result r = MM_OK;
    if (c->searches != searches_before) {
        line_text b = {0};
        search_line(&b, run, c, tick, t, c->transitions != transitions_before);
        r = write_line(out, &b);
    }
    if (r == MM_OK && run->tick_lines) {
        line_text b = {0};
        tick_line(&b, c, tick, t);
        r = write_line(out, &b);
    }
    return r;
}

/* ---- reading ----------------------------------------------------------------------------- */

typedef struct reader {
    const char *file;
    long line;
    mm_error *err;
} reader;

static mm_result bad(const reader *rd, const char *fmt, ...)
{
    char message[MM_ERROR_MESSAGE_MAX];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(message, sizeof message, fmt, ap);
    va_end(ap);
    return mm_error_set(rd->err, MM_ERR_SYNTAX, (int)rd->line, 0, "%s", message);
}

/* obj[name] as a number (required); 0 and an error when missing or not a number. */
static int number(const reader *rd, const cJSON *obj, const char *name, double *out, mm_result *r)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, name);
    if (!cJSON_IsNumber(v)) {
        if (*r == MM_OK) *r = bad(rd, "%s: missing or not a number", name);
        return 0;
    }
    *out = v->valuedouble;
    return 1;
}

static int integer(const reader *rd, const cJSON *obj, const char *name, int lo, int hi, int *out,
                   mm_result *r)
{
    double v;
    if (!number(rd, obj, name, &v, r)) return 0;
    if (!(v >= lo && v <= hi) || v != floor(v)) {
        if (*r == MM_OK) *r = bad(rd, "%s: %g is not an integer in [%d, %d]", name, v, lo, hi);
        return 0;
    }
    *out = (int)v;
    return 1;
}

static int boolean(const reader *rd, const cJSON *obj, const char *name, bool *out, mm_result *r)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, name);
    if (!cJSON_IsBool(v)) {
        if (*r == MM_OK) *r = bad(rd, "%s: missing or not true/false", name);
        return 0;
    }
    *out = cJSON_IsTrue(v);
    return 1;
}

/* A switch: null (-1), false (0) or true (1). */
static void switch_of(const reader *rd, const cJSON *obj, const char *name, int *out, mm_result *r)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, name);
    if (cJSON_IsNull(v))
        *out = -1;
    else if (cJSON_IsBool(v))
        *out = cJSON_IsTrue(v) ? 1 : 0;
    else if (*r == MM_OK)
        *r = bad(rd, "%s: missing or not null, true or false", name);
}

static void string_of(const reader *rd, const cJSON *obj, const char *name, char *out, size_t size,
                      mm_result *r)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, name);
    if (!cJSON_IsString(v) || strlen(v->valuestring) >= size) {
        if (*r == MM_OK) *r = bad(rd, "%s: missing, not a string or longer than %zu", name, size - 1);
        return;
    }
    snprintf(out, size, "%s", v->valuestring);
}

static mm_result read_header(const reader *rd, const cJSON *h, mm_trace *t)
{
    mm_result r = MM_OK;
    mm_trace_run *run = &t->run;
    const cJSON *format = cJSON_GetObjectItemCaseSensitive(h, "format");
    if (!cJSON_IsString(format) || strcmp(format->valuestring, TRACE_FORMAT) != 0)
        return bad(rd, "the first line is not an %s header (format)", TRACE_FORMAT);
    int version = 0;
    if (integer(rd, h, "version", 1, MM_TRACE_VERSION, &version, &r) == 0) return r;
    const cJSON *db = cJSON_GetObjectItemCaseSensitive(h, "database");
    if (!cJSON_IsObject(db)) return bad(rd, "database: missing or not an object");
    string_of(rd, db, "path", run->db_path, sizeof run->db_path, &r);
    char checksum[32] = "";
    string_of(rd, db, "checksum", checksum, sizeof checksum, &r);
    char *end = NULL;
    run->db_checksum = strtoull(checksum, &end, 16);
    if (r == MM_OK && (strlen(checksum) != 16 || *end)) r = bad(rd, "database.checksum: not 16 hex digits");
    double bytes = 0;
    if (number(rd, db, "bytes", &bytes, &r)) run->db_size = (uint64_t)bytes;
    integer(rd, db, "frames", 0, 0x7fffffff, &run->db_frames, &r);
    integer(rd, db, "dims", 1, MM_SEARCH_MAX_DIMS, &t->dims, &r);
    if (number(rd, h, "fps", &run->fps, &r) && !(run->fps > 0.0 && run->fps <= 1000.0) && r == MM_OK)
        r = bad(rd, "fps: %g is not in (0, 1000]", run->fps);
    integer(rd, h, "ticks", 0, 0x7fffffff, &run->ticks, &r);
    const cJSON *in = cJSON_GetObjectItemCaseSensitive(h, "input");
    const cJSON *kind = cJSON_IsObject(in) ? cJSON_GetObjectItemCaseSensitive(in, "kind") : NULL;
    if (r == MM_OK && !cJSON_IsString(kind)) r = bad(rd, "input.kind: missing or not a string");
    if (r == MM_OK && strcmp(kind->valuestring, "path") == 0) {
        string_of(rd, in, "path", run->path_file, sizeof run->path_file, &r);
    } else if (r == MM_OK && strcmp(kind->valuestring, "random") == 0) {
        double seed = -1;
        if (number(rd, in, "seed", &seed, &r)) run->random_seed = (long)seed;
        number(rd, in, "seconds", &run->random_seconds, &r);
        if (r == MM_OK && (seed < 0 || seed != floor(seed))) r = bad(rd, "input.seed: not an integer >= 0");
    } else if (r == MM_OK && strcmp(kind->valuestring, "script") == 0) {
        string_of(rd, in, "path", run->input_path, sizeof run->input_path, &r);
        const cJSON *text = cJSON_GetObjectItemCaseSensitive(in, "text");
        if (r == MM_OK && !cJSON_IsString(text)) r = bad(rd, "input.text: missing or not a string");
        if (r == MM_OK) {
            size_t n = strlen(text->valuestring);
            run->input_text = (char *)malloc(n + 1);
            if (!run->input_text) return mm_error_set(rd->err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
            memcpy(run->input_text, text->valuestring, n + 1);
        }
    } else if (r == MM_OK) {
        r = bad(rd, "input.kind: \"%s\" is not script, random or path", kind->valuestring);
    }
    const cJSON *scene = cJSON_GetObjectItemCaseSensitive(h, "scene");
    if (r == MM_OK && !cJSON_IsNull(scene))
        string_of(rd, h, "scene", run->scene_path, sizeof run->scene_path, &r);
    switch_of(rd, h, "distance_matching", &run->distance_matching, &r);
    switch_of(rd, h, "warping", &run->warping, &r);
    const cJSON *tr = cJSON_GetObjectItemCaseSensitive(h, "transition");
    if (cJSON_IsNull(tr))
        run->transition_mode = -1;
    else if (cJSON_IsString(tr) && strcmp(tr->valuestring, "crossfade") == 0)
        run->transition_mode = MM_TRANSITION_CROSSFADE;
    else if (cJSON_IsString(tr) && strcmp(tr->valuestring, "inertialize") == 0)
        run->transition_mode = MM_TRANSITION_INERTIALIZE;
    else if (r == MM_OK)
        r = bad(rd, "transition: not null, \"inertialize\" or \"crossfade\"");
    const cJSON *cf = cJSON_GetObjectItemCaseSensitive(h, "crossfade_time");
    if (cJSON_IsNull(cf))
        run->crossfade_time = -1.0;
    else
        number(rd, h, "crossfade_time", &run->crossfade_time, &r);
    integer(rd, h, "top_k", 1, MM_TRACE_MAX_K, &run->top_k, &r);
    boolean(rd, h, "tick_lines", &run->tick_lines, &r);
    return r;
}

/* Grows *array (of count items of size bytes, *room of them) to hold one more. */
static int grow(void **array, int count, int *room, size_t size)
{
    if (count < *room) return 1;
    int more = *room ? *room * 2 : TRACE_INITIAL_CAP;
    void *p = realloc(*array, (size_t)more * size);
    if (!p) return 0;
    *array = p;
    *room = more;
    return 1;
}

typedef struct trace_room {
    int searches, ticks, candidates, queries, lines;
} trace_room;

static mm_result read_search(const reader *rd, const cJSON *o, const char *text, size_t size, mm_trace *t,
                             trace_room *room)
{
    mm_result r = MM_OK;
    if (!grow((void **)&t->searches, t->search_count, &room->searches, sizeof *t->searches) ||
        !grow((void **)&t->search_lines, t->search_count, &room->lines, sizeof *t->search_lines))
        return mm_error_set(rd->err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    mm_trace_search *s = &t->searches[t->search_count];
    memset(s, 0, sizeof *s);
    s->line = rd->line;
    integer(rd, o, "tick", 0, 0x7fffffff, &s->tick, &r);
    number(rd, o, "t", &s->t, &r);
    integer(rd, o, "frame_before", -1, 0x7fffffff, &s->frame_before, &r);
    integer(rd, o, "winner", -1, 0x7fffffff, &s->winner, &r);
    boolean(rd, o, "transition", &s->transition, &r);
    s->choice = MM_TRACE_NO_CHOICE; /* traces written before the field */
    if (cJSON_GetObjectItemCaseSensitive(o, "choice"))
        integer(rd, o, "choice", -1, 0x7fffffff, &s->choice, &r);
    if (r != MM_OK) return r;
    const cJSON *query = cJSON_GetObjectItemCaseSensitive(o, "query");
    if (!cJSON_IsArray(query) || cJSON_GetArraySize(query) != t->dims)
        return bad(rd, "query: not an array of %d numbers (the header's dims)", t->dims);
    int need = (t->search_count + 1) * t->dims;
    while (room->queries < need) {
        int more = room->queries ? room->queries * 2 : TRACE_INITIAL_CAP * t->dims;
        float *q = (float *)realloc(t->queries, (size_t)more * sizeof(float));
        if (!q) return mm_error_set(rd->err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
        t->queries = q, room->queries = more;
    }
    s->query_offset = t->search_count * t->dims;
    int d = 0;
    for (const cJSON *v = query->child; v; v = v->next, ++d) {
        if (!cJSON_IsNumber(v)) return bad(rd, "query[%d]: not a number", d);
        t->queries[s->query_offset + d] = (float)v->valuedouble;
    }
    const cJSON *cands = cJSON_GetObjectItemCaseSensitive(o, "candidates");
    if (!cJSON_IsArray(cands) || cJSON_GetArraySize(cands) > t->run.top_k)
        return bad(rd, "candidates: not an array of at most %d (the header's top_k)", t->run.top_k);
    s->candidate_first = t->candidate_count;
    int i = 0;
    for (const cJSON *k = cands->child; k; k = k->next, ++i) {
        if (!grow((void **)&t->candidates, t->candidate_count, &room->candidates, sizeof *t->candidates))
            return mm_error_set(rd->err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
        mm_trace_candidate *c = &t->candidates[t->candidate_count];
        double cost = 0;
        if (!cJSON_IsObject(k)) return bad(rd, "candidates[%d]: not an object", i);
        integer(rd, k, "frame", 0, 0x7fffffff, &c->frame, &r);
        integer(rd, k, "clip", 0, 0x7fffffff, &c->clip, &r);
        number(rd, k, "cost", &cost, &r);
        c->cost = (float)cost;
        const cJSON *terms = cJSON_GetObjectItemCaseSensitive(k, "terms");
        if (r == MM_OK && !cJSON_IsObject(terms))
            r = bad(rd, "candidates[%d].terms: missing or not an object", i);
        for (int j = 0; r == MM_OK && j < MM_TRACE_TERM_COUNT; ++j) {
            double v = 0;
            /* traces written before the contact favour have no such term: it was 0 */
            if (j == TRACE_CONTACT_TERM && !cJSON_GetObjectItemCaseSensitive(terms, mm_trace_term_names[j])) {
                c->terms[j] = 0.0f;
                continue;
            }
            number(rd, terms, mm_trace_term_names[j], &v, &r);
            c->terms[j] = (float)v;
        }
        if (r != MM_OK) return r;
        ++t->candidate_count;
    }
    s->candidate_count = i;
    t->search_lines[t->search_count] = (char *)malloc(size + 1);
    if (!t->search_lines[t->search_count])
        return mm_error_set(rd->err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    memcpy(t->search_lines[t->search_count], text, size);
    t->search_lines[t->search_count][size] = 0;
    ++t->search_count;
    return MM_OK;
}

static mm_result read_tick(const reader *rd, const cJSON *o, mm_trace *t, trace_room *room)
{
    mm_result r = MM_OK;
    if (!grow((void **)&t->ticks, t->tick_count, &room->ticks, sizeof *t->ticks))
        return mm_error_set(rd->err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    mm_trace_tick *k = &t->ticks[t->tick_count];
    memset(k, 0, sizeof *k);
    k->line = rd->line;
    integer(rd, o, "tick", 0, 0x7fffffff, &k->tick, &r);
    number(rd, o, "t", &k->t, &r);
    integer(rd, o, "clip", 0, 0x7fffffff, &k->clip, &r);
    integer(rd, o, "frame", 0, 0x7fffffff, &k->frame, &r);
    const cJSON *root = cJSON_GetObjectItemCaseSensitive(o, "root");
    const cJSON *p = cJSON_IsObject(root) ? cJSON_GetObjectItemCaseSensitive(root, "position") : NULL;
    const cJSON *q = cJSON_IsObject(root) ? cJSON_GetObjectItemCaseSensitive(root, "facing") : NULL;
    if (r == MM_OK && (cJSON_GetArraySize(p) != 3 || cJSON_GetArraySize(q) != 4))
        r = bad(rd, "root: needs position [x, y, z] and facing [x, y, z, w]");
    if (r != MM_OK) return r;
    float v[7];
    int n = 0;
    for (const cJSON *e = p->child; e; e = e->next) v[n++] = (float)e->valuedouble;
    for (const cJSON *e = q->child; e; e = e->next) v[n++] = (float)e->valuedouble;
    k->root.translation = mm_vec3_make(v[0], v[1], v[2]);
    k->root.rotation = (mm_quat){v[3], v[4], v[5], v[6]};
    const cJSON *feet = cJSON_GetObjectItemCaseSensitive(o, "feet");
    if (cJSON_GetArraySize(feet) != 2) return bad(rd, "feet: not an array of two");
    int f = 0;
    for (const cJSON *e = feet->child; e && r == MM_OK; e = e->next, ++f) {
        boolean(rd, e, "heel", &k->heel_contact[f], &r);
        boolean(rd, e, "toe", &k->toe_contact[f], &r);
        boolean(rd, e, "locked", &k->foot_locked[f], &r);
    }
    if (r == MM_OK) ++t->tick_count;
    return r;
}

mm_result mm_trace_read(const char *path, mm_trace *out, mm_error *err)
{
    if (!out) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "trace: nowhere to read into");
    memset(out, 0, sizeof *out);
    mm_trace_run_defaults(&out->run);
    char *text = NULL;
    size_t size = 0;
    mm_result r = mm__read_file(path, NULL, &text, &size, err);
    if (r != MM_OK) return r;
    mm__error_set_file(err, path);
    reader rd = {path, 0, err};
    trace_room room;
    memset(&room, 0, sizeof room);
    size_t at = 0;
    while (r == MM_OK && at < size) {
        size_t end = at;
        while (end < size && text[end] != '\n') ++end;
        ++rd.line;
        if (rd.line > TRACE_MAX_LINES) {
            r = bad(&rd, "more than %ld lines", TRACE_MAX_LINES);
            break;
        }
        cJSON *o = NULL;
        mm_error line_err;
        memset(&line_err, 0, sizeof line_err);
        r = mm__json_parse(text + at, end - at, &o, &line_err);
        if (r != MM_OK) {
            r = mm_error_set(err, r, (int)rd.line, line_err.column, "%s", line_err.message);
            break;
        }
        const cJSON *type = cJSON_IsObject(o) ? cJSON_GetObjectItemCaseSensitive(o, "type") : NULL;
        if (!cJSON_IsString(type))
            r = bad(&rd, "type: missing or not a string");
        else if (rd.line == 1)
            r = strcmp(type->valuestring, "header") == 0 ? read_header(&rd, o, out)
                                                         : bad(&rd, "the first line is not the header");
        else if (strcmp(type->valuestring, "search") == 0)
            r = read_search(&rd, o, text + at, end - at, out, &room);
        else if (strcmp(type->valuestring, "tick") == 0)
            r = read_tick(&rd, o, out, &room);
        else
            r = bad(&rd, "type: \"%s\" is not header, search or tick", type->valuestring);
        cJSON_Delete(o);
        at = end + 1;
    }
    if (r == MM_OK && rd.line == 0) r = mm_error_set(err, MM_ERR_UNEXPECTED_EOF, 0, 0, "the trace is empty");
    free(text);
    if (r != MM_OK) mm_trace_free(out);
    return r;
}

void mm_trace_free(mm_trace *t)
{
    if (!t) return;
    for (int i = 0; t->search_lines && i < t->search_count; ++i) free(t->search_lines[i]);
    free(t->search_lines);
    free(t->searches);
    free(t->ticks);
    free(t->candidates);
    free(t->queries);
    mm_trace_run_free(&t->run);
    memset(t, 0, sizeof *t);
}

/* ---- replay ------------------------------------------------------------------------------ */

/* The first field where a replayed search line differs from the trace's (both parsed). */
static void describe_difference(const char *traced, const char *replayed, char *message, size_t size)
{
    cJSON *a = cJSON_Parse(traced), *b = cJSON_Parse(replayed);
    snprintf(message, size, "the search line differs");
    if (a && b) {
        const char *fields[] = {"tick", "frame_before", "winner", "transition", "choice"};
        int done = 0;
        for (size_t i = 0; i < sizeof fields / sizeof fields[0] && !done; ++i) {
            const cJSON *x = cJSON_GetObjectItemCaseSensitive(a, fields[i]);
            const cJSON *y = cJSON_GetObjectItemCaseSensitive(b, fields[i]);
            if (!cJSON_Compare(x, y, 1)) {
                char *sx = cJSON_PrintUnformatted(x), *sy = cJSON_PrintUnformatted(y);
                snprintf(message, size, "%s: the trace has %s, the replay %s", fields[i], sx ? sx : "?",
                         sy ? sy : "?");
                free(sx);
                free(sy);
                done = 1;
            }
        }
        const cJSON *qa = cJSON_GetObjectItemCaseSensitive(a, "query");
        const cJSON *qb = cJSON_GetObjectItemCaseSensitive(b, "query");
        int d = 0;
        for (const cJSON *x = qa ? qa->child : NULL, *y = qb ? qb->child : NULL; !done && x && y;
             x = x->next, y = y->next, ++d)
            if (x->valuedouble != y->valuedouble) {
                snprintf(message, size, "query[%d]: the trace has %.9g, the replay %.9g", d, x->valuedouble,
                         y->valuedouble);
                done = 1;
            }
        const cJSON *ca = cJSON_GetObjectItemCaseSensitive(a, "candidates");
        const cJSON *cb = cJSON_GetObjectItemCaseSensitive(b, "candidates");
        int i = 0;
        for (const cJSON *x = ca ? ca->child : NULL, *y = cb ? cb->child : NULL; !done && x && y;
             x = x->next, y = y->next, ++i)
            if (!cJSON_Compare(x, y, 1)) {
                char *sx = cJSON_PrintUnformatted(x), *sy = cJSON_PrintUnformatted(y);
                snprintf(message, size, "candidates[%d]: the trace has %.200s, the replay %.200s", i,
                         sx ? sx : "?", sy ? sy : "?");
                free(sx);
                free(sy);
                done = 1;
            }
        if (!done && cJSON_GetArraySize(ca) != cJSON_GetArraySize(cb))
            snprintf(message, size, "candidates: the trace has %d, the replay %d", cJSON_GetArraySize(ca),
                     cJSON_GetArraySize(cb));
    }
    cJSON_Delete(a);
    cJSON_Delete(b);
}

/* The character desc of a run: the database's settings with the run's switches over them. */
static mm_result run_desc(const mm_trace_run *run, const mm_database *db, mm_character_desc *d, mm_error *err)
{
    mm_result r = mm_character_desc_from_database(d, db, err);
    if (r != MM_OK) return r;
    if (run->distance_matching >= 0) d->distance_matching = run->distance_matching != 0;
    if (run->warping >= 0) d->warping = run->warping != 0;
    if (run->transition_mode >= 0) d->transition_mode = (mm_transition_mode)run->transition_mode;
    if (run->crossfade_time >= 0)
        d->crossfade_time = run->crossfade_time > 0 ? (float)run->crossfade_time : MM_OFF;
    return MM_OK;
}

static void diverge(mm_trace_divergence *out, int tick, long line, const char *fmt, ...)
{
    if (out->diverged) return;
    out->diverged = true;
    out->tick = tick;
    out->line = line;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(out->message, sizeof out->message, fmt, ap);
    va_end(ap);
}

/* A replay going tick by tick: the run the header describes, made again. */
struct mm_trace_player {
    const mm_trace *trace;
    const mm_database *db;
    mm_input_script script;
    mm_path path;
    mm_scene scene;
    mm_searcher searcher;
    mm_character character;
    mm_moves moves;
    mm_input input; /* of the last tick */
    int tick;       /* ticks run */
    int next;       /* the trace's next search line */
    int search;     /* the trace's search of the last tick, -1 */
    float future_times[MM_MAX_TRAJ_SAMPLES];
    int future_count;
    mm_trace_divergence divergence;
};

void mm_trace_player_close(mm_trace_player *p)
{
    if (!p) return;
    mm_character_free(&p->character);
    mm_searcher_free(&p->searcher);
    mm_input_script_free(&p->script);
    mm_path_free(&p->path);
    free(p);
}

mm_result mm_trace_player_open(mm_trace_player **out, const mm_trace *t, const mm_database *db, mm_error *err)
{
    if (!out || !t || !db)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "replay: needs a trace and a database");
    *out = NULL;
    const mm_trace_run *run = &t->run;
    if (mm_trace_db_checksum(db) != run->db_checksum || (uint64_t)db->size != run->db_size ||
        db->dims != t->dims)
        return mm_error_set(
            err, MM_ERR_INVALID_ARGUMENT, 0, 0,
            "replay: the trace was made on another database (checksum %016llx, %llu bytes; this one "
            "%016llx, %llu bytes)",
            (unsigned long long)run->db_checksum, (unsigned long long)run->db_size,
            (unsigned long long)mm_trace_db_checksum(db), (unsigned long long)db->size);
    mm_trace_player *p = (mm_trace_player *)calloc(1, sizeof *p);
    if (!p) return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    p->trace = t;
    p->db = db;
    p->search = -1;
    p->divergence.tick = -1;
    mm_result r = MM_OK;
    if (run->path_file[0]) {
        r = mm_path_load_json(run->path_file, &p->path, err);
    } else if (run->random_seed >= 0) {
        mm_input_random_desc rd;
        memset(&rd, 0, sizeof rd);
        rd.seconds = (float)run->random_seconds;
        r = mm_input_script_random(&p->script, (uint64_t)run->random_seed, &rd);
        if (r != MM_OK) mm_error_set(err, r, 0, 0, "replay: cannot make the random input");
    } else {
        const char *text = run->input_text ? run->input_text : "";
        r = mm_input_script_parse_json(text, strlen(text), run->input_path, &p->script, err);
    }
    if (r == MM_OK && run->scene_path[0]) r = mm_scene_load_json(run->scene_path, &p->scene, err);
    mm_character_desc desc;
    if (r == MM_OK) r = run_desc(run, db, &desc, err);
    if (r == MM_OK) r = mm_searcher_init(&p->searcher, db, NULL, err);
    if (r == MM_OK) r = mm_character_init(&p->character, db, &p->searcher, &desc, err);
    if (r == MM_OK) r = mm_character_set_candidates(&p->character, run->top_k, err);
    if (r == MM_OK && run->scene_path[0]) mm_character_place_in_scene(&p->character, &p->scene);
    mm_moves_desc moves_desc;
    mm_moves_desc_from_database(&moves_desc, db);
    if (r == MM_OK) r = mm_moves_init(&p->moves, db, run->scene_path[0] ? &p->scene : NULL, &moves_desc, err);
    if (r != MM_OK) {
        mm_trace_player_close(p);
        return r;
    }
    p->future_count = mm_character_future_times(&p->character, p->future_times);
    *out = p;
    return MM_OK;
}

mm_result mm_trace_player_step(mm_trace_player *p, mm_error *err)
{
    if (!p) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "replay: no player");
    const mm_trace *t = p->trace;
    const mm_trace_run *run = &t->run;
    p->search = -1;
    if (p->tick >= run->ticks) return MM_ERR_INVALID_ARGUMENT; /* played out */
    int f = p->tick++;
    double fps = run->fps, time = f / fps;
    float dt = (float)(1.0 / fps);
    mm_character *c = &p->character;
    if (run->path_file[0]) { /* as mm simulate --path */
        mm_vec3 positions[MM_MAX_TRAJ_SAMPLES];
        mm_quat facings[MM_MAX_TRAJ_SAMPLES];
        mm_drive_input_path(c->trajectory, &p->path, (float)time, 0.0f, &p->input);
        mm_path_future(&p->path, (float)time + dt, p->future_times, p->future_count, c->trajectory->facing,
                       positions, facings);
        mm_character_set_future(c, positions, facings, p->future_count, NULL);
    } else {
        mm_input_script_sample_tick(&p->script, (float)time, dt, &p->input);
    }
    int searches = c->searches, transitions = c->transitions;
    mm_moves_update(&p->moves, c, &p->input, dt);
    mm_trace_divergence *out = &p->divergence;
    if (c->searches == searches) {
        /* a search the trace has here and the replay did not make */
        if (p->next < t->search_count && t->searches[p->next].tick == f)
            diverge(out, f, t->searches[p->next].line, "the trace searched at tick %d, the replay did not",
                    f);
        if (p->next < t->search_count && t->searches[p->next].tick <= f) ++p->next;
        return MM_OK;
    }
    line_text b = {0};
    search_line(&b, run, c, f, (f + 1) / fps, c->transitions != transitions);
    mm_result r = MM_OK;
    if (b.failed) {
        r = mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    } else if (p->next >= t->search_count || t->searches[p->next].tick > f) {
        diverge(out, f, p->next < t->search_count ? t->searches[p->next].line : 0,
                "the replay searched at tick %d, the trace did not", f);
    } else {
        p->search = p->next++;
        if (strcmp(b.data, t->search_lines[p->search]) != 0) {
            char message[sizeof out->message];
            describe_difference(t->search_lines[p->search], b.data, message, sizeof message);
            diverge(out, f, t->searches[p->search].line, "%s", message);
        }
    }
    free(b.data);
    return r;
}

mm_character *mm_trace_player_character(mm_trace_player *p) { return p ? &p->character : NULL; }
const mm_input *mm_trace_player_input(const mm_trace_player *p) { return p ? &p->input : NULL; }
int mm_trace_player_tick(const mm_trace_player *p) { return p ? p->tick : 0; }
int mm_trace_player_search(const mm_trace_player *p) { return p ? p->search : -1; }
const mm_trace_divergence *mm_trace_player_divergence(const mm_trace_player *p)
{
    return p ? &p->divergence : NULL;
}

mm_result mm_trace_replay(const mm_trace *t, const mm_database *db, mm_trace_divergence *out, mm_error *err)
{
    if (!out) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "replay: nowhere to say how it went");
    memset(out, 0, sizeof *out);
    out->tick = -1;
    mm_trace_player *p;
    mm_result r = mm_trace_player_open(&p, t, db, err);
    while (r == MM_OK && p->tick < t->run.ticks && !p->divergence.diverged) r = mm_trace_player_step(p, err);
    if (r == MM_OK) {
        if (!p->divergence.diverged && p->next < t->search_count)
            diverge(&p->divergence, t->searches[p->next].tick, t->searches[p->next].line,
                    "the trace searched at tick %d, after the replay's last tick", t->searches[p->next].tick);
        *out = p->divergence;
    }
    mm_trace_player_close(p);
    return r;
}
