/* The release's 31-joint character: rest.bvh for names and End Sites, character_parents.bin for the
 * hierarchy, character_xforms.bin (local rest transforms, centimetres) for the offsets. */
#include <mm/bvh.h>
#include <mm/pfnn_character.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "io/file.h"

#define CMU_TO_CM 5.644 /* rest.bvh units to centimetres (README of the release) */

static mm_result read_exact(const char *path, size_t count, const mm_allocator *a, float *out, mm_error *err)
{
    char *data = NULL;
    size_t size = 0;
    mm_result r = mm__read_file(path, a, &data, &size, err);
    if (r != MM_OK) return r;
    if (size != count * 4) {
        mm_free(a, data);
        return mm_error_set(err, size < count * 4 ? MM_ERR_UNEXPECTED_EOF : MM_ERR_VALUE_COUNT, 0, 0,
                            "%s file: %zu bytes, expected %zu (%zu float32)",
                            size < count * 4 ? "short" : "long", size, count * 4, count);
    }
    const unsigned char *p = (const unsigned char *)data;
    for (size_t i = 0; i < count; ++i) {
        /* little-endian on any host */
        unsigned bits = (unsigned)p[4 * i] | (unsigned)p[4 * i + 1] << 8 | (unsigned)p[4 * i + 2] << 16 |
                        (unsigned)p[4 * i + 3] << 24;
        float v;
        memcpy(&v, &bits, 4);
        out[i] = v;
    }
    mm_free(a, data);
    for (size_t i = 0; i < count; ++i)
        if (!isfinite(out[i]))
            return mm_error_set(err, MM_ERR_BAD_NUMBER, 0, 0, "value %zu is not finite", i);
    return MM_OK;
}

mm_result mm_pfnn_character_load(const char *dir, const mm_allocator *allocator, mm_skeleton *out,
                                 mm_error *err)
{
    if (!out) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no output given");
    memset(out, 0, sizeof *out);
    if (!dir) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no folder given");
    enum { J = MM_PFNN_JOINT_COUNT };
    char path[4096];
    float parents[J], xforms[J * 16];
    snprintf(path, sizeof path, "%s/character_parents.bin", dir);
    mm__error_set_file(err, path);
    mm_result r = read_exact(path, J, allocator, parents, err);
    if (r != MM_OK) return r;
    for (int j = 0; j < J; ++j)
        if (parents[j] != floorf(parents[j]) || parents[j] >= (float)j || parents[j] < -1.0f ||
            (j == 0) != (parents[j] < 0.0f))
            return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0, "parent of joint %d is %g", j,
                                (double)parents[j]);
    snprintf(path, sizeof path, "%s/character_xforms.bin", dir);
    mm__error_set_file(err, path);
    r = read_exact(path, J * 16, allocator, xforms, err);
    if (r != MM_OK) return r;

    snprintf(path, sizeof path, "%s/bvh/rest.bvh", dir);
    mm_bvh bvh;
    mm_bvh_read_desc rd;
    memset(&rd, 0, sizeof rd);
    rd.allocator = allocator;
    r = mm_bvh_load(path, &rd, &bvh, err);
    if (r != MM_OK) return r;
    mm__error_set_file(err, path);
    if (bvh.skeleton.joint_count != J) {
        r = mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0, "%d joints, expected %d", bvh.skeleton.joint_count,
                         J);
        mm_bvh_free(&bvh);
        return r;
    }
    for (int j = 0; j < J; ++j) {
        const mm_joint *bj = &bvh.skeleton.joints[j];
        mm_vec3 t = mm_vec3_make(xforms[16 * j + 3], xforms[16 * j + 7], xforms[16 * j + 11]);
        mm_vec3 bo = mm_vec3_scale(bj->offset, (float)CMU_TO_CM);
        if (bj->parent != (int)parents[j] || (j > 0 && mm_vec3_distance(t, bo) > 0.01f)) {
            r = mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0,
                             "joint %d (%s) does not match character_parents.bin / character_xforms.bin", j,
                             bj->name);
            mm_bvh_free(&bvh);
            return r;
        }
    }
    r = mm_skeleton_copy(out, &bvh.skeleton, allocator);
    mm_bvh_free(&bvh);
    if (r != MM_OK) return mm_error_set(err, r, 0, 0, "out of memory");
    for (int j = 0; j < J; ++j) {
        mm_joint *jt = &out->joints[j];
        jt->offset =
            mm_vec3_scale(mm_vec3_make(xforms[16 * j + 3], xforms[16 * j + 7], xforms[16 * j + 11]), 0.01f);
        if (j == 0) jt->offset = mm_vec3_make(0.0f, 0.0f, 0.0f);
        jt->end_site = mm_vec3_scale(jt->end_site, (float)(CMU_TO_CM * 0.01));
        jt->order = MM_EULER_ZYX;
        jt->flags = j == 0 ? MM_JOINT_TRANSLATES : 0u;
    }
    if (err) memset(err, 0, sizeof *err);
    return MM_OK;
}
