/* A database config from the takes alone (mm/config_init.h). */
#include <mm/config_init.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "db/process.h"

/* ---- gait speeds ------------------------------------------------------------------------ */

#define MM_GAIT_MIN_SECONDS 0.25 /* s of windows a speed is measured on */
#define MM_GAIT_PEAK_BAND   1.1f /* the walk's pace: the speed with the most windows within /1.1 to x1.1 */
#define MM_GAIT_WALK_SPREAD 1.5f /* the walk: the windows within /1.5 to x1.5 of its pace */

typedef struct speed_list {
    float *v;
    int n, cap;
    double seconds;
} speed_list;

static int push_speed(speed_list *l, float v, double dt)
{
    if (l->n == l->cap) {
        int cap = l->cap ? 2 * l->cap : 1024;
        float *p = (float *)realloc(l->v, sizeof(float) * (size_t)cap);
        if (!p) return 0;
        l->v = p;
        l->cap = cap;
    }
    l->v[l->n++] = v;
    l->seconds += dt;
    return 1;
}

/* The windows of frames [b, e) (a piece of a span): p the root's x z per frame, sum the prefix
 * sums of the unit facing. 0: out of memory. */
static int piece_speeds(const double *p, const double *sum, int b, int e, float fps, speed_list lists[3])
{
    const double cos45 = sqrt(0.5);
    int h = (int)lround(0.5 * MM_GAIT_WINDOW * fps);
    if (h > (e - b) / 8) h = (e - b) / 8;
    if (h < 1) return 1;
    for (int f = b + h; f + h < e; ++f) {
        double vx = (p[2 * (f + h)] - p[2 * (f - h)]) * fps / (2.0 * h);
        double vz = (p[2 * (f + h) + 1] - p[2 * (f - h) + 1]) * fps / (2.0 * h);
        double speed = hypot(vx, vz);
        if (speed < MM_GAIT_SPEED_MIN) continue;
        double fx = sum[2 * (f + h + 1)] - sum[2 * (f - h)],
               fz = sum[2 * (f + h + 1) + 1] - sum[2 * (f - h) + 1];
        double fl = hypot(fx, fz);
        if (fl < 1e-6) continue;
        double c = (vx * fx + vz * fz) / (speed * fl);
        int dir = c >= cos45 ? 0 : c <= -cos45 ? 2 : 1;
        if (!push_speed(&lists[dir], (float)speed, 1.0 / fps)) return 0;
    }
    return 1;
}

/* Frame f is played by the walk and run gaits: it and every frame within pad of it are upright.
 * The build tags crouched and bent frames Crouch (the crouch gait's), leaves out arms spread,
 * and cuts pad more around each change of posture (docs/database.md, "Postures"). */
static int gait_frame(const mm_take_spans *spans, int f, int pad)
{
    if (pad < 0) return 1; /* every frame */
    for (int k = f - pad; k <= f + pad; ++k)
        if (k >= 0 && k < spans->frame_count && spans->kinds[k] != MM_POSTURE_UPRIGHT) return 0;
    return 1;
}

/* Root speeds of the locomotion spans in windows, by direction in the facing frame: forward
 * within 45 degrees of the facing, backward within 45 degrees of its opposite, sideways between.
 * Only the pieces of the spans the walk and run gaits play count (gait_frame, pad seconds; all
 * with pad_seconds < 0). */
static mm_result collect_speeds(const mm_clip *clip, const mm_take_spans *spans, int root_bone, int facing,
                                mm_vec3 axis, float pad_seconds, speed_list lists[3])
{
    int n = clip->frame_count, jc = clip->skeleton.joint_count;
    mm_xform *g = (mm_xform *)malloc(sizeof(mm_xform) * (size_t)jc);
    double *p = (double *)malloc(sizeof(double) * 4 * (size_t)(n + 1)); /* x z | facing prefix sums */
    if (!g || !p) {
        free(g);
        free(p);
        return MM_ERR_OUT_OF_MEMORY;
    }
    double *sum = p + 2 * (size_t)n; /* [2 (n + 1)] prefix sums of the unit facing */
    sum[0] = sum[1] = 0.0;
    axis = mm_vec3_normalize(axis);
    for (int f = 0; f < n; ++f) {
        mm_clip_fk(clip, f, g);
        p[2 * f] = g[root_bone].translation.x;
        p[2 * f + 1] = g[root_bone].translation.z;
        mm_vec3 d = mm_quat_rotate(g[facing].rotation, axis);
        double len = hypot(d.x, d.z);
        sum[2 * f + 2] = sum[2 * f] + (len > 1e-6 ? d.x / len : 0.0);
        sum[2 * f + 3] = sum[2 * f + 1] + (len > 1e-6 ? d.z / len : 0.0);
    }
    int ok = 1;
    int pad = pad_seconds < 0.0f ? -1 : (int)lroundf(pad_seconds * clip->fps);
    for (int s = 0; s < spans->locomotion_count && ok; ++s)
        for (int b = spans->locomotion[s].begin, end = spans->locomotion[s].end; b < end && ok;) {
            if (!gait_frame(spans, b, pad)) {
                ++b;
                continue;
            }
            int e = b + 1;
            while (e < end && gait_frame(spans, e, pad)) ++e;
            ok = piece_speeds(p, sum, b, e, clip->fps, lists);
            b = e;
        }
    free(g);
    free(p);
    return ok ? MM_OK : MM_ERR_OUT_OF_MEMORY;
}

static float round_speed(float v)
{
    float r = roundf(v * 20.0f) / 20.0f;
    return r < 0.05f ? 0.05f : r;
}

/* The q quantile of the speeds of l in [lo, hi) (hi 0: no bound), when they last at least
 * MM_GAIT_MIN_SECONDS. 0 otherwise. */
static int quantile_between(const speed_list *l, float lo, float hi, float q, mm_gait_speed_estimate *out)
{
    float *v = (float *)malloc(sizeof(float) * (size_t)(l->n + 1));
    if (!v) return 0;
    int n = 0;
    for (int i = 0; i < l->n; ++i)
        if (l->v[i] >= lo && (hi <= 0.0f || l->v[i] < hi)) v[n++] = l->v[i];
    double seconds = l->n ? l->seconds * n / l->n : 0.0;
    int found = seconds >= MM_GAIT_MIN_SECONDS && n > 0;
    if (found) {
        out->speed = round_speed(mm__quantile(v, n, q));
        out->seconds = (float)seconds;
        out->quantile = q;
    }
    free(v);
    return found;
}

/* The walk's own pace in l: the speed under MM_GAIT_SPEED_RUN with the most windows within
 * MM_GAIT_PEAK_BAND of it (the slowest of equals); 0 when there is none. */
static float walk_peak(const speed_list *l)
{
    float *v = (float *)malloc(sizeof(float) * (size_t)(l->n + 1));
    if (!v) return 0.0f;
    int n = 0;
    for (int i = 0; i < l->n; ++i)
        if (l->v[i] < MM_GAIT_SPEED_RUN) v[n++] = l->v[i];
    mm__quantile(v, n, 0.0f); /* sorts */
    float peak = 0.0f;
    int best = 0;
    for (int i = 0, lo = 0, hi = 0; i < n; ++i) {
        while (v[lo] < v[i] / MM_GAIT_PEAK_BAND) ++lo;
        while (hi < n && v[hi] <= v[i] * MM_GAIT_PEAK_BAND) ++hi;
        if (hi - lo > best) {
            best = hi - lo;
            peak = v[i];
        }
    }
    free(v);
    return peak;
}

static void estimate_speeds(speed_list lists[3], mm_config_init_report *rep, mm_runtime_config *rt)
{
    mm_gait_speed_estimate(*e)[3] = rep->speeds;
    memset(rep->speeds, 0, sizeof rep->speeds);
    rep->moving_seconds = (float)(lists[0].seconds + lists[1].seconds + lists[2].seconds);
    if (rep->moving_seconds < MM_GAIT_MIN_SECONDS)
        return; /* the takes never move: the runtime keeps its defaults */
    static const float walk_q[3] = {0.85f, 0.5f, 0.6f};
    for (int d = 0; d < 3; ++d) {
        /* the walk around its own pace: not the stroll or jog a take also holds for a moment */
        float peak = walk_peak(&lists[d]), lo = peak / MM_GAIT_WALK_SPREAD,
              hi = fminf(peak * MM_GAIT_WALK_SPREAD, MM_GAIT_SPEED_RUN);
        if (!(peak > 0.0f && quantile_between(&lists[d], lo, hi, walk_q[d], &e[0][d])) &&
            !quantile_between(&lists[d], 0.0f, 0.0f, 0.1f, &e[0][d])) { /* running alone: the slowest of it */
            e[0][d].speed = MM_GAIT_SPEED_MIN;                          /* not moving this way: a creep */
            e[0][d].seconds = e[0][d].quantile = 0.0f;
        }
        mm_gait_speed_estimate running; /* takes that never run: the brisk end of their walk */
        int runs = quantile_between(&lists[d], MM_GAIT_SPEED_RUN, 0.0f, 0.5f, &running);
        if (!(runs ? quantile_between(&lists[d], 0.0f, 0.0f, 0.95f, &e[1][d])
                   : peak > 0.0f && quantile_between(&lists[d], lo, hi, 0.95f, &e[1][d]))) {
            e[1][d] = e[0][d];
            e[1][d].seconds = 0.0f;
            e[1][d].quantile = 0.0f;
        }
        if (d == 0 && runs && running.speed > e[1][d].speed) /* a short run forward among long walks */
            e[1][d] = running;
        if (e[1][d].speed < e[0][d].speed) e[1][d].speed = e[0][d].speed;
    }
    mm_runtime_gait *gaits[2] = {&rt->walk, &rt->run};
    for (int k = 0; k < 2; ++k) {
        gaits[k]->forward_speed = e[k][0].speed;
        gaits[k]->side_speed = e[k][1].speed;
        gaits[k]->backward_speed = e[k][2].speed;
        gaits[k]->set |= MM_RUNTIME_FORWARD_SPEED | MM_RUNTIME_SIDE_SPEED | MM_RUNTIME_BACKWARD_SPEED;
    }
}

/* ---- the config ------------------------------------------------------------------------- */

/* Puts clip's joints in reference's order when both have the same joints (names) with the same
 * parents (files of one skeleton often list its joints in different orders). 0: they differ. */
static int reorder_like(const mm_skeleton *reference, mm_clip *clip)
{
    const mm_skeleton *s = &clip->skeleton;
    int n = reference->joint_count, same = 1;
    if (s->joint_count != n) return 0;
    int *map = (int *)malloc(sizeof(int) * (size_t)n);
    if (!map) return 0;
    for (int j = 0; j < n; ++j) {
        map[j] = mm_skeleton_find(s, reference->joints[j].name);
        int rp = reference->joints[j].parent, sp = map[j] >= 0 ? s->joints[map[j]].parent : -2;
        if (map[j] < 0 || (rp < 0) != (sp < 0) ||
            (rp >= 0 && strcmp(reference->joints[rp].name, s->joints[sp].name) != 0)) {
            free(map);
            return 0;
        }
        same &= map[j] == j;
    }
    mm_clip sorted;
    if (!same && mm_clip_init(&sorted, reference, clip->frame_count, clip->fps, NULL) == MM_OK) {
        for (int f = 0; f < clip->frame_count; ++f)
            for (int j = 0; j < n; ++j) {
                mm_clip_rotations(&sorted, f)[j] = mm_clip_rotations(clip, f)[map[j]];
                mm_clip_positions(&sorted, f)[j] = mm_clip_positions(clip, f)[map[j]];
            }
        for (int j = 0; j < n; ++j) { /* each take keeps its own offsets */
            sorted.skeleton.joints[j] = s->joints[map[j]];
            sorted.skeleton.joints[j].parent = reference->joints[j].parent;
        }
        mm_clip_free(clip);
        *clip = sorted;
    } else if (!same) {
        free(map);
        return 0;
    }
    free(map);
    return 1;
}

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

/* The body's upright height in file units: the 0.9 quantile of the height over up to 16 frames of
 * every take. */
static float upright_height(const mm_clip *clips, int count)
{
    float h[16 * 64];
    int n = 0, per = count > 64 ? 1 : 16;
    for (int t = 0; t < count && t < 1024 && n < (int)(sizeof h / sizeof h[0]); ++t) {
        const mm_clip *c = &clips[t];
        int frames = c->frame_count < per ? c->frame_count : per;
        for (int k = 0; k < frames && n < (int)(sizeof h / sizeof h[0]); ++k) {
            int f = (int)((k + 0.5) * c->frame_count / frames);
            h[n++] =
                mm_skeleton_estimate_height(&c->skeleton, mm_clip_rotations(c, f), mm_clip_positions(c, f));
        }
    }
    if (n == 0) return 0.0f;
    qsort(h, (size_t)n, sizeof(float), cmp_float);
    return h[(int)(0.9f * (float)(n - 1))];
}

/* The file's name without folders and extension, or the take's name. */
static void stem_of(const mm_config_init_take *t, char *out, size_t size)
{
    if (t->name && t->name[0]) {
        snprintf(out, size, "%s", t->name);
        return;
    }
    const char *base = strrchr(t->file, '/');
    base = base ? base + 1 : t->file;
    size_t n = strcspn(base, ".");
    snprintf(out, size, "%.*s", (int)n, base);
    if (t->take && t->take[0]) {
        size_t len = strlen(out);
        snprintf(out + len, size - len, "_%s", t->take);
    }
}

static int name_used(const mm_config *cfg, const char *name)
{
    for (int i = 0; i < cfg->clip_count; ++i)
        if (strcmp(cfg->clips[i].name, name) == 0) return 1;
    return 0;
}

/* A clip of take t's spans (kind "" or "_idle"), unless it has none. */
static mm_result add_clip(mm_config *cfg, const mm_config_init_take *t, const char *stem, const char *kind,
                          const mm_config_range *ranges, int count, mm_clip_type type, bool mirror)
{
    if (count == 0) return MM_OK;
    mm_config_clip *c = &cfg->clips[cfg->clip_count];
    memset(c, 0, sizeof *c);
    snprintf(c->name, MM_NAME_MAX, "%s%s", stem, kind);
    snprintf(c->file, MM_PATH_MAX, "%s", t->file);
    if (t->take) snprintf(c->take, MM_NAME_MAX, "%s", t->take);
    c->type = type;
    c->mirror = mirror;
    c->ranges = (mm_config_range *)mm_alloc_array(&cfg->allocator, (size_t)count, sizeof(mm_config_range));
    if (!c->ranges) return MM_ERR_OUT_OF_MEMORY;
    memcpy(c->ranges, ranges, sizeof(mm_config_range) * (size_t)count);
    c->range_count = count;
    cfg->clip_count++;
    return MM_OK;
}

mm_result mm_config_init(const mm_config_init_take *takes, int count, const mm_config_init_desc *desc,
                         mm_config *out, mm_config_init_report *report, mm_error *err)
{
    double scale = desc ? desc->scale : 0.0;
    mm_config_init_report local;
    mm_config_init_report *rep = report ? report : &local;
    memset(rep, 0, sizeof *rep);
    mm_config_defaults(out);
    if (!takes || count < 1) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no takes given");
    for (int t = 0; t < count; ++t)
        if (!takes[t].clip || !takes[t].file || !takes[t].file[0])
            return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "take %d: no clip or file name", t);
    /* frame rates, length */
    rep->fps_min = INFINITY;
    for (int t = 0; t < count; ++t) {
        const mm_clip *c = takes[t].clip;
        rep->fps_min = fminf(rep->fps_min, c->fps);
        rep->fps_max = fmaxf(rep->fps_max, c->fps);
        rep->seconds += c->frame_count / c->fps;
    }
    /* up and forward: detected from the first take whose up is clear (given in desc), and every
     * take whose up is clear must agree */
    int given_up = desc && desc->up_given && desc->up_axis >= 0 && desc->up_axis < 6 ? desc->up_axis : -1;
    int first = -1;
    rep->up_axis = MM_AXIS_POS_Y; /* no telling: the BVH convention */
    for (int t = 0; t < count; ++t) {
        if (takes[t].clip->frame_count < 2 && !(t == count - 1 && first < 0)) continue;
        float confidence = 0.0f;
        int up = mm_clip_up_axis(takes[t].clip, &confidence);
        if (first < 0 && confidence > rep->up_confidence) rep->up_confidence = confidence;
        if (confidence < MM_UP_MIN_CONFIDENCE) continue;
        if (first < 0) {
            first = t;
            rep->up_axis = up;
            rep->up_confidence = confidence;
            rep->up_detected = true;
        } else if (up != rep->up_axis && given_up < 0) {
            if (err)
                snprintf(err->file, sizeof err->file, "%s", takes[t].path ? takes[t].path : takes[t].file);
            return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0,
                                "the body stands along %s (confidence %.2f) but along %s in %s: the takes of "
                                "one config share their axes; give the up axis (--up)",
                                mm_axis_name(up), (double)confidence, mm_axis_name(rep->up_axis),
                                takes[first].path ? takes[first].path : takes[first].file);
        }
    }
    rep->up_given = given_up >= 0;
    if (given_up >= 0) rep->up_axis = given_up;
    rep->forward_given = desc && desc->forward_given && desc->forward_axis >= 0 && desc->forward_axis < 6;
    rep->forward_axis = mm_axes_forward(rep->up_axis, rep->forward_given ? desc->forward_axis : -1);
    if (rep->forward_axis % 3 == rep->up_axis % 3)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "forward %s lies along up %s",
                            mm_axis_name(rep->forward_axis), mm_axis_name(rep->up_axis));
    out->axes_up = rep->up_axis;
    out->axes_forward =
        rep->up_axis == MM_AXIS_POS_Y && rep->forward_axis == MM_AXIS_POS_Z ? -1 : rep->forward_axis;
    const mm_quat turn = mm_axes_turn(rep->up_axis, rep->forward_axis);
    const bool turned = rep->up_axis != MM_AXIS_POS_Y || rep->forward_axis != MM_AXIS_POS_Z;

    /* the takes turned to +Y up, +Z forward, then in metres */
    mm_clip *metric = (mm_clip *)calloc((size_t)count, sizeof(mm_clip));
    mm_take_spans *spans = (mm_take_spans *)calloc((size_t)count, sizeof(mm_take_spans));
    speed_list lists[3], all_lists[3]; /* the windows the walk and run gaits play; all of them */
    memset(lists, 0, sizeof lists);
    memset(all_lists, 0, sizeof all_lists);
    mm_result r = metric && spans ? MM_OK : MM_ERR_OUT_OF_MEMORY;
    int made = 0;
    for (int t = 0; t < count && r == MM_OK; ++t) {
        r = mm_clip_copy(&metric[t], takes[t].clip, NULL);
        if (r == MM_OK) {
            ++made;
            if (turned) mm_clip_turn(&metric[t], turn);
        }
    }
    /* unit */
    float raw_height = r == MM_OK ? upright_height(metric, count) : 0.0f;
    rep->scale = scale > 0.0 ? scale : mm_unit_scale_for_height(raw_height);
    if (r == MM_OK && !(rep->scale > 0.0))
        r = mm_error_set(
            err, MM_ERR_OUT_OF_RANGE, 0, 0,
            "the body is %g file units tall along %s: no unit (metres, centimetres, millimetres, "
            "inches, feet, CMU units) gives a human height; give the scale (or the up axis)",
            (double)raw_height, mm_axis_name(rep->up_axis));
    rep->height = (float)(raw_height * rep->scale);
    out->scale = (float)rep->scale;
    out->interval = 1.0f / 60.0f;
    for (int t = 0; t < count && r == MM_OK; ++t) {
        mm_clip_scale(&metric[t], (float)rep->scale);
        if (t > 0 && !reorder_like(&metric[0].skeleton, &metric[t])) {
            if (err)
                snprintf(err->file, sizeof err->file, "%s", takes[t].path ? takes[t].path : takes[t].file);
            r = mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0,
                             "another skeleton than %s's (joint names or parents differ)",
                             takes[0].path ? takes[0].path : takes[0].file);
        }
    }
    if (r == MM_OK) {
        r = mm_skeleton_roles_find(metric, count, &rep->roles, err);
    } else if (r == MM_ERR_OUT_OF_MEMORY && !(err && err->message[0])) {
        mm_error_set(err, r, 0, 0, "out of memory");
    }
    if (r == MM_OK) {
        const mm_skeleton_roles *roles = &rep->roles;
        mm_skeleton_roles_apply(roles, &metric[0].skeleton, out);
        out->clips =
            (mm_config_clip *)mm_alloc_array(&out->allocator, (size_t)count * 2, sizeof(mm_config_clip));
        if (!out->clips) r = mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
        int root = roles->roles[MM_BODY_ROOT_BONE].joint;
        int facing = roles->roles[MM_BODY_FACING_BONE].joint;
        const mm_take_joints joints = {
            roles->roles[MM_BODY_HIPS].joint, root, roles->roles[MM_BODY_HEAD].joint,
            roles->roles[MM_BODY_LEFT_HAND].joint, roles->roles[MM_BODY_RIGHT_HAND].joint};
        for (int t = 0; t < count && r == MM_OK; ++t) {
            if (metric[t].frame_count < 2) continue;
            r = mm_take_spans_find(&metric[t], &joints, NULL, &spans[t]);
            if (r == MM_OK) {
                const mm_take_spans *s = &spans[t];
                for (int f = 0; f < s->frame_count; ++f)
                    rep->kind_seconds[s->kinds[f]] += 1.0f / metric[t].fps;
                rep->calibration_starts += s->frame_count > 0 && (s->kinds[0] == MM_POSTURE_CALIBRATION ||
                                                                  s->kinds[0] == MM_SPAN_A_POSE);
                rep->arms_missing += !s->arms_found;
            }
            if (r == MM_OK)
                r = collect_speeds(&metric[t], &spans[t], root, facing, roles->forward_axis,
                                   out->postures_pad, lists);
            if (r == MM_OK)
                r = collect_speeds(&metric[t], &spans[t], root, facing, roles->forward_axis, -1.0f,
                                   all_lists);
            if (r != MM_OK) {
                mm_error_set(err, r, 0, 0, "out of memory");
                break;
            }
            const mm_take_spans *s = &spans[t];
            for (int i = 0; i < s->locomotion_count; ++i)
                rep->locomotion_seconds += (s->locomotion[i].end - s->locomotion[i].begin) / metric[t].fps;
            for (int i = 0; i < s->idle_count; ++i)
                rep->idle_seconds += (s->idle[i].end - s->idle[i].begin) / metric[t].fps;
            for (int i = 0; i < s->excluded_count; ++i)
                rep->excluded_seconds += (s->excluded[i].end - s->excluded[i].begin) / metric[t].fps;
            /* a name no other clip has, with room for "_idle" */
            char stem[MM_NAME_MAX], base[MM_NAME_MAX], idle[MM_NAME_MAX + 8];
            stem_of(&takes[t], base, 48);
            snprintf(stem, sizeof stem, "%s", base);
            for (int k = 2;; ++k) {
                snprintf(idle, sizeof idle, "%s_idle", stem);
                if (!name_used(out, stem) && !name_used(out, idle)) break;
                snprintf(stem, sizeof stem, "%.47s_%d", base, k % 100000);
            }
            r = add_clip(out, &takes[t], stem, "", s->locomotion, s->locomotion_count, MM_CLIP_LOCOMOTION,
                         roles->mirror);
            if (r == MM_OK)
                r = add_clip(out, &takes[t], stem, "_idle", s->idle, s->idle_count, MM_CLIP_IDLE,
                             roles->mirror);
            if (r != MM_OK) mm_error_set(err, r, 0, 0, "out of memory");
        }
        if (r == MM_OK && out->clip_count == 0)
            r = mm_error_set(err, MM_ERR_NOT_FOUND, 0, 0,
                             "no take has frames to use: every frame lies down or the takes are too short");
        if (r == MM_OK) /* takes that only crouch: their speeds all the same */
            estimate_speeds(lists[0].seconds + lists[1].seconds + lists[2].seconds >= MM_GAIT_MIN_SECONDS
                                ? lists
                                : all_lists,
                            rep, &out->runtime);
        if (r == MM_OK && !(desc && desc->no_tuning)) { /* configs/mocap.json's tuning */
            mm_runtime_config *rt = &out->runtime;
            out->contact_speed = 0.3f;
            rt->sync_halflife = 0.1f;
            rt->distance_matching = rt->warping = true;
            rt->set |= MM_RUNTIME_SYNC_HALFLIFE | MM_RUNTIME_DISTANCE_MATCHING | MM_RUNTIME_WARPING;
            rt->walk.rotation_halflife = 0.3f;
            rt->run.rotation_halflife = 0.35f;
            rt->run.velocity_halflife = 0.4f;
            rt->walk.set |= MM_RUNTIME_ROTATION_HALFLIFE;
            rt->run.set |= MM_RUNTIME_ROTATION_HALFLIFE | MM_RUNTIME_VELOCITY_HALFLIFE;
        }
    }
    for (int t = 0; t < made; ++t) mm_clip_free(&metric[t]);
    for (int t = 0; spans && t < count; ++t) mm_take_spans_free(&spans[t]);
    for (int d = 0; d < 3; ++d) {
        free(lists[d].v);
        free(all_lists[d].v);
    }
    free(metric);
    free(spans);
    if (r != MM_OK) mm_config_free(out);
    return r;
}
