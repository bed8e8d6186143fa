/* Contact sheets: many poses of a body in one image, each tile framed the same way, with the
 * ground, head and feet heights marked and labelled (mm/render.h). */
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <mm/render.h>

#include "render_internal.h"
#include "math_private.h"

#define SIDE_TURN     0.349066f /* rad: the side view turned 20 degrees toward the front */
#define JOINT_RADIUS  0.036f    /* the renderer's joint spheres (1.2 x its default bone radius) */
#define HEAD_RADIUS   0.1f      /* and its head sphere */
#define BELOW_GROUND  0.001f    /* m: a joint this far below the ground is below it */
#define FIT_MARGIN    6         /* pixels kept free around the bodies */
#define FIT_PASSES    8
#define LABEL_COLUMNS 25 /* the longest label line, "head 1234.5  feet -123.4 cm" aside */
/* Every tile is drawn from this yaw, the one toward the renderer's key light (0.35, 1, 0.25), its
 * pose (and boxes) turned about the camera's target to keep what the tile's camera sees: the same
 * image, lit the same whatever the body's heading. */
#define LIT_YAW -2.19105f /* atan2(-0.35, -0.25) */

typedef struct rgb8 {
    uint8_t r, g, b;
} rgb8;

static const rgb8 border_color = {50, 52, 56};
static const rgb8 earth_color = {214, 198, 170};
static const rgb8 ground_color = {70, 48, 28};
static const rgb8 head_color = {40, 90, 210};
static const rgb8 feet_color = {20, 140, 60};
static const rgb8 text_color = {255, 255, 255};
static const rgb8 panel_color = {40, 42, 48};
static const rgb8 alarm_color = {200, 24, 24};
static const mm_rgba below_joint_color = {0.9f, 0.1f, 0.1f, 1.0f};
static const mm_rgba body_color = {0.62f, 0.68f, 0.78f, 1.0f};
static const mm_rgba far_side_color = {0.80f, 0.62f, 0.46f, 1.0f}; /* the body's right side */

static bool name_has(const char *name, const char *word)
{
    size_t n = strlen(word);
    for (const char *p = name; *p; ++p) {
        size_t i = 0;
        while (i < n && p[i] && tolower((unsigned char)p[i]) == word[i]) ++i;
        if (i == n) return true;
    }
    return false;
}

int mm_render_find_feet(const mm_joint *joints, int count, int *out, int max)
{
    int n = 0;
    for (int j = 1; j < count && n < max; ++j)
        if (name_has(joints[j].name, "foot") || name_has(joints[j].name, "toe") ||
            name_has(joints[j].name, "ankle"))
            out[n++] = j;
    return n;
}

float mm_render_facing(const mm_joint *joints, int count, const mm_xform *global, float fallback)
{
    mm_vec3 left = mm_vec3_make(0.0f, 0.0f, 0.0f), right = left;
    int nl = 0, nr = 0;
    for (int j = 0; j < count; ++j) {
        mm_vec3 p = global[j].translation;
        if (!finite3(p)) continue;
        if (name_has(joints[j].name, "left")) {
            left = mm_vec3_add(left, p);
            ++nl;
        } else if (name_has(joints[j].name, "right")) {
            right = mm_vec3_add(right, p);
            ++nr;
        }
    }
    if (nl == 0 || nr == 0) return fallback;
    mm_vec3 l = mm_vec3_sub(mm_vec3_scale(left, 1.0f / (float)nl), mm_vec3_scale(right, 1.0f / (float)nr));
    /* the front is left x up: (-l.z, 0, l.x) */
    if (!(l.x * l.x + l.z * l.z > 1e-8f)) return fallback;
    return atan2f(-l.z, l.x);
}

mm_result mm_sheet_tile_size(const mm_sheet_desc *d, int *tile_width, int *tile_height, mm_error *err)
{
    if (d->columns < 1 || d->columns > 32 || d->rows < 1 || d->rows > 32)
        return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0, "a grid of %d x %d tiles: each must be 1 to 32",
                            d->columns, d->rows);
    if (d->width < 1 || d->width > 4096 || d->height < 1 || d->height > 4096)
        return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0, "image size %d x %d: each side must be 1 to 4096",
                            d->width, d->height);
    int tw = d->width / d->columns, th = d->height / d->rows;
    if (tw < MM_SHEET_MIN_TILE || th < MM_SHEET_MIN_TILE)
        return mm_error_set(
            err, MM_ERR_OUT_OF_RANGE, 0, 0,
            "a grid of %d x %d on %d x %d pixels makes tiles of %d x %d: each side must be at "
            "least %d",
            d->columns, d->rows, d->width, d->height, tw, th, MM_SHEET_MIN_TILE);
    *tile_width = tw;
    *tile_height = th;
    return MM_OK;
}

/* The layout of a tile's label: font scale, padding, the band's height. */
typedef struct label_layout {
    int scale, pad, band;
} label_layout;

static label_layout label_layout_of(int tw, int th)
{
    label_layout l;
    l.scale = 3;
    while (l.scale > 1 && (LABEL_COLUMNS * MM_FONT_CELL_W * l.scale + 4 * l.scale > tw ||
                           2 * MM_FONT_CELL_H * l.scale + 4 * l.scale > th / 4))
        --l.scale;
    l.pad = 2 * l.scale;
    l.band = 2 * MM_FONT_CELL_H * l.scale + 2 * l.pad;
    return l;
}

static const mm_xform *pose_of(const mm_sheet_desc *d, int tile)
{
    return d->poses + (size_t)tile * (size_t)d->joint_count;
}

static int first_of(const mm_sheet_desc *d)
{
    return d->first_joint > 0 && d->first_joint < d->joint_count ? d->first_joint : 0;
}

/* The screen-space bounds of a tile's body (spheres included) under camera c; false when none of
 * its joints is finite and in front of the camera. */
static bool body_bounds(const mm_sheet_desc *d, int tile, int head, const mm_camera *c, int tw, int th,
                        float b[4])
{
    const mm_xform *g = pose_of(d, tile);
    mm_vec3 eye = mm_camera_eye(c), forward = mm_vec3_normalize(mm_vec3_sub(c->target, eye));
    float focal = 0.5f * (float)th / tanf(0.5f * c->fov_y);
    bool any = false;
    b[0] = b[1] = INFINITY;
    b[2] = b[3] = -INFINITY;
    for (int j = first_of(d); j < d->joint_count; ++j) {
        mm_vec3 p = g[j].translation;
        float px, py, depth = mm_vec3_dot(mm_vec3_sub(p, eye), forward);
        if (!finite3(p) || !(depth > c->z_near) || !mm_camera_project(c, tw, th, p, &px, &py)) continue;
        float r = focal * (j == head ? HEAD_RADIUS : JOINT_RADIUS) / depth;
        b[0] = fminf(b[0], px - r), b[1] = fminf(b[1], py - r);
        b[2] = fmaxf(b[2], px + r), b[3] = fmaxf(b[3], py + r);
        any = true;
    }
    return any;
}

mm_result mm_sheet_cameras(const mm_sheet_desc *d, mm_camera *cameras, mm_error *err)
{
    int tw, th;
    mm_result res = mm_sheet_tile_size(d, &tw, &th, err);
    if (res != MM_OK) return res;
    if (!d->joints || !d->poses || d->joint_count < 1)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "a contact sheet needs a body and its poses");
    int tiles = d->columns * d->rows, first = first_of(d),
        head = mm_render_find_head(d->joints, d->joint_count);
    label_layout label = label_layout_of(tw, th);
    float ground = isfinite(d->ground_height) ? d->ground_height : 0.0f;
    /* the vertical span of every pose and the ground: the cameras' common height starts at its middle */
    float low = ground, high = ground + 1.0f, facing = 0.0f;
    for (int i = 0; i < tiles; ++i) {
        const mm_xform *g = pose_of(d, i);
        mm_vec3 centre = mm_vec3_make(0.0f, 0.0f, 0.0f);
        int n = 0;
        for (int j = first; j < d->joint_count; ++j) {
            mm_vec3 p = g[j].translation;
            if (!finite3(p)) continue;
            low = fminf(low, p.y), high = fmaxf(high, p.y);
            centre = mm_vec3_add(centre, p);
            ++n;
        }
        facing = mm_render_facing(d->joints, d->joint_count, g, facing);
        mm_camera *c = &cameras[i];
        mm_camera_defaults(c);
        /* the eye on the body's left, where the renderer's light comes from */
        c->yaw = remainderf(facing - 0.5f * (float)MM_PI - SIDE_TURN, 2.0f * (float)MM_PI);
        c->pitch = 0.0f;
        c->target = n ? mm_vec3_scale(centre, 1.0f / (float)n) : mm_vec3_make(0.0f, 0.0f, 0.0f);
    }
    float height = 0.5f * (low + high), distance = 2.0f * (high - low) + 1.0f;
    /* Fit by passes: the distance scaled by how much the widest and the tallest body overflow or
     * underfill what the tiles leave them, then each tile's target moved sideways to centre its body
     * and the common height moved to set the lowest point of all on the band's top. Perspective
     * makes this inexact by a little, so it is repeated; the last pass only moves. */
    const float top = FIT_MARGIN, bottom = (float)(th - label.band - FIT_MARGIN);
    const float half_width = 0.5f * (float)tw - FIT_MARGIN;
    for (int pass = 0; pass < FIT_PASSES; ++pass) {
        for (int zoom = pass == FIT_PASSES - 1 ? 1 : 0; zoom < 2; ++zoom) {
            float widest = 0.0f, lowest = -INFINITY, highest = INFINITY;
            for (int i = 0; i < tiles; ++i) {
                mm_camera *c = &cameras[i];
                c->target.y = height;
                c->distance = distance;
                float b[4], gx, gy;
                if (!body_bounds(d, i, head, c, tw, th, b)) continue;
                /* the ground under the target is in the frame too */
                if (mm_camera_project(c, tw, th, mm_vec3_make(c->target.x, ground, c->target.z), &gx, &gy))
                    b[3] = fmaxf(b[3], gy);
                if (zoom == 0) {
                    widest = fmaxf(widest, b[2] - b[0]);
                } else {
                    /* moving the target by dx along the camera's right moves the image by -dx * f / z */
                    float focal = 0.5f * (float)th / tanf(0.5f * c->fov_y);
                    float shift = (0.5f * (b[0] + b[2]) - 0.5f * (float)tw) * distance / focal;
                    mm_vec3 right = mm_vec3_make(-cosf(c->yaw), 0.0f, sinf(c->yaw));
                    c->target = mm_vec3_add(c->target, mm_vec3_scale(right, shift));
                }
                lowest = fmaxf(lowest, b[3]);
                highest = fminf(highest, b[1]);
            }
            if (!isfinite(lowest) || !isfinite(highest)) break;
            float focal = 0.5f * (float)th / tanf(0.5f * cameras[0].fov_y);
            if (zoom == 0) {
                float grow = fminf((bottom - top) / fmaxf(lowest - highest, 1.0f),
                                   2.0f * half_width / fmaxf(widest, 1.0f));
                distance = fminf(fmaxf(distance / grow, 0.5f), 150.0f);
            } else {
                /* raising the eye by dy moves the image down by dy * f / z */
                height += (bottom - lowest) * distance / focal;
            }
        }
    }
    for (int i = 0; i < tiles; ++i) {
        cameras[i].target.y = height;
        cameras[i].distance = distance;
    }
    return MM_OK;
}

/* ---- drawing on the sheet ---- */

typedef struct canvas {
    uint8_t *rgb;
    int width, height;     /* the whole image */
    int x0, y0, x1, y1;    /* the tile: drawing is clipped to [x0, x1) x [y0, y1) */
    const uint8_t *render; /* the tile's rendered pixels (tile-local), to tell the background */
    rgb8 background;
} canvas;

static uint8_t *pixel(canvas *c, int x, int y)
{
    return c->rgb + ((size_t)y * (size_t)c->width + (size_t)x) * 3;
}

static bool is_background(const canvas *c, int x, int y)
{
    const uint8_t *p = c->render + ((size_t)(y - c->y0) * (size_t)(c->x1 - c->x0) + (size_t)(x - c->x0)) * 3;
    return p[0] == c->background.r && p[1] == c->background.g && p[2] == c->background.b;
}

static void put(canvas *c, int x, int y, rgb8 color)
{
    if (x < c->x0 || x >= c->x1 || y < c->y0 || y >= c->y1) return;
    uint8_t *p = pixel(c, x, y);
    p[0] = color.r, p[1] = color.g, p[2] = color.b;
}

static void fill(canvas *c, int x, int y, int w, int h, rgb8 color)
{
    for (int yy = y; yy < y + h; ++yy)
        for (int xx = x; xx < x + w; ++xx) put(c, xx, yy, color);
}

/* A horizontal line of thickness rows from row y down, over the background only when behind. */
static void hline(canvas *c, int y, int thickness, rgb8 color, bool behind)
{
    for (int yy = y; yy < y + thickness; ++yy)
        for (int x = c->x0; x < c->x1; ++x)
            if (yy >= c->y0 && yy < c->y1 && (!behind || is_background(c, x, yy))) put(c, x, yy, color);
}

/* Text in the renderer's font at scale, on a panel of whole character cells. */
static void text(canvas *c, int x0, int y0, int scale, const char *s, rgb8 color, rgb8 panel)
{
    int x = x0, y = y0;
    for (const char *p = s; *p; ++p) {
        if (*p == '\n') {
            x = x0;
            y += MM_FONT_CELL_H * scale;
            continue;
        }
        fill(c, x - scale, y - scale, (MM_FONT_CELL_W + 1) * scale, MM_FONT_CELL_H * scale, panel);
        for (int fy = 0; fy < MM_FONT_CELL_H; ++fy)
            for (int fx = 0; fx < MM_FONT_CELL_W; ++fx)
                if (mm_font_pixel((unsigned char)*p, fx, fy))
                    fill(c, x + fx * scale, y + fy * scale, scale, scale, color);
        x += MM_FONT_CELL_W * scale;
    }
}

/* The row at which height y shows in a tile of camera cam (pitch 0: the same row across it); -1
 * when it is off the tile. */
static int row_of(const mm_camera *cam, int tw, int th, float y)
{
    float px, py;
    if (!mm_camera_project(cam, tw, th, mm_vec3_make(cam->target.x, y, cam->target.z), &px, &py) ||
        !(py > -1.0f && py < (float)th + 1.0f))
        return -1; /* off the tile (or not a number) */
    return (int)floorf(py);
}

mm_result mm_sheet_render(const mm_sheet_desc *d, uint8_t *rgb, mm_error *err)
{
    int tw, th;
    mm_result res = mm_sheet_tile_size(d, &tw, &th, err);
    if (res != MM_OK) return res;
    int tiles = d->columns * d->rows, n = d->joint_count;
    mm_camera *cameras = malloc(sizeof(mm_camera) * (size_t)tiles);
    int *parents = malloc(sizeof(int) * (size_t)(n > 0 ? n : 1));
    int *feet = malloc(sizeof(int) * (size_t)(n > 0 ? n : 1));
    mm_rgba *colors = malloc(sizeof(mm_rgba) * (size_t)(n > 0 ? n : 1));
    mm_xform *turned = malloc(sizeof(mm_xform) * (size_t)(n > 0 ? n : 1));
    mm_render_box *boxes = malloc(sizeof(mm_render_box) * (size_t)(d->box_count > 0 ? d->box_count : 1));
    mm_offscreen *o = NULL;
    if (!cameras || !parents || !feet || !colors || !turned || !boxes) {
        res = mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
        goto done;
    }
    res = mm_sheet_cameras(d, cameras, err);
    if (res == MM_OK) res = mm_offscreen_create(tw, th, &o, err);
    if (res != MM_OK) goto done;
    for (int j = 0; j < n; ++j) parents[j] = d->joints[j].parent;
    int foot_count = mm_render_find_feet(d->joints, n, feet, n), first = first_of(d);
    int head = mm_render_find_head(d->joints, n);
    float ground = isfinite(d->ground_height) ? d->ground_height : 0.0f;
    label_layout label = label_layout_of(tw, th);

    mm_render_scene scene;
    memset(&scene, 0, sizeof scene);
    scene.no_ground = true;
    scene.parents = parents;
    scene.first_joint = first;
    scene.head_joint = head;
    scene.boxes = boxes;
    scene.box_count = d->boxes && d->box_count > 0 ? d->box_count : 0;
    scene.ground_height = ground;
    scene.joint_colors = colors;
    /* the background's exact colour: an empty frame */
    const uint8_t *empty = mm_offscreen_render(o, &cameras[0], &scene);
    if (!empty) {
        res = mm_error_set(err, MM_ERR_UNSUPPORTED, 0, 0, "the offscreen context was lost");
        goto done;
    }
    rgb8 background = {empty[0], empty[1], empty[2]};
    for (size_t i = 0; i < (size_t)d->width * (size_t)d->height; ++i)
        rgb[3 * i] = border_color.r, rgb[3 * i + 1] = border_color.g, rgb[3 * i + 2] = border_color.b;

    for (int t = 0; t < tiles; ++t) {
        const mm_xform *g = pose_of(d, t);
        /* heights above the ground: the head (the highest joint without one), the lowest foot */
        float head_y = -INFINITY, feet_y = INFINITY;
        bool below = false;
        for (int j = first; j < n; ++j) {
            float y = g[j].translation.y;
            bool ok = finite3(g[j].translation);
            colors[j] = ok && y < ground - BELOW_GROUND        ? below_joint_color
                        : name_has(d->joints[j].name, "right") ? far_side_color
                                                               : body_color;
            if (!ok) continue;
            below = below || y < ground - BELOW_GROUND;
            if (head == 0) head_y = fmaxf(head_y, y);
            if (foot_count == 0) feet_y = fminf(feet_y, y);
        }
        if (head > 0 && head < n) head_y = g[head].translation.y;
        for (int k = 0; k < foot_count; ++k)
            if (isfinite(g[feet[k]].translation.y)) feet_y = fminf(feet_y, g[feet[k]].translation.y);

        /* the pose and the boxes turned about the target's vertical, the camera to LIT_YAW */
        mm_camera cam = cameras[t];
        float turn = LIT_YAW - cam.yaw, ct = cosf(turn), st = sinf(turn);
        mm_quat q = mm_quat_from_axis_angle(mm_vec3_make(0.0f, 1.0f, 0.0f), turn);
        for (int j = 0; j < n; ++j) {
            mm_vec3 p = mm_vec3_sub(g[j].translation, cam.target);
            turned[j].rotation = mm_quat_mul(q, g[j].rotation);
            turned[j].translation = mm_vec3_make(cam.target.x + ct * p.x + st * p.z, g[j].translation.y,
                                                 cam.target.z - st * p.x + ct * p.z);
        }
        for (int b = 0; b < scene.box_count; ++b) {
            mm_vec3 p = mm_vec3_sub(d->boxes[b].position, cam.target);
            boxes[b] = d->boxes[b];
            boxes[b].position = mm_vec3_make(cam.target.x + ct * p.x + st * p.z, d->boxes[b].position.y,
                                             cam.target.z - st * p.x + ct * p.z);
            boxes[b].yaw = d->boxes[b].yaw + turn;
        }
        cam.yaw = LIT_YAW;
        scene.joint_count = n;
        scene.global = turned;
        const uint8_t *tile = mm_offscreen_render(o, &cam, &scene);
        if (!tile) {
            res = mm_error_set(err, MM_ERR_UNSUPPORTED, 0, 0, "the offscreen context was lost");
            goto done;
        }
        int x0 = (t % d->columns) * tw, y0 = (t / d->columns) * th;
        for (int y = 0; y < th; ++y)
            memcpy(rgb + ((size_t)(y0 + y) * (size_t)d->width + (size_t)x0) * 3,
                   tile + (size_t)y * (size_t)tw * 3, (size_t)tw * 3);
        canvas c = {rgb, d->width, d->height, x0, y0, x0 + tw, y0 + th, tile, background};
        int line = label.scale > 1 ? 2 : 1;
        /* the earth below the ground line, behind the body; the ground line over everything */
        int ground_row = row_of(&cameras[t], tw, th, ground);
        if (ground_row >= 0)
            for (int y = y0 + ground_row; y < y0 + th; ++y) hline(&c, y, 1, earth_color, true);
        int head_row = isfinite(head_y) ? row_of(&cameras[t], tw, th, head_y) : -1;
        int feet_row = isfinite(feet_y) ? row_of(&cameras[t], tw, th, feet_y) : -1;
        if (head_row >= 0) hline(&c, y0 + head_row, line, head_color, true);
        if (feet_row >= 0) hline(&c, y0 + feet_row, line, feet_color, true);
        if (ground_row >= 0) hline(&c, y0 + ground_row, line + 1, ground_color, false);
        /* the label in the band */
        char s[128];
        int len = 0;
        if (d->times) len = snprintf(s, sizeof s, "t %.2f s\n", d->times[t]);
        if (isfinite(head_y) && isfinite(feet_y))
            snprintf(s + len, sizeof s - (size_t)len, "head %.1f  feet %.1f cm", 100.0f * (head_y - ground),
                     100.0f * (feet_y - ground));
        else
            snprintf(s + len, sizeof s - (size_t)len, "no finite joint");
        int lines = d->times ? 2 : 1;
        text(&c, x0 + label.pad + label.scale,
             y0 + th - label.pad - lines * MM_FONT_CELL_H * label.scale + label.scale, label.scale, s,
             text_color, below ? alarm_color : panel_color);
        /* the border */
        for (int x = x0; x < x0 + tw; ++x)
            put(&c, x, y0, border_color), put(&c, x, y0 + th - 1, border_color);
        for (int y = y0; y < y0 + th; ++y)
            put(&c, x0, y, border_color), put(&c, x0 + tw - 1, y, border_color);
    }
done:
    mm_offscreen_destroy(o);
    free(cameras);
    free(parents);
    free(feet);
    free(colors);
    free(turned);
    free(boxes);
    return res;
}
