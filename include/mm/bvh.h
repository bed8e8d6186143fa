/* mm/bvh.h - Biovision Hierarchy (BVH) reading and writing.
 *
 * Reading keeps the file as written (mm_bvh: hierarchy, channels, frame values in file units
 * and degrees, in double precision), so tools can report and compute exactly what the file
 * says. mm_bvh_to_clip turns it into an mm_clip (quaternions, optional scaling to metres).
 *
 * Semantics: rotation channels compose in the order listed (intrinsic): "Zrotation Yrotation
 * Xrotation" is R = Rz * Ry * Rx. Position channels REPLACE the joint's OFFSET; they are not
 * added to it. Any joint may have 0, 3 or 6 channels, in any order. The reader accepts tabs,
 * CRLF line ends, trailing spaces and numbers like ".0083333". BVH has no unit: the import
 * scale is explicit or detected (see docs/bvh.md).
 *
 *   mm_bvh bvh; mm_error err;
 *   if (mm_bvh_load("walk.bvh", NULL, &bvh, &err) != MM_OK) { report err; }
 *   mm_clip clip; mm_bvh_import_desc imp = {0}; imp.auto_scale = true;
 *   mm_bvh_to_clip(&bvh, &imp, &clip, &err);
 *   mm_bvh_free(&bvh);
 *   mm_bvh_save("out.bvh", &clip, NULL, &err);
 *
 * Functions: mm_bvh_parse mm_bvh_load mm_bvh_free mm_bvh_fk mm_bvh_to_clip
 *            mm_bvh_detect_scale mm_bvh_write mm_bvh_save mm_bvh_channel_name
 *            mm_bvh_stream_open mm_bvh_stream_frame mm_bvh_stream_close mm_bvh_frame_bytes_max
 */
#ifndef MM_BVH_H
#define MM_BVH_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include "alloc.h"
#include "clip.h"
#include "result.h"
#include "skeleton.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum mm_bvh_channel {
    MM_BVH_XPOSITION,
    MM_BVH_YPOSITION,
    MM_BVH_ZPOSITION,
    MM_BVH_XROTATION,
    MM_BVH_YROTATION,
    MM_BVH_ZROTATION
} mm_bvh_channel;

/* "Xposition" ... "Zrotation"; NULL for an invalid value. */
const char *mm_bvh_channel_name(mm_bvh_channel c);

typedef struct mm_bvh_joint_channels {
    int first;             /* index of the joint's first value in a frame's values */
    int count;             /* 0, 3 or 6 */
    unsigned char type[6]; /* mm_bvh_channel of each, in file order */
} mm_bvh_joint_channels;

typedef struct mm_bvh {
    mm_skeleton skeleton;            /* file units; order and flags from the channels */
    mm_bvh_joint_channels *channels; /* [joint_count] */
    double *offsets;                 /* [3 * joint_count] OFFSETs exactly as written */
    int channel_count;               /* values per frame */
    int frame_count;
    double frame_time; /* seconds per frame, > 0 */
    double *values;    /* [frame_count * channel_count], as written: file units, degrees */
    mm_allocator allocator;
} mm_bvh;

typedef struct mm_bvh_read_desc {
    const char *name;              /* used in error messages; NULL: the path, or "<memory>" */
    const mm_allocator *allocator; /* NULL: malloc */
} mm_bvh_read_desc;

/* Parses BVH text (not necessarily zero-terminated) of size bytes. desc may be NULL. On error
 * returns the code, fills err (line, column, message) and leaves out zeroed. */
mm_result mm_bvh_parse(const char *text, size_t size, const mm_bvh_read_desc *desc, mm_bvh *out,
                       mm_error *err);
/* Reads the file at path and parses it. */
mm_result mm_bvh_load(const char *path, const mm_bvh_read_desc *desc, mm_bvh *out, mm_error *err);
void mm_bvh_free(mm_bvh *bvh);

/* World positions of every joint (End Sites excluded) at frame, in file units, computed in double
 * precision directly from the channel values and OFFSETs. out_xyz holds 3 * joint_count doubles.
 * Fails with MM_ERR_OUT_OF_RANGE for a frame outside [0, frame_count). */
mm_result mm_bvh_fk(const mm_bvh *bvh, int frame, double *out_xyz);

/* Scale that converts the file's units to metres (mm_unit_scale_for_height of the character's
 * height: the vertical extent of the joints and End Sites at frame 0, or of the rest pose if
 * there are no frames). Returns 0 when no unit fits. out_height (may be NULL) receives the
 * height in file units. */
double mm_bvh_detect_scale(const mm_bvh *bvh, double *out_height);

typedef struct mm_bvh_import_desc {
    float scale;     /* multiplies every length; 0: 1 (keep the file's units) */
    bool auto_scale; /* use mm_bvh_detect_scale (fails with MM_ERR_OUT_OF_RANGE if it finds none) */
    const mm_allocator *allocator; /* NULL: malloc */
} mm_bvh_import_desc;

/* Converts to a clip: fps = 1 / frame_time, quaternion rotations, translations (the OFFSET, or
 * the position channels where the joint has them), all lengths times the scale. desc may be
 * NULL. */
mm_result mm_bvh_to_clip(const mm_bvh *bvh, const mm_bvh_import_desc *desc, mm_clip *out, mm_error *err);

typedef struct mm_bvh_write_desc {
    mm_euler_order order;          /* rotation order of every joint; MM_EULER_NONE: each joint's own
                                      order from the skeleton, ZYX where it has none */
    int precision;                 /* significant digits of every number; 0: 9 (float round trip) */
    const mm_allocator *allocator; /* for the output buffer; NULL: malloc */
} mm_bvh_write_desc;

/* Writes clip as BVH text into a buffer allocated with desc->allocator (free with mm_free).
 * The root and every joint flagged MM_JOINT_TRANSLATES get 6 channels (positions first), the
 * others 3. Numbers are printed in the C locale whatever the process locale. */
mm_result mm_bvh_write(const mm_clip *clip, const mm_bvh_write_desc *desc, char **out_text, size_t *out_size,
                       mm_error *err);
/* Writes to path atomically: a temporary file beside it, then a rename; nothing is left behind
 * on failure. */
mm_result mm_bvh_save(const char *path, const mm_clip *clip, const mm_bvh_write_desc *desc, mm_error *err);

/* Writes a BVH file frame by frame, in bounded memory whatever the length: the same bytes
 * mm_bvh_write gives for the same skeleton, fps and frames. open writes the hierarchy and the
 * MOTION header declaring frame_count frames; each frame call writes one (local rotations and
 * positions, skeleton->joint_count each); close flushes and frees the stream (also after an
 * error) and fails when fewer frames than declared were written. The skeleton must outlive the
 * stream; the caller owns and closes file. */
typedef struct mm_bvh_stream mm_bvh_stream;
mm_result mm_bvh_stream_open(mm_bvh_stream **out, FILE *file, const mm_skeleton *skeleton, float fps,
                             int frame_count, const mm_bvh_write_desc *desc, mm_error *err);
mm_result mm_bvh_stream_frame(mm_bvh_stream *stream, const mm_quat *rotations, const mm_vec3 *positions,
                              mm_error *err);
mm_result mm_bvh_stream_close(mm_bvh_stream *stream, mm_error *err);
/* The most bytes one frame's line can take (every number at its longest): what a caller sizes a
 * run against the readers' file-size limit with. */
size_t mm_bvh_frame_bytes_max(const mm_skeleton *skeleton, const mm_bvh_write_desc *desc);

#ifdef __cplusplus
}
#endif

#endif /* MM_BVH_H */
