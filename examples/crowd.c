/* crowd.c - many characters sharing one database: a crowd of CHARACTERS (default 500), each on
 * its own random input, placed on a grid and ticked together at 60 Hz for SECONDS (default 10)
 * by mm_crowd (mm/crowd.h) on THREADS threads (default 1: the calling thread alone) of mm's pool,
 * their searches spread over the ticks.
 * The database and the searcher are loaded once and shared read-only; each character owns its
 * context. The output is the same whatever THREADS is. It links the mm_runtime library alone (with
 * libm and pthreads).
 *   usage: crowd DB.mmdb [CHARACTERS [SECONDS [THREADS]]]
 *
 * A game with a job system hands the crowd its own parallel-for instead of mm's threads:
 *   static void engine_for(void *jobs, int count, mm_crowd_work work, void *context) {
 *       ... split [0, count) into jobs that call work(context, begin, end), wait for them ...
 *   }
 *   mm_crowd_desc d = {.count = n, .parallel_for = engine_for, .user = jobs};
 */
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
    if (argc < 2 || argc > 5) {
        fprintf(stderr, "usage: %s DB.mmdb [CHARACTERS [SECONDS [THREADS]]]\n", argv[0]);
        return 2;
    }
    int count = argc > 2 ? atoi(argv[2]) : CROWD_DEFAULT_CHARACTERS;
    double seconds = argc > 3 ? atof(argv[3]) : CROWD_DEFAULT_SECONDS;
    int threads = argc > 4 ? atoi(argv[4]) : 1;
    if (count < 1 || count > 100000 || !(seconds > 0 && seconds <= 3600) || threads < 1 ||
        threads > MM_SEARCH_MAX_THREADS) {
        fprintf(stderr, "crowd: CHARACTERS must be 1 to 100000, SECONDS in (0, 3600], THREADS 1 to %d\n",
                MM_SEARCH_MAX_THREADS);
        return 2;
    }
    mm_error err;
    memset(&err, 0, sizeof err);

    /* One database; the crowd makes one searcher for all its characters and everything they will
     * ever need, before the first tick. */
    mm_database db;
    if (mm_database_load(argv[1], NULL, &db, &err) != MM_OK) {
        fprintf(stderr, "%s: %s\n", err.file, err.message);
        return 1;
    }
    mm_crowd crowd;
    mm_crowd_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.count = count;
    desc.threads = threads;
    desc.spread_searches = true; /* the searches spread over the ticks: each tick costs about the same */
    if (mm_crowd_init(&crowd, &db, NULL, &desc, &err) != MM_OK) {
        fprintf(stderr, "crowd: %s\n", err.message);
        mm_database_free(&db);
        return 1;
    }

    /* Each character: its own random input (seeded by its index), a place on the grid. */
    mm_input_script *scripts = calloc((size_t)count, sizeof *scripts);
    mm_input *inputs = calloc((size_t)count, sizeof *inputs);
    mm_vec3 *start = calloc((size_t)count, sizeof *start);
    int made = 0, status = 0;
    int side = (int)ceil(sqrt((double)count));
    mm_input_random_desc random;
    memset(&random, 0, sizeof random);
    random.seconds = (float)seconds;
    for (; scripts && inputs && start && made < count; ++made) {
        if (mm_input_script_random(&scripts[made], (uint64_t)made + 1, &random) != MM_OK) break;
        start[made] =
            mm_vec3_make(CROWD_SPACING * (float)(made % side), 0.0f, CROWD_SPACING * (float)(made / side));
        mm_character_set_root(&crowd.characters[made], mm_xform_make(mm_quat_identity(), start[made]));
        mm_character_teleport_simulation(&crowd.characters[made], start[made], mm_quat_identity());
    }
    if (made < count) {
        fprintf(stderr, "crowd: out of memory for character %d\n", made);
        status = 1;
        goto done;
    }

    /* The game loop: every character gets its input, then the crowd ticks. */
    int ticks = (int)(seconds / CROWD_TICK + 0.5);
    for (int tick = 0; tick < ticks; ++tick) {
        float t = (float)(tick + 1) * CROWD_TICK;
        for (int i = 0; i < count; ++i) mm_input_script_sample_tick(&scripts[i], t, CROWD_TICK, &inputs[i]);
        mm_crowd_update(&crowd, inputs, CROWD_TICK);
    }

    /* What the crowd did: how far each character went from its start, and whether every joint
     * of every pose is a number. */
    int finite = 1, searches = 0;
    double travelled = 0.0;
    for (int i = 0; i < count; ++i) {
        const mm_character *c = &crowd.characters[i];
        for (int j = 0; j < db.joint_count; ++j) {
            mm_vec3 p = c->global[j].translation;
            finite = finite && isfinite(p.x) && isfinite(p.y) && isfinite(p.z);
        }
        travelled += hypot(c->root.translation.x - start[i].x, c->root.translation.z - start[i].z);
        searches += c->searches;
    }
    printf("crowd: %d characters, %d ticks of %.4f s, %d searches, mean distance from start %.2f m, %s\n",
           count, ticks, (double)CROWD_TICK, searches, travelled / count,
           finite ? "every pose finite" : "NaN in a pose");
    status = finite ? 0 : 1;

done:
    for (int i = 0; i < made; ++i) mm_input_script_free(&scripts[i]);
    free(start);
    free(inputs);
    free(scripts);
    mm_crowd_free(&crowd);
    mm_database_free(&db);
    return status;
}
