/* The LAFAN1 config (scripts/data_configs.sh) on the real takes ($MM_DATA_DIR): builds, mirrors correctly,
 * finds contacts and idle where they are, and is byte-identical when built twice. */
#include <math.h>

#include <mm/config_json.h>
#include <mm/database_build.h>

#include "test_util.h"

static mm_database db;

static int build(mm_database *out)
{
    mm_config cfg;
    memset(&cfg, 0, sizeof cfg);
    mm_error err;
    memset(&err, 0, sizeof err);
    char *text = NULL;
    if (mm_config_load_json(MM_DATA_CONFIGS "/lafan1.json", &cfg, &text, &err) != MM_OK) {
        print_error("%s: %s\n", err.file, err.message);
        return -1;
    }
    mm_clip *sources = NULL;
    mm_result r = mm_config_load_sources(&cfg, &sources, &err);
    if (r == MM_OK) {
        mm_db_build_desc desc;
        memset(&desc, 0, sizeof desc);
        desc.config_json = text;
        r = mm_database_build(&cfg, sources, &desc, out, &err);
    }
    if (r != MM_OK) print_error("%s: %s\n", err.file, err.message);
    mm_config_free_sources(&cfg, sources);
    mm_config_free(&cfg);
    free(text);
    return r == MM_OK ? 0 : -1;
}

static int setup(void **state)
{
    (void)state;
    return build(&db);
}

static int teardown(void **state)
{
    (void)state;
    mm_database_free(&db);
    return 0;
}

static void test_shape(void **state)
{
    (void)state;
    assert_int_equal(db.dims, 27);
    assert_int_equal(db.joint_count, 23);
    assert_true(db.frame_count > 50000);
    assert_int_equal(db.clip_count % 2, 0);
    for (int c = 0; c < db.clip_count; c += 2) {
        assert_int_equal(db.clips[c].mirrored, 0);
        assert_int_equal(db.clips[c + 1].mirrored, 1);
        assert_int_equal(db.clips[c].frame_count, db.clips[c + 1].frame_count);
    }
}

/* Every joint of a mirrored clip is where its partner was, reflected (the skeleton is close to
 * symmetric: within 1 cm). */
static void test_mirror_positions(void **state)
{
    (void)state;
    mm_skeleton s;
    assert_int_equal(mm_skeleton_init(&s, db.joint_count, NULL), MM_OK);
    memcpy(s.joints, db.joints, sizeof(mm_joint) * (size_t)db.joint_count);
    int partner[64];
    for (int j = 0; j < db.joint_count; ++j) {
        char name[MM_NAME_MAX];
        const char *n = db.joints[j].name;
        if (strncmp(n, "Left", 4) == 0)
            snprintf(name, sizeof name, "Right%s", n + 4);
        else if (strncmp(n, "Right", 5) == 0)
            snprintf(name, sizeof name, "Left%s", n + 5);
        else
            snprintf(name, sizeof name, "%s", n);
        partner[j] = mm_skeleton_find(&s, name);
        assert_true(partner[j] >= 0);
    }
    mm_xform g[64], m[64];
    double worst = 0;
    for (int c = 0; c < db.clip_count; c += 2)
        for (int k = 0; k < db.clips[c].frame_count; k += 97) {
            int f = db.clips[c].first_frame + k, fm = db.clips[c + 1].first_frame + k;
            mm_fk(&s, mm_database_rotations(&db, f), mm_database_positions(&db, f), g);
            mm_fk(&s, mm_database_rotations(&db, fm), mm_database_positions(&db, fm), m);
            for (int j = 0; j < db.joint_count; ++j) {
                mm_vec3 want = g[partner[j]].translation;
                want.x = -want.x;
                worst = fmax(worst, mm_vec3_distance(want, m[j].translation));
            }
        }
    print_message("mirror: largest joint position error %.3g m\n", worst);
    assert_true(worst < 0.01);
    mm_skeleton_free(&s);
}

static int compare_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

/* Locomotion moves and idle stands; feet are in contact a plausible share of the time. */
static void test_motion_statistics(void **state)
{
    (void)state;
    float *speeds[2];
    int count[2] = {0, 0};
    speeds[0] = malloc(sizeof(float) * (size_t)db.frame_count);
    speeds[1] = malloc(sizeof(float) * (size_t)db.frame_count);
    long contact_frames = 0, locomotion_frames = 0;
    for (int f = 0; f < db.frame_count; ++f) {
        int type = db.clips[db.frame_clip[f]].type;
        mm_vec3 v = db.root_velocity[f];
        speeds[type][count[type]++] = sqrtf(v.x * v.x + v.z * v.z);
        if (type == MM_CLIP_LOCOMOTION) {
            ++locomotion_frames;
            contact_frames += (db.contacts[f] & (MM_CONTACT_LEFT_HEEL | MM_CONTACT_LEFT_TOE)) != 0;
        }
    }
    qsort(speeds[0], (size_t)count[0], sizeof(float), compare_float);
    qsort(speeds[1], (size_t)count[1], sizeof(float), compare_float);
    float loco = speeds[0][count[0] / 2], idle = speeds[1][count[1] / 2];
    double share = (double)contact_frames / locomotion_frames;
    print_message(
        "median root speed: locomotion %.2f m/s, idle %.3f m/s; left foot in contact %.0f%% of locomotion\n",
        loco, idle, 100 * share);
    assert_true(loco > 0.5f && loco < 4.0f);
    assert_true(idle < 0.15f);
    assert_true(share > 0.3 && share < 0.9);
    free(speeds[0]);
    free(speeds[1]);
}

static void test_deterministic(void **state)
{
    (void)state;
    mm_database again;
    assert_int_equal(build(&again), 0);
    assert_int_equal(again.size, db.size);
    assert_memory_equal(again.data, db.data, db.size);
    mm_database_free(&again);
}

int main(void)
{
    TEST_SKIP_WITHOUT_DATA_DIR();
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_shape),
        cmocka_unit_test(test_mirror_positions),
        cmocka_unit_test(test_motion_statistics),
        cmocka_unit_test(test_deterministic),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
