/* The runtime tuning a config carries: the `runtime` object read and checked, applied to a
 * character (exactly the defaults when nothing is set), and saved back into a config file with
 * the feature weights and clip tags, everything else kept. */
#define _POSIX_C_SOURCE 200809L
#include <cjson/cJSON.h>
#include <math.h>

#include <mm/character_config.h>
#include <mm/character.h>
#include <mm/config_json.h>
#include <mm/input.h>

#include "test_databases.h"
#include "test_util.h"

static mm_database db;
static mm_searcher searcher;

/* ---- helpers ---------------------------------------------------------------------------- */

static const char *out_path(const char *name)
{
    static char buf[4][1024];
    static int next;
    char *p = buf[next++ % 4];
    snprintf(p, 1024, "%s/%s", MM_TEST_OUT, name);
    return p;
}

static void write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(text, 1, strlen(text), f), strlen(text));
    assert_int_equal(fclose(f), 0);
}

static char *read_text(const char *path)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *text = (char *)malloc((size_t)n + 1);
    assert_non_null(text);
    assert_int_equal(fread(text, 1, (size_t)n, f), (size_t)n);
    text[n] = 0;
    fclose(f);
    return text;
}

static void load(const char *path, mm_config *cfg)
{
    mm_error err;
    memset(&err, 0, sizeof err);
    memset(cfg, 0, sizeof *cfg);
    mm_result r = mm_config_load_json(path, cfg, NULL, &err);
    if (r != MM_OK) print_error("%s: %s\n", err.file, err.message);
    assert_int_equal(r, MM_OK);
}

/* The config the test database was built from, as a file of its own. */
static const char *synth_config_copy(const char *name)
{
    const char *path = out_path(name);
    write_text(path, db.config_json);
    return path;
}

static mm_result parse(const char *text, mm_config *cfg, mm_error *err)
{
    memset(cfg, 0, sizeof *cfg);
    memset(err, 0, sizeof *err);
    return mm_config_parse_json(text, strlen(text), "rt.json", NULL, cfg, err);
}

/* ---- the runtime object ----------------------------------------------------------------- */

static void test_parse_runtime(void **state)
{
    (void)state;
    mm_config c;
    mm_error err;
    const char *text = "{\"runtime\": {\"pose_trajectory_ratio\": 0.7, \"next_pose_favour\": 0.5,\n"
                       "  \"loop_anim_favour\": 0.9, \"continuing_bias\": 0.01, \"search_interval\": 0.05,\n"
                       "  \"transition_halflife\": 0.15, \"idle_speed\": 0.2, \"sync_halflife\": 0.5,\n"
                       "  \"distance_matching\": true, \"warping\": false,\n"
                       "  \"walk\": {\"forward_speed\": 1.4, \"side_speed\": 1, \"backward_speed\": 0.9,\n"
                       "           \"velocity_halflife\": 0.2, \"rotation_halflife\": 0.3},\n"
                       "  \"run\": {\"forward_speed\": 3.5}, \"crouch\": {\"rotation_halflife\": 0.4}}}";
    assert_int_equal(parse(text, &c, &err), MM_OK);
    const mm_runtime_config *rt = &c.runtime;
    assert_int_equal(rt->set, 0x3ff);
    assert_true(rt->distance_matching && !rt->warping);
    assert_true(rt->pose_trajectory_ratio == 0.7f && rt->next_pose_favour == 0.5f);
    assert_true(rt->loop_anim_favour == 0.9f && rt->continuing_bias == 0.01f);
    assert_true(rt->search_interval == 0.05f && rt->transition_halflife == 0.15f && rt->idle_speed == 0.2f);
    assert_true(rt->sync_halflife == 0.5f);
    assert_int_equal(rt->walk.set, 0x1f);
    assert_true(rt->walk.forward_speed == 1.4f && rt->walk.side_speed == 1.0f);
    assert_true(rt->walk.backward_speed == 0.9f && rt->walk.velocity_halflife == 0.2f);
    assert_true(rt->walk.rotation_halflife == 0.3f);
    assert_int_equal(rt->run.set, MM_RUNTIME_FORWARD_SPEED);
    assert_true(rt->run.forward_speed == 3.5f);
    assert_int_equal(rt->crouch.set, MM_RUNTIME_ROTATION_HALFLIFE);
    mm_config_free(&c);

    /* without it nothing is set */
    assert_int_equal(parse("{}", &c, &err), MM_OK);
    assert_int_equal(c.runtime.set | c.runtime.walk.set | c.runtime.run.set | c.runtime.crouch.set, 0);
    mm_config_free(&c);

    /* mistakes name the field */
    static const struct {
        const char *text, *message;
        mm_result code;
    } bad[] = {
        {"{\"runtime\": {\"ratio\": 1}}", "runtime.ratio: unknown field", MM_ERR_UNKNOWN_KEYWORD},
        {"{\"runtime\": {\"walk\": {\"speed\": 1}}}", "runtime.walk.speed: unknown field",
         MM_ERR_UNKNOWN_KEYWORD},
        {"{\"runtime\": 3}", "runtime must be an object", MM_ERR_SYNTAX},
        {"{\"runtime\": {\"run\": []}}", "runtime.run must be an object", MM_ERR_SYNTAX},
        {"{\"runtime\": {\"idle_speed\": \"x\"}}", "runtime.idle_speed must be a finite number",
         MM_ERR_BAD_NUMBER},
        {"{\"runtime\": {\"warping\": 1}}", "runtime.warping must be true or false", MM_ERR_SYNTAX},
        {"{\"runtime\": {\"pose_trajectory_ratio\": 1.5}}", "runtime.pose_trajectory_ratio",
         MM_ERR_OUT_OF_RANGE},
        {"{\"runtime\": {\"pose_trajectory_ratio\": -0.1}}", "runtime.pose_trajectory_ratio",
         MM_ERR_OUT_OF_RANGE},
        {"{\"runtime\": {\"next_pose_favour\": 0}}", "runtime.next_pose_favour", MM_ERR_OUT_OF_RANGE},
        {"{\"runtime\": {\"loop_anim_favour\": -1}}", "runtime.loop_anim_favour", MM_ERR_OUT_OF_RANGE},
        {"{\"runtime\": {\"continuing_bias\": -1}}", "runtime.continuing_bias", MM_ERR_OUT_OF_RANGE},
        {"{\"runtime\": {\"contact_favour\": 0.9}}", "runtime.contact_favour: 0.9 must be at least 1",
         MM_ERR_OUT_OF_RANGE},
        {"{\"runtime\": {\"search_interval\": 0}}", "runtime.search_interval", MM_ERR_OUT_OF_RANGE},
        {"{\"runtime\": {\"transition_halflife\": 0}}", "runtime.transition_halflife", MM_ERR_OUT_OF_RANGE},
        {"{\"runtime\": {\"idle_speed\": -0.1}}", "runtime.idle_speed", MM_ERR_OUT_OF_RANGE},
        {"{\"runtime\": {\"sync_halflife\": -0.1}}",
         "runtime.sync_halflife: -0.1 s is out of range (0 to 60 s)", MM_ERR_OUT_OF_RANGE},
        {"{\"runtime\": {\"sync_halflife\": 61}}", "runtime.sync_halflife: 61 s is out of range",
         MM_ERR_OUT_OF_RANGE},
        {"{\"runtime\": {\"sync_halflife\": true}}", "runtime.sync_halflife must be a finite number",
         MM_ERR_BAD_NUMBER},
        {"{\"runtime\": {\"run\": {\"side_speed\": -1}}}", "runtime.run.side_speed", MM_ERR_OUT_OF_RANGE},
        {"{\"runtime\": {\"crouch\": {\"velocity_halflife\": 0}}}", "runtime.crouch.velocity_halflife",
         MM_ERR_OUT_OF_RANGE},
        {"{\"runtime\": {\"walk\": {\"rotation_halflife\": -2}}}", "runtime.walk.rotation_halflife",
         MM_ERR_OUT_OF_RANGE},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        mm_result r = parse(bad[i].text, &c, &err);
        if (r != bad[i].code || !strstr(err.message, bad[i].message))
            print_error("%s: got %s '%s'\n", bad[i].text, mm_result_name(r), err.message);
        assert_int_equal(r, bad[i].code);
        assert_non_null(strstr(err.message, bad[i].message));
        assert_string_equal(err.file, "rt.json");
    }
    /* speeds of 0 are allowed, and a sync half-life of 0 (the root on the simulation) */
    assert_int_equal(parse("{\"runtime\": {\"idle_speed\": 0, \"walk\": {\"side_speed\": 0}}}", &c, &err),
                     MM_OK);
    mm_config_free(&c);
    assert_int_equal(parse("{\"runtime\": {\"sync_halflife\": 0}}", &c, &err), MM_OK);
    assert_true(c.runtime.set == MM_RUNTIME_SYNC_HALFLIFE && c.runtime.sync_halflife == 0.0f);
    mm_config_free(&c);
}

/* `mm config explain runtime` lists every field. */
static void test_docs_list_runtime(void **state)
{
    (void)state;
    static const char *const fields[] = {"runtime.pose_trajectory_ratio",
                                         "runtime.next_pose_favour",
                                         "runtime.loop_anim_favour",
                                         "runtime.continuing_bias",
                                         "runtime.search_interval",
                                         "runtime.transition_halflife",
                                         "runtime.idle_speed",
                                         "runtime.sync_halflife",
                                         "runtime.walk.forward_speed",
                                         "runtime.run.side_speed",
                                         "runtime.crouch.backward_speed",
                                         "runtime.walk.velocity_halflife",
                                         "runtime.crouch.rotation_halflife"};
    int n = 0;
    const mm_config_field_doc *d = mm_config_field_docs(&n);
    for (size_t f = 0; f < sizeof fields / sizeof fields[0]; ++f) {
        int found = 0;
        for (int i = 0; i < n; ++i) found |= strcmp(d[i].path, fields[f]) == 0;
        if (!found) print_error("no doc for %s\n", fields[f]);
        assert_true(found);
    }
}

/* ---- applying it ------------------------------------------------------------------------ */

/* Walk, turn, run, crouch, strafe and stop in 10 s. */
static void scripted_input(mm_input_script *s)
{
    assert_int_equal(mm_input_script_init(s, 7, NULL), MM_OK);
    const float t[7] = {0.0f, 1.0f, 3.0f, 5.0f, 7.0f, 8.5f, 9.5f};
    const float sx[7] = {0.0f, 0.0f, 0.8f, 0.0f, -0.6f, 1.0f, 0.0f};
    const float sz[7] = {0.0f, 1.0f, 0.6f, 1.0f, 0.8f, 0.0f, 0.0f};
    const mm_gait g[7] = {MM_GAIT_WALK,   MM_GAIT_WALK, MM_GAIT_WALK, MM_GAIT_RUN,
                          MM_GAIT_CROUCH, MM_GAIT_WALK, MM_GAIT_WALK};
    for (int i = 0; i < 7; ++i) {
        s->keys[i].t = t[i];
        s->keys[i].input.stick[0] = sx[i];
        s->keys[i].input.stick[1] = sz[i];
        s->keys[i].input.gait = g[i];
        s->keys[i].input.strafe = i == 5;
        s->keys[i].input.has_facing = i == 5;
        s->keys[i].input.facing[1] = 1.0f;
    }
    assert_int_equal(mm_input_script_validate(s, NULL), MM_OK);
}

/* Runs 600 ticks of the script with desc (NULL: defaults) into poses [600 x joint_count]. */
static void simulate(const mm_character_desc *desc, mm_xform *poses, int *transitions)
{
    mm_input_script script;
    scripted_input(&script);
    mm_character c;
    assert_int_equal(mm_character_init(&c, &db, &searcher, desc, NULL), MM_OK);
    for (int i = 0; i < 600; ++i) {
        mm_input in;
        mm_input_script_sample(&script, (float)i / 60.0f, &in);
        mm_character_update(&c, &in, 1.0f / 60.0f);
        memcpy(poses + (size_t)i * (size_t)db.joint_count, c.global,
               sizeof(mm_xform) * (size_t)db.joint_count);
    }
    if (transitions) *transitions = c.transitions;
    mm_character_free(&c);
    mm_input_script_free(&script);
}

static void desc_from_text(const char *text, mm_character_desc *d)
{
    mm_config cfg;
    mm_error err;
    mm_result r = parse(text, &cfg, &err);
    if (r != MM_OK) print_error("%s\n", err.message);
    assert_int_equal(r, MM_OK);
    mm_character_defaults(d);
    mm_character_desc_apply_config(d, &db, &cfg);
    mm_config_free(&cfg);
}

/* The database's config with its runtime object taken out (configs/synth.json carries one):
 * a config that sets nothing at run time. Free with free(). */
static char *config_without_runtime(const char *text)
{
    cJSON *root = cJSON_Parse(text);
    assert_non_null(root);
    cJSON_DeleteItemFromObjectCaseSensitive(root, "runtime");
    char *out = cJSON_PrintUnformatted(root);
    assert_non_null(out);
    cJSON_Delete(root);
    return out;
}

/* With the database's own config and no runtime object, the character is bit for bit the
 * default one; a set field changes what it does. */
static void test_apply_defaults_bit_identical(void **state)
{
    (void)state;
    size_t n = 600 * (size_t)db.joint_count;
    mm_xform *a = (mm_xform *)calloc(n, sizeof(mm_xform)), *b = (mm_xform *)calloc(n, sizeof(mm_xform));
    assert_non_null(a);
    assert_non_null(b);
    int ta = 0, tb = 0;
    /* the runtime's defaults with the speed envelope the build measured (a config applies it unless
     * runtime.speed_envelope is false) */
    mm_character_desc enveloped;
    mm_character_defaults(&enveloped);
    enveloped.trajectory.bounded = true;
    for (int g = 0; g < MM_GAIT_COUNT; ++g)
        memcpy(enveloped.trajectory.envelopes[g].speeds, db.settings->envelope[g],
               sizeof enveloped.trajectory.envelopes[g].speeds);
    simulate(&enveloped, a, &ta);

    mm_character_desc d;
    char *no_runtime = config_without_runtime(db.config_json);
    desc_from_text(no_runtime, &d);
    cJSON_free(no_runtime);
    mm_character_desc run;
    mm_character_desc_resolve(&db, &d, &run);
    mm_search_params p;
    mm_character_default_params(&db, &p);
    assert_memory_equal(&p, &run.params, sizeof p);
    mm_trajectory_desc t;
    mm_trajectory_defaults(&t);
    t.bounded = true;
    memcpy(t.envelopes, enveloped.trajectory.envelopes, sizeof t.envelopes);
    assert_memory_equal(&t, &run.trajectory, sizeof t);
    simulate(&d, b, &tb);
    assert_int_equal(ta, tb);
    assert_memory_equal(a, b, n * sizeof(mm_xform));

    /* the defaults written out: the same */
    d = enveloped;
    mm_character_desc_apply_config(&d, &db, NULL);
    simulate(&d, b, NULL);
    assert_memory_equal(a, b, n * sizeof(mm_xform));
    /* the envelope off: the runtime's defaults alone (a character made without a database's settings) */
    desc_from_text("{\"runtime\": {\"speed_envelope\": false}}", &d);
    assert_false(d.trajectory.bounded);
    simulate(&d, b, NULL);
    int tn = 0;
    mm_xform *c = (mm_xform *)calloc(n, sizeof(mm_xform));
    assert_non_null(c);
    simulate(NULL, c, &tn);
    assert_memory_equal(c, b, n * sizeof(mm_xform));
    free(c);

    /* a walk speed of its own changes the motion */
    desc_from_text("{\"runtime\": {\"walk\": {\"forward_speed\": 0.9}}}", &d);
    assert_true(d.trajectory.gaits[MM_GAIT_WALK].forward_speed == 0.9f);
    assert_true(d.trajectory.gaits[MM_GAIT_RUN].forward_speed == t.gaits[MM_GAIT_RUN].forward_speed);
    simulate(&d, b, NULL);
    assert_true(memcmp(a, b, n * sizeof(mm_xform)) != 0);

    /* so does a search parameter: a strong next-pose favour keeps playing, with fewer jumps */
    desc_from_text("{\"runtime\": {\"next_pose_favour\": 0.05, \"search_interval\": 0.2}}", &d);
    assert_true(d.params.next_pose_favour == 0.05f && d.search_interval == 0.2f);
    simulate(&d, b, &tb);
    assert_true(memcmp(a, b, n * sizeof(mm_xform)) != 0);
    assert_true(tb < ta);
    /* and the contact favour: off (1; on, 2, by default), the run differs from the default's */
    desc_from_text("{\"runtime\": {\"contact_favour\": 1}}", &d);
    assert_true(d.params.contact_mismatch_favour == 1.0f);
    simulate(&d, b, NULL);
    assert_true(memcmp(a, b, n * sizeof(mm_xform)) != 0);
    free(a);
    free(b);
}

/* ---- saving tuning ---------------------------------------------------------------------- */

/* Everything but the runtime tuning and the feature weights is the same in both configs. */
static void assert_same_except_tuning(const mm_config *a, const mm_config *b)
{
    assert_true(a->interval == b->interval && a->scale == b->scale && a->root_smoothing == b->root_smoothing);
    assert_string_equal(a->hips, b->hips);
    assert_string_equal(a->root_bone, b->root_bone);
    assert_string_equal(a->facing_bone, b->facing_bone);
    assert_memory_equal(&a->forward_axis, &b->forward_axis, sizeof a->forward_axis);
    assert_string_equal(a->left_toe, b->left_toe);
    assert_string_equal(a->head, b->head);
    assert_true(a->contact_height == b->contact_height && a->contact_speed == b->contact_speed);
    assert_int_equal(a->bone_count, b->bone_count);
    for (int i = 0; i < a->bone_count; ++i) {
        assert_string_equal(a->bones[i].name, b->bones[i].name);
        assert_int_equal(a->bones[i].features, b->bones[i].features);
    }
    assert_int_equal(a->traj_count, b->traj_count);
    assert_memory_equal(a->traj_times, b->traj_times, sizeof(float) * (size_t)a->traj_count);
    assert_int_equal(a->root_velocity, b->root_velocity);
    assert_memory_equal(a->mirror_pairs, b->mirror_pairs, sizeof a->mirror_pairs);
    assert_int_equal(a->tag_count, b->tag_count);
    assert_memory_equal(a->tag_names, b->tag_names, sizeof a->tag_names);
    assert_int_equal(a->clip_count, b->clip_count);
    for (int i = 0; i < a->clip_count; ++i) {
        const mm_config_clip *x = &a->clips[i], *y = &b->clips[i];
        assert_string_equal(x->name, y->name);
        assert_string_equal(x->file, y->file);
        assert_string_equal(x->take, y->take);
        assert_true(x->type == y->type && x->loop == y->loop && x->mirror == y->mirror);
        assert_int_equal(x->range_count, y->range_count);
        if (x->range_count)
            assert_memory_equal(x->ranges, y->ranges, sizeof(mm_config_range) * (size_t)x->range_count);
        assert_int_equal(x->tag_range_count, y->tag_range_count);
        if (x->tag_range_count)
            assert_memory_equal(x->tag_ranges, y->tag_ranges,
                                sizeof(mm_config_tag_range) * (size_t)x->tag_range_count);
    }
    assert_int_equal(a->blend_count, b->blend_count);
    if (a->blend_count)
        assert_memory_equal(a->blends, b->blends, sizeof(mm_config_blend) * (size_t)a->blend_count);
}

static void test_save_tuning_round_trip(void **state)
{
    (void)state;
    const char *path = synth_config_copy("tune.json");
    mm_config before;
    load(path, &before);

    mm_character_desc d;
    mm_character_defaults(&d);
    mm_character_desc_apply_config(&d, &db, &before);
    d.params.pose_trajectory_ratio = 0.65f;
    d.params.next_pose_favour = 0.45f;
    d.params.loop_anim_favour = 0.9f;
    d.params.continuing_bias = 0.02f;
    d.params.contact_mismatch_favour = 1.75f;
    d.params.joint_position_weights[0] = 1.25f; /* LeftFoot */
    d.params.joint_velocity_weights[2] = 0.3f;  /* Hips */
    d.params.position_multiplier = 1.1f;
    d.params.angle_multiplier = 2.0f;
    d.search_interval = 0.08f;
    d.transition_halflife = 0.12f;
    d.idle_speed = 0.25f;
    d.sync_halflife = 0.45f;
    d.distance_matching = true;
    d.trajectory.gaits[MM_GAIT_WALK].forward_speed = 1.3f;
    d.trajectory.gaits[MM_GAIT_RUN].side_speed = 2.1f;
    d.trajectory.gaits[MM_GAIT_CROUCH].rotation_halflife = 0.35f;
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_result r = mm_config_save_tuning(path, &db, &d, &err);
    if (r != MM_OK) print_error("%s: %s\n", err.file, err.message);
    assert_int_equal(r, MM_OK);

    mm_config after;
    load(path, &after);
    assert_same_except_tuning(&before, &after);
    const mm_runtime_config *rt = &after.runtime;
    assert_int_equal(rt->set, MM_RUNTIME_FIELDS_ALL);
    assert_true(rt->contact_favour == 1.75f);
    assert_true(rt->distance_matching && !rt->warping);
    assert_int_equal(rt->walk.set & rt->run.set & rt->crouch.set, 0x1f);
    assert_true(rt->pose_trajectory_ratio == 0.65f && rt->next_pose_favour == 0.45f);
    assert_true(rt->loop_anim_favour == 0.9f && rt->continuing_bias == 0.02f);
    assert_true(rt->search_interval == 0.08f && rt->transition_halflife == 0.12f && rt->idle_speed == 0.25f);
    assert_true(rt->sync_halflife == 0.45f);
    assert_true(rt->walk.forward_speed == 1.3f && rt->run.side_speed == 2.1f);
    /* a field not tuned keeps its value: synth.json's walk.side_speed */
    assert_true(rt->crouch.rotation_halflife == 0.35f && rt->walk.side_speed == 0.5f);
    assert_string_equal(after.bones[0].name, "LeftFoot");
    assert_true(after.bones[0].position_weight == 1.25f && after.bones[0].velocity_weight == 1.0f);
    assert_string_equal(after.bones[2].name, "Hips");
    assert_true(after.bones[2].velocity_weight == 0.3f);
    assert_true(after.position_multiplier == 1.1f && after.angle_multiplier == 2.0f);
    assert_true(after.body_velocity_weight == before.body_velocity_weight); /* no root velocity group */

    /* applied to a fresh desc it gives back the tuned desc */
    mm_character_desc e;
    mm_character_defaults(&e);
    mm_character_desc_apply_config(&e, &db, &after);
    assert_memory_equal(&e.params, &d.params, sizeof d.params);
    assert_memory_equal(&e.trajectory, &d.trajectory, sizeof d.trajectory);
    assert_true(e.search_interval == d.search_interval && e.transition_halflife == d.transition_halflife &&
                e.idle_speed == d.idle_speed);

    /* numbers are written short, and saving again changes nothing */
    char *text = read_text(path);
    assert_non_null(strstr(text, "\"next_pose_favour\": 0.45"));
    assert_non_null(strstr(text, "\"trajectory_times\": [0.3333333, 0.6666667, 1]"));
    assert_int_equal(mm_config_save_tuning(path, &db, &e, &err), MM_OK);
    char *again = read_text(path);
    assert_string_equal(text, again);
    free(text);
    free(again);
    mm_config_free(&before);
    mm_config_free(&after);
}

/* A config without features.bones (the defaults) gets them written out, with the weights. */
static void test_save_tuning_default_bones(void **state)
{
    (void)state;
    const char *path = out_path("tune_defaults.json");
    write_text(path, "{\"scale\": 1, \"clips\": [{\"file\": \"a.bvh\"}]}\n");
    mm_character_desc d;
    mm_character_defaults(&d); /* params zero: the default params */
    d.transition_halflife = 0.3f;
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_config_save_tuning(path, &db, &d, &err), MM_OK);
    mm_config c;
    load(path, &c);
    assert_int_equal(c.bone_count, 3);
    assert_string_equal(c.bones[2].name, "Hips");
    assert_int_equal(c.bones[2].features, MM_MATCH_VELOCITY);
    assert_true(c.bones[0].position_weight == 0.75f);
    assert_true(c.scale == 1.0f && c.clip_count == 1);
    assert_string_equal(c.clips[0].file, "a.bvh");
    assert_true(c.runtime.transition_halflife == 0.3f && c.runtime.next_pose_favour == 0.6f);
    assert_true(c.runtime.pose_trajectory_ratio == 0.5f && c.runtime.run.forward_speed == 4.0f);
    mm_config_free(&c);
}

static void test_save_errors(void **state)
{
    (void)state;
    mm_character_desc d;
    mm_character_defaults(&d);
    mm_error err;
    memset(&err, 0, sizeof err);
    const char *missing = out_path("no_such_config.json");
    remove(missing);
    assert_int_equal(mm_config_save_tuning(missing, &db, &d, &err), MM_ERR_IO);
    assert_string_equal(err.file, missing);
    const float range[1][2] = {{0.0f, 1.0f}};
    assert_int_equal(mm_config_save_clip_tags(missing, "a", "T", range, 1, &err), MM_ERR_IO);
    assert_string_equal(err.file, missing);

    const char *bad = out_path("malformed.json");
    const char *text = "{\"scale\": 1,\n \"clips\": [}\n";
    write_text(bad, text);
    assert_int_equal(mm_config_save_tuning(bad, &db, &d, &err), MM_ERR_SYNTAX);
    assert_string_equal(err.file, bad);
    assert_int_equal(err.line, 2);
    assert_int_equal(mm_config_save_clip_tags(bad, "a", "T", range, 1, &err), MM_ERR_SYNTAX);
    char *kept = read_text(bad);
    assert_string_equal(kept, text);
    free(kept);

    /* a value out of range is refused, and the file stays as it was */
    const char *path = out_path("refused.json");
    write_text(path, "{\"clips\": [{\"file\": \"a.bvh\"}]}");
    d.transition_halflife = -1.0f;
    assert_int_equal(mm_config_save_tuning(path, &db, &d, &err), MM_ERR_OUT_OF_RANGE);
    assert_non_null(strstr(err.message, "runtime.transition_halflife"));
    assert_string_equal(err.file, path);
    kept = read_text(path);
    assert_string_equal(kept, "{\"clips\": [{\"file\": \"a.bvh\"}]}");
    free(kept);

    assert_int_equal(mm_config_save_clip_tags(path, "nope", "T", range, 1, &err), MM_ERR_NOT_FOUND);
    assert_non_null(strstr(err.message, "nope"));
    assert_string_equal(err.file, path);
    const float backwards[1][2] = {{2.0f, 1.0f}};
    assert_int_equal(mm_config_save_clip_tags(path, "a", "T", backwards, 1, &err), MM_ERR_OUT_OF_RANGE);
    assert_int_equal(mm_config_save_clip_tags(path, "a", "", range, 1, &err), MM_ERR_INVALID_ARGUMENT);
    kept = read_text(path);
    assert_string_equal(kept, "{\"clips\": [{\"file\": \"a.bvh\"}]}");
    free(kept);
}

/* ---- saving clip tags ------------------------------------------------------------------- */

static int tag_ranges(const mm_config *c, int clip, const char *tag, float (*out)[2])
{
    int t = mm_config_tag_index(c, tag), n = 0;
    for (int i = 0; t >= 0 && i < c->clips[clip].tag_range_count; ++i)
        if (c->clips[clip].tag_ranges[i].tag == t) {
            out[n][0] = c->clips[clip].tag_ranges[i].begin;
            out[n][1] = c->clips[clip].tag_ranges[i].end;
            ++n;
        }
    return n;
}

static void test_save_clip_tags(void **state)
{
    (void)state;
    const char *path = synth_config_copy("tags.json");
    mm_config before;
    load(path, &before);
    int walk = -1, other = -1;
    for (int i = 0; i < before.clip_count; ++i) {
        if (strcmp(before.clips[i].name, "walk_1.05") == 0) walk = i;
        if (other < 0 && i != walk && before.clips[i].tag_range_count > 0 &&
            strcmp(before.clips[i].name, "walk_1.05"))
            other = i;
    }
    assert_true(walk >= 0 && other >= 0);
    float old_other[64][2];
    int old_other_n = before.clips[other].tag_range_count;
    assert_true(old_other_n <= 64);
    for (int i = 0; i < old_other_n; ++i) {
        old_other[i][0] = before.clips[other].tag_ranges[i].begin;
        old_other[i][1] = before.clips[other].tag_ranges[i].end;
    }

    /* replace an existing tag's ranges */
    const float walk_ranges[2][2] = {{0.5f, 2.25f}, {3.0f, 8.1f}};
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_result r = mm_config_save_clip_tags(path, "walk_1.05", "Walk", walk_ranges, 2, &err);
    if (r != MM_OK) print_error("%s: %s\n", err.file, err.message);
    assert_int_equal(r, MM_OK);
    mm_config c;
    load(path, &c);
    float got[64][2];
    assert_int_equal(tag_ranges(&c, walk, "Walk", got), 2);
    assert_memory_equal(got, walk_ranges, sizeof walk_ranges);
    assert_int_equal(c.tag_count, before.tag_count);
    assert_int_equal(c.clips[other].tag_range_count, old_other_n);
    for (int i = 0; i < old_other_n; ++i)
        assert_true(c.clips[other].tag_ranges[i].begin == old_other[i][0] &&
                    c.clips[other].tag_ranges[i].end == old_other[i][1]);
    mm_config_free(&c);

    /* a new tag is declared */
    const float stop[1][2] = {{1.0f, 1.5f}};
    assert_int_equal(mm_config_save_clip_tags(path, "walk_1.05", "Stop", stop, 1, &err), MM_OK);
    load(path, &c);
    assert_int_equal(c.tag_count, before.tag_count + 1);
    assert_string_equal(c.tag_names[before.tag_count], "Stop");
    assert_int_equal(tag_ranges(&c, walk, "Stop", got), 1);
    assert_true(got[0][0] == 1.0f && got[0][1] == 1.5f);
    assert_int_equal(tag_ranges(&c, walk, "Walk", got), 2);
    mm_config_free(&c);

    /* no ranges: the tag leaves the clip (the name stays declared) */
    assert_int_equal(mm_config_save_clip_tags(path, "walk_1.05", "Walk", NULL, 0, &err), MM_OK);
    assert_int_equal(mm_config_save_clip_tags(path, "walk_1.05", "Stop", NULL, 0, &err), MM_OK);
    load(path, &c);
    assert_int_equal(tag_ranges(&c, walk, "Walk", got), 0);
    assert_int_equal(c.clips[walk].tag_range_count, 0);
    assert_int_equal(c.tag_count, before.tag_count + 1);
    mm_config_free(&c);

    /* put back as it was: the config equals the original in everything but the new tag name */
    float orig[64][2];
    int orig_n = tag_ranges(&before, walk, "Walk", orig);
    assert_int_equal(
        mm_config_save_clip_tags(path, "walk_1.05", "Walk", (const float(*)[2])orig, orig_n, &err), MM_OK);
    load(path, &c);
    assert_int_equal(c.tag_count, before.tag_count + 1);
    c.tag_count = before.tag_count;
    memset(c.tag_names[before.tag_count], 0, MM_TAG_NAME_MAX);
    assert_same_except_tuning(&before, &c);
    assert_int_equal(c.runtime.set, before.runtime.set); /* the runtime block is kept as it was */
    assert_true(c.runtime.sync_halflife == before.runtime.sync_halflife);
    mm_config_free(&c);

    /* a clip named after its file, and a config without tags at all */
    const char *plain = out_path("tags_plain.json");
    write_text(plain, "{\"clips\": [{\"file\": \"moves/jog.fast.bvh\"}]}");
    assert_int_equal(mm_config_save_clip_tags(plain, "jog", "Run", stop, 1, &err), MM_OK);
    load(plain, &c);
    assert_int_equal(c.tag_count, 1);
    assert_int_equal(tag_ranges(&c, 0, "Run", got), 1);
    assert_string_equal(c.clips[0].name, "jog");
    mm_config_free(&c);
    mm_config_free(&before);
}

static int setup(void **state)
{
    (void)state;
    if (test_build_synth_database(&db) != 0) return -1;
    if (!db.config_json) return -1;
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
        cmocka_unit_test(test_parse_runtime),
        cmocka_unit_test(test_docs_list_runtime),
        cmocka_unit_test(test_apply_defaults_bit_identical),
        cmocka_unit_test(test_save_tuning_round_trip),
        cmocka_unit_test(test_save_tuning_default_bones),
        cmocka_unit_test(test_save_errors),
        cmocka_unit_test(test_save_clip_tags),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
