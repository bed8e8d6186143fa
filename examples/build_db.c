/* build_db.c - making a database offline with the mm_build library: read a config (JSON), load
 * the motion it lists, build, save. What `mm db build CONFIG --data DIR -o OUT` does, without its
 * report; the same bytes.   usage: build_db CONFIG.json DATA_DIR OUT.mmdb */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <mm/config_json.h>
#include <mm/database_build.h>

int main(int argc, char **argv)
{
    if (argc != 4) {
        fprintf(stderr, "usage: %s CONFIG.json DATA_DIR OUT.mmdb\n", argv[0]);
        return 2;
    }
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_config config;
    memset(&config, 0, sizeof config);
    char *text = NULL; /* the config as read: the database keeps a copy */
    if (mm_config_load_json(argv[1], &config, &text, &err) != MM_OK) {
        fprintf(stderr, "%s: %s\n", err.file, err.message);
        return 1;
    }
    /* the folder the config's clip files are relative to */
    snprintf(config.data_dir, sizeof config.data_dir, "%s", argv[2]);
    mm_clip *sources = NULL;
    if (mm_config_load_sources(&config, &sources, &err) != MM_OK) {
        fprintf(stderr, "%s: %s\n", err.file, err.message);
        free(text);
        mm_config_free(&config);
        return 1;
    }
    mm_db_build_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.config_json = text;
    mm_database db;
    mm_result r = mm_database_build(&config, sources, &desc, &db, &err);
    mm_config_free_sources(&config, sources);
    mm_config_free(&config);
    free(text);
    if (r == MM_OK) {
        r = mm_database_save(&db, argv[3], &err);
        if (r == MM_OK)
            printf("%s: %d frames, %d clips, %d joints\n", argv[3], db.frame_count, db.clip_count,
                   db.joint_count);
        mm_database_free(&db);
    }
    if (r != MM_OK) fprintf(stderr, "%s: %s\n", err.file[0] ? err.file : argv[1], err.message);
    return r == MM_OK ? 0 : 1;
}
