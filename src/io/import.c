/* Import front end: BVH through mm's own reader, everything else through assimp when built with it
 * (src/io/import_assimp.c, the only file that includes assimp's headers). */
#include <mm/bvh.h>
#include <mm/import.h>

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "io/file.h"
#include "io/import_private.h"

bool mm_import_has_assimp(void)
{
#ifdef MM_HAVE_ASSIMP
    return true;
#else
    return false;
#endif
}

void mm_clip_list_free(mm_clip_list *list)
{
    if (!list) return;
    if (list->clips)
        for (int i = 0; i < list->count; ++i) mm_clip_free(&list->clips[i]);
    mm_free(&list->allocator, list->clips);
    mm_free(&list->allocator, list->names);
    memset(list, 0, sizeof *list);
}

mm_result mm__clip_list_alloc(mm_clip_list *list, int count, const mm_allocator *allocator)
{
    memset(list, 0, sizeof *list);
    if (allocator) list->allocator = *allocator;
    list->clips = (mm_clip *)mm_alloc_array(allocator, (size_t)count, sizeof *list->clips);
    list->names = (char(*)[MM_TAKE_NAME_MAX])mm_alloc_array(allocator, (size_t)count, sizeof *list->names);
    if (!list->clips || !list->names) {
        mm_clip_list_free(list);
        if (allocator) list->allocator = *allocator;
        return MM_ERR_OUT_OF_MEMORY;
    }
    list->count = count;
    return MM_OK;
}

double mm__import_detect_unit(double height_units, double declared)
{
    if (!(height_units > 0.0) || !isfinite(height_units)) return 0.0;
    if (declared > 0.0) {
        double h = height_units * declared;
        if (h >= 0.8 && h <= 2.6) return declared;
    }
    return mm_unit_scale_for_height(height_units);
}

mm_result mm__import_apply_scale(mm_clip *clip, const mm_import_desc *desc, double declared, mm_error *err)
{
    double scale = 1.0;
    if (desc && desc->auto_scale) {
        const mm_quat *rot = clip->frame_count > 0 ? mm_clip_rotations(clip, 0) : NULL;
        const mm_vec3 *pos = clip->frame_count > 0 ? mm_clip_positions(clip, 0) : NULL;
        double height = mm_skeleton_estimate_height(&clip->skeleton, rot, pos);
        scale = mm__import_detect_unit(height, declared);
        if (scale == 0.0)
            return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0,
                                "cannot detect the unit: the character is %g units tall, which is no human "
                                "height in metres, centimetres, millimetres, inches or feet; give a scale",
                                height);
    } else if (desc && desc->scale != 0.0f) {
        scale = desc->scale;
    }
    if (scale != 1.0) mm_clip_scale(clip, (float)scale);
    return MM_OK;
}

/* The extension after the last dot of the file name, or "". */
static const char *extension(const char *path)
{
    const char *slash = strrchr(path, '/');
    const char *name = slash ? slash + 1 : path;
    const char *dot = strrchr(name, '.');
    return dot && dot != name ? dot + 1 : "";
}

static bool equal_nocase(const char *a, const char *b)
{
    for (; *a && *b; ++a, ++b)
        if (tolower((unsigned char)*a) != tolower((unsigned char)*b)) return false;
    return *a == *b;
}

static mm_result import_bvh(const char *path, const mm_import_desc *desc, mm_clip_list *out, mm_error *err)
{
    const mm_allocator *allocator = desc ? desc->allocator : NULL;
    mm_bvh_read_desc rd;
    memset(&rd, 0, sizeof rd);
    rd.allocator = allocator;
    mm_bvh bvh;
    mm_result r = mm_bvh_load(path, &rd, &bvh, err);
    if (r != MM_OK) return r;
    mm_bvh_import_desc imp;
    memset(&imp, 0, sizeof imp);
    if (desc) {
        imp.scale = desc->scale;
        imp.auto_scale = desc->auto_scale;
    }
    imp.allocator = allocator;
    mm_clip clip;
    r = mm_bvh_to_clip(&bvh, &imp, &clip, err);
    mm_bvh_free(&bvh);
    if (r != MM_OK) return r;
    if (desc && desc->fps > 0.0f && desc->fps != clip.fps) {
        mm_clip resampled;
        r = mm_clip_resample_interp(&resampled, &clip, desc->fps, MM_INTERP_CUBIC, allocator);
        mm_clip_free(&clip);
        if (r != MM_OK)
            return mm_error_set(err, r, 0, 0, "cannot resample to %g fps: %s", desc->fps, mm_result_str(r));
        clip = resampled;
    }
    r = mm__clip_list_alloc(out, 1, allocator);
    if (r != MM_OK) {
        mm_clip_free(&clip);
        return mm_error_set(err, r, 0, 0, "out of memory");
    }
    out->clips[0] = clip;
    /* A BVH file is one take, named after the file. */
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    size_t len = strlen(base) - (strlen(extension(base)) + 1);
    if (len >= MM_TAKE_NAME_MAX) len = MM_TAKE_NAME_MAX - 1;
    memcpy(out->names[0], base, len);
    out->names[0][len] = 0;
    if (!out->names[0][0]) snprintf(out->names[0], MM_TAKE_NAME_MAX, "take1");
    snprintf(out->format, sizeof out->format, "bvh");
    return MM_OK;
}

mm_result mm_import_clips(const char *path, const mm_import_desc *desc, mm_clip_list *out, mm_error *err)
{
    if (err) memset(err, 0, sizeof *err);
    if (!out) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no output list given");
    memset(out, 0, sizeof *out);
    if (desc && desc->allocator) out->allocator = *desc->allocator;
    if (!path) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no file name given");
    mm__error_set_file(err, path);
    if (desc && (!isfinite(desc->scale) || desc->scale < 0.0f))
        return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0, "scale %g must be finite and positive (0: keep)",
                            (double)desc->scale);
    if (desc && (!isfinite(desc->fps) || desc->fps < 0.0f || desc->fps > 10000.0f))
        return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0,
                            "fps %g must be in (0, 10000] (0: the take's own)", (double)desc->fps);

    const char *ext = extension(path);
    mm_result r;
    if (equal_nocase(ext, "bvh")) {
        r = import_bvh(path, desc, out, err);
    } else {
#ifdef MM_HAVE_ASSIMP
        r = mm__import_assimp(path, desc, out, err);
#else
        FILE *f = fopen(path, "rb");
        if (!f) return mm_error_set(err, MM_ERR_IO, 0, 0, "cannot open: %s", strerror(errno));
        fclose(f);
        r = mm_error_set(err, MM_ERR_UNSUPPORTED, 0, 0,
                         "mm was built without assimp, so only BVH files can be imported (install "
                         "libassimp-dev and configure with -DMM_WITH_ASSIMP=ON for FBX, glTF, Collada)");
#endif
    }
    if (r != MM_OK) mm_clip_list_free(out);
    return r;
}
