/* The recorder (mm/recorder.h) and what it stands on in mm/character.h: restoring a recorded tick
 * repeats the run bit for bit (poses and whole state, compared byte for byte with what the first
 * run recorded), asking for candidates changes nothing of the run, the candidates are the
 * brute-force search's best with cost terms that add up, and the ring keeps the newest ticks. */
#include <math.h>

#include "test_util.h"

#include <mm/recorder.h>

#include "test_databases.h"

#define TICKS      600
#define TOP_K      5
#define TICK_DT    (1.0f / 60.0f)
#define INPUT_SEED 7u

static mm_database db;
static mm_searcher searcher;
static mm_input inputs[TICKS];

/* The tuning of a run: the database's, or with crossfades, distance matching and warping on (more
 * of the state in play: the mixer's slots, the play rate, the warp's springs). */
static void make_desc(mm_character_desc *d, int variant)
{
    assert_int_equal(mm_character_desc_from_database(d, &db, NULL), MM_OK);
    d->params.contact_mismatch_favour = 2.0f; /* the contact favour in play (off by default) */
    if (variant == 1) {
        d->transition_mode = MM_TRANSITION_CROSSFADE;
        d->distance_matching = true;
        d->warping = true;
    }
}

static void make_character(mm_character *c, int variant)
{
    mm_character_desc d;
    make_desc(&d, variant);
    assert_int_equal(mm_character_init(c, &db, &searcher, &d, NULL), MM_OK);
}

/* Varied input: a random script (walks, runs, strafes, stops, turns) sampled tick by tick. */
static void make_inputs(void)
{
    mm_input_script script;
    mm_input_random_desc rd;
    memset(&rd, 0, sizeof rd);
    rd.seconds = TICKS * TICK_DT;
    rd.mean_hold = 0.8f; /* changes every 0.8 s on average: many searches and transitions */
    assert_int_equal(mm_input_script_random(&script, INPUT_SEED, &rd), MM_OK);
    for (int f = 0; f < TICKS; ++f)
        mm_input_script_sample_tick(&script, (float)(f * (double)TICK_DT), TICK_DT, &inputs[f]);
    mm_input_script_free(&script);
}

typedef struct recording {
    mm_character c;
    mm_recorder rec;
    void *memory;
} recording;

static void record_run(recording *r, int variant, int ticks, int top_k)
{
    make_character(&r->c, variant);
    size_t bytes = mm_recorder_bytes(&r->c, ticks, top_k);
    assert_true(bytes > 0);
    r->memory = malloc(bytes);
    assert_non_null(r->memory);
    assert_int_equal(mm_recorder_init(&r->rec, r->memory, bytes, &r->c, ticks, top_k, NULL), MM_OK);
    for (int f = 0; f < TICKS; ++f) {
        mm_character_update(&r->c, &inputs[f], TICK_DT);
        mm_recorder_record(&r->rec, &r->c, &inputs[f], TICK_DT);
    }
}

static void free_recording(recording *r)
{
    mm_character_free(&r->c);
    free(r->memory);
}

/* Restored at tick `from`, character c runs on with the same inputs: after every tick its pose and
 * its whole state (a snapshot) are the bytes recorded the first time. */
static void replay_from(const mm_recorder *rec, int from, mm_character *c)
{
    assert_int_equal(mm_recorder_restore(rec, from, c, NULL), MM_OK);
    const mm_recorded_tick *t0 = mm_recorder_tick(rec, from);
    assert_memory_equal(c->global, t0->global, sizeof(mm_xform) * (size_t)db.joint_count);
    size_t bytes = mm_character_snapshot_bytes(c);
    assert_int_equal(bytes, rec->snapshot_bytes);
    unsigned char *snap = malloc(bytes);
    assert_non_null(snap);
    for (int i = from + 1; i < mm_recorder_count(rec); ++i) {
        const mm_recorded_tick *t = mm_recorder_tick(rec, i);
        int f = (int)t->number;
        mm_character_update(c, &inputs[f], TICK_DT);
        if (memcmp(c->global, t->global, sizeof(mm_xform) * (size_t)db.joint_count) != 0) {
            print_error("restored at tick %d: the pose of tick %d differs\n", from, i);
            fail();
        }
        assert_int_equal(mm_character_snapshot_save(c, snap, bytes, NULL), MM_OK);
        const unsigned char *kept =
            rec->snapshots + (size_t)((rec->head + i) % rec->capacity) * rec->snapshot_bytes;
        if (memcmp(snap, kept, bytes) != 0) {
            size_t at = 0;
            while (snap[at] == kept[at]) ++at;
            print_error("restored at tick %d: the state of tick %d differs at byte %zu of %zu\n", from, i, at,
                        bytes);
            fail();
        }
        assert_int_equal(c->frame, t->frame);
        assert_int_equal(c->searches, t->searches);
        assert_int_equal(c->transitions, t->transitions);
    }
    free(snap);
}

/* 600 ticks recorded; restored at several ticks, into the character recorded and into a second
 * one made the same way (other memory: the pointers are laid out again), the run repeats bit for
 * bit, in both tunings. */
static void test_restore_repeats_the_run(void **state)
{
    (void)state;
    const int restore_at[] = {0, 1, 57, 250, 417, 598};
    for (int variant = 0; variant < 2; ++variant) {
        recording r;
        record_run(&r, variant, TICKS, TOP_K);
        assert_int_equal(mm_recorder_count(&r.rec), TICKS);
        assert_true(r.c.searches > 20);
        assert_true(r.c.transitions > 5);
        for (size_t k = 0; k < sizeof restore_at / sizeof restore_at[0]; ++k)
            replay_from(&r.rec, restore_at[k], &r.c);
        mm_character other;
        make_character(&other, variant);
        assert_int_equal(mm_character_set_candidates(&other, TOP_K, NULL), MM_OK);
        for (int i = 0; i < 3; ++i) mm_character_update(&other, &inputs[i], TICK_DT); /* somewhere else */
        replay_from(&r.rec, 123, &other);
        replay_from(&r.rec, 0, &other);
        mm_character_free(&other);
        free_recording(&r);
    }
}

/* Asking for candidates changes nothing: a character with the winner alone runs the same bits. */
static void test_candidates_leave_the_run_alone(void **state)
{
    (void)state;
    recording r;
    record_run(&r, 0, TICKS, TOP_K);
    mm_character plain;
    make_character(&plain, 0);
    for (int f = 0; f < TICKS; ++f) {
        mm_character_update(&plain, &inputs[f], TICK_DT);
        const mm_recorded_tick *t = mm_recorder_tick(&r.rec, f);
        assert_memory_equal(plain.global, t->global, sizeof(mm_xform) * (size_t)db.joint_count);
    }
    assert_int_equal(plain.searches, r.c.searches);
    /* the winner alone: one candidate, the search's result */
    mm_candidate one[TOP_K];
    assert_int_equal(mm_character_candidates(&plain, one, TOP_K), 1);
    assert_int_equal(one[0].frame, plain.last_result.frame);
    mm_character_free(&plain);
    free_recording(&r);
}

/* Every search's candidates: the brute-force search's best TOP_K (a second method) with the
 * parameters and query the character weighed, the winner first and the rest by cost; the five
 * terms add up to the base (mm_search_cost_terms's own sum, within float rounding) and the
 * favours and bias to the cost. */
static void test_candidates_and_terms(void **state)
{
    (void)state;
    recording r;
    make_character(&r.c, 0);
    assert_int_equal(mm_character_set_candidates(&r.c, TOP_K, NULL), MM_OK);
    int searched = 0, with_next = 0, with_contact = 0;
    for (int f = 0; f < TICKS; ++f) {
        int before = r.c.searches;
        mm_character_update(&r.c, &inputs[f], TICK_DT);
        if (r.c.searches == before) continue;
        ++searched;
        mm_candidate got[TOP_K];
        int n = mm_character_candidates(&r.c, got, TOP_K);
        mm_search_result brute[TOP_K];
        int m = mm_searcher_search(&searcher, r.c.query, &r.c.last_params, MM_SEARCH_BRUTE, brute, TOP_K);
        assert_int_equal(n, m);
        assert_true(n >= 2);
        assert_int_equal(got[0].frame, r.c.last_result.frame);
        for (int i = 0; i < n; ++i) {
            assert_int_equal(got[i].frame, brute[i].frame);
            assert_float_equal(got[i].cost, brute[i].cost, 1e-5f * (1.0f + fabsf(brute[i].cost)));
            assert_int_equal(got[i].clip, db.frame_clip[got[i].frame]);
            if (i > 1) assert_true(got[i].cost >= got[i - 1].cost);
            const mm_search_terms *t = &got[i].terms;
            float five =
                t->pose_position + t->pose_velocity + t->root_velocity + t->traj_position + t->traj_direction;
            assert_float_equal(five, got[i].base, 1e-4f * (1.0f + got[i].base));
            float total = got[i].base + got[i].loop_favour + got[i].contact_favour + got[i].next_pose_favour +
                          got[i].continuing_bias;
            assert_float_equal(total, got[i].cost, 1e-5f * (1.0f + fabsf(got[i].cost)));
            /* the contact favour: exactly on the frames in other contacts than the frame playing's */
            int pattern = r.c.last_params.contact_pattern; /* -1: no favour (standing) */
            bool other = pattern >= 0 && (int)db.contacts[got[i].frame] != pattern;
            assert_true(other == (got[i].contact_favour != 0.0f));
            with_contact += other;
            if (got[i].next_pose_favour != 0.0f) {
                ++with_next;
                assert_int_equal(got[i].frame, db.frame_next[r.c.last_params.current_frame]);
            }
        }
        /* the winner is at most the tie tolerance above the lowest */
        assert_true(got[0].cost <= got[1].cost + 1e-5f * fabsf(got[1].cost));
    }
    assert_true(searched > 20);
    assert_true(with_next > 0);    /* the favour of carrying on was seen at work */
    assert_true(with_contact > 0); /* and the contact favour */
    mm_character_free(&r.c);
}

/* A ring of 50 ticks keeps the newest 50; numbers, indices and the view's fields. */
static void test_ring_and_view(void **state)
{
    (void)state;
    enum { RING = 50 };
    recording r;
    record_run(&r, 0, RING, TOP_K);
    assert_int_equal(mm_recorder_count(&r.rec), RING);
    assert_int_equal(mm_recorder_oldest(&r.rec), TICKS - RING);
    assert_int_equal(mm_recorder_newest(&r.rec), TICKS - 1);
    assert_int_equal(mm_recorder_index(&r.rec, TICKS - RING), 0);
    assert_int_equal(mm_recorder_index(&r.rec, TICKS - RING - 1), -1);
    assert_null(mm_recorder_tick(&r.rec, RING));
    const mm_recorded_tick *last = mm_recorder_tick(&r.rec, RING - 1);
    assert_int_equal(last->number, TICKS - 1);
    assert_float_equal(last->time, TICKS * (double)TICK_DT, 1e-6);
    assert_memory_equal(last->global, r.c.global, sizeof(mm_xform) * (size_t)db.joint_count);
    assert_int_equal(last->frame, r.c.frame);
    assert_int_equal(last->searches, r.c.searches);
    int searches = 0, transitions = 0;
    for (int i = 0; i < RING; ++i) {
        const mm_recorded_tick *t = mm_recorder_tick(&r.rec, i);
        assert_int_equal(t->number, TICKS - RING + i);
        assert_memory_equal(&t->input, &inputs[t->number], sizeof(mm_input));
        searches += t->searched;
        transitions += t->transition;
        assert_int_equal(t->candidate_count > 0, t->searched);
        unsigned label = db.contacts[t->frame];
        assert_int_equal(t->heel_contact[0], (label & MM_CONTACT_LEFT_HEEL) != 0);
        assert_int_equal(t->toe_contact[1], (label & MM_CONTACT_RIGHT_TOE) != 0);
        /* the trajectory's present sample is the simulation's position */
        for (int k = 0; k < t->traj_count; ++k)
            if (t->traj_times[k] == 0.0f) assert_true(t->traj_positions[k].x == t->traj_positions[k].x);
    }
    const mm_recorded_tick *first = mm_recorder_tick(&r.rec, 0);
    assert_int_equal(searches, r.c.searches - (first->searches - first->searched));
    assert_int_equal(transitions, r.c.transitions - (first->transitions - first->transition));
    /* back to the tenth tick kept, the rest forgotten: recording on numbers from there */
    assert_int_equal(mm_recorder_restore(&r.rec, 9, &r.c, NULL), MM_OK);
    mm_recorder_truncate(&r.rec, 9);
    assert_int_equal(mm_recorder_count(&r.rec), 10);
    int64_t next = mm_recorder_newest(&r.rec) + 1;
    mm_character_update(&r.c, &inputs[next], TICK_DT);
    mm_recorder_record(&r.rec, &r.c, &inputs[next], TICK_DT);
    assert_int_equal(mm_recorder_newest(&r.rec), next);
    free_recording(&r);
}

/* Refusals: too little memory, ticks out of range, a snapshot of another layout, a short one. */
static void test_refusals(void **state)
{
    (void)state;
    mm_character c;
    make_character(&c, 0);
    mm_recorder rec;
    mm_error err;
    memset(&err, 0, sizeof err);
    size_t bytes = mm_recorder_bytes(&c, 10, TOP_K);
    void *memory = malloc(bytes);
    assert_int_equal(mm_recorder_bytes(&c, 0, TOP_K), 0);
    assert_int_equal(mm_recorder_bytes(&c, 10, MM_RECORDER_MAX_CANDIDATES + 1), 0);
    assert_int_equal(mm_recorder_init(&rec, memory, bytes - 1, &c, 10, TOP_K, &err), MM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "bytes"));
    assert_int_equal(mm_recorder_init(&rec, memory, bytes, &c, 10, TOP_K, NULL), MM_OK);
    assert_int_equal(mm_recorder_restore(&rec, 0, &c, NULL), MM_ERR_INVALID_ARGUMENT); /* empty */
    mm_character_update(&c, &inputs[0], TICK_DT);
    mm_recorder_record(&rec, &c, &inputs[0], TICK_DT);
    assert_int_equal(mm_recorder_restore(&rec, 1, &c, NULL), MM_ERR_INVALID_ARGUMENT);
    /* a character keeping another number of candidates has another layout */
    mm_character other;
    make_character(&other, 0);
    assert_int_equal(mm_recorder_restore(&rec, 0, &other, &err), MM_ERR_INVALID_ARGUMENT);
    size_t snap = mm_character_snapshot_bytes(&c);
    unsigned char *s = malloc(snap);
    assert_int_equal(mm_character_snapshot_save(&c, s, snap - 1, NULL), MM_ERR_INVALID_ARGUMENT);
    assert_int_equal(mm_character_snapshot_save(&c, s, snap, NULL), MM_OK);
    assert_int_equal(mm_character_snapshot_load(&c, s, snap - 1, NULL), MM_ERR_INVALID_ARGUMENT);
    s[0] ^= 0xff; /* not a snapshot */
    assert_int_equal(mm_character_snapshot_load(&c, s, snap, NULL), MM_ERR_INVALID_ARGUMENT);
    assert_int_equal(mm_character_set_candidates(&c, 0, NULL), MM_ERR_INVALID_ARGUMENT);
    free(s);
    mm_character_free(&other);
    mm_character_free(&c);
    free(memory);
}

static int setup(void **state)
{
    (void)state;
    if (test_build_synth_database(&db) != 0) return -1;
    make_inputs();
    return mm_searcher_init(&searcher, &db, NULL, NULL) == MM_OK ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    mm_searcher_free(&searcher);
    mm_database_free(&db);
    return 0;
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_restore_repeats_the_run),
        cmocka_unit_test(test_candidates_leave_the_run_alone),
        cmocka_unit_test(test_candidates_and_terms),
        cmocka_unit_test(test_ring_and_view),
        cmocka_unit_test(test_refusals),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
