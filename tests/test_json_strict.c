/* Strict JSON in the config, input-script and scene readers: a key given twice and text after the
 * value are refused at their line and column; every meaning error (wrong type, out of range,
 * unknown field, a name used twice) names the line and column of its value besides the field
 * path, in the file it is in (a config that extends another); numbers a float cannot hold are
 * reported as written; the documented size limits are refused with a message. Expected messages
 * and positions are written out by hand from the texts below. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <unistd.h>

#include <mm/config_json.h>
#include <mm/input_json.h>
#include <mm/scene_json.h>

#include "test_util.h"

/* The formatted error of reading text as a config named c.json, "" when it reads. */
static const char *config_error(const char *text, char *out, size_t size)
{
    mm_config cfg;
    memset(&cfg, 0, sizeof cfg);
    mm_error err;
    memset(&err, 0, sizeof err);
    out[0] = 0;
    if (mm_config_parse_json(text, strlen(text), "c.json", NULL, &cfg, &err) == MM_OK) {
        mm_config_free(&cfg);
        return out;
    }
    mm_error_format(&err, out, size);
    return out;
}

static void expect_config(const char *text, const char *want)
{
    char got[600];
    config_error(text, got, sizeof got);
    if (strcmp(got, want) != 0) fail_msg("%s\n  got  '%s'\n  want '%s'", text, got, want);
}

static void test_config_strict(void **state)
{
    (void)state;
    /* the cases: the second interval used to be ignored, the junk after the value too */
    expect_config("{\"interval\": 0.1, \"interval\": 0.5}",
                  "c.json:1:19: key 'interval' given twice (first at line 1, column 2)");
    expect_config("{\"interval\": 0.1} junk", "c.json:1:19: text after the JSON value");
    expect_config("{\"interval\": 0.1}\n\n  {}", "c.json:3:3: text after the JSON value");
    expect_config("[]", "c.json:1:1: the config must be an object");
    /* keys compared after unescaping: "a" and "\u0061" are the same key */
    expect_config("{\"roles\": {\"hips\": \"A\",\n \"hi\\u0070s\": \"B\"}}",
                  "c.json:2:2: key 'hips' given twice (first at line 1, column 12)");
    /* a duplicate among many keys (the hashed path) */
    char text[4096];
    int n = snprintf(text, sizeof text, "{\"runtime\": {");
    const char *keys[] = {
        "pose_trajectory_ratio", "next_pose_favour",    "loop_anim_favour", "continuing_bias",
        "search_interval",       "transition_halflife", "idle_speed",       "sync_halflife",
        "distance_matching"};
    for (int i = 0; i < 9; ++i) n += snprintf(text + n, sizeof text - (size_t)n, "\"%s\": 1, ", keys[i]);
    snprintf(text + n, sizeof text - (size_t)n, "\"idle_speed\": 2}}");
    char got[600];
    config_error(text, got, sizeof got);
    assert_non_null(strstr(got, "key 'idle_speed' given twice (first at line 1, column 158)"));
    /* RFC 8259's numbers, nothing more */
    expect_config("{\"interval\": .5}", "c.json:1:14: not valid JSON here");
    expect_config("{\"interval\": 00.5}", "c.json:1:14: not valid JSON here: not a JSON number");
    expect_config("{\"interval\": 0.5e}", "c.json:1:17: not valid JSON here");
}

static void test_config_meaning_errors(void **state)
{
    (void)state;
    /* wrong type, out of range (checked after parsing, by mm_config_validate), unknown field, a name
     * used twice: each at its value */
    expect_config(
        "{\n  \"clips\": [\n    {\"file\": \"a.bvh\"},\n    {\"file\": \"b.bvh\", \"type\": \"run\"}\n  ]\n}",
        "c.json:4:31: clips[1].type must be \"idle\" or \"locomotion\"");
    expect_config("{\n \"runtime\": {\"sync_halflife\": 61}\n}",
                  "c.json:2:31: runtime.sync_halflife: 61 s is out of range (0 to 60 s)");
    expect_config("{\n \"interval\": 2\n}", "c.json:2:14: interval: 2 s is out of range (0 to 1 s)");
    expect_config("{\"roles\": {\"hips\": \"H\",\n           \"feet\": 3}}",
                  "c.json:2:20: roles.feet: unknown field (see mm config explain)");
    expect_config("{\"clips\": [{\"file\": \"a.bvh\"},\n {\"file\": \"x/a.bvh\"}]}",
                  "c.json:2:2: clips[1].name 'a' is used twice");
    expect_config("{\"clips\": [{\"file\": \"a.bvh\", \"ranges\": [[0, 5],\n [7, 3]]}]}",
                  "c.json:2:2: clips[0] (a).ranges[1]: [7, 3) is empty or negative");
    expect_config("{\"features\": {\"trajectory_times\": [0.5,\n  \"1\"]}}",
                  "c.json:2:3: features.trajectory_times[1] must be a finite number");
    /* numbers a float cannot hold: as written, not inf */
    expect_config("{\n  \"interval\": 1e308\n}",
                  "c.json:2:15: interval: 1e308 does not fit a float (at most 3.40282e+38)");
    expect_config("{\"roles\": {\"forward_axis\": [0, 0, -4.5E+39]}}",
                  "c.json:1:35: roles.forward_axis[2]: -4.5E+39 does not fit a float (at most 3.40282e+38)");
}

/* An error in the config a config extends names that file and its line. */
static void test_config_extends(void **state)
{
    (void)state;
    char dir[] = "/tmp/mm_test_json_strict_XXXXXX";
    assert_non_null(mkdtemp(dir));
    char base[256], top[256];
    snprintf(base, sizeof base, "%s/base.json", dir);
    snprintf(top, sizeof top, "%s/top.json", dir);
    FILE *f = fopen(base, "w");
    assert_non_null(f);
    fputs("{\n  \"contacts\": {\"height\": -1}\n}\n", f);
    fclose(f);
    f = fopen(top, "w");
    assert_non_null(f);
    fputs("{\"extends\": \"base.json\",\n \"interval\": 0.5}\n", f);
    fclose(f);
    mm_config cfg;
    memset(&cfg, 0, sizeof cfg);
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_config_load_json(top, &cfg, NULL, &err), MM_ERR_OUT_OF_RANGE);
    assert_string_equal(err.file, base);
    assert_int_equal(err.line, 2);
    assert_int_equal(err.column, 26);
    assert_non_null(strstr(err.message, "contacts.height: -1 must be positive"));
    /* and one in the top file names the top file */
    f = fopen(top, "w");
    assert_non_null(f);
    fputs("{\"extends\": \"base.json\",\n \"interval\": 3}\n", f);
    fclose(f);
    f = fopen(base, "w");
    assert_non_null(f);
    fputs("{}\n", f);
    fclose(f);
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_config_load_json(top, &cfg, NULL, &err), MM_ERR_OUT_OF_RANGE);
    assert_string_equal(err.file, top);
    assert_int_equal(err.line, 2);
    assert_int_equal(err.column, 14);
    unlink(base);
    unlink(top);
    rmdir(dir);
}

static void expect_script(const char *text, const char *want)
{
    mm_input_script s;
    mm_error err;
    memset(&err, 0, sizeof err);
    char got[600] = "";
    if (mm_input_script_parse_json(text, strlen(text), "in.json", &s, &err) == MM_OK)
        mm_input_script_free(&s);
    else
        mm_error_format(&err, got, sizeof got);
    if (strcmp(got, want) != 0) fail_msg("%s\n  got  '%s'\n  want '%s'", text, got, want);
}

static void test_input_and_scene(void **state)
{
    (void)state;
    expect_script("{\"keys\": [{\"t\": 0, \"stick\": [0, 1], \"stick\": [1, 0]}]}",
                  "in.json:1:37: key 'stick' given twice (first at line 1, column 20)");
    expect_script("{\"keys\": []} {\"keys\": []}", "in.json:1:14: text after the JSON value");
    /* the facing: [1e308, 0] was "[-nan, 0] is not a unit direction" */
    expect_script("{\"keys\": [\n  {\"t\": 0, \"stick\": [0, 1], \"facing\": [1e308, 0]}]}",
                  "in.json:2:40: keys[0].facing[0]: 1e308 does not fit a float (at most 3.40282e+38)");
    expect_script("{\"keys\": [\n  {\"t\": 0, \"stick\": [0, 1], \"gait\": \"fly\"}]}",
                  "in.json:2:37: keys[0].gait must be \"walk\", \"run\", \"crouch\" or \"jump\"");
    expect_script("{\"keys\": [{\"t\": 0, \"stick\": [0, 1]},\n {\"t\": 0, \"stick\": [0, 1], \"wind\": 1}]}",
                  "in.json:2:36: keys[1].wind: unknown field");
    expect_script("{\"keys\": [{\"t\": 0, \"stick\": [0, 1]}], \"extra\": 1}",
                  "in.json:1:48: extra: unknown field");
    mm_scene scene;
    mm_error err;
    memset(&err, 0, sizeof err);
    static const char sc[] = "{\"ground\": 0, \"ground\": 1}";
    assert_int_equal(mm_scene_parse_json(sc, sizeof sc - 1, "s.json", &scene, &err), MM_ERR_DUPLICATE_NAME);
    assert_int_equal(err.line, 1);
    assert_int_equal(err.column, 15);
}

/* 100,000 clips read (the readers are linear: a benchmark, bench_json, has the times), a name
 * repeated at the very end found, and the documented limit refused. */
static void test_large_config(void **state)
{
    (void)state;
    const int n = 100000;
    size_t cap = (size_t)n * 64 + 256, len = 0;
    char *text = malloc(cap);
    assert_non_null(text);
    len += (size_t)snprintf(text + len, cap - len, "{\"clips\": [\n");
    for (int i = 0; i < n; ++i)
        len += (size_t)snprintf(text + len, cap - len, "{\"name\": \"c%d\", \"file\": \"w.bvh\"}%s\n",
                                i == n - 1 ? 7 : i, i + 1 < n ? "," : "");
    len += (size_t)snprintf(text + len, cap - len, "]}");
    char got[600];
    config_error(text, got, sizeof got);
    assert_string_equal(got, "c.json:100001:10: clips[99999].name 'c7' is used twice");
    /* the same with every name different reads */
    char *last = strstr(text + len - 60, "\"c7\"");
    assert_non_null(last);
    memcpy(last, "\"zz\"", 4);
    mm_config cfg;
    memset(&cfg, 0, sizeof cfg);
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_config_parse_json(text, len, "c.json", NULL, &cfg, &err), MM_OK);
    assert_int_equal(cfg.clip_count, n);
    assert_string_equal(cfg.clips[n - 1].name, "zz");
    mm_config_free(&cfg);
    free(text);
    /* more clips than MM_CONFIG_MAX_CLIPS: refused before anything is allocated for them */
    cap = (size_t)(MM_CONFIG_MAX_CLIPS + 1) * 3 + 64;
    text = malloc(cap);
    assert_non_null(text);
    len = (size_t)snprintf(text, cap, "{\"clips\": [");
    for (int i = 0; i <= MM_CONFIG_MAX_CLIPS; ++i) {
        memcpy(text + len, i ? ",{}" : "{}", i ? 3 : 2);
        len += i ? 3 : 2;
    }
    len += (size_t)snprintf(text + len, cap - len, "]}");
    config_error(text, got, sizeof got);
    assert_string_equal(got, "c.json:1:11: clips: 1000001 clips (at most 1000000)");
    free(text);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_config_strict),  cmocka_unit_test(test_config_meaning_errors),
        cmocka_unit_test(test_config_extends), cmocka_unit_test(test_input_and_scene),
        cmocka_unit_test(test_large_config),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
