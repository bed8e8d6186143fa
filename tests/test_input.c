/* Input scripts: the shipped scripts, sampling, the random generator, JSON round trip, errors. */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <math.h>

#include <mm/input_json.h>

#include "test_util.h"

static void test_shipped_scripts(void **state)
{
    (void)state;
    const char *dir = MM_TEST_DATA "/../../scripts/input";
    DIR *d = opendir(dir);
    assert_non_null(d);
    int count = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        size_t n = strlen(e->d_name);
        if (n < 6 || strcmp(e->d_name + n - 5, ".json") != 0) continue;
        char path[1024];
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        mm_input_script s;
        mm_error err;
        memset(&err, 0, sizeof err);
        mm_result r = mm_input_script_load_json(path, &s, &err);
        if (r != MM_OK) print_error("%s: %s\n", path, err.message);
        assert_int_equal(r, MM_OK);
        assert_true(s.key_count >= 2);
        mm_input_script_free(&s);
        ++count;
    }
    closedir(d);
    assert_true(count >= 9); /* walk, run, stop-and-go, 90, 180, circle, zig-zag, strafe, walk/run */
}

static void test_sampling(void **state)
{
    (void)state;
    const char text[] =
        "{\"keys\": [{\"t\": 1, \"stick\": [0, 1]}, {\"t\": 2.5, \"stick\": [0.6, 0.8], \"gait\": \"run\", "
        "\"strafe\": true, \"facing\": [0, 2]}]}";
    mm_input_script s;
    assert_int_equal(mm_input_script_parse_json(text, sizeof text - 1, "t.json", &s, NULL), MM_OK);
    mm_input in;
    mm_input_script_sample(&s, 0.5f, &in); /* before the first key: neutral */
    assert_near(in.stick[1], 0, 0);
    assert_int_equal(in.gait, MM_GAIT_WALK);
    mm_input_script_sample(&s, 1.0f, &in);
    assert_near(in.stick[1], 1, 0);
    mm_input_script_sample(&s, 2.4999f, &in); /* a key holds until the next */
    assert_near(in.stick[1], 1, 0);
    mm_input_script_sample(&s, 100.0f, &in);
    assert_near(in.stick[0], 0.6, 1e-7);
    assert_int_equal(in.gait, MM_GAIT_RUN);
    assert_true(in.strafe && in.has_facing);
    assert_near(in.facing[1], 1.0, 1e-7); /* normalised */
    mm_input_script_sample(&s, NAN, &in);
    assert_near(in.stick[1], 0, 0);
    mm_input_script_free(&s);
}

/* "jump": true presses the button on exactly one tick: the one whose interval holds the key. */
static void test_jump_presses(void **state)
{
    (void)state;
    const char *text =
        "{\"keys\": [{\"t\": 0, \"stick\": [0, 0], \"jump\": true}, {\"t\": 0.5, \"stick\": [0, 1]},"
        " {\"t\": 1.0, \"stick\": [0, 1], \"jump\": true}, {\"t\": 1.01, \"stick\": [0, 1], "
        "\"jump\": true}]}";
    mm_input_script s;
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_input_script_parse_json(text, strlen(text), "jump", &s, &err), MM_OK);
    assert_true(s.keys[0].input.jump && !s.keys[1].input.jump && s.keys[2].input.jump);
    int presses = 0, first = -1, second = -1;
    float dt = 1.0f / 60.0f;
    for (int f = 0; f < 120; ++f) {
        mm_input in;
        mm_input_script_sample_tick(&s, (float)f * dt, dt, &in);
        if (!in.jump) continue;
        if (presses == 0) first = f;
        if (presses == 1) second = f;
        ++presses;
    }
    /* the keys at 1.0 and 1.01 s fall into ticks 60 and 61: three presses in all */
    assert_int_equal(presses, 3);
    assert_int_equal(first, 0);
    assert_int_equal(second, 60);
    mm_input in; /* plain sampling reports the key's flag as long as it holds */
    mm_input_script_sample(&s, 0.3f, &in);
    assert_true(in.jump);
    FILE *f = tmpfile();
    assert_non_null(f);
    assert_int_equal(mm_input_script_write_json(&s, f), MM_OK);
    rewind(f);
    char back[1024];
    size_t n = fread(back, 1, sizeof back - 1, f);
    back[n] = 0;
    fclose(f);
    assert_non_null(strstr(back, "\"jump\": true"));
    mm_input_script_free(&s);
}

static void test_random(void **state)
{
    (void)state;
    mm_input_script a, b, c;
    mm_input_random_desc desc = {120.0f, 0, 0, 0, 0, NULL};
    assert_int_equal(mm_input_script_random(&a, 7, &desc), MM_OK);
    assert_int_equal(mm_input_script_random(&b, 7, &desc), MM_OK);
    assert_int_equal(mm_input_script_random(&c, 8, &desc), MM_OK);
    assert_int_equal(a.key_count, b.key_count);
    assert_memory_equal(a.keys, b.keys, sizeof(mm_input_key) * (size_t)a.key_count);
    assert_true(c.key_count != a.key_count ||
                memcmp(a.keys, c.keys, sizeof(mm_input_key) * (size_t)a.key_count));
    assert_int_equal(mm_input_script_validate(&a, NULL), MM_OK);
    assert_true(a.keys[a.key_count - 1].t < 120.0f);
    /* 120 s with 1.5 s holds: about 80 keys; runs, strafes and idle all appear */
    assert_true(a.key_count > 40 && a.key_count < 160);
    int runs = 0, strafes = 0, idle = 0;
    for (int i = 0; i < a.key_count; ++i) {
        runs += a.keys[i].input.gait == MM_GAIT_RUN;
        strafes += a.keys[i].input.strafe;
        idle += a.keys[i].input.stick[0] == 0.0f && a.keys[i].input.stick[1] == 0.0f;
    }
    assert_true(runs > 0 && strafes > 0 && idle > 0);

    /* written and read back, the same keys */
    char *buf = NULL;
    size_t size = 0;
    FILE *f = open_memstream(&buf, &size);
    assert_int_equal(mm_input_script_write_json(&a, f), MM_OK);
    fclose(f);
    mm_input_script back;
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_input_script_parse_json(buf, size, "written.json", &back, &err), MM_OK);
    assert_int_equal(back.key_count, a.key_count);
    for (int i = 0; i < a.key_count; ++i) {
        assert_true(back.keys[i].t == a.keys[i].t);
        assert_true(back.keys[i].input.stick[0] == a.keys[i].input.stick[0]);
        assert_int_equal(back.keys[i].input.gait, a.keys[i].input.gait);
        assert_int_equal(back.keys[i].input.strafe, a.keys[i].input.strafe);
    }
    free(buf);
    mm_input_script_free(&back);
    mm_input_script_free(&a);
    mm_input_script_free(&b);
    mm_input_script_free(&c);
}

static void expect_error(const char *text, mm_result code, const char *message)
{
    mm_input_script s;
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_result r = mm_input_script_parse_json(text, strlen(text), "bad.json", &s, &err);
    if (r != code || !strstr(err.message, message))
        print_error("%s -> %s '%s', wanted %s '%s'\n", text, mm_result_name(r), err.message,
                    mm_result_name(code), message);
    assert_int_equal(r, code);
    assert_non_null(strstr(err.message, message));
    assert_string_equal(err.file, "bad.json");
    assert_null(s.keys);
}

static void test_errors(void **state)
{
    (void)state;
    expect_error("", MM_ERR_UNEXPECTED_EOF, "empty");
    expect_error("{\"keys\": [", MM_ERR_SYNTAX, "not valid JSON");
    expect_error("[1]", MM_ERR_SYNTAX, "an input script is an object");
    expect_error("{\"key\": []}", MM_ERR_SYNTAX, "keys: missing");
    expect_error("{\"keys\": [], \"speed\": 2}", MM_ERR_UNKNOWN_KEYWORD, "speed: unknown field");
    expect_error("{\"keys\": [{\"stick\": [0, 1]}]}", MM_ERR_SYNTAX, "keys[0].t is missing");
    expect_error("{\"keys\": [{\"t\": 0}]}", MM_ERR_SYNTAX, "keys[0].stick is missing");
    expect_error("{\"keys\": [{\"t\": 0, \"stick\": [0, 1, 2]}]}", MM_ERR_SYNTAX,
                 "keys[0].stick must be [x, z]");
    expect_error("{\"keys\": [{\"t\": 0, \"stick\": [0, 1e999]}]}", MM_ERR_BAD_NUMBER, "keys[0].stick");
    expect_error("{\"keys\": [{\"t\": 0, \"stick\": [1, 1]}]}", MM_ERR_OUT_OF_RANGE,
                 "keys[0].stick: [1, 1] is not within");
    expect_error("{\"keys\": [{\"t\": 1, \"stick\": [0, 1]}, {\"t\": 1, \"stick\": [0, 1]}]}",
                 MM_ERR_OUT_OF_RANGE, "keys[1].t: 1 does not come after 1");
    expect_error("{\"keys\": [{\"t\": -1, \"stick\": [0, 1]}]}", MM_ERR_OUT_OF_RANGE, "keys[0].t");
    expect_error("{\"keys\": [{\"t\": 0, \"stick\": [0, 1], \"gait\": \"fly\"}]}", MM_ERR_SYNTAX,
                 "keys[0].gait");
    expect_error("{\"keys\": [{\"t\": 0, \"stick\": [0, 1], \"facing\": [0, 0]}]}", MM_ERR_OUT_OF_RANGE,
                 "keys[0].facing must not be zero");
    expect_error("{\"keys\": [{\"t\": 0, \"stick\": [0, 1], \"jumps\": true}]}", MM_ERR_UNKNOWN_KEYWORD,
                 "keys[0].jumps: unknown field");
    expect_error("{\"keys\": [{\"t\": 0, \"stick\": [0, 1], \"jump\": 1}]}", MM_ERR_SYNTAX,
                 "keys[0].jump must be true or false");
    mm_input_script s;
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_input_script_load_json("/nonexistent/in.json", &s, &err), MM_ERR_IO);
    assert_string_equal(err.file, "/nonexistent/in.json");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_shipped_scripts), cmocka_unit_test(test_sampling),
        cmocka_unit_test(test_random),          cmocka_unit_test(test_jump_presses),
        cmocka_unit_test(test_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
