/* motion_metrics.h - the quality metrics of docs/metrics.md, measured the same way for every
 * controller (mm simulate: motion matching; mm pfnn run: the neural controller) and for motion read
 * from a file (mm metrics: the measures of the pose alone), frame by frame. */
#ifndef MM_TOOLS_MOTION_METRICS_H
#define MM_TOOLS_MOTION_METRICS_H

#include <stdint.h>
#include <stdio.h>

#include <mm/database.h>
#include <mm/input.h>
#include <mm/math.h>
#include <mm/posture.h>
#include <mm/scene.h>
#include <mm/skeleton.h>

#define MOTION_METRICS_MAX_MOVES 1024
/* m: foot_slide_height_cm_s counts a foot while it is less than this above its planted height */
#define MOTION_METRICS_SLIDE_HEIGHT 0.025
/* s: and has been for longer than this (a foot swinging past the ground is not planted) */
#define MOTION_METRICS_SLIDE_DWELL 0.1
/* s: foot_float_cm counts a foot once its label has been on this long (the feet stage's longest
 * landing, MM_FEET_LANDING_MAX_TIME) */
#define MOTION_METRICS_FLOAT_LANDING 0.1

/* The height-weighted slide of the contact bones (foot_slide_height_cm_s) as it accumulates. */
typedef struct motion_metrics_slide {
    double sum, weight;
    long near[4]; /* frames each bone has been within MOTION_METRICS_SLIDE_HEIGHT */
} motion_metrics_slide;
/* Contact bone k at h (m) above its planted height moved (dx, dz) (m) since the frame before, at fps. */
void motion_metrics_slide_add(motion_metrics_slide *s, int k, double h, double dx, double dz, double fps);
/* cm/s; NAN when no frame counted. */
double motion_metrics_slide_value(const motion_metrics_slide *s);
/* m: with a scene, a box top at most this far above a joint is the ground under it (the joint sank
 * into it); a higher top is a wall the joint is inside (penetration_max_cm), not ground */
#define MOTION_METRICS_STEP_HEIGHT 0.3f

/* Where a worst value happened: the frame of the output (its time frame / fps) and the joint (-1:
 * none); value in the metric's own unit. frame -1: never measured. */
typedef struct motion_metrics_worst {
    double value;
    long frame;
    int joint;
} motion_metrics_worst;
/* s: the window the worst stretch of labelled slide is found over */
#define MOTION_METRICS_SLIDE_WINDOW 1.0

/* The time a point takes to move the way a sharp stick turn asks, as it accumulates. */
typedef struct motion_metrics_response {
    double sum;
    int count, pending;
    float direction, since; /* the turn's desired direction (yaw) and when it came */
    mm_vec3 previous;       /* the point on the frame before */
} motion_metrics_response;

typedef struct motion_metrics {
    int joint_count;
    const mm_joint *joints; /* their names in "where" (NULL: joint indices) */
    double fps;
    int contact_joint[4]; /* left heel, left toe, right heel, right toe (-1: none) */
    mm_vec3 *world[3];    /* the last three frames' joint positions */
    mm_vec3 raw_previous[4];
    long frames;
    double slide_sum, slide_frames, raw_sum, traj_err, heading_err, max_pop;
    int nan_frames;
    /* response: time from a sharp stick turn to the root (and, apart, the simulated path) moving
     * within 20 degrees of it */
    motion_metrics_response response_root, response_sim;
    int had_stick;
    float last_stick_direction;
    /* per-frame controller cost and search times (us), kept for medians */
    float *frame_us, *search_us;
    long frame_capacity, search_count;
    /* moves (mm/moves.h): the scene (NULL: none), the deepest any joint went into a box (m), the
     * moves performed */
    const mm_scene *scene;
    double penetration_max;
    int move_count;
    struct {
        const char *kind;
        double t_start, t_end, target_error_cm;
    } moves[MOTION_METRICS_MAX_MOVES];
    /* What a person sees. The posture's joints (-1: none), the upright head height (0: unknown),
     * each contact joint's planted height above the ground (m; NAN: unknown); pose_only: no
     * controller gives labels, a path or timings (their keys are null). */
    mm_posture_joints posture_joints;
    mm_posture_reference reference;
    double planted[4];
    int pose_only;
    int crouch_input;        /* the input of the coming frame asks for the crouch gait */
    double below_ground;     /* m: the deepest any joint but joint 0 went below the ground under it */
    double foot_float;       /* m: the largest gap under a foot whose contact label is on (its lower
                                of ankle and toe, each above its planted height) */
    long foot_float_frames;  /* frames with a labelled foot measured */
    long labelled_frames[2]; /* frames each foot's heel or toe label has been on */
    double contact_err_sum, contact_err_count, contact_on, contact_pairs;
    motion_metrics_slide slide_height;
    double hands_apart_max; /* m */
    long arms_out_frames;
    /* where the largest pop (cm), the deepest joint below the ground (cm) and the largest float
     * (cm) happened */
    motion_metrics_worst worst_pop, worst_below, worst_float;
    /* per frame (frame_capacity of each): the head's height above the ground (m; NAN: none), the
     * largest second difference over joints (m; from the third frame on, at index frame - 2), the
     * posture (mm_posture) and whether the input asked for the crouch gait */
    float *head_height, *pop;
    uint8_t *posture, *crouch;
    /* per frame: the labelled contact bones' ground speeds summed (cm/s) and how many there were */
    float *slide;
    uint8_t *slide_count;
} motion_metrics;

/* The heading of a rotation: the yaw of its +Z axis on the ground (radians, 0 = +Z). */
float motion_metrics_yaw(mm_quat q);

/* Room for frames frames of joint_count joints at fps; contact_joint: see above. No posture
 * joints, reference or planted heights yet (motion_metrics_reference). 0 on success. */
int motion_metrics_init(motion_metrics *m, int joint_count, const int contact_joint[4], double fps,
                        long frames);
void motion_metrics_free(motion_metrics *m);

/* The posture's joints, the upright head height (m, 0: unknown) and the contact joints' planted
 * heights (m above the ground, NULL or NAN: unknown), before the first frame. */
void motion_metrics_reference(motion_metrics *m, const mm_posture_joints *joints, float head_height,
                              const double planted[4]);
/* The same from the motion itself, frames x joint_count world positions (the posture's joints
 * given): the head height is mm_posture_reference_height of the head's heights, each contact
 * joint's planted height the 5th percentile of its heights (above the ground: call it after
 * motion_metrics_scene). */
void motion_metrics_reference_from_motion(motion_metrics *m, const mm_posture_joints *joints,
                                          const mm_vec3 *world, long frames);

/* Before the controller's update of frame t: the input and the desired velocity it gives (for
 * the response measure and the posture's crouch exemption). */
void motion_metrics_input(motion_metrics *m, double t, const mm_input *in, mm_vec3 desired_velocity);
/* After it: world joint positions; which contact labels are on (bits: left heel, left toe, right
 * heel, right toe); the contact joints before foot IK (NULL: the same as world); the desired
 * path's position and yaw (the trajectory simulation) and the character's root and yaw; the
 * controller's cost of this frame (us). */
void motion_metrics_frame(motion_metrics *m, double t, const mm_vec3 *world, unsigned contacts,
                          const mm_vec3 *raw_contacts, mm_vec3 sim_position, float sim_yaw, mm_vec3 root,
                          float root_yaw, float frame_us);
/* A frame of motion without a controller (mm metrics): the measures of the pose alone. Sets
 * pose_only: the keys that need a controller are null. */
void motion_metrics_pose(motion_metrics *m, const mm_vec3 *world);
void motion_metrics_search(motion_metrics *m, float us);
/* The scene the character moves in (penetration_max_cm is measured against its boxes; heights are
 * above the surface under a joint). */
void motion_metrics_scene(motion_metrics *m, const mm_scene *scene);
/* A move performed (kind: a static string); the first MOTION_METRICS_MAX_MOVES are kept. */
void motion_metrics_move(motion_metrics *m, const char *kind, double t_start, double t_end,
                         double target_error_cm);

/* The largest |now - 2 before + before2| over n joints (m; non-finite joints left out, 0 if none);
 * the joint it is at in *joint when joint is not NULL (-1 if none). */
double motion_metrics_frame_pop(const mm_vec3 *now, const mm_vec3 *before, const mm_vec3 *before2, int n,
                                int *joint);
/* The value at rank floor(q (n - 1)) of the finite values of v once sorted (v is left as it is);
 * NAN when none is finite or memory runs out. */
double motion_metrics_percentile(const float *v, long n, double q);

/* The contact joints (left heel, left toe, right heel, right toe) and the posture's joints: from a
 * database's bone roles (mm_database_role_joint: its settings, else the default names), or (by
 * name) from a skeleton's joints named as the roles' defaults (mm_role_default_name; a toe's
 * default name with "Base" after it first: LeftToeBase). -1: none. */
void motion_metrics_roles_of_database(const mm_database *db, int contact[4], mm_posture_joints *joints);
void motion_metrics_roles_by_name(const mm_skeleton *s, int contact[4], mm_posture_joints *joints);

/* What a database gives the metrics (docs/metrics.md). */
typedef struct motion_metrics_db {
    double max_pop_cm, pop_p99_cm;  /* over its clips played in order at the output rate */
    double foot_slide_height_cm_s;  /* the same, on the planted heights below */
    double head_p5_cm, head_p50_cm; /* the head's height over its upright locomotion (NAN: none) */
    float reference;                /* m: the upright head height (0: no head) */
    double planted[4];              /* m: each contact joint's planted height (NAN: none) */
} motion_metrics_db;
/* Measures db at fps (one pass over its clips resampled to fps, one over its frames); roles from
 * its settings. 0 on success, -1 when out of memory. */
int motion_metrics_database(const mm_database *db, double fps, motion_metrics_db *out);

typedef struct motion_metrics_extra { /* what only the caller knows; NAN: null */
    double db_max_pop_cm, searches, transitions_per_s, memory_mb;
    double db_pop_p99_cm, db_head_p5_cm, db_head_p50_cm, db_foot_slide_height_cm_s;
} motion_metrics_extra;

/* The measures of the pose (NAN: null), as motion_metrics_write_json writes them. 0 on success,
 * -1 when out of memory. */
typedef struct motion_metrics_seen {
    double below_ground_cm, contact_height_err_cm, contact_share, foot_slide_height_cm_s, foot_float_cm;
    double max_pop_cm, pop_p99_cm, head_p2_cm, head_p5_cm, head_p50_cm;
    double crouched_s, bent_s, lying_s, calibration_s, arms_spread_s, hand_raised_s, knee_raised_s,
        arms_out_s, hands_apart_max_cm;
    /* the longest stretch counted in those seconds: its first frame (-1: none), length (frames) and
     * posture */
    long posture_first, posture_frames;
    mm_posture posture_worst;
} motion_metrics_seen;
int motion_metrics_summary(const motion_metrics *m, motion_metrics_seen *out);
/* The MOTION_METRICS_SLIDE_WINDOW seconds of frames (all of them in a shorter motion) whose
 * labelled slide adds the most to foot_slide_cm_s: their first frame (-1: no labelled slide), their
 * length (s), the mean of their labelled bones' speeds (cm/s) and their share of all the labelled
 * slide. */
long motion_metrics_worst_slide(const motion_metrics *m, double *seconds, double *cm_s, double *share);

/* The metrics as JSON (docs/metrics.md's keys). extra may be NULL. */
void motion_metrics_write_json(motion_metrics *m, FILE *f, const motion_metrics_extra *extra);
double motion_metrics_foot_slide(const motion_metrics *m);
double motion_metrics_traj_err(const motion_metrics *m);

#endif
