/* Compressed poses (mm_database_compress, docs/database.md "A smaller database for shipping"):
 * every frame's world joint positions, put through FK here from what mm_database_local_pose
 * decodes, within the bound of the floats' (on the built-in set, and on LAFAN1 when MM_DATA_DIR is
 * set); the measured error the file states is that largest distance; at most a quarter of the
 * floats' bytes; every other section byte for byte the same, so that searches give the same
 * winners; a character run on both databases plays the same frames with its joints within the
 * bound; the same bytes for any thread count and after a save and load; a crafted file refused
 * with a message naming what is wrong. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdint.h>
#include <unistd.h>

#include <mm/character.h>
#include <mm/database_build.h>
#include <mm/search.h>

#include "feet_ties.h"
#include "test_databases.h"
#include "test_util.h"

#define BOUND 0.0005f /* m: the default bound */

static mm_database synth_floats, synth_small;

static int setup(void **state)
{
    (void)state;
    if (test_build_synth_database(&synth_floats) != 0) return -1;
    mm_error err;
    memset(&err, 0, sizeof err);
    if (mm_database_compress(&synth_floats, NULL, &synth_small, &err) != MM_OK) {
        fprintf(stderr, "compress: %s\n", err.message);
        return -1;
    }
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    mm_database_free(&synth_floats);
    mm_database_free(&synth_small);
    return 0;
}

/* The largest distance over every frame between the world joint positions of a's floats and b's
 * decoded poses (mm_fk of what mm_database_local_pose gives). */
static double max_joint_error(const mm_database *a, const mm_database *b)
{
    int n = a->joint_count;
    mm_skeleton s;
    assert_int_equal(mm_skeleton_init(&s, n, NULL), MM_OK);
    memcpy(s.joints, a->joints, sizeof(mm_joint) * (size_t)n);
    mm_quat *ra = malloc(sizeof(mm_quat) * (size_t)n), *rb = malloc(sizeof(mm_quat) * (size_t)n);
    mm_vec3 *pa = malloc(sizeof(mm_vec3) * (size_t)n), *pb = malloc(sizeof(mm_vec3) * (size_t)n);
    mm_xform *ga = malloc(sizeof(mm_xform) * (size_t)n), *gb = malloc(sizeof(mm_xform) * (size_t)n);
    double worst = 0.0;
    for (int f = 0; f < a->frame_count; ++f) {
        mm_database_local_pose(a, f, ra, pa);
        mm_database_local_pose(b, f, rb, pb);
        mm_fk(&s, ra, pa, ga);
        mm_fk(&s, rb, pb, gb);
        for (int j = 0; j < n; ++j) {
            double d = mm_vec3_distance(ga[j].translation, gb[j].translation);
            worst = d > worst ? d : worst;
        }
    }
    free(ra), free(rb), free(pa), free(pb), free(ga), free(gb);
    mm_skeleton_free(&s);
    return worst;
}

/* The bytes of db's section s (the header's table, docs/format.md). */
static const unsigned char *section(const mm_database *db, int s, uint64_t *size)
{
    uint64_t off;
    memcpy(&off, (const unsigned char *)db->data + 112 + 16 * s, 8);
    memcpy(size, (const unsigned char *)db->data + 112 + 16 * s + 8, 8);
    return (const unsigned char *)db->data + off;
}

/* What a compressed database must hold against its floats: the bound, the error it states, the
 * size, and every section but the poses (10, 11 and 25-30) the same bytes. */
static void check_compressed(const mm_database *floats, const mm_database *small, float bound)
{
    assert_int_equal(floats->pose_codec, MM_POSE_FLOATS);
    assert_int_equal(small->pose_codec, MM_POSE_SEGMENTS);
    assert_null(small->rotations);
    double worst = max_joint_error(floats, small);
    printf("  %d frames: %.1f pose bytes per frame (floats %.1f), file %.1f per frame (floats %.1f), largest "
           "joint error %.4f mm (stated %.4f mm)\n",
           floats->frame_count, (double)mm_database_pose_bytes(small) / small->frame_count,
           (double)mm_database_pose_bytes(floats) / floats->frame_count,
           (double)small->size / small->frame_count, (double)floats->size / floats->frame_count,
           1000.0 * worst, 1000.0 * small->compressed.max_error);
    assert_true(worst <= bound);
    assert_true(fabs(worst - small->compressed.max_error) <= 1e-7);
    assert_true(small->compressed.error_bound == bound);
    assert_true(mm_database_pose_bytes(small) * 4 <= mm_database_pose_bytes(floats));
    assert_int_equal(mm_database_pose_bytes(floats), (size_t)floats->frame_count *
                                                         (size_t)floats->joint_count *
                                                         (sizeof(mm_quat) + sizeof(mm_vec3)));
    for (int s = 0; s < 25; ++s) {
        if (s == 10 || s == 11) continue;
        uint64_t na, nb;
        const unsigned char *a = section(floats, s, &na), *b = section(small, s, &nb);
        assert_true(na == nb);
        if (na && memcmp(a, b, (size_t)na) != 0) fail_msg("section %d differs", s);
    }
    uint64_t total = 0, size;
    for (int s = 25; s < 31; ++s) section(small, s, &size), total += size;
    assert_true(total == mm_database_pose_bytes(small));
    /* one joint alone decodes as the whole frame does */
    mm_quat rot[MM_MAX_JOINTS];
    mm_vec3 pos[MM_MAX_JOINTS];
    for (int f = 0; f < small->frame_count; f += 97) {
        mm_database_local_pose(small, f, rot, pos);
        for (int j = 0; j < small->joint_count; ++j) {
            mm_quat q;
            mm_vec3 p;
            mm_database_local_joint(small, f, j, &q, &p);
            assert_memory_equal(&q, &rot[j], sizeof q);
            assert_memory_equal(&p, &pos[j], sizeof p);
        }
    }
}

static void test_round_trip(void **state)
{
    (void)state;
    check_compressed(&synth_floats, &synth_small, BOUND);
    /* saved and loaded: the same bytes, the same decoded frames */
    char path[] = "/tmp/mm_pose_codec_XXXXXX";
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    close(fd);
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_database_save(&synth_small, path, &err), MM_OK);
    mm_database loaded;
    assert_int_equal(mm_database_load(path, NULL, &loaded, &err), MM_OK);
    remove(path);
    assert_true(loaded.size == synth_small.size);
    assert_memory_equal(loaded.data, synth_small.data, loaded.size);
    assert_true(max_joint_error(&synth_small, &loaded) == 0.0);
    mm_database_free(&loaded);
    /* the same bytes on two threads */
    mm_db_compress_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.threads = 2;
    mm_database two;
    assert_int_equal(mm_database_compress(&synth_floats, &desc, &two, &err), MM_OK);
    assert_true(two.size == synth_small.size);
    assert_memory_equal(two.data, synth_small.data, two.size);
    mm_database_free(&two);
    /* a database compressed already is refused */
    assert_int_equal(mm_database_compress(&synth_small, NULL, &two, &err), MM_ERR_INVALID_ARGUMENT);
}

/* A tighter bound costs bytes and holds; a bound no quantization meets keeps the floats exactly. */
static void test_bounds(void **state)
{
    (void)state;
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_db_compress_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.error_bound = 0.00005f; /* 0.05 mm */
    mm_database tight, exact;
    assert_int_equal(mm_database_compress(&synth_floats, &desc, &tight, &err), MM_OK);
    printf("bound 0.05 mm:\n");
    double worst = max_joint_error(&synth_floats, &tight);
    assert_true(worst <= desc.error_bound);
    assert_true(mm_database_pose_bytes(&tight) > mm_database_pose_bytes(&synth_small));
    printf("  %.1f pose bytes per frame, largest joint error %.4f mm\n",
           (double)mm_database_pose_bytes(&tight) / tight.frame_count, 1000.0 * worst);
    mm_database_free(&tight);
    desc.error_bound = 1e-12f;
    desc.segment_frames = 64;
    assert_int_equal(mm_database_compress(&synth_floats, &desc, &exact, &err), MM_OK);
    mm_quat r[MM_MAX_JOINTS];
    mm_vec3 p[MM_MAX_JOINTS];
    for (int f = 0; f < exact.frame_count; ++f) {
        mm_database_local_pose(&exact, f, r, p);
        assert_memory_equal(r, mm_database_rotations(&synth_floats, f),
                            sizeof(mm_quat) * (size_t)exact.joint_count);
        assert_memory_equal(p, mm_database_positions(&synth_floats, f),
                            sizeof(mm_vec3) * (size_t)exact.joint_count);
    }
    assert_true(exact.compressed.max_error == 0.0f);
    mm_database_free(&exact);
    desc.error_bound = -1.0f;
    assert_int_equal(mm_database_compress(&synth_floats, &desc, &exact, &err), MM_ERR_OUT_OF_RANGE);
    desc.error_bound = 0.0f;
    desc.segment_frames = MM_POSE_SEGMENT_FRAMES_MAX + 1;
    assert_int_equal(mm_database_compress(&synth_floats, &desc, &exact, &err), MM_ERR_OUT_OF_RANGE);
}

/* The same winners for queries made of one frame's pose and another's trajectory. */
static void check_same_search(const mm_database *a, const mm_database *b, int queries)
{
    mm_searcher sa, sb;
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_searcher_init(&sa, a, NULL, &err), MM_OK);
    assert_int_equal(mm_searcher_init(&sb, b, NULL, &err), MM_OK);
    mm_search_params p;
    mm_search_params_defaults(a, &p);
    float query[MM_SEARCH_MAX_DIMS];
    uint32_t seed = 12345u;
    for (int q = 0; q < queries; ++q) {
        seed = seed * 1664525u + 1013904223u;
        int pose = (int)(seed % (uint32_t)a->frame_count);
        seed = seed * 1664525u + 1013904223u;
        int traj = (int)(seed % (uint32_t)a->frame_count);
        mm_search_query_from_frames(a, pose, traj, query);
        p.current_frame = pose;
        for (int m = 0; m < 2; ++m) {
            mm_search_method method = m ? MM_SEARCH_FAST : MM_SEARCH_BRUTE;
            mm_search_result ra[3], rb[3];
            int na = mm_searcher_search(&sa, query, &p, method, ra, 3);
            int nb = mm_searcher_search(&sb, query, &p, method, rb, 3);
            assert_int_equal(na, nb);
            for (int i = 0; i < na; ++i) {
                assert_int_equal(ra[i].frame, rb[i].frame);
                assert_true(ra[i].cost == rb[i].cost);
            }
        }
    }
    mm_searcher_free(&sa);
    mm_searcher_free(&sb);
}

static void test_same_search(void **state)
{
    (void)state;
    check_same_search(&synth_floats, &synth_small, 500);
}

/* A character on each database, the same input: the same frames played and the same root (the
 * search reads the features and root motion, both exact); the joints apart by what the pose error
 * becomes through inertialization: its offsets' velocities come from two consecutive decoded
 * frames, whose errors may differ by twice the bound in one frame interval, and its springs carry
 * that over their half-life (docs/database.md, "A smaller database for shipping"). */
#define RUN_FACTOR    8.0f
#define RUN_TOLERANCE (RUN_FACTOR * BOUND)
/* The largest distance between the joints of a character on the floats and one on `small` over a
 * 30 s run of the same input; checks that both play the same frames with the same root. */
static double run_difference(const mm_database *small)
{
    const mm_database *dbs[2] = {&synth_floats, small};
    mm_searcher s[2];
    mm_character ch[2];
    mm_error err;
    memset(&err, 0, sizeof err);
    for (int k = 0; k < 2; ++k) {
        assert_int_equal(mm_searcher_init(&s[k], dbs[k], NULL, &err), MM_OK);
        mm_character_desc desc;
        assert_int_equal(mm_character_desc_from_database(&desc, dbs[k], &err), MM_OK);
        assert_int_equal(mm_character_init(&ch[k], dbs[k], &s[k], &desc, &err), MM_OK);
    }
    mm_input in;
    memset(&in, 0, sizeof in);
    double worst = 0.0;
    int tie = -1; /* the tick at which the feet parted at a tie (feet_ties.h), when they did */
    for (int i = 0; i < 1800; ++i) { /* 30 s at 60 Hz: walking, turning, stopping, running */
        float t = (float)i / 60.0f;
        in.stick[0] = sinf(0.37f * t);
        in.stick[1] = (i / 300) % 3 == 2 ? 0.0f : cosf(0.23f * t);
        in.gait = (i / 450) % 2 == 1 ? MM_GAIT_RUN : MM_GAIT_WALK;
        mm_vec3 held[2][2];
        feet_ties_before(ch, held);
        for (int k = 0; k < 2; ++k) mm_character_update(&ch[k], &in, 1.0f / 60.0f);
        if (tie < 0 && (feet_unlock_tie(ch, held) || feet_lock_tie(ch))) tie = i;
        assert_int_equal(ch[0].frame, ch[1].frame);
        assert_true(ch[0].frame_fraction == ch[1].frame_fraction);
        assert_memory_equal(&ch[0].root, &ch[1].root, sizeof ch[0].root);
        for (int j = 0; j < synth_floats.joint_count && tie < 0; ++j) {
            double d = mm_vec3_distance(ch[0].global[j].translation, ch[1].global[j].translation);
            worst = d > worst ? d : worst;
        }
    }
    printf("character (bound %.3f mm): %d transitions, the same frames and root; joints at most %.4f mm "
           "apart%s\n",
           1000.0 * small->compressed.error_bound, ch[0].transitions, 1000.0 * worst,
           tie >= 0 ? " until the feet parted at a tie (a lock let go or taken a tick apart)" : "");
    if (tie >= 0) printf("  (the feet parted at that tie at tick %d)\n", tie);
    assert_true(ch[0].transitions > 5);
    for (int k = 0; k < 2; ++k) {
        mm_character_free(&ch[k]);
        mm_searcher_free(&s[k]);
    }
    return worst;
}

static void test_character_run(void **state)
{
    (void)state;
    assert_true(run_difference(&synth_small) <= RUN_TOLERANCE);
    /* compressed within an eighth of the bound, the character stays as close (the feet's locks
     * follow the animated feet, so micrometres in a pose reach the planted feet: not within the
     * bound itself) */
    mm_db_compress_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.error_bound = BOUND / RUN_FACTOR;
    mm_database fine;
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_database_compress(&synth_floats, &desc, &fine, &err), MM_OK);
    assert_true(run_difference(&fine) <= RUN_TOLERANCE);
    mm_database_free(&fine);
}

/* Loads a copy of db with `width` bytes at byte `at` set to value (checksum not verified); the
 * message must hold `want`. */
static void expect_refused(const mm_database *db, size_t at, const void *value, size_t width,
                           const char *want)
{
    unsigned char *copy = aligned_alloc(MM_DB_ALIGN, (db->size + MM_DB_ALIGN) / MM_DB_ALIGN * MM_DB_ALIGN);
    memcpy(copy, db->data, db->size);
    memcpy(copy + at, value, width);
    mm_database out;
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_result r = mm_database_load_memory(copy, db->size, false, &out, &err);
    if (r == MM_OK) fail_msg("byte %zu: loaded, expected \"%s\"", at, want);
    if (!strstr(err.message, want)) fail_msg("byte %zu: \"%s\", expected \"%s\"", at, err.message, want);
    free(copy);
}

static void test_refused(void **state)
{
    (void)state;
    const mm_database *db = &synth_small;
    uint64_t size;
    size_t tracks = (size_t)(section(db, 28, &size) - (const unsigned char *)db->data);
    size_t segments = (size_t)(section(db, 27, &size) - (const unsigned char *)db->data);
    size_t bits = (size_t)(section(db, 30, &size) - (const unsigned char *)db->data);
    uint64_t bits_size = size;
    uint8_t u8 = 17;
    expect_refused(db, tracks + offsetof(mm_db_rotation_track, bits), &u8, 1, "rotation bits 17");
    u8 = 8;
    expect_refused(db, tracks + offsetof(mm_db_rotation_track, dropped), &u8, 1, "dropped component");
    mm_db_rotation_track track = db->compressed.rotation_tracks[0];
    track.lo[0] = 65535;
    track.extent[0] = 1;
    expect_refused(db, tracks, &track, sizeof track, "past 65535");
    uint32_t u32 = db->compressed.segments[0].frame_bits + 1;
    expect_refused(db, segments + offsetof(mm_db_pose_segment, frame_bits), &u32, 4, "bits per frame");
    int32_t i32 = 1;
    expect_refused(db, segments + offsetof(mm_db_pose_segment, first_frame), &i32, 4, "segment 0: frames 1");
    u8 = 1;
    expect_refused(db, bits + (size_t)bits_size - 1, &u8, 1, "bit stream's last 8 bytes");
    /* the header: an unknown codec, a measured error above the bound */
    u32 = 2;
    expect_refused(db, 84, &u32, 4, "pose codec 2 is unknown");
    float f = 2.0f * db->compressed.error_bound;
    expect_refused(db, 104, &f, 4, "error bound");
    /* a raw rotation whose floats are not a unit quaternion */
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_db_compress_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.error_bound = 1e-12f;
    mm_database exact;
    assert_int_equal(mm_database_compress(&synth_floats, &desc, &exact, &err), MM_OK);
    assert_int_equal(exact.compressed.rotation_tracks[0].bits, MM_POSE_RAW_BITS);
    f = 3.0f;
    bits = (size_t)(section(&exact, 30, &size) - (const unsigned char *)exact.data);
    expect_refused(&exact, bits, &f, 4, "frame 0, joint 0: rotation not of unit length");
    mm_database_free(&exact);
}

/* LAFAN1 ($MM_DATA_DIR): every frame within the bound, a quarter of the bytes at most, the same
 * winners. */
static void test_lafan1(void **state)
{
    (void)state;
    const char *dir = getenv("MM_DATA_DIR");
    if (!dir || !*dir) skip();
    mm_database floats, small;
    assert_int_equal(test_build_data_database("lafan1", &floats), 0);
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_db_compress_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.threads = 2;
    assert_int_equal(mm_database_compress(&floats, &desc, &small, &err), MM_OK);
    printf("LAFAN1:\n");
    check_compressed(&floats, &small, BOUND);
    check_same_search(&floats, &small, 200);
    mm_database_free(&small);
    mm_database_free(&floats);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_round_trip),  cmocka_unit_test(test_bounds),
        cmocka_unit_test(test_same_search), cmocka_unit_test(test_character_run),
        cmocka_unit_test(test_refused),     cmocka_unit_test(test_lafan1),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
