/* Compressing a database's local transforms (mm_database_compress, docs/database.md "A smaller
 * database for shipping"): every clip cut into segments; per segment, each joint's rotation as
 * three quaternion components over the segment's range and each translating joint's translation
 * over its range, with as few bits as keep every frame's world joint positions within the bound.
 *
 * A segment's bits come from an estimate (the error a track's step makes at the distance of the
 * joints it moves, its share of the bound along the longest chain), scaled: from generous down by
 * MM__SCALE_STEP until the segment, decoded by the runtime's own decoder and put through FK, holds
 * every frame within the bound (the joints, and the shell points that hold each joint's own
 * rotation). A segment no scale fits keeps its floats exactly. Segments are independent: threads
 * take every n-th one, and the bytes never depend on their number. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <mm/clip.h>
#include <mm/database_build.h>

#include "db/db_file.h"
#include "db/pose_codec.h"
#include "search/pool.h"

/* The first scale of the estimate's budget, the factor between trials and how many are tried
 * before a segment keeps its floats. */
#define MM__SCALE_FIRST 8.0f
#define MM__SCALE_STEP  0.7f
#define MM__SCALE_TRIES 40
/* A kept component below this magnitude as the dropped one would magnify the others' errors:
 * prefer a component of the right sign only down to it. */
#define MM__DROPPED_MIN 0.3f
/* A joint's translation counts as constant when it varies (over the whole database) by less than
 * the bound / (MM__CONSTANT_SHARE x the skeleton's depth): resampling leaves rest offsets a
 * fraction of a micrometre apart, which a translation track per segment would store for nothing. */
#define MM__CONSTANT_SHARE 100.0f

typedef struct segment_out {
    int first, count;
    mm_db_rotation_track *rot;      /* [joint_count] */
    mm_db_translation_track *trans; /* [translating_count] */
    uint8_t *bytes;                 /* the frames, then MM__POSE_BITS_TAIL zero bytes */
    size_t byte_count;              /* without the tail */
    uint32_t frame_bits;
    float max_error; /* m: joints */
    mm_result result;
} segment_out;

typedef struct encode_job {
    const mm_database *db;
    mm_skeleton skeleton; /* a view of db's joints */
    float bound, shell;
    int per, depth;
    int translating_count;
    const int32_t *translating;
    const mm_vec3 *constants;
    segment_out *segments;
    int segment_count;
} encode_job;

/* A worker's scratch for a segment of up to `per` frames. */
typedef struct scratch {
    mm_quat *orig; /* [per x joints]: the floats */
    mm_quat *rot;  /* [per x joints]: the same, sign-aligned to each track's dropped component */
    mm_db_rotation_track *ranges;          /* [joints]: the ranges and dropped components */
    mm_db_translation_track *trans_ranges; /* [translating] */
    mm_vec3 *pos;                          /* [per x joints] */
    mm_xform *reference;                   /* [per x joints]: their FK */
    mm_xform *decoded;                     /* [joints] */
    mm_quat *drot;                         /* [joints] */
    mm_vec3 *dpos;                         /* [joints] */
    float *reach;                          /* [joints]: m, farthest descendant point */
    float *dropped_min;                    /* [joints] */
    float *rot_extent;                     /* [joints]: the widest kept component's range */
    float *trans_extent;                   /* [translating] */
    uint8_t *bits;                         /* [joints], [translating]: the last trial's */
    uint8_t *bytes;                        /* the largest segment's frames + tail */
} scratch;

static void write_bits(uint8_t *stream, uint64_t at, unsigned bits, uint32_t value)
{
    for (unsigned i = 0; i < bits; ++i, ++at)
        if ((value >> i) & 1u) stream[at >> 3] |= (uint8_t)(1u << (at & 7u));
}

static uint32_t bits_of_float(float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

static uint32_t quantize(float v, float lo, float extent, unsigned bits)
{
    if (bits == 0 || !(extent > 0.0f)) return 0;
    double top = (double)((1u << bits) - 1u), t = ((double)v - lo) / extent * top;
    t = floor(t + 0.5);
    return t < 0 ? 0u : t > top ? (uint32_t)top : (uint32_t)t;
}

/* The fewest bits (0..max) whose half step over extent, times gain, is within allowed; -1: none. */
static int bits_for(float extent, float gain, float allowed, int max)
{
    for (int b = 0; b <= max; ++b) {
        float step_error = b == 0 ? extent : extent / (2.0f * (float)((1u << b) - 1u));
        if (step_error * gain <= allowed) return b;
    }
    return -1;
}

/* Picks each joint's dropped component and sign, aligns the frames to it, and sets its range. */
static void rotation_ranges(const encode_job *job, scratch *w, int count)
{
    int jc = job->db->joint_count;
    for (int j = 0; j < jc; ++j) {
        float best = -1.0f, best_any = -1.0f;
        int pick = -1, pick_any = 0;
        for (int c = 0; c < 4; ++c) {
            float mn = INFINITY;
            int pos = 0, neg = 0;
            for (int f = 0; f < count; ++f) {
                float v = (&w->rot[(size_t)f * jc + j].x)[c];
                mn = fminf(mn, fabsf(v));
                pos += v > 0.0f, neg += v < 0.0f;
            }
            if ((pos == count || neg == count) && mn > best) best = mn, pick = c;
            if (mn > best_any) best_any = mn, pick_any = c;
        }
        bool keep_sign = pick >= 0 && best >= MM__DROPPED_MIN;
        int d = keep_sign ? pick : pick_any;
        bool negative = keep_sign && (&w->rot[j].x)[d] < 0.0f;
        w->dropped_min[j] = keep_sign ? best : best_any;
        float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (int f = 0; f < count; ++f) {
            mm_quat *q = &w->rot[(size_t)f * jc + j];
            if (!keep_sign && (&q->x)[d] < 0.0f) *q = mm_quat_make(-q->x, -q->y, -q->z, -q->w);
            for (int c = 0, k = 0; c < 4; ++c) {
                if (c == d) continue;
                lo[k] = fminf(lo[k], (&q->x)[c]), hi[k] = fmaxf(hi[k], (&q->x)[c]);
                ++k;
            }
        }
        mm_db_rotation_track *t = &w->ranges[j];
        memset(t, 0, sizeof *t);
        t->dropped = (uint8_t)(d | (negative ? 4 : 0));
        w->rot_extent[j] = 0.0f;
        for (int k = 0; k < 3; ++k) {
            double a = floor(((double)lo[k] + 1.0) * 0.5 * 65535.0),
                   b = ceil(((double)hi[k] + 1.0) * 0.5 * 65535.0);
            a = a < 0 ? 0 : a > 65535 ? 65535 : a;
            b = b < a ? a : b > 65535 ? 65535 : b;
            t->lo[k] = (uint16_t)a;
            t->extent[k] = (uint16_t)(b - a);
            w->rot_extent[j] = fmaxf(w->rot_extent[j], mm__pose_extent_from_u16(t->extent[k]));
        }
    }
}

/* How far each joint's rotation moves points: its farthest descendant joint over the frames, plus
 * the shell distance (its own shell points, and theirs). */
static void joint_reach(const encode_job *job, scratch *w, int count)
{
    int jc = job->db->joint_count;
    for (int j = 0; j < jc; ++j) w->reach[j] = 0.0f;
    for (int f = 0; f < count; ++f) {
        const mm_xform *g = &w->reference[(size_t)f * jc];
        for (int k = 0; k < jc; ++k)
            for (int a = k; a >= 0; a = job->db->joints[a].parent)
                w->reach[a] = fmaxf(w->reach[a], mm_vec3_distance(g[k].translation, g[a].translation));
    }
    for (int j = 0; j < jc; ++j) w->reach[j] += job->shell;
}

/* Encodes the segment with the bits in w->bits; returns the largest joint error (m) and, in
 * *shell_error, the largest shell point error. */
static float encode_and_measure(const encode_job *job, scratch *w, segment_out *out, float *shell_error)
{
    int jc = job->db->joint_count, tc = job->translating_count;
    uint32_t frame_bits = 0;
    for (int j = 0; j < jc; ++j) {
        mm_db_rotation_track *t = &out->rot[j];
        *t = w->ranges[j];
        t->bits = w->bits[j];
        if (t->bits == MM_POSE_RAW_BITS) memset(t, 0, sizeof *t), t->bits = MM_POSE_RAW_BITS;
        if (t->bits == 0) memset(t->extent, 0, sizeof t->extent); /* every frame holds lo */
        frame_bits += mm__pose_rotation_frame_bits(t->bits);
    }
    for (int t = 0; t < tc; ++t) {
        mm_db_translation_track *tr = &out->trans[t];
        *tr = w->trans_ranges[t];
        tr->bits = w->bits[jc + t];
        if (tr->bits == MM_POSE_RAW_BITS) memset(tr, 0, sizeof *tr), tr->bits = MM_POSE_RAW_BITS;
        if (tr->bits == 0) memset(tr->extent, 0, sizeof tr->extent);
        frame_bits += mm__pose_translation_frame_bits(tr->bits);
    }
    size_t bytes = ((uint64_t)frame_bits * (uint64_t)out->count + 7u) / 8u;
    memset(w->bytes, 0, bytes + MM__POSE_BITS_TAIL);
    for (int f = 0; f < out->count; ++f) {
        uint64_t at = (uint64_t)f * frame_bits;
        for (int j = 0; j < jc; ++j) {
            const mm_db_rotation_track *t = &out->rot[j];
            const mm_quat *q = &w->rot[(size_t)f * jc + j];
            if (t->bits == MM_POSE_RAW_BITS) { /* the floats as they are, sign and all */
                q = &w->orig[(size_t)f * jc + j];
                for (int c = 0; c < 4; ++c, at += 32) write_bits(w->bytes, at, 32, bits_of_float((&q->x)[c]));
                continue;
            }
            for (int c = 0, k = 0; c < 4; ++c) {
                if (c == (t->dropped & 3)) continue;
                float lo = mm__pose_unit_from_u16(t->lo[k]), ext = mm__pose_extent_from_u16(t->extent[k]);
                write_bits(w->bytes, at, t->bits, quantize((&q->x)[c], lo, ext, t->bits));
                at += t->bits;
                ++k;
            }
        }
        for (int t = 0; t < tc; ++t) {
            const mm_db_translation_track *tr = &out->trans[t];
            const mm_vec3 *p = &w->pos[(size_t)f * jc + job->translating[t]];
            for (int c = 0; c < 3; ++c) {
                if (tr->bits == MM_POSE_RAW_BITS) {
                    write_bits(w->bytes, at, 32, bits_of_float((&p->x)[c]));
                    at += 32;
                } else {
                    write_bits(w->bytes, at, tr->bits,
                               quantize((&p->x)[c], tr->lo[c], tr->extent[c], tr->bits));
                    at += tr->bits;
                }
            }
        }
    }
    mm__pose_segment_view v = {jc,       tc,         job->translating, job->constants,
                               out->rot, out->trans, w->bytes,         frame_bits};
    float worst = 0.0f, worst_shell = 0.0f, s = job->shell;
    const mm_vec3 axes[3] = {mm_vec3_make(s, 0, 0), mm_vec3_make(0, s, 0), mm_vec3_make(0, 0, s)};
    for (int f = 0; f < out->count; ++f) {
        mm__pose_decode(&v, f, w->drot, w->dpos);
        mm_fk(&job->skeleton, w->drot, w->dpos, w->decoded);
        const mm_xform *ref = &w->reference[(size_t)f * jc];
        for (int j = 0; j < jc; ++j) {
            worst = fmaxf(worst, mm_vec3_distance(w->decoded[j].translation, ref[j].translation));
            for (int a = 0; a < 3; ++a)
                worst_shell =
                    fmaxf(worst_shell, mm_vec3_distance(mm_xform_apply_point(w->decoded[j], axes[a]),
                                                        mm_xform_apply_point(ref[j], axes[a])));
        }
    }
    out->frame_bits = frame_bits;
    out->byte_count = bytes;
    *shell_error = worst_shell;
    return worst;
}

static void encode_segment(const encode_job *job, scratch *w, segment_out *out)
{
    const mm_database *db = job->db;
    int jc = db->joint_count, tc = job->translating_count, n = out->count;
    for (int f = 0; f < n; ++f) {
        memcpy(&w->orig[(size_t)f * jc], mm_database_rotations(db, out->first + f),
               sizeof(mm_quat) * (size_t)jc);
        memcpy(&w->pos[(size_t)f * jc], mm_database_positions(db, out->first + f),
               sizeof(mm_vec3) * (size_t)jc);
        mm_fk(&job->skeleton, &w->orig[(size_t)f * jc], &w->pos[(size_t)f * jc],
              &w->reference[(size_t)f * jc]);
    }
    memcpy(w->rot, w->orig, sizeof(mm_quat) * (size_t)n * (size_t)jc);
    joint_reach(job, w, n);
    rotation_ranges(job, w, n);
    for (int t = 0; t < tc; ++t) {
        mm_db_translation_track *tr = &w->trans_ranges[t];
        memset(tr, 0, sizeof *tr);
        w->trans_extent[t] = 0.0f;
        for (int c = 0; c < 3; ++c) {
            float lo = INFINITY, hi = -INFINITY;
            for (int f = 0; f < n; ++f) {
                float v = (&w->pos[(size_t)f * jc + job->translating[t]].x)[c];
                lo = fminf(lo, v), hi = fmaxf(hi, v);
            }
            tr->lo[c] = lo;
            tr->extent[c] = hi - lo;
            w->trans_extent[t] = fmaxf(w->trans_extent[t], hi - lo);
        }
    }
    /* the estimate: a rotation step of e per kept component turns the joint by at most
     * 2 sqrt(3) e sqrt(1 + 1 / d^2) (d: the dropped component's least magnitude), moving points
     * at reach r by that times r; a translation step moves them sqrt(3) e; each joint of the longest
     * chain takes an equal share of the bound */
    float scale = MM__SCALE_FIRST;
    for (int trial = 0; trial < MM__SCALE_TRIES; ++trial, scale *= MM__SCALE_STEP) {
        float share = scale * job->bound / (float)job->depth;
        for (int j = 0; j < jc; ++j) {
            float d = fmaxf(w->dropped_min[j], 1e-3f);
            float gain = 2.0f * sqrtf(3.0f) * sqrtf(1.0f + 1.0f / (d * d)) * w->reach[j];
            int b = bits_for(w->rot_extent[j], gain, share, MM_POSE_ROTATION_BITS_MAX);
            w->bits[j] = (uint8_t)(b < 0 ? MM_POSE_RAW_BITS : b);
        }
        for (int t = 0; t < tc; ++t) {
            int b = bits_for(w->trans_extent[t], sqrtf(3.0f), share, MM_POSE_TRANSLATION_BITS_MAX);
            w->bits[jc + t] = (uint8_t)(b < 0 ? MM_POSE_RAW_BITS : b);
        }
        float shell_error, error = encode_and_measure(job, w, out, &shell_error);
        if (error <= job->bound && shell_error <= job->bound) {
            out->max_error = error;
            return;
        }
    }
    memset(w->bits, MM_POSE_RAW_BITS, (size_t)(jc + tc)); /* the floats, exactly */
    float shell_error;
    out->max_error = encode_and_measure(job, w, out, &shell_error);
}

typedef struct worker_ctx {
    encode_job *job;
} worker_ctx;

static void encode_worker(void *ctx, int worker, int workers)
{
    encode_job *job = ((worker_ctx *)ctx)->job;
    size_t jc = (size_t)job->db->joint_count, tc = (size_t)job->translating_count, per = (size_t)job->per;
    size_t max_bytes = per * (jc * 128u + tc * 96u) / 8u + 1u + MM__POSE_BITS_TAIL;
    scratch w;
    w.orig = malloc(sizeof(mm_quat) * per * jc);
    w.rot = malloc(sizeof(mm_quat) * per * jc);
    w.ranges = malloc(sizeof(mm_db_rotation_track) * jc);
    w.trans_ranges = malloc(sizeof(mm_db_translation_track) * (tc + 1));
    w.pos = malloc(sizeof(mm_vec3) * per * jc);
    w.reference = malloc(sizeof(mm_xform) * per * jc);
    w.decoded = malloc(sizeof(mm_xform) * jc);
    w.drot = malloc(sizeof(mm_quat) * jc);
    w.dpos = malloc(sizeof(mm_vec3) * jc);
    w.reach = malloc(sizeof(float) * jc);
    w.dropped_min = malloc(sizeof(float) * jc);
    w.rot_extent = malloc(sizeof(float) * jc);
    w.trans_extent = malloc(sizeof(float) * (tc + 1));
    w.bits = malloc(jc + tc);
    w.bytes = malloc(max_bytes);
    bool ok = w.orig && w.ranges && w.trans_ranges && w.rot && w.pos && w.reference && w.decoded && w.drot &&
              w.dpos && w.reach && w.dropped_min && w.rot_extent && w.trans_extent && w.bits && w.bytes;
    for (int s = worker; s < job->segment_count; s += workers) {
        segment_out *out = &job->segments[s];
        if (!ok) {
            out->result = MM_ERR_OUT_OF_MEMORY;
            continue;
        }
        encode_segment(job, &w, out);
        out->bytes = malloc(out->byte_count + MM__POSE_BITS_TAIL);
        if (!out->bytes) {
            out->result = MM_ERR_OUT_OF_MEMORY;
            continue;
        }
        memcpy(out->bytes, w.bytes, out->byte_count + MM__POSE_BITS_TAIL);
        out->result = MM_OK;
    }
    free(w.orig), free(w.ranges), free(w.trans_ranges), free(w.rot), free(w.pos), free(w.reference),
        free(w.decoded), free(w.drot), free(w.dpos);
    free(w.reach), free(w.dropped_min), free(w.rot_extent), free(w.trans_extent), free(w.bits), free(w.bytes);
}

mm_result mm_database_compress(const mm_database *db, const mm_db_compress_desc *desc, mm_database *out,
                               mm_error *err)
{
    if (out) memset(out, 0, sizeof *out);
    if (!db || !db->data || !out)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "compress: no database");
    if (db->pose_codec != MM_POSE_FLOATS)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0,
                            "compress: the database is compressed already");
    float bound = desc && desc->error_bound != 0.0f ? desc->error_bound : MM_POSE_ERROR_DEFAULT;
    int per = desc && desc->segment_frames ? desc->segment_frames : MM_POSE_SEGMENT_FRAMES_DEFAULT;
    int threads = desc && desc->threads > 1 ? desc->threads : 1;
    if (!(bound > 0.0f && bound <= MM__POSE_ERROR_BOUND_MAX))
        return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0,
                            "compress: error bound %g m out of range (above 0, at most %g m)", (double)bound,
                            (double)MM__POSE_ERROR_BOUND_MAX);
    if (per < 1 || per > MM_POSE_SEGMENT_FRAMES_MAX)
        return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0,
                            "compress: segment frames %d out of range (1 to %d)", per,
                            MM_POSE_SEGMENT_FRAMES_MAX);
    if (threads > MM_DB_MAX_THREADS) threads = MM_DB_MAX_THREADS;
    int jc = db->joint_count;
    encode_job job;
    memset(&job, 0, sizeof job);
    job.db = db;
    job.skeleton.joint_count = jc;
    job.skeleton.joints = (mm_joint *)(uintptr_t)db->joints; /* mm_fk only reads it */
    job.bound = bound;
    job.shell = MM_POSE_SHELL_DISTANCE;
    job.per = per;
    for (int j = 0; j < jc; ++j) {
        int depth = 1;
        for (int a = db->joints[j].parent; a >= 0; a = db->joints[a].parent) ++depth;
        job.depth = depth > job.depth ? depth : job.depth;
    }
    /* translating joints: those whose translation is not the same on every frame */
    int32_t *translating = malloc(sizeof(int32_t) * (size_t)jc);
    mm_vec3 *constants = calloc((size_t)jc, sizeof(mm_vec3));
    for (int c = 0; c < db->clip_count; ++c) job.segment_count += (db->clips[c].frame_count + per - 1) / per;
    job.segments = calloc((size_t)job.segment_count, sizeof(segment_out));
    mm_db_pose_segment *table = calloc((size_t)job.segment_count, sizeof(mm_db_pose_segment));
    mm_db_rotation_track *rot = calloc((size_t)job.segment_count * (size_t)jc, sizeof(mm_db_rotation_track));
    mm_db_translation_track *trans = NULL;
    uint8_t *stream = NULL;
    mm_result r = MM_OK;
    if (!translating || !constants || !job.segments || !table || !rot) {
        r = mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "compress: out of memory");
        goto done;
    }
    /* a joint whose translation varies less than this keeps one, the middle of its range: the
     * errors of every such joint of a chain together take at most 1 / (2 MM__CONSTANT_SHARE) of the
     * bound (0 for a bound no quantization meets: only exact constants) */
    float constant_range = bound / (MM__CONSTANT_SHARE * (float)job.depth);
    for (int j = 0; j < jc; ++j) {
        mm_vec3 lo = mm_database_positions(db, 0)[j], hi = lo;
        for (int f = 1; f < db->frame_count; ++f) {
            mm_vec3 p = mm_database_positions(db, f)[j];
            lo = mm_vec3_make(fminf(lo.x, p.x), fminf(lo.y, p.y), fminf(lo.z, p.z));
            hi = mm_vec3_make(fmaxf(hi.x, p.x), fmaxf(hi.y, p.y), fmaxf(hi.z, p.z));
        }
        mm_vec3 range = mm_vec3_sub(hi, lo);
        bool exact = range.x == 0.0f && range.y == 0.0f && range.z == 0.0f;
        if (!exact && !(fmaxf(range.x, fmaxf(range.y, range.z)) <= constant_range))
            translating[job.translating_count++] = j;
        else
            constants[j] = exact ? lo : mm_vec3_add(lo, mm_vec3_scale(range, 0.5f));
    }
    trans = calloc((size_t)job.segment_count * (size_t)(job.translating_count + 1),
                   sizeof(mm_db_translation_track));
    if (!trans) {
        r = mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "compress: out of memory");
        goto done;
    }
    job.translating = translating;
    job.constants = constants;
    for (int c = 0, s = 0; c < db->clip_count; ++c)
        for (int first = 0; first < db->clips[c].frame_count; first += per, ++s) {
            segment_out *o = &job.segments[s];
            o->first = db->clips[c].first_frame + first;
            o->count = db->clips[c].frame_count - first < per ? db->clips[c].frame_count - first : per;
            o->rot = rot + (size_t)s * (size_t)jc;
            o->trans = trans + (size_t)s * (size_t)job.translating_count;
        }
    worker_ctx ctx = {&job};
    mm_searcher_pool *pool = threads > 1 ? mm__pool_create(threads, NULL) : NULL;
    if (pool)
        mm__pool_run(pool, encode_worker, &ctx);
    else
        encode_worker(&ctx, 0, 1);
    mm__pool_destroy(pool);
    size_t total = 0;
    float max_error = 0.0f;
    for (int s = 0; s < job.segment_count; ++s) {
        if (job.segments[s].result != MM_OK) {
            r = mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "compress: out of memory");
            goto done;
        }
        if (total + job.segments[s].byte_count > UINT32_MAX) {
            r = mm_error_set(err, MM_ERR_LIMIT, 0, 0, "compress: the poses take more than 4 GiB");
            goto done;
        }
        table[s].first_frame = job.segments[s].first;
        table[s].frame_count = job.segments[s].count;
        table[s].data_offset = (uint32_t)total;
        table[s].frame_bits = job.segments[s].frame_bits;
        total += job.segments[s].byte_count;
        max_error = fmaxf(max_error, job.segments[s].max_error);
    }
    stream = calloc(total + MM__POSE_BITS_TAIL, 1);
    if (!stream) {
        r = mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "compress: out of memory");
        goto done;
    }
    for (int s = 0; s < job.segment_count; ++s)
        memcpy(stream + table[s].data_offset, job.segments[s].bytes, job.segments[s].byte_count);
    mm__db_parts p;
    mm__db_parts_of(db, &p);
    p.pose_codec = MM_POSE_SEGMENTS;
    p.pose_segment_frames = per;
    p.pose_segment_count = job.segment_count;
    p.pose_translating_count = job.translating_count;
    p.pose_error_bound = bound;
    p.pose_max_error = max_error;
    p.data[MM__SEC_ROTATIONS] = p.data[MM__SEC_POSITIONS] = NULL;
    p.size[MM__SEC_ROTATIONS] = p.size[MM__SEC_POSITIONS] = 0;
    p.data[MM__SEC_POSE_CONSTANTS] = constants;
    p.data[MM__SEC_POSE_TRANSLATING] = translating;
    p.data[MM__SEC_POSE_SEGMENTS] = table;
    p.data[MM__SEC_POSE_ROTATION_TRACKS] = rot;
    p.data[MM__SEC_POSE_TRANSLATION_TRACKS] = trans;
    p.data[MM__SEC_POSE_BITS] = stream;
    p.size[MM__SEC_POSE_BITS] = total + MM__POSE_BITS_TAIL;
    r = mm__db_pack(&p, desc ? desc->allocator : NULL, out, err);
done:
    if (job.segments)
        for (int s = 0; s < job.segment_count; ++s) free(job.segments[s].bytes);
    free(job.segments), free(table), free(rot), free(trans), free(stream), free(translating), free(constants);
    return r;
}
