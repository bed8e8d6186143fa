/* bench_runtime: the tick cost of characters sharing one database, and how many tick at 60 Hz on
 * the machine's cores through mm_crowd. LAFAN1 (lafan1.json, scripts/data_configs.sh) or the built-in set.
 * usage: bench_runtime [CHARACTERS]   Prints figures; never fails on speed. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <mm/character.h>
#include <mm/crowd.h>
#include <mm/input.h>

#include "../tests/test_databases.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

#define CROWD_TICKS 600 /* 10 s at 60 Hz */

int main(int argc, char **argv)
{
    int n = argc > 1 ? atoi(argv[1]) : 200;
    if (n < 1) n = 1;
    mm_database db;
    int lafan = 0;
    if (test_build_real_database(&db, &lafan) != 0) return 1;
    mm_searcher s;
    if (mm_searcher_init(&s, &db, NULL, NULL) != MM_OK) return 1;
    /* the settings the database was tuned with, as mm simulate runs it */
    mm_character_desc desc;
    if (mm_character_desc_from_database(&desc, &db, NULL) != MM_OK) return 1;
    printf("database: %s, %d frames (distance matching %s, warping %s)\n", lafan ? "LAFAN1" : "built-in set",
           db.frame_count, desc.distance_matching ? "on" : "off", desc.warping ? "on" : "off");
    mm_input_script *scripts = calloc((size_t)n, sizeof(mm_input_script));
    for (int i = 0; i < n; ++i) {
        mm_input_random_desc rd = {20.0f, 0, 0, 0, 0, NULL};
        mm_input_script_random(&scripts[i], (uint64_t)i + 1, &rd);
    }
    /* one character alone: ticks with and without a search */
    {
        mm_character one;
        mm_character_init(&one, &db, &s, &desc, NULL);
        double with = 0, without = 0;
        int nw = 0, nwo = 0;
        for (int t = 0; t < 60 * 20; ++t) {
            mm_input in;
            mm_input_script_sample(&scripts[0], t / 60.0f, &in);
            int before = one.searches;
            double a = now();
            mm_character_update(&one, &in, 1.0f / 60.0f);
            double e = now() - a;
            if (one.searches != before)
                with += e, ++nw;
            else
                without += e, ++nwo;
        }
        printf("one character: %.1f us per tick without a search, %.1f us with (%d searches in 20 s)\n",
               1e6 * without / nwo, 1e6 * with / nw, nw);
        mm_character_free(&one);
    }
    /* the crowd, 10 s of game time, through mm_crowd (mm/crowd.h) on 1 and 2 threads of mm's pool:
     * a fresh crowd each time (the same work), its update timed (the inputs sampled outside) */
    mm_input *inputs = calloc((size_t)n, sizeof(mm_input));
    double first_sum = 0.0;
    for (int threads = 1; threads <= 2; ++threads) {
        mm_crowd crowd;
        mm_crowd_desc cd = {.count = n, .character = &desc, .threads = threads};
        if (mm_crowd_init(&crowd, &db, &s, &cd, NULL) != MM_OK) return 1;
        double spent = 0.0;
        for (int t = 0; t < CROWD_TICKS; ++t) {
            for (int i = 0; i < n; ++i) mm_input_script_sample(&scripts[i], t / 60.0f, &inputs[i]);
            double a = now();
            mm_crowd_update(&crowd, inputs, 1.0f / 60.0f);
            spent += now() - a;
        }
        /* the same crowd whatever the threads: a sum over every character's joints */
        double sum = 0.0;
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < db.joint_count; ++j) sum += crowd.characters[i].global[j].translation.x;
        if (threads == 1) first_sum = sum;
        double per_tick = spent / CROWD_TICKS;
        printf("mm_crowd, %d characters, %d thread%s: %.2f ms per 60 Hz tick (%.1f us per character); %d "
               "characters per 60 Hz tick (16.7 ms)%s\n",
               n, threads, threads > 1 ? "s" : "", 1e3 * per_tick, 1e6 * per_tick / n,
               (int)(n * (1.0 / 60.0) / per_tick), threads > 1 && sum != first_sum ? " DIFFERENT POSES" : "");
        mm_crowd_free(&crowd);
    }
    free(inputs);
    for (int i = 0; i < n; ++i) mm_input_script_free(&scripts[i]);
    free(scripts);
    mm_searcher_free(&s);
    mm_database_free(&db);
    return 0;
}
