/* How the JSON readers scale: a config of N clips (each with a range and a tag range, every 100th
 * a blend's source), an input script of N keys, each made in memory and read (parsed, checked
 * strictly, validated) the way mm config check and mm simulate read them; and the same config
 * with its last clip named like the first (the duplicate found at the very end).
 *
 *   bench_json [N...]          default: 1000 10000 100000
 *
 * Prints the best of 3 reads in milliseconds and the time per entry: a linear reader keeps the
 * time per entry flat as N grows (docs/reliability.md has the figures; issue 25 asks for 100,000
 * entries in under a second on the 2-core CI machine). Not a test: nothing here is timed against
 * a threshold. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <mm/config_json.h>
#include <mm/input_json.h>

#define BENCH_REPEATS 3

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Appends to a growing buffer. */
typedef struct text {
    char *s;
    size_t n, cap;
} text;

static void put(text *t, const char *fmt, int a, int b)
{
    if (t->cap - t->n < 256) {
        t->cap = t->cap ? 2 * t->cap : 1 << 16;
        t->s = (char *)realloc(t->s, t->cap);
        if (!t->s) exit(1);
    }
    t->n += (size_t)snprintf(t->s + t->n, t->cap - t->n, fmt, a, b);
}

static text make_config(int n, int duplicate_last)
{
    text t = {NULL, 0, 0};
    put(&t, "{\"tags\": [\"Walk\"], \"clips\": [\n", 0, 0);
    for (int i = 0; i < n; ++i)
        put(&t,
            "  {\"name\": \"clip%d\", \"file\": \"walk.bvh\", \"ranges\": [[0, %d]], "
            "\"tags\": {\"Walk\": [[0.0, 0.1]]}},\n",
            duplicate_last && i == n - 1 ? 0 : i, 10 + i % 7);
    put(&t, "  {\"name\": \"last\", \"file\": \"walk.bvh\"}],\n \"blend_clips\": [\n", 0, 0);
    for (int i = 0; i < n / 100; ++i)
        put(&t, "  {\"name\": \"mix%d\", \"left\": \"clip%d\", \"right\": \"last\"},\n", i, 100 * i);
    put(&t, "  {\"name\": \"mix\", \"left\": \"last\", \"right\": \"last\"}]}\n", 0, 0);
    return t;
}

static text make_script(int n)
{
    text t = {NULL, 0, 0};
    put(&t, "{\"keys\": [\n", 0, 0);
    for (int i = 0; i < n; ++i) put(&t, "  {\"t\": %d.%d, \"stick\": [0, 1], \"gait\": \"run\"},\n", i, 5);
    put(&t, "  {\"t\": %d, \"stick\": [0, 0]}]}\n", n + 1, 0);
    return t;
}

int main(int argc, char **argv)
{
    int sizes[16] = {1000, 10000, 100000}, count = 3;
    if (argc > 1) {
        count = 0;
        for (int i = 1; i < argc && count < 16; ++i) sizes[count++] = atoi(argv[i]);
    }
    printf("%-8s %-22s %10s %12s  %s\n", "entries", "read", "best ms", "us/entry", "result");
    for (int s = 0; s < count; ++s) {
        int n = sizes[s];
        for (int kind = 0; kind < 3; ++kind) {
            text t = kind == 2 ? make_script(n) : make_config(n, kind == 1);
            double best = 1e30;
            char result[160] = "";
            for (int r = 0; r < BENCH_REPEATS; ++r) {
                mm_error err;
                memset(&err, 0, sizeof err);
                double t0 = now_seconds();
                mm_result code;
                if (kind == 2) {
                    mm_input_script script;
                    code = mm_input_script_parse_json(t.s, t.n, "script.json", &script, &err);
                    if (code == MM_OK) mm_input_script_free(&script);
                } else {
                    mm_config cfg;
                    memset(&cfg, 0, sizeof cfg);
                    code = mm_config_parse_json(t.s, t.n, "config.json", ".", &cfg, &err);
                    if (code == MM_OK) mm_config_free(&cfg);
                }
                double dt = now_seconds() - t0;
                if (dt < best) best = dt;
                if (code == MM_OK)
                    snprintf(result, sizeof result, "ok");
                else
                    mm_error_format(&err, result, sizeof result);
            }
            static const char *const names[3] = {"config", "config, last repeats", "input script"};
            printf("%-8d %-22s %10.1f %12.3f  %s\n", n, names[kind], 1e3 * best, 1e6 * best / n, result);
            free(t.s);
        }
    }
    return 0;
}
