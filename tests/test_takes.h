/* test_takes.h - hand-made takes for the database build tests: the nine-joint skeleton they are
 * made on (hips, spine, head, hands, feet and toes). */
#ifndef MM_TEST_TAKES_H
#define MM_TEST_TAKES_H

#include <mm/skeleton.h>

#include "test_util.h"

/* Hips `size` m up, a spine, the head 0.55 size above the hips, hands hanging beside the spine,
 * legs with the toes 0.95 size below the hips; the hands named left_hand and right_hand. */
static inline void test_take_skeleton_named(mm_skeleton *s, float size, const char *left_hand,
                                            const char *right_hand)
{
    assert_int_equal(mm_skeleton_init(s, 9, NULL), MM_OK);
    const char *names[9] = {"Hips",     "Spine2",  "Head",      left_hand, right_hand,
                            "LeftFoot", "LeftToe", "RightFoot", "RightToe"};
    const int parents[9] = {-1, 0, 1, 1, 1, 0, 5, 0, 7};
    const float off[9][3] = {{0, 1, 0},          {0, 0.3f, 0},       {0, 0.25f, 0},
                             {0.2f, -0.45f, 0},  {-0.2f, -0.45f, 0}, {0.1f, -0.9f, 0},
                             {0, -0.05f, 0.15f}, {-0.1f, -0.9f, 0},  {0, -0.05f, 0.15f}};
    for (int j = 0; j < 9; ++j) {
        snprintf(s->joints[j].name, MM_NAME_MAX, "%s", names[j]);
        s->joints[j].parent = parents[j];
        s->joints[j].offset = mm_vec3_make(off[j][0] * size, off[j][1] * size, off[j][2] * size);
        s->joints[j].order = MM_EULER_ZYX;
    }
    s->joints[0].flags = MM_JOINT_TRANSLATES;
}

/* The skeleton at 1 m hips with the hands named LeftHand and RightHand. */
static inline void test_take_skeleton(mm_skeleton *s)
{
    test_take_skeleton_named(s, 1.0f, "LeftHand", "RightHand");
}

#endif /* MM_TEST_TAKES_H */
