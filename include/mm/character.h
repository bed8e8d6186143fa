/* mm/character.h - the character that moves: input -> trajectory -> search -> transition ->
 * pose, every tick, with no allocation.
 *
 * A character plays a database frame by frame (interpolating when the database interval is
 * coarser than the tick). Every search_interval seconds, at once when the input changes sharply,
 * and when its clip ends, it builds a query from the pose it plays and the simulated trajectory
 * (mm/trajectory.h) and searches (mm/search.h). When the winner is not where playback goes anyway
 * (same clip, a few frames ahead), it jumps there and hides the jump by inertialization: the
 * difference between the old and the new pose, joint by joint, decays to zero through a
 * critically damped spring. It asks for idle frames when the desired speed stays low and the
 * simulated character has slowed down (with hysteresis). The root integrates the database's root
 * velocity and is pulled toward the simulation, within a distance and angle clamp.
 *
 * Many characters can share one database and one searcher (with one thread) read-only; each
 * character owns its context. The gait asked for steers matching through tags named after the
 * gaits ("Walk", "Run", "Crouch", "Jump"): frames tagged with another gait are left out.
 *
 *   mm_character c;
 *   mm_character_init(&c, &db, &searcher, NULL, &err);
 *   each tick: mm_character_update(&c, &input, dt);  read c.global (joint_count transforms)
 *   mm_character_free(&c);
 *
 * Distance matching and stride warping (docs/distance.md, "In the controller") are switched by
 * desc.distance_matching and desc.warping, both off by default (measured on LAFAN1: no gain in raw
 * foot slide, and the turn_90 response over 0.5 s with them on); frames tagged "NoDistanceMatching" play by
 * the clock either way.
 *
 * Instead of inertialization, transitions may go through seed 000's five-slot crossfade mixer
 * (desc.transition_mode, mm/mixer.h, docs/transitions.md).
 *
 * A database carries the runtime tuning it was built with (its settings section,
 * mm_database_settings: the config's feature weights, its "runtime" object and its bone roles):
 * mm_character_desc_from_database makes a desc of it, in this library, with no JSON.
 * (mm_character_desc_apply_config, mm/character_config.h in the mm_build library, applies a config's tuning
 * to a desc directly, for tools that load a config file at run time.)
 *
 * For a debugger (docs/viewer.md, "Record, rewind, trace"): mm_character_set_candidates and
 * mm_character_candidates (the last search's best frames with every cost term),
 * mm_character_snapshot_bytes, mm_character_snapshot_save and mm_character_snapshot_load (the
 * whole state as bytes, put back bit for bit; mm/recorder.h keeps the last N ticks).
 *
 * Moves (mm/moves.h) play a clip through mm_character_play_move: no search until its end frame,
 * root motion as animated (not pulled toward the simulation); the move layer may set the root
 * between ticks (mm_character_set_root: the body moves with it) and mm_character_shift_root moves
 * the root under a pose that stays where it is. The root's height is kept from tick to tick (0
 * unless changed).
 *
 * The tick runs in stages (src/runtime/character/, one module each): input -> trajectory,
 * playback, search, transition, root motion, warping, feet, pose.
 *
 * Functions: mm_character_defaults mm_character_default_params mm_character_desc_resolve
 *            mm_character_desc_from_database mm_character_desc_apply_settings
 *            mm_character_init mm_character_free mm_character_update mm_character_tune
 *            mm_character_play_move mm_character_move_playing mm_character_shift_root
 *            mm_character_set_root mm_character_move_foot_locks mm_character_translate
 *            mm_character_teleport_simulation mm_character_push_simulation mm_character_halt_simulation
 *            mm_character_set_future mm_character_future_times mm_character_set_scene
 *            mm_character_set_walls mm_character_set_wall_pass mm_character_place_in_scene
 *            mm_character_set_search_phase
 *
 * Terrain: mm_character_set_scene gives the character the scene it walks on (mm/scene.h). Its
 * root and simulated trajectory then follow the height of the ground under them
 * (mm_scene_ground_height, smoothed), and planted feet stand on the ground under each of them,
 * turned to its slope (docs/scene.md, "Characters on terrain"). Without a scene, or on a flat
 * one (mm_scene_is_flat), the character runs exactly as on the plane y = 0.
 *
 * Walls: the same scene's boxes higher than a step stop the character (docs/scene.md,
 * "Collision"): its simulation and root are a vertical capsule that slides along them.
 */
#ifndef MM_CHARACTER_H
#define MM_CHARACTER_H

#include <stdbool.h>

#include "database.h"
#include "input.h"
#include "math.h"
#include "mixer.h"
#include "result.h"
#include "scene.h"
#include "search.h"
#include "trajectory.h"

#ifdef __cplusplus
extern "C" {
#endif

/* How a transition hides the jump (docs/transitions.md). */
typedef enum mm_transition_mode {
    MM_TRANSITION_INERTIALIZE = 0, /* offsets decaying through a spring (transition_halflife) */
    MM_TRANSITION_CROSSFADE = 1,   /* mm_mixer: each slot plays on, weights linear over crossfade_time;
                                      a winner the mixer cancels is dropped (cancelled_transitions) */
} mm_transition_mode;

/* Defaults of mm_character_desc, listed once. Zero means default: a field left 0 takes the value
 * here, so a zero-initialized desc with one field set is the defaults plus that field. Where 0 is
 * a value of its own (a half-life of 0: at once; a clamp of 0; a switch off), set MM_OFF (any
 * negative value): the field is then 0. Integer fields likewise (any negative: 0). */
#define MM_CHARACTER_SEARCH_INTERVAL       0.1f  /* s */
#define MM_CHARACTER_TURN_THRESHOLD        0.5f  /* rad */
#define MM_CHARACTER_TRANSITION_HALFLIFE   0.2f  /* s */
#define MM_CHARACTER_CROSSFADE_TIME        0.2f  /* s */
#define MM_CHARACTER_IDLE_SPEED            0.15f /* m/s */
#define MM_CHARACTER_IDLE_HYSTERESIS       0.1f  /* m/s */
#define MM_CHARACTER_IDLE_ROOT_SPEED       1.0f  /* m/s */
#define MM_CHARACTER_SYNC_HALFLIFE         0.3f  /* s */
#define MM_CHARACTER_SYNC_MAX_DISTANCE     0.3f  /* m */
#define MM_CHARACTER_SYNC_MAX_ANGLE        0.6f  /* rad */
#define MM_CHARACTER_ANGLE_THRESHOLD       0.35f /* rad */
#define MM_CHARACTER_ANGLE_REVISE_SPEED    0.0f  /* rad/s: off */
#define MM_CHARACTER_SKIP_FRAMES           3
#define MM_CHARACTER_VELOCITY_CHANGE_RATIO 0.9f
#define MM_CHARACTER_VELOCITY_CHANGE_SPEED 2.0f   /* m/s */
#define MM_CHARACTER_PLANT_TIME            0.033f /* s */
#define MM_CHARACTER_UNLOCK_RADIUS         0.8f   /* m */
#define MM_CHARACTER_FOOT_HALFLIFE         0.15f  /* s */
#define MM_CHARACTER_MAX_HIP_DROP          0.1f   /* m */
#define MM_CHARACTER_RATE_MIN              0.75f
#define MM_CHARACTER_RATE_MAX              1.25f
#define MM_CHARACTER_STRIDE_MIN            0.8f
#define MM_CHARACTER_STRIDE_MAX            1.2f
#define MM_CHARACTER_ORIENTATION_SPEED     10.0f   /* 1/s */
#define MM_CHARACTER_ORIENTATION_MAX       1.5708f /* rad: 90 degrees */
#define MM_CHARACTER_NEXT_POSE_FAVOUR      0.6f
#define MM_CHARACTER_CONTACT_FAVOUR        2.0f  /* factor on frames in other contacts (1: off) */
#define MM_CHARACTER_END_MARGIN            0.25f /* s */

typedef struct mm_character_desc {
    float search_interval;       /* s between searches (MM_OFF: every tick) */
    float turn_threshold;        /* rad: a desired-direction change that searches at once */
    float transition_halflife;   /* s: inertialization decay (MM_OFF: none, the jump shows) */
    float idle_speed;            /* m/s: desired speed under which idle is asked for, once the
                                    simulated speed is under idle_speed + idle_hysteresis too
                                    (MM_OFF: never) */
    float idle_hysteresis;       /* m/s: leave idle above idle_speed + this */
    float idle_root_speed;       /* m/s: idle is not asked for while the root motion played is
                                    this fast or faster, unless the simulation has stopped (MM_OFF:
                                    no such wait) */
    float sync_halflife;         /* s: the root is pulled toward the simulation (MM_OFF: put on it
                                    every tick) */
    float sync_max_distance;     /* m: clamp of the root's distance to the simulation */
    float sync_max_angle;        /* rad: clamp of the root's facing to the simulation's */
    float angle_threshold;       /* rad: at full speed, a facing error below this is corrected
                                    (the seed's AngleThreshold) */
    float angle_revise_speed;    /* rad/s: how fast (the seed's AngleReviseSpeed); default off */
    int skip_frames;             /* the winner is "where playback goes anyway" within this many
                                    frames ahead in the same clip */
    float velocity_change_ratio; /* the search's pose_trajectory_ratio while the simulated velocity
                                    must change (a stop, a turn, a start: |desired - current|): it
                                    moves from params' toward this in proportion to the change,
                                    fully at velocity_change_speed, so that the trajectory outweighs
                                    the pose and stops and turns can win over carrying on (under
                                    0.5 m/s it comes in with the simulated speed: a start is the
                                    pose's to choose); MM_OFF (or at most params' ratio): off */
    float velocity_change_speed; /* m/s */
    mm_search_method method;     /* MM_SEARCH_FAST (0) */
    /* The search's parameters, field by field: a zero field takes mm_character_default_params'
     * (the database's weights, next_pose_favour MM_CHARACTER_NEXT_POSE_FAVOUR,
     * contact_mismatch_favour MM_CHARACTER_CONTACT_FAVOUR (MM_OFF: 1, off), the frames tagged
     * "DoNotUse", "Jump", "VaultLow", "VaultHigh", "Climb" or "Drop" (moves the locomotion search
     * must not pick) and the last MM_CHARACTER_END_MARGIN s of one-shot clips excluded); MM_OFF
     * makes a weight, pose_trajectory_ratio or end_margin 0; excluded_tags add to the defaults'.
     * current_frame and type are the character's own. */
    mm_search_params params;
    /* The simulation (mm/trajectory.h): zero fields take mm_trajectory_defaults'. */
    mm_trajectory_desc trajectory;
    /* Transitions (docs/transitions.md): inertialization (transition_halflife) or seed 000's
     * crossfade mixer, whose transitions take crossfade_time (s) */
    mm_transition_mode transition_mode; /* MM_TRANSITION_INERTIALIZE (0) */
    float crossfade_time;
    /* Foot locking and two-bone IK, on the contact labels of the frame playing: while the heel
     * label is on, the ankle is held where it was planted; while only the toe label is on, the
     * toe is held and the ankle rolls about it as animated; with both, the foot turns (at most
     * 0.8 rad from its animated orientation) so that the toe stays on its lock too. A lock the
     * animation pulls more than unlock_radius away, or that its leg cannot reach, moves toward the
     * foot a spring step a tick (it creeps after the animation); released, the difference in place and
     * velocity fades with foot_halflife. The pelvis moves on the ground plane toward planted feet out of
     * their legs' reach (in the pose only, at most 12 cm, through a spring), the hips come down (at most
     * max_hip_drop, through a spring) where the legs still cannot reach their targets, and an
     * ankle is raised where its toe would go below the ground. The legs reach them by the leg IK
     * (mm/leg_ik.h), the knee bending about its hinge, the foot keeping its animated orientation (turned by
     * the foot's turn). */
    bool no_foot_ik;                    /* turn foot locking and IK off */
    float plant_time;                   /* s: over this time before a free foot's contact label
                                           turns on in the clip playing, its step on the ground
                                           plane shrinks linearly to nothing, and on the tick the
                                           label turns on it is planted where it was: it lands at
                                           rest, not at the speed a transition's offsets or the
                                           root's pull gave it; a label that turns on sooner (a
                                           jump onto a frame whose label is on) waits for the rest
                                           of this time (MM_OFF: off) */
    float unlock_radius;                /* m */
    float foot_halflife;                /* s */
    float max_hip_drop;                 /* m: how far the hips may be lowered so that the legs
                                           reach their targets (MM_OFF: never) */
    const char *left_foot, *right_foot; /* ankle joints (the knee and hip are their parents);
                                           NULL (the default): the database's foot roles
                                           (mm_database_role_joint); a name wins over the role,
                                           and one that names no joint leaves that foot out */
    /* Distance matching and stride warping (mm/distance_matching.h, mm/warp.h, docs/distance.md
     * "In the controller"), on the database's distance curves. Off: the clock drives playback at
     * rate 1, as before. Frames tagged "NoDistanceMatching" always play at rate 1, unwarped. */
    bool distance_matching;       /* one-shot clips advance by the distance the simulated root travelled;
                                     stops and pivots match to the predicted stop or pivot point; loops
                                     play at desired speed / clip speed; default off */
    bool warping;                 /* stride warping: the legs stretched along the movement by the speed
                                     the clamped play rate leaves over; default off */
    float rate_min, rate_max;     /* play-rate clamp (both MM_OFF: no clamp) */
    float stride_min, stride_max; /* stride-scale clamp (both MM_OFF: no clamp) */
    /* orientation warping, with warping on: while strafing on a forward or backward locomotion
     * clip, the legs turn toward the movement and the spine turns back (docs/distance.md) */
    float orientation_speed; /* 1/s: how fast the angle follows (a critically damped spring of
                                half-life ln 2 / speed; MM_OFF: at once) */
    float orientation_max;   /* rad: the largest correction */
    double (*clock)(void);   /* optional: seconds, to time searches (c->last_search_us) */
    const mm_allocator *allocator;
} mm_character_desc;

/* Every field of d at its default (the values above, written out). */
void mm_character_defaults(mm_character_desc *d);

/* The desc a character runs with, written out: every zero field at its default (params over
 * mm_character_default_params(db), trajectory over mm_trajectory_defaults), every MM_OFF kept;
 * resolving it again changes nothing. db may be NULL (params are then left as they are). out may
 * be in. mm_character.desc is this of the desc given to mm_character_init. */
void mm_character_desc_resolve(const mm_database *db, const mm_character_desc *in, mm_character_desc *out);

/* The search parameters a desc's zero params resolve to (see mm_character_desc.params). */
void mm_character_default_params(const mm_database *db, mm_search_params *p);

/* The character settings a database was tuned with, from its settings section (no JSON, no
 * allocation): mm_character_defaults; then d->params = mm_character_default_params and
 * d->trajectory = mm_trajectory_defaults; then the stored feature weights and every runtime field
 * the settings set (a value of 0 as MM_OFF, so that it keeps its meaning). d->left_foot and
 * d->right_foot stay NULL: the character takes the database's foot roles (by joint index) itself. The same
 * desc, field for field, as mm_character_desc_apply_config (mm/character_config.h) with the config the
 * database was built from. A database without settings (db->settings NULL: not loaded nor built) gives the
 * defaults. MM_ERR_INVALID_ARGUMENT without d or db. */
mm_result mm_character_desc_from_database(mm_character_desc *d, const mm_database *db, mm_error *err);

/* Writes the tuning of settings s (a database's, or one made from a config) into d: the stored
 * feature weights and every runtime field s sets (a 0 as MM_OFF); the rest of d is kept. */
void mm_character_desc_apply_settings(mm_character_desc *d, const mm_database_settings *s);

/* How the clip time advanced this tick (mm_character.playback). */
typedef enum mm_character_playback {
    MM_PLAYBACK_CLOCK = 0,    /* rate 1: distance matching off, tagged off, or a stop played out */
    MM_PLAYBACK_DISTANCE = 1, /* advanced by the distance travelled (starts, and on to a stop) */
    MM_PLAYBACK_STOP = 2,     /* matched to the predicted stop point */
    MM_PLAYBACK_PIVOT = 3,    /* matched to the predicted pivot point */
    MM_PLAYBACK_CYCLE = 4,    /* a loop at desired speed / clip speed */
} mm_character_playback;

/* The stages' state (src/runtime/character/state.h): private to the runtime. */
typedef struct mm_character_state mm_character_state;

/* A character. Every field is written by the runtime only (mm_character_* functions); users read
 * them after mm_character_init and each mm_character_update. */
typedef struct mm_character {
    const mm_database *db;
    const mm_searcher *searcher;
    mm_character_desc desc;          /* as given to mm_character_init or mm_character_tune, written
                                        out (mm_character_desc_resolve) */
    const mm_trajectory *trajectory; /* the simulated character (mm/trajectory.h) */

    /* the output pose: local rotations and positions ([joint_count]; joint 0 is the root, in the
     * world) and the world transforms ([joint_count]) */
    const mm_quat *local_rotations;
    const mm_vec3 *local_positions;
    const mm_xform *global;
    mm_xform root; /* the character on the ground: position and facing (joint 0) */

    /* playback: the database frame playing and how far toward the next ([0, 1)), how the playhead
     * moved this tick, the play rate (1 without distance matching) and the stride scale (1: not
     * warped) */
    int frame;
    double frame_fraction;
    mm_character_playback playback;
    float play_rate, stride_scale;
    bool idle;         /* asking for idle */
    bool move_playing; /* a move plays (mm_character_play_move) */

    /* feet: ankle and toe joints (-1 when missing), whether each foot is held and where its ankle
     * is held this tick, and the ankles and toes before foot IK (left ankle, left toe, right
     * ankle, right toe; for the foot-slide measure) */
    int foot_joint[2], toe_joint[2];
    bool foot_locked[2];
    mm_vec3 foot_lock[2];
    mm_vec3 raw_contact_positions[4];

    /* statistics: searches, transitions, the winners the crossfade mixer cancelled, the last
     * search's time (desc.clock), result (the search's winner), choice (the candidate the jump
     * went to, or frame -1 for playing on while a swinging foot lands: docs/runtime.md, its cost
     * priced), the parameters it weighed with (desc.params as adjusted for that tick) and its
     * query ([dims_padded]) */
    int searches, transitions, cancelled_transitions;
    float last_search_us;
    mm_search_result last_result, last_choice;
    mm_search_params last_params;
    const float *query;

    const mm_scene *scene; /* the ground walked on (mm_character_set_scene); NULL: the plane y = 0 */

    mm_character_state *state;
    mm_allocator allocator;
} mm_character;

/* Allocates everything the character will ever need (no allocation happens in update). The
 * character starts at the origin facing +Z, playing the database's first idle frame (or frame 0). */
mm_result mm_character_init(mm_character *c, const mm_database *db, const mm_searcher *searcher,
                            const mm_character_desc *desc, mm_error *err);
void mm_character_free(mm_character *c);

/* One tick of dt seconds (dt <= 0 or not finite: nothing moves; a dt of 1 s is one long step).
 * Writes c->global. A NaN, infinite or oversized stick counts as zero or is clamped to the unit
 * circle; when no frame passes the search's filters the character keeps playing what it plays
 * (c->last_result.frame is -1); a database of one clip works the same way. The pose is never
 * NaN (tested with hostile input, and by bench_soak over a simulated hour). */
void mm_character_update(mm_character *c, const mm_input *in, float dt);

/* Plays a move: on the next update the character goes to database frame `frame` through an
 * inertialized transition of half-life `halflife` (<= 0: desc.transition_halflife) and plays on
 * by the clock, without searching, until the playhead reaches end_frame (in frame's clip; past
 * the clip's end: to its end), when it searches at once (hands back to matching). While a move
 * plays, the root follows the clip's root motion only (no pull toward the simulation, no
 * clamps). A frame out of range stops the move being played (the next update searches). */
void mm_character_play_move(mm_character *c, int frame, int end_frame, float halflife);

/* True from mm_character_play_move until the move hands back to matching. */
bool mm_character_move_playing(const mm_character *c);

/* Changes the tuning live, from the next update: d's search parameters and method, timing,
 * idle, sync, angle and foot fields, distance matching and warping switches and clamps, clock,
 * and the simulation's gait parameters (zero fields: the defaults, as at init). What init laid out stays (the
 * feet's joints, the transition mode, the allocator). NULL is ignored. */
void mm_character_tune(mm_character *c, const mm_character_desc *d);

/* Moves the root by delta (world, metres) while the body stays where it is: the difference is
 * taken into the offsets of the root's children, which decay as a transition's do. */
void mm_character_shift_root(mm_character *c, mm_vec3 delta);

/* Puts the root (the character on the ground) at `root` between ticks: the next update moves the
 * body from there. A non-finite root is ignored. */
void mm_character_set_root(mm_character *c, mm_xform root);

/* Moves the feet's locks by delta (world, metres): what a planted foot holds moves with the
 * ground it stands on (a character lifted over a wall). */
void mm_character_move_foot_locks(mm_character *c, mm_vec3 delta);

/* Moves the whole character by delta after its tick: the root, the output pose, the contacts and
 * the simulation (a rigid translation; nothing is blended). */
void mm_character_translate(mm_character *c, mm_vec3 delta);

/* The simulation: moved to position and facing with its recorded past (mm_trajectory_teleport);
 * moved to position alone, its past and velocity kept (a collider pushing it out of a wall); or
 * halted (its velocity zeroed). */
void mm_character_teleport_simulation(mm_character *c, mm_vec3 position, mm_quat facing);
void mm_character_push_simulation(mm_character *c, mm_vec3 position);
void mm_character_halt_simulation(mm_character *c);

/* Shifts the character's search schedule by phase (in [0, 1)) of its search interval: the search
 * after its next one comes that share of the interval sooner, and the schedule runs on from there.
 * Characters ticked together with phases spread over [0, 1) search on different ticks, so that a
 * tick's searches are as many as the average (mm_crowd_desc.spread_searches). 0, the default: the
 * schedule as mm simulate runs it. Out of range or not finite: ignored. */
void mm_character_set_search_phase(mm_character *c, float phase);

/* The scene the character walks on from the next update (not copied: it must stay valid while
 * set; it may change between ticks). NULL: the plane y = 0 and no walls. Its ground: a flat scene
 * (mm_scene_is_flat) is the plane y = 0, bit for bit as without a scene. Its walls (boxes higher
 * than a step, mm_trajectory_set_scene) stop the simulation and the root alike: both are a
 * vertical capsule (desc.trajectory.collider_radius) pushed out of them each tick, sliding along
 * them, and the predicted future the search sees stops or bends at them (docs/scene.md,
 * "Collision"). */
void mm_character_set_scene(mm_character *c, const mm_scene *scene);
/* The scene's walls alone (its ground not walked on; NULL: no walls): what mm_character_set_scene
 * does for the walls. */
void mm_character_set_walls(mm_character *c, const mm_scene *scene);
/* The character in a scene as mm simulate, mm_run, traces and the viewer put it: a scene with
 * terrain (mm_scene_has_terrain) is walked on (mm_character_set_scene); any other scene's boxes are
 * walls alone (mm_character_set_walls: their tops are for the moves to climb); NULL: none. */
void mm_character_place_in_scene(mm_character *c, const mm_scene *scene);
/* Boxes whose top is at most pass_height above the character's ground are not walls to it (the
 * move layer raises it to the highest box a move crosses, INFINITY during a move); negative: the
 * desc's collider_step. */
void mm_character_set_wall_pass(mm_character *c, float pass_height);

/* The game's own desired future (its AI's or navigation's path) for the next mm_character_update
 * only, in place of the simulation's prediction in the search's query: world positions (y
 * ignored) and facings (rotations about +Y; identity faces +Z) at the database's future trajectory
 * times (mm_character_future_times), in order. Give it each tick the game decides the path; the
 * simulation itself still follows the input (mm/drive.h steers it along a path). count 0 clears
 * it. MM_ERR_INVALID_ARGUMENT when count is not the number of future times or a value is not
 * finite (nothing is set). */
mm_result mm_character_set_future(mm_character *c, const mm_vec3 *positions, const mm_quat *facings,
                                  int count, mm_error *err);

/* The database's future trajectory times (s ahead, increasing) into times (room for
 * MM_MAX_TRAJ_SAMPLES); returns how many. */
int mm_character_future_times(const mm_character *c, float *times);

/* The last search's best candidates, for a debugger (mm/recorder.h, mm simulate --trace): the
 * frame and its clip, the cost the decision weighed (favours and bias in), the weighted distance
 * before them (base) and every term of the cost: the five weighted distances (mm_search_cost_terms,
 * summing to base up to float rounding) and what the favours and the bias added, so that
 * base + loop_favour + contact_favour + next_pose_favour + continuing_bias = cost (up to rounding). */
typedef struct mm_candidate {
    int frame, clip;
    float cost, base;
    mm_search_terms terms;
    float loop_favour;      /* base x (loop_anim_favour - 1) for frames of loop clips, else 0 */
    float contact_favour;   /* (base + loop_favour) x (contact_mismatch_favour - 1) for frames whose
                               contact bits differ from the frame playing's, else 0 */
    float next_pose_favour; /* (base + loop_favour + contact_favour) x (next_pose_favour - 1) for
                               the frame after the one playing, else 0 */
    float continuing_bias;  /* -continuing_bias for the frame after the one playing, else 0 */
} mm_candidate;

/* Asks every later search for its best k frames (k >= 1; 1, the default, is the winner alone and
 * costs nothing more): allocates room for them here, once (never per tick). The winner and the
 * run are the same whatever k. MM_ERR_INVALID_ARGUMENT for k < 1, MM_ERR_OUT_OF_MEMORY. */
mm_result mm_character_set_candidates(mm_character *c, int k, mm_error *err);

/* The last search's best candidates (at most max, at most the k asked for) into out, the winner
 * first (c->last_result), then by cost then frame, with their cost terms (computed here, on the
 * query and parameters of that search: c->query, c->last_params); returns how many (0 before any
 * search, or when no frame passed the filters). */
int mm_character_candidates(const mm_character *c, mm_candidate *out, int max);

/* The character's whole state as bytes: its public fields and everything its stages keep, to be
 * put back later (a debugger's rewind). Bytes a snapshot of c takes; save writes one into memory
 * (bytes at least that; any alignment); load puts c back to it: c must have been made the same
 * way (the same database and desc; its memory may lie elsewhere: pointers are fixed up). After a
 * load, updating c with the same inputs repeats the saved run bit for bit. No allocation.
 * MM_ERR_INVALID_ARGUMENT for too little memory or a snapshot of another layout. */
size_t mm_character_snapshot_bytes(const mm_character *c);
mm_result mm_character_snapshot_save(const mm_character *c, void *memory, size_t bytes, mm_error *err);
mm_result mm_character_snapshot_load(mm_character *c, const void *memory, size_t bytes, mm_error *err);

#ifdef __cplusplus
}
#endif

#endif /* MM_CHARACTER_H */
