/* Partial forward kinematics (mm_skeleton_global_from) against an independent computation: rotation
 * matrices and translations composed in double down a random hierarchy; the same floats as the
 * loop it stands for; joints before `first` neither written nor needed beyond their globals. */
#include <math.h>

#include <mm/skeleton.h>

#include "test_util.h"

#define JOINTS 24

typedef struct dxform {
    double r[3][3], t[3];
} dxform;

/* The rotation matrix of a unit quaternion {x, y, z, w}, in double. */
static void matrix_of(mm_quat q, double r[3][3])
{
    const double x = q.x, y = q.y, z = q.z, w = q.w;
    r[0][0] = 1 - 2 * (y * y + z * z), r[0][1] = 2 * (x * y - z * w), r[0][2] = 2 * (x * z + y * w);
    r[1][0] = 2 * (x * y + z * w), r[1][1] = 1 - 2 * (x * x + z * z), r[1][2] = 2 * (y * z - x * w);
    r[2][0] = 2 * (x * z - y * w), r[2][1] = 2 * (y * z + x * w), r[2][2] = 1 - 2 * (x * x + y * y);
}

/* parent * (rotation, translation): R = Rp Rl, t = Rp tl + tp. */
static dxform compose(const dxform *parent, mm_quat rotation, mm_vec3 translation)
{
    double l[3][3], tl[3] = {translation.x, translation.y, translation.z};
    matrix_of(rotation, l);
    dxform g;
    for (int i = 0; i < 3; ++i) {
        g.t[i] = parent->t[i];
        for (int k = 0; k < 3; ++k) {
            g.t[i] += parent->r[i][k] * tl[k];
            g.r[i][k] = 0.0;
            for (int m = 0; m < 3; ++m) g.r[i][k] += parent->r[i][m] * l[m][k];
        }
    }
    return g;
}

static mm_quat random_rotation(test_rng *rng)
{
    mm_vec3 axis = mm_vec3_make((float)test_rng_uniform(rng, -1, 1), (float)test_rng_uniform(rng, -1, 1),
                                (float)test_rng_uniform(rng, -1, 1));
    if (mm_vec3_length(axis) < 1e-3f) axis = mm_vec3_make(0, 1, 0);
    return mm_quat_from_axis_angle(mm_vec3_normalize(axis), (float)test_rng_uniform(rng, -3.0, 3.0));
}

static mm_vec3 random_offset(test_rng *rng)
{
    return mm_vec3_make((float)test_rng_uniform(rng, -0.5, 0.5), (float)test_rng_uniform(rng, -0.5, 0.5),
                        (float)test_rng_uniform(rng, -0.5, 0.5));
}

/* A random hierarchy (each parent anywhere before its child) and pose. */
static void random_pose(test_rng *rng, mm_joint *joints, mm_quat *rot, mm_vec3 *pos, mm_xform *root)
{
    memset(joints, 0, sizeof(mm_joint) * JOINTS);
    joints[0].parent = -1;
    for (int j = 0; j < JOINTS; ++j) {
        if (j > 0) joints[j].parent = (int)(test_rng_next(rng) % (uint64_t)j);
        rot[j] = random_rotation(rng);
        pos[j] = random_offset(rng);
    }
    *root = mm_xform_make(random_rotation(rng), mm_vec3_make(1.5f, 0.0f, -2.0f));
}

static void test_against_double(void **state)
{
    (void)state;
    test_rng rng = {2024};
    mm_joint joints[JOINTS];
    mm_quat rot[JOINTS];
    mm_vec3 pos[JOINTS];
    mm_xform global[JOINTS];
    for (int trial = 0; trial < 50; ++trial) {
        random_pose(&rng, joints, rot, pos, &global[0]);
        mm_skeleton_global_from(joints, JOINTS, 1, rot, pos, global);
        dxform truth[JOINTS];
        matrix_of(global[0].rotation, truth[0].r);
        truth[0].t[0] = global[0].translation.x, truth[0].t[1] = global[0].translation.y,
        truth[0].t[2] = global[0].translation.z;
        for (int j = 1; j < JOINTS; ++j) truth[j] = compose(&truth[joints[j].parent], rot[j], pos[j]);
        for (int j = 0; j < JOINTS; ++j) {
            double r[3][3];
            matrix_of(global[j].rotation, r);
            const float t[3] = {global[j].translation.x, global[j].translation.y, global[j].translation.z};
            for (int i = 0; i < 3; ++i) {
                assert_near(t[i], truth[j].t[i], 1e-5);
                for (int k = 0; k < 3; ++k) assert_near(r[i][k], truth[j].r[i][k], 1e-5);
            }
        }
    }
}

/* The same floats as the loop the controller writes, from any first joint; the joints before first
 * (joint 0 included) are left as they are. */
static void test_partial_same_floats(void **state)
{
    (void)state;
    test_rng rng = {77};
    mm_joint joints[JOINTS];
    mm_quat rot[JOINTS];
    mm_vec3 pos[JOINTS];
    mm_xform root, expected[JOINTS], global[JOINTS];
    random_pose(&rng, joints, rot, pos, &root);
    expected[0] = root;
    for (int j = 1; j < JOINTS; ++j)
        expected[j] = mm_xform_mul(expected[joints[j].parent], mm_xform_make(rot[j], pos[j]));
    const int firsts[] = {-3, 0, 1, 2, 7, JOINTS - 1, JOINTS};
    for (int f = 0; f < (int)(sizeof firsts / sizeof firsts[0]); ++f) {
        const int first = firsts[f] < 1 ? 1 : firsts[f];
        /* the joints before first hold their globals; the rest hold garbage that must be replaced */
        for (int j = 0; j < JOINTS; ++j)
            global[j] =
                j < first ? expected[j] : mm_xform_make(mm_quat_make(NAN, 0, 0, 0), mm_vec3_make(9, 9, 9));
        mm_xform before[JOINTS];
        memcpy(before, global, sizeof before);
        mm_skeleton_global_from(joints, JOINTS, firsts[f], rot, pos, global);
        assert_memory_equal(global, expected, sizeof global);
        assert_memory_equal(global, before, sizeof(mm_xform) * (size_t)first); /* untouched */
    }
    /* after a change to one joint's local rotation, recomputing from it gives the whole pose again */
    rot[9] = random_rotation(&rng);
    for (int j = 9; j < JOINTS; ++j)
        expected[j] = mm_xform_mul(expected[joints[j].parent], mm_xform_make(rot[j], pos[j]));
    mm_skeleton_global_from(joints, JOINTS, 9, rot, pos, global);
    assert_memory_equal(global, expected, sizeof global);
    /* NULL arrays: nothing happens */
    mm_skeleton_global_from(NULL, JOINTS, 1, rot, pos, global);
    mm_skeleton_global_from(joints, JOINTS, 1, NULL, pos, global);
    mm_skeleton_global_from(joints, JOINTS, 1, rot, pos, NULL);
    assert_memory_equal(global, expected, sizeof global);
}

/* Many random poses, some rotations about a coordinate axis (exact zeros in them): the same floats
 * as mm_xform_mul joint by joint. */
static void test_many_poses_same_floats(void **state)
{
    (void)state;
    test_rng rng = {4242};
    mm_joint joints[JOINTS];
    mm_quat rot[JOINTS];
    mm_vec3 pos[JOINTS];
    mm_xform root, expected[JOINTS], global[JOINTS];
    for (int trial = 0; trial < 2000; ++trial) {
        random_pose(&rng, joints, rot, pos, &root);
        for (int j = 0; j < JOINTS; j += 3) {
            float angle = (float)test_rng_uniform(&rng, -3.0, 3.0);
            mm_vec3 axis = j % 2 ? mm_vec3_make(0, 1, 0) : mm_vec3_make(-0.0f, 0, 1);
            rot[j] = mm_quat_from_axis_angle(axis, angle);
            if (j % 6 == 0) pos[j] = mm_vec3_make(0.0f, -0.0f, 0.25f);
        }
        expected[0] = global[0] = root;
        for (int j = 1; j < JOINTS; ++j)
            expected[j] = mm_xform_mul(expected[joints[j].parent], mm_xform_make(rot[j], pos[j]));
        mm_skeleton_global_from(joints, JOINTS, 1, rot, pos, global);
        assert_memory_equal(global, expected, sizeof global);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_against_double),
        cmocka_unit_test(test_many_poses_same_floats),
        cmocka_unit_test(test_partial_same_floats),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
