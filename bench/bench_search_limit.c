/* bench_search_limit: what a first limit (an upper bound known before the descent) is worth to the
 * exact search. The same queries timed three ways, each way in its own loop (no cache shared
 * between them), each query's least time of REPEATS passes:
 *   plain    no current frame: the descent starts with no limit;
 *   guessed  the better of two cheap guesses taken first: the frame nearest in pose alone and the
 *            frame nearest in trajectory alone (found here by brute force, untimed: what a pose-only
 *            and a trajectory-only index would return), their exact costs;
 *   perfect  the winner itself taken first (its exact cost, the lowest: no first limit can do better).
 * A frame is taken first by making the frame before it the current one (with a next-pose favour
 * of 1 and no bias its cost is its plain cost); the current frame itself is then not a candidate,
 * which the plain and the guessed runs share by the same rule (the current frame of each run
 * differs, so the answers are compared with brute force's under each run's own parameters).
 *
 * usage: bench_search_limit [transition|near] [--cold] [QUERIES]   (default transition, 500)
 * LAFAN1 when MM_DATA_DIR is set (as bench_search). Prints figures; exit 1 on a wrong answer. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <mm/search.h>

#include "../tests/test_databases.h"

#include "bench_common.h"

#define REPEATS    7
#define NEAR_NOISE 0.1
#define WAYS       3

static const char *const WAY_NAMES[WAYS] = {"plain", "guessed", "perfect"};

static float total_cost(const mm_database *db, const float *q, const mm_search_params *p, int frame)
{
    mm_search_terms t;
    mm_search_cost_terms(db, q, p, frame, &t);
    return t.pose_position + t.pose_velocity + t.root_velocity + t.traj_position + t.traj_direction;
}

/* Parameters that take frame f first (or none when f has no frame before it). */
static void take_first(mm_search_params *p, const mm_search_params *plain, int f)
{
    *p = *plain;
    p->current_frame = f > 0 ? f - 1 : -1;
}

int main(int argc, char **argv)
{
    int n = 500, cold = 0, near = 0;
    for (int i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--cold") == 0)
            cold = 1;
        else if (strcmp(argv[i], "near") == 0)
            near = 1;
        else if (strcmp(argv[i], "transition") != 0)
            n = atoi(argv[i]);
    }
    if (n < 10) n = 10;
    mm_database db;
    int lafan = 0;
    if (test_build_real_database(&db, &lafan) != 0) return 1;
    mm_searcher s;
    mm_error err;
    if (mm_searcher_init(&s, &db, NULL, &err) != MM_OK) return 1;
    unsigned char *sweep_buffer = calloc(BENCH_COLD_SWEEP_BYTES, 1);
    int dims = db.dims_padded;
    float *q = calloc((size_t)n * dims, sizeof(float));
    mm_search_params *p[WAYS];
    double *t[WAYS], guess_ratio = 0.0;
    long work[WAYS][3] = {{0}};
    int missing = !sweep_buffer || !q;
    for (int w = 0; w < WAYS; ++w) {
        p[w] = calloc((size_t)n, sizeof(mm_search_params));
        t[w] = malloc(sizeof(double) * (size_t)n);
        missing |= !p[w] || !t[w];
    }
    if (missing) {
        fprintf(stderr, "bench_search_limit: out of memory\n");
        return 1;
    }
    for (int i = 0; i < n; ++i) {
        float *qi = q + (size_t)i * dims;
        int a = (int)(uniform() * db.frame_count) % db.frame_count,
            b = (int)(uniform() * db.frame_count) % db.frame_count;
        mm_search_query_from_frames(&db, a, near ? a : b, qi);
        for (int d = 0; near && d < db.dims; ++d) qi[d] += (float)(NEAR_NOISE * normal());
        mm_search_params_defaults(&db, &p[0][i]);
        p[0][i].current_frame = -1;
        p[0][i].next_pose_favour = 1.0f;
        p[0][i].continuing_bias = 0.0f;
        mm_search_result best, pose, traj;
        mm_searcher_search(&s, qi, &p[0][i], MM_SEARCH_BRUTE, &best, 1);
        mm_search_params only = p[0][i];
        only.pose_trajectory_ratio = 0.0f;
        mm_searcher_search(&s, qi, &only, MM_SEARCH_BRUTE, &pose, 1);
        only.pose_trajectory_ratio = 1.0f;
        mm_searcher_search(&s, qi, &only, MM_SEARCH_BRUTE, &traj, 1);
        float cp = total_cost(&db, qi, &p[0][i], pose.frame), ct = total_cost(&db, qi, &p[0][i], traj.frame);
        guess_ratio += (cp < ct ? cp : ct) / best.cost;
        take_first(&p[1][i], &p[0][i], cp < ct ? pose.frame : traj.frame);
        take_first(&p[2][i], &p[0][i], best.frame);
    }
    int wrong = 0;
    for (int w = 0; w < WAYS; ++w) {
        for (int i = 0; i < n; ++i) t[w][i] = INFINITY;
        for (int r = 0; r < REPEATS; ++r)
            for (int i = 0; i < n; ++i) {
                const float *qi = q + (size_t)i * dims;
                if (cold) bench_cold_sweep(sweep_buffer);
                mm_search_result res;
                mm_search_stats st;
                double start = now();
                mm_searcher_search_stats(&s, qi, &p[w][i], MM_SEARCH_FAST, &res, 1, &st);
                double took = now() - start;
                if (took < t[w][i]) t[w][i] = took;
                if (r) continue;
                work[w][0] += st.boxes_tested;
                work[w][1] += st.frames_bounded;
                work[w][2] += st.frames_evaluated;
                mm_search_result brute;
                mm_searcher_search(&s, qi, &p[w][i], MM_SEARCH_BRUTE, &brute, 1);
                wrong += brute.frame != res.frame;
            }
        qsort(t[w], (size_t)n, sizeof(double), compare);
    }
    printf("%s, %s queries, %s caches, %d queries, least of %d: the better guess costs %.2f x the lowest\n",
           lafan ? "LAFAN1" : "built-in set", near ? "near" : "transition", cold ? "cold" : "warm", n,
           REPEATS, guess_ratio / n);
    for (int w = 0; w < WAYS; ++w)
        printf("%-8s median %6.1f us  p99 %6.1f us  boxes %5.0f  bounded %6.0f  exact %6.1f\n", WAY_NAMES[w],
               1e6 * t[w][n / 2], 1e6 * t[w][(int)(0.99 * (n - 1) + 0.5)], (double)work[w][0] / n,
               (double)work[w][1] / n, (double)work[w][2] / n);
    printf("answers unlike brute force's: %d\n", wrong);
    for (int w = 0; w < WAYS; ++w) free(p[w]), free(t[w]);
    free(q);
    free(sweep_buffer);
    mm_searcher_free(&s);
    mm_database_free(&db);
    return wrong ? 1 : 0;
}
