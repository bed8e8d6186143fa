/* Stage 4: the pose played and the transitions between database frames. */
#include "transition.h"

#include <math.h>
#include <string.h>
#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

#include <mm/pose.h>
#include <mm/spring.h>

#include "math_private.h"

/* Frames `frame` and `next` read into tr's frame arrays: their local transforms. */
static mm_frame_pair read_frames(mm_transition *tr, const mm_database *db, int frame, int next)
{
    size_t n = (size_t)db->joint_count;
    mm_database_local_pose(db, frame, tr->frame_rotations, tr->frame_positions);
    mm_database_local_pose(db, next, tr->frame_rotations + n, tr->frame_positions + n);
    mm_frame_pair pair = {tr->frame_rotations, tr->frame_rotations + n, tr->frame_positions,
                          tr->frame_positions + n};
    return pair;
}

/* The database pose at a playhead: frame and the next, blended by the fraction. */
static void pose_at(mm_transition *tr, const mm_database *db, int frame, float fraction, mm_quat *rot,
                    mm_vec3 *pos)
{
    int next = db->frame_next[frame] >= 0 ? db->frame_next[frame] : frame;
    mm_frame_pair pair = read_frames(tr, db, frame, next);
    const mm_quat *r0 = pair.rotations0, *r1 = pair.rotations1;
    const mm_vec3 *p0 = pair.positions0, *p1 = pair.positions1;
    /* neighbouring frames: close together */
    mm__quat_slerp_series_n(r0, r1, fraction, db->joint_count, rot);
    for (int j = 0; j < db->joint_count; ++j) pos[j] = mm_vec3_lerp(p0[j], p1[j], fraction);
}

/* The database's root motion at the playhead: that of the frame interval it is in (the root
 * velocity of a frame is the motion from the frame before to it). Distance matching plays the clip
 * at play_rate and stride warping stretches the steps by stride_scale: the root moves as much
 * faster (both are exactly 1 when off). */
static mm_root_played root_at(const mm_database *db, int frame, const mm_playback *p)
{
    int next = db->frame_next[frame] >= 0 ? db->frame_next[frame] : frame;
    mm_root_played r;
    r.velocity = mm_vec3_scale(db->root_velocity[next], p->play_rate * p->stride_scale);
    r.yaw_rate = db->root_angular_velocity[next] * p->play_rate;
    return r;
}

/* Crossfade mode: the mixer's blend of its slots' poses (into rot and pos, when not NULL) and root
 * motion (the weighted sum of theirs). */
static mm_root_played crossfade_play(mm_transition *tr, const mm_database *db, const mm_playback *p,
                                     mm_quat *rot, mm_vec3 *pos)
{
    const mm_quat *r[MM_MIXER_SLOTS];
    const mm_vec3 *ps[MM_MIXER_SLOTS];
    float w[MM_MIXER_SLOTS];
    size_t n = (size_t)db->joint_count;
    mm_root_played sum = {mm_vec3_make(0, 0, 0), 0.0f};
    for (int i = 0; i < tr->mixer.count; ++i) {
        const mm_mixer_slot *s = &tr->mixer.slots[i];
        r[i] = tr->slot_rotations + (size_t)i * n, ps[i] = tr->slot_positions + (size_t)i * n,
        w[i] = s->weight;
        if (rot) { /* blended in model space (mm/pose.h: mm_pose_to_model) */
            pose_at(tr, db, s->source, s->fraction, tr->slot_rotations + (size_t)i * n,
                    tr->slot_positions + (size_t)i * n);
            mm_pose_to_model(db->joints, (int)n, tr->slot_rotations + (size_t)i * n);
        }
        mm_root_played one = root_at(db, s->source, p);
        sum.velocity = mm_vec3_add(sum.velocity, mm_vec3_scale(one.velocity, s->weight));
        sum.yaw_rate += one.yaw_rate * s->weight;
    }
    if (rot && pos) {
        /* hemispheres from the last tick's output, so that the blend moves continuously */
        mm_quat *reference = tr->slot_rotations + (size_t)MM_MIXER_SLOTS * n;
        memcpy(reference, tr->previous_rotations, sizeof(mm_quat) * n);
        mm_pose_to_model(db->joints, (int)n, reference);
        mm_pose_blend(r, ps, w, tr->mixer.count, (int)n, reference, rot, pos);
        mm_pose_to_local(db->joints, (int)n, rot);
    }
    return sum;
}

/* The pose played (into rot and pos) and its root motion: the playhead's, or the mixer's blend. */
static mm_root_played play_pose(mm_transition *tr, const mm_database *db, const mm_playback *p, mm_quat *rot,
                                mm_vec3 *pos)
{
    if (tr->mode == MM_TRANSITION_CROSSFADE) return crossfade_play(tr, db, p, rot, pos);
    pose_at(tr, db, p->frame, (float)p->fraction, rot, pos);
    return root_at(db, p->frame, p);
}

static mm_root_played play_root(mm_transition *tr, const mm_database *db, const mm_playback *p)
{
    return tr->mode == MM_TRANSITION_CROSSFADE ? crossfade_play(tr, db, p, NULL, NULL)
                                               : root_at(db, p->frame, p);
}

void mm_transition_init(mm_transition *tr, const mm_database *db, mm_transition_mode mode,
                        const mm_playback *p)
{
    size_t n = (size_t)db->joint_count;
    tr->mode = mode;
    tr->uncancellable_tags = mm_search_tag_mask(db, "Jump") | mm_search_tag_mask(db, "Uncancellable");
    mm_mixer_init(&tr->mixer, p->frame, 0.0f);
    play_pose(tr, db, p, tr->rotations, tr->positions);
    memcpy(tr->previous_rotations, tr->rotations, n * sizeof(mm_quat));
    memcpy(tr->previous_positions, tr->positions, n * sizeof(mm_vec3));
    tr->played_rate = p->play_rate;
}

void mm_transition_advance(mm_transition *tr, const mm_database *db, const mm_playback *p, float dt)
{
    if (tr->mode != MM_TRANSITION_CROSSFADE) return;
    mm_mixer_advance(&tr->mixer, dt);
    mm_mixer_play(&tr->mixer, db->frame_next, db->frame_count, p->play_rate * dt / db->interval);
    tr->mixer.slots[0].source = p->frame;
    tr->mixer.slots[0].fraction = (float)p->fraction;
}

/* Crossfade mode: frame `to` enters the mixer's slot 0 (the playhead), unless the mixer cancels it
 * (dropped, counted). Frames with uncancellable_tags are never cancelled. */
static void crossfade_to(mm_transition *tr, const mm_database *db, int to, bool uncancellable, float time,
                         mm_playback *p)
{
    uncancellable = uncancellable || (db->frame_tags && (db->frame_tags[to] & tr->uncancellable_tags));
    if (!mm_mixer_start(&tr->mixer, to, 0.0f, time, uncancellable)) {
        ++tr->cancelled;
        return;
    }
    p->frame = to;
    p->fraction = 0.0;
    ++tr->transitions;
}

/* The rate of a rotation offset x (a rotation vector, turning the new clip's rotation from the
 * parent's side: output = exp(x) r) that gives the output the angular velocity w_out (rad/s, parent
 * axes) while r turns at w_new: the output turns at J(x) x' + R(x) w_new, where R(x) is the offset's
 * rotation and J(x) the left Jacobian of the exponential map, so x' = J(x)^-1 (w_out - R(x) w_new).
 * Taking x' = w_out - w_new instead holds only for an offset about the axis of w_new: a leg swinging
 * under an offset turned about another axis would change its velocity at once. turn is R(x),
 * exp(x) as a quaternion. */
/* c of J^-1 = I - [x]/2 + c [x]^2 for an offset of this angle: 1 / angle^2 - cot(angle / 2) / (2
 * angle) (1/12 near 0) */
static float inverse_jacobian_c(double angle)
{
    double c = angle < 1e-3 ? 1.0 / 12.0 + angle * angle / 720.0
                            : 1.0 / (angle * angle) - 1.0 / (2.0 * angle * tan(0.5 * angle));
    return (float)c;
}

mm_vec3 mm__rotation_offset_rate(mm_vec3 x, mm_quat turn, mm_vec3 w_out, mm_vec3 w_new)
{
    mm_vec3 u = mm_vec3_sub(w_out, mm_quat_rotate(turn, w_new));
    float c = inverse_jacobian_c(mm_vec3_length(x));
    mm_vec3 xu = mm_vec3_cross(x, u), xxu = mm_vec3_cross(x, xu);
    return mm_vec3_add(mm_vec3_sub(u, mm_vec3_scale(xu, 0.5f)), mm_vec3_scale(xxu, c));
}

#if defined(__SSE2__)
/* The x, y and z of four vectors, one vector a lane. */
static void load_vec3x4(const mm_vec3 *v, __m128 *x, __m128 *y, __m128 *z)
{
    *x = _mm_setr_ps(v[0].x, v[1].x, v[2].x, v[3].x);
    *y = _mm_setr_ps(v[0].y, v[1].y, v[2].y, v[3].y);
    *z = _mm_setr_ps(v[0].z, v[1].z, v[2].z, v[3].z);
}

/* mm__rotation_offset_rate of four joints, one a lane: each lane the scalar code's float
 * operations in their order (mm_quat_rotate's, the cross products'), c from the same double code,
 * so the same bits. */
static void rotation_offset_rates4(const mm_vec3 *x, const mm_quat *turn, const mm_vec3 *w_out,
                                   const mm_vec3 *w_new, mm_vec3 *out)
{
#define MUL _mm_mul_ps
#define ADD _mm_add_ps
#define SUB _mm_sub_ps
    __m128 qx = _mm_loadu_ps(&turn[0].x), qy = _mm_loadu_ps(&turn[1].x), qz = _mm_loadu_ps(&turn[2].x),
           qw = _mm_loadu_ps(&turn[3].x);
    _MM_TRANSPOSE4_PS(qx, qy, qz, qw);
    __m128 vx, vy, vz, ox, oy, oz, xx, xy, xz;
    load_vec3x4(w_new, &vx, &vy, &vz);
    load_vec3x4(w_out, &ox, &oy, &oz);
    load_vec3x4(x, &xx, &xy, &xz);
    /* mm_quat_rotate: t = 2 (q.xyz x v), v + q.w t + q.xyz x t */
    __m128 two = _mm_set1_ps(2.0f);
    __m128 tx = MUL(SUB(MUL(qy, vz), MUL(qz, vy)), two), ty = MUL(SUB(MUL(qz, vx), MUL(qx, vz)), two),
           tz = MUL(SUB(MUL(qx, vy), MUL(qy, vx)), two);
    __m128 rx = ADD(ADD(vx, MUL(tx, qw)), SUB(MUL(qy, tz), MUL(qz, ty))),
           ry = ADD(ADD(vy, MUL(ty, qw)), SUB(MUL(qz, tx), MUL(qx, tz))),
           rz = ADD(ADD(vz, MUL(tz, qw)), SUB(MUL(qx, ty), MUL(qy, tx)));
    __m128 ux = SUB(ox, rx), uy = SUB(oy, ry), uz = SUB(oz, rz);
    float length[4];
    _mm_storeu_ps(length, _mm_sqrt_ps(ADD(ADD(MUL(xx, xx), MUL(xy, xy)), MUL(xz, xz))));
    __m128 c = _mm_setr_ps(inverse_jacobian_c(length[0]), inverse_jacobian_c(length[1]),
                           inverse_jacobian_c(length[2]), inverse_jacobian_c(length[3]));
    __m128 ax = SUB(MUL(xy, uz), MUL(xz, uy)), ay = SUB(MUL(xz, ux), MUL(xx, uz)),
           az = SUB(MUL(xx, uy), MUL(xy, ux)); /* x cross u */
    __m128 bx = SUB(MUL(xy, az), MUL(xz, ay)), by = SUB(MUL(xz, ax), MUL(xx, az)),
           bz = SUB(MUL(xx, ay), MUL(xy, ax)); /* x cross (x cross u) */
    __m128 half = _mm_set1_ps(0.5f);
    __m128 rx2 = ADD(SUB(ux, MUL(ax, half)), MUL(bx, c)), ry2 = ADD(SUB(uy, MUL(ay, half)), MUL(by, c)),
           rz2 = ADD(SUB(uz, MUL(az, half)), MUL(bz, c));
#undef MUL
#undef ADD
#undef SUB
    float ox4[4], oy4[4], oz4[4];
    _mm_storeu_ps(ox4, rx2);
    _mm_storeu_ps(oy4, ry2);
    _mm_storeu_ps(oz4, rz2);
    for (int l = 0; l < 4; ++l) out[l] = mm_vec3_make(ox4[l], oy4[l], oz4[l]);
}
#endif

void mm__rotation_offset_rates(const mm_vec3 *x, const mm_quat *turn, const mm_vec3 *w_out,
                               const mm_vec3 *w_new, int count, mm_vec3 *out)
{
    int i = 0;
#if defined(__SSE2__)
    for (; i + 4 <= count; i += 4) rotation_offset_rates4(x + i, turn + i, w_out + i, w_new + i, out + i);
#endif
    for (; i < count; ++i) out[i] = mm__rotation_offset_rate(x[i], turn[i], w_out[i], w_new[i]);
}

/* joints whose rotation offsets are turned into quaternions together (on the stack) */
#define DECAY_CHUNK 32

void mm_transition_inertialize(mm_transition *tr, int joint_count, const mm_frame_pair *to, float fraction,
                               float frame_rate, float dt)
{
    float inv_dt = dt > 0.0f ? 1.0f / dt : 0.0f;
    const mm_quat *now_r = tr->rotations, *last_r = tr->previous_rotations;
    const mm_vec3 *now_p = tr->positions, *last_p = tr->previous_positions;
    /* joint after joint in runs of DECAY_CHUNK, each step over the run at once (the packed forms) */
    for (int first = 1; first < joint_count; first += DECAY_CHUNK) {
        int count = joint_count - first < DECAY_CHUNK ? joint_count - first : DECAY_CHUNK;
        mm_quat turn[DECAY_CHUNK], back[DECAY_CHUNK];
        mm_vec3 w_out[DECAY_CHUNK], w_dst[DECAY_CHUNK], step[DECAY_CHUNK];
        /* the animated pose's velocity (from the last two ticks) and the new clip's */
        mm__quat_turns_n(last_r + first, now_r + first, count, turn);
        mm__quat_log_series_n(turn, count, w_out);
        mm__quat_turns_n(to->rotations0 + first, to->rotations1 + first, count, turn);
        mm__quat_log_series_n(turn, count, w_dst);
        for (int k = 0; k < count; ++k) {
            w_out[k] = mm_vec3_scale(w_out[k], inv_dt);
            w_dst[k] = mm_vec3_scale(w_dst[k], frame_rate);
            step[k] = mm_vec3_scale(w_dst[k], -dt);
        }
        /* the new clip one tick back: the playhead's pose moved back by dt */
        mm__quat_slerp_series_n(to->rotations0 + first, to->rotations1 + first, fraction, count, back);
        mm__quat_exp_series_n(step, count, turn);
        mm__quat_mul_normalize_n(turn, back, count);
        /* the offsets from there to the animated pose, and their rates (the velocity out minus the
         * new clip's) */
        mm__quat_turns_n(back, now_r + first, count, turn);
        mm__quat_log_series_n(turn, count, tr->rotation_offset + first);
        mm__quat_exp_series_n(tr->rotation_offset + first, count, turn);
        mm__rotation_offset_rates(tr->rotation_offset + first, turn, w_out, w_dst, count,
                                  tr->rotation_offset_velocity + first);
        for (int j = first; j < first + count; ++j) {
            mm_vec3 v_dst = mm_vec3_scale(mm_vec3_sub(to->positions1[j], to->positions0[j]), frame_rate);
            mm_vec3 pp = mm_vec3_lerp(to->positions0[j], to->positions1[j], fraction);
            mm_vec3 p_back = mm_vec3_sub(pp, mm_vec3_scale(v_dst, dt));
            mm_vec3 v_out = mm_vec3_scale(mm_vec3_sub(now_p[j], last_p[j]), inv_dt);
            tr->position_offset[j] = mm_vec3_sub(now_p[j], p_back);
            tr->position_offset_velocity[j] = mm_vec3_sub(v_out, v_dst);
        }
    }
}

void mm_transition_inertialize_root(mm_transition *tr, mm_root_played current, mm_root_played to)
{
    tr->root_velocity_offset = mm_vec3_sub(current.velocity, to.velocity);
    tr->root_velocity_offset_rate = mm_vec3_make(0, 0, 0);
    tr->root_yaw_rate_offset = current.yaw_rate - to.yaw_rate;
    tr->root_yaw_rate_offset_rate = 0.0f;
}

/* Inertialization into database frame `to` at `fraction`: the new clip stands there on this tick,
 * as the old one stands at its playhead after this tick's advance. */
static void inertialize_to(mm_transition *tr, const mm_database *db, int to, double fraction,
                           mm_root_played current, mm_playback *p, float dt)
{
    int next = db->frame_next[to];
    p->frame = to;
    p->fraction = next >= 0 && fraction > 0.0 && fraction < 1.0 ? fraction : 0.0;
    /* the new clip's velocity at the playhead: that of the frame interval it is in (zero on a
     * clip's last frame, which playback holds); it plays on at the play rate: its velocity per
     * second is the rate times its velocity per frame interval */
    mm_frame_pair pair = read_frames(tr, db, to, next >= 0 ? next : to);
    float rate = isfinite(p->play_rate) && p->play_rate >= 0.0f ? p->play_rate : 1.0f;
    float frame_rate = next >= 0 ? rate / db->interval : 0.0f;
    mm_transition_inertialize(tr, db->joint_count, &pair, (float)p->fraction, frame_rate, dt);
    tr->played_rate = p->play_rate; /* the offsets are taken at this rate: nothing left to hold */
    /* the root's motion too: the velocity and yaw rate played continue and blend into the new
     * frame's (a jump in root velocity would move every joint at once) */
    mm_transition_inertialize_root(tr, current, play_root(tr, db, p));
    ++tr->transitions;
}

void mm_transition_jump(mm_transition *tr, const mm_database *db, const mm_jump *jump, float crossfade_time,
                        mm_root_played current, mm_playback *p, float dt)
{
    if (jump->frame < 0) return;
    if (tr->mode == MM_TRANSITION_CROSSFADE)
        crossfade_to(tr, db, jump->frame, jump->uncancellable, crossfade_time, p);
    else
        inertialize_to(tr, db, jump->frame, jump->fraction, current, p, dt);
}

void mm_transition_mark_legs(mm_transition *tr, const mm_joint *skeleton, int joint_count, const int hips[2])
{
    for (int j = 0; j < joint_count; ++j) {
        int parent = skeleton[j].parent;
        tr->legs[j] = j == hips[0] || j == hips[1] || (parent >= 0 && parent < j && tr->legs[parent]);
    }
}

/* mm_transition_decay with its springs' steps made */
static void decay_steps(mm_transition *tr, int joint_count, const mm_spring_step *body,
                        const mm_spring_step *legs)
{
    /* the body's joints' offsets decay alike, the legs' alike: each run of joints of one kind (a
     * leg's joints come one after another) in one call */
    for (int first = 1; first < joint_count;) {
        int leg = tr->legs && tr->legs[first], end = first + 1;
        while (end < joint_count && (tr->legs && tr->legs[end]) == leg) ++end;
        const mm_spring_step *step = leg ? legs : body;
        mm_spring_decay_vec3_steps(tr->rotation_offset + first, tr->rotation_offset_velocity + first,
                                   end - first, step);
        mm_spring_decay_vec3_steps(tr->position_offset + first, tr->position_offset_velocity + first,
                                   end - first, step);
        first = end;
    }
    for (int first = 1; first < joint_count; first += DECAY_CHUNK) {
        int count = joint_count - first < DECAY_CHUNK ? joint_count - first : DECAY_CHUNK;
        mm_quat offset[DECAY_CHUNK];
        mm__quat_exp_series_n(tr->rotation_offset + first, count, offset);
        mm__quat_mul_normalize_n(offset, tr->rotations + first, count);
        for (int j = first; j < first + count; ++j)
            tr->positions[j] = mm_vec3_add(tr->positions[j], tr->position_offset[j]);
    }
}

void mm_transition_decay(mm_transition *tr, int joint_count, float halflife, float legs_halflife, float dt)
{
    mm_spring_step body = mm_spring_step_make(halflife, dt), legs = mm_spring_step_make(legs_halflife, dt);
    decay_steps(tr, joint_count, &body, &legs);
}

/* mm_transition_decay_root with its springs' step made (the _step updates give the same bits) */
static mm_root_played decay_root_step(mm_transition *tr, mm_root_played played, const mm_spring_step *step)
{
    mm_spring_decay_vec3_step(&tr->root_velocity_offset, &tr->root_velocity_offset_rate, step);
    mm_spring_update_step(&tr->root_yaw_rate_offset, &tr->root_yaw_rate_offset_rate, 0.0f, step);
    mm_root_played out = {mm_vec3_add(played.velocity, tr->root_velocity_offset),
                          played.yaw_rate + tr->root_yaw_rate_offset};
    return out;
}

mm_root_played mm_transition_decay_root(mm_transition *tr, mm_root_played played, float halflife, float dt)
{
    mm_spring_step step = mm_spring_step_make(halflife, dt);
    return decay_root_step(tr, played, &step);
}

void mm_transition_hold_velocity(mm_transition *tr, int joint_count, const mm_frame_pair *at,
                                 float frame_rate, float rate_before, float rate_now)
{
    float change = (rate_now - rate_before) * frame_rate;
    if (change == 0.0f || !isfinite(change)) return;
    for (int first = 1; first < joint_count; first += DECAY_CHUNK) {
        int count = joint_count - first < DECAY_CHUNK ? joint_count - first : DECAY_CHUNK;
        mm_quat turn[DECAY_CHUNK]; /* the offsets' rotations */
        mm_quat step[DECAY_CHUNK]; /* the clip's turn over the frame interval at the playhead */
        mm_vec3 w[DECAY_CHUNK], still[DECAY_CHUNK], rate[DECAY_CHUNK];
        mm__quat_exp_series_n(tr->rotation_offset + first, count, turn);
        mm__quat_turns_n(at->rotations0 + first, at->rotations1 + first, count, step);
        mm__quat_log_series_n(step, count, w);
        for (int k = 0; k < count; ++k) {
            /* the clip's velocity per frame interval, times the change of rate */
            w[k] = mm_vec3_scale(w[k], change);
            still[k] = mm_vec3_make(0, 0, 0);
        }
        /* the offsets' rates that keep the output's velocity while the clip turns w faster */
        mm__rotation_offset_rates(tr->rotation_offset + first, turn, still, w, count, rate);
        for (int j = first; j < first + count; ++j) {
            mm_vec3 v = mm_vec3_scale(mm_vec3_sub(at->positions1[j], at->positions0[j]), change);
            tr->rotation_offset_velocity[j] = mm_vec3_add(tr->rotation_offset_velocity[j], rate[j - first]);
            tr->position_offset_velocity[j] = mm_vec3_sub(tr->position_offset_velocity[j], v);
        }
    }
}

void mm_transition_pose(mm_transition *tr, const mm_database *db, const mm_playback *p, float halflife,
                        float legs_halflife, float dt, mm_root_played *root)
{
    size_t n = (size_t)db->joint_count;
    memcpy(tr->previous_rotations, tr->rotations, sizeof(mm_quat) * n);
    memcpy(tr->previous_positions, tr->positions, sizeof(mm_vec3) * n);
    if (tr->mode != MM_TRANSITION_CROSSFADE && tr->played_rate != p->play_rate) {
        int next = db->frame_next[p->frame];
        if (next >= 0) {
            mm_frame_pair pair = read_frames(tr, db, p->frame, next);
            mm_transition_hold_velocity(tr, db->joint_count, &pair, 1.0f / db->interval, tr->played_rate,
                                        p->play_rate);
        }
    }
    tr->played_rate = p->play_rate;
    mm_root_played played = play_pose(tr, db, p, tr->rotations, tr->positions);
    /* the legs' step serves the root motion's offsets too (what carries the planted feet) */
    mm_spring_step body = mm_spring_step_make(halflife, dt), legs = mm_spring_step_make(legs_halflife, dt);
    decay_steps(tr, db->joint_count, &body, &legs);
    *root = decay_root_step(tr, played, &legs);
}
