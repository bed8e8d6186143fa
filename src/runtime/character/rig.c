/* The character's rig: legs, pelvis and spine found from the ankles by parentage. */
#include "rig.h"

#include <mm/posture.h>

#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

/* Whether joint j hangs from joint a (or is a). */
static bool hangs_from(const mm_joint *joints, int j, int a)
{
    for (; j > a; j = joints[j].parent) {
    }
    return j == a;
}

/* The end (exclusive) of the run of joints from hip that hang from it, when no joint after the
 * run does; -1 otherwise or without a hip. */
static int leg_end(const mm_joint *joints, int joint_count, int hip)
{
    if (hip < 1) return -1;
    int end = hip + 1;
    while (end < joint_count && hangs_from(joints, end, hip)) ++end;
    for (int j = end; j < joint_count; ++j)
        if (hangs_from(joints, j, hip)) return -1;
    return end;
}

void mm_rig_init(mm_rig *rig, const mm_joint *joints, int joint_count, int left_ankle, int right_ankle)
{
    memset(rig, 0, sizeof *rig);
    rig->joints = joints;
    rig->joint_count = joint_count;
    const int ankles[2] = {left_ankle, right_ankle};
    rig->pelvis = -1;
    rig->head = -1;
    for (int k = 0; k < 2; ++k) {
        int ankle = ankles[k] >= 0 && ankles[k] < joint_count ? ankles[k] : -1;
        /* the chain ankle <- knee <- hip must exist below the root */
        if (ankle >= 0 && (joints[ankle].parent < 1 || joints[joints[ankle].parent].parent < 1)) ankle = -1;
        rig->ankle[k] = ankle;
        rig->knee[k] = ankle >= 0 ? joints[ankle].parent : -1;
        rig->hip[k] = ankle >= 0 ? joints[rig->knee[k]].parent : -1;
        rig->toe[k] = -1;
        for (int j = ankle + 1; ankle >= 0 && j < joint_count && rig->toe[k] < 0; ++j)
            if (joints[j].parent == ankle) rig->toe[k] = j;
    }
    for (int k = 0; k < 2; ++k) rig->leg_end[k] = leg_end(joints, joint_count, rig->hip[k]);
    if (rig->ankle[0] >= 0 && rig->ankle[1] >= 0) {
        int left = joints[rig->hip[0]].parent, right = joints[rig->hip[1]].parent;
        if (left == right && left >= 1) rig->pelvis = left;
    }
    int pelvis = rig->pelvis;
    for (int j = pelvis + 1; pelvis >= 0 && j < joint_count && rig->spine_count == 0; ++j) {
        if (joints[j].parent != pelvis) continue;
        int leg = 0;
        for (int k = 0; k < 2; ++k)
            for (int a = rig->ankle[k]; a > pelvis; a = joints[a].parent) leg |= a == j;
        if (leg) continue;
        for (int at = j; at >= 0 && rig->spine_count < MM_RIG_MAX_SPINE;) {
            rig->spine[rig->spine_count++] = at;
            int child = -1, children = 0;
            for (int k = at + 1; k < joint_count; ++k)
                if (joints[k].parent == at) child = children++ ? child : k;
            at = children == 1 ? child : -1;
        }
    }
}

void mm_rig_forward(const mm_rig *rig, int first, mm_rig_pose *pose)
{
    if (pose->body_stale) { /* the joints past the pelvis read current parents from here on */
        if (first > rig->pelvis) first = rig->pelvis;
        pose->body_stale = false;
    }
    mm_skeleton_global_from(rig->joints, rig->joint_count, first, pose->local_rotations,
                            pose->local_positions, pose->global);
}

/* Whether the legs' joints follow their hips in the skeleton's order (mm_rig.leg_end) below a
 * pelvis: the body past the pelvis is then the legs and the rest. */
static bool legs_apart(const mm_rig *rig)
{
    return rig->pelvis >= 1 && rig->leg_end[0] >= 0 && rig->leg_end[1] >= 0;
}

/* The forward kinematics of the runs of joints [begin[r], end[r]) in turn, each reading parents
 * already current; runs that meet (a leg right after the pelvis or the other leg) in one call. */
static void forward_runs(const mm_rig *rig, mm_rig_pose *pose, const int *begin, const int *end, int count)
{
    for (int r = 0; r < count;) {
        int b = begin[r], e = end[r];
        for (++r; r < count && begin[r] == e && b < e; ++r) e = end[r];
        if (b < e)
            mm_skeleton_global_from(rig->joints, e, b, pose->local_rotations, pose->local_positions,
                                    pose->global);
    }
}

void mm_rig_forward_pelvis(const mm_rig *rig, mm_rig_pose *pose)
{
    if (!pose->defer_body || !legs_apart(rig)) {
        mm_rig_forward(rig, 1, pose);
        return;
    }
    /* the joints up to the pelvis (those before it are unchanged: the same transforms again), then
     * the legs */
    int first = rig->hip[0] < rig->hip[1] ? 0 : 1;
    const int begin[3] = {1, rig->hip[first], rig->hip[1 - first]},
              end[3] = {rig->pelvis + 1, rig->leg_end[first], rig->leg_end[1 - first]};
    forward_runs(rig, pose, begin, end, 3);
    pose->body_stale = true;
}

void mm_rig_forward_finish(const mm_rig *rig, mm_rig_pose *pose)
{
    pose->defer_body = false;
    mm_rig_forward_rest(rig, pose);
}

void mm_rig_forward_rest(const mm_rig *rig, mm_rig_pose *pose)
{
    if (!pose->body_stale) return;
    pose->body_stale = false;
    /* the joints past the pelvis outside the legs, in runs between them: none of them hangs from
     * a leg (mm_rig.leg_end), so each reads parents already current */
    int first = rig->hip[0] < rig->hip[1] ? 0 : 1;
    const int begin[3] = {rig->pelvis + 1, rig->leg_end[first], rig->leg_end[1 - first]},
              end[3] = {rig->hip[first], rig->hip[1 - first], rig->joint_count};
    forward_runs(rig, pose, begin, end, 3);
}

void mm_rig_forward_legs(const mm_rig *rig, mm_rig_pose *pose)
{
    if (rig->leg_end[0] < 0 || rig->leg_end[1] < 0) {
        mm_rig_forward(rig, 1, pose);
        return;
    }
    int first = rig->hip[0] < rig->hip[1] ? 0 : 1;
    const int begin[2] = {rig->hip[first], rig->hip[1 - first]},
              end[2] = {rig->leg_end[first], rig->leg_end[1 - first]};
    forward_runs(rig, pose, begin, end, 2);
}

mm_vec3 mm_rig_pelvis_forward(const mm_rig *rig, const mm_rig_pose *pose)
{
    if (rig->hip[0] < 0 || rig->hip[1] < 0) return mm_vec3_make(0, 0, 0);
    mm_vec3 across =
        mm_vec3_sub(pose->global[rig->hip[1]].translation, pose->global[rig->hip[0]].translation);
    return mm_vec3_make(across.z, 0.0f, -across.x);
}

/* frames read per learned hinge (evenly spaced over the database) */
#define HINGE_SAMPLES 4096
/* sine of the knee's bend from which a frame counts toward its hinge */
#define HINGE_MIN_BEND 0.3f

void mm_rig_learn_hinges(mm_rig *rig, const mm_database *db)
{
    int step = db->frame_count > HINGE_SAMPLES ? db->frame_count / HINGE_SAMPLES : 1;
    for (int k = 0; k < 2; ++k) {
        rig->hinge[k] = mm_vec3_make(0, 0, 0);
        int knee = rig->knee[k], ankle = rig->ankle[k];
        if (knee < 0 || ankle < 0) continue;
        mm_vec3 sum = mm_vec3_make(0, 0, 0);
        for (int f = 0; f < db->frame_count; f += step) {
            mm_quat knee_rotation, ankle_rotation;
            mm_vec3 knee_position, shin;
            mm_database_local_joint(db, f, knee, &knee_rotation, &knee_position);
            mm_database_local_joint(db, f, ankle, &ankle_rotation, &shin);
            /* in the knee's frame: the thigh (hip to knee) and the shin (knee to ankle) */
            mm_vec3 thigh = mm_quat_inv_rotate(knee_rotation, knee_position);
            float lt = mm_vec3_length(thigh), ls = mm_vec3_length(shin);
            if (!(lt > 1e-6f) || !(ls > 1e-6f)) continue;
            mm_vec3 c = mm_vec3_scale(mm_vec3_cross(thigh, shin), 1.0f / (lt * ls));
            if (mm_vec3_length(c) >= HINGE_MIN_BEND) sum = mm_vec3_add(sum, c);
        }
        if (mm_vec3_length(sum) > 1e-3f) rig->hinge[k] = mm_vec3_normalize(sum);
    }
}

mm_vec3 mm_rig_knee_pole(const mm_rig *rig, const mm_rig_pose *pose, int k)
{
    if (mm_vec3_length(rig->hinge[k]) == 0.0f) return mm_rig_pelvis_forward(rig, pose);
    mm_vec3 ac = mm_vec3_sub(pose->global[rig->ankle[k]].translation, pose->global[rig->hip[k]].translation);
    mm_vec3 hinge = mm_quat_rotate(pose->global[rig->knee[k]].rotation, rig->hinge[k]);
    /* thigh a u + h s and shin (L - a) u - h s have cross(thigh, shin) = L h cross(s, u): along the
     * hinge when s = cross(u, hinge) */
    return mm_vec3_cross(ac, hinge);
}

/* frames read per planted height (evenly spaced over the labelled frames of the database) */
#define PLANTED_SAMPLES 1024

/* Joint j's height above joint 0 (the root, on the ground) in database frame f. */
static float height_above_root(const mm_rig *rig, const mm_database *db, int f, int j)
{
    /* from the joint up to the root: p = offset in the parent, rotated by the parent's global */
    mm_vec3 v = mm_vec3_make(0, 0, 0), p;
    mm_quat r;
    for (int k = j; k > 0; k = rig->joints[k].parent) {
        mm_database_local_joint(db, f, k, &r, &p);
        v = mm_vec3_add(p, mm_quat_rotate(r, v));
    }
    mm_database_local_joint(db, f, 0, &r, &p);
    return mm_quat_rotate(r, v).y;
}

static int compare_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

/* The median height of joint j over the sampled frames whose label bit is on (0 without any). */
static float planted_height(const mm_rig *rig, const mm_database *db, int j, unsigned bit)
{
    float h[PLANTED_SAMPLES];
    int labelled = 0, n = 0;
    for (int f = 0; f < db->frame_count; ++f) labelled += (db->contacts[f] & bit) != 0;
    int step = labelled > PLANTED_SAMPLES ? labelled / PLANTED_SAMPLES + 1 : 1;
    for (int f = 0, seen = 0; f < db->frame_count && n < PLANTED_SAMPLES; ++f)
        if ((db->contacts[f] & bit) && seen++ % step == 0) h[n++] = height_above_root(rig, db, f, j);
    if (n == 0) return 0.0f;
    qsort(h, (size_t)n, sizeof(float), compare_float);
    return h[n / 2];
}

void mm_rig_learn_planted_heights(mm_rig *rig, const mm_database *db)
{
    static const unsigned heel_bit[2] = {MM_CONTACT_LEFT_HEEL, MM_CONTACT_RIGHT_HEEL},
                          toe_bit[2] = {MM_CONTACT_LEFT_TOE, MM_CONTACT_RIGHT_TOE};
    for (int k = 0; k < 2; ++k) {
        rig->planted_ankle[k] =
            rig->ankle[k] >= 0 ? planted_height(rig, db, rig->ankle[k], heel_bit[k]) : 0.0f;
        rig->planted_toe[k] = rig->toe[k] >= 0 ? planted_height(rig, db, rig->toe[k], toe_bit[k]) : 0.0f;
    }
}

void mm_rig_learn_head_floor(mm_rig *rig, const mm_database *db)
{
    float h[PLANTED_SAMPLES];
    int frames = 0, n = 0;
    rig->head = -1;
    rig->head_floor = 0.0f;
    int head = mm_database_role_joint(db, MM_ROLE_HEAD);
    if (rig->pelvis <= 0 || head <= rig->pelvis || head >= rig->joint_count ||
        !hangs_from(rig->joints, head, rig->pelvis))
        return;
    for (int f = 0; f < db->frame_count; ++f) {
        int type = db->clips[db->frame_clip[f]].type;
        frames += type == MM_CLIP_LOCOMOTION || type == MM_CLIP_IDLE;
    }
    int step = frames > PLANTED_SAMPLES ? frames / PLANTED_SAMPLES + 1 : 1;
    for (int f = 0, seen = 0; f < db->frame_count && n < PLANTED_SAMPLES; ++f) {
        int type = db->clips[db->frame_clip[f]].type;
        if ((type == MM_CLIP_LOCOMOTION || type == MM_CLIP_IDLE) && seen++ % step == 0)
            h[n++] = height_above_root(rig, db, f, head);
    }
    if (n == 0) return;
    qsort(h, (size_t)n, sizeof(float), compare_float);
    rig->head = head;
    rig->head_floor = MM_POSTURE_CROUCHED_HEIGHT * h[(int)(MM_POSTURE_REFERENCE_QUANTILE * (float)(n - 1))];
}

float mm_rig_head_above_pelvis(const mm_rig *rig, const mm_rig_pose *pose)
{
    if (rig->head < 0) return 0.0f;
    mm_vec3 v = mm_vec3_make(0, 0, 0);
    int j = rig->head;
    for (; j != rig->pelvis; j = rig->joints[j].parent)
        v = mm_vec3_add(pose->local_positions[j], mm_quat_rotate(pose->local_rotations[j], v));
    return mm_quat_rotate(pose->global[rig->pelvis].rotation, v).y;
}

void mm_rig_learn_hip_floor(mm_rig *rig, const mm_database *db, uint64_t other_gaits)
{
    float h[PLANTED_SAMPLES];
    int upright = 0, n = 0;
    rig->hip_floor = 0.0f;
    if (rig->pelvis <= 0) return;
    for (int f = 0; f < db->frame_count; ++f)
        upright += db->clips[db->frame_clip[f]].type == MM_CLIP_LOCOMOTION &&
                   !(db->frame_tags && (db->frame_tags[f] & other_gaits));
    int step = upright > PLANTED_SAMPLES ? upright / PLANTED_SAMPLES + 1 : 1;
    for (int f = 0, seen = 0; f < db->frame_count && n < PLANTED_SAMPLES; ++f)
        if (db->clips[db->frame_clip[f]].type == MM_CLIP_LOCOMOTION &&
            !(db->frame_tags && (db->frame_tags[f] & other_gaits)) && seen++ % step == 0)
            h[n++] = height_above_root(rig, db, f, rig->pelvis);
    if (n == 0) return;
    qsort(h, (size_t)n, sizeof(float), compare_float);
    rig->hip_floor = h[(int)(MM_RIG_HIP_FLOOR_QUANTILE * (float)(n - 1))];
}
