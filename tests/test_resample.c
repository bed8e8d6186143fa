/* The C1 splines (mm_vec3_catmull_rom, mm_quat_hermite, mm_quat_catmull_rom) and the cubic
 * resampling of clips (mm_clip_sample_frame, mm_clip_resample_interp, the database's
 * mm__clip_extract) against linear interpolation and hand-computed values. */
#include <math.h>

#include <mm/clip.h>

#include "db/process.h"
#include "test_util.h"

static double quat_dot_abs(mm_quat a, mm_quat b)
{
    return fabs((double)a.x * b.x + (double)a.y * b.y + (double)a.z * b.z + (double)a.w * b.w);
}

static double quat_len(mm_quat q) { return sqrt(quat_dot_abs(q, q)); }

static mm_quat quat_neg(mm_quat q) { return mm_quat_make(-q.x, -q.y, -q.z, -q.w); }

/* The same rotation (q or -q) to tol, measured as the angle between them. */
static void assert_same_rotation(mm_quat a, mm_quat b, double tol)
{
    assert_true(mm_quat_angle_between(a, b) <= tol);
}

/* ---- math ------------------------------------------------------------------------------- */

static void test_vec3_catmull_rom(void **state)
{
    (void)state;
    mm_vec3 p0 = mm_vec3_make(0.3f, -1, 2), p1 = mm_vec3_make(1.1f, 0.5f, 2.5f),
            p2 = mm_vec3_make(2, 0.2f, 4), p3 = mm_vec3_make(2.5f, -3, 4.5f);
    /* exact at the keys, bit for bit */
    mm_vec3 a = mm_vec3_catmull_rom(p0, p1, p2, p3, 0.0f), b = mm_vec3_catmull_rom(p0, p1, p2, p3, 1.0f);
    assert_memory_equal(&a, &p1, sizeof a);
    assert_memory_equal(&b, &p2, sizeof b);
    /* points on a line at equal steps: the line at constant speed */
    mm_vec3 o = mm_vec3_make(1, 2, 3), v = mm_vec3_make(0.25f, -0.5f, 1.5f);
    for (int i = 0; i <= 10; ++i) {
        float t = (float)i / 10.0f;
        mm_vec3 p = mm_vec3_catmull_rom(o, mm_vec3_add(o, v), mm_vec3_add(o, mm_vec3_scale(v, 2)),
                                        mm_vec3_add(o, mm_vec3_scale(v, 3)), t);
        assert_near(mm_vec3_distance(p, mm_vec3_add(o, mm_vec3_scale(v, 1 + t))), 0, 1e-6);
    }
    /* a parabola at unit steps: central differences are its exact slopes, so the cubic is the
     * parabola itself. x = k, y = k^2 at k = 0..3; between 1 and 2, y(1 + t) = (1 + t)^2. */
    for (int i = 0; i <= 10; ++i) {
        float t = (float)i / 10.0f;
        mm_vec3 p = mm_vec3_catmull_rom(mm_vec3_make(0, 0, 0), mm_vec3_make(1, 1, 0), mm_vec3_make(2, 4, 0),
                                        mm_vec3_make(3, 9, 0), t);
        assert_near(p.x, 1 + t, 1e-6);
        assert_near(p.y, (1 + t) * (1 + t), 1e-6);
    }
    /* a unit step 0, 0, 1, 1: it overshoots by 2/27 at most (t (1-t)^2 / 2 at t = 1/3 on either
     * side), well within the documented 1/8 */
    double lo = 0.0, hi = 0.0;
    for (int i = 0; i <= 300; ++i) {
        float t = (float)i / 300.0f;
        mm_vec3 z = mm_vec3_make(0, 0, 0), one = mm_vec3_make(1, 1, 1);
        lo = fmin(lo, mm_vec3_catmull_rom(z, z, z, one, t).x);     /* before the step */
        hi = fmax(hi, mm_vec3_catmull_rom(z, one, one, one, t).x); /* after it */
        double mid = mm_vec3_catmull_rom(z, z, one, one, t).x;     /* across it: monotone */
        assert_true(mid >= -1e-7 && mid <= 1 + 1e-7);
    }
    assert_near(lo, -2.0 / 27.0, 1e-4);
    assert_near(hi, 1 + 2.0 / 27.0, 1e-4);
}

static void test_quat_hermite_slerp(void **state)
{
    (void)state;
    mm_quat a = mm_quat_from_axis_angle(mm_vec3_make(1, 2, 3), 0.7f);
    mm_quat b = mm_quat_from_axis_angle(mm_vec3_make(-1, 0.5f, 0.2f), 1.9f);
    /* the one-sided tangents (the turn a -> b at both ends): slerp itself */
    mm_vec3 w = mm_quat_log(mm_quat_mul(mm_quat_conj(a), b));
    for (int i = 0; i <= 20; ++i) {
        float t = (float)i / 20.0f;
        mm_quat h = mm_quat_hermite(a, w, b, w, t);
        assert_near(quat_len(h), 1, 1e-6);
        assert_same_rotation(h, mm_quat_slerp(a, b, t), 2e-6);
    }
    /* the ends are the keys themselves; b may be given as -b (the sign the curve arrives with
     * comes back) */
    mm_quat e0 = mm_quat_hermite(a, w, b, w, 0.0f), e1 = mm_quat_hermite(a, w, b, w, 1.0f);
    assert_memory_equal(&e0, &a, sizeof a);
    assert_memory_equal(&e1, &b, sizeof b);
    mm_quat nb = quat_neg(b);
    mm_quat f1 = mm_quat_hermite(a, w, nb, w, 1.0f), f_near = mm_quat_hermite(a, w, nb, w, 0.999f);
    assert_true(f1.x == b.x || f1.x == nb.x);
    assert_true(quat_dot_abs(f1, b) > 1 - 1e-7);
    assert_true(mm_quat_dot(f1, f_near) > 0.99f); /* no sign jump at the end */
    for (int i = 0; i <= 20; ++i)
        assert_same_rotation(mm_quat_hermite(a, w, nb, w, (float)i / 20), mm_quat_slerp(a, b, (float)i / 20),
                             2e-6);
    /* the tangents are the angular velocities at the ends (in the keys' own frames), estimated
     * to second order from the turns r(h), r(2h) away from the key: (4 r(h) - r(2h)) / 2h */
    mm_vec3 w0 = mm_vec3_make(0.3f, -0.2f, 0.5f), w1 = mm_vec3_make(-0.4f, 0.1f, 0.2f);
    float h = 0.01f;
    mm_quat a1 = mm_quat_hermite(a, w0, b, w1, h), a2 = mm_quat_hermite(a, w0, b, w1, 2 * h);
    mm_quat b1 = mm_quat_hermite(a, w0, b, w1, 1 - h), b2 = mm_quat_hermite(a, w0, b, w1, 1 - 2 * h);
    mm_vec3 d0 = mm_vec3_scale(mm_vec3_sub(mm_vec3_scale(mm_quat_log(mm_quat_mul(mm_quat_conj(a), a1)), 4),
                                           mm_quat_log(mm_quat_mul(mm_quat_conj(a), a2))),
                               0.5f / h);
    mm_vec3 d1 = mm_vec3_scale(mm_vec3_sub(mm_vec3_scale(mm_quat_log(mm_quat_mul(mm_quat_conj(b1), b)), 4),
                                           mm_quat_log(mm_quat_mul(mm_quat_conj(b2), b))),
                               0.5f / h);
    assert_near(mm_vec3_distance(d0, w0), 0, 2e-3);
    assert_near(mm_vec3_distance(d1, w1), 0, 2e-3);
}

/* q_i = base exp(i w): a turn at a constant rate about a fixed axis (in base's frame). */
static mm_quat uniform_key(mm_quat base, mm_vec3 w, double i)
{
    return mm_quat_mul(base, mm_quat_exp(mm_vec3_scale(w, (float)i)));
}

static void test_quat_catmull_rom_uniform(void **state)
{
    (void)state;
    mm_quat base = mm_quat_from_axis_angle(mm_vec3_make(0.2f, 1, -0.4f), 2.3f);
    mm_vec3 w = mm_vec3_make(0.15f, -0.35f, 0.25f); /* 0.45 rad per key */
    mm_quat q[4];
    for (int k = 0; k < 4; ++k) q[k] = uniform_key(base, w, k);
    mm_vec3 tangent = mm_quat_catmull_rom_tangent(q[0], q[1], q[2]);
    assert_near(mm_vec3_distance(tangent, w), 0, 1e-6);
    for (int i = 0; i <= 20; ++i) {
        float t = (float)i / 20.0f;
        mm_quat expect = uniform_key(base, w, 1.0 + t);
        mm_quat c = mm_quat_catmull_rom(q[0], q[1], q[2], q[3], t);
        assert_near(quat_len(c), 1, 1e-6);
        assert_same_rotation(c, expect, 2e-6);
        /* the same keys with their signs flipped anyhow: the same curve */
        mm_quat f = mm_quat_catmull_rom(quat_neg(q[0]), q[1], quat_neg(q[2]), q[3], t);
        assert_same_rotation(f, expect, 2e-6);
        f = mm_quat_catmull_rom(q[0], quat_neg(q[1]), q[2], quat_neg(q[3]), t);
        assert_same_rotation(f, expect, 2e-6);
    }
}

/* ---- clips -------------------------------------------------------------------------------- */

/* Root at the origin, a 1-unit "arm" along +X, a 1-unit "hand" along +X after it. */
static void make_arm_clip(mm_clip *clip, int frames, float fps)
{
    mm_skeleton s;
    assert_int_equal(mm_skeleton_init(&s, 3, NULL), MM_OK);
    strcpy(s.joints[0].name, "root");
    strcpy(s.joints[1].name, "arm");
    strcpy(s.joints[2].name, "hand");
    s.joints[1].offset = mm_vec3_make(1, 0, 0);
    s.joints[2].offset = mm_vec3_make(1, 0, 0);
    assert_int_equal(mm_clip_init(clip, &s, frames, fps, NULL), MM_OK);
    mm_skeleton_free(&s);
}

/* A smooth but not uniform motion: the root wanders and turns, the arm swings about a moving
 * axis. */
static void fill_wavy(mm_clip *clip)
{
    for (int f = 0; f < clip->frame_count; ++f) {
        double t = f / (double)clip->fps;
        mm_clip_positions(clip, f)[0] = mm_vec3_make(
            (float)(1.5 * t + 0.2 * sin(5 * t)), (float)(0.9 + 0.05 * sin(9 * t)), (float)(0.3 * cos(3 * t)));
        mm_clip_rotations(clip, f)[0] =
            mm_quat_from_axis_angle(mm_vec3_make(0, 1, 0), (float)(0.8 * sin(2 * t)));
        mm_clip_rotations(clip, f)[1] = mm_quat_from_axis_angle(
            mm_vec3_make((float)sin(t), 1, (float)cos(2 * t)), (float)(1.2 * sin(6 * t)));
    }
}

/* World position of joint j at frame position x of clip. */
static mm_vec3 world_at(const mm_clip *clip, double x, mm_interp interp, int j)
{
    mm_quat r[3];
    mm_vec3 p[3];
    mm_xform g[3];
    mm_clip_sample_frame(clip, x, interp, r, p);
    mm_fk(&clip->skeleton, r, p, g);
    return g[j].translation;
}

static void test_clip_cubic_exact_at_frames(void **state)
{
    (void)state;
    mm_clip src, up, down, odd;
    make_arm_clip(&src, 25, 30.0f);
    fill_wavy(&src);
    /* 30 -> 60: every other frame is a source frame, bit for bit */
    assert_int_equal(mm_clip_resample_interp(&up, &src, 60.0f, MM_INTERP_CUBIC, NULL), MM_OK);
    assert_int_equal(up.frame_count, 49);
    for (int f = 0; f < src.frame_count; ++f) {
        assert_memory_equal(mm_clip_rotations(&up, 2 * f), mm_clip_rotations(&src, f), sizeof(mm_quat) * 3);
        assert_memory_equal(mm_clip_positions(&up, 2 * f), mm_clip_positions(&src, f), sizeof(mm_vec3) * 3);
    }
    for (int f = 0; f < up.frame_count; ++f)
        for (int j = 0; j < 3; ++j) assert_near(quat_len(mm_clip_rotations(&up, f)[j]), 1, 1e-6);
    /* 24 -> 60: every fifth frame is every second source frame */
    mm_clip s24;
    make_arm_clip(&s24, 25, 24.0f);
    fill_wavy(&s24);
    assert_int_equal(mm_clip_resample_interp(&odd, &s24, 60.0f, MM_INTERP_CUBIC, NULL), MM_OK);
    assert_int_equal(odd.frame_count, 61);
    for (int f = 0; f < s24.frame_count; f += 2)
        assert_memory_equal(mm_clip_positions(&odd, f / 2 * 5), mm_clip_positions(&s24, f),
                            sizeof(mm_vec3) * 3);
    /* 120 -> 60: frames sampled, not filtered (documented): every other source frame */
    mm_clip s120;
    make_arm_clip(&s120, 25, 120.0f);
    fill_wavy(&s120);
    assert_int_equal(mm_clip_resample_interp(&down, &s120, 60.0f, MM_INTERP_CUBIC, NULL), MM_OK);
    assert_int_equal(down.frame_count, 13);
    for (int f = 0; f < down.frame_count; ++f)
        assert_memory_equal(mm_clip_rotations(&down, f), mm_clip_rotations(&s120, 2 * f),
                            sizeof(mm_quat) * 3);
    /* the same through mm_clip_sample_frame; clamped and NaN positions like mm_clip_sample */
    mm_quat r[3];
    mm_vec3 p[3];
    mm_clip_sample_frame(&src, 7.0, MM_INTERP_CUBIC, r, p);
    assert_memory_equal(r, mm_clip_rotations(&src, 7), sizeof r);
    mm_clip_sample_frame(&src, 1e9, MM_INTERP_CUBIC, r, p);
    assert_memory_equal(p, mm_clip_positions(&src, 24), sizeof p);
    mm_clip_sample_frame(&src, NAN, MM_INTERP_CUBIC, r, p);
    assert_memory_equal(p, mm_clip_positions(&src, 0), sizeof p);
    assert_int_equal(mm_clip_resample_interp(&down, &src, 60.0f, (mm_interp)7, NULL),
                     MM_ERR_INVALID_ARGUMENT);
    mm_clip_free(&src);
    mm_clip_free(&up);
    mm_clip_free(&down);
    mm_clip_free(&odd);
    mm_clip_free(&s24);
    mm_clip_free(&s120);
}

static void test_clip_cubic_uniform_motion(void **state)
{
    (void)state;
    /* constant velocity and constant angular velocity: reproduced between the frames, ends
     * included (the one-sided end tangents are exact here too) */
    mm_clip src, up;
    make_arm_clip(&src, 11, 30.0f);
    mm_quat base = mm_quat_from_axis_angle(mm_vec3_make(1, 1, 0), 0.4f);
    mm_vec3 w = mm_vec3_make(0.1f, 0.2f, -0.15f);
    mm_vec3 o = mm_vec3_make(0.5f, 1, -2), v = mm_vec3_make(0.05f, 0, 0.04f);
    for (int f = 0; f < 11; ++f) {
        mm_clip_rotations(&src, f)[1] = uniform_key(base, w, f);
        mm_clip_positions(&src, f)[0] = mm_vec3_add(o, mm_vec3_scale(v, (float)f));
    }
    assert_int_equal(mm_clip_resample_interp(&up, &src, 120.0f, MM_INTERP_CUBIC, NULL), MM_OK);
    assert_int_equal(up.frame_count, 41);
    for (int f = 0; f < up.frame_count; ++f) {
        double x = f / 4.0;
        assert_near(
            mm_vec3_distance(mm_clip_positions(&up, f)[0], mm_vec3_add(o, mm_vec3_scale(v, (float)x))), 0,
            1e-6);
        assert_same_rotation(mm_clip_rotations(&up, f)[1], uniform_key(base, w, x), 2e-6);
    }
    mm_clip_free(&up);
    mm_clip_free(&src);
}

/* Largest |x(f) - 2 x(f-1) + x(f-2) - expect| of a world joint over output frames [from, to]
 * (centred on f-1) of clip resampled at ratio output frames per source frame. */
static double worst_second_difference(const mm_clip *clip, mm_interp interp, int ratio, int j, int from,
                                      int to, double expect)
{
    double worst = 0.0;
    for (int f = from; f <= to; ++f) {
        mm_vec3 a = world_at(clip, (f - 1.0) / ratio, interp, j),
                b = world_at(clip, (double)f / ratio, interp, j),
                c = world_at(clip, (f + 1.0) / ratio, interp, j);
        mm_vec3 d = mm_vec3_add(mm_vec3_sub(a, mm_vec3_scale(b, 2)), c);
        worst = fmax(worst, fabs(mm_vec3_length(d) - expect));
    }
    return worst;
}

static void test_clip_cubic_quadratic_no_spikes(void **state)
{
    (void)state;
    /* The root accelerates at a = 2 m/s^2 along X (x = t^2) and the arm turns at an angular
     * acceleration (angle = t^2 rad), sampled at 30 fps and read at 60. The true second difference
     * of the root is a / 60^2 = 1/1800 m. Linear reading puts all of a source step's change of
     * velocity on the source frame: there the second difference is (x[k-1] - 2 x[k] + x[k+1]) / 2
     * = a / 30^2 / 2 = 1/900 m (twice the true one) and 0 halfway, so its error is 1/1800 m at
     * every source frame. The cubic through a parabola is the parabola on every segment whose
     * tangents are both central (frames 1 .. n-2), so its error there is float rounding only. */
    mm_clip src;
    make_arm_clip(&src, 31, 30.0f);
    for (int f = 0; f < 31; ++f) {
        double t = f / 30.0;
        mm_clip_positions(&src, f)[0] = mm_vec3_make((float)(t * t), 0, 0);
        mm_clip_rotations(&src, f)[1] = mm_quat_from_axis_angle(mm_vec3_make(0, 0, 1), (float)(t * t));
    }
    double truth = 2.0 / 3600.0;
    /* output frames 4 .. 56: second differences centred on frames between source frames 1.5 and
     * 28.5, inside the segments with central tangents */
    double lin = worst_second_difference(&src, MM_INTERP_LINEAR, 2, 0, 4, 56, truth);
    double cub = worst_second_difference(&src, MM_INTERP_CUBIC, 2, 0, 4, 56, truth);
    assert_near(lin, 1.0 / 1800.0, 1e-6);
    assert_true(cub < 0.01 * lin);
    /* the hand, one unit from the turning arm's joint: its second difference follows the turn's
     * angular acceleration and the centripetal term, smoothly; linear again spikes at the source
     * frames */
    double spike_lin = 0.0, spike_cub = 0.0;
    for (int f = 4; f <= 56; f += 2) { /* even output frames are source frames */
        double l[2], c[2];
        for (int k = 0; k < 2; ++k) { /* the source frame, then the frame halfway after it */
            int g = f + k;
            mm_vec3 a = world_at(&src, (g - 1.0) / 2, MM_INTERP_LINEAR, 2),
                    b = world_at(&src, g / 2.0, MM_INTERP_LINEAR, 2),
                    cc = world_at(&src, (g + 1.0) / 2, MM_INTERP_LINEAR, 2);
            l[k] = mm_vec3_length(mm_vec3_add(mm_vec3_sub(a, mm_vec3_scale(b, 2)), cc));
            a = world_at(&src, (g - 1.0) / 2, MM_INTERP_CUBIC, 2);
            b = world_at(&src, g / 2.0, MM_INTERP_CUBIC, 2);
            cc = world_at(&src, (g + 1.0) / 2, MM_INTERP_CUBIC, 2);
            c[k] = mm_vec3_length(mm_vec3_add(mm_vec3_sub(a, mm_vec3_scale(b, 2)), cc));
        }
        /* how much the source frame's second difference differs from its neighbour's */
        spike_lin = fmax(spike_lin, fabs(l[0] - l[1]));
        spike_cub = fmax(spike_cub, fabs(c[0] - c[1]));
    }
    /* linear: at least the root's 1/1800 (the arm's angle goes the same way at radius 1) */
    assert_true(spike_lin > 4e-4);
    assert_true(spike_cub < 0.05 * spike_lin);
    mm_clip_free(&src);
}

/* One-sided derivatives of the world position of joint j at frame position k, second order:
 * (3 x(k) - 4 x(k - h) + x(k - 2h)) / 2h and the mirror image; returns their distance. */
static double derivative_jump(const mm_clip *clip, mm_interp interp, int j, int k, double h)
{
    mm_vec3 x0 = world_at(clip, k, interp, j);
    mm_vec3 l1 = world_at(clip, k - h, interp, j), l2 = world_at(clip, k - 2 * h, interp, j);
    mm_vec3 r1 = world_at(clip, k + h, interp, j), r2 = world_at(clip, k + 2 * h, interp, j);
    mm_vec3 left = mm_vec3_scale(mm_vec3_add(mm_vec3_sub(mm_vec3_scale(x0, 3), mm_vec3_scale(l1, 4)), l2),
                                 (float)(0.5 / h));
    mm_vec3 right = mm_vec3_scale(
        mm_vec3_add(mm_vec3_sub(mm_vec3_scale(r1, 4), mm_vec3_scale(x0, 3)), mm_vec3_scale(r2, -1)),
        (float)(0.5 / h));
    return mm_vec3_distance(left, right);
}

static void test_clip_cubic_velocity_continuous(void **state)
{
    (void)state;
    /* Across every inner frame the velocity (per frame) on the left and on the right agree to
     * the estimate's own error (h^2 times the third derivative, and float rounding over 2h)
     * with the cubic; linear jumps by the change of slope between the steps. Root position
     * (translation) and hand (the arm's rotation). */
    mm_clip src;
    make_arm_clip(&src, 16, 30.0f);
    fill_wavy(&src);
    double h = 0.01, worst_cub = 0.0, least_lin = INFINITY;
    for (int j = 0; j < 3; j += 2)
        for (int k = 1; k < 15; ++k) {
            double c = derivative_jump(&src, MM_INTERP_CUBIC, j, k, h);
            double l = derivative_jump(&src, MM_INTERP_LINEAR, j, k, h);
            worst_cub = fmax(worst_cub, c);
            least_lin = fmin(least_lin, l);
            assert_true(c < 0.1 * l);
        }
    /* measured: cubic at most 1.1e-4, linear at least 3.4e-3 */
    assert_true(worst_cub < 5e-4);
    assert_true(least_lin > 3e-3);
    mm_clip_free(&src);
}

static void test_clip_cubic_short_and_flipped(void **state)
{
    (void)state;
    /* 2 frames: both tangents are the one step, so the cubic is slerp and lerp */
    mm_clip two, lin, cub;
    make_arm_clip(&two, 2, 30.0f);
    mm_clip_rotations(&two, 1)[1] = mm_quat_from_axis_angle(mm_vec3_make(0.3f, 1, 0.2f), 1.1f);
    mm_clip_positions(&two, 1)[0] = mm_vec3_make(0.2f, -0.1f, 0.4f);
    assert_int_equal(mm_clip_resample_interp(&lin, &two, 240.0f, MM_INTERP_LINEAR, NULL), MM_OK);
    assert_int_equal(mm_clip_resample_interp(&cub, &two, 240.0f, MM_INTERP_CUBIC, NULL), MM_OK);
    assert_int_equal(cub.frame_count, 9);
    for (int f = 0; f < 9; ++f)
        for (int j = 0; j < 3; ++j) {
            assert_same_rotation(mm_clip_rotations(&cub, f)[j], mm_clip_rotations(&lin, f)[j], 2e-6);
            assert_near(mm_vec3_distance(mm_clip_positions(&cub, f)[j], mm_clip_positions(&lin, f)[j]), 0,
                        1e-6);
        }
    mm_clip_free(&lin);
    mm_clip_free(&cub);
    mm_clip_free(&two);

    /* 3 frames at a constant turn and speed: exact (one-sided ends agree with the centre) */
    mm_clip three;
    make_arm_clip(&three, 3, 30.0f);
    mm_quat base = mm_quat_from_axis_angle(mm_vec3_make(0, 0, 1), 0.3f);
    mm_vec3 w = mm_vec3_make(0.2f, 0.4f, 0.1f);
    for (int f = 0; f < 3; ++f) {
        mm_clip_rotations(&three, f)[1] = uniform_key(base, w, f);
        mm_clip_positions(&three, f)[0] = mm_vec3_make(0.1f * f, 0, 0);
    }
    assert_int_equal(mm_clip_resample_interp(&cub, &three, 90.0f, MM_INTERP_CUBIC, NULL), MM_OK);
    assert_int_equal(cub.frame_count, 7);
    for (int f = 0; f < 7; ++f) {
        assert_same_rotation(mm_clip_rotations(&cub, f)[1], uniform_key(base, w, f / 3.0), 2e-6);
        assert_near(mm_clip_positions(&cub, f)[0].x, 0.1 * f / 3.0, 1e-6);
    }
    mm_clip_free(&cub);

    /* the same keys with every other one given as -q: the same rotations, and unit */
    mm_clip_rotations(&three, 1)[1] = quat_neg(mm_clip_rotations(&three, 1)[1]);
    assert_int_equal(mm_clip_resample_interp(&cub, &three, 90.0f, MM_INTERP_CUBIC, NULL), MM_OK);
    for (int f = 0; f < 7; ++f) {
        assert_same_rotation(mm_clip_rotations(&cub, f)[1], uniform_key(base, w, f / 3.0), 2e-6);
        assert_near(quat_len(mm_clip_rotations(&cub, f)[1]), 1, 1e-6);
    }
    mm_clip_free(&cub);
    mm_clip_free(&three);

    /* a longer wavy clip with hemisphere flips in the source: the same poses as without */
    mm_clip wavy, flipped, a, b;
    make_arm_clip(&wavy, 12, 30.0f);
    fill_wavy(&wavy);
    assert_int_equal(mm_clip_copy(&flipped, &wavy, NULL), MM_OK);
    for (int f = 0; f < 12; f += 3)
        for (int j = 0; j < 3; ++j)
            mm_clip_rotations(&flipped, f)[j] = quat_neg(mm_clip_rotations(&flipped, f)[j]);
    assert_int_equal(mm_clip_resample_interp(&a, &wavy, 60.0f, MM_INTERP_CUBIC, NULL), MM_OK);
    assert_int_equal(mm_clip_resample_interp(&b, &flipped, 60.0f, MM_INTERP_CUBIC, NULL), MM_OK);
    for (int f = 0; f < a.frame_count; ++f)
        for (int j = 0; j < 3; ++j) {
            assert_same_rotation(mm_clip_rotations(&a, f)[j], mm_clip_rotations(&b, f)[j], 2e-6);
            assert_near(quat_len(mm_clip_rotations(&b, f)[j]), 1, 1e-6);
        }
    mm_clip_free(&a);
    mm_clip_free(&b);
    mm_clip_free(&wavy);
    mm_clip_free(&flipped);

    /* one frame and none: that frame, the rest pose */
    mm_clip one;
    make_arm_clip(&one, 1, 30.0f);
    mm_clip_positions(&one, 0)[0] = mm_vec3_make(3, 2, 1);
    assert_int_equal(mm_clip_resample_interp(&cub, &one, 60.0f, MM_INTERP_CUBIC, NULL), MM_OK);
    assert_int_equal(cub.frame_count, 1);
    assert_near(mm_clip_positions(&cub, 0)[0].x, 3, 0);
    mm_clip_free(&cub);
    mm_clip_free(&one);
}

static void test_clip_cubic_step_bounded(void **state)
{
    (void)state;
    /* a jump of 1 (translation) and of 1 rad (rotation) between frames 4 and 5 of 10: the
     * cubic stays within 1/8 of the step outside it (documented bound; the value is 2/27) */
    mm_clip src, up;
    make_arm_clip(&src, 10, 30.0f);
    for (int f = 5; f < 10; ++f) {
        mm_clip_positions(&src, f)[0] = mm_vec3_make(1, 0, 0);
        mm_clip_rotations(&src, f)[1] = mm_quat_from_axis_angle(mm_vec3_make(0, 1, 0), 1.0f);
    }
    assert_int_equal(mm_clip_resample_interp(&up, &src, 300.0f, MM_INTERP_CUBIC, NULL), MM_OK);
    double lo = 0, hi = 1, alo = 0, ahi = 1;
    for (int f = 0; f < up.frame_count; ++f) {
        double x = mm_clip_positions(&up, f)[0].x;
        mm_quat q = mm_clip_rotations(&up, f)[1];
        double angle = 2.0 * atan2(q.y, q.w);
        lo = fmin(lo, x);
        hi = fmax(hi, x);
        alo = fmin(alo, angle);
        ahi = fmax(ahi, angle);
    }
    assert_true(lo > -0.125 && hi < 1.125);
    assert_true(alo > -0.125 && ahi < 1.125);
    assert_near(lo, -2.0 / 27.0, 2e-3);
    mm_clip_free(&up);
    mm_clip_free(&src);
}

/* ---- the database's extraction ------------------------------------------------------------ */

static void test_extract_uses_neighbours(void **state)
{
    (void)state;
    /* frames [10, 20) of a 30 fps parabola, extracted at 1/60 s: exact everywhere, the range's
     * ends included, since the tangents there come from frames 9 and 20 */
    mm_clip src, out;
    make_arm_clip(&src, 31, 30.0f);
    for (int f = 0; f < 31; ++f) {
        double t = f / 30.0;
        mm_clip_positions(&src, f)[0] = mm_vec3_make((float)(t * t), (float)(0.5 * t), 0);
    }
    assert_int_equal(mm__clip_extract(&src, 10, 20, 1.0f / 60.0f, &out, NULL), MM_OK);
    assert_int_equal(out.frame_count, 19);
    assert_near(out.fps, 60, 1e-3);
    for (int f = 0; f < out.frame_count; ++f) {
        double t = (10 + f / 2.0) / 30.0;
        assert_near(mm_clip_positions(&out, f)[0].x, t * t, 1e-6);
        assert_near(mm_clip_positions(&out, f)[0].y, 0.5 * t, 1e-6);
        if (f % 2 == 0)
            assert_memory_equal(mm_clip_positions(&out, f), mm_clip_positions(&src, 10 + f / 2),
                                sizeof(mm_vec3) * 3);
    }
    mm_clip_free(&out);
    /* the same rate keeps the frames as they are */
    assert_int_equal(mm__clip_extract(&src, 3, 8, 1.0f / 30.0f, &out, NULL), MM_OK);
    assert_int_equal(out.frame_count, 5);
    assert_memory_equal(out.positions, mm_clip_positions(&src, 3), sizeof(mm_vec3) * 3 * 5);
    mm_clip_free(&out);
    assert_int_equal(mm__clip_extract(&src, 30, 31, 1.0f / 60.0f, &out, NULL), MM_ERR_OUT_OF_RANGE);
    mm_clip_free(&src);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_vec3_catmull_rom),
        cmocka_unit_test(test_quat_hermite_slerp),
        cmocka_unit_test(test_quat_catmull_rom_uniform),
        cmocka_unit_test(test_clip_cubic_exact_at_frames),
        cmocka_unit_test(test_clip_cubic_uniform_motion),
        cmocka_unit_test(test_clip_cubic_quadratic_no_spikes),
        cmocka_unit_test(test_clip_cubic_velocity_continuous),
        cmocka_unit_test(test_clip_cubic_short_and_flipped),
        cmocka_unit_test(test_clip_cubic_step_bounded),
        cmocka_unit_test(test_extract_uses_neighbours),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
