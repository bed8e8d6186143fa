/* Skeleton, clip and forward kinematics against hand-computed poses. */
#include <math.h>

#include <mm/clip.h>

#include "test_util.h"

/* Root at the origin, a 1-unit "arm" along +X, a 1-unit "hand" along +X after it. */
static void make_arm(mm_skeleton *s)
{
    assert_int_equal(mm_skeleton_init(s, 3, NULL), MM_OK);
    strcpy(s->joints[0].name, "root");
    strcpy(s->joints[1].name, "arm");
    strcpy(s->joints[2].name, "hand");
    s->joints[1].offset = mm_vec3_make(1, 0, 0);
    s->joints[2].offset = mm_vec3_make(1, 0, 0);
    s->joints[2].has_end_site = true;
    s->joints[2].end_site = mm_vec3_make(0.5f, 0, 0);
}

static void test_fk_hand_computed(void **state)
{
    (void)state;
    mm_skeleton s;
    make_arm(&s);
    assert_int_equal(mm_skeleton_validate(&s, NULL), MM_OK);
    mm_quat rot[3] = {mm_quat_from_axis_angle(mm_vec3_make(0, 1, 0), (float)(MM_PI / 2)),
                      mm_quat_from_axis_angle(mm_vec3_make(0, 0, 1), (float)(MM_PI / 2)), mm_quat_identity()};
    mm_vec3 pos[3] = {mm_vec3_make(5, 0, 0), s.joints[1].offset, s.joints[2].offset};
    mm_xform g[3];
    mm_fk(&s, rot, pos, g);
    /* Root turned 90 degrees about Y: its +X points to -Z. The arm sits 1 unit along it. */
    assert_near(g[1].translation.x, 5, 1e-6);
    assert_near(g[1].translation.z, -1, 1e-6);
    /* The arm bends 90 degrees about its own Z: the hand goes up (+Y). */
    assert_near(g[2].translation.x, 5, 1e-6);
    assert_near(g[2].translation.y, 1, 1e-6);
    assert_near(g[2].translation.z, -1, 1e-6);
    /* Height of this pose: End Site at y = 1.5, root at 0. */
    assert_near(mm_skeleton_estimate_height(&s, rot, pos), 1.5, 1e-6);
    /* Rest pose: everything on y = 0. */
    assert_near(mm_skeleton_estimate_height(&s, NULL, NULL), 0, 1e-6);

    mm_quat lr[3];
    mm_vec3 lp[3];
    mm_global_to_local(&s, g, lr, lp);
    for (int j = 0; j < 3; ++j) {
        assert_true(fabsf(mm_quat_dot(lr[j], rot[j])) > 1 - 1e-6f);
        assert_near(mm_vec3_distance(lp[j], pos[j]), 0, 1e-6);
    }
    mm_skeleton_free(&s);
}

static void test_skeleton_validate_and_find(void **state)
{
    (void)state;
    mm_skeleton s;
    make_arm(&s);
    assert_int_equal(mm_skeleton_find(&s, "hand"), 2);
    assert_int_equal(mm_skeleton_find(&s, "foot"), -1);
    mm_error err;
    memset(&err, 0, sizeof err);
    strcpy(s.joints[2].name, "arm");
    assert_int_equal(mm_skeleton_validate(&s, &err), MM_ERR_DUPLICATE_NAME);
    assert_non_null(strstr(err.message, "arm"));
    strcpy(s.joints[2].name, "hand");
    s.joints[1].parent = 2;
    assert_int_equal(mm_skeleton_validate(&s, &err), MM_ERR_INVALID_ARGUMENT);
    s.joints[1].parent = 0;
    s.joints[1].offset.y = NAN;
    assert_int_equal(mm_skeleton_validate(&s, &err), MM_ERR_BAD_NUMBER);
    mm_skeleton_free(&s);
    assert_int_equal(mm_skeleton_init(&s, 0, NULL), MM_ERR_INVALID_ARGUMENT);
    assert_int_equal(mm_skeleton_init(&s, MM_MAX_JOINTS + 1, NULL), MM_ERR_INVALID_ARGUMENT);
}

/* A clip whose root turns at a constant rate about Y and moves at constant speed along X. */
static void make_turning_clip(mm_clip *clip, int frames, float fps)
{
    mm_skeleton s;
    make_arm(&s);
    assert_int_equal(mm_clip_init(clip, &s, frames, fps, NULL), MM_OK);
    mm_skeleton_free(&s);
    for (int f = 0; f < frames; ++f) {
        float t = (float)f / fps;
        mm_clip_rotations(clip, f)[0] = mm_quat_from_axis_angle(mm_vec3_make(0, 1, 0), 0.5f * t);
        mm_clip_positions(clip, f)[0] = mm_vec3_make(2.0f * t, 0, 0);
    }
}

static void test_clip_init_sample_resample(void **state)
{
    (void)state;
    mm_clip clip;
    make_turning_clip(&clip, 31, 30.0f);
    assert_near(mm_clip_duration(&clip), 1.0, 1e-6);
    /* Rest pose filled in for the non-root joints. */
    assert_near(mm_clip_positions(&clip, 7)[1].x, 1.0, 0);

    /* Sampling between frames: angle and position are linear in time here. */
    mm_quat r[3];
    mm_vec3 p[3];
    mm_clip_sample(&clip, 0.51f, r, p);
    assert_near(p[0].x, 1.02, 1e-5);
    assert_near(2 * acos(fabs(r[0].w)), 0.255, 1e-5);
    mm_clip_sample(&clip, 5.0f, r, p); /* clamped to the end */
    assert_near(p[0].x, 2.0, 1e-5);
    mm_clip_sample(&clip, NAN, r, p); /* NaN time reads frame 0 */
    assert_near(p[0].x, 0.0, 1e-6);

    mm_clip up;
    assert_int_equal(mm_clip_resample(&up, &clip, 120.0f, NULL), MM_OK);
    assert_int_equal(up.frame_count, 121);
    for (int f = 0; f < up.frame_count; ++f) {
        float t = (float)f / 120.0f;
        assert_near(mm_clip_positions(&up, f)[0].x, 2.0 * t, 1e-5);
        float angle = 2.0f * acosf(fminf(1.0f, fabsf(mm_clip_rotations(&up, f)[0].w)));
        assert_near(angle, 0.5 * t, 2e-4);
    }
    mm_clip down;
    assert_int_equal(mm_clip_resample(&down, &clip, 7.0f, NULL), MM_OK);
    assert_int_equal(down.frame_count, 8); /* floor(1 s * 7) + 1 */
    mm_clip_free(&down);
    assert_int_equal(mm_clip_resample(&down, &clip, 0.0f, NULL), MM_ERR_INVALID_ARGUMENT);

    mm_clip_scale(&up, 0.01f);
    assert_near(mm_clip_positions(&up, 120)[0].x, 0.02, 1e-7);
    assert_near(up.skeleton.joints[2].end_site.x, 0.005, 1e-8);

    mm_clip copy;
    assert_int_equal(mm_clip_copy(&copy, &clip, NULL), MM_OK);
    assert_memory_equal(copy.rotations, clip.rotations, sizeof(mm_quat) * 31 * 3);
    mm_clip_free(&copy);
    mm_clip_free(&up);
    mm_clip_free(&clip);
    assert_null(clip.rotations);
    assert_int_equal(mm_clip_init(&clip, NULL, 1, 30, NULL), MM_ERR_INVALID_ARGUMENT);
}

/* Counting allocator: the clip uses the caller's allocator for every allocation. */
static int live_allocations;
static void *counting_alloc(size_t size, void *user)
{
    (void)user;
    ++live_allocations;
    return malloc(size);
}
static void counting_free(void *p, void *user)
{
    (void)user;
    if (p) --live_allocations;
    free(p);
}

static void test_custom_allocator(void **state)
{
    (void)state;
    mm_allocator a = {counting_alloc, counting_free, NULL};
    mm_skeleton s;
    make_arm(&s);
    mm_clip clip;
    assert_int_equal(mm_clip_init(&clip, &s, 10, 60.0f, &a), MM_OK);
    assert_int_equal(live_allocations, 3); /* joints, rotations, positions */
    mm_clip_free(&clip);
    assert_int_equal(live_allocations, 0);
    mm_skeleton_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fk_hand_computed),
        cmocka_unit_test(test_skeleton_validate_and_find),
        cmocka_unit_test(test_clip_init_sample_resample),
        cmocka_unit_test(test_custom_allocator),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
