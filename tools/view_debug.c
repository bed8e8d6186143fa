/* The viewer's debugger: recording and replaying ticks, the search's candidates, ghost poses. */
#include "view_debug.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- the recorded character ---- */

/* The move layer and the recorder of a character just made. */
static mm_result attach(view_sim *s, mm_error *err)
{
    mm_result r = mm_moves_init(&s->moves, s->db, s->scene, NULL, err);
    int capacity = s->recorder.capacity;
    size_t bytes = mm_recorder_bytes(&s->character, capacity, s->candidates);
    if (r == MM_OK && bytes > s->memory_bytes) { /* a character of another layout (the mixer's) */
        void *more = realloc(s->memory, bytes);
        if (!more) r = mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory for the recorder");
        if (more) s->memory = more, s->memory_bytes = bytes;
    }
    if (r == MM_OK)
        r = mm_recorder_init(&s->recorder, s->memory, bytes, &s->character, capacity, s->candidates, err);
    if (r != MM_OK) mm_character_free(&s->character);
    s->now = 0;
    s->looking_back = s->diverged = false;
    return r;
}

mm_result view_sim_init(view_sim *s, const mm_database *db, const mm_searcher *searcher,
                        const mm_scene *scene, const mm_character_desc *desc, float tick, double seconds,
                        size_t max_bytes, int candidates, mm_error *err)
{
    memset(s, 0, sizeof *s);
    s->db = db;
    s->searcher = searcher;
    s->scene = scene;
    s->tick = tick;
    s->candidates = candidates;
    mm_result r = mm_character_init(&s->character, db, searcher, desc, err);
    if (r != MM_OK) return r;
    mm_character_place_in_scene(&s->character, scene);
    /* as many ticks as asked for, within max_bytes */
    size_t per_tick =
        mm_recorder_bytes(&s->character, 2, candidates) - mm_recorder_bytes(&s->character, 1, candidates);
    if (scene) per_tick += sizeof(mm_moves);
    double ticks = fmin(seconds / tick, (double)max_bytes / (double)(per_tick > 0 ? per_tick : 1));
    int capacity = ticks < 1.0 ? 1 : (int)ticks;
    s->recorder.capacity = capacity;
    s->memory_bytes = mm_recorder_bytes(&s->character, capacity, candidates);
    s->memory = malloc(s->memory_bytes);
    s->history = scene ? malloc(sizeof(mm_moves) * (size_t)capacity) : NULL;
    if (!s->memory || (scene && !s->history)) {
        mm_character_free(&s->character);
        r = mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory for %d recorded ticks", capacity);
    } else {
        r = attach(s, err);
    }
    if (r != MM_OK) {
        free(s->memory);
        free(s->history);
        memset(s, 0, sizeof *s);
    }
    return r;
}

void view_sim_free(view_sim *s)
{
    if (s->db) mm_character_free(&s->character);
    free(s->memory);
    free(s->history);
    memset(s, 0, sizeof *s);
}

void view_sim_range(const view_sim *s, int64_t *first, int64_t *last)
{
    int64_t oldest = mm_recorder_oldest(&s->recorder), newest = mm_recorder_newest(&s->recorder);
    *first = oldest < 0 ? 0 : oldest + 1;
    *last = newest < 0 ? 0 : newest + 1;
}

void view_sim_step(view_sim *s, const mm_input *in, const mm_character_desc *desc)
{
    if (s->looking_back) { /* the run resumes from the tick shown, as tuned now */
        int index = mm_recorder_index(&s->recorder, s->now - 1);
        if (index >= 0) mm_recorder_truncate(&s->recorder, index);
        mm_character_tune(&s->character, desc);
        s->looking_back = s->diverged = false;
    }
    mm_moves_update(&s->moves, &s->character, in, s->tick);
    mm_recorder_record(&s->recorder, &s->character, in, s->tick);
    if (s->history) s->history[(s->recorder.recorded - 1) % s->recorder.capacity] = s->moves;
    ++s->now;
}

void view_sim_forward(view_sim *s, const mm_input *in, const mm_character_desc *desc)
{
    int64_t first, last;
    view_sim_range(s, &first, &last);
    if (s->looking_back && s->now < last) {
        /* the tick after the one shown: gone to as recorded, or run again with its input */
        const mm_recorded_tick *t = mm_recorder_tick(&s->recorder, mm_recorder_index(&s->recorder, s->now));
        if (t && !s->diverged) {
            view_sim_seek(s, s->now + 1, NULL);
            return;
        }
        if (t) {
            mm_input recorded = t->input;
            view_sim_step(s, &recorded, desc);
            return;
        }
    }
    view_sim_step(s, in, desc);
}

mm_result view_sim_seek(view_sim *s, int64_t tick, mm_error *err)
{
    int64_t first, last;
    view_sim_range(s, &first, &last);
    if (last == 0) return MM_OK; /* nothing recorded yet */
    tick = tick < first ? first : tick > last ? last : tick;
    int index = mm_recorder_index(&s->recorder, tick - 1);
    mm_result r = mm_recorder_restore(&s->recorder, index, &s->character, err);
    if (r != MM_OK) return r;
    if (s->history) s->moves = s->history[(tick - 1) % s->recorder.capacity];
    s->now = tick;
    s->looking_back = tick < last;
    s->diverged = false;
    return MM_OK;
}

void view_sim_tune(view_sim *s, const mm_character_desc *desc)
{
    mm_character_tune(&s->character, desc);
    if (s->looking_back) s->diverged = true;
}

mm_result view_sim_restart(view_sim *s, const mm_character_desc *desc, mm_error *err)
{
    mm_character_free(&s->character);
    mm_result r = mm_character_init(&s->character, s->db, s->searcher, desc, err);
    if (r == MM_OK) mm_character_place_in_scene(&s->character, s->scene);
    return r == MM_OK ? attach(s, err) : r;
}

mm_input view_sim_input(const view_sim *s)
{
    const mm_recorded_tick *t = mm_recorder_tick(&s->recorder, mm_recorder_index(&s->recorder, s->now - 1));
    mm_input none;
    memset(&none, 0, sizeof none);
    return t ? t->input : none;
}

/* ---- ghosts ---- */

void view_ghost_pose(const mm_database *db, int frame, mm_xform anchor, mm_xform *global)
{
    size_t row = (size_t)frame * (size_t)db->joint_count;
    global[0] = anchor;
    for (int j = 1; j < db->joint_count; ++j) {
        mm_xform local = mm_xform_make(db->rotations[row + (size_t)j], db->positions[row + (size_t)j]);
        int p = db->joints[j].parent;
        global[j] = p >= 0 && p < j ? mm_xform_mul(global[p], local) : mm_xform_mul(anchor, local);
    }
}

void view_ghost_lines(const mm_database *db, const mm_xform *global, mm_rgba color, mm_render_line *lines,
                      int *count, int capacity)
{
    for (int j = 2; j < db->joint_count && *count < capacity; ++j) {
        int p = db->joints[j].parent;
        if (p < 1) continue; /* joint 0 is the simulation bone on the ground */
        mm_render_line *l = &lines[(*count)++];
        l->a = global[p].translation;
        l->b = global[j].translation;
        l->color = color;
    }
}

void view_preview_start(view_preview *p, int frame)
{
    p->start = p->frame = frame;
    p->time = 0.0;
}

void view_preview_advance(view_preview *p, const mm_database *db, double dt)
{
    if (p->frame < 0 || p->frame >= db->frame_count || !(dt > 0.0)) return;
    p->time += dt;
    while (p->time >= db->interval) {
        p->time -= db->interval;
        int next = db->frame_next[p->frame];
        p->frame = next >= 0 ? next : p->start;
    }
}
