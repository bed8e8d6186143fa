/* Rendering: the camera against hand-computed projections, the font and text layout, PNG files
 * decoded back, and headless frames whose pixels are checked against the geometry (a sphere
 * covers the disc its projection predicts, the character lies where its joints project, the
 * overlay's glyph pixels are where the font says, a scene box covers the hull of its projected
 * corners). */
#include <math.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <mm/character.h>
#include <mm/render.h>
#include <mm/view.h>

#include "runtime/character/state.h"

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
    /* 4 weights, 2 per matched bone, 4 favours and timings, 5 per gait for walk and run */
    mm_pose_data pose;
    mm_database_pose(&fx.db, 0, &pose);
    assert_int_equal(t.count, 4 + 2 * pose.bone_count + 4 + 10);
    assert_ptr_equal(t.entries[0].value, &t.desc.params.pose_trajectory_ratio);
    /* the ratio: steps of 0.05 within [0, 1] */
    float r0 = fx.ch.desc.params.pose_trajectory_ratio;
    mm_view_tuning_step(&t, 1);
    assert_float_equal(fx.ch.desc.params.pose_trajectory_ratio, r0 + 0.05f, 1e-6f);
    mm_view_tuning_step(&t, 100);
    assert_float_equal(fx.ch.desc.params.pose_trajectory_ratio, 1.0f, 0.0f);
    /* a weight: by factors of 1.25, down to 0 never below, and back up from zero */
    mm_view_tuning_select(&t, 1);
    assert_ptr_equal(t.entries[t.selected].value, &t.desc.params.body_velocity_weight);
    float w0 = fx.ch.desc.params.body_velocity_weight;
    mm_view_tuning_step(&t, -2);
    assert_float_equal(fx.ch.desc.params.body_velocity_weight, w0 / 1.5625f, 1e-6f * (1.0f + w0));
    t.desc.params.body_velocity_weight = MM_OFF; /* 0: zero means default in a desc */
    mm_view_tuning_step(&t, -1);
    assert_float_equal(fx.ch.desc.params.body_velocity_weight, MM_OFF, 0.0f);
    assert_float_equal(fx.ch.state->desc.params.body_velocity_weight, 0.0f, 0.0f); /* as it runs */
    mm_view_tuning_step(&t, 1);
    assert_float_equal(fx.ch.desc.params.body_velocity_weight, 0.1f, 1e-6f);
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
        cmocka_unit_test(test_box_corners_by_hand),
        cmocka_unit_test(test_box_covers_its_projected_hull),
    };
    int failed = cmocka_run_group_tests(tests, NULL, NULL);
    mm_offscreen_destroy(offscreen);
    return failed;
}
