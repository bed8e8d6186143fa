/* test_hostile.h - hostile numbers for the per-tick functions: NaN, infinities, 3e38, 1e-30 and
 * zero mixed into ordinary values; whatever comes in, nothing non-finite may come out. */
#ifndef MM_TEST_HOSTILE_H
#define MM_TEST_HOSTILE_H

#include <math.h>

#include <mm/math.h>

#include "test_util.h"

static inline float hostile(test_rng *rng)
{
    static const float special[] = {NAN,   INFINITY, -INFINITY, 1e30f, -1e30f,
                                    3e38f, -3e38f,   0.0f,      -1.0f, 1e-30f};
    if (test_rng_next(rng) % 3 == 0) return special[test_rng_next(rng) % 10];
    return (float)test_rng_uniform(rng, -3.0, 3.0);
}

static inline mm_vec3 hostile3(test_rng *rng)
{
    return mm_vec3_make(hostile(rng), hostile(rng), hostile(rng));
}

static inline int finite_vec(mm_vec3 v) { return isfinite(v.x) && isfinite(v.y) && isfinite(v.z); }

#endif /* MM_TEST_HOSTILE_H */
