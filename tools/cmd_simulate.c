/* mm simulate DB (--input SCRIPT | --random SEED) --seconds T [--fps F] -o OUT.bvh --metrics OUT.json
 *             [--video OUT.mp4|OUT.gif|FOLDER [--size WxH] [--video-fps F]]
 * Runs one character over scripted or random input; writes its motion, the metrics of
 * docs/metrics.md and, on request, a video of it rendered headless. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <mm/character.h>
#include <mm/config_json.h>
#include <mm/input_json.h>
#include <mm/mm.h>
#include <mm/render.h>
#include <mm/view.h>

#include "cli.h"
#include "commands.h"
#include "sim_video.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int compare_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

static float yaw_of(mm_quat q)
{
    mm_vec3 f = mm_quat_rotate(q, mm_vec3_make(0, 0, 1));
    return atan2f(f.x, f.z);
}

/* The four contact joints (left heel, left toe, right heel, right toe) from the embedded config. */
static void contact_joints(const mm_database *db, int joints[4])
{
    mm_config cfg;
    memset(&cfg, 0, sizeof cfg);
    mm_config_defaults(&cfg);
    if (db->config_json && db->config_json[0])
        mm_config_parse_json(db->config_json, strlen(db->config_json), "embedded", NULL, &cfg, NULL);
    const char *names[4] = {cfg.left_foot, cfg.left_toe, cfg.right_foot, cfg.right_toe};
    for (int k = 0; k < 4; ++k) {
        joints[k] = -1;
        for (int j = 0; j < db->joint_count; ++j)
            if (strcmp(db->joints[j].name, names[k]) == 0) joints[k] = j;
    }
    mm_config_free(&cfg);
}

/* The largest second difference of any joint's world position over the database's clips played
 * in order, resampled to fps (cm). */
static double database_max_pop(const mm_database *db, float fps)
{
    mm_skeleton s;
    if (mm_skeleton_init(&s, db->joint_count, NULL) != MM_OK) return NAN;
    memcpy(s.joints, db->joints, sizeof(mm_joint) * (size_t)db->joint_count);
    int n = db->joint_count;
    mm_xform *g[3];
    for (int k = 0; k < 3; ++k) g[k] = malloc(sizeof(mm_xform) * (size_t)n);
    mm_quat *rot = malloc(sizeof(mm_quat) * (size_t)n);
    mm_vec3 *pos = malloc(sizeof(mm_vec3) * (size_t)n);
    double worst = 0.0;
    for (int c = 0; c < db->clip_count; ++c) {
        const mm_db_clip *clip = &db->clips[c];
        double duration = (clip->frame_count - 1) * db->interval;
        int samples = (int)floor(duration * fps) + 1;
        for (int i = 0; i < samples; ++i) {
            double x = i / fps / db->interval;
            int f0 = (int)floor(x), f1 = f0 + 1 < clip->frame_count ? f0 + 1 : f0;
            float a = (float)(x - f0);
            const mm_quat *r0 = mm_database_rotations(db, clip->first_frame + f0),
                          *r1 = mm_database_rotations(db, clip->first_frame + f1);
            const mm_vec3 *p0 = mm_database_positions(db, clip->first_frame + f0),
                          *p1 = mm_database_positions(db, clip->first_frame + f1);
            for (int j = 0; j < n; ++j) {
                rot[j] = mm_quat_slerp(r0[j], r1[j], a);
                pos[j] = mm_vec3_lerp(p0[j], p1[j], a);
            }
            mm_fk(&s, rot, pos, g[i % 3]);
            if (i < 2) continue;
            for (int j = 0; j < n; ++j) {
                mm_vec3 d = mm_vec3_add(
                    mm_vec3_sub(g[i % 3][j].translation, mm_vec3_scale(g[(i + 2) % 3][j].translation, 2.0f)),
                    g[(i + 1) % 3][j].translation);
                double pop = 100.0 * mm_vec3_length(d);
                if (pop > worst) worst = pop;
            }
        }
    }
    for (int k = 0; k < 3; ++k) free(g[k]);
    free(rot);
    free(pos);
    mm_skeleton_free(&s);
    return worst;
}

static void json_number(FILE *f, const char *key, double v, int last)
{
    if (isfinite(v))
        fprintf(f, "  \"%s\": %.6g%s\n", key, v, last ? "" : ",");
    else
        fprintf(f, "  \"%s\": null%s\n", key, last ? "" : ",");
}

int mm_cmd_simulate(int argc, char **argv)
{
    const char *db_path = NULL, *input = NULL, *out = NULL, *metrics = NULL, *video_path = NULL;
    long seed = -1;
    double seconds = 0.0, fps = 60.0, video_fps = 30.0;
    int width = 640, height = 360;
    const char *usage =
        "usage: mm simulate DB.mmdb (--input SCRIPT.json | --random SEED) --seconds T [--fps F] -o OUT.bvh "
        "--metrics OUT.json [--video OUT.mp4|OUT.gif|FOLDER [--size 640x360] [--video-fps 30]]";
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (strcmp(a, "--input") == 0 && v)
            input = argv[++i];
        else if (strcmp(a, "--random") == 0 && v) {
            if (!cli_parse_int(v, 0, 0x7fffffff, &seed))
                return cli_usage_error("simulate", "--random needs a seed >= 0");
            ++i;
        } else if (strcmp(a, "--seconds") == 0 && v) {
            if (!cli_parse_double(v, &seconds) || seconds <= 0 || seconds > 36000)
                return cli_usage_error("simulate", "--seconds needs a number in (0, 36000]");
            ++i;
        } else if (strcmp(a, "--fps") == 0 && v) {
            if (!cli_parse_double(v, &fps) || fps < 1 || fps > 1000)
                return cli_usage_error("simulate", "--fps needs 1 to 1000");
            ++i;
        } else if (strcmp(a, "-o") == 0 && v)
            out = argv[++i];
        else if (strcmp(a, "--metrics") == 0 && v)
            metrics = argv[++i];
        else if (strcmp(a, "--video") == 0 && v)
            video_path = argv[++i];
        else if (strcmp(a, "--size") == 0 && v) {
            if (!cli_parse_size(v, &width, &height))
                return cli_usage_error("simulate", "--size needs WIDTHxHEIGHT, each 16 to 4096");
            ++i;
        } else if (strcmp(a, "--video-fps") == 0 && v) {
            if (!cli_parse_double(v, &video_fps) || video_fps < 1 || video_fps > 240)
                return cli_usage_error("simulate", "--video-fps needs 1 to 240");
            ++i;
        } else if (a[0] == '-' && a[1])
            return cli_usage_error("simulate", "unknown or incomplete option '%s'\n%s", a, usage);
        else if (!db_path)
            db_path = a;
        else
            return cli_usage_error("simulate", "unexpected argument '%s'", a);
    }
    if (!db_path || (!input) == (seed < 0) || seconds <= 0 || !out)
        return cli_usage_error("simulate", "%s", usage);
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_database db;
    if (mm_database_load(db_path, NULL, &db, &err) != MM_OK) return cli_report(&err);
    mm_input_script script;
    mm_result r = input ? mm_input_script_load_json(input, &script, &err) : MM_OK;
    if (!input) {
        mm_input_random_desc rd;
        memset(&rd, 0, sizeof rd);
        rd.seconds = (float)seconds;
        r = mm_input_script_random(&script, (uint64_t)seed, &rd);
        if (r != MM_OK) mm_error_set(&err, r, 0, 0, "cannot make random input");
    }
    if (r != MM_OK) {
        mm_database_free(&db);
        return cli_report(&err);
    }
    mm_searcher searcher;
    mm_character c;
    mm_character_desc desc;
    mm_character_defaults(&desc);
    desc.clock = now;
    if (mm_searcher_init(&searcher, &db, NULL, &err) != MM_OK ||
        mm_character_init(&c, &db, &searcher, &desc, &err) != MM_OK) {
        mm_input_script_free(&script);
        mm_database_free(&db);
        return cli_report(&err);
    }
    int frames = (int)floor(seconds * fps + 1e-6), n = db.joint_count;
    mm_skeleton skel;
    mm_skeleton_init(&skel, n, NULL);
    memcpy(skel.joints, db.joints, sizeof(mm_joint) * (size_t)n);
    mm_clip clip;
    r = mm_clip_init(&clip, &skel, frames, (float)fps, NULL);
    mm_skeleton_free(&skel);
    float *search_us = malloc(sizeof(float) * (size_t)frames * 2 + 8);
    mm_vec3 *world[3];
    for (int k = 0; k < 3; ++k) world[k] = malloc(sizeof(mm_vec3) * (size_t)n);
    if (r != MM_OK || !search_us || !world[0] || !world[1] || !world[2]) {
        fprintf(stderr, "mm: out of memory\n");
        return 1;
    }
    int status = 0;
    sim_video video;
    memset(&video, 0, sizeof video);
    if (video_path &&
        sim_video_open(&video, video_path, width, height, video_fps, 1.0 / fps, &db, &err) != MM_OK) {
        status = cli_report(&err);
        for (int k = 0; k < 3; ++k) free(world[k]);
        free(search_us);
        mm_clip_free(&clip);
        mm_character_free(&c);
        mm_searcher_free(&searcher);
        mm_input_script_free(&script);
        mm_database_free(&db);
        return status;
    }
    int contact[4];
    contact_joints(&db, contact);
    double slide_sum[4] = {0}, slide_frames[4] = {0}, raw_sum = 0.0, traj_err = 0.0, heading_err = 0.0,
           max_pop = 0.0;
    mm_vec3 raw_previous[4] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    double response_sum = 0.0;
    int responses = 0, pending = 0, nan_frames = 0, search_count = 0, last_searches = 0;
    float pending_direction = 0.0f, pending_since = 0.0f, last_stick_direction = 0.0f;
    int had_stick = 0;
    mm_vec3 previous_root = c.root.translation;
    float dt = (float)(1.0 / fps);
    for (int f = 0; f < frames; ++f) {
        float t = (float)(f / fps);
        mm_input in;
        mm_input_script_sample(&script, t, &in);
        /* a stick turn of more than 45 degrees while the desired speed is above 0.5 m/s */
        mm_vec3 desired;
        mm_trajectory_desired(&c.trajectory, &in, &desired, NULL);
        float stick_direction = atan2f(in.stick[0], in.stick[1]);
        int stick_on = in.stick[0] * in.stick[0] + in.stick[1] * in.stick[1] > 0.01f;
        if (stick_on && had_stick && mm_vec3_length(desired) > 0.5f &&
            fabsf(remainderf(stick_direction - last_stick_direction, (float)(2 * MM_PI))) >
                (float)(MM_PI / 4)) {
            pending = 1;
            pending_direction = atan2f(desired.x, desired.z);
            pending_since = t;
        }
        if (stick_on) last_stick_direction = stick_direction;
        had_stick = stick_on;
        mm_character_update(&c, &in, dt);
        if (video_path && status == 0 && sim_video_tick(&video, &c, &in, &err) != MM_OK)
            status = cli_report(&err);
        if (c.searches != last_searches) {
            search_us[search_count++] = c.last_search_us;
            last_searches = c.searches;
        }
        /* the pose as BVH: joint 0 carries the root */
        memcpy(mm_clip_rotations(&clip, f), c.local_rotations, sizeof(mm_quat) * (size_t)n);
        memcpy(mm_clip_positions(&clip, f), c.local_positions, sizeof(mm_vec3) * (size_t)n);
        int bad = 0;
        for (int j = 0; j < n; ++j) {
            mm_vec3 p = c.global[j].translation;
            bad |= !isfinite(p.x) || !isfinite(p.y) || !isfinite(p.z);
            world[f % 3][j] = p;
        }
        nan_frames += bad;
        if (f >= 2)
            for (int j = 0; j < n; ++j) {
                mm_vec3 d =
                    mm_vec3_add(mm_vec3_sub(world[f % 3][j], mm_vec3_scale(world[(f + 2) % 3][j], 2.0f)),
                                world[(f + 1) % 3][j]);
                max_pop = fmax(max_pop, 100.0 * mm_vec3_length(d));
            }
        if (f >= 1) {
            unsigned label = db.contacts[c.frame];
            for (int k = 0; k < 4; ++k) {
                if (contact[k] < 0 || !(label & (1u << k))) continue;
                mm_vec3 d = mm_vec3_sub(world[f % 3][contact[k]], world[(f + 2) % 3][contact[k]]);
                slide_sum[k] += 100.0 * sqrt(d.x * d.x + d.z * d.z) * fps;
                slide_frames[k] += 1;
                mm_vec3 rd = mm_vec3_sub(c.raw_contact_positions[k], raw_previous[k]); /* before foot IK */
                raw_sum += 100.0 * sqrt(rd.x * rd.x + rd.z * rd.z) * fps;
            }
        }
        memcpy(raw_previous, c.raw_contact_positions, sizeof raw_previous);
        mm_vec3 e = mm_vec3_sub(c.trajectory.position, c.root.translation);
        traj_err += 100.0 * sqrt(e.x * e.x + e.z * e.z);
        heading_err +=
            fabs(remainderf(yaw_of(c.trajectory.facing) - yaw_of(c.root.rotation), (float)(2 * MM_PI))) *
            MM_RAD_TO_DEG;
        mm_vec3 v = mm_vec3_sub(c.root.translation, previous_root);
        previous_root = c.root.translation;
        if (pending && v.x * v.x + v.z * v.z > 1e-10) {
            float a = fabsf(remainderf(atan2f(v.x, v.z) - pending_direction, (float)(2 * MM_PI)));
            if (a < (float)(20 * MM_DEG_TO_RAD)) {
                response_sum += t + dt - pending_since;
                ++responses;
                pending = 0;
            }
        }
    }
    int video_frames = 0;
    if (video_path && sim_video_close(&video, status != 0, &video_frames, &err) != MM_OK && status == 0)
        status = cli_report(&err);
    if (video_path && status == 0) printf("%s: %d video frames\n", video_path, video_frames);
    mm_bvh_write_desc wd;
    memset(&wd, 0, sizeof wd);
    snprintf(err.file, sizeof err.file, "%s", out);
    if (status == 0 && mm_bvh_save(out, &clip, &wd, &err) != MM_OK) status = cli_report(&err);
    double slide = 0.0, slide_n = 0.0;
    for (int k = 0; k < 4; ++k) {
        slide += slide_sum[k];
        slide_n += slide_frames[k];
    }
    qsort(search_us, (size_t)search_count, sizeof(float), compare_float);
    double median = search_count ? search_us[search_count / 2] : NAN;
    double p99 = search_count ? search_us[(int)(0.99 * (search_count - 1))] : NAN;
    if (metrics && status == 0) {
        FILE *m = fopen(metrics, "w");
        if (!m) {
            fprintf(stderr, "mm: %s: cannot write the metrics\n", metrics);
            status = 1;
        } else {
            fprintf(m, "{\n");
            json_number(m, "foot_slide_cm_s", slide_n > 0 ? slide / slide_n : NAN, 0);
            json_number(m, "foot_slide_raw_cm_s", slide_n > 0 ? raw_sum / slide_n : NAN, 0);
            json_number(m, "traj_err_cm", traj_err / frames, 0);
            json_number(m, "heading_err_deg", heading_err / frames, 0);
            json_number(m, "response_s", responses ? response_sum / responses : NAN, 0);
            json_number(m, "max_pop_cm", max_pop, 0);
            json_number(m, "db_max_pop_cm", database_max_pop(&db, (float)fps), 0);
            json_number(m, "searches", c.searches, 0);
            json_number(m, "transitions_per_s", c.transitions / seconds, 0);
            json_number(m, "nan_frames", nan_frames, 0);
            json_number(m, "search_median_us", median, 0);
            json_number(m, "search_p99_us", p99, 1);
            fprintf(m, "}\n");
            status = fclose(m) == 0 ? 0 : 1;
        }
    }
    printf("%s: %d frames at %g fps, %d searches, %d transitions, foot slide %.2f cm/s, trajectory error "
           "%.2f cm\n",
           out, frames, fps, c.searches, c.transitions, slide_n > 0 ? slide / slide_n : 0.0,
           traj_err / frames);
    for (int k = 0; k < 3; ++k) free(world[k]);
    free(search_us);
    mm_clip_free(&clip);
    mm_character_free(&c);
    mm_searcher_free(&searcher);
    mm_input_script_free(&script);
    mm_database_free(&db);
    return status;
}
