/* mm/input.h - what the player asks for: stick, gait, strafe, facing; scripted and random.
 *
 * An input script is a list of keys in time; a key holds until the next. Scripts are read from
 * JSON (mm/input_json.h) in the form
 *   {"keys": [{"t": 0.0, "stick": [x, z], "gait": "walk", "strafe": false, "facing": [x, z]}, ...]}
 * with the stick's x to the right and z forward in world space, magnitude at most 1, and facing
 * optional (the direction to face while strafing). A key may carry "jump": true, one press of
 * the jump button at the key's time (mm/moves.h). mm_input_script_random makes scripts of the
 * same form from a seed (it never presses jump).
 *
 * The gaits and their names are in mm/gait.h.
 *
 * Functions: mm_input_gait mm_input_script_init mm_input_script_free mm_input_script_validate
 *            mm_input_script_sample mm_input_script_sample_tick mm_input_script_random
 */
#ifndef MM_INPUT_H
#define MM_INPUT_H

#include <stdbool.h>
#include <stdint.h>

#include "alloc.h"
#include "gait.h"
#include "math.h"
#include "result.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct mm_input {
    float stick[2]; /* x (right), z (forward), world space; magnitude at most 1 */
    mm_gait gait;
    bool strafe;
    bool has_facing;
    float facing[2]; /* x, z: the direction to face when strafing (unit) */
    bool jump;       /* the jump button: pressed on this tick (mm_input_script_sample_tick) */
} mm_input;

/* The gait in asks for: in->gait, or MM_GAIT_WALK when in is NULL or its gait out of range. */
mm_gait mm_input_gait(const mm_input *in);

typedef struct mm_input_key {
    float t; /* seconds, >= 0, increasing */
    mm_input input;
} mm_input_key;

typedef struct mm_input_script {
    int key_count;
    mm_input_key *keys;
    mm_allocator allocator;
} mm_input_script;

/* Room for key_count keys (zeroed). allocator may be NULL. */
mm_result mm_input_script_init(mm_input_script *s, int key_count, const mm_allocator *allocator);
void mm_input_script_free(mm_input_script *s);
/* Keys in time order from 0, finite numbers, sticks of magnitude at most 1 (+1e-4), unit facings,
 * known gaits; err names the key and the field. */
mm_result mm_input_script_validate(const mm_input_script *s, mm_error *err);
/* The input at time t: the last key at or before t; before the first key (or with no key), the
 * neutral input (stick 0, walk, no strafe). */
void mm_input_script_sample(const mm_input_script *s, float t, mm_input *out);
/* The input of the tick that ends at time t and lasted dt seconds: mm_input_script_sample at t,
 * with jump true only when a key carrying "jump" has its time in (t - dt, t] (the first tick,
 * t - dt < 0, includes time 0): each such key presses the button on exactly one tick. */
void mm_input_script_sample_tick(const mm_input_script *s, float t, float dt, mm_input *out);

typedef struct mm_input_random_desc {
    float seconds;       /* length; 0: 60 */
    float mean_hold;     /* mean seconds a key holds; 0: 1.5 */
    float run_chance;    /* chance a key runs; 0: 0.3 (negative: never) */
    float strafe_chance; /* chance a key strafes; 0: 0.1 (negative: never) */
    float idle_chance;   /* chance a key lets go of the stick; 0: 0.15 (negative: never) */
    const mm_allocator *allocator;
} mm_input_random_desc;

/* A random script: the same seed gives the same keys. desc may be NULL. */
mm_result mm_input_script_random(mm_input_script *s, uint64_t seed, const mm_input_random_desc *desc);

#ifdef __cplusplus
}
#endif

#endif /* MM_INPUT_H */
