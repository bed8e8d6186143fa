/* The postures of a database's source frames and what the build does with them. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <mm/gait.h>
#include <mm/posture.h>

#include "db/build_postures.h"
#include "db/process.h"

static int removed(uint8_t posture)
{
    return posture == MM_POSTURE_CALIBRATION || posture == MM_POSTURE_LYING ||
           posture == MM_POSTURE_ARMS_SPREAD || posture == MM_POSTURE_HAND_RAISED ||
           posture == MM_POSTURE_KNEE_RAISED;
}

static int crouched(uint8_t posture) { return posture == MM_POSTURE_CROUCHED || posture == MM_POSTURE_BENT; }

/* Frame f is in one of the clip's ranges (all frames without ranges). */
static int in_ranges(const mm_config_clip *c, int f)
{
    for (int r = 0; r < c->range_count; ++r)
        if (f >= c->ranges[r].begin && f < c->ranges[r].end) return 1;
    return c->range_count == 0;
}

static int same_name_any_case(const char *a, const char *b)
{
    for (; *a && *b; ++a, ++b)
        if ((*a | 32) != (*b | 32)) return 0;
    return *a == *b;
}

/* The tag is named after a gait. */
static int gait_tag(const mm_config *cfg, int tag)
{
    for (int g = 0; g < MM_GAIT_COUNT; ++g)
        if (same_name_any_case(cfg->tag_names[tag], mm_gait_name((mm_gait)g))) return 1;
    return 0;
}

/* Config clip ci's frame at time t (s) carries a tag named after a gait: the config says what it is,
 * and its posture does not change that. */
static int gait_tagged(const mm_config *cfg, int ci, float t)
{
    const mm_config_clip *c = &cfg->clips[ci];
    for (int i = 0; i < c->tag_range_count; ++i) {
        if (t >= c->tag_ranges[i].begin - 1e-4f && t <= c->tag_ranges[i].end + 1e-4f &&
            gait_tag(cfg, c->tag_ranges[i].tag))
            return 1;
    }
    return 0;
}

/* Config clip ci is judged: a locomotion or idle clip whose tags, if any, are gaits (a clip tagged
 * otherwise, a move or data marked by hand, is the config's to describe). */
static int judged(const mm_config *cfg, int ci)
{
    const mm_config_clip *c = &cfg->clips[ci];
    if (!cfg->postures_detect || (c->type != MM_CLIP_LOCOMOTION && c->type != MM_CLIP_IDLE)) return 0;
    for (int i = 0; i < c->tag_range_count; ++i)
        if (!gait_tag(cfg, c->tag_ranges[i].tag)) return 0;
    return 1;
}

/* World joint positions of every frame of a source clip ([frames x joints]), and its ground: the
 * median over frames of the lowest body joint's height. The body is the hips and what hangs from
 * them: a Root joint above the hips (at the origin, or on the ground under them) is not a foot,
 * and counting it moved the ground, and so the postures, with the skeleton's arrangement. */
static mm_vec3 *world_positions(const mm_clip *c, int hips, float *ground)
{
    int n = c->frame_count, jc = c->skeleton.joint_count;
    mm_vec3 *w = (mm_vec3 *)malloc(sizeof(mm_vec3) * (size_t)n * (size_t)jc);
    mm_xform *g = (mm_xform *)malloc(sizeof(mm_xform) * (size_t)jc);
    float *lowest = (float *)malloc(sizeof(float) * (size_t)n);
    unsigned char *body = (unsigned char *)malloc((size_t)jc);
    if (!w || !g || !lowest || !body) {
        free(w);
        free(g);
        free(lowest);
        free(body);
        return NULL;
    }
    for (int j = 0; j < jc; ++j) /* parents come first */
        body[j] = (unsigned char)(j == hips ||
                                  (c->skeleton.joints[j].parent >= 0 && body[c->skeleton.joints[j].parent]));
    for (int f = 0; f < n; ++f) {
        mm_clip_fk(c, f, g);
        lowest[f] = INFINITY;
        for (int j = 0; j < jc; ++j) {
            w[(size_t)f * (size_t)jc + (size_t)j] = g[j].translation;
            if (body[j]) lowest[f] = fminf(lowest[f], g[j].translation.y);
        }
    }
    *ground = n > 0 ? mm__quantile(lowest, n, 0.5f) : 0.0f;
    free(g);
    free(lowest);
    free(body);
    return w;
}

static mm_posture_joints joints_of(const mm_config *cfg, const mm_skeleton *s)
{
    mm_posture_joints j = {mm_skeleton_find(s, cfg->hips),
                           mm_skeleton_find(s, cfg->head),
                           mm_skeleton_find(s, cfg->left_hand),
                           mm_skeleton_find(s, cfg->right_hand),
                           {-1, -1},
                           {-1, -1}};
    mm_posture_find_legs(s, mm_skeleton_find(s, cfg->left_foot), mm_skeleton_find(s, cfg->right_foot), &j);
    return j;
}

/* The shortest run of each posture that is not flicker at fps: MM_POSTURE_MIN_SECONDS, but the
 * hands spread wide are seen however briefly (an arm flung out in a hop): those frames stay out. */
static void flicker_min_frames(float fps, int min_frames[MM_POSTURE_COUNT])
{
    for (int p = 0; p < MM_POSTURE_COUNT; ++p) min_frames[p] = (int)lroundf(MM_POSTURE_MIN_SECONDS * fps);
    min_frames[MM_POSTURE_ARMS_SPREAD] = 1;
}

/* Pass 1: the head's heights over every judged frame; pass 2 (heights NULL): the postures. */
static mm_result judge(const mm_config *cfg, const mm_clip *sources, mm__postures *p, float *heights,
                       int *height_count, mm_error *err)
{
    for (int ci = 0; ci < cfg->clip_count; ++ci) {
        const mm_clip *c = &sources[ci];
        mm_posture_joints j = joints_of(cfg, &c->skeleton);
        if (!judged(cfg, ci) || j.hips < 0 || j.head < 0 || c->frame_count < 1) continue;
        float ground;
        mm_vec3 *w = world_positions(c, j.hips, &ground);
        if (!w) return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory judging postures");
        int jc = c->skeleton.joint_count;
        if (heights) {
            for (int f = 0; f < c->frame_count; ++f)
                if (in_ranges(&cfg->clips[ci], f))
                    heights[(*height_count)++] = w[(size_t)f * (size_t)jc + (size_t)j.head].y - ground;
        } else {
            uint8_t *post = (uint8_t *)malloc((size_t)c->frame_count);
            if (!post) {
                free(w);
                return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory judging postures");
            }
            mm_posture_reference ref = {p->reference_head_height};
            for (int f = 0; f < c->frame_count; ++f)
                post[f] = (uint8_t)mm_posture_classify(w + (size_t)f * (size_t)jc, &j, ground, &ref);
            int min_frames[MM_POSTURE_COUNT];
            flicker_min_frames(c->fps, min_frames);
            mm_posture_remove_flicker_each(post, c->frame_count, min_frames);
            p->frames[ci] = post;
        }
        free(w);
    }
    return MM_OK;
}

mm_result mm__postures_find(const mm_config *cfg, const mm_clip *sources, mm__postures *p,
                            mm_db_build_report *report, mm_error *err)
{
    memset(p, 0, sizeof *p);
    p->crouch_tag = -1;
    p->tag_count = cfg->tag_count;
    p->clip_count = cfg->clip_count;
    if (report) memset(report, 0, sizeof *report);
    p->frames = (uint8_t **)calloc((size_t)(cfg->clip_count > 0 ? cfg->clip_count : 1), sizeof(uint8_t *));
    long total = 0;
    for (int ci = 0; ci < cfg->clip_count; ++ci) total += judged(cfg, ci) ? sources[ci].frame_count : 0;
    float *heights = (float *)malloc(sizeof(float) * (size_t)(total > 0 ? total : 1));
    if (!p->frames || !heights) {
        free(heights);
        return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory judging postures");
    }
    int count = 0;
    mm_result r = judge(cfg, sources, p, heights, &count, err);
    if (r == MM_OK && count > 0) {
        p->reference_head_height = mm_posture_reference_height(heights, count);
        r = judge(cfg, sources, p, NULL, NULL, err);
    }
    free(heights);
    if (r != MM_OK) return r;
    /* the crouch gait's tag: the config's own, any case, or a new one after its tags */
    int any_crouched = 0;
    for (int ci = 0; ci < cfg->clip_count; ++ci)
        for (int f = 0; p->frames[ci] && f < sources[ci].frame_count; ++f) {
            if (!in_ranges(&cfg->clips[ci], f)) continue;
            uint8_t q = p->frames[ci][f];
            if (crouched(q) && gait_tagged(cfg, ci, (float)f / sources[ci].fps)) {
                p->frames[ci][f] = MM_POSTURE_UPRIGHT; /* tagged as the config says */
                continue;
            }
            any_crouched |= crouched(q);
            if (report) ++report->source_frames[q];
        }
    if (report) report->reference_head_height = p->reference_head_height;
    if (!any_crouched) return MM_OK;
    for (int t = 0; t < cfg->tag_count && p->crouch_tag < 0; ++t)
        if (same_name_any_case(cfg->tag_names[t], "crouch")) p->crouch_tag = t;
    if (p->crouch_tag < 0) {
        if (cfg->tag_count >= MM_MAX_TAGS)
            return mm_error_set(err, MM_ERR_LIMIT, 0, 0,
                                "postures: crouched frames need a Crouch tag and the config has %d tags "
                                "(at most %d): name one of them Crouch, or set postures.detect to false",
                                cfg->tag_count, MM_MAX_TAGS);
        p->crouch_tag = p->tag_count++;
    }
    return MM_OK;
}

void mm__postures_free(mm__postures *p)
{
    if (p->frames)
        for (int ci = 0; ci < p->clip_count; ++ci) free(p->frames[ci]);
    free(p->frames);
    memset(p, 0, sizeof *p);
}

/* What the build does with a frame of posture q: -1 leaves it out, 1 keeps it tagged, 0 keeps it. */
static int kind_of(uint8_t q) { return removed(q) ? -1 : crouched(q) ? 1 : 0; }

/* Frame f is kept: its posture is kept, and every frame within pad of it (in the take) is of its
 * kind, so that no piece holds the way into or out of a posture it is not of. */
static int kept(const uint8_t *post, int frame_count, int f, int pad)
{
    int kind = kind_of(post[f]);
    if (kind < 0) return 0;
    for (int k = f - pad; k <= f + pad; ++k)
        if (k >= 0 && k < frame_count && kind_of(post[k]) != kind) return 0;
    return 1;
}

int mm__postures_split(const mm__postures *p, const mm_config *cfg, int ci, const mm_clip *source,
                       mm_config_range range, mm_config_range *out)
{
    const uint8_t *post = p->frames ? p->frames[ci] : NULL;
    if (!post) {
        out[0] = range;
        return 1;
    }
    int pad = (int)lroundf(cfg->postures_pad * source->fps),
        min_piece = (int)ceilf(MM__POSTURES_MIN_PIECE * source->fps), n = source->frame_count;
    if (min_piece < 2) min_piece = 2;
    int count = 0;
    for (int f = range.begin; f < range.end;) {
        if (!kept(post, n, f, pad)) {
            ++f;
            continue;
        }
        int e = f + 1, kind = kind_of(post[f]);
        while (e < range.end && kept(post, n, e, pad) && kind_of(post[e]) == kind) ++e;
        /* a range with nothing cut keeps its length; the pieces a cut leaves must be long enough */
        int whole = f == range.begin && e == range.end;
        if (whole || e - f >= min_piece) out[count++] = (mm_config_range){f, e};
        f = e;
    }
    return count;
}

uint64_t mm__postures_tags(const mm__postures *p, int ci, float t, float fps, int frame_count)
{
    if (ci < 0 || p->crouch_tag < 0 || !p->frames[ci] || frame_count < 1) return 0;
    long f = lroundf(t * fps);
    f = f < 0 ? 0 : f >= frame_count ? frame_count - 1 : f;
    return crouched(p->frames[ci][f]) ? (uint64_t)1 << p->crouch_tag : 0;
}
