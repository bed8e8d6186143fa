/* The runtime settings a database carries in binary (its settings section): the character desc
 * that mm_character_desc_from_database makes of them (the mm_runtime library, no JSON) is, field
 * for field, the desc of parsing the config embedded in the database and applying it with
 * mm_character_desc_apply_config (the mm_build library), on the built-in set and, with
 * MM_DATA_DIR, on the LAFAN1 configs the tests build; and the bone roles reach the controller
 * whatever the skeleton calls its joints. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <sys/stat.h>

#include <mm/character_config.h>
#include <mm/character.h>
#include <mm/config_json.h>
#include <mm/moves.h>
#include <mm/search.h>
#include <mm/synth.h>

#include "runtime/character/state.h"

#include "test_databases.h"
#include "test_util.h"

/* ---- comparing descs -------------------------------------------------------------------- */

/* Bitwise (a float that is -0 in one and 0 in the other differs). The structs compared whole have
 * no padding: arrays of floats, mm_gait_params (five floats). */
#define SAME(field) assert_memory_equal(&a->field, &b->field, sizeof a->field)

static void assert_same_params(const mm_search_params *a, const mm_search_params *b)
{
    SAME(pose_trajectory_ratio);
    SAME(joint_position_weights);
    SAME(joint_velocity_weights);
    SAME(body_velocity_weight);
    SAME(position_multiplier);
    SAME(angle_multiplier);
    SAME(next_pose_favour);
    SAME(loop_anim_favour);
    SAME(continuing_bias);
    SAME(contact_mismatch_favour);
    SAME(current_frame);
    SAME(exclude_window);
    SAME(end_margin);
    SAME(type);
    SAME(required_tags);
    SAME(excluded_tags);
    SAME(facing_threshold);
}

static void assert_same_trajectory(const mm_trajectory_desc *a, const mm_trajectory_desc *b)
{
    _Static_assert(sizeof(mm_gait_params) == 5 * sizeof(float), "mm_gait_params has padding");
    SAME(gaits);
    SAME(gait_halflife);
    SAME(history_seconds);
    SAME(history_rate);
    SAME(allocator);
}

static void assert_same_name(const char *a, const char *b)
{
    assert_true((a == NULL) == (b == NULL));
    if (a) assert_string_equal(a, b);
}

/* Every field of mm_character_desc; the joint names by their text (one desc may point at string
 * literals, the other into the database), unless feet is false. */
static void assert_same_desc(const mm_character_desc *a, const mm_character_desc *b, int feet)
{
    SAME(search_interval);
    SAME(turn_threshold);
    SAME(transition_halflife);
    SAME(idle_speed);
    SAME(idle_hysteresis);
    SAME(idle_root_speed);
    SAME(sync_halflife);
    SAME(sync_max_distance);
    SAME(sync_max_angle);
    SAME(angle_threshold);
    SAME(angle_revise_speed);
    SAME(skip_frames);
    SAME(velocity_change_ratio);
    SAME(velocity_change_speed);
    SAME(method);
    assert_same_params(&a->params, &b->params);
    assert_same_trajectory(&a->trajectory, &b->trajectory);
    SAME(transition_mode);
    SAME(crossfade_time);
    SAME(no_foot_ik);
    SAME(plant_time);
    SAME(unlock_radius);
    SAME(foot_halflife);
    SAME(max_hip_drop);
    if (feet) {
        assert_same_name(a->left_foot, b->left_foot);
        assert_same_name(a->right_foot, b->right_foot);
    }
    SAME(distance_matching);
    SAME(warping);
    SAME(rate_min);
    SAME(rate_max);
    SAME(stride_min);
    SAME(stride_max);
    SAME(orientation_speed);
    SAME(orientation_max);
    SAME(clock);
    SAME(allocator);
    /* and whatever field is added later: both descs start from mm_character_defaults' memset, so
     * with the names set aside the bytes are the same too */
    mm_character_desc x = *a, y = *b;
    x.left_foot = x.right_foot = y.left_foot = y.right_foot = NULL;
    assert_memory_equal(&x, &y, sizeof x);
}
#undef SAME

/* What the build library makes of the config embedded in db (today's path before the settings
 * section: parse the JSON, apply it). */
static void desc_from_embedded_config(const mm_database *db, mm_character_desc *d)
{
    mm_config cfg;
    memset(&cfg, 0, sizeof cfg);
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_non_null(db->config_json);
    mm_result r =
        mm_config_parse_json(db->config_json, strlen(db->config_json), "embedded", NULL, &cfg, &err);
    if (r != MM_OK) print_error("%s\n", err.message);
    assert_int_equal(r, MM_OK);
    mm_character_defaults(d);
    mm_character_desc_apply_config(d, db, &cfg);
    mm_config_free(&cfg);
}

/* The desc from the settings section equals the desc from the embedded config; returns it. */
static mm_character_desc check_same_desc(const mm_database *db)
{
    mm_character_desc got, want;
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_character_desc_from_database(&got, db, &err), MM_OK);
    desc_from_embedded_config(db, &want);
    assert_same_desc(&got, &want, 1);
    /* no JSON is read: without the embedded text the desc is the same */
    mm_database no_json = *db;
    no_json.config_json = NULL;
    mm_character_desc again;
    assert_int_equal(mm_character_desc_from_database(&again, &no_json, &err), MM_OK);
    assert_same_desc(&again, &got, 1);
    return got;
}

static const char *out_path(const char *name)
{
    static char buf[1024];
    snprintf(buf, sizeof buf, "%s/%s", MM_TEST_OUT, name);
    return buf;
}

/* ---- tests ------------------------------------------------------------------------------ */

/* configs/synth.json (its runtime object: sync_halflife, walk and run speeds), built and also read
 * back from a file. */
static void test_synth_same_desc(void **state)
{
    (void)state;
    mm_database db;
    assert_int_equal(test_build_synth_database(&db), 0);
    mm_character_desc d = check_same_desc(&db);
    assert_true(d.sync_halflife == 0.1f); /* synth.json's runtime object */
    assert_true(d.trajectory.gaits[MM_GAIT_WALK].side_speed == 0.5f);
    assert_true(d.trajectory.gaits[MM_GAIT_RUN].forward_speed == 3.8f);
    assert_true(d.trajectory.gaits[MM_GAIT_RUN].velocity_halflife == 0.4f);
    assert_true(d.params.angle_multiplier == 1.5f && d.params.joint_position_weights[0] == 0.75f);
    assert_null(d.left_foot); /* the character takes the foot roles itself */
    assert_null(d.right_foot);

    const char *path = out_path("settings_synth.mmdb");
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_database_save(&db, path, &err), MM_OK);
    mm_database loaded;
    assert_int_equal(mm_database_load(path, NULL, &loaded, &err), MM_OK);
    assert_memory_equal(loaded.settings, db.settings, sizeof(mm_database_settings));
    mm_character_desc l = check_same_desc(&loaded);
    assert_same_desc(&l, &d, 1);
    mm_database_free(&loaded);
    remove(path);

    /* a desc of the defaults with the section's tuning written out drives the same character as
     * the embedded config applied: one simulated second, pose for pose */
    mm_searcher searcher;
    assert_int_equal(mm_searcher_init(&searcher, &db, NULL, &err), MM_OK);
    mm_character_desc want;
    desc_from_embedded_config(&db, &want);
    mm_character a, b;
    assert_int_equal(mm_character_init(&a, &db, &searcher, &d, &err), MM_OK);
    assert_int_equal(mm_character_init(&b, &db, &searcher, &want, &err), MM_OK);
    for (int i = 0; i < 60; ++i) {
        mm_input in;
        memset(&in, 0, sizeof in);
        in.stick[1] = 1.0f;
        in.gait = i < 30 ? MM_GAIT_WALK : MM_GAIT_RUN;
        mm_character_update(&a, &in, 1.0f / 60.0f);
        mm_character_update(&b, &in, 1.0f / 60.0f);
        assert_memory_equal(a.global, b.global, sizeof(mm_xform) * (size_t)db.joint_count);
    }
    mm_character_free(&a);
    mm_character_free(&b);
    mm_searcher_free(&searcher);
    mm_database_free(&db);
}

/* The LAFAN1 configs the tests make from $MM_DATA_DIR (configs/mocap.json's runtime object:
 * distance matching and warping on, walk and run speeds; the moves config's tags). */
static void test_lafan1_same_desc(void **state)
{
    (void)state;
    char dir[1024];
    struct stat st;
    if (!test_shared_data("lafan1", dir, sizeof dir) || stat(dir, &st) != 0) {
        print_message("MM_DATA_DIR has no lafan1: skipped\n");
        skip();
    }
    const char *names[2] = {"lafan1", "lafan1_moves"};
    for (int k = 0; k < 2; ++k) {
        mm_database db;
        assert_int_equal(test_build_data_database(names[k], &db), 0);
        mm_character_desc d = check_same_desc(&db);
        assert_true(d.distance_matching && d.warping); /* configs/mocap.json */
        assert_true(d.trajectory.gaits[MM_GAIT_RUN].forward_speed == 3.0f);
        print_message("%s: %d frames, runtime fields %#x, the same desc\n", names[k], db.frame_count,
                      (unsigned)db.settings->set);
        mm_database_free(&db);
    }
}

/* Another studio's names: the built-in set with every joint renamed (leftAnkle, not LeftFoot) and
 * a config naming its roles and bones so. The stored roles give the controller its feet, where a
 * desc of names falls back to "LeftFoot" and finds none; everything else is the same desc. */
static void rename_joint(char *name)
{
    static const char *const from[6] = {"Left", "Right", "Foot", "Toe", "Hand", "Hips"};
    static const char *const to[6] = {"left", "right", "Ankle", "Ball", "Wrist", "pelvis"};
    char out[MM_NAME_MAX] = "";
    const char *p = name;
    while (*p) {
        int k = 0;
        while (k < 6 && strncmp(p, from[k], strlen(from[k])) != 0) ++k;
        if (k < 6) {
            strncat(out, to[k], sizeof out - strlen(out) - 1);
            p += strlen(from[k]);
        } else {
            size_t n = strlen(out);
            if (n + 1 < sizeof out) out[n] = *p, out[n + 1] = 0;
            ++p;
        }
    }
    snprintf(name, MM_NAME_MAX, "%s", out);
}

static void test_roles_any_naming(void **state)
{
    (void)state;
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_config cfg;
    memset(&cfg, 0, sizeof cfg);
    assert_int_equal(mm_config_load_json(MM_SOURCE_DIR "/configs/synth.json", &cfg, NULL, &err), MM_OK);
    char *roles[] = {cfg.hips,      cfg.facing_bone, cfg.left_foot,  cfg.right_foot, cfg.left_toe,
                     cfg.right_toe, cfg.left_hand,   cfg.right_hand, cfg.head};
    for (size_t k = 0; k < sizeof roles / sizeof roles[0]; ++k) rename_joint(roles[k]);
    for (int b = 0; b < cfg.bone_count; ++b) rename_joint(cfg.bones[b].name);
    assert_string_equal(cfg.left_foot, "leftAnkle");
    assert_string_equal(cfg.bones[2].name, "pelvis");

    mm_clip *sources = test_synth_sources(&cfg);
    assert_non_null(sources);
    for (int i = 0; i < cfg.clip_count; ++i) {
        assert_int_equal(sources[i].skeleton.joint_count > 0, 1);
        for (int j = 0; j < sources[i].skeleton.joint_count; ++j)
            rename_joint(sources[i].skeleton.joints[j].name);
    }
    mm_database db;
    mm_result r = mm_database_build(&cfg, sources, NULL, &db, &err);
    if (r != MM_OK) print_error("%s\n", err.message);
    assert_int_equal(r, MM_OK);

    const mm_database_settings *s = db.settings;
    assert_string_equal(db.joints[s->roles[MM_ROLE_LEFT_FOOT]].name, "leftAnkle");
    assert_string_equal(db.joints[s->roles[MM_ROLE_RIGHT_TOE]].name, "rightBall");
    assert_string_equal(db.joints[s->roles[MM_ROLE_HIPS]].name, "pelvis");
    assert_int_equal(s->position_set, 0x3); /* leftAnkle, rightAnkle */
    assert_int_equal(s->velocity_set, 0x7); /* and pelvis */

    mm_character_desc got, names;
    assert_int_equal(mm_character_desc_from_database(&got, &db, &err), MM_OK);
    mm_character_defaults(&names);
    mm_character_desc_apply_config(&names, &db, &cfg);
    assert_same_desc(&got, &names, 0);
    assert_null(got.left_foot); /* no names: the character takes the roles by index */
    assert_null(names.left_foot);

    mm_searcher searcher;
    assert_int_equal(mm_searcher_init(&searcher, &db, NULL, &err), MM_OK);
    mm_character c;
    assert_int_equal(mm_character_init(&c, &db, &searcher, &got, &err), MM_OK);
    assert_int_equal(c.foot_joint[0], s->roles[MM_ROLE_LEFT_FOOT]);
    assert_int_equal(c.foot_joint[1], s->roles[MM_ROLE_RIGHT_FOOT]);
    assert_int_equal(c.toe_joint[0], s->roles[MM_ROLE_LEFT_TOE]);
    assert_int_equal(c.state->rig.pelvis, s->roles[MM_ROLE_HIPS]);
    mm_character_free(&c);
    assert_int_equal(mm_character_init(&c, &db, &searcher, &names, &err), MM_OK);
    assert_int_equal(c.foot_joint[0], s->roles[MM_ROLE_LEFT_FOOT]); /* the same feet */
    assert_int_equal(c.foot_joint[1], s->roles[MM_ROLE_RIGHT_FOOT]);
    mm_character_free(&c);

    mm_moves_desc md;
    mm_moves_desc_from_database(&md, &db);
    mm_moves m;
    assert_int_equal(mm_moves_init(&m, &db, NULL, &md, &err), MM_OK);
    assert_string_equal(db.joints[m.hand[0]].name, "leftWrist");
    assert_string_equal(db.joints[m.foot[1]].name, "rightAnkle");

    mm_searcher_free(&searcher);
    mm_database_free(&db);
    mm_config_free_sources(&cfg, sources);
    mm_config_free(&cfg);
}

/* Without settings (a database struct not made by a build or a load) the defaults; bad arguments. */
static void test_no_settings(void **state)
{
    (void)state;
    mm_database db;
    memset(&db, 0, sizeof db);
    mm_character_desc got, want;
    mm_character_defaults(&want);
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_character_desc_from_database(&got, &db, &err), MM_OK);
    assert_memory_equal(&got, &want, sizeof got);
    assert_int_equal(mm_character_desc_from_database(NULL, &db, &err), MM_ERR_INVALID_ARGUMENT);
    assert_int_equal(mm_character_desc_from_database(&got, NULL, &err), MM_ERR_INVALID_ARGUMENT);
    assert_memory_equal(&got, &want, sizeof got);
    mm_moves_desc md, mwant;
    mm_moves_defaults(&mwant);
    mm_moves_desc_from_database(&md, &db);
    assert_memory_equal(&md, &mwant, sizeof md);
}

/* Zero means default in a character desc, and a database that sets a field to 0 keeps its meaning:
 * a config's runtime sync_halflife 0 (the root on the simulation every tick), idle_speed 0, a walk
 * side_speed 0 and a weight 0 reach the character as 0, by the settings section and by the config;
 * a zeroed desc with one field set runs as the defaults plus that field, bit for bit. */
static void test_zero_keeps_its_meaning(void **state)
{
    (void)state;
    mm_database db;
    assert_int_equal(test_build_synth_database(&db), 0);
    mm_searcher searcher;
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_searcher_init(&searcher, &db, NULL, &err), MM_OK);
    /* the settings section: a copy of the database's with zeros set */
    mm_database_settings zeros = *db.settings;
    zeros.set |= MM_RUNTIME_SYNC_HALFLIFE | MM_RUNTIME_IDLE_SPEED;
    zeros.sync_halflife = zeros.idle_speed = 0.0f;
    zeros.walk.set |= MM_RUNTIME_SIDE_SPEED;
    zeros.walk.side_speed = 0.0f;
    zeros.weight_set |= MM_SETTINGS_BODY_VELOCITY_WEIGHT;
    zeros.body_velocity_weight = 0.0f;
    mm_database with = db;
    with.settings = &zeros;
    mm_character_desc d;
    assert_int_equal(mm_character_desc_from_database(&d, &with, &err), MM_OK);
    /* the config: the same zeros */
    mm_character_desc e;
    desc_from_embedded_config(&db, &e);
    mm_config cfg;
    mm_config_defaults(&cfg);
    cfg.runtime.set = MM_RUNTIME_SYNC_HALFLIFE | MM_RUNTIME_IDLE_SPEED;
    cfg.runtime.walk.set = MM_RUNTIME_SIDE_SPEED;
    mm_character_desc_apply_config(&e, &db, &cfg); /* sync_halflife, idle_speed, side_speed 0 */
    e.params.body_velocity_weight = MM_OFF;
    const mm_character_desc *descs[2] = {&d, &e};
    for (int k = 0; k < 2; ++k) {
        mm_character c;
        assert_int_equal(mm_character_init(&c, &db, &searcher, descs[k], &err), MM_OK);
        assert_true(c.desc.sync_halflife < 0.0f && c.state->desc.sync_halflife == 0.0f);
        assert_true(c.state->desc.idle_speed == 0.0f);
        assert_true(c.trajectory->desc.gaits[MM_GAIT_WALK].side_speed == 0.0f);
        assert_true(c.state->desc.params.body_velocity_weight == 0.0f);
        /* and it does what 0 says: the root on the simulation every tick */
        mm_input in;
        memset(&in, 0, sizeof in);
        in.stick[1] = 1.0f;
        for (int t = 0; t < 90; ++t) {
            mm_character_update(&c, &in, 1.0f / 60.0f);
            float dx = c.root.translation.x - c.trajectory->position.x,
                  dz = c.root.translation.z - c.trajectory->position.z;
            assert_true(dx * dx + dz * dz < 1e-10f);
        }
        mm_character_free(&c);
    }
    /* a zeroed desc with one field set: the defaults plus that field */
    mm_character_desc zero, full;
    memset(&zero, 0, sizeof zero);
    zero.transition_halflife = 0.35f;
    mm_character_defaults(&full);
    full.transition_halflife = 0.35f;
    mm_character a, b;
    assert_int_equal(mm_character_init(&a, &db, &searcher, &zero, &err), MM_OK);
    assert_int_equal(mm_character_init(&b, &db, &searcher, &full, &err), MM_OK);
    assert_memory_equal(&a.desc, &b.desc, sizeof a.desc);
    assert_true(a.state->desc.transition_halflife == 0.35f && a.state->desc.search_interval == 0.1f);
    mm_input_script script;
    assert_int_equal(mm_input_script_random(&script, 7, NULL), MM_OK);
    for (int t = 0; t < 600; ++t) {
        mm_input in;
        mm_input_script_sample(&script, (float)t / 60.0f, &in);
        mm_character_update(&a, &in, 1.0f / 60.0f);
        mm_character_update(&b, &in, 1.0f / 60.0f);
    }
    assert_memory_equal(a.global, b.global, sizeof(mm_xform) * (size_t)db.joint_count);
    /* resolving a resolved desc changes nothing */
    mm_character_desc again;
    mm_character_desc_resolve(&db, &a.desc, &again);
    assert_memory_equal(&again, &a.desc, sizeof again);
    mm_input_script_free(&script);
    mm_character_free(&a);
    mm_character_free(&b);
    mm_searcher_free(&searcher);
    mm_database_free(&db);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_synth_same_desc),        cmocka_unit_test(test_lafan1_same_desc),
        cmocka_unit_test(test_roles_any_naming),       cmocka_unit_test(test_no_settings),
        cmocka_unit_test(test_zero_keeps_its_meaning),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
