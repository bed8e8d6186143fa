/* crowd.c - many characters sharing one database: a crowd of CHARACTERS (default 500), each on
 * its own random input, placed on a grid and ticked together at 60 Hz for SECONDS (default 10).
 * The database and the searcher are loaded once and shared read-only; each character owns its
 * context. It links the mm_runtime library alone (with libm and pthreads).
 *   usage: crowd DB.mmdb [CHARACTERS [SECONDS]] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <mm/runtime.h>

#define CROWD_DEFAULT_CHARACTERS 500
#define CROWD_DEFAULT_SECONDS    10.0
#define CROWD_SPACING            3.0f /* m between neighbours on the starting grid */
#define CROWD_TICK               (1.0f / 60.0f)

int main(int argc, char **argv)
{
    if (argc < 2 || argc > 4) {
        fprintf(stderr, "usage: %s DB.mmdb [CHARACTERS [SECONDS]]\n", argv[0]);
        return 2;
    }
    int count = argc > 2 ? atoi(argv[2]) : CROWD_DEFAULT_CHARACTERS;
    double seconds = argc > 3 ? atof(argv[3]) : CROWD_DEFAULT_SECONDS;
    if (count < 1 || count > 100000 || !(seconds > 0 && seconds <= 3600)) {
        fprintf(stderr, "crowd: CHARACTERS must be 1 to 100000, SECONDS in (0, 3600]\n");
        return 2;
    }
    mm_error err;
    memset(&err, 0, sizeof err);

    /* One database and one searcher for the whole crowd. */
    mm_database db;
    mm_searcher searcher;
    mm_character_desc desc;
    if (mm_database_load(argv[1], NULL, &db, &err) != MM_OK) {
        fprintf(stderr, "%s: %s\n", err.file, err.message);
        return 1;
    }
    if (mm_searcher_init(&searcher, &db, NULL, &err) != MM_OK ||
        mm_character_desc_from_database(&desc, &db, &err) != MM_OK) {
        fprintf(stderr, "%s\n", err.message);
        mm_database_free(&db);
        return 1;
    }

    /* Each character: its own context, its own random input (seeded by its index), a place on
     * the grid. Everything is allocated here, before the first tick. */
    mm_character *crowd = calloc((size_t)count, sizeof *crowd);
    mm_input_script *inputs = calloc((size_t)count, sizeof *inputs);
    mm_vec3 *start = calloc((size_t)count, sizeof *start);
    int made = 0, status = 0;
    int side = (int)ceil(sqrt((double)count));
    mm_input_random_desc random;
    memset(&random, 0, sizeof random);
    random.seconds = (float)seconds;
    for (; crowd && inputs && start && made < count; ++made) {
        if (mm_input_script_random(&inputs[made], (uint64_t)made + 1, &random) != MM_OK) break;
        if (mm_character_init(&crowd[made], &db, &searcher, &desc, &err) != MM_OK) {
            mm_input_script_free(&inputs[made]);
            break;
        }
        start[made] =
            mm_vec3_make(CROWD_SPACING * (float)(made % side), 0.0f, CROWD_SPACING * (float)(made / side));
        mm_character_set_root(&crowd[made], mm_xform_make(mm_quat_identity(), start[made]));
        mm_character_teleport_simulation(&crowd[made], start[made], mm_quat_identity());
    }
    if (made < count) {
        fprintf(stderr, "crowd: cannot make character %d: %s\n", made,
                err.message[0] ? err.message : "out of memory");
        status = 1;
        goto done;
    }

    /* The game loop: every character gets its input and ticks. */
    int ticks = (int)(seconds / CROWD_TICK + 0.5);
    for (int tick = 0; tick < ticks; ++tick) {
        float t = (float)(tick + 1) * CROWD_TICK;
        for (int i = 0; i < count; ++i) {
            mm_input input;
            mm_input_script_sample_tick(&inputs[i], t, CROWD_TICK, &input);
            mm_character_update(&crowd[i], &input, CROWD_TICK);
        }
    }

    /* What the crowd did: how far each character went from its start, and whether every joint
     * of every pose is a number. */
    int finite = 1, searches = 0;
    double travelled = 0.0;
    for (int i = 0; i < count; ++i) {
        for (int j = 0; j < db.joint_count; ++j) {
            mm_vec3 p = crowd[i].global[j].translation;
            finite = finite && isfinite(p.x) && isfinite(p.y) && isfinite(p.z);
        }
        mm_vec3 root = crowd[i].root.translation;
        travelled += hypot(root.x - start[i].x, root.z - start[i].z);
        searches += crowd[i].searches;
    }
    printf("crowd: %d characters, %d ticks of %.4f s, %d searches, mean distance from start %.2f m, %s\n",
           count, ticks, (double)CROWD_TICK, searches, travelled / count,
           finite ? "every pose finite" : "NaN in a pose");
    status = finite ? 0 : 1;

done:
    for (int i = 0; i < made; ++i) {
        mm_character_free(&crowd[i]);
        mm_input_script_free(&inputs[i]);
    }
    free(start);
    free(inputs);
    free(crowd);
    mm_searcher_free(&searcher);
    mm_database_free(&db);
    return status;
}
