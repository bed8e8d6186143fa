/* The posture of a pose from its world joint positions (mm/posture.h). */
#include <limits.h>
#include <math.h>
#include <stdlib.h>

#include <mm/posture.h>

#include "db/process.h"

static const char *const posture_names[MM_POSTURE_COUNT] = {
    "upright", "crouched", "bent", "lying", "calibration", "arms_spread", "hand_raised", "knee_raised"};

const char *mm_posture_name(mm_posture p) { return (unsigned)p < MM_POSTURE_COUNT ? posture_names[p] : NULL; }

float mm_posture_reference_height(float *heights, int n)
{
    return n > 0 ? mm__quantile(heights, n, MM_POSTURE_REFERENCE_QUANTILE) : 0.0f;
}

float mm_posture_stature(const mm_posture_reference *ref)
{
    return ref->head_height / MM_POSTURE_HEAD_TO_STATURE;
}

static bool joint_ok(const mm_vec3 *world, int j)
{
    return j >= 0 && isfinite(world[j].x) && isfinite(world[j].y) && isfinite(world[j].z);
}

bool mm_posture_arms_out(const mm_vec3 *world, const mm_posture_joints *joints,
                         const mm_posture_reference *ref)
{
    if (!joint_ok(world, joints->left_hand) || !joint_ok(world, joints->right_hand) ||
        !(ref->head_height > 0))
        return false;
    float apart = mm_vec3_length(mm_vec3_sub(world[joints->left_hand], world[joints->right_hand]));
    return apart > MM_POSTURE_ARMS_OUT * mm_posture_stature(ref);
}

float mm_posture_thigh_sine(const mm_vec3 *world, const mm_posture_joints *joints, int side)
{
    if (side < 0 || side > 1 || !joint_ok(world, joints->knee[side]) || !joint_ok(world, joints->thigh[side]))
        return NAN;
    mm_vec3 thigh = mm_vec3_sub(world[joints->knee[side]], world[joints->thigh[side]]);
    float length = mm_vec3_length(thigh);
    return length > 1e-6f ? thigh.y / length : NAN;
}

/* A thigh near level: NAN (no leg) compares false */
static bool knee_raised(const mm_vec3 *world, const mm_posture_joints *joints)
{
    return mm_posture_thigh_sine(world, joints, 0) > MM_POSTURE_KNEE_RAISED_SINE ||
           mm_posture_thigh_sine(world, joints, 1) > MM_POSTURE_KNEE_RAISED_SINE;
}

mm_posture mm_posture_classify(const mm_vec3 *world, const mm_posture_joints *joints, float ground_y,
                               const mm_posture_reference *ref)
{
    float h = ref->head_height;
    if (!joint_ok(world, joints->hips) || !joint_ok(world, joints->head) || !(h > 0) || !isfinite(ground_y))
        return MM_POSTURE_UPRIGHT;
    mm_vec3 head = world[joints->head], hips = world[joints->hips];
    float head_height = head.y - ground_y;
    mm_vec3 trunk = mm_vec3_sub(head, hips);
    float length = mm_vec3_length(trunk);
    float lean =
        length > 1e-6f ? acosf(fmaxf(-1.0f, fminf(1.0f, trunk.y / length))) * (float)MM_RAD_TO_DEG : 0.0f;
    if (joint_ok(world, joints->left_hand) && joint_ok(world, joints->right_hand)) {
        mm_vec3 l = world[joints->left_hand], r = world[joints->right_hand];
        float apart = mm_vec3_length(mm_vec3_sub(l, r)), low = MM_POSTURE_CALIBRATION_HANDS * h + ground_y;
        if (apart > MM_POSTURE_CALIBRATION_ARMS * mm_posture_stature(ref) && l.y > low && r.y > low &&
            lean < MM_POSTURE_BENT_DEGREES && head_height >= MM_POSTURE_CROUCHED_HEIGHT * h)
            return MM_POSTURE_CALIBRATION;
        if (head_height < MM_POSTURE_LYING_HEIGHT * h) return MM_POSTURE_LYING;
        if (apart > MM_POSTURE_CALIBRATION_ARMS * mm_posture_stature(ref)) return MM_POSTURE_ARMS_SPREAD;
        if (fmaxf(l.y, r.y) > head.y - MM_POSTURE_HAND_RAISED_BELOW_HEAD * h) return MM_POSTURE_HAND_RAISED;
    }
    if (head_height < MM_POSTURE_LYING_HEIGHT * h) return MM_POSTURE_LYING;
    if (lean > MM_POSTURE_BENT_DEGREES) return MM_POSTURE_BENT;
    if (head_height < MM_POSTURE_CROUCHED_HEIGHT * h) return MM_POSTURE_CROUCHED;
    if (knee_raised(world, joints)) return MM_POSTURE_KNEE_RAISED;
    return MM_POSTURE_UPRIGHT;
}

/* The shortest run of posture p that is not flicker: each[p] (any value under MM_POSTURE_COUNT), or
 * all (each NULL, any value). */
static int shortest_run(const int *each, int all, uint8_t p)
{
    return !each ? all : p < MM_POSTURE_COUNT ? each[p] : 0;
}

/* Runs shorter than their shortest_run take the posture before them (after them, at the start). */
static void settle_runs(uint8_t *postures, int n, const int *each, int all)
{
    /* one pass left to right: a short run takes the posture before it, which has been settled */
    for (int f = 0; f < n;) {
        int e = f;
        while (e < n && postures[e] == postures[f]) ++e;
        if (e - f < shortest_run(each, all, postures[f]) && (f > 0 || e < n)) {
            uint8_t to = f > 0 ? postures[f - 1] : postures[e];
            for (int k = f; k < e; ++k) postures[k] = to;
            if (f > 0) {
                /* merged into the run before: look again from its start */
                while (f > 0 && postures[f - 1] == to) --f;
                continue;
            }
        }
        f = e;
    }
}

static void remove_short_runs(uint8_t *postures, int n, const int *each, int all)
{
    /* A spell away from upright as long as the shortest run of any posture in it is one spell: its
     * short runs settle among themselves first, so that a crouch that leans past the bent threshold
     * for a few frames stays out of upright whole instead of going as three flickers. */
    for (int s = 0; s < n;) {
        if (postures[s] == MM_POSTURE_UPRIGHT) {
            ++s;
            continue;
        }
        int e = s, need = INT_MAX;
        for (; e < n && postures[e] != MM_POSTURE_UPRIGHT; ++e) {
            int shortest = shortest_run(each, all, postures[e]);
            if (shortest < need) need = shortest;
        }
        if (e - s >= need) settle_runs(postures + s, e - s, each, all);
        s = e;
    }
    settle_runs(postures, n, each, all);
}

void mm_posture_remove_flicker(uint8_t *postures, int n, int min_frames)
{
    remove_short_runs(postures, n, NULL, min_frames);
}

void mm_posture_remove_flicker_each(uint8_t *postures, int n, const int min_frames[MM_POSTURE_COUNT])
{
    remove_short_runs(postures, n, min_frames, 0);
}

/* The two joints up a limb from its end joint j: up[0] the first ancestor at least bone_min from j
 * at rest, up[1] the first at least that far from up[0] (-1: not found). */
static void limb_up(const mm_skeleton *s, int j, float bone_min, int up[2])
{
    up[0] = up[1] = -1;
    if (j < 0 || j >= s->joint_count) return;
    /* up the chain, the rest position of each ancestor relative to the end's start */
    int step = 0;
    mm_vec3 from = mm_vec3_make(0, 0, 0), at = from;
    for (int k = j; s->joints[k].parent >= 0 && step < 2; k = s->joints[k].parent) {
        at = mm_vec3_sub(at, s->joints[k].offset); /* the parent's place, in rest axes summed */
        if (mm_vec3_length(mm_vec3_sub(at, from)) >= bone_min) {
            up[step++] = s->joints[k].parent;
            from = at;
        }
    }
}

int mm_posture_find_legs(const mm_skeleton *s, int left_foot, int right_foot, mm_posture_joints *joints)
{
    const int feet[2] = {left_foot, right_foot};
    int found = 0;
    for (int side = 0; side < 2; ++side) {
        int up[2];
        limb_up(s, feet[side], MM_POSTURE_LEG_BONE_MIN, up);
        if (up[1] < 0) up[0] = -1;
        joints->knee[side] = up[0];
        joints->thigh[side] = up[1];
        found += up[1] >= 0;
    }
    return found;
}

bool mm_posture_find_arms(const mm_skeleton *s, int left_hand, int right_hand, mm_posture_arms *out)
{
    const int hands[2] = {left_hand, right_hand};
    bool found = true;
    for (int side = 0; side < 2; ++side) {
        out->hand[side] = out->elbow[side] = out->shoulder[side] = -1;
        int j = hands[side];
        if (j < 0 || j >= s->joint_count) {
            found = false;
            continue;
        }
        out->hand[side] = j;
        int up[2];
        limb_up(s, j, MM_POSTURE_ARM_BONE_MIN, up);
        out->elbow[side] = up[0];
        out->shoulder[side] = up[1];
        if (up[1] < 0) found = false;
    }
    if (!found) out->elbow[0] = out->elbow[1] = out->shoulder[0] = out->shoulder[1] = -1;
    return found;
}

bool mm_posture_a_pose_shape(const mm_vec3 *world, const mm_posture_arms *arms,
                             const mm_posture_joints *joints, float ground_y, const mm_posture_reference *ref)
{
    float h = ref->head_height;
    if (!joint_ok(world, joints->hips) || !joint_ok(world, joints->head) || !(h > 0) || !isfinite(ground_y))
        return false;
    for (int side = 0; side < 2; ++side)
        if (!joint_ok(world, arms->hand[side]) || !joint_ok(world, arms->elbow[side]) ||
            !joint_ok(world, arms->shoulder[side]))
            return false;
    mm_vec3 head = world[joints->head], trunk = mm_vec3_sub(head, world[joints->hips]);
    float length = mm_vec3_length(trunk);
    if (head.y - ground_y < MM_POSTURE_CROUCHED_HEIGHT * h || length < 1e-6f ||
        trunk.y / length < cosf(MM_POSTURE_BENT_DEGREES * (float)MM_DEG_TO_RAD))
        return false;
    /* the shoulders' line, level, from the right shoulder to the left */
    mm_vec3 across = mm_vec3_sub(world[arms->shoulder[0]], world[arms->shoulder[1]]);
    across.y = 0.0f;
    float width = mm_vec3_length(across);
    if (width < 1e-6f) return false;
    for (int side = 0; side < 2; ++side) {
        mm_vec3 shoulder = world[arms->shoulder[side]], elbow = world[arms->elbow[side]],
                hand = world[arms->hand[side]];
        mm_vec3 arm = mm_vec3_sub(hand, shoulder);
        float reach = mm_vec3_length(arm),
              bones = mm_vec3_length(mm_vec3_sub(elbow, shoulder)) + mm_vec3_length(mm_vec3_sub(hand, elbow));
        if (!(bones > 1e-6f) || reach < MM_POSTURE_A_POSE_STRAIGHT * bones) return false;
        float level = sqrtf(arm.x * arm.x + arm.z * arm.z);
        float down = atan2f(-arm.y, level) * (float)MM_RAD_TO_DEG;
        if (down < MM_POSTURE_A_POSE_MIN_DEGREES || down > MM_POSTURE_A_POSE_MAX_DEGREES) return false;
        float outward = (arm.x * across.x + arm.z * across.z) / (level * width) * (side == 0 ? 1.0f : -1.0f);
        if (!(level > 1e-6f) || outward < MM_POSTURE_A_POSE_SIDEWAYS) return false;
    }
    return true;
}

int mm_posture_find_a_poses(const mm_vec3 *world, int n, int stride, float fps, const mm_posture_arms *arms,
                            const mm_posture_joints *joints, const float *ground_y,
                            const mm_posture_reference *ref, uint8_t *out)
{
    int h = (int)lroundf(0.1f * fps), hold = (int)ceilf(MM_POSTURE_A_POSE_HOLD_SECONDS * fps), found = 0;
    if (h < 1) h = 1;
    if (hold < 1) hold = 1;
    for (int f = 0; f < n; ++f) {
        const mm_vec3 *w = world + (size_t)f * (size_t)stride;
        out[f] = mm_posture_a_pose_shape(w, arms, joints, ground_y[f], ref);
        int a = f - h < 0 ? 0 : f - h, b = f + h >= n ? n - 1 : f + h;
        for (int side = 0; side < 2 && out[f] && b > a; ++side) {
            int j = arms->hand[side];
            mm_vec3 d = mm_vec3_sub(world[(size_t)b * (size_t)stride + (size_t)j],
                                    world[(size_t)a * (size_t)stride + (size_t)j]);
            if (mm_vec3_length(d) * fps / (float)(b - a) >= MM_POSTURE_A_POSE_STILL_SPEED) out[f] = 0;
        }
    }
    for (int f = 0; f < n;) { /* held long enough */
        int e = f;
        while (e < n && out[e] == out[f]) ++e;
        if (out[f] && e - f < hold)
            for (int k = f; k < e; ++k) out[k] = 0;
        else if (out[f])
            found += e - f;
        f = e;
    }
    return found;
}
