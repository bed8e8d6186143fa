/* sim_skeleton.h - mm simulate's output in the game's skeleton (--skeleton GAME.bvh, with
 * --skeleton-map MAP.json): the skeleton read, the map made (mm/skeleton_map.h), each tick's pose
 * written in the game's joint names and order. */
#ifndef MM_TOOLS_SIM_SKELETON_H
#define MM_TOOLS_SIM_SKELETON_H

#include <mm/character.h>
#include <mm/skeleton_map.h>

typedef struct sim_skeleton {
    mm_skeleton_map map;
    mm_xform *world; /* [map.joint_count]: scratch for the pose */
} sim_skeleton;

/* Reads the game's skeleton from the BVH file at path (its lengths in metres: the unit detected
 * from its height) and the map file at map_path (NULL: joints matched by name, no root, the game's
 * bone lengths) and makes the map onto db. 0 on success; otherwise reports the error, naming the
 * file (and field), and returns 1. */
int sim_skeleton_open(sim_skeleton *s, const char *path, const char *map_path, const mm_database *db);
/* The output skeleton (a copy; free with mm_skeleton_free). */
int sim_skeleton_copy(const sim_skeleton *s, mm_skeleton *out);
/* The character's pose as local rotations and positions of the output skeleton. */
void sim_skeleton_pose(sim_skeleton *s, const mm_character *c, mm_quat *rotations, mm_vec3 *positions);
void sim_skeleton_close(sim_skeleton *s);

#endif
