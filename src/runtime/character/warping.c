/* Stage 6: orientation and stride warping of the pose. */
#include "warping.h"

#include <math.h>
#include <string.h>

#include <mm/leg_ik.h>
#include <mm/spring.h>
#include <mm/warp.h>

#include "runtime/warp_private.h"

/* m/s: a clip's root moving at least this fast along its facing counts as forward (or backward)
 * locomotion, within ORIENTATION_CLIP_CONE of it */
#define ORIENTATION_CLIP_MIN_SPEED 0.2f
/* tan(60 deg): how far off its facing a clip's root motion may point and still be warped */
#define ORIENTATION_CLIP_CONE 0.577f
/* m/s: slower simulated movement asks for no orientation warp */
#define ORIENTATION_MIN_SPEED 0.05f
/* below these the orientation warp has faded out and leaves the pose as it is */
#define ORIENTATION_REST_ANGLE    1e-4f
#define ORIENTATION_REST_VELOCITY 1e-3f
/* s: half-lives of the pelvis's stride drop going down and back up (the drop changes with every
 * step and would pop if followed at once) */
#define STRIDE_DROP_DOWN_HALFLIFE 0.05f
#define STRIDE_DROP_UP_HALFLIFE   0.15f
/* m: a stride drop under this has settled back */
#define STRIDE_DROP_REST 1e-4f

void mm_warping_orientation(mm_warping *w, const mm_character_desc *d, const mm_rig *rig, mm_xform root,
                            mm_vec3 velocity, mm_warping_clip clip, bool strafe, bool off, float dt,
                            mm_rig_pose *pose)
{
    int pelvis = rig->pelvis;
    if (pelvis < 0) return;
    mm_vec3 facing = mm_quat_rotate(root.rotation, mm_vec3_make(0, 0, 1));
    mm_vec3 move = velocity, local = clip.root_velocity;
    move.y = 0.0f;
    /* the clip's own direction: forward or backward locomotion, else none */
    float along = local.z, across = fabsf(local.x);
    int side = along > ORIENTATION_CLIP_MIN_SPEED && along > ORIENTATION_CLIP_CONE * across     ? 1
               : along < -ORIENTATION_CLIP_MIN_SPEED && -along > ORIENTATION_CLIP_CONE * across ? -1
                                                                                                : 0;
    if (!strafe || off || side == 0 || !(mm_vec3_length(move) > ORIENTATION_MIN_SPEED) || clip.idle)
        move = facing; /* nothing to correct: the angle goes back to 0 */
    mm_warp_orientation_params p;
    memset(&p, 0, sizeof p);
    p.max_angle = d->orientation_max;
    p.spine_count = rig->spine_count;
    /* the target, at once (p.halflife and p.speed 0); none when the movement is more than 90
     * degrees off the clip's direction */
    mm_vec3 base = side < 0 ? mm_vec3_scale(facing, -1.0f) : facing;
    mm_warp_orientation_result r;
    if (mm_warp_orientation(base, move, w->orientation_angle, dt, &p, &r) != MM_OK) return;
    float target = r.backward ? 0.0f : r.angle;
    /* the angle follows a spring of the same half-life as speed's exponential (ln 2 / speed): a
     * target that jumps (a transition to a clip facing elsewhere) would turn the legs at once. The
     * spring follows the target eased over that half-life first: a step in the target (the clip
     * playing starts or stops going forward, strafing starts) would start the spring at its
     * largest acceleration, the legs' whole turn times y^2 in one tick */
    float halflife = d->orientation_speed > 0.0f ? 0.6931472f / d->orientation_speed : 0.0f;
    float angle = target, rate = 0.0f;
    if (halflife > 0.0f) {
        w->orientation_goal += (target - w->orientation_goal) * (1.0f - exp2f(-dt / halflife));
        angle = w->orientation_angle, rate = w->orientation_velocity;
        mm_spring_update(&angle, &rate, w->orientation_goal, halflife, dt);
        float largest = p.max_angle > 0.0f ? p.max_angle : MM_WARP_ORIENTATION_MAX_DEFAULT;
        if (fabsf(angle) > largest) angle = copysignf(largest, angle), rate = 0.0f;
    } else {
        w->orientation_goal = target;
    }
    if (fabsf(angle) < ORIENTATION_REST_ANGLE && fabsf(rate) < ORIENTATION_REST_VELOCITY &&
        fabsf(w->orientation_goal) < ORIENTATION_REST_ANGLE)
        angle = rate = w->orientation_goal = 0.0f;
    w->orientation_angle = angle;
    w->orientation_velocity = rate;
    if (angle == 0.0f) return;
    /* the warp of that angle: the movement turned from the clip's direction by it */
    mm_vec3 turned = mm_quat_rotate(mm_quat_from_axis_angle(mm_vec3_make(0, 1, 0), angle), base);
    if (mm_warp_orientation(base, turned, angle, 0.0f, &p, &r) != MM_OK) return;
    mm_rig_forward_rest(rig, pose); /* the spine's global transforms, where they wait */
    mm_quat spine_world[MM_RIG_MAX_SPINE], spine_local[MM_RIG_MAX_SPINE];
    for (int i = 0; i < rig->spine_count; ++i) spine_world[i] = pose->global[rig->spine[i]].rotation;
    if (mm_warp_orientation_pose(&r, pose->global[rig->joints[pelvis].parent].rotation,
                                 pose->global[pelvis].rotation, spine_world, rig->spine_count,
                                 &pose->local_rotations[pelvis], spine_local) != MM_OK)
        return;
    for (int i = 0; i < rig->spine_count; ++i) pose->local_rotations[rig->spine[i]] = spine_local[i];
    mm_rig_forward_pelvis(rig, pose);
}

void mm_warping_stride(mm_warping *w, const mm_rig *rig, mm_xform root, mm_vec3 velocity, float stride_scale,
                       float dt, mm_rig_pose *pose)
{
    const mm_joint *joints = rig->joints;
    float previous_drop = isfinite(w->stride_drop) && w->stride_drop > 0.0f ? w->stride_drop : 0.0f;
    w->stride_drop = 0.0f;
    if (rig->ankle[0] < 0 || rig->ankle[1] < 0 || rig->pelvis < 0) return;
    if (stride_scale == 1.0f && previous_drop < STRIDE_DROP_REST)
        return; /* at rest: the pose is not touched */
    mm_vec3 direction = velocity;
    direction.y = 0.0f;
    if (!(mm_vec3_length(direction) > 1e-3f))
        direction = mm_quat_rotate(root.rotation, mm_vec3_make(0, 0, 1));
    mm_leg_pose legs[2];
    for (int k = 0; k < 2; ++k) {
        legs[k].hip = pose->global[rig->hip[k]].translation;
        legs[k].knee = pose->global[rig->knee[k]].translation;
        legs[k].foot = pose->global[rig->ankle[k]].translation;
    }
    /* the feet's targets and the drop stride warping asks for; the legs are solved below, from the
     * pelvis where it is (mm_warp_stride would solve them first from the drop) */
    mm_vec3 target[2];
    mm_leg_warp out[2];
    float drop = 0.0f;
    if (mm__warp_stride_targets(legs, 2, direction, stride_scale, 0.0f, target, &drop) != MM_OK) return;
    if (!(drop >= 0.0f) || drop > 1.0f) return;
    /* the pelvis follows the drop the legs need on a spring-like filter, not at once; the legs are
     * then solved again from the pelvis where it is, reaching as far as they can */
    float halflife = drop > previous_drop ? STRIDE_DROP_DOWN_HALFLIFE : STRIDE_DROP_UP_HALFLIFE;
    float eased = previous_drop + (drop - previous_drop) * (1.0f - exp2f(-dt / halflife));
    if (!isfinite(eased) || eased < 0.0f) eased = 0.0f;
    /* the knees bend the way their hinges do (mm_rig_knee_pole), whichever way the body moves:
     * mm_warp_stride's pole is the movement, sideways or backward when strafing */
    for (int k = 0; k < 2; ++k) {
        mm_leg_pose lowered = legs[k];
        lowered.hip.y -= eased;
        lowered.knee.y -= eased;
        lowered.foot.y -= eased;
        if (mm_leg_ik_solve(&lowered, target[k], mm_rig_knee_pole(rig, pose, k), NULL, &out[k]) != MM_OK)
            return;
    }
    drop = eased;
    mm_quat knee_world[2], ankle_world[2];
    for (int k = 0; k < 2; ++k) {
        knee_world[k] = pose->global[rig->knee[k]].rotation;
        ankle_world[k] = pose->global[rig->ankle[k]].rotation;
    }
    int pelvis = rig->pelvis;
    w->stride_drop = drop;
    if (drop > 0.0f) {
        mm_vec3 down =
            mm_quat_inv_rotate(pose->global[joints[pelvis].parent].rotation, mm_vec3_make(0.0f, -drop, 0.0f));
        pose->local_positions[pelvis] = mm_vec3_add(pose->local_positions[pelvis], down);
    }
    /* what the legs are set from below: the pelvis as lowered and the hips' rotations (which the drop
     * leaves); every other joint follows in the forward kinematics at the end */
    pose->global[pelvis] =
        mm_xform_mul(pose->global[joints[pelvis].parent],
                     mm_xform_make(pose->local_rotations[pelvis], pose->local_positions[pelvis]));
    for (int k = 0; k < 2; ++k) {
        int hip = rig->hip[k], knee = rig->knee[k], ankle = rig->ankle[k];
        mm_quat hip_world = mm_quat_normalize(mm_quat_mul(out[k].thigh, pose->global[hip].rotation));
        pose->local_rotations[hip] = mm_quat_normalize(
            mm_quat_mul(mm_quat_conj(pose->global[joints[hip].parent].rotation), hip_world));
        pose->global[hip] =
            mm_xform_mul(pose->global[joints[hip].parent],
                         mm_xform_make(pose->local_rotations[hip], pose->local_positions[hip]));
        mm_quat knee_new = mm_quat_normalize(mm_quat_mul(out[k].shin, knee_world[k]));
        pose->local_rotations[knee] =
            mm_quat_normalize(mm_quat_mul(mm_quat_conj(pose->global[hip].rotation), knee_new));
        pose->global[knee] = mm_xform_mul(
            pose->global[hip], mm_xform_make(pose->local_rotations[knee], pose->local_positions[knee]));
        pose->local_rotations[ankle] =
            mm_quat_normalize(mm_quat_mul(mm_quat_conj(pose->global[knee].rotation), ankle_world[k]));
    }
    /* a lowered pelvis moves everything that hangs from it; else only the legs changed */
    if (drop > 0.0f)
        mm_rig_forward_pelvis(rig, pose);
    else
        mm_rig_forward_legs(rig, pose);
}
