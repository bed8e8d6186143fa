/* test_databases.h - real databases for tests: the built-in motion set (configs/synth.json over
 * mm_synth_generate, no files written), or LAFAN1 (lafan1.json, made from $MM_DATA_DIR by
 * scripts/data_configs.sh into MM_DATA_CONFIGS before the tests) when MM_DATA_DIR is set. */
#ifndef MM_TEST_DATABASES_H
#define MM_TEST_DATABASES_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <mm/config_json.h>
#include <mm/database_build.h>
#include <mm/synth.h>

/* The built-in set's clips (mm_synth_generate) for cfg's clips, matched by name, in an array of
 * cfg->clip_count (free with mm_config_free_sources); NULL when the set cannot be made. */
static inline mm_clip *test_synth_sources(const mm_config *cfg)
{
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_synth_desc sd;
    memset(&sd, 0, sizeof sd);
    mm_synth_set set;
    if (mm_synth_generate(&sd, &set, &err) != MM_OK) return NULL;
    mm_clip *sources =
        (mm_clip *)calloc((size_t)(cfg->clip_count > 0 ? cfg->clip_count : 1), sizeof(mm_clip));
    for (int i = 0; sources && i < cfg->clip_count; ++i)
        for (int k = 0; k < set.clip_count; ++k)
            if (strcmp(set.clips[k].name, cfg->clips[i].name) == 0)
                mm_clip_copy(&sources[i], &set.clips[k].clip, NULL);
    mm_synth_set_free(&set);
    return sources;
}

/* Builds the config at path; with synth, its clips come from mm_synth_generate (no files read).
 * report: the build's report, or NULL. */
static inline int test_build_database_report(const char *path, int synth, mm_database *db,
                                             mm_db_build_report *report)
{
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_config cfg;
    memset(&cfg, 0, sizeof cfg);
    char *text = NULL;
    if (mm_config_load_json(path, &cfg, &text, &err) != MM_OK) {
        fprintf(stderr, "%s: %s\n", path, err.message);
        return -1;
    }
    mm_clip *sources = NULL;
    if (synth) {
        if (!(sources = test_synth_sources(&cfg))) {
            mm_config_free(&cfg);
            free(text);
            return -1;
        }
    } else if (mm_config_load_sources(&cfg, &sources, &err) != MM_OK) {
        mm_config_free(&cfg);
        free(text);
        return -1;
    }
    mm_db_build_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.config_json = text;
    desc.report = report;
    mm_result r = mm_database_build(&cfg, sources, &desc, db, &err);
    mm_config_free_sources(&cfg, sources);
    mm_config_free(&cfg);
    free(text);
    return r == MM_OK ? 0 : -1;
}

static inline int test_build_database_at(const char *path, int synth, mm_database *db)
{
    return test_build_database_report(path, synth, db, NULL);
}

static inline int test_build_synth_database(mm_database *db)
{
    return test_build_database_at(MM_SOURCE_DIR "/configs/synth.json", 1, db);
}

/* MM_DATA_CONFIGS/<name>.json: the configs scripts/data_configs.sh makes from $MM_DATA_DIR. */
static inline int test_build_data_database(const char *name, mm_database *db)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s.json", MM_DATA_CONFIGS, name);
    return test_build_database_at(path, 0, db);
}

/* LAFAN1 when MM_DATA_DIR is set (*lafan = 1), the built-in set otherwise. */
static inline int test_build_real_database(mm_database *db, int *lafan)
{
    const char *dir = getenv("MM_DATA_DIR");
    *lafan = dir && *dir;
    return *lafan ? test_build_data_database("lafan1", db) : test_build_synth_database(db);
}

#endif
