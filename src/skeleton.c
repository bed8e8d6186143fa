#include <mm/skeleton.h>

#include <string.h>
#include "math_private.h"

mm_result mm_skeleton_init(mm_skeleton *s, int joint_count, const mm_allocator *allocator)
{
    if (!s) return MM_ERR_INVALID_ARGUMENT;
    memset(s, 0, sizeof *s);
    if (joint_count < 1 || joint_count > MM_MAX_JOINTS) return MM_ERR_INVALID_ARGUMENT;
    if (allocator) s->allocator = *allocator;
    s->joints = (mm_joint *)mm_alloc_array(&s->allocator, (size_t)joint_count, sizeof(mm_joint));
    if (!s->joints) return MM_ERR_OUT_OF_MEMORY;
    s->joint_count = joint_count;
    for (int i = 0; i < joint_count; ++i) s->joints[i].parent = i - 1;
    return MM_OK;
}

void mm_skeleton_free(mm_skeleton *s)
{
    if (!s) return;
    mm_free(&s->allocator, s->joints);
    memset(s, 0, sizeof *s);
}

mm_result mm_skeleton_copy(mm_skeleton *dst, const mm_skeleton *src, const mm_allocator *allocator)
{
    if (!dst || !src) return MM_ERR_INVALID_ARGUMENT;
    mm_result r = mm_skeleton_init(dst, src->joint_count, allocator);
    if (r != MM_OK) return r;
    memcpy(dst->joints, src->joints, (size_t)src->joint_count * sizeof(mm_joint));
    return MM_OK;
}

int mm_skeleton_find(const mm_skeleton *s, const char *name)
{
    if (!s || !name) return -1;
    for (int i = 0; i < s->joint_count; ++i)
        if (strcmp(s->joints[i].name, name) == 0) return i;
    return -1;
}

void mm_skeleton_scale(mm_skeleton *s, float factor)
{
    for (int i = 0; i < s->joint_count; ++i) {
        s->joints[i].offset = mm_vec3_scale(s->joints[i].offset, factor);
        s->joints[i].end_site = mm_vec3_scale(s->joints[i].end_site, factor);
    }
}

mm_result mm_skeleton_validate(const mm_skeleton *s, mm_error *err)
{
    if (!s || s->joint_count < 1 || !s->joints)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "skeleton has no joints");
    if (s->joint_count > MM_MAX_JOINTS)
        return mm_error_set(err, MM_ERR_LIMIT, 0, 0, "skeleton has %d joints (at most %d)", s->joint_count,
                            MM_MAX_JOINTS);
    for (int i = 0; i < s->joint_count; ++i) {
        const mm_joint *j = &s->joints[i];
        if (memchr(j->name, 0, MM_NAME_MAX) == NULL || j->name[0] == 0)
            return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "joint %d has no name", i);
        if (i == 0 ? j->parent != -1 : (j->parent < 0 || j->parent >= i))
            return mm_error_set(
                err, MM_ERR_INVALID_ARGUMENT, 0, 0,
                "joint %d '%s' has parent %d (the root must be first, parents before children)", i, j->name,
                j->parent);
        if (!finite3(j->offset) || (j->has_end_site && !finite3(j->end_site)))
            return mm_error_set(err, MM_ERR_BAD_NUMBER, 0, 0, "joint '%s' has a non-finite offset", j->name);
        for (int k = 0; k < i; ++k)
            if (strcmp(s->joints[k].name, j->name) == 0)
                return mm_error_set(err, MM_ERR_DUPLICATE_NAME, 0, 0, "joint name '%s' is used twice",
                                    j->name);
    }
    return MM_OK;
}

void mm_skeleton_global_from(const mm_joint *joints, int joint_count, int first,
                             const mm_quat *local_rotations, const mm_vec3 *local_positions, mm_xform *global)
{
    if (!joints || !local_rotations || !local_positions || !global) return;
    for (int j = first < 1 ? 1 : first; j < joint_count; ++j)
        global[j] =
            mm_xform_mul(global[joints[j].parent], mm_xform_make(local_rotations[j], local_positions[j]));
}
