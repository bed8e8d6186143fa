/* mm config explain | check | init */
#define _POSIX_C_SOURCE 200809L
#define _XOPEN_SOURCE   700 /* realpath */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <mm/config_init.h>
#include <mm/config_json.h>
#include <mm/import.h>

#include "cli.h"
#include "commands.h"

static void explain_text(const mm_config_field_doc *d)
{
    printf("%s  (%s%s%s; default %s)\n", d->path, d->type, d->unit[0] ? ", " : "", d->unit,
           d->fallback[0] ? d->fallback : "none");
    printf("    %s\n\n", d->help);
}

static int cmd_explain(int argc, char **argv)
{
    const char *field = NULL;
    int markdown = 0;
    for (int i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--markdown") == 0)
            markdown = 1;
        else if (!field)
            field = argv[i];
        else
            return cli_usage_error("config explain", "usage: mm config explain [FIELD] [--markdown]");
    }
    int n = 0;
    const mm_config_field_doc *docs = mm_config_field_docs(&n);
    if (markdown) {
        printf("| field | type | unit | default | meaning |\n|---|---|---|---|---|\n");
        for (int i = 0; i < n; ++i)
            printf("| `%s` | %s | %s | %s | %s |\n", docs[i].path, docs[i].type, docs[i].unit,
                   docs[i].fallback, docs[i].help);
        return 0;
    }
    int shown = 0;
    for (int i = 0; i < n; ++i)
        if (!field || strncmp(docs[i].path, field, strlen(field)) == 0) {
            explain_text(&docs[i]);
            ++shown;
        }
    if (!shown) {
        fprintf(stderr, "mm: no config field named '%s' (mm config explain lists them all)\n", field);
        return 1;
    }
    return 0;
}

static int cmd_check(int argc, char **argv)
{
    if (argc != 2) return cli_usage_error("config check", "usage: mm config check CONFIG");
    mm_config cfg;
    memset(&cfg, 0, sizeof cfg);
    mm_error err;
    memset(&err, 0, sizeof err);
    if (mm_config_load_json(argv[1], &cfg, NULL, &err) != MM_OK) return cli_report(&err);
    int missing = 0;
    for (int i = 0; i < cfg.clip_count; ++i) {
        char path[MM_PATH_MAX];
        mm_error e;
        memset(&e, 0, sizeof e);
        if (mm_config_resolve_path(&cfg, cfg.clips[i].file, path, sizeof path, &e) != MM_OK) {
            snprintf(e.file, sizeof e.file, "%s", argv[1]);
            cli_report(&e);
            ++missing;
        }
    }
    printf("%s: %d clips, %d blend clips, %d tags, %d matched bones, %d trajectory samples%s\n", argv[1],
           cfg.clip_count, cfg.blend_count, cfg.tag_count, cfg.bone_count, cfg.traj_count,
           missing ? "; some files are missing" : "");
    int forward = mm_axes_forward(cfg.axes_up, cfg.axes_forward);
    if (cfg.axes_up != MM_AXIS_POS_Y || forward != MM_AXIS_POS_Z)
        printf("%s: the takes are %s up, %s forward: the build turns them to +Y up, +Z forward\n", argv[1],
               mm_axis_name(cfg.axes_up), mm_axis_name(forward));
    mm_config_free(&cfg);
    return missing ? 1 : 0;
}

/* ---- init ------------------------------------------------------------------------------- */

/* The canonical path of an existing file or folder (malloc'd), or NULL. */
static char *canonical(const char *path) { return path && path[0] ? realpath(path, NULL) : NULL; }

/* dir + "/" starts path: the rest of path, else NULL. */
static const char *inside(const char *path, const char *dir)
{
    size_t n = dir ? strlen(dir) : 0;
    while (n > 1 && dir[n - 1] == '/') --n;
    if (n == 0 || strncmp(path, dir, n) != 0) return NULL;
    if (n == 1 && dir[0] == '/') return path + 1;
    return path[n] == '/' ? path + n + 1 : NULL;
}

/* How the config at config_dir names the take at path: relative to the config's folder when the
 * take is inside it, else to $MM_DATA_DIR when inside that, else absolute. */
static void config_file_name(const char *path, const char *config_dir, char *out, size_t size)
{
    char *abs = canonical(path), *cfg = canonical(config_dir), *data = canonical(getenv("MM_DATA_DIR"));
    const char *rel = abs ? inside(abs, cfg) : NULL;
    if (!rel && abs) rel = inside(abs, data);
    snprintf(out, size, "%s", rel ? rel : abs ? abs : path);
    free(abs);
    free(cfg);
    free(data);
}

static const char *unit_of(double scale)
{
    static const struct {
        double scale;
        const char *name;
    } units[] = {{1.0, "metres"},    {0.01, "centimetres"}, {0.001, "millimetres"},
                 {0.0254, "inches"}, {0.3048, "feet"},      {0.056444, "CMU units"}};
    for (size_t i = 0; i < sizeof units / sizeof units[0]; ++i)
        if (fabs(scale - units[i].scale) < 1e-9) return units[i].name;
    return "given";
}

static void evidence_text(const mm_role_match *m, const mm_skeleton *s, char *out, size_t size)
{
    const char *other = m->other >= 0 ? s->joints[m->other].name : NULL;
    unsigned both = MM_EVIDENCE_NAME | MM_EVIDENCE_GEOMETRY;
    if (m->joint < 0)
        snprintf(out, size, "not found");
    else if ((m->evidence & both) == both && !m->conflict)
        snprintf(out, size, "name and geometry");
    else if ((m->evidence & both) == both && other)
        snprintf(out, size, "name, on the limb geometry found (its pick: %s)", other);
    else if ((m->evidence & both) == both)
        snprintf(out, size, "name and geometry, but geometry puts it on the other side (names kept)");
    else if ((m->evidence & MM_EVIDENCE_GEOMETRY) && other)
        snprintf(out, size, "geometry (a name points at %s)", other);
    else if (m->evidence & MM_EVIDENCE_GEOMETRY)
        snprintf(out, size, "geometry%s", m->conflict ? ", names disagree on the side" : "");
    else
        snprintf(out, size, "name only");
}

static void speed_text(const mm_gait_speed_estimate *e, char *out, size_t size)
{
    if (e->seconds > 0.0f)
        snprintf(out, size, "%.2f (q%.2g of %.1f s)", (double)e->speed, (double)e->quantile,
                 (double)e->seconds);
    else
        snprintf(out, size, "%.2f (the takes do not move this way: %s)", (double)e->speed,
                 e->speed <= MM_GAIT_SPEED_MIN ? "a creep" : "the walk's");
}

static void print_report(const mm_config_init_report *rep, const mm_config *cfg, const mm_skeleton *s,
                         int takes)
{
    const mm_skeleton_roles *r = &rep->roles;
    if (rep->fps_max > rep->fps_min)
        printf("takes:        %d, %.1f s at %.4g to %.4g fps, %d joints\n", takes, (double)rep->seconds,
               (double)rep->fps_min, (double)rep->fps_max, s->joint_count);
    else
        printf("takes:        %d, %.1f s at %.4g fps, %d joints\n", takes, (double)rep->seconds,
               (double)rep->fps_min, s->joint_count);
    if (rep->up_given)
        printf("up axis:      %s (given; the poses say %s, confidence %.2f)\n", mm_axis_name(rep->up_axis),
               rep->up_detected ? "so" : "nothing clear", (double)rep->up_confidence);
    else if (rep->up_detected)
        printf("up axis:      %s (confidence %.2f: the body's longest extent)\n", mm_axis_name(rep->up_axis),
               (double)rep->up_confidence);
    else
        printf("up axis:      %s (assumed: the poses do not tell, confidence %.2f; give --up)\n",
               mm_axis_name(rep->up_axis), (double)rep->up_confidence);
    printf("forward axis: %s (%s)\n", mm_axis_name(rep->forward_axis),
           rep->forward_given ? "given"
           : rep->up_axis % 3 == 2
               ? "the convention for a body standing along Z, not detected: only the "
                 "world's turn about up depends on it; --forward sets it"
               : "the convention, not detected: only the world's turn about up depends on "
                 "it; --forward sets it");
    if (rep->up_axis != MM_AXIS_POS_Y || rep->forward_axis != MM_AXIS_POS_Z)
        printf("              the build turns the takes to +Y up, +Z forward (the config's axes)\n");
    printf("unit:         %s (scale %.6g; the body is %.2f m tall)\n", unit_of(rep->scale), rep->scale,
           (double)rep->height);
    printf("roles:        (confidence: 1 name and geometry agree, 0.9 a name on the limb geometry found,\n"
           "              0.8 geometry alone, 0.6 a name alone, lower when they disagree)\n");
    char text[256];
    int w = 18; /* the names' column */
    for (int i = 0; i < MM_BODY_ROLE_COUNT; ++i)
        if (r->roles[i].joint >= 0 && (int)strlen(s->joints[r->roles[i].joint].name) > w)
            w = (int)strlen(s->joints[r->roles[i].joint].name);
    for (int i = 0; i < MM_BODY_ROLE_COUNT; ++i) {
        const mm_role_match *m = &r->roles[i];
        const char *name = m->joint >= 0 ? s->joints[m->joint].name : "-";
        if (m->joint < 0 && (i == MM_BODY_LEFT_TOE || i == MM_BODY_RIGHT_TOE)) {
            printf("  %-13s %-*s  --   no toe joint: the toe contact is the ankle's\n",
                   mm_body_role_name((mm_body_role)i), w,
                   i == MM_BODY_LEFT_TOE ? cfg->left_toe : cfg->right_toe);
            continue;
        }
        evidence_text(m, s, text, sizeof text);
        printf("  %-13s %-*s %.2f  %s\n", mm_body_role_name((mm_body_role)i), w, name, (double)m->confidence,
               text);
    }
    char axis[64];
    snprintf(axis, sizeof axis, "[%g, %g, %g]", (double)r->forward_axis.x, (double)r->forward_axis.y,
             (double)r->forward_axis.z);
    printf("  %-13s %-*s %.2f  ", "forward_axis", w, axis, (double)r->forward_confidence);
    if (r->forward_toes_degrees >= 0.0f) printf("toes %.0f deg off", (double)r->forward_toes_degrees);
    if (r->forward_toes_degrees >= 0.0f && r->forward_travel_degrees >= 0.0f) printf(", ");
    if (r->forward_travel_degrees >= 0.0f)
        printf("travel %.0f deg off (%.1f s)", (double)r->forward_travel_degrees, (double)r->travel_seconds);
    if (r->forward_toes_degrees < 0.0f && r->forward_travel_degrees < 0.0f)
        printf("no toes, no travel: +Z assumed");
    printf("\n");
    printf(
        "sides:        from %s; the left limbs on the +X side (facing +Z) in %.0f%% of the sampled poses\n",
        r->sides_from_names ? "the names" : "geometry", 100.0 * (double)r->side_agreement);
    if (r->mirror) {
        printf("mirror:       yes (%s: ", r->naming);
        for (int i = 0; i < r->mirror_pair_count; ++i)
            printf("%s[\"%s\", \"%s\"]", i ? ", " : "", r->mirror_pairs[i].left, r->mirror_pairs[i].right);
        printf("), %d joints paired, confidence %.2f\n", r->paired_joints, (double)r->mirror_confidence);
    } else if (r->mirror_pair_count > 0) {
        printf("mirror:       no (%s pairs %d joints but leaves %d named as a side without a partner)\n",
               r->naming, r->paired_joints, r->unpaired_joints);
    } else {
        printf("mirror:       no (the names show no left and right convention)\n");
    }
    printf("spans:        locomotion %.1f s, idle %.1f s, left out %.1f s (the poses that are not motion,\n"
           "              1 s around each)\n",
           (double)rep->locomotion_seconds, (double)rep->idle_seconds, (double)rep->excluded_seconds);
    static const int left_out[] = {MM_POSTURE_CALIBRATION, MM_SPAN_A_POSE, MM_POSTURE_LYING,
                                   MM_SPAN_GETTING_UP, MM_SPAN_DOWN};
    static const char *const left_out_names[] = {"T pose", "A pose", "lying", "lying down or getting up",
                                                 "kneeling or sitting"};
    printf("  left out:   ");
    for (int k = 0; k < 5; ++k)
        printf("%s %s %.1f s", k ? "," : "", left_out_names[k], (double)rep->kind_seconds[left_out[k]]);
    printf("\n              from each frame's pose (mm/take_spans.h); %d of %d takes open with a calibration "
           "pose%s\n",
           rep->calibration_starts, takes,
           rep->arms_missing ? "; A poses not looked for on some takes (no elbows and shoulders found)" : "");
    if (rep->moving_seconds > 0.0f) {
        static const char *const gait[2] = {"walk", "run"}, *const dir[3] = {"forward", "side", "backward"};
        printf("gait speeds:  m/s, from %.1f s of windows (%.2g s, shorter in short spans) of the locomotion "
               "the walk and run play\n",
               (double)rep->moving_seconds, (double)MM_GAIT_WINDOW);
        for (int g = 0; g < 2; ++g)
            for (int d = 0; d < 3; ++d) {
                speed_text(&rep->speeds[g][d], text, sizeof text);
                printf("  %-4s %-9s %s\n", d == 0 ? gait[g] : "", dir[d], text);
            }
    } else {
        printf("gait speeds:  the takes never move: the runtime's defaults\n");
    }
    int mirrored = 0, idle = 0;
    for (int i = 0; i < cfg->clip_count; ++i) {
        mirrored += cfg->clips[i].mirror;
        idle += cfg->clips[i].type == MM_CLIP_IDLE;
    }
    printf("clips:        %d locomotion, %d idle%s\n", cfg->clip_count - idle, idle,
           mirrored ? ", each mirrored" : ", not mirrored");
}

static int cmd_init(int argc, char **argv)
{
    static const char *const usage =
        "usage: mm config init TAKE... [-o CONFIG.json] [--force] [--name-prefix P] [--scale S|auto] "
        "[--no-tuning] [--up AXIS] [--forward AXIS]";
    static const char default_prefix[] = "";
    const char *out = NULL, *prefix = default_prefix;
    int force = 0, no_tuning = 0;
    double scale = 0.0;
    const char *up = NULL, *forward = NULL;
    const cli_option options[] = {
        {"-o", "--output", CLI_STRING, &out, 0, 0, 0, "a config path", NULL},
        {"--name-prefix", NULL, CLI_STRING, &prefix, 0, 0, 0, "a prefix for the clip names", NULL},
        {"--force", NULL, CLI_FLAG, &force, 0, 0, 0, NULL, NULL},
        {"--no-tuning", NULL, CLI_FLAG, &no_tuning, 0, 0, 0, NULL, NULL},
        {"--scale", NULL, CLI_CUSTOM, &scale, 0, 0, 0, NULL, cli_parse_scale},
        {"--up", NULL, CLI_STRING, &up, 0, 0, 0, "an axis (+X, +Y, +Z, -X, -Y, -Z)", NULL},
        {"--forward", NULL, CLI_STRING, &forward, 0, 0, 0, "an axis (+X, +Y, +Z, -X, -Y, -Z)", NULL},
    };
    const char **files = (const char **)calloc((size_t)argc + 1, sizeof(char *));
    if (!files) {
        fprintf(stderr, "mm: out of memory\n");
        return 1;
    }
    int status = cli_parse_options("config init", argc, argv, options, CLI_COUNT(options), NULL, files, argc);
    int file_count = 0;
    while (file_count < argc && files[file_count]) ++file_count;
    if (status) {
        free(files);
        return status;
    }
    if (file_count == 0) {
        free(files);
        return cli_usage_error("config init", "%s", usage);
    }
    const char *const axis_names[2] = {up, forward}, *const axis_options[2] = {"--up", "--forward"};
    for (int k = 0; k < 2; ++k)
        if (axis_names[k] && mm_axis_parse(axis_names[k]) < 0) {
            free(files);
            return cli_usage_error("config init", "%s '%s': not an axis (+X, +Y, +Z, -X, -Y, -Z)",
                                   axis_options[k], axis_names[k]);
        }
    if (up && forward && mm_axis_parse(up) % 3 == mm_axis_parse(forward) % 3) {
        free(files);
        return cli_usage_error("config init", "--forward %s lies along --up %s: it must be at right angles",
                               forward, up);
    }
    if (strlen(prefix) > 24) {
        free(files);
        return cli_usage_error("config init", "--name-prefix: at most 24 characters");
    }
    if ((out && !out[0]) || (prefix != default_prefix && !prefix[0])) {
        free(files);
        return cli_usage_error("config init", "%s needs a non-empty value",
                               out && !out[0] ? "-o" : "--name-prefix");
    }
    struct stat st;
    if (out && !force && stat(out, &st) == 0) {
        fprintf(stderr, "mm: %s: exists; give --force to replace it\n", out);
        free(files);
        return 1;
    }
    char config_dir[MM_PATH_MAX] = ".";
    if (out && strrchr(out, '/'))
        snprintf(config_dir, sizeof config_dir, "%.*s", (int)(strrchr(out, '/') - out), out);
    if (!config_dir[0]) snprintf(config_dir, sizeof config_dir, "/");
    mm_clip_list *lists = (mm_clip_list *)calloc((size_t)file_count, sizeof(mm_clip_list));
    int take_count = 0, loaded = 0;
    mm_error err;
    memset(&err, 0, sizeof err);
    for (int i = 0; lists && i < file_count; ++i, ++loaded) {
        mm_import_desc desc;
        memset(&desc, 0, sizeof desc);
        if (mm_import_clips(files[i], &desc, &lists[i], &err) != MM_OK) {
            status = cli_report(&err);
            break;
        }
        take_count += lists[i].count;
    }
    mm_config_init_take *takes =
        (mm_config_init_take *)calloc((size_t)take_count + 1, sizeof(mm_config_init_take));
    char(*names)[2][MM_PATH_MAX] = (char(*)[2][MM_PATH_MAX])calloc((size_t)take_count + 1, sizeof *names);
    if (!lists || !takes || !names) {
        fprintf(stderr, "mm: out of memory\n");
        status = 1;
    }
    for (int i = 0, t = 0; status == 0 && i < file_count; ++i)
        for (int k = 0; k < lists[i].count; ++k, ++t) {
            char stem[512];
            cli_file_stem(files[i], stem, sizeof stem);
            config_file_name(files[i], config_dir, names[t][0], MM_PATH_MAX);
            if (lists[i].count > 1)
                snprintf(names[t][1], MM_PATH_MAX, "%s%.40s_%.40s", prefix, stem, lists[i].names[k]);
            else
                snprintf(names[t][1], MM_PATH_MAX, "%s%.40s", prefix, stem);
            takes[t].file = names[t][0];
            takes[t].path = files[i];
            takes[t].take = lists[i].count > 1 ? lists[i].names[k] : NULL;
            takes[t].name = names[t][1];
            takes[t].clip = &lists[i].clips[k];
        }
    mm_config cfg;
    memset(&cfg, 0, sizeof cfg);
    mm_config_init_report rep;
    if (status == 0) {
        mm_config_init_desc desc;
        memset(&desc, 0, sizeof desc);
        desc.scale = scale;
        desc.no_tuning = no_tuning != 0;
        desc.up_given = up != NULL;
        desc.up_axis = up ? mm_axis_parse(up) : 0;
        desc.forward_given = forward != NULL;
        desc.forward_axis = forward ? mm_axis_parse(forward) : 0;
        memset(&err, 0, sizeof err);
        mm_result r = mm_config_init(takes, take_count, &desc, &cfg, &rep, &err);
        if (r != MM_OK) {
            if (!err.file[0] && file_count == 1)
                snprintf(err.file, sizeof err.file, "%s", files[0]);
            else if (!err.file[0])
                snprintf(err.file, sizeof err.file, "%.200s and %d more", files[0], file_count - 1);
            status = cli_report(&err);
        } else {
            print_report(&rep, &cfg, &takes[0].clip->skeleton, take_count);
            printf("tuning:       %s\n",
                   no_tuning ? "the runtime's defaults (--no-tuning)"
                             : "measured on motion capture (contacts.speed 0.3, sync_halflife "
                               "0.1, distance matching and warping on; --no-tuning: none)");
            if (!out) {
                printf("nothing written (give -o CONFIG.json)\n");
            } else if (mm_config_save_json(out, &cfg, &err) != MM_OK) {
                status = cli_report(&err);
            } else {
                printf("wrote %s (mm db build %s -o DB.mmdb builds it)\n", out, out);
            }
            mm_config_free(&cfg);
        }
    }
    for (int i = 0; lists && i < loaded; ++i) mm_clip_list_free(&lists[i]);
    free(lists);
    free(takes);
    free(names);
    free(files);
    return status;
}

int mm_cmd_config(int argc, char **argv)
{
    if (argc < 2)
        return cli_usage_error("config",
                               "usage: mm config explain [FIELD] | check CONFIG | init TAKE... -o CONFIG");
    if (strcmp(argv[1], "explain") == 0) return cmd_explain(argc - 1, argv + 1);
    if (strcmp(argv[1], "check") == 0) return cmd_check(argc - 1, argv + 1);
    if (strcmp(argv[1], "init") == 0) return cmd_init(argc - 1, argv + 1);
    return cli_usage_error("config", "unknown subcommand '%s' (explain, check, init)", argv[1]);
}
