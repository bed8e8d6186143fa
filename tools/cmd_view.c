/* mm view DB.mmdb [--config CONFIG] | mm view --clip FILE.bvh [--config CONFIG] [--clip-name NAME]
 * (either with [--scene SCENE.json]: its boxes are drawn)
 * The interactive viewer (GLFW + OpenGL 3.3): drive a character on a database with keyboard or
 * gamepad, watch the debug drawing, tune the cost weights and trajectory parameters live and save
 * them into the config; or inspect a clip: play, scrub, step, and edit its tag ranges.
 * --frames N and --screenshot FILE.png run N frames and save the last one (smoke tests, docs). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <GLFW/glfw3.h>

#include <mm/character_config.h>
#include <mm/character.h>
#include <mm/config_json.h>
#include <mm/input_json.h>
#include <mm/mm.h>
#include <mm/render.h>
#include <mm/scene_json.h>
#include <mm/view.h>

#include "cli.h"
#include "commands.h"

#define TICK (1.0 / 60.0)

typedef struct options {
    const char *db, *clip, *config, *clip_name, *input, *screenshot, *scene_path;
    const char *mesh_path; /* --mesh: a user's body for the database's character */
    const mm_scene *scene; /* loaded from scene_path; NULL: none */
    int width, height;
    long frames; /* 0: until the window closes */
} options;

typedef struct window {
    GLFWwindow *glfw;
    mm_renderer *renderer;
    mm_camera camera;
    double last_x, last_y;
    bool dragging;
    float scroll;
    int pressed[GLFW_KEY_LAST + 1]; /* key presses since the last frame (edges, not levels) */
    uint8_t *pixels;
} window;

static void on_scroll(GLFWwindow *w, double dx, double dy)
{
    (void)dx;
    window *win = glfwGetWindowUserPointer(w);
    win->scroll += (float)dy;
}

static void on_key(GLFWwindow *w, int key, int scancode, int action, int mods)
{
    (void)scancode;
    (void)mods;
    window *win = glfwGetWindowUserPointer(w);
    if ((action == GLFW_PRESS || action == GLFW_REPEAT) && key >= 0 && key <= GLFW_KEY_LAST)
        ++win->pressed[key];
}

static int take(window *win, int key)
{
    int n = win->pressed[key];
    win->pressed[key] = 0;
    return n;
}

static bool down(window *win, int key) { return glfwGetKey(win->glfw, key) == GLFW_PRESS; }

static int open_window(window *win, const options *o, const char *title)
{
    memset(win, 0, sizeof *win);
    if (!glfwInit()) {
        fprintf(
            stderr,
            "mm: cannot open a window (no display? mm render and mm simulate --video work without one)\n");
        return 1;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_SAMPLES, 4);
    win->glfw = glfwCreateWindow(o->width, o->height, title, NULL, NULL);
    if (!win->glfw) {
        fprintf(stderr, "mm: cannot make an OpenGL 3.3 window\n");
        glfwTerminate();
        return 1;
    }
    glfwSetWindowUserPointer(win->glfw, win);
    glfwSetScrollCallback(win->glfw, on_scroll);
    glfwSetKeyCallback(win->glfw, on_key);
    glfwMakeContextCurrent(win->glfw);
    glfwSwapInterval(1);
    mm_error err;
    memset(&err, 0, sizeof err);
    if (mm_renderer_create(glfwGetProcAddress, &win->renderer, &err) != MM_OK) {
        glfwDestroyWindow(win->glfw);
        glfwTerminate();
        return cli_report(&err);
    }
    mm_camera_defaults(&win->camera);
    return 0;
}

static void close_window(window *win)
{
    mm_renderer_destroy(win->renderer);
    if (win->glfw) glfwDestroyWindow(win->glfw);
    glfwTerminate();
    free(win->pixels);
}

/* Mouse drag (left button) orbits, the wheel zooms, the gamepad's right stick orbits too. */
static void camera_controls(window *win, float dt)
{
    double x, y;
    glfwGetCursorPos(win->glfw, &x, &y);
    bool button = glfwGetMouseButton(win->glfw, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
    if (button && win->dragging)
        mm_camera_orbit(&win->camera, (float)(x - win->last_x) * -0.005f, (float)(y - win->last_y) * 0.005f);
    win->dragging = button;
    win->last_x = x, win->last_y = y;
    if (win->scroll != 0.0f) mm_camera_zoom(&win->camera, powf(0.9f, win->scroll));
    win->scroll = 0.0f;
    GLFWgamepadstate pad;
    if (glfwJoystickIsGamepad(GLFW_JOYSTICK_1) && glfwGetGamepadState(GLFW_JOYSTICK_1, &pad)) {
        float rx = pad.axes[GLFW_GAMEPAD_AXIS_RIGHT_X], ry = pad.axes[GLFW_GAMEPAD_AXIS_RIGHT_Y];
        if (fabsf(rx) > 0.15f || fabsf(ry) > 0.15f)
            mm_camera_orbit(&win->camera, -2.0f * rx * dt, 1.5f * ry * dt);
    }
}

/* Draws the scene, saves a screenshot when asked, and shows the frame. */
static int present(window *win, const mm_render_scene *scene, const char *screenshot)
{
    int w, h;
    glfwGetFramebufferSize(win->glfw, &w, &h);
    mm_renderer_draw(win->renderer, &win->camera, w, h, scene);
    int status = 0;
    if (screenshot && w > 0 && h > 0) {
        free(win->pixels);
        win->pixels = malloc((size_t)w * (size_t)h * 3);
        mm_error err;
        memset(&err, 0, sizeof err);
        if (!win->pixels) {
            fprintf(stderr, "mm: out of memory\n");
            status = 1;
        } else {
            mm_renderer_read_pixels(win->renderer, w, h, win->pixels);
            if (mm_png_write(screenshot, win->pixels, w, h, &err) != MM_OK) status = cli_report(&err);
        }
    }
    glfwSwapBuffers(win->glfw);
    return status;
}

/* ---- database mode ---- */

/* The character's settings: the defaults with the runtime tuning of a config: the one given with
 * --config (where tuning is saved), else the one embedded in the database. */
static mm_result desc_from_config(mm_character_desc *d, const mm_database *db, const char *config,
                                  mm_error *err)
{
    if (!config) return mm_character_desc_from_database(d, db, err);
    mm_character_defaults(d);
    mm_config cfg;
    memset(&cfg, 0, sizeof cfg);
    mm_result r = mm_config_load_json(config, &cfg, NULL, err);
    if (r == MM_OK) mm_character_desc_apply_config(d, db, &cfg);
    mm_config_free(&cfg);
    return r;
}

/* The live values: the tuning's copy of the desc. */
static mm_result save_tuning(const mm_view_tuning *t, const mm_database *db, const char *config,
                             mm_error *err)
{
    return mm_config_save_tuning(config, db, &t->desc, err);
}

static double monotonic_seconds(void) { return glfwGetTime(); }

static const char *db_help = "WASD/arrows move  shift run  Q strafe  C crouch  mouse orbit  wheel zoom\n"
                             "1 future  2 matched  3 past  4 contacts  5 bones  6 velocities  H text\n"
                             "tab/shift-tab pick a value  -/= change it  F5 save to config  R reset";

static void read_keys(window *win, mm_view_keys *k)
{
    memset(k, 0, sizeof *k);
    k->forward = down(win, GLFW_KEY_W) || down(win, GLFW_KEY_UP);
    k->back = down(win, GLFW_KEY_S) || down(win, GLFW_KEY_DOWN);
    k->left = down(win, GLFW_KEY_A) || down(win, GLFW_KEY_LEFT);
    k->right = down(win, GLFW_KEY_D) || down(win, GLFW_KEY_RIGHT);
    k->run = down(win, GLFW_KEY_LEFT_SHIFT) || down(win, GLFW_KEY_RIGHT_SHIFT);
    k->strafe = down(win, GLFW_KEY_Q);
    k->crouch = down(win, GLFW_KEY_C);
    GLFWgamepadstate pad;
    if (glfwJoystickIsGamepad(GLFW_JOYSTICK_1) && glfwGetGamepadState(GLFW_JOYSTICK_1, &pad)) {
        k->pad_stick[0] = pad.axes[GLFW_GAMEPAD_AXIS_LEFT_X];
        k->pad_stick[1] = -pad.axes[GLFW_GAMEPAD_AXIS_LEFT_Y]; /* GLFW's y points down */
        k->pad_run =
            pad.axes[GLFW_GAMEPAD_AXIS_RIGHT_TRIGGER] > 0.0f || pad.buttons[GLFW_GAMEPAD_BUTTON_RIGHT_BUMPER];
        k->pad_strafe =
            pad.axes[GLFW_GAMEPAD_AXIS_LEFT_TRIGGER] > 0.0f || pad.buttons[GLFW_GAMEPAD_BUTTON_LEFT_BUMPER];
    }
}

static int view_database(const options *o)
{
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_database db;
    if (mm_database_load(o->db, NULL, &db, &err) != MM_OK) return cli_report(&err);
    mm_input_script script;
    memset(&script, 0, sizeof script);
    if (o->input && mm_input_script_load_json(o->input, &script, &err) != MM_OK) {
        mm_database_free(&db);
        return cli_report(&err);
    }
    mm_searcher searcher;
    mm_character c;
    mm_character_desc desc;
    mm_view view;
    memset(&view, 0, sizeof view);
    mm_body_mesh user_body;
    memset(&user_body, 0, sizeof user_body);
    mm_view_tuning tuning;
    int status = 0;
    if (desc_from_config(&desc, &db, o->config, &err) != MM_OK ||
        mm_searcher_init(&searcher, &db, NULL, &err) != MM_OK) {
        mm_database_free(&db);
        mm_input_script_free(&script);
        return cli_report(&err);
    }
    if (mm_character_init(&c, &db, &searcher, &desc, &err) != MM_OK ||
        mm_view_init(&view, &db, &err) != MM_OK || mm_view_set_scene(&view, o->scene, &err) != MM_OK) {
        status = cli_report(&err);
        goto done_data;
    }
    if (o->mesh_path) {
        if (mm_body_mesh_load(o->mesh_path, db.joints, db.joint_count, &user_body, &err) != MM_OK) {
            status = cli_report(&err);
            goto done_character;
        }
        mm_view_set_body(&view, &user_body);
    }
    mm_character_set_scene(&c, o->scene); /* it walks on the scene's ground */
    mm_view_tuning_init(&tuning, &c);
    window win;
    if ((status = open_window(&win, o, "mm view")) != 0) goto done_character;
    tuning.desc.clock = monotonic_seconds; /* GLFW's clock works once a window is open */
    mm_character_tune(&c, &tuning.desc);
    mm_view_flags flags;
    mm_view_flags_defaults(&flags);
    bool text = true;
    char overlay[MM_VIEW_OVERLAY_MAX + 2048], message[640] = "";
    double last = glfwGetTime(), pending = 0.0, sim_time = 0.0, fps = 60.0;
    mm_input in;
    memset(&in, 0, sizeof in);
    for (long frame = 0; !glfwWindowShouldClose(win.glfw) && (o->frames == 0 || frame < o->frames); ++frame) {
        glfwPollEvents();
        double now = glfwGetTime(), dt = now - last;
        last = now;
        if (dt > 0.0) fps += (1.0 / dt - fps) * 0.05;
        /* scripted runs step a fixed tick per frame so that they are reproducible */
        pending += o->frames ? TICK : fmin(dt, 0.25);
        if (take(&win, GLFW_KEY_ESCAPE)) break;
        if (take(&win, GLFW_KEY_1)) flags.predicted = !flags.predicted;
        if (take(&win, GLFW_KEY_2)) flags.matched = !flags.matched;
        if (take(&win, GLFW_KEY_3)) flags.past = !flags.past;
        if (take(&win, GLFW_KEY_4)) flags.contacts = !flags.contacts;
        if (take(&win, GLFW_KEY_5)) flags.matched_bones = !flags.matched_bones;
        if (take(&win, GLFW_KEY_6)) flags.velocities = !flags.velocities;
        if (take(&win, GLFW_KEY_H)) text = !text;
        bool shift = down(&win, GLFW_KEY_LEFT_SHIFT) || down(&win, GLFW_KEY_RIGHT_SHIFT);
        for (int n = take(&win, GLFW_KEY_TAB); n > 0; --n) mm_view_tuning_select(&tuning, shift ? -1 : 1);
        for (int n = take(&win, GLFW_KEY_MINUS) + take(&win, GLFW_KEY_KP_SUBTRACT); n > 0; --n)
            mm_view_tuning_step(&tuning, -1);
        for (int n = take(&win, GLFW_KEY_EQUAL) + take(&win, GLFW_KEY_KP_ADD); n > 0; --n)
            mm_view_tuning_step(&tuning, 1);
        if (take(&win, GLFW_KEY_F5)) {
            if (!o->config)
                snprintf(message, sizeof message, "start with --config CONFIG.json to save");
            else if (save_tuning(&tuning, &db, o->config, &err) != MM_OK)
                snprintf(message, sizeof message, "not saved: %.200s", err.message);
            else
                snprintf(message, sizeof message, "saved into %.200s", o->config);
        }
        if (take(&win, GLFW_KEY_R)) {
            mm_character_desc tuned = tuning.desc; /* the character starts again, as tuned */
            mm_character_free(&c);
            if (mm_character_init(&c, &db, &searcher, &tuned, &err) != MM_OK) {
                status = cli_report(&err);
                break;
            }
            mm_character_set_scene(&c, o->scene);
            mm_view_tuning_init(&tuning, &c);
        }
        mm_view_keys keys;
        read_keys(&win, &keys);
        while (pending >= TICK) {
            if (o->input)
                mm_input_script_sample(&script, (float)sim_time, &in);
            else
                mm_view_input(&keys, win.camera.yaw, &in);
            mm_character_update(&c, &in, (float)TICK);
            sim_time += TICK;
            pending -= TICK;
        }
        camera_controls(&win, (float)dt);
        mm_vec3 root = c.root.translation;
        mm_camera_follow(&win.camera, mm_vec3_make(root.x, 0.9f, root.z), frame == 0 ? 0.0f : 0.5f,
                         (float)(o->frames ? TICK : dt));
        flags.overlay = text;
        mm_view_update(&view, &c, &in, &flags, (float)fps);
        if (text) {
            size_t at = (size_t)snprintf(overlay, sizeof overlay, "%s\n\n", view.overlay);
            at += mm_view_tuning_text(&tuning, overlay + at, sizeof overlay - at);
            snprintf(overlay + at, sizeof overlay - at, "\n%s\n\n%s", message, db_help);
            view.scene.overlay = overlay;
        }
        bool last_frame = o->frames && frame + 1 == o->frames;
        if ((status = present(&win, &view.scene, last_frame ? o->screenshot : NULL)) != 0) break;
    }
    close_window(&win);
done_character:
    mm_view_free(&view);
    mm_body_mesh_free(&user_body);
    mm_character_free(&c);
done_data:
    mm_searcher_free(&searcher);
    mm_input_script_free(&script);
    mm_database_free(&db);
    return status;
}

/* ---- clip mode ---- */

#define MAX_RANGES 64

typedef struct clip_tags {
    mm_config cfg;
    bool has_cfg;
    int clip; /* index in cfg.clips, -1: none */
    int tag;  /* the tag being edited */
    float ranges[MM_MAX_TAGS][MAX_RANGES][2];
    int counts[MM_MAX_TAGS];
    float mark; /* begin of a range being made; < 0: none */
} clip_tags;

static const char *base_name(const char *path)
{
    const char *s = strrchr(path, '/');
    return s ? s + 1 : path;
}

static int load_clip_tags(const options *o, const char *file, clip_tags *t)
{
    memset(t, 0, sizeof *t);
    t->clip = -1;
    t->mark = -1.0f;
    if (!o->config) return 0;
    mm_error err;
    memset(&err, 0, sizeof err);
    if (mm_config_load_json(o->config, &t->cfg, NULL, &err) != MM_OK) return cli_report(&err);
    t->has_cfg = true;
    for (int i = 0; i < t->cfg.clip_count && t->clip < 0; ++i) {
        const mm_config_clip *cc = &t->cfg.clips[i];
        if (o->clip_name ? strcmp(cc->name, o->clip_name) == 0
                         : strcmp(base_name(cc->file), base_name(file)) == 0)
            t->clip = i;
    }
    if (t->clip < 0) {
        fprintf(stderr, "mm: %s: no clip %s%s in this config\n", o->config,
                o->clip_name ? "named " : "for the file ", o->clip_name ? o->clip_name : base_name(file));
        return 1;
    }
    const mm_config_clip *cc = &t->cfg.clips[t->clip];
    for (int i = 0; i < cc->tag_range_count; ++i) {
        int g = cc->tag_ranges[i].tag;
        if (g < 0 || g >= MM_MAX_TAGS || t->counts[g] >= MAX_RANGES) continue;
        t->ranges[g][t->counts[g]][0] = cc->tag_ranges[i].begin;
        t->ranges[g][t->counts[g]][1] = cc->tag_ranges[i].end;
        ++t->counts[g];
    }
    return 0;
}

/* A 60-column bar over the clip's duration: '#' inside ranges, '|' at the playhead. */
static void timeline(char *out, const float (*ranges)[2], int count, double t, double duration)
{
    enum { COLUMNS = 60 };
    for (int i = 0; i < COLUMNS; ++i) {
        double a = duration * i / COLUMNS, b = duration * (i + 1) / COLUMNS;
        char ch = '-';
        for (int r = 0; r < count; ++r)
            if (ranges[r][0] < b && ranges[r][1] >= a) ch = '#';
        if (t >= a && (t < b || (i == COLUMNS - 1 && t <= duration))) ch = '|';
        out[i] = ch;
    }
    out[COLUMNS] = 0;
}

static const char *clip_help = "space play/pause  left/right step  [ ] 1 s  up/down speed  home/end\n"
                               "T next tag  B begin  E end  X delete at playhead  S save to config";

static int view_clip(const options *o)
{
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_clip clip;
    if (cli_load_clip(o->clip, 0.0, &clip)) return 1;
    static clip_tags tags;
    int status = load_clip_tags(o, o->clip, &tags);
    int n = clip.skeleton.joint_count;
    int *parents = malloc(sizeof(int) * (size_t)n);
    mm_xform *global = malloc(sizeof(mm_xform) * (size_t)n);
    mm_quat *rot = malloc(sizeof(mm_quat) * (size_t)n);
    mm_vec3 *pos = malloc(sizeof(mm_vec3) * (size_t)n);
    window win;
    memset(&win, 0, sizeof win);
    if (status == 0 && (!parents || !global || !rot || !pos)) {
        fprintf(stderr, "mm: out of memory\n");
        status = 1;
    }
    if (status == 0) status = open_window(&win, o, "mm view --clip");
    if (status == 0) {
        for (int j = 0; j < n; ++j) parents[j] = clip.skeleton.joints[j].parent;
        mm_render_scene scene;
        memset(&scene, 0, sizeof scene);
        scene.joint_count = n;
        scene.parents = parents;
        scene.global = global;
        /* the head: the config's head role, else the default name */
        int head = tags.has_cfg ? mm_skeleton_find(&clip.skeleton, tags.cfg.head) : -1;
        scene.head_joint = head > 0 ? head : mm_render_find_head(clip.skeleton.joints, n);
        static mm_render_box boxes[MM_SCENE_MAX_BOXES];
        scene.boxes = boxes;
        scene.box_count = mm_view_scene_boxes(o->scene, boxes, MM_SCENE_MAX_BOXES);
        scene.ground_height = o->scene ? o->scene->ground : 0.0f;
        double duration = mm_clip_duration(&clip), t = 0.0, speed = 1.0, last = glfwGetTime();
        bool playing = true;
        static char overlay[8192];
        char message[640] = "", bar[64];
        for (long frame = 0; !glfwWindowShouldClose(win.glfw) && (o->frames == 0 || frame < o->frames);
             ++frame) {
            glfwPollEvents();
            double now = glfwGetTime(), dt = o->frames ? TICK : fmin(now - last, 0.25);
            last = now;
            double step = 1.0 / clip.fps;
            if (take(&win, GLFW_KEY_ESCAPE)) break;
            if (take(&win, GLFW_KEY_SPACE)) playing = !playing;
            t += step * (take(&win, GLFW_KEY_RIGHT) - take(&win, GLFW_KEY_LEFT));
            t += take(&win, GLFW_KEY_RIGHT_BRACKET) - take(&win, GLFW_KEY_LEFT_BRACKET);
            for (int k = take(&win, GLFW_KEY_UP); k > 0; --k) speed = fmin(speed * 2.0, 8.0);
            for (int k = take(&win, GLFW_KEY_DOWN); k > 0; --k) speed = fmax(speed * 0.5, 0.125);
            if (take(&win, GLFW_KEY_HOME)) t = 0.0;
            if (take(&win, GLFW_KEY_END)) t = duration;
            if (playing) t += dt * speed;
            if (t > duration) t = playing ? fmod(t, duration > 0 ? duration : 1.0) : duration;
            if (t < 0.0) t = 0.0;
            /* tag editing */
            if (tags.has_cfg) {
                if (take(&win, GLFW_KEY_T) && tags.cfg.tag_count > 0)
                    tags.tag = (tags.tag + 1) % tags.cfg.tag_count;
                int g = tags.tag;
                if (take(&win, GLFW_KEY_B)) tags.mark = (float)t;
                if (take(&win, GLFW_KEY_E) && tags.mark >= 0.0f && tags.counts[g] < MAX_RANGES &&
                    tags.cfg.tag_count > 0) {
                    float a = fminf(tags.mark, (float)t), b = fmaxf(tags.mark, (float)t);
                    tags.ranges[g][tags.counts[g]][0] = a;
                    tags.ranges[g][tags.counts[g]][1] = b;
                    ++tags.counts[g];
                    tags.mark = -1.0f;
                }
                if (take(&win, GLFW_KEY_X))
                    for (int k = 0; k < tags.counts[g]; ++k)
                        if (tags.ranges[g][k][0] <= t && t <= tags.ranges[g][k][1]) {
                            memmove(tags.ranges[g][k], tags.ranges[g][k + 1],
                                    sizeof(float) * 2 * (size_t)(tags.counts[g] - k - 1));
                            --tags.counts[g];
                            --k;
                        }
                if (take(&win, GLFW_KEY_S) && tags.cfg.tag_count > 0) {
                    const char *name = tags.cfg.clips[tags.clip].name;
                    if (mm_config_save_clip_tags(o->config, name, tags.cfg.tag_names[g],
                                                 (const float(*)[2])tags.ranges[g], tags.counts[g],
                                                 &err) != MM_OK)
                        snprintf(message, sizeof message, "not saved: %.200s", err.message);
                    else
                        snprintf(message, sizeof message, "saved %s of %s into %.150s", tags.cfg.tag_names[g],
                                 name, o->config);
                }
            }
            mm_clip_sample(&clip, (float)t, rot, pos);
            mm_fk(&clip.skeleton, rot, pos, global);
            camera_controls(&win, (float)dt);
            mm_vec3 root = global[0].translation;
            mm_camera_follow(&win.camera, mm_vec3_make(root.x, 0.9f, root.z), frame == 0 ? 0.0f : 0.4f,
                             (float)dt);
            size_t at =
                (size_t)snprintf(overlay, sizeof overlay, "%s  frame %d/%d  t %.2f/%.2f s  x%g %s\n",
                                 base_name(o->clip), (int)floor(t * clip.fps + 1e-6), clip.frame_count, t,
                                 duration, speed, playing ? "playing" : "paused");
            for (int g = 0; tags.has_cfg && g < tags.cfg.tag_count && at < sizeof overlay - 128; ++g) {
                timeline(bar, (const float(*)[2])tags.ranges[g], tags.counts[g], t, duration);
                at += (size_t)snprintf(overlay + at, sizeof overlay - at, "%c%-10.10s %s\n",
                                       g == tags.tag ? '>' : ' ', tags.cfg.tag_names[g], bar);
            }
            if (!tags.has_cfg) {
                timeline(bar, NULL, 0, t, duration);
                at += (size_t)snprintf(overlay + at, sizeof overlay - at, "           %s\n", bar);
            }
            if (tags.mark >= 0.0f)
                at += (size_t)snprintf(overlay + at, sizeof overlay - at,
                                       "range begins at %.2f s: E ends it\n", (double)tags.mark);
            snprintf(overlay + at, sizeof overlay - at, "%s\n\n%s", message, clip_help);
            scene.overlay = overlay;
            bool last_frame = o->frames && frame + 1 == o->frames;
            if ((status = present(&win, &scene, last_frame ? o->screenshot : NULL)) != 0) break;
        }
        close_window(&win);
    }
    if (tags.has_cfg) mm_config_free(&tags.cfg);
    free(parents);
    free(global);
    free(rot);
    free(pos);
    mm_clip_free(&clip);
    return status;
}

int mm_cmd_view(int argc, char **argv)
{
    options o;
    memset(&o, 0, sizeof o);
    o.width = 1280;
    o.height = 720;
    const char *usage = "usage: mm view DB.mmdb [--config CONFIG.json] [--input SCRIPT.json] [--mesh FILE] | "
                        "mm view --clip FILE.bvh "
                        "[--config CONFIG.json] [--clip-name NAME]  [--scene SCENE.json] [--size 1280x720] "
                        "[--frames N --screenshot OUT.png]";
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (strcmp(a, "--clip") == 0 && v)
            o.clip = argv[++i];
        else if (strcmp(a, "--config") == 0 && v)
            o.config = argv[++i];
        else if (strcmp(a, "--clip-name") == 0 && v)
            o.clip_name = argv[++i];
        else if (strcmp(a, "--input") == 0 && v)
            o.input = argv[++i];
        else if (strcmp(a, "--scene") == 0 && v)
            o.scene_path = argv[++i];
        else if (strcmp(a, "--mesh") == 0 && v)
            o.mesh_path = argv[++i];
        else if (strcmp(a, "--screenshot") == 0 && v)
            o.screenshot = argv[++i];
        else if (strcmp(a, "--size") == 0 && v) {
            if (!cli_parse_size(v, &o.width, &o.height))
                return cli_usage_error("view", "--size needs WIDTHxHEIGHT, each 16 to 4096");
            ++i;
        } else if (strcmp(a, "--frames") == 0 && v) {
            if (!cli_parse_int(v, 1, 100000000, &o.frames))
                return cli_usage_error("view", "--frames needs 1 or more");
            ++i;
        } else if (a[0] == '-' && a[1])
            return cli_usage_error("view", "unknown or incomplete option '%s'\n%s", a, usage);
        else if (!o.db)
            o.db = a;
        else
            return cli_usage_error("view", "unexpected argument '%s'", a);
    }
    if ((!o.db) == (!o.clip)) return cli_usage_error("view", "%s", usage);
    if (o.screenshot && !o.frames) return cli_usage_error("view", "--screenshot needs --frames N");
    if (o.mesh_path && o.clip) return cli_usage_error("view", "--mesh goes with a database, not --clip");
    static mm_scene scene; /* large: kept off the stack */
    if (o.scene_path) {
        mm_error err;
        memset(&err, 0, sizeof err);
        if (mm_scene_load_json(o.scene_path, &scene, &err) != MM_OK) return cli_report(&err);
        o.scene = &scene;
    }
    return o.clip ? view_clip(&o) : view_database(&o);
}
