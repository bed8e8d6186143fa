/* mm/math.h - vectors, quaternions, rotation matrices and rigid transforms.
 *
 * Conventions (used everywhere in mm):
 *   - Units: metres, seconds, radians. Y is up, the frame is right-handed, a character faces +Z.
 *   - mm_quat is laid out {x, y, z, w}: vector part first, scalar last. Unit quaternions rotate
 *     vectors as v' = q v q^-1. Products compose right to left: mm_quat_mul(a, b) applies b first,
 *     then a (the same order as matrices acting on column vectors).
 *   - mm_mat3 is row-major, acting on column vectors: v'[r] = sum_c m[r][c] * v[c].
 *   - mm_xform is a rigid transform: p' = rotation * p + translation.
 *   - Euler angles are a mm_vec3 of angles about X, Y and Z. The order names the axes in the
 *     sequence they appear in a BVH CHANNELS line, which is the intrinsic order:
 *     MM_EULER_ZYX means q = Rz(z) * Ry(y) * Rx(x).
 *   - Logarithm and exponential use the scaled angle-axis (rotation vector) convention with the
 *     FULL angle: mm_quat_log(q) = axis * angle, angle in [0, pi] for the shortest rotation;
 *     mm_quat_exp(axis * angle) gives the quaternion of that rotation.
 *
 * Small operations are inline (written so the header compiles as C++ too); the rest are in
 * src/math.c.
 *
 * Functions:
 *   vec3:  mm_vec3_make add sub scale mul neg dot cross length length_sq distance normalize lerp
 *          catmull_rom
 *   quat:  mm_quat_identity make mul conj inverse dot normalize length rotate inv_rotate
 *          from_axis_angle abs nlerp slerp angle_between from_euler to_euler from_mat3 to_mat3
 *          log exp hermite catmull_rom_tangent catmull_rom swing_twist between
 *   mat3:  mm_mat3_identity mm_mat3_mul mm_mat3_mul_vec3 mm_mat3_transpose
 *   xform: mm_xform_identity mul inverse apply_point apply_vector
 */
#ifndef MM_MATH_H
#define MM_MATH_H

#include <math.h>

#ifdef __cplusplus
extern "C" {
#endif

#define MM_PI         3.14159265358979323846
#define MM_DEG_TO_RAD (MM_PI / 180.0)
/* In a desc where zero means default: the field is 0 (at once, none, off), not its default. Any
 * negative value means the same. */
#define MM_OFF        (-1.0f)
#define MM_RAD_TO_DEG (180.0 / MM_PI)

typedef struct mm_vec3 {
    float x, y, z;
} mm_vec3;

typedef struct mm_quat {
    float x, y, z, w;
} mm_quat;

typedef struct mm_mat3 {
    float m[3][3];
} mm_mat3;

typedef struct mm_xform {
    mm_quat rotation;
    mm_vec3 translation;
} mm_xform;

/* Euler orders, named by the sequence of axes as they appear in a BVH CHANNELS line.
 * 0 is reserved to mean "not set / default" in desc structs. */
typedef enum mm_euler_order {
    MM_EULER_NONE = 0,
    MM_EULER_XYZ,
    MM_EULER_XZY,
    MM_EULER_YXZ,
    MM_EULER_YZX,
    MM_EULER_ZXY,
    MM_EULER_ZYX
} mm_euler_order;

/* "XYZ" etc.; NULL for MM_EULER_NONE or an invalid value. */
const char *mm_euler_order_name(mm_euler_order order);
/* Parses "XYZ", "zyx", ... (case-insensitive); MM_EULER_NONE if not an order. */
mm_euler_order mm_euler_order_parse(const char *name);

/* ---- vec3 ------------------------------------------------------------------------------- */

static inline mm_vec3 mm_vec3_make(float x, float y, float z)
{
    mm_vec3 r;
    r.x = x;
    r.y = y;
    r.z = z;
    return r;
}
static inline mm_vec3 mm_vec3_add(mm_vec3 a, mm_vec3 b)
{
    return mm_vec3_make(a.x + b.x, a.y + b.y, a.z + b.z);
}
static inline mm_vec3 mm_vec3_sub(mm_vec3 a, mm_vec3 b)
{
    return mm_vec3_make(a.x - b.x, a.y - b.y, a.z - b.z);
}
static inline mm_vec3 mm_vec3_scale(mm_vec3 a, float s) { return mm_vec3_make(a.x * s, a.y * s, a.z * s); }
static inline mm_vec3 mm_vec3_mul(mm_vec3 a, mm_vec3 b)
{
    return mm_vec3_make(a.x * b.x, a.y * b.y, a.z * b.z);
}
static inline mm_vec3 mm_vec3_neg(mm_vec3 a) { return mm_vec3_make(-a.x, -a.y, -a.z); }
static inline float mm_vec3_dot(mm_vec3 a, mm_vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline mm_vec3 mm_vec3_cross(mm_vec3 a, mm_vec3 b)
{
    return mm_vec3_make(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline float mm_vec3_length_sq(mm_vec3 a) { return mm_vec3_dot(a, a); }
static inline float mm_vec3_length(mm_vec3 a) { return sqrtf(mm_vec3_dot(a, a)); }
static inline float mm_vec3_distance(mm_vec3 a, mm_vec3 b) { return mm_vec3_length(mm_vec3_sub(a, b)); }
/* Unit vector along a; the zero vector (length below 1e-12) is returned unchanged. */
static inline mm_vec3 mm_vec3_normalize(mm_vec3 a)
{
    float len = mm_vec3_length(a);
    return len > 1e-12f ? mm_vec3_scale(a, 1.0f / len) : a;
}
static inline mm_vec3 mm_vec3_lerp(mm_vec3 a, mm_vec3 b, float t)
{
    return mm_vec3_make(a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t, a.z + (b.z - a.z) * t);
}
/* Cubic Hermite interpolation from p1 (t = 0) to p2 (t = 1) with the Catmull-Rom tangents
 * (p2 - p0) / 2 at p1 and (p3 - p1) / 2 at p2 (per unit t), from the neighbours p0 before p1 and
 * p3 after p2: exact at t = 0 and 1, the velocity continuous from one segment to the next, and
 * points on a line at equal steps give that line at constant speed. Where a neighbour is
 * missing, pass the reflection (p0 = 2 p1 - p2, p3 = 2 p2 - p1): the tangent is then the
 * one-sided difference p2 - p1. The curve never leaves [min, max] of the four points (per axis)
 * by more than 1/8 of (max - min), 1/4 with a reflected neighbour: the tangent terms add at most
 * t (1 - t) max |m| to a point between p1 and p2, and |m| <= (max - min) / 2 (one-sided: <= max
 * - min). A unit step [0, 0, 1, 1] overshoots by 2/27. */
static inline mm_vec3 mm_vec3_catmull_rom(mm_vec3 p0, mm_vec3 p1, mm_vec3 p2, mm_vec3 p3, float t)
{
    float t2 = t * t, t3 = t2 * t;
    float h00 = 2.0f * t3 - 3.0f * t2 + 1.0f, h01 = 3.0f * t2 - 2.0f * t3;
    float h10 = 0.5f * (t3 - 2.0f * t2 + t), h11 = 0.5f * (t3 - t2);
    return mm_vec3_make(h00 * p1.x + h01 * p2.x + h10 * (p2.x - p0.x) + h11 * (p3.x - p1.x),
                        h00 * p1.y + h01 * p2.y + h10 * (p2.y - p0.y) + h11 * (p3.y - p1.y),
                        h00 * p1.z + h01 * p2.z + h10 * (p2.z - p0.z) + h11 * (p3.z - p1.z));
}

/* ---- quaternion ------------------------------------------------------------------------- */

static inline mm_quat mm_quat_make(float x, float y, float z, float w)
{
    mm_quat q;
    q.x = x;
    q.y = y;
    q.z = z;
    q.w = w;
    return q;
}
static inline mm_quat mm_quat_identity(void) { return mm_quat_make(0.0f, 0.0f, 0.0f, 1.0f); }
/* a * b: the rotation b followed by a. */
static inline mm_quat mm_quat_mul(mm_quat a, mm_quat b)
{
    return mm_quat_make(
        a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y, a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
        a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w, a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z);
}
static inline mm_quat mm_quat_conj(mm_quat q) { return mm_quat_make(-q.x, -q.y, -q.z, q.w); }
static inline float mm_quat_dot(mm_quat a, mm_quat b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z + a.w * b.w;
}
static inline float mm_quat_length(mm_quat q) { return sqrtf(mm_quat_dot(q, q)); }
/* Unit quaternion along q; a zero quaternion gives the identity. */
static inline mm_quat mm_quat_normalize(mm_quat q)
{
    float len = mm_quat_length(q);
    if (len < 1e-12f) return mm_quat_identity();
    float s = 1.0f / len;
    return mm_quat_make(q.x * s, q.y * s, q.z * s, q.w * s);
}
/* Inverse of any non-zero quaternion (the conjugate for unit ones); zero gives the identity. */
static inline mm_quat mm_quat_inverse(mm_quat q)
{
    float n = mm_quat_dot(q, q);
    if (n < 1e-24f) return mm_quat_identity();
    float s = 1.0f / n;
    return mm_quat_make(-q.x * s, -q.y * s, -q.z * s, q.w * s);
}
/* Rotates v by the unit quaternion q. */
static inline mm_vec3 mm_quat_rotate(mm_quat q, mm_vec3 v)
{
    /* v' = v + 2w (u x v) + 2 u x (u x v), u = vector part */
    mm_vec3 u = mm_vec3_make(q.x, q.y, q.z);
    mm_vec3 t = mm_vec3_scale(mm_vec3_cross(u, v), 2.0f);
    return mm_vec3_add(mm_vec3_add(v, mm_vec3_scale(t, q.w)), mm_vec3_cross(u, t));
}
/* Rotates v by the inverse of the unit quaternion q. */
static inline mm_vec3 mm_quat_inv_rotate(mm_quat q, mm_vec3 v) { return mm_quat_rotate(mm_quat_conj(q), v); }
/* The same rotation with w >= 0 (the hemisphere of the identity). */
static inline mm_quat mm_quat_abs(mm_quat q) { return q.w < 0.0f ? mm_quat_make(-q.x, -q.y, -q.z, -q.w) : q; }

/* Rotation of angle radians about axis (need not be unit; a zero axis gives the identity). */
mm_quat mm_quat_from_axis_angle(mm_vec3 axis, float angle);
/* Normalised linear interpolation along the shortest path; t in [0, 1]. */
mm_quat mm_quat_nlerp(mm_quat a, mm_quat b, float t);
/* Spherical linear interpolation along the shortest path; t in [0, 1]. */
mm_quat mm_quat_slerp(mm_quat a, mm_quat b, float t);
/* Angle in radians, in [0, pi], of the shortest rotation taking a to b. */
float mm_quat_angle_between(mm_quat a, mm_quat b);

/* Euler angles (radians about X, Y, Z) to a unit quaternion, composed in the given order.
 * MM_EULER_NONE or an invalid order gives the identity (and mm_quat_to_euler gives zeros). */
mm_quat mm_quat_from_euler(mm_vec3 angles, mm_euler_order order);
/* Unit quaternion to Euler angles for the given order. The middle axis angle is in
 * [-pi/2, pi/2], the other two in (-pi, pi]. At gimbal lock (middle angle at +-pi/2) the
 * third angle is set to 0 and the first carries the whole remaining rotation. */
mm_vec3 mm_quat_to_euler(mm_quat q, mm_euler_order order);

/* Rotation matrix (orthonormal, det +1) to unit quaternion with w >= 0. */
mm_quat mm_quat_from_mat3(mm_mat3 m);
mm_mat3 mm_quat_to_mat3(mm_quat q);

/* Scaled angle-axis, full angle: returns axis * angle with angle in [0, pi] (shortest). */
mm_vec3 mm_quat_log(mm_quat q);
/* Inverse of mm_quat_log: the rotation of |v| radians about v / |v|. */
mm_quat mm_quat_exp(mm_vec3 v);

/* C1 rotation splines. A tangent w at key q is an angular velocity in q's own frame, in radians
 * per unit t: near q the curve is q exp(w dt) (mm_quat_exp). Keys may be given as q or -q in any
 * mix: every step between neighbours is taken the short way round.
 *
 * mm_quat_hermite: the curve from a (t = 0) to b (t = 1) leaving a with tangent w0 and arriving
 * at b with tangent w1 (the cumulative cubic Bezier form on control rotations a exp(w0/3) and
 * b exp(-w1/3)). Returns a itself for t <= 0 and b itself (or -b, the sign the curve arrives
 * with) for t >= 1; unit in between. With w0 = w1 = mm_quat_log(a^-1 b) it is mm_quat_slerp(a,
 * b, t); for keys turning at a constant rate about a fixed axis, Catmull-Rom tangents give that
 * turn exactly.
 * mm_quat_catmull_rom_tangent: the tangent at q from its neighbours, the mean of the turns
 * prev -> q and q -> next (each in q's frame: the turn's axis is the same in both of its ends').
 * mm_quat_catmull_rom: mm_quat_hermite from q1 to q2 with the tangents at q1 (from q0, q2) and q2
 * (from q1, q3). Where a neighbour is missing pass the reflection (q0 = q1 q2^-1 q1, q3 = q2
 * q1^-1 q2): the tangent is then the one-sided turn q1 -> q2. */
mm_quat mm_quat_hermite(mm_quat a, mm_vec3 w0, mm_quat b, mm_vec3 w1, float t);
mm_vec3 mm_quat_catmull_rom_tangent(mm_quat prev, mm_quat q, mm_quat next);
mm_quat mm_quat_catmull_rom(mm_quat q0, mm_quat q1, mm_quat q2, mm_quat q3, float t);

/* Splits q into q = swing * twist, where twist rotates about the (unit or not) axis and swing
 * rotates about an axis perpendicular to it. Either output pointer may be NULL. When q has no
 * rotation about axis (its rotation axis is perpendicular to it) twist is the identity; for a
 * half-turn about such an axis the split is undefined and twist is the identity too. */
void mm_quat_swing_twist(mm_quat q, mm_vec3 axis, mm_quat *swing, mm_quat *twist);

/* Shortest rotation taking direction from to direction to (neither need be unit). Opposite
 * directions give a 180-degree turn about an axis perpendicular to from; a zero vector gives
 * the identity. */
mm_quat mm_quat_between(mm_vec3 from, mm_vec3 to);

/* ---- mat3 ------------------------------------------------------------------------------- */

mm_mat3 mm_mat3_identity(void);
mm_mat3 mm_mat3_mul(mm_mat3 a, mm_mat3 b);
mm_vec3 mm_mat3_mul_vec3(mm_mat3 m, mm_vec3 v);
mm_mat3 mm_mat3_transpose(mm_mat3 m);

/* ---- rigid transform -------------------------------------------------------------------- */

static inline mm_xform mm_xform_make(mm_quat rotation, mm_vec3 translation)
{
    mm_xform x;
    x.rotation = rotation;
    x.translation = translation;
    return x;
}
static inline mm_xform mm_xform_identity(void)
{
    return mm_xform_make(mm_quat_identity(), mm_vec3_make(0.0f, 0.0f, 0.0f));
}
static inline mm_vec3 mm_xform_apply_point(mm_xform a, mm_vec3 p)
{
    return mm_vec3_add(mm_quat_rotate(a.rotation, p), a.translation);
}
static inline mm_vec3 mm_xform_apply_vector(mm_xform a, mm_vec3 v) { return mm_quat_rotate(a.rotation, v); }
/* a * b: apply b, then a (parent * local = global). */
static inline mm_xform mm_xform_mul(mm_xform a, mm_xform b)
{
    return mm_xform_make(mm_quat_mul(a.rotation, b.rotation), mm_xform_apply_point(a, b.translation));
}
static inline mm_xform mm_xform_inverse(mm_xform a)
{
    mm_quat inv = mm_quat_conj(a.rotation);
    return mm_xform_make(inv, mm_vec3_neg(mm_quat_rotate(inv, a.translation)));
}

#ifdef __cplusplus
}
#endif

#endif /* MM_MATH_H */
