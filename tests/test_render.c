/* Rendering: the camera against hand-computed projections, the font and text layout, PNG files
 * decoded back, and headless frames whose pixels are checked against the geometry (a sphere
 * covers the disc its projection predicts, the character lies where its joints project, the
 * overlay's glyph pixels are where the font says, a scene box covers the hull of its projected
 * corners), and contact sheets (every pose whole in its tile at one scale, outlines, lines and
 * labels where the cameras put them). */
#include <math.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>

#include <mm/bvh.h>
#include <mm/character.h>
#include <mm/render.h>
#include <mm/skeleton_roles.h>
#include <mm/view.h>

#include "runtime/character/state.h"

#include "skeleton_variants.h"
#include "test_databases.h"
#include "test_util.h"

#define W 320
#define H 240

/* ---- camera ---- */

static mm_camera straight_camera(void)
{
    mm_camera c;
    mm_camera_defaults(&c);
    c.target = mm_vec3_make(0.0f, 1.0f, 0.0f);
    c.yaw = 0.0f;
    c.pitch = 0.0f;
    c.distance = 4.0f;
    return c;
}

static void test_camera_eye_and_center(void **state)
{
    (void)state;
    mm_camera c = straight_camera();
    mm_vec3 eye = mm_camera_eye(&c);
    assert_float_equal(eye.x, 0.0f, 1e-6f);
    assert_float_equal(eye.y, 1.0f, 1e-6f);
    assert_float_equal(eye.z, -4.0f, 1e-6f);
    c.yaw = 0.7f;
    c.pitch = 0.4f;
    eye = mm_camera_eye(&c);
    assert_float_equal(mm_vec3_distance(eye, c.target), 4.0f, 1e-5f);
    assert_float_equal(eye.y - c.target.y, 4.0f * sinf(0.4f), 1e-5f);
    float px = 0, py = 0;
    assert_true(mm_camera_project(&c, W, H, c.target, &px, &py));
    assert_float_equal(px, W / 2.0f, 1e-3f);
    assert_float_equal(py, H / 2.0f, 1e-3f);
    /* behind the eye: not projected */
    mm_vec3 behind = mm_vec3_add(eye, mm_vec3_sub(eye, c.target));
    assert_false(mm_camera_project(&c, W, H, behind, &px, &py));
}

static void test_camera_projection_by_hand(void **state)
{
    (void)state;
    mm_camera c = straight_camera();
    float f = 1.0f / tanf(0.5f * c.fov_y), aspect = (float)W / H, px, py;
    /* 0.5 m above the target, 4 m in front of the eye */
    assert_true(mm_camera_project(&c, W, H, mm_vec3_make(0.0f, 1.5f, 0.0f), &px, &py));
    assert_float_equal(px, W / 2.0f, 1e-3f);
    assert_float_equal(py, 0.5f * H * (1.0f - f * 0.5f / 4.0f), 1e-3f);
    /* looking along +Z, world -X is screen right */
    assert_true(mm_camera_project(&c, W, H, mm_vec3_make(-1.0f, 1.0f, 0.0f), &px, &py));
    assert_float_equal(px, 0.5f * W * (1.0f + f / aspect / 4.0f), 1e-3f);
    assert_float_equal(py, H / 2.0f, 1e-3f);
    /* the view matrix is a rotation plus translation: rows orthonormal, eye to the origin */
    float m[16];
    mm_camera_view_matrix(&c, m);
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) {
            float dot = m[a] * m[b] + m[4 + a] * m[4 + b] + m[8 + a] * m[8 + b];
            assert_float_equal(dot, a == b ? 1.0f : 0.0f, 1e-6f);
        }
    mm_vec3 e = mm_camera_eye(&c);
    for (int r = 0; r < 3; ++r)
        assert_float_equal(m[r] * e.x + m[4 + r] * e.y + m[8 + r] * e.z + m[12 + r], 0.0f, 1e-5f);
}

static void test_camera_follow_orbit_zoom(void **state)
{
    (void)state;
    mm_camera a = straight_camera(), b = straight_camera();
    mm_vec3 goal = mm_vec3_make(3.0f, 1.0f, -2.0f);
    mm_camera_follow(&a, goal, 0.5f, 0.1f);
    mm_camera_follow(&a, goal, 0.5f, 0.1f);
    mm_camera_follow(&b, goal, 0.5f, 0.2f);
    assert_float_equal(a.target.x, b.target.x, 1e-5f);
    assert_float_equal(a.target.z, b.target.z, 1e-5f);
    mm_camera h = straight_camera();
    mm_camera_follow(&h, goal, 0.5f, 0.5f); /* one half-life: half way */
    assert_float_equal(h.target.x, 1.5f, 1e-5f);
    assert_float_equal(h.target.z, -1.0f, 1e-5f);
    mm_camera_follow(&h, mm_vec3_make(NAN, 0, 0), 0.5f, 0.1f);
    assert_float_equal(h.target.x, 1.5f, 1e-6f);
    mm_camera_follow(&h, goal, 0.0f, 0.1f);
    assert_float_equal(h.target.x, 3.0f, 0.0f);
    mm_camera_orbit(&h, 0.0f, 10.0f);
    assert_float_equal(h.pitch, 1.5f, 0.0f);
    mm_camera_orbit(&h, NAN, -10.0f);
    assert_float_equal(h.pitch, -0.2f, 0.0f);
    mm_camera_zoom(&h, 1000.0f);
    assert_float_equal(h.distance, 50.0f, 0.0f);
    mm_camera_zoom(&h, -1.0f);
    assert_float_equal(h.distance, 50.0f, 0.0f);
    mm_camera_zoom(&h, 1e-6f);
    assert_float_equal(h.distance, 0.5f, 0.0f);
}

/* ---- input mapping ---- */

static void test_view_input_follows_the_camera(void **state)
{
    (void)state;
    mm_view_keys k;
    memset(&k, 0, sizeof k);
    mm_input in;
    k.forward = true;
    mm_view_input(&k, 0.0f, &in);
    assert_float_equal(in.stick[0], 0.0f, 1e-6f);
    assert_float_equal(in.stick[1], 1.0f, 1e-6f);
    assert_int_equal(in.gait, MM_GAIT_WALK);
    assert_false(in.strafe);
    /* "right" moves toward the screen's right, whatever the yaw */
    for (int i = 0; i < 8; ++i) {
        mm_camera c = straight_camera();
        c.yaw = -3.0f + 0.8f * (float)i;
        memset(&k, 0, sizeof k);
        k.right = true;
        mm_view_input(&k, c.yaw, &in);
        float px, py;
        mm_vec3 p = mm_vec3_add(c.target, mm_vec3_make(in.stick[0], 0.0f, in.stick[1]));
        assert_true(mm_camera_project(&c, W, H, p, &px, &py));
        assert_true(px > W / 2.0f + 10.0f);
        assert_float_equal(py, H / 2.0f, 1e-2f);
        /* and forward goes away from the camera: the point gets farther from the eye */
        k.right = false;
        k.forward = true;
        mm_view_input(&k, c.yaw, &in);
        mm_vec3 eye = mm_camera_eye(&c),
                ahead = mm_vec3_add(c.target, mm_vec3_make(in.stick[0], 0.0f, in.stick[1]));
        assert_true(mm_vec3_distance(eye, ahead) > mm_vec3_distance(eye, c.target) + 0.9f);
    }
    /* a diagonal is a unit stick; running and strafing */
    memset(&k, 0, sizeof k);
    k.forward = k.left = k.run = k.strafe = true;
    mm_view_input(&k, 1.0f, &in);
    assert_float_equal(hypotf(in.stick[0], in.stick[1]), 1.0f, 1e-6f);
    assert_int_equal(in.gait, MM_GAIT_RUN);
    assert_true(in.strafe && in.has_facing);
    assert_float_equal(in.facing[0], sinf(1.0f), 1e-6f);
    assert_float_equal(in.facing[1], cosf(1.0f), 1e-6f);
    /* gamepad: inside the dead zone nothing, full tilt a unit stick, NaN ignored */
    memset(&k, 0, sizeof k);
    k.pad_stick[1] = 0.1f;
    mm_view_input(&k, 0.0f, &in);
    assert_float_equal(hypotf(in.stick[0], in.stick[1]), 0.0f, 0.0f);
    k.pad_stick[1] = 1.0f;
    mm_view_input(&k, 0.0f, &in);
    assert_float_equal(in.stick[1], 1.0f, 1e-6f);
    k.pad_stick[1] = 0.575f; /* half way between the dead zone and full tilt */
    mm_view_input(&k, 0.0f, &in);
    assert_float_equal(in.stick[1], 0.5f, 1e-5f);
    k.pad_stick[0] = NAN;
    k.pad_stick[1] = INFINITY;
    k.back = true;
    mm_view_input(&k, 0.0f, &in);
    assert_float_equal(in.stick[1], -1.0f, 1e-6f);
}

/* ---- font and text ---- */

static void test_text_measure_and_font(void **state)
{
    (void)state;
    int w = -1, h = -1;
    mm_text_measure("ab\ncde", &w, &h);
    assert_int_equal(w, 3 * 12);
    assert_int_equal(h, 2 * 18);
    mm_text_measure("", &w, &h);
    assert_int_equal(w, 0);
    assert_int_equal(h, 0);
    mm_text_measure(NULL, &w, &h);
    assert_int_equal(w + h, 0);
}

/* ---- PNG ---- */

static uint32_t get32(const unsigned char *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

/* Decodes an 8-bit RGB PNG written with filters none or up (what mm writes); returns malloc'd
 * pixels or NULL. Checks every chunk's CRC. */
static unsigned char *decode_png(const char *path, int *w, int *h)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    static unsigned char file[1 << 20];
    size_t n = fread(file, 1, sizeof file, f);
    fclose(f);
    if (n < 8 || memcmp(file, "\x89PNG\r\n\x1a\n", 8) != 0) return NULL;
    unsigned char *z = malloc(n);
    size_t zn = 0, at = 8;
    while (at + 12 <= n) {
        uint32_t len = get32(file + at);
        if (at + 12 + len > n) break;
        if ((uint32_t)crc32(0L, file + at + 4, len + 4) != get32(file + at + 8 + len)) return NULL;
        if (memcmp(file + at + 4, "IHDR", 4) == 0) {
            *w = (int)get32(file + at + 8);
            *h = (int)get32(file + at + 12);
            if (file[at + 16] != 8 || file[at + 17] != 2) return NULL;
        } else if (memcmp(file + at + 4, "IDAT", 4) == 0) {
            memcpy(z + zn, file + at + 8, len);
            zn += len;
        }
        at += 12 + len;
    }
    size_t stride = (size_t)*w * 3;
    uLongf raw_n = (uLongf)((stride + 1) * (size_t)*h);
    unsigned char *raw = malloc(raw_n), *rgb = malloc(stride * (size_t)*h);
    if (uncompress(raw, &raw_n, z, (uLong)zn) != Z_OK) return NULL;
    for (int y = 0; y < *h; ++y) {
        const unsigned char *row = raw + (size_t)y * (stride + 1);
        for (size_t i = 0; i < stride; ++i) {
            unsigned char above = y > 0 ? rgb[(size_t)(y - 1) * stride + i] : 0;
            rgb[(size_t)y * stride + i] = row[0] == 2 ? (unsigned char)(row[1 + i] + above) : row[1 + i];
        }
    }
    free(z);
    free(raw);
    return rgb;
}

static void test_png_round_trip(void **state)
{
    (void)state;
    enum { PW = 37, PH = 23 };
    unsigned char img[PW * PH * 3];
    for (int i = 0; i < PW * PH * 3; ++i) img[i] = (unsigned char)(i * 7 + (i / 97) * 13);
    char path[1024];
    snprintf(path, sizeof path, "%s/render_round_trip.png", MM_TEST_OUT);
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_png_write(path, img, PW, PH, &err), MM_OK);
    int w = 0, h = 0;
    unsigned char *back = decode_png(path, &w, &h);
    assert_non_null(back);
    assert_int_equal(w, PW);
    assert_int_equal(h, PH);
    assert_memory_equal(back, img, sizeof img);
    free(back);
    assert_int_equal(mm_png_write(path, img, 0, PH, &err), MM_ERR_INVALID_ARGUMENT);
    char bad[1100];
    snprintf(bad, sizeof bad, "%s/no/such/folder/x.png", MM_TEST_OUT);
    assert_int_equal(mm_png_write(bad, img, PW, PH, &err), MM_ERR_IO);
    assert_string_equal(err.file, bad);
}

/* ---- headless frames ---- */

static mm_offscreen *offscreen;
static const unsigned char background[3] = {204, 214, 224}; /* the renderer's sky (0.80, 0.84, 0.88) */

static int is_background(const uint8_t *rgb, int x, int y)
{
    const uint8_t *p = rgb + ((size_t)y * W + (size_t)x) * 3;
    return abs(p[0] - background[0]) <= 2 && abs(p[1] - background[1]) <= 2 && abs(p[2] - background[2]) <= 2;
}

/* Nothing to draw, not even the ground: each test adds what it measures. */
static mm_render_scene empty_scene(void)
{
    mm_render_scene s;
    memset(&s, 0, sizeof s);
    s.no_ground = true;
    return s;
}

static void test_sphere_covers_its_projected_disc(void **state)
{
    (void)state;
    mm_camera c = straight_camera();
    mm_render_marker m = {c.target, 0.3f, {0.9f, 0.2f, 0.1f, 1.0f}};
    mm_render_scene s = empty_scene();
    s.markers = &m;
    s.marker_count = 1;
    const uint8_t *rgb = mm_offscreen_render(offscreen, &c, &s);
    assert_non_null(rgb);
    double count = 0, sx = 0, sy = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            if (!is_background(rgb, x, y)) {
                ++count;
                sx += x + 0.5;
                sy += y + 0.5;
            }
    /* a sphere of radius r at distance d is seen under the half-angle asin(r / d) */
    double half = asin(0.3 / 4.0), radius_px = 0.5 * H * tan(half) / tan(0.5 * c.fov_y);
    double expected = MM_PI * radius_px * radius_px;
    assert_true(fabs(count - expected) < 0.05 * expected);
    assert_float_equal(sx / count, W / 2.0, 0.5);
    assert_float_equal(sy / count, H / 2.0, 0.5);
}

/* A character on the built-in set's database, and its searcher (kept in place: the character
 * points at both). */
typedef struct synth_character {
    mm_database db;
    mm_searcher searcher;
    mm_character ch;
} synth_character;

static void synth_character_init(synth_character *fx)
{
    assert_int_equal(test_build_synth_database(&fx->db), 0);
    assert_int_equal(mm_searcher_init(&fx->searcher, &fx->db, NULL, NULL), MM_OK);
    assert_int_equal(mm_character_init(&fx->ch, &fx->db, &fx->searcher, NULL, NULL), MM_OK);
}

static void synth_character_free(synth_character *fx)
{
    mm_character_free(&fx->ch);
    mm_searcher_free(&fx->searcher);
    mm_database_free(&fx->db);
}

static void test_character_lies_where_its_joints_project(void **state)
{
    (void)state;
    synth_character fx;
    synth_character_init(&fx);
    mm_input in;
    memset(&in, 0, sizeof in);
    in.stick[1] = 1.0f;
    for (int i = 0; i < 90; ++i) mm_character_update(&fx.ch, &in, 1.0f / 60.0f);
    mm_view v;
    assert_int_equal(mm_view_init(&v, &fx.db, NULL), MM_OK);
    mm_view_flags flags;
    memset(&flags, 0, sizeof flags); /* the body alone */
    mm_view_update(&v, &fx.ch, &in, &flags, 0.0f);
    v.scene.no_ground = true;
    mm_camera c;
    mm_camera_defaults(&c);
    c.target = mm_vec3_make(fx.ch.root.translation.x, 0.9f, fx.ch.root.translation.z);
    const uint8_t *rgb = mm_offscreen_render(offscreen, &c, &v.scene);
    assert_non_null(rgb);
    /* the bounding box of the projected joints, grown by the largest projected sphere radius */
    float x0 = 1e9f, y0 = 1e9f, x1 = -1e9f, y1 = -1e9f, px, py;
    for (int j = 1; j < fx.db.joint_count; ++j) {
        assert_true(mm_camera_project(&c, W, H, fx.ch.global[j].translation, &px, &py));
        x0 = fminf(x0, px), y0 = fminf(y0, py), x1 = fmaxf(x1, px), y1 = fmaxf(y1, py);
    }
    /* the largest sphere is the head's, 0.1 m, at least 1.5 m from the eye */
    float grow = 0.5f * H * (0.1f / 1.5f) / tanf(0.5f * c.fov_y) + 1.0f;
    int inside = 0, outside = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            if (is_background(rgb, x, y)) continue;
            if (x + 0.5f >= x0 - grow && x + 0.5f <= x1 + grow && y + 0.5f >= y0 - grow &&
                y + 0.5f <= y1 + grow)
                ++inside;
            else
                ++outside;
        }
    assert_int_equal(outside, 0);
    assert_true(inside > 300); /* a body, not a few stray pixels */
    /* the hips (joint 1) are drawn where they project */
    assert_true(mm_camera_project(&c, W, H, fx.ch.global[1].translation, &px, &py));
    assert_false(is_background(rgb, (int)px, (int)py));
    /* with the ground: the bottom centre is ground, lit grey, not sky */
    v.scene.no_ground = false;
    rgb = mm_offscreen_render(offscreen, &c, &v.scene);
    assert_false(is_background(rgb, W / 2, H - 2));
    mm_view_free(&v);
    synth_character_free(&fx);
}

/* ---- the body ---- */

static mm_vec3 lerp3(mm_vec3 a, mm_vec3 b, float t) { return mm_vec3_lerp(a, b, t); }

static bool projected_background(const mm_camera *c, const uint8_t *rgb, mm_vec3 p)
{
    float px, py;
    assert_true(mm_camera_project(c, W, H, p, &px, &py));
    assert_true(px >= 0.0f && px < W && py >= 0.0f && py < H);
    return is_background(rgb, (int)px, (int)py);
}

/* The body of a pose seen from its front, turned 30 degrees, level with the waist: its pixels
 * cover the projected hips, head, hands and feet; the waist is as wide as a body (the capsules'
 * spine is not); the image a metre to either side is empty; and it covers much more of the image
 * than the capsule figure. */
static void check_body_pixels(const mm_body_mesh *body, const mm_body_roles *roles, const int *parents, int n,
                              const mm_xform *global, int first_joint)
{
    mm_render_scene s = empty_scene();
    s.joint_count = n;
    s.parents = parents;
    s.global = global;
    s.first_joint = first_joint;
    s.body_mesh = body;
    float facing = mm_body_facing(roles, parents, n, global, 0.0f);
    mm_vec3 hips = global[roles->hips].translation, head = global[roles->head].translation;
    mm_camera c;
    mm_camera_defaults(&c);
    c.target = lerp3(hips, head, 0.25f);
    c.yaw = facing + (float)MM_PI + 0.5f; /* the eye in front */
    c.pitch = 0.15f;
    c.distance = 3.4f;
    uint8_t *with = malloc((size_t)W * H * 3), *without = malloc((size_t)W * H * 3);
    assert_non_null(with);
    assert_non_null(without);
    const uint8_t *rgb = mm_offscreen_render(offscreen, &c, &s);
    assert_non_null(rgb);
    memcpy(with, rgb, (size_t)W * H * 3);
    s.body_mesh = NULL;
    rgb = mm_offscreen_render(offscreen, &c, &s);
    assert_non_null(rgb);
    memcpy(without, rgb, (size_t)W * H * 3);
    int joints[7] = {roles->hips,    roles->head, roles->hand[0], roles->hand[1], roles->foot[0],
                     roles->foot[1], -1};
    for (int i = 0; i < 6; ++i)
        if (joints[i] >= 0) assert_false(projected_background(&c, with, global[joints[i]].translation));
    /* the waist, 11 cm either side of the spine: a body's (half width 0.13 m for a 1.75 m adult) */
    mm_vec3 left = mm_vec3_make(cosf(facing), 0.0f, -sinf(facing)); /* left = up x forward */
    float leg = mm_vec3_distance(hips, global[roles->foot[0]].translation);
    mm_vec3 waist = lerp3(hips, head, 0.25f);
    for (int side = -1; side <= 1; side += 2) {
        mm_vec3 p = mm_vec3_add(waist, mm_vec3_scale(left, (float)side * 0.11f * leg / 0.9f));
        assert_false(projected_background(&c, with, p));
        assert_true(projected_background(&c, without, p));
        /* a metre beside the body: nothing */
        mm_vec3 far = mm_vec3_add(waist, mm_vec3_scale(left, (float)side * 1.0f));
        assert_true(projected_background(&c, with, far));
    }
    int body_pixels = 0, capsule_pixels = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            body_pixels += !is_background(with, x, y);
            capsule_pixels += !is_background(without, x, y);
        }
    assert_true(body_pixels > 1.6 * capsule_pixels); /* about 2 on the built-in set and the takes */
    free(with);
    free(without);
}

/* The built-in set's character through its view (the body made from the database's roles). */
static void test_body_of_the_built_in_set(void **state)
{
    (void)state;
    synth_character fx;
    synth_character_init(&fx);
    mm_input in;
    memset(&in, 0, sizeof in);
    in.stick[1] = 1.0f;
    for (int i = 0; i < 50; ++i) mm_character_update(&fx.ch, &in, 1.0f / 60.0f);
    mm_view v;
    assert_int_equal(mm_view_init(&v, &fx.db, NULL), MM_OK);
    assert_true(v.body.vertex_count > 1000);
    mm_view_flags flags;
    memset(&flags, 0, sizeof flags);
    mm_view_update(&v, &fx.ch, &in, &flags, 0.0f);
    assert_ptr_equal(v.scene.body_mesh, &v.body);
    mm_body_roles roles;
    mm_body_roles_from_database(&fx.db, &roles);
    check_body_pixels(&v.body, &roles, v.parents, fx.db.joint_count, fx.ch.global, 1);
    /* a user's body in its place, and back */
    mm_body_mesh other;
    memset(&other, 0, sizeof other);
    mm_view_set_body(&v, &other);
    mm_view_update(&v, &fx.ch, &in, &flags, 0.0f);
    assert_ptr_equal(v.scene.body_mesh, &other);
    mm_view_set_body(&v, NULL);
    mm_view_update(&v, &fx.ch, &in, &flags, 0.0f);
    assert_ptr_equal(v.scene.body_mesh, &v.body);
    mm_view_free(&v);
    synth_character_free(&fx);
}

/* A shared take (skipped without MM_DATA_DIR): its roles found from the motion, its joints renamed
 * to say nothing first (the body is found from the roles, never the names). */
static void body_of_a_take(const char *relative, float at_seconds)
{
    char path[1024];
    if (!test_shared_data(relative, path, sizeof path)) skip();
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_bvh bvh;
    assert_int_equal(mm_bvh_load(path, NULL, &bvh, &err), MM_OK);
    mm_bvh_import_desc imp;
    memset(&imp, 0, sizeof imp);
    imp.auto_scale = true;
    mm_clip clip;
    assert_int_equal(mm_bvh_to_clip(&bvh, &imp, &clip, &err), MM_OK);
    mm_bvh_free(&bvh);
    int n = clip.skeleton.joint_count;
    for (int j = 0; j < n; ++j) snprintf(clip.skeleton.joints[j].name, MM_NAME_MAX, "j%d", j);
    mm_skeleton_roles found;
    assert_int_equal(mm_skeleton_roles_find(&clip, 1, &found, &err), MM_OK);
    mm_body_roles roles;
    roles.hips = found.roles[MM_BODY_HIPS].joint;
    roles.head = found.roles[MM_BODY_HEAD].joint;
    for (int k = 0; k < 2; ++k) {
        roles.foot[k] = found.roles[k ? MM_BODY_RIGHT_FOOT : MM_BODY_LEFT_FOOT].joint;
        roles.toe[k] = found.roles[k ? MM_BODY_RIGHT_TOE : MM_BODY_LEFT_TOE].joint;
        roles.hand[k] = found.roles[k ? MM_BODY_RIGHT_HAND : MM_BODY_LEFT_HAND].joint;
    }
    enum { POSES = 32 };
    int *parents = malloc(sizeof(int) * (size_t)n);
    mm_xform *poses = malloc(sizeof(mm_xform) * (size_t)n * POSES),
             *now = malloc(sizeof(mm_xform) * (size_t)n);
    mm_quat *rot = malloc(sizeof(mm_quat) * (size_t)n);
    mm_vec3 *pos = malloc(sizeof(mm_vec3) * (size_t)n);
    for (int j = 0; j < n; ++j) parents[j] = clip.skeleton.joints[j].parent;
    double duration = mm_clip_duration(&clip);
    for (int i = 0; i < POSES; ++i) {
        mm_clip_sample(&clip, (float)(duration * i / (POSES - 1)), rot, pos);
        mm_fk(&clip.skeleton, rot, pos, poses + (size_t)i * (size_t)n);
    }
    mm_body_desc d;
    memset(&d, 0, sizeof d);
    d.joint_count = n;
    d.parents = parents;
    d.poses = poses;
    d.pose_count = POSES;
    d.roles = roles;
    mm_body_mesh body;
    assert_int_equal(mm_body_mesh_build(&d, &body, &err), MM_OK);
    mm_clip_sample(&clip, (float)fmin(at_seconds, duration), rot, pos);
    mm_fk(&clip.skeleton, rot, pos, now);
    check_body_pixels(&body, &roles, parents, n, now, 0);
    mm_body_mesh_free(&body);
    free(parents);
    free(poses);
    free(now);
    free(rot);
    free(pos);
    mm_clip_free(&clip);
}

static void test_body_of_lafan1(void **state)
{
    (void)state;
    body_of_a_take("lafan1/multipleActions1_subject1.bvh", 11.5f);
}

static void test_body_of_games105(void **state)
{
    (void)state;
    body_of_a_take("games105/walk_and_turn_left.bvh", 1.5f);
}

static void test_body_of_pfnn(void **state)
{
    (void)state;
    body_of_a_take("pfnn/bvh/LocomotionFlat09_000.bvh", 2.5f);
}

/* The body a clip's skeleton makes (roles found from its motion unless given), bound to one of 16
 * of its poses, skinned at time t into out (vertex_count returned). */
static int clip_body_at(const mm_clip *clip, const mm_body_roles *given, float t, mm_vec3 *out, int capacity,
                        mm_body_roles *roles_out)
{
    enum { POSES = 16 };
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_body_roles roles;
    if (given) {
        roles = *given;
    } else {
        mm_skeleton_roles found;
        assert_int_equal(mm_skeleton_roles_find(clip, 1, &found, &err), MM_OK);
        roles.hips = found.roles[MM_BODY_HIPS].joint;
        roles.head = found.roles[MM_BODY_HEAD].joint;
        for (int k = 0; k < 2; ++k) {
            roles.foot[k] = found.roles[k ? MM_BODY_RIGHT_FOOT : MM_BODY_LEFT_FOOT].joint;
            roles.toe[k] = found.roles[k ? MM_BODY_RIGHT_TOE : MM_BODY_LEFT_TOE].joint;
            roles.hand[k] = found.roles[k ? MM_BODY_RIGHT_HAND : MM_BODY_LEFT_HAND].joint;
        }
    }
    if (roles_out) *roles_out = roles;
    int n = clip->skeleton.joint_count;
    int *par = malloc(sizeof(int) * (size_t)n);
    mm_xform *poses = malloc(sizeof(mm_xform) * (size_t)n * POSES),
             *now = malloc(sizeof(mm_xform) * (size_t)n);
    mm_quat *rot = malloc(sizeof(mm_quat) * (size_t)n);
    mm_vec3 *pos = malloc(sizeof(mm_vec3) * (size_t)n);
    assert_true(par && poses && now && rot && pos);
    for (int j = 0; j < n; ++j) par[j] = clip->skeleton.joints[j].parent;
    double duration = mm_clip_duration(clip);
    for (int i = 0; i < POSES; ++i) {
        mm_clip_sample(clip, (float)(duration * i / (POSES - 1)), rot, pos);
        mm_fk(&clip->skeleton, rot, pos, poses + (size_t)i * (size_t)n);
    }
    mm_body_desc d;
    memset(&d, 0, sizeof d);
    d.joint_count = n;
    d.parents = par;
    d.poses = poses;
    d.pose_count = POSES;
    d.roles = roles;
    mm_body_mesh body;
    assert_int_equal(mm_body_mesh_build(&d, &body, &err), MM_OK);
    assert_true(body.vertex_count <= capacity);
    mm_clip_sample(clip, t, rot, pos);
    mm_fk(&clip->skeleton, rot, pos, now);
    mm_body_mesh_skin(&body, now, out, NULL);
    int count = body.vertex_count;
    mm_body_mesh_free(&body);
    free(par);
    free(poses);
    free(now);
    free(rot);
    free(pos);
    return count;
}

/* One body whatever the skeleton says beside the motion: joints renamed to another convention, the
 * rest frames turned, a root added on the ground that carries the travel and turns, centimetres
 * (the body 100 times larger, point for point). */
static void test_body_of_skeleton_variants(void **state)
{
    (void)state;
    mm_synth_desc sd;
    memset(&sd, 0, sizeof sd);
    mm_synth_set set;
    mm_error err;
    assert_int_equal(mm_synth_generate(&sd, &set, &err), MM_OK);
    const mm_clip *walk = NULL;
    for (int i = 0; i < set.clip_count && !walk; ++i)
        if (strcmp(set.clips[i].name, "walk_1.40") == 0) walk = &set.clips[i].clip;
    assert_non_null(walk);
    enum { CAPACITY = 20000 };
    mm_vec3 *base = malloc(sizeof(mm_vec3) * CAPACITY), *other = malloc(sizeof(mm_vec3) * CAPACITY);
    assert_true(base && other);
    const float t = 0.7f;
    mm_body_roles roles;
    int n = clip_body_at(walk, NULL, t, base, CAPACITY, &roles);
    for (int k = 0; k < 4; ++k) {
        sv_variant v;
        const char *what = k == 0   ? "renamed"
                           : k == 1 ? "rest axes"
                           : k == 2 ? "root on the ground"
                                    : "centimetres";
        if (k == 0) sv_rename(walk, SV_NAMES_SUFFIX_LR, &v);
        if (k == 1) sv_rest_axes(walk, 2, &v);
        if (k == 2) sv_reroot(walk, SV_ROOT_YAW, &v);
        if (k == 3) sv_units(walk, 0.01, &v);
        float unit = k == 3 ? 100.0f : 1.0f;
        /* centimetres: the roles finder reads metres; the joints are the same ones */
        int m = clip_body_at(&v.clip, k == 3 ? &roles : NULL, t, other, CAPACITY, NULL);
        assert_int_equal(m, n);
        float worst = 0.0f;
        for (int i = 0; i < n; ++i)
            worst = fmaxf(worst, mm_vec3_distance(mm_vec3_scale(other[i], 1.0f / unit), base[i]));
        if (worst > 1e-3f) print_error("%s: the body moved by %.4f m\n", what, worst);
        assert_true(worst <= 1e-3f);
        sv_free(&v);
    }
    free(base);
    free(other);
    mm_synth_set_free(&set);
}

static void test_overlay_is_drawn_where_placed(void **state)
{
    (void)state;
    /* a capsule figure standing at the top left of the image: the text goes elsewhere */
    mm_xform pose[3];
    int par[3] = {-1, 0, 1};
    pose[0] = mm_xform_make(mm_quat_identity(), mm_vec3_make(0, 0.1f, 0));
    pose[1] = mm_xform_make(mm_quat_identity(), mm_vec3_make(0, 0.9f, 0));
    pose[2] = mm_xform_make(mm_quat_identity(), mm_vec3_make(0, 1.7f, 0));
    mm_render_scene s = empty_scene();
    s.joint_count = 3;
    s.parents = par;
    s.global = pose;
    s.overlay = "0123456789\nABCDEFGHIJ";
    mm_camera c = straight_camera();
    c.target = mm_vec3_make(-1.1f, 0.4f, 0.0f); /* the figure left of and above the centre (+X is left) */
    mm_overlay_place o;
    mm_render_overlay_place(&c, W, H, &s, &o);
    float box[4];
    assert_true(mm_render_character_box(&c, W, H, &s, box));
    assert_true(box[0] < W / 2 && box[1] < 20.0f); /* it does reach the top left corner */
    assert_false(o.x == 8 && o.y == 8);
    assert_false(o.x < box[2] && o.x + o.width > box[0] && o.y < box[3] && o.y + o.height > box[1]);
    const uint8_t *rgb = mm_offscreen_render(offscreen, &c, &s);
    assert_non_null(rgb);
    /* the panel darkens its top left cell's first pixel (a space in no glyph: '0' starts dark) */
    assert_false(is_background(rgb, o.x, o.y));
    assert_false(is_background(rgb, o.x + o.width - 1, o.y + o.height - 1));
    assert_true(is_background(rgb, 8, 8) || box[0] < 9.0f);
}

static void test_overlay_glyph_pixels(void **state)
{
    (void)state;
    mm_camera c = straight_camera();
    mm_render_scene s = empty_scene();
    s.overlay = "A";
    const uint8_t *rgb = mm_offscreen_render(offscreen, &c, &s);
    assert_non_null(rgb);
    /* 'A' row 0 is .###. and row 3 is #####: at 2x from the 8-pixel margin */
    const uint8_t *on = rgb + ((size_t)(8 + 1) * W + (size_t)(8 + 2 * 1 + 1)) * 3;   /* (1, 0) */
    const uint8_t *off = rgb + ((size_t)(8 + 1) * W + (size_t)(8 + 2 * 0 + 1)) * 3;  /* (0, 0) */
    const uint8_t *bar = rgb + ((size_t)(8 + 7) * W + (size_t)(8 + 2 * 0 + 1)) * 3;  /* (0, 3) */
    const uint8_t *gap = rgb + ((size_t)(8 + 15) * W + (size_t)(8 + 2 * 2 + 1)) * 3; /* (2, 7): spacing */
    assert_int_equal(on[0], 255);
    assert_int_equal(bar[1], 255);
    /* the dark panel: 0.55 of (0.05, 0.06, 0.08) over the background */
    int expect = (int)lround(255.0 * (0.45 * 0.80 + 0.55 * 0.05));
    assert_true(abs(off[0] - expect) <= 2);
    assert_true(abs(gap[0] - expect) <= 2);
    /* outside the one-character panel: background */
    assert_true(is_background(rgb, 8 + 12 + 2, 10));
}

static void test_video_folder_and_errors(void **state)
{
    (void)state;
    char dir[1024];
    snprintf(dir, sizeof dir, "%s/render_frames", MM_TEST_OUT);
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_video *v = NULL;
    assert_int_equal(mm_video_open(dir, W, H, 30.0f, &v, &err), MM_OK);
    unsigned char img[W * H * 3];
    memset(img, 100, sizeof img);
    for (int i = 0; i < 3; ++i) assert_int_equal(mm_video_write(v, img, &err), MM_OK);
    int frames = 0;
    assert_int_equal(mm_video_close(v, false, &frames, &err), MM_OK);
    assert_int_equal(frames, 3);
    char path[1100];
    struct stat st;
    snprintf(path, sizeof path, "%s/frame_00002.png", dir);
    assert_int_equal(stat(path, &st), 0);
    /* errors */
    assert_int_equal(mm_video_open(dir, W, H, 0.0f, &v, &err), MM_ERR_OUT_OF_RANGE);
    assert_int_equal(mm_video_open("odd.mp4", 321, 240, 30.0f, &v, &err), MM_ERR_OUT_OF_RANGE);
    assert_int_equal(mm_video_open(path, W, H, 30.0f, &v, &err), MM_ERR_IO); /* a file, not a folder */
    assert_string_equal(err.file, path);
    /* an MP4 through ffmpeg, when installed; aborting leaves nothing behind */
    if (!mm_video_encoder_available()) return;
    snprintf(path, sizeof path, "%s/render_test.mp4", MM_TEST_OUT);
    remove(path);
    assert_int_equal(mm_video_open(path, W, H, 30.0f, &v, &err), MM_OK);
    for (int i = 0; i < 5; ++i) assert_int_equal(mm_video_write(v, img, &err), MM_OK);
    assert_int_equal(mm_video_close(v, false, &frames, &err), MM_OK);
    assert_int_equal(stat(path, &st), 0);
    assert_true(st.st_size > 100);
    remove(path);
    assert_int_equal(mm_video_open(path, W, H, 30.0f, &v, &err), MM_OK);
    assert_int_equal(mm_video_write(v, img, &err), MM_OK);
    assert_int_equal(mm_video_close(v, true, &frames, &err), MM_OK);
    assert_int_not_equal(stat(path, &st), 0);
}

static void test_overlay_text_of_a_character(void **state)
{
    (void)state;
    synth_character fx;
    synth_character_init(&fx);
    mm_input in;
    memset(&in, 0, sizeof in);
    in.stick[0] = 1.0f;
    in.gait = MM_GAIT_RUN;
    for (int i = 0; i < 60; ++i) mm_character_update(&fx.ch, &in, 1.0f / 60.0f);
    char text[MM_VIEW_OVERLAY_MAX], expect[256];
    mm_view_overlay(text, sizeof text, &fx.ch, &in, 59.6f);
    const mm_db_clip *clip = &fx.db.clips[fx.db.frame_clip[fx.ch.frame]];
    snprintf(expect, sizeof expect, "clip %s  frame %d/%d", clip->name, fx.ch.frame - clip->first_frame,
             clip->frame_count);
    assert_non_null(strstr(text, expect));
    snprintf(expect, sizeof expect, "searches %d  transitions %d", fx.ch.searches, fx.ch.transitions);
    assert_non_null(strstr(text, expect));
    assert_non_null(strstr(text, "gait run"));
    assert_non_null(strstr(text, "fps 60"));
    /* the cost printed is the sum of the five terms printed (the base cost, no favours here) */
    mm_search_terms t;
    mm_search_cost_terms(&fx.db, fx.ch.query, &fx.ch.last_params, fx.ch.last_result.frame, &t);
    float sum = t.pose_position + t.pose_velocity + t.root_velocity + t.traj_position + t.traj_direction;
    assert_float_equal(sum, fx.ch.last_result.base, 1e-3f * (1.0f + sum));
    /* truncation is safe */
    assert_int_equal(mm_view_overlay(text, 8, &fx.ch, &in, 0.0f), 7);
    assert_int_equal(strlen(text), 7);
    synth_character_free(&fx);
}

static void test_tuning_steps_select_and_clamp(void **state)
{
    (void)state;
    synth_character fx;
    synth_character_init(&fx);
    mm_view_tuning t;
    mm_view_tuning_init(&t, &fx.ch);
    /* only what the database uses: the ratio, a weight per feature group kind it has (root velocity,
     * trajectory positions, directions), a weight per bone feature, the favours (loop_anim_favour
     * with loop clips, contact_favour), bias, search interval, transition half-life, idle speed, sync
     * half-life, and 5 per gait for walk and run (no crouch tag) */
    int kinds[5] = {0, 0, 0, 0, 0};
    for (int g = 0; g < fx.db.group_count; ++g) ++kinds[fx.db.groups[g].kind];
    int loops = 0;
    for (int i = 0; i < fx.db.clip_count; ++i) loops |= fx.db.clips[i].loop != 0;
    assert_int_equal(mm_search_tag_mask(&fx.db, "Crouch"), 0);
    assert_int_equal(t.count, 1 + (kinds[MM_FEATURE_ROOT_VELOCITY] > 0) +
                                  (kinds[MM_FEATURE_TRAJ_POSITION] > 0) +
                                  (kinds[MM_FEATURE_TRAJ_DIRECTION] > 0) + kinds[MM_FEATURE_BONE_POSITION] +
                                  kinds[MM_FEATURE_BONE_VELOCITY] + 1 + loops + 1 + 1 + 4 + 10);
    /* a bone's weight is there only where a feature uses the bone */
    for (int i = 0; i < t.count; ++i) {
        if (!t.entries[i].bone[0]) continue;
        int joint = mm_database_find_joint(&fx.db, t.entries[i].bone), found = 0;
        bool velocity = strcmp(t.entries[i].key, "velocity_weight") == 0;
        for (int g = 0; g < fx.db.group_count; ++g)
            found |= fx.db.groups[g].bone == joint &&
                     fx.db.groups[g].kind == (velocity ? MM_FEATURE_BONE_VELOCITY : MM_FEATURE_BONE_POSITION);
        assert_true(found);
    }
    assert_ptr_equal(t.entries[0].value, &t.desc.params.pose_trajectory_ratio);
    /* the ratio: steps of 0.05 within [0, 1] */
    float r0 = fx.ch.desc.params.pose_trajectory_ratio;
    mm_view_tuning_step(&t, 1);
    assert_float_equal(fx.ch.desc.params.pose_trajectory_ratio, r0 + 0.05f, 1e-6f);
    mm_view_tuning_step(&t, 100);
    assert_float_equal(fx.ch.desc.params.pose_trajectory_ratio, 1.0f, 0.0f);
    /* a weight: by factors of 1.25, down to 0 never below, and back up from zero */
    mm_view_tuning_select(&t, 1);
    assert_true(t.entries[t.selected].multiply);
    float *weight = t.entries[t.selected].value;
    float *running = (float *)((char *)&fx.ch.desc + ((char *)weight - (char *)&t.desc));
    float w0 = *running;
    mm_view_tuning_step(&t, -2);
    assert_float_equal(*running, w0 / 1.5625f, 1e-6f * (1.0f + w0));
    *weight = MM_OFF; /* 0: zero means default in a desc */
    mm_view_tuning_step(&t, -1);
    assert_float_equal(*running, MM_OFF, 0.0f);
    mm_view_tuning_step(&t, 1);
    assert_float_equal(*running, 0.1f, 1e-6f);
    /* selection wraps both ways; the last entries are the run gait's */
    mm_view_tuning_select(&t, -2);
    assert_int_equal(t.selected, t.count - 1);
    assert_ptr_equal(t.entries[t.selected].value, &t.desc.trajectory.gaits[MM_GAIT_RUN].rotation_halflife);
    mm_view_tuning_select(&t, 1);
    assert_int_equal(t.selected, 0);
    /* the text: five lines, the selected one in the middle and marked */
    char text[512];
    mm_view_tuning_text(&t, text, sizeof text);
    int lines = 1;
    for (const char *p = text; *p; ++p) lines += *p == '\n';
    assert_int_equal(lines, 5);
    assert_non_null(strstr(text, "> pose_trajectory_ratio"));
    assert_true(strstr(text, "run.rotation_halflife") < strstr(text, "> pose_trajectory_ratio"));
    /* a tuned walk speed changes what the trajectory asks for */
    for (int i = 0; i < t.count; ++i)
        if (strcmp(t.entries[i].name, "walk.forward_speed") == 0) t.selected = i;
    mm_view_tuning_step(&t, -5); /* 1.5 m/s - 0.5 */
    mm_input in;
    memset(&in, 0, sizeof in);
    in.stick[1] = 1.0f;
    mm_vec3 v;
    mm_trajectory_desired(fx.ch.trajectory, &in, &v, NULL);
    assert_float_equal(mm_vec3_length(v), fx.ch.trajectory->desc.gaits[MM_GAIT_WALK].forward_speed, 1e-5f);
    assert_float_equal(fx.ch.trajectory->desc.gaits[MM_GAIT_WALK].forward_speed, 1.0f, 1e-5f);
    synth_character_free(&fx);
}

/* The layers switch the desc's fields; they act from the next tick (foot IK off: the ankles stay where
 * the animation puts them),
 * and only the transition's layer asks for the character to be made again. */
static void test_tuning_layers(void **state)
{
    (void)state;
    synth_character fx;
    synth_character_init(&fx);
    mm_view_tuning t;
    mm_view_tuning_init(&t, &fx.ch);
    assert_true(t.layers.foot_ik && t.layers.root_sync && t.layers.root_clamps && !t.layers.crossfade);
    mm_input in;
    memset(&in, 0, sizeof in);
    in.stick[1] = 1.0f;
    /* how far the IK moved the ankles from where the animation put them (raw_contact_positions) */
    float moved = 0.0f;
    for (int i = 0; i < 60; ++i) {
        mm_character_update(&fx.ch, &in, 1.0f / 60.0f);
        for (int k = 0; k < 2; ++k)
            moved = fmaxf(moved, mm_vec3_length(mm_vec3_sub(fx.ch.global[fx.ch.foot_joint[k]].translation,
                                                            fx.ch.raw_contact_positions[2 * k])));
    }
    assert_true(moved > 1e-4f);
    t.layers.foot_ik = t.layers.root_sync = t.layers.root_clamps = false;
    mm_character_desc d;
    mm_view_tuning_desc(&t, &d);
    assert_true(d.no_foot_ik);
    assert_float_equal(d.sync_halflife, MM_VIEW_NO_SYNC_HALFLIFE, 0.0f);
    assert_float_equal(d.sync_max_distance, MM_VIEW_NO_CLAMP, 0.0f);
    assert_float_equal(d.sync_max_angle, MM_VIEW_NO_CLAMP, 0.0f);
    assert_false(mm_view_tuning_apply(&t));
    moved = 0.0f;
    for (int i = 0; i < 60; ++i) {
        mm_character_update(&fx.ch, &in, 1.0f / 60.0f);
        for (int k = 0; k < 2; ++k)
            moved = fmaxf(moved, mm_vec3_length(mm_vec3_sub(fx.ch.global[fx.ch.foot_joint[k]].translation,
                                                            fx.ch.raw_contact_positions[2 * k])));
    }
    assert_float_equal(moved, 0.0f, 0.0f);
    /* the layers read back from the desc they made */
    mm_character saved = fx.ch;
    saved.desc = d;
    mm_view_tuning back;
    mm_view_tuning_init(&back, &saved);
    assert_false(back.layers.foot_ik || back.layers.root_sync || back.layers.root_clamps);
    t.layers.crossfade = true;
    assert_true(mm_view_tuning_apply(&t));
    synth_character_free(&fx);
}

/* ---- scene boxes ---- */

static void test_box_corners_by_hand(void **state)
{
    (void)state;
    /* yaw 90 degrees: the box's +Z turns to world +X and its +X to world -Z */
    mm_render_box b = {{1.0f, 0.5f, 2.0f}, {2.0f, 1.0f, 4.0f}, (float)(MM_PI / 2), {0, 0, 0, 0}};
    mm_vec3 c[8];
    mm_render_box_corners(&b, c);
    /* corner i: local x = -1 or +1 (bit 0), y = 0 or 1 (bit 1), z = -2 or +2 (bit 2);
       world = position + (z, y, -x) */
    for (int i = 0; i < 8; ++i) {
        float x = i & 1 ? 1.0f : -1.0f, y = i & 2 ? 1.0f : 0.0f, z = i & 4 ? 2.0f : -2.0f;
        assert_float_equal(c[i].x, 1.0f + z, 1e-5f);
        assert_float_equal(c[i].y, 0.5f + y, 1e-6f);
        assert_float_equal(c[i].z, 2.0f - x, 1e-5f);
    }
    /* the scene's boxes become render boxes with the same placement */
    mm_scene scene;
    mm_scene_init(&scene, 0.25f);
    assert_int_equal(mm_scene_add_box(&scene, mm_vec3_make(0, 0.25f, 3), mm_vec3_make(4, 1, 0.4f), 0.3f),
                     MM_OK);
    assert_int_equal(mm_scene_add_box(&scene, mm_vec3_make(5, 0.25f, 3), mm_vec3_make(1, 2.2f, 1), -0.5f),
                     MM_OK);
    mm_render_box out[2];
    assert_int_equal(mm_view_scene_boxes(&scene, out, 1), 2); /* capacity 1: one written, 2 counted */
    assert_float_equal(out[0].size.x, 4.0f, 0);
    assert_float_equal(out[0].yaw, 0.3f, 0);
    assert_true(out[0].color.a > 0.0f);
    mm_view v;
    memset(&v, 0, sizeof v);
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_view_set_scene(&v, &scene, &err), MM_OK);
    assert_int_equal(v.box_count, 2);
    assert_float_equal(v.boxes[1].position.x, 5.0f, 0);
    assert_float_equal(v.boxes[1].size.y, 2.2f, 0);
    assert_float_equal(v.ground, 0.25f, 0);
    assert_int_equal(mm_view_set_scene(&v, NULL, &err), MM_OK);
    assert_int_equal(v.box_count, 0);
    assert_null(v.boxes);
}

/* Twice the signed area of the triangle (o, a, b). */
static double cross2(const double *o, const double *a, const double *b)
{
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

static void test_box_covers_its_projected_hull(void **state)
{
    (void)state;
    mm_camera c = straight_camera();
    c.pitch = 0.35f; /* from above: the top face shows too */
    mm_render_box b = {{0.1f, 0.4f, 0.2f}, {1.0f, 0.9f, 0.6f}, 0.6f, {0.8f, 0.6f, 0.4f, 1.0f}};
    mm_render_scene s = empty_scene();
    s.boxes = &b;
    s.box_count = 1;
    const uint8_t *rgb = mm_offscreen_render(offscreen, &c, &s);
    assert_non_null(rgb);
    /* the projected corners' convex hull (monotone chain) is what the box covers */
    mm_vec3 corner[8];
    mm_render_box_corners(&b, corner);
    double p[8][2], hull[16][2];
    for (int i = 0; i < 8; ++i) {
        float px, py;
        assert_true(mm_camera_project(&c, W, H, corner[i], &px, &py));
        p[i][0] = px, p[i][1] = py;
    }
    for (int i = 1; i < 8; ++i) /* sort by x, then y */
        for (int k = i; k > 0 && (p[k][0] < p[k - 1][0] || (p[k][0] == p[k - 1][0] && p[k][1] < p[k - 1][1]));
             --k) {
            double t0 = p[k][0], t1 = p[k][1];
            p[k][0] = p[k - 1][0], p[k][1] = p[k - 1][1];
            p[k - 1][0] = t0, p[k - 1][1] = t1;
        }
    int n = 0;
    for (int pass = 0; pass < 2; ++pass) {
        int start = n;
        for (int j = 0; j < 8; ++j) {
            int i = pass ? 7 - j : j;
            while (n >= start + 2 && cross2(hull[n - 2], hull[n - 1], p[i]) <= 0) --n;
            hull[n][0] = p[i][0], hull[n][1] = p[i][1];
            ++n;
        }
        --n; /* the last point starts the other half */
    }
    double area = 0.0;
    for (int i = 0; i < n; ++i) area += 0.5 * cross2(hull[0], hull[i], hull[(i + 1) % n]);
    area = fabs(area);
    double count = 0;
    int outside = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            if (is_background(rgb, x, y)) continue;
            ++count;
            /* no covered pixel lies more than 1.5 px outside the hull */
            double q[2] = {x + 0.5, y + 0.5};
            for (int i = 0; i < n; ++i) {
                const double *a = hull[i], *e = hull[(i + 1) % n];
                double len = hypot(e[0] - a[0], e[1] - a[1]);
                if (len > 0 && cross2(a, e, q) / len < -1.5) { /* the hull runs counter-clockwise in y-down */
                    ++outside;
                    break;
                }
            }
        }
    assert_true(area > 1000.0);
    assert_int_equal(outside, 0);
    assert_true(fabs(count - area) < 0.05 * area);
}

/* ---- contact sheets ---- */

/* A stick figure facing +Z (its left on +X): hips, spine, head, legs with feet, hands. */
enum { FIG_JOINTS = 9, SHEET_COLS = 3, SHEET_ROWS = 2, SHEET_W = 480, SHEET_H = 360 };
static const char *fig_names[FIG_JOINTS] = {"Hips",       "Spine",     "Head",     "LeftUpLeg", "LeftFoot",
                                            "RightUpLeg", "RightFoot", "LeftHand", "RightHand"};
static const int fig_parents[FIG_JOINTS] = {-1, 0, 1, 0, 3, 0, 5, 1, 1};
static const float fig_rest[FIG_JOINTS][3] = {{0, 0.95f, 0},     {0, 1.3f, 0},        {0, 1.65f, 0},
                                              {0.1f, 0.9f, 0},   {0.1f, 0.08f, 0},    {-0.1f, 0.9f, 0},
                                              {-0.1f, 0.08f, 0}, {0.25f, 1.0f, 0.1f}, {-0.25f, 1.0f, 0.1f}};

static void fig_joints(mm_joint *joints)
{
    memset(joints, 0, sizeof(mm_joint) * FIG_JOINTS);
    for (int j = 0; j < FIG_JOINTS; ++j) {
        snprintf(joints[j].name, sizeof joints[j].name, "%s", fig_names[j]);
        joints[j].parent = fig_parents[j];
    }
}

/* Tile i's pose: 0 upright, 1 moved and turned, 2 lying along its facing, 3 a foot 5 cm below the
 * ground, 4 crouched, 5 arms straight out. */
static void fig_pose(int tile, mm_xform *g)
{
    float yaw[SHEET_COLS * SHEET_ROWS] = {0.0f, 1.2f, 0.4f, -2.0f, 2.8f, -0.7f};
    float ox = 3.0f * (float)tile, oz = tile == 1 ? 5.0f : -1.0f * (float)tile;
    for (int j = 0; j < FIG_JOINTS; ++j) {
        float x = fig_rest[j][0], y = fig_rest[j][1], z = fig_rest[j][2];
        if (tile == 2) { /* lying on its back, head first along +Z */
            z = y;
            y = 0.12f;
        }
        if (tile == 3 && j == 4) y = -0.05f;
        if (tile == 4) y *= 0.6f;
        if (tile == 5 && j >= 7) x = j == 7 ? 0.8f : -0.8f, y = 1.4f;
        float c = cosf(yaw[tile]), s = sinf(yaw[tile]);
        g[j].rotation = mm_quat_identity();
        g[j].translation = mm_vec3_make(ox + c * x + s * z, y, oz - s * x + c * z);
    }
}

static void fig_sheet(mm_sheet_desc *d, mm_joint *joints, mm_xform *poses, double *times)
{
    fig_joints(joints);
    for (int t = 0; t < SHEET_COLS * SHEET_ROWS; ++t) {
        fig_pose(t, poses + t * FIG_JOINTS);
        times[t] = 0.5 * t;
    }
    memset(d, 0, sizeof *d);
    d->columns = SHEET_COLS;
    d->rows = SHEET_ROWS;
    d->width = SHEET_W;
    d->height = SHEET_H;
    d->joint_count = FIG_JOINTS;
    d->joints = joints;
    d->poses = poses;
    d->times = times;
}

static void test_sheet_feet_and_facing(void **state)
{
    (void)state;
    mm_joint joints[FIG_JOINTS];
    mm_xform g[FIG_JOINTS];
    fig_joints(joints);
    int feet[FIG_JOINTS];
    assert_int_equal(mm_render_find_feet(joints, FIG_JOINTS, feet, FIG_JOINTS), 2);
    assert_int_equal(feet[0], 4);
    assert_int_equal(feet[1], 6);
    assert_int_equal(mm_render_find_feet(joints, FIG_JOINTS, feet, 1), 1);
    snprintf(joints[6].name, sizeof joints[6].name, "r_ANKLE");
    snprintf(joints[0].name, sizeof joints[0].name, "RootToe"); /* joint 0 never */
    assert_int_equal(mm_render_find_feet(joints, FIG_JOINTS, feet, FIG_JOINTS), 2);
    fig_joints(joints);
    fig_pose(0, g);
    assert_float_equal(mm_render_facing(joints, FIG_JOINTS, g, 9.0f), 0.0f, 1e-5f);
    fig_pose(1, g); /* turned by 1.2 rad */
    assert_float_equal(mm_render_facing(joints, FIG_JOINTS, g, 9.0f), 1.2f, 1e-5f);
    fig_pose(2, g); /* lying, turned by 0.4: the left-right line is still horizontal */
    assert_float_equal(mm_render_facing(joints, FIG_JOINTS, g, 9.0f), 0.4f, 1e-5f);
    /* no left or right joints, or a vertical left-right line: the fallback */
    assert_float_equal(mm_render_facing(joints, 3, g, 9.0f), 9.0f, 0.0f);
    fig_pose(0, g);
    for (int j = 0; j < FIG_JOINTS; ++j) g[j].translation.x = g[j].translation.z = 0.0f;
    assert_float_equal(mm_render_facing(joints, FIG_JOINTS, g, 9.0f), 9.0f, 0.0f);
}

static void test_sheet_frames_every_pose_alike(void **state)
{
    (void)state;
    mm_joint joints[FIG_JOINTS];
    mm_xform poses[SHEET_COLS * SHEET_ROWS * FIG_JOINTS];
    double times[SHEET_COLS * SHEET_ROWS];
    mm_sheet_desc d;
    fig_sheet(&d, joints, poses, times);
    int tw = 0, th = 0;
    assert_int_equal(mm_sheet_tile_size(&d, &tw, &th, NULL), MM_OK);
    assert_int_equal(tw, SHEET_W / SHEET_COLS);
    assert_int_equal(th, SHEET_H / SHEET_ROWS);
    mm_camera cams[SHEET_COLS * SHEET_ROWS];
    assert_int_equal(mm_sheet_cameras(&d, cams, NULL), MM_OK);
    float ground_row = -1.0f, used_w = 0.0f, used_h = 0.0f, top = 1e9f, bottom = -1e9f;
    for (int t = 0; t < SHEET_COLS * SHEET_ROWS; ++t) {
        const mm_camera *c = &cams[t];
        /* the same distance and height everywhere, level: heights compare across tiles */
        assert_float_equal(c->distance, cams[0].distance, 0.0f);
        assert_float_equal(c->target.y, cams[0].target.y, 0.0f);
        assert_float_equal(c->pitch, 0.0f, 0.0f);
        float px, py;
        assert_true(mm_camera_project(c, tw, th, mm_vec3_make(c->target.x, 0.0f, c->target.z), &px, &py));
        if (t == 0) ground_row = py;
        assert_float_equal(py, ground_row, 1e-3f);
        /* the whole body, spheres included, inside the tile and above the label's band (2 lines of
           the 1x font and its padding) */
        const mm_xform *g = poses + t * FIG_JOINTS;
        float x0 = 1e9f, x1 = -1e9f;
        for (int j = 0; j < FIG_JOINTS; ++j) {
            assert_true(mm_camera_project(c, tw, th, g[j].translation, &px, &py));
            float depth = mm_vec3_distance(mm_camera_eye(c), g[j].translation);
            float r = 0.5f * (float)th / tanf(0.5f * c->fov_y) * (j == 2 ? 0.1f : 0.036f) / depth * 1.05f;
            assert_true(px - r >= 1.0f && px + r <= (float)tw - 1.0f);
            assert_true(py - r >= 1.0f && py + r <= (float)th - 2 * 9 - 4);
            x0 = fminf(x0, px - r), x1 = fmaxf(x1, px + r);
            top = fminf(top, py - r), bottom = fmaxf(bottom, py + r);
        }
        used_w = fmaxf(used_w, x1 - x0);
        /* the body faces the tile's left: a point ahead of the hips lies left of them */
        float yaw = mm_render_facing(joints, FIG_JOINTS, g, 0.0f), hx, hy, ax, ay;
        mm_vec3 hips = g[0].translation, ahead = mm_vec3_make(hips.x + sinf(yaw), hips.y, hips.z + cosf(yaw));
        assert_true(mm_camera_project(c, tw, th, hips, &hx, &hy));
        assert_true(mm_camera_project(c, tw, th, ahead, &ax, &ay));
        assert_true(ax < hx - 10.0f);
    }
    used_h = bottom - top;
    /* as large as the tiles allow: the lying body spans most of a tile's width or the tallest most of
       its height */
    assert_true(used_w > 0.8f * (float)tw || used_h > 0.8f * (float)(th - 2 * 9 - 4));
}

static void test_sheet_render_tiles_lines_and_labels(void **state)
{
    (void)state;
    mm_joint joints[FIG_JOINTS];
    mm_xform poses[SHEET_COLS * SHEET_ROWS * FIG_JOINTS];
    double times[SHEET_COLS * SHEET_ROWS];
    mm_sheet_desc d;
    fig_sheet(&d, joints, poses, times);
    uint8_t *rgb = malloc((size_t)SHEET_W * SHEET_H * 3);
    assert_non_null(rgb);
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_sheet_render(&d, rgb, &err), MM_OK);
    const int tw = SHEET_W / SHEET_COLS, th = SHEET_H / SHEET_ROWS;
    const uint8_t border[3] = {50, 52, 56}, red[3] = {200, 24, 24}, head[3] = {40, 90, 210},
                  ground[3] = {70, 48, 28};
#define PX(x, y) (rgb + ((size_t)(y)*SHEET_W + (size_t)(x)) * 3)
#define IS(p, c) ((p)[0] == (c)[0] && (p)[1] == (c)[1] && (p)[2] == (c)[2])
    /* every tile is outlined */
    for (int r = 0; r < SHEET_ROWS; ++r)
        for (int x = 0; x < SHEET_W; ++x)
            assert_true(IS(PX(x, r * th), border) && IS(PX(x, r * th + th - 1), border));
    for (int c = 0; c < SHEET_COLS; ++c)
        for (int y = 0; y < SHEET_H; ++y)
            assert_true(IS(PX(c * tw, y), border) && IS(PX(c * tw + tw - 1, y), border));
    mm_camera cams[SHEET_COLS * SHEET_ROWS];
    assert_int_equal(mm_sheet_cameras(&d, cams, NULL), MM_OK);
    for (int t = 0; t < SHEET_COLS * SHEET_ROWS; ++t) {
        int x0 = (t % SHEET_COLS) * tw, y0 = (t / SHEET_COLS) * th, reds = 0, bodies = 0;
        for (int y = y0 + 1; y < y0 + th - 1; ++y)
            for (int x = x0 + 1; x < x0 + tw - 1; ++x) {
                const uint8_t *p = PX(x, y);
                reds += IS(p, red);
                /* the body's default colour, lit: blue above red */
                bodies += p[2] > p[0] + 20 && p[2] < 200 && !IS(p, head);
            }
        /* only the tile with a foot below the ground has a red label */
        if (t == 3)
            assert_true(reds > 100);
        else
            assert_int_equal(reds, 0);
        assert_true(bodies > 100);
        /* the head line left of the body (where the feet line does not cover it: not on the lying
           body), the ground line across the tile */
        const mm_xform *g = poses + t * FIG_JOINTS;
        float px, py;
        assert_true(mm_camera_project(&cams[t], tw, th,
                                      mm_vec3_make(cams[t].target.x, g[2].translation.y, cams[t].target.z),
                                      &px, &py));
        if (t != 2) assert_true(IS(PX(x0 + 2, y0 + (int)floorf(py)), head));
        assert_true(mm_camera_project(&cams[t], tw, th,
                                      mm_vec3_make(cams[t].target.x, 0.0f, cams[t].target.z), &px, &py));
        for (int x = x0 + 1; x < x0 + tw - 1; ++x) assert_true(IS(PX(x, y0 + (int)floorf(py)), ground));
        /* tile 1 is tile 0's pose moved and turned: the same picture but for its label's time; the
           other poses differ */
        for (int u = 0; u < t; ++u) {
            int ux = (u % SHEET_COLS) * tw, uy = (u / SHEET_COLS) * th, differ = 0, label_rows = 2 * 9 + 4;
            for (int y = 1; y < th - 1; ++y)
                for (int x = 1; x < tw - 1; ++x)
                    if (memcmp(PX(x0 + x, y0 + y), PX(ux + x, uy + y), 3) != 0) {
                        ++differ;
                        if (t == 1) assert_true(y >= th - label_rows);
                    }
            assert_true(differ > (t == 1 ? 0 : 200));
        }
    }
    char path[1024];
    snprintf(path, sizeof path, "%s/sheet.png", MM_TEST_OUT);
    assert_int_equal(mm_png_write(path, rgb, SHEET_W, SHEET_H, &err), MM_OK);
#undef PX
#undef IS
    /* a bad grid, tiles too small */
    d.columns = 0;
    assert_int_equal(mm_sheet_render(&d, rgb, &err), MM_ERR_OUT_OF_RANGE);
    assert_non_null(strstr(err.message, "1 to 32"));
    d.columns = 8;
    d.rows = 6;
    assert_int_equal(mm_sheet_render(&d, rgb, &err), MM_ERR_OUT_OF_RANGE);
    assert_non_null(strstr(err.message, "at least 64"));
    free(rgb);
}

/* Poses no body holds: a tile of NaN joints, a joint 1e30 m away, a body 1 km up. The sheet is
 * still drawn, its cameras finite. */
static void test_sheet_hostile_poses(void **state)
{
    (void)state;
    mm_joint joints[FIG_JOINTS];
    mm_xform poses[SHEET_COLS * SHEET_ROWS * FIG_JOINTS];
    double times[SHEET_COLS * SHEET_ROWS];
    mm_sheet_desc d;
    fig_sheet(&d, joints, poses, times);
    for (int j = 0; j < FIG_JOINTS; ++j) poses[FIG_JOINTS + j].translation.x = NAN;
    poses[2 * FIG_JOINTS + 4].translation = mm_vec3_make(1e30f, -1e30f, 1e30f);
    for (int j = 0; j < FIG_JOINTS; ++j) poses[3 * FIG_JOINTS + j].translation.y += 1000.0f;
    times[4] = INFINITY;
    mm_camera cams[SHEET_COLS * SHEET_ROWS];
    assert_int_equal(mm_sheet_cameras(&d, cams, NULL), MM_OK);
    for (int t = 0; t < SHEET_COLS * SHEET_ROWS; ++t)
        assert_true(isfinite(cams[t].distance) && isfinite(cams[t].target.x) && isfinite(cams[t].target.y) &&
                    isfinite(cams[t].target.z) && isfinite(cams[t].yaw));
    uint8_t *rgb = malloc((size_t)SHEET_W * SHEET_H * 3);
    assert_non_null(rgb);
    assert_int_equal(mm_sheet_render(&d, rgb, NULL), MM_OK);
    free(rgb);
}

/* mm render --contact-sheet on a hand-written BVH (centimetres, a body walking along +Z): the PNG
 * has the size asked for and as many outlined tiles as the grid, each one different. */
static void test_sheet_of_a_bvh_through_the_program(void **state)
{
    (void)state;
    const char *mm = getenv("MM_BIN");
    if (!mm) {
        printf("MM_BIN is not set (run through ctest): skipping\n");
        skip();
    }
    char bvh[1024], png[1024], cmd[4096];
    snprintf(bvh, sizeof bvh, "%s/sheet_walk.bvh", MM_TEST_OUT);
    snprintf(png, sizeof png, "%s/sheet_walk.png", MM_TEST_OUT);
    FILE *f = fopen(bvh, "w");
    assert_non_null(f);
    fprintf(f, "HIERARCHY\nROOT Hips\n{\n OFFSET 0 0 0\n CHANNELS 6 Xposition Yposition Zposition Zrotation "
               "Yrotation Xrotation\n");
    const char *limbs[3][2] = {{"Spine", "Head"}, {"LeftUpLeg", "LeftFoot"}, {"RightUpLeg", "RightFoot"}};
    const char *offsets[3][2] = {{"0 30 0", "0 35 0"}, {"10 -5 0", "0 -85 0"}, {"-10 -5 0", "0 -85 0"}};
    for (int l = 0; l < 3; ++l)
        fprintf(f,
                " JOINT %s\n {\n  OFFSET %s\n  CHANNELS 3 Zrotation Yrotation Xrotation\n  JOINT %s\n  {\n"
                "   OFFSET %s\n   CHANNELS 3 Zrotation Yrotation Xrotation\n   End Site\n   {\n    OFFSET 0 "
                "%s 0\n   }\n  }\n }\n",
                limbs[l][0], offsets[l][0], limbs[l][1], offsets[l][1], l == 0 ? "10" : "-5");
    fprintf(f, "}\nMOTION\nFrames: 40\nFrame Time: 0.05\n");
    for (int i = 0; i < 40; ++i) {
        double swing = 35.0 * sin(0.4 * i);
        fprintf(f, "0 95 %g 0 0 0  0 0 %g 0 0 0  0 0 %g 0 0 %g  0 0 %g 0 0 %g\n", 6.0 * i, 0.3 * swing, swing,
                fabs(swing) * 0.5, -swing, fabs(swing) * 0.5);
    }
    fclose(f);
    snprintf(cmd, sizeof cmd,
             "\"%s\" render \"%s\" --contact-sheet \"%s\" --grid 4x3 --size 640x480 >/dev/null", mm, bvh,
             png);
    assert_int_equal(system(cmd), 0);
    int w = 0, h = 0;
    unsigned char *rgb = decode_png(png, &w, &h);
    assert_non_null(rgb);
    assert_int_equal(w, 640);
    assert_int_equal(h, 480);
    /* runs of border-coloured whole columns and rows: the outlines, one run more than tiles */
    const unsigned char border[3] = {50, 52, 56};
    int runs[2] = {0, 0};
    for (int axis = 0; axis < 2; ++axis) {
        int along = axis ? h : w, across = axis ? w : h, previous = 0;
        for (int i = 0; i < along; ++i) {
            int whole = 1;
            for (int k = 0; k < across && whole; ++k) {
                size_t x = (size_t)(axis ? k : i), y = (size_t)(axis ? i : k);
                whole = memcmp(rgb + (y * (size_t)w + x) * 3, border, 3) == 0;
            }
            runs[axis] += whole && !previous;
            previous = whole;
        }
    }
    assert_int_equal(runs[0], 4 + 1);
    assert_int_equal(runs[1], 3 + 1);
    /* every tile differs from the next (the legs swing; the labels' times differ anyway, so above
       the label band) */
    const int tw = 640 / 4, th = 480 / 3;
    for (int t = 1; t < 12; ++t) {
        int x0 = (t % 4) * tw, y0 = (t / 4) * th, px = ((t - 1) % 4) * tw, py = ((t - 1) / 4) * th,
            differ = 0;
        for (int y = 1; y < th / 2; ++y)
            for (int x = 1; x < tw - 1; ++x)
                differ += memcmp(rgb + ((size_t)(y0 + y) * 640 + (size_t)(x0 + x)) * 3,
                                 rgb + ((size_t)(py + y) * 640 + (size_t)(px + x)) * 3, 3) != 0;
        assert_true(differ > 20);
    }
    free(rgb);
    /* a grid that is not COLUMNSxROWS is a usage error */
    snprintf(cmd, sizeof cmd, "\"%s\" render \"%s\" --contact-sheet \"%s\" --grid 4by3 2>/dev/null", mm, bvh,
             png);
    int status = system(cmd);
    assert_true(WIFEXITED(status) && WEXITSTATUS(status) == 2);
}

int main(void)
{
    mm_error err;
    memset(&err, 0, sizeof err);
    if (mm_offscreen_create(W, H, &offscreen, &err) != MM_OK) {
        fprintf(stderr, "offscreen rendering: %s\n", err.message);
        return 1;
    }
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_camera_eye_and_center),
        cmocka_unit_test(test_camera_projection_by_hand),
        cmocka_unit_test(test_camera_follow_orbit_zoom),
        cmocka_unit_test(test_view_input_follows_the_camera),
        cmocka_unit_test(test_text_measure_and_font),
        cmocka_unit_test(test_png_round_trip),
        cmocka_unit_test(test_sphere_covers_its_projected_disc),
        cmocka_unit_test(test_character_lies_where_its_joints_project),
        cmocka_unit_test(test_overlay_glyph_pixels),
        cmocka_unit_test(test_video_folder_and_errors),
        cmocka_unit_test(test_overlay_text_of_a_character),
        cmocka_unit_test(test_tuning_steps_select_and_clamp),
        cmocka_unit_test(test_tuning_layers),
        cmocka_unit_test(test_box_corners_by_hand),
        cmocka_unit_test(test_box_covers_its_projected_hull),
        cmocka_unit_test(test_sheet_feet_and_facing),
        cmocka_unit_test(test_sheet_frames_every_pose_alike),
        cmocka_unit_test(test_sheet_render_tiles_lines_and_labels),
        cmocka_unit_test(test_sheet_hostile_poses),
        cmocka_unit_test(test_sheet_of_a_bvh_through_the_program),
        cmocka_unit_test(test_body_of_the_built_in_set),
        cmocka_unit_test(test_body_of_lafan1),
        cmocka_unit_test(test_body_of_games105),
        cmocka_unit_test(test_body_of_pfnn),
        cmocka_unit_test(test_body_of_skeleton_variants),
        cmocka_unit_test(test_overlay_is_drawn_where_placed),
    };
    int failed = cmocka_run_group_tests(tests, NULL, NULL);
    mm_offscreen_destroy(offscreen);
    return failed;
}
