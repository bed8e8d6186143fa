/* The cost of the body (mm/body_mesh.h) per frame: making it, skinning it on the CPU, and drawing a
 * frame with it against the capsule figure, on the built-in set's walk (or a BVH given).
 *
 *   bench_body [frames] [WIDTHxHEIGHT] [FILE.bvh]
 *
 * Prints the body's size, the time to make it, the median skinning time per frame and the median
 * time to draw and read back a frame (OSMesa, one core) with the body and with capsules, and their
 * ratio; then one line of JSON. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <mm/body_mesh.h>
#include <mm/bvh.h>
#include <mm/render.h>
#include <mm/skeleton_roles.h>
#include <mm/synth.h>

#include "bench_common.h"

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, compare);
    return v[n / 2];
}

static int load_clip(const char *path, mm_clip *clip)
{
    mm_error err;
    if (path) {
        mm_bvh bvh;
        mm_bvh_import_desc imp;
        memset(&imp, 0, sizeof imp);
        imp.auto_scale = true;
        if (mm_bvh_load(path, NULL, &bvh, &err) != MM_OK || mm_bvh_to_clip(&bvh, &imp, clip, &err) != MM_OK) {
            fprintf(stderr, "bench_body: %s: %s\n", path, err.message);
            return 1;
        }
        mm_bvh_free(&bvh);
        return 0;
    }
    mm_synth_desc desc;
    memset(&desc, 0, sizeof desc);
    mm_synth_set set;
    if (mm_synth_generate(&desc, &set, &err) != MM_OK) return 1;
    int found = -1;
    for (int i = 0; i < set.clip_count && found < 0; ++i)
        if (strncmp(set.clips[i].name, "walk_", 5) == 0) found = i;
    if (found < 0 || mm_clip_copy(clip, &set.clips[found].clip, NULL) != MM_OK) return 1;
    mm_synth_set_free(&set);
    return 0;
}

int main(int argc, char **argv)
{
    int frames = argc > 1 ? atoi(argv[1]) : 120, width = 1280, height = 720;
    if (argc > 2 && sscanf(argv[2], "%dx%d", &width, &height) != 2) return 2;
    if (frames < 1) frames = 1;
    mm_clip clip;
    if (load_clip(argc > 3 ? argv[3] : NULL, &clip)) return 1;
    mm_error err;
    mm_skeleton_roles found;
    if (mm_skeleton_roles_find(&clip, 1, &found, &err) != MM_OK) {
        fprintf(stderr, "bench_body: %s\n", err.message);
        return 1;
    }
    mm_body_roles roles;
    roles.hips = found.roles[MM_BODY_HIPS].joint;
    roles.head = found.roles[MM_BODY_HEAD].joint;
    for (int k = 0; k < 2; ++k) {
        roles.foot[k] = found.roles[k ? MM_BODY_RIGHT_FOOT : MM_BODY_LEFT_FOOT].joint;
        roles.toe[k] = found.roles[k ? MM_BODY_RIGHT_TOE : MM_BODY_LEFT_TOE].joint;
        roles.hand[k] = found.roles[k ? MM_BODY_RIGHT_HAND : MM_BODY_LEFT_HAND].joint;
    }
    int n = clip.skeleton.joint_count;
    int *parents = malloc(sizeof(int) * (size_t)n);
    mm_xform *poses = malloc(sizeof(mm_xform) * (size_t)n * (size_t)frames);
    mm_quat *rot = malloc(sizeof(mm_quat) * (size_t)n);
    mm_vec3 *pos = malloc(sizeof(mm_vec3) * (size_t)n);
    double *skin = malloc(sizeof(double) * (size_t)frames), *with = malloc(sizeof(double) * (size_t)frames),
           *without = malloc(sizeof(double) * (size_t)frames);
    if (!parents || !poses || !rot || !pos || !skin || !with || !without) return 1;
    for (int j = 0; j < n; ++j) parents[j] = clip.skeleton.joints[j].parent;
    double duration = mm_clip_duration(&clip);
    for (int f = 0; f < frames; ++f) {
        mm_clip_sample(&clip, (float)(duration * f / frames), rot, pos);
        mm_fk(&clip.skeleton, rot, pos, poses + (size_t)f * (size_t)n);
    }
    mm_body_desc d;
    memset(&d, 0, sizeof d);
    d.joint_count = n;
    d.parents = parents;
    d.poses = poses;
    d.pose_count = frames < 256 ? frames : 256;
    d.roles = roles;
    mm_body_mesh body;
    double t0 = now();
    if (mm_body_mesh_build(&d, &body, &err) != MM_OK) {
        fprintf(stderr, "bench_body: %s\n", err.message);
        return 1;
    }
    double build_ms = 1e3 * (now() - t0);
    mm_vec3 *vp = malloc(sizeof(mm_vec3) * (size_t)body.vertex_count),
            *vn = malloc(sizeof(mm_vec3) * (size_t)body.vertex_count);
    if (!vp || !vn) return 1;
    for (int f = 0; f < frames; ++f) {
        double s0 = now();
        mm_body_mesh_skin(&body, poses + (size_t)f * (size_t)n, vp, vn);
        skin[f] = 1e6 * (now() - s0);
    }
    mm_offscreen *o;
    if (mm_offscreen_create(width, height, &o, &err) != MM_OK) {
        fprintf(stderr, "bench_body: %s\n", err.message);
        return 1;
    }
    mm_render_scene scene;
    memset(&scene, 0, sizeof scene);
    scene.joint_count = n;
    scene.parents = parents;
    scene.head_joint = roles.head;
    mm_camera cam;
    mm_camera_defaults(&cam);
    /* alternating, so that both see the same load */
    for (int f = 0; f < frames; ++f)
        for (int pass = 0; pass < 2; ++pass) {
            scene.global = poses + (size_t)f * (size_t)n;
            scene.body_mesh = pass == 0 ? &body : NULL;
            cam.target = scene.global[roles.hips].translation;
            double r0 = now();
            if (!mm_offscreen_render(o, &cam, &scene)) return 1;
            (pass == 0 ? with : without)[f] = 1e3 * (now() - r0);
        }
    double skin_us = median(skin, frames), with_ms = median(with, frames),
           without_ms = median(without, frames);
    printf("body: %d vertices, %d triangles, %d joints; made in %.1f ms\n", body.vertex_count,
           body.triangle_count, n, build_ms);
    printf("skinning (CPU): %.1f us per frame (median of %d)\n", skin_us, frames);
    printf("frame %dx%d: %.2f ms with the body, %.2f ms with capsules, ratio %.2f\n", width, height, with_ms,
           without_ms, with_ms / without_ms);
    printf("{\"vertices\": %d, \"triangles\": %d, \"build_ms\": %.2f, \"skin_us\": %.2f, \"frame_body_ms\": "
           "%.3f, "
           "\"frame_capsules_ms\": %.3f, \"ratio\": %.3f}\n",
           body.vertex_count, body.triangle_count, build_ms, skin_us, with_ms, without_ms,
           with_ms / without_ms);
    mm_offscreen_destroy(o);
    mm_body_mesh_free(&body);
    mm_clip_free(&clip);
    free(parents);
    free(poses);
    free(rot);
    free(pos);
    free(skin);
    free(with);
    free(without);
    free(vp);
    free(vn);
    return 0;
}
