/* The compressed local transforms: decoding a frame and validating the sections on load.
 *
 * A segment's frames follow each other in its bit stream, frame_bits bits apart; within a frame the
 * rotation tracks come first (joint order), then the translation tracks (translating joint order),
 * each as its components in order (x y z, or the three kept quaternion components), each `bits`
 * bits, least significant bit first (bit i of the stream is bit i % 8 of byte i / 8). */
#include "db/pose_codec.h"

#include <math.h>
#include <string.h>

/* `bits` (<= 32) bits of the stream from bit `at`. */
static inline uint32_t read_bits(const uint8_t *stream, uint64_t at, unsigned bits)
{
    const uint8_t *b = stream + (at >> 3);
    uint64_t w = (uint64_t)b[0] | (uint64_t)b[1] << 8 | (uint64_t)b[2] << 16 | (uint64_t)b[3] << 24 |
                 (uint64_t)b[4] << 32;
    w >>= (at & 7u);
    return bits >= 32 ? (uint32_t)w : (uint32_t)(w & ((1u << bits) - 1u));
}

static inline float float_of_bits(uint32_t u)
{
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

static mm_quat decode_rotation(const mm_db_rotation_track *t, const uint8_t *stream, uint64_t *at)
{
    if (t->bits == MM_POSE_RAW_BITS) {
        float c[4];
        for (int k = 0; k < 4; ++k, *at += 32) c[k] = float_of_bits(read_bits(stream, *at, 32));
        return mm_quat_make(c[0], c[1], c[2], c[3]);
    }
    float kept[3], scale = t->bits ? 1.0f / (float)((1u << t->bits) - 1u) : 0.0f, sum = 0.0f;
    for (int k = 0; k < 3; ++k) {
        float q = t->bits ? (float)read_bits(stream, *at, t->bits) * scale : 0.0f;
        *at += t->bits;
        kept[k] = mm__pose_unit_from_u16(t->lo[k]) + mm__pose_extent_from_u16(t->extent[k]) * q;
        sum += kept[k] * kept[k];
    }
    float dropped = sum < 1.0f ? sqrtf(1.0f - sum) : 0.0f, c[4];
    int d = t->dropped & 3;
    if (t->dropped & 4) dropped = -dropped;
    for (int k = 0, i = 0; k < 4; ++k) c[k] = k == d ? dropped : kept[i++];
    float n = sqrtf(c[0] * c[0] + c[1] * c[1] + c[2] * c[2] + c[3] * c[3]), inv = 1.0f / n;
    return mm_quat_make(c[0] * inv, c[1] * inv, c[2] * inv, c[3] * inv);
}

static mm_vec3 decode_translation(const mm_db_translation_track *t, const uint8_t *stream, uint64_t *at)
{
    float c[3];
    if (t->bits == MM_POSE_RAW_BITS) {
        for (int k = 0; k < 3; ++k, *at += 32) c[k] = float_of_bits(read_bits(stream, *at, 32));
    } else {
        float scale = t->bits ? 1.0f / (float)((1u << t->bits) - 1u) : 0.0f;
        for (int k = 0; k < 3; ++k) {
            float q = t->bits ? (float)read_bits(stream, *at, t->bits) * scale : 0.0f;
            *at += t->bits;
            c[k] = t->lo[k] + t->extent[k] * q;
        }
    }
    return mm_vec3_make(c[0], c[1], c[2]);
}

void mm__pose_decode(const mm__pose_segment_view *v, int frame, mm_quat *rot, mm_vec3 *pos)
{
    uint64_t at = (uint64_t)frame * v->frame_bits;
    for (int j = 0; j < v->joint_count; ++j) rot[j] = decode_rotation(&v->rotations[j], v->bits, &at);
    memcpy(pos, v->constant_positions, sizeof(mm_vec3) * (size_t)v->joint_count);
    for (int t = 0; t < v->translating_count; ++t)
        pos[v->translating_joints[t]] = decode_translation(&v->translations[t], v->bits, &at);
}

void mm__pose_segment_of(const mm_database *db, int s, mm__pose_segment_view *out)
{
    const mm_db_compressed_poses *c = &db->compressed;
    out->joint_count = db->joint_count;
    out->translating_count = c->translating_count;
    out->translating_joints = c->translating_joints;
    out->constant_positions = c->constant_positions;
    out->rotations = c->rotation_tracks + (size_t)s * (size_t)db->joint_count;
    out->translations = c->translation_tracks + (size_t)s * (size_t)c->translating_count;
    out->bits = c->bits + c->segments[s].data_offset;
    out->frame_bits = c->segments[s].frame_bits;
}

/* The segment holding frame (segments are in frame order and tile the frames). */
static int segment_of_frame(const mm_db_compressed_poses *c, int frame)
{
    int lo = 0, hi = c->segment_count - 1;
    while (lo < hi) {
        int mid = lo + (hi - lo + 1) / 2;
        if (c->segments[mid].first_frame <= frame)
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

void mm_database_local_pose(const mm_database *db, int frame, mm_quat *rotations, mm_vec3 *positions)
{
    size_t n = (size_t)db->joint_count;
    if (db->pose_codec != MM_POSE_SEGMENTS) {
        memcpy(rotations, db->rotations + (size_t)frame * n, n * sizeof(mm_quat));
        memcpy(positions, db->positions + (size_t)frame * n, n * sizeof(mm_vec3));
        return;
    }
    int s = segment_of_frame(&db->compressed, frame);
    mm__pose_segment_view v;
    mm__pose_segment_of(db, s, &v);
    mm__pose_decode(&v, frame - db->compressed.segments[s].first_frame, rotations, positions);
}

void mm_database_local_joint(const mm_database *db, int frame, int joint, mm_quat *rotation,
                             mm_vec3 *position)
{
    size_t n = (size_t)db->joint_count;
    if (db->pose_codec != MM_POSE_SEGMENTS) {
        *rotation = db->rotations[(size_t)frame * n + (size_t)joint];
        *position = db->positions[(size_t)frame * n + (size_t)joint];
        return;
    }
    int s = segment_of_frame(&db->compressed, frame);
    mm__pose_segment_view v;
    mm__pose_segment_of(db, s, &v);
    uint64_t start = (uint64_t)(frame - db->compressed.segments[s].first_frame) * v.frame_bits, at = start;
    for (int j = 0; j < joint; ++j) at += mm__pose_rotation_frame_bits(v.rotations[j].bits);
    *rotation = decode_rotation(&v.rotations[joint], v.bits, &at);
    *position = v.constant_positions[joint];
    at = start;
    for (int j = 0; j < v.joint_count; ++j) at += mm__pose_rotation_frame_bits(v.rotations[j].bits);
    for (int t = 0; t < v.translating_count && v.translating_joints[t] <= joint; ++t) {
        if (v.translating_joints[t] == joint) {
            *position = decode_translation(&v.translations[t], v.bits, &at);
            break;
        }
        at += mm__pose_translation_frame_bits(v.translations[t].bits);
    }
}

size_t mm_database_pose_bytes(const mm_database *db)
{
    size_t f = (size_t)db->frame_count, j = (size_t)db->joint_count;
    if (db->pose_codec != MM_POSE_SEGMENTS) return f * j * (sizeof(mm_quat) + sizeof(mm_vec3));
    const mm_db_compressed_poses *c = &db->compressed;
    size_t s = (size_t)c->segment_count, t = (size_t)c->translating_count;
    return j * sizeof(mm_vec3) + t * sizeof(int32_t) + s * sizeof(mm_db_pose_segment) +
           s * j * sizeof(mm_db_rotation_track) + s * t * sizeof(mm_db_translation_track) + c->bits_size;
}

/* ---- validation -------------------------------------------------------------------------- */

#define BAD(...) mm_error_set(err, MM_ERR_SYNTAX, 0, 0, "compressed poses: " __VA_ARGS__)

static mm_result validate_rotation_track(const mm_db_rotation_track *t, int s, int j, mm_error *err)
{
    if (t->bits == MM_POSE_RAW_BITS) {
        if (t->dropped || t->reserved || t->lo[0] || t->lo[1] || t->lo[2] || t->extent[0] || t->extent[1] ||
            t->extent[2])
            return BAD("segment %d, joint %d: a raw rotation track's range and dropped component must be 0",
                       s, j);
        return MM_OK;
    }
    if (t->bits > MM_POSE_ROTATION_BITS_MAX)
        return BAD("segment %d, joint %d: rotation bits %u (0 to %d, or %d for floats)", s, j,
                   (unsigned)t->bits, MM_POSE_ROTATION_BITS_MAX, MM_POSE_RAW_BITS);
    if ((t->dropped & ~7u) || t->reserved)
        return BAD("segment %d, joint %d: dropped component byte 0x%x or reserved bytes not valid", s, j,
                   (unsigned)t->dropped);
    for (int k = 0; k < 3; ++k)
        if ((unsigned)t->lo[k] + t->extent[k] > 65535u || (t->bits == 0 && t->extent[k] != 0))
            return BAD(
                "segment %d, joint %d: rotation component range %u + %u is past 65535 (or not 0 with 0 "
                "bits)",
                s, j, (unsigned)t->lo[k], (unsigned)t->extent[k]);
    return MM_OK;
}

static mm_result validate_translation_track(const mm_db_translation_track *t, int s, int j, mm_error *err)
{
    if (t->reserved[0] || t->reserved[1] || t->reserved[2])
        return BAD("segment %d, joint %d: translation track's reserved bytes not 0", s, j);
    if (t->bits == MM_POSE_RAW_BITS) {
        for (int k = 0; k < 3; ++k)
            if (t->lo[k] != 0.0f || t->extent[k] != 0.0f)
                return BAD("segment %d, joint %d: a raw translation track's range must be 0", s, j);
        return MM_OK;
    }
    if (t->bits > MM_POSE_TRANSLATION_BITS_MAX)
        return BAD("segment %d, joint %d: translation bits %u (0 to %d, or %d for floats)", s, j,
                   (unsigned)t->bits, MM_POSE_TRANSLATION_BITS_MAX, MM_POSE_RAW_BITS);
    for (int k = 0; k < 3; ++k) {
        /* the range's ends within the loader's limit on lengths (floats' own limit, 1e6 m) */
        float lo = t->lo[k], hi = t->lo[k] + t->extent[k];
        if (!(fabsf(lo) <= 1e6f) || !(t->extent[k] >= 0.0f) || !(fabsf(hi) <= 1e6f) ||
            (t->bits == 0 && t->extent[k] != 0.0f))
            return BAD("segment %d, joint %d: translation range [%g, +%g] out of range or not 0 with 0 bits",
                       s, j, (double)lo, (double)t->extent[k]);
    }
    return MM_OK;
}

mm_result mm__pose_codec_validate(const mm_database *db, mm_error *err)
{
    const mm_db_compressed_poses *c = &db->compressed;
    int jc = db->joint_count, tc = c->translating_count, per = c->segment_frames;
    for (int t = 0; t < tc; ++t)
        if (c->translating_joints[t] < (t ? c->translating_joints[t - 1] + 1 : 0) ||
            c->translating_joints[t] >= jc)
            return BAD("translating joint %d: joint %d is not one of the %d joints in increasing order", t,
                       (int)c->translating_joints[t], jc);
    for (int j = 0, t = 0; j < jc; ++j) {
        bool moving = t < tc && c->translating_joints[t] == j;
        const mm_vec3 *p = &c->constant_positions[j];
        t += moving;
        if (!(fabsf(p->x) <= 1e6f && fabsf(p->y) <= 1e6f && fabsf(p->z) <= 1e6f) ||
            (moving && (p->x != 0.0f || p->y != 0.0f || p->z != 0.0f)))
            return BAD("joint %d: constant translation out of range, or not 0 for a translating joint", j);
    }
    /* the segments: every clip cut into segment_frames frames from its first (the last shorter), in
     * order; their frames packed one after the other in the bit stream */
    int s = 0;
    uint64_t offset = 0;
    for (int k = 0; k < db->clip_count; ++k) {
        const mm_db_clip *clip = &db->clips[k];
        for (int first = 0; first < clip->frame_count; first += per, ++s) {
            if (s >= c->segment_count)
                return BAD("the %d segments end before clip %d (%s)", c->segment_count, k, clip->name);
            const mm_db_pose_segment *g = &c->segments[s];
            int want = clip->frame_count - first < per ? clip->frame_count - first : per;
            if (g->first_frame != clip->first_frame + first || g->frame_count != want)
                return BAD("segment %d: frames %d (+%d), not %d (+%d): clip %d (%s) cut every %d frames", s,
                           (int)g->first_frame, (int)g->frame_count, clip->first_frame + first, want, k,
                           clip->name, per);
            uint64_t bits = 0;
            for (int j = 0; j < jc; ++j) {
                const mm_db_rotation_track *rt = &c->rotation_tracks[(size_t)s * (size_t)jc + (size_t)j];
                mm_result r = validate_rotation_track(rt, s, j, err);
                if (r != MM_OK) return r;
                bits += mm__pose_rotation_frame_bits(rt->bits);
            }
            for (int t = 0; t < tc; ++t) {
                const mm_db_translation_track *tt =
                    &c->translation_tracks[(size_t)s * (size_t)tc + (size_t)t];
                mm_result r = validate_translation_track(tt, s, (int)c->translating_joints[t], err);
                if (r != MM_OK) return r;
                bits += mm__pose_translation_frame_bits(tt->bits);
            }
            if (g->frame_bits != bits || g->data_offset != offset)
                return BAD("segment %d: %u bits per frame from byte %u, its tracks say %llu from byte %llu",
                           s, (unsigned)g->frame_bits, (unsigned)g->data_offset, (unsigned long long)bits,
                           (unsigned long long)offset);
            offset += (bits * (uint64_t)want + 7u) / 8u;
        }
    }
    if (s != c->segment_count)
        return BAD("%d segments, the clips cut every %d frames make %d", c->segment_count, per, s);
    if (offset + MM__POSE_BITS_TAIL != c->bits_size)
        return BAD("the bit stream is %zu bytes, the segments use %llu and %d more of zeros", c->bits_size,
                   (unsigned long long)offset, MM__POSE_BITS_TAIL);
    for (size_t b = (size_t)offset; b < c->bits_size; ++b)
        if (c->bits[b] != 0) return BAD("the bit stream's last %d bytes are not 0", MM__POSE_BITS_TAIL);
    /* the floats of raw tracks, checked as loading checks floats (a quantized track decodes within
     * its range, checked above: unit rotations, bounded translations); the padding bits after each
     * segment's last frame are zero, so that one content has one file */
    const mm_quat identity = mm_quat_identity();
    const mm_vec3 origin = mm_vec3_make(0, 0, 0);
    for (s = 0; s < c->segment_count; ++s) {
        mm__pose_segment_view v;
        mm__pose_segment_of(db, s, &v);
        const mm_db_pose_segment *g = &c->segments[s];
        for (int f = 0; f < g->frame_count; ++f) {
            uint64_t at = (uint64_t)f * g->frame_bits;
            for (int j = 0; j < jc; ++j) {
                const mm_db_rotation_track *rt = &v.rotations[j];
                if (rt->bits != MM_POSE_RAW_BITS) {
                    at += mm__pose_rotation_frame_bits(rt->bits);
                    continue;
                }
                mm_quat q = decode_rotation(rt, v.bits, &at);
                if (mm__pose_first_bad_joint(&q, &origin, 1) == 0)
                    return BAD("frame %d, joint %d: rotation not of unit length or not finite",
                               g->first_frame + f, j);
            }
            for (int t = 0; t < tc; ++t) {
                const mm_db_translation_track *tt = &v.translations[t];
                if (tt->bits != MM_POSE_RAW_BITS) {
                    at += mm__pose_translation_frame_bits(tt->bits);
                    continue;
                }
                mm_vec3 p = decode_translation(tt, v.bits, &at);
                if (mm__pose_first_bad_joint(&identity, &p, 1) == 0)
                    return BAD("frame %d, joint %d: translation out of range", g->first_frame + f,
                               (int)c->translating_joints[t]);
            }
        }
        uint64_t used = (uint64_t)g->frame_bits * (uint64_t)g->frame_count, end = (used + 7u) / 8u * 8u;
        for (uint64_t b = used; b < end; ++b)
            if ((v.bits[b >> 3] >> (b & 7u)) & 1u) return BAD("segment %d: padding bits not 0", s);
    }
    return MM_OK;
}
