/* mm render FILE.bvh -o OUT [--size WxH] [--fps F] [--from S] [--seconds T] [--scale S|auto]
 *           [--scene SCENE.json]
 * Draws a BVH clip headless (OSMesa) into an MP4 or GIF (through ffmpeg) or a folder of PNG
 * frames, with a scene's boxes when given; the camera follows the root. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <mm/mm.h>
#include <mm/render.h>
#include <mm/scene_json.h>
#include <mm/view.h>

#include "cli.h"
#include "commands.h"

int mm_cmd_render(int argc, char **argv)
{
    const char *in = NULL, *out = NULL, *scene_path = NULL;
    int size[2] = {640, 360};
    double fps = 30.0, from = 0.0, seconds = -1.0, scale = 0.0; /* scale 0: auto */
    const char *usage =
        "usage: mm render FILE.bvh -o OUT.mp4|OUT.gif|FOLDER [--size 640x360] [--fps 30] [--from S] "
        "[--seconds T] [--scale S|auto] [--scene SCENE.json]";
    const cli_option options[] = {
        {.name = "-o", .kind = CLI_STRING, .target = &out},
        {.name = "--scene", .kind = CLI_STRING, .target = &scene_path},
        {.name = "--size", .kind = CLI_SIZE, .target = size, .need = "WIDTHxHEIGHT, each 16 to 4096"},
        {.name = "--fps", .kind = CLI_DOUBLE, .target = &fps, .min = 1, .max = 240, .need = "1 to 240"},
        {.name = "--from",
         .kind = CLI_DOUBLE,
         .target = &from,
         .min = 0,
         .max = HUGE_VAL,
         .need = "seconds >= 0"},
        {.name = "--seconds",
         .kind = CLI_DOUBLE,
         .target = &seconds,
         .min = 0,
         .max = 36000,
         .open_min = 1,
         .need = "a number in (0, 36000]"},
        {.name = "--scale", .kind = CLI_CUSTOM, .target = &scale, .parse = cli_parse_scale},
    };
    int status = cli_parse_options("render", argc, argv, options, CLI_COUNT(options), usage, &in, 1);
    if (status) return status;
    int width = size[0], height = size[1];
    if (!in || !out) return cli_usage_error("render", "%s", usage);
    mm_error err;
    memset(&err, 0, sizeof err);
    static mm_scene obstacles; /* large: kept off the stack */
    static mm_render_box boxes[MM_SCENE_MAX_BOXES];
    int box_count = 0;
    if (scene_path) {
        if (mm_scene_load_json(scene_path, &obstacles, &err) != MM_OK) return cli_report(&err);
        box_count = mm_view_scene_boxes(&obstacles, boxes, MM_SCENE_MAX_BOXES);
    }
    mm_bvh bvh;
    if (mm_bvh_load(in, NULL, &bvh, &err) != MM_OK) return cli_report(&err);
    mm_bvh_import_desc imp;
    memset(&imp, 0, sizeof imp);
    imp.auto_scale = scale == 0.0;
    imp.scale = (float)scale;
    mm_clip clip;
    mm_result r = mm_bvh_to_clip(&bvh, &imp, &clip, &err);
    mm_bvh_free(&bvh);
    if (r != MM_OK) {
        snprintf(err.file, sizeof err.file, "%s", in);
        return cli_report(&err);
    }
    double duration = mm_clip_duration(&clip);
    if (from > duration) from = duration;
    double until = seconds > 0 ? fmin(duration, from + seconds) : duration;
    int frames = (int)floor((until - from) * fps + 1e-6) + 1, n = clip.skeleton.joint_count;
    int *parents = malloc(sizeof(int) * (size_t)n);
    mm_xform *global = malloc(sizeof(mm_xform) * (size_t)n);
    mm_quat *rot = malloc(sizeof(mm_quat) * (size_t)n);
    mm_vec3 *pos = malloc(sizeof(mm_vec3) * (size_t)n);
    mm_offscreen *o = NULL;
    mm_video *video = NULL;
    if (!parents || !global || !rot || !pos) {
        fprintf(stderr, "mm: out of memory\n");
        status = 1;
    } else if (mm_offscreen_create(width, height, &o, &err) != MM_OK ||
               mm_video_open(out, width, height, (float)fps, &video, &err) != MM_OK) {
        status = cli_report(&err);
    }
    if (status == 0) {
        for (int j = 0; j < n; ++j) parents[j] = clip.skeleton.joints[j].parent;
        mm_camera cam;
        mm_camera_defaults(&cam);
        mm_render_scene scene;
        memset(&scene, 0, sizeof scene);
        scene.joint_count = n;
        scene.parents = parents;
        scene.global = global;
        scene.head_joint = mm_render_find_head(clip.skeleton.joints, n);
        scene.boxes = boxes;
        scene.box_count = box_count;
        scene.ground_height = scene_path ? obstacles.ground : 0.0f;
        char overlay[256];
        scene.overlay = overlay;
        for (int f = 0; f < frames && status == 0; ++f) {
            double t = from + f / fps;
            mm_clip_sample(&clip, (float)t, rot, pos);
            mm_fk(&clip.skeleton, rot, pos, global);
            mm_vec3 root = global[0].translation;
            mm_camera_follow(&cam, mm_vec3_make(root.x, 0.9f, root.z), f == 0 ? 0.0f : 0.4f,
                             (float)(1.0 / fps));
            snprintf(overlay, sizeof overlay, "%s\nframe %d  t %.2f s", in, (int)floor(t * clip.fps + 1e-6),
                     t);
            const uint8_t *rgb = mm_offscreen_render(o, &cam, &scene);
            if (!rgb || mm_video_write(video, rgb, &err) != MM_OK) {
                if (!rgb) mm_error_set(&err, MM_ERR_UNSUPPORTED, 0, 0, "the offscreen context was lost");
                status = cli_report(&err);
            }
        }
    }
    int written = 0;
    if (video && mm_video_close(video, status != 0, &written, &err) != MM_OK && status == 0)
        status = cli_report(&err);
    if (status == 0) printf("%s: %d frames, %d x %d at %g fps\n", out, written, width, height, fps);
    mm_offscreen_destroy(o);
    free(parents);
    free(global);
    free(rot);
    free(pos);
    mm_clip_free(&clip);
    return status;
}
