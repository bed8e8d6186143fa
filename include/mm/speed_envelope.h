/* mm/speed_envelope.h - what a database's locomotion covers: for each gait, the speed its frames
 * move at in each direction of travel relative to the facing (the mm_build library).
 *
 * The runtime's gait speeds (runtime.walk.forward_speed, ...) are what the user asks for; the
 * envelope is what the data can do. The build measures it (mm_database_build stores it in the
 * settings section) and the simulated trajectory moves at most at the envelope's speed in the
 * direction asked for (mm/trajectory.h, mm_trajectory_envelope_speed): the character is never
 * asked to move where no clip goes (docs/runtime.md, "The speed envelope").
 *
 * A gait's frames are those its search may play: locomotion clips' frames not left out by the
 * character's default search (DoNotUse, Jump, ...) nor tagged with another gait's tag (as the
 * character leaves them out). Each moving frame (the simulation bone faster than
 * MM_SPEED_SUMMARY_STILL) has a direction, atan2 of its root velocity's x (left) and z (forward).
 * Bin k (direction 2 pi k / MM_SPEED_ENVELOPE_BINS) takes the frames within
 * MM_SPEED_ENVELOPE_WINDOW of its direction (a window wider than a bin: neighbouring bins share
 * frames, which smooths the envelope across bins), and its speed is the fastest that at least
 * MM_SPEED_ENVELOPE_COVER_SECONDS of them reach (the data's speed that way, robust to a few fast
 * frames); 0 with fewer frames than that. Only the root velocities count: skeletons whose forward
 * kinematics agree give the same envelope.
 *
 *   mm_speed_envelope env[MM_GAIT_COUNT];
 *   mm_speed_envelope_measure(&db, NULL, env);
 *
 * Functions: mm_speed_envelope_measure
 */
#ifndef MM_SPEED_ENVELOPE_H
#define MM_SPEED_ENVELOPE_H

#include "alloc.h"
#include "database.h"
#include "result.h"
#include "trajectory.h"

#ifdef __cplusplus
extern "C" {
#endif

/* s: the frames a bin's speed needs, at least that speed */
#define MM_SPEED_ENVELOPE_COVER_SECONDS 0.5f
/* rad: a bin takes the frames within this of its direction (30 degrees; a bin is 22.5) */
#define MM_SPEED_ENVELOPE_WINDOW 0.5235988f

/* Measures db's envelope of every gait into out (allocator NULL: malloc; scratch of frame_count
 * floats). MM_ERR_INVALID_ARGUMENT without db or out, MM_ERR_OUT_OF_MEMORY. */
mm_result mm_speed_envelope_measure(const mm_database *db, const mm_allocator *allocator,
                                    mm_speed_envelope out[MM_GAIT_COUNT]);

#ifdef __cplusplus
}
#endif

#endif /* MM_SPEED_ENVELOPE_H */
