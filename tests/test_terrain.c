/* Terrain: the ground's height and normal under a point (hand-computed on a ramp, stairs and a
 * height field), ray casts agreeing with it, scene JSON with terrain read and written back, the
 * terrain's triangles, and a character on terrain: bit for bit as without a scene on a flat one,
 * its root on a ramp's height, its planted feet on the ground, up and down stairs. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <mm/character.h>
#include <mm/scene.h>
#include <mm/scene_json.h>
#include <mm/search.h>
#include <mm/terrain_mesh.h>

#include "test_databases.h"

static mm_scene scene, again; /* large: kept off the stack */
static mm_database db;

/* A ramp rising 1 m over 4 m toward +Z from z = 1, 2 m wide; stairs of 4 steps of 0.2 m over 1.2 m
 * toward +X (yaw 90 degrees) centred at x = 10; a 3 x 3 field at x in [-10, -8], z in [0, 2]. */
static void build(mm_scene *s)
{
    mm_scene_init(s, 0.0f);
    assert_int_equal(mm_scene_add_ramp(s, mm_vec3_make(0, 0, 3), mm_vec3_make(2, 1, 4), 0.0f), MM_OK);
    assert_int_equal(
        mm_scene_add_stairs(s, mm_vec3_make(10, 0, 0), mm_vec3_make(2, 0.8f, 1.2f), (float)(MM_PI / 2), 4),
        MM_OK);
    const float h[9] = {0, 0.1f, 0.2f, 0, 0.3f, 0, 0, 0, 0};
    assert_int_equal(mm_scene_set_field(s, mm_vec3_make(-10, 0, 0), 1.0f, 3, 3, h), MM_OK);
}

static void test_ground_height_by_hand(void **state)
{
    (void)state;
    build(&scene);
    mm_vec3 n;
    /* the ramp: a quarter of the way up at z = 2; its normal (0, 4, -1) / sqrt(17) */
    assert_float_equal(mm_scene_ground_height(&scene, 0.5f, 2.0f, &n), 0.25f, 1e-6f);
    assert_float_equal(n.y, 4.0f / sqrtf(17.0f), 1e-6f);
    assert_float_equal(n.z, -1.0f / sqrtf(17.0f), 1e-6f);
    assert_float_equal(mm_scene_ground_height(&scene, 0.0f, 5.0f, NULL), 1.0f, 1e-6f);
    /* beside it: the plane */
    assert_float_equal(mm_scene_ground_height(&scene, 1.2f, 3.0f, &n), 0.0f, 0.0f);
    assert_float_equal(n.y, 1.0f, 0.0f);
    /* the stairs rise toward +X from x = 9.4: runs of 0.3 m, risers of 0.2 m */
    assert_float_equal(mm_scene_ground_height(&scene, 9.5f, 0.0f, NULL), 0.2f, 1e-6f);
    assert_float_equal(mm_scene_ground_height(&scene, 9.85f, 0.5f, NULL), 0.4f, 1e-6f);
    assert_float_equal(mm_scene_ground_height(&scene, 10.55f, -0.9f, NULL), 0.8f, 1e-6f);
    assert_float_equal(mm_scene_ground_height(&scene, 10.55f, -1.1f, NULL), 0.0f, 0.0f); /* off its side */
    /* the field: on the triangle (0,0) (1,0) (1,1) at (0.75, 0.25) from its corner: 0 + 0.75 * 0.1 +
     * 0.25 * (0.3 - 0.1); on the other, (0.25, 0.75): 0.75 * 0 + 0.25 * (0.3 - 0) */
    assert_float_equal(mm_scene_ground_height(&scene, -9.25f, 0.25f, &n), 0.125f, 1e-6f);
    mm_vec3 expect = mm_vec3_normalize(mm_vec3_make(-0.1f, 1.0f, -0.2f));
    assert_float_equal(n.x, expect.x, 1e-6f);
    assert_float_equal(n.z, expect.z, 1e-6f);
    assert_float_equal(mm_scene_ground_height(&scene, -9.75f, 0.75f, NULL), 0.075f, 1e-6f);
    assert_float_equal(mm_scene_ground_height(&scene, -9.0f, 1.0f, NULL), 0.3f, 1e-6f);
    /* a box on the ramp: the higher of the two */
    assert_int_equal(mm_scene_add_box(&scene, mm_vec3_make(0, 0, 4), mm_vec3_make(0.5f, 1.0f, 0.5f), 0.0f),
                     MM_OK);
    assert_float_equal(mm_scene_ground_height(&scene, 0.0f, 3.9f, NULL), 1.0f, 1e-6f);
    assert_float_equal(mm_scene_ground_height(&scene, 0.0f, 4.3f, NULL), 0.825f, 1e-6f);
    /* no scene, NaN: the plane y = 0 */
    assert_float_equal(mm_scene_ground_height(NULL, 3.0f, 3.0f, &n), 0.0f, 0.0f);
    assert_float_equal(mm_scene_ground_height(&scene, NAN, 3.0f, &n), 0.0f, 0.0f);
    assert_true(mm_scene_is_flat(NULL));
    assert_false(mm_scene_is_flat(&scene));
    mm_scene_init(&again, 0.0f);
    assert_true(mm_scene_is_flat(&again));
    /* bad terrain refused */
    assert_int_equal(mm_scene_add_ramp(&again, mm_vec3_make(0, 0, 0), mm_vec3_make(1, 1, 0), 0.0f),
                     MM_ERR_OUT_OF_RANGE);
    assert_int_equal(mm_scene_add_stairs(&again, mm_vec3_make(0, 0, 0), mm_vec3_make(1, 1, 1), 0.0f, 0),
                     MM_ERR_OUT_OF_RANGE);
    float one = 0.0f;
    assert_int_equal(mm_scene_set_field(&again, mm_vec3_make(0, 0, 0), 1.0f, 1, 1, &one),
                     MM_ERR_OUT_OF_RANGE);
}

/* A ray straight down meets the terrain where mm_scene_ground_height says, at many points. */
static void test_rays_agree(void **state)
{
    (void)state;
    build(&scene);
    int checked = 0;
    for (float x = -11.0f; x <= 12.0f; x += 0.37f)
        for (float z = -1.5f; z <= 6.0f; z += 0.29f) {
            mm_scene_hit hit;
            mm_vec3 n;
            float h = mm_scene_ground_height(&scene, x, z, &n);
            assert_true(
                mm_scene_raycast(&scene, mm_vec3_make(x, 5.0f, z), mm_vec3_make(0, -1, 0), INFINITY, &hit));
            if (fabsf(hit.point.y - h) > 1e-4f)
                fprintf(stderr, "x %g z %g ray %g ground %g\n", x, z, hit.point.y, h);
            assert_float_equal(hit.point.y, h, 1e-4f);
            assert_true(mm_scene_ground_probe(&scene, mm_vec3_make(x, h + 0.01f, z), 0.05f, 1.0f, &hit));
            assert_float_equal(hit.point.y, h, 1e-6f);
            ++checked;
        }
    assert_true(checked > 1000);
    /* a slanting ray onto the ramp's top: the plane y = (z - 1) / 4 met by (0, 2, 0) + t (0, -1, 1) / sqrt 2
     * at 2 - t' = (t' - 1) / 4 with t' = t / sqrt 2: t' = 1.8 */
    mm_scene_hit hit;
    assert_true(mm_scene_raycast(&scene, mm_vec3_make(0, 2, 0), mm_vec3_make(0, -1, 1), INFINITY, &hit));
    assert_float_equal(hit.point.z, 1.8f, 1e-5f);
    assert_float_equal(hit.point.y, 0.2f, 1e-5f);
    assert_float_equal(hit.normal.z, -1.0f / sqrtf(17.0f), 1e-5f);
    assert_int_equal(hit.box, -1);
}

static void test_json_round_trip(void **state)
{
    (void)state;
    static const char text[] =
        "{\"ground\": -0.5, \"ramps\": [{\"position\": [0, 0, 3], \"size\": [2, 1, 4], \"yaw\": 30}],\n"
        " \"stairs\": [{\"position\": [5, 0, 0], \"size\": [2, 0.8, 1.2], \"steps\": 4, \"yaw\": 180}],\n"
        " \"field\": {\"origin\": [-10, 0.1, 0], \"spacing\": 0.5, \"columns\": 3, \"rows\": 2,\n"
        "   \"heights\": [0, 0.1, 0.2, 0.3, 0.4, 0.5]}}";
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_scene_parse_json(text, sizeof text - 1, "t.json", &scene, &err), MM_OK);
    assert_int_equal(scene.ramp_count, 1);
    assert_int_equal(scene.stairs[0].steps, 4);
    assert_float_equal(scene.field.heights[5], 0.5f, 0.0f);
    FILE *f = tmpfile();
    assert_non_null(f);
    assert_int_equal(mm_scene_write_json(&scene, f), MM_OK);
    static char buffer[4096];
    rewind(f);
    size_t size = fread(buffer, 1, sizeof buffer, f);
    fclose(f);
    assert_true(size > 0 && size < sizeof buffer);
    assert_int_equal(mm_scene_parse_json(buffer, size, "back.json", &again, &err), MM_OK);
    assert_memory_equal(&scene.ramps[0], &again.ramps[0], sizeof scene.ramps[0]);
    assert_memory_equal(&scene.stairs[0], &again.stairs[0], sizeof scene.stairs[0]);
    assert_memory_equal(&scene.field, &again.field, sizeof scene.field);
    assert_float_equal(again.ground, -0.5f, 0.0f);
    /* errors name the field */
    static const char bad[] =
        "{\"stairs\": [{\"position\": [0, 0, 0], \"size\": [1, 1, 1], \"steps\": 2.5}]}";
    assert_int_equal(mm_scene_parse_json(bad, sizeof bad - 1, "bad.json", &scene, &err), MM_ERR_OUT_OF_RANGE);
    assert_non_null(strstr(err.message, "stairs[0].steps"));
    static const char short_field[] =
        "{\"field\": {\"spacing\": 1, \"columns\": 2, \"rows\": 2, \"heights\": [0, 1, 2]}}";
    assert_int_equal(mm_scene_parse_json(short_field, sizeof short_field - 1, "f.json", &scene, &err),
                     MM_ERR_SYNTAX);
    assert_non_null(strstr(err.message, "field.heights"));
}

/* The shipped image-based scene: its PGM read, white at height_scale. */
static void test_pgm_field(void **state)
{
    (void)state;
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_scene_load_json(MM_SOURCE_DIR "/scenes/terrain_hills.json", &scene, &err), MM_OK);
    assert_int_equal(scene.field.columns, 49);
    assert_int_equal(scene.field.rows, 49);
    float lo = INFINITY, hi = -INFINITY;
    for (int i = 0; i < 49 * 49; ++i)
        lo = fminf(lo, scene.field.heights[i]), hi = fmaxf(hi, scene.field.heights[i]);
    assert_true(lo >= 0.0f && hi <= 1.0f && hi - lo > 0.5f);
}

/* Every vertex of the terrain's triangles lies on the ground mm_scene_ground_height gives (the top
 * faces), or below it (sides); the field's normals point up. */
static void test_mesh(void **state)
{
    (void)state;
    build(&scene);
    int n = mm_terrain_mesh(&scene, NULL, 0);
    assert_int_equal(n, 6 + 4 * 10 + 2 * 2 * 2);
    float *v = malloc(sizeof(float) * MM_TERRAIN_MESH_FLOATS * (size_t)n);
    assert_int_equal(mm_terrain_mesh(&scene, v, n), n);
    for (int t = 0; t < n; ++t) {
        const float *p = v + t * MM_TERRAIN_MESH_FLOATS;
        float cx = (p[0] + p[6] + p[12]) / 3.0f, cy = (p[1] + p[7] + p[13]) / 3.0f,
              cz = (p[2] + p[8] + p[14]) / 3.0f;
        float h = mm_scene_ground_height(&scene, cx, cz, NULL);
        if (p[4] > 0.5f)
            assert_float_equal(cy, h, 1e-5f); /* a top: the ground there */
        else
            assert_true(cy < h + 1e-5f); /* a side: under it */
    }
    for (int t = 0; t < 8; ++t)
        assert_true(v[t * MM_TERRAIN_MESH_FLOATS + 4] > 0.0f); /* the field's, first */
    free(v);
}

/* Runs a character for ticks on a walk forward; with scene (NULL: none). Returns it for reading. */
static void run(mm_character *c, const mm_searcher *searcher, const mm_scene *s, int ticks)
{
    assert_int_equal(mm_character_init(c, &db, searcher, NULL, NULL), MM_OK);
    mm_character_set_scene(c, s);
    mm_input in;
    memset(&in, 0, sizeof in);
    for (int i = 0; i < ticks; ++i) {
        in.stick[1] = i > 30 ? 1.0f : 0.0f;
        in.stick[0] = i > 200 ? 0.5f : 0.0f;
        mm_character_update(c, &in, 1.0f / 60.0f);
    }
}

static void test_flat_scene_is_no_scene(void **state)
{
    (void)state;
    mm_searcher searcher;
    assert_int_equal(mm_searcher_init(&searcher, &db, NULL, NULL), MM_OK);
    mm_character a, b;
    mm_scene_init(&scene, 0.0f);
    run(&a, &searcher, NULL, 400);
    run(&b, &searcher, &scene, 400);
    assert_memory_equal(a.global, b.global, sizeof(mm_xform) * (size_t)db.joint_count);
    assert_memory_equal(&a.root, &b.root, sizeof a.root);
    mm_character_free(&b);
    /* a scene with something in it is not flat: the plane raised 0.5 m lifts the whole body */
    mm_scene_init(&scene, 0.5f);
    run(&b, &searcher, &scene, 400);
    assert_float_equal(b.root.translation.y, 0.5f, 1e-4f);
    /* (within 6 cm: on terrain a foot is planted on the ground, on the plane where it is, above it
     * at times; the hips come down a few centimetres more to reach, by 0.2 to 5.3 cm over the
     * strides of ticks 300-400 on the built-in set) */
    double raised = 0.0;
    for (int j = 1; j < db.joint_count; ++j) raised += b.global[j].translation.y - a.global[j].translation.y;
    assert_float_equal(raised / (db.joint_count - 1), 0.5, 0.06);
    mm_character_free(&a);
    mm_character_free(&b);
    mm_searcher_free(&searcher);
}

/* The mean height of the planted ankles above the ground under them, along its normal (cos
 * slope), over ticks 60 to 600 walking forward; the root's largest distance from the ground's
 * height under it after the first second. */
static double planted_height(const mm_searcher *searcher, const mm_scene *s, float slope, double *root_error,
                             int *count)
{
    mm_character c;
    assert_int_equal(mm_character_init(&c, &db, searcher, NULL, NULL), MM_OK);
    mm_character_set_scene(&c, s);
    mm_input in;
    memset(&in, 0, sizeof in);
    in.stick[1] = 1.0f;
    double sum = 0.0;
    *count = 0;
    *root_error = 0.0;
    for (int i = 0; i < 600; ++i) {
        mm_character_update(&c, &in, 1.0f / 60.0f);
        if (i < 60) continue;
        float ground = mm_scene_ground_height(s, c.root.translation.x, c.root.translation.z, NULL);
        *root_error = fmax(*root_error, fabs(c.root.translation.y - ground));
        for (int k = 0; k < 2; ++k) {
            mm_vec3 a = c.global[c.foot_joint[k]].translation;
            float under = mm_scene_ground_height(s, a.x, a.z, NULL);
            assert_true(a.y > under); /* no ankle in the ground */
            if (!c.foot_locked[k]) continue;
            sum += (a.y - under) * cosf(slope);
            ++*count;
        }
    }
    assert_true(c.root.translation.z > 8.0f);
    mm_character_free(&c);
    return *count ? sum / *count : NAN;
}

/* The scene: a ramp 20 m wide rising at slope (rad) from z = -1 to z = 39, its low end behind
 * the character's start. */
static void long_ramp(float slope)
{
    mm_scene_init(&scene, 0.0f);
    assert_int_equal(
        mm_scene_add_ramp(&scene, mm_vec3_make(0, 0, 19), mm_vec3_make(20, 40 * tanf(slope), 40), 0.0f),
        MM_OK);
}

/* Walking up a long 15-degree ramp: the root at the ramp's height (within 2 cm), the planted ankles
 * as high above it, along its normal, as on level terrain (a plane raised 0.25 m; within 2 cm, the
 * bound docs/scene.md gives). */
static void test_walk_up_a_ramp(void **state)
{
    (void)state;
    mm_searcher searcher;
    assert_int_equal(mm_searcher_init(&searcher, &db, NULL, NULL), MM_OK);
    float slope = 15.0f * (float)MM_DEG_TO_RAD;
    long_ramp(slope);
    int on_ramp = 0, on_flat = 0;
    double root_error = 0.0, flat_error = 0.0;
    double ramp = planted_height(&searcher, &scene, slope, &root_error, &on_ramp);
    mm_scene_init(&again, 0.25f);
    double flat = planted_height(&searcher, &again, 0.0f, &flat_error, &on_flat);
    assert_true(on_ramp > 200 && on_flat > 200);
    assert_true(root_error < 0.02 && flat_error < 1e-4);
    assert_float_equal(ramp, flat, 0.02);
    mm_searcher_free(&searcher);
}

/* Heights of the planted feet over ticks 60 to 600 walking forward on s: for each tick and locked
 * foot, its ankle's and its toe's distance above the ground under each along the ground's normal
 * (height above it times cos slope); the means of each, the largest foot's gap (the lower of its
 * ankle's and its toe's heights, less the mean of that joint on level ground: flat_ankle and
 * flat_toe, when given) and the deepest either went below the ground. */
typedef struct planted_feet {
    double ankle, toe, worst_gap, deepest;
    int count, across; /* locked feet, and those whose ankle and toe are over different ground */
} planted_feet;

static planted_feet walk_planted(const mm_searcher *searcher, const mm_scene *s, float slope,
                                 const planted_feet *flat)
{
    mm_character c;
    assert_int_equal(mm_character_init(&c, &db, searcher, NULL, NULL), MM_OK);
    mm_character_set_scene(&c, s);
    mm_input in;
    memset(&in, 0, sizeof in);
    in.stick[1] = 1.0f;
    planted_feet out = {0.0, 0.0, 0.0, 0.0, 0, 0};
    for (int i = 0; i < 600; ++i) {
        mm_character_update(&c, &in, 1.0f / 60.0f);
        if (i < 60) continue;
        for (int k = 0; k < 2; ++k) {
            assert_true(c.toe_joint[k] >= 0);
            mm_vec3 a = c.global[c.foot_joint[k]].translation, t = c.global[c.toe_joint[k]].translation;
            float under_ankle = mm_scene_ground_height(s, a.x, a.z, NULL),
                  under_toe = mm_scene_ground_height(s, t.x, t.z, NULL);
            double ha = (a.y - under_ankle) * cos(slope), ht = (t.y - under_toe) * cos(slope);
            out.deepest = fmax(out.deepest, fmax(-ha, -ht));
            if (!c.foot_locked[k]) continue;
            out.ankle += ha, out.toe += ht;
            ++out.count;
            out.across += slope == 0.0f && fabsf(under_ankle - under_toe) > 0.01f;
            if (flat) out.worst_gap = fmax(out.worst_gap, fmin(ha - flat->ankle, ht - flat->toe));
        }
    }
    assert_true(c.root.translation.z > 8.0f);
    mm_character_free(&c);
    if (out.count) out.ankle /= out.count, out.toe /= out.count;
    return out;
}

/* Walking up a 20-degree ramp (an angle the shipped scenes do not have): the planted feet turned to
 * the slope, heel and toe each, on average, as high above it along its normal as on level ground
 * (a plane raised 0.25 m), within 1 cm; none below it; every planted foot has its heel or its toe
 * within 1.5 cm of its height on level ground (a trailing foot rolled onto its toe, its ankle
 * raised, did not count as below the root's ground for the hips' drop: 2.5 cm). */
static void test_feet_on_a_20_degree_slope(void **state)
{
    (void)state;
    mm_searcher searcher;
    assert_int_equal(mm_searcher_init(&searcher, &db, NULL, NULL), MM_OK);
    float slope = 20.0f * (float)MM_DEG_TO_RAD;
    long_ramp(slope);
    mm_scene_init(&again, 0.25f);
    planted_feet flat = walk_planted(&searcher, &again, 0.0f, NULL);
    planted_feet ramp = walk_planted(&searcher, &scene, slope, &flat);
    assert_true(flat.count > 200 && ramp.count > 200);
    assert_float_equal(ramp.ankle, flat.ankle, 0.01);
    assert_float_equal(ramp.toe, flat.toe, 0.01);
    assert_true(ramp.deepest < 0.005);
    assert_true(ramp.worst_gap < 0.015);
    mm_searcher_free(&searcher);
}

/* scene: stairs up along +Z, 4 m wide, of steps treads riser high and run_length deep from z =
 * start, on level ground; the treads' heights checked by hand on the stairs' middle line (a
 * step's count times the riser). */
static void build_stairs(int steps, float riser, float run_length, float start)
{
    mm_scene_init(&scene, 0.0f);
    assert_int_equal(mm_scene_add_stairs(&scene, mm_vec3_make(0, 0, start + 0.5f * steps * run_length),
                                         mm_vec3_make(4, steps * riser, steps * run_length), 0.0f, steps),
                     MM_OK);
    for (int i = 0; i < steps; ++i) {
        float z = start + ((float)i + 0.5f) * run_length;
        assert_float_equal(mm_scene_ground_height(&scene, 0.0f, z, NULL), (float)(i + 1) * riser, 1e-4f);
    }
}

/* Walking up stairs of risers and runs the shipped scenes do not have (0.15 m over 0.28 m, 50
 * steps; the treads' heights checked by hand: a step's count times the riser): the planted feet
 * stand on one tread, their ankle and toe over the same tread on at least 90% of the planted ticks
 * (a foot planted where the data puts it lands across an edge on more than half of them), the
 * ankles on average as high above the tread as on level ground within 2.5 cm (a foot held at the
 * higher tread's height over the lower one floats), none below the tread; every planted foot has
 * its heel or its toe within 15 cm of its height on level ground. */
static void test_feet_on_stairs(void **state)
{
    (void)state;
    mm_searcher searcher;
    assert_int_equal(mm_searcher_init(&searcher, &db, NULL, NULL), MM_OK);
    build_stairs(50, 0.15f, 0.28f, 1.0f);
    mm_scene_init(&again, 0.25f);
    planted_feet flat = walk_planted(&searcher, &again, 0.0f, NULL);
    planted_feet stairs = walk_planted(&searcher, &scene, 0.0f, &flat);
    assert_true(flat.count > 200 && stairs.count > 200);
    assert_true(stairs.across < stairs.count / 10);
    assert_float_equal(stairs.ankle, flat.ankle, 0.025);
    assert_true(stairs.deepest < 0.005);
    assert_true(stairs.worst_gap < 0.15);
    mm_searcher_free(&searcher);
}

/* Walking down stairs (0.15 m over 0.28 m, 12 steps, from a plateau of their height; the treads'
 * heights checked by hand): every planted foot has its heel or its toe within 3 cm of its height on
 * level ground (a swinging foot whose shift to the ground followed only the ground under it, and
 * hips lowered no sooner than the leg needed, stood 8.7 cm above the lower tread as it was
 * planted), the feet over one tread on at least 90% of the planted ticks, no ankle or toe more than
 * 3 cm below the ground under it (a heel landing just past an edge with the hips at their lowest
 * reaches 2.5 cm short of it, over the edge, for a tick). */
static void test_feet_down_stairs(void **state)
{
    (void)state;
    mm_searcher searcher;
    assert_int_equal(mm_searcher_init(&searcher, &db, NULL, NULL), MM_OK);
    const int steps = 12;
    const float riser = 0.15f, run_length = 0.28f, start = 2.0f, height = steps * riser;
    mm_scene_init(&scene, 0.0f);
    assert_int_equal(
        mm_scene_add_box(&scene, mm_vec3_make(0, 0, start - 2.5f), mm_vec3_make(4, height, 5), 0.0f), MM_OK);
    assert_int_equal(mm_scene_add_stairs(&scene, mm_vec3_make(0, 0, start + 0.5f * steps * run_length),
                                         mm_vec3_make(4, height, steps * run_length), (float)MM_PI, steps),
                     MM_OK);
    /* the ground by hand on the stairs' middle line: the plateau, then a riser lower each run */
    assert_float_equal(mm_scene_ground_height(&scene, 0.0f, start - 0.1f, NULL), height, 1e-4f);
    for (int i = 0; i < steps; ++i) {
        float z = start + ((float)i + 0.5f) * run_length;
        assert_float_equal(mm_scene_ground_height(&scene, 0.0f, z, NULL), (float)(steps - i) * riser, 1e-4f);
    }
    mm_scene_init(&again, 0.25f);
    planted_feet flat = walk_planted(&searcher, &again, 0.0f, NULL);
    planted_feet down = walk_planted(&searcher, &scene, 0.0f, &flat);
    assert_true(flat.count > 200 && down.count > 200);
    assert_true(down.across < down.count / 10);
    assert_true(down.deepest < 0.03);
    assert_true(down.worst_gap < 0.03);
    mm_searcher_free(&searcher);
}

/* Walking up stairs of the shipped scenes' risers and runs (0.17 m over 0.30 m, 60 steps): the
 * walk takes about two treads a step, so a trailing foot still on its toe is a riser or two below
 * the root's ground. Every planted foot has its heel or its toe within 2 cm of its height on level
 * ground (hips lowered no further than 0.15 m below max_hip_drop, and by how far its rolled-up
 * ankle, not the ground under it, was below the root's ground, left the trailing toe 8.8 cm in
 * the air before it let go); none below the tread. */
static void test_trailing_foot_reached_up_stairs(void **state)
{
    (void)state;
    mm_searcher searcher;
    assert_int_equal(mm_searcher_init(&searcher, &db, NULL, NULL), MM_OK);
    build_stairs(60, 0.17f, 0.30f, 2.0f);
    mm_scene_init(&again, 0.25f);
    planted_feet flat = walk_planted(&searcher, &again, 0.0f, NULL);
    planted_feet up = walk_planted(&searcher, &scene, 0.0f, &flat);
    assert_true(flat.count > 200 && up.count > 200);
    assert_true(up.deepest < 0.005);
    assert_true(up.worst_gap < 0.02);
    mm_searcher_free(&searcher);
}

/* The largest change of velocity of any joint but the root in a tick (the metrics' pop, m) over
 * 7 s walking forward on s. */
static double largest_pop(const mm_searcher *searcher, const mm_scene *s)
{
    mm_character c;
    assert_int_equal(mm_character_init(&c, &db, searcher, NULL, NULL), MM_OK);
    mm_character_set_scene(&c, s);
    mm_input in;
    memset(&in, 0, sizeof in);
    in.stick[1] = 1.0f;
    int n = db.joint_count;
    mm_vec3 *p = malloc(sizeof(mm_vec3) * (size_t)n * 3);
    assert_non_null(p);
    double worst = 0.0;
    for (int i = 0; i < 420; ++i) {
        mm_character_update(&c, &in, 1.0f / 60.0f);
        mm_vec3 *now = p + (i % 3) * n, *one = p + ((i + 2) % 3) * n, *two = p + ((i + 1) % 3) * n;
        for (int j = 0; j < n; ++j) now[j] = c.global[j].translation;
        for (int j = 1; i >= 2 && j < n; ++j) {
            double x = now[j].x - 2.0 * one[j].x + two[j].x, y = now[j].y - 2.0 * one[j].y + two[j].y,
                   z = now[j].z - 2.0 * one[j].z + two[j].z;
            worst = fmax(worst, sqrt(x * x + y * y + z * z));
        }
    }
    free(p);
    mm_character_free(&c);
    return worst;
}

/* Walking up a flight of the shipped scenes' stairs (6 steps of 0.17 m over 0.30 m) onto a plateau
 * of their height: no joint's velocity changes by more than 9.5 cm a tick in a tick (3.3 on level
 * ground, a plane raised 1.02 m: the swinging feet cleared over the risers and landed on the
 * treads make the rest). A trailing foot letting go takes back the extra drop the hips were allowed
 * for it: held to the new bound at once, the whole body jumped up by the difference in a tick
 * (12.1 cm a tick squared); a foot let go just short of a riser jumped onto the clearance above
 * it. */
static void test_smooth_up_stairs(void **state)
{
    (void)state;
    mm_searcher searcher;
    assert_int_equal(mm_searcher_init(&searcher, &db, NULL, NULL), MM_OK);
    const int steps = 6;
    const float riser = 0.17f, run_length = 0.30f, start = 2.0f, height = steps * riser;
    mm_scene_init(&scene, 0.0f);
    assert_int_equal(mm_scene_add_stairs(&scene, mm_vec3_make(0, 0, start + 0.5f * steps * run_length),
                                         mm_vec3_make(4, height, steps * run_length), 0.0f, steps),
                     MM_OK);
    float plateau = start + steps * run_length;
    assert_int_equal(
        mm_scene_add_box(&scene, mm_vec3_make(0, 0, plateau + 5.0f), mm_vec3_make(4, height, 10), 0.0f),
        MM_OK);
    assert_float_equal(mm_scene_ground_height(&scene, 0.0f, start + 0.15f, NULL), riser, 1e-4f);
    assert_float_equal(mm_scene_ground_height(&scene, 0.0f, plateau + 1.0f, NULL), height, 1e-4f);
    mm_scene_init(&again, height);
    double flat = largest_pop(&searcher, &again), up = largest_pop(&searcher, &scene);
    assert_true(flat < 0.05);
    assert_true(up < 0.095);
    mm_searcher_free(&searcher);
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
        cmocka_unit_test(test_ground_height_by_hand),
        cmocka_unit_test(test_rays_agree),
        cmocka_unit_test(test_json_round_trip),
        cmocka_unit_test(test_pgm_field),
        cmocka_unit_test(test_mesh),
        cmocka_unit_test(test_flat_scene_is_no_scene),
        cmocka_unit_test(test_walk_up_a_ramp),
        cmocka_unit_test(test_feet_on_a_20_degree_slope),
        cmocka_unit_test(test_feet_on_stairs),
        cmocka_unit_test(test_feet_down_stairs),
        cmocka_unit_test(test_trailing_foot_reached_up_stairs),
        cmocka_unit_test(test_smooth_up_stairs),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
