/* bench_pfnn: the phase-functioned network on the released weights ($MM_DATA_DIR/pfnn): load time
 * and memory of each mode, microseconds per network evaluation in each mode (phase advancing as at
 * run time, and at random phases), and the per-frame cost of the whole controller.
 * usage: bench_pfnn [EVALS]   Prints figures; never fails on speed. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <mm/pfnn.h>

#include "bench_common.h"

/* Median over 5 rounds of the mean microseconds per evaluation. random: 0 the phase advances by 0.1
 * rad per evaluation (a fast walk), 1 random phases, 2 always the same phase (weights stay in cache). */
static double time_evals(const mm_pfnn_network *net, mm_pfnn_mode mode, const float *x, int evals, int random)
{
    double rounds[5];
    float y[MM_PFNN_OUTPUT_DIM];
    volatile float sink = 0.0f;
    for (int r = 0; r < 5; ++r) {
        double phase = 0.0, t0 = now();
        for (int i = 0; i < evals; ++i) {
            phase = random == 1 ? 6.283185307179586 * uniform() : random == 2 ? 1.0 : phase + 0.1;
            mm_pfnn_network_eval(net, mode, (float)phase, x, y);
            sink += y[0];
        }
        rounds[r] = (now() - t0) * 1e6 / evals;
    }
    (void)sink;
    qsort(rounds, 5, sizeof rounds[0], compare);
    return rounds[2];
}

static double time_controller(const mm_pfnn_network *net, mm_pfnn_mode mode, mm_pfnn_symmetry symmetry,
                              int frames)
{
    mm_pfnn_controller_desc cd;
    memset(&cd, 0, sizeof cd);
    cd.network = net;
    cd.mode = mode;
    cd.symmetry = symmetry;
    cd.height = mm_pfnn_height_slopes;
    mm_pfnn_obstacle obs[4];
    memset(obs, 0, sizeof obs);
    for (int i = 0; i < 4; ++i) {
        obs[i].shape = i % 2 ? MM_PFNN_OBSTACLE_BOX : MM_PFNN_OBSTACLE_CIRCLE;
        obs[i].centre.x = 4.0f * (float)(i - 2);
        obs[i].centre.z = 3.0f;
        obs[i].radius = obs[i].half_x = obs[i].half_z = 0.7f;
    }
    cd.obstacles = obs;
    cd.obstacle_count = 4;
    mm_pfnn_controller *c = NULL;
    if (mm_pfnn_controller_create(&cd, &c, NULL) != MM_OK) return -1.0;
    mm_pfnn_input in;
    memset(&in, 0, sizeof in);
    double t0 = now();
    for (int f = 0; f < frames; ++f) {
        if (f % 90 == 0) {
            double a = 6.283185307179586 * uniform(), v = 4.0 * uniform();
            in.velocity.x = (float)(v * sin(a));
            in.velocity.z = (float)(v * cos(a));
            in.gait = (mm_pfnn_gait)(f / 90 % 3);
        }
        mm_pfnn_controller_step(c, &in, 1.0f / 60.0f);
    }
    double us = (now() - t0) * 1e6 / frames;
    mm_pfnn_controller_destroy(c);
    return us;
}

int main(int argc, char **argv)
{
    const char *data = getenv("MM_DATA_DIR");
    if (!data || !*data) {
        printf("bench_pfnn: MM_DATA_DIR is not set; skipped\n");
        return 0;
    }
    int evals = argc > 1 ? atoi(argv[1]) : 2000;
    if (evals < 1) evals = 2000;
    char dir[4096], path[4200];
    snprintf(dir, sizeof dir, "%s/pfnn", data);
    float x[MM_PFNN_INPUT_DIM];
    snprintf(path, sizeof path, "%s/reference/X_C_reset.bin", dir);
    FILE *f = fopen(path, "rb");
    if (!f || fread(x, 4, MM_PFNN_INPUT_DIM, f) != MM_PFNN_INPUT_DIM) {
        printf("bench_pfnn: cannot read %s\n", path);
        if (f) fclose(f);
        return 1;
    }
    fclose(f);
    printf("bench_pfnn: %d evaluations x 5 rounds per figure (median round), one thread\n", evals);
    /* controller us/f: mirror-averaged (the default, two evaluations a frame) and the network as
       released (one) */
    printf("%-9s %8s %8s %13s %13s %13s %16s %16s\n", "mode", "load s", "MiB", "us/eval step", "us/eval rand",
           "us/eval fixed", "ctrl us/f mirror", "ctrl us/f raw");
    for (int m = MM_PFNN_MODE_CONSTANT; m <= MM_PFNN_MODE_CUBIC; ++m) {
        mm_pfnn_network_desc d;
        memset(&d, 0, sizeof d);
        d.modes = MM_PFNN_MODE_BIT(m);
        mm_pfnn_network *net = NULL;
        mm_error err;
        double t0 = now();
        if (mm_pfnn_network_load(dir, &d, &net, &err) != MM_OK) {
            char buf[600];
            mm_error_format(&err, buf, sizeof buf);
            printf("bench_pfnn: %s\n", buf);
            return 1;
        }
        double load = now() - t0;
        double step = time_evals(net, (mm_pfnn_mode)m, x, evals, 0);
        double rnd = time_evals(net, (mm_pfnn_mode)m, x, evals, 1);
        double fixed = time_evals(net, (mm_pfnn_mode)m, x, evals, 2);
        int frames = 5 * evals > 6000 ? 6000 : 5 * evals;
        double ctrl = time_controller(net, (mm_pfnn_mode)m, MM_PFNN_SYMMETRY_MIRROR, frames);
        double raw = time_controller(net, (mm_pfnn_mode)m, MM_PFNN_SYMMETRY_NONE, frames);
        printf("%-9s %8.3f %8.1f %13.1f %13.1f %13.1f %16.1f %16.1f\n", mm_pfnn_mode_name((mm_pfnn_mode)m),
               load, (double)mm_pfnn_network_bytes(net, (mm_pfnn_mode)m) / (1024.0 * 1024.0), step, rnd,
               fixed, ctrl, raw);
        mm_pfnn_network_free(net);
    }
    return 0;
}
