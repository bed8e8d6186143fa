/* test_util.h - shared helpers for the cmocka tests. */
#ifndef MM_TEST_UTIL_H
#define MM_TEST_UTIL_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

/* Path of a file in tests/data, in a static buffer; an absolute path is returned as it is. */
static inline const char *test_data_path(const char *relative)
{
    if (relative[0] == '/') return relative;
    static char buf[2048];
    snprintf(buf, sizeof buf, "%s/%s", MM_TEST_DATA, relative);
    return buf;
}

/* $MM_DATA_DIR/relative, or NULL when MM_DATA_DIR is unset (the caller then skips). */
static inline const char *test_shared_data(const char *relative, char *buf, size_t size)
{
    const char *dir = getenv("MM_DATA_DIR");
    if (!dir || !*dir) return NULL;
    snprintf(buf, size, "%s/%s", dir, relative);
    return buf;
}

/* A short take of the CMU skeleton (31 joints, ZYX channels, 120 fps, inches-like units), cut
 * from the shared data: the header and the first 4 frames of CMU_TAKE_SOURCE, written as it is
 * to MM_TEST_OUT/name. Returns that path (static buffer), or NULL without MM_DATA_DIR. */
#ifndef MM_TEST_OUT
#define MM_TEST_OUT "."
#endif
#define CMU_TAKE_SOURCE "pfnn/bvh/LocomotionFlat09_000.bvh"
#define CMU_TAKE_FRAMES 4
static inline const char *test_cmu_take(const char *name)
{
    static char out_path[1024], line[1 << 16];
    char source[1024];
    if (!test_shared_data(CMU_TAKE_SOURCE, source, sizeof source)) return NULL;
    snprintf(out_path, sizeof out_path, "%s/%s", MM_TEST_OUT, name);
    FILE *in = fopen(source, "rb"), *out = fopen(out_path, "wb");
    if (!in || !out) {
        fprintf(stderr, "cannot copy %s to %s\n", source, out_path);
        exit(1);
    }
    int motion_lines = -1; /* counts frames after the Frame Time line */
    while (motion_lines < CMU_TAKE_FRAMES && fgets(line, sizeof line, in)) {
        if (strncmp(line, "Frames:", 7) == 0)
            fprintf(out, "Frames: %d\n", CMU_TAKE_FRAMES);
        else
            fputs(line, out);
        if (motion_lines >= 0) ++motion_lines;
        if (strncmp(line, "Frame Time:", 11) == 0) motion_lines = 0;
    }
    fclose(in);
    fclose(out);
    return out_path;
}

/* For test programs that need the shared motion capture: when MM_DATA_DIR is unset, say so and
 * return 77, which CTest reports as skipped (SKIP_RETURN_CODE), not passed. */
#define TEST_SKIP_WITHOUT_DATA_DIR()                                                                         \
    do {                                                                                                     \
        const char *test_dir = getenv("MM_DATA_DIR");                                                        \
        if (!test_dir || !*test_dir) {                                                                       \
            printf("MM_DATA_DIR is not set: skipping the tests on shared motion capture\n");                 \
            return 77;                                                                                       \
        }                                                                                                    \
    } while (0)

/* Deterministic xorshift generator: tests never depend on rand(). */
typedef struct test_rng {
    uint64_t s;
} test_rng;
static inline uint64_t test_rng_next(test_rng *r)
{
    r->s ^= r->s << 13;
    r->s ^= r->s >> 7;
    r->s ^= r->s << 17;
    return r->s;
}
/* Uniform in [lo, hi). */
static inline double test_rng_uniform(test_rng *r, double lo, double hi)
{
    return lo + (hi - lo) * (double)(test_rng_next(r) >> 11) * (1.0 / 9007199254740992.0);
}

#define assert_near(a, b, tol)                                                                               \
    do {                                                                                                     \
        double assert_near_a = (double)(a), assert_near_b = (double)(b);                                     \
        if (!(fabs(assert_near_a - assert_near_b) <= (tol))) {                                               \
            print_error("%s = %.9g, expected %s = %.9g (tolerance %g)\n", #a, assert_near_a, #b,             \
                        assert_near_b, (double)(tol));                                                       \
            fail();                                                                                          \
        }                                                                                                    \
    } while (0)

#endif
