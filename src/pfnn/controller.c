/* The PFNN character controller: seed 004's Update, one 60 Hz frame at a time.
 *
 * Inside, everything is in the network's units: centimetres, and velocities in centimetres per
 * 60 Hz frame. The trajectory is 120 frames long (60 past, the current at index 60, 59 future); the
 * network sees every 10th point. Order of one frame (docs/pfnn.md explains each step):
 *   1. target velocity and direction blended toward the player's input;
 *   2. gait weights of the current point blended toward the requested gait;
 *   3. future trajectory predicted by blending its own motion toward the target, kept out of
 *      obstacles, facing turned toward the target direction;
 *   4. terrain heights under the current and future points, the root height their mean;
 *   5. network input assembled (trajectory, gaits, previous pose, terrain), 6. network evaluated;
 *   7. past trajectory shifted one frame; 8. current point moved and turned by the predicted root
 *      motion (scaled by (1 - stand)^0.25), kept out of obstacles; 9. future points replaced by
 *      (blended toward) the network's trajectory; 10. posture: positions half (previous + velocity),
 *      half predicted, rotations from the exponential maps; 11. phase advanced. */
#include <mm/pfnn.h>
#include <mm/scene.h>

#include <math.h>
#include <string.h>

#include "pfnn/pfnn_private.h"
#include "math_private.h"

#define TL            120
#define HALF          60
#define J             MM_PFNN_JOINT_COUNT
#define CM            100.0f
#define MAX_OBSTACLES 256
#define MAX_FRAMES    600 /* per mm_pfnn_controller_step call */
#define TWO_PI        6.283185307179586
#define GAIT_STAND    0
#define SIDE_WIDTH    25.0f /* cm either side of a trajectory point for the terrain heights */

struct mm_pfnn_controller {
    mm_allocator allocator;
    bool has_allocator;
    const mm_pfnn_network *net;
    mm_pfnn_mode mode;
    mm_pfnn_height_fn height;
    void *height_user;
    mm_pfnn_obstacle obstacles[MAX_OBSTACLES]; /* centres and sizes in centimetres */
    int obstacle_count;
    float clearance; /* cm */
    float target_blend, strafe_blend, gait_blend, correction, joint_smooth, pos_bias, dir_bias;
    bool mirror; /* average the network with its mirror image (mm_pfnn_symmetry) */
    const float *ymean;

    /* trajectory, centimetres */
    mm_vec3 pos[TL];
    float dir_x[TL], dir_z[TL]; /* unit facing directions */
    float root_h[TL];           /* the root height when each point was the current one */
    float gait[TL][MM_PFNN_GAIT_COUNT];

    float target_vx, target_vz; /* cm per frame */
    float target_dx, target_dz; /* unit */
    float strafe;               /* 0..1 */
    float facing_x, facing_z;   /* the latest requested facing */

    mm_vec3 joint_pos[J], joint_vel[J], joint_pred[J]; /* world, cm and cm per frame */
    mm_quat joint_rot[J];
    float phase;
    double time_acc;
    long frame;
    float x[MM_PFNN_INPUT_DIM], y[MM_PFNN_OUTPUT_DIM];
    float x_mirror[MM_PFNN_INPUT_DIM], y_mirror[MM_PFNN_OUTPUT_DIM];
    mm_pfnn_state state;
};

/* ---- small helpers ---------------------------------------------------------------------------- */

static float lerpf(float a, float b, float t) { return a + (b - a) * t; }

/* Rotation by yaw about Y (0 faces +Z): x' = cos x + sin z, z' = -sin x + cos z. */
static mm_vec3 rot_y(float yaw, mm_vec3 v)
{
    float c = cosf(yaw), s = sinf(yaw);
    return mm_vec3_make(c * v.x + s * v.z, v.y, -s * v.x + c * v.z);
}
static float yaw_of_direction(float dx, float dz) { return atan2f(dx, dz); }

/* Direction between a and b (yaw angles, shortest way), as a unit (x, z). */
static void mix_dir(float ax, float az, float bx, float bz, float t, float *ox, float *oz)
{
    float a = yaw_of_direction(ax, az), b = yaw_of_direction(bx, bz);
    float d = b - a;
    while (d > (float)MM_PI) d -= (float)TWO_PI;
    while (d < -(float)MM_PI) d += (float)TWO_PI;
    float r = a + d * t;
    *ox = sinf(r);
    *oz = cosf(r);
}

static float height_cm(const mm_pfnn_controller *c, float x, float z)
{
    float h = c->height ? c->height(x / CM, z / CM, c->height_user) : 0.0f;
    return isfinite(h) ? h * CM : 0.0f;
}

/* The half-angle exponential map of the release: a rotation by 2 |l| about l, identity below 0.01. */
static mm_quat exp_half(float lx, float ly, float lz)
{
    float n = sqrtf(lx * lx + ly * ly + lz * lz);
    if (n < 0.01f) return mm_quat_identity();
    float s = sinf(n) / n;
    return mm_quat_normalize(mm_quat_make(lx * s, ly * s, lz * s, cosf(n)));
}

float mm_pfnn_height_flat(float x, float z, void *user)
{
    (void)x;
    (void)z;
    (void)user;
    return 0.0f;
}

float mm_pfnn_height_scene(float x, float z, void *user)
{
    return user ? mm_scene_ground_height((const mm_scene *)user, x, z, NULL) : 0.0f;
}

float mm_pfnn_height_slopes(float x, float z, void *user)
{
    (void)user;
    return 0.35f * sinf(0.4f * x) + 0.25f * sinf(0.3f * z + 0.5f * sinf(0.2f * x));
}

/* ---- left/right symmetry ----------------------------------------------------------------------- */

/* The release's joints mirrored left <-> right: LHipJoint..LeftToeBase (1-5) with RHipJoint..
 * RightToeBase (6-10), LeftShoulder..LThumb (17-23) with RightShoulder..RThumb (24-30). */
static int mirror_joint(int j)
{
    if (j >= 1 && j <= 5) return j + 5;
    if (j >= 6 && j <= 10) return j - 5;
    if (j >= 17 && j <= 23) return j + 7;
    if (j >= 24 && j <= 30) return j - 7;
    return j;
}

/* The input of the character reflected in its own sagittal plane (x -> -x): trajectory x and
 * direction x negated, left and right joints exchanged (x negated), right and left heights exchanged. */
static void mirror_input(const float *x, float *m)
{
    memcpy(m, x, sizeof(float) * MM_PFNN_INPUT_DIM);
    for (int s = 0; s < MM_PFNN_TRAJ_SAMPLES; ++s) {
        m[MM_PFNN_X_TRAJ_POS_X + s] = -x[MM_PFNN_X_TRAJ_POS_X + s];
        m[MM_PFNN_X_TRAJ_DIR_X + s] = -x[MM_PFNN_X_TRAJ_DIR_X + s];
        m[MM_PFNN_X_HEIGHT_RIGHT + s] = x[MM_PFNN_X_HEIGHT_LEFT + s];
        m[MM_PFNN_X_HEIGHT_LEFT + s] = x[MM_PFNN_X_HEIGHT_RIGHT + s];
    }
    for (int j = 0; j < J; ++j) {
        int k = mirror_joint(j);
        for (int b = 0; b < 2; ++b) {
            int o = b ? MM_PFNN_X_JOINT_VEL : MM_PFNN_X_JOINT_POS;
            m[o + 3 * j + 0] = -x[o + 3 * k + 0];
            m[o + 3 * j + 1] = x[o + 3 * k + 1];
            m[o + 3 * j + 2] = x[o + 3 * k + 2];
        }
    }
}

/* y = (y + M m) / 2, M reflecting an output like mirror_input does an input: root x and turn
 * negated, left and right contacts exchanged, trajectory x negated, joints exchanged with x negated,
 * and rotation exponential maps (x, y, z) -> (x, -y, -z) (a reflection keeps the angle's axis
 * component along the normal and reverses the sense of rotation). */
static void average_mirrored_output(float *y, const float *m)
{
    float r[MM_PFNN_OUTPUT_DIM];
    memcpy(r, m, sizeof r);
    r[MM_PFNN_Y_ROOT_X] = -m[MM_PFNN_Y_ROOT_X];
    r[MM_PFNN_Y_ROOT_TURN] = -m[MM_PFNN_Y_ROOT_TURN];
    for (int k = 0; k < 2; ++k) {
        r[MM_PFNN_Y_CONTACTS + k] = m[MM_PFNN_Y_CONTACTS + 2 + k];
        r[MM_PFNN_Y_CONTACTS + 2 + k] = m[MM_PFNN_Y_CONTACTS + k];
    }
    for (int s = 0; s < MM_PFNN_FUTURE_SAMPLES; ++s) {
        r[MM_PFNN_Y_TRAJ_POS_X + s] = -m[MM_PFNN_Y_TRAJ_POS_X + s];
        r[MM_PFNN_Y_TRAJ_DIR_X + s] = -m[MM_PFNN_Y_TRAJ_DIR_X + s];
    }
    for (int j = 0; j < J; ++j) {
        int k = mirror_joint(j);
        for (int b = 0; b < 3; ++b) {
            int o = b == 0 ? MM_PFNN_Y_JOINT_POS : b == 1 ? MM_PFNN_Y_JOINT_VEL : MM_PFNN_Y_JOINT_ROT;
            float sx = b == 2 ? 1.0f : -1.0f, syz = b == 2 ? -1.0f : 1.0f;
            r[o + 3 * j + 0] = sx * m[o + 3 * k + 0];
            r[o + 3 * j + 1] = syz * m[o + 3 * k + 1];
            r[o + 3 * j + 2] = syz * m[o + 3 * k + 2];
        }
    }
    for (int i = 0; i < MM_PFNN_OUTPUT_DIM; ++i) y[i] = 0.5f * (y[i] + r[i]);
}

/* The network at the current phase; mirror-averaged unless the symmetry is off. The mirror image
 * of a gait half a cycle on is the same gait on the other foot, hence phase + pi. */
static void evaluate(mm_pfnn_controller *c)
{
    mm_pfnn_network_eval(c->net, c->mode, c->phase, c->x, c->y);
    if (!c->mirror) return;
    mirror_input(c->x, c->x_mirror);
    mm_pfnn_network_eval(c->net, c->mode, c->phase + (float)MM_PI, c->x_mirror, c->y_mirror);
    average_mirrored_output(c->y, c->y_mirror);
}

/* ---- obstacles -------------------------------------------------------------------------------- */

/* Pushes p (cm) out of every obstacle grown by the clearance, along the shortest way. */
static void collide(const mm_pfnn_controller *c, mm_vec3 *p)
{
    for (int o = 0; o < c->obstacle_count; ++o) {
        const mm_pfnn_obstacle *ob = &c->obstacles[o];
        float vx = p->x - ob->centre.x, vz = p->z - ob->centre.z;
        float nx, nz, d; /* outward normal and signed distance to the surface */
        if (ob->shape == MM_PFNN_OBSTACLE_BOX) {
            mm_vec3 l = rot_y(-ob->yaw, mm_vec3_make(vx, 0.0f, vz));
            float qx = fabsf(l.x) - ob->half_x, qz = fabsf(l.z) - ob->half_z;
            float lnx, lnz;
            if (qx > 0.0f || qz > 0.0f) {
                float ex = fmaxf(qx, 0.0f), ez = fmaxf(qz, 0.0f);
                d = sqrtf(ex * ex + ez * ez);
                lnx = copysignf(ex, l.x) / d;
                lnz = copysignf(ez, l.z) / d;
            } else if (qx > qz) {
                d = qx;
                lnx = copysignf(1.0f, l.x);
                lnz = 0.0f;
            } else {
                d = qz;
                lnx = 0.0f;
                lnz = copysignf(1.0f, l.z);
            }
            mm_vec3 n = rot_y(ob->yaw, mm_vec3_make(lnx, 0.0f, lnz));
            nx = n.x;
            nz = n.z;
        } else {
            float r = sqrtf(vx * vx + vz * vz);
            d = r - ob->radius;
            if (r > 1e-6f) {
                nx = vx / r;
                nz = vz / r;
            } else {
                nx = 0.0f;
                nz = 1.0f;
            }
        }
        if (d < c->clearance) {
            p->x += nx * (c->clearance - d);
            p->z += nz * (c->clearance - d);
        }
    }
}

/* ---- create, reset, state --------------------------------------------------------------------- */

static void refresh_state(mm_pfnn_controller *c)
{
    mm_pfnn_state *s = &c->state;
    const float inv = 1.0f / CM, vel = (float)MM_PFNN_FPS / CM;
    s->frame = c->frame;
    s->phase = c->phase;
    s->root_position = mm_vec3_make(c->pos[HALF].x * inv, c->root_h[HALF] * inv, c->pos[HALF].z * inv);
    s->root_yaw = yaw_of_direction(c->dir_x[HALF], c->dir_z[HALF]);
    for (int g = 0; g < MM_PFNN_GAIT_COUNT; ++g) s->gait[g] = c->gait[HALF][g];
    for (int k = 0; k < 4; ++k) s->contacts[k] = c->y[MM_PFNN_Y_CONTACTS + k];
    s->target_velocity = mm_vec3_make(c->target_vx * vel, 0.0f, c->target_vz * vel);
    s->target_direction = mm_vec3_make(c->target_dx, 0.0f, c->target_dz);
    for (int j = 0; j < J; ++j) {
        s->joint_positions[j] = mm_vec3_scale(c->joint_pos[j], inv);
        s->joint_predicted[j] = mm_vec3_scale(c->joint_pred[j], inv);
        s->joint_velocities[j] = mm_vec3_scale(c->joint_vel[j], vel);
        s->joint_rotations[j] = c->joint_rot[j];
    }
    for (int k = 0; k < MM_PFNN_TRAJ_SAMPLES; ++k) {
        s->trajectory_positions[k] = mm_vec3_scale(c->pos[10 * k], inv);
        s->trajectory_directions[k] = mm_vec3_make(c->dir_x[10 * k], 0.0f, c->dir_z[10 * k]);
    }
    memcpy(s->input, c->x, sizeof c->x);
    memcpy(s->output, c->y, sizeof c->y);
}

mm_result mm_pfnn_controller_create(const mm_pfnn_controller_desc *desc, mm_pfnn_controller **out,
                                    mm_error *err)
{
    if (out) *out = NULL;
    if (!desc || !out || !desc->network)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no desc, network or output given");
    mm_pfnn_mode mode = desc->mode ? desc->mode : MM_PFNN_MODE_CUBIC;
    if (!mm_pfnn_network_has_mode(desc->network, mode))
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "the network was not loaded with the %s mode",
                            mm_pfnn_mode_name(mode) ? mm_pfnn_mode_name(mode) : "given");
    if (desc->obstacle_count < 0 || desc->obstacle_count > MAX_OBSTACLES ||
        (desc->obstacle_count && !desc->obstacles))
        return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0, "obstacle_count must be 0..%d", MAX_OBSTACLES);
    if (desc->symmetry < MM_PFNN_SYMMETRY_DEFAULT || desc->symmetry > MM_PFNN_SYMMETRY_NONE)
        return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0, "symmetry must be a mm_pfnn_symmetry value");
    const float blends[] = {
        desc->target_blend, desc->strafe_blend, desc->gait_blend, desc->trajectory_correction,
        desc->joint_smooth, desc->clearance,    desc->pos_bias,   desc->dir_bias};
    for (size_t i = 0; i < sizeof blends / sizeof blends[0]; ++i)
        if (!isfinite(blends[i]) || blends[i] < 0.0f || (i < 5 && blends[i] > 1.0f))
            return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0, "blends must be in [0, 1], distances >= 0");
    mm_pfnn_controller *c = (mm_pfnn_controller *)mm_alloc_array(desc->allocator, 1, sizeof *c);
    if (!c) return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    if (desc->allocator) {
        c->allocator = *desc->allocator;
        c->has_allocator = true;
    }
    c->net = desc->network;
    c->mode = mode;
    c->height = desc->height;
    c->height_user = desc->height_user;
    c->obstacle_count = desc->obstacle_count;
    for (int o = 0; o < desc->obstacle_count; ++o) {
        mm_pfnn_obstacle ob = desc->obstacles[o];
        ob.centre = mm_vec3_scale(ob.centre, CM);
        ob.radius *= CM;
        ob.half_x *= CM;
        ob.half_z *= CM;
        c->obstacles[o] = ob;
    }
    c->clearance = (desc->clearance > 0.0f ? desc->clearance : 0.3f) * CM;
    c->target_blend = desc->target_blend > 0.0f ? desc->target_blend : 0.1f;
    c->strafe_blend = desc->strafe_blend > 0.0f ? desc->strafe_blend : 0.1f;
    c->gait_blend = desc->gait_blend > 0.0f ? desc->gait_blend : 0.1f;
    c->correction = desc->trajectory_correction > 0.0f ? desc->trajectory_correction : 0.5f;
    c->joint_smooth = desc->joint_smooth > 0.0f ? desc->joint_smooth : 0.5f;
    c->pos_bias = desc->pos_bias > 0.0f ? desc->pos_bias : 2.0f;
    c->dir_bias = desc->dir_bias > 0.0f ? desc->dir_bias : 5.0f;
    c->mirror = desc->symmetry != MM_PFNN_SYMMETRY_NONE;
    c->ymean = mm__pfnn_network_ymean(c->net);
    mm_pfnn_controller_reset(c, desc->start_position, desc->start_yaw);
    *out = c;
    return MM_OK;
}

void mm_pfnn_controller_destroy(mm_pfnn_controller *ctrl)
{
    if (!ctrl) return;
    mm_allocator a = ctrl->allocator;
    mm_free(ctrl->has_allocator ? &a : NULL, ctrl);
}

/* World joint positions, velocities and rotations from a network output and the root. */
static void pose_from_output(const float *y, mm_vec3 root, float yaw, mm_vec3 *pos, mm_vec3 *vel,
                             mm_quat *rot)
{
    mm_quat rq = yaw_quat(yaw);
    for (int j = 0; j < J; ++j) {
        const float *p = y + MM_PFNN_Y_JOINT_POS + 3 * j, *v = y + MM_PFNN_Y_JOINT_VEL + 3 * j;
        const float *r = y + MM_PFNN_Y_JOINT_ROT + 3 * j;
        pos[j] = mm_vec3_add(rot_y(yaw, mm_vec3_make(p[0], p[1], p[2])), root);
        vel[j] = rot_y(yaw, mm_vec3_make(v[0], v[1], v[2]));
        rot[j] = mm_quat_normalize(mm_quat_mul(rq, exp_half(r[0], r[1], r[2])));
    }
}

void mm_pfnn_controller_reset(mm_pfnn_controller *c, mm_vec3 position, float yaw)
{
    if (!c) return;
    if (!isfinite(position.x) || !isfinite(position.z)) position = mm_vec3_make(0.0f, 0.0f, 0.0f);
    if (!isfinite(yaw)) yaw = 0.0f;
    float x = position.x * CM, z = position.z * CM;
    mm_vec3 root = mm_vec3_make(x, height_cm(c, x, z), z);
    float dx = sinf(yaw), dz = cosf(yaw);
    for (int i = 0; i < TL; ++i) {
        c->pos[i] = root;
        c->dir_x[i] = dx;
        c->dir_z[i] = dz;
        c->root_h[i] = root.y;
        for (int g = 0; g < MM_PFNN_GAIT_COUNT; ++g) c->gait[i][g] = 0.0f;
    }
    c->target_vx = c->target_vz = 0.0f;
    c->target_dx = dx;
    c->target_dz = dz;
    c->facing_x = dx;
    c->facing_z = dz;
    c->strafe = 0.0f;
    pose_from_output(c->ymean, root, yaw, c->joint_pos, c->joint_vel, c->joint_rot);
    memcpy(c->joint_pred, c->joint_pos, sizeof c->joint_pred);
    c->phase = 0.0f;
    c->time_acc = 0.0;
    c->frame = 0;
    memcpy(c->y, c->ymean, sizeof c->y);
    mm_pfnn_controller_assemble_input(c, c->x);
    refresh_state(c);
}

const mm_pfnn_state *mm_pfnn_controller_state(const mm_pfnn_controller *ctrl) { return &ctrl->state; }

/* ---- the input -------------------------------------------------------------------------------- */

void mm_pfnn_controller_assemble_input(const mm_pfnn_controller *c, float *x)
{
    mm_vec3 root = mm_vec3_make(c->pos[HALF].x, c->root_h[HALF], c->pos[HALF].z);
    float yaw = yaw_of_direction(c->dir_x[HALF], c->dir_z[HALF]);
    for (int s = 0; s < MM_PFNN_TRAJ_SAMPLES; ++s) {
        int i = 10 * s;
        mm_vec3 p = rot_y(-yaw, mm_vec3_sub(c->pos[i], root));
        mm_vec3 d = rot_y(-yaw, mm_vec3_make(c->dir_x[i], 0.0f, c->dir_z[i]));
        x[MM_PFNN_X_TRAJ_POS_X + s] = p.x;
        x[MM_PFNN_X_TRAJ_POS_Z + s] = p.z;
        x[MM_PFNN_X_TRAJ_DIR_X + s] = d.x;
        x[MM_PFNN_X_TRAJ_DIR_Z + s] = d.z;
        for (int g = 0; g < MM_PFNN_GAIT_COUNT; ++g)
            x[MM_PFNN_X_GAIT + g * MM_PFNN_TRAJ_SAMPLES + s] = g < 5 ? c->gait[i][g] : 0.0f;
        float side_yaw = yaw_of_direction(c->dir_x[i], c->dir_z[i]);
        mm_vec3 r = mm_vec3_add(c->pos[i], rot_y(side_yaw, mm_vec3_make(SIDE_WIDTH, 0.0f, 0.0f)));
        mm_vec3 l = mm_vec3_add(c->pos[i], rot_y(side_yaw, mm_vec3_make(-SIDE_WIDTH, 0.0f, 0.0f)));
        x[MM_PFNN_X_HEIGHT_RIGHT + s] = height_cm(c, r.x, r.z) - root.y;
        x[MM_PFNN_X_HEIGHT_MID + s] = c->pos[i].y - root.y;
        x[MM_PFNN_X_HEIGHT_LEFT + s] = height_cm(c, l.x, l.z) - root.y;
    }
    mm_vec3 prev = mm_vec3_make(c->pos[HALF - 1].x, c->root_h[HALF - 1], c->pos[HALF - 1].z);
    float prev_yaw = yaw_of_direction(c->dir_x[HALF - 1], c->dir_z[HALF - 1]);
    for (int j = 0; j < J; ++j) {
        mm_vec3 p = rot_y(-prev_yaw, mm_vec3_sub(c->joint_pos[j], prev));
        mm_vec3 v = rot_y(-prev_yaw, c->joint_vel[j]);
        x[MM_PFNN_X_JOINT_POS + 3 * j + 0] = p.x;
        x[MM_PFNN_X_JOINT_POS + 3 * j + 1] = p.y;
        x[MM_PFNN_X_JOINT_POS + 3 * j + 2] = p.z;
        x[MM_PFNN_X_JOINT_VEL + 3 * j + 0] = v.x;
        x[MM_PFNN_X_JOINT_VEL + 3 * j + 1] = v.y;
        x[MM_PFNN_X_JOINT_VEL + 3 * j + 2] = v.z;
    }
}

/* ---- one frame -------------------------------------------------------------------------------- */

static void update_targets(mm_pfnn_controller *c, const mm_pfnn_input *in)
{
    const float to_cm_per_frame = CM / (float)MM_PFNN_FPS;
    float vx = in && isfinite(in->velocity.x) ? in->velocity.x * to_cm_per_frame : 0.0f;
    float vz = in && isfinite(in->velocity.z) ? in->velocity.z * to_cm_per_frame : 0.0f;
    c->target_vx = lerpf(c->target_vx, vx, c->target_blend);
    c->target_vz = lerpf(c->target_vz, vz, c->target_blend);
    float fx = in && isfinite(in->facing.x) ? in->facing.x : 0.0f;
    float fz = in && isfinite(in->facing.z) ? in->facing.z : 0.0f;
    float fl = sqrtf(fx * fx + fz * fz);
    bool strafing = fl > 1e-6f;
    if (strafing) {
        c->facing_x = fx / fl;
        c->facing_z = fz / fl;
    }
    c->strafe = lerpf(c->strafe, strafing ? 1.0f : 0.0f, c->strafe_blend);
    float speed = sqrtf(c->target_vx * c->target_vx + c->target_vz * c->target_vz);
    float mx = c->target_dx, mz = c->target_dz;
    if (speed > 1e-5f) {
        mx = c->target_vx / speed;
        mz = c->target_vz / speed;
    }
    float nx, nz;
    mix_dir(mx, mz, c->facing_x, c->facing_z, c->strafe, &nx, &nz);
    mix_dir(c->target_dx, c->target_dz, nx, nz, c->target_blend, &c->target_dx, &c->target_dz);
}

static void update_gait(mm_pfnn_controller *c, const mm_pfnn_input *in)
{
    float target[MM_PFNN_GAIT_COUNT] = {0};
    float speed = sqrtf(c->target_vx * c->target_vx + c->target_vz * c->target_vz);
    mm_pfnn_gait g = in ? in->gait : MM_PFNN_GAIT_WALK;
    if (speed < 0.1f) { /* cm per frame: standing, crouched if asked */
        target[GAIT_STAND] = 1.0f - clampf(speed / 0.1f, 0.0f, 1.0f);
        if (g == MM_PFNN_GAIT_CROUCH) target[3] = 1.0f;
    } else {
        switch (g) {
        case MM_PFNN_GAIT_JOG:
            target[2] = 1.0f;
            break;
        case MM_PFNN_GAIT_CROUCH:
            target[3] = 1.0f;
            break;
        case MM_PFNN_GAIT_JUMP:
            target[4] = 1.0f;
            break;
        default:
            target[1] = 1.0f;
            break;
        }
    }
    for (int k = 0; k < MM_PFNN_GAIT_COUNT; ++k)
        c->gait[HALF][k] = lerpf(c->gait[HALF][k], target[k], c->gait_blend);
}

static void predict_trajectory(mm_pfnn_controller *c)
{
    mm_vec3 blend[TL];
    blend[HALF] = c->pos[HALF];
    float bias_pos = lerpf(c->pos_bias, 1.0f, c->strafe), bias_dir = lerpf(c->dir_bias, 0.5f, c->strafe);
    for (int i = HALF + 1; i < TL; ++i) {
        float f = (float)(i - HALF) / (float)HALF;
        float scale_pos = 1.0f - powf(1.0f - f, bias_pos);
        float scale_dir = 1.0f - powf(1.0f - f, bias_dir);
        float mx = lerpf(c->pos[i].x - c->pos[i - 1].x, c->target_vx, scale_pos);
        float mz = lerpf(c->pos[i].z - c->pos[i - 1].z, c->target_vz, scale_pos);
        blend[i] = mm_vec3_make(blend[i - 1].x + mx, c->pos[i].y, blend[i - 1].z + mz);
        collide(c, &blend[i]);
        mix_dir(c->dir_x[i], c->dir_z[i], c->target_dx, c->target_dz, scale_dir, &c->dir_x[i], &c->dir_z[i]);
        for (int g = 0; g < MM_PFNN_GAIT_COUNT; ++g) c->gait[i][g] = c->gait[HALF][g];
    }
    for (int i = HALF + 1; i < TL; ++i) c->pos[i] = blend[i];
}

static void sample_heights(mm_pfnn_controller *c)
{
    for (int i = HALF; i < TL; ++i) c->pos[i].y = height_cm(c, c->pos[i].x, c->pos[i].z);
    float sum = 0.0f;
    for (int s = 0; s < MM_PFNN_TRAJ_SAMPLES; ++s) sum += c->pos[10 * s].y;
    c->root_h[HALF] = sum / (float)MM_PFNN_TRAJ_SAMPLES;
}

static void update_trajectory(mm_pfnn_controller *c, const float *y, float stand_scale)
{
    /* past: one frame older */
    for (int i = 0; i < HALF; ++i) {
        c->pos[i] = c->pos[i + 1];
        c->dir_x[i] = c->dir_x[i + 1];
        c->dir_z[i] = c->dir_z[i + 1];
        c->root_h[i] = c->root_h[i + 1];
        memcpy(c->gait[i], c->gait[i + 1], sizeof c->gait[i]);
    }
    /* current: the predicted root motion */
    float yaw = yaw_of_direction(c->dir_x[HALF], c->dir_z[HALF]);
    mm_vec3 move = rot_y(yaw, mm_vec3_make(y[MM_PFNN_Y_ROOT_X], 0.0f, y[MM_PFNN_Y_ROOT_Z]));
    move = mm_vec3_scale(move, stand_scale);
    c->pos[HALF] = mm_vec3_add(c->pos[HALF], move);
    mm_vec3 d =
        rot_y(-stand_scale * y[MM_PFNN_Y_ROOT_TURN], mm_vec3_make(c->dir_x[HALF], 0.0f, c->dir_z[HALF]));
    d = mm_vec3_normalize(d);
    c->dir_x[HALF] = d.x;
    c->dir_z[HALF] = d.z;
    collide(c, &c->pos[HALF]);
    /* future: carried along, then toward the network's trajectory */
    for (int i = HALF + 1; i < TL; ++i) c->pos[i] = mm_vec3_add(c->pos[i], move);
    float new_yaw = yaw_of_direction(d.x, d.z);
    for (int i = HALF + 1; i < TL; ++i) {
        float u = (float)(i - HALF) / 10.0f;
        int k = (int)u;
        if (k > MM_PFNN_FUTURE_SAMPLES - 2) k = MM_PFNN_FUTURE_SAMPLES - 2; /* past +50: extrapolate */
        float m = u - (float)k;
        float px = lerpf(y[MM_PFNN_Y_TRAJ_POS_X + k], y[MM_PFNN_Y_TRAJ_POS_X + k + 1], m);
        float pz = lerpf(y[MM_PFNN_Y_TRAJ_POS_Z + k], y[MM_PFNN_Y_TRAJ_POS_Z + k + 1], m);
        float dx = lerpf(y[MM_PFNN_Y_TRAJ_DIR_X + k], y[MM_PFNN_Y_TRAJ_DIR_X + k + 1], m);
        float dz = lerpf(y[MM_PFNN_Y_TRAJ_DIR_Z + k], y[MM_PFNN_Y_TRAJ_DIR_Z + k + 1], m);
        mm_vec3 wp = mm_vec3_add(rot_y(new_yaw, mm_vec3_make(px, 0.0f, pz)), c->pos[HALF]);
        mm_vec3 wd = rot_y(new_yaw, mm_vec3_make(dx, 0.0f, dz));
        c->pos[i].x = lerpf(c->pos[i].x, wp.x, c->correction);
        c->pos[i].z = lerpf(c->pos[i].z, wp.z, c->correction);
        if (wd.x * wd.x + wd.z * wd.z > 1e-12f)
            mix_dir(c->dir_x[i], c->dir_z[i], wd.x, wd.z, c->correction, &c->dir_x[i], &c->dir_z[i]);
        collide(c, &c->pos[i]);
    }
}

static void run_frame(mm_pfnn_controller *c, const mm_pfnn_input *in)
{
    update_targets(c, in);
    update_gait(c, in);
    predict_trajectory(c);
    sample_heights(c);
    mm_pfnn_controller_assemble_input(c, c->x);
    mm_vec3 root = mm_vec3_make(c->pos[HALF].x, c->root_h[HALF], c->pos[HALF].z);
    float yaw = yaw_of_direction(c->dir_x[HALF], c->dir_z[HALF]);
    evaluate(c);
    float stand_scale = powf(clampf(1.0f - c->gait[HALF][GAIT_STAND], 0.0f, 1.0f), 0.25f);
    update_trajectory(c, c->y, stand_scale);

    mm_vec3 pos[J], vel[J];
    pose_from_output(c->y, root, yaw, pos, vel, c->joint_rot);
    for (int j = 0; j < J; ++j) {
        c->joint_pos[j] = mm_vec3_lerp(mm_vec3_add(c->joint_pos[j], vel[j]), pos[j], c->joint_smooth);
        c->joint_vel[j] = vel[j];
        c->joint_pred[j] = pos[j];
    }
    double phase = c->phase + (stand_scale * 0.9 + 0.1) * TWO_PI * (double)c->y[MM_PFNN_Y_PHASE];
    phase = fmod(phase, TWO_PI);
    if (phase < 0.0) phase += TWO_PI;
    c->phase = phase < TWO_PI ? (float)phase : 0.0f;
    if (c->phase >= (float)TWO_PI) c->phase = 0.0f;
    c->frame++;
}

int mm_pfnn_controller_step(mm_pfnn_controller *c, const mm_pfnn_input *in, float dt)
{
    if (!c) return 0;
    int n = 1;
    if (dt > 0.0f && isfinite(dt)) {
        c->time_acc += dt;
        double frames = floor(c->time_acc * MM_PFNN_FPS + 1e-6);
        n = frames > MAX_FRAMES ? MAX_FRAMES : (int)frames;
        c->time_acc -= frames / MM_PFNN_FPS;
        if (c->time_acc < 0.0) c->time_acc = 0.0;
    }
    for (int k = 0; k < n; ++k) run_frame(c, in);
    if (n) refresh_state(c);
    return n;
}

void mm_pfnn_controller_local_pose(const mm_pfnn_controller *c, const mm_skeleton *skeleton,
                                   mm_quat *rotations, mm_vec3 *positions)
{
    for (int j = 0; j < J; ++j) {
        int p = skeleton && j < skeleton->joint_count ? skeleton->joints[j].parent : j - 1;
        if (p < 0) {
            rotations[j] = c->joint_rot[j];
            positions[j] = mm_vec3_scale(c->joint_pos[j], 1.0f / CM);
        } else {
            rotations[j] = mm_quat_normalize(mm_quat_mul(mm_quat_conj(c->joint_rot[p]), c->joint_rot[j]));
            positions[j] = skeleton ? skeleton->joints[j].offset : mm_vec3_make(0.0f, 0.0f, 0.0f);
        }
    }
}
