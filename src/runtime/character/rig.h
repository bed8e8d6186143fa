/* The character's rig: the joints its stages work on, found once in the database's skeleton. */
#ifndef MM_RUNTIME_RIG_H
#define MM_RUNTIME_RIG_H

#include <mm/database.h>

/* spine joints turned back by orientation warping */
#define MM_RIG_MAX_SPINE 8

typedef struct mm_rig {
    const mm_joint *joints; /* the database's skeleton: parents before children */
    int joint_count;
    /* per leg (0 left, 1 right): ankle, knee, hip; the toe is the ankle's first child (the
     * character sets the toe role instead where it hangs from the ankle); -1 when the leg is
     * missing or does not hang two joints below the root */
    int ankle[2], knee[2], hip[2], toe[2];
    /* per leg: the end (exclusive) of the joints that hang from its hip, which follow the hip in
     * the skeleton's order (hip .. leg_end - 1); -1 when they do not (mm_rig_forward_legs then runs
     * the whole skeleton's forward kinematics) */
    int leg_end[2];
    int pelvis;                  /* the joint both legs hang from, -1 */
    int spine[MM_RIG_MAX_SPINE]; /* from the pelvis up: its child that no leg hangs from, then
                                    single children up to where the chain branches */
    int spine_count;
    /* per leg: the knee's hinge, the axis it bends about, in the knee joint's own frame (learned
     * from the database: cross(thigh, shin) where the knee is clearly bent); zero when unknown */
    mm_vec3 hinge[2];
    /* per leg: the ankle's and the toe's height above the ground (the root's height) where the
     * database labels them planted (the median over its labelled frames); 0 when unknown */
    float planted_ankle[2], planted_toe[2];
    /* m: the hips' (the pelvis's) lowest height above the ground in the database's upright
     * locomotion, MM_RIG_HIP_FLOOR_QUANTILE of it over its locomotion frames not tagged for another
     * gait (mm_rig_learn_hip_floor); the feet stage lowers the hips no further; 0 when unknown */
    float hip_floor;
    /* the head joint (the database's head role, hanging from the pelvis; -1 when unknown) and m: the
     * height above the ground under which the metric's posture classifier calls a head crouched,
     * MM_POSTURE_CROUCHED_HEIGHT x the reference (MM_POSTURE_REFERENCE_QUANTILE of the head's heights
     * over the database's locomotion and idle frames; mm_rig_learn_head_floor); the feet stage
     * lowers the hips no further than keeps the head above it; 0 when unknown */
    int head;
    float head_floor;
} mm_rig;

/* Learns each knee's hinge from the frames of db (whose skeleton the rig was made on). */
void mm_rig_learn_hinges(mm_rig *rig, const mm_database *db);

/* Learns each foot's planted heights (mm_rig.planted_ankle, planted_toe) from the frames of db
 * whose contact labels are on. */
void mm_rig_learn_planted_heights(mm_rig *rig, const mm_database *db);

/* the share of the database's upright locomotion frames whose hips are lower than mm_rig.hip_floor:
 * its lowest strides and turns, where the feet stage would rather let a lock creep than sink the
 * body (a trade of posture against slide: docs/metrics.md, "Seeds never tuned on, and the hips'
 * floor at the 5% quantile") */
#define MM_RIG_HIP_FLOOR_QUANTILE 0.05f

/* Learns mm_rig.hip_floor from the frames of db's locomotion clips that carry none of the tags in
 * other_gaits (the crouch and jump gaits' tags); 0 without any such frame or without a pelvis. */
void mm_rig_learn_hip_floor(mm_rig *rig, const mm_database *db, uint64_t other_gaits);

/* Learns mm_rig.head and head_floor from db's head role and its locomotion and idle frames; head -1
 * and head_floor 0 without a head hanging from the pelvis or without such frames. */
void mm_rig_learn_head_floor(mm_rig *rig, const mm_database *db);

/* A pose on the rig: local rotations and positions (joint 0: the root, in the world) and the
 * global transforms they give. */
typedef struct mm_rig_pose {
    mm_quat *local_rotations;
    mm_vec3 *local_positions;
    mm_xform *global;
    /* set (by the character, over the stages that read only the legs): mm_rig_forward_pelvis
     * leaves the global transforms of the rest of the body to mm_rig_forward_finish */
    bool defer_body;
    bool body_stale; /* the rest of the body's global transforms are waiting */
} mm_rig_pose;

/* The height of the head joint above the pelvis in pose (the pelvis's global transform current, the
 * local transforms of the joints between them read); 0 when rig->head < 0. */
float mm_rig_head_above_pelvis(const mm_rig *rig, const mm_rig_pose *pose);

/* Finds the legs of the ankle joints left_ankle and right_ankle (-1: that leg is missing; the
 * character gives its desc's feet or the database's foot roles). */
void mm_rig_init(mm_rig *rig, const mm_joint *joints, int joint_count, int left_ankle, int right_ankle);

/* The side leg k's knee bends to (a pole for mm_leg_ik_solve): square to its hip-foot line, from
 * its hinge turned as the knee is in pose, so defined even where the leg is straight or the
 * animation hyperextends it; the pelvis's facing when the hinge is unknown. */
mm_vec3 mm_rig_knee_pole(const mm_rig *rig, const mm_rig_pose *pose, int k);

/* Where the pelvis faces, on the ground: square to the line from the left hip to the right one
 * (facing +Z, the left hip is at +X); the way the knees bend. Zero without both legs. */
mm_vec3 mm_rig_pelvis_forward(const mm_rig *rig, const mm_rig_pose *pose);

/* The global transforms of joints first .. joint_count - 1 (>= 1) from their local ones; those of
 * the joints before `first` are taken as they are (mm_skeleton_global_from on the pose). */
void mm_rig_forward(const mm_rig *rig, int first, mm_rig_pose *pose);

/* The global transforms of both legs' joints (each hip and every joint that hangs from it) from
 * their local ones, the rest taken as they are: after a stage that turned or moved only joints of
 * the legs, the same transforms as mm_rig_forward from joint 1 for less work. */
void mm_rig_forward_legs(const mm_rig *rig, mm_rig_pose *pose);

/* After a stage moved or turned the pelvis (and perhaps joints that hang from it): the global
 * transforms of joints 1 .. joint_count - 1, as mm_rig_forward from joint 1. With
 * pose->defer_body, only those of the joints up to the pelvis and of the legs: the rest of the body
 * waits for mm_rig_forward_finish (the same transforms, computed once however often the pelvis
 * moved; the stages in between read only the legs). */
void mm_rig_forward_pelvis(const mm_rig *rig, mm_rig_pose *pose);

/* The rest of the body's global transforms where mm_rig_forward_pelvis left them; ends the
 * deferral (pose->defer_body false). */
void mm_rig_forward_finish(const mm_rig *rig, mm_rig_pose *pose);

/* The rest of the body's global transforms where mm_rig_forward_pelvis left them, the deferral
 * kept (for a stage that reads them). */
void mm_rig_forward_rest(const mm_rig *rig, mm_rig_pose *pose);

#endif
