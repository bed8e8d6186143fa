/* Generation and writing speed of the built-in procedural motion set (mm/synth.h).
 *
 *   bench_synth [repetitions] [fps]
 *
 * On one core: the time to generate the whole set (best and median of the repetitions), the time
 * to write every clip as BVH text in memory (mm_bvh_write), and the set's size in clips, frames and
 * seconds of motion. The budget is the whole set in under 2 seconds. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <mm/bvh.h>
#include <mm/synth.h>

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int main(int argc, char **argv)
{
    int reps = argc > 1 ? atoi(argv[1]) : 5;
    float fps = argc > 2 ? (float)atof(argv[2]) : 60.0f;
    if (reps < 1) reps = 1;
    if (reps > 1000) reps = 1000;
    double *gen = (double *)malloc(sizeof(double) * (size_t)reps);
    double *write = (double *)malloc(sizeof(double) * (size_t)reps);
    if (!gen || !write) return 1;
    mm_synth_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.fps = fps;
    mm_error err;
    long frames = 0, bytes = 0;
    int clips = 0;
    double seconds = 0.0;
    for (int r = 0; r < reps; ++r) {
        mm_synth_set set;
        double t0 = now_seconds();
        if (mm_synth_generate(&desc, &set, &err) != MM_OK) {
            fprintf(stderr, "bench_synth: %s\n", err.message);
            return 1;
        }
        double t1 = now_seconds();
        frames = 0;
        bytes = 0;
        seconds = 0.0;
        clips = set.clip_count;
        for (int i = 0; i < set.clip_count; ++i) {
            char *text = NULL;
            size_t size = 0;
            if (mm_bvh_write(&set.clips[i].clip, NULL, &text, &size, &err) != MM_OK) {
                fprintf(stderr, "bench_synth: %s\n", err.message);
                return 1;
            }
            bytes += (long)size;
            frames += set.clips[i].clip.frame_count;
            seconds += set.clips[i].clip.frame_count / (double)set.clips[i].clip.fps;
            mm_free(NULL, text);
        }
        double t2 = now_seconds();
        gen[r] = t1 - t0;
        write[r] = t2 - t1;
        mm_synth_set_free(&set);
    }
    qsort(gen, (size_t)reps, sizeof(double), cmp_double);
    qsort(write, (size_t)reps, sizeof(double), cmp_double);
    printf("synth set: %d clips, %ld frames, %.1f s of motion at %g fps\n", clips, frames, seconds,
           (double)fps);
    printf("generate:  best %.1f ms, median %.1f ms (%.2f us per frame; budget 2000 ms)\n", gen[0] * 1e3,
           gen[reps / 2] * 1e3, gen[0] * 1e6 / (double)frames);
    printf("write BVH: best %.1f ms, median %.1f ms (%.1f MB of text)\n", write[0] * 1e3,
           write[reps / 2] * 1e3, (double)bytes / 1e6);
    free(gen);
    free(write);
    return 0;
}
