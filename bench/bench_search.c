/* bench_search: microseconds per query for each search method and three kinds of query, the
 * work pruned, and batch throughput, on the LAFAN1 database (lafan1.json, made from $MM_DATA_DIR
 * by `cmake --build build --target data_configs` or the tests) or the built-in motion set when MM_DATA_DIR is
 * unset. usage: bench_search [QUERIES]   Prints figures; never fails on speed. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <mm/config_json.h>
#include <mm/database_build.h>
#include <mm/search.h>
#include <mm/synth.h>

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int compare(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static uint64_t rng = 0x9E3779B97F4A7C15ull;
static double uniform(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return (double)(rng >> 11) / 9007199254740992.0;
}
static double normal(void)
{
    double u = uniform() + 1e-12, v = uniform();
    return sqrt(-2.0 * log(u)) * cos(2.0 * MM_PI * v);
}

static int build_database(mm_database *db, const char **name)
{
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_config cfg;
    memset(&cfg, 0, sizeof cfg);
    mm_clip *sources = NULL;
    char *text = NULL;
    if (getenv("MM_DATA_DIR")) {
        *name = "LAFAN1 (lafan1.json)";
        if (mm_config_load_json(MM_DATA_CONFIGS "/lafan1.json", &cfg, &text, &err) != MM_OK ||
            mm_config_load_sources(&cfg, &sources, &err) != MM_OK) {
            fprintf(stderr, "bench_search: %s: %s (make it: cmake --build build --target data_configs)\n",
                    err.file, err.message);
            return -1;
        }
    } else {
        *name = "the built-in set (configs/synth.json; set MM_DATA_DIR for LAFAN1)";
        if (mm_config_load_json(MM_SOURCE_DIR "/configs/synth.json", &cfg, &text, &err) != MM_OK) return -1;
        mm_synth_desc sd;
        memset(&sd, 0, sizeof sd);
        mm_synth_set set;
        if (mm_synth_generate(&sd, &set, &err) != MM_OK) return -1;
        sources = calloc((size_t)cfg.clip_count, sizeof(mm_clip));
        for (int i = 0; i < cfg.clip_count; ++i)
            for (int k = 0; k < set.clip_count; ++k)
                if (strcmp(set.clips[k].name, cfg.clips[i].name) == 0)
                    mm_clip_copy(&sources[i], &set.clips[k].clip, NULL);
        mm_synth_set_free(&set);
    }
    mm_db_build_desc desc;
    memset(&desc, 0, sizeof desc);
    mm_result r = mm_database_build(&cfg, sources, &desc, db, &err);
    if (r != MM_OK) fprintf(stderr, "bench_search: build: %s\n", err.message);
    mm_config_free_sources(&cfg, sources);
    mm_config_free(&cfg);
    free(text);
    return r == MM_OK ? 0 : -1;
}

int main(int argc, char **argv)
{
    int n = argc > 1 ? atoi(argv[1]) : 2000;
    if (n < 10) n = 10;
    mm_database db;
    const char *name;
    if (build_database(&db, &name) != 0) return 1;
    printf("database: %s: %d frames x %d dims (%d padded)\n", name, db.frame_count, db.dims, db.dims_padded);
    mm_searcher s;
    mm_error err;
    if (mm_searcher_init(&s, &db, NULL, &err) != MM_OK) return 1;
    mm_search_params p;
    mm_search_params_defaults(&db, &p);
    int dims = db.dims_padded;
    float *queries = malloc(sizeof(float) * (size_t)dims * (size_t)n * 3);
    int *current = malloc(sizeof(int) * (size_t)n);
    for (int i = 0; i < n; ++i) {
        int a = (int)(uniform() * db.frame_count), b = (int)(uniform() * db.frame_count);
        current[i] = a;
        mm_search_query_from_frames(&db, a, b, queries + (size_t)(0 * n + i) * dims);
        float *q = queries + (size_t)(1 * n + i) * dims;
        mm_search_query_from_frames(&db, a, a, q);
        for (int d = 0; d < db.dims; ++d) q[d] += (float)(0.1 * normal());
        q = queries + (size_t)(2 * n + i) * dims;
        memset(q, 0, sizeof(float) * (size_t)dims);
        for (int d = 0; d < db.dims; ++d) q[d] = (float)normal();
    }
    const char *kinds[3] = {"(a) pose of i, trajectory of j", "(b) frame i + noise 0.1", "(c) random normal"};
    double *t = malloc(sizeof(double) * (size_t)n);
    mm_search_result *found[3];
    for (int m = 0; m < 3; ++m) found[m] = malloc(sizeof(mm_search_result) * (size_t)n);
    double brute_median[3] = {0};
    int mismatches = 0;
    for (int kind = 0; kind < 3; ++kind) {
        printf("\n%s, %d queries:\n", kinds[kind], n);
        for (int m = 0; m < 3; ++m) { /* each method in its own loop: no cache pollution between them */
            double evaluated = 0, boxes = 0;
            for (int i = 0; i < n; ++i) {
                const float *q = queries + (size_t)(kind * n + i) * dims;
                p.current_frame = current[i];
                mm_search_stats st;
                double a = now();
                mm_searcher_search_stats(&s, q, &p, (mm_search_method)m, &found[m][i], 1, &st);
                t[i] = now() - a;
                evaluated += st.frames_evaluated;
                boxes += st.boxes_tested;
            }
            qsort(t, (size_t)n, sizeof(double), compare);
            double median = 1e6 * t[n / 2], p99 = 1e6 * t[(int)(0.99 * (n - 1))];
            if (m == MM_SEARCH_BRUTE) brute_median[kind] = median;
            printf(
                "  %-6s median %8.1f us  p99 %8.1f us  %6.1fx brute  frames evaluated %6.2f%%  boxes %6.0f\n",
                mm_search_method_name((mm_search_method)m), median, p99, brute_median[kind] / median,
                100.0 * evaluated / n / db.frame_count, boxes / n);
        }
        int agree = 0;
        for (int i = 0; i < n; ++i) {
            mismatches += found[MM_SEARCH_FAST][i].frame != found[MM_SEARCH_BRUTE][i].frame;
            agree += found[MM_SEARCH_FACING][i].frame == found[MM_SEARCH_BRUTE][i].frame;
        }
        printf("  facing (approximate) agrees with brute force on %.1f%% of queries\n", 100.0 * agree / n);
    }
    printf("\nexact method vs brute force: %d mismatches in %d queries\n", mismatches, 3 * n);
    printf(
        "acceleration structure: %d nodes of %d lanes, boxes on %d of %d axes, %.1f MB (of which %.1f MB the "
        "features in tree order)\n",
        s.node_count, MM_SEARCH_WIDTH, s.tree_dims, dims, s.memory / 1e6,
        (double)db.frame_count * dims * 4 / 1e6);

    /* Batch throughput, kind (b), on 1 and 2 threads. */
    mm_search_result *res = malloc(sizeof(mm_search_result) * (size_t)n);
    mm_search_params *ps = malloc(sizeof(mm_search_params) * (size_t)n);
    for (int i = 0; i < n; ++i) {
        ps[i] = p;
        ps[i].current_frame = current[i];
    }
    int first_1 = -1;
    for (int threads = 1; threads <= 2; ++threads) {
        mm_searcher sb;
        mm_searcher_desc sd = {threads, NULL};
        mm_searcher_init(&sb, &db, &sd, &err);
        double best = 1e9;
        for (int rep = 0; rep < 5; ++rep) {
            double a = now();
            mm_searcher_batch(&sb, queries + (size_t)n * dims, ps, 1, MM_SEARCH_FAST, res, n);
            double e = now() - a;
            if (e < best) best = e;
        }
        if (threads == 1) first_1 = res[n / 2].frame;
        printf("batch (b), %d thread%s: %.0f queries/s%s\n", sb.threads, sb.threads > 1 ? "s" : "", n / best,
               threads == 2 && res[n / 2].frame != first_1 ? "  (RESULT DIFFERS)" : "");
        mm_searcher_free(&sb);
    }
    free(res);
    free(ps);
    free(t);
    for (int m = 0; m < 3; ++m) free(found[m]);
    free(queries);
    free(current);
    mm_searcher_free(&s);
    mm_database_free(&db);
    return mismatches ? 1 : 0;
}
