/* test_takes.h - hand-made takes for the database build tests: the nine-joint skeleton they are
 * made on (hips, spine, head, hands, feet and toes) and the config that lists them. */
#ifndef MM_TEST_TAKES_H
#define MM_TEST_TAKES_H

#include <mm/config.h>
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

enum { TEST_TAKES_MAX = 8 };

/* Takes and the config that names them: clips[i] is the source of cfg.clips[i]. */
typedef struct test_takes {
    mm_clip clips[TEST_TAKES_MAX];
    mm_config cfg;
} test_takes;

/* No takes yet, in a config at scale 1 without root smoothing (the roots as made). */
static inline void test_takes_start(test_takes *t)
{
    memset(t, 0, sizeof *t);
    mm_config_defaults(&t->cfg);
    t->cfg.scale = 1.0f;
    t->cfg.root_smoothing = 0.0f;
    t->cfg.clips = (mm_config_clip *)calloc(TEST_TAKES_MAX, sizeof(mm_config_clip));
}

/* A take named name (file name.bvh) of type in the config: its clip, to be made by the caller. */
static inline mm_clip *test_takes_add(test_takes *t, const char *name, mm_clip_type type)
{
    assert_true(t->cfg.clip_count < TEST_TAKES_MAX);
    mm_config_clip *c = &t->cfg.clips[t->cfg.clip_count];
    snprintf(c->name, MM_NAME_MAX, "%s", name);
    snprintf(c->file, MM_PATH_MAX, "%s.bvh", name);
    c->type = type;
    return &t->clips[t->cfg.clip_count++];
}

static inline void test_takes_free(test_takes *t)
{
    for (int i = 0; i < t->cfg.clip_count; ++i) mm_clip_free(&t->clips[i]);
    mm_config_free(&t->cfg);
}

#endif /* MM_TEST_TAKES_H */
