/* BVH writer: hierarchy in depth-first order (the order any reader will give back), one line
 * per frame, numbers in the C locale with a chosen number of significant digits. */
#include <mm/bvh.h>

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "io/file.h"
#include "io/text.h"

typedef struct text_buffer {
    char *data;
    size_t size, capacity;
    const mm_allocator *allocator;
    int failed;
} text_buffer;

static int reserve(text_buffer *b, size_t extra)
{
    if (b->failed) return 0;
    if (b->size + extra + 1 <= b->capacity) return 1;
    size_t cap = b->capacity ? b->capacity : 4096;
    while (cap < b->size + extra + 1) cap *= 2;
    char *d = (char *)mm_alloc(b->allocator, cap);
    if (!d) {
        b->failed = 1;
        return 0;
    }
    if (b->size) memcpy(d, b->data, b->size);
    mm_free(b->allocator, b->data);
    b->data = d;
    b->capacity = cap;
    return 1;
}

static void append(text_buffer *b, const char *s, size_t n)
{
    if (!reserve(b, n)) return;
    memcpy(b->data + b->size, s, n);
    b->size += n;
    b->data[b->size] = 0;
}

static void append_str(text_buffer *b, const char *s) { append(b, s, strlen(s)); }

static void append_indent(text_buffer *b, int depth)
{
    for (int i = 0; i < depth; ++i) append(b, "\t", 1);
}

static void append_number(text_buffer *b, double v, int precision)
{
    char buf[64];
    int n = mm__format_number(buf, sizeof buf, v, precision);
    append(b, buf, (size_t)n);
}

static mm_euler_order joint_order(const mm_bvh_write_desc *desc, const mm_joint *j)
{
    if (desc && desc->order != MM_EULER_NONE) return desc->order;
    return j->order != MM_EULER_NONE ? j->order : MM_EULER_ZYX;
}

static int joint_translates(const mm_skeleton *s, int j)
{
    return s->joints[j].parent < 0 || (s->joints[j].flags & MM_JOINT_TRANSLATES);
}

static void append_vec3_line(text_buffer *b, int depth, const char *keyword, mm_vec3 v, int precision)
{
    append_indent(b, depth);
    append_str(b, keyword);
    double c[3] = {v.x, v.y, v.z};
    for (int i = 0; i < 3; ++i) {
        append(b, " ", 1);
        append_number(b, c[i], precision);
    }
    append(b, "\n", 1);
}

mm_result mm_bvh_write(const mm_clip *clip, const mm_bvh_write_desc *desc, char **out_text, size_t *out_size,
                       mm_error *err)
{
    if (!out_text || !out_size) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no output given");
    *out_text = NULL;
    *out_size = 0;
    if (!clip) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no clip given");
    const mm_skeleton *s = &clip->skeleton;
    mm_result r = mm_skeleton_validate(s, err);
    if (r != MM_OK) return r;
    if (!(clip->fps > 0.0f) || !isfinite(clip->fps))
        return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0, "clip fps %g must be finite and positive",
                            clip->fps);
    if (desc && (desc->order < MM_EULER_NONE || desc->order > MM_EULER_ZYX))
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "unknown rotation order %d",
                            (int)desc->order);
    int precision = desc && desc->precision > 0 ? desc->precision : 9;
    if (precision > 17) precision = 17;
    int n = s->joint_count;

    /* Depth-first order, children in index order; the joint list is topological, so each
     * joint's children come after it. */
    int order[MM_MAX_JOINTS], depth_of[MM_MAX_JOINTS], stack[MM_MAX_JOINTS];
    int count = 0, top = 0;
    stack[top++] = 0;
    while (top > 0) {
        int j = stack[--top];
        order[count++] = j;
        depth_of[j] = s->joints[j].parent < 0 ? 0 : depth_of[s->joints[j].parent] + 1;
        for (int c = n - 1; c > j; --c) /* push in reverse so the lowest index pops first */
            if (s->joints[c].parent == j) stack[top++] = c;
    }
    if (count != n)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "skeleton has more than one root");

    text_buffer b;
    memset(&b, 0, sizeof b);
    b.allocator = desc ? desc->allocator : NULL;
    append_str(&b, "HIERARCHY\n");
    for (int i = 0; i < n; ++i) {
        int j = order[i];
        const mm_joint *jt = &s->joints[j];
        int d = depth_of[j];
        append_indent(&b, d);
        append_str(&b, jt->parent < 0 ? "ROOT " : "JOINT ");
        append_str(&b, jt->name);
        append(&b, "\n", 1);
        append_indent(&b, d);
        append_str(&b, "{\n");
        append_vec3_line(&b, d + 1, "OFFSET", jt->offset, precision);
        append_indent(&b, d + 1);
        const char *axes = mm_euler_order_name(joint_order(desc, jt));
        append_str(&b, joint_translates(s, j) ? "CHANNELS 6 Xposition Yposition Zposition" : "CHANNELS 3");
        for (int a = 0; a < 3; ++a) {
            char ch[12] = " Xrotation";
            ch[1] = axes[a];
            append_str(&b, ch);
        }
        append(&b, "\n", 1);
        if (jt->has_end_site) {
            append_indent(&b, d + 1);
            append_str(&b, "End Site\n");
            append_indent(&b, d + 1);
            append_str(&b, "{\n");
            append_vec3_line(&b, d + 2, "OFFSET", jt->end_site, precision);
            append_indent(&b, d + 1);
            append_str(&b, "}\n");
        }
        /* Close this joint and every ancestor whose subtree ends here. */
        int next_depth = i + 1 < n ? depth_of[order[i + 1]] : 0;
        for (int k = d; k >= next_depth; --k) {
            append_indent(&b, k);
            append_str(&b, "}\n");
        }
    }
    char line[128];
    snprintf(line, sizeof line, "MOTION\nFrames: %d\nFrame Time: ", clip->frame_count);
    append_str(&b, line);
    append_number(&b, 1.0 / clip->fps, precision);
    append(&b, "\n", 1);
    for (int f = 0; f < clip->frame_count; ++f) {
        const mm_quat *rot = mm_clip_rotations(clip, f);
        const mm_vec3 *pos = mm_clip_positions(clip, f);
        for (int i = 0; i < n; ++i) {
            int j = order[i];
            if (joint_translates(s, j)) {
                double p[3] = {pos[j].x, pos[j].y, pos[j].z};
                if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2])) {
                    mm_free(b.allocator, b.data);
                    return mm_error_set(err, MM_ERR_BAD_NUMBER, 0, 0,
                                        "frame %d, joint '%s' has a non-finite position", f,
                                        s->joints[j].name);
                }
                for (int a = 0; a < 3; ++a) {
                    append_number(&b, p[a], precision);
                    append(&b, " ", 1);
                }
            }
            mm_euler_order o = joint_order(desc, &s->joints[j]);
            mm_vec3 e = mm_quat_to_euler(mm_quat_normalize(rot[j]), o);
            const char *axes = mm_euler_order_name(o);
            for (int a = 0; a < 3; ++a) {
                float angle = axes[a] == 'X' ? e.x : axes[a] == 'Y' ? e.y : e.z;
                if (!isfinite(angle)) {
                    mm_free(b.allocator, b.data);
                    return mm_error_set(err, MM_ERR_BAD_NUMBER, 0, 0,
                                        "frame %d, joint '%s' has a non-finite rotation", f,
                                        s->joints[j].name);
                }
                append_number(&b, angle * MM_RAD_TO_DEG, precision);
                append(&b, i + 1 == n && a == 2 ? "\n" : " ", 1);
            }
        }
    }
    if (b.failed) {
        mm_free(b.allocator, b.data);
        return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory writing BVH");
    }
    *out_text = b.data;
    *out_size = b.size;
    return MM_OK;
}

mm_result mm_bvh_save(const char *path, const mm_clip *clip, const mm_bvh_write_desc *desc, mm_error *err)
{
    if (err) mm__error_set_file(err, path);
    char *text = NULL;
    size_t size = 0;
    mm_result r = mm_bvh_write(clip, desc, &text, &size, err);
    if (r != MM_OK) return r;
    r = mm__write_file_atomic(path, text, size, err);
    mm_free(desc ? desc->allocator : NULL, text);
    return r;
}
