/* mm pfnn run [--weights DIR] (--input SCRIPT.json | --random SEED) --seconds T [--mode M]
 *             [--symmetry mirror|none] [--scene SCENE.json] -o OUT.bvh [--metrics OUT.json]
 * The neural controller (seed 004) on the same input scripts as mm simulate, measured with the
 * same metrics: the desired velocity comes from the same trajectory simulation (mm/trajectory.h),
 * whose path is also the reference for the trajectory and heading errors. With a scene the network
 * is fed the heights of its ground (mm_pfnn_height_scene), its walls are the controller's
 * obstacles and the simulation's walls, and the metrics measure against its ground. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <mm/input_json.h>
#include <mm/mm.h>
#include <mm/scene_json.h>

#include "cli.h"
#include "commands.h"
#include "motion_metrics.h"

#define RUN_USAGE                                                                                            \
    "usage: mm pfnn run [--weights DIR] (--input SCRIPT.json | --random SEED) --seconds T "                  \
    "[--mode constant|linear|cubic] [--symmetry mirror|none] [--scene SCENE.json] -o OUT.bvh "               \
    "[--metrics OUT.json]"

/* m: a box whose top is at most this above the scene's ground plane is stepped on, not a wall (a
 * step, as mm_trajectory_desc.collider_step) */
#define PFNN_WALL_MIN_HEIGHT 0.3f

/* s the controller stands still on flat ground to show where its feet rest */
#define PFNN_STAND_SECONDS 1.0f

/* Where the controller's contact joints rest (m above flat ground): their heights after it has
 * stood still for PFNN_STAND_SECONDS on flat ground, without walls (NAN for a joint not found).
 * The planted heights the contact and float metrics measure against. 0 on success. */
static int standing_heights(const mm_pfnn_controller_desc *desc, const mm_skeleton *skel,
                            const int contact[4], double planted[4])
{
    mm_pfnn_controller_desc flat = *desc;
    flat.height = NULL, flat.height_user = NULL, flat.obstacles = NULL, flat.obstacle_count = 0;
    mm_pfnn_controller *c = NULL;
    int n = skel->joint_count;
    mm_quat *rotations = malloc(sizeof(mm_quat) * (size_t)n);
    mm_vec3 *positions = malloc(sizeof(mm_vec3) * (size_t)n);
    mm_xform *global = malloc(sizeof(mm_xform) * (size_t)n);
    int status = -1;
    if (rotations && positions && global && mm_pfnn_controller_create(&flat, &c, NULL) == MM_OK) {
        mm_pfnn_input rest;
        memset(&rest, 0, sizeof rest);
        mm_pfnn_controller_step(c, &rest, PFNN_STAND_SECONDS);
        mm_pfnn_controller_local_pose(c, skel, rotations, positions);
        global[0] = mm_xform_make(rotations[0], positions[0]);
        mm_skeleton_global_from(skel->joints, n, 1, rotations, positions, global);
        for (int k = 0; k < 4; ++k) planted[k] = contact[k] >= 0 ? global[contact[k]].translation.y : NAN;
        status = 0;
    }
    mm_pfnn_controller_destroy(c);
    free(rotations);
    free(positions);
    free(global);
    return status;
}

static mm_pfnn_gait pfnn_gait(mm_gait g)
{
    switch (g) {
    case MM_GAIT_RUN:
        return MM_PFNN_GAIT_JOG;
    case MM_GAIT_CROUCH:
        return MM_PFNN_GAIT_CROUCH;
    case MM_GAIT_JUMP:
        return MM_PFNN_GAIT_JUMP;
    default:
        return MM_PFNN_GAIT_WALK;
    }
}

int mm_cmd_pfnn_run(int argc, char **argv)
{
    const char *dir = NULL, *input = NULL, *out = NULL, *metrics = NULL, *mode_name = "cubic",
               *scene_path = NULL;
    mm_pfnn_symmetry symmetry = MM_PFNN_SYMMETRY_MIRROR;
    long seed = -1;
    double seconds = 0.0;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!v || a[0] != '-')
            return cli_usage_error("pfnn run", "unexpected or incomplete '%s'\n%s", a, RUN_USAGE);
        if (strcmp(a, "--weights") == 0)
            dir = v;
        else if (strcmp(a, "--input") == 0)
            input = v;
        else if (strcmp(a, "--random") == 0) {
            if (!cli_parse_int(v, 0, 0x7fffffff, &seed))
                return cli_usage_error("pfnn run", "--random needs a seed >= 0");
        } else if (strcmp(a, "--seconds") == 0) {
            if (!cli_parse_double(v, &seconds) || seconds <= 0 || seconds > 36000)
                return cli_usage_error("pfnn run", "--seconds needs a number in (0, 36000]");
        } else if (strcmp(a, "--mode") == 0)
            mode_name = v;
        else if (strcmp(a, "--symmetry") == 0) {
            if (strcmp(v, "mirror") == 0)
                symmetry = MM_PFNN_SYMMETRY_MIRROR;
            else if (strcmp(v, "none") == 0)
                symmetry = MM_PFNN_SYMMETRY_NONE;
            else
                return cli_usage_error("pfnn run", "--symmetry must be mirror or none, not '%s'", v);
        } else if (strcmp(a, "-o") == 0)
            out = v;
        else if (strcmp(a, "--metrics") == 0)
            metrics = v;
        else if (strcmp(a, "--scene") == 0)
            scene_path = v;
        else
            return cli_usage_error("pfnn run", "unknown option '%s'\n%s", a, RUN_USAGE);
        ++i;
    }
    char default_dir[4096];
    if (!dir && getenv("MM_DATA_DIR") && *getenv("MM_DATA_DIR")) {
        snprintf(default_dir, sizeof default_dir, "%s/pfnn", getenv("MM_DATA_DIR"));
        dir = default_dir;
    }
    if (!dir || !out || seconds <= 0 || (!input) == (seed < 0))
        return cli_usage_error("pfnn run",
                               "--weights (or $MM_DATA_DIR), one of --input and --random, --seconds "
                               "and -o are required\n%s",
                               RUN_USAGE);
    mm_pfnn_mode mode = mm_pfnn_mode_parse(mode_name);
    if (mode == MM_PFNN_MODE_DEFAULT)
        return cli_usage_error("pfnn run", "--mode must be constant, linear or cubic, not '%s'", mode_name);

    mm_error err;
    memset(&err, 0, sizeof err);
    static mm_scene scene; /* large: not on the stack */
    if (scene_path && mm_scene_load_json(scene_path, &scene, &err) != MM_OK) return cli_report(&err);
    /* the scene's walls (boxes higher than a step above its ground plane) for the controller */
    static mm_pfnn_obstacle walls[MM_SCENE_MAX_BOXES];
    int wall_count = 0;
    for (int b = 0; scene_path && b < scene.box_count; ++b) {
        const mm_scene_box *box = &scene.boxes[b];
        if (box->position.y + box->size.y <= scene.ground + PFNN_WALL_MIN_HEIGHT) continue;
        mm_pfnn_obstacle *w = &walls[wall_count++];
        memset(w, 0, sizeof *w);
        w->shape = MM_PFNN_OBSTACLE_BOX;
        w->centre = box->position;
        w->half_x = 0.5f * box->size.x;
        w->half_z = 0.5f * box->size.z;
        w->yaw = box->yaw; /* the same turn about +Y as the scene's */
    }
    mm_input_script script;
    memset(&script, 0, sizeof script);
    if (input) {
        if (mm_input_script_load_json(input, &script, &err) != MM_OK) return cli_report(&err);
    } else {
        mm_input_random_desc rd;
        memset(&rd, 0, sizeof rd);
        rd.seconds = (float)seconds;
        if (mm_input_script_random(&script, (uint64_t)seed, &rd) != MM_OK) {
            fprintf(stderr, "mm: cannot make random input\n");
            return 1;
        }
    }
    int status = 0;
    mm_pfnn_network *net = NULL;
    mm_pfnn_controller *ctrl = NULL;
    mm_skeleton skel;
    memset(&skel, 0, sizeof skel);
    mm_trajectory traj;
    memset(&traj, 0, sizeof traj);
    mm_clip clip;
    memset(&clip, 0, sizeof clip);
    motion_metrics mx;
    memset(&mx, 0, sizeof mx);
    mm_pfnn_network_desc nd;
    memset(&nd, 0, sizeof nd);
    nd.modes = MM_PFNN_MODE_BIT(mode);
    const double fps = 60.0; /* the network's own rate */
    int frames = (int)floor(seconds * fps + 1e-6);
    if (mm_pfnn_network_load(dir, &nd, &net, &err) != MM_OK ||
        mm_pfnn_character_load(dir, NULL, &skel, &err) != MM_OK) {
        status = cli_report(&err);
        goto done;
    }
    mm_pfnn_controller_desc cd;
    memset(&cd, 0, sizeof cd);
    cd.network = net;
    cd.mode = mode;
    cd.symmetry = symmetry;
    if (scene_path) {
        cd.height = mm_pfnn_height_scene;
        cd.height_user = &scene;
        cd.obstacles = walls;
        cd.obstacle_count = wall_count;
    }
    if (mm_pfnn_controller_create(&cd, &ctrl, &err) != MM_OK ||
        mm_trajectory_init(&traj, NULL, NULL) != MM_OK ||
        mm_clip_init(&clip, &skel, frames, (float)fps, NULL) != MM_OK) {
        status = err.code != MM_OK ? cli_report(&err) : (fprintf(stderr, "mm: out of memory\n"), 1);
        goto done;
    }
    if (scene_path) mm_trajectory_set_scene(&traj, &scene, -1.0f); /* asked along the walls */
    /* contacts: the network's order is left heel, left toe, right heel, right toe */
    int contact[4];
    mm_posture_joints posture_joints;
    motion_metrics_roles_by_name(&skel, contact, &posture_joints);
    int n = skel.joint_count;
    mm_xform *global = malloc(sizeof(mm_xform) * (size_t)n);
    mm_vec3 *world = malloc(sizeof(mm_vec3) * (size_t)n);
    double planted[4];
    if (!global || !world || motion_metrics_init(&mx, n, contact, fps, frames) != 0 ||
        standing_heights(&cd, &skel, contact, planted) != 0) {
        free(global);
        free(world);
        fprintf(stderr, "mm: out of memory\n");
        status = 1;
        goto done;
    }
    /* no database: no upright head height to measure the posture against (mm metrics on the BVH
     * measures it against the motion itself); the feet's planted heights are where they rest
     * standing */
    motion_metrics_reference(&mx, &posture_joints, 0.0f, planted);
    mx.joints = skel.joints;
    if (scene_path) motion_metrics_scene(&mx, &scene); /* heights and walls against the scene */
    /* the metrics file is opened first, so that a bad path fails before the run and leaves no
       motion behind */
    char tmp[4096 + 32];
    FILE *m = NULL;
    if (metrics && !(m = cli_create(metrics, tmp, sizeof tmp))) {
        free(global);
        free(world);
        status = 1;
        goto done;
    }
    const double dt = 1.0 / fps;
    for (int f = 0; f < frames; ++f) {
        double t = f * dt;
        mm_input in;
        mm_input_script_sample(&script, (float)t, &in);
        mm_vec3 desired;
        mm_quat desired_facing;
        mm_trajectory_desired(&traj, &in, &desired, &desired_facing);
        motion_metrics_input(&mx, t, &in, desired);
        mm_trajectory_update(&traj, &in, (float)dt);
        traj.floor = mm_pfnn_controller_state(ctrl)->root_position.y; /* where the character stands */
        mm_pfnn_input pin;
        memset(&pin, 0, sizeof pin);
        pin.velocity = desired;
        if (in.strafe) pin.facing = mm_quat_rotate(desired_facing, mm_vec3_make(0, 0, 1));
        pin.gait = pfnn_gait(in.gait);
        double start = cli_now();
        mm_pfnn_controller_step(ctrl, &pin, 0.0f); /* one 60 Hz frame */
        float frame_us = (float)(1e6 * (cli_now() - start));
        const mm_pfnn_state *s = mm_pfnn_controller_state(ctrl);
        mm_pfnn_controller_local_pose(ctrl, &skel, mm_clip_rotations(&clip, f), mm_clip_positions(&clip, f));
        mm_clip_fk(&clip, f, global);
        for (int j = 0; j < n; ++j) world[j] = global[j].translation;
        unsigned labels = 0;
        for (int k = 0; k < 4; ++k) labels |= (s->contacts[k] > 0.5f ? 1u : 0u) << k;
        motion_metrics_frame(&mx, t, world, labels, NULL, traj.position, motion_metrics_yaw(traj.facing),
                             s->root_position, s->root_yaw, frame_us);
    }
    free(global);
    free(world);
    mm_bvh_write_desc wd;
    memset(&wd, 0, sizeof wd);
    if (mm_bvh_save(out, &clip, &wd, &err) != MM_OK) {
        if (m) cli_commit(m, tmp, metrics, 1);
        status = cli_report(&err);
        goto done;
    }
    if (m) {
        motion_metrics_extra x = {NAN, NAN, NAN, (double)mm_pfnn_network_bytes(net, mode) / (1024.0 * 1024.0),
                                  NAN, NAN, NAN, NAN};
        motion_metrics_write_json(&mx, m, &x);
        status = cli_commit(m, tmp, metrics, 0);
        if (status != 0) remove(out); /* the motion without its metrics: nothing */
    }
    if (status == 0)
        printf("%s: %d frames at 60 fps (%s), foot slide %.2f cm/s, trajectory error %.2f cm\n", out, frames,
               mm_pfnn_mode_name(mode), motion_metrics_foot_slide(&mx), motion_metrics_traj_err(&mx));
done:
    motion_metrics_free(&mx);
    mm_clip_free(&clip);
    mm_trajectory_free(&traj);
    mm_pfnn_controller_destroy(ctrl);
    if (skel.joints) mm_skeleton_free(&skel);
    mm_pfnn_network_free(net);
    mm_input_script_free(&script);
    return status;
}
