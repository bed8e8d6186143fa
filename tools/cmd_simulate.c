/* mm simulate DB (--input SCRIPT | --random SEED | --path PATH) --seconds T [--fps F] -o OUT.bvh --metrics
 * OUT.json
 *             [--scene SCENE.json] [--distance-matching on|off] [--warping on|off]
 *             [--video OUT.mp4|OUT.gif|FOLDER [--size WxH] [--video-fps F]]
 *             [--transition inertialize|crossfade] [--crossfade-time S]
 *             [--skeleton GAME.bvh [--skeleton-map MAP.json]]
 *             [--trace OUT.jsonl [--trace-ticks] [--trace-k N]]
 * Runs one character over scripted or random input, or along a desired path (mm/drive.h); writes its motion,
 * the metrics of docs/metrics.md and, on request, a video of it rendered headless. With a scene, the move
 * layer (mm/moves.h: jump, vault, climb, drop-down) runs around the character. With a skeleton, the motion is
 * written in the game's joint names and order (mm/skeleton_map.h, sim_skeleton.h). With a trace, every search
 * (and with --trace-ticks every tick) goes to JSON lines (mm/trace.h) that mm view --replay runs again. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <mm/character.h>
#include <mm/input_json.h>
#include <mm/mm.h>
#include <mm/moves.h>
#include <mm/path_json.h>
#include <mm/render.h>
#include <mm/scene_json.h>
#include <mm/trace.h>
#include <mm/view.h>

#include "cli.h"
#include "commands.h"
#include "motion_metrics.h"
#include "sim_skeleton.h"
#include "sim_video.h"

/* The motion is kept in memory until it is written: at most 10 hours at 60 fps. */
#define SIM_MAX_FRAMES 2160000
/* The BVH readers' file-size limit (src/io/file.h) and a bound on a joint's share of the header. */
#define SIM_MAX_BVH_BYTES    2147483648.0
#define SIM_BVH_HEADER_BYTES 512.0
#define SIM_MIN_FRAMES       2 /* one step between two frames: speeds, slide and the metrics need it */

int mm_cmd_simulate(int argc, char **argv)
{
    const char *db_path = NULL, *input = NULL, *out = NULL, *metrics = NULL, *video_path = NULL,
               *scene_path = NULL, *skeleton_path = NULL, *skeleton_map_path = NULL, *path_file = NULL,
               *trace_path = NULL;
    int trace_ticks = 0;
    long trace_k = MM_TRACE_DEFAULT_K;
    long seed = -1;
    double seconds = 0.0, fps = 60.0, video_fps = 30.0, crossfade_time = -1.0;
    int width = 1280, height = 720;
    const char *mesh_path = NULL;                              /* --mesh: the video's body */
    int distance_matching = -1, warping = -1, transition = -1; /* -1: the controller's default */
    const char *usage =
        "usage: mm simulate DB.mmdb (--input SCRIPT.json | --random SEED | --path PATH.json) --seconds T "
        "[--fps F] -o OUT.bvh "
        "--metrics OUT.json [--scene SCENE.json] [--distance-matching on|off] [--warping on|off] "
        "[--video OUT.mp4|OUT.gif|FOLDER [--size 1280x720] [--video-fps 30] [--mesh FILE]] "
        "[--transition inertialize|crossfade] [--crossfade-time S] [--skeleton GAME.bvh [--skeleton-map "
        "MAP.json]] [--trace OUT.jsonl [--trace-ticks] [--trace-k N]]";
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (strcmp(a, "--input") == 0 && v)
            input = argv[++i];
        else if (strcmp(a, "--path") == 0 && v)
            path_file = argv[++i];
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
        else if (strcmp(a, "--scene") == 0 && v)
            scene_path = argv[++i];
        else if (strcmp(a, "--skeleton") == 0 && v)
            skeleton_path = argv[++i];
        else if (strcmp(a, "--skeleton-map") == 0 && v)
            skeleton_map_path = argv[++i];
        else if (strcmp(a, "--video") == 0 && v)
            video_path = argv[++i];
        else if (strcmp(a, "--mesh") == 0 && v)
            mesh_path = argv[++i];
        else if (strcmp(a, "--size") == 0 && v) {
            if (!cli_parse_size(v, &width, &height))
                return cli_usage_error("simulate", "--size needs WIDTHxHEIGHT, each 16 to 4096");
            ++i;
        } else if (strcmp(a, "--video-fps") == 0 && v) {
            if (!cli_parse_double(v, &video_fps) || video_fps < 1 || video_fps > 240)
                return cli_usage_error("simulate", "--video-fps needs 1 to 240");
            ++i;
        } else if ((strcmp(a, "--distance-matching") == 0 || strcmp(a, "--warping") == 0) && v) {
            int on = strcmp(v, "on") == 0 ? 1 : strcmp(v, "off") == 0 ? 0 : -1;
            if (on < 0) return cli_usage_error("simulate", "%s needs on or off\n%s", a, usage);
            if (a[2] == 'd')
                distance_matching = on;
            else
                warping = on;
            ++i;
        } else if (strcmp(a, "--transition") == 0 && v) {
            transition = strcmp(v, "inertialize") == 0 ? MM_TRANSITION_INERTIALIZE
                         : strcmp(v, "crossfade") == 0 ? MM_TRANSITION_CROSSFADE
                                                       : -1;
            if (transition < 0)
                return cli_usage_error("simulate", "--transition needs inertialize or crossfade\n%s", usage);
            ++i;
        } else if (strcmp(a, "--crossfade-time") == 0 && v) {
            if (!cli_parse_double(v, &crossfade_time) || crossfade_time < 0 || crossfade_time > 10)
                return cli_usage_error("simulate", "--crossfade-time needs seconds in [0, 10]");
            ++i;
        } else if (strcmp(a, "--trace") == 0 && v) {
            trace_path = argv[++i];
        } else if (strcmp(a, "--trace-ticks") == 0) {
            trace_ticks = 1;
        } else if (strcmp(a, "--trace-k") == 0 && v) {
            if (!cli_parse_int(v, 1, MM_TRACE_MAX_K, &trace_k))
                return cli_usage_error("simulate", "--trace-k needs 1 to %d", MM_TRACE_MAX_K);
            ++i;
        } else if (a[0] == '-' && a[1])
            return cli_usage_error("simulate", "unknown or incomplete option '%s'\n%s", a, usage);
        else if (!db_path)
            db_path = a;
        else
            return cli_usage_error("simulate", "unexpected argument '%s'", a);
    }
    if (!db_path || (input != NULL) + (seed >= 0) + (path_file != NULL) != 1 || seconds <= 0 || !out)
        return cli_usage_error("simulate", "%s", usage);
    if (floor(seconds * fps + 1e-6) < SIM_MIN_FRAMES)
        return cli_usage_error("simulate",
                               "--seconds %g at --fps %g is less than %d frames: a run needs at least %g s",
                               seconds, fps, SIM_MIN_FRAMES, SIM_MIN_FRAMES / fps);
    if (skeleton_map_path && !skeleton_path)
        return cli_usage_error("simulate", "--skeleton-map needs --skeleton");
    if ((trace_ticks || trace_k != MM_TRACE_DEFAULT_K) && !trace_path)
        return cli_usage_error("simulate", "--trace-ticks and --trace-k need --trace");
    if (seconds * fps > SIM_MAX_FRAMES)
        return cli_usage_error("simulate",
                               "--seconds %g at --fps %g is %.0f frames, more than the %d allowed", seconds,
                               fps, floor(seconds * fps), SIM_MAX_FRAMES);
    mm_error err;
    memset(&err, 0, sizeof err);
    static mm_scene scene; /* about 7 KB: not on the stack */
    if (scene_path && mm_scene_load_json(scene_path, &scene, &err) != MM_OK) return cli_report(&err);
    mm_database db;
    if (mm_database_load(db_path, NULL, &db, &err) != MM_OK) return cli_report(&err);
    mm_input_script script;
    memset(&script, 0, sizeof script);
    mm_path path; /* --path: where the character is asked to go */
    memset(&path, 0, sizeof path);
    mm_result r = input ? mm_input_script_load_json(input, &script, &err) : MM_OK;
    if (path_file) {
        r = mm_path_load_json(path_file, &path, &err);
    } else if (!input) {
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
    double path_error_sum = 0.0, path_error_max = 0.0; /* m: the root from the path's position */
    mm_searcher searcher;
    mm_character c;
    mm_character_desc desc;
    /* the runtime tuning saved in the database (its settings section, from its config's "runtime") */
    if (mm_character_desc_from_database(&desc, &db, &err) != MM_OK) {
        mm_database_free(&db);
        return cli_report(&err);
    }
    desc.clock = cli_now;
    if (distance_matching >= 0) desc.distance_matching = distance_matching != 0;
    if (warping >= 0) desc.warping = warping != 0;
    if (transition >= 0) desc.transition_mode = (mm_transition_mode)transition;
    if (crossfade_time >= 0) desc.crossfade_time = crossfade_time > 0 ? (float)crossfade_time : MM_OFF;
    if (mm_searcher_init(&searcher, &db, NULL, &err) != MM_OK ||
        mm_character_init(&c, &db, &searcher, &desc, &err) != MM_OK) {
        mm_input_script_free(&script);
        mm_path_free(&path);
        mm_database_free(&db);
        return cli_report(&err);
    }
    /* the trace: how the run was made (all a replay needs), and the candidates kept per search */
    mm_trace_run trace_run;
    mm_trace_run_defaults(&trace_run);
    if (trace_path) {
        snprintf(trace_run.db_path, sizeof trace_run.db_path, "%s", db_path);
        trace_run.db_checksum = mm_trace_db_checksum(&db);
        trace_run.db_size = (uint64_t)db.size;
        trace_run.db_frames = db.frame_count;
        trace_run.fps = fps;
        trace_run.ticks = (int)floor(seconds * fps + 1e-6);
        trace_run.random_seed = input || path_file ? -1 : seed;
        trace_run.random_seconds = seconds;
        if (path_file) snprintf(trace_run.path_file, sizeof trace_run.path_file, "%s", path_file);
        if (scene_path) snprintf(trace_run.scene_path, sizeof trace_run.scene_path, "%s", scene_path);
        trace_run.distance_matching = distance_matching;
        trace_run.warping = warping;
        trace_run.transition_mode = transition;
        trace_run.crossfade_time = crossfade_time;
        trace_run.top_k = (int)trace_k;
        trace_run.tick_lines = trace_ticks != 0;
        if ((input && mm_trace_run_set_input_file(&trace_run, input, &err) != MM_OK) ||
            mm_character_set_candidates(&c, (int)trace_k, &err) != MM_OK) {
            mm_trace_run_free(&trace_run);
            mm_character_free(&c);
            mm_searcher_free(&searcher);
            mm_input_script_free(&script);
            mm_path_free(&path);
            mm_database_free(&db);
            return cli_report(&err);
        }
    }
    mm_moves moves; /* without a scene: plain locomotion; hands and feet by the database's roles */
    mm_moves_desc moves_desc;
    mm_moves_desc_from_database(&moves_desc, &db);
    mm_moves_init(&moves, &db, scene_path ? &scene : NULL, &moves_desc, NULL);
    if (scene_path) mm_character_place_in_scene(&c, &scene);
    int frames = (int)floor(seconds * fps + 1e-6), n = db.joint_count;
    /* the motion's skeleton: the database's, or the game's (--skeleton) */
    sim_skeleton game;
    memset(&game, 0, sizeof game);
    if (skeleton_path && sim_skeleton_open(&game, skeleton_path, skeleton_map_path, &db) != 0) {
        mm_character_free(&c);
        mm_searcher_free(&searcher);
        mm_input_script_free(&script);
        mm_path_free(&path);
        mm_database_free(&db);
        return 1;
    }
    /* the BVH is written as the run goes (mm_bvh_stream): memory does not grow with its length */
    mm_skeleton skel;
    memset(&skel, 0, sizeof skel);
    if (skeleton_path) {
        r = sim_skeleton_copy(&game, &skel) == 0 ? MM_OK : MM_ERR_OUT_OF_MEMORY;
    } else {
        r = mm_skeleton_init(&skel, n, NULL);
        if (r == MM_OK) memcpy(skel.joints, db.joints, sizeof(mm_joint) * (size_t)n);
    }
    /* one frame of the output skeleton's pose (the game's, mapped each tick) */
    int out_joints = skeleton_path ? skel.joint_count : n;
    mm_quat *out_rotations = skeleton_path ? malloc(sizeof(mm_quat) * (size_t)out_joints) : NULL;
    mm_vec3 *out_positions = skeleton_path ? malloc(sizeof(mm_vec3) * (size_t)out_joints) : NULL;
    if (r == MM_OK && skeleton_path && (!out_rotations || !out_positions)) r = MM_ERR_OUT_OF_MEMORY;
    mm_bvh_stream *stream = NULL;
    int too_long = 0;
    if (r == MM_OK) {
        /* refused up front: a BVH mm could not read back (the readers stop at 2 GiB) */
        mm_bvh_write_desc probe = {0};
        double bytes = (double)frames * (double)mm_bvh_frame_bytes_max(&skel, &probe) +
                       SIM_BVH_HEADER_BYTES * out_joints;
        if (bytes >= SIM_MAX_BVH_BYTES) {
            double most = floor(SIM_MAX_BVH_BYTES / (double)mm_bvh_frame_bytes_max(&skel, &probe) / fps);
            fprintf(stderr,
                    "mm: %s: %d frames of %d joints could make a BVH file of %.1f GB, more than the 2 GiB mm "
                    "reads: a run of at most %g s at --fps %g\n",
                    out, frames, out_joints, bytes / 1e9, most, fps);
            too_long = 1;
        }
    }
    int contact[4];
    mm_posture_joints posture_joints;
    motion_metrics_roles_of_database(&db, contact, &posture_joints);
    motion_metrics mx;
    mm_vec3 *world = malloc(sizeof(mm_vec3) * (size_t)n);
    int metrics_ok = motion_metrics_init(&mx, n, contact, fps, frames) == 0 && world;
    if (metrics_ok) mx.joints = db.joints;
    if (metrics_ok && scene_path) motion_metrics_scene(&mx, &scene);
    /* what the database gives the metrics: its own pops, its upright head height and where its
     * feet are planted */
    motion_metrics_db dbm;
    if (metrics_ok && metrics) {
        metrics_ok = motion_metrics_database(&db, fps, &dbm) == 0;
        motion_metrics_reference(&mx, &posture_joints, dbm.reference, dbm.planted);
    }
    int status = 0;
    /* the motion and the metrics go to temporary files, opened now so that a bad path fails before
     * the run; they are renamed into place only when they and the video were all written, so a
     * failure leaves none of the outputs */
    char metrics_tmp[4096 + 32], bvh_tmp[4096 + 32], trace_tmp[4096 + 32];
    FILE *m = NULL, *bf = NULL, *tf = NULL;
    if (too_long) {
        status = 1;
        goto done;
    }
    if (r != MM_OK || !metrics_ok) {
        fprintf(stderr, "mm: out of memory for %d frames of %d joints\n", frames, n);
        status = 1;
        goto done;
    }
    if (!(bf = cli_create(out, bvh_tmp, sizeof bvh_tmp)) ||
        (metrics && !(m = cli_create(metrics, metrics_tmp, sizeof metrics_tmp))) ||
        (trace_path && !(tf = cli_create(trace_path, trace_tmp, sizeof trace_tmp)))) {
        status = 1;
        goto done;
    }
    mm_bvh_write_desc wd;
    memset(&wd, 0, sizeof wd);
    snprintf(err.file, sizeof err.file, "%s", out);
    if (mm_bvh_stream_open(&stream, bf, &skel, (float)fps, frames, &wd, &err) != MM_OK) {
        status = cli_report(&err);
        goto done;
    }
    sim_video video;
    memset(&video, 0, sizeof video);
    if (video_path &&
        (sim_video_open(&video, video_path, width, height, video_fps, 1.0 / fps, &db, &err) != MM_OK ||
         (scene_path && sim_video_set_scene(&video, &scene, &err) != MM_OK) ||
         (mesh_path && sim_video_set_mesh(&video, mesh_path, &err) != MM_OK))) {
        status = cli_report(&err);
        goto done;
    }
    if (tf && mm_trace_write_header(tf, &trace_run, &db) != MM_OK) status = 1;
    int last_searches = 0;
    float dt = (float)(1.0 / fps);
    float future_times[MM_MAX_TRAJ_SAMPLES];
    int future_count = mm_character_future_times(&c, future_times);
    for (int f = 0; f < frames; ++f) {
        double t = f / fps;
        mm_input in;
        if (path_file) {
            /* steered along the path, the path itself the future the search matches (as mm_run_path) */
            mm_vec3 future_positions[MM_MAX_TRAJ_SAMPLES];
            mm_quat future_facings[MM_MAX_TRAJ_SAMPLES];
            mm_drive_input_path(c.trajectory, &path, (float)t, 0.0f, &in);
            mm_path_future(&path, (float)t + dt, future_times, future_count, c.trajectory->facing,
                           future_positions, future_facings);
            mm_character_set_future(&c, future_positions, future_facings, future_count, NULL);
        } else
            mm_input_script_sample_tick(&script, (float)t, (float)(1.0 / fps), &in);
        mm_vec3 desired;
        mm_trajectory_desired(c.trajectory, &in, &desired, NULL);
        motion_metrics_input(&mx, t, &in, desired);
        int searches_before = c.searches, transitions_before = c.transitions;
        double start = cli_now();
        mm_moves_update(&moves, &c, &in, dt);
        float frame_us = (float)(1e6 * (cli_now() - start));
        if (tf && status == 0 &&
            mm_trace_write_tick(tf, &trace_run, &c, f, (f + 1) / fps, searches_before, transitions_before) !=
                MM_OK)
            status = 1;
        if (path_file) {
            mm_vec3 want, root = c.root.translation;
            mm_path_sample(&path, (float)(t + dt), &want, NULL, NULL);
            double e = hypot(root.x - want.x, root.z - want.z);
            path_error_sum += e;
            if (e > path_error_max) path_error_max = e;
        }
        if (moves.finished)
            motion_metrics_move(&mx, mm_move_kind_name(moves.last.kind), moves.last.t_start, moves.last.t_end,
                                moves.last.target_error_cm);
        if (video_path && status == 0 && sim_video_tick(&video, &c, &in, &err) != MM_OK)
            status = cli_report(&err);
        if (c.searches != last_searches) {
            motion_metrics_search(&mx, c.last_search_us);
            last_searches = c.searches;
        }
        /* the pose as BVH: joint 0 carries the root (or in the game's skeleton) */
        const mm_quat *rotations = c.local_rotations;
        const mm_vec3 *positions = c.local_positions;
        if (skeleton_path) {
            sim_skeleton_pose(&game, &c, out_rotations, out_positions);
            rotations = out_rotations;
            positions = out_positions;
        }
        if (status == 0 && mm_bvh_stream_frame(stream, rotations, positions, &err) != MM_OK)
            status = cli_report(&err);
        for (int j = 0; j < n; ++j) world[j] = c.global[j].translation;
        motion_metrics_frame(&mx, t, world, db.contacts[c.frame], c.raw_contact_positions,
                             c.trajectory->position, motion_metrics_yaw(c.trajectory->facing),
                             c.root.translation, motion_metrics_yaw(c.root.rotation), frame_us);
    }
    mm_result closed = mm_bvh_stream_close(stream, &err);
    stream = NULL;
    if (status == 0 && closed != MM_OK) status = cli_report(&err);
    if (status == 0 && m) {
        motion_metrics_extra x = {.db_max_pop_cm = dbm.max_pop_cm,
                                  .searches = c.searches,
                                  .transitions_per_s = c.transitions / seconds,
                                  .memory_mb = (double)(db.size + searcher.memory) / (1024.0 * 1024.0),
                                  .db_pop_p99_cm = dbm.pop_p99_cm,
                                  .db_head_p5_cm = dbm.head_p5_cm,
                                  .db_head_p50_cm = dbm.head_p50_cm,
                                  .db_foot_slide_height_cm_s = dbm.foot_slide_height_cm_s};
        motion_metrics_write_json(&mx, m, &x);
    }
    /* close the temporary files, finish the video, and only then rename: a failure at any step
     * leaves none of the outputs */
    int bvh_done = 0, metrics_done = 0, video_done = 0, video_frames = 0, trace_done = 0;
    if (status == 0)
        bvh_done = cli_finish(bf, bvh_tmp, out) == 0;
    else
        cli_commit(bf, bvh_tmp, out, 1);
    bf = NULL;
    if (!bvh_done) status = 1;
    if (m) {
        if (status == 0)
            metrics_done = cli_finish(m, metrics_tmp, metrics) == 0;
        else
            cli_commit(m, metrics_tmp, metrics, 1);
        m = NULL;
        if (!metrics_done) status = 1;
    }
    if (tf) {
        if (status == 0)
            trace_done = cli_finish(tf, trace_tmp, trace_path) == 0;
        else
            cli_commit(tf, trace_tmp, trace_path, 1);
        tf = NULL;
        if (!trace_done) status = 1;
    }
    if (video_path) {
        if (sim_video_close(&video, status != 0, &video_frames, &err) != MM_OK && status == 0)
            status = cli_report(&err);
        video_done = status == 0;
    }
    if (status == 0) {
        bvh_done = 0; /* cli_publish renames the temporary file or removes it */
        if (cli_publish(bvh_tmp, out) != 0) {
            status = 1;
        } else if (metrics_done) {
            metrics_done = 0;
            if (cli_publish(metrics_tmp, metrics) != 0) {
                status = 1;
                remove(out);
            }
        }
        if (status == 0 && trace_done) {
            trace_done = 0;
            if (cli_publish(trace_tmp, trace_path) != 0) {
                status = 1;
                remove(out);
                if (metrics) remove(metrics);
            }
        }
    }
    if (status != 0) {
        if (bvh_done) remove(bvh_tmp);
        if (metrics_done) remove(metrics_tmp);
        if (trace_done) remove(trace_tmp);
        if (video_done) remove(video_path); /* an encoded file (a folder of frames stays) */
    }
    if (video_path && status == 0) printf("%s: %d video frames\n", video_path, video_frames);
    if (status == 0)
        printf("%s: %d frames at %g fps, %d searches, %d transitions, foot slide %.2f cm/s, trajectory error "
               "%.2f cm\n",
               out, frames, fps, c.searches, c.transitions, motion_metrics_foot_slide(&mx),
               motion_metrics_traj_err(&mx));
    if (status == 0 && path_file && frames > 0)
        printf("%s: the root from the path: mean %.2f cm, max %.2f cm\n", out,
               100.0 * path_error_sum / frames, 100.0 * path_error_max);
done:
    mm_bvh_stream_close(stream, NULL);             /* before its file is closed */
    if (m) cli_commit(m, metrics_tmp, metrics, 1); /* a failure before the outputs were written */
    if (bf) cli_commit(bf, bvh_tmp, out, 1);
    if (tf) cli_commit(tf, trace_tmp, trace_path, 1);
    mm_trace_run_free(&trace_run);
    free(world);
    motion_metrics_free(&mx);
    mm_skeleton_free(&skel);
    free(out_rotations);
    free(out_positions);
    sim_skeleton_close(&game);
    if (status == 0 && desc.transition_mode == MM_TRANSITION_CROSSFADE)
        printf("%s: crossfade, %d transitions cancelled\n", out, c.cancelled_transitions);
    mm_character_free(&c);
    mm_searcher_free(&searcher);
    mm_input_script_free(&script);
    mm_path_free(&path);
    mm_database_free(&db);
    return status;
}
