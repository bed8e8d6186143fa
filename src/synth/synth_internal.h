/* synth_internal.h (private) - shared pieces of the procedural motion generator.
 *
 *   synth_skeleton.c  the standard body: proportions, joint indices, rest offsets
 *   synth_rng.c       seeded PRNG and the per-seed style
 *   synth_plan.c      control plans -> root trajectory, gait phase, planned footsteps
 *   synth_leg.c       stance rockers, swing arcs, pelvis reach limit, two-bone leg IK
 *   synth_body.c      pose assembly: pelvis, spine counter-rotation, arms, head -> local transforms
 *   synth_loco.c      locomotion (and idle) clips: plan + footsteps -> per-frame poses
 *   synth_jump.c      the standing jump
 *   synth_set.c       the clip list and the public API
 *
 * Units: metres, seconds, radians; Y up, the character faces +Z; left is +X.
 */
#ifndef MM_SYNTH_INTERNAL_H
#define MM_SYNTH_INTERNAL_H

#include <stdbool.h>
#include <stdint.h>

#include <mm/math.h>
#include <mm/synth.h>

#define SYNTH_PI      3.14159265358979323846f
#define SYNTH_TAU     6.28318530717958647692f
#define SYNTH_GRAVITY 9.81f

/* Joint indices of the standard skeleton (LAFAN1 order). */
enum synth_joint {
    SJ_HIPS,
    SJ_LUPLEG,
    SJ_LLEG,
    SJ_LFOOT,
    SJ_LTOE,
    SJ_RUPLEG,
    SJ_RLEG,
    SJ_RFOOT,
    SJ_RTOE,
    SJ_SPINE,
    SJ_SPINE1,
    SJ_SPINE2,
    SJ_NECK,
    SJ_HEAD,
    SJ_LSHOULDER,
    SJ_LARM,
    SJ_LFOREARM,
    SJ_LHAND,
    SJ_RSHOULDER,
    SJ_RARM,
    SJ_RFOREARM,
    SJ_RHAND,
    SJ_COUNT
};

/* Side index: 0 left (+X), 1 right (-X). */
#define SYNTH_LEFT  0
#define SYNTH_RIGHT 1
static inline float synth_side_sign(int side) { return side == SYNTH_LEFT ? 1.0f : -1.0f; }

/* ---- body (synth_skeleton.c) ------------------------------------------------------------ */

typedef struct synth_body {
    mm_vec3 offset[SJ_COUNT]; /* rest offsets from the parent (root: rest Hips position) */
    int parent[SJ_COUNT];
    float thigh, shin;  /* bone lengths */
    float ankle_height; /* Foot joint above the ground when the foot is flat */
    mm_vec3 toe_offset; /* Foot -> Toe in the flat foot's frame */
    float leg_reach;    /* largest hip-ankle distance allowed (knee flexed at least min_knee) */
    float min_knee;     /* smallest knee flexion, rad */
    float stand_height; /* Hips height of the relaxed standing pose */
    float height;       /* top of the head when standing straight */
} synth_body;

extern const char *const synth_joint_names[SJ_COUNT];
void synth_body_init(synth_body *b);
/* Hips height at which the hip-ankle distance of a vertical leg gives knee flexion knee (rad). */
float synth_leg_length_at(const synth_body *b, float knee);

/* ---- randomness and style (synth_rng.c) ------------------------------------------------- */

typedef struct synth_rng {
    uint64_t s;
} synth_rng;
void synth_rng_seed(synth_rng *r, uint64_t seed);
uint64_t synth_rng_next(synth_rng *r);
/* Uniform in [lo, hi). */
float synth_rng_uniform(synth_rng *r, float lo, float hi);

/* Per-seed style: multipliers near 1 and small offsets, all within plausible ranges. */
typedef struct synth_style {
    float cadence;     /* multiplies the step frequency */
    float arm_swing;   /* multiplies arm swing amplitude */
    float bob;         /* multiplies vertical pelvis motion */
    float sway;        /* multiplies lateral pelvis motion */
    float pelvis_rot;  /* multiplies pelvis yaw and list */
    float step_width;  /* half distance between the feet's tracks while walking, m */
    float stand_width; /* half distance between the feet when standing, m */
    float toe_out;     /* foot progression angle, rad */
    float lean;        /* multiplies forward lean */
    float elbow;       /* walking elbow flexion, rad */
    float head_pitch;  /* gaze pitch, rad (positive looks down) */
    float idle_phase[4];
    float idle_amp[4];
} synth_style;
void synth_style_init(synth_style *st, uint64_t seed);

/* ---- small math ------------------------------------------------------------------------- */

static inline float synth_clampf(float x, float lo, float hi) { return x < lo ? lo : x > hi ? hi : x; }
static inline float synth_lerpf(float a, float b, float t) { return a + (b - a) * t; }
/* 0 for x <= 0, 1 for x >= 1, C2 in between (6x^5 - 15x^4 + 10x^3). */
static inline float synth_smoother(float x)
{
    x = synth_clampf(x, 0.0f, 1.0f);
    return x * x * x * (x * (x * 6.0f - 15.0f) + 10.0f);
}
static inline float synth_smooth(float x)
{
    x = synth_clampf(x, 0.0f, 1.0f);
    return x * x * (3.0f - 2.0f * x);
}
/* Smooth minimum (polynomial, C1); never above min(a, b); k is the blend width. */
static inline float synth_smin(float a, float b, float k)
{
    float h = synth_clampf(0.5f + 0.5f * (b - a) / k, 0.0f, 1.0f);
    return b + (a - b) * h - k * h * (1.0f - h);
}
/* Cubic Hermite: value at s in [0, 1] from p0, tangent m0 (d/ds), p1, m1. */
static inline float synth_hermite(float p0, float m0, float p1, float m1, float s)
{
    float s2 = s * s, s3 = s2 * s;
    return (2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * m0 + (-2 * s3 + 3 * s2) * p1 + (s3 - s2) * m1;
}
static inline float synth_hermite_d(float p0, float m0, float p1, float m1, float s)
{
    float s2 = s * s;
    return (6 * s2 - 6 * s) * p0 + (3 * s2 - 4 * s + 1) * m0 + (-6 * s2 + 6 * s) * p1 + (3 * s2 - 2 * s) * m1;
}
/* Quintic Hermite with zero end accelerations: C2 joins to motions that are not accelerating. */
static inline float synth_hermite5(float p0, float m0, float p1, float m1, float s)
{
    float s2 = s * s, s3 = s2 * s, s4 = s3 * s, s5 = s4 * s;
    return (1 - 10 * s3 + 15 * s4 - 6 * s5) * p0 + (s - 6 * s3 + 8 * s4 - 3 * s5) * m0 +
           (-4 * s3 + 7 * s4 - 3 * s5) * m1 + (10 * s3 - 15 * s4 + 6 * s5) * p1;
}
static inline mm_vec3 synth_vec3_hermite5(mm_vec3 p0, mm_vec3 m0, mm_vec3 p1, mm_vec3 m1, float s)
{
    return mm_vec3_make(synth_hermite5(p0.x, m0.x, p1.x, m1.x, s), synth_hermite5(p0.y, m0.y, p1.y, m1.y, s),
                        synth_hermite5(p0.z, m0.z, p1.z, m1.z, s));
}
/* Wraps an angle to (-pi, pi]. */
float synth_wrap_angle(float a);
static inline mm_vec3 synth_vec3_hermite(mm_vec3 p0, mm_vec3 m0, mm_vec3 p1, mm_vec3 m1, float s)
{
    return mm_vec3_make(synth_hermite(p0.x, m0.x, p1.x, m1.x, s), synth_hermite(p0.y, m0.y, p1.y, m1.y, s),
                        synth_hermite(p0.z, m0.z, p1.z, m1.z, s));
}
static inline mm_quat synth_quat_axis(float x, float y, float z, float angle)
{
    float h = 0.5f * angle, s = sinf(h);
    return mm_quat_make(x * s, y * s, z * s, cosf(h));
}
static inline mm_quat synth_rot_x(float a) { return synth_quat_axis(1, 0, 0, a); }
static inline mm_quat synth_rot_y(float a) { return synth_quat_axis(0, 1, 0, a); }
static inline mm_quat synth_rot_z(float a) { return synth_quat_axis(0, 0, 1, a); }
/* R_y(yaw) * R_x(pitch) * R_z(roll): pitch > 0 tips the top forward (+Z), roll > 0 tips it to
 * the right (-X). */
static inline mm_quat synth_yaw_pitch_roll(float yaw, float pitch, float roll)
{
    return mm_quat_mul(synth_rot_y(yaw), mm_quat_mul(synth_rot_x(pitch), synth_rot_z(roll)));
}
/* Rotation taking the orthonormal pair (rest_primary, rest_secondary) to (primary, secondary);
 * secondary is made orthogonal to primary first. */
mm_quat synth_quat_from_frame(mm_vec3 primary, mm_vec3 secondary, mm_vec3 rest_primary,
                              mm_vec3 rest_secondary);
/* q^t for t in [0, 1] (the same axis, t times the angle). */
mm_quat synth_quat_pow(mm_quat q, float t);
/* Horizontal unit vector of heading yaw: (sin yaw, 0, cos yaw). */
static inline mm_vec3 synth_heading_dir(float yaw) { return mm_vec3_make(sinf(yaw), 0.0f, cosf(yaw)); }

/* ---- legs (synth_leg.c) ----------------------------------------------------------------- */

/* Global state of one foot for a frame. */
typedef struct synth_foot {
    mm_vec3 ankle;   /* Foot joint target, world */
    float yaw;       /* heading of the foot, rad */
    float pitch;     /* toe-up angle, rad: > 0 toes up (heel rocker), < 0 heel up (toe rocker) */
    float toe_angle; /* Toe joint local rotation about X, rad (< 0: toes bent up) */
    bool heel, toe;  /* contact flags: this joint is planted */
    float margin;    /* extra reach margin the pelvis keeps for this foot, m (knee flexion
                        around liftoff and touchdown) */
} synth_foot;

/* Global rotation of a foot of this yaw and toe-up pitch. */
static inline mm_quat synth_foot_rotation(float yaw, float pitch)
{
    return mm_quat_mul(synth_rot_y(yaw), synth_rot_x(-pitch));
}
/* Ankle position of a foot whose flat ankle position is plant, rotated by pitch about the heel
 * (Foot joint, pitch >= 0) or the toe (Toe joint, pitch < 0). */
mm_vec3 synth_foot_pivot(const synth_body *b, mm_vec3 plant, float yaw, float pitch);
/* d(ankle)/d(pitch) of synth_foot_pivot. */
mm_vec3 synth_foot_pivot_d(const synth_body *b, float yaw, float pitch);

/* Two-bone IK: from the hip position, the ankle target and the knee pole direction, the global
 * rotations of the thigh and shin (knee a pure hinge about the thigh's X axis, bending forward
 * toward pole). Targets beyond b->leg_reach are pulled in along the hip-ankle line. Returns the
 * achieved ankle position. */
mm_vec3 synth_leg_ik(const synth_body *b, mm_vec3 hip, mm_vec3 ankle, mm_vec3 pole, mm_quat *thigh,
                     mm_quat *shin);

/* Hip joint position for a pelvis at pos with rotation rot. */
mm_vec3 synth_hip_position(const synth_body *b, int side, mm_vec3 pelvis, mm_quat rot);
/* Highest pelvis height at which the ankle target is within reach of that side's hip, for a pelvis
 * of this rotation whose horizontal position is pelvis (its y ignored). Smooth in the inputs. */
float synth_pelvis_reach(const synth_body *b, int side, mm_vec3 pelvis, mm_quat rot, mm_vec3 ankle);

/* ---- gait model (synth_gait.c) ---------------------------------------------------------- */

/* Gait parameters at a speed, walk/run blend and activity (all amplitudes already scaled by the
 * activity and the style). Phases are in gait cycles (one cycle = two steps). */
typedef struct synth_gait {
    float freq;          /* gait cycles per second */
    float duty;          /* stance fraction of a cycle, per foot */
    float width;         /* half distance between the feet's tracks, m */
    float heel_strike;   /* toe-up foot angle at touchdown, rad */
    float toe_off;       /* heel-up foot angle at liftoff, rad */
    float roll_in;       /* stance fraction of the landing rocker */
    float roll_out;      /* stance fraction of the push-off rocker */
    float swing_height;  /* ankle clearance added to the swing arc, m */
    float swing_peak;    /* swing fraction where the clearance peaks */
    float plant_ref;     /* stance fraction at which the ankle is under the hip */
    float pelvis_height; /* desired Hips height, m (lowered where a foot needs it) */
    float bob;           /* vertical pelvis amplitude, m; > 0 highest at mid-stance (walk) */
    float sway;          /* lateral pelvis amplitude toward the stance foot, m */
    float yaw;           /* pelvis transverse rotation amplitude, rad */
    float list;          /* pelvis obliquity amplitude, rad (swing side drops) */
    float lean;          /* trunk forward lean, rad */
    float counter;       /* chest yaw relative to the pelvis, as a multiple of -pelvis yaw */
    float arm_swing;     /* shoulder flexion amplitude, rad */
    float arm_carry;     /* mean shoulder flexion, rad */
    float arm_abduct;    /* rad */
    float elbow;         /* mean elbow flexion, rad */
    float elbow_swing;   /* extra elbow flexion when the arm is forward, rad */
} synth_gait;

void synth_gait_eval(const synth_body *b, const synth_style *st, float speed, float gait, float activity,
                     float turn_rate, float direction, synth_gait *out);
/* Rocker scale: 0 standing, 1 from about 0.9 m/s. */
float synth_roll_scale(float speed);

/* ---- pose (synth_body.c) ---------------------------------------------------------------- */

typedef struct synth_pose {
    mm_vec3 pelvis;     /* Hips position, world */
    mm_quat pelvis_rot; /* Hips rotation, world */
    float facing;       /* heading of the body, rad (the gaze follows it) */
    synth_foot foot[2];
    mm_quat chest;                         /* desired Spine2 rotation, world; the spine distributes it */
    float breath;                          /* -1..1: chest and clavicle breathing */
    float head_yaw, head_pitch, head_roll; /* head rotation, world (yaw absolute) */
    float arm_swing[2];                    /* shoulder flexion, rad (> 0 forward) */
    float arm_abduct[2];                   /* away from the body, rad */
    float elbow[2];                        /* elbow flexion, rad */
    float clavicle[2];                     /* clavicle elevation, rad */
    float wrist[2];                        /* wrist flexion, rad */
} synth_pose;

/* Writes the local rotations and translations (SJ_COUNT each) of the pose. */
void synth_pose_to_locals(const synth_body *b, const synth_pose *p, mm_quat *rot, mm_vec3 *pos);

/* ---- clip generation -------------------------------------------------------------------- */

/* Scratch memory reused by every clip of a set. */
#define SYNTH_WORK_SLOTS 2
typedef struct synth_work {
    void *mem[SYNTH_WORK_SLOTS];
    size_t capacity[SYNTH_WORK_SLOTS];
} synth_work;

typedef struct synth_ctx {
    synth_body body;
    synth_style style;
    float fps;
    synth_work work;
    mm_skeleton skeleton;
    const mm_allocator *allocator;
} synth_ctx;

/* Plan keyframe: values hold at t and change smoothly (C2) to the next key. */
typedef struct synth_key {
    float t;         /* s */
    float speed;     /* m/s along the travel direction */
    float curvature; /* 1/m of the path, > 0 turns left */
    float direction; /* travel direction relative to facing, rad */
    float turn_rate; /* extra facing rotation, rad/s, > 0 left (turning on the spot) */
    float gait;      /* 0 walk, 1 run */
    float activity;  /* 0 standing, 1 stepping */
} synth_key;

#define SYNTH_MAX_KEYS 32

typedef struct synth_plan {
    synth_key keys[SYNTH_MAX_KEYS];
    int key_count;
    float duration;  /* s of output; for gait loops the exact length is derived from loop_cycles */
    bool loop;       /* the clip loops: frames cover [0, duration) */
    int loop_cycles; /* > 0: a gait loop of this many cycles (the plan must be constant) */
    float period;    /* > 0: the keys (in [0, period], equal values at both ends) repeat with this
                        period; a loop of exactly this length (period * fps a whole number) */
    int lead;        /* foot that steps first from rest */
} synth_plan;

/* Plan values at time t (clamped to the keys), and d(speed)/dt. */
void synth_plan_values(const synth_plan *p, float t, synth_key *out, float *accel);

/* Lean into a turn, rad (> 0 leans left), from speed and path curvature. */
float synth_turn_lean(float speed, float curvature);

/* One stance of one foot: the plant and its rockers. Phases are in gait cycles. */
typedef struct synth_stance {
    double phi_td, phi_lo; /* touchdown and liftoff phase */
    mm_vec3 plant;         /* ankle position when the foot is flat */
    float yaw;             /* heading of the foot */
    float beta_td;         /* foot angle at touchdown (> 0 toes up: heel first) */
    float beta_lo;         /* foot angle at liftoff (< 0 heel up: toe last) */
    float u1, u2;          /* the foot is flat for stance fractions [u1, u2] */
    float swing_height;    /* clearance of the swing that follows, m */
    float swing_peak;      /* where in that swing the clearance peaks */
} synth_stance;

typedef struct synth_sample {
    double phi;     /* gait phase, cycles */
    double x, z;    /* root trajectory on the ground */
    double heading; /* facing, rad */
} synth_sample;

/* The simulated plan: root trajectory and phase at a fine rate, and the planned footsteps. */
typedef struct synth_track {
    const synth_plan *plan;
    int frames;      /* output frames */
    int substeps;    /* samples per output frame */
    float dt;        /* sample spacing, s */
    float t0;        /* time of sample 0 (negative: pre-roll) */
    int zero;        /* sample index of t = 0; frame f is sample zero + f * substeps */
    int count;       /* samples */
    synth_sample *s; /* [count] */
    double phi_rest_start, phi_rest_end;
    bool rest_start, rest_end;
    float foot_offset[2]; /* touchdown phase of each foot within a cycle */
    synth_stance *stance[2];
    int stance_count[2];
} synth_track;

/* Simulates the plan into tr, using ctx->work for memory (valid until the next call). */
mm_result synth_track_build(synth_ctx *ctx, const synth_plan *plan, synth_track *tr);
/* State of one foot at phase phi. */
void synth_track_foot(const synth_body *b, const synth_track *tr, int side, double phi, synth_foot *out);

/* At least bytes of scratch memory in slot (0: track, 1: per-frame poses), kept for the next
 * clip; NULL when out of memory. */
void *synth_work_get(synth_ctx *ctx, int slot, size_t bytes);
void synth_work_free(synth_ctx *ctx);

/* Fills out->clip and out->contacts for the plan (locomotion and idle). */
mm_result synth_make_loco(synth_ctx *ctx, const synth_plan *plan, mm_synth_clip *out);
/* Standing jump forward by about distance metres. */
mm_result synth_make_jump(synth_ctx *ctx, float distance, mm_synth_clip *out);
/* Allocates the clip and contacts of frame_count frames. */
mm_result synth_clip_alloc(synth_ctx *ctx, int frame_count, mm_synth_clip *out);

#endif
