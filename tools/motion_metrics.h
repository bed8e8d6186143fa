/* motion_metrics.h - the quality metrics of docs/metrics.md, measured the same way for every
 * controller (mm simulate: motion matching; mm pfnn run: the neural controller), frame by frame. */
#ifndef MM_TOOLS_MOTION_METRICS_H
#define MM_TOOLS_MOTION_METRICS_H

#include <stdio.h>

#include <mm/input.h>
#include <mm/math.h>
#include <mm/scene.h>

#define MOTION_METRICS_MAX_MOVES 1024

typedef struct motion_metrics {
    int joint_count;
    double fps;
    int contact_joint[4]; /* left heel, left toe, right heel, right toe (-1: none) */
    mm_vec3 *world[3];    /* the last three frames' joint positions */
    mm_vec3 raw_previous[4];
    long frames;
    double slide_sum, slide_frames, raw_sum, traj_err, heading_err, max_pop;
    int nan_frames;
    /* response: time from a sharp stick turn to the root moving within 20 degrees of it */
    double response_sum;
    int responses, pending, had_stick;
    float pending_direction, pending_since, last_stick_direction;
    mm_vec3 previous_root;
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
} motion_metrics;

/* The heading of a rotation: the yaw of its +Z axis on the ground (radians, 0 = +Z). */
float motion_metrics_yaw(mm_quat q);

/* Room for frames frames of joint_count joints at fps; contact_joint: see above. 0 on success. */
int motion_metrics_init(motion_metrics *m, int joint_count, const int contact_joint[4], double fps,
                        long frames);
void motion_metrics_free(motion_metrics *m);

/* Before the controller's update of frame t: the input and the desired velocity it gives (for
 * the response measure). */
void motion_metrics_input(motion_metrics *m, double t, const mm_input *in, mm_vec3 desired_velocity);
/* After it: world joint positions; which contact labels are on (bits: left heel, left toe, right
 * heel, right toe); the contact joints before foot IK (NULL: the same as world); the desired
 * path's position and yaw (the trajectory simulation) and the character's root and yaw; the
 * controller's cost of this frame (us). */
void motion_metrics_frame(motion_metrics *m, double t, const mm_vec3 *world, unsigned contacts,
                          const mm_vec3 *raw_contacts, mm_vec3 sim_position, float sim_yaw, mm_vec3 root,
                          float root_yaw, float frame_us);
void motion_metrics_search(motion_metrics *m, float us);
/* The scene the character moves in (penetration_max_cm is measured against its boxes). */
void motion_metrics_scene(motion_metrics *m, const mm_scene *scene);
/* A move performed (kind: a static string); the first MOTION_METRICS_MAX_MOVES are kept. */
void motion_metrics_move(motion_metrics *m, const char *kind, double t_start, double t_end,
                         double target_error_cm);

typedef struct motion_metrics_extra { /* what only the caller knows; NAN: null */
    double db_max_pop_cm, searches, transitions_per_s, memory_mb;
} motion_metrics_extra;

/* The metrics as JSON (docs/metrics.md's keys). */
void motion_metrics_write_json(motion_metrics *m, FILE *f, const motion_metrics_extra *extra);
double motion_metrics_foot_slide(const motion_metrics *m);
double motion_metrics_traj_err(const motion_metrics *m);

#endif
