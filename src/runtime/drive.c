/* Driving a character from the game's movement: inputs from velocities and paths, root motion
 * deltas (mm/drive.h). */
#include <mm/drive.h>

#include <math.h>
#include <string.h>

/* m/s: slower than this a velocity gives no direction to face */
#define FACE_MIN_SPEED 1e-3f
/* below this length a direction is none */
#define DIRECTION_MIN 1e-6f

mm_result mm_path_init(mm_path *p, int point_count, const mm_allocator *allocator)
{
    if (!p) return MM_ERR_INVALID_ARGUMENT;
    memset(p, 0, sizeof *p);
    if (point_count < 0) return MM_ERR_INVALID_ARGUMENT;
    if (allocator) p->allocator = *allocator;
    if (point_count > 0) {
        p->points = (mm_path_point *)mm_alloc_array(&p->allocator, (size_t)point_count, sizeof *p->points);
        if (!p->points) return MM_ERR_OUT_OF_MEMORY;
    }
    p->point_count = point_count;
    return MM_OK;
}

void mm_path_free(mm_path *p)
{
    if (!p) return;
    mm_allocator a = p->allocator;
    mm_free(&a, p->points);
    memset(p, 0, sizeof *p);
}

mm_result mm_path_validate(const mm_path *p, mm_error *err)
{
    if (!p || p->point_count < 1 || !p->points)
        return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0, "a path needs at least one point");
    for (int i = 0; i < p->point_count; ++i) {
        const mm_path_point *q = &p->points[i];
        if (!isfinite(q->t) || !isfinite(q->position[0]) || !isfinite(q->position[1]) ||
            !isfinite(q->facing[0]) || !isfinite(q->facing[1]))
            return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0, "points[%d]: not a finite number", i);
        if (i > 0 && !(q->t > p->points[i - 1].t))
            return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0, "points[%d].t: times must increase", i);
    }
    return MM_OK;
}

static mm_vec3 ground(const float v[2]) { return mm_vec3_make(v[0], 0.0f, v[1]); }

static mm_vec3 unit_or_zero(mm_vec3 v)
{
    v.y = 0.0f;
    float length = mm_vec3_length(v);
    return length > DIRECTION_MIN ? mm_vec3_scale(v, 1.0f / length) : mm_vec3_make(0, 0, 0);
}

/* A point's facing: its own, or the direction of travel of its segment (the one it starts, or
 * for the last point the one it ends). */
static mm_vec3 point_facing(const mm_path *p, int i)
{
    mm_vec3 f = unit_or_zero(ground(p->points[i].facing));
    if (mm_vec3_length_sq(f) > 0.0f || p->point_count < 2) return f;
    int a = i + 1 < p->point_count ? i : i - 1;
    return unit_or_zero(mm_vec3_sub(ground(p->points[a + 1].position), ground(p->points[a].position)));
}

void mm_path_sample(const mm_path *p, float t, mm_vec3 *position, mm_vec3 *velocity, mm_vec3 *facing)
{
    mm_vec3 pos = mm_vec3_make(0, 0, 0), vel = pos, face = pos;
    if (p && p->point_count > 0 && p->points) {
        const mm_path_point *pt = p->points;
        int n = p->point_count;
        if (!(t > pt[0].t)) { /* before the start (or NaN) */
            pos = ground(pt[0].position);
            face = point_facing(p, 0);
        } else if (!(t < pt[n - 1].t)) {
            pos = ground(pt[n - 1].position);
            face = point_facing(p, n - 1);
        } else {
            int i = 0;
            while (i + 1 < n && pt[i + 1].t <= t) ++i;
            float span = pt[i + 1].t - pt[i].t, s = (t - pt[i].t) / span;
            mm_vec3 a = ground(pt[i].position), b = ground(pt[i + 1].position);
            pos = mm_vec3_lerp(a, b, s);
            vel = mm_vec3_scale(mm_vec3_sub(b, a), 1.0f / span);
            /* within a segment, a point without a facing faces along it */
            mm_vec3 along = unit_or_zero(vel);
            mm_vec3 fa = unit_or_zero(ground(pt[i].facing)), fb = unit_or_zero(ground(pt[i + 1].facing));
            if (mm_vec3_length_sq(fa) == 0.0f)
                fa = mm_vec3_length_sq(along) > 0.0f ? along : point_facing(p, i);
            if (mm_vec3_length_sq(fb) == 0.0f)
                fb = mm_vec3_length_sq(along) > 0.0f ? along : point_facing(p, i + 1);
            face = unit_or_zero(mm_vec3_lerp(fa, fb, s));
            if (mm_vec3_length_sq(face) == 0.0f) face = s < 0.5f ? fa : fb;
        }
    }
    if (position) *position = pos;
    if (velocity) *velocity = vel;
    if (facing) *facing = face;
}

void mm_drive_input_velocity(const mm_trajectory *t, mm_vec3 velocity, mm_vec3 facing, mm_input *out)
{
    memset(out, 0, sizeof *out);
    if (!isfinite(velocity.x) || !isfinite(velocity.z)) velocity = mm_vec3_make(0, 0, 0);
    velocity.y = 0.0f;
    mm_vec3 face = isfinite(facing.x) && isfinite(facing.z) ? unit_or_zero(facing) : mm_vec3_make(0, 0, 0);
    if (mm_vec3_length_sq(face) == 0.0f && mm_vec3_length(velocity) > FACE_MIN_SPEED)
        face = unit_or_zero(velocity);
    out->strafe = true; /* the facing is the game's, not the stick's */
    mm_quat f = t ? t->target_facing : mm_quat_identity();
    if (mm_vec3_length_sq(face) > 0.0f) {
        out->has_facing = true;
        out->facing[0] = face.x, out->facing[1] = face.z;
        /* as the simulation turns a facing into a rotation (mm_trajectory_desired) */
        f = mm_quat_from_axis_angle(mm_vec3_make(0, 1, 0), atan2f(face.x, face.z));
    }
    /* the slowest gait whose speeds (an ellipse in the facing's frame) reach the velocity */
    mm_vec3 local = mm_quat_inv_rotate(f, velocity);
    float x = 0.0f, z = 0.0f;
    out->gait = MM_GAIT_WALK;
    for (int g = MM_GAIT_WALK; g <= MM_GAIT_RUN; ++g) {
        const mm_gait_params *p = t ? &t->desc.gaits[g] : NULL;
        float side = p ? p->side_speed : 1.0f;
        float along = p ? (local.z >= 0.0f ? p->forward_speed : p->backward_speed) : 1.0f;
        x = side > 0.0f ? local.x / side : 0.0f;
        z = along > 0.0f ? local.z / along : 0.0f;
        out->gait = (mm_gait)g;
        if (x * x + z * z <= 1.0f) break;
    }
    float m = sqrtf(x * x + z * z);
    if (m > 1.0f) x /= m, z /= m; /* beyond the fastest gait: its top speed that way */
    mm_vec3 stick = mm_quat_rotate(f, mm_vec3_make(x, 0.0f, z));
    out->stick[0] = stick.x, out->stick[1] = stick.z;
}

void mm_drive_input_path(const mm_trajectory *t, const mm_path *p, float time, float lookahead, mm_input *out)
{
    float ahead = lookahead > 0.0f && isfinite(lookahead) ? lookahead : MM_DRIVE_LOOKAHEAD;
    mm_vec3 target, facing;
    mm_path_sample(p, time + ahead, &target, NULL, &facing);
    mm_vec3 from = t ? t->position : mm_vec3_make(0, 0, 0);
    mm_vec3 velocity = mm_vec3_scale(mm_vec3_sub(target, from), 1.0f / ahead);
    mm_drive_input_velocity(t, velocity, facing, out);
}

void mm_path_future(const mm_path *p, float time, const float *times, int count, mm_quat fallback,
                    mm_vec3 *positions, mm_quat *facings)
{
    for (int k = 0; k < count; ++k) {
        mm_vec3 facing;
        mm_path_sample(p, time + times[k], &positions[k], NULL, &facing);
        facings[k] = mm_vec3_length_sq(facing) > 0.0f
                         ? mm_quat_from_axis_angle(mm_vec3_make(0, 1, 0), atan2f(facing.x, facing.z))
                         : fallback;
    }
}

/* The heading of a rotation: the angle of its forward (+Z) on the ground, about +Y. */
static float heading(mm_quat q)
{
    mm_vec3 forward = mm_quat_rotate(q, mm_vec3_make(0, 0, 1));
    return atan2f(forward.x, forward.z);
}

void mm_root_delta_between(mm_xform before, mm_xform after, mm_root_delta *out)
{
    out->world = mm_vec3_sub(after.translation, before.translation);
    out->local = mm_quat_inv_rotate(before.rotation, out->world);
    float yaw = heading(after.rotation) - heading(before.rotation);
    const float pi = 3.14159265358979f;
    while (yaw > pi) yaw -= 2.0f * pi;
    while (yaw <= -pi) yaw += 2.0f * pi;
    out->yaw = yaw;
}
