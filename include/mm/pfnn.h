/* mm/pfnn.h - the phase-functioned neural network character (Holden, Komura, Saito 2017); the
 * mm_pfnn library (libc and libm, on mm_runtime).
 *
 * An alternative to database search: a small network predicts, every 60 Hz frame, the next pose,
 * the root motion, the change of the locomotion phase and the future trajectory, from the past and
 * future trajectory, the gait weights, the previous pose and the terrain. Its weights are a cyclic
 * function of the phase: four control points joined by a periodic Catmull-Rom spline.
 *
 * This module runs the released weights (not shipped with mm; see docs/pfnn.md). Three parts:
 *   - the network: load, evaluate at any phase in one of three modes (below);
 *   - the character: the release's 31-joint skeleton, as an mm_skeleton in metres (loaded by
 *     mm_pfnn_character_load, mm/pfnn_character.h: it reads the release's BVH, so it is in the
 *     mm_build library);
 *   - the controller: seed 004's per-frame update (target blending, gaits, trajectory prediction,
 *     obstacle avoidance, terrain heights, network input, prediction, trajectory and pose update).
 *
 *   mm_pfnn_network *net; mm_error err;
 *   mm_pfnn_network_load("data/pfnn", NULL, &net, &err);          // dir holds network/
 *   mm_pfnn_controller_desc cd = {0}; cd.network = net;
 *   mm_pfnn_controller *ctrl; mm_pfnn_controller_create(&cd, &ctrl, &err);
 *   each frame: mm_pfnn_input in = {0}; in.velocity = ...; mm_pfnn_controller_step(ctrl, &in, 1/60.f);
 *               const mm_pfnn_state *s = mm_pfnn_controller_state(ctrl);
 *   mm_pfnn_controller_destroy(ctrl); mm_pfnn_network_free(net);
 *
 * Units at this API: metres, seconds, radians, Y up, the character faces +Z (the network itself
 * works in centimetres per 60 Hz frame; mm_pfnn_network_eval takes and gives its raw units).
 * Quaternions {x,y,z,w}. Network evaluation and controller steps never allocate; a network is
 * read-only after loading and may be shared by any number of controllers and threads.
 *
 * Functions: mm_pfnn_network_load mm_pfnn_network_free mm_pfnn_network_eval mm_pfnn_network_has_mode
 *            mm_pfnn_network_bytes mm_pfnn_network_layer mm_pfnn_spline_coefficients mm_pfnn_wrap_phase
 *            mm_pfnn_mode_name mm_pfnn_mode_parse
 *            mm_pfnn_controller_create mm_pfnn_controller_destroy mm_pfnn_controller_reset
 *            mm_pfnn_controller_step mm_pfnn_controller_state mm_pfnn_controller_assemble_input
 *            mm_pfnn_controller_local_pose mm_pfnn_height_flat mm_pfnn_height_slopes
 *            mm_pfnn_height_scene
 */
#ifndef MM_PFNN_H
#define MM_PFNN_H

#include <stdbool.h>
#include <stddef.h>

#include "alloc.h"
#include "math.h"
#include "result.h"
#include "skeleton.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- sizes and layouts ------------------------------------------------------------------------ */

#define MM_PFNN_INPUT_DIM      342
#define MM_PFNN_OUTPUT_DIM     311
#define MM_PFNN_HIDDEN_DIM     512
#define MM_PFNN_CONTROL_POINTS 4
#define MM_PFNN_JOINT_COUNT    31
#define MM_PFNN_TRAJ_SAMPLES   12 /* every 10th frame of 120: 6 past, the current (index 6), 5 future */
#define MM_PFNN_FUTURE_SAMPLES 6  /* output trajectory at +0, +10, ..., +50 frames */
#define MM_PFNN_GAIT_COUNT     6  /* stand, walk, jog, crouch, jump, unused */
#define MM_PFNN_FPS            60

/* Input (342, raw units: centimetres, in the root's frame; see docs/pfnn.md). */
#define MM_PFNN_X_TRAJ_POS_X   0   /* 12 */
#define MM_PFNN_X_TRAJ_POS_Z   12  /* 12 */
#define MM_PFNN_X_TRAJ_DIR_X   24  /* 12 */
#define MM_PFNN_X_TRAJ_DIR_Z   36  /* 12 */
#define MM_PFNN_X_GAIT         48  /* 6 blocks of 12: stand, walk, jog, crouch, jump, unused */
#define MM_PFNN_X_JOINT_POS    120 /* 31 x (x,y,z), previous frame's root space */
#define MM_PFNN_X_JOINT_VEL    213 /* 31 x (x,y,z) */
#define MM_PFNN_X_HEIGHT_RIGHT 306 /* 12: 25 cm along the sample's local +X (the demo's "right") */
#define MM_PFNN_X_HEIGHT_MID   318 /* 12 */
#define MM_PFNN_X_HEIGHT_LEFT  330 /* 12: local -X */

/* Output (311, raw units: centimetres and radians per frame, in the root's frame). */
#define MM_PFNN_Y_ROOT_X     0 /* root displacement x this frame */
#define MM_PFNN_Y_ROOT_Z     1
#define MM_PFNN_Y_ROOT_TURN  2 /* the facing turns by -y[2] about Y */
#define MM_PFNN_Y_PHASE      3 /* phase change, in cycles (times 2 pi for radians) */
#define MM_PFNN_Y_CONTACTS   4 /* 4: left heel, left toe, right heel, right toe */
#define MM_PFNN_Y_TRAJ_POS_X 8 /* 6 */
#define MM_PFNN_Y_TRAJ_POS_Z 14
#define MM_PFNN_Y_TRAJ_DIR_X 20
#define MM_PFNN_Y_TRAJ_DIR_Z 26
#define MM_PFNN_Y_JOINT_POS  32  /* 31 x 3 */
#define MM_PFNN_Y_JOINT_VEL  125 /* 31 x 3 */
#define MM_PFNN_Y_JOINT_ROT  218 /* 31 x 3: exponential maps, half-angle convention */

/* ---- network ---------------------------------------------------------------------------------- */

/* How the weights at a phase are obtained. 0 is "the controller's default" (cubic) in descs. */
typedef enum mm_pfnn_mode {
    MM_PFNN_MODE_DEFAULT = 0,
    MM_PFNN_MODE_CONSTANT, /* S samples of the spline at 2 pi k / S (S = 50), the nearest lower one used */
    MM_PFNN_MODE_LINEAR,   /* S samples at 2 pi k / S (S = 10), interpolated linearly (cyclically) */
    MM_PFNN_MODE_CUBIC     /* the exact spline over the 4 control points at the phase */
} mm_pfnn_mode;

#define MM_PFNN_MODE_BIT(mode) (1u << (unsigned)(mode))

/* "constant", "linear", "cubic"; NULL for anything else. */
const char *mm_pfnn_mode_name(mm_pfnn_mode mode);
/* The inverse of mm_pfnn_mode_name; MM_PFNN_MODE_DEFAULT when the name is not a mode. */
mm_pfnn_mode mm_pfnn_mode_parse(const char *name);

typedef struct mm_pfnn_network mm_pfnn_network; /* opaque */

/* Defaults: modes 0 = cubic only; constant_samples 0 = 50; linear_samples 0 = 10. */
typedef struct mm_pfnn_network_desc {
    unsigned modes;                /* OR of MM_PFNN_MODE_BIT(mode): the modes to prepare */
    int constant_samples;          /* 1..1000 */
    int linear_samples;            /* 1..1000 */
    const mm_allocator *allocator; /* NULL: malloc */
} mm_pfnn_network_desc;

/* Loads dir/network/{Xmean,Xstd,Ymean,Ystd}.bin and {W,b}{0,1,2}_ctrl{0..3}.bin (raw float32,
 * little-endian) and precomputes the samples of the requested modes. Every file must have exactly
 * its expected size; a missing, short or long file fails with err->file naming it. Non-finite
 * values and a non-positive Xstd fail too. desc may be NULL. */
mm_result mm_pfnn_network_load(const char *dir, const mm_pfnn_network_desc *desc, mm_pfnn_network **out,
                               mm_error *err);
void mm_pfnn_network_free(mm_pfnn_network *net);
bool mm_pfnn_network_has_mode(const mm_pfnn_network *net, mm_pfnn_mode mode);
/* Bytes of weights a mode holds (0 if not prepared); MM_PFNN_MODE_DEFAULT: the whole network. */
size_t mm_pfnn_network_bytes(const mm_pfnn_network *net, mm_pfnn_mode mode);

/* One forward pass: x is the raw input (MM_PFNN_INPUT_DIM), y receives the de-normalised output
 * (MM_PFNN_OUTPUT_DIM); phase in radians, any value (wrapped into [0, 2 pi)). Returns
 * MM_ERR_INVALID_ARGUMENT when the mode was not prepared (MM_PFNN_MODE_DEFAULT means cubic).
 * Deterministic, allocation-free, thread-safe. */
mm_result mm_pfnn_network_eval(const mm_pfnn_network *net, mm_pfnn_mode mode, float phase, const float *x,
                               float *y);

/* The weights the given mode uses at phase for layer 0, 1 or 2: W [out x in] row-major, b [out]
 * (out x in = 512 x 342, 512 x 512, 311 x 512). For tests and for comparing implementations. */
mm_result mm_pfnn_network_layer(const mm_pfnn_network *net, mm_pfnn_mode mode, float phase, int layer,
                                float *W, float *b);

/* The periodic Catmull-Rom spline at phase as weights of the 4 control points: W(phase) =
 * sum_k coef[k] C(k). At phase 2 pi k / 4 coef is exactly the unit vector e_k. */
void mm_pfnn_spline_coefficients(double phase, double coef[MM_PFNN_CONTROL_POINTS]);
/* phase wrapped into [0, 2 pi). Values within 1e-6 cycles of a multiple of 1/100 cycle are moved
 * onto it, so that float phases 2 pi k / 4, / 10 and / 50 select their sample exactly. */
double mm_pfnn_wrap_phase(double phase);

/* ---- controller ------------------------------------------------------------------------------- */

/* Ground height (metres) at world (x, z). */
typedef float (*mm_pfnn_height_fn)(float x, float z, void *user);
/* y = 0 everywhere. */
float mm_pfnn_height_flat(float x, float z, void *user);
/* A test terrain of gentle hills: y = 0.35 sin(0.4 x) + 0.25 sin(0.3 z + 0.5 sin(0.2 x)) (slopes
 * up to about 20 degrees). user is ignored. */
float mm_pfnn_height_slopes(float x, float z, void *user);
/* The ground of a scene: user is a const mm_scene * (mm/scene.h), the height its
 * mm_scene_ground_height gives (ramps, stairs, a height field, box tops, the ground plane); a NULL
 * user is flat. On a scene that is the plane y = 0 it is exactly mm_pfnn_height_flat. */
float mm_pfnn_height_scene(float x, float z, void *user);

typedef enum mm_pfnn_obstacle_shape {
    MM_PFNN_OBSTACLE_CIRCLE = 0, /* a vertical cylinder: centre, radius */
    MM_PFNN_OBSTACLE_BOX         /* a vertical box: centre, half_extents x and z, turned by yaw about Y */
} mm_pfnn_obstacle_shape;

typedef struct mm_pfnn_obstacle {
    mm_pfnn_obstacle_shape shape;
    mm_vec3 centre;       /* metres; y ignored */
    float radius;         /* circle */
    float half_x, half_z; /* box, in its own frame */
    float yaw;            /* box: radians about Y */
} mm_pfnn_obstacle;

/* Gaits the player can ask for while moving (standing follows from a near-zero velocity). */
typedef enum mm_pfnn_gait {
    MM_PFNN_GAIT_WALK = 0,
    MM_PFNN_GAIT_JOG,
    MM_PFNN_GAIT_CROUCH,
    MM_PFNN_GAIT_JUMP
} mm_pfnn_gait;

/* What the player asks for this frame. Zero: stand still, facing unchanged. */
typedef struct mm_pfnn_input {
    mm_vec3 velocity;  /* desired root velocity, world, m/s (y ignored): the demo's speeds are 1.5 m/s
                          (walk) to 4.5 m/s (jog) */
    mm_vec3 facing;    /* desired facing (y ignored) for strafing; zero: face where you move */
    mm_pfnn_gait gait; /* gait while moving (crouch also applies standing) */
} mm_pfnn_input;

/* How the controller uses the network's left/right symmetry. The released network is slightly
 * asymmetric: fed a perfectly straight walk it steps 0.07 cm per frame to its right, and the
 * demo's loop (the future trajectory is the network's own prediction) amplifies that into a
 * steady 0.2 m/s sideways drift. Averaging each output with the mirror image of the output for
 * the mirrored input (at phase + pi: the other foot) cancels it, at twice the network cost. */
typedef enum mm_pfnn_symmetry {
    MM_PFNN_SYMMETRY_DEFAULT = 0, /* mirror-averaged */
    MM_PFNN_SYMMETRY_MIRROR,      /* y = (f(x, p) + M f(M x, p + pi)) / 2 */
    MM_PFNN_SYMMETRY_NONE         /* the network as released (the demo; drifts to the right) */
} mm_pfnn_symmetry;

/* Defaults (0): mode cubic; start at the origin facing +Z; flat ground; no obstacles; clearance
 * 0.3 m; target_blend 0.1; strafe_blend 0.1; gait_blend 0.1; trajectory_correction 0.5 (the
 * future trajectory moved half way toward the network's each frame; 1 replaces it, as the demo
 * does); joint_smooth 0.5 (posture = half previous position + velocity, half predicted, as the
 * seed says); pos_bias 2 and dir_bias 5 (exponents shaping how fast the predicted trajectory bends
 * toward the target: the demo's "responsive" values; its default 0.5 and 2 let the network's own
 * trajectory dominate, so a slow walk can settle into walking backwards; strafing moves them to
 * 1 and 0.5); symmetry mirror-averaged. All blends are per 60 Hz frame, in (0, 1]. */
typedef struct mm_pfnn_controller_desc {
    const mm_pfnn_network *network; /* required; must outlive the controller */
    mm_pfnn_mode mode;              /* must be prepared in the network */
    mm_vec3 start_position;         /* metres; y ignored (the terrain decides) */
    float start_yaw;                /* radians about Y; 0 faces +Z */
    mm_pfnn_height_fn height;       /* NULL: flat */
    void *height_user;
    const mm_pfnn_obstacle *obstacles; /* [obstacle_count], copied */
    int obstacle_count;                /* 0..256 */
    float clearance;                   /* metres the trajectory keeps from obstacles */
    float target_blend, strafe_blend, gait_blend, trajectory_correction, joint_smooth;
    float pos_bias, dir_bias;
    mm_pfnn_symmetry symmetry;
    const mm_allocator *allocator; /* NULL: malloc */
} mm_pfnn_controller_desc;

typedef struct mm_pfnn_controller mm_pfnn_controller; /* opaque */

/* The character after the latest frame. World space, metres, radians. */
typedef struct mm_pfnn_state {
    long frame;            /* 60 Hz frames stepped since the reset */
    float phase;           /* radians in [0, 2 pi) */
    mm_vec3 root_position; /* the current trajectory point, on the ground (mean terrain height) */
    float root_yaw;        /* facing, radians about Y (0: +Z) */
    float gait[MM_PFNN_GAIT_COUNT];
    float contacts[4];        /* the network's foot contacts: left heel, left toe, right heel, right toe */
    mm_vec3 target_velocity;  /* the blended target, m/s */
    mm_vec3 target_direction; /* unit */
    mm_vec3 joint_positions[MM_PFNN_JOINT_COUNT];       /* smoothed (what the next input sees) */
    mm_vec3 joint_predicted[MM_PFNN_JOINT_COUNT];       /* the network's positions this frame */
    mm_vec3 joint_velocities[MM_PFNN_JOINT_COUNT];      /* m/s */
    mm_quat joint_rotations[MM_PFNN_JOINT_COUNT];       /* global */
    mm_vec3 trajectory_positions[MM_PFNN_TRAJ_SAMPLES]; /* every 10th frame, index 6 = now */
    mm_vec3 trajectory_directions[MM_PFNN_TRAJ_SAMPLES];
    float input[MM_PFNN_INPUT_DIM];   /* the network input of the latest frame (raw) */
    float output[MM_PFNN_OUTPUT_DIM]; /* its output (de-normalised) */
} mm_pfnn_state;

mm_result mm_pfnn_controller_create(const mm_pfnn_controller_desc *desc, mm_pfnn_controller **out,
                                    mm_error *err);
void mm_pfnn_controller_destroy(mm_pfnn_controller *ctrl);
/* Back to the demo's initial state: the mean pose (Ymean) at position (on the terrain) facing yaw,
 * every trajectory point there, gait weights 0, phase 0. */
void mm_pfnn_controller_reset(mm_pfnn_controller *ctrl, mm_vec3 position, float yaw);
/* Advances by dt seconds in whole 60 Hz frames (the remainder carries over to the next call);
 * dt = 0 runs exactly one frame; at most 600 frames per call (the rest of a longer dt is dropped).
 * in may be NULL (no input). Returns the number of frames run.
 * Never allocates. */
int mm_pfnn_controller_step(mm_pfnn_controller *ctrl, const mm_pfnn_input *in, float dt);
const mm_pfnn_state *mm_pfnn_controller_state(const mm_pfnn_controller *ctrl);
/* The network input the current state gives, before any new player input (after a reset it is
 * the demo's X_C_reset). x holds MM_PFNN_INPUT_DIM floats. */
void mm_pfnn_controller_assemble_input(const mm_pfnn_controller *ctrl, float *x);
/* The pose as local rotations and translations of skeleton (mm_pfnn_character_load): the
 * root at the smoothed hips position, each joint's rotation relative to its parent's, the other
 * translations the rest offsets. Arrays of MM_PFNN_JOINT_COUNT. */
void mm_pfnn_controller_local_pose(const mm_pfnn_controller *ctrl, const mm_skeleton *skeleton,
                                   mm_quat *rotations, mm_vec3 *positions);

#ifdef __cplusplus
}
#endif

#endif /* MM_PFNN_H */
