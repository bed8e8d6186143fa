/* mm/skeleton_roles.h - which joint of a skeleton is which: the bone roles of a database config
 * (mm/config.h) found from a skeleton and its motion (the mm_build library).
 *
 * Two kinds of evidence are used and compared:
 *   - names, in the common conventions: sides as Left* / Right*, left* / right*, *_L / *_R,
 *     *_l / *_r, *.L / *.R, l_* / r_*, L* / R* and lXxx / rXxx (followed by a capital: LHipJoint,
 *     lAnkle), a word L / R (Bip01 L Foot), a namespace before a colon (mixamorig:LeftFoot); parts
 *     as Hips / Pelvis, Foot / Ankle, Toe / ToeBase / Ball, Hand / Wrist, Head (not HeadTop_End or
 *     the fingers of a hand);
 *   - geometry and motion: the two lowest ends of the skeleton whose chains part well above them
 *     are the legs and the highest end is the head; the hips are where the legs and the spine meet;
 *     the two long branches off the spine are the arms, and the joint they leave from (the chest)
 *     is the root bone; along a leg the foot ends the second of the two longest bones (thigh and
 *     shin) and the toe follows it; along an arm the hand ends the last long bone (the forearm:
 *     the fingers' bones are short); forward is where the toes point and where the character
 *     travels, left is +X when forward is +Z (left = up x forward).
 * Each role gets a confidence: 1 when names and geometry agree, 0.9 when a name picks another
 * joint of the limb geometry found, 0.8 from geometry alone, 0.6 from a name alone, 0.4 or less
 * when they disagree (geometry is kept, except for sides, where names are).
 *
 * The motion must be in metres with +Y up (mm_clip_up_axis tells where a file's up is).
 *
 *   mm_skeleton_roles roles;
 *   if (mm_skeleton_roles_find(takes, take_count, &roles, &err) == MM_OK)
 *       mm_skeleton_roles_apply(&roles, &takes[0].skeleton, &cfg);
 *
 * Functions: mm_skeleton_roles_find mm_skeleton_roles_apply mm_body_role_name mm_clip_up_axis
 *            (mm_axis_name: mm/config.h)
 */
#ifndef MM_SKELETON_ROLES_H
#define MM_SKELETON_ROLES_H

#include <stdbool.h>

#include "clip.h"
#include "config.h"
#include "result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The joints a config's roles name (the fields of its "roles" object, in that order). */
typedef enum mm_body_role {
    MM_BODY_HIPS = 0,
    MM_BODY_ROOT_BONE,
    MM_BODY_FACING_BONE,
    MM_BODY_LEFT_FOOT,
    MM_BODY_RIGHT_FOOT,
    MM_BODY_LEFT_TOE,
    MM_BODY_RIGHT_TOE,
    MM_BODY_LEFT_HAND,
    MM_BODY_RIGHT_HAND,
    MM_BODY_HEAD,
    MM_BODY_ROLE_COUNT
} mm_body_role;

/* What supports a finding (bits). */
enum mm_role_evidence {
    MM_EVIDENCE_NAME = 1u << 0,     /* the joint's name */
    MM_EVIDENCE_GEOMETRY = 1u << 1, /* the skeleton's shape in its poses */
    MM_EVIDENCE_MOTION = 1u << 2    /* the direction of travel */
};

typedef struct mm_role_match {
    int joint;         /* joint index, -1: not found */
    float confidence;  /* 0 to 1 */
    unsigned evidence; /* mm_role_evidence bits that chose this joint */
    unsigned conflict; /* bits of evidence that pointed elsewhere */
    int other;         /* the joint the conflicting evidence pointed at, or -1 */
} mm_role_match;

typedef struct mm_skeleton_roles {
    mm_role_match roles[MM_BODY_ROLE_COUNT];
    /* forward: the axis of the facing bone's frame that points the way the body faces */
    mm_vec3 forward_axis;
    float forward_confidence;
    unsigned forward_evidence;    /* MM_EVIDENCE_GEOMETRY (the toes), MM_EVIDENCE_MOTION (travel) */
    float forward_toes_degrees;   /* angle from forward_axis to where the toes point; -1: no toes */
    float forward_travel_degrees; /* ... to the mean direction of travel; -1: the body never travels */
    float travel_seconds;         /* seconds of motion (faster than 0.5 m/s) that direction is from */
    /* sides */
    float side_agreement; /* fraction of sampled poses whose left leg and arm are on the +X side
                             of the facing (left = up x forward) as the final sides say */
    bool sides_from_names;
    /* mirroring: name patterns for the config's mirror_pairs */
    int mirror_pair_count;
    mm_config_mirror_pair mirror_pairs[MM_MAX_MIRROR_PAIRS];
    int paired_joints;   /* joints the patterns pair with another */
    int unpaired_joints; /* joints named as a side that the patterns leave without a partner */
    bool mirror;         /* the pairs pair every sided joint, feet, toes and hands with each other */
    float mirror_confidence;
    char naming[96]; /* the side conventions found, e.g. "Left* and Right*, LXxx and RXxx"; "" without */
    float stature;   /* m: the body's vertical extent upright (0.9 quantile over the sampled poses) */
} mm_skeleton_roles;

/* Finds the roles from takes[0 .. count-1], clips of one skeleton (the same joint names and
 * parents in the same order; else MM_ERR_INVALID_ARGUMENT), in metres and +Y up. A role nothing points at is
 * -1 with confidence 0; MM_ERR_NOT_FOUND (err says which) when the hips, the feet or the head cannot be
 * found. */
mm_result mm_skeleton_roles_find(const mm_clip *takes, int count, mm_skeleton_roles *out, mm_error *err);

/* Writes the roles found into cfg: the role names (those found), forward_axis, the matched bones
 * (features.bones: the feet with position and velocity, the hips with velocity, weights as the
 * defaults) and the mirror pairs (when roles->mirror). */
void mm_skeleton_roles_apply(const mm_skeleton_roles *roles, const mm_skeleton *skeleton, mm_config *cfg);

/* The config field of a role: "hips", "root_bone", "facing_bone", "left_foot" ...; NULL if out of
 * range. */
const char *mm_body_role_name(mm_body_role role);

/* The axis along which a clip's body stands, judged from its poses (any unit): the axis of the
 * largest median extent of the body's joints (from the first joint that branches: a root above
 * the hips that stays behind or on the ground is left out), signed by the end that hangs from more
 * branches. Returns 0..5 for +X, +Y, +Z, -X, -Y, -Z; *out_confidence (may be NULL) is 1 - second / largest
 * extent (0: no telling, about 0.5 for a walk). A clip without frames is judged in its rest pose. */
int mm_clip_up_axis(const mm_clip *clip, float *out_confidence);

#ifdef __cplusplus
}
#endif

#endif /* MM_SKELETON_ROLES_H */
