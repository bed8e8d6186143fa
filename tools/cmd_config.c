/* mm config explain | check */
#include <stdio.h>
#include <string.h>

#include <mm/config_json.h>

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
    mm_config_free(&cfg);
    return missing ? 1 : 0;
}

int mm_cmd_config(int argc, char **argv)
{
    if (argc < 2) return cli_usage_error("config", "usage: mm config explain [FIELD] | check CONFIG");
    if (strcmp(argv[1], "explain") == 0) return cmd_explain(argc - 1, argv + 1);
    if (strcmp(argv[1], "check") == 0) return cmd_check(argc - 1, argv + 1);
    return cli_usage_error("config", "unknown subcommand '%s' (explain, check)", argv[1]);
}
