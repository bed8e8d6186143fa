/* mm/import.h - animation import: every take of a BVH, FBX, glTF, Collada (or other) file as a clip.
 *
 * BVH files go through mm's own reader (mm/bvh.h): one take, named after the file. Every other
 * format goes through assimp when mm was built with it (CMake option MM_WITH_ASSIMP): each
 * animation take in the file becomes one clip, named after the take. Without assimp, non-BVH
 * files fail with MM_ERR_UNSUPPORTED.
 *
 * What an assimp take becomes (details in docs/import.md):
 *   - joints: the nodes the take animates plus their ancestors up to their common root, in
 *     topological order; unanimated nodes in between (and assimp's FBX "$AssimpFbx$" pivot
 *     helpers) are folded into the joint below them; a joint's single unanimated leaf child
 *     becomes its End Site;
 *   - axes: the result is Y up (FBX files' UpAxis/FrontAxis/CoordAxis are honoured; glTF is Y up
 *     by definition; assimp converts Collada's up_axis);
 *   - time: the take spans its earliest to its latest key; it is sampled at desc->fps or at its
 *     own rate (ticks per second when the keys sit on whole ticks, else the key spacing; 0 ticks
 *     per second means 25, as in assimp). Rotations are slerped and translations lerped between
 *     each channel's own keys;
 *   - world joint positions are reproduced exactly (up to float rounding) by mm_clip_fk even
 *     when the file has scales in its hierarchy; rotations have the scale removed.
 *
 *   mm_import_desc desc = {0}; desc.auto_scale = true;
 *   mm_clip_list takes; mm_error err;
 *   if (mm_import_clips("walks.fbx", &desc, &takes, &err) != MM_OK) { report err; }
 *   for (int i = 0; i < takes.count; ++i) use(takes.names[i], &takes.clips[i]);
 *   mm_clip_list_free(&takes);
 *
 * Functions: mm_import_clips mm_clip_list_free mm_import_has_assimp
 */
#ifndef MM_IMPORT_H
#define MM_IMPORT_H

#include <stdbool.h>

#include "alloc.h"
#include "clip.h"
#include "result.h"

#ifdef __cplusplus
extern "C" {
#endif

#define MM_TAKE_NAME_MAX 128 /* take names, including the terminating zero */

typedef struct mm_import_desc {
    float scale;     /* multiplies every length; 0: 1 (keep the file's units) */
    bool auto_scale; /* per take, pick the unit from the character's height as mm_bvh_detect_scale
                        does (the unit the file declares is tried first); overrides scale; fails
                        with MM_ERR_OUT_OF_RANGE when no unit gives a human height */
    float fps;       /* sample rate; 0: each take's own rate. BVH is resampled on C1 splines
                        (mm_clip_resample_interp, MM_INTERP_CUBIC) */
    const mm_allocator *allocator; /* NULL: malloc */
} mm_import_desc;

typedef struct mm_clip_list {
    int count;
    mm_clip *clips;                  /* [count], owned */
    char (*names)[MM_TAKE_NAME_MAX]; /* [count] take names (never empty; a file's unnamed takes
                                        are "take1", "take2", ...) */
    char format[16];                 /* "bvh", or the file's extension read by assimp ("fbx") */
    mm_allocator allocator;
} mm_clip_list;

/* Imports every take of the file at path. desc may be NULL (file units, own rates, malloc). On
 * success out holds count >= 1 clips; on error out is zeroed and err (may be NULL) names the file.
 * Errors: MM_ERR_IO (cannot open), MM_ERR_UNSUPPORTED (not BVH and built without assimp),
 * MM_ERR_SYNTAX (assimp cannot read the file; its message is kept), MM_ERR_NOT_FOUND (no take),
 * MM_ERR_LIMIT (over MM_MAX_JOINTS joints or MM_MAX_FRAMES frames), the BVH reader's errors,
 * MM_ERR_OUT_OF_RANGE (auto_scale found no unit; bad scale or fps). */
mm_result mm_import_clips(const char *path, const mm_import_desc *desc, mm_clip_list *out, mm_error *err);

/* Frees the clips and names; leaves list zeroed. NULL or a zeroed list is fine. */
void mm_clip_list_free(mm_clip_list *list);

/* Whether this build reads formats other than BVH (through assimp). */
bool mm_import_has_assimp(void);

#ifdef __cplusplus
}
#endif

#endif /* MM_IMPORT_H */
