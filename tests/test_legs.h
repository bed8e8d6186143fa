/* test_legs.h - legs made by hand for the leg IK and stride warping tests, and the check that a
 * solved leg keeps its thigh and shin lengths. */
#ifndef MM_TEST_LEGS_H
#define MM_TEST_LEGS_H

#include <math.h>

#include <mm/leg_ik.h>

#include "test_hostile.h"
#include "test_util.h"

/* A leg with thigh and shin 0.45 m, the knee bent forward (+Z) toward the foot. */
static inline mm_leg_pose make_leg(mm_vec3 hip, mm_vec3 foot)
{
    const double l = 0.45;
    mm_vec3 d = mm_vec3_sub(foot, hip);
    double len = mm_vec3_length(d), h = sqrt(l * l - 0.25 * len * len);
    mm_vec3 u = mm_vec3_scale(d, (float)(1.0 / len));
    mm_vec3 fwd = mm_vec3_make(0, 0, 1);
    mm_vec3 n = mm_vec3_normalize(mm_vec3_sub(fwd, mm_vec3_scale(u, mm_vec3_dot(fwd, u))));
    mm_leg_pose leg;
    leg.hip = hip;
    leg.foot = foot;
    leg.knee =
        mm_vec3_add(hip, mm_vec3_add(mm_vec3_scale(u, (float)(0.5 * len)), mm_vec3_scale(n, (float)h)));
    return leg;
}

static inline void assert_lengths_kept(const mm_leg_pose *a, const mm_leg_pose *b)
{
    assert_near(mm_vec3_distance(a->hip, a->knee), mm_vec3_distance(b->hip, b->knee), 1e-5);
    assert_near(mm_vec3_distance(a->knee, a->foot), mm_vec3_distance(b->knee, b->foot), 1e-5);
}

/* Two legs (left at +X, right at -X), some with a hostile foot or hip (test_hostile.h's rng). */
static inline void hostile_legs(test_rng *rng, mm_leg_pose legs[2])
{
    for (int i = 0; i < 2; ++i) {
        legs[i] = make_leg(mm_vec3_make(0.1f - 0.2f * (float)i, 0.9f, 0.0f),
                           mm_vec3_make(0.1f, 0.1f, 0.2f - 0.4f * (float)i));
        if (test_rng_next(rng) % 4 == 0) legs[i].foot = hostile3(rng);
        if (test_rng_next(rng) % 8 == 0) legs[i].hip = hostile3(rng);
    }
}

#endif /* MM_TEST_LEGS_H */
