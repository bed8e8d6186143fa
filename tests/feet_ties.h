/* Two characters on databases that agree to rounding play the same frames, yet their feet can
 * part: a heel lock is released once its animated ankle is unlock_radius away, and a distance that
 * sits on the radius is decided by its last bit. feet_ties tells that tie from a real difference,
 * for the tests that compare such characters. */
#ifndef MM_TESTS_FEET_TIES_H
#define MM_TESTS_FEET_TIES_H

#include <math.h>

#include <mm/character.h>

#include "runtime/character/state.h"

#define FEET_TIE        1e-3f /* relative: a distance this close to unlock_radius is a tie */
#define FEET_LOCKS_SAME 1e-4f /* m: two characters' heel locks that agree */

/* The heel locks of the characters before a tick (NaN where a heel is not held). */
static inline void feet_ties_before(const mm_character c[2], mm_vec3 held[2][2])
{
    for (int i = 0; i < 2; ++i)
        for (int k = 0; k < 2; ++k)
            held[i][k] =
                c[i].state->feet.heel_locked[k] ? c[i].state->feet.heel_lock[k] : mm_vec3_make(NAN, NAN, NAN);
}

/* After the tick: whether their heel locks moved apart where a held lock was unlock_radius from its
 * animated ankle, within FEET_TIE (released in one run and not in the other). */
static inline int feet_unlock_tie(const mm_character c[2], mm_vec3 held[2][2])
{
    for (int k = 0; k < 2; ++k) {
        if (mm_vec3_distance(c[0].state->feet.heel_lock[k], c[1].state->feet.heel_lock[k]) < FEET_LOCKS_SAME)
            continue;
        for (int i = 0; i < 2; ++i) {
            float radius = c[i].state->desc.unlock_radius;
            float gap = mm_vec3_distance(held[i][k], c[i].state->feet.raw_contacts[2 * k]);
            if (fabsf(gap - radius) <= FEET_TIE * radius) return 1; /* NaN: not held */
        }
    }
    return 0;
}

/* After the tick: whether a foot is held in one character and not in the other (a landing or a
 * release a tick apart, decided by the last bits of its threshold: the landing's share, a foot
 * still aloft). */
static inline int feet_lock_tie(const mm_character c[2])
{
    for (int k = 0; k < 2; ++k)
        if (c[0].state->feet.locked[k] != c[1].state->feet.locked[k]) return 1;
    return 0;
}

#endif
