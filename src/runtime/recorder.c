/* The last N ticks of a character, in the caller's memory (mm/recorder.h). */
#include <mm/recorder.h>

#include <string.h>

#include "character/state.h"

/* bytes: every array of the recorder starts on a multiple of this */
#define RECORDER_ALIGN 16

/* The next `bytes` of the recorder's memory (base NULL: only counted), at offset *at. */
static void *carve(unsigned char *base, size_t *at, size_t bytes)
{
    void *p = base ? base + *at : NULL;
    *at += (bytes + RECORDER_ALIGN - 1) / RECORDER_ALIGN * RECORDER_ALIGN;
    return p;
}

/* Candidates a character keeps for top_k asked (mm_character_set_candidates: 1 keeps no room). */
static int kept_candidates(int top_k) { return top_k > 1 ? top_k : 0; }

/* The snapshot bytes of c once it keeps top_k candidates. */
static size_t snapshot_bytes_with(const mm_character *c, int top_k)
{
    size_t now = mm_character_snapshot_bytes(c);
    int have = c->state->matching.candidate_capacity, want = kept_candidates(top_k);
    if (top_k < 1) want = have; /* not asked: the character keeps what it has */
    return now - (size_t)have * sizeof(mm_search_result) + (size_t)want * sizeof(mm_search_result);
}

/* Lays out (base NULL: measures) the recorder's arrays; the snapshots' slots are whole multiples
 * of RECORDER_ALIGN. Returns the bytes used. */
static size_t lay_out(mm_recorder *rec, unsigned char *base, int ticks, int top_k, int joints, int dims,
                      size_t snapshot_bytes)
{
    size_t at = 0, n = (size_t)ticks;
    mm_recorded_tick *t = (mm_recorded_tick *)carve(base, &at, n * sizeof(mm_recorded_tick));
    float *q = (float *)carve(base, &at, n * (size_t)dims * sizeof(float));
    mm_candidate *k = (mm_candidate *)carve(base, &at, n * (size_t)top_k * sizeof(mm_candidate));
    mm_xform *p = (mm_xform *)carve(base, &at, n * (size_t)joints * sizeof(mm_xform));
    unsigned char *s = (unsigned char *)carve(base, &at, n * snapshot_bytes);
    if (rec) rec->ticks = t, rec->queries = q, rec->candidates = k, rec->poses = p, rec->snapshots = s;
    return at;
}

size_t mm_recorder_bytes(const mm_character *c, int ticks, int top_k)
{
    if (!c || !c->state || !c->db || ticks < 1 || top_k < 0 || top_k > MM_RECORDER_MAX_CANDIDATES) return 0;
    return lay_out(NULL, NULL, ticks, top_k, c->db->joint_count, c->db->dims_padded,
                   snapshot_bytes_with(c, top_k)) +
           RECORDER_ALIGN; /* room to align the caller's memory */
}

mm_result mm_recorder_init(mm_recorder *rec, void *memory, size_t bytes, mm_character *c, int ticks,
                           int top_k, mm_error *err)
{
    if (!rec) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "recorder: none given");
    memset(rec, 0, sizeof *rec);
    size_t need = mm_recorder_bytes(c, ticks, top_k);
    if (!need || !memory || bytes < need)
        return mm_error_set(
            err, MM_ERR_INVALID_ARGUMENT, 0, 0,
            "recorder: needs a character, ticks >= 1, top_k in [0, %d] and %zu bytes (%zu given)",
            MM_RECORDER_MAX_CANDIDATES, need, bytes);
    if (top_k >= 1) {
        mm_result r = mm_character_set_candidates(c, top_k, err);
        if (r != MM_OK) return r;
    }
    const mm_database *db = c->db;
    rec->db = db;
    rec->capacity = ticks;
    rec->top_k = top_k;
    rec->snapshot_bytes = mm_character_snapshot_bytes(c);
    unsigned char *base = (unsigned char *)memory;
    size_t misalign = (size_t)((uintptr_t)base % RECORDER_ALIGN);
    if (misalign) base += RECORDER_ALIGN - misalign;
    lay_out(rec, base, ticks, top_k, db->joint_count, db->dims_padded, rec->snapshot_bytes);
    mm_pose_data pd; /* the trajectory times are the database's, the same for every frame */
    mm_database_pose(db, 0, &pd);
    rec->traj_count = pd.traj_count;
    memcpy(rec->traj_times, pd.traj_times, sizeof rec->traj_times);
    rec->last_searches = c->searches;
    rec->last_transitions = c->transitions;
    return MM_OK;
}

void mm_recorder_clear(mm_recorder *rec)
{
    if (!rec) return;
    rec->count = rec->head = 0;
    rec->recorded = 0;
    rec->time = 0.0;
}

/* The slot of index i (0: the oldest). */
static int slot_of(const mm_recorder *rec, int i) { return (rec->head + i) % rec->capacity; }

void mm_recorder_record(mm_recorder *rec, const mm_character *c, const mm_input *in, float dt)
{
    if (!rec || !rec->ticks || !c || !c->state || c->db != rec->db) return;
    const mm_database *db = c->db;
    int slot;
    if (rec->count < rec->capacity) {
        slot = slot_of(rec, rec->count++);
    } else { /* full: the oldest gives way */
        slot = rec->head;
        rec->head = (rec->head + 1) % rec->capacity;
    }
    mm_recorded_tick *t = &rec->ticks[slot];
    memset(t, 0, sizeof *t);
    rec->time += dt;
    t->number = rec->recorded++;
    t->time = rec->time;
    t->dt = dt;
    if (in)
        t->input = *in;
    else
        t->input.gait = MM_GAIT_WALK;
    t->frame = c->frame;
    t->clip = db->frame_clip[c->frame];
    t->frame_fraction = c->frame_fraction;
    t->root = c->root;
    t->traj_count = rec->traj_count;
    memcpy(t->traj_times, rec->traj_times, sizeof t->traj_times);
    mm_trajectory_sample(c->trajectory, in, rec->traj_times, rec->traj_count, t->traj_positions,
                         t->traj_facings);
    t->searched = c->searches != rec->last_searches;
    t->transition = c->transitions != rec->last_transitions;
    rec->last_searches = t->searches = c->searches;
    rec->last_transitions = t->transitions = c->transitions;
    t->dims = db->dims;
    float *query = rec->queries + (size_t)slot * (size_t)db->dims_padded;
    memcpy(query, c->query, sizeof(float) * (size_t)db->dims_padded);
    t->query = query;
    mm_candidate *candidates = rec->candidates + (size_t)slot * (size_t)rec->top_k;
    t->candidates = candidates;
    t->candidate_count =
        t->searched && rec->top_k > 0 ? mm_character_candidates(c, candidates, rec->top_k) : 0;
    unsigned label = db->contacts[c->frame];
    t->heel_contact[0] = (label & MM_CONTACT_LEFT_HEEL) != 0;
    t->toe_contact[0] = (label & MM_CONTACT_LEFT_TOE) != 0;
    t->heel_contact[1] = (label & MM_CONTACT_RIGHT_HEEL) != 0;
    t->toe_contact[1] = (label & MM_CONTACT_RIGHT_TOE) != 0;
    for (int k = 0; k < 2; ++k) {
        t->foot_locked[k] = c->foot_locked[k];
        t->foot_lock[k] = c->foot_lock[k];
    }
    t->joint_count = db->joint_count;
    mm_xform *pose = rec->poses + (size_t)slot * (size_t)db->joint_count;
    memcpy(pose, c->global, sizeof(mm_xform) * (size_t)db->joint_count);
    t->global = pose;
    mm_character_snapshot_save(c, rec->snapshots + (size_t)slot * rec->snapshot_bytes, rec->snapshot_bytes,
                               NULL);
}

int mm_recorder_count(const mm_recorder *rec) { return rec ? rec->count : 0; }

int64_t mm_recorder_oldest(const mm_recorder *rec)
{
    return rec && rec->count > 0 ? rec->ticks[rec->head].number : -1;
}

int64_t mm_recorder_newest(const mm_recorder *rec)
{
    return rec && rec->count > 0 ? rec->ticks[slot_of(rec, rec->count - 1)].number : -1;
}

int mm_recorder_index(const mm_recorder *rec, int64_t number)
{
    int64_t oldest = mm_recorder_oldest(rec);
    if (oldest < 0 || number < oldest || number > mm_recorder_newest(rec)) return -1;
    return (int)(number - oldest); /* numbers held are consecutive */
}

const mm_recorded_tick *mm_recorder_tick(const mm_recorder *rec, int index)
{
    if (!rec || index < 0 || index >= rec->count) return NULL;
    return &rec->ticks[slot_of(rec, index)];
}

mm_result mm_recorder_restore(const mm_recorder *rec, int index, mm_character *c, mm_error *err)
{
    if (!rec || index < 0 || index >= rec->count)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "recorder: tick %d is not held (%d are)",
                            index, rec ? rec->count : 0);
    if (!c || c->db != rec->db)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "recorder: not a character of its database");
    int slot = slot_of(rec, index);
    return mm_character_snapshot_load(c, rec->snapshots + (size_t)slot * rec->snapshot_bytes,
                                      rec->snapshot_bytes, err);
}

void mm_recorder_truncate(mm_recorder *rec, int index)
{
    if (!rec || index < 0 || index >= rec->count) return;
    const mm_recorded_tick *t = mm_recorder_tick(rec, index);
    rec->count = index + 1;
    rec->recorded = t->number + 1;
    rec->time = t->time;
    rec->last_searches = t->searches;
    rec->last_transitions = t->transitions;
}
