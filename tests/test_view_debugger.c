/* The viewer as a person uses it: mm view in a virtual display (xvfb-run) plays a key script that
 * drives, pauses, rewinds, picks a candidate, switches foot IK off and saves the tuning; its
 * screenshots are checked against what they must show: the character's pixels where its joints
 * project (mm_camera_project with the shot's camera), the panel's windows in their rectangles, the
 * picked candidate's ghost where its joints project, a rewound tick's pose equal bit for bit to
 * the pose recorded live, and a config saved with only its changed fields, layout and "extends"
 * kept; and a trace of mm simulate jumping a gap (the move layer) opened on the timeline (--replay)
 * showing the trace's tick. Also the config editor alone (tools/view_config.c). Skipped without
 * xvfb-run or MM_BIN. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>
#include <cjson/cJSON.h>
#include <zlib.h>

#include <mm/render.h>

#include "view_config.h"

/* ---- the config editor ---- */

static void expect_set(const char *text, const char *path, const char *value, const char *expected)
{
    char why[256] = "";
    char *out = view_config_set(text, path, value, why, sizeof why);
    if (!out) fail_msg("%s: %s", path, why);
    assert_string_equal(out, expected);
    free(out);
}

static void test_config_set_keeps_the_rest(void **state)
{
    (void)state;
    /* a number in place, the spaces about it kept */
    expect_set("{\"a\" :  1.5 , \"b\": 2}", "a", "0.25", "{\"a\" :  0.25 , \"b\": 2}");
    /* a missing key at the end of its object: on the last member's line when it shares one */
    expect_set("{\"runtime\": {\"walk\": {\"forward_speed\": 1.5}}}", "runtime.idle_speed", "0.2",
               "{\"runtime\": {\"walk\": {\"forward_speed\": 1.5}, \"idle_speed\": 0.2}}");
    /* on a line of its own, at the last member's indent */
    expect_set(
        "{\n   \"extends\": \"base.json\",\n   \"x\": [1, 2]\n}\n", "runtime.walk.side_speed", "0.5",
        "{\n   \"extends\": \"base.json\",\n   \"x\": [1, 2],\n   \"runtime\": {\"walk\": {\"side_speed\": "
        "0.5}}\n}\n");
    /* into an empty object */
    expect_set("{\"runtime\": {}}", "runtime.warping", "true", "{\"runtime\": {\"warping\": true}}");
    /* a bone's weight, found by its name in the list */
    expect_set("{\"features\": {\"bones\": [{\"name\": \"A\", \"position_weight\": 1},\n"
               "  {\"name\": \"B\"}]}}",
               "features.bones[B].velocity_weight", "3",
               "{\"features\": {\"bones\": [{\"name\": \"A\", \"position_weight\": 1},\n"
               "  {\"name\": \"B\", \"velocity_weight\": 3}]}}");
    /* strings with braces and escaped quotes do not confuse it */
    expect_set("{\"s\": \"}{\\\"\", \"n\": 1}", "n", "2", "{\"s\": \"}{\\\"\", \"n\": 2}");
    /* refused: no bones list in the file, a bone it does not list, not an object */
    char why[256];
    assert_null(
        view_config_set("{\"features\": {}}", "features.bones[A].position_weight", "1", why, sizeof why));
    assert_non_null(strstr(why, "no bones list"));
    assert_null(view_config_set("{\"features\": {\"bones\": [{\"name\": \"A\"}]}}",
                                "features.bones[Z].position_weight", "1", why, sizeof why));
    assert_non_null(strstr(why, "no entry named Z"));
    assert_null(view_config_set("[1, 2]", "a", "1", why, sizeof why));
    assert_null(view_config_set("{\"a\": 1", "a", "2", why, sizeof why));
}

/* ---- PNG files (8-bit RGB, as mm_png_write makes them) ---- */

typedef struct image {
    int width, height;
    uint8_t *rgb;
} image;

static uint32_t be32(const uint8_t *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

static int paeth(int a, int b, int c)
{
    int p = a + b - c, pa = abs(p - a), pb = abs(p - b), pc = abs(p - c);
    return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

static void read_png(const char *path, image *img)
{
    FILE *f = fopen(path, "rb");
    if (!f) fail_msg("%s: cannot read it", path);
    fseek(f, 0, SEEK_END);
    long size = ftell(f);
    fseek(f, 0, SEEK_SET);
    uint8_t *file = malloc((size_t)size);
    assert_non_null(file);
    assert_int_equal(fread(file, 1, (size_t)size, f), (size_t)size);
    fclose(f);
    assert_memory_equal(file, "\x89PNG\r\n\x1a\n", 8);
    uint8_t *packed = malloc((size_t)size);
    size_t packed_size = 0;
    for (long at = 8; at + 12 <= size;) {
        uint32_t n = be32(file + at);
        const uint8_t *type = file + at + 4, *data = file + at + 8;
        if (memcmp(type, "IHDR", 4) == 0) {
            img->width = (int)be32(data);
            img->height = (int)be32(data + 4);
            assert_int_equal(data[8], 8); /* bits */
            assert_int_equal(data[9], 2); /* RGB */
        } else if (memcmp(type, "IDAT", 4) == 0) {
            memcpy(packed + packed_size, data, n);
            packed_size += n;
        }
        at += 12 + (long)n;
    }
    size_t stride = (size_t)img->width * 3, raw_size = (stride + 1) * (size_t)img->height;
    uint8_t *raw = malloc(raw_size);
    uLongf got = (uLongf)raw_size;
    assert_int_equal(uncompress(raw, &got, packed, (uLong)packed_size), Z_OK);
    assert_int_equal(got, raw_size);
    img->rgb = malloc(stride * (size_t)img->height);
    for (int y = 0; y < img->height; ++y) {
        const uint8_t *in = raw + (size_t)y * (stride + 1) + 1;
        uint8_t *row = img->rgb + (size_t)y * stride, *up = y > 0 ? row - stride : NULL;
        int filter = in[-1];
        for (size_t x = 0; x < stride; ++x) {
            int a = x >= 3 ? row[x - 3] : 0, b = up ? up[x] : 0, c = up && x >= 3 ? up[x - 3] : 0, p = 0;
            switch (filter) {
            case 1:
                p = a;
                break;
            case 2:
                p = b;
                break;
            case 3:
                p = (a + b) / 2;
                break;
            case 4:
                p = paeth(a, b, c);
                break;
            default:
                p = 0;
                break;
            }
            row[x] = (uint8_t)(in[x] + p);
        }
    }
    free(raw);
    free(packed);
    free(file);
}

static const uint8_t *pixel(const image *img, int x, int y)
{
    return img->rgb + ((size_t)y * (size_t)img->width + (size_t)x) * 3;
}

/* Colours: the body is a dark bluish grey, lit (the sky and ground are light); the picked ghost is
 * yellow; the panel's windows are near black, their sliders and buttons dark blue. */
/* the body's colours (skin, shirt, trousers, shoes): darker or more saturated than the light grey
 * ground and sky */
static int is_body(const uint8_t *p)
{
    int lo = p[0] < p[1] ? (p[0] < p[2] ? p[0] : p[2]) : (p[1] < p[2] ? p[1] : p[2]);
    int hi = p[0] > p[1] ? (p[0] > p[2] ? p[0] : p[2]) : (p[1] > p[2] ? p[1] : p[2]);
    return p[0] + p[1] + p[2] < 3 * 130 || hi - lo > 40;
}
static int is_picked(const uint8_t *p) { return p[0] > 170 && p[1] > 130 && p[2] < 120; }
static int is_panel(const uint8_t *p)
{
    return (p[0] < 60 && p[1] < 60 && p[2] < 70) || (p[0] < 90 && p[2] > p[0] + 40);
}

/* Some pixel within radius of (x, y) has the colour. */
static int near(const image *img, float x, float y, int radius, int (*colour)(const uint8_t *))
{
    for (int dy = -radius; dy <= radius; ++dy)
        for (int dx = -radius; dx <= radius; ++dx) {
            int px = (int)x + dx, py = (int)y + dy;
            if (px >= 0 && py >= 0 && px < img->width && py < img->height && colour(pixel(img, px, py)))
                return 1;
        }
    return 0;
}

/* ---- the shots' facts ---- */

static cJSON *read_json(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) fail_msg("%s: cannot read it", path);
    static char text[1 << 20];
    size_t n = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    text[n] = 0;
    cJSON *j = cJSON_Parse(text);
    if (!j) fail_msg("%s: not JSON", path);
    return j;
}

static double number(const cJSON *o, const char *key)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    if (!cJSON_IsNumber(v) && !cJSON_IsBool(v)) fail_msg("no number %s", key);
    return cJSON_IsBool(v) ? (double)cJSON_IsTrue(v) : v->valuedouble;
}

static mm_vec3 vec(const cJSON *a)
{
    return mm_vec3_make((float)cJSON_GetArrayItem(a, 0)->valuedouble,
                        (float)cJSON_GetArrayItem(a, 1)->valuedouble,
                        (float)cJSON_GetArrayItem(a, 2)->valuedouble);
}

static mm_camera camera_of(const cJSON *shot)
{
    const cJSON *c = cJSON_GetObjectItemCaseSensitive(shot, "camera");
    mm_camera cam;
    cam.target = vec(cJSON_GetObjectItemCaseSensitive(c, "target"));
    cam.yaw = (float)number(c, "yaw");
    cam.pitch = (float)number(c, "pitch");
    cam.distance = (float)number(c, "distance");
    cam.fov_y = (float)number(c, "fov_y");
    cam.z_near = (float)number(c, "z_near");
    cam.z_far = (float)number(c, "z_far");
    return cam;
}

/* Inside one of the panel's windows. */
static int in_panel(const cJSON *shot, float x, float y)
{
    const cJSON *w;
    cJSON_ArrayForEach(w, cJSON_GetObjectItemCaseSensitive(shot, "panel"))
    {
        float r[4];
        for (int k = 0; k < 4; ++k) r[k] = (float)cJSON_GetArrayItem(w, k)->valuedouble;
        if (x >= r[0] && y >= r[1] && x < r[0] + r[2] && y < r[1] + r[3]) return 1;
    }
    return 0;
}

/* Of the joints (world points) that project into the image outside the panel, how many have the
 * colour within radius pixels, and how many were looked at. */
static void joints_coloured(const cJSON *shot, const image *img, const cJSON *joints, int first,
                            int (*colour)(const uint8_t *), int *hits, int *looked)
{
    mm_camera cam = camera_of(shot);
    *hits = *looked = 0;
    int n = cJSON_GetArraySize(joints);
    for (int j = first; j < n; ++j) {
        float x, y;
        if (!mm_camera_project(&cam, img->width, img->height, vec(cJSON_GetArrayItem(joints, j)), &x, &y))
            continue;
        if (x < 0 || y < 0 || x >= img->width || y >= img->height || in_panel(shot, x, y)) continue;
        ++*looked;
        *hits += near(img, x, y, 3, colour);
    }
}

typedef struct run {
    char dir[512];
    const char *mm;
} run;

static int sh(const char *fmt, ...)
{
    char cmd[4096];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(cmd, sizeof cmd, fmt, ap);
    va_end(ap);
    int r = system(cmd);
    return r;
}

static void write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

static char *read_text(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    static char text[1 << 16];
    size_t n = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    text[n] = 0;
    return text;
}

/* The config the viewer saves into: it extends the one the database was built from. */
static const char *user_config = "{\n"
                                 "    \"extends\": \"base.json\",\n"
                                 "    \"runtime\": {\"walk\": {\"forward_speed\": 1.5}}\n"
                                 "}\n";
static const char *saved_config =
    "{\n"
    "    \"extends\": \"base.json\",\n"
    "    \"runtime\": {\"walk\": {\"forward_speed\": 1.5}, \"pose_trajectory_ratio\": 0.6}\n"
    "}\n";

/* Walk, run, pause at tick 120, rewind 30 ticks to tick 90 (shot live at tick 90 too: frame 89
 * runs tick 90), pick candidate 1, switch foot IK off and resume, raise pose_trajectory_ratio by
 * two steps and save. */
static const char *key_script = "# drive\n"
                                "0.0 hold W\n"
                                "0.5 hold shift\n"
                                "1.4833 shot live90\n"
                                "1.8 release shift\n"
                                "2.0 press space   # pause\n"
                                "2.0 shot paused\n"
                                "2.1 press comma 30\n"
                                "2.1 shot rewound\n"
                                "2.2 select 1\n"
                                "2.3 shot picked\n"
                                "2.4 press F\n"
                                "2.4 press space\n"
                                "2.9 shot noik\n"
                                "3.0 press equal 2\n"
                                "3.0 press F5\n"
                                "3.1 quit\n";

static int setup(void **state)
{
    static run r;
    r.mm = getenv("MM_BIN");
    if (!r.mm || sh("command -v xvfb-run >/dev/null 2>&1") != 0) {
        *state = NULL;
        return 0;
    }
    snprintf(r.dir, sizeof r.dir, "%s/view_debugger", MM_TEST_OUT);
    if (sh("rm -rf '%s' && mkdir -p '%s/shots'", r.dir, r.dir) != 0) return -1;
    if (sh("'%s' synth '%s/synth' >/dev/null && '%s' db build '%s/configs/synth.json' --data '%s/synth' -o "
           "'%s/s.mmdb' >/dev/null",
           r.mm, r.dir, r.mm, MM_SOURCE_DIR, r.dir, r.dir) != 0)
        return -1;
    char path[1024];
    snprintf(path, sizeof path, "%s/keys.txt", r.dir);
    write_file(path, key_script);
    snprintf(path, sizeof path, "%s/user.json", r.dir);
    write_file(path, user_config);
    if (sh("cp '%s/configs/synth.json' '%s/base.json'", MM_SOURCE_DIR, r.dir) != 0) return -1;
    /* leak reports off: the X server's GL driver is loaded at run time (as in test_render_cli) */
    if (sh("cd '%s' && ASAN_OPTIONS=detect_leaks=0 xvfb-run -a -s '-screen 0 1024x768x24' '%s' view s.mmdb "
           "--config "
           "user.json --script keys.txt --screenshot-dir shots --size 800x450 >view.out 2>&1",
           r.dir, r.mm) != 0) {
        sh("cat '%s/view.out'", r.dir);
        return -1;
    }
    /* a trace of mm simulate jumping a gap (the move layer in a scene), opened on the timeline at tick
     * 250, in the jump */
    if (sh("cd '%s' && '%s' simulate s.mmdb --input '%s/scripts/input/moves_jump_gap.json' --scene "
           "'%s/scenes/jump_gap.json' --seconds 5 -o sim.bvh --trace trace.jsonl --trace-ticks >/dev/null",
           r.dir, r.mm, MM_SOURCE_DIR, MM_SOURCE_DIR) != 0)
        return -1;
    snprintf(path, sizeof path, "%s/replay_keys.txt", r.dir);
    write_file(path, "0.0 scrub 250\n0.0 shot replay250\n0.05 quit\n");
    if (sh("cd '%s' && ASAN_OPTIONS=detect_leaks=0 xvfb-run -a -s '-screen 0 1024x768x24' '%s' view s.mmdb "
           "--replay "
           "trace.jsonl --script replay_keys.txt --screenshot-dir shots --size 640x360 >replay.out 2>&1",
           r.dir, r.mm) != 0) {
        sh("cat '%s/replay.out'", r.dir);
        return -1;
    }
    *state = &r;
    return 0;
}

#define NEED_RUN(state)                                                                                      \
    do {                                                                                                     \
        if (!*(state)) skip();                                                                               \
    } while (0)

static cJSON *shot(const run *r, const char *name, image *img)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/shots/%s.png", r->dir, name);
    read_png(path, img);
    snprintf(path, sizeof path, "%s/shots/%s.json", r->dir, name);
    cJSON *j = read_json(path);
    assert_int_equal((int)number(j, "width"), img->width);
    assert_int_equal((int)number(j, "height"), img->height);
    return j;
}

static void test_character_where_its_joints_project(void **state)
{
    NEED_RUN(state);
    image img;
    cJSON *j = shot(*state, "live90", &img);
    int hits, looked;
    joints_coloured(j, &img, cJSON_GetObjectItemCaseSensitive(j, "joints"), 1, is_body, &hits, &looked);
    assert_true(looked >= 10);
    assert_true(hits >= looked * 8 / 10);
    /* and not anywhere: 1.5 m above the head is sky */
    const cJSON *joints = cJSON_GetObjectItemCaseSensitive(j, "joints");
    mm_vec3 top = vec(cJSON_GetArrayItem(joints, 0));
    top.y += 3.3f;
    mm_camera cam = camera_of(j);
    float x, y;
    assert_true(mm_camera_project(&cam, img.width, img.height, top, &x, &y));
    assert_false(near(&img, x, y, 3, is_body));
    cJSON_Delete(j);
    free(img.rgb);
}

static void test_panel_in_its_windows(void **state)
{
    NEED_RUN(state);
    image img;
    cJSON *j = shot(*state, "paused", &img);
    assert_true(number(j, "paused"));
    const cJSON *w;
    int windows = 0;
    cJSON_ArrayForEach(w, cJSON_GetObjectItemCaseSensitive(j, "panel"))
    {
        float r[4];
        for (int k = 0; k < 4; ++k) r[k] = (float)cJSON_GetArrayItem(w, k)->valuedouble;
        assert_true(r[2] >= 100.0f && r[3] >= 20.0f);
        assert_true(r[0] >= 0.0f && r[1] >= 0.0f && r[0] + r[2] <= img.width + 1 &&
                    r[1] + r[3] <= img.height + 1);
        /* a grid of points inside: mostly the windows' background and widgets (the rest is text) */
        int dark = 0, all = 0;
        for (int gy = 1; gy < 8; ++gy)
            for (int gx = 1; gx < 8; ++gx, ++all)
                dark += is_panel(
                    pixel(&img, (int)(r[0] + r[2] * (float)gx / 8), (int)(r[1] + r[3] * (float)gy / 8)));
        if (dark < all / 2) fail_msg("window %s: %d of %d points dark", w->string, dark, all);
        ++windows;
    }
    assert_int_equal(windows, 5);
    /* the 3D view between the windows is not dark */
    int dark = 0;
    for (int y = img.height / 4; y < img.height / 2; y += 8)
        dark += is_panel(pixel(&img, img.width / 2 + 60, y));
    assert_true(dark <= 2);
    cJSON_Delete(j);
    free(img.rgb);
}

static void test_rewound_tick_is_the_recorded_one(void **state)
{
    NEED_RUN(state);
    image a, b, p;
    cJSON *live = shot(*state, "live90", &a), *back = shot(*state, "rewound", &b),
          *paused = shot(*state, "paused", &p);
    assert_int_equal((int)number(live, "tick"), 90);
    assert_int_equal((int)number(paused, "tick"), 120);
    assert_int_equal((int)number(back, "tick"), 90);
    assert_int_equal((int)number(back, "last"), 120); /* the recording kept past it */
    assert_int_equal((int)number(back, "frame"), (int)number(live, "frame"));
    const cJSON *ja = cJSON_GetObjectItemCaseSensitive(live, "joints"),
                *jb = cJSON_GetObjectItemCaseSensitive(back, "joints"),
                *jp = cJSON_GetObjectItemCaseSensitive(paused, "joints");
    assert_int_equal(cJSON_GetArraySize(ja), cJSON_GetArraySize(jb));
    int moved = 0;
    for (int i = 0; i < cJSON_GetArraySize(ja); ++i)
        for (int k = 0; k < 3; ++k) {
            double x = cJSON_GetArrayItem(cJSON_GetArrayItem(ja, i), k)->valuedouble;
            assert_true(x == cJSON_GetArrayItem(cJSON_GetArrayItem(jb, i), k)->valuedouble); /* bit for bit */
            moved += x != cJSON_GetArrayItem(cJSON_GetArrayItem(jp, i), k)->valuedouble;
        }
    assert_true(moved > 0); /* 30 ticks later it was elsewhere */
    cJSON_Delete(live);
    cJSON_Delete(back);
    cJSON_Delete(paused);
    free(a.rgb);
    free(b.rgb);
    free(p.rgb);
}

static void test_picked_candidate_drawn_as_a_ghost(void **state)
{
    NEED_RUN(state);
    image img;
    cJSON *j = shot(*state, "picked", &img);
    assert_int_equal((int)number(j, "selected"), 1);
    const cJSON *cands = cJSON_GetObjectItemCaseSensitive(j, "candidates");
    assert_true(cJSON_GetArraySize(cands) >= 2);
    /* candidates by cost, each cost at least its weighted distance's share */
    assert_true(number(cJSON_GetArrayItem(cands, 0), "cost") <= number(cJSON_GetArrayItem(cands, 1), "cost"));
    const cJSON *ghost = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(j, "ghosts"), 0);
    assert_int_equal((int)number(ghost, "candidate"), 1);
    int hits, looked;
    joints_coloured(j, &img, cJSON_GetObjectItemCaseSensitive(ghost, "joints"), 1, is_picked, &hits, &looked);
    assert_true(looked >= 8);
    assert_true(hits >= looked * 6 / 10);
    /* the character's own joints are not drawn yellow */
    joints_coloured(j, &img, cJSON_GetObjectItemCaseSensitive(j, "joints"), 1, is_picked, &hits, &looked);
    assert_true(hits <= looked / 5);
    assert_true(number(j, "preview_frame") >= 0);
    cJSON_Delete(j);
    free(img.rgb);
}

static void test_foot_ik_off_and_resumed(void **state)
{
    NEED_RUN(state);
    image a, b;
    cJSON *live = shot(*state, "live90", &a), *off = shot(*state, "noik", &b);
    assert_true(number(live, "ik_offset") > 1e-4);
    assert_true(number(off, "ik_offset") == 0.0);
    assert_int_equal((int)number(cJSON_GetObjectItemCaseSensitive(off, "layers"), "foot_ik"), 0);
    /* resumed from tick 90 at 2.4 s: 30 ticks later at 2.9 s, the recording after 90 dropped */
    assert_int_equal((int)number(off, "tick"), 121);
    assert_int_equal((int)number(off, "last"), 121);
    assert_false(number(off, "paused"));
    cJSON_Delete(live);
    cJSON_Delete(off);
    free(a.rgb);
    free(b.rgb);
}

static void test_saved_config_changed_only_where_tuned(void **state)
{
    NEED_RUN(state);
    const run *r = *state;
    char path[1024];
    snprintf(path, sizeof path, "%s/user.json", r->dir);
    const char *text = read_text(path);
    assert_non_null(text);
    assert_string_equal(text, saved_config);
}

/* The trace's tick 250 (its line for tick 249, counted from 0) is the tick the viewer shows there, in
 * the jump over the gap. */
static void test_replay_shows_the_trace(void **state)
{
    NEED_RUN(state);
    const run *r = *state;
    image img;
    cJSON *j = shot(r, "replay250", &img);
    assert_int_equal((int)number(j, "tick"), 250);
    assert_int_equal((int)number(j, "last"), 300);
    assert_int_equal((int)number(j, "move"), 1);
    assert_true(number(j, "paused"));
    /* the trace's own replay agreed with it (mm_trace_player) */
    const cJSON *message = cJSON_GetObjectItemCaseSensitive(j, "message");
    assert_true(cJSON_IsString(message));
    assert_non_null(strstr(message->valuestring, "every search of the trace, byte for byte"));
    char path[1024];
    snprintf(path, sizeof path, "%s/trace.jsonl", r->dir);
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    static char line[1 << 16];
    int found = 0;
    while (fgets(line, sizeof line, f)) {
        cJSON *l = cJSON_Parse(line);
        assert_non_null(l);
        const cJSON *type = cJSON_GetObjectItemCaseSensitive(l, "type");
        if (cJSON_IsString(type) && strcmp(type->valuestring, "tick") == 0 && (int)number(l, "tick") == 249) {
            found = 1;
            assert_int_equal((int)number(l, "frame"), (int)number(j, "frame"));
            mm_vec3 root = vec(
                cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(l, "root"), "position"));
            mm_vec3 mine = vec(cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(j, "joints"), 0));
            assert_float_equal(root.x, mine.x, 1e-6f);
            assert_float_equal(root.z, mine.z, 1e-6f);
        }
        cJSON_Delete(l);
    }
    fclose(f);
    assert_true(found);
    cJSON_Delete(j);
    free(img.rgb);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_config_set_keeps_the_rest),
        cmocka_unit_test(test_character_where_its_joints_project),
        cmocka_unit_test(test_panel_in_its_windows),
        cmocka_unit_test(test_rewound_tick_is_the_recorded_one),
        cmocka_unit_test(test_picked_candidate_drawn_as_a_ghost),
        cmocka_unit_test(test_foot_ik_off_and_resumed),
        cmocka_unit_test(test_saved_config_changed_only_where_tuned),
        cmocka_unit_test(test_replay_shows_the_trace),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
