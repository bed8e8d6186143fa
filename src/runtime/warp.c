/* Stride warping and orientation warping. See mm/warp.h and docs/distance.md. Nothing here
 * allocates. */
#include <mm/warp.h>

#include <math.h>
#include <string.h>

#include <mm/spring.h>

#include "runtime/leg_ik_private.h"
#include "runtime/warp_private.h"

/* The first half of stride warping: each leg's foot target (into targets, the unit direction on the
 * ground into *dir) and how far the pelvis comes down for every leg to reach (*drop). Returns
 * MM_OK with *drop = 0 and the feet as targets where there is no direction. */
static mm_result stride_targets(const mm_leg_pose *legs, int leg_count, mm_vec3 direction, float scale,
                                double ext, dvec *targets, dvec *dir, double *drop)
{
    *drop = 0.0;
    for (int i = 0; i < leg_count; ++i) targets[i] = dv(legs[i].foot);
    *dir = (dvec){direction.x, 0.0, direction.z};
    double dl = dlen(*dir);
    if (dl < 1e-6) return MM_OK; /* no direction: nothing to scale */
    *dir = dscale(*dir, 1.0 / dl);
    for (int i = 0; i < leg_count; ++i) {
        dvec hip = dv(legs[i].hip), knee = dv(legs[i].knee), foot = dv(legs[i].foot);
        double along = ddot(dsub(foot, hip), *dir);
        targets[i] = dadd(foot, dscale(*dir, (scale - 1.0) * along));
        /* how far the hip must come down for |target - hip| <= reach */
        double l1 = dlen(dsub(knee, hip)), l2 = dlen(dsub(foot, knee)), now = dlen(dsub(foot, hip));
        if (l1 < 1e-6 || l2 < 1e-6) return MM_ERR_INVALID_ARGUMENT;
        double r = leg_reach(l1, l2, now, ext);
        double hx = targets[i].x - hip.x, hz = targets[i].z - hip.z, side = r * r - (hx * hx + hz * hz);
        double need = side > 0.0 ? hip.y - targets[i].y - sqrt(side) : hip.y - targets[i].y;
        if (need > *drop) *drop = need;
    }
    if (!isfinite((float)*drop)) return MM_ERR_OUT_OF_RANGE;
    return MM_OK;
}

/* Leg i lowered by drop (in floats, as the legs are solved). */
static mm_leg_pose lowered_leg(const mm_leg_pose *leg, double drop)
{
    mm_leg_pose lowered = *leg;
    lowered.hip.y = (float)(lowered.hip.y - drop);
    lowered.knee.y = (float)(lowered.knee.y - drop);
    lowered.foot.y = (float)(lowered.foot.y - drop);
    return lowered;
}

static int valid_stride_call(const mm_leg_pose *legs, int leg_count, mm_vec3 direction, float scale,
                             float max_extension, const void *out)
{
    if (!legs || !out || leg_count < 1 || leg_count > MM_WARP_MAX_LEGS) return 0;
    int ok = finite3(direction) && isfinite(scale) && scale > 0.0f && !bad_extension(max_extension);
    for (int i = 0; i < leg_count; ++i) ok = ok && finite_leg(&legs[i]);
    return ok;
}

mm_result mm_warp_stride(const mm_leg_pose *legs, int leg_count, mm_vec3 direction, float scale,
                         float max_extension, mm_leg_warp *out, float *pelvis_drop)
{
    if (pelvis_drop) *pelvis_drop = 0.0f;
    if (!legs || !out || leg_count < 1 || leg_count > MM_WARP_MAX_LEGS) return MM_ERR_INVALID_ARGUMENT;
    for (int i = 0; i < leg_count; ++i) leg_identity(&legs[i], &out[i]);
    if (!valid_stride_call(legs, leg_count, direction, scale, max_extension, out))
        return MM_ERR_INVALID_ARGUMENT;
    double ext = max_extension > 0.0f ? max_extension : MM_LEG_IK_MAX_EXTENSION_DEFAULT;
    dvec targets[MM_WARP_MAX_LEGS], dir;
    double drop;
    mm_result r = stride_targets(legs, leg_count, direction, scale, ext, targets, &dir, &drop);
    if (r != MM_OK) return r;
    if (dlen(dir) < 1e-6) return MM_OK; /* no direction: the legs as they are */
    for (int i = 0; i < leg_count; ++i) {
        mm_leg_pose lowered = lowered_leg(&legs[i], drop);
        mm_leg_ik_params params = {(float)ext, 0.0f};
        r = mm_leg_ik_solve(&lowered, fv(targets[i]), fv(dir), &params, &out[i]);
        if (r != MM_OK) {
            for (int k = 0; k < leg_count; ++k) leg_identity(&legs[k], &out[k]);
            return r;
        }
    }
    if (pelvis_drop) *pelvis_drop = (float)drop;
    return MM_OK;
}

mm_result mm__warp_stride_targets(const mm_leg_pose *legs, int leg_count, mm_vec3 direction, float scale,
                                  float max_extension, mm_vec3 *targets, float *pelvis_drop)
{
    if (pelvis_drop) *pelvis_drop = 0.0f;
    if (!valid_stride_call(legs, leg_count, direction, scale, max_extension, targets))
        return MM_ERR_INVALID_ARGUMENT;
    double ext = max_extension > 0.0f ? max_extension : MM_LEG_IK_MAX_EXTENSION_DEFAULT;
    dvec t[MM_WARP_MAX_LEGS], dir;
    double drop;
    mm_result r = stride_targets(legs, leg_count, direction, scale, ext, t, &dir, &drop);
    if (r != MM_OK) return r;
    for (int i = 0; i < leg_count; ++i) targets[i] = fv(t[i]);
    if (dlen(dir) < 1e-6) return MM_OK;
    /* the legs mm_warp_stride would solve: the solve's own refusals (mm_leg_ik_solve) */
    for (int i = 0; i < leg_count; ++i) {
        mm_leg_pose lowered = lowered_leg(&legs[i], drop);
        dvec hip = dv(lowered.hip), knee = dv(lowered.knee), foot = dv(lowered.foot);
        if (!finite_leg(&lowered) || !finite3(targets[i]) || !finite3(fv(dir)) ||
            !leg_solvable(dlen(dsub(knee, hip)), dlen(dsub(foot, knee)), dlen(dsub(foot, hip))))
            return MM_ERR_INVALID_ARGUMENT;
    }
    if (pelvis_drop) *pelvis_drop = (float)drop;
    return MM_OK;
}

static mm_quat about_y(double angle)
{
    return mm_quat_make(0.0f, (float)sin(0.5 * angle), 0.0f, (float)cos(0.5 * angle));
}

static void orientation_identity(mm_warp_orientation_result *out)
{
    memset(out, 0, sizeof *out);
    out->lower_body = mm_quat_identity();
    for (int i = 0; i < MM_WARP_ORIENTATION_MAX_SPINE; ++i) out->spine[i] = mm_quat_identity();
}

mm_result mm_warp_orientation(mm_vec3 facing, mm_vec3 movement, float previous_angle, float dt,
                              const mm_warp_orientation_params *params, mm_warp_orientation_result *out)
{
    if (!out) return MM_ERR_INVALID_ARGUMENT;
    orientation_identity(out);
    mm_warp_orientation_params p;
    memset(&p, 0, sizeof p);
    if (params) p = *params;
    if (!finite3(facing) || !finite3(movement) || !isfinite(previous_angle) || !isfinite(dt) || dt < 0.0f ||
        !isfinite(p.max_angle) || p.max_angle < 0.0f || !isfinite(p.speed) || p.speed < 0.0f ||
        !isfinite(p.hysteresis) || p.hysteresis < 0.0f || !isfinite(p.halflife) || p.halflife < 0.0f ||
        !isfinite(p.velocity) || p.spine_count < 0 || p.spine_count > MM_WARP_ORIENTATION_MAX_SPINE)
        return MM_ERR_INVALID_ARGUMENT;
    double weights[MM_WARP_ORIENTATION_MAX_SPINE], total = 0.0;
    for (int i = 0; i < p.spine_count; ++i) {
        double w = p.spine_weights ? p.spine_weights[i] : 1.0;
        if (!isfinite(w) || w < 0.0) return MM_ERR_INVALID_ARGUMENT;
        weights[i] = w;
        total += w;
    }
    if (p.spine_count > 0 && !(total > 0.0)) return MM_ERR_INVALID_ARGUMENT;
    const double max_angle = p.max_angle > 0.0f ? p.max_angle : MM_WARP_ORIENTATION_MAX_DEFAULT;
    const double band = p.hysteresis > 0.0f ? p.hysteresis : 0.17;
    const double half = 0.5 * MM_PI;

    double fx = facing.x, fz = facing.z, mx = movement.x, mz = movement.z;
    double target = 0.0;
    int backward = 0;
    if (fx * fx + fz * fz > 1e-12 && mx * mx + mz * mz > 1e-8) {
        double theta = atan2(fz * mx - fx * mz, fx * mx + fz * mz); /* about +Y, facing to movement */
        double back = theta > 0.0 ? theta - MM_PI : theta + MM_PI;
        if (fabs(theta) <= half - band)
            backward = 0;
        else if (fabs(theta) >= half + band)
            backward = 1;
        else /* near 90 degrees: the side nearer the angle used before */
            backward = fabs(back - previous_angle) < fabs(theta - previous_angle);
        target = clampd(backward ? back : theta, -max_angle, max_angle);
    }
    double angle = target;
    if (p.halflife > 0.0f) {
        float x = previous_angle, v = p.velocity;
        mm_spring_update(&x, &v, (float)target, p.halflife, dt);
        angle = x;
        out->velocity = v;
    } else if (p.speed > 0.0f) {
        angle = previous_angle + (target - previous_angle) * (1.0 - exp(-(double)p.speed * dt));
    }
    if (angle < -max_angle || angle > max_angle) out->velocity = 0.0f;
    angle = clampd(angle, -max_angle, max_angle);

    out->target_angle = (float)target;
    out->angle = (float)angle;
    out->backward = backward;
    out->lower_body = about_y(angle);
    double so_far = 0.0;
    for (int i = 0; i < p.spine_count; ++i) {
        so_far += weights[i] / total;
        double left = i == p.spine_count - 1 ? 0.0 : 1.0 - so_far;
        out->spine[i] = about_y(angle * left);
    }
    return MM_OK;
}

mm_vec3 mm_warp_orientation_point(const mm_warp_orientation_result *w, mm_vec3 pivot, mm_vec3 point)
{
    if (!w || !finite3(pivot) || !finite3(point)) return finite_or_zero(point);
    mm_vec3 r = mm_vec3_add(pivot, mm_quat_rotate(w->lower_body, mm_vec3_sub(point, pivot)));
    return finite3(r) ? r : point;
}

mm_result mm_warp_orientation_pose(const mm_warp_orientation_result *w, mm_quat parent_world,
                                   mm_quat pelvis_world, const mm_quat *spine_world, int spine_count,
                                   mm_quat *pelvis_local, mm_quat *spine_local)
{
    if (!w || !pelvis_local || spine_count < 0 || spine_count > MM_WARP_ORIENTATION_MAX_SPINE ||
        (spine_count > 0 && (!spine_world || !spine_local)))
        return MM_ERR_INVALID_ARGUMENT;
    if (w->angle == 0.0f || !isfinite(w->angle)) return MM_OK; /* identity: leave the pose untouched */
    mm_quat above = mm_quat_normalize(mm_quat_mul(w->lower_body, pelvis_world));
    *pelvis_local = mm_quat_normalize(mm_quat_mul(mm_quat_conj(parent_world), above));
    for (int i = 0; i < spine_count; ++i) {
        /* each joint's new world rotation, taken relative to its parent's new one */
        mm_quat world = mm_quat_normalize(mm_quat_mul(w->spine[i], spine_world[i]));
        spine_local[i] = mm_quat_normalize(mm_quat_mul(mm_quat_conj(above), world));
        above = world;
    }
    return MM_OK;
}
