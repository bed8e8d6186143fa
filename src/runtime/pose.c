/* Pose blending and the model-space round trip. See mm/pose.h. */
#include <mm/pose.h>

#include <math.h>

static float clean_weight(float w) { return isfinite(w) && w > 0.0f ? w : 0.0f; }

void mm_pose_blend(const mm_quat *const *rotations, const mm_vec3 *const *positions, const float *weights,
                   int pose_count, int joint_count, const mm_quat *reference, mm_quat *out_rotations,
                   mm_vec3 *out_positions)
{
    if (!rotations || !positions || !weights || pose_count < 1 || !out_rotations || !out_positions) return;
    float total = 0.0f;
    int heaviest = 0;
    for (int i = 0; i < pose_count; ++i) {
        total += clean_weight(weights[i]);
        if (clean_weight(weights[i]) > clean_weight(weights[heaviest])) heaviest = i;
    }
    if (!(total > 0.0f) || !isfinite(total) || pose_count < 2) {
        for (int j = 0; j < joint_count; ++j) {
            out_rotations[j] = rotations[0][j];
            out_positions[j] = positions[0][j];
        }
        return;
    }
    for (int j = 0; j < joint_count; ++j) {
        mm_quat first = reference ? reference[j] : rotations[heaviest][j], q = mm_quat_make(0, 0, 0, 0);
        mm_vec3 p = mm_vec3_make(0, 0, 0);
        for (int i = 0; i < pose_count; ++i) {
            float w = clean_weight(weights[i]) / total;
            if (w == 0.0f) continue;
            mm_quat r = rotations[i][j];
            float a = mm_quat_dot(r, first) < 0.0f ? -w : w; /* into the reference's hemisphere */
            q = mm_quat_make(q.x + a * r.x, q.y + a * r.y, q.z + a * r.z, q.w + a * r.w);
            p = mm_vec3_add(p, mm_vec3_scale(positions[i][j], w));
        }
        /* a sum that cancels (rotations half a turn apart, evenly weighted) has no direction:
         * keep the heaviest's */
        out_rotations[j] = mm_quat_length(q) > 1e-6f ? mm_quat_normalize(q) : rotations[heaviest][j];
        out_positions[j] = p;
    }
}

void mm_pose_to_model(const mm_joint *joints, int joint_count, mm_quat *rotations)
{
    if (!joints || !rotations) return;
    for (int j = 1; j < joint_count; ++j) {
        int parent = joints[j].parent;
        if (parent >= 1 && parent < j)
            rotations[j] = mm_quat_normalize(mm_quat_mul(rotations[parent], rotations[j]));
    }
}

void mm_pose_to_local(const mm_joint *joints, int joint_count, mm_quat *rotations)
{
    if (!joints || !rotations) return;
    for (int j = joint_count - 1; j >= 1; --j) { /* children first: their parents are still model */
        int parent = joints[j].parent;
        if (parent >= 1 && parent < j)
            rotations[j] = mm_quat_normalize(mm_quat_mul(mm_quat_conj(rotations[parent]), rotations[j]));
    }
}
