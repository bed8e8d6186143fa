/* mm/pfnn_character.h - the skeleton of the phase-functioned network's release (the mm_build
 * library: it reads the release's rest.bvh with the BVH reader; the network and its controller,
 * mm/pfnn.h, are the mm_pfnn library and need no part of it).
 *
 * Functions: mm_pfnn_character_load
 */
#ifndef MM_PFNN_CHARACTER_H
#define MM_PFNN_CHARACTER_H

#include "alloc.h"
#include "pfnn.h"
#include "result.h"
#include "skeleton.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The release's 31-joint skeleton: names and End Sites from dir/bvh/rest.bvh, parents from
 * dir/character_parents.bin, rest offsets from the translations of dir/character_xforms.bin
 * (centimetres, converted to metres). Rotation orders ZYX; the root translates. out must not be
 * initialised; free with mm_skeleton_free. */
mm_result mm_pfnn_character_load(const char *dir, const mm_allocator *allocator, mm_skeleton *out,
                                 mm_error *err);

#ifdef __cplusplus
}
#endif

#endif /* MM_PFNN_CHARACTER_H */
