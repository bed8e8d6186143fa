/* test_math.c - checks mm/math.h against independent constructions.
 *
 * The reference values are built here in double from first principles (single-axis rotation
 * matrices, Rodrigues' formula, hand-written quaternion products) rather than with the library,
 * so a shared mistake in a convention would show up as a failure.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

#include <mm/math.h>

#include "math_private.h"

#define PI      MM_PI
#define HALF_PI (0.5 * MM_PI)

/* ---- deterministic PRNG (splitmix64) ----------------------------------------------------- */

static uint64_t rng_state;

static void rng_seed(uint64_t seed) { rng_state = seed; }

static uint64_t rng_next(void)
{
    uint64_t z = (rng_state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* Uniform in [lo, hi). */
static double rnd(double lo, double hi)
{
    return lo + (hi - lo) * (double)(rng_next() >> 11) * (1.0 / 9007199254740992.0);
}

static mm_vec3 rnd_unit_vec3(void)
{
    for (;;) {
        double x = rnd(-1, 1), y = rnd(-1, 1), z = rnd(-1, 1);
        double n = sqrt(x * x + y * y + z * z);
        if (n > 0.1 && n <= 1.0) return mm_vec3_make((float)(x / n), (float)(y / n), (float)(z / n));
    }
}

/* Uniformly distributed unit quaternion (Shoemake), any sign of w. */
static mm_quat rnd_quat(void)
{
    double u1 = rnd(0, 1), u2 = rnd(0, 2 * PI), u3 = rnd(0, 2 * PI);
    double a = sqrt(1 - u1), b = sqrt(u1);
    return mm_quat_make((float)(a * sin(u2)), (float)(a * cos(u2)), (float)(b * sin(u3)),
                        (float)(b * cos(u3)));
}

/* ---- assertions --------------------------------------------------------------------------- */

static void near_impl(double a, double b, double tol, const char *ea, const char *eb, const char *file,
                      int line)
{
    if (!(fabs(a - b) <= tol)) {
        print_error("%s = %.9g, %s = %.9g, |diff| = %.3g > %.3g\n", ea, a, eb, b, fabs(a - b), tol);
        _fail(file, line);
    }
}
#define ASSERT_NEAR(a, b, tol) near_impl((double)(a), (double)(b), (double)(tol), #a, #b, __FILE__, __LINE__)

static void vec3_near_impl(mm_vec3 a, mm_vec3 b, double tol, const char *ea, const char *eb, const char *file,
                           int line)
{
    double d = fmax(fabs((double)a.x - b.x), fmax(fabs((double)a.y - b.y), fabs((double)a.z - b.z)));
    if (!(d <= tol)) {
        print_error("%s = (%.9g, %.9g, %.9g)\n%s = (%.9g, %.9g, %.9g)\nmax diff %.3g > %.3g\n", ea, a.x, a.y,
                    a.z, eb, b.x, b.y, b.z, d, tol);
        _fail(file, line);
    }
}
#define ASSERT_VEC3_NEAR(a, b, tol) vec3_near_impl((a), (b), (tol), #a, #b, __FILE__, __LINE__)

static double quat_diff(mm_quat a, mm_quat b)
{
    return fmax(fmax(fabs((double)a.x - b.x), fabs((double)a.y - b.y)),
                fmax(fabs((double)a.z - b.z), fabs((double)a.w - b.w)));
}

static void quat_near_impl(mm_quat a, mm_quat b, double tol, int up_to_sign, const char *ea, const char *eb,
                           const char *file, int line)
{
    double d = quat_diff(a, b);
    if (up_to_sign) d = fmin(d, quat_diff(a, mm_quat_make(-b.x, -b.y, -b.z, -b.w)));
    if (!(d <= tol)) {
        print_error("%s = (%.9g, %.9g, %.9g, %.9g)\n%s = (%.9g, %.9g, %.9g, %.9g)\nmax diff %.3g > %.3g\n",
                    ea, a.x, a.y, a.z, a.w, eb, b.x, b.y, b.z, b.w, d, tol);
        _fail(file, line);
    }
}
/* Component-wise, exactly as given. */
#define ASSERT_QUAT_NEAR(a, b, tol) quat_near_impl((a), (b), (tol), 0, #a, #b, __FILE__, __LINE__)
/* The same rotation: q or -q. */
#define ASSERT_SAME_ROT(a, b, tol) quat_near_impl((a), (b), (tol), 1, #a, #b, __FILE__, __LINE__)

/* Rotation angle between a and b, independent of the library: 2 acos |<a, b>| in double. */
static double rot_dist(mm_quat a, mm_quat b)
{
    double na = sqrt((double)a.x * a.x + (double)a.y * a.y + (double)a.z * a.z + (double)a.w * a.w);
    double nb = sqrt((double)b.x * b.x + (double)b.y * b.y + (double)b.z * b.z + (double)b.w * b.w);
    double d = ((double)a.x * b.x + (double)a.y * b.y + (double)a.z * b.z + (double)a.w * b.w) / (na * nb);
    d = fabs(d);
    return 2.0 * acos(d > 1.0 ? 1.0 : d);
}

static void assert_unit(mm_quat q)
{
    ASSERT_NEAR(sqrt((double)q.x * q.x + (double)q.y * q.y + (double)q.z * q.z + (double)q.w * q.w), 1.0,
                1e-6);
}

/* Difference of two angles modulo 2 pi, in [-pi, pi]. */
static double angle_diff(double a, double b) { return remainder(a - b, 2 * PI); }

/* ---- independent references in double ------------------------------------------------------ */

typedef struct dmat {
    double m[3][3];
} dmat;

/* Rotation by angle about the coordinate axis (0 = X, 1 = Y, 2 = Z), written out by hand. */
static dmat axis_mat(int axis, double angle)
{
    double c = cos(angle), s = sin(angle);
    dmat r = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    if (axis == 0) {
        r.m[1][1] = c, r.m[1][2] = -s;
        r.m[2][1] = s, r.m[2][2] = c;
    } else if (axis == 1) {
        r.m[0][0] = c, r.m[0][2] = s;
        r.m[2][0] = -s, r.m[2][2] = c;
    } else {
        r.m[0][0] = c, r.m[0][1] = -s;
        r.m[1][0] = s, r.m[1][1] = c;
    }
    return r;
}

static dmat dmat_mul(dmat a, dmat b)
{
    dmat r;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            r.m[i][j] = a.m[i][0] * b.m[0][j] + a.m[i][1] * b.m[1][j] + a.m[i][2] * b.m[2][j];
    return r;
}

/* Rodrigues: R = I cos t + sin t [k]x + (1 - cos t) k k^T, k unit. */
static dmat rodrigues(mm_vec3 axis, double angle)
{
    double k[3] = {axis.x, axis.y, axis.z};
    double n = sqrt(k[0] * k[0] + k[1] * k[1] + k[2] * k[2]);
    for (int i = 0; i < 3; i++) k[i] /= n;
    double c = cos(angle), s = sin(angle);
    double cross[3][3] = {{0, -k[2], k[1]}, {k[2], 0, -k[0]}, {-k[1], k[0], 0}};
    dmat r;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) r.m[i][j] = (i == j ? c : 0.0) + s * cross[i][j] + (1 - c) * k[i] * k[j];
    return r;
}

static mm_vec3 dmat_apply(dmat m, mm_vec3 v)
{
    double r[3];
    for (int i = 0; i < 3; i++) r[i] = m.m[i][0] * v.x + m.m[i][1] * v.y + m.m[i][2] * v.z;
    return mm_vec3_make((float)r[0], (float)r[1], (float)r[2]);
}

static void mat_near_impl(mm_mat3 a, dmat b, double tol, const char *file, int line)
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            if (!(fabs(a.m[i][j] - b.m[i][j]) <= tol)) {
                print_error("matrix element [%d][%d]: %.9g vs expected %.9g (tol %.3g)\n", i, j, a.m[i][j],
                            b.m[i][j], tol);
                _fail(file, line);
            }
}
#define ASSERT_MAT_NEAR(a, b, tol) mat_near_impl((a), (b), (tol), __FILE__, __LINE__)

static dmat dmat_from_mat3(mm_mat3 m)
{
    dmat r;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) r.m[i][j] = m.m[i][j];
    return r;
}

static const dmat DMAT_IDENTITY = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};

/* The quaternion of a rotation about a unit axis, from the textbook definition. */
static mm_quat ref_quat(mm_vec3 axis, double angle)
{
    double n = sqrt((double)axis.x * axis.x + (double)axis.y * axis.y + (double)axis.z * axis.z);
    double s = sin(0.5 * angle) / n;
    return mm_quat_make((float)(axis.x * s), (float)(axis.y * s), (float)(axis.z * s),
                        (float)cos(0.5 * angle));
}

static float vec_comp(mm_vec3 v, int i) { return i == 0 ? v.x : i == 1 ? v.y : v.z; }

static mm_vec3 vec_from3(const double a[3]) { return mm_vec3_make((float)a[0], (float)a[1], (float)a[2]); }

/* Axes of each Euler order, first to last, written independently of the library. */
static const struct {
    mm_euler_order order;
    const char *name;
    int axes[3];
} ORDERS[6] = {
    {MM_EULER_XYZ, "XYZ", {0, 1, 2}}, {MM_EULER_XZY, "XZY", {0, 2, 1}}, {MM_EULER_YXZ, "YXZ", {1, 0, 2}},
    {MM_EULER_YZX, "YZX", {1, 2, 0}}, {MM_EULER_ZXY, "ZXY", {2, 0, 1}}, {MM_EULER_ZYX, "ZYX", {2, 1, 0}},
};

static const mm_vec3 X = {1, 0, 0}, Y = {0, 1, 0}, Z = {0, 0, 1};

/* ---- Euler order names ---------------------------------------------------------------------- */

static void test_euler_order_names(void **state)
{
    (void)state;
    for (int o = 0; o < 6; o++) {
        assert_string_equal(mm_euler_order_name(ORDERS[o].order), ORDERS[o].name);
        assert_int_equal(mm_euler_order_parse(ORDERS[o].name), ORDERS[o].order);
    }
    assert_int_equal(mm_euler_order_parse("zyx"), MM_EULER_ZYX);
    assert_int_equal(mm_euler_order_parse("yXz"), MM_EULER_YXZ);
    assert_null(mm_euler_order_name(MM_EULER_NONE));
    assert_null(mm_euler_order_name((mm_euler_order)42));
    assert_null(mm_euler_order_name((mm_euler_order)-1));
    const char *bad[] = {"", "X", "XY", "XYZW", "XXY", "ABC", "XYZ ", " XYZ", "xy"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
        assert_int_equal(mm_euler_order_parse(bad[i]), MM_EULER_NONE);
    assert_int_equal(mm_euler_order_parse(NULL), MM_EULER_NONE);
}

/* ---- basic quaternion algebra --------------------------------------------------------------- */

static void test_quat_inverse(void **state)
{
    (void)state;
    rng_seed(1);
    mm_quat id = mm_quat_identity();
    for (int n = 0; n < 1000; n++) {
        mm_quat u = rnd_quat();
        float s = (float)rnd(0.3, 3.0);
        mm_quat q = mm_quat_make(u.x * s, u.y * s, u.z * s, u.w * s); /* not unit */
        ASSERT_QUAT_NEAR(mm_quat_mul(q, mm_quat_inverse(q)), id, 1e-6);
        ASSERT_QUAT_NEAR(mm_quat_mul(mm_quat_inverse(q), q), id, 1e-6);
        ASSERT_QUAT_NEAR(mm_quat_inverse(u), mm_quat_conj(u), 1e-6);
        mm_vec3 v = mm_vec3_scale(rnd_unit_vec3(), (float)rnd(0.1, 10));
        ASSERT_VEC3_NEAR(mm_quat_inv_rotate(u, mm_quat_rotate(u, v)), v, 1e-5);
        ASSERT_VEC3_NEAR(mm_quat_rotate(mm_quat_inverse(u), mm_quat_rotate(u, v)), v, 1e-5);
        ASSERT_QUAT_NEAR(mm_quat_normalize(q), u, 1e-6);
    }
    ASSERT_QUAT_NEAR(mm_quat_inverse(mm_quat_make(0, 0, 0, 0)), id, 0);
    ASSERT_QUAT_NEAR(mm_quat_normalize(mm_quat_make(0, 0, 0, 0)), id, 0);
    mm_quat neg = mm_quat_make(0.5f, -0.5f, 0.5f, -0.5f);
    ASSERT_QUAT_NEAR(mm_quat_abs(neg), mm_quat_make(-0.5f, 0.5f, -0.5f, 0.5f), 0);
}

static void test_known_rotations(void **state)
{
    (void)state;
    float q90 = (float)HALF_PI;
    mm_quat rz = mm_quat_from_axis_angle(Z, q90);
    mm_quat ry = mm_quat_from_axis_angle(Y, q90);
    mm_quat rx = mm_quat_from_axis_angle(X, q90);
    float h = (float)sqrt(0.5);
    ASSERT_QUAT_NEAR(rz, mm_quat_make(0, 0, h, h), 1e-7);
    ASSERT_QUAT_NEAR(ry, mm_quat_make(0, h, 0, h), 1e-7);
    ASSERT_QUAT_NEAR(rx, mm_quat_make(h, 0, 0, h), 1e-7);

    /* Right-handed: X -> Y about Z, Z -> X about Y (so X -> -Z), Y -> Z about X. */
    ASSERT_VEC3_NEAR(mm_quat_rotate(rz, X), Y, 1e-6);
    ASSERT_VEC3_NEAR(mm_quat_rotate(rz, Y), mm_vec3_neg(X), 1e-6);
    ASSERT_VEC3_NEAR(mm_quat_rotate(ry, X), mm_vec3_make(0, 0, -1), 1e-6);
    ASSERT_VEC3_NEAR(mm_quat_rotate(ry, Z), X, 1e-6);
    ASSERT_VEC3_NEAR(mm_quat_rotate(rx, Y), Z, 1e-6);
    ASSERT_VEC3_NEAR(mm_quat_rotate(rx, Z), mm_vec3_make(0, -1, 0), 1e-6);

    mm_mat3 mz = mm_quat_to_mat3(rz);
    dmat ez = {{{0, -1, 0}, {1, 0, 0}, {0, 0, 1}}};
    ASSERT_MAT_NEAR(mz, ez, 1e-6);
    ASSERT_VEC3_NEAR(mm_mat3_mul_vec3(mz, X), Y, 1e-6);
    dmat ey = {{{0, 0, 1}, {0, 1, 0}, {-1, 0, 0}}};
    ASSERT_MAT_NEAR(mm_quat_to_mat3(ry), ey, 1e-6);
    dmat ex = {{{1, 0, 0}, {0, 0, -1}, {0, 1, 0}}};
    ASSERT_MAT_NEAR(mm_quat_to_mat3(rx), ex, 1e-6);

    /* Axis length does not matter; a zero axis is the identity. */
    ASSERT_QUAT_NEAR(mm_quat_from_axis_angle(mm_vec3_make(0, 0, 5), q90), rz, 1e-7);
    ASSERT_QUAT_NEAR(mm_quat_from_axis_angle(mm_vec3_make(0, 0, 0), 1.0f), mm_quat_identity(), 0);
    /* 180 degrees about Y maps X to -X. */
    ASSERT_VEC3_NEAR(mm_quat_rotate(mm_quat_from_axis_angle(Y, (float)PI), X), mm_vec3_neg(X), 1e-6);
}

static void test_rotate_matches_rodrigues(void **state)
{
    (void)state;
    rng_seed(2);
    for (int n = 0; n < 1000; n++) {
        mm_vec3 axis = mm_vec3_scale(rnd_unit_vec3(), (float)rnd(0.2, 5));
        float angle = (float)rnd(-2 * PI, 2 * PI);
        mm_vec3 v = mm_vec3_scale(rnd_unit_vec3(), (float)rnd(0.1, 10));
        dmat r = rodrigues(axis, angle);
        mm_quat q = mm_quat_from_axis_angle(axis, angle);
        assert_unit(q);
        ASSERT_QUAT_NEAR(q, ref_quat(axis, angle), 1e-6);
        ASSERT_VEC3_NEAR(mm_quat_rotate(q, v), dmat_apply(r, v), 1e-5);
        ASSERT_MAT_NEAR(mm_quat_to_mat3(q), r, 1e-6);
        ASSERT_VEC3_NEAR(mm_mat3_mul_vec3(mm_quat_to_mat3(q), v), dmat_apply(r, v), 1e-5);
    }
}

static void test_mul_composes(void **state)
{
    (void)state;
    rng_seed(3);
    for (int n = 0; n < 1000; n++) {
        mm_quat a = rnd_quat(), b = rnd_quat();
        mm_vec3 v = mm_vec3_scale(rnd_unit_vec3(), (float)rnd(0.1, 10));
        /* a * b applies b first. */
        ASSERT_VEC3_NEAR(mm_quat_rotate(mm_quat_mul(a, b), v), mm_quat_rotate(a, mm_quat_rotate(b, v)), 2e-5);
        dmat ab = dmat_mul(dmat_from_mat3(mm_quat_to_mat3(a)), dmat_from_mat3(mm_quat_to_mat3(b)));
        ASSERT_MAT_NEAR(mm_quat_to_mat3(mm_quat_mul(a, b)), ab, 2e-6);
        ASSERT_MAT_NEAR(mm_mat3_mul(mm_quat_to_mat3(a), mm_quat_to_mat3(b)), ab, 2e-6);
    }
}

/* ---- mat3 ---------------------------------------------------------------------------------------- */

static void test_mat3_ops(void **state)
{
    (void)state;
    mm_mat3 a = {{{1, 2, 3}, {4, 5, 6}, {7, 8, 10}}};
    mm_mat3 b = {{{2, 0, 1}, {1, 3, 0}, {0, 1, 4}}};
    dmat ab = {{{4, 9, 13}, {13, 21, 28}, {22, 34, 47}}}; /* by hand */
    ASSERT_MAT_NEAR(mm_mat3_mul(a, b), ab, 0);
    ASSERT_VEC3_NEAR(mm_mat3_mul_vec3(a, mm_vec3_make(1, -1, 2)), mm_vec3_make(5, 11, 19), 0);
    dmat at = {{{1, 4, 7}, {2, 5, 8}, {3, 6, 10}}};
    ASSERT_MAT_NEAR(mm_mat3_transpose(a), at, 0);
    ASSERT_MAT_NEAR(mm_mat3_identity(), DMAT_IDENTITY, 0);
    ASSERT_MAT_NEAR(mm_mat3_mul(a, mm_mat3_identity()), dmat_from_mat3(a), 0);
    ASSERT_MAT_NEAR(mm_mat3_mul(mm_mat3_identity(), a), dmat_from_mat3(a), 0);

    rng_seed(4);
    for (int n = 0; n < 500; n++) {
        mm_quat q = rnd_quat();
        mm_mat3 m = mm_quat_to_mat3(q);
        /* Orthonormal with determinant +1; the transpose is the inverse rotation. */
        ASSERT_MAT_NEAR(mm_mat3_mul(m, mm_mat3_transpose(m)), DMAT_IDENTITY, 1e-6);
        double det = m.m[0][0] * ((double)m.m[1][1] * m.m[2][2] - (double)m.m[1][2] * m.m[2][1]) -
                     m.m[0][1] * ((double)m.m[1][0] * m.m[2][2] - (double)m.m[1][2] * m.m[2][0]) +
                     m.m[0][2] * ((double)m.m[1][0] * m.m[2][1] - (double)m.m[1][1] * m.m[2][0]);
        ASSERT_NEAR(det, 1.0, 1e-6);
        ASSERT_MAT_NEAR(mm_mat3_transpose(m), dmat_from_mat3(mm_quat_to_mat3(mm_quat_conj(q))), 1e-6);
    }
}

static mm_mat3 mat3_from_dmat(dmat d)
{
    mm_mat3 m;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) m.m[i][j] = (float)d.m[i][j];
    return m;
}

static void test_mat3_roundtrip(void **state)
{
    (void)state;
    rng_seed(5);
    for (int n = 0; n < 5000; n++) {
        mm_quat q = rnd_quat();
        mm_quat r = mm_quat_from_mat3(mm_quat_to_mat3(q));
        assert_true(r.w >= 0.0f);
        assert_unit(r);
        ASSERT_QUAT_NEAR(r, mm_quat_abs(q), 2e-6);
    }
    ASSERT_QUAT_NEAR(mm_quat_from_mat3(mm_mat3_identity()), mm_quat_identity(), 0);

    /* Matrices built by Rodrigues' formula, covering each Shepperd branch: small angles (the
     * trace is largest) and half turns about axes near X, Y and Z (one diagonal term largest). */
    mm_vec3 axes[] = {X, Y, Z, {1, 1, 1}, {-1, 2, 0.5f}, {0.1f, -0.2f, 3}, {3, 0.1f, 0.2f}, {0.2f, -4, 0.3f}};
    double angles[] = {PI, PI - 1e-3, PI - 1e-6, 3.0, 2.0, 1.0, 1e-3, 1e-6, 0.0};
    for (size_t i = 0; i < sizeof axes / sizeof axes[0]; i++)
        for (size_t j = 0; j < sizeof angles / sizeof angles[0]; j++) {
            mm_quat r = mm_quat_from_mat3(mat3_from_dmat(rodrigues(axes[i], angles[j])));
            assert_true(r.w >= 0.0f);
            assert_unit(r);
            ASSERT_SAME_ROT(r, ref_quat(axes[i], angles[j]), 2e-6);
        }

    /* Slightly off orthonormal (as after accumulating float error): still a unit quaternion,
     * close to the rotation. */
    rng_seed(55);
    for (int n = 0; n < 500; n++) {
        mm_quat q = rnd_quat();
        mm_mat3 m = mm_quat_to_mat3(q);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) m.m[i][j] += (float)rnd(-1e-4, 1e-4);
        mm_quat r = mm_quat_from_mat3(m);
        assert_true(r.w >= 0.0f);
        assert_unit(r);
        assert_true(rot_dist(r, q) < 1e-3);
    }
}

/* ---- log / exp -------------------------------------------------------------------------------- */

static void test_log_exp_random(void **state)
{
    (void)state;
    rng_seed(6);
    for (int n = 0; n < 5000; n++) {
        mm_quat q = rnd_quat();
        mm_vec3 v = mm_quat_log(q);
        double len = mm_vec3_length(v);
        assert_true(len <= PI + 1e-6);
        ASSERT_NEAR(len, rot_dist(q, mm_quat_identity()), 1e-5);
        ASSERT_SAME_ROT(mm_quat_exp(v), q, 2e-6);
        /* -q is the same rotation and has the same (shortest) log. */
        ASSERT_VEC3_NEAR(mm_quat_log(mm_quat_make(-q.x, -q.y, -q.z, -q.w)), v, 0);
        /* Direction: along the vector part of the w >= 0 representative. */
        mm_quat p = mm_quat_abs(q);
        mm_vec3 u = mm_vec3_make(p.x, p.y, p.z);
        ASSERT_VEC3_NEAR(mm_vec3_cross(v, u), mm_vec3_make(0, 0, 0), 1e-5);
        assert_true(mm_vec3_dot(v, u) >= 0.0f);
        /* And back: log(exp(v)) = v for any |v| < pi. */
        mm_vec3 w = mm_vec3_scale(rnd_unit_vec3(), (float)rnd(0, PI - 1e-3));
        ASSERT_VEC3_NEAR(mm_quat_log(mm_quat_exp(w)), w, 1e-5);
    }
}

static void test_log_exp_angles(void **state)
{
    (void)state;
    rng_seed(7);
    const double angles[] = {0,   1e-30, 1e-12, 1e-9, 1e-7, 1e-6,      1e-5,      1e-4, 1e-3,
                             0.1, 1,     2,     3,    3.1,  PI - 1e-3, PI - 1e-5, PI};
    for (int n = 0; n < 20; n++) {
        mm_vec3 axis = n < 3 ? (n == 0 ? X : n == 1 ? Y : Z) : rnd_unit_vec3();
        for (size_t i = 0; i < sizeof angles / sizeof angles[0]; i++) {
            double a = angles[i];
            mm_quat q = ref_quat(axis, a);
            mm_vec3 expect = mm_vec3_scale(axis, (float)a);
            /* Relative accuracy even for tiny angles (series branch). */
            ASSERT_VEC3_NEAR(mm_quat_log(q), expect, 2e-6 * a);
            mm_quat e = mm_quat_exp(expect);
            ASSERT_QUAT_NEAR(e, q, 1e-6);
            ASSERT_VEC3_NEAR(mm_vec3_make(e.x, e.y, e.z), mm_vec3_make(q.x, q.y, q.z), 2e-6 * a);
            ASSERT_SAME_ROT(mm_quat_exp(mm_quat_log(q)), q, 1e-6);
        }
        /* exp does not fold angles above pi: it is the rotation of exactly |v|. */
        const double big[] = {3.5, 4, 5, 6, 2 * PI - 1e-3};
        for (size_t i = 0; i < sizeof big / sizeof big[0]; i++) {
            mm_quat q = ref_quat(axis, big[i]);
            ASSERT_QUAT_NEAR(mm_quat_exp(mm_vec3_scale(axis, (float)big[i])), q, 1e-6);
            /* log picks the shortest: the same rotation as -(2pi - angle) about axis. */
            ASSERT_VEC3_NEAR(mm_quat_log(q), mm_vec3_scale(axis, (float)(big[i] - 2 * PI)), 2e-6);
        }
        /* Close to -identity (w ~ -1): a small rotation, accurate relatively. */
        mm_vec3 v = mm_quat_log(ref_quat(axis, 2 * PI - 1e-6));
        ASSERT_VEC3_NEAR(v, mm_vec3_scale(axis, -1e-6f), 1e-11);
    }
    ASSERT_QUAT_NEAR(mm_quat_exp(mm_vec3_make(0, 0, 0)), mm_quat_identity(), 0);
    ASSERT_VEC3_NEAR(mm_quat_log(mm_quat_identity()), mm_vec3_make(0, 0, 0), 0);
    ASSERT_VEC3_NEAR(mm_quat_log(mm_quat_make(0, 0, 0, -1)), mm_vec3_make(0, 0, 0), 0);
    /* Known value: 90 degrees about Z. */
    ASSERT_VEC3_NEAR(mm_quat_log(mm_quat_make(0, 0, (float)sqrt(0.5), (float)sqrt(0.5))),
                     mm_vec3_make(0, 0, (float)HALF_PI), 1e-6);
}

/* ---- Euler angles ------------------------------------------------------------------------------- */

static dmat euler_ref_mat(const double ang[3], int o)
{
    const int *ax = ORDERS[o].axes;
    return dmat_mul(dmat_mul(axis_mat(ax[0], ang[ax[0]]), axis_mat(ax[1], ang[ax[1]])),
                    axis_mat(ax[2], ang[ax[2]]));
}

static void test_euler_matches_axis_matrices(void **state)
{
    (void)state;
    rng_seed(8);
    for (int o = 0; o < 6; o++)
        for (int n = 0; n < 1000; n++) {
            double ang[3] = {rnd(-2 * PI, 2 * PI), rnd(-2 * PI, 2 * PI), rnd(-2 * PI, 2 * PI)};
            for (int c = 0; c < 3; c++) ang[c] = (float)ang[c]; /* what the float API sees */
            mm_quat q = mm_quat_from_euler(vec_from3(ang), ORDERS[o].order);
            assert_unit(q);
            dmat ref = euler_ref_mat(ang, o);
            ASSERT_MAT_NEAR(mm_quat_to_mat3(q), ref, 2e-6);
            mm_vec3 v = rnd_unit_vec3();
            ASSERT_VEC3_NEAR(mm_quat_rotate(q, v), dmat_apply(ref, v), 2e-6);
        }
}

static void test_euler_known(void **state)
{
    (void)state;
    float r90 = (float)HALF_PI;
    mm_vec3 xz = mm_vec3_make(r90, 0, r90); /* 90 degrees about X and about Z */
    /* ZYX = Rz * Rx: Y goes to Z under Rx, which Rz leaves alone. */
    ASSERT_VEC3_NEAR(mm_quat_rotate(mm_quat_from_euler(xz, MM_EULER_ZYX), Y), Z, 1e-6);
    /* XYZ = Rx * Rz: Y goes to -X under Rz, which Rx leaves alone. */
    ASSERT_VEC3_NEAR(mm_quat_rotate(mm_quat_from_euler(xz, MM_EULER_XYZ), Y), mm_vec3_neg(X), 1e-6);
    /* YXZ with 90 about Y and X: Rx takes Y to Z, Ry takes Z to X. */
    ASSERT_VEC3_NEAR(mm_quat_rotate(mm_quat_from_euler(mm_vec3_make(r90, r90, 0), MM_EULER_YXZ), Y), X, 1e-6);

    rng_seed(9);
    for (int n = 0; n < 200; n++) {
        float a = (float)rnd(-PI, PI), b = (float)rnd(-PI, PI), c = (float)rnd(-PI, PI);
        for (int o = 0; o < 6; o++) {
            mm_euler_order ord = ORDERS[o].order;
            /* A single non-zero angle is a plain axis rotation whatever the order. */
            ASSERT_SAME_ROT(mm_quat_from_euler(mm_vec3_make(a, 0, 0), ord), ref_quat(X, a), 1e-6);
            ASSERT_SAME_ROT(mm_quat_from_euler(mm_vec3_make(0, a, 0), ord), ref_quat(Y, a), 1e-6);
            ASSERT_SAME_ROT(mm_quat_from_euler(mm_vec3_make(0, 0, a), ord), ref_quat(Z, a), 1e-6);
        }
        /* ZYX is Rz(z) * Ry(y) * Rx(x) as quaternions too. */
        mm_quat zyx = mm_quat_mul(ref_quat(Z, c), mm_quat_mul(ref_quat(Y, b), ref_quat(X, a)));
        ASSERT_SAME_ROT(mm_quat_from_euler(mm_vec3_make(a, b, c), MM_EULER_ZYX), zyx, 2e-6);
        mm_quat yzx = mm_quat_mul(ref_quat(Y, b), mm_quat_mul(ref_quat(Z, c), ref_quat(X, a)));
        ASSERT_SAME_ROT(mm_quat_from_euler(mm_vec3_make(a, b, c), MM_EULER_YZX), yzx, 2e-6);
    }
    /* Back from a known rotation: 90 degrees about Z in ZYX is (0, 0, pi/2). */
    ASSERT_VEC3_NEAR(mm_quat_to_euler(ref_quat(Z, HALF_PI), MM_EULER_ZYX), mm_vec3_make(0, 0, r90), 1e-6);
    ASSERT_VEC3_NEAR(mm_quat_to_euler(ref_quat(X, -1.0), MM_EULER_YZX), mm_vec3_make(-1, 0, 0), 1e-6);
    ASSERT_VEC3_NEAR(mm_quat_to_euler(mm_quat_identity(), MM_EULER_XZY), mm_vec3_make(0, 0, 0), 0);
}

static void check_euler_ranges(mm_vec3 e, int o)
{
    const int *ax = ORDERS[o].axes;
    assert_true(fabs(vec_comp(e, ax[1])) <= HALF_PI + 1e-6);
    assert_true(fabs(vec_comp(e, ax[0])) <= PI + 1e-6);
    assert_true(fabs(vec_comp(e, ax[2])) <= PI + 1e-6);
}

static void test_euler_roundtrip_rotation(void **state)
{
    (void)state;
    rng_seed(10);
    for (int o = 0; o < 6; o++) {
        mm_euler_order ord = ORDERS[o].order;
        const int *ax = ORDERS[o].axes;
        for (int n = 0; n < 2000; n++) {
            /* Any rotation. */
            mm_quat q = rnd_quat();
            mm_vec3 e = mm_quat_to_euler(q, ord);
            check_euler_ranges(e, o);
            double d = rot_dist(mm_quat_from_euler(e, ord), q);
            assert_true(d < 1e-5);

            /* Angles with the middle one anywhere in (-pi/2, pi/2), outer ones beyond pi. */
            double ang[3];
            ang[ax[0]] = rnd(-2 * PI, 2 * PI);
            ang[ax[1]] = rnd(-HALF_PI, HALF_PI);
            ang[ax[2]] = rnd(-2 * PI, 2 * PI);
            q = mm_quat_from_euler(vec_from3(ang), ord);
            e = mm_quat_to_euler(q, ord);
            check_euler_ranges(e, o);
            ASSERT_MAT_NEAR(mm_quat_to_mat3(mm_quat_from_euler(e, ord)), euler_ref_mat(ang, o), 1e-5);
        }
        /* Approaching gimbal lock from both sides, down to and past float resolution. */
        const double deltas[] = {1e-2, 1e-3, 1e-4, 1e-5, 3e-6, 1e-6, 5e-7, 2e-7, 1e-7, 3e-8, 0};
        for (size_t i = 0; i < sizeof deltas / sizeof deltas[0]; i++)
            for (int n = 0; n < 50; n++) {
                double ang[3];
                ang[ax[0]] = rnd(-PI, PI);
                ang[ax[1]] = (n & 1 ? 1 : -1) * (HALF_PI - deltas[i]);
                ang[ax[2]] = rnd(-PI, PI);
                mm_quat q = mm_quat_from_euler(vec_from3(ang), ord);
                mm_vec3 e = mm_quat_to_euler(q, ord);
                check_euler_ranges(e, o);
                double d = rot_dist(mm_quat_from_euler(e, ord), q);
                assert_true(d < 1e-5);
            }
    }
}

static void test_euler_roundtrip_angles(void **state)
{
    (void)state;
    rng_seed(11);
    for (int o = 0; o < 6; o++) {
        mm_euler_order ord = ORDERS[o].order;
        for (int n = 0; n < 3000; n++) {
            /* Away from gimbal lock the angles themselves are unique (outer ones in (-pi, pi)). */
            double ang[3];
            const int *ax = ORDERS[o].axes;
            ang[ax[0]] = rnd(-PI + 1e-3, PI - 1e-3);
            ang[ax[1]] = rnd(-HALF_PI + 0.05, HALF_PI - 0.05);
            ang[ax[2]] = rnd(-PI + 1e-3, PI - 1e-3);
            mm_vec3 e = mm_quat_to_euler(mm_quat_from_euler(vec_from3(ang), ord), ord);
            for (int c = 0; c < 3; c++) ASSERT_NEAR(angle_diff(vec_comp(e, c), ang[c]), 0, 1e-5);
        }
    }
    /* Exact half turns put the outer angles at +-pi: they must come back as +pi, never -pi. */
    const mm_quat half[] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {-1, 0, 0, 0}, {0, 0, -1, 0}};
    for (int o = 0; o < 6; o++)
        for (size_t i = 0; i < sizeof half / sizeof half[0]; i++) {
            mm_vec3 e = mm_quat_to_euler(half[i], ORDERS[o].order);
            for (int c = 0; c < 3; c++) assert_true((double)vec_comp(e, c) > -PI);
            assert_true(rot_dist(mm_quat_from_euler(e, ORDERS[o].order), half[i]) < 1e-6);
        }
    /* Outer angles beyond pi come back wrapped into (-pi, pi]. */
    mm_vec3 e =
        mm_quat_to_euler(mm_quat_from_euler(mm_vec3_make(4.0f, 0.5f, -4.0f), MM_EULER_ZYX), MM_EULER_ZYX);
    ASSERT_VEC3_NEAR(e, mm_vec3_make((float)(4.0 - 2 * PI), 0.5f, (float)(2 * PI - 4.0)), 1e-5);
}

static void test_euler_gimbal_lock(void **state)
{
    (void)state;
    rng_seed(12);
    float lock = (float)HALF_PI;
    for (int o = 0; o < 6; o++) {
        mm_euler_order ord = ORDERS[o].order;
        const int *ax = ORDERS[o].axes;
        for (int n = 0; n < 500; n++) {
            double ang[3];
            double sign = (n & 1) ? 1.0 : -1.0;
            ang[ax[0]] = rnd(-PI, PI);
            ang[ax[1]] = sign * lock;
            ang[ax[2]] = rnd(-PI, PI);
            mm_quat q = mm_quat_from_euler(vec_from3(ang), ord);
            mm_vec3 e = mm_quat_to_euler(q, ord);
            assert_true(vec_comp(e, ax[2]) == 0.0f); /* third angle set to 0 */
            ASSERT_NEAR(vec_comp(e, ax[1]), sign * HALF_PI, 2e-6);
            assert_true(rot_dist(mm_quat_from_euler(e, ord), q) < 1e-5);
        }
    }
    /* By hand: Ry(pi/2) Rz(c) = Rx(c) Ry(pi/2) (Ry(pi/2) takes Z to X), so XYZ (a, pi/2, c)
     * is (a + c, pi/2, 0); with -pi/2 it is (a - c, -pi/2, 0). Likewise Ry(pi/2) takes X to
     * -Z, so ZYX (a, pi/2, c) about (Z, Y, X) is (a - c, pi/2, 0). */
    mm_vec3 e =
        mm_quat_to_euler(mm_quat_from_euler(mm_vec3_make(0.5f, lock, 0.25f), MM_EULER_XYZ), MM_EULER_XYZ);
    ASSERT_VEC3_NEAR(e, mm_vec3_make(0.75f, lock, 0), 2e-6);
    e = mm_quat_to_euler(mm_quat_from_euler(mm_vec3_make(0.5f, -lock, 0.25f), MM_EULER_XYZ), MM_EULER_XYZ);
    ASSERT_VEC3_NEAR(e, mm_vec3_make(0.25f, -lock, 0), 2e-6);
    e = mm_quat_to_euler(mm_quat_from_euler(mm_vec3_make(0.25f, lock, 0.5f), MM_EULER_ZYX), MM_EULER_ZYX);
    ASSERT_VEC3_NEAR(e, mm_vec3_make(0, lock, 0.25f), 2e-6);
    e = mm_quat_to_euler(mm_quat_from_euler(mm_vec3_make(0.25f, -lock, 0.5f), MM_EULER_ZYX), MM_EULER_ZYX);
    ASSERT_VEC3_NEAR(e, mm_vec3_make(0, -lock, 0.75f), 2e-6);
}

static void test_euler_invalid_order(void **state)
{
    (void)state;
    mm_vec3 ang = mm_vec3_make(0.1f, 0.2f, 0.3f);
    ASSERT_QUAT_NEAR(mm_quat_from_euler(ang, MM_EULER_NONE), mm_quat_identity(), 0);
    ASSERT_QUAT_NEAR(mm_quat_from_euler(ang, (mm_euler_order)99), mm_quat_identity(), 0);
    ASSERT_VEC3_NEAR(mm_quat_to_euler(ref_quat(X, 1.0), MM_EULER_NONE), mm_vec3_make(0, 0, 0), 0);
}

/* ---- interpolation ------------------------------------------------------------------------- */

static void test_slerp_endpoints(void **state)
{
    (void)state;
    rng_seed(13);
    for (int n = 0; n < 1000; n++) {
        mm_quat a = rnd_quat(), b = rnd_quat();
        ASSERT_QUAT_NEAR(mm_quat_slerp(a, b, 0.0f), a, 1e-6);
        ASSERT_SAME_ROT(mm_quat_slerp(a, b, 1.0f), b, 1e-6);
        assert_unit(mm_quat_slerp(a, b, (float)rnd(0, 1)));
        ASSERT_QUAT_NEAR(mm_quat_slerp(a, a, (float)rnd(0, 1)), a, 1e-6);
    }
}

static void test_slerp_path(void **state)
{
    (void)state;
    rng_seed(14);
    for (int n = 0; n < 500; n++) {
        mm_quat a = rnd_quat();
        mm_vec3 axis = rnd_unit_vec3();
        double theta = rnd(0.01, PI - 0.01); /* rotation angle from a to b */
        mm_quat b = mm_quat_mul(a, ref_quat(axis, theta));
        if (n & 1) b = mm_quat_make(-b.x, -b.y, -b.z, -b.w); /* the sign of b must not matter */
        ASSERT_NEAR(mm_quat_angle_between(a, mm_quat_slerp(a, b, 0.5f)), theta / 2, 1e-5);
        mm_quat prev = a;
        for (int k = 1; k <= 20; k++) {
            double t = k / 20.0;
            mm_quat s = mm_quat_slerp(a, b, (float)t);
            /* On the great arc: a followed by part of the same axis rotation. */
            ASSERT_SAME_ROT(s, mm_quat_mul(a, ref_quat(axis, t * theta)), 2e-6);
            ASSERT_NEAR(rot_dist(a, s), t * theta, 1e-5);
            /* Constant angular speed. */
            ASSERT_NEAR(rot_dist(prev, s), theta / 20, 1e-5);
            prev = s;
        }
    }
}

/* The series form of slerp (neighbouring frames): on the great arc as the reference rotation puts
 * it, and within a float rounding of mm_quat_slerp, from nearly parallel to past its series' reach
 * (0.3 rad between the quaternions: 0.6 rad of rotation), either sign. */
static void test_slerp_series(void **state)
{
    (void)state;
    rng_seed(19);
    for (int n = 0; n < 4000; n++) {
        mm_quat a = rnd_quat();
        mm_vec3 axis = rnd_unit_vec3();
        double theta = pow(10.0, rnd(-6.0, 0.0)); /* rotation angle from a to b: 1e-6 to 1 rad */
        mm_quat b = mm_quat_mul(a, ref_quat(axis, theta));
        if (n & 1) b = mm_quat_make(-b.x, -b.y, -b.z, -b.w);
        float t = (float)rnd(0.0, 1.0);
        mm_quat s = mm__quat_slerp_series(a, b, t), exact = mm_quat_slerp(a, b, t);
        ASSERT_SAME_ROT(s, mm_quat_mul(a, ref_quat(axis, t * theta)), 2e-6);
        ASSERT_NEAR(s.x, exact.x, 1.2e-7);
        ASSERT_NEAR(s.y, exact.y, 1.2e-7);
        ASSERT_NEAR(s.z, exact.z, 1.2e-7);
        ASSERT_NEAR(s.w, exact.w, 1.2e-7);
    }
}

/* Many series slerps at once (mm__quat_slerp_series_n, four at a time in AVX where the machine has
 * it, two in SSE2, and the rest alone; both packed paths run): the bits of one mm__quat_slerp_series
 * each, for pairs nearly parallel (the linear weights), close, past the series' reach, of either
 * sign, zero quaternions and NaN among them, and counts of every remainder. */
static void test_slerp_series_n(void **state)
{
    (void)state;
    enum { PAIRS = 37 };
    mm_quat a[PAIRS], b[PAIRS], many[PAIRS];
    for (int wide = 1; wide >= 0; --wide) {
        mm__math_wide_kernels(wide);
        rng_seed(23);
        for (int n = 0; n < 400; n++) {
            for (int i = 0; i < PAIRS; ++i) {
                a[i] = rnd_quat();
                mm_vec3 axis = rnd_unit_vec3();
                double theta = pow(10.0, rnd(-9.0, 0.3)); /* 1e-9 to 2 rad */
                b[i] = mm_quat_mul(a[i], ref_quat(axis, theta));
                if ((n + i) & 1) b[i] = mm_quat_make(-b[i].x, -b[i].y, -b[i].z, -b[i].w);
                if (i % 5 == 0) b[i] = a[i]; /* the same rotation */
            }
            if (n % 10 == 1) a[3] = mm_quat_make(0, 0, 0, 0);
            if (n % 10 == 2) b[8] = mm_quat_make(NAN, 0, 0, 1);
            float t = n % 7 == 0 ? 0.0f : n % 7 == 1 ? 1.0f : (float)rnd(0.0, 1.0);
            int count = PAIRS - n % 4;
            mm__quat_slerp_series_n(a, b, t, count, many);
            for (int i = 0; i < count; ++i) {
                mm_quat one = mm__quat_slerp_series(a[i], b[i], t);
                assert_memory_equal(&many[i], &one, sizeof one);
            }
        }
    }
    mm__math_wide_kernels(true);
}

/* The series form of exp (small offsets): the reference rotation about the axis, and within a float
 * rounding of mm_quat_exp, from 1e-7 rad to past its series' reach (0.6 rad). */
static void test_exp_series(void **state)
{
    (void)state;
    rng_seed(20);
    for (int n = 0; n < 4000; n++) {
        mm_vec3 axis = rnd_unit_vec3();
        double angle = pow(10.0, rnd(-7.0, 0.5));
        mm_vec3 v = mm_vec3_make((float)(axis.x * angle), (float)(axis.y * angle), (float)(axis.z * angle));
        mm_quat s = mm__quat_exp_series(v), exact = mm_quat_exp(v);
        ASSERT_SAME_ROT(s, ref_quat(axis, angle), 2e-6);
        ASSERT_NEAR(s.x, exact.x, 1.2e-7);
        ASSERT_NEAR(s.y, exact.y, 1.2e-7);
        ASSERT_NEAR(s.z, exact.z, 1.2e-7);
        ASSERT_NEAR(s.w, exact.w, 1.2e-7);
    }
}

/* The series form of log (the turn between neighbouring frames): the rotation vector of the axis
 * and angle it was made from, within a float rounding of mm_quat_log, from 1e-7 rad to past its
 * series' reach (0.3 rad), for quaternions of either sign and not quite unit; zero and NaN as
 * mm_quat_log gives them. */
static void test_log_series(void **state)
{
    (void)state;
    rng_seed(21);
    int equal = 0, count = 20000;
    for (int n = 0; n < count; n++) {
        mm_vec3 axis = rnd_unit_vec3();
        double angle = pow(10.0, rnd(-7.0, -0.2));
        mm_quat q = ref_quat(axis, angle);
        float sign = n % 2 ? -1.0f : 1.0f, size = (float)rnd(0.999, 1.001);
        q = mm_quat_make(q.x * sign * size, q.y * sign * size, q.z * sign * size, q.w * sign * size);
        mm_vec3 s = mm__quat_log_series(q), exact = mm_quat_log(q);
        ASSERT_NEAR(s.x, axis.x * angle, 1e-6 * angle + 1e-7 * angle);
        ASSERT_NEAR(s.y, axis.y * angle, 1e-6 * angle + 1e-7 * angle);
        ASSERT_NEAR(s.z, axis.z * angle, 1e-6 * angle + 1e-7 * angle);
        float ulp = 1.2e-7f * (float)angle;
        ASSERT_NEAR(s.x, exact.x, ulp);
        ASSERT_NEAR(s.y, exact.y, ulp);
        ASSERT_NEAR(s.z, exact.z, ulp);
        equal += memcmp(&s, &exact, sizeof s) == 0;
    }
    /* a float rounding apart at most, and almost always not at all */
    assert_true(equal >= count - count / 1000);
    mm_vec3 zero = mm__quat_log_series(mm_quat_make(0, 0, 0, 0)), z0 = mm_quat_log(mm_quat_make(0, 0, 0, 0));
    assert_memory_equal(&zero, &z0, sizeof zero);
    mm_vec3 nan = mm__quat_log_series(mm_quat_make(NAN, 0, 0, 1));
    assert_true(isnan(nan.x) && isnan(mm_quat_log(mm_quat_make(NAN, 0, 0, 1)).x));
}

/* Many series exps at once (mm__quat_exp_series_n, four wide and two wide): the bits of one
 * mm__quat_exp_series each, from zero (either sign) through the series' reach and past it, NaN
 * among them, counts of every remainder. */
static void test_exp_series_n(void **state)
{
    (void)state;
    enum { OFFSETS = 29 };
    mm_vec3 v[OFFSETS];
    mm_quat many[OFFSETS];
    for (int n = 0; n < 800; n++) {
        if (n % 400 == 0) rng_seed(24), mm__math_wide_kernels(n == 0); /* four wide (AVX), then two */
        for (int i = 0; i < OFFSETS; ++i) {
            mm_vec3 axis = rnd_unit_vec3();
            double angle = pow(10.0, rnd(-9.0, 0.5));
            v[i] = mm_vec3_make((float)(axis.x * angle), (float)(axis.y * angle), (float)(axis.z * angle));
        }
        v[n % OFFSETS] = mm_vec3_make(0.0f, -0.0f, 0.0f);
        if (n % 10 == 3) v[5] = mm_vec3_make(NAN, 0.0f, 0.0f);
        int count = OFFSETS - n % 4;
        mm__quat_exp_series_n(v, count, many);
        for (int i = 0; i < count; ++i) {
            mm_quat one = mm__quat_exp_series(v[i]);
            assert_memory_equal(&many[i], &one, sizeof one);
        }
    }
    mm__math_wide_kernels(true);
}

/* Many series logs at once (mm__quat_log_series_n, four wide and two wide): the bits of one
 * mm__quat_log_series each, from the identity (either sign) through the series' reach and past it,
 * negative w, zero, not quite unit and NaN among them, counts of every remainder. */
static void test_log_series_n(void **state)
{
    (void)state;
    enum { TURNS = 27 };
    mm_quat q[TURNS];
    mm_vec3 many[TURNS];
    for (int n = 0; n < 800; n++) {
        if (n % 400 == 0) rng_seed(26), mm__math_wide_kernels(n == 0); /* four wide (AVX), then two */
        for (int i = 0; i < TURNS; ++i) {
            mm_vec3 axis = rnd_unit_vec3();
            double half = 0.5 * pow(10.0, rnd(-9.0, 0.6)), size = rnd(0.99, 1.01), sign = i % 3 ? 1.0 : -1.0;
            double k = sin(half) * size * sign;
            q[i] = mm_quat_make((float)(axis.x * k), (float)(axis.y * k), (float)(axis.z * k),
                                (float)(cos(half) * size * sign));
        }
        q[n % TURNS] = mm_quat_make(0.0f, -0.0f, 0.0f, n % 2 ? 1.0f : -1.0f);
        if (n % 10 == 3) q[5] = mm_quat_make(NAN, 0.0f, 0.0f, 1.0f);
        if (n % 10 == 4) q[8] = mm_quat_make(0.0f, 0.0f, 0.0f, 0.0f);
        int count = TURNS - n % 4;
        mm__quat_log_series_n(q, count, many);
        for (int i = 0; i < count; ++i) {
            mm_vec3 one = mm__quat_log_series(q[i]);
            assert_memory_equal(&many[i], &one, sizeof one);
        }
    }
    mm__math_wide_kernels(true);
}

/* Many products normalized at once (mm__quat_mul_normalize_n, four at a time): the bits of
 * mm_quat_normalize(mm_quat_mul(a, b)) each, unit and not, zero and tiny products (the identity),
 * signed zeros and NaN among them, every count's remainder. */
static void test_mul_normalize_n(void **state)
{
    (void)state;
    rng_seed(25);
    enum { PAIRS = 23 };
    mm_quat a[PAIRS], b[PAIRS], many[PAIRS];
    for (int n = 0; n < 400; n++) {
        for (int i = 0; i < PAIRS; ++i) {
            a[i] = rnd_quat();
            b[i] = rnd_quat();
            if (i % 3 == 1) b[i] = mm_quat_make(b[i].x * 3.0f, b[i].y * 3.0f, b[i].z * 3.0f, b[i].w * 3.0f);
        }
        a[n % PAIRS] = mm_quat_make(0.0f, -0.0f, 0.0f, 0.0f);
        b[(n + 5) % PAIRS] = mm_quat_make(1e-20f, 0.0f, -1e-21f, 0.0f);
        if (n % 10 == 3) b[7] = mm_quat_make(NAN, 0.0f, 0.0f, 1.0f);
        int count = PAIRS - n % 4;
        for (int i = 0; i < PAIRS; ++i) many[i] = b[i];
        mm__quat_mul_normalize_n(a, many, count);
        for (int i = 0; i < PAIRS; ++i) {
            mm_quat one = i < count ? mm_quat_normalize(mm_quat_mul(a[i], b[i])) : b[i];
            assert_memory_equal(&many[i], &one, sizeof one);
        }
    }
}

/* Many turns at once (mm__quat_turns_n, four at a time): the bits of mm_quat_abs(mm_quat_mul(to,
 * mm_quat_inverse(from))) each, unit and not, a zero and a tiny `from` (the identity inverse), turns
 * past half a turn (the sign flipped), signed zeros and NaN among them, every count's remainder. */
static void test_turns_n(void **state)
{
    (void)state;
    rng_seed(27);
    enum { PAIRS = 23 };
    mm_quat from[PAIRS], to[PAIRS], many[PAIRS];
    for (int n = 0; n < 400; n++) {
        for (int i = 0; i < PAIRS; ++i) {
            from[i] = rnd_quat();
            to[i] = rnd_quat();
            if (i % 3 == 1)
                from[i] =
                    mm_quat_make(from[i].x * 2.0f, from[i].y * 2.0f, from[i].z * 2.0f, from[i].w * 2.0f);
        }
        from[n % PAIRS] = mm_quat_make(0.0f, -0.0f, 0.0f, 0.0f);
        from[(n + 5) % PAIRS] = mm_quat_make(1e-13f, 0.0f, -1e-13f, 0.0f);
        to[(n + 9) % PAIRS] = mm_quat_make(0.0f, 0.0f, -0.0f, 0.0f);
        if (n % 10 == 3) to[7] = mm_quat_make(NAN, 0.0f, 0.0f, 1.0f);
        if (n % 10 == 4) from[2] = mm_quat_make(0.0f, INFINITY, 0.0f, 1.0f);
        int count = PAIRS - n % 4;
        for (int i = 0; i < PAIRS; ++i) many[i] = mm_quat_make(7.0f, 7.0f, 7.0f, 7.0f);
        mm__quat_turns_n(from, to, count, many);
        for (int i = 0; i < PAIRS; ++i) {
            mm_quat one = i < count ? mm_quat_abs(mm_quat_mul(to[i], mm_quat_inverse(from[i])))
                                    : mm_quat_make(7.0f, 7.0f, 7.0f, 7.0f);
            assert_memory_equal(&many[i], &one, sizeof one);
        }
    }
}

static void test_slerp_shortest_path(void **state)
{
    (void)state;
    rng_seed(15);
    for (int n = 0; n < 500; n++) {
        mm_quat a = rnd_quat();
        mm_vec3 axis = rnd_unit_vec3();
        double theta = rnd(PI + 0.01, 2 * PI - 0.01); /* the long way round */
        mm_quat b = mm_quat_mul(a, ref_quat(axis, theta));
        assert_true(mm_quat_dot(a, b) < 0.0f);
        double shortest = 2 * PI - theta;
        for (int k = 0; k <= 10; k++) {
            double t = k / 10.0;
            mm_quat s = mm_quat_slerp(a, b, (float)t);
            ASSERT_SAME_ROT(s, mm_quat_mul(a, ref_quat(axis, -t * shortest)), 2e-6);
            ASSERT_NEAR(rot_dist(a, s), t * shortest, 1e-5);
        }
    }
}

static void test_slerp_nearly_parallel(void **state)
{
    (void)state;
    rng_seed(16);
    const double thetas[] = {0, 1e-8, 1e-7, 1e-6, 1e-5, 1e-4, 2e-4, 1e-3, 1e-2};
    for (int n = 0; n < 200; n++) {
        mm_quat a = rnd_quat();
        mm_vec3 axis = rnd_unit_vec3();
        for (size_t i = 0; i < sizeof thetas / sizeof thetas[0]; i++) {
            mm_quat b = mm_quat_mul(a, ref_quat(axis, thetas[i]));
            for (int k = 0; k <= 4; k++) {
                double t = k / 4.0;
                mm_quat s = mm_quat_slerp(a, b, (float)t);
                assert_unit(s);
                ASSERT_SAME_ROT(s, mm_quat_mul(a, ref_quat(axis, t * thetas[i])), 1e-6);
            }
        }
    }
}

static void test_nlerp(void **state)
{
    (void)state;
    rng_seed(17);
    for (int n = 0; n < 1000; n++) {
        mm_quat a = rnd_quat(), b = rnd_quat();
        ASSERT_QUAT_NEAR(mm_quat_nlerp(a, b, 0.0f), a, 1e-6);
        ASSERT_SAME_ROT(mm_quat_nlerp(a, b, 1.0f), b, 1e-6);
        float t = (float)rnd(0, 1);
        mm_quat s = mm_quat_nlerp(a, b, t);
        assert_unit(s);
        mm_quat nb = mm_quat_make(-b.x, -b.y, -b.z, -b.w);
        ASSERT_SAME_ROT(mm_quat_nlerp(a, nb, t), s, 1e-6);
        /* At t = 1/2 nlerp and slerp agree (both bisect the arc). */
        ASSERT_SAME_ROT(mm_quat_nlerp(a, b, 0.5f), mm_quat_slerp(a, b, 0.5f), 2e-6);
    }
    /* The path stays on the arc about the same axis, is monotonic and goes the short way. */
    for (int n = 0; n < 200; n++) {
        mm_vec3 axis = rnd_unit_vec3();
        double theta = rnd(0.1, 2 * PI - 0.1);
        double shortest = theta <= PI ? theta : theta - 2 * PI; /* signed, about axis */
        mm_quat b = ref_quat(axis, theta);
        double prev = 0;
        for (int k = 1; k <= 10; k++) {
            mm_quat s = mm_quat_nlerp(mm_quat_identity(), b, k / 10.0f);
            mm_vec3 v = mm_quat_log(s);
            ASSERT_VEC3_NEAR(mm_vec3_cross(v, axis), mm_vec3_make(0, 0, 0), 1e-5);
            double signed_angle = mm_vec3_dot(v, axis);
            assert_true(signed_angle * shortest >= 0);
            assert_true(fabs(signed_angle) > prev);
            prev = fabs(signed_angle);
            mm_quat mirror = mm_quat_nlerp(mm_quat_identity(), b, 1.0f - k / 10.0f);
            ASSERT_NEAR(fabs(signed_angle) + rot_dist(mirror, mm_quat_identity()), fabs(shortest), 1e-5);
        }
        ASSERT_NEAR(prev, fabs(shortest), 1e-5);
    }
}

static void test_angle_between(void **state)
{
    (void)state;
    rng_seed(18);
    mm_quat id = mm_quat_identity();
    for (int n = 0; n < 200; n++) {
        mm_vec3 axis = rnd_unit_vec3();
        double theta = rnd(0, 2 * PI);
        double expect = theta <= PI ? theta : 2 * PI - theta;
        ASSERT_NEAR(mm_quat_angle_between(id, ref_quat(axis, theta)), expect, 2e-6);
    }
    for (int n = 0; n < 2000; n++) {
        mm_quat a = rnd_quat(), b = rnd_quat(), c = rnd_quat();
        float ab = mm_quat_angle_between(a, b);
        assert_true(ab >= 0.0f && ab <= (float)PI);
        ASSERT_NEAR(ab, rot_dist(a, b), 1e-5);
        ASSERT_NEAR(mm_quat_angle_between(b, a), ab, 1e-6);
        ASSERT_NEAR(mm_quat_angle_between(a, mm_quat_make(-b.x, -b.y, -b.z, -b.w)), ab, 1e-6);
        ASSERT_NEAR(mm_quat_angle_between(mm_quat_mul(c, a), mm_quat_mul(c, b)), ab, 1e-5);
        ASSERT_NEAR(mm_quat_angle_between(mm_quat_make(a.x * 3, a.y * 3, a.z * 3, a.w * 3), b), ab, 1e-5);
        assert_true(mm_quat_angle_between(a, a) <= 1e-7f);
        /* Small angles stay accurate (acos(dot) would not). */
        mm_quat near = mm_quat_mul(a, ref_quat(rnd_unit_vec3(), 1e-4));
        ASSERT_NEAR(mm_quat_angle_between(a, near), 1e-4, 1e-6);
    }
}

/* ---- swing-twist and between ------------------------------------------------------------------ */

static void check_swing_twist(mm_quat q, mm_vec3 axis)
{
    mm_quat swing, twist;
    mm_vec3 u = mm_vec3_normalize(axis);
    mm_quat_swing_twist(q, axis, &swing, &twist);
    assert_unit(swing);
    assert_unit(twist);
    ASSERT_QUAT_NEAR(mm_quat_mul(swing, twist), q, 2e-6);
    /* twist rotates about the axis, swing about a perpendicular one. */
    ASSERT_VEC3_NEAR(mm_vec3_cross(mm_vec3_make(twist.x, twist.y, twist.z), u), mm_vec3_make(0, 0, 0), 2e-6);
    ASSERT_NEAR(mm_vec3_dot(mm_vec3_make(swing.x, swing.y, swing.z), u), 0, 2e-6);
    /* twist fixes the axis, so the swing alone carries it where q does. */
    ASSERT_VEC3_NEAR(mm_quat_rotate(swing, u), mm_quat_rotate(q, u), 1e-5);
}

static void test_swing_twist(void **state)
{
    (void)state;
    rng_seed(19);
    for (int n = 0; n < 3000; n++) {
        mm_vec3 axis = n < 3 ? (n == 0   ? X
                                : n == 1 ? Y
                                         : Z)
                             : mm_vec3_scale(rnd_unit_vec3(), (float)rnd(0.2, 5));
        check_swing_twist(rnd_quat(), axis);
    }
    /* Known parts: a twist about u composed with a swing about an axis perpendicular to u. */
    for (int n = 0; n < 500; n++) {
        mm_vec3 u = rnd_unit_vec3();
        mm_vec3 p = mm_vec3_normalize(mm_vec3_cross(u, rnd_unit_vec3()));
        mm_quat tw = ref_quat(u, rnd(-PI, PI)), sw = ref_quat(p, rnd(-3.0, 3.0));
        mm_quat q = mm_quat_mul(sw, tw), swing, twist;
        mm_quat_swing_twist(q, u, &swing, &twist);
        ASSERT_SAME_ROT(twist, tw, 1e-5);
        ASSERT_SAME_ROT(swing, sw, 1e-5);
        check_swing_twist(q, u);
    }
    /* Pure twist and pure swing. */
    mm_quat swing, twist, q = ref_quat(Y, 1.0);
    mm_quat_swing_twist(q, mm_vec3_make(0, 5, 0), &swing, &twist);
    ASSERT_QUAT_NEAR(twist, q, 1e-7);
    ASSERT_QUAT_NEAR(swing, mm_quat_identity(), 1e-7);
    q = ref_quat(mm_vec3_make(1, 0, -1), 0.7);
    mm_quat_swing_twist(q, Y, &swing, &twist);
    ASSERT_QUAT_NEAR(twist, mm_quat_identity(), 1e-7);
    ASSERT_QUAT_NEAR(swing, q, 1e-7);
    /* Half turn about a perpendicular axis: the twist is undetermined and is the identity. */
    q = ref_quat(X, PI);
    mm_quat_swing_twist(q, Y, &swing, &twist);
    ASSERT_QUAT_NEAR(twist, mm_quat_identity(), 0);
    ASSERT_QUAT_NEAR(swing, q, 0);
    /* The same with rounding noise: a twist of some 1e-8 along the axis must not blow up into
     * a large twist angle. */
    q = mm_quat_make(0.6f, 3e-8f, 0.8f, 2e-8f);
    mm_quat_swing_twist(q, Y, &swing, &twist);
    assert_true(rot_dist(twist, mm_quat_identity()) < 1e-6);
    ASSERT_QUAT_NEAR(mm_quat_mul(swing, twist), q, 1e-7);
    /* Either output may be NULL. */
    q = rnd_quat();
    mm_quat_swing_twist(q, Z, &swing, &twist);
    mm_quat only;
    mm_quat_swing_twist(q, Z, NULL, &only);
    ASSERT_QUAT_NEAR(only, twist, 0);
    mm_quat_swing_twist(q, Z, &only, NULL);
    ASSERT_QUAT_NEAR(only, swing, 0);
    mm_quat_swing_twist(q, Z, NULL, NULL);
}

static void check_between(mm_vec3 from, mm_vec3 to, double tol)
{
    mm_quat q = mm_quat_between(from, to);
    mm_vec3 f = mm_vec3_normalize(from), t = mm_vec3_normalize(to);
    assert_unit(q);
    ASSERT_VEC3_NEAR(mm_quat_rotate(q, f), t, tol);
    /* The shortest rotation: its angle is the angle between the vectors, and its axis is
     * perpendicular to both. */
    double c = (double)f.x * t.x + (double)f.y * t.y + (double)f.z * t.z;
    ASSERT_NEAR(rot_dist(q, mm_quat_identity()), acos(c > 1 ? 1 : c < -1 ? -1 : c), 1e-3);
    mm_vec3 v = mm_vec3_make(q.x, q.y, q.z);
    ASSERT_NEAR(mm_vec3_dot(v, f), 0, 1e-5);
}

static void test_between(void **state)
{
    (void)state;
    rng_seed(20);
    for (int n = 0; n < 3000; n++) {
        mm_vec3 from = mm_vec3_scale(rnd_unit_vec3(), (float)rnd(0.01, 100));
        mm_vec3 to = mm_vec3_scale(rnd_unit_vec3(), (float)rnd(0.01, 100));
        check_between(from, to, 2e-6);
        mm_quat q = mm_quat_between(from, to);
        mm_vec3 v = mm_vec3_make(q.x, q.y, q.z);
        ASSERT_NEAR(mm_vec3_dot(v, mm_vec3_normalize(to)), 0, 1e-5);
        ASSERT_NEAR(rot_dist(q, mm_quat_identity()),
                    acos(fmax(-1.0, fmin(1.0, mm_vec3_dot(mm_vec3_normalize(from), mm_vec3_normalize(to))))),
                    1e-5);

        /* Identical directions: the identity. */
        ASSERT_SAME_ROT(mm_quat_between(from, mm_vec3_scale(from, 3.0f)), mm_quat_identity(), 1e-6);
        /* Opposite and nearly opposite directions. */
        check_between(from, mm_vec3_scale(from, -2.0f), 2e-6);
        mm_vec3 f = mm_vec3_normalize(from);
        mm_vec3 perp = mm_vec3_normalize(mm_vec3_cross(f, rnd_unit_vec3()));
        check_between(f, mm_vec3_add(mm_vec3_neg(f), mm_vec3_scale(perp, 1e-4f)), 2e-6);
        check_between(f, mm_vec3_add(f, mm_vec3_scale(perp, 1e-4f)), 2e-6);
    }
    const mm_vec3 axes[] = {X, Y, Z, {-1, 0, 0}, {0, -1, 0}, {0, 0, -1}, {1, 1, 0}, {0, 0, 5}};
    for (size_t i = 0; i < sizeof axes / sizeof axes[0]; i++) {
        check_between(axes[i], mm_vec3_neg(axes[i]), 1e-6);
        ASSERT_NEAR(rot_dist(mm_quat_between(axes[i], mm_vec3_neg(axes[i])), mm_quat_identity()), PI, 1e-6);
        ASSERT_QUAT_NEAR(mm_quat_between(axes[i], axes[i]), mm_quat_identity(), 1e-7);
    }
    /* Known: X onto Y is 90 degrees about Z. */
    ASSERT_SAME_ROT(mm_quat_between(X, mm_vec3_make(0, 2, 0)), ref_quat(Z, HALF_PI), 1e-6);
    /* A zero vector gives the identity. */
    ASSERT_QUAT_NEAR(mm_quat_between(mm_vec3_make(0, 0, 0), X), mm_quat_identity(), 0);
    ASSERT_QUAT_NEAR(mm_quat_between(X, mm_vec3_make(0, 0, 0)), mm_quat_identity(), 0);
}

/* ---- rigid transforms --------------------------------------------------------------------------- */

static mm_xform rnd_xform(void)
{
    return mm_xform_make(rnd_quat(), mm_vec3_make((float)rnd(-5, 5), (float)rnd(-5, 5), (float)rnd(-5, 5)));
}

static void test_xform(void **state)
{
    (void)state;
    /* By hand: 90 degrees about Z then a shift: (1, 0, 0) -> (0, 1, 0) -> (1, 3, 3). */
    mm_xform a = mm_xform_make(ref_quat(Z, HALF_PI), mm_vec3_make(1, 2, 3));
    ASSERT_VEC3_NEAR(mm_xform_apply_point(a, X), mm_vec3_make(1, 3, 3), 1e-6);
    ASSERT_VEC3_NEAR(mm_xform_apply_vector(a, X), Y, 1e-6);
    ASSERT_VEC3_NEAR(mm_xform_apply_point(mm_xform_inverse(a), mm_vec3_make(1, 3, 3)), X, 1e-6);
    /* Parent * local: a child at (2, 0, 0) with no rotation of its own, under a. */
    mm_xform child = mm_xform_make(mm_quat_identity(), mm_vec3_make(2, 0, 0));
    mm_xform g = mm_xform_mul(a, child);
    ASSERT_VEC3_NEAR(g.translation, mm_vec3_make(1, 4, 3), 1e-6);
    ASSERT_VEC3_NEAR(mm_xform_apply_point(mm_xform_identity(), mm_vec3_make(4, 5, 6)), mm_vec3_make(4, 5, 6),
                     0);

    rng_seed(21);
    for (int n = 0; n < 1000; n++) {
        mm_xform x = rnd_xform(), y = rnd_xform(), z = rnd_xform();
        mm_vec3 p = mm_vec3_make((float)rnd(-10, 10), (float)rnd(-10, 10), (float)rnd(-10, 10));
        /* x * y applies y first. */
        ASSERT_VEC3_NEAR(mm_xform_apply_point(mm_xform_mul(x, y), p),
                         mm_xform_apply_point(x, mm_xform_apply_point(y, p)), 1e-4);
        /* Against the matrix form R p + t. */
        dmat r = dmat_from_mat3(mm_quat_to_mat3(x.rotation));
        ASSERT_VEC3_NEAR(mm_xform_apply_point(x, p), mm_vec3_add(dmat_apply(r, p), x.translation), 1e-4);
        ASSERT_VEC3_NEAR(mm_xform_apply_vector(x, p), dmat_apply(r, p), 1e-4);
        /* Inverse on both sides. */
        mm_xform i1 = mm_xform_mul(x, mm_xform_inverse(x)), i2 = mm_xform_mul(mm_xform_inverse(x), x);
        ASSERT_SAME_ROT(i1.rotation, mm_quat_identity(), 1e-6);
        ASSERT_SAME_ROT(i2.rotation, mm_quat_identity(), 1e-6);
        ASSERT_VEC3_NEAR(i1.translation, mm_vec3_make(0, 0, 0), 1e-5);
        ASSERT_VEC3_NEAR(i2.translation, mm_vec3_make(0, 0, 0), 1e-5);
        ASSERT_VEC3_NEAR(mm_xform_apply_point(mm_xform_inverse(x), mm_xform_apply_point(x, p)), p, 1e-4);
        /* (x y)^-1 = y^-1 x^-1, and associativity. */
        mm_xform l = mm_xform_inverse(mm_xform_mul(x, y));
        mm_xform rr = mm_xform_mul(mm_xform_inverse(y), mm_xform_inverse(x));
        ASSERT_SAME_ROT(l.rotation, rr.rotation, 1e-6);
        ASSERT_VEC3_NEAR(l.translation, rr.translation, 1e-4);
        mm_xform xyz1 = mm_xform_mul(mm_xform_mul(x, y), z), xyz2 = mm_xform_mul(x, mm_xform_mul(y, z));
        ASSERT_SAME_ROT(xyz1.rotation, xyz2.rotation, 1e-6);
        ASSERT_VEC3_NEAR(xyz1.translation, xyz2.translation, 1e-4);
        /* The identity is neutral. */
        mm_xform xi = mm_xform_mul(x, mm_xform_identity());
        ASSERT_QUAT_NEAR(xi.rotation, x.rotation, 1e-7);
        ASSERT_VEC3_NEAR(xi.translation, x.translation, 1e-6);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_euler_order_names),
        cmocka_unit_test(test_quat_inverse),
        cmocka_unit_test(test_known_rotations),
        cmocka_unit_test(test_rotate_matches_rodrigues),
        cmocka_unit_test(test_mul_composes),
        cmocka_unit_test(test_mat3_ops),
        cmocka_unit_test(test_mat3_roundtrip),
        cmocka_unit_test(test_log_exp_random),
        cmocka_unit_test(test_log_exp_angles),
        cmocka_unit_test(test_euler_matches_axis_matrices),
        cmocka_unit_test(test_euler_known),
        cmocka_unit_test(test_euler_roundtrip_rotation),
        cmocka_unit_test(test_euler_roundtrip_angles),
        cmocka_unit_test(test_euler_gimbal_lock),
        cmocka_unit_test(test_euler_invalid_order),
        cmocka_unit_test(test_slerp_endpoints),
        cmocka_unit_test(test_slerp_path),
        cmocka_unit_test(test_slerp_shortest_path),
        cmocka_unit_test(test_slerp_series),
        cmocka_unit_test(test_slerp_series_n),
        cmocka_unit_test(test_exp_series),
        cmocka_unit_test(test_log_series),
        cmocka_unit_test(test_log_series_n),
        cmocka_unit_test(test_turns_n),
        cmocka_unit_test(test_exp_series_n),
        cmocka_unit_test(test_mul_normalize_n),
        cmocka_unit_test(test_slerp_nearly_parallel),
        cmocka_unit_test(test_nlerp),
        cmocka_unit_test(test_angle_between),
        cmocka_unit_test(test_swing_twist),
        cmocka_unit_test(test_between),
        cmocka_unit_test(test_xform),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
