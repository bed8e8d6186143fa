/* One character run over an input script, its poses recorded (mm/run.h). */
#include "mm/run.h"

#include <math.h>
#include <string.h>

#include "mm/drive.h"
#include "mm/moves.h"
#include "mm/search.h"

int mm_run_frames(double seconds, double fps)
{
    double n = floor(seconds * fps + 1e-6); /* the tolerance: 2 s at 60 fps is 120 ticks, not 119 */
    return n > 0 && n < 2147483647.0 ? (int)n : 0;
}

/* The pose of c into frame f of out. */
static void record(const mm_character *c, int f, mm_run_output *out)
{
    int n = c->db->joint_count;
    size_t base3 = (size_t)f * (size_t)n * 3, base4 = (size_t)f * (size_t)n * 4;
    for (int j = 0; j < n; ++j) {
        const mm_xform *g = &c->global[j];
        const mm_quat *lr = &c->local_rotations[j];
        const mm_vec3 *lp = &c->local_positions[j];
        if (out->world_positions) {
            float *p = out->world_positions + base3 + (size_t)j * 3;
            p[0] = g->translation.x, p[1] = g->translation.y, p[2] = g->translation.z;
        }
        if (out->world_rotations) {
            float *q = out->world_rotations + base4 + (size_t)j * 4;
            q[0] = g->rotation.x, q[1] = g->rotation.y, q[2] = g->rotation.z, q[3] = g->rotation.w;
        }
        if (out->local_positions) {
            float *p = out->local_positions + base3 + (size_t)j * 3;
            p[0] = lp->x, p[1] = lp->y, p[2] = lp->z;
        }
        if (out->local_rotations) {
            float *q = out->local_rotations + base4 + (size_t)j * 4;
            q[0] = lr->x, q[1] = lr->y, q[2] = lr->z, q[3] = lr->w;
        }
    }
    if (out->db_frames) out->db_frames[f] = c->frame;
}

/* The run over a script or along a path (one of them). */
static mm_result run(const mm_database *db, const mm_input_script *script, const mm_path *path, int frames,
                     const mm_run_desc *desc, mm_run_output *out, mm_error *err)
{
    float fps = desc && desc->fps != 0.0f ? desc->fps : MM_RUN_DEFAULT_FPS;
    if (!db || (!script && !path) || !out || frames < 0 || !(fps > 0.0f) || !isfinite(fps))
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0,
                            "%s: needs a database, a %s, an output, frames >= 0 and fps > 0",
                            path ? "mm_run_path" : "mm_run_script", path ? "path" : "script");
    if (path && mm_path_validate(path, err) != MM_OK) return MM_ERR_INVALID_ARGUMENT;
    out->searches = out->transitions = 0;
    const mm_allocator *allocator = desc ? desc->allocator : NULL;
    mm_character_desc cd;
    mm_result r = MM_OK;
    if (desc && desc->character)
        cd = *desc->character;
    else
        r = mm_character_desc_from_database(&cd, db, err);
    if (r != MM_OK) return r;
    if (!cd.allocator) cd.allocator = allocator;
    mm_searcher_desc sd;
    memset(&sd, 0, sizeof sd);
    sd.allocator = allocator;
    mm_searcher searcher;
    r = mm_searcher_init(&searcher, db, &sd, err);
    if (r != MM_OK) return r;
    mm_character c;
    r = mm_character_init(&c, db, &searcher, &cd, err);
    if (r != MM_OK) {
        mm_searcher_free(&searcher);
        return r;
    }
    mm_moves moves;
    mm_moves_desc moves_desc;
    mm_moves_desc_from_database(&moves_desc, db);
    r = mm_moves_init(&moves, db, desc ? desc->scene : NULL, &moves_desc, err);
    if (desc && desc->scene) mm_character_place_in_scene(&c, desc->scene);
    if (r == MM_OK) {
        float dt = (float)(1.0 / fps);
        float times[MM_MAX_TRAJ_SAMPLES];
        int future_count = mm_character_future_times(&c, times);
        for (int f = 0; f < frames; ++f) {
            mm_input in;
            if (path) {
                /* steered along the path, and the path itself the future the search matches */
                float t = (float)(f / (double)fps);
                mm_vec3 positions[MM_MAX_TRAJ_SAMPLES];
                mm_quat facings[MM_MAX_TRAJ_SAMPLES];
                mm_drive_input_path(c.trajectory, path, t, 0.0f, &in);
                mm_path_future(path, t + dt, times, future_count, c.trajectory->facing, positions, facings);
                mm_character_set_future(&c, positions, facings, future_count, NULL);
            } else
                mm_input_script_sample_tick(script, (float)(f / (double)fps), dt, &in);
            mm_moves_update(&moves, &c, &in, dt);
            record(&c, f, out);
        }
        out->searches = c.searches;
        out->transitions = c.transitions;
    }
    mm_character_free(&c);
    mm_searcher_free(&searcher);
    return r;
}

mm_result mm_run_script(const mm_database *db, const mm_input_script *script, int frames,
                        const mm_run_desc *desc, mm_run_output *out, mm_error *err)
{
    return run(db, script, NULL, frames, desc, out, err);
}

mm_result mm_run_path(const mm_database *db, const mm_path *path, int frames, const mm_run_desc *desc,
                      mm_run_output *out, mm_error *err)
{
    return run(db, NULL, path, frames, desc, out, err);
}
