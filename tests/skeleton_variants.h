/* skeleton_variants.h - takes rewritten for the tests: the same motion under another skeleton
 * (joints renamed to a naming convention, the travel moved to a root above the hips, the rest
 * axes rotated, other units) or resampled to another rate. Every variant remembers which joint of
 * the original each of its joints is (origin), and sv_fk_distance measures how far its world
 * joint positions are from the original's, in metres: a generator bug shows there, before the
 * variant is used (sv_check fails the test above SV_FK_TOLERANCE).
 *
 * Clips are in metres unless a variant says otherwise (sv_variant.unit: metres per file unit). */
#ifndef MM_TEST_SKELETON_VARIANTS_H
#define MM_TEST_SKELETON_VARIANTS_H

#include <mm/clip.h>

#define SV_MAX_JOINTS 256
/* m: the largest distance between a variant's world joint positions and its original's (after
 * the unit is converted) that passes as the same motion (float rounding is a few micrometres) */
#define SV_FK_TOLERANCE 1e-4

typedef struct sv_variant {
    mm_clip clip;
    double unit;               /* metres per unit of clip */
    int origin[SV_MAX_JOINTS]; /* the original's joint that joint j is; -1 for a joint added */
    mm_euler_order order;      /* rotation order of every joint when written; MM_EULER_NONE: own */
} sv_variant;

/* ---- naming conventions -------------------------------------------------------------------- */
typedef enum sv_naming {
    SV_NAMES_LEFT_RIGHT, /* LeftFoot */
    SV_NAMES_SUFFIX_LR,  /* Foot_L */
    SV_NAMES_PREFIX_L_,  /* l_foot */
    SV_NAMES_PREFIX_L,   /* LFoot */
    SV_NAMES_MIXAMO,     /* mixamorig:LeftFoot, mixamorig:LeftToeBase */
    SV_NAMES_CMU,        /* LeftUpLeg, LeftLeg, LeftFoot, LeftToeBase, LeftShoulder, LeftArm */
    SV_NAMES_BIOVISION,  /* LeftHip, LeftKnee, LeftAnkle, LeftToe, LeftCollar, LeftShoulder, LeftElbow */
    SV_NAMINGS
} sv_naming;
extern const char *const sv_naming_names[SV_NAMINGS];

/* The side a joint's name gives (0 none, 1 left, 2 right: Left*, Right*, or l/L/r/R before a
 * capital, as in lHip, LHipJoint) and the rest of the name. */
int sv_name_side(const char *name, const char **part);

/* The name of a joint of skel in convention n (limb parts translated between the UpLeg / Leg /
 * Foot / Arm / ForeArm style and the Hip / Knee / Ankle / Shoulder / Elbow / Wrist style, which
 * the skeleton's own names tell). */
void sv_rename_joint(const mm_skeleton *skel, int joint, sv_naming n, char out[MM_NAME_MAX]);

/* ---- roots --------------------------------------------------------------------------------- */
typedef enum sv_root {
    SV_ROOT_STATIC,            /* a Root joint at the origin above the hips, not moving */
    SV_ROOT_PART,              /* a Root carrying half the horizontal travel, the hips the rest */
    SV_ROOT_ALL,               /* a Root carrying all the travel (the hips only turn) */
    SV_ROOT_GROUND,            /* a Root on the ground under the hips, carrying the horizontal travel */
    SV_ROOT_YAW,               /* a Root on the ground that turns too (the hips' heading and a wobble) */
    SV_ROOTS,                  /* the arrangements above are the matrix's; those below are more */
    SV_ROOT_PLACED = SV_ROOTS, /* a Root joint elsewhere, turned 40 degrees, not moving */
    SV_ROOT_TWO,               /* Reference at the origin, a turning Root on the ground under it, the hips
                                  under that */
    SV_ROOTS_ALL
} sv_root;
extern const char *const sv_root_names[SV_ROOTS_ALL];

/* ---- the generators (src in metres, joint 0 the hips for sv_reroot) ------------------------- */
void sv_copy(const mm_clip *src, sv_variant *out);
void sv_rename(const mm_clip *src, sv_naming n, sv_variant *out);
void sv_reroot(const mm_clip *src, sv_root a, sv_variant *out);
/* ... and with prop, the joint above the hips holds another child, "Prop", 10 cm above it (the
 * last joint; its origin is -1) */
void sv_reroot_prop(const mm_clip *src, sv_root a, int prop, sv_variant *out);
/* Every joint's rest frame turned so that the bones that pointed along +Y point along axis
 * (0 +X, 1 -X, 2 +Z, 3 -Z); the world motion is the same. */
void sv_rest_axes(const mm_clip *src, int axis, sv_variant *out);
/* The rest frames of the joints whose names start with prefix (NULL: every joint) turned by turn:
 * world rotations R turn, local rotations turn_p^-1 r turn_j, offsets turn_p^-1 o (turn_j: turn
 * or the identity); the world positions are the same. */
void sv_turn_rest_frames(const mm_clip *src, mm_quat turn, const char *prefix, sv_variant *out);
extern const char *const sv_axis_names[4];
/* Lengths in units of `unit` metres (0.01: centimetres, 0.0254: inches). */
void sv_units(const mm_clip *src, double unit, sv_variant *out);
/* Written with every joint's rotation channels in this order. */
void sv_rotation_order(const mm_clip *src, mm_euler_order order, sv_variant *out);
/* Resampled to fps on C1 splines (what mm db build does to a take). */
void sv_resample(const mm_clip *src, float fps, sv_variant *out);
void sv_free(sv_variant *v);

/* The largest distance (m) between the world positions of v's joints and their origins in orig
 * (in units of orig_unit metres), over the frames at the same times (every frame when the rates
 * agree; for a resampled variant the frames both have). */
double sv_fk_distance(const mm_clip *orig, double orig_unit, const sv_variant *v);

/* Fails the test when v's motion is not orig's (sv_fk_distance above SV_FK_TOLERANCE), naming
 * what; returns the distance. */
double sv_check(const mm_clip *orig, double orig_unit, const sv_variant *v, const char *what);

/* Writes v as BVH at path (v->order), reads it back as mm config init does (file units) and
 * checks the read-back against orig (sv_check). The read-back replaces v->clip. */
void sv_save_and_reload(const mm_clip *orig, double orig_unit, sv_variant *v, const char *path);

#endif
