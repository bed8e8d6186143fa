/* pose_codec.h (private) - the compressed local transforms of a database (mm_db_compressed_poses,
 * docs/format.md "Compressed poses"): decoding one frame of a segment, validating the sections on
 * load (mm_runtime), and compressing a database's float poses (mm_build, pose_encode.c). */
#ifndef MM_DB_POSE_CODEC_H
#define MM_DB_POSE_CODEC_H

#include <mm/database.h>

/* Zero bytes after the last segment's frames: the reader loads 8 bytes at a time. */
#define MM__POSE_BITS_TAIL 8
/* The largest error bound a file may state (m): far above any use, it keeps the field sane. */
#define MM__POSE_ERROR_BOUND_MAX 0.1f

/* One segment's tracks and frames, wherever they are (the file, or an encoder's trial). */
typedef struct mm__pose_segment_view {
    int joint_count, translating_count;
    const int32_t *translating_joints;           /* [translating_count] */
    const mm_vec3 *constant_positions;           /* [joint_count] */
    const mm_db_rotation_track *rotations;       /* [joint_count] */
    const mm_db_translation_track *translations; /* [translating_count] */
    const uint8_t *bits;                         /* the segment's first frame, with at least
                                                    MM__POSE_BITS_TAIL readable bytes after its last */
    uint32_t frame_bits;
} mm__pose_segment_view;

/* Bits a track takes per frame: 3 components of `bits` bits, or the raw floats (4 for a rotation,
 * 3 for a translation). */
static inline uint32_t mm__pose_rotation_frame_bits(unsigned bits)
{
    return bits == MM_POSE_RAW_BITS ? 4u * 32u : 3u * bits;
}
static inline uint32_t mm__pose_translation_frame_bits(unsigned bits)
{
    return bits == MM_POSE_RAW_BITS ? 3u * 32u : 3u * bits;
}

/* A rotation track's component range: 16-bit fractions of [-1, 1]. */
static inline float mm__pose_unit_from_u16(unsigned v) { return (float)v * (2.0f / 65535.0f) - 1.0f; }
static inline float mm__pose_extent_from_u16(unsigned v) { return (float)v * (2.0f / 65535.0f); }

/* The local transforms of frame `frame` (0-based in the segment) into rot and pos [joint_count]. */
void mm__pose_decode(const mm__pose_segment_view *v, int frame, mm_quat *rot, mm_vec3 *pos);

/* The view of db's compressed segment s. */
void mm__pose_segment_of(const mm_database *db, int s, mm__pose_segment_view *out);

/* Index of the first joint whose rotation is not of unit length (within the loader's tolerance) or
 * whose translation is not finite within the loader's limit; n when all are good. */
size_t mm__pose_first_bad_joint(const mm_quat *rot, const mm_vec3 *pos, size_t n);

/* Validates db's compressed sections (header counts already checked): the segments tiling every
 * clip in order, the tracks' bits, ranges and reserved bytes, the bit stream's offsets, padding and
 * tail, then the floats of raw tracks as loading checks floats (a quantized track decodes within
 * its range). MM_ERR_SYNTAX "compressed poses: ...". */
mm_result mm__pose_codec_validate(const mm_database *db, mm_error *err);

#endif
