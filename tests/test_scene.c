/* Scenes: ray casts against hand-computed hits, the ground probe, the obstacle measure, and the
 * JSON loader's errors and round trip. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>

#include <mm/scene_json.h>

#include "test_util.h"

#define EPS 1e-5f

static mm_scene scene; /* large: kept off the stack */

static void near3(mm_vec3 got, float x, float y, float z, float eps)
{
    if (fabsf(got.x - x) > eps || fabsf(got.y - y) > eps || fabsf(got.z - z) > eps)
        fail_msg("got (%.7g %.7g %.7g), want (%.7g %.7g %.7g)", got.x, got.y, got.z, x, y, z);
}

static void near1(float got, float want, float eps)
{
    if (!(fabsf(got - want) <= eps)) fail_msg("got %.7g, want %.7g", got, want);
}

static void add(float px, float py, float pz, float sx, float sy, float sz, float yaw_degrees)
{
    assert_int_equal(mm_scene_add_box(&scene, mm_vec3_make(px, py, pz), mm_vec3_make(sx, sy, sz),
                                      (float)(yaw_degrees * MM_DEG_TO_RAD)),
                     MM_OK);
}

static mm_scene_hit cast(float ox, float oy, float oz, float dx, float dy, float dz, float max_distance)
{
    mm_scene_hit h;
    memset(&h, 0, sizeof h);
    if (!mm_scene_raycast(&scene, mm_vec3_make(ox, oy, oz), mm_vec3_make(dx, dy, dz), max_distance, &h))
        fail_msg("ray from (%g %g %g) along (%g %g %g) hit nothing", ox, oy, oz, dx, dy, dz);
    return h;
}

static bool misses(float ox, float oy, float oz, float dx, float dy, float dz, float max_distance)
{
    return !mm_scene_raycast(&scene, mm_vec3_make(ox, oy, oz), mm_vec3_make(dx, dy, dz), max_distance, NULL);
}

/* ---- ray casts -------------------------------------------------------------------------- */

static void test_raycast_axis_aligned(void **state)
{
    (void)state;
    mm_scene_init(&scene, 0.0f);
    add(0, 0, 3, 4, 1, 0.4f, 0); /* x [-2, 2], y [0, 1], z [2.8, 3.2] */
    near3(mm_scene_box_centre(&scene.boxes[0]), 0, 0.5f, 3, 0);

    mm_scene_hit h = cast(0, 0.5f, 0, 0, 0, 1, INFINITY); /* the near face */
    near3(h.point, 0, 0.5f, 2.8f, EPS);
    near3(h.normal, 0, 0, -1, EPS);
    near1(h.distance, 2.8f, EPS);
    assert_int_equal(h.box, 0);
    assert_false(h.inside);

    h = cast(1, 5, 3, 0, -2, 0, 10); /* the top, with a direction that is not unit */
    near3(h.point, 1, 1, 3, EPS);
    near3(h.normal, 0, 1, 0, EPS);
    near1(h.distance, 4, EPS);

    h = cast(0, 0.5f, 6, 0, 0, -1, INFINITY); /* the far face, from behind */
    near3(h.point, 0, 0.5f, 3.2f, EPS);
    near3(h.normal, 0, 0, 1, EPS);

    h = cast(-5, 0.5f, 3, 1, 0, 0, INFINITY); /* a side */
    near3(h.point, -2, 0.5f, 3, EPS);
    near3(h.normal, -1, 0, 0, EPS);

    assert_true(misses(0, 0.5f, 0, 0, 0, 1, 2.7f));  /* beyond max_distance */
    assert_false(misses(0, 0.5f, 0, 0, 0, 1, 2.8f)); /* exactly at it */
    assert_true(misses(0, 0.5f, 0, 0, 0, -1, INFINITY));
    assert_true(misses(0, 0.5f, 0, 0, 0, 0, INFINITY)); /* no direction */
    assert_true(misses(NAN, 0.5f, 0, 0, 0, 1, INFINITY));
    assert_true(misses(0, 0.5f, 0, 0, 0, 1, NAN));
}

static void test_raycast_ground(void **state)
{
    (void)state;
    mm_scene_init(&scene, 0.25f);
    mm_scene_hit h = cast(10, 2.25f, 0, 1, -1, 0, INFINITY);
    near3(h.point, 12, 0.25f, 0, EPS);
    near3(h.normal, 0, 1, 0, EPS);
    near1(h.distance, 2.0f * sqrtf(2.0f), EPS);
    assert_int_equal(h.box, -1);
    assert_false(h.inside);
    assert_true(misses(10, 2.25f, 0, 1, -1, 0, 2.8f));
    assert_true(misses(10, 2.25f, 0, 0, 1, 0, INFINITY)); /* up */
    assert_true(misses(10, 2.25f, 0, 1, 0, 0, INFINITY)); /* parallel to the ground */
    assert_true(misses(10, 0.25f, 0, 1, 0, 0, INFINITY)); /* along it, from on it */
    h = cast(0, 0, 0, 0, 0, 1, INFINITY);                 /* from below: inside the ground */
    assert_true(h.inside);
    assert_int_equal(h.box, -1);
    near1(h.distance, 0, 0);
    near3(h.normal, 0, 0, -1, 0);
    /* a box standing on the ground is reported before the ground at equal distance */
    add(0, 0.25f, 0, 2, 0, 2, 0); /* zero height: its top is the ground's plane */
    h = cast(0, 1.25f, 0, 0, -1, 0, INFINITY);
    assert_int_equal(h.box, 0);
    near1(h.distance, 1, EPS);
}

static void test_raycast_inside_and_grazing(void **state)
{
    (void)state;
    mm_scene_init(&scene, -10.0f);
    add(0, 0, 0, 2, 2, 2, 0); /* x [-1, 1], y [0, 2], z [-1, 1] */

    mm_scene_hit h = cast(0.5f, 1, 0, 0, 0, 1, INFINITY); /* from inside */
    assert_true(h.inside);
    assert_int_equal(h.box, 0);
    near1(h.distance, 0, 0);
    near3(h.point, 0.5f, 1, 0, 0);
    near3(h.normal, 0, 0, -1, 0);

    assert_true(misses(0, 1, 1, 0, 0, 1, INFINITY)); /* from the far face, leaving it */
    h = cast(0, 1, -1, 0, 0, 1, INFINITY);           /* from the near face, entering */
    assert_false(h.inside);
    near1(h.distance, 0, 0);
    near3(h.normal, 0, 0, -1, 0);

    /* parallel rays: along the top face (closed boxes: it hits), just above it (misses) */
    h = cast(-3, 2, 0, 1, 0, 0, INFINITY);
    near3(h.point, -1, 2, 0, EPS);
    near3(h.normal, -1, 0, 0, EPS);
    assert_true(misses(-3, 2.001f, 0, 1, 0, 0, INFINITY));
    assert_true(misses(-3, 1, 1.001f, 1, 0, 0, INFINITY));

    /* a diagonal ray that only touches the vertical edge at (1, y, -1) */
    h = cast(0, 1, -2, 1, 0, 1, INFINITY);
    near3(h.point, 1, 1, -1, EPS);
    near1(h.distance, sqrtf(2.0f), EPS);
    near3(h.normal, 0, 0, -1, EPS); /* at an edge: the face entered along z (x is entered earlier) */
    assert_true(misses(0, 1, -2.001f, 1, 0, 1, INFINITY));
    /* a ray through the corner (1, 2, -1) from above */
    h = cast(2, 3, -2, -1, -1, 1, INFINITY);
    near3(h.point, 1, 2, -1, EPS);
}

static void test_raycast_yawed(void **state)
{
    (void)state;
    mm_scene_init(&scene, 0.0f);
    add(0, 0, 0, 2, 1, 4, 90); /* local z (4 m) along world x: x [-2, 2], z [-1, 1] */
    mm_scene_hit h = cast(-5, 0.5f, 0, 1, 0, 0, INFINITY);
    near3(h.point, -2, 0.5f, 0, EPS);
    near3(h.normal, -1, 0, 0, EPS);
    near1(h.distance, 3, EPS);
    h = cast(0.5f, 0.5f, 5, 0, 0, -1, INFINITY);
    near3(h.point, 0.5f, 0.5f, 1, EPS);
    near3(h.normal, 0, 0, 1, EPS);

    mm_scene_init(&scene, 0.0f);
    add(0, 0, 0, 2, 1, 2, 45); /* a diamond: |x - z| <= sqrt 2, |x + z| <= sqrt 2 */
    float r2 = sqrtf(2.0f), s = sqrtf(0.5f);
    h = cast(-5, 0.5f, 0.2f, 1, 0, 0, INFINITY);
    near3(h.point, 0.2f - r2, 0.5f, 0.2f, EPS);
    near1(h.distance, 5.2f - r2, EPS);
    near3(h.normal, -s, 0, s, EPS);
    h = cast(-5, 0.5f, -0.2f, 1, 0, 0, INFINITY);
    near3(h.point, 0.2f - r2, 0.5f, -0.2f, EPS);
    near3(h.normal, -s, 0, -s, EPS);
    assert_true(misses(-5, 0.5f, r2 + 0.001f, 1, 0, 0, INFINITY)); /* beside the diamond's tip */
    h = cast(0.3f, 4, 0.3f, 0, -1, 0, INFINITY);
    near3(h.point, 0.3f, 1, 0.3f, EPS);
    near3(h.normal, 0, 1, 0, EPS);
}

static void test_raycast_nearest_of_many(void **state)
{
    (void)state;
    mm_scene_init(&scene, 0.0f);
    add(0, 0, 6, 1, 1, 1, 0);
    add(0, 0, 3, 1, 1, 1, 0);
    add(0, 0, 9, 1, 1, 1, 0);
    mm_scene_hit h = cast(0, 0.5f, 0, 0, 0, 1, INFINITY);
    assert_int_equal(h.box, 1);
    near1(h.distance, 2.5f, EPS);
    h = cast(0, 0.5f, 6, 0, 0, 1, INFINITY); /* inside box 0 */
    assert_int_equal(h.box, 0);
    assert_true(h.inside);
}

/* ---- ground probe ----------------------------------------------------------------------- */

static mm_scene_hit probe(float x, float y, float z, float step, float drop, int want_box, float want_height)
{
    mm_scene_hit h;
    memset(&h, 0, sizeof h);
    if (!mm_scene_ground_probe(&scene, mm_vec3_make(x, y, z), step, drop, &h))
        fail_msg("no ground under (%g %g %g)", x, y, z);
    assert_int_equal(h.box, want_box);
    near3(h.point, x, want_height, z, EPS);
    near3(h.normal, 0, 1, 0, 0);
    near1(h.distance, y - want_height, EPS);
    return h;
}

static void test_ground_probe_stacked(void **state)
{
    (void)state;
    mm_scene_init(&scene, 0.0f);
    add(0, 0, 0, 2, 1, 2, 0);    /* top 1 */
    add(0, 1, 0, 1, 0.5f, 1, 0); /* stacked on it: top 1.5 */
    add(10, 0, 0, 2, 1, 2, 45);  /* a diamond, top 1 */
    probe(0, 1.5f, 0, 0.3f, INFINITY, 1, 1.5f);
    probe(0, 1.2f, 0, 0.3f, INFINITY, 1, 1.5f); /* a step up */
    probe(0, 1.0f, 0, 0.3f, INFINITY, 0, 1.0f); /* the upper box is a wall from there */
    probe(0.8f, 1.4f, 0, 0.3f, INFINITY, 0, 1.0f);
    probe(0.5f, 1.5f, 0.5f, 0.3f, INFINITY, 1, 1.5f); /* on the corner: closed */
    probe(3, 0, 0, 0.3f, INFINITY, -1, 0);
    probe(3, 5, 0, 0.3f, INFINITY, -1, 0);
    assert_false(mm_scene_ground_probe(&scene, mm_vec3_make(0.8f, 2.0f, 0), 0.3f, 0.5f, NULL));
    assert_false(mm_scene_ground_probe(&scene, mm_vec3_make(3, 1, 0), 0.3f, 0.5f, NULL));
    assert_false(mm_scene_ground_probe(&scene, mm_vec3_make(3, -1, 0), 0.3f, 0.5f, NULL)); /* below */
    probe(11.2f, 2, 0, 0.3f, INFINITY, 2, 1);     /* inside the diamond's footprint */
    probe(11.3f, 2, 0.3f, 0.3f, INFINITY, -1, 0); /* inside its bounding square, outside it */
    assert_false(mm_scene_ground_probe(&scene, mm_vec3_make(NAN, 2, 0), 0.3f, 1, NULL));
}

/* ---- obstacle measure ------------------------------------------------------------------- */

static mm_obstacle measure(float fx, float fz, float dx, float dz, const mm_obstacle_desc *desc)
{
    mm_obstacle o;
    memset(&o, 0, sizeof o);
    if (!mm_scene_measure_obstacle(&scene, mm_vec3_make(fx, 0, fz), mm_vec3_make(dx, 0.3f, dz), desc, &o))
        fail_msg("no obstacle ahead of (%g 0 %g)", fx, fz);
    return o;
}

static void check_obstacle(const mm_obstacle *o, int box, float distance, float height, float depth)
{
    assert_int_equal(o->hit.box, box);
    near1(o->distance, distance, 1e-4f);
    near1(o->height, height, 1e-4f);
    near1(o->top, height, 1e-4f);
    near1(o->floor, 0, 1e-4f);
    near1(o->depth, depth, 1e-4f);
    assert_false(o->too_high);
    assert_false(o->too_deep);
}

static void test_obstacle_low_and_high(void **state)
{
    (void)state;
    static const float heights[] = {1.9f, 0.3f, 1.1f};
    mm_obstacle_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.probe_heights = heights;
    desc.probe_count = 3;
    for (int high = 0; high < 2; ++high) {
        float h = high ? 2.2f : 1.0f;
        /* the short side: a 4 x 0.4 wall across the way */
        mm_scene_init(&scene, 0.0f);
        add(0, 0, 3, 4, h, 0.4f, 0);
        mm_obstacle o = measure(0, 2, 0, 1, &desc);
        check_obstacle(&o, 0, 0.8f, h, 0.4f);
        assert_int_equal(o.probe, 1); /* the lowest of the rays that hit */
        near3(o.hit.normal, 0, 0, -1, EPS);
        near3(o.hit.point, 0, 0.3f, 2.8f, EPS);
        /* the long side: the same wall turned along the way (local x along world z) */
        mm_scene_init(&scene, 0.0f);
        add(0, 0, 4, 4, h, 0.4f, 90);
        o = measure(0, 1.2f, 0, 1, &desc);
        check_obstacle(&o, 0, 0.8f, h, 4.0f);
        /* approached at an angle: the depth is along the direction */
        o = measure(-0.8f, 1.2f, 0.5f, 1, &desc); /* crosses the 0.4 m width diagonally */
        near1(o.depth, 0.4f * sqrtf(1.25f) / 0.5f, 1e-4f);
        near1(o.height, h, 1e-4f);
    }
    /* default probes */
    mm_scene_init(&scene, 0.0f);
    add(0, 0, 3, 4, 1, 0.4f, 0);
    mm_obstacle o = measure(0, 2, 0, 1, NULL);
    check_obstacle(&o, 0, 0.8f, 1, 0.4f);
    assert_int_equal(o.probe, 0);
    /* nothing ahead: too far, sideways, behind */
    assert_false(mm_scene_measure_obstacle(&scene, mm_vec3_make(0, 0, 0), mm_vec3_make(0, 0, 1), NULL, NULL));
    assert_false(mm_scene_measure_obstacle(&scene, mm_vec3_make(0, 0, 2), mm_vec3_make(1, 0, 0), NULL, NULL));
    assert_false(
        mm_scene_measure_obstacle(&scene, mm_vec3_make(0, 0, 2), mm_vec3_make(0, 0, -1), NULL, NULL));
    assert_false(mm_scene_measure_obstacle(&scene, mm_vec3_make(0, 0, 2), mm_vec3_make(0, 1, 0), NULL, NULL));
    /* a probe list with no ray low enough misses a low box */
    static const float tall[] = {1.5f};
    desc.probe_heights = tall;
    desc.probe_count = 1;
    assert_false(
        mm_scene_measure_obstacle(&scene, mm_vec3_make(0, 0, 2), mm_vec3_make(0, 0, 1), &desc, NULL));
}

static void test_obstacle_limits_joined_and_stacked(void **state)
{
    (void)state;
    /* too high to see the top */
    mm_scene_init(&scene, 0.0f);
    add(0, 0, 3, 4, 2.2f, 0.4f, 0);
    mm_obstacle_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.max_height = 2.0f;
    mm_obstacle o = measure(0, 2, 0, 1, &desc);
    assert_true(o.too_high);
    near1(o.top, 2.0f, EPS);
    /* too deep */
    desc.max_height = 0;
    desc.max_depth = 0.25f;
    o = measure(0, 2, 0, 1, &desc);
    assert_true(o.too_deep);
    near1(o.depth, 0.25f, EPS);

    /* joined walls in a row: one obstacle; a gap ends it */
    mm_scene_init(&scene, 0.0f);
    add(0, 0, 3, 4, 1, 0.4f, 0);
    add(0, 0, 3.4f, 4, 1, 0.4f, 0);    /* touching */
    add(0, 0, 3.7f, 4, 0.8f, 0.4f, 0); /* overlapping, lower */
    add(0, 0, 4.5f, 4, 1, 0.4f, 0);    /* after a gap */
    o = measure(0, 2, 0, 1, NULL);
    near1(o.depth, 3.9f - 2.8f, 1e-4f);
    near1(o.height, 1, 1e-4f);

    /* a box on the obstacle raises its top; a box standing on a platform in front of it */
    mm_scene_init(&scene, 0.0f);
    add(0, 0, 3, 4, 1, 0.4f, 0);
    add(0, 1, 3, 1, 0.5f, 0.4f, 0);
    o = measure(0, 2, 0, 1, NULL);
    near1(o.top, 1.5f, 1e-4f);
    near1(o.height, 1.5f, 1e-4f);
    mm_scene_init(&scene, 0.0f);
    add(0, 0, 2, 4, 0.5f, 4, 0);    /* a platform, z [0, 4], top 0.5 */
    add(0, 0.5f, 3, 4, 1, 0.4f, 0); /* a wall on it */
    assert_true(mm_scene_measure_obstacle(&scene, mm_vec3_make(0, 0.5f, 2), mm_vec3_make(0, 0, 1), NULL, &o));
    near1(o.floor, 0.5f, 1e-4f);
    near1(o.top, 1.5f, 1e-4f);
    near1(o.height, 1.0f, 1e-4f);
    near1(o.distance, 0.8f, 1e-4f);
}

/* ---- boxes ------------------------------------------------------------------------------ */

static void test_add_box_limits(void **state)
{
    (void)state;
    mm_scene_init(&scene, 0.0f);
    mm_vec3 p = mm_vec3_make(0, 0, 0), one = mm_vec3_make(1, 1, 1);
    assert_int_equal(mm_scene_add_box(&scene, p, mm_vec3_make(1, -1, 1), 0), MM_ERR_OUT_OF_RANGE);
    assert_int_equal(mm_scene_add_box(&scene, mm_vec3_make(NAN, 0, 0), one, 0), MM_ERR_OUT_OF_RANGE);
    assert_int_equal(mm_scene_add_box(&scene, p, one, INFINITY), MM_ERR_OUT_OF_RANGE);
    assert_int_equal(mm_scene_add_box(&scene, mm_vec3_make(2e6f, 0, 0), one, 0), MM_ERR_OUT_OF_RANGE);
    assert_int_equal(scene.box_count, 0);
    for (int i = 0; i < MM_SCENE_MAX_BOXES; ++i) assert_int_equal(mm_scene_add_box(&scene, p, one, 0), MM_OK);
    assert_int_equal(mm_scene_add_box(&scene, p, one, 0), MM_ERR_LIMIT);
    assert_int_equal(mm_scene_add_box(NULL, p, one, 0), MM_ERR_INVALID_ARGUMENT);
}

/* ---- JSON ------------------------------------------------------------------------------- */

static void test_json_reads_every_field(void **state)
{
    (void)state;
    static const char text[] = "{\"ground\": -0.5, \"boxes\": [\n"
                               "  {\"position\": [1, -0.5, 2], \"size\": [2, 1, 0.4], \"yaw\": 90},\n"
                               "  {\"position\": [0, 0, 0], \"size\": [0, 0, 0]}]}";
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_scene_parse_json(text, sizeof text - 1, "s.json", &scene, &err), MM_OK);
    near1(scene.ground, -0.5f, 0);
    assert_int_equal(scene.box_count, 2);
    near3(scene.boxes[0].position, 1, -0.5f, 2, 0);
    near3(scene.boxes[0].size, 2, 1, 0.4f, 0);
    near1(scene.boxes[0].yaw, (float)(MM_PI / 2), 1e-7f);
    near1(scene.boxes[1].yaw, 0, 0);
    /* position is the bottom face's centre: the top is at -0.5 + 1 */
    mm_scene_hit h = cast(1, 3, 2, 0, -1, 0, INFINITY);
    near1(h.point.y, 0.5f, EPS);
    static const char empty[] = "{}";
    assert_int_equal(mm_scene_parse_json(empty, 2, "e.json", &scene, &err), MM_OK);
    assert_int_equal(scene.box_count, 0);
    near1(scene.ground, 0, 0);
}

static void expect_error(const char *text, mm_result code, const char *message)
{
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_result r = mm_scene_parse_json(text, strlen(text), "bad.json", &scene, &err);
    char formatted[600];
    mm_error_format(&err, formatted, sizeof formatted);
    if (r != code || strcmp(formatted, message) != 0)
        fail_msg("%s\n  got %s '%s'\n  want %s '%s'", text, mm_result_name(r), formatted,
                 mm_result_name(code), message);
    assert_int_equal(scene.box_count, 0); /* a failed parse leaves an empty scene */
}

static void test_json_errors(void **state)
{
    (void)state;
    expect_error("{\"grund\": 0}", MM_ERR_UNKNOWN_KEYWORD, "bad.json:1:11: grund: unknown field");
    expect_error("{\"ground\": 1e999}", MM_ERR_BAD_NUMBER, "bad.json:1:12: ground must be a finite number");
    expect_error("{\"ground\": \"0\"}", MM_ERR_BAD_NUMBER, "bad.json:1:12: ground must be a finite number");
    expect_error("[]", MM_ERR_SYNTAX, "bad.json:1:1: a scene is an object {\"ground\": 0, \"boxes\": [...]}");
    expect_error("{\"boxes\": {}}", MM_ERR_SYNTAX, "bad.json:1:11: boxes must be an array of objects");
    expect_error("{\"boxes\": [1]}", MM_ERR_SYNTAX, "bad.json:1:12: boxes[0] must be an object");
    expect_error("{\"boxes\": [{\"position\": [0, 0, 0], \"size\": [1, 1, 1]},\n"
                 " {\"position\": [0, 0, 0], \"size\": [1, -1, 1]}]}",
                 MM_ERR_OUT_OF_RANGE, "bad.json:2:38: boxes[1].size[1] must not be negative");
    expect_error("{\"boxes\": [{\"position\": [0, 0, 0], \"size\": [1, 1, 1], \"colour\": 1}]}",
                 MM_ERR_UNKNOWN_KEYWORD, "bad.json:1:65: boxes[0].colour: unknown field");
    expect_error("{\"boxes\": [{\"position\": [0, 0], \"size\": [1, 1, 1]}]}", MM_ERR_SYNTAX,
                 "bad.json:1:25: boxes[0].position must be an array of 3 numbers");
    expect_error("{\"boxes\": [{\"position\": [0, 0, \"a\"], \"size\": [1, 1, 1]}]}", MM_ERR_BAD_NUMBER,
                 "bad.json:1:32: boxes[0].position[2] must be a finite number");
    expect_error("{\"boxes\": [{\"position\": [0, 0, 0], \"size\": [1, 1, -1e999]}]}", MM_ERR_BAD_NUMBER,
                 "bad.json:1:51: boxes[0].size[2] must be a finite number");
    expect_error("{\"boxes\": [{\"position\": [1e7, 0, 0], \"size\": [1, 1, 1]}]}", MM_ERR_OUT_OF_RANGE,
                 "bad.json:1:26: boxes[0].position[0] is 1e+07 (at most 1e+06 in magnitude)");
    expect_error("{\"boxes\": [{\"position\": [0, 0, 0], \"size\": [1, 1, 1], \"yaw\": \"90\"}]}",
                 MM_ERR_BAD_NUMBER, "bad.json:1:62: boxes[0].yaw must be a finite number");
    expect_error("{\"boxes\": [{\"size\": [1, 1, 1]}]}", MM_ERR_SYNTAX,
                 "bad.json:1:12: boxes[0].position is missing");
    expect_error("{\"boxes\": [{\"position\": [0, 0, 0]}]}", MM_ERR_SYNTAX,
                 "bad.json:1:12: boxes[0].size is missing");
    expect_error("{\"ground\": 0,\n \"boxes\": [}", MM_ERR_SYNTAX, "bad.json:2:12: not valid JSON here");
    expect_error("", MM_ERR_UNEXPECTED_EOF, "bad.json: the scene is empty");
    /* strict JSON: a key given twice, text after the value, numbers as RFC 8259 writes them */
    expect_error("{\"ground\": 0,\n \"ground\": 1}", MM_ERR_DUPLICATE_NAME,
                 "bad.json:2:2: key 'ground' given twice (first at line 1, column 2)");
    expect_error("{\"ground\": 0} junk", MM_ERR_SYNTAX, "bad.json:1:15: text after the JSON value");
    expect_error("{\"ground\": 0}\n{}", MM_ERR_SYNTAX, "bad.json:2:1: text after the JSON value");
    expect_error("{\"ground\": +1}", MM_ERR_SYNTAX, "bad.json:1:12: not valid JSON here");
    expect_error("{\"ground\": 01}", MM_ERR_SYNTAX, "bad.json:1:12: not valid JSON here: not a JSON number");
    expect_error("{\"ground\": 1.}", MM_ERR_SYNTAX, "bad.json:1:12: not valid JSON here: not a JSON number");
    expect_error("{\"ground\":\f0}", MM_ERR_SYNTAX, "bad.json:1:11: not valid JSON here");

    /* too many boxes */
    char *text = malloc(64 * (MM_SCENE_MAX_BOXES + 2));
    assert_non_null(text);
    size_t n = (size_t)sprintf(text, "{\"boxes\": [");
    for (int i = 0; i <= MM_SCENE_MAX_BOXES; ++i)
        n += (size_t)sprintf(text + n, "%s{\"position\": [0, 0, 0], \"size\": [1, 1, 1]}", i ? "," : "");
    sprintf(text + n, "]}");
    expect_error(text, MM_ERR_LIMIT, "bad.json:1:11: boxes: 257 boxes (at most 256)");
    free(text);

    /* a missing file names the file */
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_not_equal(mm_scene_load_json(MM_TEST_OUT "/no_such_scene.json", &scene, &err), MM_OK);
    assert_non_null(strstr(err.file, "no_such_scene.json"));
}

static mm_scene again;

static void test_json_round_trip(void **state)
{
    (void)state;
    mm_scene_init(&scene, -0.125f);
    add(1.1f, -0.125f, 2.3f, 4, 1, 0.4f, 90);
    add(-3.7f, 0.5f, 1e-3f, 0.3f, 2.2f, 5, -33.3f);
    add(0, 0, 0, 0, 0, 0, 179.9f);
    const char *path = MM_TEST_OUT "/scene_round_trip.json";
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    assert_int_equal(mm_scene_write_json(&scene, f), MM_OK);
    fclose(f);
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_result r = mm_scene_load_json(path, &again, &err);
    if (r != MM_OK) fail_msg("%s: %s", err.file, err.message);
    assert_int_equal(again.box_count, 3);
    assert_true(again.ground == scene.ground);
    for (int i = 0; i < 3; ++i) {
        assert_memory_equal(&again.boxes[i].position, &scene.boxes[i].position, sizeof(mm_vec3));
        assert_memory_equal(&again.boxes[i].size, &scene.boxes[i].size, sizeof(mm_vec3));
        near1(again.boxes[i].yaw, scene.boxes[i].yaw, 0);
    }
    /* an empty scene too */
    mm_scene_init(&scene, 2);
    char *text = NULL;
    size_t size = 0;
    f = open_memstream(&text, &size);
    assert_non_null(f);
    assert_int_equal(mm_scene_write_json(&scene, f), MM_OK);
    fclose(f);
    assert_string_equal(text, "{\"ground\": 2, \"boxes\": []}\n");
    assert_int_equal(mm_scene_parse_json(text, size, "e.json", &again, &err), MM_OK);
    near1(again.ground, 2, 0);
    free(text);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_raycast_axis_aligned),
        cmocka_unit_test(test_raycast_ground),
        cmocka_unit_test(test_raycast_inside_and_grazing),
        cmocka_unit_test(test_raycast_yawed),
        cmocka_unit_test(test_raycast_nearest_of_many),
        cmocka_unit_test(test_ground_probe_stacked),
        cmocka_unit_test(test_obstacle_low_and_high),
        cmocka_unit_test(test_obstacle_limits_joined_and_stacked),
        cmocka_unit_test(test_add_box_limits),
        cmocka_unit_test(test_json_reads_every_field),
        cmocka_unit_test(test_json_errors),
        cmocka_unit_test(test_json_round_trip),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
