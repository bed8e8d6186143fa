/* trajectory_private.h (private) - the simulation's update for the character's intent. */
#ifndef MM_RUNTIME_TRAJECTORY_PRIVATE_H
#define MM_RUNTIME_TRAJECTORY_PRIVATE_H

#include <mm/trajectory.h>

/* mm_trajectory_update(t, in, dt), then *velocity and *facing as mm_trajectory_desired(t, in)
 * gives them after it (the same bits; worked out again only where walls were touched). */
void mm__trajectory_update_desired(mm_trajectory *t, const mm_input *in, float dt, mm_vec3 *velocity,
                                   mm_quat *facing);

#endif /* MM_RUNTIME_TRAJECTORY_PRIVATE_H */
