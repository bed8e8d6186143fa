/* The frame spans of a take (mm/take_spans.h). */
#include <mm/take_spans.h>

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "db/process.h"

void mm_take_spans_desc_defaults(mm_take_spans_desc *d)
{
    d->pad = 1.0f;
    d->idle_speed = 0.15f;
    d->idle_min = 1.0f;
    d->low_hips = 0.0f;
}

void mm_take_spans_free(mm_take_spans *s)
{
    if (!s) return;
    free(s->kinds);
    free(s->excluded);
    free(s->idle);
    free(s->locomotion);
    memset(s, 0, sizeof *s);
}

const char *mm_span_kind_name(int kind)
{
    if (kind >= 0 && kind < MM_POSTURE_COUNT) return mm_posture_name((mm_posture)kind);
    return kind == MM_SPAN_A_POSE       ? "a_pose"
           : kind == MM_SPAN_GETTING_UP ? "getting_up"
           : kind == MM_SPAN_DOWN       ? "down"
                                        : NULL;
}

bool mm_span_left_out(int kind)
{
    return kind == MM_POSTURE_CALIBRATION || kind == MM_SPAN_A_POSE || kind == MM_POSTURE_LYING ||
           kind == MM_SPAN_GETTING_UP || kind == MM_SPAN_DOWN;
}

/* Whether joint j is the joint body or hangs from it. */
static int in_body(const mm_skeleton *s, int body, int j)
{
    for (; j >= 0; j = s->joints[j].parent)
        if (j == body) return 1;
    return body < 0;
}

/* A frame of this kind is part of a stretch of being low: crouched, bent or lying. */
static int low(int k) { return k == MM_POSTURE_CROUCHED || k == MM_POSTURE_BENT || k == MM_POSTURE_LYING; }

/* Each frame's kind from the world positions w [n x jc] (n >= 1), against the take's upright head
 * height (mm_posture_reference_height of the head's heights above the ground). The ground under a
 * frame is the take's floor (the median over frames of the lowest joint, as the database build
 * takes it), raised to the lowest joint of the frames within MM_SPAN_GROUND_SECONDS when that is
 * higher: a body standing on a box or an obstacle is not taller, and a jump, shorter than that,
 * keeps the floor it leaves (a body tucked in the air is not crouched). 0: out of memory. */
static int judge(const mm_clip *clip, const mm_vec3 *w, const mm_take_joints *jt, mm_take_spans *out)
{
    int n = clip->frame_count, jc = clip->skeleton.joint_count;
    float fps = clip->fps;
    uint8_t *kind = out->kinds;
    float *v = (float *)malloc(sizeof(float) * (size_t)n),
          *ground = (float *)malloc(sizeof(float) * (size_t)n),
          *lowest = (float *)malloc(sizeof(float) * (size_t)n);
    int *to_lying = (int *)malloc(sizeof(int) * (size_t)n), *to_down = (int *)malloc(sizeof(int) * (size_t)n);
    uint8_t *a_pose = (uint8_t *)calloc((size_t)n, 1);
    if (!v || !ground || !lowest || !to_lying || !to_down || !a_pose) {
        free(v);
        free(ground);
        free(lowest);
        free(to_lying);
        free(to_down);
        free(a_pose);
        return 0;
    }
    /* the body is the hips and what hangs from them: a root joint above the hips, left at the
     * origin or on the ground, is no part of it (parents come first) */
    for (int f = 0; f < n; ++f) {
        lowest[f] = INFINITY;
        for (int j = 0; j < jc; ++j)
            if (in_body(&clip->skeleton, jt->hips, j))
                lowest[f] = fminf(lowest[f], w[(size_t)f * (size_t)jc + (size_t)j].y);
    }
    memcpy(v, lowest, sizeof(float) * (size_t)n);
    float floor = mm__quantile(v, n, 0.5f); /* the take's floor: the median of the lowest joint */
    int reach = (int)lroundf(MM_SPAN_GROUND_SECONDS * fps);
    for (int f = 0; f < n; ++f) {
        int a = f - reach < 0 ? 0 : f - reach, b = f + reach >= n ? n - 1 : f + reach;
        ground[f] = lowest[a];
        for (int k = a + 1; k <= b; ++k) ground[f] = fminf(ground[f], lowest[k]);
        ground[f] = fmaxf(ground[f], floor);
    }
    /* the upright heights over the frame's own lowest joint (when above the floor): the frames just
     * up a step, or in the air, do not make the body taller */
    const mm_vec3 *head = w + jt->head, *hips = w + jt->hips;
    for (int f = 0; f < n; ++f) v[f] = hips[(size_t)f * (size_t)jc].y - fmaxf(lowest[f], floor);
    float upright_hips = mm_posture_reference_height(v, n);
    for (int f = 0; f < n; ++f) v[f] = head[(size_t)f * (size_t)jc].y - fmaxf(lowest[f], floor);
    mm_posture_reference ref = {mm_posture_reference_height(v, n)};
    out->upright_head_height = ref.head_height;
    /* the knees are not judged here: a knee raised stays in the spans, the database build cuts it */
    mm_posture_joints joints = {jt->hips, jt->head, jt->left_hand, jt->right_hand, {-1, -1}, {-1, -1}};
    for (int f = 0; f < n; ++f)
        kind[f] = (uint8_t)mm_posture_classify(w + (size_t)f * (size_t)jc, &joints, ground[f], &ref);
    mm_posture_remove_flicker(kind, n, (int)lroundf(MM_POSTURE_MIN_SECONDS * fps));
    /* A poses held still: calibration, whatever the frame-by-frame posture said */
    mm_posture_arms arms;
    out->arms_found = mm_posture_find_arms(&clip->skeleton, jt->left_hand, jt->right_hand, &arms);
    if (out->arms_found && mm_posture_find_a_poses(w, n, jc, fps, &arms, &joints, ground, &ref, a_pose) > 0)
        for (int f = 0; f < n; ++f)
            if (a_pose[f]) kind[f] = MM_SPAN_A_POSE;
    /* the frames of a low stretch within MM_SPAN_TRANSITION_SECONDS of a lying frame of it, or of
     * a frame of it with the hips down: two passes give each frame its distance to the nearest */
    for (int pass = 0; pass < 2; ++pass)
        for (int i = 0, last_lying = -1, last_down = -1; i < n; ++i) {
            int f = pass ? n - 1 - i : i;
            if (!low(kind[f])) {
                last_lying = last_down = -1;
                if (!pass) to_lying[f] = to_down[f] = INT_MAX;
                continue;
            }
            if (kind[f] == MM_POSTURE_LYING) last_lying = f;
            if (hips[(size_t)f * (size_t)jc].y - ground[f] < MM_SPAN_DOWN_HIPS * upright_hips) last_down = f;
            int dl = last_lying >= 0 ? abs(f - last_lying) : INT_MAX,
                dd = last_down >= 0 ? abs(f - last_down) : INT_MAX;
            to_lying[f] = pass && to_lying[f] < dl ? to_lying[f] : dl;
            to_down[f] = pass && to_down[f] < dd ? to_down[f] : dd;
        }
    reach = (int)lroundf(MM_SPAN_TRANSITION_SECONDS * fps);
    for (int f = 0; f < n; ++f)
        if (low(kind[f]) && kind[f] != MM_POSTURE_LYING && (to_lying[f] <= reach || to_down[f] <= reach))
            kind[f] = to_lying[f] <= reach ? MM_SPAN_GETTING_UP : MM_SPAN_DOWN;
    free(v);
    free(ground);
    free(lowest);
    free(to_lying);
    free(to_down);
    free(a_pose);
    return 1;
}

/* The runs of at least 2 frames where in[f] is set, into list. */
static int ranges_of(const uint8_t *in, int n, mm_config_range *list)
{
    int count = 0;
    for (int f = 0; f < n;) {
        int e = f;
        while (e < n && (in[e] != 0) == (in[f] != 0)) ++e;
        if (in[f] && e - f >= 2) {
            list[count].begin = f;
            list[count].end = e;
            ++count;
        }
        f = e;
    }
    return count;
}

mm_result mm_take_spans_find(const mm_clip *clip, const mm_take_joints *joints,
                             const mm_take_spans_desc *desc, mm_take_spans *out)
{
    memset(out, 0, sizeof *out);
    mm_take_spans_desc d;
    mm_take_spans_desc_defaults(&d);
    if (desc) d = *desc;
    int n = clip->frame_count, jc = clip->skeleton.joint_count;
    const int needed[3] = {joints->hips, joints->root_bone, joints->head};
    for (int k = 0; k < 3; ++k)
        if (needed[k] < 0 || needed[k] >= jc) return MM_ERR_INVALID_ARGUMENT;
    mm_take_joints jt = *joints;
    if (jt.left_hand >= jc || jt.right_hand >= jc || jt.left_hand < 0 || jt.right_hand < 0)
        jt.left_hand = jt.right_hand = -1;
    if (!(clip->fps > 0.0f) || n < 0) return MM_ERR_INVALID_ARGUMENT;
    double fps = clip->fps;
    mm_xform *g = (mm_xform *)malloc(sizeof(mm_xform) * (size_t)jc);
    mm_vec3 *w = (mm_vec3 *)malloc(sizeof(mm_vec3) * ((size_t)n + 1) * (size_t)jc);
    uint8_t *excluded = (uint8_t *)calloc((size_t)n + 1, 1), *idle = (uint8_t *)calloc((size_t)n + 1, 1),
            *in = (uint8_t *)calloc((size_t)n + 1, 1);
    size_t room = (size_t)n / 2 + 1;
    out->frame_count = n;
    out->kinds = (uint8_t *)calloc((size_t)n + 1, 1);
    out->excluded = (mm_config_range *)malloc(sizeof(mm_config_range) * room);
    out->idle = (mm_config_range *)malloc(sizeof(mm_config_range) * room);
    out->locomotion = (mm_config_range *)malloc(sizeof(mm_config_range) * room);
    int ok = g && w && excluded && idle && in && out->kinds && out->excluded && out->idle && out->locomotion;
    if (ok) {
        for (int f = 0; f < n; ++f) {
            mm_clip_fk(clip, f, g);
            for (int j = 0; j < jc; ++j) w[(size_t)f * (size_t)jc + (size_t)j] = g[j].translation;
        }
        ok = n == 0 || judge(clip, w, &jt, out);
    }
    if (ok) {
        /* left out: calibration, lying, getting up, down (and, deprecated, the hips below low_hips),
         * widened by pad seconds on each side (pad and idle_min may be huge: clamped to the take) */
        for (int f = 0; f < n; ++f)
            in[f] = mm_span_left_out(out->kinds[f]) ||
                    (d.low_hips > 0.0f && w[(size_t)f * (size_t)jc + (size_t)jt.hips].y < d.low_hips);
        int widen = (int)lround(fmin((double)d.pad * fps, (double)n));
        for (int f = 0, last = -1; f < n; ++f) {
            if (in[f]) last = f;
            if (last >= 0 && f - last <= widen) excluded[f] = 1;
        }
        for (int f = n - 1, next = -1; f >= 0; --f) {
            if (in[f]) next = f;
            if (next >= 0 && next - f <= widen) excluded[f] = 1;
        }
        /* idle: root speed (central differences over +-0.1 s) below idle_speed for idle_min seconds */
        int h = (int)lround(0.1 * fps) > 0 ? (int)lround(0.1 * fps) : 1,
            min_len = (int)lround(fmin((double)d.idle_min * fps, (double)n + 1.0));
        const mm_vec3 *root = w + jt.root_bone;
        for (int f = 0; f < n;) {
            int e = f;
            while (e < n && !excluded[e]) {
                int a = e - h < 0 ? 0 : e - h, b = e + h >= n ? n - 1 : e + h;
                const mm_vec3 pa = root[(size_t)a * (size_t)jc], pb = root[(size_t)b * (size_t)jc];
                double speed = b > a ? hypot(pb.x - pa.x, pb.z - pa.z) * fps / (b - a) : 0;
                if (speed >= d.idle_speed) break;
                ++e;
            }
            if (e - f >= min_len)
                for (int k = f; k < e; ++k) idle[k] = 1;
            f = e > f ? e : f + 1;
        }
        out->excluded_count = ranges_of(excluded, n, out->excluded);
        for (int f = 0; f < n; ++f) in[f] = !excluded[f] && idle[f];
        out->idle_count = ranges_of(in, n, out->idle);
        for (int f = 0; f < n; ++f) in[f] = !excluded[f] && !idle[f];
        out->locomotion_count = ranges_of(in, n, out->locomotion);
    }
    free(g);
    free(w);
    free(excluded);
    free(idle);
    free(in);
    if (!ok) {
        mm_take_spans_free(out);
        return MM_ERR_OUT_OF_MEMORY;
    }
    return MM_OK;
}
