/* The flat API for foreign-function interfaces (mm/flat.h): thin wrappers, no logic of their own. */
#include "mm/flat.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mm/config.h"
#include "mm/config_json.h"
#include "mm/database_build.h"
#include "mm/input_json.h"
#include "mm/path_json.h"
#include "mm/run.h"
#include "mm/search.h"

/* err's code, its message into the caller's buffer */
static int report(const mm_error *err, mm_result r, char *message, size_t size)
{
    if (message && size) {
        if (err && err->message[0])
            mm_error_format(err, message, size);
        else
            snprintf(message, size, "%s", mm_result_str(r));
    }
    return (int)r;
}

static void clear(mm_error *err, char *message, size_t size)
{
    memset(err, 0, sizeof *err);
    if (message && size) message[0] = '\0';
}

mm_database *mm_flat_database_load(const char *path, char *message, size_t message_size)
{
    mm_error err;
    clear(&err, message, message_size);
    mm_database *db = malloc(sizeof *db);
    if (!db) {
        report(NULL, MM_ERR_OUT_OF_MEMORY, message, message_size);
        return NULL;
    }
    mm_result r = path ? mm_database_load(path, NULL, db, &err) : MM_ERR_INVALID_ARGUMENT;
    if (r != MM_OK) {
        report(&err, r, message, message_size);
        free(db);
        return NULL;
    }
    return db;
}

void mm_flat_database_free(mm_database *db)
{
    if (!db) return;
    mm_database_free(db);
    free(db);
}

int mm_flat_database_count(const mm_database *db, int what)
{
    switch (what) {
    case MM_FLAT_FRAMES:
        return db->frame_count;
    case MM_FLAT_JOINTS:
        return db->joint_count;
    case MM_FLAT_CLIPS:
        return db->clip_count;
    case MM_FLAT_TAGS:
        return db->tag_count;
    case MM_FLAT_GROUPS:
        return db->group_count;
    case MM_FLAT_DIMS:
        return db->dims;
    default:
        return -1;
    }
}

float mm_flat_database_interval(const mm_database *db) { return db->interval; }

const char *mm_flat_joint(const mm_database *db, int j, int *parent)
{
    if (j < 0 || j >= db->joint_count) return NULL;
    if (parent) *parent = db->joints[j].parent;
    return db->joints[j].name;
}

const char *mm_flat_clip(const mm_database *db, int i, int *first_frame, int *frame_count, int *type,
                         int *loop)
{
    if (i < 0 || i >= db->clip_count) return NULL;
    const mm_db_clip *c = &db->clips[i];
    if (first_frame) *first_frame = c->first_frame;
    if (frame_count) *frame_count = c->frame_count;
    if (type) *type = c->type;
    if (loop) *loop = c->loop;
    return c->name;
}

const char *mm_flat_tag_name(const mm_database *db, int i)
{
    return i >= 0 && i < db->tag_count ? db->tag_names[i] : NULL;
}

const char *mm_flat_group(const mm_database *db, int i, int *offset, int *dims, float *weight)
{
    if (i < 0 || i >= db->group_count) return NULL;
    const mm_feature_group *g = &db->groups[i];
    if (offset) *offset = g->offset;
    if (dims) *dims = g->dims;
    if (weight) *weight = g->weight;
    return g->name;
}

void mm_flat_features(const mm_database *db, int raw, float *out)
{
    for (int f = 0; f < db->frame_count; ++f)
        for (int d = 0; d < db->dims; ++d)
            out[(size_t)f * (size_t)db->dims + (size_t)d] =
                raw ? mm_database_feature_raw(db, f, d)
                    : db->features[(size_t)f * (size_t)db->dims_padded + (size_t)d];
}

void mm_flat_frame_clips(const mm_database *db, int32_t *clip, int32_t *next, uint64_t *tags)
{
    size_t n = (size_t)db->frame_count;
    if (clip) memcpy(clip, db->frame_clip, n * sizeof *clip);
    if (next) memcpy(next, db->frame_next, n * sizeof *next);
    if (tags) memcpy(tags, db->frame_tags, n * sizeof *tags);
}

int mm_flat_search(const mm_database *db, const float *query, int current_frame, int method, int k,
                   int32_t *frames, float *costs, float *terms, char *message, size_t message_size)
{
    mm_error err;
    clear(&err, message, message_size);
    if (!db || !query || k < 1 || !frames || method < MM_SEARCH_FAST || method > MM_SEARCH_FACING ||
        current_frame < -1 || current_frame >= db->frame_count)
        return -report(NULL, MM_ERR_INVALID_ARGUMENT, message, message_size);
    float *padded = calloc((size_t)db->dims_padded, sizeof *padded);
    mm_search_result *results = calloc((size_t)k, sizeof *results);
    mm_searcher searcher;
    mm_result r = padded && results ? mm_searcher_init(&searcher, db, NULL, &err) : MM_ERR_OUT_OF_MEMORY;
    int found = 0;
    if (r == MM_OK) {
        memcpy(padded, query, sizeof(float) * (size_t)db->dims);
        mm_search_params p;
        mm_search_params_defaults(db, &p);
        p.current_frame = current_frame;
        found = mm_searcher_search(&searcher, padded, &p, (mm_search_method)method, results, k);
        for (int i = 0; i < k; ++i) {
            frames[i] = results[i].frame;
            if (costs) costs[i] = results[i].cost;
            if (!terms) continue;
            mm_search_terms t;
            memset(&t, 0, sizeof t);
            if (results[i].frame >= 0) mm_search_cost_terms(db, padded, &p, results[i].frame, &t);
            float *row = terms + (size_t)i * 5;
            row[0] = t.pose_position, row[1] = t.pose_velocity, row[2] = t.root_velocity;
            row[3] = t.traj_position, row[4] = t.traj_direction;
        }
        mm_searcher_free(&searcher);
    }
    free(results);
    free(padded);
    return r == MM_OK ? found : -report(&err, r, message, message_size);
}

/* The caller's arrays as a run's output (any may be NULL). */
static mm_run_output run_output(float *world_positions, float *world_rotations, float *local_positions,
                                float *local_rotations, int32_t *db_frames)
{
    mm_run_output out = {.world_positions = world_positions,
                         .world_rotations = world_rotations,
                         .local_positions = local_positions,
                         .local_rotations = local_rotations,
                         .db_frames = db_frames};
    return out;
}

int mm_flat_simulate(const mm_database *db, const char *script_path, uint64_t seed, double seconds,
                     double fps, float *world_positions, float *world_rotations, float *local_positions,
                     float *local_rotations, int32_t *db_frames, char *message, size_t message_size)
{
    mm_error err;
    clear(&err, message, message_size);
    if (!db || !(seconds > 0) || !(fps > 0))
        return report(NULL, MM_ERR_INVALID_ARGUMENT, message, message_size);
    mm_input_script script;
    mm_result r;
    if (script_path) {
        r = mm_input_script_load_json(script_path, &script, &err);
    } else {
        mm_input_random_desc rd;
        memset(&rd, 0, sizeof rd);
        rd.seconds = (float)seconds;
        r = mm_input_script_random(&script, seed, &rd);
    }
    if (r != MM_OK) return report(&err, r, message, message_size);
    mm_run_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.fps = (float)fps;
    mm_run_output out =
        run_output(world_positions, world_rotations, local_positions, local_rotations, db_frames);
    r = mm_run_script(db, &script, mm_run_frames(seconds, fps), &desc, &out, &err);
    mm_input_script_free(&script);
    return r == MM_OK ? 0 : report(&err, r, message, message_size);
}

int mm_flat_simulate_path(const mm_database *db, const char *path_file, double seconds, double fps,
                          float *world_positions, float *world_rotations, float *local_positions,
                          float *local_rotations, int32_t *db_frames, char *message, size_t message_size)
{
    mm_error err;
    clear(&err, message, message_size);
    if (!db || !path_file || !(seconds > 0) || !(fps > 0))
        return report(NULL, MM_ERR_INVALID_ARGUMENT, message, message_size);
    mm_path path;
    mm_result r = mm_path_load_json(path_file, &path, &err);
    if (r != MM_OK) return report(&err, r, message, message_size);
    mm_run_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.fps = (float)fps;
    mm_run_output out =
        run_output(world_positions, world_rotations, local_positions, local_rotations, db_frames);
    r = mm_run_path(db, &path, mm_run_frames(seconds, fps), &desc, &out, &err);
    mm_path_free(&path);
    return r == MM_OK ? 0 : report(&err, r, message, message_size);
}

int mm_flat_build(const char *config_path, const char *data_dir, const char *out_path, int threads,
                  char *message, size_t message_size)
{
    mm_error err;
    clear(&err, message, message_size);
    if (!config_path || !out_path || threads < 0 || threads > MM_DB_MAX_THREADS)
        return report(NULL, MM_ERR_INVALID_ARGUMENT, message, message_size);
    mm_config config;
    memset(&config, 0, sizeof config);
    char *text = NULL;
    mm_result r = mm_config_load_json(config_path, &config, &text, &err);
    if (r != MM_OK) return report(&err, r, message, message_size);
    if (data_dir) snprintf(config.data_dir, sizeof config.data_dir, "%s", data_dir);
    mm_clip *sources = NULL;
    r = mm_config_load_sources(&config, &sources, &err);
    if (r == MM_OK) {
        mm_db_build_desc desc;
        memset(&desc, 0, sizeof desc);
        desc.config_json = text;
        desc.threads = threads;
        mm_database db;
        snprintf(err.file, sizeof err.file, "%s", config_path);
        r = mm_database_build(&config, sources, &desc, &db, &err);
        mm_config_free_sources(&config, sources);
        if (r == MM_OK) {
            r = mm_database_save(&db, out_path, &err);
            mm_database_free(&db);
        }
    }
    mm_config_free(&config);
    free(text);
    return r == MM_OK ? 0 : report(&err, r, message, message_size);
}
