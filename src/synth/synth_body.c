/* Pose assembly: from a world-space description of the body (pelvis, feet, chest, head, arm
 * angles) to the local rotations of every joint. Legs are solved with two-bone IK, the spine
 * distributes the chest rotation evenly over its three joints, the neck and head share the gaze
 * rotation, and the arms are built in the chest's frame.
 */
#include <math.h>

#include "synth_internal.h"

float synth_wrap_angle(float a)
{
    while (a > SYNTH_PI) a -= SYNTH_TAU;
    while (a <= -SYNTH_PI) a += SYNTH_TAU;
    return a;
}

mm_quat synth_quat_from_frame(mm_vec3 primary, mm_vec3 secondary, mm_vec3 rest_primary,
                              mm_vec3 rest_secondary)
{
    mm_vec3 p = mm_vec3_normalize(primary);
    mm_vec3 s = mm_vec3_normalize(mm_vec3_sub(secondary, mm_vec3_scale(p, mm_vec3_dot(secondary, p))));
    mm_vec3 t = mm_vec3_cross(p, s);
    mm_vec3 rp = mm_vec3_normalize(rest_primary);
    mm_vec3 rs =
        mm_vec3_normalize(mm_vec3_sub(rest_secondary, mm_vec3_scale(rp, mm_vec3_dot(rest_secondary, rp))));
    mm_vec3 rt = mm_vec3_cross(rp, rs);
    const float w[3][3] = {{p.x, s.x, t.x}, {p.y, s.y, t.y}, {p.z, s.z, t.z}};
    const float r[3][3] = {{rp.x, rs.x, rt.x}, {rp.y, rs.y, rt.y}, {rp.z, rs.z, rt.z}};
    mm_mat3 m;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) m.m[i][j] = w[i][0] * r[j][0] + w[i][1] * r[j][1] + w[i][2] * r[j][2];
    return mm_quat_normalize(mm_quat_from_mat3(m));
}

mm_quat synth_quat_pow(mm_quat q, float t) { return mm_quat_exp(mm_vec3_scale(mm_quat_log(q), t)); }

/* local = parent_global^-1 * global */
static mm_quat local_of(mm_quat parent_global, mm_quat global)
{
    return mm_quat_normalize(mm_quat_mul(mm_quat_conj(parent_global), global));
}

static void build_arm(const synth_body *b, const synth_pose *p, int side, mm_quat chest, mm_quat *rot)
{
    const float s = synth_side_sign(side);
    const int sh = side == SYNTH_LEFT ? SJ_LSHOULDER : SJ_RSHOULDER;
    (void)b;
    /* Clavicle: elevation with breathing and arm swing, protraction when the arm swings forward. */
    float prot = 0.12f * p->arm_swing[side];
    mm_quat clav_local = mm_quat_mul(synth_rot_z(s * p->clavicle[side]), synth_rot_y(-s * prot));
    mm_quat clav = mm_quat_mul(chest, clav_local);
    rot[sh] = clav_local;

    /* Upper arm direction in the chest frame: down, abducted to the side, swung forward. */
    float ab = p->arm_abduct[side], sw = p->arm_swing[side];
    mm_vec3 d = mm_vec3_make(s * sinf(ab), -cosf(ab) * cosf(sw), cosf(ab) * sinf(sw));
    mm_vec3 fwd = mm_vec3_make(0.0f, 0.0f, 1.0f);
    mm_vec3 n = mm_vec3_normalize(mm_vec3_sub(fwd, mm_vec3_scale(d, mm_vec3_dot(fwd, d))));
    d = mm_quat_rotate(chest, d);
    n = mm_quat_rotate(chest, n);
    const mm_vec3 rest_dir = mm_vec3_make(s, 0.0f, 0.0f), rest_fwd = fwd;
    mm_quat upper = synth_quat_from_frame(d, n, rest_dir, rest_fwd);

    float e = p->elbow[side];
    mm_vec3 f = mm_vec3_add(mm_vec3_scale(d, cosf(e)), mm_vec3_scale(n, sinf(e)));
    mm_vec3 fn = mm_vec3_sub(mm_vec3_scale(n, cosf(e)), mm_vec3_scale(d, sinf(e)));
    mm_quat fore = synth_quat_from_frame(f, fn, rest_dir, rest_fwd);

    float w = p->wrist[side];
    mm_vec3 h = mm_vec3_add(mm_vec3_scale(f, cosf(w)), mm_vec3_scale(fn, sinf(w)));
    mm_vec3 hn = mm_vec3_sub(mm_vec3_scale(fn, cosf(w)), mm_vec3_scale(f, sinf(w)));
    mm_quat hand = synth_quat_from_frame(h, hn, rest_dir, rest_fwd);

    rot[sh + 1] = local_of(clav, upper);
    rot[sh + 2] = local_of(upper, fore);
    rot[sh + 3] = local_of(fore, hand);
}

void synth_pose_to_locals(const synth_body *b, const synth_pose *p, mm_quat *rot, mm_vec3 *pos)
{
    for (int j = 0; j < SJ_COUNT; ++j) pos[j] = b->offset[j];
    pos[SJ_HIPS] = p->pelvis;
    mm_quat pelvis = mm_quat_normalize(p->pelvis_rot);
    rot[SJ_HIPS] = pelvis;

    /* Legs. */
    for (int side = 0; side < 2; ++side) {
        const synth_foot *f = &p->foot[side];
        int up = side == SYNTH_LEFT ? SJ_LUPLEG : SJ_RUPLEG;
        mm_vec3 hip = synth_hip_position(b, side, p->pelvis, pelvis);
        mm_quat thigh, shin;
        synth_leg_ik(b, hip, f->ankle, synth_heading_dir(f->yaw), &thigh, &shin);
        mm_quat foot = synth_foot_rotation(f->yaw, f->pitch);
        rot[up] = local_of(pelvis, thigh);
        rot[up + 1] = local_of(thigh, shin);
        rot[up + 2] = local_of(shin, foot);
        rot[up + 3] = synth_rot_x(f->toe_angle);
    }

    /* Spine: the chest rotation relative to the pelvis, a third per joint, plus breathing
     * (extension of the upper two joints on the in-breath). */
    mm_quat part = synth_quat_pow(local_of(pelvis, p->chest), 1.0f / 3.0f);
    mm_quat breathe = synth_rot_x(-0.012f * p->breath);
    rot[SJ_SPINE] = part;
    rot[SJ_SPINE1] = mm_quat_mul(part, breathe);
    rot[SJ_SPINE2] = mm_quat_mul(part, breathe);
    mm_quat chest =
        mm_quat_mul(pelvis, mm_quat_mul(rot[SJ_SPINE], mm_quat_mul(rot[SJ_SPINE1], rot[SJ_SPINE2])));

    /* Neck and head share the rotation from the chest to the gaze. */
    mm_quat head = synth_yaw_pitch_roll(p->head_yaw, p->head_pitch, p->head_roll);
    mm_quat half = synth_quat_pow(local_of(chest, head), 0.5f);
    rot[SJ_NECK] = half;
    rot[SJ_HEAD] = half;

    build_arm(b, p, SYNTH_LEFT, chest, rot);
    build_arm(b, p, SYNTH_RIGHT, chest, rot);
}
