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
 *   quat:  mm_quat_identity make mul conj inverse dot normalize length rotate inv_rotate
 *          from_axis_angle abs nlerp slerp angle_between from_euler to_euler from_mat3 to_mat3
 *          log exp swing_twist between
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
