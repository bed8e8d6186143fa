/* The posture of a pose from its world joint positions (mm/posture.h). */
#include <math.h>
#include <stdlib.h>

#include <mm/posture.h>

#include "db/process.h"

static const char *const posture_names[MM_POSTURE_COUNT] = {"upright", "crouched",    "bent",
                                                            "lying",   "calibration", "arms_spread"};

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
    }
    if (head_height < MM_POSTURE_LYING_HEIGHT * h) return MM_POSTURE_LYING;
    if (lean > MM_POSTURE_BENT_DEGREES) return MM_POSTURE_BENT;
    if (head_height < MM_POSTURE_CROUCHED_HEIGHT * h) return MM_POSTURE_CROUCHED;
    return MM_POSTURE_UPRIGHT;
}

void mm_posture_remove_flicker(uint8_t *postures, int n, int min_frames)
{
    /* one pass left to right: a short run takes the posture before it, which has been settled */
    for (int f = 0; f < n;) {
        int e = f;
        while (e < n && postures[e] == postures[f]) ++e;
        if (e - f < min_frames && (f > 0 || e < n)) {
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
