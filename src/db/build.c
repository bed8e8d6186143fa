/* Database build: config + source clips -> processed clips -> per-frame arrays -> one buffer.
 *
 * Each config clip gives one database clip per frame range (and its mirror, if asked); blend
 * clips are made from their sources' first range. Every database clip is resampled to the
 * interval and gets the simulation bone; then contacts, root motion and raw features are
 * computed per clip, features are normalised per group over the whole database, and bounding
 * boxes are taken over blocks of frames. Single-threaded and free of any state but its inputs:
 * the same inputs give the same bytes. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "db/db_file.h"
#include "db/features.h"
#include "db/process.h"

typedef struct built {
    mm_clip clip;
    mm_db_clip meta;
    int config_clip; /* for tags: the config clip whose ranges apply (-1 for blends) */
    int blend;       /* config blend index, or -1 */
    float period_left, period_right, start_left, start_right; /* blends: source timing for tags */
    int tag_clip_left, tag_clip_right;
} built;

typedef struct builder {
    const mm_config *cfg;
    const mm_allocator *a;
    mm_error *err;
    built *clips;
    int count, capacity;
} builder;

static mm_result push(builder *b, built *x)
{
    if (b->count == b->capacity) {
        int cap = b->capacity ? 2 * b->capacity : 16;
        built *n = (built *)realloc(b->clips, sizeof(built) * (size_t)cap);
        if (!n) return mm_error_set(b->err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
        b->clips = n;
        b->capacity = cap;
    }
    b->clips[b->count++] = *x;
    return MM_OK;
}

static void free_builder(builder *b)
{
    for (int i = 0; i < b->count; ++i) mm_clip_free(&b->clips[i].clip);
    free(b->clips);
}

static uint64_t tags_at(const mm_config *cfg, int config_clip, float t)
{
    uint64_t mask = 0;
    if (config_clip < 0) return 0;
    const mm_config_clip *c = &cfg->clips[config_clip];
    for (int i = 0; i < c->tag_range_count; ++i)
        if (t >= c->tag_ranges[i].begin - 1e-4f && t <= c->tag_ranges[i].end + 1e-4f)
            mask |= (uint64_t)1 << c->tag_ranges[i].tag;
    return mask;
}

static mm_result process_config_clip(builder *b, int ci, const mm_clip *src)
{
    const mm_config *cfg = b->cfg;
    const mm_config_clip *cc = &cfg->clips[ci];
    mm_config_range whole = {0, src->frame_count};
    int ranges = cc->range_count ? cc->range_count : 1;
    for (int r = 0; r < ranges; ++r) {
        mm_config_range range = cc->range_count ? cc->ranges[r] : whole;
        if (range.end > src->frame_count || range.end - range.begin < 2)
            return mm_error_set(b->err, MM_ERR_OUT_OF_RANGE, 0, 0,
                                "clips[%d] (%s).ranges[%d]: [%d, %d) does not fit the file's %d frames", ci,
                                cc->name, r, range.begin, range.end, src->frame_count);
        mm_clip resampled;
        mm_result res = mm__clip_extract(src, range.begin, range.end, cfg->interval, &resampled, b->a);
        if (res != MM_OK)
            return mm_error_set(b->err, res, 0, 0, "clips[%d] (%s): cannot resample", ci, cc->name);
        built x;
        memset(&x, 0, sizeof x);
        res = mm__clip_add_root(&resampled, cfg, &x.clip, b->a, b->err);
        mm_clip_free(&resampled);
        if (res != MM_OK) return res;
        if (ranges > 1)
            snprintf(x.meta.name, MM_NAME_MAX, "%.50s#%d", cc->name, r);
        else
            snprintf(x.meta.name, MM_NAME_MAX, "%s", cc->name);
        x.meta.type = cc->type;
        x.meta.loop = cc->loop;
        x.meta.source = ci;
        x.meta.blend_left = x.meta.blend_right = -1;
        x.meta.source_start = (float)range.begin / src->fps;
        x.config_clip = ci;
        x.blend = -1;
        if ((res = push(b, &x)) != MM_OK) {
            mm_clip_free(&x.clip);
            return res;
        }
        if (cc->mirror) {
            built m = b->clips[b->count - 1];
            res = mm__clip_mirror(&b->clips[b->count - 1].clip, cfg, &m.clip, b->a);
            if (res != MM_OK)
                return mm_error_set(b->err, res, 0, 0, "clips[%d] (%s): cannot mirror", ci, cc->name);
            size_t len = strlen(m.meta.name);
            snprintf(m.meta.name + (len > MM_NAME_MAX - 8 ? MM_NAME_MAX - 8 : len), 8, "_mirror");
            m.meta.mirrored = 1;
            if ((res = push(b, &m)) != MM_OK) {
                mm_clip_free(&m.clip);
                return res;
            }
        }
    }
    return MM_OK;
}

/* First database clip made from config clip ci (mirrored or not). */
static int first_built(const builder *b, int ci, int mirrored)
{
    for (int i = 0; i < b->count; ++i)
        if (b->clips[i].blend < 0 && b->clips[i].meta.source == ci && b->clips[i].meta.mirrored == mirrored)
            return i;
    return -1;
}

static mm_result process_blend(builder *b, int bi)
{
    const mm_config *cfg = b->cfg;
    const mm_config_blend *cb = &cfg->blends[bi];
    int variants = cfg->clips[cb->left].mirror && cfg->clips[cb->right].mirror ? 2 : 1;
    for (int m = 0; m < variants; ++m) {
        int l = first_built(b, cb->left, m), r = first_built(b, cb->right, m);
        if (l < 0 || r < 0)
            return mm_error_set(b->err, MM_ERR_NOT_FOUND, 0, 0, "blend_clips[%d]: missing source", bi);
        built x;
        memset(&x, 0, sizeof x);
        int ll = b->clips[l].meta.loop, rl = b->clips[r].meta.loop;
        mm_result res = mm__clip_blend(&b->clips[l].clip, ll, &b->clips[r].clip, rl, cb->weight,
                                       cfg->interval, &x.clip, b->a);
        if (res != MM_OK)
            return mm_error_set(b->err, res, 0, 0, "blend_clips[%d] (%s): cannot blend", bi, cb->name);
        snprintf(x.meta.name, MM_NAME_MAX, m ? "%.48s_mirror" : "%s", cb->name);
        x.meta.type = b->clips[l].meta.type;
        x.meta.loop = ll && rl;
        x.meta.mirrored = m;
        x.meta.source = bi;
        x.meta.blend_left = l;
        x.meta.blend_right = r;
        x.meta.blend_weight = cb->weight;
        x.config_clip = -1;
        x.blend = bi;
        const mm_clip *lc = &b->clips[l].clip, *rc = &b->clips[r].clip;
        x.period_left = (float)(ll ? lc->frame_count : lc->frame_count - 1) * cfg->interval;
        x.period_right = (float)(rl ? rc->frame_count : rc->frame_count - 1) * cfg->interval;
        x.start_left = b->clips[l].meta.source_start;
        x.start_right = b->clips[r].meta.source_start;
        x.tag_clip_left = cb->left;
        x.tag_clip_right = cb->right;
        if ((res = push(b, &x)) != MM_OK) {
            mm_clip_free(&x.clip);
            return res;
        }
    }
    return MM_OK;
}

/* Reorders clip's joints into reference's order when both have the same joints (names) with the
 * same parents; returns 0 when they differ. Real data often lists one skeleton's joints in
 * different orders from file to file. */
static int match_skeleton(const mm_skeleton *reference, mm_clip *clip, const mm_allocator *a)
{
    const mm_skeleton *s = &clip->skeleton;
    int n = reference->joint_count;
    if (s->joint_count != n) return 0;
    int *map = (int *)malloc(sizeof(int) * (size_t)n), same_order = 1;
    if (!map) return 0;
    for (int j = 0; j < n; ++j) {
        map[j] = mm_skeleton_find(s, reference->joints[j].name);
        int rp = reference->joints[j].parent;
        int sp = map[j] >= 0 ? s->joints[map[j]].parent : -2;
        if (map[j] < 0 || (rp < 0) != (sp < 0) ||
            (rp >= 0 && strcmp(reference->joints[rp].name, s->joints[sp].name) != 0)) {
            free(map);
            return 0;
        }
        same_order &= map[j] == j;
    }
    if (!same_order) {
        mm_clip sorted;
        if (mm_clip_init(&sorted, reference, clip->frame_count, clip->fps, a) != MM_OK) {
            free(map);
            return 0;
        }
        for (int f = 0; f < clip->frame_count; ++f)
            for (int j = 0; j < n; ++j) {
                mm_clip_rotations(&sorted, f)[j] = mm_clip_rotations(clip, f)[map[j]];
                mm_clip_positions(&sorted, f)[j] = mm_clip_positions(clip, f)[map[j]];
            }
        for (int j = 0; j < n; ++j) { /* keep each clip's own offsets and flags */
            sorted.skeleton.joints[j] = s->joints[map[j]];
            sorted.skeleton.joints[j].parent = reference->joints[j].parent;
        }
        mm_clip_free(clip);
        *clip = sorted;
    }
    free(map);
    return 1;
}

static mm_result check_skeletons(builder *b)
{
    const mm_skeleton *s0 = &b->clips[0].clip.skeleton;
    for (int i = 1; i < b->count; ++i)
        if (!match_skeleton(s0, &b->clips[i].clip, b->a))
            return mm_error_set(
                b->err, MM_ERR_INVALID_ARGUMENT, 0, 0,
                "clip '%s' has a different skeleton from clip '%s' (joint names and parents must match)",
                b->clips[i].meta.name, b->clips[0].meta.name);
    const mm_config *cfg = b->cfg;
    const char *roles[] = {cfg->hips,      cfg->left_foot, cfg->right_foot, cfg->left_toe,
                           cfg->right_toe, cfg->left_hand, cfg->right_hand, cfg->head};
    const char *fields[] = {"hips",      "left_foot", "right_foot", "left_toe",
                            "right_toe", "left_hand", "right_hand", "head"};
    for (int r = 0; r < 8; ++r)
        if (roles[r][0] && mm_skeleton_find(s0, roles[r]) < 0)
            return mm_error_set(b->err, MM_ERR_NOT_FOUND, 0, 0, "roles.%s: no joint named '%s'", fields[r],
                                roles[r]);
    return MM_OK;
}

/* The distance curves of every clip's root (joint 0) path, laid out as the file stores them. */
typedef struct distance_arrays {
    mm_db_distance_clip *clips;
    float *travelled, *distance;
    mm_distance_segment *segments;
    int segment_count, segment_capacity;
} distance_arrays;

static void free_distance(distance_arrays *d)
{
    free(d->clips);
    free(d->travelled);
    free(d->distance);
    free(d->segments);
}

/* Builds clip i's curve from its simulation bone's positions (scratch holds frame_count vec3s). */
static mm_result clip_distance(const builder *b, int i, int first, mm_vec3 *scratch, distance_arrays *d)
{
    const mm_clip *c = &b->clips[i].clip;
    int n = c->frame_count;
    mm_db_distance_clip *dc = &d->clips[i];
    dc->first_segment = d->segment_count;
    dc->stop_speed = MM_DISTANCE_STOP_SPEED_DEFAULT;
    if (n < 2) return MM_OK; /* a single frame: no curve (travelled 0, no segment) */
    for (int f = 0; f < n; ++f) scratch[f] = mm_clip_positions(c, f)[0];
    mm_distance_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.positions = &scratch[0].x;
    desc.components = 3;
    desc.frame_count = n;
    desc.fps = 1.0f / b->cfg->interval;
    desc.loop = b->clips[i].meta.loop;
    desc.stop_speed = dc->stop_speed;
    mm_distance_curve curve;
    mm_error e;
    memset(&e, 0, sizeof e);
    mm_result r = mm_distance_curve_build(&curve, &desc, &e);
    if (r != MM_OK)
        return mm_error_set(b->err, r, 0, 0, "clip '%s': cannot build its distance curve: %s",
                            b->clips[i].meta.name, e.message);
    if (d->segment_count + curve.segment_count > d->segment_capacity) {
        int cap = d->segment_capacity ? 2 * d->segment_capacity : 64;
        while (cap < d->segment_count + curve.segment_count) cap *= 2;
        mm_distance_segment *grown =
            (mm_distance_segment *)realloc(d->segments, sizeof(mm_distance_segment) * (size_t)cap);
        if (!grown) {
            mm_distance_curve_free(&curve);
            return mm_error_set(b->err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
        }
        d->segments = grown;
        d->segment_capacity = cap;
    }
    memcpy(d->segments + d->segment_count, curve.segments,
           sizeof(mm_distance_segment) * (size_t)curve.segment_count);
    memcpy(d->travelled + first, curve.travelled, sizeof(float) * (size_t)n);
    memcpy(d->distance + first, curve.distance, sizeof(float) * (size_t)n);
    dc->segment_count = curve.segment_count;
    dc->path_length = curve.path_length;
    d->segment_count += curve.segment_count;
    mm_distance_curve_free(&curve);
    return MM_OK;
}

typedef struct arrays {
    mm_joint *joints;
    mm_db_clip *clips;
    char (*tag_names)[MM_TAG_NAME_MAX];
    mm_feature_group groups[2 * MM_MAX_MATCH_BONES + 1 + 2 * MM_MAX_TRAJ_SAMPLES];
    int32_t *frame_clip, *frame_next;
    uint64_t *frame_tags;
    uint8_t *contacts;
    mm_vec3 *root_velocity;
    float *root_yaw_rate;
    mm_quat *rotations;
    mm_vec3 *positions;
    float *features, *mean, *scale, *small_min, *small_max, *large_min, *large_max;
} arrays;

static void free_arrays(arrays *x)
{
    void *p[] = {x->joints,   x->clips,         x->tag_names,     x->frame_clip, x->frame_next, x->frame_tags,
                 x->contacts, x->root_velocity, x->root_yaw_rate, x->rotations,  x->positions,  x->features,
                 x->mean,     x->scale,         x->small_min,     x->small_max,  x->large_min,  x->large_max};
    for (size_t i = 0; i < sizeof p / sizeof p[0]; ++i) free(p[i]);
}

/* Normalisation: per-dimension mean; per-group scale = mean standard deviation of its
 * dimensions (1 for a group that does not vary). Padding dimensions: mean 0, scale 1. */
static void normalise(arrays *x, int frames, int dims_padded, int group_count)
{
    for (int d = 0; d < dims_padded; ++d) {
        x->mean[d] = 0.0f;
        x->scale[d] = 1.0f;
    }
    for (int g = 0; g < group_count; ++g) {
        const mm_feature_group *grp = &x->groups[g];
        double spread = 0.0;
        for (int d = grp->offset; d < grp->offset + grp->dims; ++d) {
            double sum = 0.0, sq = 0.0;
            for (int f = 0; f < frames; ++f) sum += x->features[(size_t)f * dims_padded + d];
            double mean = sum / frames;
            for (int f = 0; f < frames; ++f) {
                double v = x->features[(size_t)f * dims_padded + d] - mean;
                sq += v * v;
            }
            x->mean[d] = (float)mean;
            spread += sqrt(sq / frames);
        }
        spread /= grp->dims;
        /* Below 1e-5 (m, m/s or unit vectors) a group does not vary: float noise must not be
         * blown up into features. */
        float s = spread > 1e-5 ? (float)spread : 1.0f;
        x->groups[g].scale = s;
        for (int d = grp->offset; d < grp->offset + grp->dims; ++d) x->scale[d] = s;
    }
    for (int f = 0; f < frames; ++f)
        for (int d = 0; d < dims_padded; ++d) {
            float *v = &x->features[(size_t)f * dims_padded + d];
            *v = (*v - x->mean[d]) / x->scale[d];
        }
}

static void bounds(const float *features, int frames, int dims_padded, int block, float *mn, float *mx)
{
    int blocks = (frames + block - 1) / block;
    for (int b = 0; b < blocks; ++b) {
        float *lo = mn + (size_t)b * dims_padded, *hi = mx + (size_t)b * dims_padded;
        for (int d = 0; d < dims_padded; ++d) {
            lo[d] = INFINITY;
            hi[d] = -INFINITY;
        }
        int end = (b + 1) * block < frames ? (b + 1) * block : frames;
        for (int f = b * block; f < end; ++f)
            for (int d = 0; d < dims_padded; ++d) {
                float v = features[(size_t)f * dims_padded + d];
                lo[d] = fminf(lo[d], v);
                hi[d] = fmaxf(hi[d], v);
            }
    }
}

mm_result mm_database_build(const mm_config *cfg, const mm_clip *sources, const mm_db_build_desc *desc,
                            mm_database *out, mm_error *err)
{
    if (!out) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no output");
    memset(out, 0, sizeof *out);
    if (!cfg || (!sources && cfg->clip_count))
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no config");
    mm_result r = mm_config_validate(cfg, err);
    if (r != MM_OK) return r;
    if (cfg->clip_count < 1)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "clips: the config lists no clip");
    builder b;
    memset(&b, 0, sizeof b);
    b.cfg = cfg;
    b.err = err;
    int total = cfg->clip_count + cfg->blend_count;
    for (int i = 0; i < cfg->clip_count && r == MM_OK; ++i) {
        r = process_config_clip(&b, i, &sources[i]);
        if (desc && desc->progress) desc->progress(i + 1, total, desc->progress_user);
    }
    for (int i = 0; i < cfg->blend_count && r == MM_OK; ++i) {
        r = process_blend(&b, i);
        if (desc && desc->progress) desc->progress(cfg->clip_count + i + 1, total, desc->progress_user);
    }
    if (r == MM_OK) r = check_skeletons(&b);
    if (r != MM_OK) {
        free_builder(&b);
        return r;
    }

    const mm_skeleton *skel = &b.clips[0].clip.skeleton;
    int jc = skel->joint_count, frames = 0;
    for (int i = 0; i < b.count; ++i) frames += b.clips[i].clip.frame_count;
    arrays x;
    memset(&x, 0, sizeof x);
    int dims = 0;
    int group_count = mm__feature_layout(cfg, skel, x.groups, &dims, err);
    if (group_count < 0) {
        free_builder(&b);
        return err ? err->code : MM_ERR_NOT_FOUND;
    }
    int dims_padded = (dims + MM_DB_SIMD_WIDTH - 1) / MM_DB_SIMD_WIDTH * MM_DB_SIMD_WIDTH;
    if (dims_padded == 0) dims_padded = MM_DB_SIMD_WIDTH;
    size_t nf = (size_t)frames, nj = (size_t)jc, nd = (size_t)dims_padded;
    size_t small = (size_t)(frames + MM_DB_SMALL_BLOCK - 1) / MM_DB_SMALL_BLOCK;
    size_t large = (size_t)(frames + MM_DB_LARGE_BLOCK - 1) / MM_DB_LARGE_BLOCK;
    x.joints = (mm_joint *)calloc(nj, sizeof(mm_joint));
    x.clips = (mm_db_clip *)calloc((size_t)b.count, sizeof(mm_db_clip));
    x.tag_names = (char(*)[MM_TAG_NAME_MAX])calloc((size_t)cfg->tag_count + 1, MM_TAG_NAME_MAX);
    x.frame_clip = (int32_t *)calloc(nf, 4);
    x.frame_next = (int32_t *)calloc(nf, 4);
    x.frame_tags = (uint64_t *)calloc(nf, 8);
    x.contacts = (uint8_t *)calloc(nf, 1);
    x.root_velocity = (mm_vec3 *)calloc(nf, sizeof(mm_vec3));
    x.root_yaw_rate = (float *)calloc(nf, 4);
    x.rotations = (mm_quat *)calloc(nf * nj, sizeof(mm_quat));
    x.positions = (mm_vec3 *)calloc(nf * nj, sizeof(mm_vec3));
    x.features = (float *)calloc(nf * nd, 4);
    x.mean = (float *)calloc(nd, 4);
    x.scale = (float *)calloc(nd, 4);
    x.small_min = (float *)calloc(small * nd, 4);
    x.small_max = (float *)calloc(small * nd, 4);
    x.large_min = (float *)calloc(large * nd, 4);
    x.large_max = (float *)calloc(large * nd, 4);
    distance_arrays dist;
    memset(&dist, 0, sizeof dist);
    dist.clips = (mm_db_distance_clip *)calloc((size_t)b.count, sizeof(mm_db_distance_clip));
    dist.travelled = (float *)calloc(nf, 4);
    dist.distance = (float *)calloc(nf, 4);
    mm_xform *globals = NULL;
    mm_vec3 *root_path = NULL;
    int longest = 0;
    for (int i = 0; i < b.count; ++i)
        longest = b.clips[i].clip.frame_count > longest ? b.clips[i].clip.frame_count : longest;
    globals = (mm_xform *)malloc(sizeof(mm_xform) * (size_t)longest * nj);
    root_path = (mm_vec3 *)malloc(sizeof(mm_vec3) * (size_t)longest);
    if (!dist.clips || !dist.travelled || !dist.distance || !root_path || !x.joints || !x.clips ||
        !x.tag_names || !x.frame_clip || !x.frame_next || !x.frame_tags || !x.contacts || !x.root_velocity ||
        !x.root_yaw_rate || !x.rotations || !x.positions || !x.features || !x.mean || !x.scale ||
        !x.small_min || !x.small_max || !x.large_min || !x.large_max || !globals) {
        free(globals);
        free(root_path);
        free_distance(&dist);
        free_arrays(&x);
        free_builder(&b);
        return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory for %d frames", frames);
    }
    memcpy(x.joints, skel->joints, nj * sizeof(mm_joint));
    for (int t = 0; t < cfg->tag_count; ++t) memcpy(x.tag_names[t], cfg->tag_names[t], MM_TAG_NAME_MAX);
    int heel_toe[4] = {mm_skeleton_find(skel, cfg->left_foot), mm_skeleton_find(skel, cfg->left_toe),
                       mm_skeleton_find(skel, cfg->right_foot), mm_skeleton_find(skel, cfg->right_toe)};
    int first = 0;
    for (int i = 0; i < b.count; ++i) {
        built *bc = &b.clips[i];
        const mm_clip *c = &bc->clip;
        int n = c->frame_count;
        bc->meta.first_frame = first;
        bc->meta.frame_count = n;
        x.clips[i] = bc->meta;
        for (int f = 0; f < n; ++f) {
            mm_clip_fk(c, f, globals + (size_t)f * nj);
            int g = first + f;
            x.frame_clip[g] = i;
            x.frame_next[g] = f + 1 < n ? g + 1 : (bc->meta.loop ? first : -1);
            if (bc->blend < 0) {
                x.frame_tags[g] =
                    tags_at(cfg, bc->config_clip, bc->meta.source_start + (float)f * cfg->interval);
            } else {
                float u = bc->meta.loop ? (float)f / n : (float)f / (float)(n - 1);
                x.frame_tags[g] = tags_at(cfg, bc->tag_clip_left, bc->start_left + u * bc->period_left) |
                                  tags_at(cfg, bc->tag_clip_right, bc->start_right + u * bc->period_right);
            }
        }
        memcpy(x.rotations + (size_t)first * nj, c->rotations, (size_t)n * nj * sizeof(mm_quat));
        memcpy(x.positions + (size_t)first * nj, c->positions, (size_t)n * nj * sizeof(mm_vec3));
        mm__detect_contacts(c, globals, heel_toe, cfg, x.contacts + first);
        mm__root_motion(c, x.root_velocity + first, x.root_yaw_rate + first);
        mm__clip_features(c, bc->meta.loop, globals, x.root_velocity + first, x.groups, group_count,
                          cfg->interval, x.features + (size_t)first * nd, dims_padded);
        if ((r = clip_distance(&b, i, first, root_path, &dist)) != MM_OK) break;
        first += n;
    }
    free(globals);
    free(root_path);
    if (r != MM_OK) {
        free_distance(&dist);
        free_arrays(&x);
        free_builder(&b);
        return r;
    }
    normalise(&x, frames, dims_padded, group_count);
    bounds(x.features, frames, dims_padded, MM_DB_SMALL_BLOCK, x.small_min, x.small_max);
    bounds(x.features, frames, dims_padded, MM_DB_LARGE_BLOCK, x.large_min, x.large_max);

    mm__db_parts p;
    memset(&p, 0, sizeof p);
    p.frame_count = frames;
    p.joint_count = jc;
    p.clip_count = b.count;
    p.tag_count = cfg->tag_count;
    p.group_count = group_count;
    p.dims = dims;
    p.dims_padded = dims_padded;
    p.interval = cfg->interval;
    const char *json = desc && desc->config_json ? desc->config_json : "";
    const void *data[MM__SEC_COUNT] = {
        x.joints,     x.clips,    x.tag_names,     x.groups,        x.frame_clip,  x.frame_next,
        x.frame_tags, x.contacts, x.root_velocity, x.root_yaw_rate, x.rotations,   x.positions,
        x.features,   x.mean,     x.scale,         x.small_min,     x.small_max,   x.large_min,
        x.large_max,  json,       dist.clips,      dist.travelled,  dist.distance, dist.segments};
    memcpy(p.data, data, sizeof data);
    p.size[MM__SEC_CONFIG_JSON] = strlen(json) + 1;
    p.size[MM__SEC_DISTANCE_SEGMENTS] = sizeof(mm_distance_segment) * (size_t)dist.segment_count;
    r = mm__db_pack(&p, desc ? desc->allocator : NULL, out, err);
    free_distance(&dist);
    free_arrays(&x);
    free_builder(&b);
    return r;
}
