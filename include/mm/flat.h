/* mm/flat.h - the flat API: mm for foreign-function interfaces (Python's ctypes, the python/
 * package; C#'s P/Invoke; Lua's FFI). No struct crosses it: a database is an opaque handle,
 * everything else is a number, a string or a caller-owned array, and an error is a result code
 * (mm/result.h; 0 is MM_OK) with its message written into the caller's buffer. Part of mm_build
 * (it reads JSON input scripts and builds databases); each function is a thin wrapper over the C
 * API named in its comment.
 *
 *   mm_database *db = mm_flat_database_load("x.mmdb", msg, sizeof msg);
 *   int frames = mm_run_frames(10.0, 60.0), joints = mm_flat_database_count(db, MM_FLAT_JOINTS);
 *   float *world = malloc(sizeof(float) * frames * joints * 3);
 *   mm_flat_simulate(db, NULL, 7, 10.0, 60.0, world, NULL, NULL, NULL, NULL, msg, sizeof msg);
 *   mm_flat_database_free(db);
 *
 * Functions: mm_flat_database_load mm_flat_database_free mm_flat_database_count
 *            mm_flat_database_interval mm_flat_joint mm_flat_clip mm_flat_tag_name mm_flat_group
 *            mm_flat_features mm_flat_frame_clips mm_flat_search mm_flat_simulate mm_flat_build
 */
#ifndef MM_FLAT_H
#define MM_FLAT_H

#include <stddef.h>
#include <stdint.h>

#include "database.h"

#ifdef __cplusplus
extern "C" {
#endif

/* What mm_flat_database_count counts. */
typedef enum mm_flat_count {
    MM_FLAT_FRAMES = 0,
    MM_FLAT_JOINTS = 1,
    MM_FLAT_CLIPS = 2,
    MM_FLAT_TAGS = 3,
    MM_FLAT_GROUPS = 4, /* feature groups */
    MM_FLAT_DIMS = 5,   /* feature dimensions (unpadded) */
} mm_flat_count;

/* mm_database_load (mapped, checksum verified): a database on the heap, or NULL with the error
 * ("file: message") in message. */
mm_database *mm_flat_database_load(const char *path, char *message, size_t message_size);
void mm_flat_database_free(mm_database *db);

/* A count of the database; -1 for an unknown `what`. */
int mm_flat_database_count(const mm_database *db, int what);
/* Seconds per frame. */
float mm_flat_database_interval(const mm_database *db);

/* Joint j's name (NULL when out of range) and parent (-1 for the root). */
const char *mm_flat_joint(const mm_database *db, int j, int *parent);
/* Clip i's name (NULL when out of range), first frame, frame count, type (mm_clip_type) and
 * whether it loops. */
const char *mm_flat_clip(const mm_database *db, int i, int *first_frame, int *frame_count, int *type,
                         int *loop);
/* Tag i's name, NULL when out of range. */
const char *mm_flat_tag_name(const mm_database *db, int i);
/* Feature group i's name (NULL when out of range; "LeftFoot.position"), first dimension, number
 * of dimensions and default weight. */
const char *mm_flat_group(const mm_database *db, int i, int *offset, int *dims, float *weight);

/* The features of every frame into out ([frames][dims], unpadded): normalised as the search sees
 * them (raw 0), or raw (raw 1: in metres, m/s and unit directions of the character frame). */
void mm_flat_features(const mm_database *db, int raw, float *out);
/* Each frame's clip, next frame (-1 at the end of a clip that does not loop) and tag bits. */
void mm_flat_frame_clips(const mm_database *db, int32_t *clip, int32_t *next, uint64_t *tags);

/* mm_searcher_search with the database's default parameters (mm_search_params_defaults) and
 * current_frame (-1: none): the best k frames for query (dims normalised features, unpadded)
 * into frames[k] and costs[k] (what is minimised), and when terms is not NULL their five cost
 * terms into terms[k][5] (pose_position, pose_velocity, root_velocity, traj_position,
 * traj_direction: mm_search_cost_terms; they sum to the base cost). Brute force (method 1), the
 * tree (0) or the facing pre-filter (2). Returns the number found, or a negative mm_result. */
int mm_flat_search(const mm_database *db, const float *query, int current_frame, int method, int k,
                   int32_t *frames, float *costs, float *terms, char *message, size_t message_size);

/* mm_run_script (mm/run.h) over the input script in script_path (JSON, mm/input_json.h) or, when
 * script_path is NULL, a random script of `seconds` from seed (mm_input_script_random, as
 * `mm simulate --random SEED --seconds T`), for mm_run_frames(seconds, fps) ticks; any output
 * array may be NULL. */
int mm_flat_simulate(const mm_database *db, const char *script_path, uint64_t seed, double seconds,
                     double fps, float *world_positions, float *world_rotations, float *local_positions,
                     float *local_rotations, int32_t *db_frames, char *message, size_t message_size);

/* `mm db build CONFIG --data DATA_DIR -o OUT` (mm_config_load_json, mm_config_load_sources,
 * mm_database_build, mm_database_save): data_dir may be NULL (the config's own), threads 0 or 1
 * the calling thread alone. */
int mm_flat_build(const char *config_path, const char *data_dir, const char *out_path, int threads,
                  char *message, size_t message_size);

#ifdef __cplusplus
}
#endif

#endif /* MM_FLAT_H */
