/* mm render FILE.bvh -o OUT [--size WxH] [--fps F] [--from S] [--seconds T] [--scale S|auto]
 *           [--scene SCENE.json] [--mesh FILE] [--capsules]
 * mm render FILE.bvh --contact-sheet OUT.png [--grid 6x4] [--size 1920x1080] [--from S]
 *           [--seconds T] [--scale S|auto] [--scene SCENE.json]
 * Draws a BVH clip headless (OSMesa) into an MP4 or GIF (through ffmpeg) or a folder of PNG
 * frames, with a scene's boxes when given: the body mm makes from the skeleton (its roles found
 * from the clip), a user's mesh, or capsules; the camera chases the body from behind, framing it
 * and the path of its next second. With --contact-sheet, one
 * PNG of COLUMNS x ROWS frames evenly spaced from the first to the last (mm_sheet_render). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <mm/mm.h>
#include <mm/render.h>
#include <mm/scene_json.h>
#include <mm/skeleton_roles.h>
#include <mm/terrain_mesh.h>
#include <mm/view.h>

#include "cli.h"
#include "commands.h"

/* --grid: COLUMNSxROWS, each 1 to 32. */
static int parse_grid(const char *command, const cli_option *option, const char *value)
{
    int *grid = (int *)option->target;
    long columns = 0, rows = 0;
    const char *x = strchr(value, 'x');
    char first[16];
    if (x && (size_t)(x - value) < sizeof first) {
        memcpy(first, value, (size_t)(x - value));
        first[x - value] = '\0';
        if (cli_parse_int(first, 1, 32, &columns) && cli_parse_int(x + 1, 1, 32, &rows)) {
            grid[0] = (int)columns;
            grid[1] = (int)rows;
            return 0;
        }
    }
    return cli_usage_error(command, "--grid needs COLUMNSxROWS, each 1 to 32 (e.g. 6x4), not '%s'", value);
}

/* The roles of the clip's skeleton (mm_skeleton_roles_find); false when its hips, feet or head are
 * not found (err says which). */
static bool clip_body_roles(const mm_clip *clip, mm_body_roles *out, mm_error *err)
{
    mm_skeleton_roles found;
    if (mm_skeleton_roles_find(clip, 1, &found, err) != MM_OK) return false;
    out->hips = found.roles[MM_BODY_HIPS].joint;
    out->head = found.roles[MM_BODY_HEAD].joint;
    for (int s = 0; s < 2; ++s) {
        out->foot[s] = found.roles[s ? MM_BODY_RIGHT_FOOT : MM_BODY_LEFT_FOOT].joint;
        out->toe[s] = found.roles[s ? MM_BODY_RIGHT_TOE : MM_BODY_LEFT_TOE].joint;
        out->hand[s] = found.roles[s ? MM_BODY_RIGHT_HAND : MM_BODY_LEFT_HAND].joint;
    }
    return true;
}

/* The body mm makes for the clip, bound to the straightest of up to 256 of its frames. */
static mm_result clip_body(const mm_clip *clip, const mm_body_roles *roles, const int *parents,
                           mm_body_mesh *out, mm_error *err)
{
    enum { CANDIDATES = 256 };
    int n = clip->skeleton.joint_count, count = clip->frame_count < 1 ? 1 : clip->frame_count;
    if (count > CANDIDATES) count = CANDIDATES;
    mm_xform *poses = malloc(sizeof(mm_xform) * (size_t)n * (size_t)count);
    mm_quat *rot = malloc(sizeof(mm_quat) * (size_t)n);
    mm_vec3 *pos = malloc(sizeof(mm_vec3) * (size_t)n);
    mm_result r = MM_OK;
    if (!poses || !rot || !pos) {
        r = mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    } else {
        double duration = mm_clip_duration(clip);
        for (int i = 0; i < count; ++i) {
            mm_clip_sample(clip, (float)(count > 1 ? duration * i / (count - 1) : 0.0), rot, pos);
            mm_fk(&clip->skeleton, rot, pos, poses + (size_t)i * (size_t)n);
        }
        mm_body_desc d;
        memset(&d, 0, sizeof d);
        d.joint_count = n;
        d.parents = parents;
        d.poses = poses;
        d.pose_count = count;
        d.roles = *roles;
        r = mm_body_mesh_build(&d, out, err);
    }
    free(poses);
    free(rot);
    free(pos);
    return r;
}

/* The contact sheet of [from, until]: columns x rows poses evenly spaced over it (each on the
 * nearest frame), rendered into one PNG. */
static int contact_sheet(const char *in, const char *out, const mm_clip *clip, double from, double until,
                         const int grid[2], const int size[2], const mm_render_box *boxes, int box_count,
                         float ground)
{
    mm_error err;
    memset(&err, 0, sizeof err);
    int n = clip->skeleton.joint_count, tiles = grid[0] * grid[1], status = 0;
    mm_sheet_desc d;
    memset(&d, 0, sizeof d);
    d.columns = grid[0];
    d.rows = grid[1];
    d.width = size[0];
    d.height = size[1];
    int tw, th;
    if (mm_sheet_tile_size(&d, &tw, &th, &err) != MM_OK) return cli_usage_error("render", "%s", err.message);
    mm_xform *poses = malloc(sizeof(mm_xform) * (size_t)n * (size_t)tiles);
    double *times = malloc(sizeof(double) * (size_t)tiles);
    mm_quat *rot = malloc(sizeof(mm_quat) * (size_t)n);
    mm_vec3 *pos = malloc(sizeof(mm_vec3) * (size_t)n);
    uint8_t *rgb = malloc((size_t)size[0] * (size_t)size[1] * 3);
    if (!poses || !times || !rot || !pos || !rgb) {
        fprintf(stderr, "mm: out of memory\n");
        status = 1;
    } else {
        for (int i = 0; i < tiles; ++i) {
            double t = tiles > 1 ? from + (until - from) * i / (tiles - 1) : 0.5 * (from + until);
            t = fmin(fmax(round(t * clip->fps) / clip->fps, from), until);
            times[i] = t;
            mm_clip_sample(clip, (float)t, rot, pos);
            mm_fk(&clip->skeleton, rot, pos, poses + (size_t)i * (size_t)n);
        }
        d.joint_count = n;
        d.joints = clip->skeleton.joints;
        /* a database's simulation root, a point on the ground under the hips, is not the body */
        d.first_joint = n > 1 && strcmp(clip->skeleton.joints[0].name, "SimulationRoot") == 0 ? 1 : 0;
        d.poses = poses;
        d.times = times;
        d.ground_height = ground;
        d.boxes = boxes;
        d.box_count = box_count;
        if (mm_sheet_render(&d, rgb, &err) != MM_OK ||
            mm_png_write(out, rgb, size[0], size[1], &err) != MM_OK) {
            if (!err.file[0]) snprintf(err.file, sizeof err.file, "%s", out);
            status = cli_report(&err);
        } else {
            printf("%s: contact sheet of %s, %d frames (%d x %d) from %.2f to %.2f s, %d x %d\n", out, in,
                   tiles, grid[0], grid[1], from, until, size[0], size[1]);
        }
    }
    free(poses);
    free(times);
    free(rot);
    free(pos);
    free(rgb);
    return status;
}

int mm_cmd_render(int argc, char **argv)
{
    const char *in = NULL, *out = NULL, *scene_path = NULL, *sheet = NULL, *mesh_path = NULL;
    int capsules = 0;
    int size[2] = {0, 0}, grid[2] = {0, 0};
    double fps = 30.0, from = 0.0, seconds = -1.0, scale = 0.0; /* scale 0: auto */
    const char *usage =
        "usage: mm render FILE.bvh -o OUT.mp4|OUT.gif|FOLDER [--size 1280x720] [--fps 30] [--from S] "
        "[--seconds T] [--scale S|auto] [--scene SCENE.json] [--mesh FILE | --capsules]\n"
        "       mm render FILE.bvh --contact-sheet OUT.png [--grid 6x4] [--size 1920x1080] [--from S] "
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
        {.name = "--contact-sheet", .kind = CLI_STRING, .target = &sheet},
        {.name = "--grid", .kind = CLI_CUSTOM, .target = grid, .parse = parse_grid},
        {.name = "--mesh", .kind = CLI_STRING, .target = &mesh_path},
        {.name = "--capsules", .kind = CLI_FLAG, .target = &capsules},
    };
    int status = cli_parse_options("render", argc, argv, options, CLI_COUNT(options), usage, &in, 1);
    if (status) return status;
    if (size[0] == 0) {
        size[0] = sheet ? 1920 : 1280;
        size[1] = sheet ? 1080 : 720;
    }
    int width = size[0], height = size[1];
    if (!in || (!out == !sheet)) return cli_usage_error("render", "%s", usage);
    if (grid[0] && !sheet) return cli_usage_error("render", "--grid goes with --contact-sheet");
    if ((mesh_path || capsules) && sheet)
        return cli_usage_error("render", "--mesh and --capsules go with -o, not --contact-sheet");
    if (mesh_path && capsules) return cli_usage_error("render", "--mesh or --capsules, not both");
    if (!grid[0]) grid[0] = 6, grid[1] = 4;
    if (sheet) {
        mm_sheet_desc probe = {.columns = grid[0], .rows = grid[1], .width = width, .height = height};
        int tw, th;
        mm_error e;
        if (mm_sheet_tile_size(&probe, &tw, &th, &e) != MM_OK)
            return cli_usage_error("render", "%s", e.message);
    }
    mm_error err;
    memset(&err, 0, sizeof err);
    static mm_scene obstacles; /* large: kept off the stack */
    static mm_render_box boxes[MM_SCENE_MAX_BOXES];
    int box_count = 0;
    if (scene_path) {
        if (mm_scene_load_json(scene_path, &obstacles, &err) != MM_OK) return cli_report(&err);
        box_count = mm_view_scene_boxes(&obstacles, boxes, MM_SCENE_MAX_BOXES);
    }
    mm_clip clip;
    if (cli_load_clip(in, scale, &clip)) return 1;
    double duration = mm_clip_duration(&clip);
    if (from > duration) {
        fprintf(stderr, "mm: %s: --from %g s is past the end of the clip (%g s)\n", in, from, duration);
        mm_clip_free(&clip);
        return 1;
    }
    double until = seconds > 0 ? fmin(duration, from + seconds) : duration;
    if (sheet) {
        status = contact_sheet(in, sheet, &clip, from, until, grid, size, boxes, box_count,
                               scene_path ? obstacles.ground : 0.0f);
        mm_clip_free(&clip);
        return status;
    }
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
    char video_tmp[CLI_TEMP_NAME_MAX] = ""; /* removed if a signal ends the render */
    if (video && mm_video_temp_path(video)) {
        snprintf(video_tmp, sizeof video_tmp, "%s", mm_video_temp_path(video));
        cli_remember_child(mm_video_encoder_process(video));
        cli_remember_temp(video_tmp);
    }
    mm_body_mesh body;
    memset(&body, 0, sizeof body);
    mm_body_roles roles;
    bool have_roles = false;
    if (status == 0) {
        for (int j = 0; j < n; ++j) parents[j] = clip.skeleton.joints[j].parent;
        mm_error role_err;
        have_roles = clip_body_roles(&clip, &roles, &role_err);
        if (mesh_path) {
            if (mm_body_mesh_load(mesh_path, clip.skeleton.joints, n, &body, &err) != MM_OK)
                status = cli_report(&err);
        } else if (!capsules && !have_roles) {
            /* a skeleton whose roles are not found, or a body they cannot make: capsules, said once */
            fprintf(stderr, "mm: %s: drawn as capsules: %s\n", in, role_err.message);
        } else if (!capsules && clip_body(&clip, &roles, parents, &body, &err) != MM_OK) {
            fprintf(stderr, "mm: %s: drawn as capsules: %s\n", in, err.message);
            memset(&err, 0, sizeof err);
        }
    }
    if (status == 0) {
        mm_camera cam;
        mm_camera_defaults(&cam);
        mm_camera_framing framing;
        mm_camera_framing_defaults(&framing);
        mm_render_scene scene;
        memset(&scene, 0, sizeof scene);
        scene.joint_count = n;
        scene.parents = parents;
        scene.global = global;
        scene.head_joint =
            have_roles && roles.head > 0 ? roles.head : mm_render_find_head(clip.skeleton.joints, n);
        scene.boxes = boxes;
        scene.box_count = box_count;
        scene.ground_height = scene_path ? obstacles.ground : 0.0f;
        scene.body_mesh = body.vertex_count > 0 ? &body : NULL;
        static float terrain[MM_TERRAIN_MESH_FLOATS * 4 *
                             MM_SCENE_MAX_FIELD_SAMPLES]; /* the field's cells, and more */
        scene.terrain = terrain;
        scene.terrain_triangle_count =
            scene_path ? mm_terrain_mesh(&obstacles, terrain, 4 * MM_SCENE_MAX_FIELD_SAMPLES) : 0;
        if (scene.terrain_triangle_count > 4 * MM_SCENE_MAX_FIELD_SAMPLES)
            scene.terrain_triangle_count = 4 * MM_SCENE_MAX_FIELD_SAMPLES;
        char overlay[256];
        scene.overlay = overlay;
        /* what the camera frames: the joints, and where the hips go over the next second */
        enum { PATH_SAMPLES = 8 };
        mm_vec3 *framed = malloc(sizeof(mm_vec3) * (size_t)(n + PATH_SAMPLES));
        if (!framed) {
            fprintf(stderr, "mm: out of memory\n");
            status = 1;
        }
        int hips = have_roles && roles.hips >= 0 ? roles.hips : 0;
        float facing = 0.0f;
        for (int f = 0; f < frames && status == 0; ++f) {
            double t = from + f / fps;
            for (int k = PATH_SAMPLES; k >= 0; --k) {
                /* the future first (into global), the present last */
                mm_clip_sample(&clip, (float)fmin(t + (double)k / PATH_SAMPLES, duration), rot, pos);
                mm_fk(&clip.skeleton, rot, pos, global);
                if (k > 0)
                    framed[n + k - 1] = mm_vec3_make(global[hips].translation.x, scene.ground_height,
                                                     global[hips].translation.z);
            }
            for (int j = 0; j < n; ++j) framed[j] = global[j].translation;
            facing = have_roles ? mm_body_facing(&roles, parents, n, global, facing) : facing;
            mm_camera_chase(&cam, &framing, facing, framed, n + PATH_SAMPLES, (float)width / (float)height,
                            f == 0 ? 0.0f : (float)(1.0 / fps));
            snprintf(overlay, sizeof overlay, "%s\nframe %d  t %.2f s", in, (int)floor(t * clip.fps + 1e-6),
                     t);
            const uint8_t *rgb = mm_offscreen_render(o, &cam, &scene);
            if (!rgb || mm_video_write(video, rgb, &err) != MM_OK) {
                if (!rgb) mm_error_set(&err, MM_ERR_UNSUPPORTED, 0, 0, "the offscreen context was lost");
                status = cli_report(&err);
            }
        }
        free(framed);
    }
    mm_body_mesh_free(&body);
    int written = 0;
    if (video && mm_video_close(video, status != 0, &written, &err) != MM_OK && status == 0)
        status = cli_report(&err);
    cli_remember_child(0);
    if (video_tmp[0]) cli_forget_temp(video_tmp);
    if (status == 0) printf("%s: %d frames, %d x %d at %g fps\n", out, written, width, height, fps);
    mm_offscreen_destroy(o);
    free(parents);
    free(global);
    free(rot);
    free(pos);
    mm_clip_free(&clip);
    return status;
}
