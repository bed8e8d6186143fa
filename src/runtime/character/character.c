/* The character: its desc, its life cycle, the tick as a list of stages (one module each in this
 * folder), and what the move layer may do to it between ticks. No allocation after
 * mm_character_init. */
#include <mm/character.h>

#include <math.h>
#include <string.h>

#include "math_private.h"
#include "state.h"

/* docs/runtime.md, "Why the defaults are what they are", has what was measured for them. */
void mm_character_defaults(mm_character_desc *d)
{
    memset(d, 0, sizeof *d);
    d->search_interval = MM_CHARACTER_SEARCH_INTERVAL;
    d->turn_threshold = MM_CHARACTER_TURN_THRESHOLD;
    d->transition_halflife = MM_CHARACTER_TRANSITION_HALFLIFE;
    d->crossfade_time = MM_CHARACTER_CROSSFADE_TIME;
    d->idle_speed = MM_CHARACTER_IDLE_SPEED;
    d->idle_hysteresis = MM_CHARACTER_IDLE_HYSTERESIS;
    d->idle_root_speed = MM_CHARACTER_IDLE_ROOT_SPEED;
    d->sync_halflife = MM_CHARACTER_SYNC_HALFLIFE;
    d->sync_max_distance = MM_CHARACTER_SYNC_MAX_DISTANCE;
    d->sync_max_angle = MM_CHARACTER_SYNC_MAX_ANGLE;
    d->angle_threshold = MM_CHARACTER_ANGLE_THRESHOLD;
    d->angle_revise_speed = MM_CHARACTER_ANGLE_REVISE_SPEED;
    d->skip_frames = MM_CHARACTER_SKIP_FRAMES;
    d->velocity_change_ratio = MM_CHARACTER_VELOCITY_CHANGE_RATIO;
    d->velocity_change_speed = MM_CHARACTER_VELOCITY_CHANGE_SPEED;
    d->unlock_radius = MM_CHARACTER_UNLOCK_RADIUS;
    d->foot_halflife = MM_CHARACTER_FOOT_HALFLIFE;
    d->plant_time = MM_CHARACTER_PLANT_TIME;
    d->max_hip_drop = MM_CHARACTER_MAX_HIP_DROP;
    d->left_foot = d->right_foot = NULL; /* the database's foot roles */
    d->method = MM_SEARCH_FAST;
    d->rate_min = MM_CHARACTER_RATE_MIN;
    d->rate_max = MM_CHARACTER_RATE_MAX;
    d->stride_min = MM_CHARACTER_STRIDE_MIN;
    d->stride_max = MM_CHARACTER_STRIDE_MAX;
    d->orientation_speed = MM_CHARACTER_ORIENTATION_SPEED;
    d->orientation_max = MM_CHARACTER_ORIENTATION_MAX;
    mm_trajectory_defaults(&d->trajectory);
}

/* The desc's numbers where zero means default and MM_OFF is 0 (skip_frames, params and trajectory
 * are resolved apart), as pointers into d. */
#define DESC_SCALARS 24
static void desc_scalars(mm_character_desc *d, float *out[DESC_SCALARS])
{
    float *all[DESC_SCALARS] = {&d->search_interval,
                                &d->turn_threshold,
                                &d->transition_halflife,
                                &d->crossfade_time,
                                &d->idle_speed,
                                &d->idle_hysteresis,
                                &d->idle_root_speed,
                                &d->sync_halflife,
                                &d->sync_max_distance,
                                &d->sync_max_angle,
                                &d->angle_threshold,
                                &d->angle_revise_speed,
                                &d->velocity_change_ratio,
                                &d->velocity_change_speed,
                                &d->plant_time,
                                &d->unlock_radius,
                                &d->foot_halflife,
                                &d->max_hip_drop,
                                &d->rate_min,
                                &d->rate_max,
                                &d->stride_min,
                                &d->stride_max,
                                &d->orientation_speed,
                                &d->orientation_max};
    memcpy(out, all, sizeof all);
}

/* A desc field written out: 0 takes the default; a negative value (MM_OFF) stays. */
static float written(float given, float fallback) { return given == 0.0f ? fallback : given; }
/* ... and as the stages read it: MM_OFF is 0. */
static float effective(float value) { return value < 0.0f ? 0.0f : value; }

/* The search parameters of a desc written out, field by field over mm_character_default_params. */
static void write_params(const mm_database *db, const mm_search_params *given, mm_search_params *out)
{
    mm_search_params p;
    mm_character_default_params(db, &p);
    p.pose_trajectory_ratio = written(given->pose_trajectory_ratio, p.pose_trajectory_ratio);
    for (int b = 0; b < MM_MAX_MATCH_BONES; ++b) {
        p.joint_position_weights[b] = written(given->joint_position_weights[b], p.joint_position_weights[b]);
        p.joint_velocity_weights[b] = written(given->joint_velocity_weights[b], p.joint_velocity_weights[b]);
    }
    p.body_velocity_weight = written(given->body_velocity_weight, p.body_velocity_weight);
    p.position_multiplier = written(given->position_multiplier, p.position_multiplier);
    p.angle_multiplier = written(given->angle_multiplier, p.angle_multiplier);
    p.next_pose_favour = written(given->next_pose_favour, p.next_pose_favour);
    p.loop_anim_favour = written(given->loop_anim_favour, p.loop_anim_favour);
    p.continuing_bias = written(given->continuing_bias, p.continuing_bias);
    p.contact_mismatch_favour = written(given->contact_mismatch_favour, p.contact_mismatch_favour);
    p.exclude_window = given->exclude_window != 0 ? given->exclude_window : p.exclude_window;
    p.end_margin = given->end_margin != 0 ? given->end_margin : p.end_margin;
    p.required_tags |= given->required_tags;
    p.excluded_tags |= given->excluded_tags;
    p.facing_threshold = written(given->facing_threshold, p.facing_threshold);
    *out = p;
}

void mm_character_desc_resolve(const mm_database *db, const mm_character_desc *in, mm_character_desc *out)
{
    mm_character_desc def, r = *in;
    mm_character_defaults(&def);
    float *field[DESC_SCALARS], *fallback[DESC_SCALARS];
    desc_scalars(&r, field);
    desc_scalars(&def, fallback);
    for (int k = 0; k < DESC_SCALARS; ++k) *field[k] = written(*field[k], *fallback[k]);
    r.skip_frames = in->skip_frames != 0 ? in->skip_frames : def.skip_frames;
    if (db) write_params(db, &in->params, &r.params);
    const mm_trajectory_desc *t = &in->trajectory, *td = &def.trajectory;
    for (int g = 0; g < MM_GAIT_COUNT; ++g) {
        const mm_gait_params *a = &t->gaits[g], *b = &td->gaits[g];
        mm_gait_params *o = &r.trajectory.gaits[g];
        o->forward_speed = written(a->forward_speed, b->forward_speed);
        o->side_speed = written(a->side_speed, b->side_speed);
        o->backward_speed = written(a->backward_speed, b->backward_speed);
        o->velocity_halflife = written(a->velocity_halflife, b->velocity_halflife);
        o->rotation_halflife = written(a->rotation_halflife, b->rotation_halflife);
    }
    r.trajectory.gait_halflife = written(t->gait_halflife, td->gait_halflife);
    r.trajectory.history_seconds = written(t->history_seconds, td->history_seconds);
    r.trajectory.history_rate = written(t->history_rate, td->history_rate);
    r.trajectory.collider_radius = written(t->collider_radius, td->collider_radius);
    r.trajectory.collider_height = written(t->collider_height, td->collider_height);
    r.trajectory.collider_step = written(t->collider_step, td->collider_step);
    *out = r;
}

/* A written-out desc as the stages read it: every MM_OFF a 0. */
static void effective_desc(const mm_character_desc *in, mm_character_desc *out)
{
    mm_character_desc r = *in;
    float *field[DESC_SCALARS];
    desc_scalars(&r, field);
    for (int k = 0; k < DESC_SCALARS; ++k) *field[k] = effective(*field[k]);
#define ZERO(field) r.field = effective(in->field);
    ZERO(params.pose_trajectory_ratio)
    ZERO(params.body_velocity_weight)
    ZERO(params.position_multiplier)
    ZERO(params.angle_multiplier)
    ZERO(params.next_pose_favour)
    ZERO(params.loop_anim_favour)
    ZERO(params.continuing_bias)
    ZERO(params.facing_threshold)
    for (int b = 0; b < MM_MAX_MATCH_BONES; ++b) {
        ZERO(params.joint_position_weights[b])
        ZERO(params.joint_velocity_weights[b])
    }
#undef ZERO
    if (r.params.contact_mismatch_favour < 0.0f)
        r.params.contact_mismatch_favour = 1.0f; /* MM_OFF: a factor of 1 */
    if (r.skip_frames < 0) r.skip_frames = 0;
    if (r.params.exclude_window < 0) r.params.exclude_window = 0;
    if (r.params.end_margin < 0) r.params.end_margin = 0;
    *out = r;
}

void mm_character_default_params(const mm_database *db, mm_search_params *p)
{
    mm_search_params_defaults(db, p);
    /* keep playing unless a frame is clearly better (docs/runtime.md, "Why the defaults") */
    p->next_pose_favour = MM_CHARACTER_NEXT_POSE_FAVOUR;
    /* transitions into other contacts than the frame playing's slide the planted feet
     * (docs/metrics.md, "Transitions that keep the contacts") */
    p->contact_mismatch_favour = MM_CHARACTER_CONTACT_FAVOUR;
    /* the moves (mm/moves.h) play their clips themselves: never a place for locomotion to go */
    p->excluded_tags = mm_search_tag_mask(db, "DoNotUse") | mm_search_tag_mask(db, "Jump") |
                       mm_search_tag_mask(db, "VaultLow") | mm_search_tag_mask(db, "VaultHigh") |
                       mm_search_tag_mask(db, "Climb") | mm_search_tag_mask(db, "Drop");
    p->end_margin = (int)ceilf(MM_CHARACTER_END_MARGIN / db->interval);
}

/* The legs' and the root motion's transition offsets (what carries the planted feet) fade with
 * this share of transition_halflife; a move's all with its own (docs/runtime.md, "The legs'
 * half-life") */
#define LEGS_HALFLIFE_SHARE 0.6f

/* bytes: every array of the character's one block starts on a multiple of this (what malloc gives) */
#define BLOCK_ALIGN 16

/* The next `bytes` of the character's one block (block NULL: only counted), at offset *at. */
static void *carve(char *block, size_t *at, size_t bytes)
{
    void *p = block ? block + *at : NULL;
    *at += (bytes + BLOCK_ALIGN - 1) / BLOCK_ALIGN * BLOCK_ALIGN;
    return p;
}

/* Lays out (block NULL: measures) the state and its arrays in block. */
static mm_character_state *lay_out(char *block, size_t joints, size_t dims, size_t *size)
{
    size_t at = 0;
    mm_character_state *s = (mm_character_state *)carve(block, &at, sizeof(mm_character_state));
    mm_character_state unused;
    if (!s) s = &unused;
    mm_transition *tr = &s->transition;
    s->pose.local_rotations = (mm_quat *)carve(block, &at, joints * sizeof(mm_quat));
    s->pose.local_positions = (mm_vec3 *)carve(block, &at, joints * sizeof(mm_vec3));
    s->pose.global = (mm_xform *)carve(block, &at, joints * sizeof(mm_xform));
    tr->rotations = (mm_quat *)carve(block, &at, joints * sizeof(mm_quat));
    tr->previous_rotations = (mm_quat *)carve(block, &at, joints * sizeof(mm_quat));
    tr->positions = (mm_vec3 *)carve(block, &at, joints * sizeof(mm_vec3));
    tr->previous_positions = (mm_vec3 *)carve(block, &at, joints * sizeof(mm_vec3));
    tr->rotation_offset = (mm_vec3 *)carve(block, &at, joints * sizeof(mm_vec3));
    tr->rotation_offset_velocity = (mm_vec3 *)carve(block, &at, joints * sizeof(mm_vec3));
    tr->position_offset = (mm_vec3 *)carve(block, &at, joints * sizeof(mm_vec3));
    tr->position_offset_velocity = (mm_vec3 *)carve(block, &at, joints * sizeof(mm_vec3));
    tr->legs = (unsigned char *)carve(block, &at, joints);
    tr->slot_rotations = (mm_quat *)carve(block, &at, (MM_MIXER_SLOTS + 1) * joints * sizeof(mm_quat));
    tr->slot_positions = (mm_vec3 *)carve(block, &at, MM_MIXER_SLOTS * joints * sizeof(mm_vec3));
    tr->frame_rotations = (mm_quat *)carve(block, &at, 2 * joints * sizeof(mm_quat));
    tr->frame_positions = (mm_vec3 *)carve(block, &at, 2 * joints * sizeof(mm_vec3));
    s->matching.query = (float *)carve(block, &at, dims * sizeof(float));
    *size = at;
    return block ? s : NULL;
}

/* The public view of the state (mm_character's fields), after every change. */
static void publish(mm_character *c)
{
    const mm_character_state *s = c->state;
    c->trajectory = &s->trajectory;
    c->local_rotations = s->pose.local_rotations;
    c->local_positions = s->pose.local_positions;
    c->global = s->pose.global;
    c->root = s->root_motion.root;
    c->frame = s->playback.frame;
    c->frame_fraction = s->playback.fraction;
    c->playback = s->playback.mode;
    c->play_rate = s->playback.play_rate;
    c->stride_scale = s->playback.stride_scale;
    c->idle = s->matching.idle;
    c->move_playing = s->move.playing;
    for (int k = 0; k < 2; ++k) {
        c->foot_joint[k] = s->rig.ankle[k];
        c->toe_joint[k] = s->rig.toe[k];
        c->foot_locked[k] = s->feet.locked[k];
        c->foot_lock[k] = s->feet.lock[k];
    }
    memcpy(c->raw_contact_positions, s->feet.raw_contacts, sizeof c->raw_contact_positions);
    c->searches = s->matching.searches;
    c->transitions = s->transition.transitions;
    c->cancelled_transitions = s->transition.cancelled;
    c->last_search_us = s->matching.last_search_us;
    c->last_result = s->matching.last_result;
    c->last_choice = s->matching.last_choice;
    c->last_params = s->matching.last_params;
    c->query = s->matching.query;
}

/* The output pose from the animated one, the root set and the world transforms computed. */
static void pose_from_animation(mm_character_state *s, int joint_count)
{
    memcpy(s->pose.local_rotations, s->transition.rotations, sizeof(mm_quat) * (size_t)joint_count);
    memcpy(s->pose.local_positions, s->transition.positions, sizeof(mm_vec3) * (size_t)joint_count);
    s->pose.local_rotations[0] = s->root_motion.root.rotation;
    s->pose.local_positions[0] = s->root_motion.root.translation;
    s->pose.global[0] = s->root_motion.root;
    mm_rig_forward_pelvis(&s->rig, &s->pose);
}

/* A new tuning: the desc resolved (as at init; what init laid out kept), and the copies of its
 * values the stages keep. */
static void apply_tuning(mm_character *c, const mm_character_desc *given)
{
    mm_character_state *s = c->state;
    mm_character_desc kept = c->desc;
    mm_character_desc_resolve(c->db, given, &c->desc);
    c->desc.left_foot = c->desc.right_foot = NULL; /* not kept: the caller's strings */
    c->desc.transition_mode = kept.transition_mode;
    c->desc.allocator = kept.allocator;
    effective_desc(&c->desc, &s->desc);
    mm_trajectory_resolve_desc(&c->desc.trajectory, &s->desc.trajectory);
    for (int g = 0; g < MM_GAIT_COUNT; ++g) s->trajectory.desc.gaits[g] = s->desc.trajectory.gaits[g];
    s->trajectory.desc.collider_radius = s->desc.trajectory.collider_radius;
    s->trajectory.desc.collider_height = s->desc.trajectory.collider_height;
    s->trajectory.desc.collider_step = s->desc.trajectory.collider_step;
    s->trajectory.desc.bounded = s->desc.trajectory.bounded;
    memcpy(s->trajectory.desc.envelopes, s->desc.trajectory.envelopes, sizeof s->trajectory.desc.envelopes);
    const mm_character_desc *d = &s->desc;
    mm_playback_params *pp = &s->playback_params;
    pp->distance_matching = d->distance_matching, pp->warping = d->warping;
    pp->rate_min = d->rate_min, pp->rate_max = d->rate_max;
    pp->stride_min = d->stride_min, pp->stride_max = d->stride_max;
    pp->idle_speed = d->idle_speed;
}

/* The frame a character starts on: the first idle frame that an input asking for the walk (the
 * default gait) could play, not one tagged for another gait (a crouched or bent-over idle, which the
 * search leaves out while walking, would otherwise be the first pose shown); the first idle frame
 * where every idle frame is so tagged, frame 0 where there is no idle clip. */
static int start_frame(const mm_database *db, const mm_matching *m)
{
    uint64_t other_gaits = 0;
    for (int g = 0; g < MM_GAIT_COUNT; ++g)
        if (g != MM_GAIT_WALK) other_gaits |= m->gait_tags[g];
    int first_idle = -1;
    for (int k = 0; k < db->clip_count; ++k) {
        const mm_db_clip *clip = &db->clips[k];
        if (clip->type != MM_CLIP_IDLE || clip->frame_count <= 0) continue;
        if (first_idle < 0) first_idle = clip->first_frame;
        for (int f = clip->first_frame; f < clip->first_frame + clip->frame_count; ++f)
            if (!db->frame_tags || !(db->frame_tags[f] & other_gaits)) return f;
    }
    return first_idle >= 0 ? first_idle : 0;
}

/* m: the longer leg at rest, hip to knee to ankle (0 without legs) */
static float leg_length(const mm_rig *rig)
{
    float longest = 0.0f;
    for (int k = 0; k < 2; ++k)
        if (rig->ankle[k] >= 0 && rig->knee[k] >= 0)
            longest = fmaxf(longest, mm_vec3_length(rig->joints[rig->knee[k]].offset) +
                                         mm_vec3_length(rig->joints[rig->ankle[k]].offset));
    return longest;
}

mm_result mm_character_init(mm_character *c, const mm_database *db, const mm_searcher *searcher,
                            const mm_character_desc *desc, mm_error *err)
{
    if (!c) return MM_ERR_INVALID_ARGUMENT;
    memset(c, 0, sizeof *c);
    if (!db || !searcher || searcher->db != db)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0,
                            "a character needs a database and its searcher");
    mm_character_desc zero;
    memset(&zero, 0, sizeof zero);
    c->db = db;
    c->searcher = searcher;
    const mm_character_desc *given = desc ? desc : &zero;
    mm_character_desc_resolve(db, given, &c->desc);
    c->desc.transition_mode = given->transition_mode;
    if (c->desc.allocator) c->allocator = *c->desc.allocator;
    size_t size, n = (size_t)db->joint_count;
    lay_out(NULL, n, (size_t)db->dims_padded, &size);
    char *block = (char *)mm_alloc_array(&c->allocator, 1, size);
    if (!block) return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    mm_character_state *s = lay_out(block, n, (size_t)db->dims_padded, &size);
    s->block = block;
    c->state = s;
    mm_result r = mm_trajectory_init(&s->trajectory, &c->desc.trajectory, &c->allocator);
    if (r != MM_OK) {
        mm_character_free(c);
        return mm_error_set(err, r, 0, 0, "trajectory: bad parameters");
    }
    /* the feet the desc names, else the database's foot roles */
    int left = given->left_foot ? mm_database_find_joint(db, given->left_foot)
                                : mm_database_role_joint(db, MM_ROLE_LEFT_FOOT);
    int right = given->right_foot ? mm_database_find_joint(db, given->right_foot)
                                  : mm_database_role_joint(db, MM_ROLE_RIGHT_FOOT);
    mm_rig_init(&s->rig, db->joints, db->joint_count, left, right);
    for (int k = 0; k < 2; ++k) /* the toe roles where they hang from the ankles */
        if (s->rig.ankle[k] >= 0)
            s->rig.toe[k] =
                mm_database_toe_joint(db, s->rig.ankle[k], k ? MM_ROLE_RIGHT_TOE : MM_ROLE_LEFT_TOE);
    mm_rig_learn_hinges(&s->rig, db);
    mm_rig_learn_planted_heights(&s->rig, db);
    apply_tuning(c, &c->desc);
    const mm_character_desc *d = &s->desc;
    s->no_distance_tag = mm_search_tag_mask(db, "NoDistanceMatching");
    float *query = s->matching.query;
    mm_matching_init(&s->matching, db, query, leg_length(&s->rig));
    mm_rig_learn_hip_floor(&s->rig, db,
                           s->matching.gait_tags[MM_GAIT_CROUCH] | s->matching.gait_tags[MM_GAIT_JUMP]);
    mm_rig_learn_head_floor(&s->rig, db);
    s->playback.frame = start_frame(db, &s->matching);
    mm_playback_by_clock(&s->playback);
    s->root_motion.root = mm_xform_identity();
    mm_transition_init(&s->transition, db, d->transition_mode, &s->playback);
    mm_transition_mark_legs(&s->transition, db->joints, db->joint_count, s->rig.hip);
    pose_from_animation(s, db->joint_count);
    publish(c);
    return MM_OK;
}

void mm_character_free(mm_character *c)
{
    if (!c) return;
    if (c->state) {
        mm_trajectory_free(&c->state->trajectory);
        mm_free(&c->allocator, c->state->matching.candidates);
        mm_free(&c->allocator, c->state->block);
    }
    memset(c, 0, sizeof *c);
}

/* Moves: a move asked for starts (*jump: to its frame), or one playing hands back to matching
 * (returns true) when its clip ended or its playhead reached the end frame. */
static bool play_moves(mm_move_playback *m, const mm_database *db, const mm_playback *p, bool ended,
                       mm_jump *jump)
{
    jump->frame = -1;
    if (m->pending) { /* a move starts: no search until it hands back */
        m->pending = false;
        m->playing = true;
        jump->frame = m->frame, jump->fraction = 0.0, jump->uncancellable = true;
    } else if (m->playing &&
               (ended || db->frame_clip[p->frame] != db->frame_clip[m->frame] || p->frame >= m->end)) {
        m->playing = false; /* played out: back to matching at once */
        return true;
    }
    return false;
}

/* The distance curve of the clip playing (in *curve), or NULL when it plays by the clock: an idle
 * (standing still is no reason to slow), a frame tagged "NoDistanceMatching", a clip without one. */
static const mm_distance_curve *distance_curve_playing(const mm_character_state *s, const mm_database *db,
                                                       mm_distance_curve *curve)
{
    int frame = s->playback.frame, clip = db->frame_clip[frame];
    if (db->frame_tags && (db->frame_tags[frame] & s->no_distance_tag)) return NULL;
    if (db->clips[clip].type == MM_CLIP_IDLE || mm_database_distance_curve(db, clip, curve) != MM_OK)
        return NULL;
    return curve;
}

/* Playback's rate this tick: by distance matching (on the distance curve of the clip playing) when
 * it or warping is on and no move plays, else by the clock. */
static void choose_play_rate(mm_character_state *s, const mm_database *db, const mm_input *in, float dt)
{
    if ((s->desc.distance_matching || s->desc.warping) && !s->move.playing && !s->move.pending) {
        mm_distance_curve curve;
        int first = db->clips[db->frame_clip[s->playback.frame]].first_frame;
        mm_playback_match_distance(&s->playback, &s->playback_params, distance_curve_playing(s, db, &curve),
                                   first, &s->trajectory, in, &s->intent, dt);
    } else {
        mm_playback_by_clock(&s->playback);
    }
}

/* What the clip playing says of the feet this tick: its contact label, and how soon each foot's
 * turns on (within plant_time, or the longest landing when longer; and within a swing, for its plan). */
static mm_feet_contacts feet_contacts(const mm_database *db, const mm_playback *p, float plant_time)
{
    mm_feet_contacts fc;
    fc.label = db->contacts[p->frame];
    float ahead = fmaxf(plant_time, MM_FEET_LANDING_MAX_TIME);
    for (int k = 0; k < 2; ++k)
        fc.until_label[k] = plant_time > 0.0f ? mm_playback_time_to_contact(p, db->frame_next, db->contacts,
                                                                            db->interval, k, ahead)
                                              : -1.0f;
    for (int k = 0; k < 2; ++k)
        fc.until_contact[k] = mm_playback_time_to_contact(p, db->frame_next, db->contacts, db->interval, k,
                                                          MM_FEET_SWING_AHEAD);
    return fc;
}

/* The input the simulation follows (and the play rate and the search's query with it): while idle
 * is asked for (the matching's, from the last tick), a stick asking for no more than idle_speed +
 * idle_hysteresis (under which idle is kept) leaves the simulation standing, as the idle pose does:
 * moving, it pulled the root and the feet planted under it along at that speed for as long as idle
 * was kept (docs/metrics.md, "Idle drift"). */
static const mm_input *idle_input(const mm_character_state *s, const mm_character_desc *d, const mm_input *in,
                                  mm_input *standing)
{
    if (!in || !s->matching.idle || s->move.playing) return in;
    mm_vec3 v;
    mm_trajectory_desired(&s->trajectory, in, &v, NULL);
    if (sqrtf(v.x * v.x + v.z * v.z) > d->idle_speed + d->idle_hysteresis) return in;
    *standing = *in;
    standing->stick[0] = standing->stick[1] = 0.0f;
    return standing;
}

/* While idle is asked for with a stick under its band (idle_input) and an idle clip plays, a
 * simulation still moving stands where the character stands: moved onto the root, its velocity and
 * acceleration dropped (once: from then on it stands, and the root is pulled toward it as before).
 * Idle is chosen while the simulation still moves (up to idle_speed + idle_hysteresis), and left to
 * its velocity spring it coasted on, pulling the root and the feet planted under it after it
 * (docs/metrics.md, "The simulation stands with the idle"). */
static void stand_with_idle(mm_character_state *s, const mm_database *db, const mm_input *asked,
                            const mm_input *standing)
{
    if (asked != standing || db->clips[db->frame_clip[s->playback.frame]].type != MM_CLIP_IDLE) return;
    mm_vec3 v = s->trajectory.velocity, a = s->trajectory.acceleration;
    if (v.x == 0.0f && v.z == 0.0f && a.x == 0.0f && a.z == 0.0f) return; /* standing already */
    mm_trajectory_teleport(&s->trajectory, s->root_motion.root.translation, s->trajectory.facing);
    s->trajectory.velocity = s->trajectory.acceleration = mm_vec3_make(0.0f, 0.0f, 0.0f);
}

void mm_character_update(mm_character *c, const mm_input *in, float dt)
{
    if (!c || !c->state || !(dt > 0.0f) || !isfinite(dt)) return;
    mm_character_state *s = c->state;
    const mm_database *db = c->db;
    const mm_character_desc *d = &s->desc;
    /* the terrain walked on: none on a flat scene (the plane y = 0, as without one) */
    const mm_scene *terrain = mm_scene_is_flat(c->scene) ? NULL : c->scene;

    /* 1. input -> trajectory: the simulation, and what the input asks for; on terrain, at the
     * height of the ground under it; its capsule stands where the character stands */
    s->trajectory.floor = s->root_motion.root.translation.y;
    mm_input standing;
    const mm_input *asked = idle_input(s, d, in, &standing);
    stand_with_idle(s, db, asked, &standing);
    mm_intent_update(&s->trajectory, asked, dt, &s->intent);
    if (terrain)
        s->trajectory.position.y =
            mm_scene_ground_height(terrain, s->trajectory.position.x, s->trajectory.position.z, NULL);

    /* 2. playback: by the clock, or by distance matching (never during a move) */
    choose_play_rate(s, db, asked, dt);
    bool ended = mm_playback_advance(&s->playback, db->frame_next, db->interval, dt);
    mm_transition_advance(&s->transition, db, &s->playback, dt);

    /* 3. search: a move starting or handing back, or the search's winner */
    mm_jump jump, found = {-1, 0.0, false};
    if (play_moves(&s->move, db, &s->playback, ended, &jump)) s->matching.since_search = INFINITY;
    if (mm_matching_due(&s->matching, d, &s->intent, mm_intent_ground_speed(&s->trajectory),
                        mm_vec3_length(s->root_motion.played.velocity), ended, s->move.playing, dt)) {
        mm_matching_search(&s->matching, d, db, c->searcher, &s->trajectory, asked, &s->intent,
                           s->root_motion.root, &s->playback, &found);
    }
    if (found.frame >= 0) jump = found;
    s->matching.future_count = 0; /* the game's future is given for one tick */

    /* 4. transition: the jump hidden, and the animated pose of this tick */
    mm_transition_jump(&s->transition, db, &jump, d->crossfade_time, s->root_motion.played, &s->playback, dt);
    float halflife = s->move.playing && s->move.halflife > 0.0f ? s->move.halflife : d->transition_halflife;
    float legs_halflife = s->move.playing ? halflife : halflife * LEGS_HALFLIFE_SHARE;
    mm_root_played played;
    mm_transition_pose(&s->transition, db, &s->playback, halflife, legs_halflife, dt, &played);

    /* 5. root motion: played, pulled toward the simulation and clamped (a move's is its clip's) */
    mm_root_motion_update(&s->root_motion, d, &s->trajectory, &s->intent, played, s->move.playing, dt);
    mm_root_motion_follow_ground(&s->root_motion, s->move.playing ? NULL : terrain, dt);
    mm_matching_track_stances(&s->matching, db->contacts[s->playback.frame], s->root_motion.root.translation);
    /* through the warping (6) and the feet (7) only the legs' global transforms are read (and the
     * spine's by an orientation warp, which asks for them): the rest of the body's wait until the
     * pelvis has moved for the last time (mm_rig_forward_pelvis) */
    s->pose.defer_body = true;
    pose_from_animation(s, db->joint_count);

    /* 6. warping: the legs turned toward the movement and stretched along it */
    if (d->warping) {
        mm_warping_clip clip = {db->root_velocity[s->playback.frame],
                                db->clips[db->frame_clip[s->playback.frame]].type == MM_CLIP_IDLE};
        mm_warping_orientation(&s->warping, d, &s->rig, s->root_motion.root, s->trajectory.velocity, clip,
                               s->intent.strafe, s->move.playing, dt, &s->pose);
        mm_warping_stride(&s->warping, &s->rig, s->root_motion.root, s->trajectory.velocity,
                          s->playback.stride_scale, dt, &s->pose);
    }

    /* 7. feet: the contacts as played, then locks and IK */
    mm_feet_record(&s->feet, &s->rig, &s->pose);
    if (!d->no_foot_ik) {
        mm_feet_contacts contacts = feet_contacts(db, &s->playback, d->plant_time);
        mm_feet_ground ground = {s->root_motion.root.translation.y, !s->move.playing, terrain};
        mm_feet_update(&s->feet, d, &s->rig, &contacts, &ground, dt, &s->pose);
    }
    mm_rig_forward_finish(&s->rig, &s->pose);

    /* 8. walls: in a scene, the body out of them (not during a move: the move layer has it) */
    if (!s->move.playing && !s->move.pending) {
        mm_vec3 out =
            mm_walls_push(&s->trajectory, s->root_motion.root.translation, &s->pose, db->joint_count);
        if (out.x != 0.0f || out.z != 0.0f)
            mm_walls_move_body(&s->root_motion.root, &s->pose, db->joint_count, &s->feet, out);
    }

    /* 9. pose: what the character shows */
    publish(c);
}

void mm_character_set_scene(mm_character *c, const mm_scene *scene)
{
    if (!c) return;
    c->scene = scene;
    mm_character_set_walls(c, scene);
    if (!c->state || mm_scene_is_flat(scene)) return;
    /* on the ground from the start: the root's height spring starts there, at rest */
    mm_root_motion *r = &c->state->root_motion;
    r->root.translation.y = mm_root_motion_ground(scene, r->root);
    r->on_ground = false; /* the spring starts at rest from there */
    r->ground_velocity = 0.0f;
    c->root = r->root;
}

void mm_character_place_in_scene(mm_character *c, const mm_scene *scene)
{
    if (mm_scene_has_terrain(scene))
        mm_character_set_scene(c, scene);
    else
        mm_character_set_walls(c, scene);
}

void mm_character_tune(mm_character *c, const mm_character_desc *d)
{
    if (!c || !c->state || !d) return;
    apply_tuning(c, d);
}

void mm_character_play_move(mm_character *c, int frame, int end_frame, float halflife)
{
    if (!c || !c->state) return;
    mm_move_playback *m = &c->state->move;
    if (frame < 0 || frame >= c->db->frame_count) { /* nothing to play: back to matching */
        m->pending = m->playing = false;
        c->state->matching.since_search = INFINITY;
        publish(c);
        return;
    }
    m->pending = true;
    m->frame = frame;
    m->end = end_frame;
    m->halflife = isfinite(halflife) && halflife > 0.0f ? halflife : 0.0f;
}

bool mm_character_move_playing(const mm_character *c)
{
    return c && c->state && (c->state->move.pending || c->state->move.playing);
}

void mm_character_shift_root(mm_character *c, mm_vec3 delta)
{
    if (!c || !c->state || !finite3(delta)) return;
    mm_character_state *s = c->state;
    const mm_database *db = c->db;
    mm_xform *root = &s->root_motion.root;
    root->translation = mm_vec3_add(root->translation, delta);
    mm_vec3 local = mm_quat_inv_rotate(root->rotation, delta);
    mm_transition *tr = &s->transition;
    for (int j = 1; j < db->joint_count; ++j) {
        if (db->joints[j].parent != 0) continue;
        /* the child keeps its world place: its local position, and the offset that carries it */
        tr->position_offset[j] = mm_vec3_sub(tr->position_offset[j], local);
        s->pose.local_positions[j] = mm_vec3_sub(s->pose.local_positions[j], local);
        tr->positions[j] = mm_vec3_sub(tr->positions[j], local);
        tr->previous_positions[j] = mm_vec3_sub(tr->previous_positions[j], local);
    }
    s->pose.local_positions[0] = root->translation;
    s->pose.global[0] = *root;
    mm_rig_forward(&s->rig, 1, &s->pose);
    publish(c);
}

void mm_character_set_root(mm_character *c, mm_xform root)
{
    if (!c || !c->state || !finite3(root.translation) || !isfinite(root.rotation.x) ||
        !isfinite(root.rotation.y) || !isfinite(root.rotation.z) || !isfinite(root.rotation.w))
        return;
    c->state->root_motion.root = root;
    c->root = root;
}

void mm_character_move_foot_locks(mm_character *c, mm_vec3 delta)
{
    if (!c || !c->state || !finite3(delta)) return;
    mm_feet *f = &c->state->feet;
    for (int k = 0; k < 2; ++k) {
        f->heel_lock[k] = mm_vec3_add(f->heel_lock[k], delta);
        f->toe_lock[k] = mm_vec3_add(f->toe_lock[k], delta);
    }
}

void mm_character_translate(mm_character *c, mm_vec3 delta)
{
    if (!c || !c->state || !finite3(delta)) return;
    mm_character_state *s = c->state;
    s->root_motion.root.translation = mm_vec3_add(s->root_motion.root.translation, delta);
    s->pose.local_positions[0] = s->root_motion.root.translation;
    for (int j = 0; j < c->db->joint_count; ++j)
        s->pose.global[j].translation = mm_vec3_add(s->pose.global[j].translation, delta);
    for (int k = 0; k < 4; ++k) s->feet.raw_contacts[k] = mm_vec3_add(s->feet.raw_contacts[k], delta);
    for (int k = 0; k < 2; ++k) { /* what the feet follow moved with the body, not by itself */
        s->feet.last_ankle[k] = mm_vec3_add(s->feet.last_ankle[k], delta);
        s->feet.last_toe[k] = mm_vec3_add(s->feet.last_toe[k], delta);
    }
    s->trajectory.position = mm_vec3_add(s->trajectory.position, delta);
    publish(c);
}

void mm_character_teleport_simulation(mm_character *c, mm_vec3 position, mm_quat facing)
{
    if (!c || !c->state) return;
    mm_trajectory_teleport(&c->state->trajectory, position, facing);
}

void mm_character_push_simulation(mm_character *c, mm_vec3 position)
{
    if (!c || !c->state || !finite3(position)) return;
    c->state->trajectory.position = position;
}

void mm_character_halt_simulation(mm_character *c)
{
    if (!c || !c->state) return;
    c->state->trajectory.velocity = mm_vec3_make(0, 0, 0);
}

void mm_character_set_search_phase(mm_character *c, float phase)
{
    if (!c || !c->state || !(phase >= 0.0f && phase < 1.0f)) return;
    c->state->matching.search_phase = phase;
    c->state->matching.phase_pending = true;
}

void mm_character_set_walls(mm_character *c, const mm_scene *scene)
{
    if (!c || !c->state) return;
    mm_trajectory *t = &c->state->trajectory;
    mm_trajectory_set_scene(t, scene, t->pass_height);
}

void mm_character_set_wall_pass(mm_character *c, float pass_height)
{
    if (!c || !c->state) return;
    mm_trajectory *t = &c->state->trajectory;
    mm_trajectory_set_scene(t, t->scene, pass_height);
}

int mm_character_future_times(const mm_character *c, float *times)
{
    if (!c || !c->db || !times || c->db->frame_count < 1) return 0;
    mm_pose_data pd; /* the times are the database's, the same for every frame */
    mm_database_pose(c->db, 0, &pd);
    int n = 0;
    for (int i = 0; i < pd.traj_count; ++i)
        if (pd.traj_times[i] > 0.0f) times[n++] = pd.traj_times[i];
    return n;
}

mm_result mm_character_set_future(mm_character *c, const mm_vec3 *positions, const mm_quat *facings,
                                  int count, mm_error *err)
{
    if (!c || !c->state) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no character");
    mm_matching *m = &c->state->matching;
    if (count == 0) {
        m->future_count = 0;
        return MM_OK;
    }
    float times[MM_MAX_TRAJ_SAMPLES];
    int want = mm_character_future_times(c, times);
    if (count != want || !positions || !facings)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0,
                            "a future of %d points: the database's trajectory has %d future times", count,
                            want);
    for (int k = 0; k < count; ++k) {
        mm_vec3 p = positions[k];
        mm_quat q = facings[k];
        float len = sqrtf(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
        if (!isfinite(p.x) || !isfinite(p.z) || !isfinite(len) || !(len > 0.0f))
            return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0,
                                "future point %d: a position or facing that is not finite (or a zero facing)",
                                k);
    }
    for (int k = 0; k < count; ++k) {
        mm_quat q = facings[k];
        float len = sqrtf(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
        m->future_positions[k] = mm_vec3_make(positions[k].x, 0.0f, positions[k].z);
        m->future_facings[k] = (mm_quat){q.x / len, q.y / len, q.z / len, q.w / len};
    }
    m->future_count = count;
    return MM_OK;
}

/* ---- the debugger's view: candidates and snapshots --------------------------------------- */

mm_result mm_character_set_candidates(mm_character *c, int k, mm_error *err)
{
    if (!c || !c->state || k < 1)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "candidates: needs a character and k >= 1");
    mm_matching *m = &c->state->matching;
    if (k == m->candidate_capacity || (k == 1 && m->candidate_capacity == 0)) return MM_OK;
    mm_search_result *room = NULL;
    if (k > 1) { /* the winner alone needs no room: it is last_result */
        room = (mm_search_result *)mm_alloc_array(&c->allocator, (size_t)k, sizeof(mm_search_result));
        if (!room) return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory for %d candidates", k);
        room[0] = m->last_result;
        for (int i = 1; i < k; ++i) room[i].frame = -1, room[i].base = room[i].cost = 0.0f;
    }
    mm_free(&c->allocator, m->candidates);
    m->candidates = room;
    m->candidate_capacity = k > 1 ? k : 0;
    if (m->candidate_count > 1) m->candidate_count = 1; /* the older ones are gone */
    return MM_OK;
}

int mm_character_candidates(const mm_character *c, mm_candidate *out, int max)
{
    if (!c || !c->state || !out || max < 1) return 0;
    const mm_database *db = c->db;
    const mm_matching *m = &c->state->matching;
    const mm_search_result *found = m->candidate_capacity > 0 ? m->candidates : &m->last_result;
    int n = m->searches > 0 && m->last_result.frame >= 0 ? m->candidate_count : 0;
    if (n > (m->candidate_capacity > 0 ? m->candidate_capacity : 1)) n = m->candidate_capacity;
    if (n > max) n = max;
    const mm_search_params *p = &m->last_params;
    int playing = p->current_frame >= 0 && p->current_frame < db->frame_count ? p->current_frame : -1;
    int next = playing >= 0 ? db->frame_next[playing] : -1;
    for (int i = 0; i < n; ++i) {
        mm_candidate *o = &out[i];
        memset(o, 0, sizeof *o);
        o->frame = found[i].frame;
        if (o->frame < 0 || o->frame >= db->frame_count) {
            o->clip = -1;
            continue;
        }
        o->clip = db->frame_clip[o->frame];
        o->cost = found[i].cost;
        o->base = found[i].base;
        mm_search_cost_terms(db, m->query, p, o->frame, &o->terms);
        /* the favours as the search applies them (mm/search.h): a factor on the base for loops,
         * one for other contacts than the frame playing's, then a factor and a bias for the frame
         * after the one playing */
        float cost = o->base;
        if (db->clips[o->clip].loop) {
            o->loop_favour = cost * (p->loop_anim_favour - 1.0f);
            cost *= p->loop_anim_favour;
        }
        if (p->contact_pattern >= 0 && (int)db->contacts[o->frame] != p->contact_pattern) {
            float f = p->contact_mismatch_favour >= 0.0f ? p->contact_mismatch_favour : 0.0f;
            o->contact_favour = cost * (f - 1.0f);
            cost *= f;
        }
        if (o->frame == next) {
            o->next_pose_favour = cost * (p->next_pose_favour - 1.0f);
            o->continuing_bias = -p->continuing_bias;
        }
    }
    return n;
}

/* A snapshot: this header, then the state's block, the simulation's recorded past and the
 * candidates. The block's own pointers are laid out again on load (lay_out); pointers out of
 * the block (the database's skeleton, the past, the candidates, the desc's clock and allocator)
 * stay the loading character's. */
#define SNAPSHOT_MAGIC   0x70616e73u /* "snap" */
#define SNAPSHOT_VERSION 1u
typedef struct snapshot_header {
    uint32_t magic, version;
    uint64_t block_size;
    int32_t joint_count, dims, history_capacity, candidate_capacity;
    mm_character_desc desc; /* the public desc (mm_character_tune changes it) */
} snapshot_header;

/* A desc without its pointers (a clock, an allocator, the feet's names): what a snapshot keeps. */
static void desc_without_pointers(mm_character_desc *d)
{
    d->clock = NULL;
    d->allocator = NULL;
    d->trajectory.allocator = NULL;
    d->left_foot = d->right_foot = NULL;
}

/* The state as a snapshot keeps it: every pointer null (into the block, laid out again on load,
 * or out of it, kept by the loading character), so that the same state gives the same bytes in
 * any character. */
static void state_without_pointers(mm_character_state *s)
{
    desc_without_pointers(&s->desc);
    s->rig.joints = NULL;
    s->trajectory.history_position = NULL;
    s->trajectory.history_facing = NULL;
    memset(&s->trajectory.allocator, 0, sizeof s->trajectory.allocator);
    s->trajectory.desc.allocator = NULL;
    s->matching.query = NULL;
    s->matching.candidates = NULL;
    mm_transition *tr = &s->transition;
    tr->rotations = tr->previous_rotations = NULL;
    tr->positions = tr->previous_positions = NULL;
    tr->rotation_offset = tr->rotation_offset_velocity = NULL;
    tr->position_offset = tr->position_offset_velocity = NULL;
    tr->legs = NULL;
    tr->slot_rotations = NULL;
    tr->slot_positions = NULL;
    tr->frame_rotations = NULL;
    tr->frame_positions = NULL;
    s->pose.local_rotations = NULL;
    s->pose.local_positions = NULL;
    s->pose.global = NULL;
    s->block = NULL;
}

/* The parts of a snapshot of c, in bytes. */
static void snapshot_parts(const mm_character *c, size_t *block, size_t *history, size_t *candidates)
{
    lay_out(NULL, (size_t)c->db->joint_count, (size_t)c->db->dims_padded, block);
    size_t samples = (size_t)c->state->trajectory.history_capacity;
    *history = samples * (sizeof(mm_vec3) + sizeof(mm_quat));
    *candidates = (size_t)c->state->matching.candidate_capacity * sizeof(mm_search_result);
}

size_t mm_character_snapshot_bytes(const mm_character *c)
{
    if (!c || !c->state) return 0;
    size_t block, history, candidates;
    snapshot_parts(c, &block, &history, &candidates);
    return sizeof(snapshot_header) + block + history + candidates;
}

mm_result mm_character_snapshot_save(const mm_character *c, void *memory, size_t bytes, mm_error *err)
{
    size_t need = mm_character_snapshot_bytes(c);
    if (!need || !memory || bytes < need)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "snapshot: %zu bytes given, %zu needed",
                            bytes, need);
    const mm_character_state *s = c->state;
    size_t block, history, candidates;
    snapshot_parts(c, &block, &history, &candidates);
    snapshot_header h;
    memset(&h, 0, sizeof h);
    h.magic = SNAPSHOT_MAGIC, h.version = SNAPSHOT_VERSION;
    h.block_size = block;
    h.joint_count = c->db->joint_count, h.dims = c->db->dims_padded;
    h.history_capacity = s->trajectory.history_capacity;
    h.candidate_capacity = s->matching.candidate_capacity;
    memcpy(&h.desc, &c->desc, sizeof h.desc);
    desc_without_pointers(&h.desc);
    unsigned char *at = (unsigned char *)memory;
    memcpy(at, &h, sizeof h);
    at += sizeof h;
    memcpy(at, s->block, block); /* the state first (lay_out), then its arrays */
    mm_character_state bare;
    memcpy(&bare, s, sizeof bare);
    state_without_pointers(&bare);
    memcpy(at, &bare, sizeof bare);
    at += block;
    size_t samples = (size_t)s->trajectory.history_capacity;
    memcpy(at, s->trajectory.history_position, samples * sizeof(mm_vec3));
    at += samples * sizeof(mm_vec3);
    memcpy(at, s->trajectory.history_facing, samples * sizeof(mm_quat));
    at += samples * sizeof(mm_quat);
    if (candidates) memcpy(at, s->matching.candidates, candidates);
    return MM_OK;
}

mm_result mm_character_snapshot_load(mm_character *c, const void *memory, size_t bytes, mm_error *err)
{
    size_t need = mm_character_snapshot_bytes(c);
    snapshot_header h;
    if (!need || !memory || bytes < sizeof h)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "snapshot: no character or no snapshot");
    memcpy(&h, memory, sizeof h);
    mm_character_state *s = c->state;
    size_t block, history, candidates;
    snapshot_parts(c, &block, &history, &candidates);
    if (h.magic != SNAPSHOT_MAGIC || h.version != SNAPSHOT_VERSION || h.block_size != block ||
        h.joint_count != c->db->joint_count || h.dims != c->db->dims_padded ||
        h.history_capacity != s->trajectory.history_capacity ||
        h.candidate_capacity != s->matching.candidate_capacity || bytes < need)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0,
                            "snapshot: of another character's layout (or cut short)");
    /* what lies outside the block stays this character's */
    char *own_block = (char *)s->block;
    const mm_joint *joints = s->rig.joints;
    mm_vec3 *history_position = s->trajectory.history_position;
    mm_quat *history_facing = s->trajectory.history_facing;
    mm_allocator history_allocator = s->trajectory.allocator;
    const mm_allocator *trajectory_desc_allocator = s->trajectory.desc.allocator;
    mm_search_result *room = s->matching.candidates;
    mm_character_desc own = c->desc;
    const mm_character_desc own_state_desc = s->desc;

    const unsigned char *at = (const unsigned char *)memory + sizeof h;
    memcpy(own_block, at, block);
    at += block;
    s = lay_out(own_block, (size_t)c->db->joint_count, (size_t)c->db->dims_padded, &block);
    s->block = own_block;
    s->rig.joints = joints;
    s->trajectory.history_position = history_position;
    s->trajectory.history_facing = history_facing;
    s->trajectory.allocator = history_allocator;
    s->trajectory.desc.allocator = trajectory_desc_allocator;
    s->matching.candidates = room;
    s->desc.clock = own_state_desc.clock;
    s->desc.allocator = own_state_desc.allocator;
    s->desc.left_foot = own_state_desc.left_foot, s->desc.right_foot = own_state_desc.right_foot;
    s->desc.trajectory.allocator = own_state_desc.trajectory.allocator;
    size_t samples = (size_t)s->trajectory.history_capacity;
    memcpy(history_position, at, samples * sizeof(mm_vec3));
    at += samples * sizeof(mm_vec3);
    memcpy(history_facing, at, samples * sizeof(mm_quat));
    at += samples * sizeof(mm_quat);
    if (candidates) memcpy(room, at, candidates);
    c->state = s;
    c->desc = h.desc;
    c->desc.clock = own.clock;
    c->desc.allocator = own.allocator;
    c->desc.left_foot = own.left_foot, c->desc.right_foot = own.right_foot;
    c->desc.trajectory.allocator = own.trajectory.allocator;
    publish(c);
    return MM_OK;
}
