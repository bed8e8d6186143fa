/* mm moves detect FILE.bvh [--config C.json] [--json] [--write CONFIG.json] [--as NAME] [--no-mirror]
 * The jumps, vaults, climbs and drops of a clip (mm/move_detect.h), printed or written into a
 * config as clips tagged by kind with their events. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <mm/config_json.h>
#include <mm/import.h>
#include <mm/move_detect.h>
#include <mm/moves.h>
#include <mm/mm.h>

#include "cli.h"
#include "commands.h"

enum { MAX_MOVES = 256 };

static void print_event(FILE *f, const char *name, int frame, float fps, int json, int more)
{
    if (json) {
        fprintf(f, "\"%s\": ", name);
        if (frame < 0)
            fputs("null", f);
        else
            fprintf(f, "{\"frame\": %d, \"time\": %.4f}", frame, frame / (double)fps);
        if (more) fputs(", ", f);
    } else if (frame >= 0) {
        fprintf(f, "  %s %d (%.2f s)", name, frame, frame / (double)fps);
    }
}

static int cmd_detect(int argc, char **argv)
{
    const char *in = NULL, *config = NULL, *write = NULL, *as = NULL;
    int json = 0, no_mirror = 0;
    const char *usage =
        "usage: mm moves detect FILE.bvh [--config CONFIG.json] [--json] [--write CONFIG.json] [--as NAME] "
        "[--no-mirror]";
    const cli_option options[] = {
        {.name = "--config", .kind = CLI_STRING, .target = &config},
        {.name = "--write", .kind = CLI_STRING, .target = &write},
        {.name = "--as", .kind = CLI_STRING, .target = &as},
        {.name = "--json", .kind = CLI_FLAG, .target = &json},
        {.name = "--no-mirror", .kind = CLI_FLAG, .target = &no_mirror},
    };
    int status = cli_parse_options("moves detect", argc, argv, options, CLI_COUNT(options), usage, &in, 1);
    if (status) return status;
    if (!in) return cli_usage_error("moves detect", "%s", usage);
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_config cfg;
    memset(&cfg, 0, sizeof cfg);
    if (config) {
        if (mm_config_load_json(config, &cfg, NULL, &err) != MM_OK) return cli_report(&err);
    } else {
        mm_config_defaults(&cfg);
    }
    if (write) {
        /* --write adds to a config that must exist and be writable: found out now, not after the
         * detection (and not only when it finds something) */
        mm_config target;
        memset(&target, 0, sizeof target);
        char tmp[MM_PATH_MAX + 32];
        FILE *probe = NULL;
        if (mm_config_load_json(write, &target, NULL, &err) != MM_OK) {
            mm_config_free(&cfg);
            return cli_report(&err);
        }
        mm_config_free(&target);
        if (!(probe = cli_create(write, tmp, sizeof tmp))) {
            mm_config_free(&cfg);
            return 1;
        }
        cli_commit(probe, tmp, write, 1); /* closed and removed */
    }
    mm_clip_list takes; /* as the build reads it: the config's axes and scale */
    if (mm_config_import_takes(&cfg, in, &takes, &err) != MM_OK) {
        mm_config_free(&cfg);
        return cli_report(&err);
    }
    mm_move *moves = (mm_move *)calloc(MAX_MOVES, sizeof(mm_move));
    int count = 0;
    if (!moves) {
        fprintf(stderr, "mm: out of memory\n");
        status = 1;
    } else if (takes.count < 1) {
        fprintf(stderr, "mm: %s: no take\n", in);
        status = 1;
    } else if (mm_moves_detect_clip(&takes.clips[0], &cfg, NULL, moves, MAX_MOVES, &count, &err) != MM_OK) {
        snprintf(err.file, sizeof err.file, "%s", in);
        status = cli_report(&err);
    }
    if (count > MAX_MOVES) count = MAX_MOVES;
    float fps = takes.count > 0 ? takes.clips[0].fps : 30.0f;
    char stem[40], file[MM_PATH_MAX];
    cli_file_stem(in, stem, sizeof stem);
    cli_config_file_name(in, file, sizeof file);
    if (as) snprintf(file, sizeof file, "%s", as);
    if (status == 0 && json) {
        printf("{\"file\": ");
        cli_json_string(stdout, in);
        printf(", \"fps\": %g, \"moves\": [", (double)fps);
        for (int i = 0; i < count; ++i) {
            const mm_move *m = &moves[i];
            printf("%s\n  {\"kind\": \"%s\", \"begin\": %d, \"end\": %d, ", i ? "," : "",
                   mm_move_kind_name(m->kind), m->begin, m->end);
            print_event(stdout, "take_off", m->take_off, fps, 1, 1);
            print_event(stdout, "hand_plant", m->hand_plant, fps, 1, 1);
            print_event(stdout, "landing", m->landing, fps, 1, 1);
            printf("\"hand\": %d, \"flight\": %s, \"start_height\": %.3f, \"end_height\": %.3f, "
                   "\"obstacle_height\": %.3f}",
                   m->hand, m->flight ? "true" : "false", (double)m->start_height, (double)m->end_height,
                   (double)m->obstacle_height);
        }
        printf("\n]}\n");
    } else if (status == 0) {
        printf("%s: %d moves\n", in, count);
        for (int i = 0; i < count; ++i) {
            const mm_move *m = &moves[i];
            printf("%-10s frames [%d, %d)", mm_move_kind_name(m->kind), m->begin, m->end);
            print_event(stdout, "take-off", m->take_off, fps, 0, 0);
            print_event(stdout, "hand-plant", m->hand_plant, fps, 0, 0);
            print_event(stdout, "landing", m->landing, fps, 0, 0);
            printf("  height %.2f -> %.2f m%s", (double)m->start_height, (double)m->end_height,
                   m->flight ? "  flight" : "");
            if (m->hand >= 0) printf("  obstacle %.2f m", (double)m->obstacle_height);
            printf("\n");
        }
    }
    int per_kind[MM_MOVE_KIND_COUNT] = {0};
    for (int i = 0; status == 0 && write && i < count; ++i) {
        const mm_move *m = &moves[i];
        char name[MM_NAME_MAX];
        snprintf(name, sizeof name, "%s_%s_%d", stem, mm_move_kind_name(m->kind), ++per_kind[m->kind]);
        int first = m->take_off;
        if (m->hand_plant >= 0 && m->hand_plant < first) first = m->hand_plant;
        mm_config_named_range tags[4];
        int nt = 0;
        memset(tags, 0, sizeof tags);
        snprintf(tags[nt].tag, sizeof tags[nt].tag, "%s", mm_move_kind_tag(m->kind));
        tags[nt].begin = (float)first / fps;
        tags[nt++].end = (float)m->landing / fps;
        snprintf(tags[nt].tag, sizeof tags[nt].tag, "TakeOff");
        tags[nt].begin = tags[nt].end = (float)m->take_off / fps;
        ++nt;
        if (m->hand_plant >= 0) {
            snprintf(tags[nt].tag, sizeof tags[nt].tag, "HandPlant");
            tags[nt].begin = tags[nt].end = (float)m->hand_plant / fps;
            ++nt;
        }
        snprintf(tags[nt].tag, sizeof tags[nt].tag, "Landing");
        tags[nt].begin = tags[nt].end = (float)m->landing / fps;
        ++nt;
        mm_config_saved_clip c;
        memset(&c, 0, sizeof c);
        c.name = name;
        c.file = file;
        c.begin = m->begin;
        c.end = m->end;
        c.type = MM_CLIP_LOCOMOTION;
        c.mirror = !no_mirror;
        c.tags = tags;
        c.tag_count = nt;
        if (mm_config_save_clip(write, &c, &err) != MM_OK) status = cli_report(&err);
    }
    if (status == 0 && write && !json)
        printf(count ? "%s: %d clips written\n" : "%s: unchanged (%d moves found)\n", write, count);
    free(moves);
    mm_clip_list_free(&takes);
    mm_config_free(&cfg);
    return status;
}

int mm_cmd_moves(int argc, char **argv)
{
    if (argc >= 2 && strcmp(argv[1], "detect") == 0) return cmd_detect(argc - 1, argv + 1);
    return cli_usage_error("moves", "usage: mm moves detect FILE.bvh [--config CONFIG.json] [--json] "
                                    "[--write CONFIG.json] [--as NAME] [--no-mirror]");
}
