/* Stage 8, walls: in a scene (mm_character_set_scene), the whole body out of the walls. The root
 * is kept out by the simulation's capsule (stage 5); a stride, a foot planted ahead or a hand can
 * still reach past it, so the pose as it stands is moved back out, with what the feet hold. */
#ifndef MM_RUNTIME_WALLS_H
#define MM_RUNTIME_WALLS_H

#include <mm/character.h>

#include "feet.h"
#include "rig.h"

/* The horizontal translation that takes the joints 1 .. joint_count - 1 of pose out of the walls
 * (the boxes the trajectory's capsule collides with: mm_trajectory_collide's rule), each wall
 * left through its face toward root (the character, outside it): the deepest joint's depth along
 * that face's normal; zero when none is inside, or without a scene. */
mm_vec3 mm_walls_push(const mm_trajectory *t, mm_vec3 root, const mm_rig_pose *pose, int joint_count);

/* Moves the root, the pose and what the feet hold by delta (a rigid translation). */
void mm_walls_move_body(mm_xform *root, mm_rig_pose *pose, int joint_count, mm_feet *feet, mm_vec3 delta);

#endif
