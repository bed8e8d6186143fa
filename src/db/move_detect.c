/* Moves beyond locomotion in motion capture: foot plants at any height, flights, hand plants and
 * level changes, grouped into moves and classified (mm/move_detect.h explains the rules). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <mm/database_build.h>
#include <mm/move_detect.h>

#include "db/process.h"

void mm_move_params_defaults(mm_move_params *p)
{
    p->plant_speed = 0.5f;
    p->min_plant_time = 0.1f;
    p->min_flight_time = 0.25f;
    p->level_change = 0.4f;
    p->drop_height = 0.5f;
    p->hand_min_height = 0.5f;
    p->hand_travel = 0.3f;
    p->vault_high_height = 1.5f;
    p->merge_gap = 0.5f;
    p->lead_in = 1.0f;
    p->lead_out = 1.0f;
}

static const char *const kind_tags[MM_MOVE_KIND_COUNT] = {"Jump", "VaultLow", "VaultHigh", "Climb", "Drop"};

const char *mm_move_kind_tag(mm_move_kind k)
{
    return (int)k >= 0 && k < MM_MOVE_KIND_COUNT ? kind_tags[k] : NULL;
}

/* ---- helpers ---------------------------------------------------------------------------- */

static mm_vec3 track(const mm_vec3 *t, int frame, int which)
{
    return t[(size_t)frame * MM_MOVE_TRACK_COUNT + which];
}

typedef struct plant {
    int begin, end; /* frames, inclusive */
    int foot;       /* 0 left, 1 right; hands: 0 left, 1 right */
    float height;   /* of the surface (feet) or of the hand */
} plant;

typedef struct anchor {
    int begin, end; /* frames, inclusive */
    int kind;       /* 0 flight, 1 hand plant, 2 level change */
    int plant;      /* hand plant index for kind 1 */
} anchor;

static int compare_plants(const void *a, const void *b)
{
    const plant *x = (const plant *)a, *y = (const plant *)b;
    if (x->begin != y->begin) return (x->begin > y->begin) - (x->begin < y->begin);
    return (x->foot > y->foot) - (x->foot < y->foot);
}

static int compare_anchors(const void *a, const void *b)
{
    const anchor *x = (const anchor *)a, *y = (const anchor *)b;
    if (x->begin != y->begin) return (x->begin > y->begin) - (x->begin < y->begin);
    if (x->end != y->end) return (x->end > y->end) - (x->end < y->end);
    return (x->kind > y->kind) - (x->kind < y->kind);
}

/* Planted flags of the tracks in which[0..3] (bit k for which[k]): the database's contact
 * detector at any height (horizontal speed, flicker removed), and also vertically slow. */
static void plant_flags(const mm_vec3 *tracks, int n, float fps, const mm_move_params *p, const int which[4],
                        mm_xform *scratch, uint8_t *flags, uint8_t *run)
{
    mm_clip view; /* the contact detector reads only the frame count, joint count and fps */
    memset(&view, 0, sizeof view);
    view.fps = fps;
    view.frame_count = n;
    view.skeleton.joint_count = MM_MOVE_TRACK_COUNT;
    for (int f = 0; f < n; ++f)
        for (int t = 0; t < MM_MOVE_TRACK_COUNT; ++t) {
            scratch[(size_t)f * MM_MOVE_TRACK_COUNT + t].rotation = mm_quat_identity();
            scratch[(size_t)f * MM_MOVE_TRACK_COUNT + t].translation = track(tracks, f, t);
        }
    mm_config cfg;
    mm_config_defaults(&cfg);
    cfg.contact_height = INFINITY; /* any height: surfaces are what we look for */
    cfg.contact_speed = p->plant_speed;
    cfg.contact_min_time = p->min_plant_time;
    mm__detect_contacts(&view, scratch, which, &cfg, flags);
    int min_len = (int)lroundf(p->min_plant_time * fps);
    for (int k = 0; k < 4; ++k) {
        if (which[k] < 0) continue;
        for (int f = 0; f < n; ++f) {
            mm_vec3 a = track(tracks, f, which[k]),
                    b = track(tracks, f > 0 ? f - 1 : (n > 1 ? 1 : 0), which[k]);
            float vy = fabsf(a.y - b.y) * fps;
            run[f] = (flags[f] >> k & 1u) && vy < p->plant_speed;
        }
        mm__remove_short_runs(run, n, 0, min_len);
        mm__remove_short_runs(run, n, 1, min_len);
        for (int f = 0; f < n; ++f) flags[f] = (uint8_t)((flags[f] & ~(1u << k)) | (run[f] ? 1u << k : 0u));
    }
}

/* Runs of (flags & mask) != 0 as plants of the given foot; heights from height[]. Returns the
 * count added. */
static int add_runs(const uint8_t *flags, uint8_t mask, int n, int foot, const float *height, float *sort,
                    plant *out, int at)
{
    int count = 0, f = 0;
    while (f < n) {
        if (!(flags[f] & mask)) {
            ++f;
            continue;
        }
        int g = f;
        while (g < n && (flags[g] & mask)) ++g;
        memcpy(sort, height + f, sizeof(float) * (size_t)(g - f));
        plant *pl = &out[at + count++];
        pl->begin = f;
        pl->end = g - 1;
        pl->foot = foot;
        pl->height = mm__quantile(sort, g - f, 0.5f);
        f = g;
    }
    return count;
}

/* ---- detection -------------------------------------------------------------------------- */

typedef struct work {
    uint8_t *feet, *hands, *run;
    float *height[2], *hand_height[2], *sort;
    mm_xform *scratch;
    plant *plants, *hand_plants;
    anchor *anchors;
} work;

static void free_work(work *w)
{
    free(w->feet);
    free(w->hands);
    free(w->run);
    for (int i = 0; i < 2; ++i) {
        free(w->height[i]);
        free(w->hand_height[i]);
    }
    free(w->sort);
    free(w->scratch);
    free(w->plants);
    free(w->hand_plants);
    free(w->anchors);
}

mm_result mm_moves_detect(const mm_vec3 *tracks, int frame_count, float fps, const mm_move_params *params,
                          mm_move *out, int capacity, int *count, mm_error *err)
{
    if (count) *count = 0;
    mm_move_params p;
    if (params)
        p = *params;
    else
        mm_move_params_defaults(&p);
    if (!tracks || !count || frame_count < 0 || (capacity > 0 && !out) || !(fps > 0.0f) || !isfinite(fps))
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0,
                            "moves: tracks, a frame count and fps > 0 are needed");
    /* zero means default; MM_OFF (negative) is 0 */
    mm_move_params def;
    mm_move_params_defaults(&def);
    float *fields = &p.plant_speed;
    const float *fallback = &def.plant_speed;
    for (size_t i = 0; i < sizeof p / sizeof(float); ++i) {
        fields[i] = fields[i] == 0.0f ? fallback[i] : fields[i] < 0.0f ? 0.0f : fields[i];
        if (!isfinite(fields[i]))
            return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0, "moves: parameter %zu must be finite", i);
    }
    for (size_t i = 0; i < (size_t)frame_count * MM_MOVE_TRACK_COUNT; ++i)
        if (!isfinite(tracks[i].x) || !isfinite(tracks[i].y) || !isfinite(tracks[i].z))
            return mm_error_set(err, MM_ERR_BAD_NUMBER, 0, 0, "moves: frame %d has a non-finite position",
                                (int)(i / MM_MOVE_TRACK_COUNT));
    int n = frame_count;
    if (n < 3) return MM_OK;

    work w;
    memset(&w, 0, sizeof w);
    size_t un = (size_t)n;
    w.feet = (uint8_t *)malloc(un);
    w.hands = (uint8_t *)malloc(un);
    w.run = (uint8_t *)malloc(un);
    for (int i = 0; i < 2; ++i) {
        w.height[i] = (float *)malloc(sizeof(float) * un);
        w.hand_height[i] = (float *)malloc(sizeof(float) * un);
    }
    w.sort = (float *)malloc(sizeof(float) * un * 4);
    w.scratch = (mm_xform *)malloc(sizeof(mm_xform) * un * MM_MOVE_TRACK_COUNT);
    /* a plant lasts two frames or more (min run 1 frame each side at worst): n plants bound it */
    w.plants = (plant *)malloc(sizeof(plant) * (un + 1));
    w.hand_plants = (plant *)malloc(sizeof(plant) * (un + 1));
    w.anchors = (anchor *)malloc(sizeof(anchor) * (3 * un + 3));
    if (!w.feet || !w.hands || !w.run || !w.height[0] || !w.height[1] || !w.hand_height[0] ||
        !w.hand_height[1] || !w.sort || !w.scratch || !w.plants || !w.hand_plants || !w.anchors) {
        free_work(&w);
        return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    }

    /* feet: bit 0 left ankle, 1 left toe, 2 right ankle, 3 right toe (the database's order) */
    static const int foot_tracks[4] = {MM_MOVE_TRACK_LEFT_FOOT, MM_MOVE_TRACK_LEFT_TOE,
                                       MM_MOVE_TRACK_RIGHT_FOOT, MM_MOVE_TRACK_RIGHT_TOE};
    plant_flags(tracks, n, fps, &p, foot_tracks, w.scratch, w.feet, w.run);
    /* each joint's height above the sole: its 5th percentile height less the floor's (the lowest
     * of the four), the way the contact detector finds its floor */
    float p5[4], floor_y = INFINITY, sole[4];
    for (int k = 0; k < 4; ++k) {
        for (int f = 0; f < n; ++f) w.sort[f] = track(tracks, f, foot_tracks[k]).y;
        p5[k] = mm__quantile(w.sort, n, 0.05f);
        floor_y = fminf(floor_y, p5[k]);
    }
    for (int k = 0; k < 4; ++k) sole[k] = p5[k] - floor_y;
    for (int foot = 0; foot < 2; ++foot)
        for (int f = 0; f < n; ++f) {
            float h = INFINITY;
            for (int k = 2 * foot; k < 2 * foot + 2; ++k)
                if (w.feet[f] >> k & 1u) h = fminf(h, track(tracks, f, foot_tracks[k]).y - sole[k]);
            w.height[foot][f] = h;
        }
    int plant_count = 0;
    for (int foot = 0; foot < 2; ++foot)
        plant_count += add_runs(w.feet, (uint8_t)(3u << (2 * foot)), n, foot, w.height[foot], w.sort,
                                w.plants, plant_count);
    qsort(w.plants, (size_t)plant_count, sizeof(plant), compare_plants);

    /* hands: bit 0 left, 1 right */
    static const int hand_tracks[4] = {MM_MOVE_TRACK_LEFT_HAND, MM_MOVE_TRACK_RIGHT_HAND, -1, -1};
    plant_flags(tracks, n, fps, &p, hand_tracks, w.scratch, w.hands, w.run);
    int hand_count = 0;
    for (int hand = 0; hand < 2; ++hand) {
        for (int f = 0; f < n; ++f) w.hand_height[hand][f] = track(tracks, f, hand_tracks[hand]).y;
        hand_count += add_runs(w.hands, (uint8_t)(1u << hand), n, hand, w.hand_height[hand], w.sort,
                               w.hand_plants, hand_count);
    }
    qsort(w.hand_plants, (size_t)hand_count, sizeof(plant), compare_plants);

    /* anchors */
    int anchor_count = 0, min_flight = (int)lroundf(p.min_flight_time * fps),
        min_plant = (int)lroundf(p.min_plant_time * fps);
    for (int f = 0; f < n;) { /* flights: no foot planted, plants on both sides */
        if (w.feet[f]) {
            ++f;
            continue;
        }
        int g = f;
        while (g < n && !w.feet[g]) ++g;
        if (f > 0 && g < n && g - f >= min_flight) w.anchors[anchor_count++] = (anchor){f - 1, g, 0, -1};
        f = g;
    }
    for (int i = 0; i < hand_count; ++i) { /* hand plants above the feet, the body moving past */
        const plant *h = &w.hand_plants[i];
        float level = plant_count > 0 ? w.plants[0].height : floor_y;
        for (int k = 0; k < plant_count && w.plants[k].begin <= h->begin; ++k) level = w.plants[k].height;
        if (h->height - level < p.hand_min_height) continue;
        /* the hand carries the body: for a while no foot is planted (while walking, a swinging
           hand stands still for an instant but a foot is always down) */
        int unsupported = 0;
        for (int f = h->begin; f <= h->end; ++f) unsupported += !w.feet[f];
        if (unsupported < min_plant) continue;
        int t = hand_tracks[h->foot];
        mm_vec3 rel0 = mm_vec3_sub(track(tracks, h->begin, MM_MOVE_TRACK_HIPS), track(tracks, h->begin, t));
        float travel = 0.0f;
        for (int f = h->begin; f <= h->end; ++f) {
            mm_vec3 rel = mm_vec3_sub(track(tracks, f, MM_MOVE_TRACK_HIPS), track(tracks, f, t));
            travel = fmaxf(travel, mm_vec3_length(mm_vec3_sub(rel, rel0)));
        }
        if (travel >= p.hand_travel) w.anchors[anchor_count++] = (anchor){h->begin, h->end, 1, i};
    }
    for (int k = 1; k < plant_count; ++k) /* a foot on a new level */
        if (fabsf(w.plants[k].height - w.plants[k - 1].height) >= p.level_change)
            w.anchors[anchor_count++] = (anchor){w.plants[k].begin, w.plants[k].begin, 2, -1};
    qsort(w.anchors, (size_t)anchor_count, sizeof(anchor), compare_anchors);

    /* moves: anchors merged, then take-off, landing and the kind */
    int found = 0, gap = (int)lroundf(p.merge_gap * fps);
    for (int i = 0; i < anchor_count;) {
        int a = w.anchors[i].begin, b = w.anchors[i].end, j = i + 1;
        bool flight = w.anchors[i].kind == 0;
        int hand = w.anchors[i].kind == 1 ? w.anchors[i].plant : -1;
        while (j < anchor_count && w.anchors[j].begin <= b + gap) {
            if (w.anchors[j].end > b) b = w.anchors[j].end;
            if (w.anchors[j].kind == 0) flight = true;
            if (w.anchors[j].kind == 1 && hand < 0) hand = w.anchors[j].plant;
            ++j;
        }
        i = j;
        /* take-off: the last foot leaves the surface it stood on before the move */
        int take_off = -1;
        float h0 = 0.0f;
        for (int k = 0; k < plant_count && w.plants[k].begin < a; ++k)
            if (w.plants[k].end > take_off) take_off = w.plants[k].end, h0 = w.plants[k].height;
        if (take_off < 0 || take_off > b + gap) continue; /* the feet never left */
        /* the surface it ends on: the last plant to start by the move's end (or the first after
         * the take-off when that is later); the landing: the first plant on it */
        int first_after = -1;
        for (int k = 0; k < plant_count && first_after < 0; ++k)
            if (w.plants[k].begin > take_off) first_after = k;
        if (first_after < 0) continue; /* the clip ends in the air */
        int until = b > w.plants[first_after].begin ? b : w.plants[first_after].begin;
        float h1 = w.plants[first_after].height;
        for (int k = first_after; k < plant_count && w.plants[k].begin <= until; ++k) h1 = w.plants[k].height;
        int landing = -1;
        for (int k = first_after; k < plant_count && landing < 0; ++k)
            if (fabsf(w.plants[k].height - h1) < 0.5f * p.level_change) landing = w.plants[k].begin;
        float dh = h1 - h0;
        mm_move m;
        memset(&m, 0, sizeof m);
        m.take_off = take_off;
        m.landing = landing;
        m.flight = flight;
        m.start_height = h0;
        m.end_height = h1;
        m.hand_plant = hand >= 0 ? w.hand_plants[hand].begin : -1;
        m.hand = hand >= 0 ? w.hand_plants[hand].foot : -1;
        m.obstacle_height = hand >= 0 ? w.hand_plants[hand].height - h0 : 0.0f;
        if (dh <= -p.drop_height) {
            m.kind = MM_MOVE_DROP;
        } else if (flight && hand < 0) {
            m.kind = MM_MOVE_JUMP;
        } else if (dh >= p.level_change && hand >= 0) {
            m.kind = MM_MOVE_CLIMB;
        } else if (hand >= 0 && dh < p.level_change) {
            /* a vault: the hips pass the planted hand along the direction of travel */
            const plant *h = &w.hand_plants[hand];
            mm_vec3 at = track(tracks, h->begin, hand_tracks[h->foot]);
            int from = h->begin < take_off ? h->begin : take_off;
            mm_vec3 s = track(tracks, from, MM_MOVE_TRACK_HIPS),
                    e = track(tracks, landing, MM_MOVE_TRACK_HIPS);
            float dx = e.x - s.x, dz = e.z - s.z, len = sqrtf(dx * dx + dz * dz);
            if (!(len > 0.1f)) continue;
            float before = ((s.x - at.x) * dx + (s.z - at.z) * dz) / len,
                  after = ((e.x - at.x) * dx + (e.z - at.z) * dz) / len;
            if (!(before < 0.0f && after > 0.0f)) continue;
            m.kind = m.obstacle_height >= p.vault_high_height ? MM_MOVE_VAULT_HIGH : MM_MOVE_VAULT_LOW;
        } else {
            continue; /* a step up or down without hands or flight, or a hand that was not passed */
        }
        int first = a < take_off ? a : take_off;
        if (m.hand_plant >= 0 && m.hand_plant < first) first = m.hand_plant;
        int last = b > landing ? b : landing;
        m.begin = first - (int)lroundf(p.lead_in * fps);
        if (m.begin < 0) m.begin = 0;
        m.end = last + 1 + (int)lroundf(p.lead_out * fps);
        if (m.end > n) m.end = n;
        if (found < capacity) out[found] = m;
        ++found;
    }
    free_work(&w);
    *count = found;
    return MM_OK;
}

static int find_joint(const mm_skeleton *s, const char *name)
{
    for (int j = 0; j < s->joint_count; ++j)
        if (strcmp(s->joints[j].name, name) == 0) return j;
    return -1;
}

mm_result mm_moves_detect_clip(const mm_clip *clip, const mm_config *cfg, const mm_move_params *params,
                               mm_move *out, int capacity, int *count, mm_error *err)
{
    if (count) *count = 0;
    if (!clip || !cfg || !count)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "moves: a clip, config and count are needed");
    const char *roles[MM_MOVE_TRACK_COUNT] = {cfg->hips,      cfg->left_foot, cfg->right_foot, cfg->left_toe,
                                              cfg->right_toe, cfg->left_hand, cfg->right_hand};
    static const char *const role_names[MM_MOVE_TRACK_COUNT] = {
        "hips", "left_foot", "right_foot", "left_toe", "right_toe", "left_hand", "right_hand"};
    int joints[MM_MOVE_TRACK_COUNT];
    for (int t = 0; t < MM_MOVE_TRACK_COUNT; ++t)
        if ((joints[t] = find_joint(&clip->skeleton, roles[t])) < 0)
            return mm_error_set(err, MM_ERR_NOT_FOUND, 0, 0, "roles.%s: the skeleton has no joint '%s'",
                                role_names[t], roles[t]);
    int n = clip->frame_count, jc = clip->skeleton.joint_count;
    mm_vec3 *tracks = (mm_vec3 *)malloc(sizeof(mm_vec3) * (size_t)(n > 0 ? n : 1) * MM_MOVE_TRACK_COUNT);
    mm_xform *global = (mm_xform *)malloc(sizeof(mm_xform) * (size_t)jc);
    if (!tracks || !global) {
        free(tracks);
        free(global);
        return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    }
    for (int f = 0; f < n; ++f) {
        mm_clip_fk(clip, f, global);
        for (int t = 0; t < MM_MOVE_TRACK_COUNT; ++t)
            tracks[(size_t)f * MM_MOVE_TRACK_COUNT + t] = global[joints[t]].translation;
    }
    mm_result r = mm_moves_detect(tracks, n, clip->fps, params, out, capacity, count, err);
    free(tracks);
    free(global);
    return r;
}
