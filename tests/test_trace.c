/* The trace (mm/trace.h): a run written as the library writes it for mm simulate --trace, read
 * back (every field as written: the searches, their queries, candidates and terms, the ticks),
 * checked against the search itself (mm_search_cost_terms on the query read back, the brute-force
 * search's best), replayed without a difference, and the first difference found (and where) once
 * a line is changed. Bad files are refused naming the line. */
#include <math.h>

#include "test_util.h"

#include <mm/database.h>
#include <mm/input_json.h>
#include <mm/moves.h>
#include <mm/trace.h>

#include "runtime/character/matching.h"
#include "test_databases.h"

#define SEED    11
#define SECONDS 6.0
#define FPS     60.0
#define TOP_K   4

static mm_database db;
static char trace_path[1024], changed_path[1024];
static int run_searches, run_transitions;

/* A run as mm simulate --random SEED --trace makes it: the move layer around the character. */
static void write_trace(const char *path, const mm_trace_run *run)
{
    mm_input_script script;
    mm_input_random_desc rd;
    memset(&rd, 0, sizeof rd);
    rd.seconds = (float)run->random_seconds;
    assert_int_equal(mm_input_script_random(&script, (uint64_t)run->random_seed, &rd), MM_OK);
    mm_searcher searcher;
    assert_int_equal(mm_searcher_init(&searcher, &db, NULL, NULL), MM_OK);
    mm_character_desc desc;
    assert_int_equal(mm_character_desc_from_database(&desc, &db, NULL), MM_OK);
    mm_character c;
    assert_int_equal(mm_character_init(&c, &db, &searcher, &desc, NULL), MM_OK);
    assert_int_equal(mm_character_set_candidates(&c, run->top_k, NULL), MM_OK);
    mm_moves moves;
    mm_moves_desc md;
    mm_moves_desc_from_database(&md, &db);
    assert_int_equal(mm_moves_init(&moves, &db, NULL, &md, NULL), MM_OK);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(mm_trace_write_header(f, run, &db), MM_OK);
    float dt = (float)(1.0 / run->fps);
    for (int k = 0; k < run->ticks; ++k) {
        mm_input in;
        mm_input_script_sample_tick(&script, (float)(k / run->fps), dt, &in);
        int s = c.searches, t = c.transitions;
        mm_moves_update(&moves, &c, &in, dt);
        assert_int_equal(mm_trace_write_tick(f, run, &c, k, (k + 1) / run->fps, s, t), MM_OK);
    }
    fclose(f);
    run_searches = c.searches;
    run_transitions = c.transitions;
    mm_character_free(&c);
    mm_searcher_free(&searcher);
    mm_input_script_free(&script);
}

static void make_run(mm_trace_run *run, bool tick_lines)
{
    mm_trace_run_defaults(run);
    snprintf(run->db_path, sizeof run->db_path, "built-in set");
    run->db_checksum = mm_trace_db_checksum(&db);
    run->db_size = (uint64_t)db.size;
    run->db_frames = db.frame_count;
    run->fps = FPS;
    run->ticks = (int)(SECONDS * FPS);
    run->random_seed = SEED;
    run->random_seconds = SECONDS;
    run->top_k = TOP_K;
    run->tick_lines = tick_lines;
}

/* Everything read back is what the run did; the terms are the search's own. */
static void test_read_back(void **state)
{
    (void)state;
    mm_trace t;
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_trace_read(trace_path, &t, &err), MM_OK);
    assert_int_equal(t.run.db_checksum, mm_trace_db_checksum(&db));
    assert_int_equal(t.run.db_size, (uint64_t)db.size);
    assert_int_equal(t.run.random_seed, SEED);
    assert_float_equal(t.run.random_seconds, SECONDS, 0.0);
    assert_int_equal(t.run.ticks, (int)(SECONDS * FPS));
    assert_int_equal(t.run.top_k, TOP_K);
    assert_true(t.run.tick_lines);
    assert_int_equal(t.dims, db.dims);
    assert_int_equal(t.search_count, run_searches);
    assert_int_equal(t.tick_count, t.run.ticks);
    int transitions = 0;
    mm_search_params p;
    mm_character_default_params(&db, &p);
    for (int i = 0; i < t.search_count; ++i) {
        const mm_trace_search *s = &t.searches[i];
        transitions += s->transition;
        assert_true(s->candidate_count >= 1 && s->candidate_count <= TOP_K);
        assert_int_equal(t.ticks[s->tick].frame, s->winner); /* where playback went */
        const mm_trace_candidate *c = &t.candidates[s->candidate_first];
        if (s->transition) assert_int_equal(s->winner, s->choice); /* the candidate chosen */
        for (int k = 1; k < s->candidate_count; ++k) /* chosen over the winner: within the price */
            if (c[k].frame == s->choice)
                assert_true(c[k].cost <= c[0].cost + PLANT_PRICE * fabsf(c[0].cost) + 1e-5f);
        /* the five terms: mm_search_cost_terms on the query read back, with the weights the
         * character weighed (the database's: its ratio moves only while the velocity changes,
         * which scales the pose and trajectory terms alike, so compare shares of the sum) */
        float query[MM_SEARCH_MAX_DIMS] = {0};
        memcpy(query, t.queries + s->query_offset, sizeof(float) * (size_t)t.dims);
        for (int k = 0; k < s->candidate_count; ++k) {
            assert_int_equal(c[k].clip, db.frame_clip[c[k].frame]);
            float sum = 0.0f;
            for (int j = 0; j < MM_TRACE_TERM_COUNT; ++j) sum += c[k].terms[j];
            assert_float_equal(sum, c[k].cost, 1e-4f * (1.0f + fabsf(c[k].cost)));
            mm_search_terms own;
            mm_search_cost_terms(&db, query, &p, c[k].frame, &own);
            /* the ratio r' the search weighed with scales the pose terms by a = (1 - r') / (1 - r) and
             * the trajectory terms by b = r' / r: every term by its group's factor, and
             * a (1 - r) + b r = 1 */
            float r = p.pose_trajectory_ratio;
            float pose = c[k].terms[0] + c[k].terms[1] + c[k].terms[2], traj = c[k].terms[3] + c[k].terms[4];
            float own_pose = own.pose_position + own.pose_velocity + own.root_velocity,
                  own_traj = own.traj_position + own.traj_direction;
            assert_true(own_pose > 0.0f && own_traj > 0.0f);
            float a = pose / own_pose, b = traj / own_traj;
            assert_float_equal(a * (1.0f - r) + b * r, 1.0f, 1e-3f);
            assert_float_equal(c[k].terms[0], a * own.pose_position, 1e-4f * (1.0f + pose));
            assert_float_equal(c[k].terms[1], a * own.pose_velocity, 1e-4f * (1.0f + pose));
            assert_float_equal(c[k].terms[3], b * own.traj_position, 1e-4f * (1.0f + traj));
            assert_float_equal(c[k].terms[4], b * own.traj_direction, 1e-4f * (1.0f + traj));
            if (k > 1) assert_true(c[k].cost >= c[k - 1].cost);
        }
    }
    assert_int_equal(transitions, run_transitions);
    mm_trace_free(&t);
}

/* The run again from the header alone: no difference. */
static void test_replay_agrees(void **state)
{
    (void)state;
    mm_trace t;
    assert_int_equal(mm_trace_read(trace_path, &t, NULL), MM_OK);
    mm_trace_divergence d;
    assert_int_equal(mm_trace_replay(&t, &db, &d, NULL), MM_OK);
    if (d.diverged) print_error("tick %d, line %ld: %s\n", d.tick, d.line, d.message);
    assert_false(d.diverged);
    assert_int_equal(d.tick, -1);
    mm_trace_free(&t);
}

/* Tick by tick: after each step the character is where the trace's tick line says, the search
 * matched is the trace's search of that tick, and the run ends with the header's ticks. */
static void test_player_steps(void **state)
{
    (void)state;
    mm_trace t;
    assert_int_equal(mm_trace_read(trace_path, &t, NULL), MM_OK);
    mm_trace_player *p;
    assert_int_equal(mm_trace_player_open(&p, &t, &db, NULL), MM_OK);
    int searches = 0;
    for (int k = 0; k < t.run.ticks; ++k) {
        assert_int_equal(mm_trace_player_step(p, NULL), MM_OK);
        assert_int_equal(mm_trace_player_tick(p), k + 1);
        const mm_character *c = mm_trace_player_character(p);
        assert_int_equal(c->frame, t.ticks[k].frame);
        assert_memory_equal(&c->root.translation, &t.ticks[k].root.translation, sizeof(mm_vec3));
        int s = mm_trace_player_search(p);
        if (s >= 0) {
            assert_int_equal(s, searches++);
            assert_int_equal(t.searches[s].tick, k);
        }
        assert_false(mm_trace_player_divergence(p)->diverged);
    }
    assert_int_equal(searches, t.search_count);
    assert_int_equal(mm_trace_player_step(p, NULL), MM_ERR_INVALID_ARGUMENT); /* played out */
    mm_trace_player_close(p);
    mm_trace_free(&t);
}

/* Copies the trace, with the n-th search line's first `from` replaced by `to`; returns its line. */
static long change_search_line(int n, const char *from, const char *to)
{
    FILE *in = fopen(trace_path, "rb"), *out = fopen(changed_path, "wb");
    assert_non_null(in);
    assert_non_null(out);
    static char line[1 << 16];
    long number = 0, changed = 0;
    int search = 0;
    while (fgets(line, sizeof line, in)) {
        ++number;
        char *at = strstr(line, "\"type\":\"search\"") && search++ == n ? strstr(line, from) : NULL;
        if (at) {
            changed = number;
            fwrite(line, 1, (size_t)(at - line), out);
            fputs(to, out);
            fputs(at + strlen(from), out);
        } else {
            fputs(line, out);
        }
    }
    fclose(in);
    fclose(out);
    return changed;
}

/* A changed winner, a changed candidate cost and a missing search are found, at their line. */
static void test_replay_finds_differences(void **state)
{
    (void)state;
    mm_trace t;
    assert_int_equal(mm_trace_read(trace_path, &t, NULL), MM_OK);
    assert_true(t.search_count > 10);
    int n = t.search_count / 2;
    int tick = t.searches[n].tick;
    char winner[64], other[64];
    snprintf(winner, sizeof winner, "\"winner\":%d,", t.searches[n].winner);
    snprintf(other, sizeof other, "\"winner\":%d,", t.searches[n].winner + 1);
    mm_trace_free(&t);

    long line = change_search_line(n, winner, other);
    assert_true(line > 1);
    mm_trace_divergence d;
    assert_int_equal(mm_trace_read(changed_path, &t, NULL), MM_OK);
    assert_int_equal(mm_trace_replay(&t, &db, &d, NULL), MM_OK);
    assert_true(d.diverged);
    assert_int_equal(d.tick, tick);
    assert_int_equal(d.line, line);
    assert_non_null(strstr(d.message, "winner"));
    mm_trace_free(&t);

    line = change_search_line(n, "\"cost\":", "\"cost\":1");
    assert_int_equal(mm_trace_read(changed_path, &t, NULL), MM_OK);
    assert_int_equal(mm_trace_replay(&t, &db, &d, NULL), MM_OK);
    assert_true(d.diverged);
    assert_int_equal(d.line, line);
    assert_non_null(strstr(d.message, "candidates[0]"));
    mm_trace_free(&t);

    /* another seed in the header: the searches come at other ticks or say other things */
    FILE *f = fopen(trace_path, "rb");
    static char text[1 << 22];
    size_t size = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    text[size] = 0;
    char *seed = strstr(text, "\"seed\":11,");
    assert_non_null(seed);
    seed[8] = '2'; /* 11 -> 12 */
    f = fopen(changed_path, "wb");
    fwrite(text, 1, size, f);
    fclose(f);
    assert_int_equal(mm_trace_read(changed_path, &t, NULL), MM_OK);
    assert_int_equal(mm_trace_replay(&t, &db, &d, NULL), MM_OK);
    assert_true(d.diverged);
    mm_trace_free(&t);

    /* another database: refused */
    assert_int_equal(mm_trace_read(trace_path, &t, NULL), MM_OK);
    t.run.db_checksum ^= 1;
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_trace_replay(&t, &db, &d, &err), MM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "another database"));
    mm_trace_free(&t);
}

/* Writes text to changed_path and reads it: the result and the error's line. */
static mm_result read_text(const char *text, mm_error *err)
{
    FILE *f = fopen(changed_path, "wb");
    fputs(text, f);
    fclose(f);
    memset(err, 0, sizeof *err);
    mm_trace t;
    mm_result r = mm_trace_read(changed_path, &t, err);
    if (r == MM_OK) mm_trace_free(&t);
    return r;
}

static void test_bad_files(void **state)
{
    (void)state;
    mm_error err;
    assert_int_equal(read_text("", &err), MM_ERR_UNEXPECTED_EOF);
    assert_int_equal(read_text("{\"type\":\"search\"}\n", &err), MM_ERR_SYNTAX);
    assert_int_equal(err.line, 1);
    /* the real header, then a cut line, then an unknown type */
    FILE *f = fopen(trace_path, "rb");
    static char header[1 << 16];
    assert_non_null(fgets(header, sizeof header, f));
    fclose(f);
    static char text[1 << 17];
    snprintf(text, sizeof text, "%s{\"type\":\"search\",\"tick\":3,\n", header);
    assert_int_equal(read_text(text, &err), MM_ERR_SYNTAX);
    assert_int_equal(err.line, 2);
    snprintf(text, sizeof text, "%s{\"type\":\"tick\",\"tick\":0,\"t\":0.1}\n{\"type\":\"other\"}\n", header);
    assert_int_equal(read_text(text, &err), MM_ERR_SYNTAX);
    assert_int_equal(err.line, 2);
    assert_non_null(strstr(err.message, "clip"));
    snprintf(text, sizeof text, "%s{\"type\":\"other\"}\n", header);
    assert_int_equal(read_text(text, &err), MM_ERR_SYNTAX);
    assert_non_null(strstr(err.message, "other"));
    /* a query of the wrong length */
    snprintf(
        text, sizeof text,
        "%s{\"type\":\"search\",\"tick\":0,\"t\":0.1,\"frame_before\":0,\"winner\":1,\"transition\":false,"
        "\"query\":[1,2],\"candidates\":[]}\n",
        header);
    assert_int_equal(read_text(text, &err), MM_ERR_SYNTAX);
    assert_non_null(strstr(err.message, "query"));
    assert_int_equal(mm_trace_read("/no/such/trace.jsonl", &(mm_trace){0}, &err) != MM_OK, 1);
}

/* mm simulate's own traces replay without a difference: a script with crossfades, distance
 * matching and warping switched on over the database's settings, and a desired path. */
static void test_simulate_traces_replay(void **state)
{
    (void)state;
    const char *mm = getenv("MM_BIN");
    if (!mm) skip();
    char db_path[1024], path_file[1024], out[1024], trace[1024], cmd[8192];
    snprintf(db_path, sizeof db_path, "%s/test_trace.mmdb", MM_TEST_OUT);
    snprintf(path_file, sizeof path_file, "%s/test_trace_path.json", MM_TEST_OUT);
    snprintf(out, sizeof out, "%s/test_trace.bvh", MM_TEST_OUT);
    snprintf(trace, sizeof trace, "%s/test_trace_cli.jsonl", MM_TEST_OUT);
    assert_int_equal(mm_database_save(&db, db_path, NULL), MM_OK);
    mm_database loaded;
    assert_int_equal(mm_database_load(db_path, NULL, &loaded, NULL), MM_OK);
    FILE *f = fopen(path_file, "w");
    assert_non_null(f);
    fprintf(f, "{\"points\": [{\"t\": 0, \"position\": [0, 0]}, {\"t\": 3, \"position\": [0, 4]},\n"
               "  {\"t\": 5, \"position\": [2, 5]}]}\n");
    fclose(f);
    const char *runs[2] = {"--input " MM_SOURCE_DIR "/scripts/input/demo.json --transition crossfade "
                           "--distance-matching on --warping on --trace-k 3 --trace-ticks",
                           "--path %s"};
    for (int k = 0; k < 2; ++k) {
        char options[2048];
        snprintf(options, sizeof options, runs[k], path_file);
        snprintf(cmd, sizeof cmd, "%s simulate %s %s --seconds 5 -o %s --trace %s > %s.out", mm, db_path,
                 options, out, trace, trace);
        assert_int_equal(system(cmd), 0);
        mm_trace t;
        mm_error err;
        memset(&err, 0, sizeof err);
        assert_int_equal(mm_trace_read(trace, &t, &err), MM_OK);
        assert_true(t.search_count > 10);
        assert_int_equal(t.run.ticks, 300);
        if (k == 0) {
            assert_int_equal(t.run.transition_mode, MM_TRANSITION_CROSSFADE);
            assert_int_equal(t.run.distance_matching, 1);
            assert_int_equal(t.run.top_k, 3);
            assert_int_equal(t.tick_count, 300);
        } else {
            assert_string_equal(t.run.path_file, path_file);
        }
        mm_trace_divergence d;
        assert_int_equal(mm_trace_replay(&t, &loaded, &d, &err), MM_OK);
        if (d.diverged) print_error("run %d: tick %d, line %ld: %s\n", k, d.tick, d.line, d.message);
        assert_false(d.diverged);
        mm_trace_free(&t);
    }
    mm_database_free(&loaded);
    remove(db_path);
    remove(path_file);
    remove(out);
    remove(trace);
    snprintf(cmd, sizeof cmd, "%s.out", trace);
    remove(cmd);
}

static int setup(void **state)
{
    (void)state;
    if (test_build_synth_database(&db) != 0) return -1;
    snprintf(trace_path, sizeof trace_path, "%s/test_trace.jsonl", MM_TEST_OUT);
    snprintf(changed_path, sizeof changed_path, "%s/test_trace_changed.jsonl", MM_TEST_OUT);
    mm_trace_run run;
    make_run(&run, true);
    write_trace(trace_path, &run);
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    remove(trace_path);
    remove(changed_path);
    mm_database_free(&db);
    return 0;
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_read_back),    cmocka_unit_test(test_replay_agrees),
        cmocka_unit_test(test_player_steps), cmocka_unit_test(test_replay_finds_differences),
        cmocka_unit_test(test_bad_files),    cmocka_unit_test(test_simulate_traces_replay),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
