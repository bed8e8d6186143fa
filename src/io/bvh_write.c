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

/* The joints in depth-first order (children in index order; the joint list is topological) and
 * their depths; 0 when the skeleton has more than one root. */
static int depth_first(const mm_skeleton *s, int *order, int *depth_of)
{
    int stack[MM_MAX_JOINTS], n = s->joint_count, count = 0, top = 0;
    stack[top++] = 0;
    while (top > 0) {
        int j = stack[--top];
        order[count++] = j;
        depth_of[j] = s->joints[j].parent < 0 ? 0 : depth_of[s->joints[j].parent] + 1;
        for (int c = n - 1; c > j; --c) /* push in reverse so the lowest index pops first */
            if (s->joints[c].parent == j) stack[top++] = c;
    }
    return count == n;
}

/* Checks what mm_bvh_write and mm_bvh_stream_open are given; *precision receives the digits. */
static mm_result check_input(const mm_skeleton *s, float fps, const mm_bvh_write_desc *desc, int *precision,
                             mm_error *err)
{
    mm_result r = mm_skeleton_validate(s, err);
    if (r != MM_OK) return r;
    if (!(fps > 0.0f) || !isfinite(fps))
        return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0, "clip fps %g must be finite and positive", fps);
    if (desc && (desc->order < MM_EULER_NONE || desc->order > MM_EULER_ZYX))
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "unknown rotation order %d",
                            (int)desc->order);
    *precision = desc && desc->precision > 0 ? desc->precision : 9;
    if (*precision > 17) *precision = 17;
    return MM_OK;
}

/* HIERARCHY ... MOTION, Frames and Frame Time. */
static void write_header(text_buffer *b, const mm_skeleton *s, const int *order, const int *depth_of,
                         float fps, int frame_count, const mm_bvh_write_desc *desc, int precision)
{
    int n = s->joint_count;
    append_str(b, "HIERARCHY\n");
    for (int i = 0; i < n; ++i) {
        int j = order[i];
        const mm_joint *jt = &s->joints[j];
        int d = depth_of[j];
        append_indent(b, d);
        append_str(b, jt->parent < 0 ? "ROOT " : "JOINT ");
        append_str(b, jt->name);
        append(b, "\n", 1);
        append_indent(b, d);
        append_str(b, "{\n");
        append_vec3_line(b, d + 1, "OFFSET", jt->offset, precision);
        append_indent(b, d + 1);
        const char *axes = mm_euler_order_name(joint_order(desc, jt));
        append_str(b, joint_translates(s, j) ? "CHANNELS 6 Xposition Yposition Zposition" : "CHANNELS 3");
        for (int a = 0; a < 3; ++a) {
            char ch[12] = " Xrotation";
            ch[1] = axes[a];
            append_str(b, ch);
        }
        append(b, "\n", 1);
        if (jt->has_end_site) {
            append_indent(b, d + 1);
            append_str(b, "End Site\n");
            append_indent(b, d + 1);
            append_str(b, "{\n");
            append_vec3_line(b, d + 2, "OFFSET", jt->end_site, precision);
            append_indent(b, d + 1);
            append_str(b, "}\n");
        }
        /* Close this joint and every ancestor whose subtree ends here. */
        int next_depth = i + 1 < n ? depth_of[order[i + 1]] : 0;
        for (int k = d; k >= next_depth; --k) {
            append_indent(b, k);
            append_str(b, "}\n");
        }
    }
    char line[128];
    snprintf(line, sizeof line, "MOTION\nFrames: %d\nFrame Time: ", frame_count);
    append_str(b, line);
    append_number(b, 1.0 / fps, precision);
    append(b, "\n", 1);
}

/* One frame's line; an error names frame f and the joint whose value is not finite. */
static mm_result write_frame(text_buffer *b, const mm_skeleton *s, const int *order, const mm_quat *rot,
                             const mm_vec3 *pos, int f, const mm_bvh_write_desc *desc, int precision,
                             mm_error *err)
{
    int n = s->joint_count;
    for (int i = 0; i < n; ++i) {
        int j = order[i];
        if (joint_translates(s, j)) {
            double p[3] = {pos[j].x, pos[j].y, pos[j].z};
            if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]))
                return mm_error_set(err, MM_ERR_BAD_NUMBER, 0, 0,
                                    "frame %d, joint '%s' has a non-finite position", f, s->joints[j].name);
            for (int a = 0; a < 3; ++a) {
                append_number(b, p[a], precision);
                append(b, " ", 1);
            }
        }
        mm_euler_order o = joint_order(desc, &s->joints[j]);
        mm_vec3 e = mm_quat_to_euler(mm_quat_normalize(rot[j]), o);
        const char *axes = mm_euler_order_name(o);
        for (int a = 0; a < 3; ++a) {
            float angle = axes[a] == 'X' ? e.x : axes[a] == 'Y' ? e.y : e.z;
            if (!isfinite(angle))
                return mm_error_set(err, MM_ERR_BAD_NUMBER, 0, 0,
                                    "frame %d, joint '%s' has a non-finite rotation", f, s->joints[j].name);
            append_number(b, angle * MM_RAD_TO_DEG, precision);
            append(b, i + 1 == n && a == 2 ? "\n" : " ", 1);
        }
    }
    return MM_OK;
}

mm_result mm_bvh_write(const mm_clip *clip, const mm_bvh_write_desc *desc, char **out_text, size_t *out_size,
                       mm_error *err)
{
    if (!out_text || !out_size) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no output given");
    *out_text = NULL;
    *out_size = 0;
    if (!clip) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no clip given");
    const mm_skeleton *s = &clip->skeleton;
    int precision;
    mm_result r = check_input(s, clip->fps, desc, &precision, err);
    if (r != MM_OK) return r;
    int order[MM_MAX_JOINTS], depth_of[MM_MAX_JOINTS];
    if (!depth_first(s, order, depth_of))
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "skeleton has more than one root");
    text_buffer b;
    memset(&b, 0, sizeof b);
    b.allocator = desc ? desc->allocator : NULL;
    write_header(&b, s, order, depth_of, clip->fps, clip->frame_count, desc, precision);
    for (int f = 0; f < clip->frame_count && r == MM_OK; ++f)
        r = write_frame(&b, s, order, mm_clip_rotations(clip, f), mm_clip_positions(clip, f), f, desc,
                        precision, err);
    if (r == MM_OK && b.failed)
        r = mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory writing BVH");
    if (r != MM_OK) {
        mm_free(b.allocator, b.data);
        return r;
    }
    *out_text = b.data;
    *out_size = b.size;
    return MM_OK;
}

/* ---- streaming --------------------------------------------------------------------------- */

/* Text is handed to the file when this much has gathered. */
#define BVH_STREAM_FLUSH (1 << 16)

struct mm_bvh_stream {
    FILE *out;
    const mm_skeleton *skeleton;
    mm_bvh_write_desc desc;
    int precision, frame_count, frames_written;
    int order[MM_MAX_JOINTS];
    text_buffer text;
};

static mm_result flush(mm_bvh_stream *st, mm_error *err)
{
    if (st->text.failed) return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory writing BVH");
    if (st->text.size && fwrite(st->text.data, 1, st->text.size, st->out) != st->text.size)
        return mm_error_set(err, MM_ERR_IO, 0, 0, "cannot write");
    st->text.size = 0;
    return MM_OK;
}

mm_result mm_bvh_stream_open(mm_bvh_stream **out, FILE *file, const mm_skeleton *skeleton, float fps,
                             int frame_count, const mm_bvh_write_desc *desc, mm_error *err)
{
    if (!out) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no output given");
    *out = NULL;
    if (!file || !skeleton || frame_count < 0)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0,
                            "a file, a skeleton and a frame count are needed");
    int precision;
    mm_result r = check_input(skeleton, fps, desc, &precision, err);
    if (r != MM_OK) return r;
    const mm_allocator *allocator = desc ? desc->allocator : NULL;
    mm_bvh_stream *st = (mm_bvh_stream *)mm_alloc(allocator, sizeof *st);
    if (!st) return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    memset(st, 0, sizeof *st);
    st->out = file;
    st->skeleton = skeleton;
    if (desc) st->desc = *desc;
    st->precision = precision;
    st->frame_count = frame_count;
    st->text.allocator = allocator;
    int depth_of[MM_MAX_JOINTS];
    if (!depth_first(skeleton, st->order, depth_of)) {
        mm_free(allocator, st);
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "skeleton has more than one root");
    }
    write_header(&st->text, skeleton, st->order, depth_of, fps, frame_count, desc, precision);
    if ((r = flush(st, err)) != MM_OK) {
        mm_bvh_stream_close(st, NULL);
        return r;
    }
    *out = st;
    return MM_OK;
}

mm_result mm_bvh_stream_frame(mm_bvh_stream *st, const mm_quat *rotations, const mm_vec3 *positions,
                              mm_error *err)
{
    if (!st || !rotations || !positions)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no frame given");
    if (st->frames_written >= st->frame_count)
        return mm_error_set(err, MM_ERR_LIMIT, 0, 0, "more than the %d frames declared", st->frame_count);
    mm_result r = write_frame(&st->text, st->skeleton, st->order, rotations, positions, st->frames_written,
                              &st->desc, st->precision, err);
    if (r != MM_OK) return r;
    ++st->frames_written;
    return st->text.size >= BVH_STREAM_FLUSH ? flush(st, err) : MM_OK;
}

mm_result mm_bvh_stream_close(mm_bvh_stream *st, mm_error *err)
{
    if (!st) return MM_OK;
    mm_result r = flush(st, err);
    if (r == MM_OK && st->frames_written != st->frame_count)
        r = mm_error_set(err, MM_ERR_UNEXPECTED_EOF, 0, 0, "%d of the %d frames declared were written",
                         st->frames_written, st->frame_count);
    const mm_allocator *allocator = st->text.allocator;
    mm_free(allocator, st->text.data);
    mm_free(allocator, st);
    return r;
}

size_t mm_bvh_frame_bytes_max(const mm_skeleton *skeleton, const mm_bvh_write_desc *desc)
{
    if (!skeleton) return 0;
    size_t channels = 0;
    for (int j = 0; j < skeleton->joint_count; ++j) channels += joint_translates(skeleton, j) ? 6 : 3;
    int digits = desc && desc->precision > 0 ? (desc->precision > 17 ? 17 : desc->precision) : 9;
    /* a number at its longest: sign, the digits, point, "e-308", and the separator after it */
    return channels * (size_t)(digits + 8);
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
