/* The neural controller on a scene's ground (mm_pfnn_height_scene): on a flat scene it runs bit
 * for bit as without one; on a slope the heights fed to the network (right, centre, left of every
 * trajectory sample, less the root's) are the slope's, computed here from its equation at the
 * points the input's own trajectory names. Needs the released weights ($MM_DATA_DIR/pfnn);
 * skipped without them. */
#include "test_util.h"

#include <math.h>
#include <string.h>

#include <mm/mm.h>

/* the slope: a ramp 20 m wide and 20 m long rising RISE over its length toward +Z, its foot at
 * z = SLOPE_FOOT_Z; the character starts well inside it */
#define RISE         3.0f
#define SLOPE_LENGTH 20.0f
#define SLOPE_WIDTH  20.0f
#define SLOPE_FOOT_Z (-5.0f)
/* cm: the release's side samples, either side of a trajectory point (docs/pfnn.md) */
#define SIDE_CM 25.0f
/* cm: the heights fed agree with the equation within float rounding of positions of a few metres */
#define HEIGHT_TOLERANCE_CM 0.05f
#define FRAMES              240

static mm_pfnn_network *g_net;

static int setup(void **state)
{
    (void)state;
    char dir[1024];
    if (!test_shared_data("pfnn", dir, sizeof dir)) return 0;
    return mm_pfnn_network_load(dir, NULL, &g_net, NULL) == MM_OK ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    mm_pfnn_network_free(g_net);
    return 0;
}

/* The slope's height (m) at (x, z), from its equation (the ground plane 0 off it). */
static float slope_height(float x, float z)
{
    if (fabsf(x) > 0.5f * SLOPE_WIDTH || z < SLOPE_FOOT_Z || z > SLOPE_FOOT_Z + SLOPE_LENGTH) return 0.0f;
    return RISE * (z - SLOPE_FOOT_Z) / SLOPE_LENGTH;
}

/* (x, z) turned by yaw about +Y (the release's convention: yaw 0 faces +Z). */
static void turn(float yaw, float x, float z, float *ox, float *oz)
{
    float c = cosf(yaw), s = sinf(yaw);
    *ox = c * x + s * z;
    *oz = -s * x + c * z;
}

/* The input asked for on frame k: a walk turning from +Z toward +X and back (the side samples
 * then lie across the slope at changing heights). */
static void input_at(int k, mm_pfnn_input *in)
{
    memset(in, 0, sizeof *in);
    float a = 0.8f * sinf(0.02f * (float)k);
    in->velocity = mm_vec3_make(1.4f * sinf(a), 0.0f, 1.4f * cosf(a));
    in->gait = MM_PFNN_GAIT_WALK;
}

static void test_flat_scene_identical(void **state)
{
    (void)state;
    if (!g_net) skip();
    mm_scene flat;
    mm_scene_init(&flat, 0.0f);
    mm_pfnn_controller_desc d;
    memset(&d, 0, sizeof d);
    d.network = g_net;
    mm_pfnn_controller *plain, *scened;
    assert_int_equal(mm_pfnn_controller_create(&d, &plain, NULL), MM_OK);
    d.height = mm_pfnn_height_scene;
    d.height_user = &flat;
    assert_int_equal(mm_pfnn_controller_create(&d, &scened, NULL), MM_OK);
    for (int k = 0; k < FRAMES; ++k) {
        mm_pfnn_input in;
        input_at(k, &in);
        mm_pfnn_controller_step(plain, &in, 0.0f);
        mm_pfnn_controller_step(scened, &in, 0.0f);
        const mm_pfnn_state *a = mm_pfnn_controller_state(plain), *b = mm_pfnn_controller_state(scened);
        assert_memory_equal(a->input, b->input, sizeof a->input);
        assert_memory_equal(a->output, b->output, sizeof a->output);
        assert_memory_equal(a->joint_positions, b->joint_positions, sizeof a->joint_positions);
        assert_memory_equal(&a->root_position, &b->root_position, sizeof a->root_position);
    }
    /* and it did walk: 240 frames at about 1.4 m/s */
    assert_true(mm_vec3_length(mm_pfnn_controller_state(plain)->root_position) > 2.0f);
    mm_pfnn_controller_destroy(plain);
    mm_pfnn_controller_destroy(scened);
}

static void test_slope_heights(void **state)
{
    (void)state;
    if (!g_net) skip();
    mm_scene slope;
    mm_scene_init(&slope, 0.0f);
    assert_int_equal(mm_scene_add_ramp(&slope, mm_vec3_make(0.0f, 0.0f, SLOPE_FOOT_Z + 0.5f * SLOPE_LENGTH),
                                       mm_vec3_make(SLOPE_WIDTH, RISE, SLOPE_LENGTH), 0.0f),
                     MM_OK);
    mm_pfnn_controller_desc d;
    memset(&d, 0, sizeof d);
    d.network = g_net;
    d.height = mm_pfnn_height_scene;
    d.height_user = &slope;
    mm_pfnn_controller *c;
    assert_int_equal(mm_pfnn_controller_create(&d, &c, NULL), MM_OK);
    float worst = 0.0f, spread = 0.0f;
    for (int k = 0; k < FRAMES; ++k) {
        /* the input is assembled about the root as the last frame left it */
        const mm_pfnn_state *s = mm_pfnn_controller_state(c);
        float root_x = 100.0f * s->root_position.x, root_z = 100.0f * s->root_position.z, yaw = s->root_yaw;
        mm_pfnn_input in;
        input_at(k, &in);
        mm_pfnn_controller_step(c, &in, 0.0f);
        const float *x = s->input;
        /* the root's height: the current sample's ground less its centre height */
        float root_y = 100.0f * slope_height(root_x / 100.0f, root_z / 100.0f) - x[MM_PFNN_X_HEIGHT_MID + 6];
        for (int i = 0; i < MM_PFNN_TRAJ_SAMPLES; ++i) {
            float px, pz, dx, dz, rx, rz;
            turn(yaw, x[MM_PFNN_X_TRAJ_POS_X + i], x[MM_PFNN_X_TRAJ_POS_Z + i], &px, &pz);
            turn(yaw, x[MM_PFNN_X_TRAJ_DIR_X + i], x[MM_PFNN_X_TRAJ_DIR_Z + i], &dx, &dz);
            px += root_x, pz += root_z;
            turn(atan2f(dx, dz), SIDE_CM, 0.0f, &rx, &rz);
            float right = 100.0f * slope_height((px + rx) / 100.0f, (pz + rz) / 100.0f) - root_y;
            float mid = 100.0f * slope_height(px / 100.0f, pz / 100.0f) - root_y;
            float left = 100.0f * slope_height((px - rx) / 100.0f, (pz - rz) / 100.0f) - root_y;
            assert_float_equal(x[MM_PFNN_X_HEIGHT_RIGHT + i], right, HEIGHT_TOLERANCE_CM);
            assert_float_equal(x[MM_PFNN_X_HEIGHT_MID + i], mid, HEIGHT_TOLERANCE_CM);
            assert_float_equal(x[MM_PFNN_X_HEIGHT_LEFT + i], left, HEIGHT_TOLERANCE_CM);
            worst = fmaxf(worst, fabsf(x[MM_PFNN_X_HEIGHT_RIGHT + i] - right));
            spread = fmaxf(spread, fabsf(x[MM_PFNN_X_HEIGHT_RIGHT + i] - x[MM_PFNN_X_HEIGHT_LEFT + i]));
        }
    }
    print_message("slope: fed heights within %.4f cm of the equation; right - left up to %.1f cm\n", worst,
                  spread);
    /* the heights are not flat: the slope rises about 15 cm per metre, ahead and to the sides */
    assert_true(spread > 2.0f);
    const mm_pfnn_state *s = mm_pfnn_controller_state(c);
    assert_true(s->root_position.z > 1.5f);                                               /* it walked up */
    assert_float_equal(s->root_position.y, slope_height(0.0f, s->root_position.z), 0.2f); /* on it */
    mm_pfnn_controller_destroy(c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_flat_scene_identical),
        cmocka_unit_test(test_slope_heights),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
