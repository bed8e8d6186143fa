/* spring_private.h (private) - mm_spring_update_quat in two parts, for callers that step one
 * rotation toward one target over several times (the trajectory's samples from its present). */
#ifndef MM_RUNTIME_SPRING_PRIVATE_H
#define MM_RUNTIME_SPRING_PRIVATE_H

#include <mm/spring.h>

/* The rotation still to go from q to target, as the rotation vector mm_spring_update_quat springs
 * to zero: the same for every step from the same q toward the same target. */
mm_vec3 mm__spring_quat_gap(mm_quat q, mm_quat target);

/* mm_spring_update_quat(q, w, target, halflife, dt) given gap = mm__spring_quat_gap(*q, target):
 * the same bits. */
void mm__spring_update_quat_gap(mm_quat *q, mm_vec3 *w, mm_vec3 gap, mm_quat target, float halflife,
                                float dt);

#endif /* MM_RUNTIME_SPRING_PRIVATE_H */
