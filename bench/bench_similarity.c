/* bench_similarity: building the fusion and link tables on 1 and 2 threads, their memory, and the
 * run-time lookups (ns per call), on the built-in set (configs/synth.json: 23 loop clips, 20
 * one-shots; LAFAN1's config has no loop clips, so its tables would be empty).
 *
 * usage: bench_similarity [WINDOW] [cos|euclid]   (defaults 8, cos) */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <mm/config_json.h>
#include <mm/database_build.h>
#include <mm/similarity.h>
#include <mm/synth.h>

#include "bench_common.h"

static int build_database(mm_database *db)
{
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_config cfg;
    memset(&cfg, 0, sizeof cfg);
    if (mm_config_load_json(MM_SOURCE_DIR "/configs/synth.json", &cfg, NULL, &err) != MM_OK) return -1;
    mm_synth_desc sd;
    memset(&sd, 0, sizeof sd);
    mm_synth_set set;
    if (mm_synth_generate(&sd, &set, &err) != MM_OK) return -1;
    mm_clip *sources = calloc((size_t)cfg.clip_count, sizeof(mm_clip));
    for (int i = 0; i < cfg.clip_count; ++i)
        for (int k = 0; k < set.clip_count; ++k)
            if (strcmp(set.clips[k].name, cfg.clips[i].name) == 0)
                mm_clip_copy(&sources[i], &set.clips[k].clip, NULL);
    mm_synth_set_free(&set);
    mm_result r = mm_database_build(&cfg, sources, NULL, db, &err);
    if (r != MM_OK) fprintf(stderr, "bench_similarity: build: %s\n", err.message);
    mm_config_free_sources(&cfg, sources);
    mm_config_free(&cfg);
    return r == MM_OK ? 0 : -1;
}

static volatile int sink;

int main(int argc, char **argv)
{
    int window = argc > 1 ? atoi(argv[1]) : 8;
    mm_sim_measure measure = argc > 2 && strcmp(argv[2], "euclid") == 0 ? MM_SIM_EUCLIDEAN : MM_SIM_COSINE;
    mm_database db;
    if (build_database(&db) != 0) return 1;
    int loop_frames = 0;
    for (int c = 0; c < db.clip_count; ++c) loop_frames += db.clips[c].loop ? db.clips[c].frame_count : 0;
    printf("database: the built-in set: %d frames (%d in loop clips), %d clips, %d joints\n", db.frame_count,
           loop_frames, db.clip_count, db.joint_count);
    printf("measure %s, window %d, positions of %d joints\n", mm_sim_measure_name(measure), window,
           db.joint_count - 1);

    mm_sim_tables t[2];
    double seconds[2];
    for (int k = 0; k < 2; ++k) {
        mm_sim_desc d;
        memset(&d, 0, sizeof d);
        d.measure = measure;
        d.window = window;
        d.threads = k + 1;
        mm_error err;
        double t0 = now();
        if (mm_sim_tables_build(&db, &d, &t[k], &err) != MM_OK) {
            fprintf(stderr, "bench_similarity: %s\n", err.message);
            return 1;
        }
        seconds[k] = now() - t0;
        printf("build, %d thread%s: %.3f s\n", k + 1, k ? "s" : " ", seconds[k]);
    }
    printf("speed-up on 2 threads: %.2fx; identical: %s\n", seconds[0] / seconds[1],
           t[0].size == t[1].size && memcmp(t[0].data, t[1].data, t[0].size) == 0 ? "yes" : "NO");
    const mm_sim_tables *tb = &t[0];
    size_t fusion = (size_t)tb->fusion_rows * (size_t)tb->loop_count * sizeof(mm_sim_match);
    size_t link = (size_t)tb->link_rows * (size_t)tb->shot_count * sizeof(float);
    printf("memory: %zu bytes (%.2f MB): fusion %d rows x %d loop clips = %zu, link %d rows x %d one-shots = "
           "%zu, per-frame and per-clip index %zu\n",
           tb->size, (double)tb->size / 1048576.0, tb->fusion_rows, tb->loop_count, fusion, tb->link_rows,
           tb->shot_count, link, tb->size - fusion - link);

    /* lookups from random frames */
    enum { N = 2000000 };
    int *frames = malloc(sizeof(int) * N);
    uint64_t s = 0x9E3779B97F4A7C15ull;
    for (int i = 0; i < N; ++i) {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        frames[i] = (int)(s % (uint64_t)db.frame_count);
    }
    int acc = 0, loop0 = tb->loop_clips[0];
    double t0 = now();
    for (int i = 0; i < N; ++i) acc += mm_sim_fusion(tb, frames[i], loop0).frame;
    double ns = (now() - t0) / N * 1e9;
    printf("mm_sim_fusion (one loop clip, O(1)):           %6.1f ns\n", ns);
    t0 = now();
    for (int i = 0; i < N; ++i) acc += mm_sim_fusion_best(tb, frames[i], NULL);
    printf("mm_sim_fusion_best (%d loop clips):            %6.1f ns\n", tb->loop_count,
           (now() - t0) / N * 1e9);
    for (int rows = 1; rows <= 10; rows *= 10) {
        mm_sim_link_match m;
        t0 = now();
        for (int i = 0; i < N; ++i) acc += mm_sim_link(tb, frames[i], rows, NULL, 0, &m);
        printf("mm_sim_link (%d one-shots, %2d row%s):          %6.1f ns\n", tb->shot_count, rows,
               rows > 1 ? "s" : " ", (now() - t0) / N * 1e9);
    }
    sink = acc;
    free(frames);
    mm_sim_tables_free(&t[0]);
    mm_sim_tables_free(&t[1]);
    mm_database_free(&db);
    return 0;
}
