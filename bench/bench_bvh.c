/* BVH reading and writing speed on real motion capture, and the fast number scanner against
 * strtod.
 *
 *   MM_DATA_DIR=/path/to/data bench_bvh [repetitions]
 *
 * Reads every BVH file in $MM_DATA_DIR/lafan1 into memory, then on one core measures mm_bvh_parse and
 * mm_bvh_write throughput (best and median of the repetitions), and mm__scan_double against
 * strtod over every number in lafan1, games105 and pfnn/bvh. Every scanned value must be
 * bit-identical to strtod's and end where strtod ends: the program prints PASS or FAIL and exits
 * non-zero on any mismatch. Without MM_DATA_DIR it says so and exits 0. */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <mm/bvh.h>

#include "io/numscan.h"

typedef struct file_data {
    char name[256];
    char *data;
    size_t size;
} file_data;

typedef struct file_list {
    file_data *files;
    int count, capacity;
    size_t bytes;
} file_list;

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int compare_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, compare_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

static double best(const double *v, int n)
{
    double b = v[0];
    for (int i = 1; i < n; ++i)
        if (v[i] < b) b = v[i];
    return b;
}

static char *read_whole(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    char *data = NULL;
    long n = -1;
    if (fseek(f, 0, SEEK_END) == 0) n = ftell(f);
    if (n >= 0 && fseek(f, 0, SEEK_SET) == 0 && (data = (char *)malloc((size_t)n + 1)) != NULL) {
        if (fread(data, 1, (size_t)n, f) != (size_t)n) {
            free(data);
            data = NULL;
        } else {
            data[n] = 0;
            *size = (size_t)n;
        }
    }
    fclose(f);
    return data;
}

static int compare_names(const void *a, const void *b)
{
    return strcmp(((const file_data *)a)->name, ((const file_data *)b)->name);
}

/* Appends every *.bvh in dir (sorted by name); returns 0 when dir cannot be read. */
static int read_folder(const char *dir_path, file_list *list)
{
    DIR *dir = opendir(dir_path);
    if (!dir) return 0;
    int first = list->count;
    struct dirent *d;
    while ((d = readdir(dir)) != NULL) {
        size_t len = strlen(d->d_name);
        if (len < 5 || strcmp(d->d_name + len - 4, ".bvh") != 0) continue;
        if (list->count == list->capacity) {
            int cap = list->capacity ? 2 * list->capacity : 16;
            file_data *f = (file_data *)realloc(list->files, (size_t)cap * sizeof *f);
            if (!f) break;
            list->files = f;
            list->capacity = cap;
        }
        file_data *f = &list->files[list->count];
        char path[2048];
        snprintf(path, sizeof path, "%s/%s", dir_path, d->d_name);
        snprintf(f->name, sizeof f->name, "%s", d->d_name);
        f->data = read_whole(path, &f->size);
        if (!f->data) {
            fprintf(stderr, "cannot read %s\n", path);
            continue;
        }
        list->bytes += f->size;
        ++list->count;
    }
    closedir(dir);
    qsort(list->files + first, (size_t)(list->count - first), sizeof *list->files, compare_names);
    return 1;
}

static void free_list(file_list *list)
{
    for (int i = 0; i < list->count; ++i) free(list->files[i].data);
    free(list->files);
    memset(list, 0, sizeof *list);
}

/* ---- parse and write ----------------------------------------------------------------------- */

static int bench_parse_write(const file_list *lafan, int reps)
{
    double *t = (double *)malloc((size_t)reps * sizeof(double));
    mm_bvh *bvh = (mm_bvh *)calloc((size_t)lafan->count, sizeof *bvh);
    mm_clip *clips = (mm_clip *)calloc((size_t)lafan->count, sizeof *clips);
    if (!t || !bvh || !clips) return 1;
    const double mb = (double)lafan->bytes / 1e6;
    long frames = 0;
    for (int r = 0; r < reps; ++r) {
        double t0 = now_seconds();
        for (int i = 0; i < lafan->count; ++i) {
            mm_error err;
            memset(&err, 0, sizeof err);
            if (mm_bvh_parse(lafan->files[i].data, lafan->files[i].size, NULL, &bvh[i], &err) != MM_OK) {
                char buf[600];
                mm_error_format(&err, buf, sizeof buf);
                fprintf(stderr, "%s: %s\n", lafan->files[i].name, buf);
                return 1;
            }
        }
        t[r] = now_seconds() - t0;
        if (r + 1 < reps)
            for (int i = 0; i < lafan->count; ++i) mm_bvh_free(&bvh[i]);
    }
    for (int i = 0; i < lafan->count; ++i) frames += bvh[i].frame_count;
    printf("parse:   %d files, %.1f MB, %ld frames\n", lafan->count, mb, frames);
    printf("         best %.3f s = %.1f MB/s, median %.3f s = %.1f MB/s (%d runs, one core)\n", best(t, reps),
           mb / best(t, reps), median(t, reps), mb / median(t, reps), reps);

    /* Writing: the clips converted from the parsed files, 9 significant digits (the default). */
    for (int i = 0; i < lafan->count; ++i) {
        mm_error err;
        if (mm_bvh_to_clip(&bvh[i], NULL, &clips[i], &err) != MM_OK) {
            fprintf(stderr, "%s: %s\n", lafan->files[i].name, err.message);
            return 1;
        }
        mm_bvh_free(&bvh[i]);
    }
    size_t written = 0;
    for (int r = 0; r < reps; ++r) {
        written = 0;
        double t0 = now_seconds();
        for (int i = 0; i < lafan->count; ++i) {
            char *text = NULL;
            size_t size = 0;
            mm_error err;
            if (mm_bvh_write(&clips[i], NULL, &text, &size, &err) != MM_OK) {
                fprintf(stderr, "%s: %s\n", lafan->files[i].name, err.message);
                return 1;
            }
            written += size;
            mm_free(NULL, text);
        }
        t[r] = now_seconds() - t0;
    }
    double wmb = (double)written / 1e6;
    printf("write:   %.1f MB of BVH text (9 significant digits)\n", wmb);
    printf("         best %.3f s = %.1f MB/s, median %.3f s = %.1f MB/s\n", best(t, reps),
           wmb / best(t, reps), median(t, reps), wmb / median(t, reps));
    for (int i = 0; i < lafan->count; ++i) mm_clip_free(&clips[i]);
    free(clips);
    free(bvh);
    free(t);
    return 0;
}

/* ---- number scanner ------------------------------------------------------------------------ */

typedef struct number_tokens {
    const char **start; /* into zero-terminated copies of the files */
    const char **end;
    long count, capacity;
} number_tokens;

static int is_sep(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == 0; }

/* Collects every token that starts like a number; the copies get a zero after each token so
 * strtod sees exactly the token. */
static int collect_numbers(char *data, size_t size, number_tokens *nt)
{
    char *p = data, *end = data + size;
    while (p < end) {
        while (p < end && is_sep(*p)) ++p;
        char *t = p;
        while (p < end && !is_sep(*p)) ++p;
        if (p == t) continue;
        char c = *t;
        if (!((c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.')) continue;
        if (nt->count == nt->capacity) {
            long cap = nt->capacity ? 2 * nt->capacity : 1 << 16;
            const char **s = (const char **)realloc((void *)nt->start, (size_t)cap * sizeof *s);
            if (!s) return 0;
            nt->start = s;
            const char **e = (const char **)realloc((void *)nt->end, (size_t)cap * sizeof *e);
            if (!e) return 0;
            nt->end = e;
            nt->capacity = cap;
        }
        nt->start[nt->count] = t;
        nt->end[nt->count] = p;
        ++nt->count;
        if (p < end) *p++ = 0;
    }
    return 1;
}

static int bench_scanner(file_list *all, int reps)
{
    number_tokens nt;
    memset(&nt, 0, sizeof nt);
    size_t chars = 0;
    for (int i = 0; i < all->count; ++i)
        if (!collect_numbers(all->files[i].data, all->files[i].size, &nt)) return 1;
    for (long i = 0; i < nt.count; ++i) chars += (size_t)(nt.end[i] - nt.start[i]);
    double *a = (double *)malloc((size_t)nt.count * sizeof(double));
    double *b = (double *)malloc((size_t)nt.count * sizeof(double));
    double *t = (double *)malloc((size_t)reps * sizeof(double));
    double *u = (double *)malloc((size_t)reps * sizeof(double));
    if (!a || !b || !t || !u) return 1;

    long not_ok = 0;
    for (int r = 0; r < reps; ++r) {
        double t0 = now_seconds();
        for (long i = 0; i < nt.count; ++i) {
            const char *stop;
            not_ok +=
                mm__scan_double(nt.start[i], nt.end[i], &a[i], &stop) != MM__SCAN_OK || stop != nt.end[i];
        }
        t[r] = now_seconds() - t0;
        t0 = now_seconds();
        for (long i = 0; i < nt.count; ++i) b[i] = strtod(nt.start[i], NULL);
        u[r] = now_seconds() - t0;
    }
    /* Bit-identical values, and strtod ends at the same place. */
    long mismatches = 0;
    for (long i = 0; i < nt.count; ++i) {
        char *e = NULL;
        double v = strtod(nt.start[i], &e);
        const char *stop = NULL;
        double w = 0;
        mm__scan_status st = mm__scan_double(nt.start[i], nt.end[i], &w, &stop);
        if (st != MM__SCAN_OK || stop != e || memcmp(&v, &w, sizeof v) != 0 ||
            memcmp(&a[i], &b[i], sizeof v)) {
            if (++mismatches <= 10)
                fprintf(stderr, "mismatch: '%s' strtod %.17g, scanner %.17g (status %d)\n", nt.start[i], v, w,
                        (int)st);
        }
    }
    double n = (double)nt.count;
    printf("numbers: %ld tokens (%.1f MB of text) in %d files\n", nt.count, (double)chars / 1e6, all->count);
    printf("         mm__scan_double best %.1f ns/number = %.0f M/s, median %.1f ns\n",
           1e9 * best(t, reps) / n, n / best(t, reps) / 1e6, 1e9 * median(t, reps) / n);
    printf("         strtod          best %.1f ns/number = %.0f M/s, median %.1f ns\n",
           1e9 * best(u, reps) / n, n / best(u, reps) / 1e6, 1e9 * median(u, reps) / n);
    printf("         speedup %.2fx (best), %.2fx (median)\n", best(u, reps) / best(t, reps),
           median(u, reps) / median(t, reps));
    int ok = mismatches == 0 && not_ok == 0;
    printf("%s: %ld of %ld numbers bit-identical to strtod (%ld mismatches)\n", ok ? "PASS" : "FAIL",
           nt.count - mismatches, nt.count, mismatches);
    free(a);
    free(b);
    free(t);
    free(u);
    free((void *)nt.start);
    free((void *)nt.end);
    return ok ? 0 : 1;
}

int main(int argc, char **argv)
{
    int reps = argc > 1 ? atoi(argv[1]) : 7;
    if (reps < 1) reps = 1;
    const char *dir = getenv("MM_DATA_DIR");
    if (!dir || !*dir) {
        printf("bench_bvh: MM_DATA_DIR is not set; nothing to measure (skipped)\n");
        return 0;
    }
    char path[2048];
    file_list lafan;
    memset(&lafan, 0, sizeof lafan);
    snprintf(path, sizeof path, "%s/lafan1", dir);
    if (!read_folder(path, &lafan) || lafan.count == 0) {
        fprintf(stderr, "bench_bvh: no BVH files in %s\n", path);
        return 1;
    }
    int status = bench_parse_write(&lafan, reps);

    /* The scanner runs over every data file; the copies get zeros between tokens. */
    file_list all;
    memset(&all, 0, sizeof all);
    static const char *const folders[] = {"lafan1", "games105", "pfnn/bvh"};
    for (size_t i = 0; i < sizeof folders / sizeof folders[0]; ++i) {
        snprintf(path, sizeof path, "%s/%s", dir, folders[i]);
        read_folder(path, &all);
    }
    status |= bench_scanner(&all, reps);
    free_list(&all);
    free_list(&lafan);
    return status;
}
