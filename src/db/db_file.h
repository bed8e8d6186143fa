/* db_file.h (private) - the .mmdb layout: one header, then aligned arrays (docs/format.md). */
#ifndef MM_DB_FILE_H
#define MM_DB_FILE_H

#include <mm/database.h>

enum mm__db_section {
    MM__SEC_JOINTS,
    MM__SEC_CLIPS,
    MM__SEC_TAG_NAMES,
    MM__SEC_GROUPS,
    MM__SEC_FRAME_CLIP,
    MM__SEC_FRAME_NEXT,
    MM__SEC_FRAME_TAGS,
    MM__SEC_CONTACTS,
    MM__SEC_ROOT_VELOCITY,
    MM__SEC_ROOT_ANGULAR_VELOCITY,
    MM__SEC_ROTATIONS,
    MM__SEC_POSITIONS,
    MM__SEC_FEATURES,
    MM__SEC_FEATURE_MEAN,
    MM__SEC_FEATURE_SCALE,
    MM__SEC_SMALL_MIN,
    MM__SEC_SMALL_MAX,
    MM__SEC_LARGE_MIN,
    MM__SEC_LARGE_MAX,
    MM__SEC_CONFIG_JSON,
    MM__SEC_DISTANCE_CLIPS,
    MM__SEC_DISTANCE_TRAVELLED,
    MM__SEC_DISTANCE_SIGNED,
    MM__SEC_DISTANCE_SEGMENTS,
    MM__SEC_SETTINGS,
    /* compressed local transforms (mm_db_compressed_poses): empty with MM_POSE_FLOATS */
    MM__SEC_POSE_CONSTANTS,
    MM__SEC_POSE_TRANSLATING,
    MM__SEC_POSE_SEGMENTS,
    MM__SEC_POSE_ROTATION_TRACKS,
    MM__SEC_POSE_TRANSLATION_TRACKS,
    MM__SEC_POSE_BITS,
    MM__SEC_COUNT
};

/* Everything a database holds, as separate arrays: what the build computes and packs. */
typedef struct mm__db_parts {
    int frame_count, joint_count, clip_count, tag_count, group_count, dims, dims_padded;
    float interval;
    /* the local transforms' codec (mm_pose_codec) and, compressed, its counts and measured error */
    int pose_codec, pose_segment_frames, pose_segment_count, pose_translating_count;
    float pose_error_bound, pose_max_error;
    const void *data[MM__SEC_COUNT];
    size_t size[MM__SEC_COUNT];
} mm__db_parts;

/* Expected byte size of each section for the given counts. */
void mm__db_section_sizes(const mm__db_parts *p, size_t size[MM__SEC_COUNT]);

/* Checks settings against db (its joint count and feature groups, already validated): set bits
 * known and only for feature groups db has, values finite and in their ranges, zero where not
 * set, roles -1 or a joint. code is the result on failure (MM_ERR_SYNTAX for a file,
 * MM_ERR_OUT_OF_RANGE for a config); err says which field. */
mm_result mm__db_settings_validate(const mm_database *db, const mm_database_settings *settings,
                                   mm_result code, mm_error *err);

/* The parts of a packed database (db->data, validated), pointing into its buffer. */
void mm__db_parts_of(const mm_database *db, mm__db_parts *out);

/* Packs parts into one aligned buffer in file layout and points out into it. */
mm_result mm__db_pack(const mm__db_parts *parts, const mm_allocator *allocator, mm_database *out,
                      mm_error *err);

#endif
