/* mm bvh info | fk | convert (| spans: tools/cmd_bvh_spans.c) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <mm/config_json.h>
#include <mm/mm.h>

#include "cli.h"
#include "commands.h"

static const char *unit_name(double scale)
{
    if (scale == 1.0) return "metres";
    if (scale == 0.01) return "centimetres";
    if (scale == 0.001) return "millimetres";
    if (scale == 0.0254) return "inches";
    if (scale == 0.3048) return "feet";
    if (scale == 0.056444) return "CMU units";
    return "unknown";
}

static int load(const char *path, mm_bvh *bvh)
{
    mm_error err;
    memset(&err, 0, sizeof err);
    if (mm_bvh_load(path, NULL, bvh, &err) != MM_OK) return cli_report(&err);
    return 0;
}

static int cmd_info(int argc, char **argv)
{
    const char *path = NULL;
    int json = 0;
    for (int i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--json") == 0)
            json = 1;
        else if (argv[i][0] == '-' && argv[i][1])
            return cli_usage_error("bvh info", "unknown option '%s'", argv[i]);
        else if (!path)
            path = argv[i];
        else
            return cli_usage_error("bvh info", "unexpected argument '%s'", argv[i]);
    }
    if (!path) return cli_usage_error("bvh info", "usage: mm bvh info FILE [--json]");
    mm_bvh bvh;
    if (load(path, &bvh)) return 1;
    const mm_skeleton *s = &bvh.skeleton;
    int end_sites = 0, order_count[7] = {0};
    for (int j = 0; j < s->joint_count; ++j) {
        end_sites += s->joints[j].has_end_site;
        order_count[s->joints[j].order]++;
    }
    double height = 0.0, scale = mm_bvh_detect_scale(&bvh, &height);
    double fps = 1.0 / bvh.frame_time;
    double duration = bvh.frame_count > 1 ? (bvh.frame_count - 1) * bvh.frame_time : 0.0;
    if (json) {
        printf("{\"file\": ");
        cli_json_string(stdout, path);
        printf(", \"joints\": %d, \"end_sites\": %d, \"channels\": %d, \"frames\": %d, \"frame_time\": %.9g, "
               "\"fps\": %.9g, \"duration\": %.9g, \"height\": %.9g, \"scale_to_metres\": %.9g, \"unit\": ",
               s->joint_count, end_sites, bvh.channel_count, bvh.frame_count, bvh.frame_time, fps, duration,
               height, scale);
        cli_json_string(stdout, scale > 0 ? unit_name(scale) : "unknown");
        printf(", \"orders\": {");
        int first = 1;
        for (int o = 0; o < 7; ++o) {
            if (!order_count[o]) continue;
            printf("%s\"%s\": %d", first ? "" : ", ", o ? mm_euler_order_name((mm_euler_order)o) : "none",
                   order_count[o]);
            first = 0;
        }
        printf("}, \"joint_list\": [");
        for (int j = 0; j < s->joint_count; ++j) {
            printf("%s{\"name\": ", j ? ", " : "");
            cli_json_string(stdout, s->joints[j].name);
            printf(", \"parent\": %d, \"channels\": [", s->joints[j].parent);
            for (int c = 0; c < bvh.channels[j].count; ++c)
                printf("%s\"%s\"", c ? ", " : "",
                       mm_bvh_channel_name((mm_bvh_channel)bvh.channels[j].type[c]));
            printf("]}");
        }
        printf("]}\n");
    } else {
        printf("file:             %s\n", path);
        printf("joints:           %d (+ %d End Sites)\n", s->joint_count, end_sites);
        printf("channels:         %d per frame\n", bvh.channel_count);
        printf("frames:           %d\n", bvh.frame_count);
        printf("fps:              %.6g (frame time %.9g s)\n", fps, bvh.frame_time);
        printf("duration:         %.3f s\n", duration);
        printf("rotation orders: ");
        for (int o = 0; o < 7; ++o)
            if (order_count[o])
                printf(" %s x%d", o ? mm_euler_order_name((mm_euler_order)o) : "none", order_count[o]);
        printf("\n");
        if (scale > 0)
            printf("estimated height: %.4g file units (%s: %.3g m)\n", height, unit_name(scale),
                   height * scale);
        else
            printf("estimated height: %.4g file units (unit not recognised)\n", height);
        printf("hierarchy:\n");
        for (int j = 0; j < s->joint_count; ++j) {
            int depth = 0;
            for (int p = s->joints[j].parent; p >= 0; p = s->joints[p].parent) ++depth;
            printf("  %*s%s (", 2 * depth, "", s->joints[j].name);
            for (int c = 0; c < bvh.channels[j].count; ++c)
                printf("%s%s", c ? " " : "", mm_bvh_channel_name((mm_bvh_channel)bvh.channels[j].type[c]));
            printf(")\n");
        }
    }
    mm_bvh_free(&bvh);
    return 0;
}

static int cmd_fk(int argc, char **argv)
{
    const char *path = NULL;
    long frame = -1;
    int have_frame = 0;
    for (int i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--frame") == 0) {
            if (i + 1 >= argc || !cli_parse_int(argv[i + 1], 0, 0x7fffffff, &frame))
                return cli_usage_error("bvh fk", "--frame needs a frame number >= 0");
            have_frame = 1;
            ++i;
        } else if (argv[i][0] == '-' && argv[i][1]) {
            return cli_usage_error("bvh fk", "unknown option '%s'", argv[i]);
        } else if (!path) {
            path = argv[i];
        } else {
            return cli_usage_error("bvh fk", "unexpected argument '%s'", argv[i]);
        }
    }
    if (!path || !have_frame) return cli_usage_error("bvh fk", "usage: mm bvh fk FILE --frame K");
    mm_bvh bvh;
    if (load(path, &bvh)) return 1;
    if (frame >= bvh.frame_count) {
        fprintf(stderr, "mm: %s: frame %ld is out of range (the file has %d frames, 0 to %d)\n", path, frame,
                bvh.frame_count, bvh.frame_count - 1);
        mm_bvh_free(&bvh);
        return 1;
    }
    int n = bvh.skeleton.joint_count;
    double *xyz = (double *)malloc(sizeof(double) * 3 * (size_t)n);
    if (!xyz || mm_bvh_fk(&bvh, (int)frame, xyz) != MM_OK) {
        fprintf(stderr, "mm: out of memory\n");
        free(xyz);
        mm_bvh_free(&bvh);
        return 1;
    }
    for (int j = 0; j < n; ++j)
        printf("%s %.9g %.9g %.9g\n", bvh.skeleton.joints[j].name, xyz[3 * j], xyz[3 * j + 1],
               xyz[3 * j + 2]);
    free(xyz);
    mm_bvh_free(&bvh);
    return 0;
}

static int cmd_convert(int argc, char **argv)
{
    const char *in = NULL, *out = NULL;
    mm_bvh_import_desc imp;
    mm_bvh_write_desc wd;
    memset(&imp, 0, sizeof imp);
    memset(&wd, 0, sizeof wd);
    double fps = 0.0;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (strcmp(a, "--order") == 0) {
            if (!v || (wd.order = mm_euler_order_parse(v)) == MM_EULER_NONE)
                return cli_usage_error("bvh convert", "--order needs one of XYZ XZY YXZ YZX ZXY ZYX");
            ++i;
        } else if (strcmp(a, "--scale") == 0) {
            double s = 0.0;
            if (v && strcmp(v, "auto") == 0)
                imp.auto_scale = true;
            else if (!v || !cli_parse_double(v, &s) || s <= 0.0)
                return cli_usage_error("bvh convert", "--scale needs a positive number or 'auto'");
            imp.scale = (float)s;
            ++i;
        } else if (strcmp(a, "--fps") == 0) {
            if (!v || !cli_parse_double(v, &fps) || fps <= 0.0 || fps > 10000.0)
                return cli_usage_error("bvh convert", "--fps needs a number in (0, 10000]");
            ++i;
        } else if (a[0] == '-' && a[1]) {
            return cli_usage_error("bvh convert", "unknown option '%s'", a);
        } else if (!in) {
            in = a;
        } else if (!out) {
            out = a;
        } else {
            return cli_usage_error("bvh convert", "unexpected argument '%s'", a);
        }
    }
    if (!in || !out)
        return cli_usage_error("bvh convert",
                               "usage: mm bvh convert IN OUT [--order ZYX] [--scale S|auto] [--fps F]");
    mm_bvh bvh;
    if (load(in, &bvh)) return 1;
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_clip clip, resampled;
    snprintf(err.file, sizeof err.file, "%s", in);
    mm_result r = mm_bvh_to_clip(&bvh, &imp, &clip, &err);
    mm_bvh_free(&bvh);
    if (r != MM_OK) return cli_report(&err);
    if (fps > 0.0) {
        r = mm_clip_resample_interp(&resampled, &clip, (float)fps, MM_INTERP_CUBIC, NULL);
        mm_clip_free(&clip);
        if (r != MM_OK) {
            fprintf(stderr, "mm: %s: cannot resample to %g fps: %s\n", in, fps, mm_result_str(r));
            return 1;
        }
        clip = resampled;
    }
    r = mm_bvh_save(out, &clip, &wd, &err);
    mm_clip_free(&clip);
    if (r != MM_OK) return cli_report(&err);
    return 0;
}

int mm_cmd_bvh(int argc, char **argv)
{
    if (argc < 2)
        return cli_usage_error("bvh", "usage: mm bvh info|fk|convert|spans ... (mm bvh --help: their usage)");
    const char *sub = argv[1];
    if (strcmp(sub, "info") == 0) return cmd_info(argc - 1, argv + 1);
    if (strcmp(sub, "fk") == 0) return cmd_fk(argc - 1, argv + 1);
    if (strcmp(sub, "convert") == 0) return cmd_convert(argc - 1, argv + 1);
    if (strcmp(sub, "spans") == 0) return mm_cmd_bvh_spans(argc - 1, argv + 1);
    return cli_usage_error("bvh", "unknown subcommand '%s' (info, fk, convert, spans)", sub);
}
