/* test_synth_db.h - the built-in motion set as a database, for tests that need a real one without
 * motion capture (configs/synth.json over mm_synth_generate, no files written). */
#ifndef MM_TEST_SYNTH_DB_H
#define MM_TEST_SYNTH_DB_H

#include <stdlib.h>
#include <string.h>

#include <mm/config_json.h>
#include <mm/database.h>
#include <mm/synth.h>

static inline int test_build_synth_database(mm_database *db)
{
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_config cfg;
    memset(&cfg, 0, sizeof cfg);
    char *text = NULL;
    if (mm_config_load_json(MM_TEST_DATA "/../../configs/synth.json", &cfg, &text, &err) != MM_OK) return -1;
    mm_synth_desc sd;
    memset(&sd, 0, sizeof sd);
    mm_synth_set set;
    if (mm_synth_generate(&sd, &set, &err) != MM_OK) return -1;
    mm_clip *sources = (mm_clip *)calloc((size_t)cfg.clip_count, sizeof(mm_clip));
    for (int i = 0; i < cfg.clip_count; ++i)
        for (int k = 0; k < set.clip_count; ++k)
            if (strcmp(set.clips[k].name, cfg.clips[i].name) == 0)
                mm_clip_copy(&sources[i], &set.clips[k].clip, NULL);
    mm_synth_set_free(&set);
    mm_db_build_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.config_json = text;
    mm_result r = mm_database_build(&cfg, sources, &desc, db, &err);
    mm_config_free_sources(&cfg, sources);
    mm_config_free(&cfg);
    free(text);
    return r == MM_OK ? 0 : -1;
}

#endif
