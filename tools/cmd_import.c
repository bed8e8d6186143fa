/* mm import info FILE [--json] [--scale S|auto] [--fps F]: the takes of a BVH, FBX, glTF or
 * Collada file as mm imports them. */
#include <stdio.h>
#include <string.h>

#include <mm/import.h>

#include "cli.h"
#include "commands.h"

#define USAGE "usage: mm import info FILE [--json] [--scale S|auto] [--fps F]"

static int cmd_info(int argc, char **argv)
{
    const char *path = NULL;
    int json = 0;
    mm_import_desc desc;
    memset(&desc, 0, sizeof desc);
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        double d = 0.0;
        if (strcmp(a, "--json") == 0) {
            json = 1;
        } else if (strcmp(a, "--scale") == 0) {
            if (v && strcmp(v, "auto") == 0)
                desc.auto_scale = true;
            else if (!v || !cli_parse_double(v, &d) || d <= 0.0)
                return cli_usage_error("import info", "--scale needs a positive number or 'auto'");
            desc.scale = (float)d;
            ++i;
        } else if (strcmp(a, "--fps") == 0) {
            if (!v || !cli_parse_double(v, &d) || d <= 0.0 || d > 10000.0)
                return cli_usage_error("import info", "--fps needs a number in (0, 10000]");
            desc.fps = (float)d;
            ++i;
        } else if (a[0] == '-' && a[1]) {
            return cli_usage_error("import info", "unknown option '%s'", a);
        } else if (!path) {
            path = a;
        } else {
            return cli_usage_error("import info", "unexpected argument '%s'", a);
        }
    }
    if (!path) return cli_usage_error("import info", USAGE);
    mm_clip_list list;
    mm_error err;
    if (mm_import_clips(path, &desc, &list, &err) != MM_OK) return cli_report(&err);
    if (json) {
        printf("{\"file\": ");
        cli_json_string(stdout, path);
        printf(", \"format\": ");
        cli_json_string(stdout, list.format);
        printf(", \"takes\": [");
    } else {
        printf("file:   %s\nformat: %s\ntakes:  %d\n", path, list.format, list.count);
    }
    for (int i = 0; i < list.count; ++i) {
        const mm_clip *c = &list.clips[i];
        float height =
            mm_skeleton_estimate_height(&c->skeleton, c->frame_count ? mm_clip_rotations(c, 0) : NULL,
                                        c->frame_count ? mm_clip_positions(c, 0) : NULL);
        if (json) {
            printf("%s{\"name\": ", i ? ", " : "");
            cli_json_string(stdout, list.names[i]);
            printf(", \"joints\": %d, \"frames\": %d, \"fps\": %.9g, \"duration\": %.9g, \"height\": %.9g, "
                   "\"root\": ",
                   c->skeleton.joint_count, c->frame_count, c->fps, mm_clip_duration(c), height);
            cli_json_string(stdout, c->skeleton.joints[0].name);
            printf("}");
        } else {
            printf("  %-32s %4d joints %7d frames at %g fps (%.3f s), root %s, height %.4g\n", list.names[i],
                   c->skeleton.joint_count, c->frame_count, c->fps, mm_clip_duration(c),
                   c->skeleton.joints[0].name, height);
        }
    }
    if (json) printf("]}\n");
    mm_clip_list_free(&list);
    return 0;
}

int mm_cmd_import(int argc, char **argv)
{
    if (argc >= 2 && strcmp(argv[1], "info") == 0) return cmd_info(argc - 1, argv + 1);
    if (argc >= 2) return cli_usage_error("import", "unknown subcommand '%s' (info)\n%s", argv[1], USAGE);
    return cli_usage_error("import", USAGE);
}
