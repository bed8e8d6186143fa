/* bench_runtime: the tick cost of characters sharing one database, and how many tick at 60 Hz on
 * the machine's cores through mm_crowd. LAFAN1 (lafan1.json, scripts/data_configs.sh) or the built-in set.
 * Every character runs with the database's full runtime settings (mm_character_desc_from_database:
 * the search schedule, feet and IK, distance matching and warping as tuned) on its own random input.
 * The crowd ticks CROWD_TICKS times (10 s at 60 Hz) on 1 and then 2 threads of mm's pool, its
 * searches spread over the ticks (mm_crowd_desc.spread_searches), each tick timed; characters per
 * tick come from the p99 tick time (n x 16.7 ms / p99). The process's CPU time per tick (all its
 * threads) is timed too: on a machine shared with other work the wall-clock times are the
 * scheduler's as much as mm's, while the CPU time per character tells whether a second thread adds
 * work of its own. pose_hash is a hash of every character's final pose, the same for 1 and 2
 * threads. The ticks slower than the p95 are told apart by their work: their searches and jumps
 * (inertialization's start) each, against every tick's (more work on them: the schedule's; as much:
 * the machine's).
 * usage: bench_runtime [--json] [CHARACTERS]   (default 2000). Prints figures; never fails on speed. */
#define _POSIX_C_SOURCE 200809L
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <mm/character.h>
#include <mm/crowd.h>
#include <mm/input.h>

#include "../tests/test_databases.h"

#include "bench_common.h"

#define CROWD_TICKS          600 /* 10 s at 60 Hz */
#define SEARCH_TICKS_SKIPPED 1   /* the first tick, on which every character searches at once */
#define TICK                 (1.0 / 60.0)

/* Seconds of CPU time the process has taken, all its threads. */
static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The machine's load average over the last minute (-1 where /proc/loadavg is not to be had). */
static double load_average(void)
{
    double load = -1.0;
    FILE *f = fopen("/proc/loadavg", "r");
    if (f) {
        if (fscanf(f, "%lf", &load) != 1) load = -1.0;
        fclose(f);
    }
    return load;
}

/* FNV-1a over the bytes of every character's world transforms. */
static uint64_t pose_hash(const mm_crowd *crowd)
{
    uint64_t h = 0xcbf29ce484222325ull;
    for (int i = 0; i < crowd->count; ++i) {
        const unsigned char *b = (const unsigned char *)crowd->characters[i].global;
        size_t n = sizeof(mm_xform) * (size_t)crowd->db->joint_count;
        for (size_t k = 0; k < n; ++k) h = (h ^ b[k]) * 0x100000001b3ull;
    }
    return h;
}

int main(int argc, char **argv)
{
    int n = 2000, json = 0;
    for (int i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--json") == 0)
            json = 1;
        else
            n = atoi(argv[i]);
    }
    if (n < 1) n = 1;
    FILE *out = json ? stderr : stdout; /* with --json the figures for people go to stderr */
    mm_database db;
    int lafan = 0;
    if (test_build_real_database(&db, &lafan) != 0) return 1;
    mm_searcher s;
    if (mm_searcher_init(&s, &db, NULL, NULL) != MM_OK) return 1;
    /* the settings the database was tuned with, as mm simulate runs it */
    mm_character_desc desc;
    if (mm_character_desc_from_database(&desc, &db, NULL) != MM_OK) return 1;
    fprintf(
        out,
        "database: %s, %d frames (search every %.3f s and on turns; feet and IK %s, distance matching %s, "
        "warping %s)\n",
        lafan ? "LAFAN1" : "built-in set", db.frame_count, desc.search_interval,
        desc.no_foot_ik ? "off" : "on", desc.distance_matching ? "on" : "off", desc.warping ? "on" : "off");
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
        fprintf(out, "one character: %.1f us per tick without a search, %.1f us with (%d searches in 20 s)\n",
                1e6 * without / nwo, 1e6 * with / nw, nw);
        mm_character_free(&one);
    }
    /* the crowd, 10 s of game time, through mm_crowd (mm/crowd.h) on 1 and 2 threads of mm's pool:
     * a fresh crowd each time (the same work), each update timed (the inputs sampled outside) */
    mm_input *inputs = calloc((size_t)n, sizeof(mm_input));
    double *tick = malloc(sizeof(double) * CROWD_TICKS);
    int *tick_searches = malloc(sizeof(int) * CROWD_TICKS), *tick_jumps = malloc(sizeof(int) * CROWD_TICKS);
    int per_tick[3] = {0}, most_searches[3] = {0};
    double cpu_per_character[3] = {0};
    uint64_t hash[3] = {0};
    for (int threads = 1; threads <= 2; ++threads) {
        mm_crowd crowd;
        mm_crowd_desc cd = {.count = n, .character = &desc, .threads = threads, .spread_searches = true};
        if (mm_crowd_init(&crowd, &db, &s, &cd, NULL) != MM_OK) return 1;
        long searches = 0;
        double cpu = 0.0, load = load_average();
        for (int t = 0; t < CROWD_TICKS; ++t) {
            for (int i = 0; i < n; ++i) mm_input_script_sample(&scripts[i], (float)(t * TICK), &inputs[i]);
            long before = 0, after = 0, jumps_before = 0, jumps_after = 0;
            for (int i = 0; i < n; ++i)
                before += crowd.characters[i].searches, jumps_before += crowd.characters[i].transitions;
            double a = now(), c = cpu_now();
            mm_crowd_update(&crowd, inputs, (float)TICK);
            tick[t] = now() - a;
            cpu += cpu_now() - c;
            for (int i = 0; i < n; ++i)
                after += crowd.characters[i].searches, jumps_after += crowd.characters[i].transitions;
            tick_searches[t] = (int)(after - before);
            tick_jumps[t] = (int)(jumps_after - jumps_before);
            if (t >= SEARCH_TICKS_SKIPPED && after - before > most_searches[threads])
                most_searches[threads] = (int)(after - before);
        }
        cpu_per_character[threads] = 1e6 * cpu / CROWD_TICKS / n;
        for (int i = 0; i < n; ++i) searches += crowd.characters[i].searches;
        hash[threads] = pose_hash(&crowd);
        double total = 0.0;
        for (int t = 0; t < CROWD_TICKS; ++t) total += tick[t];
        /* the slow ticks' work: their searches and jumps against every tick's (after the first) */
        double *sorted = malloc(sizeof(double) * CROWD_TICKS);
        memcpy(sorted, tick, sizeof(double) * CROWD_TICKS);
        qsort(sorted, CROWD_TICKS, sizeof(double), compare);
        double p95 = sorted[(int)(0.95 * (CROWD_TICKS - 1))];
        double slow_searches = 0, slow_jumps = 0, all_searches = 0, all_jumps = 0;
        int slow = 0;
        for (int t = SEARCH_TICKS_SKIPPED; t < CROWD_TICKS; ++t) {
            all_searches += tick_searches[t], all_jumps += tick_jumps[t];
            if (tick[t] > p95) slow_searches += tick_searches[t], slow_jumps += tick_jumps[t], ++slow;
        }
        memcpy(tick, sorted, sizeof(double) * CROWD_TICKS);
        free(sorted);
        double median = tick[CROWD_TICKS / 2], p99 = tick[(int)(0.99 * (CROWD_TICKS - 1) + 0.5)];
        per_tick[threads] = (int)(n * TICK / p99);
        fprintf(
            out,
            "mm_crowd, %d characters, %d thread%s (load average %.1f): tick median %.2f ms, p99 %.2f ms, "
            "mean %.2f ms (%.1f us per character at p99); %d characters per 60 Hz tick (16.7 ms) at p99; "
            "CPU %.1f us per character tick (all threads); %.1f%% of character ticks search, at most %d on "
            "one tick after the first; pose hash %016" PRIx64 "%s\n",
            n, threads, threads > 1 ? "s" : "", load, 1e3 * median, 1e3 * p99, 1e3 * total / CROWD_TICKS,
            1e6 * p99 / n, per_tick[threads], cpu_per_character[threads],
            100.0 * searches / ((double)n * CROWD_TICKS), most_searches[threads], hash[threads],
            threads > 1 && hash[2] != hash[1] ? " DIFFERENT POSES" : "");
        int ticks = CROWD_TICKS - SEARCH_TICKS_SKIPPED;
        fprintf(out,
                "  the %d ticks over the p95 (%.2f ms): %.0f searches and %.0f jumps each, every tick %.0f "
                "and %.0f\n",
                slow, 1e3 * p95, slow ? slow_searches / slow : 0.0, slow ? slow_jumps / slow : 0.0,
                all_searches / ticks, all_jumps / ticks);
        mm_crowd_free(&crowd);
    }
    if (json)
        printf("{\"database\": {\"frames\": %d}, \"characters_per_tick\": {\"1\": %d, \"2\": %d}, "
               "\"cpu_us_per_character\": {\"1\": %.2f, \"2\": %.2f}, \"most_searches_in_a_tick\": {\"1\": "
               "%d, \"2\": %d}, \"pose_hash\": {\"1\": \"%016" PRIx64 "\", \"2\": \"%016" PRIx64 "\"}}\n",
               db.frame_count, per_tick[1], per_tick[2], cpu_per_character[1], cpu_per_character[2],
               most_searches[1], most_searches[2], hash[1], hash[2]);
    free(tick);
    free(tick_searches);
    free(tick_jumps);
    free(inputs);
    for (int i = 0; i < n; ++i) mm_input_script_free(&scripts[i]);
    free(scripts);
    mm_searcher_free(&s);
    mm_database_free(&db);
    return hash[1] == hash[2] ? 0 : 1;
}
