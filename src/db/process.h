/* process.h (private) - turning source clips into database clips.
 *
 * Every step takes a clip and makes a new one (the input is left alone):
 *   mm__clip_extract      frames [begin, end) of a source, resampled to the database interval
 *                         (MM_INTERP_CUBIC, the splines running through the neighbouring frames)
 *   mm__clip_fold_root    folds the joints above the hips into one static joint at the origin,
 *                         the hips (and what else hung from those joints) at their world place
 *   mm__clip_add_root     adds the simulation bone as joint 0 (position: a spine bone projected
 *                         to the ground; facing: a bone's forward axis projected; both smoothed);
 *                         the joints above the hips are folded into it
 *   mm__clip_mirror       mirrors across the character's sagittal plane, swapping left and right:
 *                         the world pose reflected, made local with each joint's rest axes
 *   mm__clip_blend        blends two clips on a common (normalised) time base
 * and the analysis used by the build:
 *   mm__root_motion       per-frame root velocity and yaw rate, in the root's frame
 *   mm__contact_tracks, mm__contact_grounds, mm__label_contacts
 *                         heel/toe contact flags from height and speed over each take, without
 *                         flicker (mm__detect_contacts: one clip on its own)
 *   mm__remove_short_runs, mm__quantile   helpers shared with the move detector
 */
#ifndef MM_DB_PROCESS_H
#define MM_DB_PROCESS_H

#include <stdint.h>

#include <mm/clip.h>
#include <mm/config.h>

#define MM__ROOT_NAME "SimulationRoot"

/* Yaw (radians about +Y, 0 = facing +Z) of a rotation's +Z axis projected to the ground. */
float mm__yaw_of(mm_quat q);
mm_quat mm__quat_yaw(float yaw);
/* Angle wrapped to (-pi, pi]. */
float mm__wrap_angle(float a);

mm_result mm__clip_extract(const mm_clip *src, int begin, int end, float interval, mm_clip *out,
                           const mm_allocator *a);
/* The body's root: roles.hips when the skeleton has it, else joint 0. */
int mm__body_root(const mm_skeleton *s, const mm_config *cfg);
/* src with the joints above joint body (0 < body < joint_count) replaced by one joint 0 that
 * keeps the top one's name and stays at the origin unrotated; the joints that hung from them
 * (body among them) hang from it with their world transforms, translating, their rest positions
 * as offsets. World transforms of the other joints are unchanged. */
mm_result mm__clip_fold_root(const mm_clip *src, int body, mm_clip *out, const mm_allocator *a);
/* The database clip of a resampled source: joint 0 the simulation bone, then the source's joints
 * but those above the body root (mm__body_root), which are left out; the joints that hung from
 * them (the body root among them; the source root when nothing is above it) hang from the
 * simulation bone with their world transforms relative to it. The roles (root_bone, facing_bone)
 * are read from src, any joint of it; body (NULL: src) gives the joints' motion: src with the
 * joints above the body root folded by mm__clip_fold_root, then resampled alike. */
mm_result mm__clip_add_root(const mm_clip *src, const mm_clip *body, const mm_config *cfg, mm_clip *out,
                            const mm_allocator *a, mm_error *err);
mm_result mm__clip_mirror(const mm_clip *src, const mm_config *cfg, mm_clip *out, const mm_allocator *a);
/* Whether a skeleton can be mirrored under the config's pairs: every joint whose name carries a
 * side (a pattern of mirror_pairs, as a word of its own) has its partner, partners are each
 * other's, and partners' bones (rest offsets) are within 10% of each other's length. Fills err
 * naming the joints. */
mm_result mm__mirror_check(const mm_skeleton *s, const mm_config *cfg, mm_error *err);
/* Clips with the simulation root as joint 0; a loop clip's frame after its last is its first. */
mm_result mm__clip_blend(const mm_clip *left, int left_loop, const mm_clip *right, int right_loop,
                         float weight, float interval, mm_clip *out, const mm_allocator *a);

/* Mirror partner of every joint (itself when it has none), from the config's name pairs. */
void mm__mirror_map(const mm_skeleton *s, const mm_config *cfg, int *partner);

/* Root velocity (m/s, root frame) and yaw rate (rad/s) of a clip whose joint 0 is the root:
 * backward differences, forward at frame 0 (the runtime measures its own motion the same way). */
void mm__root_motion(const mm_clip *clip, mm_vec3 *velocity, float *yaw_rate);

/* One heel or toe joint at one frame: its height (m; NAN for a missing joint) and horizontal
 * speed (m/s, backward difference; forward at frame 0). */
typedef struct mm__contact_track {
    float height, speed;
} mm__contact_track;
/* Where a clip's heel and toe joints stand: each one's floor (height; NAN: never in contact) and
 * its planted height above the floor (where it comes to rest). */
typedef struct mm__contact_ground {
    float floor[4], planted[4];
} mm__contact_ground;

/* The tracks of the joints heel_toe[0..3] (-1: missing) of a clip whose globals are given
 * ([frames x joints]): out[frame * 4 + k]. */
void mm__contact_tracks(const mm_clip *clip, const mm_xform *globals, const int heel_toe[4],
                        mm__contact_track *out);
/* The grounds of clip_count clips (frames[i] frames, tracks[i] from mm__contact_tracks): clips
 * with the same take (>= 0; -1: a take of its own) share floors, the 5th percentile of each
 * joint's height over the take, but a clip whose joints all stay at least contact_height above
 * them keeps its own; planted heights are the take's median height above the floor of its low,
 * slow frames (contacts.height, contacts.speed). MM_ERR_OUT_OF_MEMORY when out of memory. */
mm_result mm__contact_grounds(int clip_count, const int *take, const int *frames,
                              const mm__contact_track *const *tracks, const mm_config *cfg,
                              mm__contact_ground *out);
/* Contact flags (mm_contact_bits) of n frames at fps: a joint is in contact when under
 * contact_height above its floor, at most contact_planted_tolerance above its planted height and
 * slower than contact_speed; flicker (runs shorter than contact_min_time) removed. */
void mm__label_contacts(const mm__contact_track *tracks, int n, float fps, const mm__contact_ground *ground,
                        const mm_config *cfg, uint8_t *out);
/* Contact flags of one clip on its own: floors from the clip alone, any height under
 * contact_height (no planted height). heel/toe: joint indices (-1: never in contact). */
void mm__detect_contacts(const mm_clip *clip, const mm_xform *globals, const int heel_toe[4],
                         const mm_config *cfg, uint8_t *out);
/* Flips the runs of value v (0 or 1) shorter than min_len frames that have the other value on
 * both sides (flicker in per-frame flags). */
void mm__remove_short_runs(uint8_t *on, int n, uint8_t v, int min_len);
/* The value at fraction q (0..1) of the n values, rounded down to a sample; sorts v. */
float mm__quantile(float *v, int n, float q);

#endif
