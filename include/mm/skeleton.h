/* mm/skeleton.h - joint hierarchies.
 *
 * A skeleton is a list of joints in topological order: every joint's parent comes before it, the
 * root (parent -1) is joint 0. Each joint has a rest offset from its parent (the BVH OFFSET), the
 * Euler order of its rotation channels in the source file (so writers can keep it), flags, and an
 * optional End Site (a leaf marker with an offset, not animated, not a joint of its own).
 *
 * Lengths are in the units of the source until scaled (mm_skeleton_scale); after import into a
 * clip with mm's defaults they are metres.
 *
 * Functions: mm_skeleton_init mm_skeleton_free mm_skeleton_copy mm_skeleton_find
 *            mm_skeleton_scale mm_skeleton_validate mm_skeleton_global_from
 */
#ifndef MM_SKELETON_H
#define MM_SKELETON_H

#include <stdbool.h>

#include "alloc.h"
#include "math.h"
#include "result.h"

#ifdef __cplusplus
extern "C" {
#endif

#define MM_NAME_MAX   64   /* joint names, including the terminating zero */
#define MM_MAX_JOINTS 1024 /* a sanity bound for readers; far above any real character */

enum mm_joint_flags {
    MM_JOINT_TRANSLATES = 1u << 0 /* the joint has animated translation (BVH position channels) */
};

typedef struct mm_joint {
    char name[MM_NAME_MAX];
    int parent;           /* index of the parent joint, -1 for the root; always < this index */
    mm_vec3 offset;       /* rest translation relative to the parent */
    mm_euler_order order; /* rotation order in the source (MM_EULER_NONE: no rotation channels) */
    unsigned flags;       /* mm_joint_flags */
    bool has_end_site;
    mm_vec3 end_site; /* End Site offset from this joint, when has_end_site */
} mm_joint;

typedef struct mm_skeleton {
    int joint_count;
    mm_joint *joints;       /* [joint_count], owned */
    mm_allocator allocator; /* what joints was allocated with (zero: malloc) */
} mm_skeleton;

/* Allocates joint_count zeroed joints (parents set to i-1, orders to MM_EULER_NONE).
 * allocator may be NULL. */
mm_result mm_skeleton_init(mm_skeleton *s, int joint_count, const mm_allocator *allocator);
void mm_skeleton_free(mm_skeleton *s);
/* Deep copy of src into dst (dst must not be initialised). */
mm_result mm_skeleton_copy(mm_skeleton *dst, const mm_skeleton *src, const mm_allocator *allocator);
/* Index of the joint with this exact name, or -1. */
int mm_skeleton_find(const mm_skeleton *s, const char *name);
/* Multiplies every offset and End Site offset by factor. */
void mm_skeleton_scale(mm_skeleton *s, float factor);
/* Checks the invariants: root first, parents before children, non-empty unique names, finite
 * offsets. Returns MM_OK or fills err naming the joint. */
mm_result mm_skeleton_validate(const mm_skeleton *s, mm_error *err);

/* Forward kinematics from joint `first` on: global[j] = global[parent] * (local_rotations[j],
 * local_positions[j]) for j = first .. joint_count - 1, in joint order (parents before children),
 * parents from joints[j].parent. global[0] is the caller's (the root's world transform), as are the
 * joints before first: they are read, not written. first < 1 counts as 1. */
void mm_skeleton_global_from(const mm_joint *joints, int joint_count, int first,
                             const mm_quat *local_rotations, const mm_vec3 *local_positions,
                             mm_xform *global);

#ifdef __cplusplus
}
#endif

#endif /* MM_SKELETON_H */
