/* embed.c - the whole embedding of mm in an engine: load a database, make a character, feed it
 * input every tick, read its pose. It links the mm_runtime library alone (with libm and pthreads):
 * no JSON, no build.   usage: embed DB.mmdb */
#include <stdio.h>
#include <string.h>

#include <mm/runtime.h>

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: %s DB.mmdb\n", argv[0]);
        return 2;
    }
    mm_error err;
    memset(&err, 0, sizeof err);

    /* 1. Load the database once; it is read-only and can be shared by every character. */
    mm_database db;
    if (mm_database_load(argv[1], NULL, &db, &err) != MM_OK) {
        fprintf(stderr, "%s: %s\n", err.file, err.message);
        return 1;
    }
    /* 2. A searcher holds the search structures (one per database, shared too). */
    mm_searcher searcher;
    if (mm_searcher_init(&searcher, &db, NULL, &err) != MM_OK) {
        fprintf(stderr, "searcher: %s\n", err.message);
        mm_database_free(&db);
        return 1;
    }
    /* 3. One context per character, with the settings the database was tuned with (stored in it
     * in binary when it was built; NULL instead of &desc: the defaults). Everything it needs is
     * allocated here. */
    mm_character_desc desc;
    mm_character hero;
    if (mm_character_desc_from_database(&desc, &db, &err) != MM_OK ||
        mm_character_init(&hero, &db, &searcher, &desc, &err) != MM_OK) {
        fprintf(stderr, "character: %s\n", err.message);
        mm_searcher_free(&searcher);
        mm_database_free(&db);
        return 1;
    }

    /* 4. The game loop: input in, pose out. Nothing is allocated per tick. */
    const float dt = 1.0f / 60.0f;
    for (int tick = 0; tick < 5 * 60; ++tick) {
        mm_input input;
        memset(&input, 0, sizeof input);
        input.gait = tick < 150 ? MM_GAIT_WALK : MM_GAIT_RUN;
        input.stick[0] = tick < 150 ? 0.0f : 1.0f; /* walk forward, then run to the right */
        input.stick[1] = tick < 150 ? 1.0f : 0.0f;
        mm_character_update(&hero, &input, dt);

        /* hero.global[j] is joint j's world transform; hand it to the renderer or the skinning. */
        if (tick % 60 == 59) {
            mm_vec3 root = hero.global[0].translation, head = hero.global[db.joint_count - 1].translation;
            printf("t = %.0f s: root (%.2f, %.2f), joint %s at height %.2f m, %d searches\n", (tick + 1) * dt,
                   root.x, root.z, db.joints[db.joint_count - 1].name, head.y, hero.searches);
        }
    }

    /* 5. Tear down in reverse order. */
    mm_character_free(&hero);
    mm_searcher_free(&searcher);
    mm_database_free(&db);
    return 0;
}
