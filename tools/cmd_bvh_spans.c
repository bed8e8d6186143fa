/* mm bvh spans FILE [--config CONFIG] [--scale S|auto] [--up AXIS] [--hips NAME] [--root-bone NAME]
 *                   [--head NAME] [--pad 1] [--idle-speed 0.15] [--idle-min 1] [--low-hips H]
 *                   [--write CONFIG.json [--as NAME] [--no-mirror]]
 * The frame spans of a take for a database config, on any skeleton (mm/take_spans.h, as mm config
 * init splits takes): the roles from mm_skeleton_roles_find (or named), the take turned to +Y up
 * (the config's axes, else the up the poses show), each frame's posture against the take's own
 * upright head height; calibration (T and A poses), lying, getting-up and down spans (widened by
 * --pad) left out; in the rest, idle where the root stands, locomotion elsewhere. Prints JSON, or
 * writes the locomotion and idle spans into a config as two clips (docs/database.md, "Spans of a
 * take"). */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <mm/config_init.h>
#include <mm/config_json.h>
#include <mm/mm.h>
#include <mm/skeleton_roles.h>
#include <mm/take_spans.h>

#include "cli.h"
#include "commands.h"

#define ROLE_COUNT  5
#define ROLE_HIPS   0
#define ROLE_ROOT   1
#define ROLE_HEAD   2
#define ROLE_L_HAND 3
#define ROLE_R_HAND 4
static const char *const role_names[ROLE_COUNT] = {"hips", "root_bone", "head", "left_hand", "right_hand"};

static void list_joints(const mm_skeleton *s)
{
    fprintf(stderr, "    its joints:");
    for (int j = 0; j < s->joint_count; ++j) fprintf(stderr, "%s %s", j ? "," : "", s->joints[j].name);
    fputc('\n', stderr);
}

/* Resolves the roles: a name given (an option, else the config's) must be a joint; the others are
 * found by mm_skeleton_roles_find (clip in metres, +Y up). Returns 0, or 1 after printing. */
static int find_roles(const mm_clip *clip, const char *path, const char *const given[ROLE_COUNT],
                      const char *const from_config[ROLE_COUNT], const char *config, int roles[ROLE_COUNT])
{
    const mm_skeleton *s = &clip->skeleton;
    int missing = 0;
    for (int k = 0; k < ROLE_COUNT; ++k) {
        const char *name = given[k] ? given[k] : from_config[k];
        roles[k] = -1;
        if (!name) {
            ++missing;
            continue;
        }
        roles[k] = mm_skeleton_find(s, name);
        if (roles[k] >= 0) continue;
        int hand = k == ROLE_L_HAND || k == ROLE_R_HAND;
        if (hand && !given[k]) { /* as the database build: no hands, no calibration poses */
            fprintf(stderr, "mm: %s: no joint '%s' (roles.%s of %s): calibration poses are not looked for\n",
                    path, name, role_names[k], config);
            continue;
        }
        if (given[k])
            fprintf(stderr, "mm: %s: no joint named '%s' (--%s)\n", path, name,
                    k == ROLE_ROOT ? "root-bone" : role_names[k]);
        else
            fprintf(stderr, "mm: %s: no joint named '%s' (roles.%s of %s)\n", path, name, role_names[k],
                    config);
        list_joints(s);
        return 1;
    }
    if (!missing) return 0;
    mm_skeleton_roles found;
    mm_error err;
    memset(&err, 0, sizeof err);
    if (mm_skeleton_roles_find(clip, 1, &found, &err) != MM_OK) {
        /* without the finder the take can still be judged when the needed joints are named */
        if (roles[ROLE_HIPS] >= 0 && roles[ROLE_HEAD] >= 0) {
            if (roles[ROLE_ROOT] < 0) roles[ROLE_ROOT] = roles[ROLE_HIPS];
            return 0;
        }
        fprintf(stderr,
                "mm: %s: the roles cannot be found: %s; name the hips and the head (--hips NAME --head NAME, "
                "or a config's roles: --config)\n",
                path, err.message);
        list_joints(s);
        return 1;
    }
    const mm_body_role body[ROLE_COUNT] = {MM_BODY_HIPS, MM_BODY_ROOT_BONE, MM_BODY_HEAD, MM_BODY_LEFT_HAND,
                                           MM_BODY_RIGHT_HAND};
    for (int k = 0; k < ROLE_COUNT; ++k)
        if (roles[k] < 0 && !given[k] && !from_config[k]) roles[k] = found.roles[body[k]].joint;
    return 0;
}

static void print_spans(const char *indent, const char *key, const int (*spans)[2], int n, int last)
{
    printf("%s\"%s\": [", indent, key);
    for (int i = 0; i < n; ++i) printf("%s[%d, %d]", i ? ", " : "", spans[i][0], spans[i][1]);
    printf("]%s\n", last ? "" : ",");
}

/* The spans [b, e) of at least min_len frames where in[f] is set. */
static int spans_of(const unsigned char *in, int n, int min_len, int (*spans)[2])
{
    int count = 0;
    for (int f = 0; f < n;) {
        int e = f;
        while (e < n && (in[e] != 0) == (in[f] != 0)) ++e;
        if (in[f] && e - f >= min_len) {
            spans[count][0] = f;
            spans[count][1] = e;
            ++count;
        }
        f = e;
    }
    return count;
}

/* --write: the spans of one kind as a clip of the config (NAME, or NAME_idle for the idle ones). */
static int write_spans(const char *config, const char *path, const char *as, int idle, int mirror,
                       const int (*spans)[2], int count)
{
    char stem[1024], name[sizeof stem + 8], file[1024];
    if (as)
        snprintf(stem, sizeof stem, "%s", as);
    else
        cli_file_stem(path, stem, sizeof stem);
    if (strlen(stem) + 5 >= MM_NAME_MAX) /* room for "_idle" */
        return cli_usage_error("bvh spans", "clip name '%s' (--as): at most %d characters", stem,
                               MM_NAME_MAX - 6);
    snprintf(name, sizeof name, "%s%s", stem, idle ? "_idle" : "");
    cli_config_file_name(path, file, sizeof file);
    mm_config_saved_clip c;
    memset(&c, 0, sizeof c);
    c.name = name;
    c.file = file;
    c.ranges = spans;
    c.range_count = count;
    c.type = idle ? MM_CLIP_IDLE : MM_CLIP_LOCOMOTION;
    c.mirror = mirror != 0;
    mm_error err;
    memset(&err, 0, sizeof err);
    if (mm_config_save_clip(config, &c, &err) != MM_OK) return cli_report(&err);
    printf("%s: clip %s, %d spans\n", config, name, count);
    return 0;
}

int mm_cmd_bvh_spans(int argc, char **argv)
{
    const char *path = NULL, *config = NULL, *write = NULL, *as = NULL, *up_name = NULL;
    const char *given[ROLE_COUNT] = {NULL}, *from_config[ROLE_COUNT] = {NULL};
    int no_mirror = 0;
    /* scale and low -1: not given */
    double scale = -1.0, low = -1.0, pad = 1.0, idle_speed = 0.15, idle_min = 1.0;
    const char *number = "a number >= 0";
    const cli_option options[] = {
        {.name = "--config", .kind = CLI_STRING, .target = &config, .need = "a config path"},
        {.name = "--scale", .kind = CLI_CUSTOM, .target = &scale, .parse = cli_parse_scale},
        {.name = "--up", .kind = CLI_STRING, .target = &up_name, .need = "an axis (+X, +Y, +Z, -X, -Y, -Z)"},
        {.name = "--hips", .kind = CLI_STRING, .target = &given[ROLE_HIPS], .need = "a joint name"},
        {.name = "--root-bone", .kind = CLI_STRING, .target = &given[ROLE_ROOT], .need = "a joint name"},
        {.name = "--head", .kind = CLI_STRING, .target = &given[ROLE_HEAD], .need = "a joint name"},
        {.name = "--pad", .kind = CLI_DOUBLE, .target = &pad, .max = FLT_MAX, .need = number},
        {.name = "--idle-speed", .kind = CLI_DOUBLE, .target = &idle_speed, .max = FLT_MAX, .need = number},
        {.name = "--idle-min", .kind = CLI_DOUBLE, .target = &idle_min, .max = FLT_MAX, .need = number},
        {.name = "--low-hips", .kind = CLI_DOUBLE, .target = &low, .max = FLT_MAX, .need = number},
        {.name = "--write", .kind = CLI_STRING, .target = &write, .need = "a config path"},
        {.name = "--as", .kind = CLI_STRING, .target = &as, .need = "a name"},
        {.name = "--no-mirror", .kind = CLI_FLAG, .target = &no_mirror},
    };
    int status = cli_parse_options("bvh spans", argc, argv, options, CLI_COUNT(options), NULL, &path, 1);
    if (status) return status;
    if (!path)
        return cli_usage_error("bvh spans",
                               "usage: mm bvh spans FILE [--config CONFIG.json] [--scale S|auto] [--up AXIS] "
                               "[--hips NAME] [--root-bone NAME] [--head NAME] [--pad 1] "
                               "[--idle-speed 0.15] [--idle-min 1] [--low-hips H] "
                               "[--write CONFIG.json [--as NAME] [--no-mirror]] (mm bvh spans "
                               "--help: the options)");
    if (up_name && mm_axis_parse(up_name) < 0)
        return cli_usage_error("bvh spans", "--up '%s': not an axis (+X, +Y, +Z, -X, -Y, -Z)", up_name);
    if (low >= 0)
        fprintf(stderr, "mm bvh spans: --low-hips is deprecated: lying and getting up are found from the "
                        "pose (docs/database.md, \"Spans of a take\")\n");
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_config cfg;
    memset(&cfg, 0, sizeof cfg);
    mm_config_defaults(&cfg);
    if (config) {
        if (mm_config_load_json(config, &cfg, NULL, &err) != MM_OK) return cli_report(&err);
        const char *names[ROLE_COUNT] = {cfg.hips, cfg.root_bone, cfg.head, cfg.left_hand, cfg.right_hand};
        for (int k = 0; k < ROLE_COUNT; ++k) from_config[k] = names[k][0] ? names[k] : NULL;
        if (scale < 0) scale = cfg.scale;
    }
    /* the axes: --up, else the config's, else the up the poses show; the unit is detected after the
     * turn (the height is measured along +Y) */
    mm_clip clip;
    if (cli_load_clip(path, scale > 0.0 ? scale : 1.0, &clip)) {
        mm_config_free(&cfg);
        return 1;
    }
    int up = cfg.axes_up, forward = cfg.axes_forward;
    float up_confidence = 0.0f;
    if (up_name) {
        up = mm_axis_parse(up_name);
        forward = -1;
    } else if (!config) {
        int detected = mm_clip_up_axis(&clip, &up_confidence);
        if (up_confidence >= MM_UP_MIN_CONFIDENCE) up = detected;
    }
    if (up != MM_AXIS_POS_Y || mm_axes_forward(up, forward) != MM_AXIS_POS_Z)
        mm_clip_turn(&clip, mm_axes_turn(up, forward));
    if (!(scale > 0.0)) {
        const mm_quat *rot = clip.frame_count > 0 ? mm_clip_rotations(&clip, 0) : NULL;
        const mm_vec3 *pos = clip.frame_count > 0 ? mm_clip_positions(&clip, 0) : NULL;
        double height = mm_skeleton_estimate_height(&clip.skeleton, rot, pos),
               unit = mm_unit_scale_for_height(height);
        if (unit == 0.0) {
            fprintf(
                stderr,
                "mm: %s: cannot detect the unit: the character is %g units tall along %s, which is no human "
                "height; give --scale (or --up)\n",
                path, height, mm_axis_name(up));
            mm_clip_free(&clip);
            mm_config_free(&cfg);
            return 1;
        }
        mm_clip_scale(&clip, (float)unit);
    }
    int roles[ROLE_COUNT];
    status = find_roles(&clip, path, given, from_config, config, roles);
    int n = clip.frame_count;
    mm_take_spans spans;
    memset(&spans, 0, sizeof spans);
    unsigned char *in = calloc((size_t)n + 1, 1);
    int(*list)[2] = malloc(sizeof(int[2]) * ((size_t)n + 1));
    if (!status && (!in || !list)) {
        fprintf(stderr, "mm: out of memory\n");
        status = 1;
    }
    if (!status) {
        mm_take_spans_desc desc;
        mm_take_spans_desc_defaults(&desc);
        desc.pad = (float)pad;
        desc.idle_speed = (float)idle_speed;
        desc.idle_min = (float)idle_min;
        desc.low_hips = low > 0.0 ? (float)low : 0.0f;
        const mm_take_joints joints = {roles[ROLE_HIPS], roles[ROLE_ROOT], roles[ROLE_HEAD],
                                       roles[ROLE_L_HAND], roles[ROLE_R_HAND]};
        if (mm_take_spans_find(&clip, &joints, &desc, &spans) != MM_OK) {
            fprintf(stderr, "mm: out of memory\n");
            status = 1;
        }
    }
    if (!status && !write) {
        printf("{\n  \"file\": ");
        cli_json_string(stdout, path);
        printf(",\n  \"frames\": %d,\n  \"fps\": %.6g,\n  \"up\": \"%s\",\n  \"roles\": {", n, clip.fps,
               mm_axis_name(up));
        for (int k = 0; k < ROLE_COUNT; ++k) {
            printf("%s\"%s\": ", k ? ", " : "", role_names[k]);
            if (roles[k] >= 0)
                cli_json_string(stdout, clip.skeleton.joints[roles[k]].name);
            else
                printf("null");
        }
        printf("},\n  \"upright_head_height\": %.4f,\n  \"postures\": {\n", spans.upright_head_height);
        static const int order[] = {MM_POSTURE_CALIBRATION, MM_SPAN_A_POSE,  MM_POSTURE_LYING,
                                    MM_SPAN_GETTING_UP,     MM_SPAN_DOWN,    MM_POSTURE_ARMS_SPREAD,
                                    MM_POSTURE_HAND_RAISED, MM_POSTURE_BENT, MM_POSTURE_CROUCHED};
        const int kinds = (int)(sizeof order / sizeof order[0]);
        for (int k = 0; k < kinds; ++k) {
            for (int f = 0; f < n; ++f) in[f] = spans.kinds[f] == order[k];
            print_spans("    ", mm_span_kind_name(order[k]), (const int(*)[2])list, spans_of(in, n, 1, list),
                        k == kinds - 1);
        }
        printf("  },\n");
    }
    /* the excluded spans (printed only), the locomotion clip, then the idle one */
    static const int write_order[3] = {0, 2, 1};
    for (int step = 0; step < 3 && !status; ++step) {
        int which = write ? write_order[step] : step;
        const mm_config_range *ranges = which == 0   ? spans.excluded
                                        : which == 1 ? spans.idle
                                                     : spans.locomotion;
        int count = which == 0   ? spans.excluded_count
                    : which == 1 ? spans.idle_count
                                 : spans.locomotion_count;
        for (int i = 0; i < count; ++i) {
            list[i][0] = ranges[i].begin;
            list[i][1] = ranges[i].end;
        }
        if (!write)
            print_spans("  ",
                        which == 0   ? "excluded"
                        : which == 1 ? "idle"
                                     : "locomotion",
                        (const int(*)[2])list, count, which == 2);
        else if (which > 0 && count > 0)
            status = write_spans(write, path, as, which == 1, !no_mirror, (const int(*)[2])list, count);
    }
    if (!status && !write) printf("}\n");
    free(in);
    free(list);
    mm_take_spans_free(&spans);
    mm_clip_free(&clip);
    mm_config_free(&cfg);
    return status;
}
