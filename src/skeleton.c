#include <mm/skeleton.h>

#include <string.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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

#if defined(__SSE2__)
/* The forward kinematics' product in four lanes: each lane the same products and sums, in the same
 * order, as mm_xform_mul's scalar code (x - y is x + (-y) exactly, and a product's sign flips
 * exactly), so the same bits for less work. */

static inline __m128 load_vec3(const mm_vec3 *v)
{
    /* x and y as one unaligned 64-bit load (a vec3 is only 4-byte aligned), z alone */
    return _mm_movelh_ps(_mm_castsi128_ps(_mm_loadl_epi64((const __m128i *)(const void *)v)),
                         _mm_load_ss(&v->z));
}

static inline void store_vec3(mm_vec3 *v, __m128 r)
{
    _mm_storel_epi64((__m128i *)(void *)v, _mm_castps_si128(r)); /* x and y, unaligned */
    _mm_store_ss(&v->z, _mm_movehl_ps(r, r));
}

#define LANE(v, i) _mm_shuffle_ps((v), (v), _MM_SHUFFLE(i, i, i, i))

/* mm_quat_mul(a, b), lanes x y z w */
static inline __m128 quat_mul4(__m128 a, __m128 b)
{
    const __m128 s2 = _mm_set_ps(-0.0f, 0.0f, -0.0f, 0.0f), s3 = _mm_set_ps(-0.0f, -0.0f, 0.0f, 0.0f),
                 s4 = _mm_set_ps(-0.0f, 0.0f, 0.0f, -0.0f);
    __m128 t1 = _mm_mul_ps(LANE(a, 3), b);
    __m128 t2 = _mm_xor_ps(_mm_mul_ps(LANE(a, 0), _mm_shuffle_ps(b, b, _MM_SHUFFLE(0, 1, 2, 3))), s2);
    __m128 t3 = _mm_xor_ps(_mm_mul_ps(LANE(a, 1), _mm_shuffle_ps(b, b, _MM_SHUFFLE(1, 0, 3, 2))), s3);
    __m128 t4 = _mm_xor_ps(_mm_mul_ps(LANE(a, 2), _mm_shuffle_ps(b, b, _MM_SHUFFLE(2, 3, 0, 1))), s4);
    return _mm_add_ps(_mm_add_ps(_mm_add_ps(t1, t2), t3), t4);
}

/* mm_vec3_cross(a, b) in lanes x y z (lane w: whatever) */
static inline __m128 cross4(__m128 a, __m128 b)
{
    __m128 a_yzx = _mm_shuffle_ps(a, a, _MM_SHUFFLE(3, 0, 2, 1)),
           a_zxy = _mm_shuffle_ps(a, a, _MM_SHUFFLE(3, 1, 0, 2));
    __m128 b_yzx = _mm_shuffle_ps(b, b, _MM_SHUFFLE(3, 0, 2, 1)),
           b_zxy = _mm_shuffle_ps(b, b, _MM_SHUFFLE(3, 1, 0, 2));
    return _mm_sub_ps(_mm_mul_ps(a_yzx, b_zxy), _mm_mul_ps(a_zxy, b_yzx));
}

/* mm_quat_rotate(q, v) */
static inline __m128 quat_rotate4(__m128 q, __m128 v)
{
    __m128 t = _mm_mul_ps(cross4(q, v), _mm_set1_ps(2.0f));
    return _mm_add_ps(_mm_add_ps(v, _mm_mul_ps(t, LANE(q, 3))), cross4(q, t));
}

void mm_skeleton_global_from(const mm_joint *joints, int joint_count, int first,
                             const mm_quat *local_rotations, const mm_vec3 *local_positions, mm_xform *global)
{
    if (!joints || !local_rotations || !local_positions || !global) return;
    for (int j = first < 1 ? 1 : first; j < joint_count; ++j) {
        const mm_xform *parent = &global[joints[j].parent];
        __m128 parent_rotation = _mm_loadu_ps(&parent->rotation.x);
        __m128 parent_translation = load_vec3(&parent->translation);
        __m128 rotation = quat_mul4(parent_rotation, _mm_loadu_ps(&local_rotations[j].x));
        __m128 translation =
            _mm_add_ps(quat_rotate4(parent_rotation, load_vec3(&local_positions[j])), parent_translation);
        _mm_storeu_ps(&global[j].rotation.x, rotation);
        store_vec3(&global[j].translation, translation);
    }
}
#else
void mm_skeleton_global_from(const mm_joint *joints, int joint_count, int first,
                             const mm_quat *local_rotations, const mm_vec3 *local_positions, mm_xform *global)
{
    if (!joints || !local_rotations || !local_positions || !global) return;
    for (int j = first < 1 ? 1 : first; j < joint_count; ++j)
        global[j] =
            mm_xform_mul(global[joints[j].parent], mm_xform_make(local_rotations[j], local_positions[j]));
}
#endif
