/* mm metrics FILE.bvh [--db DB.mmdb | --config CONFIG.json] [--scale S|auto] [--scene SCENE.json] [-o
 * OUT.json] The metrics of docs/metrics.md that a motion gives alone, without a controller, measured on any
 * BVH file by the same code as mm simulate's (tools/motion_metrics.c): pops, the body below the ground, the
 * head's height, the posture, the arms and the height-weighted foot slide. The keys that need a controller
 * are null. With --db the bone roles, the upright head height and the planted heights are the database's (the
 * file must have its joint names) and its own db_* keys are given; with
 * --config the roles are the config's (by name in the file); without either they are the joints
 * named as the roles' defaults, and the references come from the file itself. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <mm/mm.h>
#include <mm/config_json.h>
#include <mm/scene_json.h>

#include "cli.h"
#include "commands.h"
#include "motion_metrics.h"

/* The joint of the file named name (a role of the config, "" for none: -1); -2 when the file has
 * no such joint (after printing). */
static int config_joint(const mm_skeleton *file, const char *name, const char *role, const char *path)
{
    if (!name[0]) return -1;
    int k = mm_skeleton_find(file, name);
    if (k < 0) fprintf(stderr, "mm: %s: no joint '%s' (roles.%s of the config)\n", path, name, role);
    return k >= 0 ? k : -2;
}

/* The joint of the file named like joint j of the database, -1 for j < 0; -2 when the file has
 * no such joint (after printing). */
static int file_joint(const mm_skeleton *file, const mm_database *db, int j, const char *path)
{
    if (j < 0 || j >= db->joint_count) return -1;
    int k = mm_skeleton_find(file, db->joints[j].name);
    if (k < 0)
        fprintf(stderr, "mm: %s: no joint '%s' (a bone role of the database)\n", path, db->joints[j].name);
    return k >= 0 ? k : -2;
}

int mm_cmd_metrics(int argc, char **argv)
{
    const char *in = NULL, *out = NULL, *db_path = NULL, *config_path = NULL, *scene_path = NULL;
    double scale = 0.0; /* 0: auto */
    const char *usage = "usage: mm metrics FILE.bvh [--db DB.mmdb | --config CONFIG.json] [--scale S|auto] "
                        "[--scene SCENE.json] [-o OUT.json]";
    const cli_option options[] = {
        {.name = "-o", .kind = CLI_STRING, .target = &out},
        {.name = "--db", .kind = CLI_STRING, .target = &db_path},
        {.name = "--config", .kind = CLI_STRING, .target = &config_path},
        {.name = "--scene", .kind = CLI_STRING, .target = &scene_path},
        {.name = "--scale", .kind = CLI_CUSTOM, .target = &scale, .parse = cli_parse_scale},
    };
    int status = cli_parse_options("metrics", argc, argv, options, CLI_COUNT(options), usage, &in, 1);
    if (status) return status;
    if (!in) return cli_usage_error("metrics", "%s", usage);
    if (db_path && config_path) return cli_usage_error("metrics", "--db and --config: give one\n%s", usage);
    mm_error err;
    memset(&err, 0, sizeof err);
    static mm_scene scene; /* about 7 KB: not on the stack */
    if (scene_path && mm_scene_load_json(scene_path, &scene, &err) != MM_OK) return cli_report(&err);
    mm_clip clip;
    if (cli_load_clip(in, scale, &clip)) return 1;
    mm_database db;
    memset(&db, 0, sizeof db);
    if (db_path && mm_database_load(db_path, NULL, &db, &err) != MM_OK) {
        mm_clip_free(&clip);
        return cli_report(&err);
    }
    mm_config cfg;
    memset(&cfg, 0, sizeof cfg);
    if (config_path && mm_config_load_json(config_path, &cfg, NULL, &err) != MM_OK) {
        mm_clip_free(&clip);
        return cli_report(&err);
    }
    int n = clip.skeleton.joint_count, frames = clip.frame_count, contact[4];
    double fps = clip.fps;
    mm_posture_joints joints;
    motion_metrics_db dbm;
    motion_metrics mx;
    memset(&mx, 0, sizeof mx);
    mm_xform *global = malloc(sizeof(mm_xform) * (size_t)n);
    mm_vec3 *world = malloc(sizeof(mm_vec3) * (size_t)n * (size_t)(frames > 0 ? frames : 1));
    FILE *f = stdout;
    char tmp[4096 + 32];
    if (db_path) { /* the database's roles, by their joints' names */
        int db_contact[4];
        mm_posture_joints db_joints;
        motion_metrics_roles_of_database(&db, db_contact, &db_joints);
        int *from[8] = {&db_contact[0],  &db_contact[1],  &db_contact[2],       &db_contact[3],
                        &db_joints.hips, &db_joints.head, &db_joints.left_hand, &db_joints.right_hand};
        int *to[8] = {&contact[0],  &contact[1],  &contact[2],       &contact[3],
                      &joints.hips, &joints.head, &joints.left_hand, &joints.right_hand};
        for (int k = 0; k < 8; ++k)
            if ((*to[k] = file_joint(&clip.skeleton, &db, *from[k], in)) == -2) status = 1;
    } else if (config_path) { /* the config's roles */
        const char *names[8] = {cfg.left_foot, cfg.left_toe, cfg.right_foot, cfg.right_toe,
                                cfg.hips,      cfg.head,     cfg.left_hand,  cfg.right_hand};
        const char *roles[8] = {"left_foot", "left_toe", "right_foot", "right_toe",
                                "hips",      "head",     "left_hand",  "right_hand"};
        int *to[8] = {&contact[0],  &contact[1],  &contact[2],       &contact[3],
                      &joints.hips, &joints.head, &joints.left_hand, &joints.right_hand};
        for (int k = 0; k < 8; ++k)
            if ((*to[k] = config_joint(&clip.skeleton, names[k], roles[k], in)) == -2) status = 1;
    } else {
        motion_metrics_roles_by_name(&clip.skeleton, contact, &joints);
    }
    if (status) goto done;
    mm_posture_find_legs(&clip.skeleton, contact[0], contact[2], &joints); /* the knees from the feet */
    if (!global || !world || motion_metrics_init(&mx, n, contact, fps, frames) != 0 ||
        (db_path && motion_metrics_database(&db, fps, &dbm) != 0)) {
        fprintf(stderr, "mm: out of memory for %d frames of %d joints\n", frames, n);
        status = 1;
        goto done;
    }
    mx.joints = clip.skeleton.joints;
    if (scene_path) motion_metrics_scene(&mx, &scene);
    for (int k = 0; k < frames; ++k) {
        mm_clip_fk(&clip, k, global);
        for (int j = 0; j < n; ++j) world[(size_t)k * (size_t)n + j] = global[j].translation;
    }
    if (db_path)
        motion_metrics_reference(&mx, &joints, dbm.reference, dbm.planted);
    else
        motion_metrics_reference_from_motion(&mx, &joints, world, frames);
    for (int k = 0; k < frames; ++k) motion_metrics_pose(&mx, world + (size_t)k * (size_t)n);
    if (out && !(f = cli_create(out, tmp, sizeof tmp))) {
        status = 1;
        goto done;
    }
    motion_metrics_extra x = {NAN, NAN, NAN, NAN, NAN, NAN, NAN, NAN};
    if (db_path) {
        x.db_max_pop_cm = dbm.max_pop_cm;
        x.db_pop_p99_cm = dbm.pop_p99_cm;
        x.db_head_p5_cm = dbm.head_p5_cm;
        x.db_head_p50_cm = dbm.head_p50_cm;
        x.db_foot_slide_height_cm_s = dbm.foot_slide_height_cm_s;
    }
    motion_metrics_write_json(&mx, f, &x);
    if (out) status = cli_commit(f, tmp, out, 0);
done:
    motion_metrics_free(&mx);
    free(global);
    free(world);
    if (db_path) mm_database_free(&db);
    if (config_path) mm_config_free(&cfg);
    mm_clip_free(&clip);
    return status;
}
