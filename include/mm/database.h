/* mm/database.h - the motion database: poses, features, clips, tags, its runtime settings, and
 * its .mmdb file (the mm_runtime library).
 *
 * A database is built once, offline, from a config and the source clips it names
 * (mm_database_build in mm/database_build.h, the mm_build library), saved to a .mmdb file, and
 * loaded at run time (mm_database_load*), where it is read-only. Everything lives in ONE buffer
 * laid out exactly as the file: loading validates the header and the array offsets and points
 * into the buffer, with no pointer fix-ups, so a file can be read or mapped and used in place.
 * docs/format.md specifies it.
 *
 * Skeleton: joint 0 is the simulation bone ("root"): the character's position on the ground and
 * its facing, extracted from the source (docs/database.md). The source root (hips) is its child.
 *
 * Features: a row-major [frame_count x dims_padded] float matrix, each dimension normalised
 * (x - mean) / scale where scale is the feature group's spread (the mean standard deviation of
 * its dimensions). Weights are NOT baked in: the search multiplies by them, so tuning needs no
 * rebuild. Padding dimensions are 0. Bounding boxes over blocks of MM_DB_SMALL_BLOCK and
 * MM_DB_LARGE_BLOCK consecutive frames (a block may span the end of one clip and the start of
 * the next: a box only bounds) give frame-order tools a cheap lower bound.
 *
 * Settings (mm_database_settings, db->settings): the runtime tuning the database was built with,
 * in binary: the config's feature weights resolved against the database's feature groups, its
 * `runtime` object with the bits of the fields it sets, and the joints of its bone roles.
 * mm_character_desc_from_database (mm/character.h) makes a character desc of them, with no JSON.
 *
 * Character frame: positions and directions are expressed relative to the simulation bone:
 * x is the character's local X (its left, since it faces +Z with Y up), z its forward, y up.
 *
 * Local transforms: each frame's joint rotations and translations, stored as floats or compressed
 * (mm_db_compressed_poses: quantized per clip segment within a measured error bound, docs/format.md
 * "Compressed poses"). Read them with mm_database_local_pose, which copies or decodes one frame into
 * the caller's arrays (no allocation); db->rotations and db->positions are NULL when compressed.
 *
 * Functions: mm_database_save mm_database_load mm_database_load_memory mm_database_free
 *            mm_database_local_pose mm_database_local_joint mm_database_pose_bytes mm_database_pose
 * mm_database_matched_bone mm_database_find_clip mm_feature_kind_name mm_database_distance_curve
 * mm_database_find_joint mm_database_role_joint mm_database_toe_joint mm_role_default_name
 *
 * Distance curves (mm/distance_curve.h): each clip's root (joint 0) path measured at build time by
 * mm_distance_curve_build (stop speed MM_DISTANCE_STOP_SPEED_DEFAULT), stored as flat arrays and
 * read through mm_database_distance_curve, which makes a view into the buffer (no allocation).
 */
#ifndef MM_DATABASE_H
#define MM_DATABASE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "alloc.h"
#include "clip.h"
#include "distance_curve.h"
#include "math.h"
#include "result.h"
#include "skeleton.h"

#ifdef __cplusplus
extern "C" {
#endif

#define MM_DB_VERSION     6
#define MM_DB_ALIGN       64  /* every array starts at a multiple of this in the buffer */
#define MM_DB_SIMD_WIDTH  8   /* dims_padded is a multiple of this */
#define MM_DB_SMALL_BLOCK 16  /* frames per small bounding box */
#define MM_DB_LARGE_BLOCK 128 /* frames per large bounding box */

/* Limits shared with the configs (mm/config.h) the databases are built from. */
#define MM_MAX_TAGS         64 /* tags are bits of a 64-bit mask */
#define MM_TAG_NAME_MAX     32 /* including the terminating zero */
#define MM_MAX_MATCH_BONES  16 /* bones whose position / velocity are features */
#define MM_MAX_TRAJ_SAMPLES 16 /* trajectory sample times, past and future */

typedef enum mm_clip_type { MM_CLIP_LOCOMOTION = 0, MM_CLIP_IDLE = 1 } mm_clip_type;

/* Contact bits of mm_database.contacts. */
enum mm_contact_bits {
    MM_CONTACT_LEFT_HEEL = 1u << 0,
    MM_CONTACT_LEFT_TOE = 1u << 1,
    MM_CONTACT_RIGHT_HEEL = 1u << 2,
    MM_CONTACT_RIGHT_TOE = 1u << 3
};

typedef enum mm_feature_kind {
    MM_FEATURE_BONE_POSITION = 0, /* 3 dims: bone position in the character frame (m) */
    MM_FEATURE_BONE_VELOCITY = 1, /* 3 dims: bone velocity in the character frame (m/s) */
    MM_FEATURE_ROOT_VELOCITY = 2, /* 3 dims: simulation bone velocity in the character frame (m/s) */
    MM_FEATURE_TRAJ_POSITION = 3, /* 2 dims: x, z of the root at time t, character frame (m) */
    MM_FEATURE_TRAJ_DIRECTION = 4 /* 2 dims: x, z of the facing at time t, character frame */
} mm_feature_kind;

/* "bone_position" ... ; NULL if invalid. */
const char *mm_feature_kind_name(mm_feature_kind kind);

typedef struct mm_feature_group {
    char name[MM_NAME_MAX]; /* e.g. "LeftFoot.position", "trajectory.position@0.33" */
    int32_t kind;           /* mm_feature_kind */
    int32_t bone;           /* joint index for bone features, -1 otherwise */
    float time;             /* seconds, for trajectory features; 0 otherwise */
    int32_t offset;         /* first dimension */
    int32_t dims;           /* number of dimensions */
    float weight;           /* default weight from the config (the search may override) */
    float scale;            /* the group's spread used in normalisation */
} mm_feature_group;

typedef struct mm_db_clip {
    char name[MM_NAME_MAX];
    int32_t first_frame; /* index of its first frame in the database */
    int32_t frame_count;
    int32_t type;       /* mm_clip_type */
    int32_t loop;       /* 1: the frame after the last is the first */
    int32_t mirrored;   /* 1: made by mirroring another clip */
    int32_t source;     /* index of the config clip (or blend, for blends) it comes from */
    int32_t blend_left; /* for blend clips: database clip indices of the sources; -1 otherwise */
    int32_t blend_right;
    float blend_weight; /* for blend clips: weight of the left source */
    float source_start; /* seconds: time of its first frame in the source file */
} mm_db_clip;

/* Where a clip's distance curve lives in the database's distance arrays (16 bytes, stored as it
 * is). A clip of a single frame has no curve: segment_count 0. */
typedef struct mm_db_distance_clip {
    int32_t first_segment; /* index of its first segment in mm_database.distance_segments */
    int32_t segment_count; /* >= 1 (0 only for a clip of one frame) */
    float path_length;     /* m: the curve's path_length */
    float stop_speed;      /* m/s: the stop threshold the curve was built with */
} mm_db_distance_clip;

/* How a database stores its frames' local transforms (mm_database.pose_codec). */
typedef enum mm_pose_codec {
    MM_POSE_FLOATS = 0,  /* rotations and positions as float arrays (sections 10 and 11) */
    MM_POSE_SEGMENTS = 1 /* quantized per clip segment (sections 25-29, mm_db_compressed_poses) */
} mm_pose_codec;

#define MM_POSE_RAW_BITS             32 /* a track's bits: its values stored as floats, exactly */
#define MM_POSE_ROTATION_BITS_MAX    16 /* quantized rotation components: 0..16 bits (or raw) */
#define MM_POSE_TRANSLATION_BITS_MAX 24 /* quantized translation components: 0..24 bits (or raw) */
#define MM_POSE_SEGMENT_FRAMES_MAX   256

/* One segment of a clip's frames (16 bytes, stored as it is): frame_count frames from first_frame,
 * each frame_bits bits long in the bit stream from byte data_offset. */
typedef struct mm_db_pose_segment {
    int32_t first_frame, frame_count;
    uint32_t data_offset; /* bytes into mm_db_compressed_poses.bits */
    uint32_t frame_bits;  /* the sum of the segment's tracks' bits per frame */
} mm_db_pose_segment;

/* A joint's rotation over one segment (16 bytes): three of the quaternion's components (all but
 * `dropped & 3`), each `bits` bits over its range [lo, lo + extent] (16-bit fractions of [-1, 1]);
 * the fourth is sqrt(1 - the others' squares), negative when `dropped & 4`. bits 0: every frame
 * holds lo. bits MM_POSE_RAW_BITS: x y z w as floats (lo, extent and dropped 0). */
typedef struct mm_db_rotation_track {
    uint16_t lo[3], extent[3];
    uint8_t bits, dropped;
    uint16_t reserved; /* 0 */
} mm_db_rotation_track;

/* A translating joint's translation over one segment (28 bytes): x y z, each `bits` bits over
 * [lo, lo + extent] (m). bits 0: every frame holds lo. bits MM_POSE_RAW_BITS: floats (lo and
 * extent 0). */
typedef struct mm_db_translation_track {
    float lo[3], extent[3];
    uint8_t bits, reserved[3]; /* reserved 0 */
} mm_db_translation_track;

/* The compressed local transforms of a database whose pose_codec is MM_POSE_SEGMENTS (everything
 * zero otherwise). Every clip is cut into segments of segment_frames frames (its last one
 * shorter); a segment holds a rotation track per joint and a translation track per translating
 * joint; the other joints keep constant_positions on every frame. The build measured every
 * frame's world joint positions against the floats it compressed: max_error <= error_bound. */
typedef struct mm_db_compressed_poses {
    int segment_frames, segment_count, translating_count;
    float error_bound;                           /* m: the bound the build held every frame to */
    float max_error;                             /* m: the largest world joint position error it measured */
    const mm_vec3 *constant_positions;           /* [joint_count]; 0 for translating joints */
    const int32_t *translating_joints;           /* [translating_count], increasing */
    const mm_db_pose_segment *segments;          /* [segment_count], in frame order */
    const mm_db_rotation_track *rotation_tracks; /* [segment_count x joint_count] */
    const mm_db_translation_track *translation_tracks; /* [segment_count x translating_count] */
    const uint8_t *bits;                               /* the segments' frames */
    size_t bits_size;
} mm_db_compressed_poses;

/* ---- runtime settings -------------------------------------------------------------------- */

/* Bits of mm_database_settings.set (and of mm_runtime_config.set in mm/config.h): which runtime
 * fields the config gives. A field whose bit is clear keeps the runtime's default. */
enum mm_runtime_field {
    MM_RUNTIME_POSE_TRAJECTORY_RATIO = 1u << 0,
    MM_RUNTIME_NEXT_POSE_FAVOUR = 1u << 1,
    MM_RUNTIME_LOOP_ANIM_FAVOUR = 1u << 2,
    MM_RUNTIME_CONTINUING_BIAS = 1u << 3,
    MM_RUNTIME_SEARCH_INTERVAL = 1u << 4,
    MM_RUNTIME_TRANSITION_HALFLIFE = 1u << 5,
    MM_RUNTIME_IDLE_SPEED = 1u << 6,
    MM_RUNTIME_SYNC_HALFLIFE = 1u << 7,
    MM_RUNTIME_DISTANCE_MATCHING = 1u << 8,
    MM_RUNTIME_WARPING = 1u << 9,
    MM_RUNTIME_CONTACT_FAVOUR = 1u << 10,
    MM_RUNTIME_SPEED_ENVELOPE = 1u << 11
};
#define MM_RUNTIME_FIELDS_ALL 0xfffu
enum mm_runtime_gait_field {
    MM_RUNTIME_FORWARD_SPEED = 1u << 0,
    MM_RUNTIME_SIDE_SPEED = 1u << 1,
    MM_RUNTIME_BACKWARD_SPEED = 1u << 2,
    MM_RUNTIME_VELOCITY_HALFLIFE = 1u << 3,
    MM_RUNTIME_ROTATION_HALFLIFE = 1u << 4
};
#define MM_RUNTIME_GAIT_FIELDS_ALL 0x1fu

/* One gait's speeds and half-lives (the fields of mm_gait_params, mm/trajectory.h); 24 bytes,
 * stored as it is in the settings section. */
typedef struct mm_runtime_gait {
    uint32_t set;            /* mm_runtime_gait_field bits of the fields given */
    float forward_speed;     /* m/s, [0, 50] */
    float side_speed;        /* m/s, [0, 50] */
    float backward_speed;    /* m/s, [0, 50] */
    float velocity_halflife; /* s, (0, 60] */
    float rotation_halflife; /* s, (0, 60] */
} mm_runtime_gait;

/* Bits of mm_database_settings.weight_set: the weights of the feature groups that are not per
 * bone, given where the database has such a group. */
enum mm_settings_weight_field {
    MM_SETTINGS_BODY_VELOCITY_WEIGHT = 1u << 0, /* a root velocity group */
    MM_SETTINGS_POSITION_MULTIPLIER = 1u << 1,  /* trajectory position groups */
    MM_SETTINGS_ANGLE_MULTIPLIER = 1u << 2      /* trajectory direction groups */
};

/* The bone roles the runtime needs, as indices of mm_database_settings.roles. */
typedef enum mm_role {
    MM_ROLE_HIPS = 0,
    MM_ROLE_LEFT_FOOT = 1,
    MM_ROLE_RIGHT_FOOT = 2,
    MM_ROLE_LEFT_TOE = 3,
    MM_ROLE_RIGHT_TOE = 4,
    MM_ROLE_LEFT_HAND = 5,
    MM_ROLE_RIGHT_HAND = 6,
    MM_ROLE_HEAD = 7,
    MM_ROLE_COUNT = 8
} mm_role;

/* Directions of the settings' speed envelopes (MM_SPEED_ENVELOPE_BINS of mm/trajectory.h) and the
 * gaits they are for (MM_GAIT_COUNT of mm/gait.h: walk, run, crouch, jump). */
#define MM_SETTINGS_ENVELOPE_BINS  16
#define MM_SETTINGS_ENVELOPE_GAITS 4

/* The runtime tuning a database carries (its settings section, 564 bytes stored as they are;
 * docs/format.md). Written by mm_database_build from the config: what
 * mm_character_desc_apply_config would take from it, resolved against this database. Loading
 * checks every value: set bits known, values finite and in their ranges, zero where not set. */
typedef struct mm_database_settings {
    /* Feature weights (the config's features): per matched bone (mm_pose_data.bones order, the
     * order of mm_search_params' joint weights), bit b of position_set / velocity_set says
     * joint_position_weights[b] / joint_velocity_weights[b] is given: the config names that bone
     * with that feature. Weights are finite and >= 0. */
    uint32_t weight_set;   /* mm_settings_weight_field bits */
    uint32_t position_set; /* bit per matched bone */
    uint32_t velocity_set; /* bit per matched bone */
    float joint_position_weights[MM_MAX_MATCH_BONES];
    float joint_velocity_weights[MM_MAX_MATCH_BONES];
    float body_velocity_weight;
    float position_multiplier;
    float angle_multiplier;
    /* The config's runtime object (mm_runtime_config, mm/config.h) */
    uint32_t set;                /* mm_runtime_field bits */
    float pose_trajectory_ratio; /* [0, 1] */
    float next_pose_favour;      /* > 0 */
    float loop_anim_favour;      /* > 0 */
    float continuing_bias;       /* >= 0 */
    float search_interval;       /* s, (0, 10] */
    float transition_halflife;   /* s, (0, 60] */
    float idle_speed;            /* m/s, [0, 50] */
    float sync_halflife;         /* s, [0, 60] */
    uint32_t distance_matching;  /* 0 or 1 */
    uint32_t warping;            /* 0 or 1 */
    mm_runtime_gait walk, run, crouch;
    /* Bone roles: joint indices (mm_role order), -1 where the config names no joint */
    int32_t roles[MM_ROLE_COUNT];
    float contact_favour; /* >= 1 (the runtime object's, after the roles: added in version 5) */
    /* Added in version 6: the runtime object's speed_envelope switch (0 or 1; not set: on), and
     * the speed envelope the build measured from the database's locomotion
     * (mm_speed_envelope_measure, mm/speed_envelope.h): per gait, m/s in [0, 50] per direction */
    uint32_t speed_envelope;
    float envelope[MM_SETTINGS_ENVELOPE_GAITS][MM_SETTINGS_ENVELOPE_BINS];
} mm_database_settings;

/* The seed's PoseData of one frame, assembled by mm_database_pose. Positions and directions are
 * in the character frame of that frame; units m, m/s, rad/s. */
typedef struct mm_pose_data {
    int id, next_id, clip; /* next_id: -1 at the end of a non-loop clip, wraps in a loop clip */
    float time;            /* seconds from the clip's first frame */
    mm_vec3 root_velocity;
    float root_angular_velocity; /* about +Y */
    int type;                    /* mm_clip_type */
    uint64_t tags;
    bool is_blend;
    float blend_weight;
    int blend_left, blend_right;
    unsigned contacts; /* mm_contact_bits */
    /* Matched bones (the config's features.bones, in order), relative to the character; a
     * quantity the database does not store is zero. */
    int bone_count;
    int bones[MM_MAX_MATCH_BONES]; /* joint indices */
    mm_vec3 bone_positions[MM_MAX_MATCH_BONES];
    mm_vec3 bone_velocities[MM_MAX_MATCH_BONES];
    /* Trajectory samples (the config's trajectory_times, in order): positions on the ground and
     * unit facing directions, relative to the character. */
    int traj_count;
    float traj_times[MM_MAX_TRAJ_SAMPLES];
    mm_vec3 traj_positions[MM_MAX_TRAJ_SAMPLES];
    mm_vec3 traj_directions[MM_MAX_TRAJ_SAMPLES];
} mm_pose_data;

typedef struct mm_database {
    int frame_count, joint_count, clip_count, tag_count, group_count;
    int dims, dims_padded;
    float interval; /* seconds per frame */

    const mm_joint *joints;  /* [joint_count]; joint 0 is the simulation bone */
    const mm_db_clip *clips; /* [clip_count] */
    const char (*tag_names)[MM_TAG_NAME_MAX];
    const mm_feature_group *groups; /* [group_count] */

    /* Per frame */
    const int32_t *frame_clip;          /* clip index */
    const int32_t *frame_next;          /* next frame or -1 */
    const uint64_t *frame_tags;         /* tag bit mask */
    const uint8_t *contacts;            /* mm_contact_bits */
    const mm_vec3 *root_velocity;       /* simulation bone velocity in its own frame (m/s) */
    const float *root_angular_velocity; /* about +Y (rad/s) */
    /* Local transforms: read them with mm_database_local_pose. With MM_POSE_FLOATS: */
    const mm_quat *rotations; /* [frame_count x joint_count] local rotations (NULL when compressed) */
    const mm_vec3 *positions; /* [frame_count x joint_count] local translations (NULL when compressed) */
    int pose_codec;           /* mm_pose_codec */
    mm_db_compressed_poses compressed; /* with MM_POSE_SEGMENTS */

    /* Features */
    const float *features;      /* [frame_count x dims_padded], normalised */
    const float *feature_mean;  /* [dims_padded] */
    const float *feature_scale; /* [dims_padded]; raw = features * scale + mean */
    int small_block_count, large_block_count;
    const float *small_min, *small_max; /* [small_block_count x dims_padded] */
    const float *large_min, *large_max; /* [large_block_count x dims_padded] */

    const char *config_json; /* the config the database was built from (zero-terminated) */

    /* Distance curves of the clips' root paths (read them with mm_database_distance_curve) */
    const mm_db_distance_clip *distance_clips;    /* [clip_count] */
    const float *distance_travelled;              /* [frame_count] m from the clip's first frame */
    const float *distance_signed;                 /* [frame_count] m to the segment's marker */
    const mm_distance_segment *distance_segments; /* [distance_segment_count], clip by clip; frames
                                                   * are relative to the clip's first frame */
    int distance_segment_count;

    /* The runtime settings it was built with (mm_character_desc_from_database reads them) */
    const mm_database_settings *settings;

    /* Storage: the whole file */
    const void *data;
    size_t size;
    void *owned; /* buffer to free, or NULL when the caller owns data */
    bool mapped; /* data is a read-only mapping of the file (unmapped by free) */
    mm_allocator allocator;
} mm_database;

typedef struct mm_db_load_desc {
    bool skip_checksum;            /* skip the whole-file checksum (structure is still validated) */
    bool no_map;                   /* read into memory instead of mapping the file */
    const mm_allocator *allocator; /* for the read buffer; NULL: malloc */
} mm_db_load_desc;

/* Writes the database's buffer (atomically: temporary file and rename). */
mm_result mm_database_save(const mm_database *db, const char *path, mm_error *err);

/* Loads a .mmdb file and validates it: by default the file is mapped read-only (it is used in
 * place, pages come in as they are touched) and its checksum verified. desc may be NULL. */
mm_result mm_database_load(const char *path, const mm_db_load_desc *desc, mm_database *out, mm_error *err);
/* Validates a buffer holding a .mmdb file and points into it (the caller keeps it alive and
 * aligned to MM_DB_ALIGN). verify_checksum: check the whole-file checksum too. */
mm_result mm_database_load_memory(const void *data, size_t size, bool verify_checksum, mm_database *out,
                                  mm_error *err);
void mm_database_free(mm_database *db);

/* The seed's PoseData of frame (0 <= frame < frame_count). */
void mm_database_pose(const mm_database *db, int frame, mm_pose_data *out);
/* Index of feature group's bone among the matched bones (mm_pose_data.bones order, the order of
 * mm_search_params' joint weights); -1 when group is not a bone group or past the limit. */
int mm_database_matched_bone(const mm_database *db, int group);
/* Clip index by name, or -1. */
int mm_database_find_clip(const mm_database *db, const char *name);
/* Joint index by name (the last joint so named), or -1 (also for a NULL name). */
int mm_database_find_joint(const mm_database *db, const char *name);
/* The joint of a bone role: the index the database's settings give it (-1 where its config named
 * no joint); for a database without settings (db->settings NULL: one made in code, not built nor
 * loaded) the joint named mm_role_default_name(role), or -1. Everything the runtime does with feet,
 * toes, hands and the head starts here (docs/runtime.md, "Bone roles"). */
int mm_database_role_joint(const mm_database *db, mm_role role);
/* The toe of an ankle joint: the joint of toe_role (MM_ROLE_LEFT_TOE or MM_ROLE_RIGHT_TOE) when it
 * is a child of ankle, else ankle's first child; -1 when ankle has no child or is no joint. */
int mm_database_toe_joint(const mm_database *db, int ankle, mm_role toe_role);
/* The joint name a config gives a role by default ("Hips", "LeftFoot", ...: mm_config_defaults,
 * docs/config.md), the only place the default names are written; NULL out of range. */
const char *mm_role_default_name(mm_role role);
/* A view of clip's distance curve into the database (block NULL: do not free it; it lives as long
 * as db). Loading validated it. MM_ERR_INVALID_ARGUMENT for a bad clip index, MM_ERR_OUT_OF_RANGE
 * for a clip of a single frame (no curve); *out is zeroed then. */
mm_result mm_database_distance_curve(const mm_database *db, int clip, mm_distance_curve *out);
/* Frame's local rotations and translations ([joint_count] each) into the caller's arrays: copied
 * from the floats, or decoded from the compressed segments. Allocates nothing; frame must be in
 * [0, frame_count). */
void mm_database_local_pose(const mm_database *db, int frame, mm_quat *rotations, mm_vec3 *positions);
/* One joint's local rotation and translation at frame (both in range): what mm_database_local_pose
 * gives for it, decoding that joint alone. */
void mm_database_local_joint(const mm_database *db, int frame, int joint, mm_quat *rotation,
                             mm_vec3 *position);
/* Bytes of the file that hold the local transforms (the float arrays, or the compressed sections
 * with their tables). */
size_t mm_database_pose_bytes(const mm_database *db);
/* Pointers into the float arrays of a frame ([joint_count] each): only for a database stored with
 * MM_POSE_FLOATS (tools and tests that know it; the runtime reads mm_database_local_pose). */
static inline const mm_quat *mm_database_rotations(const mm_database *db, int frame)
{
    return db->rotations + (size_t)frame * (size_t)db->joint_count;
}
static inline const mm_vec3 *mm_database_positions(const mm_database *db, int frame)
{
    return db->positions + (size_t)frame * (size_t)db->joint_count;
}
/* Raw (un-normalised) value of feature dimension d at frame. */
static inline float mm_database_feature_raw(const mm_database *db, int frame, int d)
{
    return db->features[(size_t)frame * (size_t)db->dims_padded + (size_t)d] * db->feature_scale[d] +
           db->feature_mean[d];
}

#ifdef __cplusplus
}
#endif

#endif /* MM_DATABASE_H */
