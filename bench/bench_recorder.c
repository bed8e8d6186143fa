/* bench_recorder: what recording costs a character: the bytes a tick takes in the recorder, the time
 * to record one (the snapshot, the pose, the candidates' terms), the tick with the top-K
 * candidates asked for against the winner alone (as a ratio, in one run), and a restore. LAFAN1
 * (lafan1.json, scripts/data_configs.sh) or the built-in set.
 * usage: bench_recorder [TOP_K]   Prints figures (and a JSON line); never fails on speed. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <mm/character.h>
#include <mm/input.h>
#include <mm/recorder.h>

#include "../tests/test_databases.h"

#include "bench_common.h"

#define TICKS      1200 /* 20 s at 60 Hz */
#define RING       600
#define TICK_DT    (1.0f / 60.0f)
#define RESTORES   200
#define INPUT_SEED 5u
#define LAPS       5

/* Seconds of TICKS updates of a character keeping k candidates (k 1: the winner alone), recording
 * into rec when given (record_s: the seconds recording took). */
static double run(const mm_database *db, const mm_searcher *s, const mm_character_desc *d,
                  const mm_input_script *script, int k, mm_recorder *rec, void *memory, size_t bytes,
                  double *record_s, mm_character *c)
{
    mm_character_init(c, db, s, d, NULL);
    mm_character_set_candidates(c, k, NULL);
    if (rec) mm_recorder_init(rec, memory, bytes, c, RING, k, NULL);
    double update = 0.0, record = 0.0;
    for (int t = 0; t < TICKS; ++t) {
        mm_input in;
        mm_input_script_sample_tick(script, t * TICK_DT, TICK_DT, &in);
        double a = now();
        mm_character_update(c, &in, TICK_DT);
        double b = now();
        if (rec) mm_recorder_record(rec, c, &in, TICK_DT);
        update += b - a;
        record += now() - b;
    }
    if (record_s) *record_s = record;
    return update;
}

int main(int argc, char **argv)
{
    int k = argc > 1 ? atoi(argv[1]) : 5;
    if (k < 1 || k > MM_RECORDER_MAX_CANDIDATES) k = 5;
    mm_database db;
    int lafan = 0;
    if (test_build_real_database(&db, &lafan) != 0) return 1;
    mm_searcher s;
    if (mm_searcher_init(&s, &db, NULL, NULL) != MM_OK) return 1;
    mm_character_desc desc;
    if (mm_character_desc_from_database(&desc, &db, NULL) != MM_OK) return 1;
    mm_input_script script;
    mm_input_random_desc rd = {TICKS * TICK_DT, 0, 0, 0, 0, NULL};
    mm_input_script_random(&script, INPUT_SEED, &rd);

    /* the tick with the winner alone and with the top k, runs taken in turn, the fastest of each
     * (a shared machine's noise only ever adds) */
    mm_character c;
    double alone = 1e30, top = 1e30;
    for (int lap = 0; lap < LAPS; ++lap) {
        double t1 = run(&db, &s, &desc, &script, 1, NULL, NULL, 0, NULL, &c);
        mm_character_free(&c);
        double tk = run(&db, &s, &desc, &script, k, NULL, NULL, 0, NULL, &c);
        mm_character_free(&c);
        if (t1 < alone) alone = t1;
        if (tk < top) top = tk;
    }
    mm_character probe;
    mm_character_init(&probe, &db, &s, &desc, NULL);
    size_t bytes = mm_recorder_bytes(&probe, RING, k);
    size_t snapshot = mm_character_snapshot_bytes(&probe);
    mm_character_free(&probe);
    void *memory = malloc(bytes);
    memset(memory, 0, bytes); /* its pages touched: the first lap of the ring is not timed with page faults */
    mm_recorder rec;
    double record = 0.0;
    run(&db, &s, &desc, &script, k, &rec, memory, bytes, &record, &c);
    double with_k = top;
    /* restores: back and forth over the ring */
    double a = now();
    for (int i = 0; i < RESTORES; ++i) mm_recorder_restore(&rec, (i * 37) % RING, &c, NULL);
    double restore = (now() - a) / RESTORES;
    printf("database: %s, %d frames, %d joints, %d dims\n", lafan ? "LAFAN1" : "built-in set", db.frame_count,
           db.joint_count, db.dims_padded);
    printf("recorder: %d ticks, top %d: %.2f MB (%.1f KB a tick; the state snapshot %.1f KB of it)\n", RING,
           k, bytes / 1e6, bytes / 1024.0 / RING, snapshot / 1024.0);
    printf("tick: %.2f us with the winner alone, %.2f us with the top %d (ratio %.3f)\n", 1e6 * alone / TICKS,
           1e6 * with_k / TICKS, k, with_k / alone);
    printf("record: %.2f us a tick; restore: %.2f us\n", 1e6 * record / TICKS, 1e6 * restore);
    printf("{\"bench\":\"recorder\",\"database\":\"%s\",\"top_k\":%d,\"bytes_per_tick\":%.0f,\"snapshot_"
           "bytes\":%zu,"
           "\"tick_us\":%.3f,\"tick_top_k_us\":%.3f,\"top_k_ratio\":%.4f,\"record_us\":%.3f,\"restore_us\":%."
           "3f}\n",
           lafan ? "lafan1" : "synth", k, (double)bytes / RING, snapshot, 1e6 * alone / TICKS,
           1e6 * with_k / TICKS, with_k / alone, 1e6 * record / TICKS, 1e6 * restore);
    mm_character_free(&c);
    free(memory);
    mm_input_script_free(&script);
    mm_searcher_free(&s);
    mm_database_free(&db);
    return 0;
}
