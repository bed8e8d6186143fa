/* bench_pose: the compressed poses (mm_database_compress): bytes per frame and the largest error for
 * a few bounds and segment lengths, the time to compress (1 and 2 threads), and the cost of reading
 * one frame's local transforms (mm_database_local_pose: a copy from the floats, a decode from the
 * segments), in the same run.
 * usage: bench_pose [DB.mmdb] [--json]   (default: builds lafan1.json made by scripts/data_configs.sh,
 * clips through $MM_DATA_DIR). Prints figures; never fails on speed. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <mm/config_json.h>
#include <mm/database_build.h>

#include "bench_common.h"

/* frames read per timing, and timings per figure (the median is printed) */
#define READS 200000
#define RUNS  5

static int load_or_build(const char *path, mm_database *db)
{
    mm_error err;
    memset(&err, 0, sizeof err);
    if (path) {
        if (mm_database_load(path, NULL, db, &err) == MM_OK) return 0;
        fprintf(stderr, "bench_pose: %s: %s\n", path, err.message);
        return 1;
    }
    mm_config cfg;
    memset(&cfg, 0, sizeof cfg);
    char *text = NULL;
    if (mm_config_load_json(MM_DATA_CONFIGS "/lafan1.json", &cfg, &text, &err) != MM_OK) {
        fprintf(stderr, "bench_pose: %s: %s (make it: cmake --build build --target data_configs)\n", err.file,
                err.message);
        return 1;
    }
    mm_clip *sources = NULL;
    mm_result r = mm_config_load_sources(&cfg, &sources, &err);
    mm_db_build_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.config_json = text;
    desc.threads = 2;
    if (r == MM_OK) r = mm_database_build(&cfg, sources, &desc, db, &err);
    if (r != MM_OK) fprintf(stderr, "bench_pose: %s\n", err.message);
    mm_config_free_sources(&cfg, sources);
    mm_config_free(&cfg);
    free(text);
    return r == MM_OK ? 0 : 1;
}

/* ns per frame read by mm_database_local_pose over READS frames in a fixed random order (median of
 * RUNS); whole: every joint, else one joint (mm_database_local_joint) */
static double read_ns(const mm_database *db, int whole)
{
    mm_quat *rot = malloc(sizeof(mm_quat) * (size_t)db->joint_count);
    mm_vec3 *pos = malloc(sizeof(mm_vec3) * (size_t)db->joint_count);
    double runs[RUNS], sink = 0.0;
    for (int k = 0; k < RUNS; ++k) {
        uint32_t seed = 99u;
        double t = now();
        for (int i = 0; i < READS; ++i) {
            seed = seed * 1664525u + 1013904223u;
            int f = (int)(seed % (uint32_t)db->frame_count);
            if (whole) {
                mm_database_local_pose(db, f, rot, pos);
            } else {
                mm_database_local_joint(db, f, db->joint_count - 1, rot, pos);
            }
            sink += rot[0].w;
        }
        runs[k] = (now() - t) * 1e9 / READS;
    }
    qsort(runs, RUNS, sizeof runs[0], compare);
    free(rot);
    free(pos);
    if (sink == 12345.0) printf(" ");
    return runs[RUNS / 2];
}

int main(int argc, char **argv)
{
    const char *path = NULL;
    int json = 0;
    for (int i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--json") == 0)
            json = 1;
        else
            path = argv[i];
    }
    if (!path && !getenv("MM_DATA_DIR")) {
        printf("bench_pose: MM_DATA_DIR is not set and no database given; skipped\n");
        return 0;
    }
    mm_database floats;
    if (load_or_build(path, &floats)) return 1;
    if (floats.pose_codec != MM_POSE_FLOATS) {
        fprintf(stderr, "bench_pose: the database is compressed already\n");
        return 1;
    }
    const float bounds[3] = {0.0005f, 0.0001f, 0.002f};
    const int segments[3] = {16, 32, 64};
    mm_database small;
    mm_error err;
    memset(&err, 0, sizeof err);
    if (json)
        printf("{\"database\": {\"frames\": %d, \"joints\": %d, \"bytes_per_frame\": %.2f, "
               "\"pose_bytes_per_frame\": "
               "%.2f}, \"compressed\": [",
               floats.frame_count, floats.joint_count, (double)floats.size / floats.frame_count,
               (double)mm_database_pose_bytes(&floats) / floats.frame_count);
    else
        printf("database: %d frames, %d joints; floats: file %.1f bytes per frame, poses %.1f\n",
               floats.frame_count, floats.joint_count, (double)floats.size / floats.frame_count,
               (double)mm_database_pose_bytes(&floats) / floats.frame_count);
    int rows = 0;
    for (int b = 0; b < 3; ++b)
        for (int s = 0; s < 3; ++s) {
            if (b > 0 && segments[s] != MM_POSE_SEGMENT_FRAMES_DEFAULT) continue;
            mm_db_compress_desc desc;
            memset(&desc, 0, sizeof desc);
            desc.error_bound = bounds[b];
            desc.segment_frames = segments[s];
            double times[2];
            for (int threads = 1; threads <= 2; ++threads) {
                desc.threads = threads;
                double t = now();
                if (mm_database_compress(&floats, &desc, &small, &err) != MM_OK) {
                    fprintf(stderr, "bench_pose: %s\n", err.message);
                    return 1;
                }
                times[threads - 1] = now() - t;
                if (threads == 1) mm_database_free(&small);
            }
            double pose = (double)mm_database_pose_bytes(&small) / small.frame_count;
            double file = (double)small.size / small.frame_count;
            double ns = 0.0;
            if (bounds[b] == MM_POSE_ERROR_DEFAULT) ns = read_ns(&small, 1);
            if (json)
                printf(
                    "%s{\"error_bound_mm\": %.3g, \"segment_frames\": %d, \"pose_bytes_per_frame\": %.2f, "
                    "\"bytes_per_frame\": %.2f, \"max_joint_error_mm\": %.4f, \"compress_s\": {\"1\": %.3f, "
                    "\"2\": %.3f}, \"decode_ns_per_frame\": %.1f}",
                    rows++ ? ", " : "", 1000.0 * bounds[b], segments[s], pose, file,
                    1000.0 * small.compressed.max_error, times[0], times[1], ns);
            else
                printf("bound %.2f mm, segments of %2d: poses %6.1f bytes per frame (%.1f%% of the floats), "
                       "file "
                       "%6.1f; largest error %.3f mm; compress %.2f s (1 thread) %.2f s (2)%s",
                       1000.0 * bounds[b], segments[s], pose,
                       100.0 * pose / ((double)mm_database_pose_bytes(&floats) / floats.frame_count), file,
                       1000.0 * small.compressed.max_error, times[0], times[1], ns > 0 ? "; " : "\n");
            if (!json && ns > 0) printf("decode %.0f ns per frame\n", ns);
            if (bounds[b] == MM_POSE_ERROR_DEFAULT && segments[s] == MM_POSE_SEGMENT_FRAMES_DEFAULT) {
                double copy = read_ns(&floats, 1), joint = read_ns(&small, 0),
                       joint_copy = read_ns(&floats, 0);
                if (json)
                    printf(", {\"read_ns_per_frame\": {\"floats\": %.1f, \"compressed\": %.1f}, "
                           "\"read_ns_per_joint\": {\"floats\": %.1f, \"compressed\": %.1f}}",
                           copy, ns, joint_copy, joint);
                else
                    printf(
                        "  a frame's %d joints: %.0f ns copied from the floats, %.0f ns decoded (x%.1f); one "
                        "joint: %.0f ns, %.0f ns\n",
                        floats.joint_count, copy, ns, ns / copy, joint_copy, joint);
            }
            mm_database_free(&small);
        }
    if (json) printf("]}\n");
    mm_database_free(&floats);
    return 0;
}
