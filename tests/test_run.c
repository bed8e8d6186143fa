/* mm/run.h and mm/flat.h on the built-in set: mm_run_script records what the tick loop it
 * replaces (the move layer around a character, the script sampled per tick) produces, bit for bit
 * and in the documented layout; it allocates nothing per tick; bad arguments are errors; the flat
 * API's errors are codes with messages naming the file. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <mm/flat.h>
#include <mm/moves.h>
#include <mm/run.h>

#include "test_databases.h"
#include "test_util.h"

#define RUN_FRAMES 240 /* 4 s at 60 fps: several searches and transitions */
#define RUN_SEED   4

static mm_database db;

static mm_input_script random_script(uint64_t seed, float seconds)
{
    mm_input_random_desc rd;
    memset(&rd, 0, sizeof rd);
    rd.seconds = seconds;
    mm_input_script s;
    assert_int_equal(mm_input_script_random(&s, seed, &rd), MM_OK);
    return s;
}

static void test_run_is_the_tick_loop(void **state)
{
    (void)state;
    int n = db.joint_count;
    mm_input_script script = random_script(RUN_SEED, RUN_FRAMES / 60.0f);
    float *world = malloc(sizeof(float) * RUN_FRAMES * (size_t)n * 3);
    float *wrot = malloc(sizeof(float) * RUN_FRAMES * (size_t)n * 4);
    float *lpos = malloc(sizeof(float) * RUN_FRAMES * (size_t)n * 3);
    float *lrot = malloc(sizeof(float) * RUN_FRAMES * (size_t)n * 4);
    int32_t *frames = malloc(sizeof(int32_t) * RUN_FRAMES);
    assert_non_null(world && wrot && lpos && lrot && frames);
    mm_run_output out = {world, wrot, lpos, lrot, frames, 0, 0};
    mm_error err;
    assert_int_equal(mm_run_script(&db, &script, RUN_FRAMES, NULL, &out, &err), MM_OK);
    assert_true(out.searches > 10 && out.transitions > 0);

    /* the loop written out: the database's desc, the move layer, the script sampled at f / 60 */
    mm_character_desc desc;
    assert_int_equal(mm_character_desc_from_database(&desc, &db, NULL), MM_OK);
    mm_searcher searcher;
    assert_int_equal(mm_searcher_init(&searcher, &db, NULL, NULL), MM_OK);
    mm_character c;
    assert_int_equal(mm_character_init(&c, &db, &searcher, &desc, NULL), MM_OK);
    mm_moves moves;
    mm_moves_desc md;
    mm_moves_desc_from_database(&md, &db);
    assert_int_equal(mm_moves_init(&moves, &db, NULL, &md, NULL), MM_OK);
    for (int f = 0; f < RUN_FRAMES; ++f) {
        mm_input in;
        mm_input_script_sample_tick(&script, (float)(f / 60.0), (float)(1.0 / 60.0), &in);
        mm_moves_update(&moves, &c, &in, (float)(1.0 / 60.0));
        for (int j = 0; j < n; ++j) {
            size_t i3 = ((size_t)f * (size_t)n + (size_t)j) * 3, i4 = ((size_t)f * (size_t)n + (size_t)j) * 4;
            mm_vec3 p = c.global[j].translation, lp = c.local_positions[j];
            mm_quat q = c.global[j].rotation, lq = c.local_rotations[j];
            float want[14] = {p.x, p.y, p.z, q.x, q.y, q.z, q.w, lp.x, lp.y, lp.z, lq.x, lq.y, lq.z, lq.w};
            float got[14] = {world[i3],    world[i3 + 1], world[i3 + 2], wrot[i4],     wrot[i4 + 1],
                             wrot[i4 + 2], wrot[i4 + 3],  lpos[i3],      lpos[i3 + 1], lpos[i3 + 2],
                             lrot[i4],     lrot[i4 + 1],  lrot[i4 + 2],  lrot[i4 + 3]};
            assert_memory_equal(got, want, sizeof want);
        }
        assert_int_equal(frames[f], c.frame);
    }
    assert_int_equal(out.searches, c.searches);
    assert_int_equal(out.transitions, c.transitions);
    mm_character_free(&c);
    mm_searcher_free(&searcher);

    /* outputs are optional: world positions alone are the same */
    float *alone = malloc(sizeof(float) * RUN_FRAMES * (size_t)n * 3);
    assert_non_null(alone);
    mm_run_output only = {.world_positions = alone};
    assert_int_equal(mm_run_script(&db, &script, RUN_FRAMES, NULL, &only, NULL), MM_OK);
    assert_memory_equal(alone, world, sizeof(float) * RUN_FRAMES * (size_t)n * 3);
    free(alone);
    free(world), free(wrot), free(lpos), free(lrot), free(frames);
    mm_input_script_free(&script);
}

static long allocations;
static void *counting_alloc(size_t size, void *user)
{
    (void)user;
    ++allocations;
    return malloc(size);
}
static void counting_free(void *p, void *user)
{
    (void)user;
    free(p);
}

/* as many allocations for a long run as for a short one: none per tick */
static void test_run_allocates_nothing_per_tick(void **state)
{
    (void)state;
    mm_input_script script = random_script(RUN_SEED, 10.0f);
    mm_allocator a = {counting_alloc, counting_free, NULL};
    mm_run_desc desc = {.allocator = &a};
    mm_run_output out;
    memset(&out, 0, sizeof out);
    long counts[2];
    int lengths[2] = {2, 600};
    for (int i = 0; i < 2; ++i) {
        allocations = 0;
        assert_int_equal(mm_run_script(&db, &script, lengths[i], &desc, &out, NULL), MM_OK);
        counts[i] = allocations;
    }
    assert_true(counts[0] > 0);
    assert_int_equal(counts[0], counts[1]);
    mm_input_script_free(&script);
}

static void test_run_arguments(void **state)
{
    (void)state;
    assert_int_equal(mm_run_frames(2.0, 60.0), 120);
    assert_int_equal(mm_run_frames(1.0 / 3.0, 30.0), 10);
    assert_int_equal(mm_run_frames(0.01, 60.0), 0);
    assert_int_equal(mm_run_frames(-1.0, 60.0), 0);
    mm_input_script script = random_script(1, 1.0f);
    mm_run_output out;
    memset(&out, 0, sizeof out);
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_run_script(&db, NULL, 10, NULL, &out, &err), MM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "mm_run_script"));
    assert_int_equal(mm_run_script(&db, &script, -1, NULL, &out, NULL), MM_ERR_INVALID_ARGUMENT);
    mm_run_desc bad_fps = {.fps = -30.0f};
    assert_int_equal(mm_run_script(&db, &script, 10, &bad_fps, &out, NULL), MM_ERR_INVALID_ARGUMENT);
    assert_int_equal(mm_run_script(&db, &script, 0, NULL, &out, NULL), MM_OK);
    mm_input_script_free(&script);
}

static void test_flat_errors_name_the_file(void **state)
{
    (void)state;
    char message[512];
    assert_null(mm_flat_database_load("/nonexistent/a.mmdb", message, sizeof message));
    assert_non_null(strstr(message, "/nonexistent/a.mmdb"));
    float out[3];
    int r = mm_flat_simulate(&db, "/nonexistent/script.json", 0, 1.0, 60.0, NULL, NULL, NULL, NULL, NULL,
                             message, sizeof message);
    assert_int_equal(r, MM_ERR_IO);
    assert_non_null(strstr(message, "/nonexistent/script.json"));
    assert_int_equal(
        mm_flat_simulate(&db, NULL, 0, 0.0, 60.0, out, NULL, NULL, NULL, NULL, message, sizeof message),
        MM_ERR_INVALID_ARGUMENT);
    assert_int_equal(mm_flat_build("/nonexistent/c.json", NULL, "x.mmdb", 1, message, sizeof message),
                     MM_ERR_IO);
    assert_non_null(strstr(message, "/nonexistent/c.json"));
    /* search: a frame out of range is a negative code */
    float query[MM_SEARCH_MAX_DIMS] = {0};
    int32_t frame;
    assert_int_equal(
        mm_flat_search(&db, query, db.frame_count, 0, 1, &frame, NULL, NULL, message, sizeof message),
        -MM_ERR_INVALID_ARGUMENT);
    assert_int_equal(mm_flat_database_count(&db, MM_FLAT_FRAMES), db.frame_count);
    assert_int_equal(mm_flat_database_count(&db, 99), -1);
    assert_null(mm_flat_joint(&db, db.joint_count, NULL));
}

static int setup(void **state)
{
    (void)state;
    return test_build_synth_database(&db) != 0 ? -1 : 0;
}

static int teardown(void **state)
{
    (void)state;
    mm_database_free(&db);
    return 0;
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_run_is_the_tick_loop),
        cmocka_unit_test(test_run_allocates_nothing_per_tick),
        cmocka_unit_test(test_run_arguments),
        cmocka_unit_test(test_flat_errors_name_the_file),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
