/* Mirroring for any rest-axis convention. A mirrored clip is its original's world pose reflected
 * across x = 0 with left and right swapped: every joint's world rotation is its partner's,
 * reflected, M R_p N, where M = diag(-1, 1, 1) and N is the reflection of the joint's rest axes
 * (the plane its skeleton's rest pose is symmetric across: x = 0 for a T-pose facing +Z, z = 0
 * for LAFAN1's, a tilted one when the rest axes are rotated; M for the simulation bone). Checked
 * on the built-in set, LAFAN1, games105 and the PFNN (CMU) take, and on each with every joint's
 * rest frame rotated (the same world motion): world rotations within 1e-4 rad; world positions
 * within 0.1 mm where a joint's chain of bones is the mirror image of its partner's, elsewhere
 * within the difference. And mm_database_build refuses to mirror a skeleton with a joint named
 * for a side without its partner, or partners whose bones differ by more than 10%. */
#define _POSIX_C_SOURCE 200809L
#include <ctype.h>
#include <math.h>

#include <mm/config_json.h>
#include <mm/database_build.h>
#include <mm/synth.h>

#include "db/process.h"
#include "test_util.h"

typedef struct dataset {
    const char *name;
    const char *file;   /* under MM_DATA_DIR; NULL: the built-in set's clip */
    const char *config; /* JSON with %s for the file's path */
    double normal[3];   /* the rest pose's plane of symmetry */
    /* how well the plane is found once the rest axes are turned (rad): the skeleton's own
     * asymmetry (CMU's offsets are mirror images to within 0.4 degrees; unturned, the plane is
     * an axis plane and found exactly) */
    double turned_plane;
} dataset;

static const dataset datasets[] = {
    {"built-in set",
     NULL,
     "{\"scale\": 1, \"postures\": {\"detect\": false},"
     " \"clips\": [{\"name\": \"walk_arc_left_r1.5\", \"file\": \"%s\", \"mirror\": true}]}",
     {1, 0, 0},
     0.0},
    {"LAFAN1",
     "lafan1/walk4_subject1.bvh",
     "{\"extends\": \"" MM_SOURCE_DIR "/configs/mocap.json\", \"postures\": {\"detect\": false},"
     " \"clips\": [{\"name\": \"walk4\", \"file\": \"%s\", \"ranges\": [[0, 600]], \"mirror\": true}]}",
     {0, 0, 1},
     0.0},
    {"games105",
     "games105/walk_and_turn_left.bvh",
     "{\"scale\": 1, \"roles\": {\"hips\": \"RootJoint\", \"root_bone\": \"lowerback_torso\","
     " \"facing_bone\": \"RootJoint\", \"forward_axis\": [0, 0, 1], \"left_foot\": \"lAnkle\","
     " \"right_foot\": \"rAnkle\", \"left_toe\": \"lToeJoint\", \"right_toe\": \"rToeJoint\","
     " \"left_hand\": \"lWrist\", \"right_hand\": \"rWrist\", \"head\": \"torso_head\"},"
     " \"features\": {\"bones\": [{\"name\": \"lAnkle\"}, {\"name\": \"rAnkle\"}]},"
     " \"mirror_pairs\": [[\"^l\", \"^r\"]], \"postures\": {\"detect\": false},"
     " \"clips\": [{\"name\": \"walk\", \"file\": \"%s\", \"mirror\": true}]}",
     {1, 0, 0},
     0.0},
    {"PFNN (CMU)",
     "pfnn/bvh/LocomotionFlat09_000.bvh",
     "{\"scale\": 0.056444, \"roles\": {\"hips\": \"Hips\", \"root_bone\": \"Spine\", \"facing_bone\": "
     "\"Hips\","
     " \"forward_axis\": [0, 0, 1], \"left_foot\": \"LeftFoot\", \"right_foot\": \"RightFoot\","
     " \"left_toe\": \"LeftToeBase\", \"right_toe\": \"RightToeBase\", \"left_hand\": \"LeftHand\","
     " \"right_hand\": \"RightHand\", \"head\": \"Head\"},"
     " \"mirror_pairs\": [[\"Left\", \"Right\"], [\"^L\", \"^R\"]], \"postures\": {\"detect\": false},"
     " \"clips\": [{\"name\": \"cmu\", \"file\": \"%s\", \"ranges\": [[240, 840]], \"mirror\": true}]}",
     {1, 0, 0},
     0.01},
};
#define DATASETS (int)(sizeof datasets / sizeof datasets[0])

/* ---- 3 x 3 matrices in double -------------------------------------------------------------- */

typedef struct mat {
    double m[3][3];
} mat;

static mat of_quat(mm_quat q)
{
    double x = q.x, y = q.y, z = q.z, w = q.w, n = sqrt(x * x + y * y + z * z + w * w);
    x /= n, y /= n, z /= n, w /= n;
    mat r = {{{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
              {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
              {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}}};
    return r;
}

static mat mul(mat a, mat b)
{
    mat r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            r.m[i][j] = a.m[i][0] * b.m[0][j] + a.m[i][1] * b.m[1][j] + a.m[i][2] * b.m[2][j];
    return r;
}

/* I - 2 n n^T */
static mat reflection(const double n[3])
{
    mat r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) r.m[i][j] = (i == j) - 2.0 * n[i] * n[j];
    return r;
}

/* The angle of the rotation between two rotation matrices. */
static double angle_between(mat a, mat b)
{
    double f = 0.0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) f += (a.m[i][j] - b.m[i][j]) * (a.m[i][j] - b.m[i][j]);
    return 2.0 * asin(fmin(1.0, sqrt(f) / (2.0 * sqrt(2.0))));
}

static mm_vec3 apply(mat a, mm_vec3 v)
{
    return mm_vec3_make((float)(a.m[0][0] * v.x + a.m[0][1] * v.y + a.m[0][2] * v.z),
                        (float)(a.m[1][0] * v.x + a.m[1][1] * v.y + a.m[1][2] * v.z),
                        (float)(a.m[2][0] * v.x + a.m[2][1] * v.y + a.m[2][2] * v.z));
}

/* ---- clips ------------------------------------------------------------------------------- */

/* The joint named for the other side: Left/Right, or a single l/L/r/R before a capital. */
static int partner_of(const mm_skeleton *s, int j)
{
    const char *n = s->joints[j].name;
    char other[MM_NAME_MAX];
    if (strncmp(n, "Left", 4) == 0)
        snprintf(other, sizeof other, "Right%s", n + 4);
    else if (strncmp(n, "Right", 5) == 0)
        snprintf(other, sizeof other, "Left%s", n + 5);
    else if (strchr("lLrR", n[0]) && isupper((unsigned char)n[1])) {
        snprintf(other, sizeof other, "%s", n);
        other[0] = n[0] == 'l' ? 'r' : n[0] == 'L' ? 'R' : n[0] == 'r' ? 'l' : 'L';
    } else
        return j;
    int k = mm_skeleton_find(s, other);
    assert_true(k >= 0);
    return k;
}

static mm_skeleton skeleton_of(const mm_database *db);

/* Whether joint j's rest frame is turned: every joint when prefix is NULL, else those whose name
 * starts with it. */
static int turned_joint(const mm_skeleton *s, int j, const char *prefix)
{
    return !prefix || strncmp(s->joints[j].name, prefix, strlen(prefix)) == 0;
}

/* src with the rest frames of some joints (turned_joint) turned by q: the same world motion
 * (world rotations R q_j, local rotations q_p^-1 r q_j, offsets q_p^-1 o, q_j the joint's turn:
 * q or the identity). */
static void rotate_rest_axes(const mm_clip *src, mm_quat q, const char *prefix, mm_clip *out)
{
    assert_int_equal(mm_clip_copy(out, src, NULL), MM_OK);
    mm_skeleton *s = &out->skeleton;
    int jc = s->joint_count;
    mm_quat *turn = malloc(sizeof(mm_quat) * (size_t)jc);
    for (int j = 0; j < jc; ++j) turn[j] = turned_joint(s, j, prefix) ? q : mm_quat_identity();
    for (int j = 0; j < jc; ++j) {
        int p = s->joints[j].parent;
        if (p >= 0) s->joints[j].offset = mm_quat_rotate(mm_quat_conj(turn[p]), s->joints[j].offset);
        s->joints[j].end_site = mm_quat_rotate(mm_quat_conj(turn[j]), s->joints[j].end_site);
    }
    for (int f = 0; f < out->frame_count; ++f) {
        mm_quat *r = mm_clip_rotations(out, f);
        mm_vec3 *pos = mm_clip_positions(out, f);
        for (int j = 0; j < jc; ++j) {
            int p = s->joints[j].parent;
            mm_quat before = p >= 0 ? mm_quat_conj(turn[p]) : mm_quat_identity();
            r[j] = mm_quat_mul(before, mm_quat_mul(r[j], turn[j]));
            if (p >= 0) pos[j] = mm_quat_rotate(before, pos[j]);
        }
    }
    mm_xform *a = malloc(sizeof(mm_xform) * (size_t)jc);
    mm_xform *b = malloc(sizeof(mm_xform) * (size_t)jc);
    double worst = 0.0;
    for (int f = 0; f < out->frame_count; ++f) {
        mm_clip_fk(src, f, a);
        mm_clip_fk(out, f, b);
        for (int j = 0; j < jc; ++j) {
            worst = fmax(worst, mm_vec3_distance(a[j].translation, b[j].translation));
            worst = fmax(
                worst, angle_between(mul(of_quat(a[j].rotation), of_quat(turn[j])), of_quat(b[j].rotation)));
        }
    }
    assert_true(worst < 1e-5);
    free(turn);
    free(a);
    free(b);
}

/* The largest differences between the mirrored clips of two databases whose takes differ in the
 * rest frames of some joints (turned_joint: by q) and not in the world: world rotations R q_j and
 * positions. */
static void compare_mirrors(const mm_database *a, const mm_database *b, mm_quat q, const char *prefix,
                            double *rotation, double *position)
{
    mm_skeleton sa = skeleton_of(a), sb = skeleton_of(b);
    mm_xform *ga = malloc(sizeof(mm_xform) * (size_t)sa.joint_count);
    mm_xform *gb = malloc(sizeof(mm_xform) * (size_t)sb.joint_count);
    *rotation = *position = 0.0;
    for (int f = a->clips[1].first_frame; f < a->frame_count; ++f) {
        mm_fk(&sa, mm_database_rotations(a, f), mm_database_positions(a, f), ga);
        mm_fk(&sb, mm_database_rotations(b, f), mm_database_positions(b, f), gb);
        for (int j = 1; j < sa.joint_count; ++j) {
            mat turn = of_quat(turned_joint(&sa, j, prefix) ? q : mm_quat_identity());
            *rotation =
                fmax(*rotation, angle_between(mul(of_quat(ga[j].rotation), turn), of_quat(gb[j].rotation)));
            *position = fmax(*position, mm_vec3_distance(ga[j].translation, gb[j].translation));
        }
    }
    free(ga);
    free(gb);
}

/* The dataset's config and its source clip; 0 when its file is not there (no MM_DATA_DIR). */
static int load(const dataset *d, mm_config *cfg, mm_clip *clip)
{
    char path[1024] = "walk.bvh", text[4096];
    if (d->file && !test_shared_data(d->file, path, sizeof path)) return 0;
    snprintf(text, sizeof text, d->config, path);
    memset(cfg, 0, sizeof *cfg);
    mm_error err;
    memset(&err, 0, sizeof err);
    if (mm_config_parse_json(text, strlen(text), d->name, MM_SOURCE_DIR, cfg, &err) != MM_OK)
        fail_msg("%s: %s", d->name, err.message);
    if (!d->file) {
        mm_synth_set set;
        assert_int_equal(mm_synth_generate(NULL, &set, NULL), MM_OK);
        int found = 0;
        for (int i = 0; i < set.clip_count; ++i)
            if (strcmp(set.clips[i].name, cfg->clips[0].name) == 0)
                found = mm_clip_copy(clip, &set.clips[i].clip, NULL) == MM_OK;
        mm_synth_set_free(&set);
        assert_true(found);
        return 1;
    }
    mm_clip *sources = NULL;
    if (mm_config_load_sources(cfg, &sources, &err) != MM_OK) fail_msg("%s: %s", d->name, err.message);
    *clip = sources[0];
    memset(&sources[0], 0, sizeof sources[0]);
    mm_config_free_sources(cfg, sources);
    return 1;
}

static void build(const mm_config *cfg, const mm_clip *clip, mm_database *db)
{
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_config given = *cfg;
    given.standing_make = false; /* the clip and its mirror, no standing pose made from them */
    if (mm_database_build(&given, clip, NULL, db, &err) != MM_OK) fail_msg("%s", err.message);
    assert_int_equal(db->clip_count, 2);
    assert_int_equal(db->clips[1].mirrored, 1);
    assert_int_equal(db->clips[0].frame_count, db->clips[1].frame_count);
}

/* The database's skeleton as an mm_skeleton (a view: do not free). */
static mm_skeleton skeleton_of(const mm_database *db)
{
    mm_skeleton s;
    memset(&s, 0, sizeof s);
    s.joint_count = db->joint_count;
    s.joints = (mm_joint *)db->joints;
    return s;
}

/* Checks the database's mirrored clip against its original (the rest pose symmetric across the
 * plane with this normal); *rotation and *position receive the largest errors (position: beyond
 * the chain's difference from its partner's). */
static void check_mirror(const mm_database *db, const double normal[3], double *rotation, double *position)
{
    mm_skeleton s = skeleton_of(db);
    int jc = s.joint_count;
    const double x_axis[3] = {1, 0, 0};
    mat M = reflection(x_axis), S = reflection(normal);
    int *partner = malloc(sizeof(int) * (size_t)jc);
    double *slack = malloc(sizeof(double) * (size_t)jc);
    for (int j = 0; j < jc; ++j) partner[j] = partner_of(&s, j);
    /* how far a joint may be from its partner's reflected place: the differences between the
     * rest offsets of its chain and its partner's chain's, reflected (0 for a symmetric skeleton) */
    for (int j = 0; j < jc; ++j) {
        int p = s.joints[j].parent;
        int own = p >= 0 && !(s.joints[j].flags & MM_JOINT_TRANSLATES);
        slack[j] =
            own ? slack[p] + mm_vec3_distance(s.joints[j].offset, apply(S, s.joints[partner[j]].offset))
                : 0.0;
    }
    mm_xform *g = malloc(sizeof(mm_xform) * (size_t)jc), *m = malloc(sizeof(mm_xform) * (size_t)jc);
    *rotation = *position = 0.0;
    int first = db->clips[0].first_frame, mirrored = db->clips[1].first_frame;
    for (int f = 0; f < db->clips[0].frame_count; ++f) {
        mm_fk(&s, mm_database_rotations(db, first + f), mm_database_positions(db, first + f), g);
        mm_fk(&s, mm_database_rotations(db, mirrored + f), mm_database_positions(db, mirrored + f), m);
        for (int j = 0; j < jc; ++j) {
            const mm_xform *from = &g[partner[j]];
            mat want = mul(mul(M, of_quat(from->rotation)), j == 0 ? M : S);
            *rotation = fmax(*rotation, angle_between(of_quat(m[j].rotation), want));
            mm_vec3 t = from->translation;
            double off = mm_vec3_distance(m[j].translation, mm_vec3_make(-t.x, t.y, t.z));
            *position = fmax(*position, off - slack[j]);
        }
    }
    free(partner);
    free(slack);
    free(g);
    free(m);
}

/* Mirroring the mirrored clip gives the original back. */
static void check_twice(const mm_database *db, const mm_config *cfg)
{
    mm_skeleton s = skeleton_of(db);
    int n = db->clips[1].frame_count, jc = db->joint_count;
    mm_clip once, twice;
    assert_int_equal(mm_clip_init(&once, &s, n, 1.0f / db->interval, NULL), MM_OK);
    memcpy(once.rotations, mm_database_rotations(db, db->clips[1].first_frame),
           sizeof(mm_quat) * (size_t)(n * jc));
    memcpy(once.positions, mm_database_positions(db, db->clips[1].first_frame),
           sizeof(mm_vec3) * (size_t)(n * jc));
    assert_int_equal(mm__clip_mirror(&once, cfg, &twice, NULL), MM_OK);
    double worst = 0.0;
    for (int f = 0; f < n; ++f)
        for (int j = 0; j < jc; ++j) {
            mm_quat a = mm_database_rotations(db, db->clips[0].first_frame + f)[j];
            mm_vec3 pa = mm_database_positions(db, db->clips[0].first_frame + f)[j];
            worst = fmax(worst, angle_between(of_quat(a), of_quat(mm_clip_rotations(&twice, f)[j])));
            worst = fmax(worst, mm_vec3_distance(pa, mm_clip_positions(&twice, f)[j]));
        }
    assert_true(worst < 1e-4);
    mm_clip_free(&once);
    mm_clip_free(&twice);
}

static void test_rest_axes(void **state)
{
    (void)state;
    const mm_quat q = mm_quat_from_axis_angle(mm_vec3_normalize(mm_vec3_make(0.3f, 0.8f, 0.5f)), 1.1f);
    int ran = 0;
    for (int i = 0; i < DATASETS; ++i) {
        mm_config cfg;
        mm_clip clip, turned;
        if (!load(&datasets[i], &cfg, &clip)) continue;
        ++ran;
        mm_database db[2];
        build(&cfg, &clip, &db[0]);
        check_twice(&db[0], &cfg);
        /* the rest frames turned: the facing bone's forward axis turns with them */
        rotate_rest_axes(&clip, q, NULL, &turned);
        cfg.forward_axis = mm_quat_rotate(mm_quat_conj(q), cfg.forward_axis);
        build(&cfg, &turned, &db[1]);
        mm_vec3 n = mm_quat_rotate(mm_quat_conj(q),
                                   mm_vec3_make((float)datasets[i].normal[0], (float)datasets[i].normal[1],
                                                (float)datasets[i].normal[2]));
        const double turned_normal[3] = {n.x, n.y, n.z};
        double rotation[2], position[2];
        check_mirror(&db[0], datasets[i].normal, &rotation[0], &position[0]);
        check_mirror(&db[1], turned_normal, &rotation[1], &position[1]);
        /* and the same world motion as the original's mirror */
        double same_rotation, same_position;
        compare_mirrors(&db[0], &db[1], q, NULL, &same_rotation, &same_position);
        print_message("%-12s rotation %.2g rad, position %.2g m beyond the skeleton's asymmetry; turned: "
                      "%.2g rad, %.2g m; as the original's mirror: %.2g rad, %.2g m\n",
                      datasets[i].name, rotation[0], position[0], rotation[1], position[1], same_rotation,
                      same_position);
        /* a plane off by an angle a turns the reflection by 2 a, and a joint a metre from the hips
         * by 2 a metres */
        double slack = 2.0 * datasets[i].turned_plane;
        assert_true(rotation[0] < 1e-4);
        assert_true(position[0] < 1e-4);
        assert_true(rotation[1] < 1e-4 + slack);
        assert_true(position[1] < 1e-4 + slack);
        assert_true(same_rotation < 1e-4 + slack);
        assert_true(same_position < 1e-4 + 2.0 * slack);
        mm_database_free(&db[0]);
        mm_database_free(&db[1]);
        mm_clip_free(&clip);
        mm_clip_free(&turned);
        mm_config_free(&cfg);
    }
    assert_true(ran >= 1);
}

/* A skeleton whose right side has other rest axes than the mirror image of its left (every
 * joint named Right... turned a quarter about z): its rest pose is not symmetric at the upper
 * legs and shoulders, whose reflections are fitted to their children; the mirror is the same
 * world motion as the symmetric skeleton's. */
static void test_one_side_turned(void **state)
{
    (void)state;
    const mm_quat q = mm_quat_from_axis_angle(mm_vec3_make(0, 0, 1), 1.5707963f);
    mm_config cfg;
    mm_clip clip, turned;
    assert_true(load(&datasets[0], &cfg, &clip));
    rotate_rest_axes(&clip, q, "Right", &turned);
    mm_database db[2];
    build(&cfg, &clip, &db[0]);
    build(&cfg, &turned, &db[1]);
    double rotation, position;
    compare_mirrors(&db[0], &db[1], q, "Right", &rotation, &position);
    print_message("right side turned: as the symmetric skeleton's mirror within %.2g rad, %.2g m\n", rotation,
                  position);
    assert_true(rotation < 1e-4);
    assert_true(position < 1e-4);
    check_twice(&db[1], &cfg);
    mm_database_free(&db[0]);
    mm_database_free(&db[1]);
    mm_clip_free(&clip);
    mm_clip_free(&turned);
    mm_config_free(&cfg);
}

/* A build error's message (the build must fail). */
static void build_fails(const mm_config *cfg, const mm_clip *clip, char *message)
{
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_database db;
    assert_int_not_equal(mm_database_build(cfg, clip, NULL, &db, &err), MM_OK);
    snprintf(message, MM_ERROR_MESSAGE_MAX, "%s", err.message);
    print_message("refused: %s\n", message);
}

static int builds(const mm_config *cfg, const mm_clip *clip)
{
    mm_database db;
    if (mm_database_build(cfg, clip, NULL, &db, NULL) != MM_OK) return 0;
    mm_database_free(&db);
    return 1;
}

/* A joint named for a side without its partner, and partners whose bones differ by more than
 * 10%: no mirror (and a clear message); without mirroring the same clip builds. */
static void test_refuse(void **state)
{
    (void)state;
    mm_config cfg;
    mm_clip clip;
    char message[MM_ERROR_MESSAGE_MAX];
    assert_true(load(&datasets[0], &cfg, &clip));
    mm_skeleton *s = &clip.skeleton;
    int right_leg = mm_skeleton_find(s, "RightLeg"), right_hand = mm_skeleton_find(s, "RightHand");
    mm_vec3 rest = s->joints[right_leg].offset;
    s->joints[right_leg].offset = mm_vec3_scale(rest, 1.05f); /* 5%: mirrored */
    assert_true(builds(&cfg, &clip));
    s->joints[right_leg].offset = mm_vec3_scale(rest, 1.2f);
    build_fails(&cfg, &clip, message);
    assert_non_null(strstr(message, "'LeftLeg'"));
    assert_non_null(strstr(message, "'RightLeg'"));
    cfg.clips[0].mirror = false;
    assert_true(builds(&cfg, &clip));
    cfg.clips[0].mirror = true;
    s->joints[right_leg].offset = rest;
    snprintf(s->joints[right_hand].name, MM_NAME_MAX, "RightPalm");
    build_fails(&cfg, &clip, message);
    assert_non_null(strstr(message, "'LeftHand'"));
    assert_non_null(strstr(message, "'RightHand'"));
    mm_clip_free(&clip);
    mm_config_free(&cfg);

    /* games105's lowerback_torso starts with "l" but is no side ("^l" before a lowercase letter);
     * its lWrist without rWrist is refused */
    if (!load(&datasets[2], &cfg, &clip)) return;
    assert_true(builds(&cfg, &clip));
    snprintf(clip.skeleton.joints[mm_skeleton_find(&clip.skeleton, "rWrist")].name, MM_NAME_MAX, "rHand");
    build_fails(&cfg, &clip, message);
    assert_non_null(strstr(message, "'lWrist'"));
    assert_non_null(strstr(message, "'rWrist'"));
    mm_clip_free(&clip);
    mm_config_free(&cfg);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rest_axes),
        cmocka_unit_test(test_one_side_turned),
        cmocka_unit_test(test_refuse),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
