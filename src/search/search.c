/* Search: the cost kernel, filters and favours, brute force, the exact bounding-box search, the
 * facing pre-filter, threads and batches. docs/search.md is the reference for the rules.
 *
 * Exactness: every frame's cost comes from one kernel (8 lanes, a fixed order of additions). The
 * exact search skips a box only when a lower bound of the cost of every frame in it, computed in
 * the tree's rotated coordinates and scaled down by 1 - 1e-5 (more than the float rounding of
 * either computation), exceeds the limit. Pass 1 finds the lowest cost; pass 2 finds the lowest
 * index whose cost is within 1e-6 of it. Both passes prune with the same bounds. */
#include <mm/search.h>

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "math_private.h"
#include "search/pool.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#define LANES                 8
#define TIE_TOLERANCE         1e-6f
#define CONTACT_PATTERNS_MASK 0xfu /* the four mm_contact_bits */
/* slots of the tree's coordinates, at most: the axes of both blocks, each padded to a multiple of 4 */
#define SEARCH_MAX_SLOTS (MM_SEARCH_MAX_DIMS + 8)
#define PREFETCH_STRIDE  64 /* bytes: a cache line */
/* The nearest-first phase of a descent evaluates at most this share of the frames (and this many
 * at least) before the rest is walked in memory order; it records at most MAX_SORTED_LEAVES. */
#define SORTED_BUDGET_PERCENT 5
#define SORTED_BUDGET_MIN     64
#define MAX_SORTED_LEAVES     512
/* After the nearest-first phase, a query whose limit leaves more than SCAN_SHARE_PERCENT of the
 * frames under the lanes SCAN_LEVELS node levels below the root (64 lanes of about 900 frames on
 * LAFAN1) scans the rest of the quantized copy in memory order instead of walking the tree: random
 * queries (90% and 97% measured alike; transition queries reach it rarely at 97%) */
#define SCAN_LEVELS        3
#define SCAN_SHARE_PERCENT 97
/* The quantized copy of the features: one byte per dimension, in blocks of QUANT_BLOCK positions
 * stored dimension by dimension (a block's codes of one dimension side by side, so that one SIMD
 * pass bounds the whole block); each dimension's grid spans its values but the QUANT_TAIL share at
 * either end (those take the end codes), located with a histogram of QUANT_BINS bins. Query weights
 * become 16-bit integers whose largest is QUANT_WEIGHT_MAX. */
#define QUANT_LEVELS     256
#define QUANT_BLOCK      16
#define QUANT_TAIL       0.0005
#define QUANT_BINS       4096
#define QUANT_WEIGHT_MAX 32767
#define QUANT_CHECK      8 /* slots between the checks whether a block's bounds all exceed the limit */
#define QUANT_HEAD       8 /* slots stored apart (the widest): all a far block's bound usually reads */
#define BEYOND_FAR_MAX                                                                                       \
    3800 /* steps beyond the grid counted: (far + 255)^2 stays below 2^24, exact in float */

const char *mm_search_method_name(mm_search_method m)
{
    switch (m) {
    case MM_SEARCH_BRUTE:
        return "brute";
    case MM_SEARCH_FAST:
        return "fast";
    case MM_SEARCH_FACING:
        return "facing";
    default:
        return NULL;
    }
}

/* ---- parameters and queries ------------------------------------------------------------- */

/* Index of a bone group's bone among the matched bones, in order of first appearance. */
static int bone_slot(const mm_database *db, int group)
{
    int bones[MM_MAX_MATCH_BONES], count = 0;
    for (int g = 0; g <= group; ++g) {
        const mm_feature_group *grp = &db->groups[g];
        if (grp->kind != MM_FEATURE_BONE_POSITION && grp->kind != MM_FEATURE_BONE_VELOCITY) continue;
        int b = 0;
        while (b < count && bones[b] != grp->bone) ++b;
        if (b == count && count < MM_MAX_MATCH_BONES) bones[count++] = grp->bone;
        if (g == group) return b < MM_MAX_MATCH_BONES ? b : MM_MAX_MATCH_BONES - 1;
    }
    return 0;
}

void mm_search_params_defaults(const mm_database *db, mm_search_params *p)
{
    memset(p, 0, sizeof *p);
    p->pose_trajectory_ratio = 0.5f;
    p->body_velocity_weight = 1.0f;
    p->position_multiplier = 1.0f;
    p->angle_multiplier = 1.0f;
    for (int b = 0; b < MM_MAX_MATCH_BONES; ++b)
        p->joint_position_weights[b] = p->joint_velocity_weights[b] = 1.0f;
    for (int g = 0; db && g < db->group_count; ++g) {
        const mm_feature_group *grp = &db->groups[g];
        switch (grp->kind) {
        case MM_FEATURE_BONE_POSITION:
            p->joint_position_weights[bone_slot(db, g)] = grp->weight;
            break;
        case MM_FEATURE_BONE_VELOCITY:
            p->joint_velocity_weights[bone_slot(db, g)] = grp->weight;
            break;
        case MM_FEATURE_ROOT_VELOCITY:
            p->body_velocity_weight = grp->weight;
            break;
        case MM_FEATURE_TRAJ_POSITION:
            p->position_multiplier = grp->weight;
            break;
        case MM_FEATURE_TRAJ_DIRECTION:
            p->angle_multiplier = grp->weight;
            break;
        }
    }
    p->next_pose_favour = 0.95f;
    p->loop_anim_favour = 1.0f;
    p->continuing_bias = 0.0f;
    p->contact_pattern = -1;
    p->contact_mismatch_favour = 1.0f;
    p->current_frame = -1;
    p->type = MM_SEARCH_ANY;
    p->facing_threshold = 1.0f;
}

uint64_t mm_search_tag_mask(const mm_database *db, const char *name)
{
    for (int t = 0; t < db->tag_count; ++t)
        if (strcmp(db->tag_names[t], name) == 0) return (uint64_t)1 << t;
    return 0;
}

static int is_pose_group(int kind)
{
    return kind == MM_FEATURE_BONE_POSITION || kind == MM_FEATURE_BONE_VELOCITY ||
           kind == MM_FEATURE_ROOT_VELOCITY;
}

void mm_search_query_from_frames(const mm_database *db, int pose_frame, int traj_frame, float *out)
{
    memset(out, 0, sizeof(float) * (size_t)db->dims_padded);
    const float *pose = db->features + (size_t)pose_frame * db->dims_padded;
    const float *traj = db->features + (size_t)traj_frame * db->dims_padded;
    for (int g = 0; g < db->group_count; ++g) {
        const mm_feature_group *grp = &db->groups[g];
        const float *src = is_pose_group(grp->kind) ? pose : traj;
        memcpy(out + grp->offset, src + grp->offset, sizeof(float) * (size_t)grp->dims);
    }
}

void mm_search_query_from_pose(const mm_database *db, const mm_pose_data *pose, float *out)
{
    memset(out, 0, sizeof(float) * (size_t)db->dims_padded);
    for (int g = 0; g < db->group_count; ++g) {
        const mm_feature_group *grp = &db->groups[g];
        mm_vec3 v = mm_vec3_make(0, 0, 0);
        int t = 0;
        switch (grp->kind) {
        case MM_FEATURE_BONE_POSITION:
            v = pose->bone_positions[bone_slot(db, g)];
            break;
        case MM_FEATURE_BONE_VELOCITY:
            v = pose->bone_velocities[bone_slot(db, g)];
            break;
        case MM_FEATURE_ROOT_VELOCITY:
            v = pose->root_velocity;
            break;
        default:
            while (t < pose->traj_count && pose->traj_times[t] != grp->time) ++t;
            if (t < pose->traj_count)
                v = grp->kind == MM_FEATURE_TRAJ_POSITION ? pose->traj_positions[t]
                                                          : pose->traj_directions[t];
            v = mm_vec3_make(v.x, v.z, 0); /* trajectory groups store x, z */
            break;
        }
        float raw[3] = {v.x, v.y, v.z};
        for (int d = 0; d < grp->dims; ++d) {
            int k = grp->offset + d;
            out[k] = (raw[d] - db->feature_mean[k]) / db->feature_scale[k];
        }
    }
}

/* Per-dimension weights of the cost; padding dimensions weigh 0. */
static void dimension_weights(const mm_database *db, const mm_search_params *p, float *w)
{
    memset(w, 0, sizeof(float) * (size_t)db->dims_padded);
    float r = p->pose_trajectory_ratio;
    if (!(r >= 0.0f)) r = 0.0f; /* also NaN */
    if (r > 1.0f) r = 1.0f;
    float pose = 2.0f * (1.0f - r), traj = 2.0f * r;
    int bones[MM_MAX_MATCH_BONES], bone_count = 0; /* bone_slot's order, built along the way */
    for (int g = 0; g < db->group_count; ++g) {
        const mm_feature_group *grp = &db->groups[g];
        float x = 0.0f;
        int slot = 0;
        if (grp->kind == MM_FEATURE_BONE_POSITION || grp->kind == MM_FEATURE_BONE_VELOCITY) {
            while (slot < bone_count && bones[slot] != grp->bone) ++slot;
            if (slot == bone_count && bone_count < MM_MAX_MATCH_BONES) bones[bone_count++] = grp->bone;
            if (slot >= MM_MAX_MATCH_BONES) slot = MM_MAX_MATCH_BONES - 1;
        }
        switch (grp->kind) {
        case MM_FEATURE_BONE_POSITION:
            x = pose * p->joint_position_weights[slot];
            break;
        case MM_FEATURE_BONE_VELOCITY:
            x = pose * p->joint_velocity_weights[slot];
            break;
        case MM_FEATURE_ROOT_VELOCITY:
            x = pose * p->body_velocity_weight;
            break;
        case MM_FEATURE_TRAJ_POSITION:
            x = traj * p->position_multiplier;
            break;
        case MM_FEATURE_TRAJ_DIRECTION:
            x = traj * p->angle_multiplier;
            break;
        }
        if (!(x >= 0.0f) || !isfinite(x)) x = 0.0f; /* negative or NaN weights count as 0 */
        for (int d = 0; d < grp->dims; ++d) w[grp->offset + d] = x;
    }
}

/* Which block of the tree's coordinates dimension d belongs to: the pose (bones and root velocity)
 * or the trajectory, whose weights the ratio scales apart; or none (padding, default weight 0). */
enum { BLOCK_POSE = 0, BLOCK_TRAJECTORY = 1, BLOCK_NONE = 2 };
static void dimension_blocks(const mm_database *db, const float *w0, unsigned char *block)
{
    for (int d = 0; d < db->dims_padded; ++d) block[d] = BLOCK_NONE;
    for (int g = 0; g < db->group_count; ++g) {
        const mm_feature_group *grp = &db->groups[g];
        for (int d = grp->offset; d < grp->offset + grp->dims; ++d)
            if (w0[d] > 0.0f) block[d] = is_pose_group(grp->kind) ? BLOCK_POSE : BLOCK_TRAJECTORY;
    }
}

void mm_search_cost_terms(const mm_database *db, const float *query, const mm_search_params *p, int frame,
                          mm_search_terms *out)
{
    memset(out, 0, sizeof *out);
    if (frame < 0 || frame >= db->frame_count || db->dims_padded > MM_SEARCH_MAX_DIMS) return;
    float w[MM_SEARCH_MAX_DIMS];
    dimension_weights(db, p, w);
    const float *x = db->features + (size_t)frame * db->dims_padded;
    for (int g = 0; g < db->group_count; ++g) {
        const mm_feature_group *grp = &db->groups[g];
        float sum = 0.0f;
        for (int d = grp->offset; d < grp->offset + grp->dims; ++d)
            sum += w[d] * (query[d] - x[d]) * (query[d] - x[d]);
        float *term = grp->kind == MM_FEATURE_BONE_POSITION   ? &out->pose_position
                      : grp->kind == MM_FEATURE_BONE_VELOCITY ? &out->pose_velocity
                      : grp->kind == MM_FEATURE_ROOT_VELOCITY ? &out->root_velocity
                      : grp->kind == MM_FEATURE_TRAJ_POSITION ? &out->traj_position
                                                              : &out->traj_direction;
        *term += sum;
    }
}

/* ---- kernels ---------------------------------------------------------------------------- */

/* Weighted squared distance, 8 lanes, fixed order: the same numbers whatever the compiler
 * vectorises (no contraction in ISO C mode). */
static inline float distance(const float *q, const float *x, const float *w, int dims)
{
    float acc[LANES] = {0};
    for (int d = 0; d < dims; d += LANES)
        for (int l = 0; l < LANES; ++l) {
            float t = q[d + l] - x[d + l];
            acc[l] += w[d + l] * (t * t);
        }
    return ((acc[0] + acc[4]) + (acc[1] + acc[5])) + ((acc[2] + acc[6]) + (acc[3] + acc[7]));
}

/* Lower bounds of the default-weight distance over the boxes of a node's lanes, in the tree's
 * coordinates (unit weights): per dimension the gap from q to [lo, hi], the lanes side by side.
 * The terms are non-negative, so any order of additions is within float rounding of the exact
 * sum, which the bound's factor 1 - 1e-5 covers. */
#if defined(__SSE2__) && MM_SEARCH_WIDTH == 4
static inline __m128 gap_sum(const float *q, const float *lo, const float *hi, int d0, int d1)
{
    __m128 acc[4] = {_mm_setzero_ps(), _mm_setzero_ps(), _mm_setzero_ps(), _mm_setzero_ps()};
    const __m128 zero = _mm_setzero_ps();
    for (int d = d0; d < d1; d += 4)
        for (int h = 0; h < 4; ++h) { /* d1 - d0 is a multiple of 4 */
            __m128 x = _mm_loadu_ps(q + (d + h) * 4);
            __m128 below = _mm_sub_ps(_mm_loadu_ps(lo + (d + h) * 4), x);
            __m128 above = _mm_sub_ps(x, _mm_loadu_ps(hi + (d + h) * 4));
            __m128 t = _mm_max_ps(_mm_max_ps(below, above), zero); /* at most one gap is positive */
            acc[h] = _mm_add_ps(acc[h], _mm_mul_ps(t, t));
        }
    return _mm_add_ps(_mm_add_ps(acc[0], acc[1]), _mm_add_ps(acc[2], acc[3]));
}
/* scale[0] x the pose slots' sum + scale[1] x the trajectory slots' */
static inline void lane_bounds(const float *q, const float *lo, const float *hi, int split, int dims,
                               const float *scale, float *out)
{
    __m128 pose = gap_sum(q, lo, hi, 0, split), traj = gap_sum(q, lo, hi, split, dims);
    _mm_storeu_ps(
        out, _mm_add_ps(_mm_mul_ps(pose, _mm_set1_ps(scale[0])), _mm_mul_ps(traj, _mm_set1_ps(scale[1]))));
}
#else
static inline void lane_bounds(const float *q, const float *lo, const float *hi, int split, int dims,
                               const float *scale, float *out)
{
    float acc[2][MM_SEARCH_WIDTH] = {{0}};
    for (int d = 0; d < dims; ++d)
        for (int l = 0; l < MM_SEARCH_WIDTH; ++l) {
            int i = d * MM_SEARCH_WIDTH + l;
            float below = lo[i] - q[i], above = q[i] - hi[i];
            float t = (below > 0.0f ? below : 0.0f) + (above > 0.0f ? above : 0.0f); /* one is 0 */
            acc[d >= split][l] += t * t;
        }
    for (int l = 0; l < MM_SEARCH_WIDTH; ++l) out[l] = scale[0] * acc[0][l] + scale[1] * acc[1][l];
}
#endif

/* The slots on which the query lies beyond the quantized grid by at least half a step: its code is
 * the end code `end` there, and a frame of code c != end is at least far + |end - c| - 1 steps from it
 * along the slot's dimension (far: the query's distance to the grid's end point in steps, rounded
 * down from half a step on; the frame within half a step of its code's point), further than the
 * in-grid gap |end - c| - 1 by far, and its term (far + |end - c| - 1)^2 w step^2 grows with the
 * cross term: it is taken here in float (far at most BEYOND_FAR_MAX, so the squared gap is exact),
 * times scale (the sum's unit: the slot's integer weight / 2^16, rounded down), truncated and
 * saturated at 65535, in place of the in-grid term (the slot's integer weight is then 0). A frame at
 * the end code may lie anywhere beyond it and gets nothing. */
typedef struct quant_beyond {
    int count;
    int16_t slot[MM_SEARCH_MAX_DIMS];
    int32_t end[MM_SEARCH_MAX_DIMS], far[MM_SEARCH_MAX_DIMS];
    float scale[MM_SEARCH_MAX_DIMS];
} quant_beyond;

/* The integer parts of the quantized bounds of the QUANT_BLOCK positions of a block: per slot j (a
 * dimension), g = max(|query code - code| - 1, 0) adds floor(g^2 weight_j / 2^16), in 16 bits
 * saturating (a saturated sum is still a lower bound). head: the block's codes of the first
 * head_slots slots, tail: those of the others (slot by slot, QUANT_BLOCK codes side by side); query
 * and weight: per slot, repeated per lane. Returns the mask of the positions whose sum is at most
 * thr, stopping early when none can be. */
#if defined(__SSE2__) && QUANT_BLOCK == 16
static inline unsigned quant_block_mask(const uint8_t *head, const uint8_t *tail, const uint8_t *query,
                                        const uint16_t *weight, int head_slots, int slots,
                                        const quant_beyond *beyond, uint16_t thr)
{
    const __m128i zero = _mm_setzero_si128(), one = _mm_set1_epi8(1), t = _mm_set1_epi16((short)thr);
    __m128i sum_lo = zero, sum_hi = zero;
    unsigned mask = 0xFFFF;
    for (int i = 0; i < beyond->count; ++i) { /* the slots where the query is beyond the grid */
        int j = beyond->slot[i];
        const uint8_t *codes =
            j < head_slots ? head + j * QUANT_BLOCK : tail + (j - head_slots) * QUANT_BLOCK;
        __m128i x = _mm_loadu_si128((const __m128i *)codes);
        __m128i x_lo = _mm_unpacklo_epi8(x, zero), x_hi = _mm_unpackhi_epi8(x, zero);
        const __m128i end = _mm_set1_epi32(beyond->end[i]), far = _mm_set1_epi32(beyond->far[i] - 1),
                      bias = _mm_set1_epi32(32768), flip = _mm_set1_epi16((short)0x8000);
        const __m128 scale = _mm_set1_ps(beyond->scale[i]), most = _mm_set1_ps(65535.0f);
        __m128i term[4];
        for (int h = 0; h < 4; ++h) { /* 4 frames each, as 32-bit integers */
            __m128i c = h < 2 ? (h ? _mm_unpackhi_epi16(x_lo, zero) : _mm_unpacklo_epi16(x_lo, zero))
                              : (h == 3 ? _mm_unpackhi_epi16(x_hi, zero) : _mm_unpacklo_epi16(x_hi, zero));
            __m128i d = _mm_sub_epi32(c, end), sign = _mm_srai_epi32(d, 31);
            __m128i gap = _mm_add_epi32(_mm_sub_epi32(_mm_xor_si128(d, sign), sign), far);
            gap = _mm_andnot_si128(_mm_cmpeq_epi32(c, end), gap);
            __m128 g = _mm_cvtepi32_ps(gap);
            __m128 v = _mm_min_ps(_mm_mul_ps(_mm_mul_ps(g, g), scale), most);
            term[h] = _mm_sub_epi32(_mm_cvttps_epi32(v), bias); /* packed with signed saturation */
        }
        sum_lo = _mm_adds_epu16(sum_lo, _mm_xor_si128(_mm_packs_epi32(term[0], term[1]), flip));
        sum_hi = _mm_adds_epu16(sum_hi, _mm_xor_si128(_mm_packs_epi32(term[2], term[3]), flip));
    }
    for (int j = 0; j < slots; ++j) {
        if (j % QUANT_CHECK == 0 && j > 0) { /* every sum already above thr: the rest cannot help */
            mask = (unsigned)_mm_movemask_epi8(
                _mm_packs_epi16(_mm_cmpeq_epi16(_mm_subs_epu16(sum_lo, t), zero),
                                _mm_cmpeq_epi16(_mm_subs_epu16(sum_hi, t), zero)));
            if (!mask) return 0;
        }
        const uint8_t *codes =
            j < head_slots ? head + j * QUANT_BLOCK : tail + (j - head_slots) * QUANT_BLOCK;
        __m128i x = _mm_loadu_si128((const __m128i *)codes);
        __m128i q = _mm_loadu_si128((const __m128i *)(query + j * QUANT_BLOCK));
        __m128i w = _mm_loadu_si128((const __m128i *)(weight + j * 8));
        __m128i gap = _mm_subs_epu8(_mm_or_si128(_mm_subs_epu8(x, q), _mm_subs_epu8(q, x)), one);
        __m128i lo = _mm_unpacklo_epi8(gap, zero), hi = _mm_unpackhi_epi8(gap, zero);
        sum_lo = _mm_adds_epu16(sum_lo, _mm_mulhi_epu16(_mm_mullo_epi16(lo, lo), w));
        sum_hi = _mm_adds_epu16(sum_hi, _mm_mulhi_epu16(_mm_mullo_epi16(hi, hi), w));
    }
    return (unsigned)_mm_movemask_epi8(_mm_packs_epi16(_mm_cmpeq_epi16(_mm_subs_epu16(sum_lo, t), zero),
                                                       _mm_cmpeq_epi16(_mm_subs_epu16(sum_hi, t), zero)));
}
#else
/* One frame's term of a slot where the query is beyond the grid (as quant_beyond says), in the
 * order of the SIMD kernels' operations. */
static inline uint32_t beyond_term(int code, int32_t end, int32_t far, float scale)
{
    if (code == end) return 0;
    float g = (float)((code > end ? code - end : end - code) + far - 1);
    float v = (g * g) * scale;
    return (uint32_t)(v < 65535.0f ? v : 65535.0f);
}

static inline unsigned quant_block_mask(const uint8_t *head, const uint8_t *tail, const uint8_t *query,
                                        const uint16_t *weight, int head_slots, int slots,
                                        const quant_beyond *beyond, uint16_t thr)
{
    unsigned mask = 0;
    for (int i = 0; i < QUANT_BLOCK; ++i) {
        uint32_t sum = 0;
        for (int k = 0; k < beyond->count; ++k) { /* the slots where the query is beyond the grid */
            int j = beyond->slot[k];
            const uint8_t *codes =
                j < head_slots ? head + j * QUANT_BLOCK : tail + (j - head_slots) * QUANT_BLOCK;
            sum += beyond_term(codes[i], beyond->end[k], beyond->far[k], beyond->scale[k]);
            if (sum > 0xFFFF) sum = 0xFFFF;
        }
        for (int j = 0; j < slots; ++j) {
            const uint8_t *codes =
                j < head_slots ? head + j * QUANT_BLOCK : tail + (j - head_slots) * QUANT_BLOCK;
            int x = codes[i], q = query[j * QUANT_BLOCK];
            int g = x > q ? x - q : q - x;
            g = g > 1 ? g - 1 : 0;
            sum += ((uint32_t)(g * g) * weight[j * 8]) >> 16;
            if (sum > 0xFFFF) sum = 0xFFFF;
        }
        if (sum <= thr) mask |= 1u << i;
    }
    return mask;
}
#endif

/* The kernels above in 256-bit registers, for a machine with AVX (the distance, the box bounds) and
 * AVX2 (the quantized bounds), chosen at run time (query_ctx.wide): each lane does the operations
 * of the 128-bit code in its order (AVX's arithmetic is IEEE's, without FMA nothing is fused, the
 * integer steps are exact), so the same floats, bounds and masks, on any machine. */
#if defined(MM_WIDE_KERNELS) && QUANT_BLOCK == 16 && LANES == 8 && MM_SEARCH_WIDTH == 4
#define SEARCH_WIDE_KERNELS 1
__attribute__((target("avx"))) static float distance_wide(const float *q, const float *x, const float *w,
                                                          int dims)
{
    __m256 acc = _mm256_setzero_ps();
    for (int d = 0; d < dims; d += LANES) {
        __m256 t = _mm256_sub_ps(_mm256_loadu_ps(q + d), _mm256_loadu_ps(x + d));
        acc = _mm256_add_ps(acc, _mm256_mul_ps(_mm256_loadu_ps(w + d), _mm256_mul_ps(t, t)));
    }
    /* ((acc[0] + acc[4]) + (acc[1] + acc[5])) + ((acc[2] + acc[6]) + (acc[3] + acc[7])) */
    __m128 s = _mm_add_ps(_mm256_castps256_ps128(acc), _mm256_extractf128_ps(acc, 1));
    float v[4];
    _mm_storeu_ps(v, s);
    return (v[0] + v[1]) + (v[2] + v[3]);
}

/* gap_sum's four accumulators, two to a register: h and h + 1 of each step side by side */
__attribute__((target("avx"))) static __m128 gap_sum_wide(const float *q, const float *lo, const float *hi,
                                                          int d0, int d1)
{
    __m256 acc01 = _mm256_setzero_ps(), acc23 = _mm256_setzero_ps();
    const __m256 zero = _mm256_setzero_ps();
    for (int d = d0; d < d1; d += 4) {
        __m256 x = _mm256_loadu_ps(q + d * 4);
        __m256 t = _mm256_max_ps(_mm256_max_ps(_mm256_sub_ps(_mm256_loadu_ps(lo + d * 4), x),
                                               _mm256_sub_ps(x, _mm256_loadu_ps(hi + d * 4))),
                                 zero);
        acc01 = _mm256_add_ps(acc01, _mm256_mul_ps(t, t));
        x = _mm256_loadu_ps(q + d * 4 + 8);
        t = _mm256_max_ps(_mm256_max_ps(_mm256_sub_ps(_mm256_loadu_ps(lo + d * 4 + 8), x),
                                        _mm256_sub_ps(x, _mm256_loadu_ps(hi + d * 4 + 8))),
                          zero);
        acc23 = _mm256_add_ps(acc23, _mm256_mul_ps(t, t));
    }
    /* (acc[0] + acc[1]) + (acc[2] + acc[3]) */
    return _mm_add_ps(_mm_add_ps(_mm256_castps256_ps128(acc01), _mm256_extractf128_ps(acc01, 1)),
                      _mm_add_ps(_mm256_castps256_ps128(acc23), _mm256_extractf128_ps(acc23, 1)));
}

__attribute__((target("avx"))) static void lane_bounds_wide(const float *q, const float *lo, const float *hi,
                                                            int split, int dims, const float *scale,
                                                            float *out)
{
    __m128 pose = gap_sum_wide(q, lo, hi, 0, split), traj = gap_sum_wide(q, lo, hi, split, dims);
    _mm_storeu_ps(
        out, _mm_add_ps(_mm_mul_ps(pose, _mm_set1_ps(scale[0])), _mm_mul_ps(traj, _mm_set1_ps(scale[1]))));
}

/* quant_block_mask with the block's 16 sums in one register of 16-bit lanes (the gap taken in 16
 * bits: |x - q| - 1 saturated at 0, the same integers as the bytes' saturating steps). */
__attribute__((target("avx2"))) static unsigned sums_at_most(__m256i sum, __m256i t)
{
    __m256i ok = _mm256_cmpeq_epi16(_mm256_subs_epu16(sum, t), _mm256_setzero_si256());
    return (unsigned)_mm_movemask_epi8(
        _mm_packs_epi16(_mm256_castsi256_si128(ok), _mm256_extracti128_si256(ok, 1)));
}

/* One slot's term added to the sums: codes and query the slot's 16 bytes, weight its 8 copies. */
__attribute__((target("avx2"))) static inline __m256i add_slot(__m256i sum, const uint8_t *codes,
                                                               const uint8_t *query, const uint16_t *weight)
{
    const __m256i one = _mm256_set1_epi16(1);
    __m256i x = _mm256_cvtepu8_epi16(_mm_loadu_si128((const __m128i *)codes));
    __m256i q = _mm256_cvtepu8_epi16(_mm_loadu_si128((const __m128i *)query));
    __m256i w = _mm256_broadcastsi128_si256(_mm_loadu_si128((const __m128i *)weight));
    __m256i gap = _mm256_subs_epu16(_mm256_abs_epi16(_mm256_sub_epi16(x, q)), one);
    return _mm256_adds_epu16(sum, _mm256_mulhi_epu16(_mm256_mullo_epi16(gap, gap), w));
}

__attribute__((target("avx2"))) static unsigned
quant_block_mask_wide(const uint8_t *head, const uint8_t *tail, const uint8_t *query, const uint16_t *weight,
                      int head_slots, int slots, const quant_beyond *beyond, uint16_t thr)
{
    const __m256i t = _mm256_set1_epi16((short)thr);
    __m256i sum = _mm256_setzero_si256();
    for (int i = 0; i < beyond->count; ++i) { /* the slots where the query is beyond the grid */
        int j = beyond->slot[i];
        const uint8_t *codes =
            j < head_slots ? head + j * QUANT_BLOCK : tail + (j - head_slots) * QUANT_BLOCK;
        const __m256i end = _mm256_set1_epi32(beyond->end[i]), far = _mm256_set1_epi32(beyond->far[i] - 1);
        const __m256 scale = _mm256_set1_ps(beyond->scale[i]), most = _mm256_set1_ps(65535.0f);
        __m256i term[2];
        for (int h = 0; h < 2; ++h) { /* 8 frames each, as 32-bit integers */
            __m256i c = _mm256_cvtepu8_epi32(_mm_loadl_epi64((const __m128i *)(codes + 8 * h)));
            __m256i gap = _mm256_add_epi32(_mm256_abs_epi32(_mm256_sub_epi32(c, end)), far);
            gap = _mm256_andnot_si256(_mm256_cmpeq_epi32(c, end), gap);
            __m256 g = _mm256_cvtepi32_ps(gap);
            __m256 v = _mm256_min_ps(_mm256_mul_ps(_mm256_mul_ps(g, g), scale), most);
            term[h] = _mm256_cvttps_epi32(v);
        }
        /* packus works within 128-bit halves: frames 0-3, 8-11, 4-7, 12-15, put back in order */
        __m256i packed = _mm256_permute4x64_epi64(_mm256_packus_epi32(term[0], term[1]), 0xD8);
        sum = _mm256_adds_epu16(sum, packed);
    }
    for (int j0 = 0; j0 < slots; j0 += QUANT_CHECK) {
        if (j0 > 0 && !sums_at_most(sum, t)) return 0; /* every sum already above thr */
        int j1 = j0 + QUANT_CHECK < slots ? j0 + QUANT_CHECK : slots;
        if (j1 - j0 == QUANT_CHECK && (j1 <= head_slots || j0 >= head_slots)) { /* one run of codes */
            const uint8_t *codes =
                j0 < head_slots ? head + j0 * QUANT_BLOCK : tail + (j0 - head_slots) * QUANT_BLOCK;
            for (int j = 0; j < QUANT_CHECK; ++j)
                sum = add_slot(sum, codes + j * QUANT_BLOCK, query + (j0 + j) * QUANT_BLOCK,
                               weight + (j0 + j) * 8);
        } else {
            for (int j = j0; j < j1; ++j)
                sum = add_slot(
                    sum, j < head_slots ? head + j * QUANT_BLOCK : tail + (j - head_slots) * QUANT_BLOCK,
                    query + j * QUANT_BLOCK, weight + j * 8);
        }
    }
    return sums_at_most(sum, t);
}
#endif

/* ---- one query -------------------------------------------------------------------------- */

typedef struct query_ctx {
    const mm_searcher *s;
    const mm_database *db;
    const float *q;
    const mm_search_params *p;
    mm_search_method method;
    float w[MM_SEARCH_MAX_DIMS];
    uint8_t types;                     /* accepted type bits */
    int current, next;                 /* -1 when none */
    float loop_lo;                     /* the smallest factor a frame of a loop clip can get */
    int contact_pattern;               /* the contact bits the favour compares with; -1: no favour */
    float contact_lo;                  /* the smallest factor a frame of other contacts can get */
    float query_facing[2], facing_cos; /* unit (x, z) of the query's furthest facing; cos(threshold) */
    float zq_lanes[SEARCH_MAX_SLOTS * MM_SEARCH_WIDTH]; /* the query in the tree's coordinates, each
                                                         * slot repeated per lane */
    float bound_scale[2]; /* rho (1 - 1e-5) of the pose and trajectory blocks: turn their box
                           * distances into a bound on the cost */
    int use_facing;
    /* the two phases of a descent: nearest first until sorted_budget frames are evaluated, then in
     * memory order (streaming), skipping the leaves the first phase scanned (their first positions,
     * scanned[0..scanned_count)) */
    int sorted_budget, streaming, scanned_count, skip_at;
    int32_t scanned[MAX_SORTED_LEAVES];
    int64_t scanned_span[MAX_SORTED_LEAVES]; /* the same leaves, begin << 32 | end */
    int touched; /* frames of the leaves scanned so far (what the nearest-first budget counts) */
    /* the quantized first pass: the query's codes and integer weights (quant_dims each), and the
     * factor turning their integer sum into a lower bound of the cost; off (use_quant 0) when the
     * query or its weights do not fit the grid (NaN, all weights 0) */
    int use_quant;
    float quant_scale;
    uint8_t quant_query[MM_SEARCH_MAX_DIMS * QUANT_BLOCK]; /* per slot, repeated per lane */
    uint16_t quant_weight[MM_SEARCH_MAX_DIMS * 8];
    quant_beyond quant_beyond;
    /* node_factor(flags) for flags 0-3, and node_contact_factor's values: 1 for nodes whose frames
     * all have contact_same (0 when there is no favour), contact_none when none has, contact_some
     * when some have */
    float loop_factor[4], contact_none, contact_some;
    unsigned contact_same;
    int wide;                      /* the 256-bit kernels (the machine has AVX2 and mm__wide_kernels is on) */
    int evaluated, boxes, bounded; /* work counters (single-threaded paths) */
} query_ctx;

/* The weighted distance of the query to the feature row x. */
static inline float query_distance(const query_ctx *c, const float *x)
{
#if defined(SEARCH_WIDE_KERNELS)
    if (c->wide) return distance_wide(c->q, x, c->w, c->db->dims_padded);
#endif
    return distance(c->q, x, c->w, c->db->dims_padded);
}

/* Whether frame f (of clip clip_index, with tags) is a candidate. */
static inline int accepted_with(const query_ctx *c, int f, int clip_index, uint64_t tags)
{
    const mm_database *db = c->db;
    const mm_db_clip *clip = &db->clips[clip_index];
    if (!(c->types & (1u << clip->type))) return 0;
    if ((tags & c->p->required_tags) != c->p->required_tags || (tags & c->p->excluded_tags)) return 0;
    if (c->current >= 0 && f != c->next && clip_index == db->frame_clip[c->current]) {
        int d = f - c->current;
        if (d < 0) d = -d;
        if (d <= (c->p->exclude_window > 0 ? c->p->exclude_window : 0)) return 0;
    }
    if (!clip->loop && c->p->end_margin > 0 && f >= clip->first_frame + clip->frame_count - c->p->end_margin)
        return 0;
    if (c->use_facing) { /* angle to the query's facing within the threshold: cos above its cosine */
        const float *d = c->s->facing + 2 * (size_t)f;
        if (d[0] * c->query_facing[0] + d[1] * c->query_facing[1] < c->facing_cos) return 0;
    }
    return 1;
}

static int accepted(const query_ctx *c, int f)
{
    return accepted_with(c, f, c->db->frame_clip[f], c->db->frame_tags[f]);
}

/* base after the favours of every frame (loop clips, contacts), in that order of products: frame f
 * of clip clip. */
static inline float favoured(const query_ctx *c, int f, int clip, float base)
{
    float cost = c->db->clips[clip].loop ? base * c->p->loop_anim_favour : base;
    if (c->contact_pattern >= 0 &&
        (c->db->contacts[f] & CONTACT_PATTERNS_MASK) != (unsigned)c->contact_pattern)
        cost *= c->contact_lo;
    return cost;
}

/* Cost after favours and bias of an accepted frame whose features are at x. */
static inline float frame_cost(query_ctx *c, int f, const float *x, float *base)
{
    const mm_database *db = c->db;
    ++c->evaluated;
    float b = query_distance(c, x);
    *base = b;
    float cost = favoured(c, f, db->frame_clip[f], b);
    if (f == c->next) cost = cost * c->p->next_pose_favour - c->p->continuing_bias;
    return cost;
}

static float at_most_one(float x) { return x < 1.0f ? x : 1.0f; }

/* Factor bounding from below what the loop favour can do to the frames of a node (the next frame
 * is handled on its own). flags: bit 0 some frame loops, bit 1 every frame loops. */
static float node_factor(const query_ctx *c, uint8_t flags)
{
    if (flags & 2) return c->loop_lo;
    if (flags & 1) return at_most_one(c->loop_lo);
    return 1.0f;
}

/* The same for the contact favour: patterns, bit p set when some frame of the node has contact
 * bits p. */
static float node_contact_factor(const query_ctx *c, uint16_t patterns)
{
    if (c->contact_pattern < 0) return 1.0f;
    unsigned same = 1u << c->contact_pattern;
    if (patterns == same) return 1.0f;            /* every frame has the pattern */
    if (!(patterns & same)) return c->contact_lo; /* none has it */
    return at_most_one(c->contact_lo);
}

/* node_contact_factor from the values prepare keeps. */
static inline float contact_factor(const query_ctx *c, uint16_t patterns)
{
    if (patterns == c->contact_same) return 1.0f;
    return patterns & c->contact_same ? c->contact_some : c->contact_none;
}

static float tie_limit(float lowest) { return lowest + TIE_TOLERANCE * fabsf(lowest); }

/* Whether some frame under lane l of node n can be a candidate (by type and tags). */
static inline int lane_possible(const query_ctx *c, const mm_search_node *n, int l)
{
    return (n->types[l] & c->types) && (n->tags_any[l] & c->p->required_tags) == c->p->required_tags &&
           !(n->tags_all[l] & c->p->excluded_tags);
}

/* z = basis^T (sqrt_w0 x - center): a point in the tree's coordinates, tree_dims slots (the sum
 * for each slot in the order of the components). */
static void rotate(const mm_searcher *s, const float *x, double *z)
{
    int dims = s->db->dims_padded, slots = s->tree_dims;
    double sum[SEARCH_MAX_SLOTS]; /* local: the loop vectorises (z might alias the basis) */
    for (int j = 0; j < slots; ++j) sum[j] = 0.0;
    for (int k = 0; k < dims; ++k) {
        double y = s->sqrt_w0[k] * (double)x[k] - s->center[k];
        if (y == 0.0) continue; /* padding: adds nothing */
        const double *axis = s->basis + (size_t)k * slots;
        for (int j = 0; j < slots; ++j) sum[j] += axis[j] * y;
    }
    memcpy(z, sum, sizeof(double) * (size_t)slots);
}

#if defined(SEARCH_WIDE_KERNELS)
/* rotate four slots at a time (the slots are a multiple of 4): each lane the same product and sum */
__attribute__((target("avx"))) static void rotate_wide(const mm_searcher *s, const float *x, double *z)
{
    int dims = s->db->dims_padded, slots = s->tree_dims;
    __m256d sum[SEARCH_MAX_SLOTS / 4];
    for (int j = 0; j < slots / 4; ++j) sum[j] = _mm256_setzero_pd();
    for (int k = 0; k < dims; ++k) {
        double y = s->sqrt_w0[k] * (double)x[k] - s->center[k];
        if (y == 0.0) continue; /* padding: adds nothing */
        const double *axis = s->basis + (size_t)k * slots;
        __m256d yy = _mm256_set1_pd(y);
        for (int j = 0; j < slots / 4; ++j)
            sum[j] = _mm256_add_pd(sum[j], _mm256_mul_pd(_mm256_loadu_pd(axis + 4 * j), yy));
    }
    for (int j = 0; j < slots / 4; ++j) _mm256_storeu_pd(z + 4 * j, sum[j]);
}
#endif

/* The query on the quantized grid, and its weights as integers. With g the gap in steps between
 * the query's code and a frame's, less one (half a step for the frame's rounding and half for the
 * query's; the end codes also stand for everything beyond, where the same gap holds), a frame's
 * distance along d is at least w_d step_d^2 g^2. The integer kernel sums
 * floor(g^2 quant_weight_d / 2^16), quant_weight_d = floor(w_d step_d^2 (1 - 1e-5) / unit), so that
 * sum x unit x 2^16 never exceeds the cost (1 - 1e-5 covers the rounding of the float kernel). */
static void prepare_quantized(query_ctx *c)
{
    const mm_searcher *s = c->s;
    c->use_quant = 0;
    if (!s->quantized) return;
    double largest = 0.0, term[MM_SEARCH_MAX_DIMS], beyond[MM_SEARCH_MAX_DIMS];
    for (int j = 0; j < s->quant_slots; ++j) {
        int d = s->quant_order[j];
        term[j] = (double)c->w[d] * s->quant_step[d] * s->quant_step[d];
        if (term[j] > largest) largest = term[j];
        double v = floor(((double)c->q[d] - s->quant_lo[d]) / s->quant_step[d] + 0.5);
        if (v != v) return; /* NaN: no bound */
        double below = s->quant_lo[d] - (double)c->q[d],
               above = (double)c->q[d] - (s->quant_lo[d] + (QUANT_LEVELS - 1) * s->quant_step[d]);
        beyond[j] = floor((below > above ? below : above) / s->quant_step[d] + 0.5); /* steps, rounded down
                                                                                      * from half a step */
        memset(c->quant_query + j * QUANT_BLOCK,
               (uint8_t)(v < 0.0                ? 0.0
                         : v > QUANT_LEVELS - 1 ? QUANT_LEVELS - 1
                                                : v),
               QUANT_BLOCK);
    }
    if (!(largest > 0.0) || !isfinite(largest)) return;
    double unit = largest / QUANT_WEIGHT_MAX;
    for (int j = 0; j < s->quant_slots; ++j) {
        double x = floor(term[j] * (1.0 - 1e-5) / unit);
        uint16_t weight = (uint16_t)(x < 0.0 ? 0.0 : x > QUANT_WEIGHT_MAX ? QUANT_WEIGHT_MAX : x);
        for (int l = 0; l < 8; ++l) c->quant_weight[j * 8 + l] = weight;
    }
    c->quant_beyond.count = 0;
    for (int j = 0; j < s->quant_slots; ++j) {
        if (!(beyond[j] >= 1.0) || c->quant_weight[j * 8] == 0) continue; /* in the grid, or weight 0 */
        quant_beyond *b = &c->quant_beyond;
        b->slot[b->count] = (int16_t)j;
        b->end[b->count] = c->quant_query[j * QUANT_BLOCK];
        b->far[b->count] = (int32_t)(beyond[j] < BEYOND_FAR_MAX ? beyond[j] : BEYOND_FAR_MAX);
        b->scale[b->count] = nextafterf((float)(c->quant_weight[j * 8] / 65536.0 * (1.0 - 1e-6)), 0.0f);
        ++b->count;
        for (int l = 0; l < 8; ++l) c->quant_weight[j * 8 + l] = 0; /* the term is taken above */
    }
    c->quant_scale = nextafterf((float)(unit * 65536.0 * (1.0 - 1e-6)), 0.0f);
    c->use_quant = 1;
}

static void prepare(query_ctx *c, const mm_searcher *s, const float *query, const mm_search_params *p,
                    mm_search_method method)
{
    const mm_database *db = s->db;
    c->s = s;
    c->db = db;
    c->q = query;
    c->p = p;
    c->method = method == MM_SEARCH_FAST || method == MM_SEARCH_FACING ? method : MM_SEARCH_BRUTE;
    dimension_weights(db, p, c->w);
    c->types = p->type == MM_SEARCH_LOCOMOTION ? 1u : p->type == MM_SEARCH_IDLE ? 2u : 3u;
    c->current = p->current_frame >= 0 && p->current_frame < db->frame_count ? p->current_frame : -1;
    c->next = c->current >= 0 ? db->frame_next[c->current] : -1;
    c->loop_lo = p->loop_anim_favour;
    if (!(c->loop_lo >= 0.0f)) c->loop_lo = 0.0f; /* a negative or NaN favour gives no bound */
    c->contact_pattern = p->contact_pattern >= 0 && p->contact_pattern <= (int)CONTACT_PATTERNS_MASK &&
                                 p->contact_mismatch_favour != 1.0f
                             ? p->contact_pattern
                             : -1; /* a factor of 1 changes no cost */
    c->contact_lo = p->contact_mismatch_favour;
    if (!(c->contact_lo >= 0.0f)) c->contact_lo = 0.0f; /* as the loop favour */
    c->use_facing = 0;
    for (int flags = 0; flags < 4; ++flags) c->loop_factor[flags] = node_factor(c, (uint8_t)flags);
    c->contact_same = c->contact_pattern >= 0 ? 1u << c->contact_pattern : 0u;
    c->contact_none = node_contact_factor(c, 0);
    c->contact_some = c->contact_pattern >= 0 ? at_most_one(c->contact_lo) : 1.0f;
#if defined(SEARCH_WIDE_KERNELS)
    c->wide = mm__wide_kernels() && __builtin_cpu_supports("avx2");
#else
    c->wide = 0;
#endif
    c->evaluated = c->boxes = c->bounded = c->touched = 0;
    c->sorted_budget = INT32_MAX; /* work units of a thread: nearest first throughout */
    c->streaming = c->scanned_count = c->skip_at = 0;

    /* The tree lives in rotated, default-weighted coordinates z = V^T (sqrt(w0) x - mean). There
     * |z(q) - z(x)|^2 is the cost with the default weights w0; for other weights the cost is at
     * least rho times that, rho = min over dimensions of w / w0. The factor 1 - 1e-5 covers float
     * rounding in the kernels (the boxes are widened by the rounding of the coordinates). */
    int dims = db->dims_padded;
    unsigned char block[MM_SEARCH_MAX_DIMS];
    dimension_blocks(db, s->w0, block);
    double rho[2] = {INFINITY, INFINITY}; /* pose, trajectory */
    for (int d = 0; d < dims; ++d)
        if (block[d] != BLOCK_NONE) {
            double r = (double)c->w[d] / s->w0[d];
            if (r < rho[block[d]]) rho[block[d]] = r;
        }
    for (int b = 0; b < 2; ++b) {
        if (!(rho[b] < INFINITY)) rho[b] = 0.0;
        c->bound_scale[b] = (float)(rho[b] * (1.0 - 1e-5));
    }
    double zq[SEARCH_MAX_SLOTS];
#if defined(SEARCH_WIDE_KERNELS)
    if (c->wide && s->tree_dims % 4 == 0)
        rotate_wide(s, query, zq);
    else
#endif
        rotate(s, query, zq);
    for (int j = 0; j < s->tree_dims; ++j)
        for (int l = 0; l < MM_SEARCH_WIDTH; ++l) c->zq_lanes[j * MM_SEARCH_WIDTH + l] = (float)zq[j];
    prepare_quantized(c);
    if (c->method == MM_SEARCH_FACING) {
        if (s->facing_group >= 0) {
            int o = db->groups[s->facing_group].offset;
            float x = query[o] * db->feature_scale[o] + db->feature_mean[o];
            float z = query[o + 1] * db->feature_scale[o + 1] + db->feature_mean[o + 1],
                  len = sqrtf(x * x + z * z);
            c->query_facing[0] = len > 1e-6f ? x / len : 0.0f;
            c->query_facing[1] = len > 1e-6f ? z / len : 1.0f;
            c->facing_cos = cosf(p->facing_threshold);
            c->use_facing = 1;
        }
        c->method = MM_SEARCH_FAST; /* the exact descent, with the pre-filter as one more rule */
    }
}

/* ---- the search state: lowest k, and the ties of the lowest ---------------------------------- */

#define MAX_TIES 16

typedef struct scan_state {
    mm_search_result *list; /* the k lowest (cost, index), in order */
    int k, count;
    /* k == 1: frames within the tie tolerance of the lowest so far (a frame within the tolerance
     * of the final lowest is always among them unless they overflowed) */
    mm_search_result ties[MAX_TIES];
    int tie_count, overflow;
    /* the fallback mode: the lowest frame index with a cost at or under first_limit */
    int find_first;
    float first_limit;
    mm_search_result first;
    float limit; /* limit_of(this state), kept as the state changes: the scans read it per frame */
    float cap;   /* k > 1: a cost the k-th lowest is known not to exceed (INFINITY: none) */
} scan_state;

/* The cost a frame must not exceed to matter: the fallback's limit, the tie limit of the lowest, or
 * the k-th lowest cost once k are kept. */
static float limit_of(const scan_state *st)
{
    if (st->find_first) return st->first_limit;
    if (st->k < 1) return INFINITY; /* k 0: a state that keeps no list */
    if (st->k == 1) return st->count < 1 ? INFINITY : tie_limit(st->list[0].cost);
    float kth = st->count < st->k ? INFINITY : st->list[st->k - 1].cost;
    return st->cap < kth ? st->cap : kth;
}

static inline float state_limit(const scan_state *st) { return st->limit; }

/* Keeps the k lowest (cost, index) in order; list has room for k. */
static void offer(mm_search_result *list, int k, int *count, int f, float cost, float base)
{
    int n = *count;
    if (n == k && !(cost < list[k - 1].cost || (cost == list[k - 1].cost && f < list[k - 1].frame))) return;
    int i = n < k ? n : k - 1;
    while (i > 0 && (cost < list[i - 1].cost || (cost == list[i - 1].cost && f < list[i - 1].frame))) {
        list[i] = list[i - 1];
        --i;
    }
    list[i].frame = f;
    list[i].cost = cost;
    list[i].base = base;
    if (n < k) *count = n + 1;
}

static void take(scan_state *st, int f, float cost, float base)
{
    if (st->find_first) {
        if (cost <= st->first_limit && (st->first.frame < 0 || f < st->first.frame)) {
            st->first.frame = f;
            st->first.cost = cost;
            st->first.base = base;
        }
        return;
    }
    float old_limit = state_limit(st);
    offer(st->list, st->k, &st->count, f, cost, base);
    st->limit = limit_of(st);
    if (st->k != 1) return;
    float limit = state_limit(st);
    if (limit < old_limit) { /* the lowest fell: drop ties no longer within reach */
        int n = 0;
        for (int i = 0; i < st->tie_count; ++i)
            if (st->ties[i].cost <= limit) st->ties[n++] = st->ties[i];
        st->tie_count = n;
    }
    if (cost <= limit) {
        if (st->tie_count < MAX_TIES) {
            st->ties[st->tie_count].frame = f;
            st->ties[st->tie_count].cost = cost;
            st->ties[st->tie_count].base = base;
            ++st->tie_count;
        } else {
            st->overflow = 1;
        }
    }
}

static void state_init(scan_state *st, mm_search_result *list, int k)
{
    memset(st, 0, sizeof *st);
    st->list = list;
    st->k = k;
    st->first.frame = -1;
    st->cap = INFINITY;
    st->limit = limit_of(st);
}

/* The fallback mode: the lowest frame index with a cost at or under limit. */
static void state_find_first(scan_state *st, float limit)
{
    st->find_first = 1;
    st->first_limit = limit;
    st->limit = limit_of(st);
}

/* ---- traversal ----------------------------------------------------------------------------
 * The searcher orders the frames by a tree of bounding boxes (median splits of the widest axis,
 * leaves of at most MM_SEARCH_LEAF frames, pairs of levels merged into nodes of up to four lanes)
 * and keeps their features in that order. Brute force and the facing filter walk the positions of
 * a node; the exact method bounds the lanes of a node in one pass, visits them nearest first and
 * skips a lane when its lower bound (times the smallest favour its frames can get) exceeds the
 * current limit. */

/* Distances of a run of consecutive feature rows, in a tight loop the compiler vectorises. */
static void run_distances(const query_ctx *c, const float *x, int count, float *out)
{
    int dims = c->db->dims_padded;
    for (int i = 0; i < count; ++i) out[i] = query_distance(c, x + (size_t)i * dims);
}

#define RUN 64 /* rows per run: distances first, then the rules for the few that can matter */

/* Row at (of the tree order, or of the database when order is NULL) with distance base: taken if
 * it is a candidate whose cost can enter the list or the ties. */
static inline void consider(query_ctx *c, const int32_t *order, const int32_t *clips, const uint64_t *tags,
                            int at, float base, float least_loop, float least_contact, scan_state *st)
{
    const mm_database *db = c->db;
    float limit = state_limit(st);
    /* the factors in the order of favoured: the product rounds below the cost */
    if (base * least_loop * least_contact > limit) return; /* cannot enter the list nor the ties */
    int f = order ? order[at] : at;
    int clip = clips ? clips[at] : db->frame_clip[f];
    if (f == c->next || !accepted_with(c, f, clip, tags ? tags[at] : db->frame_tags[f])) return;
    float cost = favoured(c, f, clip, base);
    if (cost > limit && !st->find_first) return;
    take(st, f, cost, base);
}

/* Rows [p0, p1) of the searcher's tree order, or of the database when order is NULL. */
static void scan_rows(query_ctx *c, const float *features, const int32_t *order, const int32_t *clips,
                      const uint64_t *tags, int p0, int p1, scan_state *st)
{
    const mm_database *db = c->db;
    int dims = db->dims_padded;
    /* no frame but the next one (handled apart) can cost less than its base times these (applied
     * in the order of favoured: the product rounds below the cost) */
    float least_loop = at_most_one(c->loop_lo),
          least_contact = c->contact_pattern >= 0 ? at_most_one(c->contact_lo) : 1.0f;
    float base[RUN];
    for (int p = p0; p < p1; p += RUN) {
        int n = p1 - p < RUN ? p1 - p : RUN;
        run_distances(c, features + (size_t)p * dims, n, base);
        c->evaluated += n;
        for (int i = 0; i < n; ++i)
            consider(c, order, clips, tags, p + i, base[i], least_loop, least_contact, st);
    }
}

/* The codes of block b's slots after the head ones. */
static inline const uint8_t *quant_tail(const mm_searcher *s, int b)
{
    size_t blocks = ((size_t)s->db->frame_count + QUANT_BLOCK - 1) / QUANT_BLOCK;
    return s->quantized +
           QUANT_BLOCK * (blocks * (size_t)s->quant_head + (size_t)b * (s->quant_slots - s->quant_head));
}

/* The largest integer sum of the quantized bound with which a frame can still reach limit (the
 * frames above it have a cost above limit; rounding errs towards keeping). */
static uint16_t quant_threshold(const query_ctx *c, float limit, float least)
{
    double t = (double)limit / ((double)c->quant_scale * least) * (1.0 + 1e-5) + 1.0;
    if (!(t < 65535.0)) return 65535; /* also NaN, and least 0 */
    return t < 0.0 ? 0 : (uint16_t)t;
}

/* Rows [p0, p1) of the tree order: the bounds of their blocks from the quantized copy first, the
 * exact cost only for the frames whose bound can reach the limit (the limit only falls, so the one
 * at the start of a block is safe for the block). */
static void scan_positions(query_ctx *c, int p0, int p1, scan_state *st)
{
    const mm_searcher *s = c->s;
    c->touched += p1 - p0;
    if (!c->use_quant) {
        scan_rows(c, s->features, s->order, s->order_clip, s->order_tags, p0, p1, st);
        return;
    }
    int dims = c->db->dims_padded;
    float least_loop = at_most_one(c->loop_lo),
          least_contact = c->contact_pattern >= 0 ? at_most_one(c->contact_lo) : 1.0f;
    float least = least_loop * least_contact; /* the threshold keeps a margin for its rounding */
    c->bounded += p1 - p0;
    float limit = state_limit(st);
    uint16_t thr = quant_threshold(c, limit, least);
    for (int block = p0 / QUANT_BLOCK; block * QUANT_BLOCK < p1; ++block) {
        int first = block * QUANT_BLOCK;
        if (state_limit(st) != limit) {
            limit = state_limit(st);
            thr = quant_threshold(c, limit, least);
        }
        int head = s->quant_head;
        const uint8_t *codes = s->quantized + (size_t)block * head * QUANT_BLOCK,
                      *tail = quant_tail(s, block);
#if defined(SEARCH_WIDE_KERNELS)
        unsigned mask = c->wide ? quant_block_mask_wide(codes, tail, c->quant_query, c->quant_weight, head,
                                                        s->quant_slots, &c->quant_beyond, thr)
                                : quant_block_mask(codes, tail, c->quant_query, c->quant_weight, head,
                                                   s->quant_slots, &c->quant_beyond, thr);
#else
        unsigned mask = quant_block_mask(codes, tail, c->quant_query, c->quant_weight, head, s->quant_slots,
                                         &c->quant_beyond, thr);
#endif
        if (first < p0) mask &= ~0u << (p0 - first);
        if (p1 - first < QUANT_BLOCK) mask &= (1u << (p1 - first)) - 1u;
        while (mask) {
            int at = first + __builtin_ctz(mask);
            mask &= mask - 1u;
            ++c->evaluated;
            float base = query_distance(c, s->features + (size_t)at * dims);
            consider(c, s->order, s->order_clip, s->order_tags, at, base, least_loop, least_contact, st);
        }
    }
}

/* The boxes of node n: its lanes' minima ([axis][lane]), then their maxima. */
static inline const float *node_boxes(const mm_searcher *s, int n)
{
    return s->boxes + (size_t)n * 2 * s->tree_dims * MM_SEARCH_WIDTH;
}

/* Bounds of the lanes of node n: the least cost any frame under a lane can have, favours
 * included (the next frame is handled on its own). */
static inline void node_bounds(query_ctx *c, int n, float *out)
{
    const mm_searcher *s = c->s;
    const mm_search_node *node = &s->nodes[n];
    const float *lo = node_boxes(s, n), *hi = lo + (size_t)s->tree_dims * MM_SEARCH_WIDTH;
#if defined(SEARCH_WIDE_KERNELS)
    if (c->wide)
        lane_bounds_wide(c->zq_lanes, lo, hi, s->pose_dims, s->tree_dims, c->bound_scale, out);
    else
#endif
        lane_bounds(c->zq_lanes, lo, hi, s->pose_dims, s->tree_dims, c->bound_scale, out);
    c->boxes += node->count;
    for (int l = 0; l < MM_SEARCH_WIDTH; ++l)
        out[l] = out[l] * c->loop_factor[node->loop[l] & 3] * contact_factor(c, node->contacts[l]);
}

static void visit_lane(query_ctx *c, int n, int l, float bound, scan_state *st);

/* Asks for the memory lane l of node n leads to (its node's boxes, or its frames' features) ahead
 * of the visit: the lanes after the first are visited later, so their loads overlap the first's
 * walk (with cold caches the tree's scattered reads otherwise wait on memory one by one). */
static inline void prefetch_lane(const query_ctx *c, const mm_search_node *node, int l)
{
#if defined(__GNUC__)
    const mm_searcher *s = c->s;
    const char *at, *end;
    if (node->child[l] >= 0) {
        __builtin_prefetch(&s->nodes[node->child[l]]);
        at = (const char *)node_boxes(s, node->child[l]);
        end = at + 2 * sizeof(float) * (size_t)s->tree_dims * MM_SEARCH_WIDTH;
    } else { /* the rows the leaf's first pass reads */
        size_t dims = (size_t)c->db->dims_padded;
        if (c->use_quant) { /* the head codes of its blocks */
            size_t head = (size_t)s->quant_head * QUANT_BLOCK;
            at = (const char *)s->quantized + head * (size_t)(node->begin[l] / QUANT_BLOCK);
            end = (const char *)s->quantized + head * (size_t)((node->end[l] - 1) / QUANT_BLOCK + 1);
        } else {
            at = (const char *)(s->features + dims * (size_t)node->begin[l]);
            end = (const char *)(s->features + dims * (size_t)node->end[l]);
        }
    }
    for (; at < end; at += PREFETCH_STRIDE) __builtin_prefetch(at);
#else
    (void)c, (void)node, (void)l;
#endif
}

/* Visits the lanes of node n whose frames can matter: nearest first, or in memory order once
 * streaming (the lanes that pass asked for ahead: they are read in turn). */
static void expand(query_ctx *c, int n, scan_state *st)
{
    const mm_search_node *node = &c->s->nodes[n];
    float bounds[MM_SEARCH_WIDTH];
    node_bounds(c, n, bounds);
    float limit = state_limit(st);
    int idx[MM_SEARCH_WIDTH], m = 0;
    for (int l = 0; l < node->count; ++l) { /* the lanes that can matter, by bound */
        if (bounds[l] > limit || !lane_possible(c, node, l)) continue;
        int i = m++;
        while (!c->streaming && i > 0 && bounds[idx[i - 1]] > bounds[l]) {
            idx[i] = idx[i - 1];
            --i;
        }
        idx[i] = l;
    }
    if (c->streaming)
        for (int i = 0; i < m; ++i) prefetch_lane(c, node, idx[i]);
    for (int i = 0; i < m; ++i) {
        visit_lane(c, n, idx[i], bounds[idx[i]], st);
        if (c->streaming < 0) return; /* the nearest-first phase is over */
    }
}

/* Visits lane l of node n, whose bound is known (the limit may have fallen since): its frames, or
 * its node's lanes. */
static void visit_lane(query_ctx *c, int n, int l, float bound, scan_state *st)
{
    const mm_search_node *node = &c->s->nodes[n];
    if (bound > state_limit(st)) return;
    if (st->find_first && st->first.frame >= 0 && node->min_frame[l] >= st->first.frame)
        return; /* cannot win */
    int begin = node->begin[l];
    if (node->child[l] >= 0) {
        expand(c, node->child[l], st);
        return;
    }
    if (c->streaming > 0) { /* skip the leaves the first phase scanned (met in the same order) */
        while (c->skip_at < c->scanned_count && c->scanned[c->skip_at] < begin) ++c->skip_at;
        if (c->skip_at < c->scanned_count && c->scanned[c->skip_at] == begin) return;
    } else if (c->sorted_budget < INT32_MAX) { /* in the nearest-first phase of a descent */
        if (c->touched >= c->sorted_budget || c->scanned_count == MAX_SORTED_LEAVES) {
            c->streaming = -1; /* unwind: the rest streams */
            return;
        }
        c->scanned_span[c->scanned_count] = (int64_t)begin << 32 | node->end[l];
        c->scanned[c->scanned_count++] = begin;
    }
    scan_positions(c, begin, node->end[l], st);
}

static int compare_positions(const void *a, const void *b)
{
    int32_t x = *(const int32_t *)a, y = *(const int32_t *)b;
    return (x > y) - (x < y);
}

static int compare_spans(const void *a, const void *b)
{
    int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
    return (x > y) - (x < y);
}

/* Frames under the lanes `levels` node levels below node n (or leaves above) whose bounds are at
 * most limit. */
static long admitted_below(query_ctx *c, int n, int levels, float limit)
{
    const mm_search_node *node = &c->s->nodes[n];
    float bounds[MM_SEARCH_WIDTH];
    node_bounds(c, n, bounds);
    long admitted = 0;
    for (int l = 0; l < node->count; ++l) {
        if (bounds[l] > limit) continue;
        admitted += node->child[l] < 0 || levels <= 1 ? node->end[l] - node->begin[l]
                                                      : admitted_below(c, node->child[l], levels - 1, limit);
    }
    return admitted;
}

/* After the nearest-first phase: whether the bounds will prune so little that scanning the rest of
 * the quantized copy in memory order costs less than walking the tree (the lanes SCAN_LEVELS node
 * levels below the root that the limit admits hold more than SCAN_SHARE_PERCENT of the frames). */
static int scan_pays(query_ctx *c, const scan_state *st)
{
    if (!c->use_quant) return 0;
    long admitted = admitted_below(c, 0, SCAN_LEVELS, state_limit(st));
    return admitted * 100 > (long)SCAN_SHARE_PERCENT * c->db->frame_count;
}

/* Every position of the tree order the nearest-first phase did not scan, in memory order through
 * the quantized copy: the leaves it scanned sorted, the runs between them scanned (each position
 * once). */
static void scan_rest(query_ctx *c, scan_state *st)
{
    qsort(c->scanned_span, (size_t)c->scanned_count, sizeof c->scanned_span[0], compare_spans);
    int at = 0;
    for (int i = 0; i <= c->scanned_count; ++i) {
        int begin = i < c->scanned_count ? (int)(c->scanned_span[i] >> 32) : c->db->frame_count;
        if (begin > at) scan_positions(c, at, begin, st);
        if (i < c->scanned_count) at = (int)(c->scanned_span[i] & 0xffffffff);
    }
}

/* The whole tree: nearest first (the lowest limit soonest) while that evaluates at most
 * sorted_budget frames; what it did not reach then in memory order, pruned by the same bounds.
 * Nearest-first visits are scattered in memory, and where the bounds prune little (queries far
 * from every frame) a walk that reads the tree and the features in order costs less; where they
 * prune almost nothing (scan_pays), the rest is scanned through the quantized copy in memory order,
 * without the tree. */
static void descend(query_ctx *c, scan_state *st)
{
    long budget = (long)c->db->frame_count * SORTED_BUDGET_PERCENT / 100;
    if (budget < SORTED_BUDGET_MIN) budget = SORTED_BUDGET_MIN;
    c->sorted_budget = (int)(c->touched + budget < INT32_MAX ? c->touched + budget : INT32_MAX);
    c->streaming = c->scanned_count = c->skip_at = 0;
    expand(c, 0, st);
    if (c->streaming != 0 && scan_pays(c, st)) {
        scan_rest(c, st);
    } else if (c->streaming != 0) {
        qsort(c->scanned, (size_t)c->scanned_count, sizeof c->scanned[0], compare_positions);
        c->streaming = 1;
        expand(c, 0, st);
    }
    c->sorted_budget = INT32_MAX;
    c->streaming = c->scanned_count = c->skip_at = 0;
}

/* Brute force and the facing filter: database frames [f0, f1) in order. */
static void scan_frames(query_ctx *c, int f0, int f1, scan_state *st)
{
    scan_rows(c, c->db->features, NULL, NULL, NULL, f0, f1, st);
}

/* Work units [u0, u1) of the searcher: for the exact method lanes of the tree, otherwise equal
 * runs of frames; one run of units per thread. All units: the whole tree from its root. */
static void scan_units(query_ctx *c, int u0, int u1, scan_state *st)
{
    const mm_searcher *s = c->s;
    if (c->method != MM_SEARCH_FAST) {
        long n = c->db->frame_count, units = s->unit_count;
        scan_frames(c, (int)(n * u0 / units), (int)(n * u1 / units), st);
        return;
    }
    if (u0 == 0 && u1 == s->unit_count) {
        descend(c, st);
        return;
    }
    for (int u = u0; u < u1; ++u) {
        int n = s->units[u] / MM_SEARCH_WIDTH, l = s->units[u] % MM_SEARCH_WIDTH;
        float bounds[MM_SEARCH_WIDTH];
        node_bounds(c, n, bounds);
        c->boxes -= s->nodes[n].count - 1; /* one lane's bound is used */
        if (lane_possible(c, &s->nodes[n], l)) visit_lane(c, n, l, bounds[l], st);
    }
}

/* The next frame competes on its own: favours and bias do not fit the node bounds. */
static void take_next(query_ctx *c, scan_state *st)
{
    if (c->next >= 0 && accepted(c, c->next)) {
        const mm_database *db = c->db;
        float base, cost = frame_cost(c, c->next, db->features + (size_t)c->next * db->dims_padded, &base);
        take(st, c->next, cost, base);
    }
}

/* The tie-rule winner among ties (lowest index within the limit), or frame -1. */
static mm_search_result winner_of(const mm_search_result *ties, int n, float limit)
{
    mm_search_result w = {-1, INFINITY, INFINITY};
    for (int i = 0; i < n; ++i)
        if (ties[i].cost <= limit && (w.frame < 0 || ties[i].frame < w.frame)) w = ties[i];
    return w;
}

/* The fallback when the ties did not fit: the lowest index at or under limit in units [u0, u1). */
static mm_search_result first_under(query_ctx *c, int u0, int u1, float limit, int with_next)
{
    scan_state st;
    state_init(&st, NULL, 0);
    state_find_first(&st, limit);
    if (with_next) take_next(c, &st);
    scan_units(c, u0, u1, &st);
    return st.first;
}

/* Puts w first in list (count entries), keeping the others in order. */
static void put_first(mm_search_result *list, int count, mm_search_result w)
{
    if (w.frame < 0 || count == 0 || list[0].frame == w.frame) return;
    int at = 0;
    while (at < count && list[at].frame != w.frame) ++at;
    if (at == count) at = count - 1; /* not among the k: it replaces the last */
    for (; at > 0; --at) list[at] = list[at - 1];
    list[0] = w;
}

/* k > 1: the k-th lowest cost among the distinct candidates of hints (INFINITY with fewer than k
 * of them). No candidate outside the best k costs less, so it bounds their k-th from above. */
static float hints_cap(query_ctx *c, const int *hints, int hint_count, int k)
{
    float kth[MM_SEARCH_MAX_HINTS];
    int n = 0;
    const mm_database *db = c->db;
    for (int i = 0; i < hint_count && i < MM_SEARCH_MAX_HINTS; ++i) {
        int f = hints[i], seen = 0;
        if (f < 0 || f >= db->frame_count || f == c->current || !accepted(c, f)) continue;
        for (int j = 0; j < i && !seen; ++j) seen = hints[j] == f;
        if (seen) continue;
        float base, cost = frame_cost(c, f, db->features + (size_t)f * db->dims_padded, &base);
        if (!(cost == cost)) continue; /* NaN: bounds nothing */
        int at;                        /* the k lowest, in order */
        if (n < k) {
            at = n++;
        } else {
            if (!(cost < kth[k - 1])) continue;
            at = k - 1;
        }
        while (at > 0 && cost < kth[at - 1]) kth[at] = kth[at - 1], --at;
        kth[at] = cost;
    }
    return k <= MM_SEARCH_MAX_HINTS && n >= k ? kth[k - 1] : INFINITY;
}

static int search_one(query_ctx *c, mm_search_result *results, int k, const int *hints, int hint_count)
{
    scan_state st;
    state_init(&st, results, k);
    if (k > 1 && hint_count > 0) {
        st.cap = hints_cap(c, hints, hint_count, k);
        st.limit = limit_of(&st);
    }
    take_next(c, &st);
    scan_units(c, 0, c->s->unit_count, &st);
    if (st.count == 0) return 0;
    float limit = tie_limit(results[0].cost);
    /* the tie-rule winner: among the ties kept (k 1), or among the k lowest when they hold every
     * frame within the tie limit (fewer than k found, or the k-th above it: the list is the k
     * lowest of all candidates); otherwise a second pass for the lowest index under the limit */
    mm_search_result w;
    if (k == 1)
        w = !st.overflow ? winner_of(st.ties, st.tie_count, limit)
                         : first_under(c, 0, c->s->unit_count, limit, 1);
    else if (st.count < k || results[k - 1].cost > limit)
        w = winner_of(results, st.count, limit);
    else
        w = first_under(c, 0, c->s->unit_count, limit, 1);
    put_first(results, st.count, w);
    return st.count;
}

/* ---- threads ---------------------------------------------------------------------------- */

typedef struct parallel_job {
    const query_ctx *c;
    query_ctx worker_ctx[MM_SEARCH_MAX_THREADS];
    scan_state state[MM_SEARCH_MAX_THREADS];
    mm_search_result lowest[MM_SEARCH_MAX_THREADS];
    mm_search_result first[MM_SEARCH_MAX_THREADS];
    float limit;
    int pass;
} parallel_job;

static void chunk(int n, int worker, int workers, int *a, int *b)
{
    *a = (int)((long)n * worker / workers);
    *b = (int)((long)n * (worker + 1) / workers);
}

static void parallel_pass(void *ctx, int worker, int workers)
{
    parallel_job *job = (parallel_job *)ctx;
    int a, b;
    chunk(job->c->s->unit_count, worker, workers, &a, &b);
    query_ctx *c = &job->worker_ctx[worker]; /* a private copy: the counters are written */
    *c = *job->c;
    if (job->pass == 1) {
        state_init(&job->state[worker], &job->lowest[worker], 1);
        scan_units(c, a, b, &job->state[worker]);
    } else {
        job->first[worker] = first_under(c, a, b, job->limit, 0);
    }
}

/* One query, k = 1, over the pool: each thread takes a run of work units; the results are
 * merged by the same rule, so they do not depend on the number of threads. */
static int search_parallel(const mm_searcher *s, query_ctx *c, mm_search_result *result)
{
    parallel_job *job = s->job;
    job->c = c;
    job->pass = 1;
    mm__pool_run(s->pool, parallel_pass, job);
    int workers = mm__pool_size(s->pool), overflow = 0;
    scan_state all;
    mm_search_result lowest;
    state_init(&all, &lowest, 1);
    take_next(c, &all);
    for (int t = 0; t < workers; ++t) {
        const scan_state *st = &job->state[t];
        for (int i = 0; i < st->tie_count; ++i)
            take(&all, st->ties[i].frame, st->ties[i].cost, st->ties[i].base);
        overflow |= st->overflow;
        c->evaluated += job->worker_ctx[t].evaluated;
        c->boxes += job->worker_ctx[t].boxes;
        c->bounded += job->worker_ctx[t].bounded;
    }
    if (all.count == 0) return 0;
    float limit = tie_limit(lowest.cost);
    mm_search_result w = winner_of(all.ties, all.tie_count, limit);
    if (overflow || all.overflow) {
        job->limit = limit;
        job->pass = 2;
        mm__pool_run(s->pool, parallel_pass, job);
        scan_state first;
        state_init(&first, NULL, 0);
        state_find_first(&first, limit);
        take_next(c, &first);
        for (int t = 0; t < workers; ++t)
            if (job->first[t].frame >= 0)
                take(&first, job->first[t].frame, job->first[t].cost, job->first[t].base);
        w = first.first;
    }
    *result = w;
    return w.frame >= 0;
}

int mm_searcher_search(const mm_searcher *s, const float *query, const mm_search_params *p,
                       mm_search_method method, mm_search_result *results, int k)
{
    return mm_searcher_search_hinted(s, query, p, method, results, k, NULL, 0, NULL);
}

int mm_searcher_search_stats(const mm_searcher *s, const float *query, const mm_search_params *p,
                             mm_search_method method, mm_search_result *results, int k,
                             mm_search_stats *stats)
{
    return mm_searcher_search_hinted(s, query, p, method, results, k, NULL, 0, stats);
}

int mm_searcher_search_hinted(const mm_searcher *s, const float *query, const mm_search_params *p,
                              mm_search_method method, mm_search_result *results, int k, const int *hints,
                              int hint_count, mm_search_stats *stats)
{
    if (stats) memset(stats, 0, sizeof *stats);
    if (!s || !s->db || !query || !p || !results || k < 1) return 0;
    for (int i = 0; i < k; ++i) {
        results[i].frame = -1;
        results[i].cost = results[i].base = INFINITY;
    }
    query_ctx c;
    prepare(&c, s, query, p, method);
    int found = k > 1 || !s->pool ? search_one(&c, results, k, hints, hints ? hint_count : 0)
                                  : search_parallel(s, &c, results);
    if (stats) {
        stats->frames_evaluated = c.evaluated;
        stats->boxes_tested = c.boxes;
        stats->frames_bounded = c.bounded;
    }
    return found;
}

typedef struct batch_job {
    const mm_searcher *s;
    const float *queries;
    const mm_search_params *params;
    int params_stride, count;
    mm_search_method method;
    mm_search_result *results;
} batch_job;

static void batch_worker(void *ctx, int worker, int workers)
{
    batch_job *job = (batch_job *)ctx;
    int a, b;
    chunk(job->count, worker, workers, &a, &b);
    const mm_database *db = job->s->db;
    for (int i = a; i < b; ++i) {
        query_ctx c;
        prepare(&c, job->s, job->queries + (size_t)i * db->dims_padded,
                job->params + (size_t)i * job->params_stride, job->method);
        mm_search_result *r = &job->results[i];
        r->frame = -1;
        r->cost = r->base = INFINITY;
        search_one(&c, r, 1, NULL, 0);
    }
}

void mm_searcher_batch(const mm_searcher *s, const float *queries, const mm_search_params *params,
                       int params_stride, mm_search_method method, mm_search_result *results, int count)
{
    if (!s || !queries || !params || !results || count < 1) return;
    batch_job job = {s, queries, params, params_stride ? 1 : 0, count, method, results};
    mm__pool_run(s->pool, batch_worker, &job);
}

/* ---- building the tree ------------------------------------------------------------------ */

/* The builder's binary tree, collapsed into the searcher's wide tree at the end. */
typedef struct bin_node {
    int32_t begin, end, left, right, min_frame, depth, height;
    uint8_t types, loop;
    uint16_t contacts; /* bit p: some frame has contact bits p */
    uint64_t tags_any, tags_all;
} bin_node;

typedef struct builder {
    mm_searcher *s;
    const mm_database *db;
    int dims, node_count, wide_count;
    const float *coords; /* [frames x dims] the frames in the tree's coordinates */
    float margin;        /* boxes are widened by this: the rounding of the coordinates */
    bin_node *bin;       /* the binary tree, with boxes bin_min / bin_max (dims floats each) */
    float *bin_min, *bin_max;
} builder;

/* Partially orders order[a..b) so the element of rank m (by feature d, then frame index) is at
 * m, smaller before, larger after: a deterministic quickselect (middle pivot). */
static float key(const builder *b, int f, int d) { return b->coords[(size_t)f * b->dims + d]; }
static int before(const builder *b, int f, int g, int d)
{
    float x = key(b, f, d), y = key(b, g, d);
    return x < y || (x == y && f < g);
}
static void select_rank(const builder *b, int *order, int lo, int hi, int m, int d)
{
    while (hi - lo > 1) {
        int pivot = order[lo + (hi - lo) / 2], i = lo, j = hi - 1;
        while (i <= j) {
            while (before(b, order[i], pivot, d)) ++i;
            while (before(b, pivot, order[j], d)) --j;
            if (i <= j) {
                int t = order[i];
                order[i] = order[j];
                order[j] = t;
                ++i;
                --j;
            }
        }
        if (m <= j)
            hi = j + 1;
        else if (m >= i)
            lo = i;
        else
            return;
    }
}

static int build_node(builder *b, int begin, int end, int depth)
{
    mm_searcher *s = b->s;
    const mm_database *db = b->db;
    int n = b->node_count++, dims = b->dims;
    bin_node *node = &b->bin[n];
    memset(node, 0, sizeof *node);
    node->begin = begin;
    node->end = end;
    node->left = node->right = -1;
    node->depth = depth;
    node->min_frame = db->frame_count;
    node->tags_all = ~(uint64_t)0;
    node->loop = 2;
    float *lo = b->bin_min + (size_t)n * dims, *hi = b->bin_max + (size_t)n * dims;
    for (int d = 0; d < dims; ++d) {
        lo[d] = INFINITY;
        hi[d] = -INFINITY;
    }
    for (int i = begin; i < end; ++i) {
        int f = s->order[i];
        const float *x = b->coords + (size_t)f * dims;
        for (int d = 0; d < dims; ++d) {
            lo[d] = x[d] < lo[d] ? x[d] : lo[d];
            hi[d] = x[d] > hi[d] ? x[d] : hi[d];
        }
        const mm_db_clip *clip = &db->clips[db->frame_clip[f]];
        node->types |= (uint8_t)(1u << clip->type);
        node->tags_any |= db->frame_tags[f];
        node->tags_all &= db->frame_tags[f];
        node->loop = (uint8_t)(clip->loop ? (node->loop | 1) : (node->loop & 1));
        node->contacts |= (uint16_t)(1u << (db->contacts[f] & CONTACT_PATTERNS_MASK));
        if (f < node->min_frame) node->min_frame = f;
    }
    for (int d = 0; d < dims; ++d) {
        lo[d] -= b->margin;
        hi[d] += b->margin;
    }
    if (end - begin <= MM_SEARCH_LEAF) return n;
    int split = 0;
    double widest = -1.0;
    for (int d = 0; d < dims; ++d) {
        double sum = 0, sq = 0;
        for (int i = begin; i < end; ++i) {
            double v = b->coords[(size_t)s->order[i] * dims + d];
            sum += v;
            sq += v * v;
        }
        double mean = sum / (end - begin), var = sq / (end - begin) - mean * mean;
        if (var > widest) {
            widest = var;
            split = d;
        }
    }
    /* near the median, on a boundary of the quantized copy's blocks (so that leaves are whole blocks) */
    int mid = (begin + (end - begin) / 2 + QUANT_BLOCK / 2) / QUANT_BLOCK * QUANT_BLOCK;
    if (mid <= begin || mid >= end) mid = begin + (end - begin) / 2;
    select_rank(b, s->order, begin, end, mid, split);
    int left = build_node(b, begin, mid, depth + 1);
    int right = build_node(b, mid, end, depth + 1);
    b->bin[n].left = left;
    b->bin[n].right = right;
    int h = b->bin[left].height > b->bin[right].height ? b->bin[left].height : b->bin[right].height;
    b->bin[n].height = h + 1;
    return n;
}

/* The lanes of binary node n in the wide tree: its grandchildren, except where a child is a leaf
 * or of even height (those stay lanes themselves, so that the nodes just above the leaves have
 * four leaves each). A leaf root is its own single lane. */
static int lanes_of(const builder *b, int n, int *lanes)
{
    const bin_node *node = &b->bin[n];
    if (node->left < 0) {
        lanes[0] = n;
        return 1;
    }
    int count = 0, children[2] = {node->left, node->right};
    for (int i = 0; i < 2; ++i) {
        const bin_node *c = &b->bin[children[i]];
        if (c->left < 0 || c->height % 2 == 0) {
            lanes[count++] = children[i];
        } else {
            lanes[count++] = c->left;
            lanes[count++] = c->right;
        }
    }
    return count;
}

static int count_wide(const builder *b, int n)
{
    int lanes[MM_SEARCH_WIDTH], count = lanes_of(b, n, lanes), total = 1;
    for (int l = 0; l < count; ++l)
        if (b->bin[lanes[l]].left >= 0) total += count_wide(b, lanes[l]);
    return total;
}

/* Makes the wide node of binary node n (and those below) and lists the work units in it (unless
 * it is inside one already); returns its index. */
static int make_wide(builder *b, int n, int in_unit)
{
    mm_searcher *s = b->s;
    int w = b->wide_count++, dims = s->tree_dims;
    int lanes[MM_SEARCH_WIDTH], count = lanes_of(b, n, lanes);
    mm_search_node *node = &s->nodes[w];
    memset(node, 0, sizeof *node);
    node->count = count;
    float *lo = s->boxes + (size_t)w * 2 * dims * MM_SEARCH_WIDTH, *hi = lo + (size_t)dims * MM_SEARCH_WIDTH;
    for (int l = 0; l < MM_SEARCH_WIDTH; ++l) {
        node->child[l] = -1;
        for (int d = 0; d < dims; ++d) /* unused lanes: empty boxes (never visited: count) */
            lo[d * MM_SEARCH_WIDTH + l] = hi[d * MM_SEARCH_WIDTH + l] = INFINITY;
    }
    for (int l = 0; l < count; ++l) {
        const bin_node *x = &b->bin[lanes[l]];
        node->begin[l] = x->begin;
        node->end[l] = x->end;
        node->min_frame[l] = x->min_frame;
        node->tags_any[l] = x->tags_any;
        node->tags_all[l] = x->tags_all;
        node->types[l] = x->types;
        node->loop[l] = x->loop;
        node->contacts[l] = x->contacts;
        for (int d = 0; d < dims; ++d) {
            lo[d * MM_SEARCH_WIDTH + l] = b->bin_min[(size_t)lanes[l] * b->dims + d];
            hi[d * MM_SEARCH_WIDTH + l] = b->bin_max[(size_t)lanes[l] * b->dims + d];
        }
    }
    for (int l = 0; l < count; ++l) {
        const bin_node *x = &b->bin[lanes[l]];
        /* work units: the first lanes at depth MM_SEARCH_UNIT_DEPTH or deeper, and leaves above */
        int unit = !in_unit && (x->left < 0 || x->depth >= MM_SEARCH_UNIT_DEPTH);
        if (unit) s->units[s->unit_count++] = w * MM_SEARCH_WIDTH + l;
        if (x->left >= 0) {
            int child = make_wide(b, lanes[l], in_unit || unit);
            s->nodes[w].child[l] = child;
        }
    }
    return w;
}

/* Principal axes of the default-weighted features, the pose and the trajectory blocks apart
 * (cyclic Jacobi on their covariance, the entries between blocks zeroed: each axis mixes the
 * dimensions of one block only, so that a bound can weigh the two blocks by their own ratio of
 * weights). Fills s->sqrt_w0, s->center, s->basis (column j: the axis of slot j), s->pose_dims and
 * s->tree_dims: the pose axes by decreasing variance, zero columns up to a multiple of 4, then the
 * trajectory axes the same way. cov and v are scratch of dims x dims. */
static void principal_axes(const mm_database *db, mm_searcher *s, double *cov, double *v)
{
    int n = db->dims_padded;
    unsigned char block[MM_SEARCH_MAX_DIMS];
    dimension_blocks(db, s->w0, block);
    for (int d = 0; d < n; ++d) s->sqrt_w0[d] = sqrtf(s->w0[d]);
    for (int d = 0; d < n; ++d) s->center[d] = 0.0;
    for (int f = 0; f < db->frame_count; ++f)
        for (int d = 0; d < n; ++d) s->center[d] += s->sqrt_w0[d] * (double)db->features[(size_t)f * n + d];
    for (int d = 0; d < n; ++d) s->center[d] /= db->frame_count;
    memset(cov, 0, sizeof(double) * (size_t)n * n);
    for (int f = 0; f < db->frame_count; ++f) {
        const float *x = db->features + (size_t)f * n;
        for (int i = 0; i < n; ++i) {
            double yi = s->sqrt_w0[i] * (double)x[i] - s->center[i];
            for (int j = i; j < n; ++j)
                if (block[i] == block[j] && block[i] != BLOCK_NONE)
                    cov[i * n + j] += yi * (s->sqrt_w0[j] * (double)x[j] - s->center[j]);
        }
    }
    for (int i = 0; i < n; ++i)
        for (int j = i; j < n; ++j) cov[j * n + i] = cov[i * n + j] /= db->frame_count;
    for (int i = 0; i < n * n; ++i) v[i] = 0.0;
    for (int i = 0; i < n; ++i) v[i * n + i] = 1.0;
    for (int sweep = 0; sweep < 64; ++sweep) {
        double off = 0.0, total = 0.0;
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) {
                total += cov[i * n + j] * cov[i * n + j];
                if (i != j) off += cov[i * n + j] * cov[i * n + j];
            }
        if (off <= 1e-24 * total || off == 0.0) break;
        for (int p = 0; p < n - 1; ++p)
            for (int q = p + 1; q < n; ++q) {
                double apq = cov[p * n + q]; /* 0 between blocks: they never mix */
                if (fabs(apq) < 1e-300) continue;
                double theta = (cov[q * n + q] - cov[p * n + p]) / (2.0 * apq);
                double t = (theta >= 0.0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1.0));
                double c = 1.0 / sqrt(t * t + 1.0), sn = t * c;
                for (int k = 0; k < n; ++k) { /* columns p and q */
                    double kp = cov[k * n + p], kq = cov[k * n + q];
                    cov[k * n + p] = c * kp - sn * kq;
                    cov[k * n + q] = sn * kp + c * kq;
                }
                for (int k = 0; k < n; ++k) { /* rows p and q */
                    double pk = cov[p * n + k], qk = cov[q * n + k];
                    cov[p * n + k] = c * pk - sn * qk;
                    cov[q * n + k] = sn * pk + c * qk;
                }
                for (int k = 0; k < n; ++k) {
                    double kp = v[k * n + p], kq = v[k * n + q];
                    v[k * n + p] = c * kp - sn * kq;
                    v[k * n + q] = sn * kp + c * kq;
                }
            }
    }
    /* the block of each axis (that of its components: one block per axis) */
    unsigned char axis_block[MM_SEARCH_MAX_DIMS];
    for (int j = 0; j < n; ++j) {
        axis_block[j] = BLOCK_NONE;
        for (int k = 0; k < n && axis_block[j] == BLOCK_NONE; ++k)
            if (block[k] != BLOCK_NONE && v[k * n + j] != 0.0) axis_block[j] = block[k];
    }
    /* slots: each block's axes by decreasing variance, then zero columns (-1) to a multiple of 4 */
    int slots = 0, slot_axis[SEARCH_MAX_SLOTS];
    unsigned char taken[MM_SEARCH_MAX_DIMS] = {0};
    for (int b = BLOCK_POSE; b <= BLOCK_TRAJECTORY; ++b) {
        for (;;) {
            int best = -1;
            for (int j = 0; j < n; ++j)
                if (!taken[j] && axis_block[j] == b && (best < 0 || cov[j * n + j] > cov[best * n + best]))
                    best = j;
            if (best < 0) break;
            taken[best] = 1;
            slot_axis[slots++] = best;
        }
        while (slots % 4 || (b == BLOCK_TRAJECTORY && slots == 0)) slot_axis[slots++] = -1;
        if (b == BLOCK_POSE) s->pose_dims = slots;
    }
    s->tree_dims = slots;
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < slots; ++j)
            s->basis[(size_t)k * slots + j] = slot_axis[j] >= 0 ? v[k * n + slot_axis[j]] : 0.0;
}

/* The quantized copy of the features (in tree order, already in s->features): per dimension a
 * grid of QUANT_LEVELS codes from the QUANT_TAIL quantile to the 1 - QUANT_TAIL one (the values
 * beyond take the end codes), each value coded to the nearest point. hist: QUANT_BINS counters. */
static void quantize_features(mm_searcher *s, uint32_t *hist)
{
    size_t frames = (size_t)s->db->frame_count;
    int dims = s->db->dims_padded;
    size_t blocks = (frames + QUANT_BLOCK - 1) / QUANT_BLOCK;
    double tail = QUANT_TAIL * (double)frames, spread[MM_SEARCH_MAX_DIMS];
    s->quant_slots = 0;
    for (int d = 0; d < dims; ++d) {
        double lo = INFINITY, hi = -INFINITY, sum = 0.0, sq = 0.0;
        for (size_t i = 0; i < frames; ++i) {
            double x = s->features[i * dims + d];
            lo = x < lo ? x : lo;
            hi = x > hi ? x : hi;
            sum += x;
            sq += x * x;
        }
        spread[d] = s->w0[d] * (sq / (double)frames - (sum / (double)frames) * (sum / (double)frames));
        if (hi > lo && isfinite(hi - lo)) { /* the quantiles, to a bin */
            double width = (hi - lo) / QUANT_BINS;
            memset(hist, 0, sizeof(uint32_t) * QUANT_BINS);
            for (size_t i = 0; i < frames; ++i) {
                int bin = (int)((s->features[i * dims + d] - lo) / width);
                ++hist[bin < 0 ? 0 : bin >= QUANT_BINS ? QUANT_BINS - 1 : bin];
            }
            int first = 0, last = QUANT_BINS - 1;
            for (double below = hist[0]; below <= tail && first < QUANT_BINS - 1;) below += hist[++first];
            for (double above = hist[last]; above <= tail && last > 0;) above += hist[--last];
            if (first < last) {
                hi = lo + (last + 1) * width;
                lo = lo + first * width;
            }
        }
        s->quant_lo[d] = isfinite(lo) ? lo : 0.0;
        s->quant_step[d] = hi > lo && isfinite(hi - lo) ? (hi - lo) / (QUANT_LEVELS - 1) : 1.0;
        if (!(s->w0[d] > 0.0f)) continue; /* padding: no slot (a bound may leave dimensions out) */
        int j = s->quant_slots++;         /* slots by decreasing spread, then index */
        while (j > 0 && spread[s->quant_order[j - 1]] < spread[d]) {
            s->quant_order[j] = s->quant_order[j - 1];
            --j;
        }
        s->quant_order[j] = (int16_t)d;
    }
    s->quant_head = s->quant_slots < QUANT_HEAD ? s->quant_slots : QUANT_HEAD;
    for (int j = 0; j < s->quant_slots; ++j) {
        int d = s->quant_order[j];
        for (size_t i = 0; i < frames; ++i) {
            double v = floor((s->features[i * dims + d] - s->quant_lo[d]) / s->quant_step[d] + 0.5);
            size_t b = i / QUANT_BLOCK;
            uint8_t *at = j < s->quant_head
                              ? s->quantized + (b * s->quant_head + j) * QUANT_BLOCK
                              : (uint8_t *)quant_tail(s, (int)b) + (j - s->quant_head) * QUANT_BLOCK;
            at[i % QUANT_BLOCK] = (uint8_t)(v > 0.0 ? (v < QUANT_LEVELS - 1 ? v : QUANT_LEVELS - 1) : 0.0);
        }
    }
    for (size_t i = frames; i < blocks * QUANT_BLOCK; ++i) /* the last block's unused positions */
        for (int j = 0; j < s->quant_slots; ++j) {
            size_t b = i / QUANT_BLOCK;
            uint8_t *at = j < s->quant_head
                              ? s->quantized + (b * s->quant_head + j) * QUANT_BLOCK
                              : (uint8_t *)quant_tail(s, (int)b) + (j - s->quant_head) * QUANT_BLOCK;
            at[i % QUANT_BLOCK] = 0;
        }
}

/* ---- the searcher ----------------------------------------------------------------------- */

mm_result mm_searcher_init(mm_searcher *s, const mm_database *db, const mm_searcher_desc *desc, mm_error *err)
{
    if (!s) return MM_ERR_INVALID_ARGUMENT;
    memset(s, 0, sizeof *s);
    if (!db || !db->features || db->frame_count < 1)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no database");
    if (db->dims_padded > MM_SEARCH_MAX_DIMS || db->dims_padded % LANES)
        return mm_error_set(err, MM_ERR_LIMIT, 0, 0, "the database has %d feature dimensions (at most %d)",
                            db->dims_padded, MM_SEARCH_MAX_DIMS);
    if (desc && desc->allocator) s->allocator = *desc->allocator;
    const mm_allocator *a = &s->allocator;
    s->db = db;
    size_t frames = (size_t)db->frame_count, dims = (size_t)db->dims_padded;
    size_t max_bin = 2 * (frames / (MM_SEARCH_LEAF / 2) + 1);
    s->order = (int32_t *)mm_alloc_array(a, frames, sizeof(int32_t));
    s->order_clip = (int32_t *)mm_alloc_array(a, frames, sizeof(int32_t));
    s->order_tags = (uint64_t *)mm_alloc_array(a, frames, sizeof(uint64_t));
    s->features = (float *)mm_alloc_array(a, frames * dims, sizeof(float));
    size_t quant_bytes = (frames + QUANT_BLOCK - 1) / QUANT_BLOCK * QUANT_BLOCK * dims;
    s->quantized = (uint8_t *)mm_alloc_array(a, quant_bytes, 1);
    uint32_t *hist = (uint32_t *)mm_alloc_array(a, QUANT_BINS, sizeof(uint32_t));
    s->facing = (float *)mm_alloc_array(a, 2 * frames, sizeof(float));
    s->basis = (double *)mm_alloc_array(a, dims * (dims + 8), sizeof(double)); /* tree_dims <= dims + 8 */
    s->job = mm_alloc_array(a, 1, sizeof(parallel_job));
    builder *b = (builder *)mm_alloc_array(a, 1, sizeof(builder));
    float *coords = (float *)mm_alloc_array(a, frames * (dims + 8), sizeof(float));
    double *cov = (double *)mm_alloc_array(a, 2 * dims * dims, sizeof(double)); /* and the axes */
    bin_node *bin = (bin_node *)mm_alloc_array(a, max_bin, sizeof(bin_node));
    float *bin_min = (float *)mm_alloc_array(a, max_bin * (dims + 8), sizeof(float));
    float *bin_max = (float *)mm_alloc_array(a, max_bin * (dims + 8), sizeof(float));
    int ok = s->order && s->order_clip && s->order_tags && s->features && s->facing && s->job && s->basis &&
             s->quantized && hist && b && coords && cov && bin && bin_min && bin_max;
    if (ok) {
        for (size_t f = 0; f < frames; ++f) s->order[f] = (int32_t)f;
        mm_search_params defaults;
        mm_search_params_defaults(db, &defaults);
        dimension_weights(db, &defaults, s->w0);
        principal_axes(db, s, cov, cov + dims * dims);
        size_t slots = (size_t)s->tree_dims;
        double largest = 0.0, z[SEARCH_MAX_SLOTS];
        for (size_t f = 0; f < frames; ++f) {
            rotate(s, db->features + f * dims, z);
            for (size_t j = 0; j < slots; ++j) {
                coords[f * slots + j] = (float)z[j];
                if (fabs(z[j]) > largest) largest = fabs(z[j]);
            }
        }
        memset(b, 0, sizeof *b);
        b->s = s;
        b->db = db;
        b->dims = (int)slots;
        b->coords = coords;
        b->margin = (float)(1e-5 * (1.0 + largest)); /* far above float rounding of these coordinates */
        b->bin = bin;
        b->bin_min = bin_min;
        b->bin_max = bin_max;
        build_node(b, 0, (int)frames, 0);
        s->node_count = count_wide(b, 0);
        size_t boxes = (size_t)s->node_count * s->tree_dims * MM_SEARCH_WIDTH;
        s->nodes = (mm_search_node *)mm_alloc_array(a, (size_t)s->node_count, sizeof(mm_search_node));
        s->boxes = (float *)mm_alloc_array(a, 2 * boxes, sizeof(float));
        ok = s->nodes && s->boxes;
        if (ok) make_wide(b, 0, 0);
    }
    mm_free(a, b);
    mm_free(a, coords);
    mm_free(a, cov);
    mm_free(a, bin);
    mm_free(a, bin_min);
    mm_free(a, bin_max);
    if (!ok) {
        mm_free(a, hist);
        mm_searcher_free(s);
        return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    }
    for (size_t i = 0; i < frames; ++i) {
        memcpy(s->features + i * dims, db->features + (size_t)s->order[i] * dims, dims * sizeof(float));
        s->order_clip[i] = db->frame_clip[s->order[i]];
        s->order_tags[i] = db->frame_tags[s->order[i]];
    }
    quantize_features(s, hist);
    mm_free(a, hist);
    /* MM_SEARCH_FACING: the yaw of each frame's furthest future trajectory direction. */
    s->facing_group = -1;
    for (int g = 0; g < db->group_count; ++g)
        if (db->groups[g].kind == MM_FEATURE_TRAJ_DIRECTION &&
            (s->facing_group < 0 || db->groups[g].time > db->groups[s->facing_group].time))
            s->facing_group = g;
    for (size_t f = 0; f < frames && s->facing_group >= 0; ++f) {
        int o = db->groups[s->facing_group].offset;
        float x = mm_database_feature_raw(db, (int)f, o), z = mm_database_feature_raw(db, (int)f, o + 1);
        float len = sqrtf(x * x + z * z);
        s->facing[2 * f] = len > 1e-6f ? x / len : 0.0f;
        s->facing[2 * f + 1] = len > 1e-6f ? z / len : 1.0f;
    }
    s->memory = frames * (2 * sizeof(int32_t) + sizeof(uint64_t) + dims * sizeof(float) + 2 * sizeof(float)) +
                quant_bytes +
                (size_t)s->node_count *
                    (sizeof(mm_search_node) + 2 * (size_t)s->tree_dims * MM_SEARCH_WIDTH * sizeof(float)) +
                dims * (size_t)s->tree_dims * sizeof(double);
    int threads = desc && desc->threads > 1 ? desc->threads : 1;
    if (threads > MM_SEARCH_MAX_THREADS) threads = MM_SEARCH_MAX_THREADS;
    if (threads > 1) s->pool = mm__pool_create(threads, a); /* NULL: the calling thread alone */
    s->threads = mm__pool_size(s->pool);
    return MM_OK;
}

void mm_searcher_free(mm_searcher *s)
{
    if (!s) return;
    mm__pool_destroy(s->pool);
    const mm_allocator *a = &s->allocator;
    mm_free(a, s->order);
    mm_free(a, s->order_clip);
    mm_free(a, s->order_tags);
    mm_free(a, s->features);
    mm_free(a, s->quantized);
    mm_free(a, s->nodes);
    mm_free(a, s->basis);
    mm_free(a, s->boxes);
    mm_free(a, s->facing);
    mm_free(a, s->job);
    memset(s, 0, sizeof *s);
}
