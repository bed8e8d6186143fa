/* bench_scale: how a database's size and search time grow with its frames (docs/scaling.md): for
 * each database given, its frames, file and pose bytes (floats, and compressed with the defaults),
 * and the search's microseconds per query (median and p99; brute force and the fast search, in
 * the same run) for two kinds of query: a frame's pose with another frame's trajectory (a
 * transition) and a frame's own features with small noise (as a character asks while playing).
 * usage: bench_scale DB.mmdb... [--queries N] [--json]   Prints figures; never fails on speed. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <mm/character.h>
#include <mm/database_build.h>
#include <mm/input.h>
#include <mm/search.h>

#include "bench_common.h"

#define NOISE 0.05 /* standard deviation of the noise on the near queries (normalised units) */

/* An allocator that counts the bytes a character takes (mm_character_desc.allocator). */
static void *count_alloc(size_t size, void *user)
{
    *(size_t *)user += size;
    return malloc(size);
}
static void count_free(void *ptr, void *user)
{
    (void)user;
    free(ptr);
}

/* Bytes one character on db allocates (its state and its trajectory). */
static size_t character_bytes(const mm_database *db, const mm_searcher *s)
{
    size_t bytes = 0;
    mm_allocator a = {count_alloc, count_free, &bytes};
    mm_character_desc desc;
    mm_error err;
    if (mm_character_desc_from_database(&desc, db, &err) != MM_OK) return 0;
    desc.allocator = &a;
    mm_character c;
    if (mm_character_init(&c, db, s, &desc, &err) != MM_OK) return 0;
    mm_character_free(&c);
    return bytes;
}

/* Microseconds per 60 Hz tick of one character on db (TICKS ticks of a stick that turns, stops and
 * runs; searches included), the median of RUNS runs. */
#define TICKS 1200
#define RUNS  3
static double tick_us(const mm_database *db, const mm_searcher *s)
{
    double runs[RUNS];
    for (int k = 0; k < RUNS; ++k) {
        mm_character_desc desc;
        mm_error err;
        mm_character c;
        if (mm_character_desc_from_database(&desc, db, &err) != MM_OK ||
            mm_character_init(&c, db, s, &desc, &err) != MM_OK)
            return 0.0;
        mm_input in;
        memset(&in, 0, sizeof in);
        double t0 = now();
        for (int i = 0; i < TICKS; ++i) {
            float t = (float)i / 60.0f;
            in.stick[0] = sinf(0.37f * t);
            in.stick[1] = (i / 300) % 3 == 2 ? 0.0f : cosf(0.23f * t);
            in.gait = (i / 450) % 2 == 1 ? MM_GAIT_RUN : MM_GAIT_WALK;
            mm_character_update(&c, &in, 1.0f / 60.0f);
        }
        runs[k] = (now() - t0) * 1e6 / TICKS;
        mm_character_free(&c);
    }
    qsort(runs, RUNS, sizeof runs[0], compare);
    return runs[RUNS / 2];
}

/* median and p99 of n times (sorted in place) */
static void percentiles(double *t, int n, double *median, double *p99)
{
    qsort(t, (size_t)n, sizeof t[0], compare);
    *median = t[n / 2];
    *p99 = t[(int)floor(0.99 * (n - 1))];
}

int main(int argc, char **argv)
{
    int queries = 300, json = 0, count = 0;
    const char *paths[16];
    for (int i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--json") == 0)
            json = 1;
        else if (strcmp(argv[i], "--queries") == 0 && i + 1 < argc)
            queries = atoi(argv[++i]);
        else if (count < 16)
            paths[count++] = argv[i];
    }
    if (!count || queries < 10) {
        fprintf(stderr, "usage: bench_scale DB.mmdb... [--queries N] [--json]\n");
        return 2;
    }
    if (json) printf("{\"databases\": [");
    for (int k = 0; k < count; ++k) {
        mm_database db, small;
        mm_error err;
        memset(&err, 0, sizeof err);
        if (mm_database_load(paths[k], NULL, &db, &err) != MM_OK) {
            fprintf(stderr, "bench_scale: %s: %s\n", paths[k], err.message);
            return 1;
        }
        mm_db_compress_desc cd;
        memset(&cd, 0, sizeof cd);
        cd.threads = 2;
        if (db.pose_codec != MM_POSE_FLOATS || mm_database_compress(&db, &cd, &small, &err) != MM_OK) {
            fprintf(stderr, "bench_scale: %s: a database stored with floats is needed (%s)\n", paths[k],
                    err.message);
            return 1;
        }
        mm_searcher s;
        if (mm_searcher_init(&s, &db, NULL, &err) != MM_OK) return 1;
        mm_search_params p;
        mm_search_params_defaults(&db, &p);
        int dims = db.dims_padded;
        float *q = malloc(sizeof(float) * (size_t)dims);
        double *t[2][2]; /* [kind][method] */
        for (int a = 0; a < 2; ++a)
            for (int b = 0; b < 2; ++b) t[a][b] = malloc(sizeof(double) * (size_t)queries);
        for (int i = 0; i < queries; ++i) {
            int a = (int)(uniform() * db.frame_count), b = (int)(uniform() * db.frame_count);
            for (int kind = 0; kind < 2; ++kind) {
                mm_search_query_from_frames(&db, a, kind == 0 ? b : a, q);
                if (kind == 1)
                    for (int d = 0; d < db.dims; ++d)
                        q[d] += (float)(NOISE * (2.0 * uniform() - 1.0) * 1.7320508);
                p.current_frame = a;
                for (int m = 0; m < 2; ++m) {
                    mm_search_result r;
                    double t0 = now();
                    mm_searcher_search(&s, q, &p, m ? MM_SEARCH_FAST : MM_SEARCH_BRUTE, &r, 1);
                    t[kind][m][i] = (now() - t0) * 1e6;
                }
            }
        }
        double med[2][2], p99[2][2];
        for (int a = 0; a < 2; ++a)
            for (int b = 0; b < 2; ++b) percentiles(t[a][b], queries, &med[a][b], &p99[a][b]);
        double f = db.frame_count;
        size_t character = character_bytes(&db, &s);
        mm_searcher s_small;
        if (mm_searcher_init(&s_small, &small, NULL, &err) != MM_OK) return 1;
        double tick[2] = {tick_us(&db, &s), tick_us(&small, &s_small)};
        mm_searcher_free(&s_small);
        if (json)
            printf("%s{\"file\": \"%s\", \"frames\": %d, \"searcher_bytes\": %zu, \"character_bytes\": %zu, "
                   "\"tick_us\": {\"floats\": %.2f, \"compressed\": %.2f}, "
                   "\"bytes_per_frame\": %.1f, "
                   "\"pose_bytes_per_frame\": %.1f, "
                   "\"compressed_bytes_per_frame\": %.1f, \"compressed_pose_bytes_per_frame\": %.1f, "
                   "\"transition\": {\"brute_median_us\": %.1f, \"brute_p99_us\": %.1f, \"median_us\": %.1f, "
                   "\"p99_us\": %.1f}, \"near\": {\"brute_median_us\": %.1f, \"brute_p99_us\": %.1f, "
                   "\"median_us\": %.1f, \"p99_us\": %.1f}}",
                   k ? ", " : "", paths[k], db.frame_count, s.memory, character, tick[0], tick[1],
                   db.size / f, mm_database_pose_bytes(&db) / f, small.size / f,
                   mm_database_pose_bytes(&small) / f, med[0][0], p99[0][0], med[0][1], p99[0][1], med[1][0],
                   p99[1][0], med[1][1], p99[1][1]);
        else
            printf("%s: %d frames; file %.1f MB (%.0f bytes per frame), compressed %.1f MB (%.0f); poses "
                   "%.0f -> %.0f bytes per frame; searcher %.1f MB; a character %.1f KB\n"
                   "  a character's 60 Hz tick: %.1f us on the floats, %.1f us compressed\n"
                   "  transition queries: brute %.0f us median (p99 %.0f), fast %.1f us (p99 %.0f)\n"
                   "  near queries:       brute %.0f us median (p99 %.0f), fast %.1f us (p99 %.0f)\n",
                   paths[k], db.frame_count, db.size / 1e6, db.size / f, small.size / 1e6, small.size / f,
                   mm_database_pose_bytes(&db) / f, mm_database_pose_bytes(&small) / f, s.memory / 1e6,
                   character / 1024.0, tick[0], tick[1], med[0][0], p99[0][0], med[0][1], p99[0][1],
                   med[1][0], p99[1][0], med[1][1], p99[1][1]);
        for (int a = 0; a < 2; ++a)
            for (int b = 0; b < 2; ++b) free(t[a][b]);
        free(q);
        mm_searcher_free(&s);
        mm_database_free(&small);
        mm_database_free(&db);
    }
    if (json) printf("]}\n");
    return 0;
}
