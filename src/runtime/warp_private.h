/* warp_private.h (private) - the part of stride warping the character needs without its solves. */
#ifndef MM_RUNTIME_WARP_PRIVATE_H
#define MM_RUNTIME_WARP_PRIVATE_H

#include <mm/warp.h>

/* mm_warp_stride's feet targets and pelvis drop alone, without solving the legs (a caller that
 * solves them itself, from a pelvis of its own): targets[i] and *pelvis_drop are the out[i].target
 * and *pelvis_drop mm_warp_stride gives, and the result its result, but for MM_ERR_OUT_OF_RANGE
 * from solves whose numbers would overflow floats, which are not run. */
mm_result mm__warp_stride_targets(const mm_leg_pose *legs, int leg_count, mm_vec3 direction, float scale,
                                  float max_extension, mm_vec3 *targets, float *pelvis_drop);

#endif /* MM_RUNTIME_WARP_PRIVATE_H */
