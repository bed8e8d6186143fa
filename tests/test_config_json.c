/* Database configs in JSON: every field read, every mistake reported with the field's path. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>

#include <mm/config_json.h>

#include "test_util.h"

static const char full[] =
    "{\n"
    "  \"interval\": 0.02, \"scale\": 0.01, \"root_smoothing\": 0.2,\n"
    "  \"roles\": {\"hips\": \"Pelvis\", \"root_bone\": \"Chest\", \"facing_bone\": \"Pelvis\",\n"
    "            \"forward_axis\": [0, 1, 0], \"left_foot\": \"LF\", \"right_foot\": \"RF\", \"left_toe\": "
    "\"LT\",\n"
    "            \"right_toe\": \"RT\", \"left_hand\": \"LH\", \"right_hand\": \"RH\", \"head\": \"H\"},\n"
    "  \"contacts\": {\"height\": 0.04, \"speed\": 0.5, \"min_time\": 0.05, \"planted_tolerance\": 0.015},\n"
    "  \"features\": {\"bones\": [{\"name\": \"LF\", \"position_weight\": 2, \"velocity_weight\": 0.5},\n"
    "                           {\"name\": \"Pelvis\", \"position\": false}],\n"
    "               \"trajectory_times\": [-0.33, 0.5, 1.0], \"root_velocity\": true,\n"
    "               \"body_velocity_weight\": 0.7, \"position_multiplier\": 1.1, \"angle_multiplier\": "
    "1.9},\n"
    "  \"mirror_pairs\": [[\"^l\", \"^r\"]],\n"
    "  \"tags\": [\"Required\", \"DoNotUse\"],\n"
    "  \"clips\": [\n"
    "    {\"file\": \"moves/walk.bvh\", \"ranges\": [[0, 100], [120, 300]], \"mirror\": true,\n"
    "     \"tags\": {\"DoNotUse\": [[1.5, 2.0], [3, 4]], \"Required\": [[0, 1]]}},\n"
    "    {\"name\": \"stand\", \"file\": \"/abs/idle.bvh\", \"type\": \"idle\", \"loop\": true}\n"
    "  ],\n"
    "  \"blend_clips\": [{\"name\": \"mix\", \"left\": \"walk\", \"right\": \"stand\", \"weight\": 0.3}]\n"
    "}\n";

static void test_every_field(void **state)
{
    (void)state;
    mm_config c;
    memset(&c, 0, sizeof c);
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_result r = mm_config_parse_json(full, sizeof full - 1, "full.json", "/cfg", &c, &err);
    if (r != MM_OK) print_error("%s\n", err.message);
    assert_int_equal(r, MM_OK);
    assert_near(c.interval, 0.02, 1e-8);
    assert_near(c.scale, 0.01, 1e-8);
    assert_near(c.root_smoothing, 0.2, 1e-7);
    assert_string_equal(c.hips, "Pelvis");
    assert_string_equal(c.root_bone, "Chest");
    assert_near(c.forward_axis.y, 1, 0);
    assert_string_equal(c.right_toe, "RT");
    assert_string_equal(c.head, "H");
    assert_near(c.contact_height, 0.04, 1e-8);
    assert_near(c.contact_min_time, 0.05, 1e-8);
    assert_near(c.contact_planted_tolerance, 0.015, 1e-8);
    assert_int_equal(c.bone_count, 2);
    assert_int_equal(c.bones[0].features, MM_MATCH_POSITION | MM_MATCH_VELOCITY);
    assert_near(c.bones[0].position_weight, 2, 0);
    assert_near(c.bones[0].velocity_weight, 0.5, 0);
    assert_int_equal(c.bones[1].features, MM_MATCH_VELOCITY);
    assert_int_equal(c.traj_count, 3);
    assert_near(c.traj_times[0], -0.33, 1e-7);
    assert_true(c.root_velocity);
    assert_near(c.angle_multiplier, 1.9, 1e-7);
    assert_int_equal(c.mirror_pair_count, 1);
    assert_string_equal(c.mirror_pairs[0].right, "^r");
    assert_int_equal(c.tag_count, 2);
    assert_int_equal(c.clip_count, 2);
    assert_string_equal(c.clips[0].name, "walk"); /* from the file name */
    assert_int_equal(c.clips[0].range_count, 2);
    assert_int_equal(c.clips[0].ranges[1].begin, 120);
    assert_true(c.clips[0].mirror);
    assert_int_equal(c.clips[0].tag_range_count, 3);
    int donotuse = 0;
    for (int i = 0; i < 3; ++i) donotuse += c.clips[0].tag_ranges[i].tag == 1;
    assert_int_equal(donotuse, 2);
    assert_int_equal(c.clips[1].type, MM_CLIP_IDLE);
    assert_true(c.clips[1].loop);
    assert_int_equal(c.blend_count, 1);
    assert_int_equal(c.blends[0].left, 0);
    assert_int_equal(c.blends[0].right, 1);
    assert_near(c.blends[0].weight, 0.3, 1e-7);
    assert_string_equal(c.base_dir, "/cfg");
    mm_config_free(&c);
}

/* Replaces the first occurrence of from in full by to, parses, and checks the error. */
static void expect_error(const char *from, const char *to, mm_result code, const char *message)
{
    char text[4096];
    const char *at = strstr(full, from);
    assert_non_null(at);
    snprintf(text, sizeof text, "%.*s%s%s", (int)(at - full), full, to, at + strlen(from));
    mm_config c;
    memset(&c, 0, sizeof c);
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_result r = mm_config_parse_json(text, strlen(text), "bad.json", NULL, &c, &err);
    if (r != code || !strstr(err.message, message))
        print_error("'%s' -> '%s': got %s '%s'\n", from, to, mm_result_name(r), err.message);
    assert_int_equal(r, code);
    assert_non_null(strstr(err.message, message));
    assert_string_equal(err.file, "bad.json");
    assert_null(c.clips); /* nothing left allocated */
}

static void test_errors_name_the_field(void **state)
{
    (void)state;
    expect_error("\"interval\": 0.02", "\"interval\": -1", MM_ERR_OUT_OF_RANGE, "interval");
    expect_error("\"interval\": 0.02", "\"interval\": \"fast\"", MM_ERR_BAD_NUMBER,
                 "interval must be a finite number");
    expect_error("\"interval\": 0.02", "\"interval\": 1e999", MM_ERR_BAD_NUMBER, "interval");
    expect_error("\"planted_tolerance\": 0.015", "\"planted_tolerance\": -0.01", MM_ERR_OUT_OF_RANGE,
                 "contacts.planted_tolerance");
    expect_error("\"interval\": 0.02", "\"intervall\": 0.02", MM_ERR_UNKNOWN_KEYWORD,
                 "intervall: unknown field");
    expect_error("\"hips\": \"Pelvis\"", "\"hip\": \"Pelvis\"", MM_ERR_UNKNOWN_KEYWORD,
                 "roles.hip: unknown field");
    expect_error("\"forward_axis\": [0, 1, 0]", "\"forward_axis\": [0, 1]", MM_ERR_SYNTAX,
                 "roles.forward_axis");
    expect_error("\"forward_axis\": [0, 1, 0]", "\"forward_axis\": [0, 0, 0]", MM_ERR_OUT_OF_RANGE,
                 "forward_axis");
    expect_error("\"height\": 0.04", "\"height\": 0", MM_ERR_OUT_OF_RANGE, "contacts.height");
    expect_error("\"position_weight\": 2", "\"position_weight\": -2", MM_ERR_OUT_OF_RANGE,
                 "features.bones[0]");
    expect_error("{\"name\": \"Pelvis\", \"position\": false}", "{\"position\": false}", MM_ERR_SYNTAX,
                 "features.bones[1].name is missing");
    expect_error("\"position\": false", "\"position\": false, \"velocity\": false", MM_ERR_OUT_OF_RANGE,
                 "features.bones[1] (Pelvis) has neither");
    expect_error("[-0.33, 0.5, 1.0]", "[-0.33, 0.5, 0.5]", MM_ERR_OUT_OF_RANGE,
                 "trajectory_times[2]: 0.5 s is listed twice");
    expect_error("[\"Required\", \"DoNotUse\"]", "[\"Required\", \"Required\"]", MM_ERR_DUPLICATE_NAME,
                 "tags[1]");
    expect_error("\"DoNotUse\": [[1.5, 2.0]", "\"DoNotUsed\": [[1.5, 2.0]", MM_ERR_NOT_FOUND,
                 "clips[0].tags.DoNotUsed: not declared");
    expect_error("[[1.5, 2.0], [3, 4]]", "[[1.5, 2.0], [4, 3]]", MM_ERR_OUT_OF_RANGE,
                 "clips[0] (walk).tags.DoNotUse[1]");
    expect_error("[[0, 100], [120, 300]]", "[[0, 100], [300, 120]]", MM_ERR_OUT_OF_RANGE,
                 "clips[0] (walk).ranges[1]");
    expect_error("[[0, 100], [120, 300]]", "[[0, 100], [120.5, 300]]", MM_ERR_BAD_NUMBER,
                 "clips[0].ranges[1] must be an integer");
    expect_error("\"type\": \"idle\"", "\"type\": \"sitting\"", MM_ERR_SYNTAX, "clips[1].type");
    expect_error("\"name\": \"stand\"", "\"name\": \"walk\"", MM_ERR_DUPLICATE_NAME,
                 "clips[1].name 'walk' is used twice");
    expect_error("\"file\": \"/abs/idle.bvh\", ", "", MM_ERR_SYNTAX, "clips[1].file is missing");
    expect_error("\"right\": \"stand\"", "\"right\": \"run\"", MM_ERR_NOT_FOUND,
                 "blend_clips[0].right: no clip named 'run'");
    expect_error("\"weight\": 0.3", "\"weight\": 1.5", MM_ERR_OUT_OF_RANGE, "blend_clips[0] (mix): weight");
    expect_error("\"loop\": true}", "\"loop\": true, \"ranges\": [[0, 5], [6, 9]]}", MM_ERR_OUT_OF_RANGE,
                 "a loop clip has one range");
}

static void test_json_syntax_errors(void **state)
{
    (void)state;
    mm_config c;
    memset(&c, 0, sizeof c);
    mm_error err;
    memset(&err, 0, sizeof err);
    const char broken[] = "{\n  \"interval\": 0.02,\n  \"scale\" 0.01\n}\n";
    assert_int_equal(mm_config_parse_json(broken, sizeof broken - 1, "broken.json", NULL, &c, &err),
                     MM_ERR_SYNTAX);
    assert_int_equal(err.line, 3);
    assert_true(err.column >= 10);
    assert_int_equal(mm_config_parse_json("", 0, "empty.json", NULL, &c, &err), MM_ERR_UNEXPECTED_EOF);
    assert_int_equal(mm_config_parse_json("[1, 2]", 6, "array.json", NULL, &c, &err), MM_ERR_SYNTAX);
    assert_non_null(strstr(err.message, "must be an object"));
    const char garbage[] = "\x01\xff\xfe{";
    assert_int_equal(mm_config_parse_json(garbage, 4, "garbage.json", NULL, &c, &err), MM_ERR_SYNTAX);
    assert_int_equal(mm_config_load_json("/nonexistent/c.json", &c, NULL, &err), MM_ERR_IO);
    assert_string_equal(err.file, "/nonexistent/c.json");
}

static void test_defaults(void **state)
{
    (void)state;
    mm_config c;
    memset(&c, 0, sizeof c);
    assert_int_equal(mm_config_parse_json("{}", 2, "empty.json", NULL, &c, NULL), MM_OK);
    assert_near(c.interval, 1.0 / 60.0, 1e-7);
    assert_int_equal(c.bone_count, 3);
    assert_int_equal(c.traj_count, 3);
    assert_string_equal(c.hips, "Hips");
    assert_int_equal(c.clip_count, 0);
    mm_config_free(&c);
}

/* An interval written to six digits is the whole frame rate it rounds (0.0166667 is 1/60, so that a
 * 60 Hz tick is exactly one frame); one that rounds none is read as written. */
static void test_interval_whole_rate(void **state)
{
    (void)state;
    static const struct {
        const char *text;
        float expect;
    } cases[] = {
        {"{\"interval\": 0.0166667}", 1.0f / 60.0f},   /* 1/60 to 6 digits: 2e-6 off */
        {"{\"interval\": 0.0333333}", 1.0f / 30.0f},   /* 1/30: 1e-6 off */
        {"{\"interval\": 0.00833333}", 1.0f / 120.0f}, /* 1/120: 4e-7 off */
        {"{\"interval\": 0.05}", 1.0f / 20.0f},
        {"{\"interval\": 0.0167}", 0.0167f}, /* 59.88 frames per second: 2e-3 off, kept */
        {"{\"interval\": 0.0123}", 0.0123f},
        {"{\"interval\": 0.7}", 0.7f},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        mm_config c;
        memset(&c, 0, sizeof c);
        assert_int_equal(mm_config_parse_json(cases[i].text, strlen(cases[i].text), "i.json", NULL, &c, NULL),
                         MM_OK);
        if (c.interval != cases[i].expect) print_error("%s: %.9g\n", cases[i].text, c.interval);
        assert_true(c.interval == cases[i].expect);
        mm_config_free(&c);
    }
}

/* Clip paths: the config's folder first, then $MM_DATA_DIR. */
static void test_resolve_paths(void **state)
{
    (void)state;
    mm_config c;
    mm_config_defaults(&c);
    snprintf(c.base_dir, sizeof c.base_dir, "%s", MM_TEST_DATA);
    char out[MM_PATH_MAX];
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_config_resolve_path(&c, "bvh/chain2.bvh", out, sizeof out, &err), MM_OK);
    assert_non_null(strstr(out, "tests/data/bvh/chain2.bvh"));
    snprintf(c.base_dir, sizeof c.base_dir, "/nonexistent");
    setenv("MM_DATA_DIR", MM_TEST_DATA, 1);
    assert_int_equal(mm_config_resolve_path(&c, "bvh/chain2.bvh", out, sizeof out, &err), MM_OK);
    unsetenv("MM_DATA_DIR");
    assert_int_equal(mm_config_resolve_path(&c, "bvh/chain2.bvh", out, sizeof out, &err), MM_ERR_NOT_FOUND);
    assert_non_null(strstr(err.message, "bvh/chain2.bvh"));
}

static void write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

/* "extends": the base's clips and tags first, this file's appended, objects merged field by
 * field, other fields replaced; the merged text reads without the base; cycles and missing bases
 * are errors naming the file; clips written into the extending file stay in it. */
static void test_extends(void **state)
{
    (void)state;
    char base[512], derived[512], a[512], b[512], missing[512];
    snprintf(base, sizeof base, "%s/extends_base.json", MM_TEST_OUT);
    snprintf(derived, sizeof derived, "%s/extends_derived.json", MM_TEST_OUT);
    snprintf(a, sizeof a, "%s/extends_a.json", MM_TEST_OUT);
    snprintf(b, sizeof b, "%s/extends_b.json", MM_TEST_OUT);
    snprintf(missing, sizeof missing, "%s/extends_missing.json", MM_TEST_OUT);
    write_text(
        base,
        "{\"interval\": 0.02, \"scale\": 0.01, \"roles\": {\"hips\": \"Pelvis\", \"head\": \"Skull\"},\n"
        " \"tags\": [\"DoNotUse\"],\n"
        " \"clips\": [{\"name\": \"walk\", \"file\": \"walk.bvh\", \"tags\": {\"DoNotUse\": [[1, 2]]}}]}\n");
    write_text(derived,
               "{\"extends\": \"extends_base.json\", \"interval\": 0.05, \"roles\": {\"head\": \"Head\"},\n"
               " \"tags\": [\"DoNotUse\", \"Jump\", \"TakeOff\"],\n"
               " \"clips\": [{\"name\": \"hop\", \"file\": \"hop.bvh\", \"ranges\": [[10, 40]],\n"
               "   \"tags\": {\"Jump\": [[0.5, 1.2]], \"TakeOff\": [[0.5, 0.5]]}}]}\n");
    mm_config c;
    memset(&c, 0, sizeof c);
    mm_error err;
    memset(&err, 0, sizeof err);
    char *text = NULL;
    assert_int_equal(mm_config_load_json(derived, &c, &text, &err), MM_OK);
    assert_int_equal(c.clip_count, 2);
    assert_string_equal(c.clips[0].name, "walk");
    assert_string_equal(c.clips[1].name, "hop");
    assert_float_equal(c.interval, 0.05f, 0); /* replaced */
    assert_float_equal(c.scale, 0.01f, 0);    /* from the base */
    assert_string_equal(c.hips, "Pelvis");    /* roles merged field by field */
    assert_string_equal(c.head, "Head");
    assert_int_equal(c.tag_count, 3); /* DoNotUse once */
    int jump = mm_config_tag_index(&c, "Jump"), take_off = mm_config_tag_index(&c, "TakeOff");
    assert_true(jump >= 0 && take_off >= 0);
    assert_int_equal(c.clips[1].tag_range_count, 2);
    for (int i = 0; i < 2; ++i) { /* a one-frame tag range [t, t] is accepted */
        const mm_config_tag_range *r = &c.clips[1].tag_ranges[i];
        if (r->tag == take_off) assert_float_equal(r->end, r->begin, 0);
    }
    assert_string_equal(c.clips[0].file, "walk.bvh");
    mm_config_free(&c);
    /* the text for a database is the merged config: it reads alone */
    assert_non_null(text);
    assert_null(strstr(text, "extends"));
    assert_int_equal(mm_config_parse_json(text, strlen(text), "embedded", NULL, &c, &err), MM_OK);
    assert_int_equal(c.clip_count, 2);
    assert_float_equal(c.interval, 0.05f, 0);
    mm_config_free(&c);
    free(text);

    /* clips written into the extending file land in it; writing again replaces, not duplicates */
    mm_config_named_range tags[2];
    memset(tags, 0, sizeof tags);
    snprintf(tags[0].tag, sizeof tags[0].tag, "Drop");
    tags[0].begin = 3.0f, tags[0].end = 3.5f;
    snprintf(tags[1].tag, sizeof tags[1].tag, "Landing");
    tags[1].begin = tags[1].end = 3.5f;
    mm_config_saved_clip sc = {.name = "drop_1",
                               .file = "drop.bvh",
                               .begin = 80,
                               .end = 120,
                               .type = MM_CLIP_LOCOMOTION,
                               .mirror = true,
                               .tags = tags,
                               .tag_count = 2};
    for (int pass = 0; pass < 2; ++pass) assert_int_equal(mm_config_save_clip(derived, &sc, &err), MM_OK);
    assert_int_equal(mm_config_load_json(derived, &c, NULL, &err), MM_OK);
    assert_int_equal(c.clip_count, 3);
    assert_string_equal(c.clips[2].name, "drop_1");
    assert_true(c.clips[2].mirror);
    assert_int_equal(c.clips[2].ranges[0].begin, 80);
    assert_int_equal(c.clips[2].tag_range_count, 2);
    assert_true(mm_config_tag_index(&c, "Drop") >= 0 && mm_config_tag_index(&c, "Landing") >= 0);
    mm_config_free(&c);
    /* several ranges (mm bvh spans --write): written in order, and whole frame numbers as integers */
    static const int spans[3][2] = {{0, 100}, {250, 300}, {1000, 1200}};
    mm_config_saved_clip multi = {
        .name = "standing", .file = "walk.bvh", .ranges = spans, .range_count = 3, .type = MM_CLIP_IDLE};
    assert_int_equal(mm_config_save_clip(derived, &multi, &err), MM_OK);
    assert_int_equal(mm_config_load_json(derived, &c, NULL, &err), MM_OK);
    assert_int_equal(c.clip_count, 4);
    assert_int_equal(c.clips[3].type, MM_CLIP_IDLE);
    assert_int_equal(c.clips[3].range_count, 3);
    for (int i = 0; i < 3; ++i) {
        assert_int_equal(c.clips[3].ranges[i].begin, spans[i][0]);
        assert_int_equal(c.clips[3].ranges[i].end, spans[i][1]);
    }
    mm_config_free(&c);
    char saved[4096] = {0};
    FILE *f = fopen(derived, "rb");
    assert_non_null(f);
    assert_true(fread(saved, 1, sizeof saved - 1, f) > 0);
    fclose(f);
    assert_non_null(strstr(saved, "[[0, 100], [250, 300], [1000, 1200]]")); /* not 1e+02 */
    multi.range_count = -1;
    assert_int_equal(mm_config_save_clip(derived, &multi, &err), MM_ERR_INVALID_ARGUMENT);
    sc.name = "walk"; /* the base's clip */
    assert_int_equal(mm_config_save_clip(derived, &sc, &err), MM_ERR_DUPLICATE_NAME);
    static const float range[1][2] = {{0.1f, 0.2f}};
    assert_int_equal(mm_config_save_clip_tags(derived, "walk", "DoNotUse", range, 1, &err),
                     MM_ERR_INVALID_ARGUMENT);
    assert_int_equal(mm_config_save_clip_tags(derived, "hop", "Jump", range, 1, &err), MM_OK);
    assert_int_equal(mm_config_load_json(derived, &c, NULL, &err), MM_OK);
    assert_float_equal(c.clips[1].tag_ranges[c.clips[1].tag_ranges[0].tag == jump ? 0 : 1].begin, 0.1f,
                       1e-6f);
    mm_config_free(&c);

    /* a cycle, a missing base */
    write_text(a, "{\"extends\": \"extends_b.json\", \"clips\": []}\n");
    write_text(b, "{\"extends\": \"extends_a.json\"}\n");
    assert_int_not_equal(mm_config_load_json(a, &c, NULL, &err), MM_OK);
    assert_non_null(strstr(err.message, "cycle"));
    write_text(missing, "{\"extends\": \"no_such_base.json\"}\n");
    assert_int_equal(mm_config_load_json(missing, &c, NULL, &err), MM_ERR_NOT_FOUND);
    assert_non_null(strstr(err.message, "no_such_base.json"));
    assert_non_null(strstr(err.file, "extends_missing.json"));
    write_text(missing, "{\"extends\": 3}\n");
    assert_int_equal(mm_config_load_json(missing, &c, NULL, &err), MM_ERR_SYNTAX);
    /* an error in the base names the base */
    write_text(base, "{\"intervall\": 0.02}\n");
    assert_int_equal(mm_config_load_json(derived, &c, NULL, &err), MM_ERR_UNKNOWN_KEYWORD);
    assert_int_equal(mm_config_load_json(base, &c, NULL, &err), MM_ERR_UNKNOWN_KEYWORD);
}

/* docs/config.md holds the same table that `mm config explain --markdown` prints. */
static void test_docs_in_sync(void **state)
{
    (void)state;
    FILE *f = fopen(MM_TEST_DATA "/../../docs/config.md", "rb");
    assert_non_null(f);
    static char doc[1 << 16];
    size_t n = fread(doc, 1, sizeof doc - 1, f);
    fclose(f);
    doc[n] = 0;
    int count = 0;
    const mm_config_field_doc *d = mm_config_field_docs(&count);
    assert_true(count > 30);
    for (int i = 0; i < count; ++i) {
        char row[2048];
        snprintf(row, sizeof row, "| `%s` | %s | %s | %s | %s |", d[i].path, d[i].type, d[i].unit,
                 d[i].fallback, d[i].help);
        if (!strstr(doc, row)) print_error("docs/config.md lacks the row: %s\n", row);
        assert_non_null(strstr(doc, row));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_field),         cmocka_unit_test(test_errors_name_the_field),
        cmocka_unit_test(test_json_syntax_errors),  cmocka_unit_test(test_defaults),
        cmocka_unit_test(test_interval_whole_rate), cmocka_unit_test(test_resolve_paths),
        cmocka_unit_test(test_docs_in_sync),        cmocka_unit_test(test_extends),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
