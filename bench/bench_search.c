/* bench_search: the exact search against brute force on the queries games make, on the LAFAN1
 * database (lafan1.json, made from $MM_DATA_DIR by `cmake --build build --target data_configs` or
 * the tests) or the built-in motion set when MM_DATA_DIR is unset.
 *
 * Four kinds of query:
 *   near        a database frame plus small noise (0.1 per normalised dimension)
 *   recorded    the queries characters searched with on random input (the database's own runtime
 *               settings: weights, favours, tags and type as the runtime adjusts them)
 *   transition  the pose of frame i with the trajectory of frame j
 *   random      normal in feature space
 * each timed query by query with warm caches and with cold ones (a BENCH_COLD_SWEEP_BYTES sweep before
 * each query), median and p99 for the fast search and brute force in the same run; then batch
 * throughput of each kind on 1 and 2 threads. Every answer of the fast search is checked against
 * brute force (the exit status is 1 on a mismatch).
 *
 * usage: bench_search [--json] [--repeat R] [QUERIES]   (QUERIES per kind, default 1000; the cold
 *        runs take a quarter of them, at least 100; with R > 1 every query is timed R times, in R
 *        passes, and its least time kept: on a shared machine a query the scheduler preempted in one
 *        pass is timed again in the next, so the p99 is the search's rather than the scheduler's).
 *        Prints figures; never fails on speed. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <mm/character.h>
#include <mm/input.h>
#include <mm/search.h>

#include "../tests/test_databases.h"

#include "bench_common.h"

#define NEAR_NOISE        0.1 /* per normalised dimension */
#define RECORD_CHARACTERS 16  /* characters whose searches are recorded, ticked in turn */
#define RECORD_INPUT_SECS 120.0f
#define BATCH_REPEATS     3
#define BATCH_BRUTE_MAX   200 /* queries per brute-force batch (it is slow) */
#define KINDS             4
#define CACHES            2

static const char *const KIND_NAMES[KINDS] = {"near", "recorded", "transition", "random"};
static const char *const CACHE_NAMES[CACHES] = {"warm", "cold"};

static unsigned char *sweep_buffer; /* BENCH_COLD_SWEEP_BYTES */

/* The queries of one kind and their parameters. */
typedef struct query_set {
    float *q;            /* [n x dims_padded] */
    mm_search_params *p; /* [n] */
    int n;
} query_set;

static int frame_at_random(const mm_database *db)
{
    return (int)(uniform() * db->frame_count) % db->frame_count;
}

/* What characters searched with: RECORD_CHARACTERS characters with the database's runtime
 * settings on random input, ticked in turn at 60 Hz, every search's query and parameters kept
 * until n are. */
static int record_queries(const mm_database *db, const mm_searcher *s, query_set *set)
{
    mm_character_desc desc;
    if (mm_character_desc_from_database(&desc, db, NULL) != MM_OK) return -1;
    int dims = db->dims_padded, got = 0;
    mm_character chars[RECORD_CHARACTERS];
    mm_input_script scripts[RECORD_CHARACTERS];
    int searches[RECORD_CHARACTERS];
    for (int i = 0; i < RECORD_CHARACTERS; ++i) {
        mm_input_random_desc rd = {RECORD_INPUT_SECS, 0, 0, 0, 0, NULL};
        if (mm_input_script_random(&scripts[i], 1000 + (uint64_t)i, &rd) != MM_OK) return -1;
        if (mm_character_init(&chars[i], db, s, &desc, NULL) != MM_OK) return -1;
        searches[i] = 0;
    }
    for (int t = 0; got < set->n && t < (int)(RECORD_INPUT_SECS * 60.0f); ++t)
        for (int i = 0; i < RECORD_CHARACTERS && got < set->n; ++i) {
            mm_input in;
            mm_input_script_sample(&scripts[i], (float)t / 60.0f, &in);
            mm_character_update(&chars[i], &in, 1.0f / 60.0f);
            if (chars[i].searches == searches[i]) continue;
            searches[i] = chars[i].searches;
            memcpy(set->q + (size_t)got * dims, chars[i].query, sizeof(float) * (size_t)dims);
            set->p[got++] = chars[i].last_params;
        }
    for (int i = 0; i < RECORD_CHARACTERS; ++i) {
        mm_character_free(&chars[i]);
        mm_input_script_free(&scripts[i]);
    }
    set->n = got;
    return got > 0 ? 0 : -1;
}

static void make_queries(const mm_database *db, int kind, query_set *set)
{
    int dims = db->dims_padded;
    for (int i = 0; i < set->n; ++i) {
        float *q = set->q + (size_t)i * dims;
        mm_search_params *p = &set->p[i];
        mm_search_params_defaults(db, p);
        int a = frame_at_random(db), b = frame_at_random(db);
        p->current_frame = a;
        if (kind == 0) {
            mm_search_query_from_frames(db, a, a, q);
            for (int d = 0; d < db->dims; ++d) q[d] += (float)(NEAR_NOISE * normal());
        } else if (kind == 2) {
            mm_search_query_from_frames(db, a, b, q);
        } else {
            memset(q, 0, sizeof(float) * (size_t)dims);
            for (int d = 0; d < db->dims; ++d) q[d] = (float)normal();
        }
    }
}

typedef struct timing {
    double median_us, p99_us;
} timing;

static timing summarise(double *t, int n)
{
    qsort(t, (size_t)n, sizeof(double), compare);
    timing r = {1e6 * t[n / 2], 1e6 * t[(int)(0.99 * (n - 1) + 0.5)]};
    return r;
}

/* Times the first n queries of set one by one, with the fast search into fast (times tf) and brute
 * force into brute (times tb); its work summed into total (over the first repetition). Warm: each
 * method in its own loop (no cache shared between them). Cold: a sweep before each search, the two
 * methods in turn on each query (the machine's load then weighs on both alike). Each query's time
 * is the least of repeat passes over all n. */
static void time_queries(const mm_searcher *s, const query_set *set, int n, int cold, int repeat,
                         mm_search_result *fast, mm_search_result *brute, double *tf, double *tb,
                         mm_search_stats *total)
{
    int dims = s->db->dims_padded;
    memset(total, 0, sizeof *total);
    for (int i = 0; i < n; ++i) tf[i] = tb[i] = INFINITY;
    for (int pass = 0; pass < (cold ? 1 : 2); ++pass)
        for (int r = 0; r < repeat; ++r)
            for (int i = 0; i < n; ++i)
                for (int m = 0; m < 2; ++m) {
                    if (!cold && m != pass) continue;
                    if (cold) bench_cold_sweep(sweep_buffer);
                    mm_search_stats st;
                    const float *q = set->q + (size_t)i * dims;
                    double a = now();
                    mm_searcher_search_stats(s, q, &set->p[i], m ? MM_SEARCH_BRUTE : MM_SEARCH_FAST,
                                             m ? &brute[i] : &fast[i], 1, &st);
                    double t = now() - a;
                    double *kept = m ? &tb[i] : &tf[i];
                    if (t < *kept) *kept = t;
                    if (m || r) continue;
                    total->frames_evaluated += st.frames_evaluated;
                    total->boxes_tested += st.boxes_tested;
                }
}

/* Queries per second of a batch of the first n queries (the best of BATCH_REPEATS). */
static double batch_rate(const mm_searcher *s, const query_set *set, int n, mm_search_method method,
                         mm_search_result *found)
{
    double best = INFINITY;
    for (int rep = 0; rep < BATCH_REPEATS; ++rep) {
        double a = now();
        mm_searcher_batch(s, set->q, set->p, 1, method, found, n);
        double e = now() - a;
        if (e < best) best = e;
    }
    return n / best;
}

int main(int argc, char **argv)
{
    int n = 1000, json = 0, repeat = 1;
    for (int i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--json") == 0)
            json = 1;
        else if (strcmp(argv[i], "--repeat") == 0 && i + 1 < argc)
            repeat = atoi(argv[++i]);
        else
            n = atoi(argv[i]);
    }
    if (repeat < 1) repeat = 1;
    if (n < 100) n = 100;
    int cold_n = n / 4 > 100 ? n / 4 : 100;
    FILE *out = json ? stderr : stdout; /* with --json the figures for people go to stderr */
    mm_database db;
    int lafan = 0;
    if (test_build_real_database(&db, &lafan) != 0) return 1;
    mm_searcher s;
    mm_error err;
    if (mm_searcher_init(&s, &db, NULL, &err) != MM_OK) return 1;
    int dims = db.dims_padded;
    fprintf(
        out,
        "database: %s: %d frames x %d dims (%d padded); searcher %.1f MB, %d nodes of %d lanes, boxes on %d "
        "pose and %d trajectory slots\n",
        lafan ? "LAFAN1 (lafan1.json)" : "the built-in set (set MM_DATA_DIR for LAFAN1)", db.frame_count,
        db.dims, dims, s.memory / 1e6, s.node_count, MM_SEARCH_WIDTH, s.pose_dims, s.tree_dims - s.pose_dims);
    sweep_buffer = calloc(BENCH_COLD_SWEEP_BYTES, 1);
    query_set sets[KINDS];
    for (int k = 0; k < KINDS; ++k) {
        sets[k].n = n;
        sets[k].q = calloc((size_t)n * dims, sizeof(float));
        sets[k].p = calloc((size_t)n, sizeof(mm_search_params));
        if (k == 1) {
            if (record_queries(&db, &s, &sets[k]) != 0) return 1;
        } else {
            make_queries(&db, k, &sets[k]);
        }
    }
    double *t = malloc(sizeof(double) * (size_t)n), *tb = malloc(sizeof(double) * (size_t)n);
    mm_search_result *fast = malloc(sizeof(mm_search_result) * (size_t)n),
                     *brute = malloc(sizeof(mm_search_result) * (size_t)n);
    timing fast_t[KINDS][CACHES], brute_t[KINDS][CACHES];
    long mismatches = 0, checked = 0;
    fprintf(
        out,
        "\nper query (fast / brute force, the same queries; cold: a %u MB sweep before each; each query's "
        "least time of %d)\n",
        BENCH_COLD_SWEEP_BYTES >> 20, repeat);
    fprintf(out, "%-10s %-4s %5s  %9s %9s  %9s %9s  %7s %7s  %8s %6s\n", "kind", "cache", "n", "fast med",
            "p99", "brute med", "p99", "x med", "x p99", "frames%", "boxes");
    for (int k = 0; k < KINDS; ++k)
        for (int c = 0; c < CACHES; ++c) {
            int m = c ? (cold_n < sets[k].n ? cold_n : sets[k].n) : sets[k].n;
            mm_search_stats fs;
            time_queries(&s, &sets[k], m, c, repeat, fast, brute, t, tb, &fs);
            fast_t[k][c] = summarise(t, m);
            brute_t[k][c] = summarise(tb, m);
            for (int i = 0; i < m; ++i) mismatches += fast[i].frame != brute[i].frame;
            checked += m;
            fprintf(
                out, "%-10s %-5s %5d  %6.1f us %6.1f us  %6.1f us %6.1f us  %6.1fx %6.1fx  %7.2f%% %6.0f\n",
                KIND_NAMES[k], CACHE_NAMES[c], m, fast_t[k][c].median_us, fast_t[k][c].p99_us,
                brute_t[k][c].median_us, brute_t[k][c].p99_us,
                brute_t[k][c].median_us / fast_t[k][c].median_us, brute_t[k][c].p99_us / fast_t[k][c].p99_us,
                100.0 * fs.frames_evaluated / m / db.frame_count, (double)fs.boxes_tested / m);
        }

    /* batch throughput of each kind on 1 and 2 threads */
    fprintf(out, "\nbatch, queries/s (fast / brute force, the same queries)\n");
    for (int threads = 1; threads <= 2; ++threads) {
        mm_searcher sb;
        mm_searcher_desc sd = {threads, NULL};
        if (mm_searcher_init(&sb, &db, &sd, &err) != MM_OK) return 1;
        for (int k = 0; k < KINDS; ++k) {
            int bn = sets[k].n < BATCH_BRUTE_MAX ? sets[k].n : BATCH_BRUTE_MAX;
            double f = batch_rate(&sb, &sets[k], sets[k].n, MM_SEARCH_FAST, fast);
            double b = batch_rate(&sb, &sets[k], bn, MM_SEARCH_BRUTE, brute);
            for (int i = 0; i < bn; ++i) mismatches += fast[i].frame != brute[i].frame;
            checked += bn;
            fprintf(out, "%-10s %d thread%s  fast %9.0f  brute %7.0f  %6.1fx\n", KIND_NAMES[k], sb.threads,
                    sb.threads > 1 ? "s" : " ", f, b, f / b);
        }
        mm_searcher_free(&sb);
    }
    fprintf(out, "\nfast vs brute force: %ld mismatches in %ld answers\n", mismatches, checked);
    if (json) {
        printf("{\"database\": {\"frames\": %d}, \"repeat\": %d", db.frame_count, repeat);
        for (int k = 0; k < KINDS; ++k) {
            printf(", \"%s\": {", KIND_NAMES[k]);
            for (int c = 0; c < CACHES; ++c)
                printf("%s\"%s\": {\"median_us\": %.2f, \"p99_us\": %.2f, \"brute_median_us\": %.2f, "
                       "\"brute_p99_us\": %.2f}",
                       c ? ", " : "", CACHE_NAMES[c], fast_t[k][c].median_us, fast_t[k][c].p99_us,
                       brute_t[k][c].median_us, brute_t[k][c].p99_us);
            printf("}");
        }
        printf("}\n");
    }
    for (int k = 0; k < KINDS; ++k) {
        free(sets[k].q);
        free(sets[k].p);
    }
    free(t);
    free(tb);
    free(fast);
    free(brute);
    free(sweep_buffer);
    mm_searcher_free(&s);
    mm_database_free(&db);
    return mismatches ? 1 : 0;
}
