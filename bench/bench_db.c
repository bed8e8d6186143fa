/* bench_db: database build time (with 1, 2 and 4 threads, median of 3) and peak memory, bytes per
 * frame, load time.
 * usage: bench_db [CONFIG]   (default: lafan1.json made by scripts/data_configs.sh; clips found through
 * $MM_DATA_DIR) Prints figures; never fails on speed. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

#include <mm/config_json.h>
#include <mm/database_build.h>

#include "bench_common.h"

static double peak_mib(void)
{
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return ru.ru_maxrss / 1024.0;
}

int main(int argc, char **argv)
{
    const char *config = argc > 1 ? argv[1] : MM_DATA_CONFIGS "/lafan1.json";
    if (!getenv("MM_DATA_DIR")) {
        printf("bench_db: MM_DATA_DIR is not set; skipped\n");
        return 0;
    }
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_config cfg;
    memset(&cfg, 0, sizeof cfg);
    char *text = NULL;
    double t0 = now();
    if (mm_config_load_json(config, &cfg, &text, &err) != MM_OK) {
        fprintf(stderr, "bench_db: %s: %s (make it: cmake --build build --target data_configs)\n", err.file,
                err.message);
        return 1;
    }
    mm_clip *sources = NULL;
    if (mm_config_load_sources(&cfg, &sources, &err) != MM_OK) {
        fprintf(stderr, "bench_db: %s: %s\n", err.file, err.message);
        return 1;
    }
    double t1 = now();
    double mem_sources = peak_mib();
    mm_db_build_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.config_json = text;
    mm_database db;
    if (mm_database_build(&cfg, sources, &desc, &db, &err) != MM_OK) {
        fprintf(stderr, "bench_db: build: %s\n", err.message);
        return 1;
    }
    double t2 = now();
    /* the same build on 1, 2 and 4 threads: its time, and its bytes (which must not change) */
    double by_threads[3];
    for (int k = 0; k < 3; ++k) {
        double runs[3];
        for (int i = 0; i < 3; ++i) {
            mm_database other;
            desc.threads = 1 << k;
            double a = now();
            if (mm_database_build(&cfg, sources, &desc, &other, &err) != MM_OK) {
                fprintf(stderr, "bench_db: build: %s\n", err.message);
                return 1;
            }
            runs[i] = now() - a;
            if (other.size != db.size || memcmp(other.data, db.data, db.size) != 0) {
                fprintf(stderr, "bench_db: the build on %d threads gave other bytes\n", desc.threads);
                return 1;
            }
            mm_database_free(&other);
        }
        qsort(runs, 3, sizeof(double), compare);
        by_threads[k] = runs[1];
    }
    printf("config           %s\n", config);
    printf("read sources     %.3f s (%d clips)\n", t1 - t0, cfg.clip_count);
    printf("build            %.3f s for %d frames, %d clips, %d dims (%.1f us per frame)\n", t2 - t1,
           db.frame_count, db.clip_count, db.dims, 1e6 * (t2 - t1) / db.frame_count);
    printf("total            %.3f s (target: under 10 s on one core)\n", t2 - t0);
    printf("build threads    1: %.3f s, 2: %.3f s (x%.2f), 4: %.3f s (x%.2f), same bytes (median of 3)\n",
           by_threads[0], by_threads[1], by_threads[0] / by_threads[1], by_threads[2],
           by_threads[0] / by_threads[2]);
    printf("peak memory      %.1f MiB (%.1f MiB after reading the sources)\n", peak_mib(), mem_sources);
    printf("file size        %zu bytes, %.1f bytes per frame (features %zu, pose %zu)\n", db.size,
           (double)db.size / db.frame_count, sizeof(float) * (size_t)db.dims_padded,
           (sizeof(mm_quat) + sizeof(mm_vec3)) * (size_t)db.joint_count);
    char path[] = "/tmp/bench_db_XXXXXX";
    int fd = mkstemp(path);
    if (fd < 0 || mm_database_save(&db, path, &err) != MM_OK) {
        fprintf(stderr, "bench_db: cannot save\n");
        return 1;
    }
    double times[9];
    const char *modes[3] = {"map + checksum", "map, no checksum", "read + checksum"};
    for (int m = 0; m < 3; ++m) {
        mm_db_load_desc ld;
        memset(&ld, 0, sizeof ld);
        ld.skip_checksum = m == 1;
        ld.no_map = m == 2;
        for (int i = 0; i < 9; ++i) {
            mm_database loaded;
            double a = now();
            if (mm_database_load(path, &ld, &loaded, &err) != MM_OK) {
                fprintf(stderr, "bench_db: load: %s\n", err.message);
                return 1;
            }
            times[i] = now() - a;
            mm_database_free(&loaded);
        }
        qsort(times, 9, sizeof(double), compare);
        printf("load (%s) median %.2f ms, best %.2f ms (target: under 10 ms)\n", modes[m], 1e3 * times[4],
               1e3 * times[0]);
    }
    for (int i = 0; i < 9; ++i) {
        mm_database view;
        double a = now();
        if (mm_database_load_memory(db.data, db.size, false, &view, &err) != MM_OK) return 1;
        times[i] = now() - a;
    }
    qsort(times, 9, sizeof(double), compare);
    printf("load in place (validate, no checksum) median %.3f ms\n", 1e3 * times[4]);
    for (int i = 0; i < 9; ++i) {
        mm_database view;
        double a = now();
        if (mm_database_load_memory(db.data, db.size, true, &view, &err) != MM_OK) return 1;
        times[i] = now() - a;
    }
    qsort(times, 9, sizeof(double), compare);
    printf("load in place (validate + checksum) median %.3f ms (%.1f GB/s)\n", 1e3 * times[4],
           db.size / times[4] / 1e9);
    remove(path);
    mm_database_free(&db);
    mm_config_free_sources(&cfg, sources);
    mm_config_free(&cfg);
    free(text);
    return 0;
}
