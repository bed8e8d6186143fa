/* Stage 7, feet: contacts, foot locking, the hips lowered where the legs cannot reach, and two-bone
 * IK on the (warped) legs. */
#ifndef MM_RUNTIME_FEET_H
#define MM_RUNTIME_FEET_H

#include <stdbool.h>

#include <mm/character.h>

#include "rig.h"

/* The feet's state. The heel lock holds the ankle; the toe lock holds the toe, the ankle turning
 * about it as animated; with both, the foot turns so that the toe stays on its lock too (turn: the
 * rotation added to the animated foot, a rotation vector, rad; it fades once a lock is let go).
 * Every change of what a foot follows is carried by offset, which decays: the ankle keeps its place,
 * and its velocity on the ground where the foot is let go (a foot is planted at rest: its landing
 * slows it first). */
typedef struct mm_feet {
    bool locked[2], heel_locked[2], toe_locked[2];
    mm_vec3 lock[2]; /* where the ankle is held this tick (its IK target) */
    mm_vec3 heel_lock[2], toe_lock[2], offset[2], offset_velocity[2];
    mm_vec3 turn[2], turn_velocity[2];
    /* planted on heel and toe: what the turn has yet to go to hold the toe on its lock (it fades,
     * so that a foot whose second lock begins turns onto it as a transition does, not in a tick) */
    mm_vec3 turn_offset[2], turn_offset_velocity[2];
    bool placed;                        /* lock holds last tick's ankle targets (landing eases from them) */
    mm_vec3 last_ankle[2], last_toe[2]; /* last tick's animated ankles and toes (when placed) */
    mm_vec3 shown_foot[2];              /* last tick's ankle-to-toe vectors as shown (after the IK) */
    float landed[2];       /* how far a free foot whose contact is coming has landed (share of plant_time) */
    float landing_time[2]; /* s: how long that landing takes (plant_time, or longer for a fast foot) */
    float hip_drop, hip_drop_velocity; /* m: how far the pelvis is lowered */
    float hip_need;                    /* m: on terrain, how far the legs needed it lowered last tick */
    /* m: how far each free foot is lifted as it catches up with its animated place (a spring's
     * state) */
    float step_lift[2], step_lift_velocity[2];
    /* m: how far each free foot is kept above where it would stand for its speed over the ground
     * (swing_clear in feet.c; a spring's state) */
    float clearance[2], clearance_velocity[2];
    /* m: how far the pelvis is moved on the ground plane toward planted feet out of their legs'
     * reach (in the pose only, not the simulated root) */
    mm_vec3 pelvis_shift, pelvis_shift_velocity;
    /* m: how far each ankle was left short of its target last tick (out of its leg's reach) */
    float reach_miss[2];
    /* how far each foot planted on its toe alone was pivoted about it last tick (pivot_on_toe in
     * feet.c): the ankle's move and the turn, carried by the offset and the turn when it lets go */
    mm_vec3 pivot_shift[2], pivot_turn[2];
    mm_vec3 tilt_normal[2]; /* on terrain: the ground's normal each foot was last turned to */
    /* on terrain: how far each animated foot is raised (or lowered) to the ground under it from the
     * root's ground (a spring's state) */
    float ground_shift[2], ground_shift_velocity[2];
    /* each ankle's target as reached for last tick (after the toe pivot), and its velocity then (m/s):
     * a free foot's offset speeds it up from there (ease_swing in feet.c) */
    mm_vec3 last_target[2], target_velocity[2];
    mm_vec3 raw_contacts[4]; /* left ankle, left toe, right ankle, right toe before IK */
    /* rad: each leg's bend as solved last tick (the angle at the hip between thigh and hip-to-ankle
     * line) and its rate (rad/s); the bend the target asked for last tick; the animated bend and
     * its rate (ease_bend in feet.c) */
    float bend[2], bend_velocity[2], bend_want[2];
    float animated_bend[2], animated_bend_velocity[2];
} mm_feet;

/* s: the longest landing (a fast foot slowed to rest before its contact, see feet.c): how far ahead
 * the contacts coming are looked for, when longer than plant_time */
#define MM_FEET_LANDING_MAX_TIME 0.1f
/* s: how far ahead a free foot's coming contact is looked for, to plan its swing onto the ground it
 * will land on (about a walking swing) */
#define MM_FEET_SWING_AHEAD 0.5f

/* What the clip playing says of the feet this tick. */
typedef struct mm_feet_contacts {
    unsigned label;         /* mm_contact_bits of the frame playing */
    float until_label[2];   /* s until foot k's label turns on, when within the landing's look-ahead
                             * (plant_time, at least MM_FEET_LANDING_MAX_TIME); -1 otherwise */
    float until_contact[2]; /* s until foot k's label turns on, within MM_FEET_SWING_AHEAD; 0 or less:
                             * none coming */
} mm_feet_contacts;

/* The ground a foot stands on: its height (scene NULL: the plane at that height; else the scene's
 * ground under each foot, mm_scene_ground_height), and whether the feet keep to it (not during a
 * move, whose root follows its clip). */
typedef struct mm_feet_ground {
    float height;
    bool hold;
    const mm_scene *scene;
} mm_feet_ground;

/* Records the raw contact positions (ankles and toes of the pose as it comes). */
void mm_feet_record(mm_feet *f, const mm_rig *rig, const mm_rig_pose *pose);

/* Locks, hip drop and IK (mm/character.h, desc's foot fields; the leg IK of mm/leg_ik.h, the
 * knees bending toward the pelvis's facing): writes the legs and the joints below them. ground:
 * what no target goes below, when ground->hold (not during a move: its root follows its clip).
 * On a scene's terrain each foot is turned to the ground's normal under it (within MAX_FOOT_TILT,
 * fully when planted, fading as a free foot rises) and kept above the ground under its ankle and
 * its toe, a free foot also above the ground just ahead of its toe (it clears a step's edge); the
 * hips may come down further (TERRAIN_HIP_DROP more) so that a leg reaches a lower step. */
void mm_feet_update(mm_feet *f, const mm_character_desc *d, const mm_rig *rig,
                    const mm_feet_contacts *contacts, const mm_feet_ground *ground, float dt,
                    mm_rig_pose *pose);

#endif
