/* The standard body of the synthetic set: an adult of about 1.75 m with LAFAN1 joint names.
 *
 * Proportions (metres) follow anthropometric ratios of stature H = 1.75: hip joint height
 * 0.52 H, thigh 0.24 H, shank 0.235 H, ankle height 0.046 H, shoulder height 0.82 H, upper arm
 * 0.166 H, forearm 0.143 H. The rest pose is a T-pose facing +Z with the legs straight and the
 * feet flat on the ground: every local rotation is the identity.
 */
#include <math.h>
#include <string.h>

#include <mm/skeleton.h>

#include "synth_internal.h"

const char *const synth_joint_names[SJ_COUNT] = {
    "Hips",          "LeftUpLeg", "LeftLeg",      "LeftFoot", "LeftToe",     "RightUpLeg",
    "RightLeg",      "RightFoot", "RightToe",     "Spine",    "Spine1",      "Spine2",
    "Neck",          "Head",      "LeftShoulder", "LeftArm",  "LeftForeArm", "LeftHand",
    "RightShoulder", "RightArm",  "RightForeArm", "RightHand"};

/* End Sites (leaf markers): toe tips, top of the head, finger tips. */
static const struct {
    int joint;
    float x, y, z;
} synth_end_sites[] = {{SJ_LTOE, 0.0f, -0.01f, 0.06f},
                       {SJ_RTOE, 0.0f, -0.01f, 0.06f},
                       {SJ_HEAD, 0.0f, 0.15f, 0.02f},
                       {SJ_LHAND, 0.17f, 0.0f, 0.0f},
                       {SJ_RHAND, -0.17f, 0.0f, 0.0f}};

void synth_body_init(synth_body *b)
{
    memset(b, 0, sizeof *b);
    static const int parent[SJ_COUNT] = {
        -1,       SJ_HIPS,     SJ_LUPLEG, SJ_LLEG,      SJ_LFOOT,  SJ_HIPS,    SJ_RUPLEG, SJ_RLEG,
        SJ_RFOOT, SJ_HIPS,     SJ_SPINE,  SJ_SPINE1,    SJ_SPINE2, SJ_NECK,    SJ_SPINE2, SJ_LSHOULDER,
        SJ_LARM,  SJ_LFOREARM, SJ_SPINE2, SJ_RSHOULDER, SJ_RARM,   SJ_RFOREARM};
    memcpy(b->parent, parent, sizeof parent);

    b->thigh = 0.42f;
    b->shin = 0.41f;
    b->ankle_height = 0.08f;
    b->toe_offset = mm_vec3_make(0.0f, -0.05f, 0.13f);
    const float hip_half_width = 0.09f, hip_drop = 0.05f;
    const float hips_y = b->ankle_height + b->thigh + b->shin + hip_drop; /* 0.96 */

    b->offset[SJ_HIPS] = mm_vec3_make(0.0f, hips_y, 0.0f);
    for (int side = 0; side < 2; ++side) {
        float s = synth_side_sign(side);
        int up = side == SYNTH_LEFT ? SJ_LUPLEG : SJ_RUPLEG;
        b->offset[up] = mm_vec3_make(s * hip_half_width, -hip_drop, 0.0f);
        b->offset[up + 1] = mm_vec3_make(0.0f, -b->thigh, 0.0f);
        b->offset[up + 2] = mm_vec3_make(0.0f, -b->shin, 0.0f);
        b->offset[up + 3] = b->toe_offset;
        int sh = side == SYNTH_LEFT ? SJ_LSHOULDER : SJ_RSHOULDER;
        b->offset[sh] = mm_vec3_make(s * 0.03f, 0.15f, -0.01f);
        b->offset[sh + 1] = mm_vec3_make(s * 0.15f, 0.0f, 0.0f); /* clavicle */
        b->offset[sh + 2] = mm_vec3_make(s * 0.29f, 0.0f, 0.0f); /* upper arm */
        b->offset[sh + 3] = mm_vec3_make(s * 0.25f, 0.0f, 0.0f); /* forearm */
    }
    b->offset[SJ_SPINE] = mm_vec3_make(0.0f, 0.09f, -0.01f);
    b->offset[SJ_SPINE1] = mm_vec3_make(0.0f, 0.12f, 0.0f);
    b->offset[SJ_SPINE2] = mm_vec3_make(0.0f, 0.12f, 0.0f);
    b->offset[SJ_NECK] = mm_vec3_make(0.0f, 0.21f, 0.0f);
    b->offset[SJ_HEAD] = mm_vec3_make(0.0f, 0.10f, 0.02f);

    b->min_knee = 3.0f * (float)MM_DEG_TO_RAD;
    b->leg_reach = synth_leg_length_at(b, b->min_knee);
    /* Relaxed standing: knees flexed about 6 degrees. */
    b->stand_height = b->ankle_height + synth_leg_length_at(b, 6.0f * (float)MM_DEG_TO_RAD) + hip_drop;
    b->height = hips_y + 0.09f + 0.12f + 0.12f + 0.21f + 0.10f + 0.15f;
}

float synth_leg_length_at(const synth_body *b, float knee)
{
    float a = b->thigh, c = b->shin;
    return sqrtf(a * a + c * c + 2.0f * a * c * cosf(knee));
}

mm_result mm_synth_skeleton(mm_skeleton *out, const mm_allocator *allocator)
{
    if (!out) return MM_ERR_INVALID_ARGUMENT;
    mm_result r = mm_skeleton_init(out, SJ_COUNT, allocator);
    if (r != MM_OK) return r;
    synth_body b;
    synth_body_init(&b);
    for (int j = 0; j < SJ_COUNT; ++j) {
        mm_joint *jt = &out->joints[j];
        strncpy(jt->name, synth_joint_names[j], MM_NAME_MAX - 1);
        jt->name[MM_NAME_MAX - 1] = 0;
        jt->parent = b.parent[j];
        jt->offset = b.offset[j];
        jt->order = MM_EULER_ZYX;
        jt->flags = j == SJ_HIPS ? MM_JOINT_TRANSLATES : 0u;
    }
    for (size_t i = 0; i < sizeof synth_end_sites / sizeof synth_end_sites[0]; ++i) {
        mm_joint *jt = &out->joints[synth_end_sites[i].joint];
        jt->has_end_site = true;
        jt->end_site = mm_vec3_make(synth_end_sites[i].x, synth_end_sites[i].y, synth_end_sites[i].z);
    }
    return MM_OK;
}
