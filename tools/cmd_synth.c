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

/* clips.json into f; non-zero when a range list could not be made (the caller checks f itself). */
static int write_json(FILE *f, const mm_synth_set *set, uint64_t seed, float fps)
{
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
    return bad;
}

/* Writes file i of the set (its clips' BVH, then clips.json) to f. */
static int write_file(FILE *f, const mm_synth_set *set, int i, uint64_t seed, float fps, const char *path)
{
    if (i == set->clip_count) return write_json(f, set, seed, fps);
    char *text = NULL;
    size_t size = 0;
    mm_error err;
    memset(&err, 0, sizeof err);
    snprintf(err.file, sizeof err.file, "%s", path);
    if (mm_bvh_write(&set->clips[i].clip, NULL, &text, &size, &err) != MM_OK) {
        cli_report(&err);
        return 1;
    }
    fwrite(text, 1, size, f);
    free(text);
    return 0;
}

/* Every file goes to a temporary file beside it; they are renamed into place only when all of
 * them were written, so a failure leaves none of them. */
static int write_set(const char *outdir, const mm_synth_set *set, uint64_t seed, float fps)
{
    enum { PATH_MAX_ = 4096 };
    int n = set->clip_count + 1, finished = 0, rc = 0;
    char(*paths)[PATH_MAX_] = (char(*)[PATH_MAX_])calloc((size_t)n, PATH_MAX_);
    char(*tmps)[PATH_MAX_ + 32] = (char(*)[PATH_MAX_ + 32]) calloc((size_t)n, PATH_MAX_ + 32);
    if (!paths || !tmps) {
        fprintf(stderr, "mm synth: out of memory\n");
        rc = 1;
    }
    for (int i = 0; i < n && rc == 0; ++i) {
        int len = i < set->clip_count ? snprintf(paths[i], PATH_MAX_, "%s/%s.bvh", outdir, set->clips[i].name)
                                      : snprintf(paths[i], PATH_MAX_, "%s/clips.json", outdir);
        if (len < 0 || len >= PATH_MAX_) {
            fprintf(stderr, "mm synth: %s: path too long\n", outdir);
            rc = 1;
            break;
        }
        FILE *f = cli_create(paths[i], tmps[i], sizeof tmps[i]);
        if (!f) {
            rc = 1;
            break;
        }
        if (write_file(f, set, i, seed, fps, paths[i]) != 0) {
            cli_commit(f, tmps[i], paths[i], 1);
            rc = 1;
        } else if (cli_finish(f, tmps[i], paths[i]) != 0) {
            rc = 1;
        } else {
            finished = i + 1;
        }
    }
    int published = 0;
    for (; rc == 0 && published < n; ++published)
        if (cli_publish(tmps[published], paths[published]) != 0) rc = 1;
    if (rc != 0) {
        for (int i = 0; i + 1 < published; ++i) remove(paths[i]); /* the last one failed: nothing to remove */
        for (int i = published; i < finished; ++i) remove(tmps[i]);
    }
    free(paths);
    free(tmps);
    return rc;
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

    int rc = write_set(outdir, &set, seed, (float)fps);
    if (rc == 0) {
        double total = 0.0;
        for (int i = 0; i < set.clip_count; ++i) total += clip_seconds(&set.clips[i]);
        printf("mm synth: wrote %d clips (%.1f s at %g fps) and clips.json to %s\n", set.clip_count, total,
               fps, outdir);
    }
    mm_synth_set_free(&set);
    return rc;
}
