/* Database build: config + source clips -> processed clips -> per-frame arrays -> one buffer.
 *
 * Each config clip gives one database clip per frame range (and its mirror, if asked); blend
 * clips are made from their sources' first range. Every database clip is resampled to the
 * interval and gets the simulation bone; then contacts, root motion and raw features are
 * computed per clip, features are normalised per group over the whole database, and bounding
 * boxes are taken over blocks of frames. Free of any state but its inputs: the same inputs give
 * the same bytes, with any number of threads. Threads (mm_db_build_desc.threads) take whole units
 * of work (a config clip, a database clip, a feature dimension, a block of frames) from a shared
 * counter, write their results to fixed places, and every sum runs in one thread in frame order,
 * so the work split never changes a bit; lists (clips, distance segments) are joined afterwards
 * in index order, and an error is reported for the first failing unit in that order. */
#include <ctype.h>
#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include <mm/database_build.h>
#include <mm/distance_curve_build.h>

#include "db/build_postures.h"
#include "db/db_file.h"
#include "db/features.h"
#include "db/idle_loop.h"
#include "db/process.h"
#include "db/settings_build.h"
#include "db/standing.h"
#include "search/pool.h"

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
    const mm__postures *postures;
    const mm_clip *sources; /* [cfg->clip_count] */
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

/* The tags of config clip config_clip's source at time t: its tag ranges, and its posture's. */
static uint64_t tags_at(const builder *b, int config_clip, float t)
{
    uint64_t mask = 0;
    if (config_clip < 0) return 0;
    const mm_config_clip *c = &b->cfg->clips[config_clip];
    for (int i = 0; i < c->tag_range_count; ++i)
        if (t >= c->tag_ranges[i].begin - 1e-4f && t <= c->tag_ranges[i].end + 1e-4f)
            mask |= (uint64_t)1 << c->tag_ranges[i].tag;
    const mm_clip *source = &b->sources[config_clip];
    return mask | mm__postures_tags(b->postures, config_clip, t, source->fps, source->frame_count);
}

static mm_result process_range(builder *b, int ci, const mm_clip *src, const mm_clip *body,
                               mm_config_range range, int piece);

/* The database clips of config clip ci: one per range (the ranges less the postures left out). */
static mm_result process_config_clip(builder *b, int ci, const mm_clip *src)
{
    const mm_config *cfg = b->cfg;
    const mm_config_clip *cc = &cfg->clips[ci];
    mm_config_range whole = {0, src->frame_count};
    int given = cc->range_count ? cc->range_count : 1, ranges = 0;
    for (int r = 0; r < given; ++r) {
        mm_config_range range = cc->range_count ? cc->ranges[r] : whole;
        if (range.end > src->frame_count || range.end - range.begin < 2)
            return mm_error_set(b->err, MM_ERR_OUT_OF_RANGE, 0, 0,
                                "clips[%d] (%s).ranges[%d]: [%d, %d) does not fit the file's %d frames", ci,
                                cc->name, r, range.begin, range.end, src->frame_count);
    }
    /* the ranges as given, less the postures left out (a loop clip is kept whole) */
    size_t room = 0;
    for (int r = 0; r < given; ++r)
        room += (size_t)((cc->range_count ? cc->ranges[r] : whole).end -
                         (cc->range_count ? cc->ranges[r] : whole).begin);
    mm_config_range *pieces = (mm_config_range *)malloc(sizeof(mm_config_range) * room);
    if (!pieces) return mm_error_set(b->err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    for (int r = 0; r < given; ++r) {
        mm_config_range range = cc->range_count ? cc->ranges[r] : whole;
        if (cc->loop)
            pieces[ranges++] = range;
        else
            ranges += mm__postures_split(b->postures, cfg, ci, src, range, pieces + ranges);
    }
    /* Joints above the hips are folded away before resampling: the hips' world motion is read
     * on the splines then, whichever joints carried it in the file. */
    mm_result res = MM_OK;
    mm_clip folded;
    memset(&folded, 0, sizeof folded);
    int body_root = mm__body_root(&src->skeleton, cfg);
    if (body_root > 0 && (res = mm__clip_fold_root(src, body_root, &folded, b->a)) != MM_OK)
        res = mm_error_set(b->err, res, 0, 0, "clips[%d] (%s): out of memory", ci, cc->name);
    for (int r = 0; r < ranges && res == MM_OK; ++r)
        res = process_range(b, ci, src, body_root > 0 ? &folded : NULL, pieces[r], ranges > 1 ? r : -1);
    if (body_root > 0) mm_clip_free(&folded);
    free(pieces);
    return res;
}

/* One database clip (and its mirror) from frames range of config clip ci's source (body: the
 * source with the joints above the hips folded, or NULL); piece: its number among the clip's
 * ranges (-1: the only one). */
static mm_result process_range(builder *b, int ci, const mm_clip *src, const mm_clip *body,
                               mm_config_range range, int piece)
{
    const mm_config *cfg = b->cfg;
    const mm_config_clip *cc = &cfg->clips[ci];
    mm_clip resampled, resampled_body;
    memset(&resampled_body, 0, sizeof resampled_body);
    mm_result res = mm__clip_extract(src, range.begin, range.end, cfg->interval, &resampled, b->a);
    if (res == MM_OK && body) {
        res = mm__clip_extract(body, range.begin, range.end, cfg->interval, &resampled_body, b->a);
        if (res != MM_OK) mm_clip_free(&resampled);
    }
    if (res != MM_OK) return mm_error_set(b->err, res, 0, 0, "clips[%d] (%s): cannot resample", ci, cc->name);
    built x;
    memset(&x, 0, sizeof x);
    res = mm__clip_add_root(&resampled, body ? &resampled_body : NULL, cfg, &x.clip, b->a, b->err);
    mm_clip_free(&resampled);
    mm_clip_free(&resampled_body);
    if (res != MM_OK) return res;
    if (piece >= 0)
        snprintf(x.meta.name, MM_NAME_MAX, "%.50s#%d", cc->name, piece);
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

static int same_name_any_case(const char *a, const char *b)
{
    for (; *a && *b; ++a, ++b)
        if (tolower((unsigned char)*a) != tolower((unsigned char)*b)) return 0;
    return *a == *b;
}

/* Pushes x, a clip the build made (its clip freed on failure), and with mirror its mirror named
 * <name>_mirror after it; what names the step in errors. */
static mm_result push_made(builder *b, built *x, int mirror, const char *what)
{
    mm_result r = push(b, x);
    if (r != MM_OK) {
        mm_clip_free(&x->clip);
        return r;
    }
    if (!mirror) return MM_OK;
    built m = b->clips[b->count - 1];
    if ((r = mm__clip_mirror(&b->clips[b->count - 1].clip, b->cfg, &m.clip, b->a)) != MM_OK)
        return mm_error_set(b->err, r, 0, 0, "%s (%s): cannot mirror", what, m.meta.name);
    size_t len = strlen(m.meta.name);
    snprintf(m.meta.name + (len > MM_NAME_MAX - 8 ? MM_NAME_MAX - 8 : len), 8, "_mirror");
    m.meta.mirrored = 1;
    if ((r = push(b, &m)) != MM_OK) mm_clip_free(&m.clip);
    return r;
}

/* With no idle clip (and standing.make), the stillest standing frames of the locomotion clips, held,
 * as idle loops (db/standing.h), each mirrored when its clip is; says so in report. */
static mm_result add_standing(builder *b, float head_height, mm_db_standing_report *report)
{
    const mm_config *cfg = b->cfg;
    mm_db_standing_report said;
    memset(&said, 0, sizeof said);
    said.from_frame = -1;
    said.status = MM_STANDING_NOT_NEEDED;
    for (int i = 0; i < b->count; ++i)
        if (b->clips[i].meta.type == MM_CLIP_IDLE) {
            if (report) *report = said;
            return MM_OK;
        }
    said.status = cfg->standing_make ? MM_STANDING_NOT_FOUND : MM_STANDING_OFF;
    if (!cfg->standing_make) {
        if (report) *report = said;
        return MM_OK;
    }
    /* the clips as recorded: not the mirrors (the pose's mirror is made from it) nor blends; their
     * frames that locomotion plays */
    static const char *const skip_names[] = MM__STANDING_SKIP_TAGS;
    uint64_t skip = 0;
    for (int t = 0; t < cfg->tag_count; ++t)
        for (size_t k = 0; k < sizeof skip_names / sizeof skip_names[0]; ++k)
            if (same_name_any_case(cfg->tag_names[t], skip_names[k])) skip |= (uint64_t)1 << t;
    if (b->postures->crouch_tag >= 0) skip |= (uint64_t)1 << b->postures->crouch_tag;
    const mm_clip **candidates = (const mm_clip **)calloc((size_t)b->count, sizeof(mm_clip *));
    uint8_t **usable = (uint8_t **)calloc((size_t)b->count, sizeof(uint8_t *));
    int *index = (int *)malloc(sizeof(int) * (size_t)b->count), count = 0;
    int *take = (int *)malloc(sizeof(int) * (size_t)b->count); /* as the contacts' (contact_grounds) */
    mm_result r = candidates && usable && index && take ? MM_OK : MM_ERR_OUT_OF_MEMORY;
    for (int i = 0; i < b->count && r == MM_OK; ++i) {
        const built *c = &b->clips[i];
        if (c->blend >= 0 || c->meta.mirrored || c->meta.type != MM_CLIP_LOCOMOTION) continue;
        int n = c->clip.frame_count;
        if (!(usable[count] = (uint8_t *)malloc((size_t)(n > 0 ? n : 1)))) {
            r = MM_ERR_OUT_OF_MEMORY;
            break;
        }
        for (int f = 0; f < n; ++f)
            usable[count][f] =
                !(tags_at(b, c->config_clip, c->meta.source_start + (float)f * cfg->interval) & skip);
        candidates[count] = &c->clip;
        take[count] = 2 * c->meta.source;
        index[count++] = i;
    }
    mm__standing_pick picks[MM__STANDING_POSES];
    int found = 0;
    if (r == MM_OK)
        r = mm__standing_find(cfg, candidates, (const uint8_t *const *)usable, take, count, head_height,
                              MM__STANDING_POSES, picks, &found, &said.standing_frames);
    for (int k = 0; k < found; ++k) picks[k].clip = index[picks[k].clip]; /* now a builder clip */
    for (int i = 0; usable && i < count; ++i) free(usable[i]);
    free(usable);
    free(candidates);
    free(index);
    free(take);
    if (r != MM_OK) return mm_error_set(b->err, r, 0, 0, "standing: out of memory");
    for (int k = 0; k < found; ++k) {
        const built *src = &b->clips[picks[k].clip];
        const mm_clip *file = &b->sources[src->meta.source];
        float t = src->meta.source_start + (float)picks[k].frame * cfg->interval;
        int source_frame = (int)lroundf(t * file->fps);
        built x;
        memset(&x, 0, sizeof x);
        snprintf(x.meta.name, MM_NAME_MAX, MM__STANDING_PREFIX "%.32s_%d", src->meta.name, source_frame);
        x.meta.type = MM_CLIP_IDLE;
        x.meta.loop = 1;
        x.meta.source = src->meta.source;
        x.meta.blend_left = x.meta.blend_right = -1;
        x.meta.source_start = t;
        x.config_clip = -1; /* no tags: the pose stands in no gait */
        x.blend = -1;
        int mirror = cfg->clips[src->meta.source].mirror;
        if (k == 0) {
            said.status = MM_STANDING_MADE;
            said.from_time = t;
            said.from_frame = source_frame;
            said.root_speed = picks[k].root_speed;
            said.joint_speed = picks[k].joint_speed;
            said.stride = picks[k].stride;
            said.offset = picks[k].offset;
            said.mirrored = mirror;
            snprintf(said.from_clip, MM_NAME_MAX, "%s", src->meta.name);
            snprintf(said.clip, MM_NAME_MAX, "%s", x.meta.name);
        }
        ++said.poses;
        if ((r = mm__standing_hold(&src->clip, picks[k].frame, &x.clip, b->a)) != MM_OK)
            return mm_error_set(b->err, r, 0, 0, "standing: out of memory");
        if ((r = push_made(b, &x, mirror, "standing")) != MM_OK) return r;
    }
    if (report) *report = said;
    return MM_OK;
}

/* With idle_loop.make, each idle clip that does not loop gets a loop clip made of its last still
 * stretch (db/idle_loop.h), mirrored when its clip is; says so in report. */
static mm_result add_idle_loops(builder *b, mm_db_idle_loop_report *report)
{
    const mm_config *cfg = b->cfg;
    mm_db_idle_loop_report said;
    memset(&said, 0, sizeof said);
    said.make = cfg->idle_loop_make;
    int count = b->count; /* the clips made so far: not the loops added below */
    for (int i = 0; i < count && said.make; ++i) {
        const built *src = &b->clips[i];
        if (src->meta.type != MM_CLIP_IDLE || src->meta.loop || src->meta.mirrored || src->blend >= 0)
            continue;
        ++said.idle_clips;
        mm__idle_loop loop;
        if (mm__idle_loop_find(&src->clip, &loop) != MM_OK)
            return mm_error_set(b->err, MM_ERR_OUT_OF_MEMORY, 0, 0, "idle loops: out of memory");
        if (!loop.found) {
            if (loop.still_end > loop.still_begin)
                ++said.no_match;
            else
                ++said.no_still;
            continue;
        }
        built x;
        memset(&x, 0, sizeof x);
        snprintf(x.meta.name, MM_NAME_MAX, "%.*s" MM_IDLE_LOOP_SUFFIX,
                 (int)(MM_NAME_MAX - sizeof MM_IDLE_LOOP_SUFFIX - sizeof "_mirror" + 1), src->meta.name);
        x.meta.type = MM_CLIP_IDLE;
        x.meta.loop = 1;
        x.meta.source = src->meta.source;
        x.meta.blend_left = x.meta.blend_right = -1;
        x.meta.source_start = src->meta.source_start + (float)loop.begin * cfg->interval;
        x.config_clip = src->config_clip; /* the tags of the frames it is made of */
        x.blend = -1;
        int mirror = src->config_clip >= 0 && cfg->clips[src->config_clip].mirror;
        mm_result r = mm__idle_loop_make(&src->clip, &loop, &x.clip, b->a);
        if (r != MM_OK) return mm_error_set(b->err, r, 0, 0, "idle loop (%s): out of memory", x.meta.name);
        ++said.made;
        said.seconds += (float)x.clip.frame_count * cfg->interval;
        said.worst_error = fmaxf(said.worst_error, loop.error);
        if ((r = push_made(b, &x, mirror, "idle loop")) != MM_OK) return r; /* src may move from here on */
    }
    if (report) *report = said;
    return MM_OK;
}

/* Runs unit(ctx, u, worker) for every u in [0, count) on the pool's threads (the caller alone
 * without a pool): each thread takes the next unit from a shared counter, so uneven units
 * balance themselves; results must go to places fixed by u. */
typedef void (*unit_fn)(void *ctx, int unit, int worker);

typedef struct par_job {
    atomic_int next;
    int count;
    unit_fn fn;
    void *ctx;
} par_job;

static void par_worker(void *ctx, int worker, int workers)
{
    (void)workers;
    par_job *j = (par_job *)ctx;
    for (int u; (u = atomic_fetch_add(&j->next, 1)) < j->count;) j->fn(j->ctx, u, worker);
}

static void par_for(mm_searcher_pool *pool, int count, unit_fn fn, void *ctx)
{
    par_job j;
    atomic_init(&j.next, 0);
    j.count = count;
    j.fn = fn;
    j.ctx = ctx;
    mm__pool_run(pool, par_worker, &j);
}

/* Copies a unit's error into the caller's, keeping the file name the caller put there. */
static mm_result pass_error(mm_error *to, const mm_error *from, mm_result r)
{
    return mm_error_set(to, r, from->line, from->column, "%s", from->message);
}

/* Stage 1: each config clip's database clips (ranges, mirrors) into its own list. */
typedef struct source_job {
    const mm_config *cfg;
    const mm__postures *postures;
    const mm_clip *sources;
    builder *parts;   /* [clip_count] */
    mm_error *errors; /* [clip_count] */
    mm_result *results;
    const mm_db_build_desc *desc;
    atomic_int done;
    int total, reported; /* progress: reported only by the calling thread (worker 0) */
} source_job;

static void source_unit(void *ctx, int ci, int worker)
{
    source_job *j = (source_job *)ctx;
    builder *part = &j->parts[ci];
    part->cfg = j->cfg;
    part->postures = j->postures;
    part->sources = j->sources;
    part->err = &j->errors[ci];
    j->results[ci] = process_config_clip(part, ci, &j->sources[ci]);
    int done = atomic_fetch_add(&j->done, 1) + 1;
    if (worker == 0 && j->desc && j->desc->progress) {
        j->desc->progress(done, j->total, j->desc->progress_user);
        j->reported = done;
    }
}

static mm_result process_sources(builder *b, const mm_clip *sources, const mm_db_build_desc *desc,
                                 mm_searcher_pool *pool)
{
    int n = b->cfg->clip_count;
    source_job j;
    memset(&j, 0, sizeof j);
    j.cfg = b->cfg;
    j.postures = b->postures;
    j.sources = sources;
    j.parts = (builder *)calloc((size_t)n, sizeof(builder));
    j.errors = (mm_error *)calloc((size_t)n, sizeof(mm_error));
    j.results = (mm_result *)calloc((size_t)n, sizeof(mm_result));
    j.desc = desc;
    atomic_init(&j.done, 0);
    j.total = n + b->cfg->blend_count;
    mm_result r = MM_OK;
    if (!j.parts || !j.errors || !j.results) {
        r = mm_error_set(b->err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    } else {
        par_for(pool, n, source_unit, &j);
        if (desc && desc->progress && j.reported < n) desc->progress(n, j.total, desc->progress_user);
        int count = 0;
        for (int i = 0; i < n && r == MM_OK; ++i) {
            if (j.results[i] != MM_OK) r = pass_error(b->err, &j.errors[i], j.results[i]);
            count += j.parts[i].count;
        }
        if (r == MM_OK &&
            !(b->clips = (built *)malloc(sizeof(built) * (size_t)(count + 2 * b->cfg->blend_count + 1))))
            r = mm_error_set(b->err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
        if (r == MM_OK) {
            b->capacity = count + 2 * b->cfg->blend_count;
            for (int i = 0; i < n; ++i) { /* the clips move; their lists go */
                if (j.parts[i].count > 0) /* a clip whose frames were all left out has none */
                    memcpy(b->clips + b->count, j.parts[i].clips, sizeof(built) * (size_t)j.parts[i].count);
                b->count += j.parts[i].count;
                free(j.parts[i].clips);
            }
        }
    }
    if (r != MM_OK && j.parts)
        for (int i = 0; i < n; ++i) free_builder(&j.parts[i]);
    free(j.parts);
    free(j.errors);
    free(j.results);
    return r;
}

/* The distance curves of every clip's root (joint 0) path, laid out as the file stores them. */
typedef struct distance_arrays {
    mm_db_distance_clip *clips;
    float *travelled, *distance;
    mm_distance_segment *segments;
    mm_distance_curve *curves; /* [clip count] while building */
    int segment_count;
} distance_arrays;

static void free_distance(distance_arrays *d, int clip_count)
{
    if (d->curves)
        for (int i = 0; i < clip_count; ++i) mm_distance_curve_free(&d->curves[i]);
    free(d->curves);
    free(d->clips);
    free(d->travelled);
    free(d->distance);
    free(d->segments);
}

/* Builds clip i's curve from its simulation bone's positions (scratch holds frame_count vec3s)
 * into d->curves[i], its travelled and signed distances into place; segments are joined later. */
static mm_result clip_distance(const builder *b, int i, int first, mm_vec3 *scratch, distance_arrays *d,
                               mm_error *err)
{
    const mm_clip *c = &b->clips[i].clip;
    int n = c->frame_count;
    mm_db_distance_clip *dc = &d->clips[i];
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
    mm_distance_curve *curve = &d->curves[i];
    mm_error e;
    memset(&e, 0, sizeof e);
    mm_result r = mm_distance_curve_build(curve, &desc, &e);
    if (r != MM_OK)
        return mm_error_set(err, r, 0, 0, "clip '%s': cannot build its distance curve: %s",
                            b->clips[i].meta.name, e.message);
    memcpy(d->travelled + first, curve->travelled, sizeof(float) * (size_t)n);
    memcpy(d->distance + first, curve->distance, sizeof(float) * (size_t)n);
    dc->segment_count = curve->segment_count;
    dc->path_length = curve->path_length;
    return MM_OK;
}

/* Joins the clips' segments in clip order. */
static mm_result join_segments(distance_arrays *d, int clip_count, mm_error *err)
{
    int total = 0;
    for (int i = 0; i < clip_count; ++i) total += d->clips[i].segment_count;
    d->segments = (mm_distance_segment *)malloc(sizeof(mm_distance_segment) * (size_t)(total ? total : 1));
    if (!d->segments) return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    for (int i = 0; i < clip_count; ++i) {
        d->clips[i].first_segment = d->segment_count;
        if (d->clips[i].segment_count)
            memcpy(d->segments + d->segment_count, d->curves[i].segments,
                   sizeof(mm_distance_segment) * (size_t)d->clips[i].segment_count);
        d->segment_count += d->clips[i].segment_count;
        mm_distance_curve_free(&d->curves[i]);
    }
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

/* Stage 2: each database clip's frames (poses, tags, contacts, root motion, raw features,
 * distance curve) into its rows. */
typedef struct clip_job {
    const builder *b;
    arrays *x;
    distance_arrays *dist;
    const int *first; /* [clip count] first database frame */
    const int *heel_toe;
    mm__contact_track *const *tracks;  /* [clip count] each clip's heel and toe tracks */
    const mm__contact_ground *grounds; /* [clip count] */
    int group_count, dims_padded, longest;
    mm_xform *globals;   /* [workers x longest x joints] */
    mm_vec3 *root_paths; /* [workers x longest] */
    mm_error *errors;    /* [clip count] */
    mm_result *results;
} clip_job;

static void clip_unit(void *ctx, int i, int worker)
{
    clip_job *j = (clip_job *)ctx;
    const mm_config *cfg = j->b->cfg;
    arrays *x = j->x;
    const built *bc = &j->b->clips[i];
    const mm_clip *c = &bc->clip;
    size_t nj = (size_t)c->skeleton.joint_count, nd = (size_t)j->dims_padded;
    mm_xform *globals = j->globals + (size_t)worker * (size_t)j->longest * nj;
    int n = c->frame_count, first = j->first[i];
    x->clips[i] = bc->meta;
    x->clips[i].first_frame = first;
    x->clips[i].frame_count = n;
    for (int f = 0; f < n; ++f) {
        mm_clip_fk(c, f, globals + (size_t)f * nj);
        int g = first + f;
        x->frame_clip[g] = i;
        x->frame_next[g] = f + 1 < n ? g + 1 : (bc->meta.loop ? first : -1);
        if (bc->blend < 0) {
            x->frame_tags[g] =
                tags_at(j->b, bc->config_clip, bc->meta.source_start + (float)f * cfg->interval);
        } else {
            float u = bc->meta.loop ? (float)f / n : (float)f / (float)(n - 1);
            x->frame_tags[g] = tags_at(j->b, bc->tag_clip_left, bc->start_left + u * bc->period_left) |
                               tags_at(j->b, bc->tag_clip_right, bc->start_right + u * bc->period_right);
        }
    }
    memcpy(x->rotations + (size_t)first * nj, c->rotations, (size_t)n * nj * sizeof(mm_quat));
    memcpy(x->positions + (size_t)first * nj, c->positions, (size_t)n * nj * sizeof(mm_vec3));
    mm__label_contacts(j->tracks[i], n, c->fps, &j->grounds[i], cfg, x->contacts + first);
    mm__root_motion(c, x->root_velocity + first, x->root_yaw_rate + first);
    mm__clip_features(c, bc->meta.loop, globals, x->root_velocity + first, x->groups, j->group_count,
                      cfg->interval, x->features + (size_t)first * nd, j->dims_padded);
    j->results[i] = clip_distance(j->b, i, first, j->root_paths + (size_t)worker * (size_t)j->longest,
                                  j->dist, &j->errors[i]);
}

/* Stage 2a: each database clip's heel and toe tracks, for the contacts' floors over whole takes. */
static void tracks_unit(void *ctx, int i, int worker)
{
    clip_job *j = (clip_job *)ctx;
    const mm_clip *c = &j->b->clips[i].clip;
    size_t nj = (size_t)c->skeleton.joint_count;
    mm_xform *globals = j->globals + (size_t)worker * (size_t)j->longest * nj;
    for (int f = 0; f < c->frame_count; ++f) mm_clip_fk(c, f, globals + (size_t)f * nj);
    mm__contact_tracks(c, globals, j->heel_toe, j->tracks[i]);
}

/* The contacts' grounds of every database clip: a take is a config clip's frames, mirrored apart
 * (a mirrored clip's left heel is the source's right); a blend is a take of its own. */
static mm_result contact_grounds(const builder *b, mm__contact_track *const *tracks, mm__contact_ground *out)
{
    int *take = (int *)malloc(sizeof(int) * (size_t)b->count);
    int *frames = (int *)malloc(sizeof(int) * (size_t)b->count);
    mm_result r = take && frames ? MM_OK : MM_ERR_OUT_OF_MEMORY;
    for (int i = 0; i < b->count && r == MM_OK; ++i) {
        const built *c = &b->clips[i];
        take[i] = c->blend >= 0 ? -1 : 2 * c->meta.source + (c->meta.mirrored ? 1 : 0);
        frames[i] = c->clip.frame_count;
    }
    if (r == MM_OK)
        r = mm__contact_grounds(b->count, take, frames, (const mm__contact_track *const *)tracks, b->cfg,
                                out);
    free(take);
    free(frames);
    return r;
}

/* Stage 3: normalisation: per-dimension mean; per-group scale = mean standard deviation of its
 * dimensions (1 for a group that does not vary). Padding dimensions: mean 0, scale 1. A unit
 * is MM_DB_SIMD_WIDTH dimensions, each summed in frame order in doubles; then blocks of frames
 * are normalised. */
#define NORM_FRAMES 1024

typedef struct norm_job {
    arrays *x;
    int frames, dims, dims_padded;
    double *deviation; /* [dims_padded] */
} norm_job;

static void moments_unit(void *ctx, int u, int worker)
{
    (void)worker;
    norm_job *j = (norm_job *)ctx;
    const float *feat = j->x->features;
    size_t stride = (size_t)j->dims_padded;
    int d0 = u * MM_DB_SIMD_WIDTH, d1 = d0 + MM_DB_SIMD_WIDTH < j->dims ? d0 + MM_DB_SIMD_WIDTH : j->dims;
    double sum[MM_DB_SIMD_WIDTH] = {0}, sq[MM_DB_SIMD_WIDTH] = {0}, mean[MM_DB_SIMD_WIDTH];
    for (int f = 0; f < j->frames; ++f)
        for (int d = d0; d < d1; ++d) sum[d - d0] += feat[(size_t)f * stride + (size_t)d];
    for (int d = d0; d < d1; ++d) mean[d - d0] = sum[d - d0] / j->frames;
    for (int f = 0; f < j->frames; ++f)
        for (int d = d0; d < d1; ++d) {
            double v = feat[(size_t)f * stride + (size_t)d] - mean[d - d0];
            sq[d - d0] += v * v;
        }
    for (int d = d0; d < d1; ++d) {
        j->x->mean[d] = (float)mean[d - d0];
        j->deviation[d] = sqrt(sq[d - d0] / j->frames);
    }
}

static void apply_unit(void *ctx, int u, int worker)
{
    (void)worker;
    norm_job *j = (norm_job *)ctx;
    const arrays *x = j->x;
    int f1 = (u + 1) * NORM_FRAMES < j->frames ? (u + 1) * NORM_FRAMES : j->frames;
    for (int f = u * NORM_FRAMES; f < f1; ++f)
        for (int d = 0; d < j->dims_padded; ++d) {
            float *v = &x->features[(size_t)f * (size_t)j->dims_padded + (size_t)d];
            *v = (*v - x->mean[d]) / x->scale[d];
        }
}

static mm_result normalise(arrays *x, int frames, int dims, int dims_padded, int group_count,
                           mm_searcher_pool *pool, mm_error *err)
{
    norm_job j;
    j.x = x;
    j.frames = frames;
    j.dims = dims;
    j.dims_padded = dims_padded;
    j.deviation = (double *)calloc((size_t)dims_padded, sizeof(double));
    if (!j.deviation) return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    for (int d = 0; d < dims_padded; ++d) {
        x->mean[d] = 0.0f;
        x->scale[d] = 1.0f;
    }
    par_for(pool, (dims + MM_DB_SIMD_WIDTH - 1) / MM_DB_SIMD_WIDTH, moments_unit, &j);
    for (int g = 0; g < group_count; ++g) {
        const mm_feature_group *grp = &x->groups[g];
        double spread = 0.0;
        for (int d = grp->offset; d < grp->offset + grp->dims; ++d) spread += j.deviation[d];
        spread /= grp->dims;
        /* Below 1e-5 (m, m/s or unit vectors) a group does not vary: float noise must not be
         * blown up into features. */
        float s = spread > 1e-5 ? (float)spread : 1.0f;
        x->groups[g].scale = s;
        for (int d = grp->offset; d < grp->offset + grp->dims; ++d) x->scale[d] = s;
    }
    par_for(pool, (frames + NORM_FRAMES - 1) / NORM_FRAMES, apply_unit, &j);
    free(j.deviation);
    return MM_OK;
}

/* Stage 4: bounding boxes; a unit is NORM_FRAMES frames of blocks (both block sizes divide it). */
typedef struct bounds_job {
    const float *features;
    int frames, dims_padded;
    float *small_min, *small_max, *large_min, *large_max;
} bounds_job;

static void bounds(const float *features, int frames, int dims_padded, int block, int b0, int b1, float *mn,
                   float *mx)
{
    int blocks = (frames + block - 1) / block;
    if (b1 > blocks) b1 = blocks;
    for (int b = b0; b < b1; ++b) {
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

static void bounds_unit(void *ctx, int u, int worker)
{
    (void)worker;
    const bounds_job *j = (const bounds_job *)ctx;
    int s = NORM_FRAMES / MM_DB_SMALL_BLOCK, l = NORM_FRAMES / MM_DB_LARGE_BLOCK;
    bounds(j->features, j->frames, j->dims_padded, MM_DB_SMALL_BLOCK, u * s, (u + 1) * s, j->small_min,
           j->small_max);
    bounds(j->features, j->frames, j->dims_padded, MM_DB_LARGE_BLOCK, u * l, (u + 1) * l, j->large_min,
           j->large_max);
}

mm_result mm_database_build(const mm_config *cfg, const mm_clip *sources, const mm_db_build_desc *desc,
                            mm_database *out, mm_error *err)
{
    if (!out) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no output");
    memset(out, 0, sizeof *out);
    if (!cfg || (!sources && cfg->clip_count))
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no config");
    if (desc && (desc->threads < 0 || desc->threads > MM_DB_MAX_THREADS))
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "threads: %d is not in [0, %d]",
                            desc->threads, MM_DB_MAX_THREADS);
    mm_result r = mm_config_validate(cfg, err);
    if (r != MM_OK) return r;
    if (cfg->clip_count < 1)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "clips: the config lists no clip");
    for (int i = 0; i < cfg->clip_count; ++i) {
        mm_error why;
        memset(&why, 0, sizeof why);
        if (cfg->clips[i].mirror && (r = mm__mirror_check(&sources[i].skeleton, cfg, &why)) != MM_OK)
            return mm_error_set(err, r, 0, 0, "clips[%d] (%s): cannot mirror: %s", i, cfg->clips[i].name,
                                why.message);
    }
    /* NULL (one thread, or no threads could start): everything runs on the calling thread */
    mm_searcher_pool *pool =
        desc && desc->threads > 1 ? mm__pool_create(desc->threads, desc->allocator) : NULL;
    int workers = mm__pool_size(pool);
    mm__postures postures;
    r = mm__postures_find(cfg, sources, &postures, desc ? desc->report : NULL, err);
    if (r != MM_OK) {
        mm__pool_destroy(pool);
        mm__postures_free(&postures);
        return r;
    }
    builder b;
    memset(&b, 0, sizeof b);
    b.cfg = cfg;
    b.postures = &postures;
    b.sources = sources;
    b.err = err;
    int total = cfg->clip_count + cfg->blend_count;
    r = process_sources(&b, sources, desc, pool);
    for (int i = 0; i < cfg->blend_count && r == MM_OK; ++i) {
        r = process_blend(&b, i);
        if (desc && desc->progress) desc->progress(cfg->clip_count + i + 1, total, desc->progress_user);
    }
    if (r == MM_OK && b.count == 0)
        r = mm_error_set(
            err, MM_ERR_INVALID_ARGUMENT, 0, 0,
            "no frames left: every clip's frames are calibration or lying poses (postures.detect)");
    if (r == MM_OK) r = check_skeletons(&b);
    if (r == MM_OK)
        r = add_standing(&b, postures.reference_head_height,
                         desc && desc->report ? &desc->report->standing : NULL);
    if (r == MM_OK) r = add_idle_loops(&b, desc && desc->report ? &desc->report->idle_loops : NULL);
    if (r != MM_OK) {
        mm__pool_destroy(pool);
        free_builder(&b);
        mm__postures_free(&postures);
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
        mm__pool_destroy(pool);
        free_builder(&b);
        mm__postures_free(&postures);
        return err ? err->code : MM_ERR_NOT_FOUND;
    }
    int dims_padded = (dims + MM_DB_SIMD_WIDTH - 1) / MM_DB_SIMD_WIDTH * MM_DB_SIMD_WIDTH;
    if (dims_padded == 0) dims_padded = MM_DB_SIMD_WIDTH;
    size_t nf = (size_t)frames, nj = (size_t)jc, nd = (size_t)dims_padded;
    size_t small = (size_t)(frames + MM_DB_SMALL_BLOCK - 1) / MM_DB_SMALL_BLOCK;
    size_t large = (size_t)(frames + MM_DB_LARGE_BLOCK - 1) / MM_DB_LARGE_BLOCK;
    x.joints = (mm_joint *)calloc(nj, sizeof(mm_joint));
    x.clips = (mm_db_clip *)calloc((size_t)b.count, sizeof(mm_db_clip));
    x.tag_names = (char(*)[MM_TAG_NAME_MAX])calloc((size_t)postures.tag_count + 1, MM_TAG_NAME_MAX);
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
    dist.curves = (mm_distance_curve *)calloc((size_t)b.count, sizeof(mm_distance_curve));
    dist.travelled = (float *)calloc(nf, 4);
    dist.distance = (float *)calloc(nf, 4);
    int longest = 0;
    for (int i = 0; i < b.count; ++i)
        longest = b.clips[i].clip.frame_count > longest ? b.clips[i].clip.frame_count : longest;
    clip_job cj;
    memset(&cj, 0, sizeof cj);
    int heel_toe[4] = {mm_skeleton_find(skel, cfg->left_foot), mm_skeleton_find(skel, cfg->left_toe),
                       mm_skeleton_find(skel, cfg->right_foot), mm_skeleton_find(skel, cfg->right_toe)};
    int *first = (int *)malloc(sizeof(int) * (size_t)b.count);
    cj.globals = (mm_xform *)malloc(sizeof(mm_xform) * (size_t)workers * (size_t)longest * nj);
    cj.root_paths = (mm_vec3 *)malloc(sizeof(mm_vec3) * (size_t)workers * (size_t)longest);
    cj.errors = (mm_error *)calloc((size_t)b.count, sizeof(mm_error));
    cj.results = (mm_result *)calloc((size_t)b.count, sizeof(mm_result));
    mm__contact_track **tracks = (mm__contact_track **)calloc((size_t)b.count, sizeof *tracks);
    mm__contact_ground *grounds = (mm__contact_ground *)calloc((size_t)b.count, sizeof *grounds);
    mm__contact_track *track_frames = (mm__contact_track *)malloc(sizeof(mm__contact_track) * 4 * nf);
    if (tracks && track_frames)
        for (int i = 0, f = 0; i < b.count; f += b.clips[i++].clip.frame_count)
            tracks[i] = track_frames + (size_t)f * 4;
    if (!dist.clips || !dist.curves || !dist.travelled || !dist.distance || !cj.root_paths || !x.joints ||
        !x.clips || !x.tag_names || !x.frame_clip || !x.frame_next || !x.frame_tags || !x.contacts ||
        !x.root_velocity || !x.root_yaw_rate || !x.rotations || !x.positions || !x.features || !x.mean ||
        !x.scale || !x.small_min || !x.small_max || !x.large_min || !x.large_max || !cj.globals || !first ||
        !cj.errors || !cj.results || !tracks || !grounds || !track_frames)
        r = mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory for %d frames", frames);
    if (r == MM_OK) {
        memcpy(x.joints, skel->joints, nj * sizeof(mm_joint));
        for (int t = 0; t < cfg->tag_count; ++t) memcpy(x.tag_names[t], cfg->tag_names[t], MM_TAG_NAME_MAX);
        if (postures.crouch_tag >= cfg->tag_count)
            snprintf(x.tag_names[postures.crouch_tag], MM_TAG_NAME_MAX, "Crouch");
        for (int i = 0, f = 0; i < b.count; f += b.clips[i++].clip.frame_count) first[i] = f;
        cj.b = &b;
        cj.x = &x;
        cj.dist = &dist;
        cj.first = first;
        cj.heel_toe = heel_toe;
        cj.group_count = group_count;
        cj.dims_padded = dims_padded;
        cj.longest = longest;
        cj.tracks = tracks;
        cj.grounds = grounds;
        par_for(pool, b.count, tracks_unit, &cj);
        if (contact_grounds(&b, tracks, grounds) != MM_OK)
            r = mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory for the contacts' floors");
    }
    if (r == MM_OK) {
        par_for(pool, b.count, clip_unit, &cj);
        for (int i = 0; i < b.count && r == MM_OK; ++i)
            if (cj.results[i] != MM_OK) r = pass_error(err, &cj.errors[i], cj.results[i]);
    }
    free(cj.globals);
    free(cj.root_paths);
    free(cj.errors);
    free(cj.results);
    free(tracks);
    free(grounds);
    free(track_frames);
    free(first);
    if (r == MM_OK) r = join_segments(&dist, b.count, err);
    if (r == MM_OK) r = normalise(&x, frames, dims, dims_padded, group_count, pool, err);
    if (r == MM_OK) {
        bounds_job bj = {x.features, frames, dims_padded, x.small_min, x.small_max, x.large_min, x.large_max};
        par_for(pool, (frames + NORM_FRAMES - 1) / NORM_FRAMES, bounds_unit, &bj);
    }
    mm__pool_destroy(pool);
    if (r != MM_OK) {
        free_distance(&dist, b.count);
        free_arrays(&x);
        free_builder(&b);
        mm__postures_free(&postures);
        return r;
    }

    mm__db_parts p;
    memset(&p, 0, sizeof p);
    p.frame_count = frames;
    p.joint_count = jc;
    p.clip_count = b.count;
    p.tag_count = postures.tag_count;
    p.group_count = group_count;
    p.dims = dims;
    p.dims_padded = dims_padded;
    p.interval = cfg->interval;
    /* the runtime settings, resolved against the database's skeleton and feature groups */
    mm_database view;
    memset(&view, 0, sizeof view);
    view.joints = x.joints;
    view.joint_count = jc;
    view.groups = x.groups;
    view.group_count = group_count;
    view.dims = dims;
    view.dims_padded = dims_padded;
    /* and its clips, tags and root velocities, for the speed envelope */
    view.frame_count = p.frame_count;
    view.interval = cfg->interval;
    view.clips = x.clips;
    view.clip_count = b.count;
    view.tag_names = (const char(*)[MM_TAG_NAME_MAX])x.tag_names;
    view.tag_count = postures.tag_count;
    view.frame_tags = x.frame_tags;
    view.root_velocity = x.root_velocity;
    mm_database_settings settings;
    r = mm__db_settings_resolve(cfg, &view, &settings, err);
    if (r != MM_OK) {
        free_distance(&dist, b.count);
        free_arrays(&x);
        free_builder(&b);
        mm__postures_free(&postures);
        return r;
    }
    const char *json = desc && desc->config_json ? desc->config_json : "";
    const void *data[MM__SEC_COUNT] = {
        x.joints,     x.clips,        x.tag_names,   x.groups,        x.frame_clip,
        x.frame_next, x.frame_tags,   x.contacts,    x.root_velocity, x.root_yaw_rate,
        x.rotations,  x.positions,    x.features,    x.mean,          x.scale,
        x.small_min,  x.small_max,    x.large_min,   x.large_max,     json,
        dist.clips,   dist.travelled, dist.distance, dist.segments,   &settings};
    memcpy(p.data, data, sizeof data);
    p.size[MM__SEC_CONFIG_JSON] = strlen(json) + 1;
    p.size[MM__SEC_DISTANCE_SEGMENTS] = sizeof(mm_distance_segment) * (size_t)dist.segment_count;
    r = mm__db_pack(&p, desc ? desc->allocator : NULL, out, err);
    if (r == MM_OK && desc && desc->compress) { /* the shipping form: the poses compressed */
        mm_db_compress_desc cd = *desc->compress;
        if (cd.threads == 0) cd.threads = workers;
        if (!cd.allocator) cd.allocator = desc->allocator;
        mm_database floats = *out;
        r = mm_database_compress(&floats, &cd, out, err);
        mm_database_free(&floats);
    }
    free_distance(&dist, b.count);
    free_arrays(&x);
    free_builder(&b);
    mm__postures_free(&postures);
    return r;
}
