/* mm/crowd.h on the built-in set: every way of scheduling a crowd's tick (the calling thread, a
 * serial parallel-for, mm's pool of 1, 2 and 3 threads, a parallel-for that runs the items in
 * reverse, one that runs them shuffled in uneven pieces, one on threads of its own) gives the same
 * bits; each character of a crowd moves exactly as one character run alone over its input
 * (mm_run_script), on flat ground and in a scene with moves; spread searches even out the searches
 * per tick, each character then moving as one alone with its search phase; a tick allocates
 * nothing; bad arguments are errors with messages. */
#define _POSIX_C_SOURCE 200809L
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <mm/crowd.h>
#include <mm/input_json.h>
#include <mm/run.h>
#include <mm/scene_json.h>

#include "runtime/character/state.h"
#include "test_databases.h"
#include "test_util.h"

#define CROWD_SIZE   13  /* not a multiple of the pool's batch nor of the thread counts */
#define CROWD_TICKS  180 /* 3 s at 60 Hz: each character searches many times and transitions */
#define CROWD_FPS    60.0
#define SHUFFLE_SEED 12345u

static mm_database db;

/* The inputs of CROWD_SIZE characters on their own random scripts, tick after tick, sampled as
 * mm_run_script samples them (t = f / fps). */
static mm_input *make_inputs(mm_input_script *scripts, int count, int ticks)
{
    mm_input *inputs = malloc(sizeof(mm_input) * (size_t)count * (size_t)ticks);
    assert_non_null(inputs);
    for (int f = 0; f < ticks; ++f)
        for (int i = 0; i < count; ++i)
            mm_input_script_sample_tick(&scripts[i], (float)(f / CROWD_FPS), (float)(1.0 / CROWD_FPS),
                                        &inputs[(size_t)f * (size_t)count + (size_t)i]);
    return inputs;
}

static void random_scripts(mm_input_script *scripts, int count, float seconds)
{
    mm_input_random_desc rd;
    memset(&rd, 0, sizeof rd);
    rd.seconds = seconds;
    for (int i = 0; i < count; ++i)
        assert_int_equal(mm_input_script_random(&scripts[i], (uint64_t)i + 7, &rd), MM_OK);
}

/* --- parallel-fors, as a game's job system might be --- */

/* one item at a time, in order */
static void serial_for(void *user, int count, mm_crowd_work work, void *context)
{
    (void)user;
    for (int i = 0; i < count; ++i) work(context, i, i + 1);
}

/* one item at a time, last first */
static void reverse_for(void *user, int count, mm_crowd_work work, void *context)
{
    (void)user;
    for (int i = count - 1; i >= 0; --i) work(context, i, i + 1);
}

/* pieces of 1 to 4 items, in an order shuffled anew every tick (user: the generator's state) */
static void shuffled_for(void *user, int count, mm_crowd_work work, void *context)
{
    unsigned *rng = (unsigned *)user;
    int begin[64], end[64], pieces = 0;
    for (int at = 0; at < count; ++pieces) {
        *rng = *rng * 1103515245u + 12345u;
        int size = 1 + (int)((*rng >> 16) % 4u);
        begin[pieces] = at;
        end[pieces] = at + size < count ? at + size : count;
        at = end[pieces];
    }
    for (int k = pieces - 1; k > 0; --k) { /* Fisher-Yates */
        *rng = *rng * 1103515245u + 12345u;
        int j = (int)((*rng >> 16) % (unsigned)(k + 1));
        int b = begin[k], e = end[k];
        begin[k] = begin[j], end[k] = end[j];
        begin[j] = b, end[j] = e;
    }
    for (int k = 0; k < pieces; ++k) work(context, begin[k], end[k]);
}

/* three threads of its own, each taking every third item from the end */
typedef struct striped {
    mm_crowd_work work;
    void *context;
    int count, first;
} striped;

static void *stripe(void *p)
{
    striped *s = (striped *)p;
    for (int i = s->count - 1 - s->first; i >= 0; i -= 3) s->work(s->context, i, i + 1);
    return NULL;
}

static void threaded_for(void *user, int count, mm_crowd_work work, void *context)
{
    (void)user;
    pthread_t th[3];
    striped s[3];
    for (int k = 0; k < 3; ++k) {
        s[k] = (striped){work, context, count, k};
        assert_int_equal(pthread_create(&th[k], NULL, stripe, &s[k]), 0);
    }
    for (int k = 0; k < 3; ++k) pthread_join(th[k], NULL);
}

/* --- runs --- */

typedef struct schedule {
    const char *name;
    mm_crowd_parallel_for parallel_for;
    int threads;
} schedule;

/* The crowd on inputs for `ticks` ticks: every character's world positions and rotations and
 * database frame, tick after tick, into world ([ticks][count][joints][7]) and frames. */
static void run_crowd(const schedule *how, const mm_scene *scene, const mm_input *inputs, int count,
                      int ticks, float *world, int *frames, int *searches, int *moves)
{
    unsigned rng = SHUFFLE_SEED;
    mm_crowd_desc d;
    memset(&d, 0, sizeof d);
    d.count = count;
    d.scene = scene;
    d.parallel_for = how->parallel_for;
    d.user = &rng;
    d.threads = how->threads;
    mm_crowd crowd;
    mm_error err;
    assert_int_equal(mm_crowd_init(&crowd, &db, NULL, &d, &err), MM_OK);
    assert_int_equal(crowd.count, count);
    assert_true(scene ? crowd.moves != NULL : crowd.moves == NULL);
    int n = db.joint_count;
    for (int f = 0; f < ticks; ++f) {
        mm_crowd_update(&crowd, inputs + (size_t)f * (size_t)count, (float)(1.0 / CROWD_FPS));
        for (int i = 0; i < count; ++i) {
            const mm_character *c = &crowd.characters[i];
            for (int j = 0; j < n; ++j) {
                float *w = world + (((size_t)f * (size_t)count + (size_t)i) * (size_t)n + (size_t)j) * 7;
                mm_xform g = c->global[j];
                float v[7] = {g.translation.x, g.translation.y, g.translation.z, g.rotation.x,
                              g.rotation.y,    g.rotation.z,    g.rotation.w};
                memcpy(w, v, sizeof v);
            }
            frames[(size_t)f * (size_t)count + (size_t)i] = c->frame;
        }
    }
    *searches = 0;
    *moves = 0;
    for (int i = 0; i < count; ++i) {
        *searches += crowd.characters[i].searches;
        *moves += crowd.moves ? crowd.moves[i].count : 0;
    }
    mm_crowd_free(&crowd);
    assert_null(crowd.characters);
}

static const schedule SCHEDULES[] = {
    {"the calling thread", NULL, 0},
    {"a serial parallel-for", serial_for, 0},
    {"mm's pool, 1 thread", NULL, 1},
    {"mm's pool, 2 threads", NULL, 2},
    {"mm's pool, 3 threads", NULL, 3},
    {"a reversed parallel-for", reverse_for, 0},
    {"a shuffled parallel-for", shuffled_for, 0},
    {"a parallel-for on 3 threads", threaded_for, 0},
};
#define SCHEDULE_COUNT ((int)(sizeof SCHEDULES / sizeof SCHEDULES[0]))

static void test_crowd_same_bits_whatever_the_schedule(void **state)
{
    (void)state;
    mm_input_script scripts[CROWD_SIZE];
    random_scripts(scripts, CROWD_SIZE, (float)(CROWD_TICKS / CROWD_FPS));
    mm_input *inputs = make_inputs(scripts, CROWD_SIZE, CROWD_TICKS);
    size_t cells = (size_t)CROWD_TICKS * CROWD_SIZE * (size_t)db.joint_count * 7;
    float *first = malloc(sizeof(float) * cells), *other = malloc(sizeof(float) * cells);
    int *first_frames = malloc(sizeof(int) * CROWD_TICKS * CROWD_SIZE);
    int *other_frames = malloc(sizeof(int) * CROWD_TICKS * CROWD_SIZE);
    assert_non_null(first && other && first_frames && other_frames);
    int searches = 0, other_searches = 0, moves;
    run_crowd(&SCHEDULES[0], NULL, inputs, CROWD_SIZE, CROWD_TICKS, first, first_frames, &searches, &moves);
    /* a run that searched and moved: the characters went apart from one another */
    assert_true(searches > CROWD_SIZE * 10);
    for (int k = 1; k < SCHEDULE_COUNT; ++k) {
        run_crowd(&SCHEDULES[k], NULL, inputs, CROWD_SIZE, CROWD_TICKS, other, other_frames, &other_searches,
                  &moves);
        if (memcmp(first, other, sizeof(float) * cells) != 0 ||
            memcmp(first_frames, other_frames, sizeof(int) * CROWD_TICKS * CROWD_SIZE) != 0)
            fail_msg("%s gives other bits than %s", SCHEDULES[k].name, SCHEDULES[0].name);
        assert_int_equal(other_searches, searches);
    }
    free(first), free(other), free(first_frames), free(other_frames);
    free(inputs);
    for (int i = 0; i < CROWD_SIZE; ++i) mm_input_script_free(&scripts[i]);
}

/* Each character of the crowd against itself run alone (mm_run_script: one character, its move
 * layer, its own searcher) over its own input: the same bits, tick after tick. */
static void check_against_alone(const mm_scene *scene, mm_input_script *scripts, int count, int ticks,
                                const schedule *how, int min_moves)
{
    mm_input *inputs = make_inputs(scripts, count, ticks);
    int n = db.joint_count;
    size_t cells = (size_t)ticks * (size_t)count * (size_t)n * 7;
    float *world = malloc(sizeof(float) * cells);
    int *frames = malloc(sizeof(int) * (size_t)ticks * (size_t)count);
    float *alone_pos = malloc(sizeof(float) * (size_t)ticks * (size_t)n * 3);
    float *alone_rot = malloc(sizeof(float) * (size_t)ticks * (size_t)n * 4);
    int32_t *alone_frames = malloc(sizeof(int32_t) * (size_t)ticks);
    assert_non_null(world && frames && alone_pos && alone_rot && alone_frames);
    int searches, moves;
    run_crowd(how, scene, inputs, count, ticks, world, frames, &searches, &moves);
    assert_true(moves >= min_moves);
    for (int i = 0; i < count; ++i) {
        mm_run_desc rd = {.fps = (float)CROWD_FPS, .scene = scene};
        mm_run_output out = {
            .world_positions = alone_pos, .world_rotations = alone_rot, .db_frames = alone_frames};
        assert_int_equal(mm_run_script(&db, &scripts[i], ticks, &rd, &out, NULL), MM_OK);
        for (int f = 0; f < ticks; ++f) {
            assert_int_equal(frames[(size_t)f * (size_t)count + (size_t)i], alone_frames[f]);
            for (int j = 0; j < n; ++j) {
                const float *w =
                    world + (((size_t)f * (size_t)count + (size_t)i) * (size_t)n + (size_t)j) * 7;
                assert_memory_equal(w, alone_pos + ((size_t)f * (size_t)n + (size_t)j) * 3,
                                    sizeof(float) * 3);
                assert_memory_equal(w + 3, alone_rot + ((size_t)f * (size_t)n + (size_t)j) * 4,
                                    sizeof(float) * 4);
            }
        }
    }
    free(world), free(frames), free(alone_pos), free(alone_rot), free(alone_frames);
    free(inputs);
}

static void test_crowd_is_characters_alone(void **state)
{
    (void)state;
    enum { COUNT = 5 };
    mm_input_script scripts[COUNT];
    random_scripts(scripts, COUNT, (float)(CROWD_TICKS / CROWD_FPS));
    check_against_alone(NULL, scripts, COUNT, CROWD_TICKS, &SCHEDULES[3], 0);
    for (int i = 0; i < COUNT; ++i) mm_input_script_free(&scripts[i]);
}

/* In a scene, with moves: two characters jump onto a wall (the script of the moves' demo), with a
 * third on random input; on mm's pool of two threads, each as alone. */
static void test_crowd_moves_in_a_scene(void **state)
{
    (void)state;
    static mm_scene scene;
    mm_error err;
    assert_int_equal(mm_scene_load_json(MM_SOURCE_DIR "/scenes/jump_onto_wall.json", &scene, &err), MM_OK);
    mm_input_script scripts[3];
    assert_int_equal(
        mm_input_script_load_json(MM_SOURCE_DIR "/scripts/input/moves_jump_wall.json", &scripts[0], &err),
        MM_OK);
    assert_int_equal(
        mm_input_script_load_json(MM_SOURCE_DIR "/scripts/input/moves_jump_wall.json", &scripts[1], &err),
        MM_OK);
    mm_input_random_desc rd;
    memset(&rd, 0, sizeof rd);
    rd.seconds = 5.0f;
    assert_int_equal(mm_input_script_random(&scripts[2], 3, &rd), MM_OK);
    check_against_alone(&scene, scripts, 3, 300, &SCHEDULES[3], 2); /* both jumps onto the wall */
    for (int i = 0; i < 3; ++i) mm_input_script_free(&scripts[i]);
}

static long allocations;
/* The most characters that searched on one tick after the first, over `ticks` ticks of a crowd of
 * count on inputs (spread: with spread searches, on mm's pool of two threads); world and frames as
 * run_crowd's, and each character's search phase into phases. */
static int most_searches_in_a_tick(bool spread, const mm_input *inputs, int count, int ticks, mm_xform *world,
                                   float *phases)
{
    mm_crowd_desc d;
    memset(&d, 0, sizeof d);
    d.count = count;
    d.threads = spread ? 2 : 0;
    d.spread_searches = spread;
    mm_crowd crowd;
    assert_int_equal(mm_crowd_init(&crowd, &db, NULL, &d, NULL), MM_OK);
    int n = db.joint_count, most = 0;
    for (int f = 0; f < ticks; ++f) {
        int before = 0, after = 0;
        for (int i = 0; i < count; ++i) before += crowd.characters[i].searches;
        mm_crowd_update(&crowd, inputs + (size_t)f * (size_t)count, (float)(1.0 / CROWD_FPS));
        for (int i = 0; i < count; ++i) after += crowd.characters[i].searches;
        if (f > 0 && after - before > most) most = after - before;
        for (int i = 0; i < count; ++i)
            memcpy(world + ((size_t)f * (size_t)count + (size_t)i) * (size_t)n, crowd.characters[i].global,
                   sizeof(mm_xform) * (size_t)n);
    }
    for (int i = 0; i < count; ++i) phases[i] = crowd.characters[i].state->matching.search_phase;
    mm_crowd_free(&crowd);
    return most;
}

static void test_crowd_spreads_searches(void **state)
{
    (void)state;
    enum { COUNT = 30, TICKS = 120 };
    mm_input_script scripts[COUNT];
    random_scripts(scripts, COUNT, (float)(TICKS / CROWD_FPS));
    mm_input *inputs = make_inputs(scripts, COUNT, TICKS);
    int n = db.joint_count;
    size_t cells = (size_t)TICKS * COUNT * (size_t)n;
    mm_xform *world = malloc(sizeof(mm_xform) * cells);
    float phases[COUNT];
    assert_non_null(world);
    /* together: every character searches on the same ticks (the search interval's), most at once */
    int together = most_searches_in_a_tick(false, inputs, COUNT, TICKS, world, phases);
    for (int i = 0; i < COUNT; ++i) assert_true(phases[i] == 0.0f);
    assert_true(together >= COUNT * 3 / 4);
    /* spread: the phases fill [0, 1) (no gap wider than 3 characters' share), and a tick has about
     * the average of searches (search_interval / dt ticks between a character's searches, and the
     * searches on turns and idle changes) */
    int spread = most_searches_in_a_tick(true, inputs, COUNT, TICKS, world, phases);
    float sorted[COUNT];
    memcpy(sorted, phases, sizeof sorted);
    for (int i = 1; i < COUNT; ++i) /* insertion sort */
        for (int k = i; k > 0 && sorted[k] < sorted[k - 1]; --k) {
            float t = sorted[k];
            sorted[k] = sorted[k - 1], sorted[k - 1] = t;
        }
    assert_true(sorted[0] >= 0.0f && sorted[COUNT - 1] < 1.0f);
    for (int i = 1; i <= COUNT; ++i) {
        float gap = i < COUNT ? sorted[i] - sorted[i - 1] : 1.0f + sorted[0] - sorted[COUNT - 1];
        assert_true(gap > 0.0f && gap < 3.0f / COUNT);
    }
    assert_true(spread <= COUNT / 2);
    /* each character of the spread crowd (on two threads) moves as one alone with its phase */
    mm_searcher searcher;
    mm_character_desc desc;
    assert_int_equal(mm_searcher_init(&searcher, &db, NULL, NULL), MM_OK);
    assert_int_equal(mm_character_desc_from_database(&desc, &db, NULL), MM_OK);
    for (int i = 0; i < COUNT; ++i) {
        mm_character c;
        assert_int_equal(mm_character_init(&c, &db, &searcher, &desc, NULL), MM_OK);
        mm_character_set_search_phase(&c, phases[i]);
        for (int f = 0; f < TICKS; ++f) {
            mm_character_update(&c, &inputs[(size_t)f * COUNT + (size_t)i], (float)(1.0 / CROWD_FPS));
            assert_memory_equal(c.global, world + ((size_t)f * COUNT + (size_t)i) * (size_t)n,
                                sizeof(mm_xform) * (size_t)n);
        }
        mm_character_free(&c);
    }
    mm_searcher_free(&searcher);
    free(world);
    free(inputs);
    for (int i = 0; i < COUNT; ++i) mm_input_script_free(&scripts[i]);
}

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

/* everything allocated at init, on mm's pool and through a parallel-for: nothing per tick */
static void test_crowd_allocates_nothing_per_tick(void **state)
{
    (void)state;
    mm_input_script scripts[CROWD_SIZE];
    random_scripts(scripts, CROWD_SIZE, 10.0f);
    mm_input *inputs = make_inputs(scripts, CROWD_SIZE, 600);
    mm_allocator a = {counting_alloc, counting_free, NULL};
    for (int k = 0; k < 2; ++k) {
        mm_crowd_desc d = {.count = CROWD_SIZE, .allocator = &a};
        if (k == 0)
            d.threads = 2;
        else
            d.parallel_for = serial_for;
        mm_crowd crowd;
        allocations = 0;
        assert_int_equal(mm_crowd_init(&crowd, &db, NULL, &d, NULL), MM_OK);
        long at_init = allocations;
        assert_true(at_init > CROWD_SIZE); /* the allocator was used: a character each, and more */
        for (int f = 0; f < 600; ++f) mm_crowd_update(&crowd, inputs + (size_t)f * CROWD_SIZE, 1.0f / 60.0f);
        assert_int_equal(allocations, at_init);
        mm_crowd_free(&crowd);
    }
    free(inputs);
    for (int i = 0; i < CROWD_SIZE; ++i) mm_input_script_free(&scripts[i]);
}

/* no input: every character stands where it was put; an empty crowd ticks */
static void test_crowd_without_input(void **state)
{
    (void)state;
    mm_crowd crowd;
    mm_crowd_desc d = {.count = 3, .threads = 2};
    assert_int_equal(mm_crowd_init(&crowd, &db, NULL, &d, NULL), MM_OK);
    for (int i = 0; i < 3; ++i) {
        mm_vec3 at = mm_vec3_make(5.0f * (float)i, 0.0f, -2.0f);
        mm_character_set_root(&crowd.characters[i], mm_xform_make(mm_quat_identity(), at));
        mm_character_teleport_simulation(&crowd.characters[i], at, mm_quat_identity());
    }
    for (int f = 0; f < 120; ++f) mm_crowd_update(&crowd, NULL, 1.0f / 60.0f);
    for (int i = 0; i < 3; ++i) {
        mm_vec3 r = crowd.characters[i].root.translation;
        assert_float_equal(r.x, 5.0f * (float)i, 0.05f);
        assert_float_equal(r.z, -2.0f, 0.05f);
    }
    mm_crowd_free(&crowd);
    mm_crowd_desc empty = {.count = 0, .threads = 2};
    assert_int_equal(mm_crowd_init(&crowd, &db, NULL, &empty, NULL), MM_OK);
    mm_crowd_update(&crowd, NULL, 1.0f / 60.0f);
    assert_int_equal(crowd.count, 0);
    mm_crowd_free(&crowd);
    mm_crowd_update(NULL, NULL, 1.0f / 60.0f);
    mm_crowd_free(NULL);
}

static void test_crowd_arguments(void **state)
{
    (void)state;
    mm_crowd crowd;
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_crowd_desc d = {.count = -1};
    assert_int_equal(mm_crowd_init(&crowd, &db, NULL, &d, &err), MM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "count"));
    d.count = 2, d.threads = MM_SEARCH_MAX_THREADS + 1;
    assert_int_equal(mm_crowd_init(&crowd, &db, NULL, &d, &err), MM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "threads"));
    d.threads = 0;
    assert_int_equal(mm_crowd_init(&crowd, NULL, NULL, &d, &err), MM_ERR_INVALID_ARGUMENT);
    assert_int_equal(mm_crowd_init(NULL, &db, NULL, &d, &err), MM_ERR_INVALID_ARGUMENT);
    /* a searcher with a pool would serialise the crowd's searches */
    mm_searcher pooled;
    mm_searcher_desc sd = {.threads = 2};
    assert_int_equal(mm_searcher_init(&pooled, &db, &sd, NULL), MM_OK);
    assert_int_equal(mm_crowd_init(&crowd, &db, &pooled, &d, &err), MM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "one"));
    assert_null(crowd.characters);
    mm_searcher_free(&pooled);
    /* a searcher of another database */
    mm_searcher other;
    memset(&other, 0, sizeof other);
    assert_int_equal(mm_crowd_init(&crowd, &db, &other, &d, &err), MM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "database"));
    /* the caller's searcher, shared: the crowd does not free it */
    mm_searcher shared;
    assert_int_equal(mm_searcher_init(&shared, &db, NULL, NULL), MM_OK);
    assert_int_equal(mm_crowd_init(&crowd, &db, &shared, &d, &err), MM_OK);
    assert_ptr_equal(crowd.searcher, &shared);
    assert_ptr_equal(crowd.characters[1].searcher, &shared);
    mm_crowd_update(&crowd, NULL, 1.0f / 60.0f);
    mm_crowd_free(&crowd);
    assert_ptr_equal(shared.db, &db);
    mm_searcher_free(&shared);
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
        cmocka_unit_test(test_crowd_same_bits_whatever_the_schedule),
        cmocka_unit_test(test_crowd_is_characters_alone),
        cmocka_unit_test(test_crowd_moves_in_a_scene),
        cmocka_unit_test(test_crowd_spreads_searches),
        cmocka_unit_test(test_crowd_allocates_nothing_per_tick),
        cmocka_unit_test(test_crowd_without_input),
        cmocka_unit_test(test_crowd_arguments),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
