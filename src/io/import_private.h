/* import_private.h (private) - what src/io/import.c shares with the assimp importer. */
#ifndef MM_IO_IMPORT_PRIVATE_H
#define MM_IO_IMPORT_PRIVATE_H

#include <mm/import.h>

/* Allocates count zeroed clips and names in list (count >= 1). */
mm_result mm__clip_list_alloc(mm_clip_list *list, int count, const mm_allocator *allocator);

/* Metres per file unit for a character height_units tall: declared (> 0: the unit the file
 * declares) if it gives a human height, else mm_bvh_detect_scale's rule; 0 when nothing fits. */
double mm__import_detect_unit(double height_units, double declared);

/* Scales the clip for desc (scale / auto_scale); declared as above. Fills err on failure. */
mm_result mm__import_apply_scale(mm_clip *clip, const mm_import_desc *desc, double declared, mm_error *err);

#ifdef MM_HAVE_ASSIMP
/* Every take of a non-BVH file through assimp (src/io/import_assimp.c). out is zeroed, err->file
 * already names path. */
mm_result mm__import_assimp(const char *path, const mm_import_desc *desc, mm_clip_list *out, mm_error *err);
#endif

#endif
