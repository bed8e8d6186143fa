/* The viewer's debugger: recording and replaying ticks, the search's candidates, ghost poses. */
#include "view_debug.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- the recorded character ---- */

static mm_result make_character(view_sim *s, const mm_character_desc *desc, mm_error *err)
{
    mm_result r = mm_character_init(&s->character, s->db, s->searcher, desc, err);
    if (r != MM_OK) return r;
    r = mm_moves_init(&s->moves, s->db, s->scene, NULL, err);
    if (r != MM_OK) mm_character_free(&s->character);
    return r;
}

static bool grow(void **items, long *capacity, long need, size_t size)
{
    if (need <= *capacity) return true;
    long cap = *capacity ? *capacity : 1024;
    while (cap < need) cap *= 2;
    void *p = realloc(*items, (size_t)cap * size);
    if (!p) return false;
    *items = p;
    *capacity = cap;
    return true;
}

static bool record_change(view_sim *s, long tick, const mm_character_desc *desc)
{
    /* a later change at the same tick replaces the earlier one (not the desc made with) */
    if (s->change_count > 1 && s->changes[s->change_count - 1].tick == tick) {
        s->changes[s->change_count - 1].desc = *desc;
        return true;
    }
    long cap = s->change_capacity;
    if (!grow((void **)&s->changes, &cap, s->change_count + 1, sizeof *s->changes)) return false;
    s->change_capacity = (int)cap;
    s->changes[s->change_count].tick = tick;
    s->changes[s->change_count++].desc = *desc;
    return true;
}

mm_result view_sim_init(view_sim *s, const mm_database *db, const mm_searcher *searcher,
                        const mm_scene *scene, const mm_character_desc *desc, float tick, mm_error *err)
{
    memset(s, 0, sizeof *s);
    s->db = db;
    s->searcher = searcher;
    s->scene = scene;
    s->tick = tick;
    mm_result r = make_character(s, desc, err);
    if (r != MM_OK) return r;
    if (!record_change(s, 0, desc)) {
        view_sim_free(s);
        return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    }
    return MM_OK;
}

void view_sim_free(view_sim *s)
{
    if (s->db) mm_character_free(&s->character);
    free(s->inputs);
    free(s->changes);
    memset(s, 0, sizeof *s);
}

static void play(view_sim *s, const mm_input *in)
{
    mm_moves_update(&s->moves, &s->character, in, s->tick);
    ++s->now;
}

bool view_sim_step(view_sim *s, const mm_input *in)
{
    if (s->count > s->now) { /* resumed from a recorded tick: what followed it is dropped */
        s->count = s->now;
        while (s->change_count > 1 && s->changes[s->change_count - 1].tick > s->now) --s->change_count;
    }
    if (!grow((void **)&s->inputs, &s->capacity, s->count + 1, sizeof *s->inputs)) return false;
    s->inputs[s->count++] = *in;
    play(s, in);
    return true;
}

/* The desc recorded for tick (the last change at or before it): applied when it starts there. */
static void apply_changes_at(view_sim *s, long tick)
{
    for (int i = 1; i < s->change_count; ++i)
        if (s->changes[i].tick == tick) mm_character_tune(&s->character, &s->changes[i].desc);
}

bool view_sim_replay_one(view_sim *s)
{
    if (s->now >= s->count) return false;
    apply_changes_at(s, s->now);
    play(s, &s->inputs[s->now]);
    return true;
}

mm_result view_sim_seek(view_sim *s, long tick, mm_error *err)
{
    if (tick < 0) tick = 0;
    if (tick > s->count) tick = s->count;
    mm_character_free(&s->character);
    mm_result r = make_character(s, &s->changes[0].desc, err);
    if (r != MM_OK) return r;
    s->now = 0;
    while (s->now < tick) view_sim_replay_one(s);
    /* a change made at the tick sought acts from it, as when it was made */
    apply_changes_at(s, s->now);
    return MM_OK;
}

bool view_sim_tune(view_sim *s, const mm_character_desc *desc)
{
    mm_character_tune(&s->character, desc);
    return record_change(s, s->now, desc);
}

mm_result view_sim_restart(view_sim *s, const mm_character_desc *desc, mm_error *err)
{
    mm_character_free(&s->character);
    s->count = s->now = 0;
    s->change_count = 0;
    mm_result r = make_character(s, desc, err);
    if (r == MM_OK && !record_change(s, 0, desc))
        r = mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    return r;
}

/* ---- candidates ---- */

int view_candidates(const mm_character *c, int k, view_candidate *out)
{
    if (k > VIEW_MAX_CANDIDATES) k = VIEW_MAX_CANDIDATES;
    if (k < 1 || c->searches == 0 || !c->query) return 0;
    const mm_database *db = c->db;
    mm_search_result results[VIEW_MAX_CANDIDATES];
    int n = mm_searcher_search(c->searcher, c->query, &c->last_params, c->desc.method, results, k);
    for (int i = 0; i < n; ++i) {
        view_candidate *v = &out[i];
        memset(v, 0, sizeof *v);
        v->frame = results[i].frame;
        v->base = results[i].base;
        v->cost = results[i].cost;
        if (v->frame < 0 || v->frame >= db->frame_count) {
            v->clip = v->clip_frame = -1;
            continue;
        }
        v->clip = db->frame_clip[v->frame];
        v->clip_frame = v->frame - db->clips[v->clip].first_frame;
        mm_search_cost_terms(db, c->query, &c->last_params, v->frame, &v->terms);
    }
    return n;
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
