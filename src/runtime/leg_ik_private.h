/* leg_ik_private.h (private) - the double-precision vector helpers and leg checks that leg IK
 * (leg_ik.c) and stride warping (warp.c) share. Positions in metres (mm/leg_ik.h).
 */
#ifndef MM_RUNTIME_LEG_IK_PRIVATE_H
#define MM_RUNTIME_LEG_IK_PRIVATE_H

#include <math.h>

#include <mm/leg_ik.h>
#include "math_private.h"

static inline double clampd(double x, double lo, double hi) { return x < lo ? lo : x > hi ? hi : x; }

static inline int finite_leg(const mm_leg_pose *l)
{
    return finite3(l->hip) && finite3(l->knee) && finite3(l->foot);
}

static inline mm_vec3 finite_or_zero(mm_vec3 v)
{
    return mm_vec3_make(isfinite(v.x) ? v.x : 0.0f, isfinite(v.y) ? v.y : 0.0f, isfinite(v.z) ? v.z : 0.0f);
}

/* The unchanged leg, as the output of a call that could not warp (non-finite parts zeroed). */
static inline void leg_identity(const mm_leg_pose *leg, mm_leg_warp *out)
{
    out->pose.hip = finite_or_zero(leg->hip);
    out->pose.knee = finite_or_zero(leg->knee);
    out->pose.foot = finite_or_zero(leg->foot);
    out->target = out->pose.foot;
    out->thigh = mm_quat_identity();
    out->shin = mm_quat_identity();
}

typedef struct dvec {
    double x, y, z;
} dvec;
static inline dvec dv(mm_vec3 v)
{
    dvec r = {v.x, v.y, v.z};
    return r;
}
static inline dvec dsub(dvec a, dvec b)
{
    dvec r = {a.x - b.x, a.y - b.y, a.z - b.z};
    return r;
}
static inline dvec dadd(dvec a, dvec b)
{
    dvec r = {a.x + b.x, a.y + b.y, a.z + b.z};
    return r;
}
static inline dvec dscale(dvec a, double s)
{
    dvec r = {a.x * s, a.y * s, a.z * s};
    return r;
}

static inline dvec dcross(dvec a, dvec b)
{
    return (dvec){a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
static inline double ddot(dvec a, dvec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline double dlen(dvec a) { return sqrt(ddot(a, a)); }
static inline mm_vec3 fv(dvec a) { return mm_vec3_make((float)a.x, (float)a.y, (float)a.z); }

/* The longest the leg may reach: max_extension of its length, or as far as it reaches now. */
static inline double leg_reach(double l1, double l2, double now, double max_extension)
{
    double r = max_extension * (l1 + l2);
    if (now > r) r = now;
    return r < l1 + l2 ? r : l1 + l2;
}

static inline int bad_extension(float e)
{
    return !isfinite(e) || e < 0.0f || e > 1.0f || (e > 0.0f && e < 0.1f);
}

/* A leg of bones l1 (hip to knee), l2 (knee to foot) and hip-to-foot span now (m) can be solved:
 * mm_leg_ik_solve refuses the others, and stride warping asks the same before it leaves a solve
 * to the feet. */
static inline int leg_solvable(double l1, double l2, double now)
{
    return l1 >= 1e-6 && l2 >= 1e-6 && now >= 1e-9;
}

#endif /* MM_RUNTIME_LEG_IK_PRIVATE_H */
