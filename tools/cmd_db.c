/* mm db build | info | dump | search */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <mm/config_json.h>
#include <mm/database_build.h>
#include <mm/diagnose.h>
#include <mm/gait.h>
#include <mm/search.h>

#include "cli.h"
#include "commands.h"

/* What the postures of the takes did to the database (docs/database.md, "Postures"). */
static void print_postures(const mm_db_build_report *report)
{
    const int *n = report->source_frames;
    if (report->reference_head_height <= 0) {
        printf("postures: not judged (no locomotion or idle clip with a head and hips)\n");
        return;
    }
    printf("postures: upright head height %.2f m; source frames upright %d, left out: calibration %d, lying "
           "%d, arms spread %d, hand raised %d, knee raised %d; "
           "tagged Crouch: crouched %d, bent %d\n",
           report->reference_head_height, n[MM_POSTURE_UPRIGHT], n[MM_POSTURE_CALIBRATION],
           n[MM_POSTURE_LYING], n[MM_POSTURE_ARMS_SPREAD], n[MM_POSTURE_HAND_RAISED],
           n[MM_POSTURE_KNEE_RAISED], n[MM_POSTURE_CROUCHED], n[MM_POSTURE_BENT]);
}

/* The standing clip the build made when no clip is an idle clip (docs/database.md, "A standing pose
 * when the takes have no idle"). */
static void print_standing(const mm_db_standing_report *s)
{
    if (s->status == MM_STANDING_MADE)
        printf(
            "standing:   no idle clip: made %d standing pose%s%s held for 2 s with the feet planted, the "
            "stillest %s: clip %s's frame %d (%.2f s; root %.3f m/s, joints %.3f m/s around it, feet %.2f m "
            "apart along the facing, %.2f m from the root)\n",
            s->poses, s->poses == 1 ? "" : "s", s->mirrored ? " (and mirrors)" : "", s->clip, s->from_clip,
            s->from_frame, s->from_time, s->root_speed, s->joint_speed, s->stride, s->offset);
    else if (s->status == MM_STANDING_OFF)
        printf("standing:   no idle clip, none made (standing.make is false)\n");
    else if (s->status == MM_STANDING_NOT_FOUND)
        printf("standing:   no idle clip, none made: no locomotion frame is upright with both feet down\n");
}

/* Whether a clip is an idle loop the build made (idle_loop.make): an idle loop clip named
 * "<clip>_loop" or "<clip>_loop_mirror". */
static int is_idle_loop(const mm_db_clip *c)
{
    if (c->type != MM_CLIP_IDLE || !c->loop) return 0;
    size_t n = strlen(c->name), s = strlen(MM_IDLE_LOOP_SUFFIX), m = strlen("_mirror");
    if (c->mirrored && n > m && strcmp(c->name + n - m, "_mirror") == 0) n -= m;
    return n > s && strncmp(c->name + n - s, MM_IDLE_LOOP_SUFFIX, s) == 0;
}

/* The loop clips the build made of the idle clips (docs/database.md, "Idle that loops"). */
static void print_idle_loops(const mm_db_idle_loop_report *s)
{
    if (!s->make)
        printf("idle loops: none made (idle_loop.make is false)\n");
    else if (s->idle_clips > 0)
        printf(
            "idle loops: %d of %d idle clips made to loop (%.1f s in all, seams within %.1f cm before "
            "their blend); %d without a still stretch of a loop's length, %d without a seam close enough\n",
            s->made, s->idle_clips, s->seconds, 100.0f * s->worst_error, s->no_still, s->no_match);
}

/* What the database lacks (mm/diagnose.h): its height, the gait speeds against the data, the
 * warnings; as text, or as JSON members (json). Returns 0, or 1 after printing an error. */
static int print_diagnosis(const mm_database *db, const mm_db_build_report *report, int json)
{
    mm_diagnosis d;
    mm_result r = mm_database_diagnose(db, report, NULL, &d);
    if (r != MM_OK) {
        fprintf(stderr, "mm: cannot diagnose the database: %s\n", mm_result_str(r));
        return 1;
    }
    static const char *const directions[3] = {"forward", "side", "backward"};
    if (json) {
        printf(", \"height\": %.4g, \"gait_speeds\": [", d.height);
        for (int k = 0; k < MM_DIAGNOSE_SPEEDS; ++k) {
            const mm_speed_coverage *c = &d.speeds[k];
            printf("%s{\"gait\": \"%s\", \"direction\": \"%s\", \"speed\": %.4g, \"source\": \"%s\", "
                   "\"frames\": %d, "
                   "\"p10\": %.4g, \"p50\": %.4g, \"p90\": %.4g, \"near\": %d, \"covered\": %s}",
                   k ? ", " : "", mm_gait_name((mm_gait)c->gait), directions[c->direction], c->speed,
                   c->from_settings ? "settings" : "default", c->frames, c->p10, c->p50, c->p90, c->near,
                   c->covered ? "true" : "false");
        }
        printf("], \"speed_envelope\": {\"bounded\": %s", d.bounded ? "true" : "false");
        for (int g = 0; g < MM_GAIT_COUNT; ++g) {
            printf(", \"%s\": [", mm_gait_name((mm_gait)g));
            for (int k = 0; k < MM_SPEED_ENVELOPE_BINS; ++k)
                printf("%s%.4g", k ? ", " : "", d.envelope[g].speeds[k]);
            printf("]");
        }
        printf("}, \"warnings\": [");
        for (int i = 0; i < d.count; ++i) {
            printf("%s{\"code\": \"%s\", \"message\": ", i ? ", " : "",
                   mm_diagnostic_code_name(d.items[i].code));
            cli_json_string(stdout, d.items[i].message);
            printf("}");
        }
        printf("]");
        return 0;
    }
    printf("height:     %.2f m standing (%s)\n", d.height,
           db->settings && db->settings->roles[MM_ROLE_HEAD] >= 0 ? "the head's height / 0.92"
                                                                  : "the top joint's height / 0.92");
    printf(
        "gait:       the runtime's speeds against the locomotion each gait plays: p10 p50 p90 (frames); the "
        "frames near the speed (/%g to x%g)\n",
        (double)MM_DIAGNOSE_SPEED_BAND, (double)MM_DIAGNOSE_SPEED_BAND);
    for (int k = 0; k < MM_DIAGNOSE_SPEEDS; ++k) {
        const mm_speed_coverage *c = &d.speeds[k];
        printf("  %-4s %-8s %5.2f m/s %-8s", mm_gait_name((mm_gait)c->gait), directions[c->direction],
               c->speed, c->from_settings ? "settings" : "default");
        if (c->frames)
            printf("  data %.2f %.2f %.2f (%d)", c->p10, c->p50, c->p90, c->frames);
        else
            printf("  data    -    -    - (0)");
        printf("  near %d (%.1f s)", c->near, c->near * db->interval);
        if (isfinite(c->envelope)) printf("  envelope %.2f", c->envelope);
        printf("  %s\n", c->covered ? "covered" : "NOT COVERED");
    }
    printf("envelope:   the speed each gait's locomotion covers (m/s) by direction of travel, forward, then "
           "every %.1f degrees toward the left; %s\n",
           360.0 / MM_SPEED_ENVELOPE_BINS,
           d.bounded ? "the runtime bounds the gait speeds by it"
                     : "not applied (runtime.speed_envelope false, or no settings)");
    for (int g = 0; g < MM_GAIT_COUNT; ++g) {
        printf("  %-6s", mm_gait_name((mm_gait)g));
        for (int k = 0; k < MM_SPEED_ENVELOPE_BINS; ++k) printf(" %5.2f", d.envelope[g].speeds[k]);
        printf("\n");
    }
    printf("warnings:   %d%s\n", d.count, d.count ? " (docs/database.md, \"Diagnostics\")" : "");
    for (int i = 0; i < d.count; ++i)
        printf("  %s: %s\n", mm_diagnostic_code_name(d.items[i].code), d.items[i].message);
    return 0;
}

static void progress(int done, int total, void *user)
{
    (void)user;
    if (isatty(2)) fprintf(stderr, "\rmm db build: clip %d/%d", done, total);
    if (isatty(2) && done == total) fputc('\n', stderr);
}

/* The compressed poses of db in a line: their bytes per frame against the file's, the error. */
static void print_poses(const mm_database *db)
{
    double per_frame = (double)mm_database_pose_bytes(db) / db->frame_count;
    if (db->pose_codec == MM_POSE_SEGMENTS)
        printf("poses:      compressed, %.1f bytes per frame (file %.1f), segments of %d frames, world joint "
               "positions within %.3f mm of the floats (bound %.3f mm)\n",
               per_frame, (double)db->size / db->frame_count, db->compressed.segment_frames,
               1000.0 * db->compressed.max_error, 1000.0 * db->compressed.error_bound);
    else
        printf("poses:      floats, %.1f bytes per frame (file %.1f)\n", per_frame,
               (double)db->size / db->frame_count);
}

/* Bounds (mm) and segment lengths the compressing options take. */
#define COMPRESS_ERROR_MAX_MM 100.0

static int cmd_build(int argc, char **argv)
{
    const char *config = NULL, *out = NULL, *data = NULL;
    long threads = cli_default_threads();
    int compress = 0;
    double error_mm = 1000.0 * MM_POSE_ERROR_DEFAULT;
    const cli_option options[] = {
        {.name = "-o", .alias = "--output", .kind = CLI_STRING, .target = &out, .need = "a file name"},
        {.name = "--data", .kind = CLI_STRING, .target = &data, .need = "a folder"},
        {.name = "--threads", .kind = CLI_INT, .target = &threads, .min = 1, .max = MM_DB_MAX_THREADS},
        {.name = "--compress", .kind = CLI_FLAG, .target = &compress},
        {.name = "--compress-error",
         .kind = CLI_DOUBLE,
         .target = &error_mm,
         .min = 0.0,
         .open_min = 1,
         .max = COMPRESS_ERROR_MAX_MM,
         .need = "millimetres"},
    };
    int status = cli_parse_options("db build", argc, argv, options, CLI_COUNT(options), NULL, &config, 1);
    if (status) return status;
    if (!config || !out)
        return cli_usage_error("db build", "usage: mm db build CONFIG -o OUT.mmdb [--data DIR] [--threads N] "
                                           "[--compress [--compress-error MM]]");
    double t0 = cli_now();
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_config cfg;
    memset(&cfg, 0, sizeof cfg);
    char *text = NULL;
    if (mm_config_load_json(config, &cfg, &text, &err) != MM_OK) return cli_report(&err);
    if (data) snprintf(cfg.data_dir, sizeof cfg.data_dir, "%s", data);
    mm_clip *sources = NULL;
    if (mm_config_load_sources(&cfg, &sources, &err) != MM_OK) {
        free(text);
        mm_config_free(&cfg);
        return cli_report(&err);
    }
    double t1 = cli_now();
    mm_db_build_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.config_json = text;
    desc.progress = progress;
    desc.threads = (int)threads;
    mm_db_build_report report;
    desc.report = &report;
    mm_db_compress_desc compress_desc;
    memset(&compress_desc, 0, sizeof compress_desc);
    compress_desc.error_bound = (float)(error_mm / 1000.0);
    if (compress) desc.compress = &compress_desc;
    mm_database db;
    snprintf(err.file, sizeof err.file, "%s", config);
    mm_result r = mm_database_build(&cfg, sources, &desc, &db, &err);
    mm_config_free_sources(&cfg, sources);
    mm_config_free(&cfg);
    free(text);
    if (r != MM_OK) return cli_report(&err);
    double t2 = cli_now();
    r = mm_database_save(&db, out, &err);
    if (r != MM_OK) {
        mm_database_free(&db);
        return cli_report(&err);
    }
    printf("%s: %d frames, %d dims, %d clips, %zu bytes, %.2f s (load %.2f s, build %.2f s)\n", out,
           db.frame_count, db.dims, db.clip_count, db.size, cli_now() - t0, t1 - t0, t2 - t1);
    print_poses(&db);
    print_postures(&report);
    print_standing(&report.standing);
    print_idle_loops(&report.idle_loops);
    status = print_diagnosis(&db, &report, 0);
    mm_database_free(&db);
    return status;
}

static int load(const char *path, mm_database *db)
{
    mm_error err;
    memset(&err, 0, sizeof err);
    if (mm_database_load(path, NULL, db, &err) != MM_OK) return cli_report(&err);
    return 0;
}

/* Distance segments per kind over the database, and the one-shot clips that start from rest (their
 * root's first step is slower than the curve's stop speed: start clips, matched by distance from
 * their first frame). */
typedef struct distance_summary {
    int segments, stops, pivots, none, starts;
} distance_summary;

static void clip_distance_counts(const mm_database *db, int c, distance_summary *s)
{
    mm_distance_curve curve;
    if (mm_database_distance_curve(db, c, &curve) != MM_OK) return;
    s->segments += curve.segment_count;
    for (int g = 0; g < curve.segment_count; ++g) {
        s->stops += curve.segments[g].kind == MM_DISTANCE_STOP;
        s->pivots += curve.segments[g].kind == MM_DISTANCE_PIVOT;
        s->none += curve.segments[g].kind == MM_DISTANCE_NONE;
    }
    float first_speed = (curve.travelled[1] - curve.travelled[0]) * curve.fps;
    s->starts += !curve.loop && first_speed < db->distance_clips[c].stop_speed;
}

static void json_percentiles(const char *name, const mm_speed_percentiles *p)
{
    printf(", \"%s\": {\"frames\": %d, \"p10\": %.4g, \"p50\": %.4g, \"p90\": %.4g}", name, p->frames, p->p10,
           p->p50, p->p90);
}

static void text_percentiles(const char *name, const mm_speed_percentiles *p)
{
    if (p->frames)
        printf("  %s %.2f %.2f %.2f (%d)", name, p->p10, p->p50, p->p90, p->frames);
    else
        printf("  %s    -    -    - (0)", name);
}

/* The runtime settings: the fields set, as "name value" items (runtime fields, then the gaits'),
 * the weights given (per matched bone by joint name) and the roles. json: as JSON objects. */
static void print_settings(const mm_database *db, int json)
{
    const mm_database_settings *s = db->settings;
    const char *names[8] = {
        "pose_trajectory_ratio", "next_pose_favour",    "loop_anim_favour", "continuing_bias",
        "search_interval",       "transition_halflife", "idle_speed",       "sync_halflife"};
    const float values[8] = {
        s->pose_trajectory_ratio, s->next_pose_favour,    s->loop_anim_favour, s->continuing_bias,
        s->search_interval,       s->transition_halflife, s->idle_speed,       s->sync_halflife};
    const mm_runtime_gait *gaits[3] = {&s->walk, &s->run, &s->crouch};
    const char *gait_names[3] = {"walk", "run", "crouch"};
    const char *gait_fields[5] = {"forward_speed", "side_speed", "backward_speed", "velocity_halflife",
                                  "rotation_halflife"};
    const char *roles[MM_ROLE_COUNT] = {"hips",      "left_foot", "right_foot", "left_toe",
                                        "right_toe", "left_hand", "right_hand", "head"};
    const char *bone[MM_MAX_MATCH_BONES] = {NULL}; /* matched bone slot -> joint name */
    for (int g = 0; g < db->group_count; ++g) {
        int slot = mm_database_matched_bone(db, g);
        if (slot >= 0) bone[slot] = db->joints[db->groups[g].bone].name;
    }
    int fields = 0;
    printf(json ? ", \"settings\": {\"runtime\": {" : "settings:   runtime");
    for (int k = 0; k < 8; ++k)
        if (s->set & (1u << k))
            printf(json ? "%s\"%s\": %.9g" : "%s%s %g", fields++ ? (json ? ", " : " ") : " ", names[k],
                   values[k]);
    const unsigned switch_bits[3] = {MM_RUNTIME_DISTANCE_MATCHING, MM_RUNTIME_WARPING,
                                     MM_RUNTIME_SPEED_ENVELOPE};
    const char *switch_names[3] = {"distance_matching", "warping", "speed_envelope"};
    const uint32_t switches[3] = {s->distance_matching, s->warping, s->speed_envelope};
    for (int k = 0; k < 3; ++k)
        if (s->set & switch_bits[k])
            printf(json ? "%s\"%s\": %s" : "%s%s %s", fields++ ? (json ? ", " : " ") : " ", switch_names[k],
                   switches[k] ? "true" : "false");
    if (s->set & MM_RUNTIME_CONTACT_FAVOUR)
        printf(json ? "%s\"%s\": %.9g" : "%s%s %g", fields++ ? (json ? ", " : " ") : " ", "contact_favour",
               (double)s->contact_favour);
    for (int g = 0; g < 3; ++g) {
        const mm_runtime_gait *a = gaits[g];
        const float v[5] = {a->forward_speed, a->side_speed, a->backward_speed, a->velocity_halflife,
                            a->rotation_halflife};
        if (!a->set) continue;
        if (json) printf("%s\"%s\": {", fields++ ? ", " : "", gait_names[g]);
        for (int k = 0, n = 0; k < 5; ++k)
            if (a->set & (1u << k)) {
                if (json)
                    printf("%s\"%s\": %.9g", n++ ? ", " : "", gait_fields[k], v[k]);
                else
                    printf(" %s.%s %g", gait_names[g], gait_fields[k], v[k]), ++fields;
            }
        if (json) printf("}");
    }
    if (!json && !fields) printf(" none set (the defaults)");
    printf(json ? "}, \"weights\": {" : "\n            weights");
    int weights = 0;
    for (int b = 0; b < MM_MAX_MATCH_BONES; ++b) {
        unsigned pos = (s->position_set >> b) & 1u, vel = (s->velocity_set >> b) & 1u;
        if (!pos && !vel) continue;
        if (json) {
            printf("%s", weights++ ? ", " : "");
            cli_json_string(stdout, bone[b] ? bone[b] : "?");
            printf(": {");
            if (pos) printf("\"position\": %.9g", s->joint_position_weights[b]);
            if (vel) printf("%s\"velocity\": %.9g", pos ? ", " : "", s->joint_velocity_weights[b]);
            printf("}");
        } else {
            printf("%s %s", weights++ ? "," : "", bone[b] ? bone[b] : "?");
            if (pos) printf(" position %g", s->joint_position_weights[b]);
            if (vel) printf(" velocity %g", s->joint_velocity_weights[b]);
        }
    }
    const unsigned weight_bits[3] = {MM_SETTINGS_BODY_VELOCITY_WEIGHT, MM_SETTINGS_POSITION_MULTIPLIER,
                                     MM_SETTINGS_ANGLE_MULTIPLIER};
    const char *weight_names[3] = {"body_velocity_weight", "position_multiplier", "angle_multiplier"};
    const float weight_values[3] = {s->body_velocity_weight, s->position_multiplier, s->angle_multiplier};
    for (int k = 0; k < 3; ++k)
        if (s->weight_set & weight_bits[k])
            printf(json ? "%s\"%s\": %.9g" : "%s %s %g", weights++ ? (json ? ", " : ",") : "",
                   weight_names[k], weight_values[k]);
    if (!json && !weights) printf(" none");
    printf(json ? "}, \"roles\": {" : "\n            roles");
    for (int k = 0; k < MM_ROLE_COUNT; ++k) {
        int j = s->roles[k];
        if (json) {
            printf("%s\"%s\": ", k ? ", " : "", roles[k]);
            if (j >= 0)
                cli_json_string(stdout, db->joints[j].name);
            else
                printf("null");
        } else {
            printf(" %s %s", roles[k], j >= 0 ? db->joints[j].name : "-");
        }
    }
    printf(json ? "}}" : "\n");
}

static int cmd_info(int argc, char **argv)
{
    const char *path = NULL;
    int json = 0;
    const cli_option options[] = {{.name = "--json", .kind = CLI_FLAG, .target = &json}};
    int status = cli_parse_options("db info", argc, argv, options, CLI_COUNT(options), NULL, &path, 1);
    if (status) return status;
    if (!path) return cli_usage_error("db info", "usage: mm db info FILE [--json]");
    mm_database db;
    if (load(path, &db)) return 1;
    int idle = 0, loops = 0, mirrored = 0, blends = 0, idle_loops = 0;
    float idle_loop_seconds = 0.0f;
    distance_summary dist = {0, 0, 0, 0, 0};
    mm_speed_summary speeds[MM_SPEED_SUMMARY_MAX];
    int speed_count = 0;
    if (mm_database_speed_summary(&db, NULL, speeds, &speed_count) != MM_OK) {
        fprintf(stderr, "mm: db info: out of memory\n");
        mm_database_free(&db);
        return 1;
    }
    for (int c = 0; c < db.clip_count; ++c) {
        clip_distance_counts(&db, c, &dist);
        idle += db.clips[c].type == MM_CLIP_IDLE;
        loops += db.clips[c].loop != 0;
        mirrored += db.clips[c].mirrored != 0;
        blends += db.clips[c].blend_left >= 0;
        if (is_idle_loop(&db.clips[c]) && !db.clips[c].mirrored) {
            ++idle_loops;
            idle_loop_seconds += (float)db.clips[c].frame_count * db.interval;
        }
    }
    if (json) {
        printf("{\"file\": ");
        cli_json_string(stdout, path);
        printf(", \"version\": %d, \"frames\": %d, \"dims\": %d, \"dims_padded\": %d, \"clips\": %d, "
               "\"joints\": %d, "
               "\"interval\": %.9g, \"duration\": %.9g, \"bytes\": %zu, ",
               MM_DB_VERSION, db.frame_count, db.dims, db.dims_padded, db.clip_count, db.joint_count,
               db.interval, db.frame_count * db.interval, db.size);
        printf("\"poses\": {\"codec\": \"%s\", \"segment_frames\": %d, \"error_bound_mm\": %.9g}, "
               "\"pose_bytes_per_frame\": %.9g, \"bytes_per_frame\": %.9g, \"max_joint_error_mm\": %.9g, ",
               db.pose_codec == MM_POSE_SEGMENTS ? "segments" : "floats", db.compressed.segment_frames,
               1000.0 * db.compressed.error_bound, (double)mm_database_pose_bytes(&db) / db.frame_count,
               (double)db.size / db.frame_count, 1000.0 * db.compressed.max_error);
        printf("\"clip_names\": [");
        for (int c = 0; c < db.clip_count; ++c) {
            if (c) printf(", ");
            cli_json_string(stdout, db.clips[c].name);
        }
        printf("], \"tags\": [");
        for (int t = 0; t < db.tag_count; ++t) {
            if (t) printf(", ");
            cli_json_string(stdout, db.tag_names[t]);
        }
        printf("], \"features\": [");
        for (int g = 0; g < db.group_count; ++g) {
            printf("%s{\"name\": ", g ? ", " : "");
            cli_json_string(stdout, db.groups[g].name);
            printf(", \"kind\": \"%s\", \"offset\": %d, \"dims\": %d, \"weight\": %.9g, \"scale\": %.9g}",
                   mm_feature_kind_name((mm_feature_kind)db.groups[g].kind), db.groups[g].offset,
                   db.groups[g].dims, db.groups[g].weight, db.groups[g].scale);
        }
        printf("], \"idle_clips\": %d, \"loop_clips\": %d, \"idle_loop_clips\": %d, \"mirrored_clips\": %d, "
               "\"blend_clips\": %d, "
               "\"distance\": {\"segments\": %d, \"stops\": %d, \"pivots\": %d, \"no_stop\": %d, "
               "\"starts\": %d}, \"speeds\": [",
               idle, loops, idle_loops, mirrored, blends, dist.segments, dist.stops, dist.pivots, dist.none,
               dist.starts);
        for (int k = 0; k < speed_count; ++k) {
            printf("%s{\"name\": ", k ? ", " : "");
            cli_json_string(stdout, speeds[k].name);
            printf(", \"frames\": %d, \"still\": %d", speeds[k].frames, speeds[k].still);
            json_percentiles("forward", &speeds[k].forward);
            json_percentiles("side", &speeds[k].side);
            json_percentiles("backward", &speeds[k].backward);
            printf("}");
        }
        printf("]");
        print_settings(&db, 1);
        status = print_diagnosis(&db, NULL, 1);
        printf("}\n");
    } else {
        printf("file:       %s (%zu bytes, format version %d)\n", path, db.size, MM_DB_VERSION);
        printf("frames:     %d (%.1f s at %.6g s per frame)\n", db.frame_count, db.frame_count * db.interval,
               db.interval);
        printf("joints:     %d (joint 0: %s)\n", db.joint_count, db.joints[0].name);
        printf("clips:      %d (%d idle, %d loop, %d mirrored, %d blend)\n", db.clip_count, idle, loops,
               mirrored, blends);
        if (idle_loops)
            printf("idle loops: %d made by the build of its idle clips' still stretches (%.1f s; mirrors "
                   "aside): "
                   "the clips named *%s\n",
                   idle_loops, idle_loop_seconds, MM_IDLE_LOOP_SUFFIX);
        print_poses(&db);
        printf("features:   %d dims (%d padded)\n", db.dims, db.dims_padded);
        for (int g = 0; g < db.group_count; ++g)
            printf("  %-34s %-21s dims %d..%d  weight %-6g scale %.4g\n", db.groups[g].name,
                   mm_feature_kind_name((mm_feature_kind)db.groups[g].kind), db.groups[g].offset,
                   db.groups[g].offset + db.groups[g].dims - 1, db.groups[g].weight, db.groups[g].scale);
        printf("distance:   %d segments (%d stops, %d pivots, %d without a stop), %d clips start from rest\n",
               dist.segments, dist.stops, dist.pivots, dist.none, dist.starts);
        print_settings(&db, 0);
        printf("speeds:     root m/s in its facing frame, p10 p50 p90 (frames); still: under %g m/s\n",
               (double)MM_SPEED_SUMMARY_STILL);
        for (int k = 0; k < speed_count; ++k) {
            printf("  %-12s %6d frames %6d still", speeds[k].name, speeds[k].frames, speeds[k].still);
            text_percentiles("forward", &speeds[k].forward);
            text_percentiles("side", &speeds[k].side);
            text_percentiles("backward", &speeds[k].backward);
            printf("\n");
        }
        printf("tags:      ");
        for (int t = 0; t < db.tag_count; ++t) printf(" %s", db.tag_names[t]);
        printf("%s\n", db.tag_count ? "" : " none");
        for (int c = 0; c < db.clip_count; ++c) {
            const mm_db_clip *k = &db.clips[c];
            distance_summary one = {0, 0, 0, 0, 0};
            clip_distance_counts(&db, c, &one);
            printf("  clip %3d %-32s frames %6d..%-6d %-10s path %7.2f m", c, k->name, k->first_frame,
                   k->first_frame + k->frame_count - 1, k->type == MM_CLIP_IDLE ? "idle" : "locomotion",
                   db.distance_clips[c].path_length);
            if (one.stops) printf(" %d stop%s", one.stops, one.stops == 1 ? "" : "s");
            if (one.pivots) printf(" %d pivot%s", one.pivots, one.pivots == 1 ? "" : "s");
            printf("%s%s%s\n", one.starts ? " start" : "", k->loop ? " loop" : "",
                   k->blend_left >= 0 ? " blend" : "");
        }
        status = print_diagnosis(&db, NULL, 0);
    }
    mm_database_free(&db);
    return status;
}

static int cmd_dump(int argc, char **argv)
{
    if (argc != 2 || argv[1][0] == '-') return cli_usage_error("db dump", "usage: mm db dump FILE");
    mm_database db;
    if (load(argv[1], &db)) return 1;
    mm_result r = mm_database_dump(&db, stdout);
    mm_database_free(&db);
    if (r != MM_OK) {
        fprintf(stderr, "mm: cannot write the dump: %s\n", mm_result_str(r));
        return 1;
    }
    return 0;
}

static int parse_method(const char *command, const cli_option *option, const char *value)
{
    mm_search_method *method = (mm_search_method *)option->target;
    if (strcmp(value, "brute") == 0)
        *method = MM_SEARCH_BRUTE;
    else if (strcmp(value, "fast") == 0)
        *method = MM_SEARCH_FAST;
    else if (strcmp(value, "facing") == 0)
        *method = MM_SEARCH_FACING;
    else
        return cli_usage_error(command, "--method needs brute, fast or facing, not '%s'", value);
    return 0;
}

static int parse_type(const char *command, const cli_option *option, const char *value)
{
    if (strcmp(value, "idle") && strcmp(value, "locomotion") && strcmp(value, "any"))
        return cli_usage_error(command, "--type needs idle, locomotion or any");
    *(const char **)option->target = value;
    return 0;
}

/* The tags of --require or --exclude, each option given once per tag. */
typedef struct tag_list {
    const char *tags[64];
    int count;
} tag_list;

static int parse_tag(const char *command, const cli_option *option, const char *value)
{
    tag_list *list = (tag_list *)option->target;
    if (list->count == 64) return cli_usage_error(command, "%s: at most 64 tags", option->name);
    list->tags[list->count++] = value;
    return 0;
}

static int cmd_search(int argc, char **argv)
{
    const char *path = NULL;
    long frame = -1, traj = -1, top = 1;
    int json = 0, no_bias = 0;
    mm_search_method method = MM_SEARCH_FAST;
    const char *type = NULL;
    tag_list require = {{NULL}, 0}, exclude = {{NULL}, 0};
    const char *usage =
        "usage: mm db search DB.mmdb --frame I [--traj-from J] [--method brute|fast|facing] [--top K] "
        "[--type idle|locomotion|any] [--require TAG]... [--exclude TAG]... [--no-bias] [--json]";
    const char *frame_number = "a frame number >= 0";
    const cli_option options[] = {
        {.name = "--frame", .kind = CLI_INT, .target = &frame, .max = 0x7fffffff, .need = frame_number},
        {.name = "--traj-from", .kind = CLI_INT, .target = &traj, .max = 0x7fffffff, .need = frame_number},
        {.name = "--top", .kind = CLI_INT, .target = &top, .min = 1, .max = 1000},
        {.name = "--method",
         .kind = CLI_CUSTOM,
         .target = &method,
         .need = "brute, fast or facing",
         .parse = parse_method},
        {.name = "--type",
         .kind = CLI_CUSTOM,
         .target = &type,
         .need = "idle, locomotion or any",
         .parse = parse_type},
        {.name = "--require",
         .kind = CLI_CUSTOM,
         .target = &require,
         .need = "a tag name",
         .parse = parse_tag},
        {.name = "--exclude",
         .kind = CLI_CUSTOM,
         .target = &exclude,
         .need = "a tag name",
         .parse = parse_tag},
        {.name = "--no-bias", .kind = CLI_FLAG, .target = &no_bias},
        {.name = "--json", .kind = CLI_FLAG, .target = &json},
    };
    int status = cli_parse_options("db search", argc, argv, options, CLI_COUNT(options), NULL, &path, 1);
    if (status) return status;
    if (!path || frame < 0) return cli_usage_error("db search", "%s", usage);
    mm_database db;
    if (load(path, &db)) return 1;
    mm_searcher s;
    mm_search_result *results = NULL;
    mm_error err;
    memset(&err, 0, sizeof err);
    if (frame >= db.frame_count || traj >= db.frame_count) {
        fprintf(stderr, "mm: %s: frame %ld is out of range (the database has %d frames, 0 to %d)\n", path,
                frame >= db.frame_count ? frame : traj, db.frame_count, db.frame_count - 1);
        mm_database_free(&db);
        return 1;
    }
    mm_search_params p;
    mm_search_params_defaults(&db, &p);
    p.current_frame = (int)frame;
    const mm_db_clip *current = &db.clips[db.frame_clip[frame]];
    p.type = !type ? (current->type == MM_CLIP_IDLE ? MM_SEARCH_IDLE : MM_SEARCH_LOCOMOTION)
             : strcmp(type, "idle") == 0       ? MM_SEARCH_IDLE
             : strcmp(type, "locomotion") == 0 ? MM_SEARCH_LOCOMOTION
                                               : MM_SEARCH_ANY;
    for (int i = 0; i < require.count + exclude.count; ++i) {
        const char *tag = i < require.count ? require.tags[i] : exclude.tags[i - require.count];
        uint64_t mask = mm_search_tag_mask(&db, tag);
        if (!mask) {
            fprintf(stderr, "mm: %s: the database has no tag '%s'\n", path, tag);
            mm_database_free(&db);
            return 1;
        }
        if (i < require.count)
            p.required_tags |= mask;
        else
            p.excluded_tags |= mask;
    }
    if (no_bias) {
        p.next_pose_favour = p.loop_anim_favour = 1.0f;
        p.continuing_bias = 0.0f;
    }
    float query[MM_SEARCH_MAX_DIMS];
    if (mm_searcher_init(&s, &db, NULL, &err) != MM_OK) {
        snprintf(err.file, sizeof err.file, "%s", path);
        mm_database_free(&db);
        return cli_report(&err);
    }
    mm_search_query_from_frames(&db, (int)frame, traj >= 0 ? (int)traj : (int)frame, query);
    results = malloc(sizeof(mm_search_result) * (size_t)top);
    int found = results ? mm_searcher_search(&s, query, &p, method, results, (int)top) : 0;
    if (json)
        printf("{\"query\": {\"frame\": %ld, \"traj_from\": %ld, \"method\": \"%s\"}, \"results\": [", frame,
               traj >= 0 ? traj : frame, mm_search_method_name(method));
    else
        printf("query: pose of frame %ld, trajectory of frame %ld, method %s, %d result%s\n", frame,
               traj >= 0 ? traj : frame, mm_search_method_name(method), found, found == 1 ? "" : "s");
    for (int i = 0; i < found; ++i) {
        const mm_search_result *r = &results[i];
        const mm_db_clip *c = &db.clips[db.frame_clip[r->frame]];
        double t = c->source_start + (r->frame - c->first_frame) * db.interval;
        mm_search_terms terms;
        mm_search_cost_terms(&db, query, &p, r->frame, &terms);
        if (json) {
            printf("%s{\"frame\": %d, \"clip\": ", i ? ", " : "", r->frame);
            cli_json_string(stdout, c->name);
            printf(", \"clip_index\": %d, \"time\": %.9g, \"base\": %.9g, \"cost\": %.9g, \"terms\": "
                   "{\"pose_position\": "
                   "%.9g, \"pose_velocity\": %.9g, \"root_velocity\": %.9g, \"traj_position\": %.9g, "
                   "\"traj_direction\": %.9g}}",
                   db.frame_clip[r->frame], t, r->base, r->cost, terms.pose_position, terms.pose_velocity,
                   terms.root_velocity, terms.traj_position, terms.traj_direction);
        } else {
            printf("%2d. frame %-7d %-28s t %7.3f s  cost %-10.5g base %-10.5g (pose %.4g + %.4g, root %.4g, "
                   "trajectory %.4g + %.4g)\n",
                   i + 1, r->frame, c->name, t, r->cost, r->base, terms.pose_position, terms.pose_velocity,
                   terms.root_velocity, terms.traj_position, terms.traj_direction);
        }
    }
    if (json)
        printf("]}\n");
    else if (found == 0)
        printf("no frame passes the filters\n");
    free(results);
    mm_searcher_free(&s);
    mm_database_free(&db);
    return status;
}

static int cmd_compress(int argc, char **argv)
{
    const char *in = NULL, *out = NULL;
    long threads = cli_default_threads(), segment = MM_POSE_SEGMENT_FRAMES_DEFAULT;
    double error_mm = 1000.0 * MM_POSE_ERROR_DEFAULT;
    const cli_option options[] = {
        {.name = "-o", .alias = "--output", .kind = CLI_STRING, .target = &out, .need = "a file name"},
        {.name = "--error",
         .kind = CLI_DOUBLE,
         .target = &error_mm,
         .min = 0.0,
         .open_min = 1,
         .max = COMPRESS_ERROR_MAX_MM,
         .need = "millimetres"},
        {.name = "--segment-frames",
         .kind = CLI_INT,
         .target = &segment,
         .min = 1,
         .max = MM_POSE_SEGMENT_FRAMES_MAX},
        {.name = "--threads", .kind = CLI_INT, .target = &threads, .min = 1, .max = MM_DB_MAX_THREADS},
    };
    int status = cli_parse_options("db compress", argc, argv, options, CLI_COUNT(options), NULL, &in, 1);
    if (status) return status;
    if (!in || !out)
        return cli_usage_error("db compress", "usage: mm db compress DB.mmdb -o OUT.mmdb [--error MM] "
                                              "[--segment-frames N] [--threads N]");
    mm_database db, small;
    if (load(in, &db)) return 1;
    mm_db_compress_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.error_bound = (float)(error_mm / 1000.0);
    desc.segment_frames = (int)segment;
    desc.threads = (int)threads;
    mm_error err;
    memset(&err, 0, sizeof err);
    snprintf(err.file, sizeof err.file, "%s", in);
    double t0 = cli_now();
    mm_result r = mm_database_compress(&db, &desc, &small, &err);
    mm_database_free(&db);
    if (r != MM_OK) return cli_report(&err);
    double t1 = cli_now();
    r = mm_database_save(&small, out, &err);
    if (r == MM_OK) {
        printf("%s: %d frames, %zu bytes, %.2f s\n", out, small.frame_count, small.size, t1 - t0);
        print_poses(&small);
    }
    mm_database_free(&small);
    return r == MM_OK ? 0 : cli_report(&err);
}

int mm_cmd_db(int argc, char **argv)
{
    if (argc < 2) return cli_usage_error("db", "usage: mm db build|info|dump|search|compress ...");
    if (strcmp(argv[1], "build") == 0) return cmd_build(argc - 1, argv + 1);
    if (strcmp(argv[1], "info") == 0) return cmd_info(argc - 1, argv + 1);
    if (strcmp(argv[1], "dump") == 0) return cmd_dump(argc - 1, argv + 1);
    if (strcmp(argv[1], "search") == 0) return cmd_search(argc - 1, argv + 1);
    if (strcmp(argv[1], "compress") == 0) return cmd_compress(argc - 1, argv + 1);
    return cli_usage_error("db", "unknown subcommand '%s' (build, info, dump, search, compress)", argv[1]);
}
