/* mm/clip.h - animation clips and forward kinematics.
 *
 * A clip is a skeleton plus, for every frame, the local rotation and local translation of every
 * joint. Local translation is the joint's position in its parent's frame: the rest offset for
 * joints that do not translate, the animated position for those that do (in BVH, position
 * channels replace the OFFSET). Frames are sampled uniformly at fps.
 *
 *   mm_clip clip;
 *   mm_clip_init(&clip, &skeleton, frames, 30.0f, NULL);
 *   ... fill mm_clip_rotations(&clip, f)[j] and mm_clip_positions(&clip, f)[j] ...
 *   mm_clip_fk(&clip, f, globals);            // globals: joint_count transforms
 *   mm_clip_free(&clip);
 *
 * Functions: mm_clip_init mm_clip_free mm_clip_copy mm_clip_rotations mm_clip_positions
 *            mm_clip_duration mm_clip_scale mm_clip_sample_frame mm_clip_sample
 *            mm_clip_resample_interp mm_clip_resample
 *            mm_fk mm_clip_fk mm_global_to_local mm_skeleton_estimate_height mm_unit_scale_for_height
 */
#ifndef MM_CLIP_H
#define MM_CLIP_H

#include "alloc.h"
#include "math.h"
#include "result.h"
#include "skeleton.h"

#ifdef __cplusplus
extern "C" {
#endif

#define MM_MAX_FRAMES (1 << 24) /* a sanity bound: over 77 hours at 60 fps */

typedef struct mm_clip {
    mm_skeleton skeleton; /* owned copy */
    float fps;            /* frames per second, > 0 */
    int frame_count;
    mm_quat *rotations; /* [frame_count * joint_count] local rotations (unit quaternions) */
    mm_vec3 *positions; /* [frame_count * joint_count] local translations */
    mm_allocator allocator;
} mm_clip;

/* Copies skeleton and allocates frame_count frames, filled with the rest pose (identity
 * rotations, rest offsets). frame_count may be 0. fps must be finite and > 0. */
mm_result mm_clip_init(mm_clip *clip, const mm_skeleton *skeleton, int frame_count, float fps,
                       const mm_allocator *allocator);
void mm_clip_free(mm_clip *clip);
mm_result mm_clip_copy(mm_clip *dst, const mm_clip *src, const mm_allocator *allocator);

/* The joint_count local rotations / translations of frame (0 <= frame < frame_count). */
static inline mm_quat *mm_clip_rotations(const mm_clip *clip, int frame)
{
    return clip->rotations + (long)frame * clip->skeleton.joint_count;
}
static inline mm_vec3 *mm_clip_positions(const mm_clip *clip, int frame)
{
    return clip->positions + (long)frame * clip->skeleton.joint_count;
}
/* Seconds from the first to the last frame: (frame_count - 1) / fps, 0 for fewer than 2. */
float mm_clip_duration(const mm_clip *clip);

/* Multiplies all lengths (offsets, End Sites, translations) by factor. */
void mm_clip_scale(mm_clip *clip, float factor);

/* Turns the clip's world by the rotation turn: every root joint's (parent -1) rotation, translation
 * and rest offset, so that each joint's world position p becomes turn p in every frame. */
void mm_clip_turn(mm_clip *clip, mm_quat turn);

/* How a clip is read between its frames. */
typedef enum mm_interp {
    /* rotations by slerp, translations linearly, between the two nearest frames: the velocity
     * jumps at every frame */
    MM_INTERP_LINEAR = 0,
    /* C1 splines through the frames (mm_quat_catmull_rom, mm_vec3_catmull_rom in mm/math.h):
     * tangents from the neighbouring frames, one-sided at the first and last; a whole frame
     * position gives that frame exactly */
    MM_INTERP_CUBIC = 1
} mm_interp;

/* Pose at frame position x (a fractional frame index, clamped to [0, frame_count - 1]; NaN reads
 * frame 0). out arrays hold joint_count entries. A clip without frames gives the rest pose. */
void mm_clip_sample_frame(const mm_clip *clip, double x, mm_interp interp, mm_quat *out_rotations,
                          mm_vec3 *out_positions);

/* Pose at time t seconds (clamped to the clip), MM_INTERP_LINEAR: mm_clip_sample_frame at t * fps. */
void mm_clip_sample(const mm_clip *clip, float t, mm_quat *out_rotations, mm_vec3 *out_positions);

/* Resamples src to fps into dst (not initialised): the new clip covers the same duration,
 * frame_count = floor(duration * fps + 1e-4) + 1, frame f sampled at src frame position
 * f * src->fps / fps (mm_clip_sample_frame). Going down in rate, frames are sampled, not
 * filtered. mm_clip_resample is mm_clip_resample_interp with MM_INTERP_LINEAR. */
mm_result mm_clip_resample_interp(mm_clip *dst, const mm_clip *src, float fps, mm_interp interp,
                                  const mm_allocator *allocator);
mm_result mm_clip_resample(mm_clip *dst, const mm_clip *src, float fps, const mm_allocator *allocator);

/* Forward kinematics: global transforms of every joint from local rotations and translations.
 * out_global holds joint_count transforms; the root's global is its local transform. */
void mm_fk(const mm_skeleton *s, const mm_quat *local_rotations, const mm_vec3 *local_positions,
           mm_xform *out_global);
void mm_clip_fk(const mm_clip *clip, int frame, mm_xform *out_global);
/* Inverse of mm_fk: local rotations and translations from global transforms. */
void mm_global_to_local(const mm_skeleton *s, const mm_xform *global, mm_quat *out_rotations,
                        mm_vec3 *out_positions);

/* Standing height estimate, in the skeleton's units: the vertical (Y) extent of the joints and
 * End Sites in the given pose (for example frame 0 of a clip). Pass NULL rotations and positions
 * for the rest pose. */
float mm_skeleton_estimate_height(const mm_skeleton *s, const mm_quat *local_rotations,
                                  const mm_vec3 *local_positions);

/* Scale that converts lengths in an unknown unit to metres, judged from a human character's
 * height in that unit: among metres (1), centimetres (0.01), millimetres (0.001), inches (0.0254),
 * feet (0.3048) and the CMU converter's unit (0.056444), those giving a height of 0.8 to 2.6 m are
 * kept and the one closest to 1.75 m (by ratio) wins. 0 when none fits. */
double mm_unit_scale_for_height(double height);

#ifdef __cplusplus
}
#endif

#endif /* MM_CLIP_H */
