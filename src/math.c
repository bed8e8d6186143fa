/* math.c - the non-inline parts of mm/math.h.
 *
 * Rotations are computed in double internally and rounded to float on return: the Euler,
 * matrix and log/exp conversions involve cancellations and inverse trigonometry that lose
 * several digits in single precision.
 *
 * Internally a quaternion is a double[4] laid out {x, y, z, w} like mm_quat, so that the
 * component about axis n (0 = X, 1 = Y, 2 = Z) is simply q[n].
 */
#include <mm/math.h>
#include "math_private.h"

#include <stddef.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(MM_WIDE_KERNELS)
static int wide_off; /* mm__math_wide_kernels(false): the tests' check of the two-wide kernels */

bool mm__wide_kernels(void) { return !wide_off && __builtin_cpu_supports("avx"); }

void mm__math_wide_kernels(bool on) { wide_off = !on; }
#else
bool mm__wide_kernels(void) { return false; }

void mm__math_wide_kernels(bool on) { (void)on; }
#endif

/* ---- internal double-precision helpers -------------------------------------------------- */

static void dq_from_quat(mm_quat q, double out[4])
{
    out[0] = q.x;
    out[1] = q.y;
    out[2] = q.z;
    out[3] = q.w;
}

static mm_quat dq_to_quat(const double q[4])
{
    return mm_quat_make((float)q[0], (float)q[1], (float)q[2], (float)q[3]);
}

/* out = a * b (b applied first). out may not alias a or b. */
static void dq_mul(const double a[4], const double b[4], double out[4])
{
    out[0] = a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1];
    out[1] = a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0];
    out[2] = a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3];
    out[3] = a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2];
}

static double dq_norm(const double q[4])
{
    return sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
}

/* Normalises q in place; returns 0 (and sets the identity) if q is zero. */
static int dq_normalize(double q[4])
{
    double n = dq_norm(q);
    if (n < 1e-300) {
        q[0] = q[1] = q[2] = 0.0;
        q[3] = 1.0;
        return 0;
    }
    for (int c = 0; c < 4; c++) q[c] /= n;
    return 1;
}

/* Rotation matrix of q; q need not be unit (the result is that of q / |q|). */
static void dq_to_mat(const double q[4], double m[3][3])
{
    double n2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
    double s = n2 > 0.0 ? 2.0 / n2 : 0.0;
    double x = q[0], y = q[1], z = q[2], w = q[3];
    m[0][0] = 1.0 - s * (y * y + z * z);
    m[0][1] = s * (x * y - w * z);
    m[0][2] = s * (x * z + w * y);
    m[1][0] = s * (x * y + w * z);
    m[1][1] = 1.0 - s * (x * x + z * z);
    m[1][2] = s * (y * z - w * x);
    m[2][0] = s * (x * z - w * y);
    m[2][1] = s * (y * z + w * x);
    m[2][2] = 1.0 - s * (x * x + y * y);
}

/* Maps an angle in [-pi, pi] to (-pi, pi]: atan2 returns -pi for a -0.0 numerator. */
static double wrap_pi(double a) { return a <= -MM_PI ? a + 2.0 * MM_PI : a; }

/* ---- Euler orders ------------------------------------------------------------------------ */

static const char *const euler_names[] = {NULL, "XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX"};

const char *mm_euler_order_name(mm_euler_order order)
{
    int o = (int)order;
    if (o <= (int)MM_EULER_NONE || o > (int)MM_EULER_ZYX) return NULL;
    return euler_names[o];
}

mm_euler_order mm_euler_order_parse(const char *name)
{
    if (name == NULL) return MM_EULER_NONE;
    for (int o = (int)MM_EULER_XYZ; o <= (int)MM_EULER_ZYX; o++) {
        const char *ref = euler_names[o];
        int n = 0;
        while (n < 3) {
            char c = name[n];
            if (c >= 'a' && c <= 'z') c = (char)(c - 'a' + 'A'); /* ASCII only, locale-free */
            if (c != ref[n]) break;
            n++;
        }
        if (n == 3 && name[3] == '\0') return (mm_euler_order)o;
    }
    return MM_EULER_NONE;
}

/* Axis indices of an order, first to last; returns 0 for an invalid order. */
static int euler_axes(mm_euler_order order, int axes[3])
{
    const char *name = mm_euler_order_name(order);
    if (name == NULL) return 0;
    for (int n = 0; n < 3; n++) axes[n] = name[n] - 'X';
    return 1;
}

/* ---- quaternion --------------------------------------------------------------------------- */

mm_quat mm_quat_from_axis_angle(mm_vec3 axis, float angle)
{
    double ax = axis.x, ay = axis.y, az = axis.z;
    double len = sqrt(ax * ax + ay * ay + az * az);
    if (len <= 1e-12) return mm_quat_identity();
    double h = 0.5 * (double)angle;
    double s = sin(h) / len;
    double q[4] = {ax * s, ay * s, az * s, cos(h)};
    return dq_to_quat(q);
}

mm_quat mm_quat_nlerp(mm_quat a, mm_quat b, float t)
{
    if (mm_quat_dot(a, b) < 0.0f) b = mm_quat_make(-b.x, -b.y, -b.z, -b.w);
    return mm_quat_normalize(mm_quat_make(a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t, a.z + (b.z - a.z) * t,
                                          a.w + (b.w - a.w) * t));
}

/* Angle on the 4D unit sphere between unit a and b (half the rotation angle between them),
 * via atan2 of the chord lengths, which stays accurate near 0 and pi/2 unlike acos(dot). */
static double dq_sphere_angle(const double a[4], const double b[4])
{
    double d2 = 0.0, s2 = 0.0;
    for (int c = 0; c < 4; c++) {
        d2 += (a[c] - b[c]) * (a[c] - b[c]);
        s2 += (a[c] + b[c]) * (a[c] + b[c]);
    }
    return 2.0 * atan2(sqrt(d2), sqrt(s2));
}

/* a and b as unit quaternions in double, b on a's side of the sphere (q and -q are the same
 * rotation: an interpolation between them takes the shorter arc) */
static void dq_shorter_arc(mm_quat a, mm_quat b, double qa[4], double qb[4])
{
    dq_from_quat(a, qa);
    dq_from_quat(b, qb);
    dq_normalize(qa);
    dq_normalize(qb);
    double dot = qa[0] * qb[0] + qa[1] * qb[1] + qa[2] * qb[2] + qa[3] * qb[3];
    if (dot < 0.0)
        for (int c = 0; c < 4; c++) qb[c] = -qb[c];
}

mm_quat mm_quat_slerp(mm_quat a, mm_quat b, float t)
{
    double qa[4], qb[4], out[4];
    dq_shorter_arc(a, b, qa, qb);
    double theta = dq_sphere_angle(qa, qb); /* in [0, pi/2] */
    double td = t, wa, wb;
    if (theta < 1e-4) {
        /* Nearly parallel: sin(theta) is too small to divide by; linear interpolation
         * (normalised below) differs from slerp by O(theta^3) here. */
        wa = 1.0 - td;
        wb = td;
    } else {
        double s = sin(theta);
        wa = sin((1.0 - td) * theta) / s;
        wb = sin(td * theta) / s;
    }
    for (int c = 0; c < 4; c++) out[c] = wa * qa[c] + wb * qb[c];
    dq_normalize(out);
    return dq_to_quat(out);
}

/* The 4D angle under which mm__quat_slerp_series takes its series: up to it the series below are
 * truncated under double rounding (their next terms are under 1e-16 of their sums). */
#define SERIES_MAX_ANGLE 0.3

/* sin(x) / x, of y = x^2 <= SERIES_MAX_ANGLE^2: the Taylor series, sum of (-y)^n / (2n + 1)!. */
static double sin_over_x(double y)
{
    return 1.0 + y * (-1.0 / 6.0 +
                      y * (1.0 / 120.0 +
                           y * (-1.0 / 5040.0 +
                                y * (1.0 / 362880.0 + y * (-1.0 / 39916800.0 + y * (1.0 / 6227020800.0))))));
}

/* asin(h) / h, of z = h^2 <= sin^2(SERIES_MAX_ANGLE / 2): the Taylor series, sum of
 * (2n)! / (4^n n!^2 (2n + 1)) z^n, these its coefficients. */
static const double ASIN_OVER_H[] = {1.0,
                                     1.0 / 6.0,
                                     3.0 / 40.0,
                                     15.0 / 336.0,
                                     105.0 / 3456.0,
                                     945.0 / 42240.0,
                                     10395.0 / 599040.0,
                                     135135.0 / 9676800.0,
                                     2027025.0 / 175472640.0,
                                     34459425.0 / 3530096640.0};

static double asin_over_h(double z)
{
    double sum = 0.0;
    for (int n = (int)(sizeof ASIN_OVER_H / sizeof ASIN_OVER_H[0]) - 1; n >= 0; --n)
        sum = sum * z + ASIN_OVER_H[n];
    return sum;
}

/* cos(x), of y = x^2 <= SERIES_MAX_ANGLE^2: the Taylor series, sum of (-y)^n / (2n)!. */
static double cos_series(double y)
{
    return 1.0 +
           y * (-1.0 / 2.0 +
                y * (1.0 / 24.0 + y * (-1.0 / 720.0 + y * (1.0 / 40320.0 + y * (-1.0 / 3628800.0 +
                                                                                y * (1.0 / 479001600.0))))));
}

mm_quat mm__quat_exp_series(mm_vec3 v)
{
    double d[3] = {v.x, v.y, v.z}, q[4];
    double angle2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2], h2 = 0.25 * angle2; /* h = angle / 2 */
    if (!(h2 < SERIES_MAX_ANGLE * SERIES_MAX_ANGLE)) return mm_quat_exp(v);
    double scale = 0.5 * sin_over_x(h2); /* sin(h) / angle */
    for (int c = 0; c < 3; c++) q[c] = d[c] * scale;
    q[3] = cos_series(h2);
    return dq_to_quat(q);
}

/* sin^2 of half the largest angle mm__quat_log_series takes from its series (the reach of
 * asin_over_h: sin^2(SERIES_MAX_ANGLE / 2) = 0.02233, rounded down) */
#define LOG_SERIES_MAX_SIN2 0.0223

mm_vec3 mm__quat_log_series(mm_quat quat)
{
    double q[4];
    dq_from_quat(quat, q);
    if (q[3] < 0.0) { /* as dq_log: -q is the same rotation with angle <= pi */
        for (int c = 0; c < 4; c++) q[c] = -q[c];
    }
    double s2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2], n2 = s2 + q[3] * q[3];
    double s = sqrt(s2), sin2 = s2 / n2; /* sin^2 of half the angle */
    /* dq_log's own series below 1e-6 (and a zero quaternion, NaN) are left to it */
    if (!(s >= 1e-6 * q[3]) || !(sin2 < LOG_SERIES_MAX_SIN2)) return mm_quat_log(quat);
    /* angle / s = 2 asin(s / n) / s = 2 asin_over_h(s^2 / n^2) / n */
    double scale = 2.0 * asin_over_h(sin2) / sqrt(n2);
    return mm_vec3_make((float)(q[0] * scale), (float)(q[1] * scale), (float)(q[2] * scale));
}

mm_quat mm__quat_slerp_series(mm_quat a, mm_quat b, float t)
{
    double qa[4], qb[4], out[4];
    dq_shorter_arc(a, b, qa, qb);
    /* the angle theta from the half chord h = sin(theta / 2) = |qa - qb| / 2 */
    double d2 = 0.0;
    for (int c = 0; c < 4; c++) d2 += (qa[c] - qb[c]) * (qa[c] - qb[c]);
    double h2 = 0.25 * d2, half = asin_over_h(h2), theta2 = 4.0 * h2 * half * half;
    if (!(theta2 < SERIES_MAX_ANGLE * SERIES_MAX_ANGLE)) return mm_quat_slerp(a, b, t);
    double td = t, wa, wb;
    if (theta2 < 1e-8) { /* as mm_quat_slerp: linear under 1e-4 rad */
        wa = 1.0 - td;
        wb = td;
    } else { /* sin(k theta) / sin(theta) = k sinc(k theta) / sinc(theta) */
        double s = sin_over_x(theta2), ua = 1.0 - td;
        wa = ua * sin_over_x(ua * ua * theta2) / s;
        wb = td * sin_over_x(td * td * theta2) / s;
    }
    for (int c = 0; c < 4; c++) out[c] = wa * qa[c] + wb * qb[c];
    dq_normalize(out);
    return dq_to_quat(out);
}

#if defined(__SSE2__)
/* mm__quat_slerp_series for two pairs at once: each lane of a packed double does what the scalar
 * code does, operation for operation and in its order, so the same bits. Lanes off the series'
 * common path (a zero quaternion, rotations 0.3 rad or more apart, NaN) are done again by the
 * scalar code. */

typedef struct dq2 {
    __m128d c[4]; /* x, y, z, w: each the two lanes */
} dq2;

static dq2 dq2_from_quats(mm_quat q0, mm_quat q1)
{
    __m128 a = _mm_loadu_ps(&q0.x), b = _mm_loadu_ps(&q1.x);
    __m128 xy = _mm_unpacklo_ps(a, b), zw = _mm_unpackhi_ps(a, b); /* x0 x1 y0 y1, z0 z1 w0 w1 */
    dq2 r = {{_mm_cvtps_pd(xy), _mm_cvtps_pd(_mm_movehl_ps(xy, xy)), _mm_cvtps_pd(zw),
              _mm_cvtps_pd(_mm_movehl_ps(zw, zw))}};
    return r;
}

/* the sum of the squares, in dq_norm's order, and its square root */
static __m128d dq2_norm(const dq2 *q)
{
    __m128d n = _mm_mul_pd(q->c[0], q->c[0]);
    for (int c = 1; c < 4; ++c) n = _mm_add_pd(n, _mm_mul_pd(q->c[c], q->c[c]));
    return _mm_sqrt_pd(n);
}

/* lanes where n >= 1e-300 (dq_normalize divides there; the rest are left to the scalar code) */
static __m128d dq2_divide(dq2 *q, __m128d n)
{
    for (int c = 0; c < 4; ++c) q->c[c] = _mm_div_pd(q->c[c], n);
    return _mm_cmpge_pd(n, _mm_set1_pd(1e-300));
}

static __m128d sin_over_x2(__m128d y)
{
    static const double k[] = {1.0 / 6227020800.0, -1.0 / 39916800.0, 1.0 / 362880.0,
                               -1.0 / 5040.0,      1.0 / 120.0,       -1.0 / 6.0};
    /* 1 + y (-1/6 + y (1/120 + ... + y (1/6227020800)))) from the inside out */
    __m128d r = _mm_mul_pd(y, _mm_set1_pd(k[0]));
    for (int i = 1; i < 6; ++i) r = _mm_mul_pd(y, _mm_add_pd(_mm_set1_pd(k[i]), r));
    return _mm_add_pd(_mm_set1_pd(1.0), r);
}

static __m128d asin_over_h2(__m128d z)
{
    __m128d sum = _mm_setzero_pd();
    for (int n = (int)(sizeof ASIN_OVER_H / sizeof ASIN_OVER_H[0]) - 1; n >= 0; --n)
        sum = _mm_add_pd(_mm_mul_pd(sum, z), _mm_set1_pd(ASIN_OVER_H[n]));
    return sum;
}

static __m128d blend2(__m128d mask, __m128d yes, __m128d no)
{
    return _mm_or_pd(_mm_and_pd(mask, yes), _mm_andnot_pd(mask, no));
}

/* Two slerps; returns the lanes (bit 0: the first, bit 1: the second) the scalar code must redo. */
static int slerp_series2(mm_quat a0, mm_quat a1, mm_quat b0, mm_quat b1, float t, mm_quat *out0,
                         mm_quat *out1)
{
    dq2 qa = dq2_from_quats(a0, a1), qb = dq2_from_quats(b0, b1);
    __m128d ok = _mm_and_pd(dq2_divide(&qa, dq2_norm(&qa)), dq2_divide(&qb, dq2_norm(&qb)));
    /* the shorter arc */
    __m128d dot = _mm_mul_pd(qa.c[0], qb.c[0]);
    for (int c = 1; c < 4; ++c) dot = _mm_add_pd(dot, _mm_mul_pd(qa.c[c], qb.c[c]));
    __m128d flip = _mm_and_pd(_mm_cmplt_pd(dot, _mm_setzero_pd()), _mm_set1_pd(-0.0));
    for (int c = 0; c < 4; ++c) qb.c[c] = _mm_xor_pd(qb.c[c], flip);
    /* the angle from the half chord */
    __m128d d2 = _mm_setzero_pd();
    for (int c = 0; c < 4; ++c) {
        __m128d e = _mm_sub_pd(qa.c[c], qb.c[c]);
        d2 = _mm_add_pd(d2, _mm_mul_pd(e, e));
    }
    __m128d h2 = _mm_mul_pd(_mm_set1_pd(0.25), d2), half = asin_over_h2(h2);
    __m128d theta2 = _mm_mul_pd(_mm_mul_pd(_mm_mul_pd(_mm_set1_pd(4.0), h2), half), half);
    ok = _mm_and_pd(ok, _mm_cmplt_pd(theta2, _mm_set1_pd(SERIES_MAX_ANGLE * SERIES_MAX_ANGLE)));
    __m128d td = _mm_set1_pd((double)t), ua = _mm_sub_pd(_mm_set1_pd(1.0), td);
    __m128d s = sin_over_x2(theta2);
    __m128d wa = _mm_div_pd(_mm_mul_pd(ua, sin_over_x2(_mm_mul_pd(_mm_mul_pd(ua, ua), theta2))), s);
    __m128d wb = _mm_div_pd(_mm_mul_pd(td, sin_over_x2(_mm_mul_pd(_mm_mul_pd(td, td), theta2))), s);
    __m128d linear = _mm_cmplt_pd(theta2, _mm_set1_pd(1e-8)); /* as mm_quat_slerp: linear under 1e-4 rad */
    wa = blend2(linear, ua, wa);
    wb = blend2(linear, td, wb);
    dq2 r;
    for (int c = 0; c < 4; ++c) r.c[c] = _mm_add_pd(_mm_mul_pd(wa, qa.c[c]), _mm_mul_pd(wb, qb.c[c]));
    ok = _mm_and_pd(ok, dq2_divide(&r, dq2_norm(&r)));
    __m128 x = _mm_cvtpd_ps(r.c[0]), y = _mm_cvtpd_ps(r.c[1]), z = _mm_cvtpd_ps(r.c[2]),
           w = _mm_cvtpd_ps(r.c[3]);
    __m128 xy = _mm_unpacklo_ps(x, y), zw = _mm_unpacklo_ps(z, w); /* x0 y0 x1 y1, z0 w0 z1 w1 */
    _mm_storeu_ps(&out0->x, _mm_movelh_ps(xy, zw));
    _mm_storeu_ps(&out1->x, _mm_movehl_ps(zw, xy));
    return ~_mm_movemask_pd(ok) & 3;
}

static __m128d cos_series2(__m128d y)
{
    static const double k[] = {1.0 / 479001600.0, -1.0 / 3628800.0, 1.0 / 40320.0,
                               -1.0 / 720.0,      1.0 / 24.0,       -1.0 / 2.0};
    __m128d r = _mm_mul_pd(y, _mm_set1_pd(k[0]));
    for (int i = 1; i < 6; ++i) r = _mm_mul_pd(y, _mm_add_pd(_mm_set1_pd(k[i]), r));
    return _mm_add_pd(_mm_set1_pd(1.0), r);
}

/* Two exps; returns the lanes (bit 0: the first, bit 1: the second) the scalar code must redo. */
static int exp_series2(mm_vec3 v0, mm_vec3 v1, mm_quat *out0, mm_quat *out1)
{
    __m128d d[3] = {_mm_set_pd(v1.x, v0.x), _mm_set_pd(v1.y, v0.y), _mm_set_pd(v1.z, v0.z)};
    __m128d angle2 =
        _mm_add_pd(_mm_add_pd(_mm_mul_pd(d[0], d[0]), _mm_mul_pd(d[1], d[1])), _mm_mul_pd(d[2], d[2]));
    __m128d h2 = _mm_mul_pd(_mm_set1_pd(0.25), angle2);
    __m128d ok = _mm_cmplt_pd(h2, _mm_set1_pd(SERIES_MAX_ANGLE * SERIES_MAX_ANGLE));
    __m128d scale = _mm_mul_pd(_mm_set1_pd(0.5), sin_over_x2(h2));
    __m128 x = _mm_cvtpd_ps(_mm_mul_pd(d[0], scale)), y = _mm_cvtpd_ps(_mm_mul_pd(d[1], scale)),
           z = _mm_cvtpd_ps(_mm_mul_pd(d[2], scale)), w = _mm_cvtpd_ps(cos_series2(h2));
    __m128 xy = _mm_unpacklo_ps(x, y), zw = _mm_unpacklo_ps(z, w); /* x0 y0 x1 y1, z0 w0 z1 w1 */
    _mm_storeu_ps(&out0->x, _mm_movelh_ps(xy, zw));
    _mm_storeu_ps(&out1->x, _mm_movehl_ps(zw, xy));
    return ~_mm_movemask_pd(ok) & 3;
}

/* Two series logs; returns the lanes (bit 0: the first, bit 1: the second) the scalar code must
 * redo. */
static int log_series2(mm_quat q0, mm_quat q1, mm_vec3 *out0, mm_vec3 *out1)
{
    dq2 q = dq2_from_quats(q0, q1);
    __m128d flip = _mm_and_pd(_mm_cmplt_pd(q.c[3], _mm_setzero_pd()), _mm_set1_pd(-0.0));
    for (int c = 0; c < 4; ++c) q.c[c] = _mm_xor_pd(q.c[c], flip);
    __m128d s2 = _mm_add_pd(_mm_add_pd(_mm_mul_pd(q.c[0], q.c[0]), _mm_mul_pd(q.c[1], q.c[1])),
                            _mm_mul_pd(q.c[2], q.c[2]));
    __m128d n2 = _mm_add_pd(s2, _mm_mul_pd(q.c[3], q.c[3]));
    __m128d s = _mm_sqrt_pd(s2), sin2 = _mm_div_pd(s2, n2);
    __m128d ok = _mm_and_pd(_mm_cmpge_pd(s, _mm_mul_pd(_mm_set1_pd(1e-6), q.c[3])),
                            _mm_cmplt_pd(sin2, _mm_set1_pd(LOG_SERIES_MAX_SIN2)));
    __m128d scale = _mm_div_pd(_mm_mul_pd(_mm_set1_pd(2.0), asin_over_h2(sin2)), _mm_sqrt_pd(n2));
    float x[4], y[4], z[4];
    _mm_storeu_ps(x, _mm_cvtpd_ps(_mm_mul_pd(q.c[0], scale)));
    _mm_storeu_ps(y, _mm_cvtpd_ps(_mm_mul_pd(q.c[1], scale)));
    _mm_storeu_ps(z, _mm_cvtpd_ps(_mm_mul_pd(q.c[2], scale)));
    *out0 = mm_vec3_make(x[0], y[0], z[0]);
    *out1 = mm_vec3_make(x[1], y[1], z[1]);
    return ~_mm_movemask_pd(ok) & 3;
}

#if defined(MM_WIDE_KERNELS)
/* slerp_series2 for four pairs in the four double lanes of AVX, operation for operation (AVX's
 * arithmetic is IEEE's as SSE2's is, and without FMA nothing is fused): the same bits. */
typedef struct dq4 {
    __m256d c[4]; /* x, y, z, w: each the four lanes */
} dq4;

MM_WIDE static dq4 dq4_from_quats(const mm_quat *q)
{
    __m128 x = _mm_loadu_ps(&q[0].x), y = _mm_loadu_ps(&q[1].x), z = _mm_loadu_ps(&q[2].x),
           w = _mm_loadu_ps(&q[3].x);
    _MM_TRANSPOSE4_PS(x, y, z, w);
    dq4 r = {{_mm256_cvtps_pd(x), _mm256_cvtps_pd(y), _mm256_cvtps_pd(z), _mm256_cvtps_pd(w)}};
    return r;
}

MM_WIDE static __m256d dq4_norm(const dq4 *q)
{
    __m256d n = _mm256_mul_pd(q->c[0], q->c[0]);
    for (int c = 1; c < 4; ++c) n = _mm256_add_pd(n, _mm256_mul_pd(q->c[c], q->c[c]));
    return _mm256_sqrt_pd(n);
}

MM_WIDE static __m256d dq4_divide(dq4 *q, __m256d n)
{
    for (int c = 0; c < 4; ++c) q->c[c] = _mm256_div_pd(q->c[c], n);
    return _mm256_cmp_pd(n, _mm256_set1_pd(1e-300), _CMP_GE_OQ);
}

MM_WIDE static __m256d sin_over_x4(__m256d y)
{
    static const double k[] = {1.0 / 6227020800.0, -1.0 / 39916800.0, 1.0 / 362880.0,
                               -1.0 / 5040.0,      1.0 / 120.0,       -1.0 / 6.0};
    __m256d r = _mm256_mul_pd(y, _mm256_set1_pd(k[0]));
    for (int i = 1; i < 6; ++i) r = _mm256_mul_pd(y, _mm256_add_pd(_mm256_set1_pd(k[i]), r));
    return _mm256_add_pd(_mm256_set1_pd(1.0), r);
}

MM_WIDE static __m256d asin_over_h4(__m256d z)
{
    __m256d sum = _mm256_setzero_pd();
    for (int n = (int)(sizeof ASIN_OVER_H / sizeof ASIN_OVER_H[0]) - 1; n >= 0; --n)
        sum = _mm256_add_pd(_mm256_mul_pd(sum, z), _mm256_set1_pd(ASIN_OVER_H[n]));
    return sum;
}

/* Four slerps; returns the lanes (bit k: pair k) the scalar code must redo. */
MM_WIDE static int slerp_series4(const mm_quat *a, const mm_quat *b, float t, mm_quat *out)
{
    dq4 qa = dq4_from_quats(a), qb = dq4_from_quats(b);
    __m256d ok = _mm256_and_pd(dq4_divide(&qa, dq4_norm(&qa)), dq4_divide(&qb, dq4_norm(&qb)));
    __m256d dot = _mm256_mul_pd(qa.c[0], qb.c[0]);
    for (int c = 1; c < 4; ++c) dot = _mm256_add_pd(dot, _mm256_mul_pd(qa.c[c], qb.c[c]));
    __m256d flip = _mm256_and_pd(_mm256_cmp_pd(dot, _mm256_setzero_pd(), _CMP_LT_OQ), _mm256_set1_pd(-0.0));
    for (int c = 0; c < 4; ++c) qb.c[c] = _mm256_xor_pd(qb.c[c], flip);
    __m256d d2 = _mm256_setzero_pd();
    for (int c = 0; c < 4; ++c) {
        __m256d e = _mm256_sub_pd(qa.c[c], qb.c[c]);
        d2 = _mm256_add_pd(d2, _mm256_mul_pd(e, e));
    }
    __m256d h2 = _mm256_mul_pd(_mm256_set1_pd(0.25), d2), half = asin_over_h4(h2);
    __m256d theta2 = _mm256_mul_pd(_mm256_mul_pd(_mm256_mul_pd(_mm256_set1_pd(4.0), h2), half), half);
    ok = _mm256_and_pd(
        ok, _mm256_cmp_pd(theta2, _mm256_set1_pd(SERIES_MAX_ANGLE * SERIES_MAX_ANGLE), _CMP_LT_OQ));
    __m256d td = _mm256_set1_pd((double)t), ua = _mm256_sub_pd(_mm256_set1_pd(1.0), td);
    __m256d s = sin_over_x4(theta2);
    __m256d wa =
        _mm256_div_pd(_mm256_mul_pd(ua, sin_over_x4(_mm256_mul_pd(_mm256_mul_pd(ua, ua), theta2))), s);
    __m256d wb =
        _mm256_div_pd(_mm256_mul_pd(td, sin_over_x4(_mm256_mul_pd(_mm256_mul_pd(td, td), theta2))), s);
    __m256d linear = _mm256_cmp_pd(theta2, _mm256_set1_pd(1e-8), _CMP_LT_OQ);
    wa = _mm256_blendv_pd(wa, ua, linear);
    wb = _mm256_blendv_pd(wb, td, linear);
    dq4 r;
    for (int c = 0; c < 4; ++c)
        r.c[c] = _mm256_add_pd(_mm256_mul_pd(wa, qa.c[c]), _mm256_mul_pd(wb, qb.c[c]));
    ok = _mm256_and_pd(ok, dq4_divide(&r, dq4_norm(&r)));
    __m128 x = _mm256_cvtpd_ps(r.c[0]), y = _mm256_cvtpd_ps(r.c[1]), z = _mm256_cvtpd_ps(r.c[2]),
           w = _mm256_cvtpd_ps(r.c[3]);
    _MM_TRANSPOSE4_PS(x, y, z, w);
    _mm_storeu_ps(&out[0].x, x);
    _mm_storeu_ps(&out[1].x, y);
    _mm_storeu_ps(&out[2].x, z);
    _mm_storeu_ps(&out[3].x, w);
    return ~_mm256_movemask_pd(ok) & 15;
}

MM_WIDE static __m256d cos_series4(__m256d y)
{
    static const double k[] = {1.0 / 479001600.0, -1.0 / 3628800.0, 1.0 / 40320.0,
                               -1.0 / 720.0,      1.0 / 24.0,       -1.0 / 2.0};
    __m256d r = _mm256_mul_pd(y, _mm256_set1_pd(k[0]));
    for (int i = 1; i < 6; ++i) r = _mm256_mul_pd(y, _mm256_add_pd(_mm256_set1_pd(k[i]), r));
    return _mm256_add_pd(_mm256_set1_pd(1.0), r);
}

/* exp_series2 for four; returns the lanes the scalar code must redo. */
MM_WIDE static int exp_series4(const mm_vec3 *v, mm_quat *out)
{
    __m256d d[3] = {_mm256_set_pd(v[3].x, v[2].x, v[1].x, v[0].x),
                    _mm256_set_pd(v[3].y, v[2].y, v[1].y, v[0].y),
                    _mm256_set_pd(v[3].z, v[2].z, v[1].z, v[0].z)};
    __m256d angle2 = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(d[0], d[0]), _mm256_mul_pd(d[1], d[1])),
                                   _mm256_mul_pd(d[2], d[2]));
    __m256d h2 = _mm256_mul_pd(_mm256_set1_pd(0.25), angle2);
    __m256d ok = _mm256_cmp_pd(h2, _mm256_set1_pd(SERIES_MAX_ANGLE * SERIES_MAX_ANGLE), _CMP_LT_OQ);
    __m256d scale = _mm256_mul_pd(_mm256_set1_pd(0.5), sin_over_x4(h2));
    __m128 x = _mm256_cvtpd_ps(_mm256_mul_pd(d[0], scale)), y = _mm256_cvtpd_ps(_mm256_mul_pd(d[1], scale)),
           z = _mm256_cvtpd_ps(_mm256_mul_pd(d[2], scale)), w = _mm256_cvtpd_ps(cos_series4(h2));
    _MM_TRANSPOSE4_PS(x, y, z, w);
    _mm_storeu_ps(&out[0].x, x);
    _mm_storeu_ps(&out[1].x, y);
    _mm_storeu_ps(&out[2].x, z);
    _mm_storeu_ps(&out[3].x, w);
    return ~_mm256_movemask_pd(ok) & 15;
}

/* log_series2 for four; returns the lanes the scalar code must redo. */
MM_WIDE static int log_series4(const mm_quat *in, mm_vec3 *out)
{
    dq4 q = dq4_from_quats(in);
    __m256d flip =
        _mm256_and_pd(_mm256_cmp_pd(q.c[3], _mm256_setzero_pd(), _CMP_LT_OQ), _mm256_set1_pd(-0.0));
    for (int c = 0; c < 4; ++c) q.c[c] = _mm256_xor_pd(q.c[c], flip);
    __m256d s2 = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(q.c[0], q.c[0]), _mm256_mul_pd(q.c[1], q.c[1])),
                               _mm256_mul_pd(q.c[2], q.c[2]));
    __m256d n2 = _mm256_add_pd(s2, _mm256_mul_pd(q.c[3], q.c[3]));
    __m256d s = _mm256_sqrt_pd(s2), sin2 = _mm256_div_pd(s2, n2);
    __m256d ok = _mm256_and_pd(_mm256_cmp_pd(s, _mm256_mul_pd(_mm256_set1_pd(1e-6), q.c[3]), _CMP_GE_OQ),
                               _mm256_cmp_pd(sin2, _mm256_set1_pd(LOG_SERIES_MAX_SIN2), _CMP_LT_OQ));
    __m256d scale = _mm256_div_pd(_mm256_mul_pd(_mm256_set1_pd(2.0), asin_over_h4(sin2)), _mm256_sqrt_pd(n2));
    float x[4], y[4], z[4];
    _mm_storeu_ps(x, _mm256_cvtpd_ps(_mm256_mul_pd(q.c[0], scale)));
    _mm_storeu_ps(y, _mm256_cvtpd_ps(_mm256_mul_pd(q.c[1], scale)));
    _mm_storeu_ps(z, _mm256_cvtpd_ps(_mm256_mul_pd(q.c[2], scale)));
    for (int k = 0; k < 4; ++k) out[k] = mm_vec3_make(x[k], y[k], z[k]);
    return ~_mm256_movemask_pd(ok) & 15;
}
#endif

void mm__quat_log_series_n(const mm_quat *q, int count, mm_vec3 *out)
{
    int i = 0;
#if defined(MM_WIDE_KERNELS)
    if (mm__wide_kernels())
        for (; i + 3 < count; i += 4) {
            int redo = log_series4(q + i, out + i);
            for (int k = 0; k < 4; ++k)
                if (redo & 1 << k) out[i + k] = mm__quat_log_series(q[i + k]);
        }
#endif
    for (; i + 1 < count; i += 2) {
        int redo = log_series2(q[i], q[i + 1], &out[i], &out[i + 1]);
        if (redo & 1) out[i] = mm__quat_log_series(q[i]);
        if (redo & 2) out[i + 1] = mm__quat_log_series(q[i + 1]);
    }
    for (; i < count; ++i) out[i] = mm__quat_log_series(q[i]);
}

void mm__quat_exp_series_n(const mm_vec3 *v, int count, mm_quat *out)
{
    int i = 0;
#if defined(MM_WIDE_KERNELS)
    if (mm__wide_kernels())
        for (; i + 3 < count; i += 4) {
            int redo = exp_series4(v + i, out + i);
            for (int k = 0; k < 4; ++k)
                if (redo & 1 << k) out[i + k] = mm__quat_exp_series(v[i + k]);
        }
#endif
    for (; i + 1 < count; i += 2) {
        int redo = exp_series2(v[i], v[i + 1], &out[i], &out[i + 1]);
        if (redo & 1) out[i] = mm__quat_exp_series(v[i]);
        if (redo & 2) out[i + 1] = mm__quat_exp_series(v[i + 1]);
    }
    for (; i < count; ++i) out[i] = mm__quat_exp_series(v[i]);
}

void mm__quat_slerp_series_n(const mm_quat *a, const mm_quat *b, float t, int count, mm_quat *out)
{
    int i = 0;
#if defined(MM_WIDE_KERNELS)
    if (mm__wide_kernels())
        for (; i + 3 < count; i += 4) {
            int redo = slerp_series4(a + i, b + i, t, out + i);
            for (int k = 0; k < 4; ++k)
                if (redo & 1 << k) out[i + k] = mm__quat_slerp_series(a[i + k], b[i + k], t);
        }
#endif
    for (; i + 1 < count; i += 2) {
        int redo = slerp_series2(a[i], a[i + 1], b[i], b[i + 1], t, &out[i], &out[i + 1]);
        if (redo & 1) out[i] = mm__quat_slerp_series(a[i], b[i], t);
        if (redo & 2) out[i + 1] = mm__quat_slerp_series(a[i + 1], b[i + 1], t);
    }
    for (; i < count; ++i) out[i] = mm__quat_slerp_series(a[i], b[i], t);
}

/* The product of four pairs of quaternions, one joint a lane (a's and b's coordinates transposed
 * into x y z w vectors), normalized: each lane mm_quat_mul's and mm_quat_normalize's operations in
 * their order, so the same bits. */
static void mul_normalize4(const mm_quat *a, mm_quat *b)
{
    __m128 ax = _mm_loadu_ps(&a[0].x), ay = _mm_loadu_ps(&a[1].x), az = _mm_loadu_ps(&a[2].x),
           aw = _mm_loadu_ps(&a[3].x);
    __m128 bx = _mm_loadu_ps(&b[0].x), by = _mm_loadu_ps(&b[1].x), bz = _mm_loadu_ps(&b[2].x),
           bw = _mm_loadu_ps(&b[3].x);
    _MM_TRANSPOSE4_PS(ax, ay, az, aw);
    _MM_TRANSPOSE4_PS(bx, by, bz, bw);
#define MUL _mm_mul_ps
    __m128 x = _mm_sub_ps(_mm_add_ps(_mm_add_ps(MUL(aw, bx), MUL(ax, bw)), MUL(ay, bz)), MUL(az, by));
    __m128 y = _mm_add_ps(_mm_add_ps(_mm_sub_ps(MUL(aw, by), MUL(ax, bz)), MUL(ay, bw)), MUL(az, bx));
    __m128 z = _mm_add_ps(_mm_sub_ps(_mm_add_ps(MUL(aw, bz), MUL(ax, by)), MUL(ay, bx)), MUL(az, bw));
    __m128 w = _mm_sub_ps(_mm_sub_ps(_mm_sub_ps(MUL(aw, bw), MUL(ax, bx)), MUL(ay, by)), MUL(az, bz));
    __m128 len = _mm_sqrt_ps(_mm_add_ps(_mm_add_ps(_mm_add_ps(MUL(x, x), MUL(y, y)), MUL(z, z)), MUL(w, w)));
    __m128 s = _mm_div_ps(_mm_set1_ps(1.0f), len);
    __m128 zero = _mm_cmplt_ps(len, _mm_set1_ps(1e-12f)); /* mm_quat_normalize's identity */
    x = _mm_andnot_ps(zero, MUL(x, s));
    y = _mm_andnot_ps(zero, MUL(y, s));
    z = _mm_andnot_ps(zero, MUL(z, s));
    w = _mm_or_ps(_mm_andnot_ps(zero, MUL(w, s)), _mm_and_ps(zero, _mm_set1_ps(1.0f)));
#undef MUL
    _MM_TRANSPOSE4_PS(x, y, z, w);
    _mm_storeu_ps(&b[0].x, x);
    _mm_storeu_ps(&b[1].x, y);
    _mm_storeu_ps(&b[2].x, z);
    _mm_storeu_ps(&b[3].x, w);
}

/* The turns of four pairs, one pair a lane: each lane mm_quat_inverse's, mm_quat_mul's and
 * mm_quat_abs's operations in their order, so the same bits. */
static void turns4(const mm_quat *from, const mm_quat *to, mm_quat *out)
{
#define MUL _mm_mul_ps
    __m128 fx = _mm_loadu_ps(&from[0].x), fy = _mm_loadu_ps(&from[1].x), fz = _mm_loadu_ps(&from[2].x),
           fw = _mm_loadu_ps(&from[3].x);
    __m128 ax = _mm_loadu_ps(&to[0].x), ay = _mm_loadu_ps(&to[1].x), az = _mm_loadu_ps(&to[2].x),
           aw = _mm_loadu_ps(&to[3].x);
    _MM_TRANSPOSE4_PS(fx, fy, fz, fw);
    _MM_TRANSPOSE4_PS(ax, ay, az, aw);
    /* b = mm_quat_inverse(from): the identity under a norm of 1e-24 */
    __m128 n = _mm_add_ps(_mm_add_ps(_mm_add_ps(MUL(fx, fx), MUL(fy, fy)), MUL(fz, fz)), MUL(fw, fw));
    __m128 s = _mm_div_ps(_mm_set1_ps(1.0f), n), sign = _mm_set1_ps(-0.0f);
    __m128 tiny = _mm_cmplt_ps(n, _mm_set1_ps(1e-24f));
    __m128 bx = _mm_andnot_ps(tiny, MUL(_mm_xor_ps(fx, sign), s)),
           by = _mm_andnot_ps(tiny, MUL(_mm_xor_ps(fy, sign), s)),
           bz = _mm_andnot_ps(tiny, MUL(_mm_xor_ps(fz, sign), s)),
           bw = _mm_or_ps(_mm_andnot_ps(tiny, MUL(fw, s)), _mm_and_ps(tiny, _mm_set1_ps(1.0f)));
    __m128 x = _mm_sub_ps(_mm_add_ps(_mm_add_ps(MUL(aw, bx), MUL(ax, bw)), MUL(ay, bz)), MUL(az, by));
    __m128 y = _mm_add_ps(_mm_add_ps(_mm_sub_ps(MUL(aw, by), MUL(ax, bz)), MUL(ay, bw)), MUL(az, bx));
    __m128 z = _mm_add_ps(_mm_sub_ps(_mm_add_ps(MUL(aw, bz), MUL(ax, by)), MUL(ay, bx)), MUL(az, bw));
    __m128 w = _mm_sub_ps(_mm_sub_ps(_mm_sub_ps(MUL(aw, bw), MUL(ax, bx)), MUL(ay, by)), MUL(az, bz));
#undef MUL
    /* mm_quat_abs: negated where w < 0 */
    __m128 flip = _mm_and_ps(_mm_cmplt_ps(w, _mm_setzero_ps()), sign);
    x = _mm_xor_ps(x, flip), y = _mm_xor_ps(y, flip), z = _mm_xor_ps(z, flip), w = _mm_xor_ps(w, flip);
    _MM_TRANSPOSE4_PS(x, y, z, w);
    _mm_storeu_ps(&out[0].x, x);
    _mm_storeu_ps(&out[1].x, y);
    _mm_storeu_ps(&out[2].x, z);
    _mm_storeu_ps(&out[3].x, w);
}

void mm__quat_turns_n(const mm_quat *from, const mm_quat *to, int count, mm_quat *out)
{
    int i = 0;
    for (; i + 4 <= count; i += 4) turns4(from + i, to + i, out + i);
    for (; i < count; ++i) out[i] = mm_quat_abs(mm_quat_mul(to[i], mm_quat_inverse(from[i])));
}

void mm__quat_mul_normalize_n(const mm_quat *a, mm_quat *b, int count)
{
    int i = 0;
    for (; i + 4 <= count; i += 4) mul_normalize4(a + i, b + i);
    for (; i < count; ++i) b[i] = mm_quat_normalize(mm_quat_mul(a[i], b[i]));
}
#else
void mm__quat_turns_n(const mm_quat *from, const mm_quat *to, int count, mm_quat *out)
{
    for (int i = 0; i < count; ++i) out[i] = mm_quat_abs(mm_quat_mul(to[i], mm_quat_inverse(from[i])));
}

void mm__quat_log_series_n(const mm_quat *q, int count, mm_vec3 *out)
{
    for (int i = 0; i < count; ++i) out[i] = mm__quat_log_series(q[i]);
}

void mm__quat_mul_normalize_n(const mm_quat *a, mm_quat *b, int count)
{
    for (int i = 0; i < count; ++i) b[i] = mm_quat_normalize(mm_quat_mul(a[i], b[i]));
}

void mm__quat_exp_series_n(const mm_vec3 *v, int count, mm_quat *out)
{
    for (int i = 0; i < count; ++i) out[i] = mm__quat_exp_series(v[i]);
}

void mm__quat_slerp_series_n(const mm_quat *a, const mm_quat *b, float t, int count, mm_quat *out)
{
    for (int i = 0; i < count; ++i) out[i] = mm__quat_slerp_series(a[i], b[i], t);
}
#endif

float mm_quat_angle_between(mm_quat a, mm_quat b)
{
    double qa[4], qb[4];
    dq_from_quat(a, qa);
    dq_from_quat(b, qb);
    dq_normalize(qa);
    dq_normalize(qb);
    double dot = qa[0] * qb[0] + qa[1] * qb[1] + qa[2] * qb[2] + qa[3] * qb[3];
    if (dot < 0.0) {
        for (int c = 0; c < 4; c++) qb[c] = -qb[c];
    }
    return (float)(2.0 * dq_sphere_angle(qa, qb));
}

/* ---- Euler angles --------------------------------------------------------------------------- */

mm_quat mm_quat_from_euler(mm_vec3 angles, mm_euler_order order)
{
    int axes[3];
    if (!euler_axes(order, axes)) return mm_quat_identity();
    double ang[3] = {angles.x, angles.y, angles.z};
    double q[4] = {0.0, 0.0, 0.0, 1.0};
    /* q = R(first) * R(second) * R(third), accumulated left to right. */
    for (int n = 0; n < 3; n++) {
        double h = 0.5 * ang[axes[n]];
        double r[4] = {0.0, 0.0, 0.0, cos(h)};
        double tmp[4];
        r[axes[n]] = sin(h);
        dq_mul(q, r, tmp);
        for (int c = 0; c < 4; c++) q[c] = tmp[c];
    }
    return dq_to_quat(q);
}

/* Below this cosine of the middle angle (about 1e-6 rad from +-pi/2, a few times the
 * resolution of a float quaternion) the first and third axes are treated as aligned. */
#define MM_GIMBAL_EPS 1e-6

mm_vec3 mm_quat_to_euler(mm_quat quat, mm_euler_order order)
{
    int axes[3];
    if (!euler_axes(order, axes)) return mm_vec3_make(0.0f, 0.0f, 0.0f);
    double q[4], m[3][3];
    dq_from_quat(quat, q);
    dq_normalize(q);
    dq_to_mat(q, m);

    /* M = R_i(a) R_j(b) R_k(c). With s = +1 when (i, j, k) is a cyclic permutation of
     * (X, Y, Z) and -1 otherwise, expanding the product gives
     *   column k: M[i][k] = s sin b,  M[j][k] = -s sin a cos b,  M[k][k] = cos a cos b
     *   row i:    M[i][i] = cos b cos c,  M[i][j] = -s cos b sin c
     * and, when c = 0, column j is R_i(a) e_j: M[j][j] = cos a, M[k][j] = s sin a. */
    int i = axes[0], j = axes[1], k = axes[2];
    double s = ((j - i + 3) % 3 == 1) ? 1.0 : -1.0;
    double cb = hypot(m[i][i], m[i][j]);
    double a, b, c;
    b = atan2(s * m[i][k], cb); /* cb >= 0 keeps b in [-pi/2, pi/2] */
    if (cb > MM_GIMBAL_EPS) {
        a = atan2(-s * m[j][k], m[k][k]);
        c = atan2(-s * m[i][j], m[i][i]);
    } else {
        /* Gimbal lock: only a +- c is determined; put it all in the first angle. */
        a = atan2(s * m[k][j], m[j][j]);
        c = 0.0;
    }
    double out[3];
    out[i] = wrap_pi(a);
    out[j] = b;
    out[k] = wrap_pi(c);
    return mm_vec3_make((float)out[0], (float)out[1], (float)out[2]);
}

/* ---- matrices ------------------------------------------------------------------------------- */

mm_quat mm_quat_from_mat3(mm_mat3 mat)
{
    double m[3][3];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) m[r][c] = mat.m[r][c];

    /* Shepperd: 4w^2 = 1 + tr, 4x^2 = 1 + m00 - m11 - m22, ... Take the square root of the
     * largest of the four, which is at least 1/4, and get the others from the off-diagonal
     * sums and differences, so nothing is divided by a small number. */
    double tr = m[0][0] + m[1][1] + m[2][2];
    double q[4];
    if (tr >= m[0][0] && tr >= m[1][1] && tr >= m[2][2]) {
        double r = sqrt(1.0 + tr); /* 2|w| */
        double f = 0.5 / r;
        q[3] = 0.5 * r;
        q[0] = (m[2][1] - m[1][2]) * f;
        q[1] = (m[0][2] - m[2][0]) * f;
        q[2] = (m[1][0] - m[0][1]) * f;
    } else {
        /* n is the largest diagonal term; (n, n1, n2) is cyclic. */
        int n = 0;
        if (m[1][1] > m[n][n]) n = 1;
        if (m[2][2] > m[n][n]) n = 2;
        int n1 = (n + 1) % 3, n2 = (n + 2) % 3;
        double r = sqrt(1.0 + m[n][n] - m[n1][n1] - m[n2][n2]);
        double f = 0.5 / r;
        q[n] = 0.5 * r;
        q[n1] = (m[n1][n] + m[n][n1]) * f;
        q[n2] = (m[n2][n] + m[n][n2]) * f;
        q[3] = (m[n2][n1] - m[n1][n2]) * f;
    }
    if (q[3] < 0.0) {
        for (int c = 0; c < 4; c++) q[c] = -q[c];
    }
    dq_normalize(q); /* absorbs small deviations from orthonormality */
    return dq_to_quat(q);
}

mm_mat3 mm_quat_to_mat3(mm_quat quat)
{
    double q[4], m[3][3];
    mm_mat3 out;
    dq_from_quat(quat, q);
    dq_to_mat(q, m);
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) out.m[r][c] = (float)m[r][c];
    return out;
}

/* ---- log / exp ------------------------------------------------------------------------------- */

/* Rotation vector (axis * full angle, angle in [0, pi]) of q, which need not be unit. */
static void dq_log(const double quat[4], double out[3])
{
    double q[4] = {quat[0], quat[1], quat[2], quat[3]};
    if (q[3] < 0.0) { /* -q is the same rotation with angle <= pi */
        for (int c = 0; c < 4; c++) q[c] = -q[c];
    }
    /* For q = |q| (axis sin(angle/2), cos(angle/2)): s = |q| sin(angle/2), w = |q| cos(angle/2). */
    double s = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
    double w = q[3];
    if (!(s > 0.0) && !(w > 0.0)) { /* zero quaternion */
        out[0] = out[1] = out[2] = 0.0;
        return;
    }
    double scale; /* angle / s */
    if (s < 1e-6 * w) {
        /* 2 atan(s/w) / s = (2/w) (1 - (s/w)^2 / 3 + ...); the next term is below 1e-24. */
        double r = s / w;
        scale = (2.0 / w) * (1.0 - r * r / 3.0);
    } else {
        scale = 2.0 * atan2(s, w) / s; /* s >= 1e-6 w > 0, or s > 0 when w == 0 */
    }
    for (int c = 0; c < 3; c++) out[c] = q[c] * scale;
}

/* Unit quaternion of the rotation vector v (inverse of dq_log). */
static void dq_exp(const double v[3], double q[4])
{
    double angle = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    double h = 0.5 * angle;
    double scale; /* sin(angle / 2) / angle */
    if (angle < 1e-4) {
        /* sin(h) / (2h) = (1 - h^2/6 + h^4/120) / 2 + O(h^6), exact in double here. */
        double h2 = h * h;
        scale = 0.5 * (1.0 - h2 / 6.0 + h2 * h2 / 120.0);
    } else {
        scale = sin(h) / angle;
    }
    for (int c = 0; c < 3; c++) q[c] = v[c] * scale;
    q[3] = cos(h);
}

mm_vec3 mm_quat_log(mm_quat quat)
{
    double q[4], v[3];
    dq_from_quat(quat, q);
    dq_log(q, v);
    return mm_vec3_make((float)v[0], (float)v[1], (float)v[2]);
}

mm_quat mm_quat_exp(mm_vec3 v)
{
    double d[3] = {v.x, v.y, v.z}, q[4];
    dq_exp(d, q);
    return dq_to_quat(q);
}

/* ---- splines ------------------------------------------------------------------------------ */

/* Rotation vector of a^-1 b (the turn from a to b in a's frame, shortest); a and b unit. */
static void dq_delta(const double a[4], const double b[4], double out[3])
{
    double ac[4] = {-a[0], -a[1], -a[2], a[3]}, d[4];
    dq_mul(ac, b, d);
    dq_log(d, out);
}

/* out = q exp(v * s), for unit q. */
static void dq_mul_exp(const double q[4], const double v[3], double s, double out[4])
{
    double sv[3] = {v[0] * s, v[1] * s, v[2] * s}, e[4];
    dq_exp(sv, e);
    dq_mul(q, e, out);
}

/* The curve of mm_quat_hermite at t in (0, 1), with a and b unit and double; w0, w1 the
 * tangents at a and b. Control points c1 = a exp(w0/3) and c2 = b exp(-w1/3); the curve is
 * a exp(w0/3 B1(t)) exp(log(c1^-1 c2) B2(t)) exp(w1/3 B3(t)) with the cumulative Bernstein
 * bases B1 = 1 - (1-t)^3, B2 = 3t^2 - 2t^3, B3 = t^3. B1' = 3 and B2' = B3' = 0 at t = 0,
 * B1' = B2' = 0 and B3' = 3 at t = 1, so the angular velocity is w0 at a and w1 at b; all
 * three are 1 at t = 1 and the product telescopes to b (or -b). */
static void dq_hermite(const double a[4], const double w0[3], const double b[4], const double w1[3], double t,
                       double out[4])
{
    double c1[4], c2[4], mid[3], x[4], y[4];
    dq_mul_exp(a, w0, 1.0 / 3.0, c1);
    dq_mul_exp(b, w1, -1.0 / 3.0, c2);
    dq_delta(c1, c2, mid);
    double u = 1.0 - t;
    double b1 = 1.0 - u * u * u, b2 = t * t * (3.0 - 2.0 * t), b3 = t * t * t;
    dq_mul_exp(a, w0, b1 / 3.0, x);
    dq_mul_exp(x, mid, b2, y);
    dq_mul_exp(y, w1, b3 / 3.0, out);
    dq_normalize(out);
}

/* q and b as doubles, normalised. */
static void dq_unit(mm_quat q, double out[4])
{
    dq_from_quat(q, out);
    dq_normalize(out);
}

/* b or -b, whichever is nearer the curve's end c (the curve arrives at one of them). */
static mm_quat end_key(mm_quat b, const double c[4])
{
    double d = c[0] * b.x + c[1] * b.y + c[2] * b.z + c[3] * b.w;
    return d < 0.0 ? mm_quat_make(-b.x, -b.y, -b.z, -b.w) : b;
}

mm_quat mm_quat_hermite(mm_quat a, mm_vec3 w0, mm_quat b, mm_vec3 w1, float t)
{
    double qa[4], qb[4], v0[3] = {w0.x, w0.y, w0.z}, v1[3] = {w1.x, w1.y, w1.z}, out[4];
    if (!(t > 0.0f)) return a;
    dq_unit(a, qa);
    dq_unit(b, qb);
    dq_hermite(qa, v0, qb, v1, t < 1.0f ? (double)t : 1.0, out);
    return t < 1.0f ? dq_to_quat(out) : end_key(b, out);
}

mm_vec3 mm_quat_catmull_rom_tangent(mm_quat prev, mm_quat q, mm_quat next)
{
    double qp[4], qq[4], qn[4], d0[3], d1[3];
    dq_unit(prev, qp);
    dq_unit(q, qq);
    dq_unit(next, qn);
    dq_delta(qp, qq, d0);
    dq_delta(qq, qn, d1);
    return mm_vec3_make((float)(0.5 * (d0[0] + d1[0])), (float)(0.5 * (d0[1] + d1[1])),
                        (float)(0.5 * (d0[2] + d1[2])));
}

mm_quat mm_quat_catmull_rom(mm_quat q0, mm_quat q1, mm_quat q2, mm_quat q3, float t)
{
    double a[4], b[4], c[4], d[4], d0[3], d1[3], d2[3], w1[3], w2[3], out[4];
    if (!(t > 0.0f)) return q1;
    dq_unit(q0, a);
    dq_unit(q1, b);
    dq_unit(q2, c);
    dq_unit(q3, d);
    dq_delta(a, b, d0);
    dq_delta(b, c, d1);
    dq_delta(c, d, d2);
    for (int k = 0; k < 3; k++) {
        w1[k] = 0.5 * (d0[k] + d1[k]);
        w2[k] = 0.5 * (d1[k] + d2[k]);
    }
    dq_hermite(b, w1, c, w2, t < 1.0f ? (double)t : 1.0, out);
    return t < 1.0f ? dq_to_quat(out) : end_key(q2, out);
}

/* ---- decompositions ------------------------------------------------------------------------ */

void mm_quat_swing_twist(mm_quat quat, mm_vec3 axis, mm_quat *swing, mm_quat *twist)
{
    double q[4], t[4] = {0.0, 0.0, 0.0, 1.0};
    double u[3] = {axis.x, axis.y, axis.z};
    dq_from_quat(quat, q);
    double ulen = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    double qlen = dq_norm(q);
    if (ulen > 1e-12) {
        for (int c = 0; c < 3; c++) u[c] /= ulen;
        /* The twist keeps the part of q's vector along the axis, and w. */
        double p = q[0] * u[0] + q[1] * u[1] + q[2] * u[2];
        double cand[4] = {p * u[0], p * u[1], p * u[2], q[3]};
        /* When both are ~0, q is a half-turn about an axis perpendicular to u and the twist
         * is undetermined: keep the identity. */
        if (dq_norm(cand) > 1e-6 * qlen) {
            for (int c = 0; c < 4; c++) t[c] = cand[c];
            dq_normalize(t);
        }
    }
    if (twist != NULL) *twist = dq_to_quat(t);
    if (swing != NULL) {
        /* swing = q * twist^-1; its vector part w(v - p) - v x p is perpendicular to u. */
        double tc[4] = {-t[0], -t[1], -t[2], t[3]}, sw[4];
        dq_mul(q, tc, sw);
        *swing = dq_to_quat(sw);
    }
}

mm_quat mm_quat_between(mm_vec3 from, mm_vec3 to)
{
    double f[3] = {from.x, from.y, from.z}, t[3] = {to.x, to.y, to.z};
    double fl = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    double tl = sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
    if (fl <= 1e-12 || tl <= 1e-12) return mm_quat_identity();
    for (int c = 0; c < 3; c++) {
        f[c] /= fl;
        t[c] /= tl;
    }
    /* The rotation by angle A about f x t is (f x t, 1 + cos A) up to scale. 1 + cos A is
     * computed as |f + t|^2 / 2, which does not cancel when f and t are nearly opposite. */
    double h[3] = {f[0] + t[0], f[1] + t[1], f[2] + t[2]};
    double q[4];
    q[0] = f[1] * t[2] - f[2] * t[1];
    q[1] = f[2] * t[0] - f[0] * t[2];
    q[2] = f[0] * t[1] - f[1] * t[0];
    q[3] = 0.5 * (h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
    if (dq_norm(q) < 1e-12) {
        /* Opposite: half-turn about an axis perpendicular to f, taken as f x e where e is
         * the basis axis least aligned with f. */
        int e = 0;
        if (fabs(f[1]) < fabs(f[e])) e = 1;
        if (fabs(f[2]) < fabs(f[e])) e = 2;
        double b[3] = {0.0, 0.0, 0.0};
        b[e] = 1.0;
        q[0] = f[1] * b[2] - f[2] * b[1];
        q[1] = f[2] * b[0] - f[0] * b[2];
        q[2] = f[0] * b[1] - f[1] * b[0];
        q[3] = 0.0;
    }
    dq_normalize(q);
    return dq_to_quat(q);
}

/* ---- mat3 --------------------------------------------------------------------------------- */

mm_mat3 mm_mat3_identity(void)
{
    mm_mat3 r;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) r.m[i][j] = i == j ? 1.0f : 0.0f;
    return r;
}

mm_mat3 mm_mat3_mul(mm_mat3 a, mm_mat3 b)
{
    mm_mat3 r;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            r.m[i][j] = a.m[i][0] * b.m[0][j] + a.m[i][1] * b.m[1][j] + a.m[i][2] * b.m[2][j];
    return r;
}

mm_vec3 mm_mat3_mul_vec3(mm_mat3 m, mm_vec3 v)
{
    return mm_vec3_make(m.m[0][0] * v.x + m.m[0][1] * v.y + m.m[0][2] * v.z,
                        m.m[1][0] * v.x + m.m[1][1] * v.y + m.m[1][2] * v.z,
                        m.m[2][0] * v.x + m.m[2][1] * v.y + m.m[2][2] * v.z);
}

mm_mat3 mm_mat3_transpose(mm_mat3 m)
{
    mm_mat3 r;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) r.m[i][j] = m.m[j][i];
    return r;
}
