/* math_private.h - small math helpers shared by the library's files, one copy
 * each: clamping, the horizontal part of a vector, yaw about +Y, angle wrapping, finiteness.
 * Internal: not part of the public headers. */
#ifndef MM_MATH_PRIVATE_H
#define MM_MATH_PRIVATE_H

#include <math.h>
#include <stdbool.h>

#include <mm/math.h>

/* v clamped to [lo, hi] (NaN stays NaN). */
static inline float clampf(float v, float lo, float hi) { return v < lo ? lo : v > hi ? hi : v; }

/* v clamped to [0, 1] (NaN stays NaN). */
static inline float clamp01(float v) { return v < 0.0f ? 0.0f : v > 1.0f ? 1.0f : v; }

/* The horizontal part of v (y set to 0). */
static inline mm_vec3 flat(mm_vec3 v) { return mm_vec3_make(v.x, 0.0f, v.z); }

/* The yaw (radians about +Y, 0 facing +Z) of the direction q turns +Z to. */
static inline float yaw_of(mm_quat q)
{
    mm_vec3 f = mm_quat_rotate(q, mm_vec3_make(0, 0, 1));
    return atan2f(f.x, f.z);
}

/* The rotation by yaw radians about +Y. */
static inline mm_quat yaw_quat(float yaw) { return mm_quat_from_axis_angle(mm_vec3_make(0, 1, 0), yaw); }

/* An angle wrapped into [-pi, pi]. */
static inline float wrap_angle(float a) { return remainderf(a, (float)(2.0 * MM_PI)); }

/* Are all three coordinates finite? */
static inline bool finite3(mm_vec3 v) { return isfinite(v.x) && isfinite(v.y) && isfinite(v.z); }

/* mm_quat_slerp without its sines, for rotations close together (neighbouring frames of a clip):
 * under 0.3 rad apart as unit quaternions the angle and the weights come from their Taylor series,
 * exact to double rounding (the result differs from mm_quat_slerp's by at most a float rounding);
 * mm_quat_slerp itself beyond. */
mm_quat mm__quat_slerp_series(mm_quat a, mm_quat b, float t);
/* Kernels four doubles wide (AVX, MM_WIDE on a function), where the compiler can build them for a
 * machine without AVX, run where the machine has it (mm__wide_kernels): the same operations as the
 * two-wide SSE2 ones (AVX's arithmetic is IEEE's, and without FMA nothing is fused), so the same
 * bits on any machine. mm__math_wide_kernels(false) keeps them off (on at start): the tests check
 * both paths. */
#if defined(__SSE2__) && defined(__x86_64__) && defined(__GNUC__)
#define MM_WIDE_KERNELS 1
#define MM_WIDE         __attribute__((target("avx")))
#include <immintrin.h>
#endif
bool mm__wide_kernels(void);
void mm__math_wide_kernels(bool on);
/* out[i] = mm__quat_slerp_series(a[i], b[i], t) for i in [0, count): the same bits, four or two
 * at a time where the machine has the lanes for it. */
void mm__quat_slerp_series_n(const mm_quat *a, const mm_quat *b, float t, int count, mm_quat *out);

/* mm_quat_exp without its sine and cosine, for small rotations (offsets decaying to none): under
 * 0.6 rad from the Taylor series, exact to double rounding; mm_quat_exp itself beyond. */
mm_quat mm__quat_exp_series(mm_vec3 v);
/* out[i] = mm__quat_exp_series(v[i]) for i in [0, count): the same bits, two at a time where the
 * machine has the lanes for it. */
void mm__quat_exp_series_n(const mm_vec3 *v, int count, mm_quat *out);

/* mm_quat_log without its arc tangent, for small rotations (the turn between neighbouring
 * frames): under 0.3 rad from the Taylor series of the arc sine, exact to double rounding (the
 * result differs from mm_quat_log's by at most a float rounding); mm_quat_log itself beyond. */
mm_vec3 mm__quat_log_series(mm_quat quat);
/* out[i] = mm__quat_log_series(q[i]) for i in [0, count): the same bits, two at a time where the
 * machine has the lanes for it. */
void mm__quat_log_series_n(const mm_quat *q, int count, mm_vec3 *out);

/* out[i] = mm_quat_abs(mm_quat_mul(to[i], mm_quat_inverse(from[i]))) for i in [0, count): the turn
 * from one rotation to the next, the same bits, four at a time where the machine has the lanes. */
void mm__quat_turns_n(const mm_quat *from, const mm_quat *to, int count, mm_quat *out);

/* b[i] = mm_quat_normalize(mm_quat_mul(a[i], b[i])) for i in [0, count): the same bits, four at
 * a time where the machine has the lanes for it. */
void mm__quat_mul_normalize_n(const mm_quat *a, mm_quat *b, int count);

#endif /* MM_MATH_PRIVATE_H */
