/* mm synth OUTDIR [--seed N] [--fps F]
 *
 * Writes the built-in procedural motion set: one BVH file per clip (metres, ZYX, root Hips with 6
 * channels) and OUTDIR/clips.json describing every clip (see docs/synth.md).
 */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>

#include <mm/mm.h>
#include <mm/synth.h>

#include "cli.h"
#include "commands.h"

#define SYNTH_USAGE "usage: mm synth OUTDIR [--seed N] [--fps F]"

static int parse_seed(const char *s, uint64_t *out)
{
    if (!s || !*s || *s == '-') return 0;
    char *end = NULL;
    errno = 0;
    unsigned long long v = strtoull(s, &end, 10);
    if (*end || errno) return 0;
    *out = (uint64_t)v;
    return 1;
}

/* Creates path and any missing parent folders (like mkdir -p). */
static int make_dir(const char *path)
{
    char parent[4096];
    size_t n = strlen(path);
    if (n >= sizeof parent) {
        fprintf(stderr, "mm synth: path too long: '%s'\n", path);
        return 1;
    }
    memcpy(parent, path, n + 1);
    for (char *p = parent + 1; *p; ++p)
        if (*p == '/') {
            *p = 0;
            if (mkdir(parent, 0777) != 0 && errno != EEXIST) {
                fprintf(stderr, "mm synth: cannot create '%s': %s\n", parent, strerror(errno));
                return 1;
            }
            *p = '/';
        }
    if (mkdir(path, 0777) == 0) return 0;
    if (errno == EEXIST) {
        struct stat st;
        if (stat(path, &st) == 0 && S_ISDIR(st.st_mode)) return 0;
        fprintf(stderr, "mm synth: '%s' exists and is not a directory\n", path);
        return 1;
    }
    fprintf(stderr, "mm synth: cannot create '%s': %s\n", path, strerror(errno));
    return 1;
}

static int json_ranges(FILE *f, const mm_synth_clip *c, unsigned flag)
{
    int n = mm_synth_contact_ranges(c, flag, NULL, 0);
    int *r = n ? (int *)malloc(2 * (size_t)n * sizeof(int)) : NULL;
    if (n && !r) return 1;
    mm_synth_contact_ranges(c, flag, r, n);
    fputc('[', f);
    for (int i = 0; i < n; ++i) fprintf(f, "%s[%d, %d]", i ? ", " : "", r[2 * i], r[2 * i + 1]);
    fputc(']', f);
    free(r);
    return 0;
}

/* Seconds a clip covers: a loop's last frame wraps to its first. */
static double clip_seconds(const mm_synth_clip *c)
{
    return (double)(c->loop ? c->clip.frame_count : c->clip.frame_count - 1) / (double)c->clip.fps;
}

static int write_json(const char *path, const mm_synth_set *set, uint64_t seed, float fps)
{
    char tmp[4096];
    if (snprintf(tmp, sizeof tmp, "%s.tmp", path) >= (int)sizeof tmp) {
        fprintf(stderr, "mm synth: path too long\n");
        return 1;
    }
    FILE *f = fopen(tmp, "w");
    if (!f) {
        fprintf(stderr, "mm synth: cannot write '%s': %s\n", tmp, strerror(errno));
        return 1;
    }
    int bad = 0;
    double total = 0.0;
    long frames = 0;
    for (int i = 0; i < set->clip_count; ++i) {
        total += clip_seconds(&set->clips[i]);
        frames += set->clips[i].clip.frame_count;
    }
    mm_skeleton *sk = &set->clips[0].clip.skeleton;
    fprintf(
        f, "{\n  \"generator\": \"mm synth\",\n  \"version\": \"%s\",\n  \"seed\": %llu,\n  \"fps\": %.9g,\n",
        MM_VERSION_STRING, (unsigned long long)seed, (double)fps);
    fprintf(f, "  \"units\": {\"length\": \"m\", \"time\": \"s\", \"angle\": \"rad\"},\n");
    fprintf(f, "  \"skeleton\": {\"joints\": %d, \"height\": %.4f},\n", sk->joint_count,
            (double)mm_skeleton_estimate_height(sk, NULL, NULL));
    fprintf(f, "  \"clip_count\": %d,\n  \"total_frames\": %ld,\n  \"total_duration\": %.4f,\n",
            set->clip_count, frames, total);
    fprintf(f, "  \"clips\": [\n");
    for (int i = 0; i < set->clip_count; ++i) {
        const mm_synth_clip *c = &set->clips[i];
        char file[MM_SYNTH_NAME_MAX + 8];
        snprintf(file, sizeof file, "%s.bvh", c->name);
        fprintf(f, "    {\"name\": ");
        cli_json_string(f, c->name);
        fprintf(f, ", \"file\": ");
        cli_json_string(f, file);
        fprintf(f, ", \"kind\": ");
        cli_json_string(f, mm_synth_kind_name(c->kind));
        fprintf(f,
                ", \"loop\": %s, \"frames\": %d, \"fps\": %.9g, \"duration\": %.6f,\n"
                "     \"speed\": %.6g, \"speed_in\": %.6g, \"speed_out\": %.6g, \"turn_radius\": %.6g, "
                "\"turn_angle\": %.6g, \"direction\": %.6g,\n",
                c->loop ? "true" : "false", c->clip.frame_count, (double)c->clip.fps, clip_seconds(c),
                (double)c->speed, (double)c->speed_in, (double)c->speed_out, (double)c->turn_radius,
                (double)c->turn_angle, (double)c->direction);
        fprintf(f, "     \"contacts\": {\"left_heel\": ");
        bad |= json_ranges(f, c, MM_SYNTH_LEFT_HEEL);
        fprintf(f, ", \"left_toe\": ");
        bad |= json_ranges(f, c, MM_SYNTH_LEFT_TOE);
        fprintf(f, ",\n                  \"right_heel\": ");
        bad |= json_ranges(f, c, MM_SYNTH_RIGHT_HEEL);
        fprintf(f, ", \"right_toe\": ");
        bad |= json_ranges(f, c, MM_SYNTH_RIGHT_TOE);
        fprintf(f, "}}%s\n", i + 1 < set->clip_count ? "," : "");
    }
    fprintf(f, "  ]\n}\n");
    if (ferror(f)) bad = 1;
    if (fclose(f) != 0) bad = 1;
    if (bad || rename(tmp, path) != 0) {
        fprintf(stderr, "mm synth: cannot write '%s'\n", path);
        remove(tmp);
        return 1;
    }
    return 0;
}

int mm_cmd_synth(int argc, char **argv)
{
    const char *outdir = NULL;
    uint64_t seed = 0;
    double fps = 60.0;
    for (int i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--seed") == 0) {
            if (i + 1 >= argc || !parse_seed(argv[i + 1], &seed))
                return cli_usage_error("synth", "--seed needs a non-negative integer");
            ++i;
        } else if (strcmp(argv[i], "--fps") == 0) {
            if (i + 1 >= argc || !cli_parse_double(argv[i + 1], &fps) || fps < 10.0 || fps > 240.0)
                return cli_usage_error("synth", "--fps needs a number from 10 to 240");
            ++i;
        } else if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            printf("%s\n", SYNTH_USAGE);
            return 0;
        } else if (argv[i][0] == '-' && argv[i][1]) {
            return cli_usage_error("synth", "unknown option '%s'\n%s", argv[i], SYNTH_USAGE);
        } else if (!outdir) {
            outdir = argv[i];
        } else {
            return cli_usage_error("synth", "unexpected argument '%s'\n%s", argv[i], SYNTH_USAGE);
        }
    }
    if (!outdir) return cli_usage_error("synth", SYNTH_USAGE);
    if (make_dir(outdir)) return 1;

    mm_synth_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.seed = seed;
    desc.fps = (float)fps;
    mm_synth_set set;
    mm_error err;
    memset(&err, 0, sizeof err);
    if (mm_synth_generate(&desc, &set, &err) != MM_OK) return cli_report(&err);

    int rc = 0;
    char path[4096];
    for (int i = 0; i < set.clip_count && rc == 0; ++i) {
        if (snprintf(path, sizeof path, "%s/%s.bvh", outdir, set.clips[i].name) >= (int)sizeof path) {
            fprintf(stderr, "mm synth: path too long\n");
            rc = 1;
            break;
        }
        if (mm_bvh_save(path, &set.clips[i].clip, NULL, &err) != MM_OK) rc = cli_report(&err);
    }
    if (rc == 0) {
        if (snprintf(path, sizeof path, "%s/clips.json", outdir) >= (int)sizeof path)
            rc = 1;
        else
            rc = write_json(path, &set, seed, (float)fps);
    }
    if (rc == 0) {
        double total = 0.0;
        for (int i = 0; i < set.clip_count; ++i) total += clip_seconds(&set.clips[i]);
        printf("mm synth: wrote %d clips (%.1f s at %g fps) and clips.json to %s\n", set.clip_count, total,
               fps, outdir);
    }
    mm_synth_set_free(&set);
    return rc;
}
