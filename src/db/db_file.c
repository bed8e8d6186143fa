/* The .mmdb file: packing, validation on load, saving and per-frame PoseData.
 *
 * Layout (little-endian, docs/format.md): a fixed header with the counts and, for each section,
 * its offset and size; then the sections, each starting at a multiple of MM_DB_ALIGN. The
 * checksum covers every byte after the checksum field. Loading checks the header, every offset
 * and size against the counts, and the cross references (parents, clip ranges, next frames,
 * feature groups), then points into the buffer: no pointer is ever stored in the file. */
#define _POSIX_C_SOURCE 200809L
#include "db/db_file.h"
#include "db/pose_codec.h"

#include <errno.h>
#include <fcntl.h>
#include <float.h>
#include <math.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <mm/gait.h>
#include <mm/trajectory.h>

#include "io/checksum.h"
#include "io/file.h"
#include "io/sections.h"

static const char mm__db_magic[8] = {'M', 'M', 'D', 'B', 0, '\r', '\n', 0x1a};
#define MM__DB_BYTE_ORDER 0x01020304u
/* How far from 1 a stored rotation's squared length may be: the build writes unit quaternions in
 * float, a crafted file may not scale the skeleton through them. */
#define MM__DB_UNIT_TOLERANCE 1e-3f
/* The largest magnitude of a stored length, speed or normalisation value (m, m/s, rad/s): far
 * beyond any capture, and small enough that every product the runtime forms of them stays finite. */
#define MM__DB_VALUE_MAX 1e6f
/* The smallest normalisation scale the build writes (a group that varies less gets 1), and the
 * largest normalised feature that implies for values within MM__DB_VALUE_MAX. */
#define MM__DB_SCALE_MIN   1e-5f
#define MM__DB_FEATURE_MAX 1e12f

typedef struct mm__db_header {
    char magic[8];
    uint32_t byte_order; /* 0x01020304 as written by the machine */
    uint32_t version;
    uint64_t checksum; /* of bytes [24, file_size) */
    uint64_t file_size;
    uint32_t header_size;
    int32_t frame_count, joint_count, clip_count, tag_count, group_count, dims, dims_padded;
    int32_t small_block, large_block, small_block_count, large_block_count;
    float interval;
    uint32_t pose_codec; /* mm_pose_codec */
    int32_t pose_segment_frames, pose_segment_count, pose_translating_count;
    float pose_error_bound, pose_max_error; /* m */
    uint32_t section_count;
    mm__section sections[MM__SEC_COUNT];
} mm__db_header;

/* The file stores these structs as they are: their layout is part of the format. */
_Static_assert(sizeof(mm_joint) == 104, "mm_joint layout changed: bump MM_DB_VERSION");
_Static_assert(offsetof(mm_joint, end_site) == 92, "mm_joint layout changed: bump MM_DB_VERSION");
_Static_assert(sizeof(mm_db_clip) == 104, "mm_db_clip layout changed: bump MM_DB_VERSION");
_Static_assert(sizeof(mm_feature_group) == 92, "mm_feature_group layout changed: bump MM_DB_VERSION");
_Static_assert(sizeof(mm_db_distance_clip) == 16, "mm_db_distance_clip layout changed: bump MM_DB_VERSION");
_Static_assert(sizeof(mm_distance_segment) == 20, "mm_distance_segment layout changed: bump MM_DB_VERSION");
_Static_assert(sizeof(mm_runtime_gait) == 24, "mm_runtime_gait layout changed: bump MM_DB_VERSION");
_Static_assert(sizeof(mm_database_settings) == 564,
               "mm_database_settings layout changed: bump MM_DB_VERSION");
_Static_assert(offsetof(mm_database_settings, walk) == 196 && offsetof(mm_database_settings, roles) == 268 &&
                   offsetof(mm_database_settings, envelope) == 308,
               "mm_database_settings layout changed: bump MM_DB_VERSION");
_Static_assert(MM_SETTINGS_ENVELOPE_BINS == MM_SPEED_ENVELOPE_BINS &&
                   MM_SETTINGS_ENVELOPE_GAITS == MM_GAIT_COUNT,
               "the settings' envelopes are the trajectory's");
_Static_assert(sizeof(mm_db_pose_segment) == 16 && sizeof(mm_db_rotation_track) == 16 &&
                   sizeof(mm_db_translation_track) == 28,
               "compressed pose layout changed: bump MM_DB_VERSION");
_Static_assert(sizeof(mm_quat) == 16 && sizeof(mm_vec3) == 12, "vector layout");
_Static_assert(offsetof(mm__db_header, checksum) == 16 && offsetof(mm__db_header, sections) == 112,
               "header layout");

static int block_count(int frames, int block) { return (frames + block - 1) / block; }

void mm__db_section_sizes(const mm__db_parts *p, size_t size[MM__SEC_COUNT])
{
    size_t f = (size_t)p->frame_count, j = (size_t)p->joint_count, d = (size_t)p->dims_padded;
    size_t sb = (size_t)block_count(p->frame_count, MM_DB_SMALL_BLOCK);
    size_t lb = (size_t)block_count(p->frame_count, MM_DB_LARGE_BLOCK);
    size[MM__SEC_JOINTS] = j * sizeof(mm_joint);
    size[MM__SEC_CLIPS] = (size_t)p->clip_count * sizeof(mm_db_clip);
    size[MM__SEC_TAG_NAMES] = (size_t)p->tag_count * MM_TAG_NAME_MAX;
    size[MM__SEC_GROUPS] = (size_t)p->group_count * sizeof(mm_feature_group);
    size[MM__SEC_FRAME_CLIP] = f * 4;
    size[MM__SEC_FRAME_NEXT] = f * 4;
    size[MM__SEC_FRAME_TAGS] = f * 8;
    size[MM__SEC_CONTACTS] = f;
    size[MM__SEC_ROOT_VELOCITY] = f * sizeof(mm_vec3);
    size[MM__SEC_ROOT_ANGULAR_VELOCITY] = f * 4;
    bool floats = p->pose_codec == MM_POSE_FLOATS;
    size_t segments = (size_t)p->pose_segment_count, moving = (size_t)p->pose_translating_count;
    size[MM__SEC_ROTATIONS] = floats ? f * j * sizeof(mm_quat) : 0;
    size[MM__SEC_POSITIONS] = floats ? f * j * sizeof(mm_vec3) : 0;
    size[MM__SEC_FEATURES] = f * d * 4;
    size[MM__SEC_FEATURE_MEAN] = d * 4;
    size[MM__SEC_FEATURE_SCALE] = d * 4;
    size[MM__SEC_SMALL_MIN] = size[MM__SEC_SMALL_MAX] = sb * d * 4;
    size[MM__SEC_LARGE_MIN] = size[MM__SEC_LARGE_MAX] = lb * d * 4;
    size[MM__SEC_CONFIG_JSON] = p->size[MM__SEC_CONFIG_JSON]; /* free size, zero-terminated */
    size[MM__SEC_DISTANCE_CLIPS] = (size_t)p->clip_count * sizeof(mm_db_distance_clip);
    size[MM__SEC_DISTANCE_TRAVELLED] = f * 4;
    size[MM__SEC_DISTANCE_SIGNED] = f * 4;
    /* free size: a whole number of segments, checked against the clips on load */
    size[MM__SEC_DISTANCE_SEGMENTS] = p->size[MM__SEC_DISTANCE_SEGMENTS];
    size[MM__SEC_SETTINGS] = sizeof(mm_database_settings);
    size[MM__SEC_POSE_CONSTANTS] = floats ? 0 : j * sizeof(mm_vec3);
    size[MM__SEC_POSE_TRANSLATING] = moving * sizeof(int32_t);
    size[MM__SEC_POSE_SEGMENTS] = segments * sizeof(mm_db_pose_segment);
    size[MM__SEC_POSE_ROTATION_TRACKS] = segments * j * sizeof(mm_db_rotation_track);
    size[MM__SEC_POSE_TRANSLATION_TRACKS] = segments * moving * sizeof(mm_db_translation_track);
    /* free size: the segments' frames, checked against the segment table on load */
    size[MM__SEC_POSE_BITS] = floats ? 0 : p->size[MM__SEC_POSE_BITS];
}

static void point_into(mm_database *db, const unsigned char *base, const mm__db_header *h)
{
#define AT(sec) ((const void *)(base + h->sections[sec].offset))
    db->frame_count = h->frame_count;
    db->joint_count = h->joint_count;
    db->clip_count = h->clip_count;
    db->tag_count = h->tag_count;
    db->group_count = h->group_count;
    db->dims = h->dims;
    db->dims_padded = h->dims_padded;
    db->interval = h->interval;
    db->small_block_count = h->small_block_count;
    db->large_block_count = h->large_block_count;
    db->joints = (const mm_joint *)AT(MM__SEC_JOINTS);
    db->clips = (const mm_db_clip *)AT(MM__SEC_CLIPS);
    db->tag_names = (const char(*)[MM_TAG_NAME_MAX])AT(MM__SEC_TAG_NAMES);
    db->groups = (const mm_feature_group *)AT(MM__SEC_GROUPS);
    db->frame_clip = (const int32_t *)AT(MM__SEC_FRAME_CLIP);
    db->frame_next = (const int32_t *)AT(MM__SEC_FRAME_NEXT);
    db->frame_tags = (const uint64_t *)AT(MM__SEC_FRAME_TAGS);
    db->contacts = (const uint8_t *)AT(MM__SEC_CONTACTS);
    db->root_velocity = (const mm_vec3 *)AT(MM__SEC_ROOT_VELOCITY);
    db->root_angular_velocity = (const float *)AT(MM__SEC_ROOT_ANGULAR_VELOCITY);
    db->pose_codec = (int)h->pose_codec;
    if (h->pose_codec == MM_POSE_FLOATS) {
        db->rotations = (const mm_quat *)AT(MM__SEC_ROTATIONS);
        db->positions = (const mm_vec3 *)AT(MM__SEC_POSITIONS);
    } else {
        mm_db_compressed_poses *c = &db->compressed;
        c->segment_frames = h->pose_segment_frames;
        c->segment_count = h->pose_segment_count;
        c->translating_count = h->pose_translating_count;
        c->error_bound = h->pose_error_bound;
        c->max_error = h->pose_max_error;
        c->constant_positions = (const mm_vec3 *)AT(MM__SEC_POSE_CONSTANTS);
        c->translating_joints = (const int32_t *)AT(MM__SEC_POSE_TRANSLATING);
        c->segments = (const mm_db_pose_segment *)AT(MM__SEC_POSE_SEGMENTS);
        c->rotation_tracks = (const mm_db_rotation_track *)AT(MM__SEC_POSE_ROTATION_TRACKS);
        c->translation_tracks = (const mm_db_translation_track *)AT(MM__SEC_POSE_TRANSLATION_TRACKS);
        c->bits = (const uint8_t *)AT(MM__SEC_POSE_BITS);
        c->bits_size = (size_t)h->sections[MM__SEC_POSE_BITS].size;
    }
    db->features = (const float *)AT(MM__SEC_FEATURES);
    db->feature_mean = (const float *)AT(MM__SEC_FEATURE_MEAN);
    db->feature_scale = (const float *)AT(MM__SEC_FEATURE_SCALE);
    db->small_min = (const float *)AT(MM__SEC_SMALL_MIN);
    db->small_max = (const float *)AT(MM__SEC_SMALL_MAX);
    db->large_min = (const float *)AT(MM__SEC_LARGE_MIN);
    db->large_max = (const float *)AT(MM__SEC_LARGE_MAX);
    db->config_json = (const char *)AT(MM__SEC_CONFIG_JSON);
    db->distance_clips = (const mm_db_distance_clip *)AT(MM__SEC_DISTANCE_CLIPS);
    db->distance_travelled = (const float *)AT(MM__SEC_DISTANCE_TRAVELLED);
    db->distance_signed = (const float *)AT(MM__SEC_DISTANCE_SIGNED);
    db->distance_segments = (const mm_distance_segment *)AT(MM__SEC_DISTANCE_SEGMENTS);
    db->distance_segment_count =
        (int)(h->sections[MM__SEC_DISTANCE_SEGMENTS].size / sizeof(mm_distance_segment));
    db->settings = (const mm_database_settings *)AT(MM__SEC_SETTINGS);
#undef AT
}

mm_result mm__db_pack(const mm__db_parts *parts, const mm_allocator *allocator, mm_database *out,
                      mm_error *err)
{
    size_t size[MM__SEC_COUNT];
    mm__db_section_sizes(parts, size);
    mm__db_header h;
    memset(&h, 0, sizeof h);
    memcpy(h.magic, mm__db_magic, 8);
    h.byte_order = MM__DB_BYTE_ORDER;
    h.version = MM_DB_VERSION;
    h.header_size = (uint32_t)sizeof h;
    h.frame_count = parts->frame_count;
    h.joint_count = parts->joint_count;
    h.clip_count = parts->clip_count;
    h.tag_count = parts->tag_count;
    h.group_count = parts->group_count;
    h.dims = parts->dims;
    h.dims_padded = parts->dims_padded;
    h.small_block = MM_DB_SMALL_BLOCK;
    h.large_block = MM_DB_LARGE_BLOCK;
    h.small_block_count = block_count(parts->frame_count, MM_DB_SMALL_BLOCK);
    h.large_block_count = block_count(parts->frame_count, MM_DB_LARGE_BLOCK);
    h.interval = parts->interval;
    h.pose_codec = (uint32_t)parts->pose_codec;
    h.pose_segment_frames = parts->pose_segment_frames;
    h.pose_segment_count = parts->pose_segment_count;
    h.pose_translating_count = parts->pose_translating_count;
    h.pose_error_bound = parts->pose_error_bound;
    h.pose_max_error = parts->pose_max_error;
    h.section_count = MM__SEC_COUNT;
    size_t at = mm__sections_layout(sizeof h, MM_DB_ALIGN, size, MM__SEC_COUNT, h.sections);
    h.file_size = at;
    unsigned char *raw;
    unsigned char *base =
        mm__sections_pack(allocator, at, MM_DB_ALIGN, h.sections, parts->data, MM__SEC_COUNT, &raw);
    if (!base) return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory (%zu bytes)", at);
    h.checksum = mm__sections_seal(base, at, &h, sizeof h);
    memset(out, 0, sizeof *out);
    if (allocator) out->allocator = *allocator;
    out->owned = raw;
    out->data = base;
    out->size = at;
    point_into(out, base, &h);
    return MM_OK;
}

void mm__db_parts_of(const mm_database *db, mm__db_parts *p)
{
    mm__db_header h;
    memcpy(&h, db->data, sizeof h);
    memset(p, 0, sizeof *p);
    p->frame_count = h.frame_count;
    p->joint_count = h.joint_count;
    p->clip_count = h.clip_count;
    p->tag_count = h.tag_count;
    p->group_count = h.group_count;
    p->dims = h.dims;
    p->dims_padded = h.dims_padded;
    p->interval = h.interval;
    p->pose_codec = (int)h.pose_codec;
    p->pose_segment_frames = h.pose_segment_frames;
    p->pose_segment_count = h.pose_segment_count;
    p->pose_translating_count = h.pose_translating_count;
    p->pose_error_bound = h.pose_error_bound;
    p->pose_max_error = h.pose_max_error;
    for (int s = 0; s < MM__SEC_COUNT; ++s) {
        p->data[s] = (const unsigned char *)db->data + h.sections[s].offset;
        p->size[s] = (size_t)h.sections[s].size;
    }
}

#define BAD(...) mm_error_set(err, MM_ERR_SYNTAX, 0, 0, __VA_ARGS__)

static mm_result validate(const unsigned char *base, size_t size, bool verify_checksum, mm__db_header *h,
                          mm_error *err)
{
    if (size < 24 || memcmp(base, mm__db_magic, 8) != 0) return BAD("not an mm database (bad magic)");
    if (size < sizeof *h)
        return mm_error_set(err, MM_ERR_UNEXPECTED_EOF, 0, 0, "truncated header (%zu bytes)", size);
    memcpy(h, base, sizeof *h);
    if (h->byte_order != MM__DB_BYTE_ORDER) return BAD("written on a machine of the other byte order");
    if (h->version != MM_DB_VERSION)
        return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0,
                            "format version %u, this mm reads version %d: rebuild it", h->version,
                            MM_DB_VERSION);
    if (h->header_size != sizeof *h || h->section_count != MM__SEC_COUNT)
        return BAD("unexpected header size");
    if (h->file_size != size)
        return mm_error_set(err, h->file_size > size ? MM_ERR_UNEXPECTED_EOF : MM_ERR_SYNTAX, 0, 0,
                            "the header says %llu bytes, the file has %zu (truncated or padded)",
                            (unsigned long long)h->file_size, size);
    if (verify_checksum && mm__checksum64(base + 24, size - 24) != h->checksum)
        return BAD("checksum mismatch: the file is corrupted");
    if (h->frame_count < 1 || h->frame_count > MM_MAX_FRAMES || h->joint_count < 1 ||
        h->joint_count > MM_MAX_JOINTS || h->clip_count < 1 || h->clip_count > h->frame_count ||
        h->tag_count < 0 || h->tag_count > MM_MAX_TAGS || h->group_count < 0 ||
        h->group_count > 4 * MM_MAX_TRAJ_SAMPLES + 64 || h->dims < 0 || h->dims_padded < h->dims ||
        h->dims_padded % MM_DB_SIMD_WIDTH != 0 || h->dims_padded > 4096 ||
        !(h->interval > 0.0f && h->interval <= 1.0f) || h->small_block != MM_DB_SMALL_BLOCK ||
        h->large_block != MM_DB_LARGE_BLOCK ||
        h->small_block_count != block_count(h->frame_count, MM_DB_SMALL_BLOCK) ||
        h->large_block_count != block_count(h->frame_count, MM_DB_LARGE_BLOCK))
        return BAD("header counts are out of range");
    if (h->pose_codec == MM_POSE_FLOATS) {
        if (h->pose_segment_frames != 0 || h->pose_segment_count != 0 || h->pose_translating_count != 0 ||
            h->pose_error_bound != 0.0f || h->pose_max_error != 0.0f)
            return BAD("header: the pose fields of a database stored as floats must be 0");
    } else if (h->pose_codec == MM_POSE_SEGMENTS) {
        if (h->pose_segment_frames < 1 || h->pose_segment_frames > MM_POSE_SEGMENT_FRAMES_MAX ||
            h->pose_segment_count < h->clip_count || h->pose_segment_count > h->frame_count ||
            h->pose_translating_count < 0 || h->pose_translating_count > h->joint_count)
            return BAD("compressed poses: header counts are out of range (segment frames %d, segments %d, "
                       "translating joints %d)",
                       h->pose_segment_frames, h->pose_segment_count, h->pose_translating_count);
        if (!(h->pose_error_bound > 0.0f && h->pose_error_bound <= MM__POSE_ERROR_BOUND_MAX) ||
            !(h->pose_max_error >= 0.0f && h->pose_max_error <= h->pose_error_bound))
            return BAD("compressed poses: error bound %g m or measured error %g m out of range (0 < error "
                       "<= bound <= %g m)",
                       (double)h->pose_error_bound, (double)h->pose_max_error,
                       (double)MM__POSE_ERROR_BOUND_MAX);
    } else {
        return BAD("header: pose codec %u is unknown (0 floats, 1 segments)", (unsigned)h->pose_codec);
    }
    mm__db_parts p;
    memset(&p, 0, sizeof p);
    p.frame_count = h->frame_count;
    p.joint_count = h->joint_count;
    p.clip_count = h->clip_count;
    p.tag_count = h->tag_count;
    p.group_count = h->group_count;
    p.dims_padded = h->dims_padded;
    p.pose_codec = (int)h->pose_codec;
    p.pose_segment_count = h->pose_segment_count;
    p.pose_translating_count = h->pose_translating_count;
    p.size[MM__SEC_POSE_BITS] = (size_t)h->sections[MM__SEC_POSE_BITS].size;
    p.size[MM__SEC_CONFIG_JSON] = (size_t)h->sections[MM__SEC_CONFIG_JSON].size;
    p.size[MM__SEC_DISTANCE_SEGMENTS] = (size_t)h->sections[MM__SEC_DISTANCE_SEGMENTS].size;
    size_t want[MM__SEC_COUNT];
    mm__db_section_sizes(&p, want);
    int s = mm__sections_check(h->sections, MM__SEC_COUNT, sizeof *h, MM_DB_ALIGN, size, want);
    if (s >= 0)
        return BAD("section %d: offset %llu size %llu does not fit the file or the counts, or overlaps "
                   "the one before",
                   s, (unsigned long long)h->sections[s].offset, (unsigned long long)h->sections[s].size);
    const unsigned char *json = base + h->sections[MM__SEC_CONFIG_JSON].offset;
    size_t json_size = (size_t)h->sections[MM__SEC_CONFIG_JSON].size;
    if (json_size < 1 || json[json_size - 1] != 0) return BAD("embedded config is not terminated");
    uint64_t segments = h->sections[MM__SEC_DISTANCE_SEGMENTS].size;
    if (segments % sizeof(mm_distance_segment) != 0 ||
        segments / sizeof(mm_distance_segment) > (uint64_t)h->frame_count)
        return BAD("distance curves: the segments section is not a whole number of segments, at most one "
                   "per frame");
    return MM_OK;
}

/* Cross references: everything an index in the file points at must exist. */
static mm_result validate_references(const mm_database *db, mm_error *err)
{
    for (int j = 0; j < db->joint_count; ++j) {
        const mm_joint *jt = &db->joints[j];
        /* bool and enum fields are read as bytes first: a bool holding 32 must not be loaded */
        unsigned char end_site;
        int32_t order;
        memcpy(&end_site, (const unsigned char *)jt + offsetof(mm_joint, has_end_site), 1);
        memcpy(&order, (const unsigned char *)jt + offsetof(mm_joint, order), 4);
        if (memchr(jt->name, 0, MM_NAME_MAX) == NULL ||
            (j == 0 ? jt->parent != -1 : (jt->parent < 0 || jt->parent >= j)))
            return BAD("joint %d: bad name or parent", j);
        if (end_site > 1 || order < MM_EULER_NONE || order > MM_EULER_ZYX ||
            (jt->flags & ~(unsigned)MM_JOINT_TRANSLATES))
            return BAD("joint %d: bad End Site flag, rotation order or flags", j);
    }
    int expect_first = 0;
    for (int c = 0; c < db->clip_count; ++c) {
        const mm_db_clip *k = &db->clips[c];
        if (memchr(k->name, 0, MM_NAME_MAX) == NULL || k->first_frame != expect_first || k->frame_count < 1 ||
            k->frame_count > db->frame_count - k->first_frame ||
            (k->type != MM_CLIP_IDLE && k->type != MM_CLIP_LOCOMOTION) || k->blend_left < -1 ||
            k->blend_left >= db->clip_count || k->blend_right < -1 || k->blend_right >= db->clip_count)
            return BAD("clip %d: bad name, frame range, type or blend sources", c);
        /* a blend has both sources and a weight in [0, 1]; any other clip has neither */
        bool blend = k->blend_left >= 0;
        if ((k->loop != 0 && k->loop != 1) || (k->mirrored != 0 && k->mirrored != 1) || k->source < 0 ||
            (k->blend_right >= 0) != blend ||
            !(k->source_start >= 0.0f && k->source_start <= MM__DB_VALUE_MAX) ||
            (blend ? !(k->blend_weight >= 0.0f && k->blend_weight <= 1.0f) : k->blend_weight != 0.0f))
            return BAD("clip %d (%s): bad loop or mirrored flag, source, start time or blend weight", c,
                       k->name);
        expect_first += k->frame_count;
    }
    if (expect_first != db->frame_count)
        return BAD("clips cover %d of %d frames", expect_first, db->frame_count);
    for (int f = 0; f < db->frame_count; ++f) {
        int c = db->frame_clip[f];
        if (c < 0 || c >= db->clip_count || f < db->clips[c].first_frame ||
            f >= db->clips[c].first_frame + db->clips[c].frame_count)
            return BAD("frame %d: bad clip index %d", f, c);
        int n = db->frame_next[f];
        if (n < -1 || n >= db->frame_count || (n >= 0 && db->frame_clip[n] != c))
            return BAD("frame %d: bad next frame %d", f, n);
    }
    int dims_end = 0;
    for (int g = 0; g < db->group_count; ++g) {
        const mm_feature_group *grp = &db->groups[g];
        /* the groups tile [0, dims) in order: each starts where the one before ends (so the sum
         * cannot overflow: offset is at most dims here) */
        int want_dims = grp->kind >= MM_FEATURE_TRAJ_POSITION ? 2 : 3;
        if (grp->offset != dims_end || grp->dims != want_dims || grp->dims > db->dims - grp->offset ||
            grp->kind < MM_FEATURE_BONE_POSITION || grp->kind > MM_FEATURE_TRAJ_DIRECTION ||
            (grp->kind >= MM_FEATURE_TRAJ_POSITION ? grp->bone != -1 : grp->bone < 0) ||
            grp->bone >= db->joint_count || memchr(grp->name, 0, MM_NAME_MAX) == NULL ||
            !isfinite(grp->time) || !isfinite(grp->weight) || grp->weight < 0.0f || !isfinite(grp->scale) ||
            !(grp->scale > 0.0f))
            return BAD("feature group %d is inconsistent", g);
        dims_end = grp->offset + grp->dims;
    }
    if (dims_end != db->dims) return BAD("the feature groups cover %d of %d dimensions", dims_end, db->dims);
    for (int t = 0; t < db->tag_count; ++t)
        if (memchr(db->tag_names[t], 0, MM_TAG_NAME_MAX) == NULL)
            return BAD("tag %d: name not terminated", t);
    for (int d = 0; d < db->dims_padded; ++d)
        if (!isfinite(db->feature_mean[d]) || !(db->feature_scale[d] > 0.0f) ||
            !isfinite(db->feature_scale[d]))
            return BAD("feature dimension %d: bad normalisation", d);
    return MM_OK;
}

/* Whether n floats are finite and at most limit in magnitude. */
static bool bounded_floats(const float *v, size_t n, float limit)
{
    for (size_t i = 0; i < n; ++i)
        if (!(fabsf(v[i]) <= limit)) return false;
    return true;
}
#define finite_floats(v, n) bounded_floats(v, n, MM__DB_VALUE_MAX)

size_t mm__pose_first_bad_joint(const mm_quat *q, const mm_vec3 *p, size_t n)
{
    for (size_t j = 0; j < n; ++j) {
        float len = q[j].x * q[j].x + q[j].y * q[j].y + q[j].z * q[j].z + q[j].w * q[j].w;
        if (!finite_floats(&q[j].x, 4) || !finite_floats(&p[j].x, 3) ||
            !(fabsf(len - 1.0f) <= MM__DB_UNIT_TOLERANCE))
            return j;
    }
    return n;
}

/* Whether mn / mx hold the exact per-dimension bounds of the features over blocks of block frames
 * (the last block may be short), as the build computes them. */
static bool bounds_exact(const mm_database *db, int block, const float *mn, const float *mx)
{
    size_t dp = (size_t)db->dims_padded;
    for (int f0 = 0, b = 0; f0 < db->frame_count; f0 += block, ++b) {
        int end = db->frame_count - f0 < block ? db->frame_count : f0 + block;
        for (size_t d = 0; d < dp; ++d) {
            float lo = INFINITY, hi = -INFINITY;
            for (int f = f0; f < end; ++f) {
                float v = db->features[(size_t)f * dp + d];
                lo = v < lo ? v : lo;
                hi = v > hi ? v : hi;
            }
            if (mn[(size_t)b * dp + d] != lo || mx[(size_t)b * dp + d] != hi) return false;
        }
    }
    return true;
}

/* Every value a search or a pose reads: finite, tags and contacts only of known bits, rotations of
 * unit length, feature padding zero and the block bounds exactly those of the features (a crafted
 * file cannot make the search read NaN or prune with wrong boxes). */
static mm_result validate_values(const mm_database *db, mm_error *err)
{
    for (int j = 0; j < db->joint_count; ++j) {
        const mm_joint *jt = &db->joints[j];
        static const unsigned char zeros[sizeof(mm_joint)];
        const unsigned char *bytes = (const unsigned char *)jt;
        /* no End Site: its offset is zero, as are the bytes after the flag */
        size_t pad = offsetof(mm_joint, has_end_site) + 1, pad_end = offsetof(mm_joint, end_site);
        if (!finite_floats(&jt->offset.x, 3) || !finite_floats(&jt->end_site.x, 3) ||
            (!jt->has_end_site && memcmp(&jt->end_site, zeros, sizeof jt->end_site) != 0) ||
            memcmp(bytes + pad, zeros, pad_end - pad) != 0)
            return BAD("joint %d (%s): offset or End Site out of range, or padding not zero", j, jt->name);
    }
    for (int g = 0; g < db->group_count; ++g) {
        const mm_feature_group *grp = &db->groups[g];
        if (!(grp->scale >= MM__DB_SCALE_MIN && grp->scale <= MM__DB_VALUE_MAX) ||
            !(fabsf(grp->time) <= MM__DB_VALUE_MAX))
            return BAD("feature group %d (%s): scale %g or time %g out of range", g, grp->name,
                       (double)grp->scale, (double)grp->time);
        for (int d = grp->offset; d < grp->offset + grp->dims; ++d)
            if (db->feature_scale[d] != grp->scale)
                return BAD("feature dimension %d: scale %g is not its group's (%g)", d,
                           (double)db->feature_scale[d], (double)grp->scale);
    }
    for (int d = 0; d < db->dims_padded; ++d)
        if (!(fabsf(db->feature_mean[d]) <= MM__DB_VALUE_MAX) ||
            (d >= db->dims && (db->feature_mean[d] != 0.0f || db->feature_scale[d] != 1.0f)))
            return BAD("feature dimension %d: mean %g out of range, or padding not of mean 0 and scale 1", d,
                       (double)db->feature_mean[d]);
    uint64_t known_tags = db->tag_count == 64 ? ~(uint64_t)0 : (((uint64_t)1 << db->tag_count) - 1);
    const uint8_t known_contacts =
        MM_CONTACT_LEFT_HEEL | MM_CONTACT_LEFT_TOE | MM_CONTACT_RIGHT_HEEL | MM_CONTACT_RIGHT_TOE;
    size_t f_count = (size_t)db->frame_count, j_count = (size_t)db->joint_count, dp = (size_t)db->dims_padded;
    for (size_t f = 0; f < f_count; ++f) {
        if (db->frame_tags[f] & ~known_tags)
            return BAD("frame %zu: tag bits 0x%llx name none of the %d tags", f,
                       (unsigned long long)(db->frame_tags[f] & ~known_tags), db->tag_count);
        if (db->contacts[f] & ~known_contacts)
            return BAD("frame %zu: contact bits 0x%x are unknown", f,
                       (unsigned)(db->contacts[f] & ~known_contacts));
        if (!finite_floats(&db->root_velocity[f].x, 3) || !finite_floats(&db->root_angular_velocity[f], 1))
            return BAD("frame %zu: root velocity is not finite or out of range", f);
        if (db->pose_codec == MM_POSE_FLOATS) {
            size_t j =
                mm__pose_first_bad_joint(db->rotations + f * j_count, db->positions + f * j_count, j_count);
            if (j < j_count)
                return BAD("frame %zu, joint %zu: rotation not of unit length or position out of range", f,
                           j);
        }
        const float *x = db->features + f * dp;
        if (!bounded_floats(x, (size_t)db->dims, MM__DB_FEATURE_MAX))
            return BAD("frame %zu: a feature is not finite or out of range", f);
        for (size_t d = (size_t)db->dims; d < dp; ++d)
            if (x[d] != 0.0f)
                return BAD("frame %zu: padding dimension %zu holds %g (must be 0)", f, d, (double)x[d]);
    }
    if (!bounds_exact(db, MM_DB_SMALL_BLOCK, db->small_min, db->small_max) ||
        !bounds_exact(db, MM_DB_LARGE_BLOCK, db->large_min, db->large_max))
        return BAD("the feature bounds are not those of the features");
    return MM_OK;
}

/* The view of clip c's curve (valid or not: validate_distance checks it). */
static void distance_view(const mm_database *db, int c, mm_distance_curve *out)
{
    const mm_db_clip *k = &db->clips[c];
    const mm_db_distance_clip *d = &db->distance_clips[c];
    memset(out, 0, sizeof *out);
    out->frame_count = k->frame_count;
    out->loop = k->loop != 0;
    out->fps = 1.0f / db->interval;
    out->path_length = d->path_length;
    out->segment_count = d->segment_count;
    out->travelled = db->distance_travelled + k->first_frame;
    out->distance = db->distance_signed + k->first_frame;
    out->segments = db->distance_segments + d->first_segment;
}

/* Distance curves: the clips' segment ranges tile the segments section in order; each curve passes
 * mm_distance_curve_validate. Segment frame ranges are bounded here first, so the validator's
 * sums cannot overflow on a crafted file. */
static mm_result validate_distance(const mm_database *db, mm_error *err)
{
    int64_t next = 0;
    for (int c = 0; c < db->clip_count; ++c) {
        const mm_db_clip *k = &db->clips[c];
        const mm_db_distance_clip *d = &db->distance_clips[c];
        int n = k->frame_count;
        if (d->first_segment != next || d->segment_count < (n >= 2 ? 1 : 0) || d->segment_count > n ||
            (n < 2 && d->segment_count != 0) ||
            d->segment_count > db->distance_segment_count - d->first_segment)
            return BAD("distance curves: clip %d (%s): bad segment range", c, k->name);
        if (!(d->stop_speed > 0.0f && d->stop_speed <= MM__DB_VALUE_MAX))
            return BAD("distance curves: clip %d (%s): bad stop speed", c, k->name);
        next += d->segment_count;
        if (n < 2) {
            if (db->distance_travelled[k->first_frame] != 0.0f ||
                db->distance_signed[k->first_frame] != 0.0f || d->path_length != 0.0f)
                return BAD("distance curves: clip %d (%s): a clip of one frame has no curve", c, k->name);
            continue;
        }
        int64_t covered = 0;
        for (int s = 0; s < d->segment_count; ++s) {
            const mm_distance_segment *g = &db->distance_segments[d->first_segment + s];
            if (g->first_frame < 0 || g->first_frame >= n || g->frame_count < 1 || g->frame_count > n ||
                g->marker_frame < 0 || g->marker_frame >= n)
                return BAD("distance curves: clip %d (%s): segment %d: bad frames", c, k->name, s);
            covered += g->frame_count;
        }
        if (covered != n)
            return BAD("distance curves: clip %d (%s): the segments cover %lld of %d frames", c, k->name,
                       (long long)covered, n);
        mm_distance_curve view;
        distance_view(db, c, &view);
        mm_error e;
        memset(&e, 0, sizeof e);
        if (mm_distance_curve_validate(&view, &e) != MM_OK) {
            const char *why = e.message;
            if (strncmp(why, "distance curve: ", 16) == 0) why += 16;
            return BAD("distance curves: clip %d (%s): %s", c, k->name, why);
        }
    }
    if (next != db->distance_segment_count)
        return BAD("distance curves: the clips use %lld of %d segments", (long long)next,
                   db->distance_segment_count);
    return MM_OK;
}

/* ---- the settings section ----------------------------------------------------------------- */

/* A float field of the settings: its bit in the set mask, where it is, and the range it must be
 * in when set (lo excluded when lo_open; FLT_MAX: no upper bound but finite). */
typedef struct settings_rule {
    unsigned bit;
    size_t offset;
    const char *name, *unit;
    float lo, hi;
    int lo_open;
} settings_rule;

#define RULE(bit, field, unit, lo, hi, open)                                                                 \
    {                                                                                                        \
        bit, offsetof(mm_database_settings, field), #field, unit, lo, hi, open                               \
    }
static const settings_rule runtime_rules[] = {
    RULE(MM_RUNTIME_POSE_TRAJECTORY_RATIO, pose_trajectory_ratio, "", 0.0f, 1.0f, 0),
    RULE(MM_RUNTIME_NEXT_POSE_FAVOUR, next_pose_favour, "", 0.0f, FLT_MAX, 1),
    RULE(MM_RUNTIME_LOOP_ANIM_FAVOUR, loop_anim_favour, "", 0.0f, FLT_MAX, 1),
    RULE(MM_RUNTIME_CONTINUING_BIAS, continuing_bias, "", 0.0f, FLT_MAX, 0),
    RULE(MM_RUNTIME_SEARCH_INTERVAL, search_interval, " s", 0.0f, 10.0f, 1),
    RULE(MM_RUNTIME_TRANSITION_HALFLIFE, transition_halflife, " s", 0.0f, 60.0f, 1),
    RULE(MM_RUNTIME_IDLE_SPEED, idle_speed, " m/s", 0.0f, 50.0f, 0),
    RULE(MM_RUNTIME_SYNC_HALFLIFE, sync_halflife, " s", 0.0f, 60.0f, 0),
    RULE(MM_RUNTIME_CONTACT_FAVOUR, contact_favour, "", 1.0f, FLT_MAX, 0),
};
static const settings_rule weight_rules[] = {
    RULE(MM_SETTINGS_BODY_VELOCITY_WEIGHT, body_velocity_weight, "", 0.0f, FLT_MAX, 0),
    RULE(MM_SETTINGS_POSITION_MULTIPLIER, position_multiplier, "", 0.0f, FLT_MAX, 0),
    RULE(MM_SETTINGS_ANGLE_MULTIPLIER, angle_multiplier, "", 0.0f, FLT_MAX, 0),
};
#undef RULE
#define GAIT_RULE(bit, field, unit, lo, hi, open)                                                            \
    {                                                                                                        \
        bit, offsetof(mm_runtime_gait, field), #field, unit, lo, hi, open                                    \
    }
static const settings_rule gait_rules[] = {
    GAIT_RULE(MM_RUNTIME_FORWARD_SPEED, forward_speed, " m/s", 0.0f, 50.0f, 0),
    GAIT_RULE(MM_RUNTIME_SIDE_SPEED, side_speed, " m/s", 0.0f, 50.0f, 0),
    GAIT_RULE(MM_RUNTIME_BACKWARD_SPEED, backward_speed, " m/s", 0.0f, 50.0f, 0),
    GAIT_RULE(MM_RUNTIME_VELOCITY_HALFLIFE, velocity_halflife, " s", 0.0f, 60.0f, 1),
    GAIT_RULE(MM_RUNTIME_ROTATION_HALFLIFE, rotation_halflife, " s", 0.0f, 60.0f, 1),
};
#undef GAIT_RULE

static int in_rule(const settings_rule *r, float v)
{
    return isfinite(v) && (r->lo_open ? v > r->lo : v >= r->lo) && v <= r->hi;
}

/* The float fields of rules in the struct at base: set ones in range, the others zero. */
static mm_result check_rules(const unsigned char *base, unsigned set, const settings_rule *rules, int count,
                             const char *prefix, mm_result code, mm_error *err)
{
    for (int i = 0; i < count; ++i) {
        const settings_rule *r = &rules[i];
        float v;
        memcpy(&v, base + r->offset, sizeof v);
        if ((set & r->bit) && !in_rule(r, v)) {
            if (r->hi == FLT_MAX)
                return mm_error_set(err, code, 0, 0, "settings: %s%s: %g is out of range (%s %g)", prefix,
                                    r->name, (double)v, r->lo_open ? "above" : "at least", (double)r->lo);
            return mm_error_set(err, code, 0, 0, "settings: %s%s: %g%s is out of range (%s %g, at most %g%s)",
                                prefix, r->name, (double)v, r->unit, r->lo_open ? "above" : "from",
                                (double)r->lo, (double)r->hi, r->unit);
        }
        if (!(set & r->bit) && v != 0.0f)
            return mm_error_set(err, code, 0, 0, "settings: %s%s is not set but holds %g (must be 0)", prefix,
                                r->name, (double)v);
    }
    return MM_OK;
}

mm_result mm__db_settings_validate(const mm_database *db, const mm_database_settings *s, mm_result code,
                                   mm_error *err)
{
#define FAIL(...) return mm_error_set(err, code, 0, 0, __VA_ARGS__)
    /* which weights db has groups for */
    uint32_t positions = 0, velocities = 0;
    unsigned weights = 0;
    for (int g = 0; g < db->group_count; ++g) {
        int kind = db->groups[g].kind, slot = mm_database_matched_bone(db, g);
        if (kind == MM_FEATURE_BONE_POSITION && slot >= 0) positions |= 1u << slot;
        if (kind == MM_FEATURE_BONE_VELOCITY && slot >= 0) velocities |= 1u << slot;
        if (kind == MM_FEATURE_ROOT_VELOCITY) weights |= MM_SETTINGS_BODY_VELOCITY_WEIGHT;
        if (kind == MM_FEATURE_TRAJ_POSITION) weights |= MM_SETTINGS_POSITION_MULTIPLIER;
        if (kind == MM_FEATURE_TRAJ_DIRECTION) weights |= MM_SETTINGS_ANGLE_MULTIPLIER;
    }
    if (s->weight_set & ~weights)
        FAIL("settings: weight bits 0x%x are unknown or name feature groups the database does not have",
             (unsigned)(s->weight_set & ~weights));
    if (s->position_set & ~positions)
        FAIL("settings: position weight bits 0x%x name matched bones without a position feature",
             (unsigned)(s->position_set & ~positions));
    if (s->velocity_set & ~velocities)
        FAIL("settings: velocity weight bits 0x%x name matched bones without a velocity feature",
             (unsigned)(s->velocity_set & ~velocities));
    for (int b = 0; b < MM_MAX_MATCH_BONES; ++b) {
        const float w[2] = {s->joint_position_weights[b], s->joint_velocity_weights[b]};
        const uint32_t set[2] = {s->position_set, s->velocity_set};
        static const char *const what[2] = {"joint_position_weights", "joint_velocity_weights"};
        for (int k = 0; k < 2; ++k) {
            if ((set[k] >> b) & 1u) {
                if (!(isfinite(w[k]) && w[k] >= 0.0f))
                    FAIL("settings: %s[%d]: %g must be finite and >= 0", what[k], b, (double)w[k]);
            } else if (w[k] != 0.0f) {
                FAIL("settings: %s[%d] is not set but holds %g (must be 0)", what[k], b, (double)w[k]);
            }
        }
    }
    const unsigned char *base = (const unsigned char *)s;
    mm_result r = check_rules(base, s->weight_set, weight_rules, 3, "", code, err);
    if (r != MM_OK) return r;
    if (s->set & ~MM_RUNTIME_FIELDS_ALL)
        FAIL("settings: runtime bits 0x%x are unknown", (unsigned)(s->set & ~MM_RUNTIME_FIELDS_ALL));
    r = check_rules(base, s->set, runtime_rules, (int)(sizeof runtime_rules / sizeof runtime_rules[0]),
                    "runtime.", code, err);
    if (r != MM_OK) return r;
    const uint32_t switches[3] = {s->distance_matching, s->warping, s->speed_envelope};
    const unsigned switch_bits[3] = {MM_RUNTIME_DISTANCE_MATCHING, MM_RUNTIME_WARPING,
                                     MM_RUNTIME_SPEED_ENVELOPE};
    static const char *const switch_names[3] = {"distance_matching", "warping", "speed_envelope"};
    for (int k = 0; k < 3; ++k)
        if (switches[k] > ((s->set & switch_bits[k]) ? 1u : 0u))
            FAIL("settings: runtime.%s: %u is not %s", switch_names[k], (unsigned)switches[k],
                 (s->set & switch_bits[k]) ? "0 or 1" : "0 (not set)");
    const mm_runtime_gait *gaits[3] = {&s->walk, &s->run, &s->crouch};
    static const char *const gait_prefix[3] = {"runtime.walk.", "runtime.run.", "runtime.crouch."};
    static const char *const gait_names[3] = {"walk", "run", "crouch"};
    for (int g = 0; g < 3; ++g) {
        if (gaits[g]->set & ~MM_RUNTIME_GAIT_FIELDS_ALL)
            FAIL("settings: runtime.%s: bits 0x%x are unknown", gait_names[g],
                 (unsigned)(gaits[g]->set & ~MM_RUNTIME_GAIT_FIELDS_ALL));
        r = check_rules((const unsigned char *)gaits[g], gaits[g]->set, gait_rules, 5, gait_prefix[g], code,
                        err);
        if (r != MM_OK) return r;
    }
    for (int g = 0; g < MM_SETTINGS_ENVELOPE_GAITS; ++g)
        for (int k = 0; k < MM_SETTINGS_ENVELOPE_BINS; ++k)
            if (!(s->envelope[g][k] >= 0.0f && s->envelope[g][k] <= MM_SPEED_ENVELOPE_MAX))
                FAIL("settings: envelope of %s, direction %d: %g m/s is out of range (0 to %g m/s)",
                     mm_gait_name((mm_gait)g), k, (double)s->envelope[g][k], (double)MM_SPEED_ENVELOPE_MAX);
    static const char *const roles[MM_ROLE_COUNT] = {"hips",      "left_foot", "right_foot", "left_toe",
                                                     "right_toe", "left_hand", "right_hand", "head"};
    for (int k = 0; k < MM_ROLE_COUNT; ++k)
        if (s->roles[k] < -1 || s->roles[k] >= db->joint_count)
            FAIL("settings: roles.%s: joint %d is not -1 nor one of the %d joints", roles[k],
                 (int)s->roles[k], db->joint_count);
    return MM_OK;
#undef FAIL
}

mm_result mm_database_distance_curve(const mm_database *db, int clip, mm_distance_curve *out)
{
    if (out) memset(out, 0, sizeof *out);
    if (!db || !out || !db->data || clip < 0 || clip >= db->clip_count) return MM_ERR_INVALID_ARGUMENT;
    if (db->distance_clips[clip].segment_count < 1) return MM_ERR_OUT_OF_RANGE;
    distance_view(db, clip, out);
    return MM_OK;
}

mm_result mm_database_load_memory(const void *data, size_t size, bool verify_checksum, mm_database *out,
                                  mm_error *err)
{
    if (!out) return MM_ERR_INVALID_ARGUMENT;
    memset(out, 0, sizeof *out);
    if (!data || ((uintptr_t)data % MM_DB_ALIGN) != 0)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "the buffer must be aligned to %d bytes",
                            MM_DB_ALIGN);
    mm__db_header h;
    mm_result r = validate((const unsigned char *)data, size, verify_checksum, &h, err);
    if (r != MM_OK) return r;
    mm_database db;
    memset(&db, 0, sizeof db);
    point_into(&db, (const unsigned char *)data, &h);
    r = validate_references(&db, err);
    if (r == MM_OK) r = validate_values(&db, err);
    if (r == MM_OK && db.pose_codec == MM_POSE_SEGMENTS) r = mm__pose_codec_validate(&db, err);
    if (r == MM_OK) r = validate_distance(&db, err);
    if (r == MM_OK) r = mm__db_settings_validate(&db, db.settings, MM_ERR_SYNTAX, err);
    if (r != MM_OK) return r;
    db.data = data;
    db.size = size;
    *out = db;
    return MM_OK;
}

mm_result mm_database_load(const char *path, const mm_db_load_desc *desc, mm_database *out, mm_error *err)
{
    if (!out) return MM_ERR_INVALID_ARGUMENT;
    memset(out, 0, sizeof *out);
    mm__error_set_file(err, path);
    const mm_allocator *allocator = desc ? desc->allocator : NULL;
    bool verify = !(desc && desc->skip_checksum);
    int fd = path ? open(path, O_RDONLY) : -1;
    if (fd < 0) return mm_error_set(err, MM_ERR_IO, 0, 0, "cannot open: %s", strerror(errno));
    struct stat st;
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        close(fd);
        return mm_error_set(err, MM_ERR_IO, 0, 0, "not a regular file");
    }
    if ((unsigned long long)st.st_size >= MM__MAX_FILE_BYTES) {
        close(fd);
        return mm_error_set(err, MM_ERR_LIMIT, 0, 0, "file is %lld bytes, more than allowed",
                            (long long)st.st_size);
    }
    size_t size = (size_t)st.st_size;
    mm_result r;
    if (!(desc && desc->no_map) && size > 0) {
        void *map = mmap(NULL, size, PROT_READ, MAP_PRIVATE, fd, 0);
        if (map != MAP_FAILED) { /* page-aligned, so MM_DB_ALIGN-aligned */
            close(fd);
            r = mm_database_load_memory(map, size, verify, out, err);
            if (r != MM_OK) {
                munmap(map, size);
                return r;
            }
            out->owned = map;
            out->mapped = true;
            return MM_OK;
        }
    }
    unsigned char *raw;
    unsigned char *base = mm__alloc_aligned(allocator, size, MM_DB_ALIGN, &raw);
    if (!base) {
        close(fd);
        return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory (%zu bytes)", size);
    }
    size_t got = 0;
    while (got < size) {
        ssize_t n = read(fd, base + got, size - got);
        if (n <= 0) break;
        got += (size_t)n;
    }
    close(fd);
    r = got == size ? mm_database_load_memory(base, size, verify, out, err)
                    : mm_error_set(err, MM_ERR_IO, 0, 0, "read error");
    if (r != MM_OK) {
        mm_free(allocator, raw);
        return r;
    }
    if (allocator) out->allocator = *allocator;
    out->owned = raw;
    return MM_OK;
}

void mm_database_free(mm_database *db)
{
    if (!db) return;
    if (db->mapped) {
        munmap(db->owned, db->size);
    } else {
        mm_allocator a = db->allocator;
        mm_free(&a, db->owned);
    }
    memset(db, 0, sizeof *db);
}

mm_result mm_database_save(const mm_database *db, const char *path, mm_error *err)
{
    if (!db || !db->data) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no database");
    return mm__write_file_atomic(path, db->data, db->size, err);
}

int mm_database_find_clip(const mm_database *db, const char *name)
{
    for (int c = 0; c < db->clip_count; ++c)
        if (strcmp(db->clips[c].name, name) == 0) return c;
    return -1;
}

int mm_database_matched_bone(const mm_database *db, int group)
{
    if (group < 0 || group >= db->group_count) return -1;
    int kind = db->groups[group].kind;
    if (kind != MM_FEATURE_BONE_POSITION && kind != MM_FEATURE_BONE_VELOCITY) return -1;
    int bones[MM_MAX_MATCH_BONES], count = 0;
    for (int g = 0; g <= group; ++g) {
        const mm_feature_group *grp = &db->groups[g];
        if (grp->kind != MM_FEATURE_BONE_POSITION && grp->kind != MM_FEATURE_BONE_VELOCITY) continue;
        int b = 0;
        while (b < count && bones[b] != grp->bone) ++b;
        if (b == count) {
            if (count == MM_MAX_MATCH_BONES) return -1;
            bones[count++] = grp->bone;
        }
        if (g == group) return b;
    }
    return -1;
}

void mm_database_pose(const mm_database *db, int frame, mm_pose_data *out)
{
    memset(out, 0, sizeof *out);
    if (frame < 0 || frame >= db->frame_count) {
        out->id = out->next_id = out->clip = -1;
        return;
    }
    const mm_db_clip *c = &db->clips[db->frame_clip[frame]];
    out->id = frame;
    out->next_id = db->frame_next[frame];
    out->clip = db->frame_clip[frame];
    out->time = (float)(frame - c->first_frame) * db->interval;
    out->root_velocity = db->root_velocity[frame];
    out->root_angular_velocity = db->root_angular_velocity[frame];
    out->type = c->type;
    out->tags = db->frame_tags[frame];
    out->is_blend = c->blend_left >= 0;
    out->blend_weight = c->blend_weight;
    out->blend_left = c->blend_left;
    out->blend_right = c->blend_right;
    out->contacts = db->contacts[frame];
    for (int g = 0; g < db->group_count; ++g) {
        const mm_feature_group *grp = &db->groups[g];
        float v[3] = {0, 0, 0};
        for (int d = 0; d < grp->dims; ++d) v[d] = mm_database_feature_raw(db, frame, grp->offset + d);
        if (grp->kind == MM_FEATURE_BONE_POSITION || grp->kind == MM_FEATURE_BONE_VELOCITY) {
            int b = 0;
            while (b < out->bone_count && out->bones[b] != grp->bone) ++b;
            if (b == out->bone_count) {
                if (b == MM_MAX_MATCH_BONES) continue;
                out->bones[out->bone_count++] = grp->bone;
            }
            mm_vec3 *dst =
                grp->kind == MM_FEATURE_BONE_POSITION ? &out->bone_positions[b] : &out->bone_velocities[b];
            *dst = mm_vec3_make(v[0], v[1], v[2]);
        } else if (grp->kind == MM_FEATURE_TRAJ_POSITION || grp->kind == MM_FEATURE_TRAJ_DIRECTION) {
            int t = 0;
            while (t < out->traj_count && out->traj_times[t] != grp->time) ++t;
            if (t == out->traj_count) {
                if (t == MM_MAX_TRAJ_SAMPLES) continue;
                out->traj_times[out->traj_count++] = grp->time;
            }
            mm_vec3 *dst =
                grp->kind == MM_FEATURE_TRAJ_POSITION ? &out->traj_positions[t] : &out->traj_directions[t];
            *dst = mm_vec3_make(v[0], 0.0f, v[1]);
        }
    }
}

const char *mm_feature_kind_name(mm_feature_kind kind)
{
    static const char *names[] = {"bone_position", "bone_velocity", "root_velocity", "trajectory_position",
                                  "trajectory_direction"};
    return (int)kind >= 0 && (int)kind < 5 ? names[kind] : NULL;
}
