/* mm/run.h - one character run over an input script, its poses recorded into arrays: what
 * `mm simulate` does before it writes files, for tools, tests and other languages (the Python
 * package, python/). Part of mm_runtime.
 *
 * Tick f (f = 0 .. frames-1) samples the script at t = f / fps (mm_input_script_sample_tick),
 * runs the move layer around the character (mm_moves_update: on flat ground without a scene) for
 * 1 / fps seconds and records the pose after it. The same database, script, fps and character
 * desc give the same bits as `mm simulate` (the character starts at the origin facing +Z).
 *
 *   mm_run_output out = {.world_positions = world};   // frames x joint_count x 3 floats
 *   mm_run_script(&db, &script, frames, NULL, &out, &err);
 *
 * mm_run_path runs the character along a desired path instead (mm/drive.h: mm_drive_input_path
 * at t = f / fps), as `mm simulate --path` does.
 *
 * Functions: mm_run_frames mm_run_script mm_run_path
 */
#ifndef MM_RUN_H
#define MM_RUN_H

#include <stdint.h>

#include "alloc.h"
#include "character.h"
#include "database.h"
#include "drive.h"
#include "input.h"
#include "result.h"
#include "scene.h"

#ifdef __cplusplus
extern "C" {
#endif

#define MM_RUN_DEFAULT_FPS 60.0f

typedef struct mm_run_desc {
    float fps;                          /* ticks per second; 0: MM_RUN_DEFAULT_FPS */
    const mm_character_desc *character; /* NULL: the database's settings (mm_character_desc_from_database) */
    const mm_scene *scene;              /* NULL: flat ground (the move layer has no obstacle to use);
                                           its walls stop the character (mm_character_set_walls) */
    const mm_allocator *allocator;      /* the searcher's and the character's memory; NULL: malloc */
} mm_run_desc;

/* Where the run writes, frame after frame: arrays the caller owns, each NULL (not recorded) or of
 * the size given; joint order and joint 0 (the simulation root, on the ground) as in the database. */
typedef struct mm_run_output {
    float *world_positions; /* [frames][joint_count][3]: x y z, metres, world */
    float *world_rotations; /* [frames][joint_count][4]: x y z w, world */
    float *local_positions; /* [frames][joint_count][3]: relative to the parent (joint 0: world) */
    float *local_rotations; /* [frames][joint_count][4]: x y z w, relative to the parent */
    int32_t *db_frames;     /* [frames]: the database frame playing */
    /* written by the run */
    int searches, transitions;
} mm_run_output;

/* The number of ticks in `seconds` at `fps` (as mm simulate counts them): floor(seconds * fps). */
int mm_run_frames(double seconds, double fps);

/* Runs a character of db over script for `frames` ticks, recording into out (desc may be NULL).
 * Allocates a searcher and a character at the start and frees them at the end; nothing per tick.
 * MM_ERR_INVALID_ARGUMENT without db, script or out, or with frames < 0 or a non-positive fps. */
mm_result mm_run_script(const mm_database *db, const mm_input_script *script, int frames,
                        const mm_run_desc *desc, mm_run_output *out, mm_error *err);

/* The same along path (mm_path_validate'd: MM_ERR_INVALID_ARGUMENT naming the point otherwise). */
mm_result mm_run_path(const mm_database *db, const mm_path *path, int frames, const mm_run_desc *desc,
                      mm_run_output *out, mm_error *err);

#ifdef __cplusplus
}
#endif

#endif /* MM_RUN_H */
