/* mm/skeleton_map.h - the pose of a character written in the game's own skeleton: its joint names
 * and order, with joints the database does not have. Part of mm_runtime.
 *
 * The game's skeleton is a list of joints in topological order (mm_skeleton: names, parents, rest
 * offsets; read from a BVH with mm_bvh_load, or filled in by the game), with optional rest
 * rotations (BVH rest poses have none). Each game joint is, in the output:
 *  - mapped to a database joint (by equal name, or by a pair of the desc): in world it turns as the
 *    database joint turned from its rest (both skeletons' rest poses taken as the same posture:
 *    world rotation = database world rotation x the game joint's rest world rotation, the
 *    database's rest rotations being the identity) and stands where the database joint stands
 *    (with game_lengths: at the game's rest offset from its parent, except the game's roots);
 *  - following a database joint it lacks a counterpart of (a twist bone): its rest local rotation
 *    turned, in its parent's frame, by `weight` of that joint's local rotation (twist: of the part
 *    of it about the joint's rest offset, the bone it ends; weight 0.5 on a forearm's twist bone
 *    following the hand turns it half the hand's twist);
 *  - or at the game's rest pose (fingers, props) relative to its parent.
 * The added simulation root of the database (its joint 0, on the ground under the character) is
 * in the output only with with_root: it is then output joint 0 and the game's roots its children.
 * The output is the pose as local transforms in the output's joint order (and world transforms).
 *
 *   mm_skeleton_map map;
 *   mm_skeleton_map_init(&map, &db, &game_skeleton, NULL, &err);       // names matched as they are
 *   each tick, after mm_character_update(&c, ...):
 *     mm_skeleton_map_pose(&map, c.global, c.local_rotations, local_rotations, local_positions, world);
 *   mm_skeleton_map_free(&map);
 *
 * A map is read-only once made: many characters (a crowd, on many threads) may share it. Writing a
 * pose allocates nothing.
 *
 * Functions: mm_skeleton_map_init mm_skeleton_map_pose mm_skeleton_map_free
 */
#ifndef MM_SKELETON_MAP_H
#define MM_SKELETON_MAP_H

#include <stdbool.h>

#include "alloc.h"
#include "database.h"
#include "math.h"
#include "result.h"
#include "skeleton.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A game joint and the database joint it is (names). */
typedef struct mm_skeleton_map_pair {
    const char *game, *database;
} mm_skeleton_map_pair;

/* A game joint the database lacks, following a database joint (a twist bone). */
typedef struct mm_skeleton_map_follow {
    const char *game, *database;
    float weight; /* the share of the database joint's rotation it takes (0 to 1, say) */
    bool twist;   /* only the part about the database joint's bone (its rest offset) */
} mm_skeleton_map_follow;

typedef struct mm_skeleton_map_desc {
    const mm_skeleton_map_pair *pairs; /* beyond the joints of equal names (a pair overrides them) */
    int pair_count;
    const mm_skeleton_map_follow *follow;
    int follow_count;
    const mm_quat *rest_rotations; /* [game joint count]: the game's rest local rotations; NULL:
                                      the identity (a BVH's) */
    bool with_root;                /* output joint 0 is the database's joint 0 (the simulation root) */
    bool game_lengths;             /* mapped joints other than the game's roots stand at the game's
                                      rest offsets (the game's bone lengths) instead of where the
                                      database's joints stand */
    const mm_allocator *allocator; /* NULL: malloc */
} mm_skeleton_map_desc;

/* How an output joint is made. */
typedef enum mm_skeleton_map_source {
    MM_MAP_REST = 0,   /* the game's rest pose */
    MM_MAP_JOINT = 1,  /* a database joint */
    MM_MAP_FOLLOW = 2, /* following a database joint */
    MM_MAP_ROOT = 3,   /* the database's joint 0 (with_root) */
} mm_skeleton_map_source;

typedef struct mm_skeleton_map {
    int joint_count;         /* output joints: the game's, plus 1 with with_root */
    mm_joint *joints;        /* [joint_count]: the output skeleton (names, parents, offsets, Euler orders
                                of the game's; the root's and the translating joints' flags set) */
    int *source_kind;        /* [joint_count]: mm_skeleton_map_source */
    int *source;             /* [joint_count]: the database joint mapped or followed, -1 */
    float *weight;           /* [joint_count]: a follower's weight */
    mm_vec3 *axis;           /* [joint_count]: a twist follower's axis (unit, in its parent's frame);
                                zero: the whole rotation */
    mm_quat *rest_rotations; /* [joint_count]: local */
    mm_quat *rest_world;     /* [joint_count]: world rotations at rest */
    int database_joint_count;
    int mapped; /* game joints mapped to a database joint */
    bool game_lengths;
    mm_allocator allocator;
} mm_skeleton_map;

/* Makes the map of game (validated: mm_skeleton_validate) onto db's skeleton. Errors
 * (MM_ERR_INVALID_ARGUMENT, naming the joint): a pair or follower naming a joint neither skeleton
 * has, a game joint both mapped and following, a weight that is not finite, rest rotations that
 * are not finite, with_root when the game already has a joint of the root's name, no game joint
 * mapped at all; MM_ERR_OUT_OF_MEMORY. */
mm_result mm_skeleton_map_init(mm_skeleton_map *map, const mm_database *db, const mm_skeleton *game,
                               const mm_skeleton_map_desc *desc, mm_error *err);
void mm_skeleton_map_free(mm_skeleton_map *map);

/* The output pose from the database pose (db_global: world transforms [database joints], as
 * mm_character.global; db_local_rotations: as mm_character.local_rotations, read by followers
 * only): local rotations and positions and world transforms, each [map->joint_count], in the
 * output's joint order. Any output may be NULL except world (the parents' world transforms are
 * needed). Allocates nothing. */
void mm_skeleton_map_pose(const mm_skeleton_map *map, const mm_xform *db_global,
                          const mm_quat *db_local_rotations, mm_quat *local_rotations,
                          mm_vec3 *local_positions, mm_xform *world);

#ifdef __cplusplus
}
#endif

#endif /* MM_SKELETON_MAP_H */
