/* mm/moves.h - the moves beyond locomotion: jump, vault, climb and drop-down (seed 000, 三.4),
 * a layer on top of a character (mm/character.h) in a scene of boxes (mm/scene.h).
 *
 * The layer finds the move clips in the database by their tags ("Jump", "VaultLow",
 * "VaultHigh", "Climb", "Drop": every span of frames carrying the tag, each measured once: its
 * rise, its hand's height at the plant, its distances) and their events by
 * single-frame tags ("TakeOff", "HandPlant", "Landing"; without them take-off and landing are the
 * ends of the longest run of frames with no foot contact). Each tick, instead of
 * mm_character_update, mm_moves_update:
 *  - in locomotion, keeps the character on the ground (it follows steps up to step_height and
 *    falls with gravity), pushes it out of walls (a circle of `radius` about the root; the
 *    simulation too), and looks for a move: the jump key (in->jump, on its rising edge), a wall
 *    ahead while moving toward it (mm_scene_measure_obstacle; the move chosen by its height and
 *    depth, mm_moves_choose), no ground within step_height ahead while moving (drop-down); among
 *    the clips of the kind, the one whose own geometry (rise, hand height, distance) needs the
 *    smallest correction to fit the obstacle or the landing found (the lowest index on a tie),
 *    then of it and its mirror the one whose leading foot fits the gait (mm_moves_pick_side);
 *  - starts a move: mm_character_play_move (no search until it ends) and plans it: where the hand
 *    goes at HandPlant (on the wall's top edge) and where the root lands at Landing (past the
 *    wall, on its top, or on the ground found ahead), each with a target match (mm/target_match.h)
 *    of the horizontal position and the facing (turned to face the wall); the height follows a
 *    schedule through those points (the seed's rise and fall moments), so the hand is on the
 *    top edge at HandPlant and the feet on the ground found at Landing, whatever height the clip
 *    was recorded at;
 *  - keeps every joint of the pose about to play out of the boxes' tops (the root raised over the
 *    schedule by `lift`: a trailing leg over a wall, a toe on its edge);
 *  - in locomotion, stops a character not asked to move on at a ledge (no walking off without
 *    a drop);
 *  - hands back to matching recover_time after Landing: the root moved to the ground under the
 *    body (the pose kept), the trajectory simulation moved to the root (mm_trajectory_teleport).
 * During a move the collider is off; the ground below is probed for the landing height.
 *
 * Without a scene, or with no move clip in the database, the layer does nothing but call
 * mm_character_update. The layer never allocates; all its state is in mm_moves, which the
 * caller owns. docs/moves.md describes the parameters and the measured results.
 *
 * Functions: mm_moves_defaults mm_moves_desc_from_database mm_moves_init mm_moves_update
 *            mm_moves_choose mm_move_kind_name
 *            mm_moves_pick_side mm_moves_penetration
 */
#ifndef MM_MOVES_H
#define MM_MOVES_H

#include <stdbool.h>

#include "character.h"
#include "database.h"
#include "input.h"
#include "math.h"
#include "move_kind.h"
#include "result.h"
#include "scene.h"
#include "target_match.h"

#ifdef __cplusplus
extern "C" {
#endif

/* "jump", "vault_low", "vault_high", "climb", "drop"; NULL for anything else. */
const char *mm_move_kind_name(mm_move_kind kind);

/* Zero means default in every number of mm_moves_desc (the values below, set by
 * mm_moves_defaults); MM_OFF (any negative value) makes it 0. NULL names: the defaults. */
typedef struct mm_moves_desc {
    float max_jump_height;              /* m: the highest surface a jump lands on, above the feet (the
                                           seed's Max jump height); 1.2 */
    float jump_start_offset;            /* s before take-off where the jump clip starts (the seed's Jump
                                           anim start offset); 0.45 */
    float rise_start;                   /* a jump up rises from this fraction of the flight (take-off to
                                           landing; the seed's Rise start moment); 0 */
    float fall_start;                   /* a jump up has risen by, and a jump down starts falling at, this
                                           fraction of the flight (the seed's Fall start moment); 0.55 */
    float step_height;                  /* m: ground within this of the feet is walked on; 0.3 */
    float ledge_probe;                  /* m ahead of the root where the ground is probed for a ledge; 0.45 */
    float trigger_slack;                /* m: a wall triggers a vault this much before the clip's own
                                           distance to its hand plant; 0.1 */
    float low_max_height;               /* m: walls up to this are low; 1.5 */
    float high_max_height;              /* m: walls up to this are high; higher ones are not crossed; 2.6 */
    float short_max_depth;              /* m: a wall up to this deep is crossed over (its short side);
                                           deeper, it is climbed onto (its long side); 1.0 */
    float landing_margin;               /* m: a move over a wall lands at least this far past it; 0.5 */
    float recover_time;                 /* s after Landing when matching resumes; 0.35 */
    float transition_halflife;          /* s: into and out of a move; 0.12 */
    float gravity;                      /* m/s^2; 9.81 */
    float radius;                       /* m: the collider, a circle about the root; 0.4 */
    float cooldown;                     /* s after a move before the next can start (a drop at a
                                           ledge waits 0.15 s at most); 0.25 */
    float max_jump_distance;            /* m ahead of the root: the farthest a jump looks for the far
                                           side of a gap; 3.0 */
    float moving_speed;                 /* m/s: a desired speed above this is moving on (walls and
                                           ledges trigger moves); at or below it, the character stops
                                           at a ledge; 0.5 */
    float collider_height;              /* m: a box whose bottom is this far above the root is
                                           walked under, not a wall; 1.8 */
    float knee_height, chest_height;    /* m above a landing spot where room for the body (radius)
                                           is tested; 0.4, 1.2 */
    float max_lift;                     /* m: the most the reactive lift raises the root during a
                                           move (a joint of the pose about to play, or as played,
                                           inside a box's top; the planned lift is not capped); 0.6 */
    const char *left_hand, *right_hand; /* joints; NULL (the default): the database's hand
                                           and foot roles (mm_database_role_joint); a name
                                           wins over the role */
    const char *left_foot, *right_foot;
} mm_moves_desc;

void mm_moves_defaults(mm_moves_desc *d);
/* mm_moves_defaults: the joint names stay NULL, so that mm_moves_init takes the hands and feet
 * of db's bone roles (mm_database_role_joint; kept for the callers that name db here). */
void mm_moves_desc_from_database(mm_moves_desc *d, const mm_database *db);

/* At most this many move clips (spans tagged as a move) are kept; further ones are ignored. */
#define MM_MOVES_MAX_CLIPS 160

/* Frames of a move (from its start) over which the lift over a wall is planned. */
#define MM_MOVES_PLAN_FRAMES 512

/* Keys of a move's height schedule: the start, the hand plant or two for a jump's flight, the
 * landing, the hand-back. */
#define MM_MOVES_MAX_KEYS 6

/* A move clip as found in the database. Frames are database frames; -1: none. */
typedef struct mm_move_clip {
    mm_move_kind kind;                 /* its tag */
    int clip;                          /* database clip, -1 when the database has none */
    int first, last;                   /* the tagged span */
    int start;                         /* where the move starts playing */
    int take_off, hand_plant, landing; /* events (hand_plant -1 for moves without one) */
    int hand;                          /* the hand planted (joint), -1 */
    bool onto;                         /* the clip ends higher than it starts (climbs onto) */
    float rise;                        /* m: the clip's ground at landing less at start */
    float plant_height;                /* m: the planted hand at HandPlant above the clip's ground at
                                          the start (0 without) */
    float plant_distance;              /* m: forward from the root at start to the hand at
                                          HandPlant (0 without) */
    float hand_inset;                  /* m: how far in from the obstacle's near face the hand plants
                                          (no joint below the top is ahead of the face up to just
                                          after the plant) */
    float land_distance;               /* m: forward from the root at start to the root at
                                          Landing */
    int twin;                          /* index in mm_moves.options of the same span of its mirrored
                                          twin (the other side), -1 */
} mm_move_clip;

/* One move performed. */
typedef struct mm_move_record {
    mm_move_kind kind;
    int clip;              /* the database clip played */
    float t_start, t_end;  /* s: layer time (the sum of dt) when it started and handed back */
    float target_error_cm; /* the larger of the hand's error at HandPlant and the landing's
                              (root on the ground, horizontally, and the feet's height) */
} mm_move_record;

typedef struct mm_moves {
    const mm_database *db;
    const mm_scene *scene; /* NULL: no moves */
    mm_moves_desc desc;
    mm_move_clip clips[MM_MOVE_KIND_COUNT];   /* per kind: the first usable span (a clip that is not a
                                                 mirror first); clip -1 when none */
    mm_move_clip options[MM_MOVES_MAX_CLIPS]; /* every usable span of every kind, measured once at
                                                 init; a move plays the one that best fits */
    int option_count;
    int hand[2], foot[2], toe[2]; /* toe: mm_database_toe_joint of the feet, -1 */
    float ankle_height;           /* m: the ankles' height above the ground when standing */
    float toe_height;             /* m: the toes' then */
    bool enabled;                 /* a scene and at least one move clip */

    /* state */
    double time;              /* s: sum of dt */
    mm_move_kind kind;        /* the move playing, MM_MOVE_NONE in locomotion */
    mm_move_clip active;      /* its clip */
    int start_frame;          /* where it started (database frame) */
    bool started;             /* the character has begun playing it */
    mm_target_match match[2]; /* hand at HandPlant, root at Landing (horizontal and yaw) */
    bool match_on[2];
    /* the root's height schedule: per key its clip time and height; per segment its shape (0
     * linear, 1 smooth, 2 falling, 3 rising) */
    float key_time[MM_MOVES_MAX_KEYS], key_y[MM_MOVES_MAX_KEYS];
    int key_shape[MM_MOVES_MAX_KEYS];
    int key_count;
    mm_vec3 hand_target, land_target; /* where the hand and the feet go (land_target.y: ground) */
    float hand_error, land_error;     /* m, measured when the events are reached */
    bool jump_held;                   /* the jump key's state last tick */
    float fall_velocity;              /* m/s, downwards: falling in locomotion */
    float lift;                       /* m: the root raised over the schedule during a move so that no
                                         joint of the pose about to play is inside a box's top */
    /* per frame of the move (from its start): how far the root must rise over the schedule for
     * the body, as predicted, to pass over a box's top after the hand plant (a trailing leg over
     * a wall); the lift follows a smooth envelope of it (planned_lift) */
    float need[MM_MOVES_PLAN_FRAMES];
    float planned_lift;     /* m: that envelope now */
    float applied_lift;     /* m: the lift the root was given on the last tick (the larger) */
    float since_move;       /* s since the last move handed back */
    mm_move_record current; /* the move playing */
    /* per tick: a move handed back on this tick (last holds it); moves performed so far */
    bool finished;
    mm_move_record last;
    int count;
} mm_moves;

/* Finds the move clips and their events (once) and starts in locomotion. scene may be NULL (the
 * layer then does nothing); the scene and db must outlive m. desc may be NULL (defaults).
 * MM_ERR_INVALID_ARGUMENT without m or db. */
mm_result mm_moves_init(mm_moves *m, const mm_database *db, const mm_scene *scene, const mm_moves_desc *desc,
                        mm_error *err);

/* One tick of dt seconds: the move layer around mm_character_update(c, in, dt) (see above). c
 * must use m's database. in may be NULL (no input). */
void mm_moves_update(mm_moves *m, mm_character *c, const mm_input *in, float dt);

/* The move for a measured obstacle, from its height and depth and the clips m has (see
 * docs/moves.md): MM_MOVE_NONE when it is a step (height <= step_height), too high, or no clip
 * fits. */
mm_move_kind mm_moves_choose(const mm_moves *m, const mm_obstacle *o);

/* Of option `option` (an index into m->options) and its mirrored twin, the one whose start fits
 * the character's gait phase better (the index returned): the feet of the frame playing against
 * the feet at the clip's start, planted or swinging, where and how fast (docs/moves.md), so that
 * the transition into the move does not switch the legs. The option itself when it has no twin,
 * on a tie, or for an index out of range. */
int mm_moves_pick_side(const mm_moves *m, const mm_character *c, int option);

/* How deep (m) the deepest of the points is inside any box of the scene (0: none inside). */
float mm_moves_penetration(const mm_scene *scene, const mm_vec3 *points, int count);

#ifdef __cplusplus
}
#endif

#endif /* MM_MOVES_H */
