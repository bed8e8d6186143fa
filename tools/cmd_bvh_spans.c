/* mm bvh spans FILE [--config CONFIG] [--scale S|auto] [--hips NAME] [--root-bone NAME] [--head NAME]
 *                   [--pad 1] [--idle-speed 0.15] [--idle-min 1] [--low-hips H]
 *                   [--write CONFIG.json [--as NAME] [--no-mirror]]
 * The frame spans of a take for a database config, on any skeleton: each frame's posture
 * (mm/posture.h) against the take's own upright head height; calibration, lying, getting-up and
 * down spans (widened by --pad) left out; in the rest, idle where the root stands, locomotion
 * elsewhere. Prints JSON, or writes the locomotion and idle spans into a config as two clips
 * (docs/database.md, "Spans of a take"). */
#include <ctype.h>
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <mm/config_json.h>
#include <mm/mm.h>
#include <mm/posture.h>

#include "cli.h"
#include "commands.h"

/* The kinds of span a frame is in: the postures, the way into or out of lying, and going down to
 * the ground. */
#define GETTING_UP MM_POSTURE_COUNT
#define DOWN       (MM_POSTURE_COUNT + 1)
#define KIND_COUNT (MM_POSTURE_COUNT + 2)
/* A crouched or bent stretch whose hips come lower than this x their upright height goes down to
 * the ground (kneeling, squatting, sitting, picking something up): not a way of walking. */
#define DOWN_HIPS 0.65f
/* Lying down, getting up and going down to the ground and back take at most this long (s): the
 * crouched or bent frames farther from a lying frame or from the hips' lowest are another motion. */
#define TRANSITION_SECONDS 2.0f
#define ROLE_COUNT         5
#define ROLE_HIPS          0
#define ROLE_ROOT          1
#define ROLE_HEAD          2
#define ROLE_L_HAND        3
#define ROLE_R_HAND        4
static const char *const role_names[ROLE_COUNT] = {"hips", "root_bone", "head", "left_hand", "right_hand"};

static int lower(int c) { return tolower((unsigned char)c); }
static int is_letter(int c) { return isalpha((unsigned char)c); }

/* name is word in any case, or ends with it after a character that is not a letter
 * (mixamorig:Hips, Bip01_Pelvis, torso_head). */
static int name_is(const char *name, const char *word)
{
    size_t n = strlen(name), w = strlen(word);
    if (n < w) return 0;
    for (size_t i = 0; i < w; ++i)
        if (lower(name[n - w + i]) != lower(word[i])) return 0;
    return n == w || !is_letter(name[n - w - 1]);
}

/* name holds word in any case. */
static int name_has(const char *name, const char *word)
{
    size_t n = strlen(name), w = strlen(word);
    for (size_t s = 0; s + w <= n; ++s) {
        size_t i = 0;
        while (i < w && lower(name[s + i]) == lower(word[i])) ++i;
        if (i == w) return 1;
    }
    return 0;
}

/* The side a name gives: 'l', 'r' or 0. Left, L_/l_ or lX (lWrist) at the start, _L/.l/ L at
 * the end. */
static int side_of(const char *name)
{
    if (name_has(name, "left")) return 'l';
    if (name_has(name, "right")) return 'r';
    size_t n = strlen(name);
    int first = lower(name[0]);
    if ((first == 'l' || first == 'r') && n > 1 && (!is_letter(name[1]) || isupper((unsigned char)name[1])))
        return first;
    int last = n > 1 ? lower(name[n - 1]) : 0;
    if ((last == 'l' || last == 'r') && !is_letter(name[n - 2])) return last;
    return 0;
}

/* The first joint (parents before children) named one of words (NULL-terminated), in order of
 * the words; -1 when none. */
static int find_named(const mm_skeleton *s, const char *const *words)
{
    for (; *words; ++words)
        for (int j = 0; j < s->joint_count; ++j)
            if (name_is(s->joints[j].name, *words)) return j;
    return -1;
}

/* The hand of a side: the first joint holding "hand", else "wrist", of that side. */
static int find_hand(const mm_skeleton *s, int side)
{
    const char *words[2] = {"hand", "wrist"};
    for (int w = 0; w < 2; ++w)
        for (int j = 0; j < s->joint_count; ++j)
            if (name_has(s->joints[j].name, words[w]) && side_of(s->joints[j].name) == side) return j;
    return -1;
}

/* The hips by convention: a joint named Hips, Hip or Pelvis; else the root when it has two
 * children or more (legs and spine), else the root's first child. */
static int find_hips(const mm_skeleton *s)
{
    static const char *const names[] = {"Hips", "Hip", "Pelvis", NULL};
    int j = find_named(s, names);
    if (j >= 0 || s->joint_count < 2) return j >= 0 ? j : 0;
    int children = 0, first = -1;
    for (int k = 1; k < s->joint_count; ++k)
        if (s->joints[k].parent == 0) {
            if (first < 0) first = k;
            ++children;
        }
    return children >= 2 || first < 0 ? 0 : first;
}

static void list_joints(const mm_skeleton *s)
{
    fprintf(stderr, "    its joints:");
    for (int j = 0; j < s->joint_count; ++j) fprintf(stderr, "%s %s", j ? "," : "", s->joints[j].name);
    fputc('\n', stderr);
}

/* Resolves the roles: a name given (an option, else the config's) must be a joint; without one the
 * conventions decide. Returns 0, or 1 after printing. */
static int find_roles(const mm_skeleton *s, const char *path, const char *const given[ROLE_COUNT],
                      const char *const from_config[ROLE_COUNT], const char *config, int roles[ROLE_COUNT])
{
    static const char *const heads[] = {"Head", NULL};
    for (int k = 0; k < ROLE_COUNT; ++k) {
        const char *name = given[k] ? given[k] : from_config[k];
        if (name) {
            roles[k] = mm_skeleton_find(s, name);
            if (roles[k] >= 0) continue;
            int hand = k == ROLE_L_HAND || k == ROLE_R_HAND;
            if (hand && !given[k]) { /* as the database build: no hands, no calibration poses */
                fprintf(stderr,
                        "mm: %s: no joint '%s' (roles.%s of %s): calibration poses are not looked for\n",
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
        roles[k] = k == ROLE_HIPS   ? find_hips(s)
                   : k == ROLE_ROOT ? -1 /* the hips, below */
                   : k == ROLE_HEAD ? find_named(s, heads)
                                    : find_hand(s, k == ROLE_L_HAND ? 'l' : 'r');
        if (k == ROLE_HEAD && roles[k] < 0) {
            fprintf(stderr,
                    "mm: %s: no joint named Head (or ending in _head): name the head with --head NAME or a "
                    "config's roles.head (--config)\n",
                    path);
            list_joints(s);
            return 1;
        }
    }
    if (roles[ROLE_ROOT] < 0) roles[ROLE_ROOT] = roles[ROLE_HIPS];
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

static int compare_floats(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

/* A frame of posture k is part of a stretch of being low: crouched, bent or lying. */
static int low(int k) { return k == MM_POSTURE_CROUCHED || k == MM_POSTURE_BENT || k == MM_POSTURE_LYING; }

/* Each frame's kind of span from the world positions w [n x jc] (n >= 1): its posture, judged against
 * the take's upright head height (mm_posture_reference_height of the head's heights above the
 * ground: the median over frames of the lowest joint's height, as the database build takes them),
 * short runs merged (mm_posture_remove_flicker); then, in each stretch of low frames (crouched, bent,
 * lying), the crouched and bent frames within TRANSITION_SECONDS of a lying frame are GETTING_UP
 * (lying down, getting up), and those within TRANSITION_SECONDS of a frame with the hips below
 * DOWN_HIPS x their upright height (their heights' same quantile) DOWN. Returns the reference; -1
 * when out of memory. */
static float judge(const mm_vec3 *w, int n, int jc, float fps, const int roles[ROLE_COUNT],
                   unsigned char *kind)
{
    float *v = malloc(sizeof(float) * (size_t)n);
    if (!v) return -1.0f;
    for (int f = 0; f < n; ++f) {
        v[f] = INFINITY;
        for (int j = 0; j < jc; ++j) v[f] = fminf(v[f], w[(size_t)f * (size_t)jc + (size_t)j].y);
    }
    qsort(v, (size_t)n, sizeof(float), compare_floats);
    float ground = v[(n - 1) / 2];
    const mm_vec3 *head = w + roles[ROLE_HEAD], *hips = w + roles[ROLE_HIPS];
    for (int f = 0; f < n; ++f) v[f] = hips[(size_t)f * (size_t)jc].y - ground;
    float upright_hips = mm_posture_reference_height(v, n);
    for (int f = 0; f < n; ++f) v[f] = head[(size_t)f * (size_t)jc].y - ground;
    mm_posture_reference ref = {mm_posture_reference_height(v, n)};
    free(v);
    mm_posture_joints joints = {roles[ROLE_HIPS], roles[ROLE_HEAD], roles[ROLE_L_HAND], roles[ROLE_R_HAND]};
    for (int f = 0; f < n; ++f)
        kind[f] = (unsigned char)mm_posture_classify(w + (size_t)f * (size_t)jc, &joints, ground, &ref);
    mm_posture_remove_flicker(kind, n, (int)lroundf(MM_POSTURE_MIN_SECONDS * fps));
    /* the frames of a low stretch within TRANSITION_SECONDS of a lying frame of it, or of a frame
     * of it with the hips down: two passes give each frame its distance to the nearest */
    int *to_lying = malloc(sizeof(int) * (size_t)n), *to_down = malloc(sizeof(int) * (size_t)n);
    if (!to_lying || !to_down) {
        free(to_lying);
        free(to_down);
        return -1.0f;
    }
    for (int pass = 0; pass < 2; ++pass)
        for (int i = 0, last_lying = -1, last_down = -1; i < n; ++i) {
            int f = pass ? n - 1 - i : i;
            if (!low(kind[f])) {
                last_lying = last_down = -1;
                if (!pass) to_lying[f] = to_down[f] = INT_MAX;
                continue;
            }
            if (kind[f] == MM_POSTURE_LYING) last_lying = f;
            if (hips[(size_t)f * (size_t)jc].y - ground < DOWN_HIPS * upright_hips) last_down = f;
            int dl = last_lying >= 0 ? abs(f - last_lying) : INT_MAX,
                dd = last_down >= 0 ? abs(f - last_down) : INT_MAX;
            to_lying[f] = pass && to_lying[f] < dl ? to_lying[f] : dl;
            to_down[f] = pass && to_down[f] < dd ? to_down[f] : dd;
        }
    int reach = (int)lroundf(TRANSITION_SECONDS * fps);
    for (int f = 0; f < n; ++f)
        if (low(kind[f]) && kind[f] != MM_POSTURE_LYING && (to_lying[f] <= reach || to_down[f] <= reach))
            kind[f] = to_lying[f] <= reach ? GETTING_UP : DOWN;
    free(to_lying);
    free(to_down);
    return ref.head_height;
}

/* The name of a kind of span in the JSON. */
static const char *kind_name(int k)
{
    return k == GETTING_UP ? "getting_up" : k == DOWN ? "down" : mm_posture_name((mm_posture)k);
}

/* Left out of the idle and locomotion spans. */
static int left_out(int k)
{
    return k == MM_POSTURE_CALIBRATION || k == MM_POSTURE_LYING || k == GETTING_UP || k == DOWN;
}

int mm_cmd_bvh_spans(int argc, char **argv)
{
    const char *path = NULL, *config = NULL, *write = NULL, *as = NULL;
    const char *given[ROLE_COUNT] = {NULL}, *from_config[ROLE_COUNT] = {NULL};
    int no_mirror = 0;
    /* scale and low -1: not given */
    double scale = -1.0, low = -1.0, pad = 1.0, idle_speed = 0.15, idle_min = 1.0;
    const char *number = "a number >= 0";
    const cli_option options[] = {
        {.name = "--config", .kind = CLI_STRING, .target = &config, .need = "a config path"},
        {.name = "--scale", .kind = CLI_CUSTOM, .target = &scale, .parse = cli_parse_scale},
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
                               "usage: mm bvh spans FILE [--config CONFIG.json] [--scale S|auto] "
                               "[--hips NAME] [--root-bone NAME] [--head NAME] [--pad 1] "
                               "[--idle-speed 0.15] [--idle-min 1] [--low-hips H] "
                               "[--write CONFIG.json [--as NAME] [--no-mirror]] (mm bvh spans "
                               "--help: the options)");
    if (low >= 0)
        fprintf(stderr, "mm bvh spans: --low-hips is deprecated: lying and getting up are found from the "
                        "pose (docs/database.md, \"Spans of a take\")\n");
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_config cfg;
    memset(&cfg, 0, sizeof cfg);
    if (config) {
        if (mm_config_load_json(config, &cfg, NULL, &err) != MM_OK) return cli_report(&err);
        const char *names[ROLE_COUNT] = {cfg.hips, cfg.root_bone, cfg.head, cfg.left_hand, cfg.right_hand};
        for (int k = 0; k < ROLE_COUNT; ++k) from_config[k] = names[k][0] ? names[k] : NULL;
        if (scale < 0) scale = cfg.scale;
    }
    mm_clip clip;
    if (cli_load_clip(path, scale, &clip)) {
        mm_config_free(&cfg);
        return 1;
    }
    int roles[ROLE_COUNT];
    status = find_roles(&clip.skeleton, path, given, from_config, config, roles);
    int n = clip.frame_count, jc = clip.skeleton.joint_count;
    mm_xform *g = malloc(sizeof(mm_xform) * (size_t)jc);
    mm_vec3 *w = malloc(sizeof(mm_vec3) * ((size_t)n + 1) * (size_t)jc);
    unsigned char *kind = calloc((size_t)n + 1, 1), *excluded = calloc((size_t)n + 1, 1),
                  *idle = calloc((size_t)n + 1, 1), *in = calloc((size_t)n + 1, 1);
    int(*spans)[2] = malloc(sizeof(int[2]) * ((size_t)n + 1));
    float reference = 0.0f;
    if (!status && (!g || !w || !kind || !excluded || !idle || !in || !spans)) {
        fprintf(stderr, "mm: out of memory\n");
        status = 1;
    }
    if (!status) {
        for (int f = 0; f < n; ++f) {
            mm_clip_fk(&clip, f, g);
            for (int j = 0; j < jc; ++j) w[(size_t)f * (size_t)jc + (size_t)j] = g[j].translation;
        }
        reference = n > 0 ? judge(w, n, jc, clip.fps, roles, kind) : 0.0f;
        if (reference < 0) {
            fprintf(stderr, "mm: out of memory\n");
            status = 1;
        }
    }
    if (!status) {
        /* excluded: calibration, lying and getting up (and, deprecated, the hips below --low-hips),
         * widened by pad seconds on each side (pad and idle_min may be huge: clamped to the take) */
        for (int f = 0; f < n; ++f)
            in[f] = left_out(kind[f]) ||
                    (low >= 0 && w[(size_t)f * (size_t)jc + (size_t)roles[ROLE_HIPS]].y < low);
        int widen = (int)lround(fmin(pad * clip.fps, (double)n));
        for (int f = 0, last = -1; f < n; ++f) {
            if (in[f]) last = f;
            if (last >= 0 && f - last <= widen) excluded[f] = 1;
        }
        for (int f = n - 1, next = -1; f >= 0; --f) {
            if (in[f]) next = f;
            if (next >= 0 && next - f <= widen) excluded[f] = 1;
        }
        /* idle: root speed (central differences over +-0.1 s) below idle_speed for idle_min seconds */
        int h = (int)lround(0.1 * clip.fps) > 0 ? (int)lround(0.1 * clip.fps) : 1,
            min_len = (int)lround(fmin(idle_min * clip.fps, (double)n + 1.0));
        const mm_vec3 *root = w + roles[ROLE_ROOT];
        for (int f = 0; f < n;) {
            int e = f;
            while (e < n && !excluded[e]) {
                int a = e - h < 0 ? 0 : e - h, b = e + h >= n ? n - 1 : e + h;
                const mm_vec3 pa = root[(size_t)a * (size_t)jc], pb = root[(size_t)b * (size_t)jc];
                double speed = b > a ? hypot(pb.x - pa.x, pb.z - pa.z) * clip.fps / (b - a) : 0;
                if (speed >= idle_speed) break;
                ++e;
            }
            if (e - f >= min_len)
                for (int k = f; k < e; ++k) idle[k] = 1;
            f = e > f ? e : f + 1;
        }
    }
    if (!status && !write) {
        printf("{\n  \"file\": ");
        cli_json_string(stdout, path);
        printf(",\n  \"frames\": %d,\n  \"fps\": %.6g,\n  \"roles\": {", n, clip.fps);
        for (int k = 0; k < ROLE_COUNT; ++k) {
            printf("%s\"%s\": ", k ? ", " : "", role_names[k]);
            if (roles[k] >= 0)
                cli_json_string(stdout, clip.skeleton.joints[roles[k]].name);
            else
                printf("null");
        }
        printf("},\n  \"upright_head_height\": %.4f,\n  \"postures\": {\n", reference);
        static const int order[KIND_COUNT - 1] = {
            MM_POSTURE_CALIBRATION, MM_POSTURE_LYING, GETTING_UP,         DOWN,
            MM_POSTURE_ARMS_SPREAD, MM_POSTURE_BENT,  MM_POSTURE_CROUCHED};
        for (int k = 0; k < KIND_COUNT - 1; ++k) {
            for (int f = 0; f < n; ++f) in[f] = kind[f] == order[k];
            print_spans("    ", kind_name(order[k]), (const int(*)[2])spans, spans_of(in, n, 1, spans),
                        k == KIND_COUNT - 2);
        }
        printf("  },\n");
    }
    /* the excluded spans (printed only), the locomotion clip, then the idle one */
    static const int write_order[3] = {0, 2, 1};
    for (int step = 0; step < 3 && !status; ++step) {
        int which = write ? write_order[step] : step;
        for (int f = 0; f < n; ++f)
            in[f] = which == 0   ? excluded[f]
                    : which == 1 ? (!excluded[f] && idle[f])
                                 : (!excluded[f] && !idle[f]);
        int count = spans_of(in, n, 2, spans);
        if (!write)
            print_spans("  ",
                        which == 0   ? "excluded"
                        : which == 1 ? "idle"
                                     : "locomotion",
                        (const int(*)[2])spans, count, which == 2);
        else if (which > 0 && count > 0)
            status = write_spans(write, path, as, which == 1, !no_mirror, (const int(*)[2])spans, count);
    }
    if (!status && !write) printf("}\n");
    free(g);
    free(w);
    free(kind);
    free(excluded);
    free(idle);
    free(in);
    free(spans);
    mm_clip_free(&clip);
    mm_config_free(&cfg);
    return status;
}
