/* mm view DB.mmdb [--config CONFIG] | mm view --clip FILE.bvh [--config CONFIG] [--clip-name NAME]
 * (either with [--scene SCENE.json]: its boxes are drawn)
 * The interactive viewer (GLFW + OpenGL 3.3): drive a character on a database with keyboard or
 * gamepad and debug its motion matching in a panel (Dear ImGui, view_panel.h): its status and
 * every cost term, the runtime layers as switches, live tuning saved into the config, the
 * search's best candidates drawn as ghosts, and a timeline of the recorded ticks to pause, step,
 * rewind and resume from (view_debug.h); or inspect a clip: play, scrub, step, and edit its tag
 * ranges. --frames N and --screenshot FILE.png run N frames and save the last one; --script
 * KEYS.txt plays a key script (view_script.h) with --screenshot-dir DIR for its shots. */
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <GLFW/glfw3.h>

#include <mm/body_mesh.h>
#include <mm/character_config.h>
#include <mm/character.h>
#include <mm/config_json.h>
#include <mm/input_json.h>
#include <mm/mm.h>
#include <mm/render.h>
#include <mm/scene_json.h>
#include <mm/trace.h>
#include <mm/view.h>

#include "cli.h"
#include "commands.h"
#include "view_config.h"
#include "view_debug.h"
#include "view_panel.h"
#include "view_script.h"

#define TICK (1.0 / 60.0)

typedef struct options {
    const char *db, *clip, *config, *clip_name, *input, *screenshot, *scene_path, *script, *screenshot_dir,
        *replay;
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
    double orbited;                 /* when the user last turned or zoomed the camera (glfwGetTime) */
    int pressed[GLFW_KEY_LAST + 1]; /* key presses since the last frame (edges, not levels) */
    bool script;                    /* keys come from a key script: held is their state */
    bool held[GLFW_KEY_LAST + 1];
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

static bool down(window *win, int key)
{
    return win->script ? win->held[key] : glfwGetKey(win->glfw, key) == GLFW_PRESS;
}

static int open_window(window *win, const options *o, const char *title)
{
    memset(win, 0, sizeof *win);
    win->orbited = -INFINITY; /* the camera chases from the start */
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
    if (button && win->dragging && (x != win->last_x || y != win->last_y)) {
        mm_camera_orbit(&win->camera, (float)(x - win->last_x) * -0.005f, (float)(y - win->last_y) * 0.005f);
        win->orbited = glfwGetTime();
    }
    win->dragging = button;
    win->last_x = x, win->last_y = y;
    if (win->scroll != 0.0f) {
        mm_camera_zoom(&win->camera, powf(0.9f, win->scroll));
        win->orbited = glfwGetTime();
    }
    win->scroll = 0.0f;
    GLFWgamepadstate pad;
    if (glfwJoystickIsGamepad(GLFW_JOYSTICK_1) && glfwGetGamepadState(GLFW_JOYSTICK_1, &pad)) {
        float rx = pad.axes[GLFW_GAMEPAD_AXIS_RIGHT_X], ry = pad.axes[GLFW_GAMEPAD_AXIS_RIGHT_Y];
        if (fabsf(rx) > 0.15f || fabsf(ry) > 0.15f) {
            mm_camera_orbit(&win->camera, -2.0f * rx * dt, 1.5f * ry * dt);
            win->orbited = glfwGetTime();
        }
    }
}

/* Saves the current framebuffer's w x h pixels as a PNG. */
static int save_screenshot(window *win, const char *png, int w, int h)
{
    free(win->pixels);
    win->pixels = malloc((size_t)w * (size_t)h * 3);
    if (!win->pixels) {
        fprintf(stderr, "mm: out of memory\n");
        return 1;
    }
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_renderer_read_pixels(win->renderer, w, h, win->pixels);
    return mm_png_write(png, win->pixels, w, h, &err) != MM_OK ? cli_report(&err) : 0;
}

/* Draws the scene, saves a screenshot when asked, and shows the frame. */
static int present(window *win, const mm_render_scene *scene, const char *screenshot)
{
    int w, h;
    glfwGetFramebufferSize(win->glfw, &w, &h);
    mm_renderer_draw(win->renderer, &win->camera, w, h, scene);
    int status = screenshot && w > 0 && h > 0 ? save_screenshot(win, screenshot, w, h) : 0;
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

static double monotonic_seconds(void) { return glfwGetTime(); }

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
    if (!win->script && glfwJoystickIsGamepad(GLFW_JOYSTICK_1) &&
        glfwGetGamepadState(GLFW_JOYSTICK_1, &pad)) {
        k->pad_stick[0] = pad.axes[GLFW_GAMEPAD_AXIS_LEFT_X];
        k->pad_stick[1] = -pad.axes[GLFW_GAMEPAD_AXIS_LEFT_Y]; /* GLFW's y points down */
        k->pad_run =
            pad.axes[GLFW_GAMEPAD_AXIS_RIGHT_TRIGGER] > 0.0f || pad.buttons[GLFW_GAMEPAD_BUTTON_RIGHT_BUMPER];
        k->pad_strafe =
            pad.axes[GLFW_GAMEPAD_AXIS_LEFT_TRIGGER] > 0.0f || pad.buttons[GLFW_GAMEPAD_BUTTON_LEFT_BUMPER];
    }
}

static bool jump_down(window *win)
{
    GLFWgamepadstate pad;
    if (!win->script && glfwJoystickIsGamepad(GLFW_JOYSTICK_1) &&
        glfwGetGamepadState(GLFW_JOYSTICK_1, &pad) && pad.buttons[GLFW_GAMEPAD_BUTTON_A])
        return true;
    return down(win, GLFW_KEY_J);
}

/* What the debugger draws beside the character. */
/* s after the user last turned or zoomed the camera from which it chases the character again */
#define CHASE_AFTER_ORBIT 3.0
/* s: the chase turns the camera behind the character slowly, so that the keys (relative to the
 * camera) keep their meaning while the character turns */
#define CHASE_YAW_HALFLIFE 2.0f
/* the chase keeps what it frames within this much of the image's half-width about its middle,
 * clear of the panel's windows on either side */
#define CHASE_HALF_WIDTH 0.35f
/* The camera behind the character, framing its body and its predicted path, turning slowly. */
static void chase_camera(window *win, const mm_character *c, const mm_input *in, float dt)
{
    mm_camera_framing framing;
    mm_camera_framing_defaults(&framing);
    framing.yaw_halflife = CHASE_YAW_HALFLIFE;
    framing.half_width = CHASE_HALF_WIDTH;
    int w = 0, h = 0;
    glfwGetFramebufferSize(win->glfw, &w, &h);
    mm_view_chase(&win->camera, &framing, c, in, h > 0 ? (float)w / (float)h : 1.0f, dt);
}

#define CANDIDATES       5                   /* listed in the panel */
#define RECORD_SECONDS   120.0               /* the timeline keeps this much */
#define RECORD_MAX_BYTES ((size_t)512 << 20) /* or less, to stay within this memory */
#define GHOSTS           3                   /* of them drawn beside the character (the one picked nearest) */
#define GHOST_SPACING    0.7f                /* m between ghosts, to the camera's right of the character */
#define PREVIEW_DISTANCE 0.9f                /* m to the camera's left: the picked candidate's clip playing */
static const mm_rgba ghost_color = {0.55f, 0.6f, 0.75f, 1.0f};
static const mm_rgba picked_color = {0.95f, 0.8f, 0.25f, 1.0f};
static const mm_rgba preview_color = {0.3f, 0.85f, 0.45f, 1.0f};

typedef struct debugger {
    view_sim sim;
    mm_view_tuning tuning;
    mm_view_flags flags;
    view_draws draws;
    mm_candidate candidates[CANDIDATES];
    int candidate_count, selected;
    view_preview preview;
    bool paused;
    bool jumped;           /* went to another tick: the camera is put on the character at once */
    mm_render_line *lines; /* the view's lines with the ghosts' */
    int line_capacity;
    mm_xform *pose; /* a ghost's pose */
    char message[640];
} debugger;

/* The camera's right on the ground (mm_view_input's). */
static mm_vec3 camera_right(const mm_camera *cam)
{
    return mm_vec3_make(-cosf(cam->yaw), 0.0f, sinf(cam->yaw));
}

static mm_xform ghost_anchor(const mm_character *c, const mm_camera *cam, float offset)
{
    mm_xform a = c->root;
    a.translation = mm_vec3_add(a.translation, mm_vec3_scale(camera_right(cam), offset));
    return a;
}

/* The candidates drawn as ghosts, nearest first: the one picked, then the best GHOSTS. Returns how
 * many. */
static int ghost_order(const debugger *d, int *order)
{
    int n = 0;
    if (!d->draws.ghosts) return 0;
    if (d->selected >= 0 && d->selected < d->candidate_count && d->candidates[d->selected].frame >= 0)
        order[n++] = d->selected;
    for (int i = 0; i < d->candidate_count && i < GHOSTS; ++i)
        if (i != d->selected && d->candidates[i].frame >= 0) order[n++] = i;
    return n;
}

/* The view's lines, then the ghosts of the candidates and the preview. */
static void add_ghosts(debugger *d, mm_view *view, const mm_camera *cam)
{
    const mm_character *c = &d->sim.character;
    const mm_database *db = c->db;
    int n = view->scene.line_count < d->line_capacity ? view->scene.line_count : d->line_capacity;
    memcpy(d->lines, view->scene.lines, sizeof *d->lines * (size_t)n);
    int order[CANDIDATES];
    int shown = ghost_order(d, order);
    for (int k = 0; k < shown; ++k) {
        int i = order[k];
        view_ghost_pose(db, d->candidates[i].frame, ghost_anchor(c, cam, GHOST_SPACING * (float)(k + 1)),
                        d->pose);
        view_ghost_lines(db, d->pose, i == d->selected ? picked_color : ghost_color, d->lines, &n,
                         d->line_capacity);
    }
    if (d->draws.preview && d->selected >= 0 && d->preview.frame >= 0) {
        view_ghost_pose(db, d->preview.frame, ghost_anchor(c, cam, -PREVIEW_DISTANCE), d->pose);
        view_ghost_lines(db, d->pose, preview_color, d->lines, &n, d->line_capacity);
    }
    view->scene.lines = d->lines;
    view->scene.line_count = n;
}

static void select_candidate(debugger *d, int i)
{
    d->selected = i >= 0 && i < d->candidate_count ? i : -1;
    view_preview_start(&d->preview, d->selected >= 0 ? d->candidates[d->selected].frame : -1);
}

/* Hands the tuning and layers to the character (recorded); a switch of the transition layer
 * starts the character again. */
static int retune(debugger *d, mm_error *err)
{
    mm_character_desc desc;
    mm_view_tuning_desc(&d->tuning, &desc);
    if (desc.transition_mode != d->sim.character.desc.transition_mode) {
        if (view_sim_restart(&d->sim, &desc, err) != MM_OK) return cli_report(err);
        snprintf(d->message, sizeof d->message, "%s: the character started again",
                 d->tuning.layers.crossfade ? "crossfade" : "inertialization");
        mm_view_tuning tuned = d->tuning; /* the entries follow the transition in use */
        mm_view_tuning_init(&d->tuning, &d->sim.character);
        for (int i = 0; i < d->tuning.count; ++i)
            for (int k = 0; k < tuned.count; ++k)
                if (strcmp(d->tuning.entries[i].name, tuned.entries[k].name) == 0)
                    d->tuning.entries[i].saved = tuned.entries[k].saved;
        d->tuning.desc = tuned.desc; /* the values as tuned, not as the layers set them */
        d->tuning.saved_layers = tuned.saved_layers;
        d->tuning.layers = tuned.layers;
        return 0;
    }
    view_sim_tune(&d->sim, &desc);
    return 0;
}

/* What a screenshot shows, beside it: DIR/NAME.json (the camera, the character's joints, the
 * candidates and their ghosts, the panel's windows), for the tests to check the image against. */
static int write_shot_facts(const char *path, debugger *d, const mm_camera *cam, int w, int h,
                            const view_ui *ui)
{
    FILE *f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "mm: %s: cannot create it\n", path);
        return 1;
    }
    const mm_character *c = &d->sim.character;
    const mm_database *db = c->db;
    int64_t first, last;
    view_sim_range(&d->sim, &first, &last);
    fprintf(
        f,
        "{\"width\": %d, \"height\": %d, \"tick\": %lld, \"first\": %lld, \"last\": %lld, \"paused\": %s, "
        "\"frame\": %d, \"move\": %d,\n",
        w, h, (long long)d->sim.now, (long long)first, (long long)last, d->paused ? "true" : "false",
        c->frame, c->move_playing);
    fprintf(
        f,
        " \"camera\": {\"target\": [%.9g, %.9g, %.9g], \"yaw\": %.9g, \"pitch\": %.9g, \"distance\": %.9g, "
        "\"fov_y\": %.9g, \"z_near\": %.9g, \"z_far\": %.9g},\n",
        (double)cam->target.x, (double)cam->target.y, (double)cam->target.z, (double)cam->yaw,
        (double)cam->pitch, (double)cam->distance, (double)cam->fov_y, (double)cam->z_near,
        (double)cam->z_far);
    fprintf(f, " \"joints\": [");
    for (int j = 0; j < db->joint_count; ++j)
        fprintf(f, "%s[%.9g, %.9g, %.9g]", j ? ", " : "", (double)c->global[j].translation.x,
                (double)c->global[j].translation.y, (double)c->global[j].translation.z);
    /* how far foot IK moved the ankles from the animation (0 with it off) */
    float ik_offset = 0.0f;
    for (int k = 0; k < 2; ++k)
        if (c->foot_joint[k] >= 0)
            ik_offset = fmaxf(ik_offset, mm_vec3_length(mm_vec3_sub(c->global[c->foot_joint[k]].translation,
                                                                    c->raw_contact_positions[2 * k])));
    fprintf(f, "],\n \"ik_offset\": %.9g, \"selected\": %d, \"preview_frame\": %d,\n", (double)ik_offset,
            d->selected, d->selected >= 0 ? d->preview.frame : -1);
    const mm_view_layers *l = &d->tuning.layers;
    fprintf(f,
            " \"layers\": {\"crossfade\": %d, \"foot_ik\": %d, \"distance_matching\": %d, \"warping\": %d, "
            "\"root_sync\": %d, \"root_clamps\": %d},\n",
            l->crossfade, l->foot_ik, l->distance_matching, l->warping, l->root_sync, l->root_clamps);
    fprintf(f, " \"candidates\": [");
    for (int i = 0; i < d->candidate_count; ++i) {
        const mm_candidate *v = &d->candidates[i];
        fprintf(
            f,
            "%s\n  {\"frame\": %d, \"cost\": %.9g, \"base\": %.9g, \"terms\": [%.9g, %.9g, %.9g, %.9g, %.9g]",
            i ? "," : "", v->frame, (double)v->cost, (double)v->base, (double)v->terms.pose_position,
            (double)v->terms.pose_velocity, (double)v->terms.root_velocity, (double)v->terms.traj_position,
            (double)v->terms.traj_direction);
        fprintf(f, "}");
    }
    fprintf(f, "],\n \"ghosts\": [");
    int order[CANDIDATES];
    int shown = ghost_order(d, order);
    for (int k = 0; k < shown; ++k) {
        int i = order[k];
        view_ghost_pose(db, d->candidates[i].frame, ghost_anchor(c, cam, GHOST_SPACING * (float)(k + 1)),
                        d->pose);
        fprintf(f, "%s\n  {\"candidate\": %d, \"joints\": [", k ? "," : "", i);
        for (int j = 1; j < db->joint_count; ++j)
            fprintf(f, "%s[%.9g, %.9g, %.9g]", j > 1 ? ", " : "", (double)d->pose[j].translation.x,
                    (double)d->pose[j].translation.y, (double)d->pose[j].translation.z);
        fprintf(f, "]}");
    }
    static const char *const names[VIEW_PANEL_WINDOWS] = {"status", "layers", "tuning", "candidates",
                                                          "timeline"};
    fprintf(f, "],\n \"panel\": {");
    for (int k = 0; k < VIEW_PANEL_WINDOWS; ++k)
        fprintf(f, "%s\"%s\": [%.1f, %.1f, %.1f, %.1f]", k ? ", " : "", names[k], (double)ui->rects[k][0],
                (double)ui->rects[k][1], (double)ui->rects[k][2], (double)ui->rects[k][3]);
    fprintf(f, "},\n \"message\": \"");
    for (const char *m = d->message; *m; ++m) { /* JSON-escaped */
        if (*m == '"' || *m == '\\') fputc('\\', f);
        fputc((unsigned char)*m < 0x20 ? ' ' : *m, f);
    }
    fprintf(f, "\"}\n");
    return fclose(f) == 0 ? 0 : 1;
}

/* Keys of the debugger and its layers (the panel's buttons do the same). */
static void debugger_keys(window *win, debugger *d, view_ui *ui)
{
    if (take(win, GLFW_KEY_SPACE)) ui->toggle_pause = true;
    ui->step_back += take(win, GLFW_KEY_COMMA);
    ui->step_forward += take(win, GLFW_KEY_PERIOD);
    if (take(win, GLFW_KEY_HOME)) ui->seek = 0;
    if (take(win, GLFW_KEY_END)) ui->seek = LONG_MAX;
    mm_view_flags *f = &d->flags;
    if (take(win, GLFW_KEY_1)) f->predicted = !f->predicted;
    if (take(win, GLFW_KEY_2)) f->matched = !f->matched;
    if (take(win, GLFW_KEY_3)) f->past = !f->past;
    if (take(win, GLFW_KEY_4)) f->contacts = !f->contacts;
    if (take(win, GLFW_KEY_5)) f->matched_bones = !f->matched_bones;
    if (take(win, GLFW_KEY_6)) f->velocities = !f->velocities;
    if (take(win, GLFW_KEY_7)) d->draws.ghosts = !d->draws.ghosts;
    if (take(win, GLFW_KEY_8)) d->draws.preview = !d->draws.preview;
    mm_view_layers *l = &d->tuning.layers;
    bool *switches[] = {&l->foot_ik, &l->distance_matching, &l->warping, &l->root_sync, &l->root_clamps};
    int keys[] = {GLFW_KEY_F, GLFW_KEY_G, GLFW_KEY_V, GLFW_KEY_Y, GLFW_KEY_U};
    for (int k = 0; k < 5; ++k)
        if (take(win, keys[k]) % 2) {
            *switches[k] = !*switches[k];
            ui->layers_changed = true;
        }
    if (take(win, GLFW_KEY_X) % 2) {
        l->crossfade = !l->crossfade;
        ui->layers_changed = true;
    }
    bool shift = down(win, GLFW_KEY_LEFT_SHIFT) || down(win, GLFW_KEY_RIGHT_SHIFT);
    for (int n = take(win, GLFW_KEY_TAB); n > 0; --n) mm_view_tuning_select(&d->tuning, shift ? -1 : 1);
    for (int n = take(win, GLFW_KEY_MINUS) + take(win, GLFW_KEY_KP_SUBTRACT); n > 0; --n) {
        mm_view_tuning_step(&d->tuning, -1);
        ui->tuning_changed = true;
    }
    for (int n = take(win, GLFW_KEY_EQUAL) + take(win, GLFW_KEY_KP_ADD); n > 0; --n) {
        mm_view_tuning_step(&d->tuning, 1);
        ui->tuning_changed = true;
    }
    for (int n = take(win, GLFW_KEY_RIGHT_BRACKET); n > 0; --n) {
        *ui->selected = *ui->selected + 1 < d->candidate_count ? *ui->selected + 1 : 0;
        ui->select_changed = true;
    }
    for (int n = take(win, GLFW_KEY_LEFT_BRACKET); n > 0; --n) {
        *ui->selected = *ui->selected > 0 ? *ui->selected - 1 : d->candidate_count - 1;
        ui->select_changed = true;
    }
    if (take(win, GLFW_KEY_F5)) ui->save = true;
    if (take(win, GLFW_KEY_R)) ui->reset = true;
}

/* Carries out the panel's and the keys' requests. */
static int debugger_requests(debugger *d, const options *o, view_ui *ui, const mm_input *live, mm_error *err)
{
    view_sim *sim = &d->sim;
    if (ui->layers_changed || ui->tuning_changed) {
        int status = retune(d, err);
        if (status) return status;
    }
    if (ui->save) {
        if (!o->config) {
            snprintf(d->message, sizeof d->message, "start with --config CONFIG.json to save");
        } else {
            char why[400] = "";
            int n = view_config_save(o->config, &d->tuning, why, sizeof why);
            if (n < 0)
                snprintf(d->message, sizeof d->message, "not saved: %.300s", why);
            else
                snprintf(d->message, sizeof d->message, "%d value%s saved into %.200s", n, n == 1 ? "" : "s",
                         o->config);
        }
    }
    if (ui->reset) {
        mm_character_desc desc;
        mm_view_tuning_desc(&d->tuning, &desc);
        if (view_sim_restart(sim, &desc, err) != MM_OK) return cli_report(err);
    }
    if (ui->toggle_pause) d->paused = !d->paused;
    long seek = ui->seek;
    if (ui->step_back > 0) {
        d->paused = true;
        seek = sim->now > ui->step_back ? sim->now - ui->step_back : 0;
    }
    if (seek >= 0 && view_sim_seek(sim, seek, err) != MM_OK) return cli_report(err);
    if (seek >= 0) d->paused = d->jumped = true;
    mm_character_desc desc;
    mm_view_tuning_desc(&d->tuning, &desc);
    for (int n = 0; n < ui->step_forward; ++n) {
        d->paused = true;
        view_sim_forward(sim, live, &desc);
    }
    ui->layers_changed = ui->tuning_changed = ui->save = ui->reset = ui->toggle_pause = false;
    ui->step_back = ui->step_forward = 0;
    ui->seek = -1;
    return 0;
}

/* The input of tick `tick` from --input's script, or a trace's (as mm simulate ran it); else in is
 * left as the keys made it. */
static void scripted_input(const options *o, const mm_input_script *script, int64_t tick, mm_input *in)
{
    if (o->replay)
        mm_input_script_sample_tick(script, (float)((double)tick * TICK), (float)TICK, in);
    else if (o->input)
        mm_input_script_sample(script, (float)((double)tick * TICK), in);
}

/* A trace (mm simulate --trace) to open on the timeline: its input and switches, and its searches
 * to set beside the viewer's own. */
typedef struct replay {
    mm_trace trace;
    bool loaded;
    int search; /* the trace's search at or before the tick shown, -1: none */
    char note[320];
} replay;

static int load_replay(const options *o, const mm_database *db, replay *rp, mm_input_script *script,
                       mm_character_desc *desc, mm_error *err)
{
    if (mm_trace_read(o->replay, &rp->trace, err) != MM_OK) return cli_report(err);
    rp->loaded = true;
    const mm_trace_run *run = &rp->trace.run;
    if (mm_trace_db_checksum(db) != run->db_checksum || (uint64_t)db->size != run->db_size) {
        fprintf(stderr, "mm: %s: the trace was made on another database (%s)\n", o->replay, run->db_path);
        return 1;
    }
    if (fabs(run->fps - 1.0 / TICK) > 1e-9) {
        fprintf(stderr, "mm: %s: the trace ticks %g times a second; the viewer ticks 60\n", o->replay,
                run->fps);
        return 1;
    }
    if (run->path_file[0]) {
        fprintf(stderr, "mm: %s: a trace of a path run (--path) cannot be opened in the viewer\n", o->replay);
        return 1;
    }
    mm_result r;
    if (run->random_seed >= 0) {
        mm_input_random_desc rd;
        memset(&rd, 0, sizeof rd);
        rd.seconds = (float)run->random_seconds;
        r = mm_input_script_random(script, (uint64_t)run->random_seed, &rd);
        if (r != MM_OK) mm_error_set(err, r, 0, 0, "%s: cannot make the random input", o->replay);
    } else {
        const char *text = run->input_text ? run->input_text : "";
        r = mm_input_script_parse_json(text, strlen(text), run->input_path, script, err);
    }
    if (r != MM_OK) return cli_report(err);
    /* the run's switches over the database's settings */
    if (run->distance_matching >= 0) desc->distance_matching = run->distance_matching != 0;
    if (run->warping >= 0) desc->warping = run->warping != 0;
    if (run->transition_mode >= 0) desc->transition_mode = (mm_transition_mode)run->transition_mode;
    if (run->crossfade_time >= 0)
        desc->crossfade_time = run->crossfade_time > 0 ? (float)run->crossfade_time : MM_OFF;
    return 0;
}

/* The trace's last search at or before the tick shown, against the viewer's own. */
static void replay_note(replay *rp, const mm_character *c, int64_t now)
{
    const mm_trace *t = &rp->trace;
    int lo = 0, hi = t->search_count - 1, found = -1;
    while (lo <= hi) { /* the trace's ticks count from 0: tick k ends with now = k + 1 */
        int mid = (lo + hi) / 2;
        if (t->searches[mid].tick <= now - 1)
            found = mid, lo = mid + 1;
        else
            hi = mid - 1;
    }
    rp->search = found;
    if (found < 0) {
        snprintf(rp->note, sizeof rp->note, "trace: no search yet");
        return;
    }
    const mm_trace_search *s = &t->searches[found];
    const mm_trace_candidate *best = s->candidate_count > 0 ? &t->candidates[s->candidate_first] : NULL;
    int mine = c->last_result.frame;
    snprintf(rp->note, sizeof rp->note,
             "trace: search at tick %d (line %ld): best frame %d cost %.4f%s; here %d: %s", s->tick + 1,
             s->line, best ? best->frame : -1, best ? (double)best->cost : 0.0,
             s->transition ? " (jumped)" : "", mine, best && best->frame == mine ? "the same" : "DIFFERENT");
}

static int view_database(const options *o)
{
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_database db;
    if (mm_database_load(o->db, NULL, &db, &err) != MM_OK) return cli_report(&err);
    mm_input_script script;
    memset(&script, 0, sizeof script);
    view_script keys_script;
    memset(&keys_script, 0, sizeof keys_script);
    if (o->input && mm_input_script_load_json(o->input, &script, &err) != MM_OK) {
        mm_database_free(&db);
        return cli_report(&err);
    }
    if (o->script && view_script_load(o->script, TICK, &keys_script)) {
        mm_input_script_free(&script);
        mm_database_free(&db);
        return 1;
    }
    mm_searcher searcher;
    mm_character_desc desc;
    mm_view view;
    memset(&view, 0, sizeof view);
    static debugger d; /* large: kept off the stack */
    memset(&d, 0, sizeof d);
    mm_body_mesh user_body;
    memset(&user_body, 0, sizeof user_body);
    int status = 0;
    if (desc_from_config(&desc, &db, o->config, &err) != MM_OK ||
        mm_searcher_init(&searcher, &db, NULL, &err) != MM_OK) {
        mm_database_free(&db);
        mm_input_script_free(&script);
        view_script_free(&keys_script);
        return cli_report(&err);
    }
    static replay rp; /* large: kept off the stack */
    memset(&rp, 0, sizeof rp);
    const mm_scene *scene = o->scene;
    static mm_scene trace_scene;
    if (o->replay && (status = load_replay(o, &db, &rp, &script, &desc, &err)) != 0) goto done_data;
    if (o->replay && !scene && rp.trace.run.scene_path[0]) {
        if (mm_scene_load_json(rp.trace.run.scene_path, &trace_scene, &err) != MM_OK) {
            status = cli_report(&err);
            goto done_data;
        }
        scene = &trace_scene;
    }
    d.line_capacity = 256 + (GHOSTS + 2) * db.joint_count;
    d.lines = malloc(sizeof *d.lines * (size_t)d.line_capacity);
    d.pose = malloc(sizeof *d.pose * (size_t)db.joint_count);
    if (!d.lines || !d.pose) {
        fprintf(stderr, "mm: out of memory\n");
        status = 1;
        goto done_data;
    }
    if (view_sim_init(&d.sim, &db, &searcher, scene, &desc, (float)TICK, RECORD_SECONDS, RECORD_MAX_BYTES,
                      CANDIDATES, &err) != MM_OK) {
        status = cli_report(&err);
        goto done_data;
    }
    if (mm_view_init(&view, &db, &err) != MM_OK || mm_view_set_scene(&view, scene, &err) != MM_OK) {
        status = cli_report(&err);
        goto done_character;
    }
    if (o->mesh_path) {
        if (mm_body_mesh_load(o->mesh_path, db.joints, db.joint_count, &user_body, &err) != MM_OK) {
            status = cli_report(&err);
            goto done_character;
        }
        mm_view_set_body(&view, &user_body);
    }
    mm_view_tuning_init(&d.tuning, &d.sim.character);
    mm_view_flags_defaults(&d.flags);
    d.flags.overlay = false; /* the panel shows it */
    d.draws.ghosts = d.draws.preview = true;
    d.selected = -1;
    d.preview.frame = -1;
    window win;
    if ((status = open_window(&win, o, "mm view")) != 0) goto done_character;
    win.script = o->script != NULL;
    view_panel *panel = view_panel_create(win.glfw);
    if (!panel) {
        fprintf(stderr, "mm: the panel (Dear ImGui) cannot start in this OpenGL context\n");
        status = 1;
        goto done_window;
    }
    d.tuning.desc.clock = monotonic_seconds; /* GLFW's clock works once a window is open */
    if ((status = retune(&d, &err)) != 0) goto done_panel;
    if (rp.loaded) { /* the trace's run, recorded, shown from its start */
        mm_character_desc tuned;
        mm_view_tuning_desc(&d.tuning, &tuned);
        for (int f = 0; f < rp.trace.run.ticks; ++f) {
            mm_input in_f;
            memset(&in_f, 0, sizeof in_f);
            scripted_input(o, &script, d.sim.now, &in_f);
            view_sim_step(&d.sim, &in_f, &tuned);
        }
        /* the trace's own replay, search line against search line (mm_trace_player) */
        mm_trace_player *player = NULL;
        if (mm_trace_player_open(&player, &rp.trace, &db, &err) != MM_OK) {
            status = cli_report(&err);
            goto done_panel;
        }
        while (mm_trace_player_step(player, NULL) == MM_OK) continue;
        const mm_trace_divergence *dv = mm_trace_player_divergence(player);
        if (dv->diverged)
            snprintf(d.message, sizeof d.message,
                     "the replay differs from the trace from tick %d (line %ld): %.300s", dv->tick + 1,
                     dv->line, dv->message);
        else
            snprintf(d.message, sizeof d.message,
                     "the replay makes every search of the trace, byte for byte");
        mm_trace_player_close(player);
        if (view_sim_seek(&d.sim, 1, &err) != MM_OK) {
            status = cli_report(&err);
            goto done_panel;
        }
        d.paused = true;
    }
    view_ui ui;
    memset(&ui, 0, sizeof ui);
    ui.seek = -1;
    bool show_panel = true, scripted = o->script || o->frames;
    double last = glfwGetTime(), pending = 0.0, fps = 60.0;
    mm_input in;
    memset(&in, 0, sizeof in);
    long end = o->frames                            ? o->frames
               : o->script && keys_script.count > 0 ? keys_script.events[keys_script.count - 1].frame + 1
                                                    : 0;
    for (long frame = 0; !glfwWindowShouldClose(win.glfw) && (end == 0 || frame < end); ++frame) {
        glfwPollEvents();
        double now = glfwGetTime(), dt = now - last;
        last = now;
        if (dt > 0.0) fps += (1.0 / dt - fps) * 0.05;
        /* scripted runs step a fixed tick per frame so that they are reproducible */
        double frame_dt = scripted ? TICK : fmin(dt, 0.25);
        const char *shot = NULL;
        bool quit = false;
        for (const view_script_event *e; (e = view_script_next(&keys_script, frame)) != NULL;) {
            if (e->action == VIEW_SCRIPT_HOLD) win.held[e->key] = true, ++win.pressed[e->key];
            if (e->action == VIEW_SCRIPT_RELEASE) win.held[e->key] = false;
            if (e->action == VIEW_SCRIPT_PRESS) win.pressed[e->key] += (int)e->count;
            if (e->action == VIEW_SCRIPT_SHOT) shot = e->name;
            if (e->action == VIEW_SCRIPT_SCRUB) ui.seek = e->count;
            if (e->action == VIEW_SCRIPT_SELECT) d.selected = (int)e->count, ui.select_changed = true;
            if (e->action == VIEW_SCRIPT_QUIT) quit = true;
        }
        if (!win.script && view_panel_wants_keyboard(panel)) memset(win.pressed, 0, sizeof win.pressed);
        if (take(&win, GLFW_KEY_ESCAPE)) break;
        if (take(&win, GLFW_KEY_H)) show_panel = !show_panel;
        ui.selected = &d.selected;
        debugger_keys(&win, &d, &ui);
        mm_view_keys keys;
        read_keys(&win, &keys);
        mm_input live;
        mm_view_input(&keys, win.camera.yaw, &live);
        live.jump = jump_down(&win);
        scripted_input(o, &script, d.sim.now, &live);
        if ((status = debugger_requests(&d, o, &ui, &live, &err)) != 0) break;
        if (!d.paused) {
            pending += frame_dt;
            mm_character_desc tuned;
            mm_view_tuning_desc(&d.tuning, &tuned);
            for (; pending >= TICK; pending -= TICK) {
                scripted_input(o, &script, d.sim.now, &live);
                view_sim_step(&d.sim, &live, &tuned);
            }
        } else {
            pending = 0.0;
        }
        in = d.sim.now > 0 ? view_sim_input(&d.sim) : live;
        const mm_character *c = &d.sim.character;
        /* the candidates of the search that chose the frame playing (the preview plays on) */
        d.candidate_count = mm_character_candidates(c, d.candidates, CANDIDATES);
        if (ui.select_changed) select_candidate(&d, d.selected);
        if (d.selected >= d.candidate_count) select_candidate(&d, -1);
        view_preview_advance(&d.preview, &db, frame_dt);
        if (!win.script && !view_panel_wants_mouse(panel)) camera_controls(&win, (float)dt);
        if (win.script || glfwGetTime() - win.orbited > CHASE_AFTER_ORBIT) {
            chase_camera(&win, c, &in, frame == 0 || d.jumped ? 0.0f : (float)frame_dt);
        } else {
            mm_vec3 root = c->root.translation;
            mm_camera_follow(&win.camera, mm_vec3_make(root.x, 0.9f, root.z),
                             frame == 0 || d.jumped ? 0.0f : 0.5f, (float)frame_dt);
        }
        d.jumped = false;
        mm_view_update(&view, c, &in, &d.flags, (float)fps);
        add_ghosts(&d, &view, &win.camera);
        int w, h;
        glfwGetFramebufferSize(win.glfw, &w, &h);
        mm_renderer_draw(win.renderer, &win.camera, w, h, &view.scene);
        ui.character = c;
        ui.input = &in;
        ui.fps = (float)fps;
        ui.message = d.message;
        if (rp.loaded) replay_note(&rp, c, d.sim.now);
        ui.note = rp.loaded ? rp.note : NULL;
        ui.candidates = d.candidates;
        ui.candidate_count = d.candidate_count;
        ui.preview_frame = d.selected >= 0 ? d.preview.frame : -1;
        int64_t kept_first, kept_last;
        view_sim_range(&d.sim, &kept_first, &kept_last);
        ui.tick = (long)d.sim.now;
        ui.first = (long)kept_first;
        ui.last = (long)kept_last;
        ui.tick_seconds = (float)TICK;
        ui.paused = d.paused;
        ui.can_save = o->config != NULL;
        ui.tuning = &d.tuning;
        ui.flags = &d.flags;
        ui.draws = &d.draws;
        ui.selected = &d.selected;
        if (show_panel) view_panel_draw(panel, &ui); /* its requests act on the next frame */
        bool last_frame = o->frames && frame + 1 == o->frames;
        if (last_frame && o->screenshot && w > 0 && h > 0 &&
            (status = save_screenshot(&win, o->screenshot, w, h)))
            break;
        if (shot && o->screenshot_dir && w > 0 && h > 0) {
            char path[4096];
            snprintf(path, sizeof path, "%s/%s.png", o->screenshot_dir, shot);
            if ((status = save_screenshot(&win, path, w, h)) != 0) break;
            snprintf(path, sizeof path, "%s/%s.json", o->screenshot_dir, shot);
            if ((status = write_shot_facts(path, &d, &win.camera, w, h, &ui)) != 0) break;
        }
        glfwSwapBuffers(win.glfw);
        if (quit) break;
    }
done_panel:
    view_panel_destroy(panel);
done_window:
    close_window(&win);
done_character:
    mm_view_free(&view);
    mm_body_mesh_free(&user_body);
    view_sim_free(&d.sim);
done_data:
    if (rp.loaded) mm_trace_free(&rp.trace);
    free(d.lines);
    free(d.pose);
    mm_searcher_free(&searcher);
    mm_input_script_free(&script);
    view_script_free(&keys_script);
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
    const char *usage =
        "usage: mm view DB.mmdb [--config CONFIG.json] [--input SCRIPT.json] [--mesh FILE] | mm view --clip "
        "FILE.bvh "
        "[--config CONFIG.json] [--clip-name NAME]  [--scene SCENE.json] [--size 1280x720] "
        "[--frames N --screenshot OUT.png] [--script KEYS.txt [--screenshot-dir DIR]] [--replay TRACE.jsonl]";
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
        else if (strcmp(a, "--script") == 0 && v)
            o.script = argv[++i];
        else if (strcmp(a, "--replay") == 0 && v)
            o.replay = argv[++i];
        else if (strcmp(a, "--screenshot-dir") == 0 && v)
            o.screenshot_dir = argv[++i];
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
    if (o.screenshot_dir && !o.script)
        return cli_usage_error("view", "--screenshot-dir needs --script KEYS.txt");
    if (o.clip && (o.script || o.replay))
        return cli_usage_error("view", "--script and --replay go with a database, not --clip");
    if (o.replay && o.input)
        return cli_usage_error("view", "--replay runs the trace's input: no --input with it");
    static mm_scene scene; /* large: kept off the stack */
    if (o.scene_path) {
        mm_error err;
        memset(&err, 0, sizeof err);
        if (mm_scene_load_json(o.scene_path, &scene, &err) != MM_OK) return cli_report(&err);
        o.scene = &scene;
    }
    return o.clip ? view_clip(&o) : view_database(&o);
}
