/* The character controller: playback, matching, inertialization, root motion. No allocation
 * after mm_character_init. */
#include <mm/character.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

#include <mm/distance.h>
#include <mm/spring.h>

void mm_character_defaults(mm_character_desc *d)
{
    memset(d, 0, sizeof *d);
    d->search_interval = 0.1f;
    d->turn_threshold = 0.5f;
    d->transition_halflife = 0.2f; /* 0.1 s left hand pops of 32 cm on LAFAN1, 0.2 s 10-12 cm */
    d->crossfade_time = 0.2f;
    d->idle_speed = 0.15f;
    d->idle_hysteresis = 0.1f;
    d->idle_root_speed = 1.0f; /* LAFAN1: demo slide 6.1 -> 5.2 cm/s; 0.5 and 0.3 hurt stop_and_go */
    d->sync_halflife = 0.3f;
    d->sync_max_distance = 0.3f;
    d->sync_max_angle = 0.6f;
    d->angle_threshold = 0.35f;
    d->angle_revise_speed = 0.0f; /* off: 0.2-0.5 rad/s was measured to triple foot slide on LAFAN1 walks */
    d->skip_frames = 3;
    d->velocity_change_ratio = 0.9f; /* LAFAN1: docs/metrics.md, "What got it there" */
    d->velocity_change_speed = 2.0f;
    /* 0.2 m: 5.7 cm/s mean foot slide over the shipped scripts on LAFAN1 and 10.1 on the built-in
     * set, 0.4 m: 4.7 and 9.0 (the legs' length still bounds how far a lock can be held) */
    d->unlock_radius = 0.4f;
    d->foot_halflife = 0.1f;
    d->plant_time = 0.033f; /* LAFAN1 mean slide 0.80 -> 0.52 cm/s; 0.05 / 0.1 s: 0.54 / 0.70 */
    d->max_hip_drop = 0.1f;
    d->left_foot = "LeftFoot";
    d->right_foot = "RightFoot";
    d->method = MM_SEARCH_FAST;
    d->distance_matching = false; /* measured on LAFAN1: docs/distance.md "In the controller" */
    d->warping = false;
    d->rate_min = MM_DISTANCE_RATE_MIN_DEFAULT;
    d->rate_max = MM_DISTANCE_RATE_MAX_DEFAULT;
    d->stride_min = 0.8f;
    d->stride_max = 1.2f;
    d->orientation_speed = 10.0f;
    d->orientation_max = MM_WARP_ORIENTATION_MAX_DEFAULT;
}

void mm_character_default_params(const mm_database *db, mm_search_params *p)
{
    mm_search_params_defaults(db, p);
    /* keep playing unless a frame is clearly better: on LAFAN1's straight walk 0.6 made
     * 3 transitions per second instead of 5 (0.8), half the foot slide and pops */
    p->next_pose_favour = 0.6f;
    /* the moves (mm/moves.h) play their clips themselves: never a place for locomotion to go */
    p->excluded_tags = mm_search_tag_mask(db, "DoNotUse") | mm_search_tag_mask(db, "Jump") |
                       mm_search_tag_mask(db, "VaultLow") | mm_search_tag_mask(db, "VaultHigh") |
                       mm_search_tag_mask(db, "Climb") | mm_search_tag_mask(db, "Drop");
    /* the last 0.25 s of a one-shot clip only extrapolates its trajectory: not a place to go */
    p->end_margin = (int)ceilf(0.25f / db->interval);
}

static float yaw_of(mm_quat q)
{
    mm_vec3 f = mm_quat_rotate(q, mm_vec3_make(0, 0, 1));
    return atan2f(f.x, f.z);
}

static mm_quat yaw_quat(float yaw) { return mm_quat_from_axis_angle(mm_vec3_make(0, 1, 0), yaw); }

static float wrap(float a) { return remainderf(a, (float)(2.0 * MM_PI)); }

/* The database pose at a playhead: frame and the next, blended by the fraction. */
static void play_pose_at(const mm_character *c, int frame, float fraction, mm_quat *rot, mm_vec3 *pos)
{
    const mm_database *db = c->db;
    int next = db->frame_next[frame] >= 0 ? db->frame_next[frame] : frame;
    const mm_quat *r0 = mm_database_rotations(db, frame), *r1 = mm_database_rotations(db, next);
    const mm_vec3 *p0 = mm_database_positions(db, frame), *p1 = mm_database_positions(db, next);
    for (int j = 0; j < db->joint_count; ++j) {
        rot[j] = mm_quat_slerp(r0[j], r1[j], fraction);
        pos[j] = mm_vec3_lerp(p0[j], p1[j], fraction);
    }
}

/* The database's root motion at the playhead: that of the frame interval it is in (the root
 * velocity of a frame is the motion from the frame before to it). */
static void play_root_at(const mm_character *c, int frame, mm_vec3 *velocity, float *yaw_rate)
{
    const mm_database *db = c->db;
    int next = db->frame_next[frame] >= 0 ? db->frame_next[frame] : frame;
    /* distance matching plays the clip at play_rate and stride warping stretches the steps by
     * stride_scale: the root moves as much faster (both are exactly 1 when off) */
    *velocity = mm_vec3_scale(db->root_velocity[next], c->play_rate * c->stride_scale);
    *yaw_rate = db->root_angular_velocity[next] * c->play_rate;
}

/* Crossfade mode: the mixer's blend of its slots' poses (into rot and pos) or root motion (the
 * weighted sum of theirs); either pair may be NULL. */
static void crossfade_play(const mm_character *c, mm_quat *rot, mm_vec3 *pos, mm_vec3 *velocity,
                           float *yaw_rate)
{
    const mm_quat *r[MM_MIXER_SLOTS];
    const mm_vec3 *p[MM_MIXER_SLOTS];
    float w[MM_MIXER_SLOTS];
    size_t n = (size_t)c->db->joint_count;
    mm_vec3 v_sum = mm_vec3_make(0, 0, 0);
    float y_sum = 0.0f;
    for (int i = 0; i < c->mixer.count; ++i) {
        const mm_mixer_slot *s = &c->mixer.slots[i];
        r[i] = c->slot_rotations + (size_t)i * n, p[i] = c->slot_positions + (size_t)i * n, w[i] = s->weight;
        if (rot) { /* blended in model space (mm/mixer.h: mm_pose_to_model) */
            play_pose_at(c, s->source, s->fraction, c->slot_rotations + (size_t)i * n,
                         c->slot_positions + (size_t)i * n);
            mm_pose_to_model(c->db->joints, (int)n, c->slot_rotations + (size_t)i * n);
        }
        mm_vec3 v;
        float y;
        play_root_at(c, s->source, &v, &y);
        v_sum = mm_vec3_add(v_sum, mm_vec3_scale(v, s->weight));
        y_sum += y * s->weight;
    }
    if (rot && pos) {
        /* hemispheres from the last tick's output, so that the blend moves continuously */
        mm_quat *reference = c->slot_rotations + (size_t)MM_MIXER_SLOTS * n;
        memcpy(reference, c->pose_previous_rotations, sizeof(mm_quat) * n);
        mm_pose_to_model(c->db->joints, (int)n, reference);
        mm_pose_blend(r, p, w, c->mixer.count, (int)n, reference, rot, pos);
        mm_pose_to_local(c->db->joints, (int)n, rot);
    }
    if (velocity) *velocity = v_sum;
    if (yaw_rate) *yaw_rate = y_sum;
}

/* The pose and root motion played: the playhead's, or in crossfade mode the mixer's blend. */
static void play_pose(const mm_character *c, mm_quat *rot, mm_vec3 *pos)
{
    if (c->desc.transition_mode == MM_TRANSITION_CROSSFADE)
        crossfade_play(c, rot, pos, NULL, NULL);
    else
        play_pose_at(c, c->frame, (float)c->frame_fraction, rot, pos);
}

static void play_root(const mm_character *c, mm_vec3 *velocity, float *yaw_rate)
{
    if (c->desc.transition_mode == MM_TRANSITION_CROSSFADE)
        crossfade_play(c, NULL, NULL, velocity, yaw_rate);
    else
        play_root_at(c, c->frame, velocity, yaw_rate);
}

static void compute_global(mm_character *c)
{
    const mm_database *db = c->db;
    c->global[0] = c->root;
    for (int j = 1; j < db->joint_count; ++j) {
        mm_xform local = mm_xform_make(c->local_rotations[j], c->local_positions[j]);
        c->global[j] = mm_xform_mul(c->global[db->joints[j].parent], local);
    }
}

mm_result mm_character_init(mm_character *c, const mm_database *db, const mm_searcher *searcher,
                            const mm_character_desc *desc, mm_error *err)
{
    if (!c) return MM_ERR_INVALID_ARGUMENT;
    memset(c, 0, sizeof *c);
    if (!db || !searcher || searcher->db != db)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0,
                            "a character needs a database and its searcher");
    mm_character_defaults(&c->desc);
    if (desc) c->desc = *desc;
    if (c->desc.allocator) c->allocator = *c->desc.allocator;
    c->db = db;
    c->searcher = searcher;
    if (!c->desc.use_params) mm_character_default_params(db, &c->desc.params);
    mm_result r = mm_trajectory_init(&c->trajectory, c->desc.has_trajectory ? &c->desc.trajectory : NULL,
                                     &c->allocator);
    if (r != MM_OK) return mm_error_set(err, r, 0, 0, "trajectory: bad parameters");
    size_t n = (size_t)db->joint_count;
    const mm_allocator *a = &c->allocator;
    c->local_rotations = (mm_quat *)mm_alloc_array(a, n, sizeof(mm_quat));
    c->local_positions = (mm_vec3 *)mm_alloc_array(a, n, sizeof(mm_vec3));
    c->previous_rotations = (mm_quat *)mm_alloc_array(a, n, sizeof(mm_quat));
    c->previous_positions = (mm_vec3 *)mm_alloc_array(a, n, sizeof(mm_vec3));
    c->rotation_offset = (mm_vec3 *)mm_alloc_array(a, n, sizeof(mm_vec3));
    c->rotation_offset_velocity = (mm_vec3 *)mm_alloc_array(a, n, sizeof(mm_vec3));
    c->position_offset = (mm_vec3 *)mm_alloc_array(a, n, sizeof(mm_vec3));
    c->position_offset_velocity = (mm_vec3 *)mm_alloc_array(a, n, sizeof(mm_vec3));
    c->global = (mm_xform *)mm_alloc_array(a, n, sizeof(mm_xform));
    c->pose_rotations = (mm_quat *)mm_alloc_array(a, n, sizeof(mm_quat));
    c->pose_previous_rotations = (mm_quat *)mm_alloc_array(a, n, sizeof(mm_quat));
    c->pose_positions = (mm_vec3 *)mm_alloc_array(a, n, sizeof(mm_vec3));
    c->pose_previous_positions = (mm_vec3 *)mm_alloc_array(a, n, sizeof(mm_vec3));
    c->query = (float *)mm_alloc_array(a, (size_t)db->dims_padded, sizeof(float));
    c->slot_rotations = (mm_quat *)mm_alloc_array(a, (MM_MIXER_SLOTS + 1) * n, sizeof(mm_quat));
    c->slot_positions = (mm_vec3 *)mm_alloc_array(a, MM_MIXER_SLOTS * n, sizeof(mm_vec3));
    if (!c->local_rotations || !c->local_positions || !c->previous_rotations || !c->previous_positions ||
        !c->rotation_offset || !c->rotation_offset_velocity || !c->position_offset ||
        !c->position_offset_velocity || !c->global || !c->pose_rotations || !c->pose_previous_rotations ||
        !c->pose_positions || !c->pose_previous_positions || !c->query || !c->slot_rotations ||
        !c->slot_positions) {
        mm_character_free(c);
        return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    }
    const char *feet[2] = {c->desc.left_foot ? c->desc.left_foot : "LeftFoot",
                           c->desc.right_foot ? c->desc.right_foot : "RightFoot"};
    c->pelvis_joint = -1;
    for (int k = 0; k < 2; ++k) {
        c->foot_joint[k] = c->toe_joint[k] = -1;
        for (int j = 0; j < db->joint_count; ++j)
            if (strcmp(db->joints[j].name, feet[k]) == 0) c->foot_joint[k] = j;
        /* the chain ankle <- knee <- hip must exist below the root */
        if (c->foot_joint[k] >= 0 && (db->joints[c->foot_joint[k]].parent < 1 ||
                                      db->joints[db->joints[c->foot_joint[k]].parent].parent < 1))
            c->foot_joint[k] = -1;
        int ankle = c->foot_joint[k]; /* the toe: the ankle's first child */
        for (int j = ankle + 1; ankle >= 0 && j < db->joint_count && c->toe_joint[k] < 0; ++j)
            if (db->joints[j].parent == ankle) c->toe_joint[k] = j;
    }
    if (c->foot_joint[0] >= 0 && c->foot_joint[1] >= 0) { /* the pelvis: the parent both legs hang from */
        int left = db->joints[db->joints[db->joints[c->foot_joint[0]].parent].parent].parent;
        int right = db->joints[db->joints[db->joints[c->foot_joint[1]].parent].parent].parent;
        if (left == right && left >= 1) c->pelvis_joint = left;
    }
    c->desc.left_foot = c->desc.right_foot = NULL; /* not kept: the caller's strings */
    for (int g = 0; g < MM_GAIT_COUNT; ++g) {
        char name[16];
        snprintf(name, sizeof name, "%s", mm_gait_name((mm_gait)g));
        name[0] = (char)(name[0] - 'a' + 'A'); /* "Walk" */
        c->gait_tags[g] = mm_search_tag_mask(db, name) | mm_search_tag_mask(db, mm_gait_name((mm_gait)g));
    }
    c->frame = 0;
    for (int k = 0; k < db->clip_count; ++k)
        if (db->clips[k].type == MM_CLIP_IDLE) {
            c->frame = db->clips[k].first_frame;
            break;
        }
    c->idle = true;
    c->play_rate = c->stride_scale = 1.0f;
    c->no_distance_tag = mm_search_tag_mask(db, "NoDistanceMatching");
    c->root = mm_xform_identity();
    c->since_search = INFINITY; /* search on the first tick */
    c->last_result.frame = -1;
    mm_mixer_init(&c->mixer, c->frame, 0.0f);
    play_pose(c, c->local_rotations, c->local_positions);
    memcpy(c->previous_rotations, c->local_rotations, n * sizeof(mm_quat));
    memcpy(c->previous_positions, c->local_positions, n * sizeof(mm_vec3));
    memcpy(c->pose_rotations, c->local_rotations, n * sizeof(mm_quat));
    memcpy(c->pose_positions, c->local_positions, n * sizeof(mm_vec3));
    memcpy(c->pose_previous_rotations, c->local_rotations, n * sizeof(mm_quat));
    memcpy(c->pose_previous_positions, c->local_positions, n * sizeof(mm_vec3));
    compute_global(c);
    return MM_OK;
}

void mm_character_free(mm_character *c)
{
    if (!c) return;
    mm_trajectory_free(&c->trajectory);
    const mm_allocator *a = &c->allocator;
    void *p[] = {c->local_rotations,
                 c->local_positions,
                 c->previous_rotations,
                 c->previous_positions,
                 c->rotation_offset,
                 c->rotation_offset_velocity,
                 c->position_offset,
                 c->position_offset_velocity,
                 c->global,
                 c->pose_rotations,
                 c->pose_previous_rotations,
                 c->pose_positions,
                 c->pose_previous_positions,
                 c->query,
                 c->slot_rotations,
                 c->slot_positions};
    for (size_t i = 0; i < sizeof p / sizeof p[0]; ++i) mm_free(a, p[i]);
    memset(c, 0, sizeof *c);
}

/* The query: the pose of the frame playing (from the database) and the simulated trajectory in
 * the character's frame. */
static void build_query(mm_character *c, const mm_input *in)
{
    mm_pose_data pd;
    mm_database_pose(c->db, c->frame, &pd);
    mm_vec3 positions[MM_MAX_TRAJ_SAMPLES];
    mm_quat facings[MM_MAX_TRAJ_SAMPLES];
    mm_trajectory_sample(&c->trajectory, in, pd.traj_times, pd.traj_count, positions, facings);
    mm_xform inverse = mm_xform_inverse(c->root);
    for (int i = 0; i < pd.traj_count; ++i) {
        pd.traj_positions[i] = mm_xform_apply_point(inverse, positions[i]);
        pd.traj_directions[i] =
            mm_quat_inv_rotate(c->root.rotation, mm_quat_rotate(facings[i], mm_vec3_make(0, 0, 1)));
    }
    mm_search_query_from_pose(c->db, &pd, c->query);
}

/* Jumps to frame `to`, keeping the animated pose where it is: the difference becomes an offset that
 * decays (inertialization). The pose is the one before foot IK: IK is a layer on top, continuous
 * by itself (its locks and offsets carry over), and taking it into the offsets would make the
 * animated feet drift from their locks as the offsets decay. Joint 0 (the root) is driven by root
 * motion and left out.
 *
 * The new clip stands at (to, fraction) on this tick, as the old one stands at its playhead after
 * this tick's advance. The offsets are taken one tick earlier, against the new clip's pose there
 * (its pose at the playhead moved back by its own velocity over dt), and then decay by dt in the
 * update while the clip plays on: the output keeps its position and its velocity (the last two
 * ticks') across the jump. Taken against the playhead itself, the tick of the jump would show the
 * new clip standing still (its velocity lost: pops and foot slide one tick after each jump). */
static void crossfade_to(mm_character *c, int to, bool uncancellable);

static void transition(mm_character *c, int to, double fraction, float dt)
{
    const mm_database *db = c->db;
    if (c->desc.transition_mode == MM_TRANSITION_CROSSFADE) { /* a jump asked for: never cancelled */
        crossfade_to(c, to, true);
        return;
    }
    int next = db->frame_next[to];
    c->frame = to;
    c->frame_fraction = next >= 0 && fraction > 0.0 && fraction < 1.0 ? fraction : 0.0;
    /* the new clip's velocity at the playhead: that of the frame interval it is in (zero on a
     * clip's last frame, which playback holds) */
    const mm_quat *r0 = mm_database_rotations(db, to), *r1 = mm_database_rotations(db, next >= 0 ? next : to);
    const mm_vec3 *p0 = mm_database_positions(db, to), *p1 = mm_database_positions(db, next >= 0 ? next : to);
    /* the new clip plays on at the play rate (distance matching; 1 otherwise): its velocity per
     * second is the rate times its velocity per frame interval */
    float rate = isfinite(c->play_rate) && c->play_rate >= 0.0f ? c->play_rate : 1.0f;
    float inv_interval = next >= 0 ? rate / db->interval : 0.0f, inv_dt = dt > 0.0f ? 1.0f / dt : 0.0f;
    const mm_quat *now_r = c->pose_rotations, *last_r = c->pose_previous_rotations;
    const mm_vec3 *now_p = c->pose_positions, *last_p = c->pose_previous_positions;
    for (int j = 1; j < db->joint_count; ++j) {
        /* the animated pose's velocity (from the last two ticks) minus the new clip's */
        mm_vec3 w_out = mm_vec3_scale(
            mm_quat_log(mm_quat_abs(mm_quat_mul(now_r[j], mm_quat_inverse(last_r[j])))), inv_dt);
        mm_vec3 w_dst =
            mm_vec3_scale(mm_quat_log(mm_quat_abs(mm_quat_mul(r1[j], mm_quat_inverse(r0[j])))), inv_interval);
        mm_vec3 v_dst = mm_vec3_scale(mm_vec3_sub(p1[j], p0[j]), inv_interval);
        /* the new clip one tick back: the playhead's pose (slerp and lerp within one frame
         * interval, whose rates are w_dst and v_dst) moved back by dt */
        mm_quat r = mm_quat_slerp(r0[j], r1[j], (float)c->frame_fraction);
        mm_vec3 p = mm_vec3_lerp(p0[j], p1[j], (float)c->frame_fraction);
        mm_quat r_back = mm_quat_normalize(mm_quat_mul(mm_quat_exp(mm_vec3_scale(w_dst, -dt)), r));
        mm_vec3 p_back = mm_vec3_sub(p, mm_vec3_scale(v_dst, dt));
        c->rotation_offset[j] = mm_quat_log(mm_quat_abs(mm_quat_mul(now_r[j], mm_quat_inverse(r_back))));
        c->rotation_offset_velocity[j] = mm_vec3_sub(w_out, w_dst);
        mm_vec3 v_out = mm_vec3_scale(mm_vec3_sub(now_p[j], last_p[j]), inv_dt);
        c->position_offset[j] = mm_vec3_sub(now_p[j], p_back);
        c->position_offset_velocity[j] = mm_vec3_sub(v_out, v_dst);
    }
    /* the root's motion too: the velocity and yaw rate played continue and blend into the new
     * frame's (a jump in root velocity would move every joint at once) */
    mm_vec3 v;
    float w;
    play_root(c, &v, &w);
    c->root_velocity_offset = mm_vec3_sub(c->root_velocity, v);
    c->root_velocity_offset_rate = mm_vec3_make(0, 0, 0);
    c->root_yaw_rate_offset = c->root_yaw_rate - w;
    c->root_yaw_rate_offset_rate = 0.0f;
    ++c->transitions;
}

/* Crossfade mode: frame `to` enters the mixer's slot 0 (the playhead), unless the mixer cancels
 * it (dropped, counted). Frames tagged "Jump" or "Uncancellable" (the seed's jumps) are never
 * cancelled. */
static void crossfade_to(mm_character *c, int to, bool uncancellable)
{
    const mm_database *db = c->db;
    uint64_t forced = mm_search_tag_mask(db, "Jump") | mm_search_tag_mask(db, "Uncancellable");
    uncancellable = uncancellable || (db->frame_tags && (db->frame_tags[to] & forced));
    if (!mm_mixer_start(&c->mixer, to, 0.0f, c->desc.crossfade_time, uncancellable)) {
        ++c->cancelled_transitions;
        return;
    }
    c->frame = to;
    c->frame_fraction = 0.0;
    ++c->transitions;
}

/* Stops and turns (issue 6): when the stick is let go at a run, or turned, the playing clip
 * carries on while the simulation changes its velocity; the stops and turns are other clips', far
 * in pose (40-60 on LAFAN1), and lose to carrying on. While the simulated velocity must change
 * (its distance to the desired one) the trajectory weighs more: the ratio moves toward
 * velocity_change_ratio in proportion to the change, fully at velocity_change_speed. */
#define VELOCITY_CHANGE_FROM_SPEED 0.5f /* m/s */

static void velocity_change_weights(const mm_character *c, const mm_input *in, mm_search_params *p)
{
    const mm_character_desc *d = &c->desc;
    mm_vec3 desired, v = c->trajectory.velocity;
    mm_trajectory_desired(&c->trajectory, in, &desired, NULL);
    float dx = desired.x - v.x, dz = desired.z - v.z, change = sqrtf(dx * dx + dz * dz);
    /* from standing they come in with the speed: a start is the pose's to choose (with the
     * trajectory alone a standing pose went into the run-up of a jump) */
    float speed = sqrtf(v.x * v.x + v.z * v.z);
    if (speed < VELOCITY_CHANGE_FROM_SPEED) change *= speed / VELOCITY_CHANGE_FROM_SPEED;
    if (change > 0.0f && d->velocity_change_speed > 0.0f &&
        d->velocity_change_ratio > p->pose_trajectory_ratio && d->velocity_change_ratio <= 1.0f) {
        float s = change < d->velocity_change_speed ? change / d->velocity_change_speed : 1.0f;
        p->pose_trajectory_ratio += (d->velocity_change_ratio - p->pose_trajectory_ratio) * s;
    }
}

static void search(mm_character *c, const mm_input *in, float dt)
{
    const mm_database *db = c->db;
    build_query(c, in);
    mm_search_params p = c->desc.params;
    p.current_frame = c->frame;
    int has_idle = 0;
    for (int k = 0; k < db->clip_count && !has_idle; ++k) has_idle = db->clips[k].type == MM_CLIP_IDLE;
    p.type = !has_idle ? MM_SEARCH_ANY : c->idle ? MM_SEARCH_IDLE : MM_SEARCH_LOCOMOTION;
    /* the gait influences matching through tags named after the gaits ("Walk", "Run", ...):
     * frames tagged with another gait than the one asked for are left out */
    int gait = in && (int)in->gait >= 0 && in->gait < MM_GAIT_COUNT ? (int)in->gait : MM_GAIT_WALK;
    for (int g = 0; g < MM_GAIT_COUNT; ++g)
        if (g != gait) p.excluded_tags |= c->gait_tags[g];
    velocity_change_weights(c, in, &p);
    mm_search_result best;
    double start = c->desc.clock ? c->desc.clock() : 0.0;
    int found = mm_searcher_search(c->searcher, c->query, &p, c->desc.method, &best, 1);
    if (c->desc.clock) c->last_search_us = (float)(1e6 * (c->desc.clock() - start));
    ++c->searches;
    c->since_search = 0.0f;
    c->last_result = best;
    c->last_params = p;
    if (!found || best.frame < 0) return;
    /* where playback goes anyway (a few frames ahead in the same clip): no jump; nor a few frames
     * back in the same clip: jumping back by about what played since the last search would replay
     * the same stretch over and over (an idle frozen in a loop of a few frames) */
    int ahead = best.frame - c->frame;
    int behind = c->desc.skip_frames + (int)ceilf(c->desc.search_interval / db->interval);
    if (db->frame_clip[best.frame] == db->frame_clip[c->frame] && ahead >= -behind &&
        ahead <= c->desc.skip_frames)
        return;
    /* crossfade: cancellable, but not at the end of the clip (the playhead would stand still) */
    if (c->desc.transition_mode == MM_TRANSITION_CROSSFADE)
        crossfade_to(c, best.frame, db->frame_next[c->frame] < 0);
    else
        transition(c, best.frame, c->frame_fraction, dt);
}

/* fraction of the leg's length over which the IK's reach softens (soft_reach) */
#define SOFT_REACH 0.05f

/* Soft IK: the distance the leg is asked to span, for a target at distance lat from the hip of a
 * leg of length `length`. Near full extension the knee moves as the square root of what the leg
 * lacks (a target a millimetre out of reach and back moves the knee centimetres: pops); within
 * the last SOFT_REACH of the length the span approaches the length exponentially instead
 * (continuous in value and slope where it starts), so the knee moves smoothly and the ankle falls
 * short by at most SOFT_REACH * length. */
static float soft_reach(float lat, float length)
{
    float soft = SOFT_REACH * length, start = length - soft;
    if (!(lat > start) || !(soft > 0.0f)) return lat;
    return length - soft * expf(-(lat - start) / soft);
}

/* Two-bone IK: turns the hip (a) and knee (b) so that the ankle (c) reaches target, the knee
 * bending in the plane it bends in now; the ankle takes the world orientation ankle_world. Works
 * on the local rotations and the global transforms of the three joints. */
static void two_bone_ik(mm_character *c, int ankle, mm_vec3 target, mm_quat ankle_world)
{
    const mm_database *db = c->db;
    int knee = db->joints[ankle].parent, hip = db->joints[knee].parent;
    mm_vec3 a = c->global[hip].translation, b = c->global[knee].translation, e = c->global[ankle].translation;
    float lab = mm_vec3_distance(b, a), lcb = mm_vec3_distance(b, e);
    if (lab < 1e-5f || lcb < 1e-5f) return;
    float lat = mm_vec3_distance(target, a), eps = 1e-4f;
    if (lat < eps) lat = eps;
    lat = soft_reach(lat, lab + lcb);
    if (lat > lab + lcb - eps) lat = lab + lcb - eps;
#define CLAMPED_ACOS(x) acosf(fmaxf(-1.0f, fminf(1.0f, (x))))
    mm_vec3 ac = mm_vec3_normalize(mm_vec3_sub(e, a)), ab = mm_vec3_normalize(mm_vec3_sub(b, a));
    mm_vec3 ba = mm_vec3_normalize(mm_vec3_sub(a, b)), bc = mm_vec3_normalize(mm_vec3_sub(e, b));
    mm_vec3 at = mm_vec3_normalize(mm_vec3_sub(target, a));
    float ac_ab_0 = CLAMPED_ACOS(mm_vec3_dot(ac, ab)), ba_bc_0 = CLAMPED_ACOS(mm_vec3_dot(ba, bc));
    float ac_at_0 = CLAMPED_ACOS(mm_vec3_dot(ac, at));
    float ac_ab_1 = CLAMPED_ACOS((lcb * lcb - lab * lab - lat * lat) / (-2.0f * lab * lat));
    float ba_bc_1 = CLAMPED_ACOS((lat * lat - lab * lab - lcb * lcb) / (-2.0f * lab * lcb));
#undef CLAMPED_ACOS
    /* the knee's bending axis. A knee bending forward turns about the character's left axis
     * (cross(leg down, knee forward) points left); where the animated plane is noise (nearly
     * straight leg) or would bend the knee backwards, that axis takes over. */
    mm_vec3 bend = mm_vec3_cross(ac, ab);
    mm_vec3 left = mm_quat_rotate(c->root.rotation, mm_vec3_make(-1, 0, 0));
    left = mm_vec3_normalize(mm_vec3_sub(left, mm_vec3_scale(ac, mm_vec3_dot(left, ac))));
    float straight = mm_vec3_length(bend); /* sine of the knee's bend seen from the hip */
    float w = straight > 1e-6f ? mm_vec3_dot(mm_vec3_scale(bend, 1.0f / straight), left) : 0.0f;
    w = w <= 0.0f ? 0.0f : fminf(1.0f, straight / 0.1f) * w; /* trust in the animated plane */
    bend = mm_vec3_add(mm_vec3_scale(straight > 1e-6f ? mm_vec3_scale(bend, 1.0f / straight) : left, w),
                       mm_vec3_scale(left, 1.0f - w));
    if (mm_vec3_length(bend) < 1e-6f) return;
    bend = mm_vec3_normalize(bend);
    (void)ac_at_0;
    mm_quat a_world = c->global[hip].rotation, b_world = c->global[knee].rotation;
    mm_quat r0 = mm_quat_from_axis_angle(mm_quat_inv_rotate(a_world, bend), ac_ab_1 - ac_ab_0);
    mm_quat r1 = mm_quat_from_axis_angle(mm_quat_inv_rotate(b_world, bend), ba_bc_1 - ba_bc_0);
    c->local_rotations[hip] = mm_quat_normalize(mm_quat_mul(c->local_rotations[hip], r0));
    c->local_rotations[knee] = mm_quat_normalize(mm_quat_mul(c->local_rotations[knee], r1));
    int hip_parent = db->joints[hip].parent;
    c->global[hip] =
        mm_xform_mul(c->global[hip_parent], mm_xform_make(c->local_rotations[hip], c->local_positions[hip]));
    c->global[knee] =
        mm_xform_mul(c->global[hip], mm_xform_make(c->local_rotations[knee], c->local_positions[knee]));
    /* then the leg swings about the hip onto the target, from where the bend left the ankle (the
     * bend axis is not always normal to the plane of ankle and target: swinging from the ankle's
     * old direction missed the target by millimetres) */
    mm_vec3 bent = mm_xform_apply_point(c->global[knee], c->local_positions[ankle]);
    mm_vec3 from = mm_vec3_sub(bent, a);
    if (mm_vec3_length(from) > 1e-6f) {
        mm_quat swing = mm_quat_between(mm_vec3_normalize(from), at);
        c->local_rotations[hip] = mm_quat_normalize(mm_quat_mul(mm_quat_conj(c->global[hip_parent].rotation),
                                                                mm_quat_mul(swing, c->global[hip].rotation)));
        c->global[hip] = mm_xform_mul(c->global[hip_parent],
                                      mm_xform_make(c->local_rotations[hip], c->local_positions[hip]));
        c->global[knee] =
            mm_xform_mul(c->global[hip], mm_xform_make(c->local_rotations[knee], c->local_positions[knee]));
    }
    c->local_rotations[ankle] =
        mm_quat_normalize(mm_quat_mul(mm_quat_conj(c->global[knee].rotation), ankle_world));
}

/* Where foot k's ankle goes by its locks alone: the heel lock; or the toe lock less the animated
 * ankle-to-toe vector (turned by the foot's turn), so that the foot rolls about its planted toe as
 * animated; or, free, the animated ankle. */
static mm_vec3 foot_source(const mm_character *c, int k, mm_vec3 ankle, mm_vec3 toe)
{
    if (c->heel_locked[k]) return c->heel_lock[k];
    if (c->toe_locked[k])
        return mm_vec3_sub(c->toe_lock[k],
                           mm_quat_rotate(mm_quat_exp(c->foot_turn[k]), mm_vec3_sub(toe, ankle)));
    return ankle;
}

/* s until foot k's contact label (heel or toe) turns on in the clip playing at its play rate,
 * if it does within `window`; -1 otherwise */
static float time_to_plant(const mm_character *c, int k, float window)
{
    const mm_database *db = c->db;
    unsigned mask = 3u << (2 * k);
    double step = (double)db->interval / (c->play_rate > 0.1f ? c->play_rate : 0.1f);
    double t = (1.0 - c->frame_fraction) * step;
    for (int f = db->frame_next[c->frame]; f >= 0 && t <= window; f = db->frame_next[f], t += step)
        if (db->contacts[f] & mask) return (float)t;
    return -1.0f;
}

/* rad: the most a foot planted on heel and toe is turned from its animated orientation */
#define MAX_FOOT_TURN 0.8f

/* Foot locking on the contact labels, lowering the hips where the legs cannot reach, then IK; the
 * joints below are recomputed. Every change of what a foot follows (a lock made or released) is
 * carried by foot_offset, which decays: the ankle never jumps. */
static void feet(mm_character *c, float dt)
{
    const mm_database *db = c->db;
    const mm_character_desc *d = &c->desc;
    unsigned label = db->contacts[c->frame];
    mm_vec3 target[2] = {{0, 0, 0}, {0, 0, 0}};
    mm_quat orientation[2] = {{0, 0, 0, 1}, {0, 0, 0, 1}};
    for (int k = 0; k < 2; ++k) {
        int ankle = c->foot_joint[k], toe = c->toe_joint[k];
        if (ankle < 0) continue;
        mm_vec3 a = c->global[ankle].translation, t = toe >= 0 ? c->global[toe].translation : a;
        int heel_on = (label >> (2 * k)) & 1u, toe_on = (label >> (2 * k + 1)) & 1u;
        if (toe < 0) heel_on |= toe_on, toe_on = 0; /* no toe: the ankle holds for both */
        mm_vec3 before = foot_source(c, k, a, t);
        int was_locked = c->heel_locked[k] || c->toe_locked[k];
        if (was_locked && mm_vec3_distance(before, a) > d->unlock_radius) {
            /* pulled too far from the animation: released, and planted again below where the
             * foot now is, one spring step toward the animation (the foot creeps after it;
             * releasing it for the rest of the contact was measured worse: it then slides back
             * at the spring's pace) */
            c->heel_locked[k] = c->toe_locked[k] = false;
        }
        if (!heel_on) c->heel_locked[k] = false;
        if (!toe_on) c->toe_locked[k] = false;
        c->foot_offset[k] = mm_vec3_add(c->foot_offset[k], mm_vec3_sub(before, foot_source(c, k, a, t)));
        mm_spring_decay_vec3(&c->foot_offset[k], &c->foot_offset_velocity[k], d->foot_halflife, dt);
        mm_vec3 out = mm_vec3_add(foot_source(c, k, a, t), c->foot_offset[k]);
        if (d->plant_time > 0.0f && c->foot_placed && !was_locked) {
            /* landing: the foot's step on the ground plane shrinks to nothing as its contact
             * comes (w: the share of plant_time gone; 1 on the tick the label turns on, where
             * the foot is planted where it was), the difference carried by foot_offset like any
             * other. A transition's offsets, or the root's pull, would otherwise bring the foot
             * down at the speed they give it, and the lock would stop it dead from there. */
            float w = 0.0f;
            if (heel_on || toe_on) {
                w = 1.0f;
            } else {
                float left = time_to_plant(c, k, d->plant_time);
                if (left >= 0.0f) w = 1.0f - left / d->plant_time;
            }
            if (w > 0.0f) {
                mm_vec3 from = c->foot_lock[k];
                out.x = from.x + (1.0f - w) * (out.x - from.x);
                out.z = from.z + (1.0f - w) * (out.z - from.z);
                c->foot_offset[k] = mm_vec3_sub(out, foot_source(c, k, a, t));
                c->foot_offset_velocity[k] = mm_vec3_make(0, 0, 0);
            }
        }
        int planted = 0; /* plant where the foot is now */
        if (heel_on && !c->heel_locked[k]) {
            c->heel_locked[k] = true;
            c->heel_lock[k] = out;
            planted = 1;
        }
        if (toe_on && !c->toe_locked[k]) {
            c->toe_locked[k] = true;
            c->toe_lock[k] =
                mm_vec3_add(out, mm_quat_rotate(mm_quat_exp(c->foot_turn[k]), mm_vec3_sub(t, a)));
            planted = 1;
        }
        if (planted) { /* held exactly from here */
            c->foot_offset[k] =
                c->heel_locked[k] ? mm_vec3_make(0, 0, 0) : mm_vec3_sub(out, foot_source(c, k, a, t));
            c->foot_offset_velocity[k] = mm_vec3_make(0, 0, 0);
        }
        if (c->heel_locked[k] && c->toe_locked[k]) {
            /* both planted: the foot turns so that its toe stays on the toe lock (the animated
             * foot may pitch or yaw under a transition's offsets while both labels are on) */
            mm_vec3 turn =
                mm_quat_log(mm_quat_between(mm_vec3_sub(t, a), mm_vec3_sub(c->toe_lock[k], c->heel_lock[k])));
            float angle = mm_vec3_length(turn);
            if (angle > MAX_FOOT_TURN) {
                /* the animation turns the foot further than a planted foot should follow: the
                 * toe lock goes round the heel's as far as it must */
                turn = mm_vec3_scale(turn, MAX_FOOT_TURN / angle);
                c->toe_lock[k] =
                    mm_vec3_add(c->heel_lock[k], mm_quat_rotate(mm_quat_exp(turn), mm_vec3_sub(t, a)));
            }
            c->foot_turn_velocity[k] = mm_vec3_scale(mm_vec3_sub(turn, c->foot_turn[k]), 1.0f / dt);
            c->foot_turn[k] = turn;
        } else {
            mm_spring_decay_vec3(&c->foot_turn[k], &c->foot_turn_velocity[k], d->foot_halflife, dt);
        }
        target[k] = mm_vec3_add(foot_source(c, k, a, t), c->foot_offset[k]);
        /* never below the ground: the root's height in locomotion (it stands on the ground, which
         * a scene may put anywhere); a move's root follows its clip, not the ground */
        if (!c->move_playing && target[k].y < c->root.translation.y) target[k].y = c->root.translation.y;
        orientation[k] = mm_quat_mul(mm_quat_exp(c->foot_turn[k]), c->global[ankle].rotation);
        c->foot_locked[k] = c->heel_locked[k] || c->toe_locked[k];
        c->foot_lock[k] = target[k];
    }
    /* the hips come down as far as the legs need to reach their targets (never below what they
     * need, rising back through a spring) */
    int pelvis = c->pelvis_joint;
    if (pelvis >= 0 && d->max_hip_drop > 0.0f) {
        float need = 0.0f;
        for (int k = 0; k < 2; ++k) {
            int ankle = c->foot_joint[k];
            int knee = db->joints[ankle].parent, hip = db->joints[knee].parent;
            mm_vec3 h = c->global[hip].translation;
            float length = mm_vec3_distance(h, c->global[knee].translation) +
                           mm_vec3_distance(c->global[knee].translation, c->global[ankle].translation);
            float reach = (1.0f - SOFT_REACH) * length;
            float dx = target[k].x - h.x, dz = target[k].z - h.z, across = dx * dx + dz * dz;
            float down =
                across < reach * reach ? h.y - target[k].y - sqrtf(reach * reach - across) : d->max_hip_drop;
            need = fmaxf(need, down);
        }
        need = fminf(need, d->max_hip_drop);
        /* down at once, up through a spring from rest, never past [0, max_hip_drop] (the drop's
         * velocity used to be kept when it went down at once: the spring then carried it past
         * what the legs needed, and past max_hip_drop, moving the whole body) */
        mm_spring_update(&c->hip_drop, &c->hip_drop_velocity, need, d->foot_halflife, dt);
        if (c->hip_drop < need) c->hip_drop = need, c->hip_drop_velocity = 0.0f;
        if (c->hip_drop > d->max_hip_drop || c->hip_drop < 0.0f) {
            c->hip_drop = fminf(fmaxf(c->hip_drop, 0.0f), d->max_hip_drop);
            c->hip_drop_velocity = 0.0f;
        }
        if (c->hip_drop > 0.0f) {
            mm_vec3 down = mm_quat_inv_rotate(c->global[db->joints[pelvis].parent].rotation,
                                              mm_vec3_make(0.0f, -c->hip_drop, 0.0f));
            c->local_positions[pelvis] = mm_vec3_add(c->local_positions[pelvis], down);
            for (int j = pelvis; j < db->joint_count; ++j)
                c->global[j] = mm_xform_mul(c->global[db->joints[j].parent],
                                            mm_xform_make(c->local_rotations[j], c->local_positions[j]));
        }
    }
    for (int k = 0; k < 2; ++k) {
        if (c->foot_joint[k] < 0) continue;
        /* a target out of the leg's reach (a lock the hips moved away from, or the offset a
         * released lock leaves) is brought onto the reach, and the offset with it: otherwise the
         * offset fades out of reach (the leg stays straight) and then sweeps the ankle through its
         * reach at the spring's speed */
        int ankle = c->foot_joint[k], knee = db->joints[ankle].parent, hip = db->joints[knee].parent;
        mm_vec3 h = c->global[hip].translation;
        float reach = mm_vec3_distance(h, c->global[knee].translation) +
                      mm_vec3_distance(c->global[knee].translation, c->global[ankle].translation);
        mm_vec3 r = mm_vec3_sub(target[k], h);
        float len = mm_vec3_length(r);
        if (!c->foot_locked[k] && len > reach && len > 1e-6f) {
            mm_vec3 u = mm_vec3_scale(r, 1.0f / len), onto = mm_vec3_add(h, mm_vec3_scale(u, reach));
            c->foot_offset[k] = mm_vec3_add(c->foot_offset[k], mm_vec3_sub(onto, target[k]));
            float out = mm_vec3_dot(c->foot_offset_velocity[k], u);
            if (out > 0.0f)
                c->foot_offset_velocity[k] = mm_vec3_sub(c->foot_offset_velocity[k], mm_vec3_scale(u, out));
            target[k] = onto;
            c->foot_lock[k] = onto;
        }
        two_bone_ik(c, ankle, target[k], orientation[k]);
    }
    c->foot_placed = true;
    for (int j = 1; j < db->joint_count; ++j) /* below the ankles */
        c->global[j] = mm_xform_mul(c->global[db->joints[j].parent],
                                    mm_xform_make(c->local_rotations[j], c->local_positions[j]));
}

/* Distance matching (docs/distance.md, "In the controller"): the play rate of this tick and the
 * stride scale that warping is to make up. travelled: the simulated root's ground displacement
 * this tick (m). Sets c->playback, c->play_rate and c->stride_scale (the scale asked for; see
 * distance_playback for its easing); never NaN, no allocation. */
static void distance_playback_target(mm_character *c, const mm_input *in, float dt, float travelled)
{
    const mm_database *db = c->db;
    const mm_character_desc *d = &c->desc;
    c->playback = MM_PLAYBACK_CLOCK;
    c->play_rate = 1.0f;
    c->stride_scale = 1.0f;
    if (c->db->frame_tags && (db->frame_tags[c->frame] & c->no_distance_tag)) return;
    int clip = db->frame_clip[c->frame];
    mm_distance_curve curve; /* idle clips play by the clock: standing still is no reason to slow */
    if (db->clips[clip].type == MM_CLIP_IDLE || mm_database_distance_curve(db, clip, &curve) != MM_OK) return;
    const mm_trajectory *t = &c->trajectory;
    float speed = sqrtf(t->velocity.x * t->velocity.x + t->velocity.z * t->velocity.z);
    if (!isfinite(speed)) speed = 0.0f;
    if (!isfinite(travelled) || travelled < 0.0f) travelled = 0.0f;
    float time = (float)((double)(c->frame - db->clips[clip].first_frame) + c->frame_fraction) / curve.fps;
    float rate = 1.0f;
    if (curve.loop) {
        /* a cycle: desired speed / the clip's average speed, clamped */
        float clip_speed = mm_distance_clip_speed(&curve);
        if (d->distance_matching) {
            mm_distance_play_rate(speed, clip_speed, d->rate_min, d->rate_max, &rate);
            c->playback = MM_PLAYBACK_CYCLE;
        }
        mm_distance_stride_scale(speed, clip_speed, rate, d->stride_min, d->stride_max, &c->stride_scale);
    } else {
        int segment = mm_distance_segment_at(&curve, time);
        int kind = curve.segments[segment].kind;
        float before = mm_distance_signed(&curve, time); /* < 0: the stop or pivot is ahead */
        mm_vec3 desired;
        mm_trajectory_desired(t, in, &desired, NULL);
        float wanted = sqrtf(desired.x * desired.x + desired.z * desired.z);
        mm_distance_prediction stop, pivot;
        memset(&stop, 0, sizeof stop);
        memset(&pivot, 0, sizeof pivot);
        if (kind != MM_DISTANCE_NONE && before < 0.0f)
            mm_distance_predict_trajectory(t, in, 0.0f, &stop, &pivot);
        float target = -1.0f;
        if (kind == MM_DISTANCE_STOP && before < 0.0f && stop.found && wanted < d->idle_speed &&
            mm_distance_match_to_target(&curve, segment, stop.distance, &target) == MM_OK) {
            c->playback = MM_PLAYBACK_STOP; /* braking: the clip's stop where the character's is */
        } else if (kind == MM_DISTANCE_PIVOT && before < 0.0f && pivot.found &&
                   mm_distance_match_to_target(&curve, segment, pivot.distance, &target) == MM_OK) {
            c->playback = MM_PLAYBACK_PIVOT;
        } else if (kind == MM_DISTANCE_STOP && before >= 0.0f) {
            c->playback = MM_PLAYBACK_CLOCK; /* past the stop: played out */
        } else {
            float next;
            mm_distance_advance(&curve, time, travelled, dt, d->rate_min, d->rate_max, &next, &rate);
            c->playback = MM_PLAYBACK_DISTANCE;
        }
        if (c->playback == MM_PLAYBACK_STOP || c->playback == MM_PLAYBACK_PIVOT) {
            /* toward the matched time, never backwards, within the clamp */
            rate = (target - time) / dt;
            if (d->rate_min > 0.0f || d->rate_max > 0.0f) rate = fminf(fmaxf(rate, d->rate_min), d->rate_max);
            if (!(rate >= 0.0f)) rate = 0.0f;
        }
        if (!d->distance_matching) rate = 1.0f, c->playback = MM_PLAYBACK_CLOCK; /* warping only */
        /* the clip's root speed over a step (0.25 s either side, within the clip), not this
         * tick's: the root's speed swings within each step, and a stride scale following it
         * would stretch and shrink the legs every tick, dragging the planted foot along */
        float duration = mm_distance_duration(&curve), h = 0.25f;
        float a = fmaxf(time - h, 0.0f), b = fminf(time + h, duration);
        float clip_speed =
            b - a > 1e-3f ? (mm_distance_travelled(&curve, b) - mm_distance_travelled(&curve, a)) / (b - a)
                          : 0.0f;
        if (clip_speed * rate > 1e-2f && speed > 0.05f) {
            float scale = speed / (clip_speed * rate);
            if (d->stride_min > 0.0f || d->stride_max > 0.0f)
                scale = fminf(fmaxf(scale, d->stride_min), d->stride_max);
            c->stride_scale = isfinite(scale) && scale > 0.0f ? scale : 1.0f;
        }
    }
    c->play_rate = isfinite(rate) && rate >= 0.0f ? fminf(rate, 16.0f) : 1.0f;
    if (!d->warping || !(speed > 0.05f)) c->stride_scale = 1.0f;
}

static void distance_playback(mm_character *c, const mm_input *in, float dt, float travelled)
{
    float previous = c->stride_scale;
    distance_playback_target(c, in, dt, travelled);
    /* outside loop cycles the stride scale follows its target with a 0.1 s half-life, also back
     * to 1 at rest or on clips played by the clock: a change of scale moves a planted foot by the
     * change times its distance from the hip */
    if (c->desc.warping && c->playback != MM_PLAYBACK_CYCLE && isfinite(previous) && previous > 0.0f) {
        float scale = previous + (c->stride_scale - previous) * (1.0f - exp2f(-dt / 0.1f));
        c->stride_scale = fabsf(scale - 1.0f) < 1e-4f && c->stride_scale == 1.0f ? 1.0f : scale;
    }
}

/* Stride warping: the legs of the animated pose stretched along the simulated movement by
 * c->stride_scale about their hips (mm_warp_stride), the pelvis eased toward the drop they need; the
 * feet keep their animated world orientation. Foot locking and IK then work on this pose. */
static void stride_warp(mm_character *c, float dt)
{
    const mm_database *db = c->db;
    float previous_drop = isfinite(c->stride_drop) && c->stride_drop > 0.0f ? c->stride_drop : 0.0f;
    c->stride_drop = 0.0f;
    if (c->foot_joint[0] < 0 || c->foot_joint[1] < 0 || c->pelvis_joint < 0) return;
    if (c->stride_scale == 1.0f && previous_drop < 1e-4f) return; /* at rest: the pose is not touched */
    mm_vec3 direction = c->trajectory.velocity;
    direction.y = 0.0f;
    if (!(mm_vec3_length(direction) > 1e-3f))
        direction = mm_quat_rotate(c->root.rotation, mm_vec3_make(0, 0, 1));
    mm_leg_pose legs[2];
    int joint[2][3];
    for (int k = 0; k < 2; ++k) {
        int ankle = c->foot_joint[k], knee = db->joints[ankle].parent, hip = db->joints[knee].parent;
        joint[k][0] = hip, joint[k][1] = knee, joint[k][2] = ankle;
        legs[k].hip = c->global[hip].translation;
        legs[k].knee = c->global[knee].translation;
        legs[k].foot = c->global[ankle].translation;
    }
    mm_leg_warp out[2];
    float drop = 0.0f;
    if (mm_warp_stride(legs, 2, direction, c->stride_scale, 0.0f, out, &drop) != MM_OK) return;
    if (!(drop >= 0.0f) || drop > 1.0f) return;
    /* the pelvis follows the drop the legs need on a spring-like filter (half-life 0.05 s down,
     * 0.15 s back up), not at once: the drop changes with every step and would pop; the legs are
     * then solved again from the pelvis where it is, reaching as far as they can */
    float halflife = drop > previous_drop ? 0.05f : 0.15f;
    float eased = previous_drop + (drop - previous_drop) * (1.0f - exp2f(-dt / halflife));
    if (!isfinite(eased) || eased < 0.0f) eased = 0.0f;
    /* the knees bend toward where the pelvis faces (square to the line from the left hip to the
     * right one: facing +Z, the left hip is at +X), whichever way the body moves: mm_warp_stride's
     * pole is the movement, sideways or backward when strafing, and the root's facing is off the
     * pelvis's in turns */
    mm_vec3 across = mm_vec3_sub(legs[1].hip, legs[0].hip);
    mm_vec3 forward = mm_vec3_make(across.z, 0.0f, -across.x);
    for (int k = 0; k < 2; ++k) {
        mm_leg_pose lowered = legs[k];
        lowered.hip.y -= eased;
        lowered.knee.y -= eased;
        lowered.foot.y -= eased;
        if (mm_warp_leg_ik(&lowered, out[k].target, forward, 0.0f, &out[k]) != MM_OK) return;
    }
    drop = eased;
    mm_quat knee_world[2], ankle_world[2];
    for (int k = 0; k < 2; ++k) {
        knee_world[k] = c->global[joint[k][1]].rotation;
        ankle_world[k] = c->global[joint[k][2]].rotation;
    }
    int pelvis = c->pelvis_joint;
    c->stride_drop = drop;
    if (drop > 0.0f) {
        mm_vec3 down = mm_quat_inv_rotate(c->global[db->joints[pelvis].parent].rotation,
                                          mm_vec3_make(0.0f, -drop, 0.0f));
        c->local_positions[pelvis] = mm_vec3_add(c->local_positions[pelvis], down);
    }
    for (int j = pelvis; j < db->joint_count; ++j)
        c->global[j] = mm_xform_mul(c->global[db->joints[j].parent],
                                    mm_xform_make(c->local_rotations[j], c->local_positions[j]));
    for (int k = 0; k < 2; ++k) {
        int hip = joint[k][0], knee = joint[k][1], ankle = joint[k][2];
        mm_quat hip_world = mm_quat_normalize(mm_quat_mul(out[k].thigh, c->global[hip].rotation));
        c->local_rotations[hip] = mm_quat_normalize(
            mm_quat_mul(mm_quat_conj(c->global[db->joints[hip].parent].rotation), hip_world));
        c->global[hip] = mm_xform_mul(c->global[db->joints[hip].parent],
                                      mm_xform_make(c->local_rotations[hip], c->local_positions[hip]));
        mm_quat knee_new = mm_quat_normalize(mm_quat_mul(out[k].shin, knee_world[k]));
        c->local_rotations[knee] =
            mm_quat_normalize(mm_quat_mul(mm_quat_conj(c->global[hip].rotation), knee_new));
        c->global[knee] =
            mm_xform_mul(c->global[hip], mm_xform_make(c->local_rotations[knee], c->local_positions[knee]));
        c->local_rotations[ankle] =
            mm_quat_normalize(mm_quat_mul(mm_quat_conj(c->global[knee].rotation), ankle_world[k]));
    }
    for (int j = 1; j < db->joint_count; ++j)
        c->global[j] = mm_xform_mul(c->global[db->joints[j].parent],
                                    mm_xform_make(c->local_rotations[j], c->local_positions[j]));
}

/* Orientation warping (docs/distance.md): while strafing on a forward (or backward) locomotion
 * clip, the pelvis and legs turn about +Y by the angle from the root's facing to the simulated
 * movement (mm_warp_orientation: flipped past 90 degrees, clamped, smoothed into
 * c->orientation_angle), the spine above the pelvis turns back by equal shares so the chest
 * keeps its facing; the feet go with the legs, and foot locking and IK re-plant them. */
static void orientation_warp(mm_character *c, const mm_input *in, float dt)
{
    const mm_database *db = c->db;
    const mm_character_desc *d = &c->desc;
    int pelvis = c->pelvis_joint;
    if (pelvis < 0) return;
    mm_vec3 facing = mm_quat_rotate(c->root.rotation, mm_vec3_make(0, 0, 1));
    mm_vec3 move = c->trajectory.velocity, local = db->root_velocity[c->frame];
    move.y = 0.0f;
    /* the clip's own direction: forward or backward locomotion within 60 degrees, else none */
    float along = local.z, across = fabsf(local.x);
    int side = along > 0.2f && along > 0.577f * across     ? 1
               : along < -0.2f && -along > 0.577f * across ? -1
                                                           : 0;
    if (!in || !in->strafe || c->move_playing || side == 0 || !(mm_vec3_length(move) > 0.05f) ||
        db->clips[db->frame_clip[c->frame]].type == MM_CLIP_IDLE)
        move = facing; /* nothing to correct: the angle goes back to 0 */
    mm_warp_orientation_params p;
    memset(&p, 0, sizeof p);
    p.max_angle = d->orientation_max;
    /* a spring of the same half-life as speed's exponential (ln 2 / speed): a target that jumps (a
     * transition to a clip facing elsewhere) turned the legs at 10 rad/s from one tick to the next
     * (knee pops of 10-25 cm on LAFAN1's demo with warping on) */
    p.halflife = d->orientation_speed > 0.0f ? 0.6931472f / d->orientation_speed : 0.0f;
    p.velocity = c->orientation_velocity;
    int spine[MM_WARP_ORIENTATION_MAX_SPINE];
    /* the spine: the pelvis's child that no leg hangs from, up to the joint where it branches */
    for (int j = pelvis + 1; j < db->joint_count && p.spine_count == 0; ++j) {
        if (db->joints[j].parent != pelvis) continue;
        int leg = 0;
        for (int k = 0; k < 2; ++k)
            for (int a = c->foot_joint[k]; a > pelvis; a = db->joints[a].parent) leg |= a == j;
        if (leg) continue;
        for (int at = j; at >= 0 && p.spine_count < MM_WARP_ORIENTATION_MAX_SPINE;) {
            spine[p.spine_count++] = at;
            int child = -1, children = 0;
            for (int k = at + 1; k < db->joint_count; ++k)
                if (db->joints[k].parent == at) child = children++ ? child : k;
            at = children == 1 ? child : -1;
        }
    }
    mm_warp_orientation_result w;
    if (mm_warp_orientation(side < 0 ? mm_vec3_scale(facing, -1.0f) : facing, move, c->orientation_angle, dt,
                            &p, &w) != MM_OK)
        return;
    if (w.backward) /* the movement is more than 90 degrees off the clip's direction: no warp */
        mm_warp_orientation(facing, facing, c->orientation_angle, dt, &p, &w);
    if (fabsf(w.angle) < 1e-4f && fabsf(w.velocity) < 1e-3f) /* faded out: the pose is left as it is */
        w.angle = w.velocity = 0.0f;
    c->orientation_angle = w.angle;
    c->orientation_velocity = w.velocity;
    if (w.angle == 0.0f) return;
    mm_quat spine_world[MM_WARP_ORIENTATION_MAX_SPINE], spine_local[MM_WARP_ORIENTATION_MAX_SPINE];
    for (int i = 0; i < p.spine_count; ++i) spine_world[i] = c->global[spine[i]].rotation;
    if (mm_warp_orientation_pose(&w, c->global[db->joints[pelvis].parent].rotation,
                                 c->global[pelvis].rotation, spine_world, p.spine_count,
                                 &c->local_rotations[pelvis], spine_local) != MM_OK)
        return;
    for (int i = 0; i < p.spine_count; ++i) c->local_rotations[spine[i]] = spine_local[i];
    for (int j = pelvis; j < db->joint_count; ++j)
        c->global[j] = mm_xform_mul(c->global[db->joints[j].parent],
                                    mm_xform_make(c->local_rotations[j], c->local_positions[j]));
}

/* m/s: the simulated character counts as stopped */
#define IDLE_STOPPED 0.01f

void mm_character_update(mm_character *c, const mm_input *in, float dt)
{
    if (!c || !c->db || !(dt > 0.0f) || !isfinite(dt)) return;
    const mm_database *db = c->db;
    const mm_character_desc *d = &c->desc;
    mm_vec3 sim_before = c->trajectory.position;
    mm_trajectory_update(&c->trajectory, in, dt);

    /* playback: by the clock, or by distance matching (never during a move) */
    int ended = 0;
    if ((d->distance_matching || d->warping) && !c->move_playing && !c->move_pending) {
        float dx = c->trajectory.position.x - sim_before.x, dz = c->trajectory.position.z - sim_before.z;
        distance_playback(c, in, dt, sqrtf(dx * dx + dz * dz));
        c->frame_fraction += (double)c->play_rate * (double)dt / (double)db->interval;
    } else {
        c->playback = MM_PLAYBACK_CLOCK;
        c->play_rate = 1.0f;
        c->stride_scale = 1.0f;
        c->frame_fraction += (double)dt / (double)db->interval;
    }
    /* no epsilon: the fraction is a double advanced by dt / interval, so a tick of the database's
     * interval (or a power-of-two multiple or divisor of it) lands exactly on a frame and other
     * rates drift by double rounding only. The interval must then be the one meant: a config's
     * 0.0166667 is read as 1/60 (config_json.c), not as 1.000002 ticks of 60 Hz */
    while (c->frame_fraction >= 1.0) {
        c->frame_fraction -= 1.0;
        int next = db->frame_next[c->frame];
        if (next < 0) {
            c->frame_fraction = 0.0;
            ended = 1;
            break;
        }
        c->frame = next;
    }
    if (d->transition_mode == MM_TRANSITION_CROSSFADE) { /* older slots play on; slot 0 is the playhead */
        mm_mixer_advance(&c->mixer, dt);
        mm_mixer_play(&c->mixer, db->frame_next, db->frame_count, c->play_rate * dt / db->interval);
        c->mixer.slots[0].source = c->frame;
        c->mixer.slots[0].fraction = (float)c->frame_fraction;
    }

    /* when to search: on time, on a sharp change of the desired direction, on idle in or out,
     * at the end of a clip */
    mm_vec3 desired;
    mm_trajectory_desired(&c->trajectory, in, &desired, NULL);
    float speed = mm_vec3_length(desired), direction = atan2f(desired.x, desired.z);
    /* idle is asked for once the simulated character has (nearly) stopped too, not when the
     * stick is let go: until then the locomotion search finds the stops, where an idle pose
     * would have its planted feet dragged along by the root still moving. Nor while the
     * animation still runs (its root faster than idle_root_speed): the jump from a stride into
     * a standing pose, both feet labelled planted, slid them 70-90 cm/s on LAFAN1's run stops;
     * once the simulation has stopped (IDLE_STOPPED) idle is asked for whatever plays */
    float moving = sqrtf(c->trajectory.velocity.x * c->trajectory.velocity.x +
                         c->trajectory.velocity.z * c->trajectory.velocity.z);
    int idle_changed = 0;
    if (c->idle && speed > d->idle_speed + d->idle_hysteresis)
        c->idle = false, idle_changed = 1;
    else if (!c->idle && speed < d->idle_speed && moving < d->idle_speed + d->idle_hysteresis &&
             (!(d->idle_root_speed > 0.0f) || mm_vec3_length(c->root_velocity) < d->idle_root_speed ||
              moving < IDLE_STOPPED))
        c->idle = true, idle_changed = 1;
    int turned = speed > 0.3f && fabsf(wrap(direction - c->last_direction)) > d->turn_threshold;
    c->since_search += dt;
    if (c->move_pending) { /* a move starts: no search until it hands back */
        c->move_pending = false;
        c->move_playing = true;
        transition(c, c->move_frame, 0.0f, dt);
    } else if (c->move_playing && (ended || db->frame_clip[c->frame] != db->frame_clip[c->move_frame] ||
                                   c->frame >= c->move_end)) {
        c->move_playing = false; /* played out: back to matching at once */
        c->since_search = INFINITY;
    }
    if (!c->move_playing && (c->since_search >= d->search_interval || turned || idle_changed || ended)) {
        search(c, in, dt);
        if (speed > 0.3f) c->last_direction = direction;
    }
    float halflife = c->move_playing && c->move_halflife > 0.0f ? c->move_halflife : d->transition_halflife;

    /* the pose: the database's at the playhead plus the decaying offsets */
    size_t n = (size_t)db->joint_count;
    memcpy(c->previous_rotations, c->local_rotations, sizeof(mm_quat) * n);
    memcpy(c->previous_positions, c->local_positions, sizeof(mm_vec3) * n);
    memcpy(c->pose_previous_rotations, c->pose_rotations, sizeof(mm_quat) * n);
    memcpy(c->pose_previous_positions, c->pose_positions, sizeof(mm_vec3) * n);
    play_pose(c, c->pose_rotations, c->pose_positions);
    for (int j = 1; j < db->joint_count; ++j) {
        mm_spring_decay_vec3(&c->rotation_offset[j], &c->rotation_offset_velocity[j], halflife, dt);
        mm_spring_decay_vec3(&c->position_offset[j], &c->position_offset_velocity[j], halflife, dt);
        c->pose_rotations[j] =
            mm_quat_normalize(mm_quat_mul(mm_quat_exp(c->rotation_offset[j]), c->pose_rotations[j]));
        c->pose_positions[j] = mm_vec3_add(c->pose_positions[j], c->position_offset[j]);
    }
    memcpy(c->local_rotations, c->pose_rotations, sizeof(mm_quat) * n);
    memcpy(c->local_positions, c->pose_positions, sizeof(mm_vec3) * n);

    /* root motion: the database's root velocity (inertialized), then pulled toward the simulation
     * and clamped */
    mm_vec3 played;
    float yaw_rate;
    play_root(c, &played, &yaw_rate);
    mm_spring_decay_vec3(&c->root_velocity_offset, &c->root_velocity_offset_rate, halflife, dt);
    mm_spring_update(&c->root_yaw_rate_offset, &c->root_yaw_rate_offset_rate, 0.0f, halflife, dt);
    c->root_velocity = mm_vec3_add(played, c->root_velocity_offset);
    c->root_yaw_rate = yaw_rate + c->root_yaw_rate_offset;
    mm_vec3 v = mm_quat_rotate(c->root.rotation, c->root_velocity);
    float yaw = yaw_of(c->root.rotation) + c->root_yaw_rate * dt;
    mm_vec3 position = mm_vec3_add(c->root.translation, mm_vec3_scale(v, dt));
    const mm_trajectory *t = &c->trajectory;
    /* a move plays the clip's root motion alone (the move layer corrects it): no pull, no clamps */
    int free_root = c->move_playing;
    float pull = free_root ? 0.0f : d->sync_halflife > 0.0f ? 1.0f - exp2f(-dt / d->sync_halflife) : 1.0f;
    mm_vec3 gap = mm_vec3_sub(t->position, position);
    gap.y = 0.0f;
    position = mm_vec3_add(position, mm_vec3_scale(gap, pull));
    yaw += wrap(yaw_of(t->facing) - yaw) * pull;
    mm_vec3 off = mm_vec3_sub(position, t->position);
    off.y = 0.0f;
    float dist = mm_vec3_length(off);
    if (!free_root && dist > d->sync_max_distance)
        position = mm_vec3_add(t->position, mm_vec3_scale(off, d->sync_max_distance / dist));
    /* angle correction at full speed (seed 000): a small error between the character's facing
     * and the one asked for is turned away at a bounded rate, as the animation alone may never
     * quite line up */
    mm_quat wanted;
    mm_trajectory_desired(t, in, NULL, &wanted);
    int gait = in && (int)in->gait >= 0 && in->gait < MM_GAIT_COUNT ? (int)in->gait : MM_GAIT_WALK;
    float full = t->desc.gaits[gait].forward_speed;
    float error = wrap(yaw_of(wanted) - yaw);
    if (!free_root && full > 0.0f && mm_vec3_length(t->velocity) >= 0.9f * full &&
        fabsf(error) < d->angle_threshold) {
        float step = d->angle_revise_speed * dt;
        yaw += error > step ? step : error < -step ? -step : error;
    }
    float angle = wrap(yaw - yaw_of(t->facing));
    if (!free_root && fabsf(angle) > d->sync_max_angle)
        yaw = yaw_of(t->facing) + (angle > 0 ? d->sync_max_angle : -d->sync_max_angle);
    /* the height is kept: 0 on flat ground, or where the move layer put the character */
    c->root = mm_xform_make(yaw_quat(wrap(yaw)), mm_vec3_make(position.x, c->root.translation.y, position.z));
    c->local_rotations[0] = c->root.rotation;
    c->local_positions[0] = c->root.translation;
    compute_global(c);
    if (d->warping) {
        orientation_warp(c, in, dt);
        stride_warp(c, dt);
    }
    for (int k = 0; k < 2; ++k) { /* ankle and the ankle's first child (the toe) before IK (after warping) */
        int ankle = c->foot_joint[k], toe = c->toe_joint[k];
        c->raw_contact_positions[2 * k] = ankle >= 0 ? c->global[ankle].translation : mm_vec3_make(0, 0, 0);
        c->raw_contact_positions[2 * k + 1] =
            toe >= 0 ? c->global[toe].translation : c->raw_contact_positions[2 * k];
    }
    if (!d->no_foot_ik) feet(c, dt);
}

void mm_character_play_move(mm_character *c, int frame, int end_frame, float halflife)
{
    if (!c || !c->db) return;
    if (frame < 0 || frame >= c->db->frame_count) { /* nothing to play: back to matching */
        c->move_pending = c->move_playing = false;
        c->since_search = INFINITY;
        return;
    }
    c->move_pending = true;
    c->move_frame = frame;
    c->move_end = end_frame;
    c->move_halflife = isfinite(halflife) && halflife > 0.0f ? halflife : 0.0f;
}

bool mm_character_move_playing(const mm_character *c) { return c && (c->move_pending || c->move_playing); }

void mm_character_shift_root(mm_character *c, mm_vec3 delta)
{
    if (!c || !c->db || !isfinite(delta.x) || !isfinite(delta.y) || !isfinite(delta.z)) return;
    const mm_database *db = c->db;
    c->root.translation = mm_vec3_add(c->root.translation, delta);
    mm_vec3 local = mm_quat_inv_rotate(c->root.rotation, delta);
    for (int j = 1; j < db->joint_count; ++j) {
        if (db->joints[j].parent != 0) continue;
        /* the child keeps its world place: its local position, and the offset that carries it */
        c->position_offset[j] = mm_vec3_sub(c->position_offset[j], local);
        c->local_positions[j] = mm_vec3_sub(c->local_positions[j], local);
        c->previous_positions[j] = mm_vec3_sub(c->previous_positions[j], local);
        c->pose_positions[j] = mm_vec3_sub(c->pose_positions[j], local);
        c->pose_previous_positions[j] = mm_vec3_sub(c->pose_previous_positions[j], local);
    }
    c->local_positions[0] = c->root.translation;
    compute_global(c);
}
