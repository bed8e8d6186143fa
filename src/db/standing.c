/* A standing pose for a database whose takes have no idle clip (db/standing.h). */
#include "db/standing.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <mm/database.h>
#include <mm/posture.h>

#include "db/process.h"

static float ground_distance(mm_vec3 a, mm_vec3 b)
{
    float dx = a.x - b.x, dz = a.z - b.z;
    return sqrtf(dx * dx + dz * dz);
}

/* Per-frame measures of one clip. */
typedef struct frame_measure {
    float root_speed, joint_speed, stride, offset;
    int standing; /* upright with both feet flat */
} frame_measure;

static void heel_toe_of(const mm_skeleton *s, const mm_config *cfg, int heel_toe[4])
{
    heel_toe[0] = mm_skeleton_find(s, cfg->left_foot);
    heel_toe[1] = mm_skeleton_find(s, cfg->left_toe);
    heel_toe[2] = mm_skeleton_find(s, cfg->right_foot);
    heel_toe[3] = mm_skeleton_find(s, cfg->right_toe);
}

/* The measures of every frame of clip c (globals, world, contacts: scratch for its frames), its
 * contacts labelled as the build labels them: tracks and ground from mm__contact_grounds. */
static void measure_clip(const mm_config *cfg, const mm_clip *c, const mm__contact_track *tracks,
                         const mm__contact_ground *contact_ground, float head_height, mm_xform *globals,
                         mm_vec3 *world, uint8_t *contacts, float *heights, frame_measure *m)
{
    const mm_skeleton *s = &c->skeleton;
    int n = c->frame_count, jc = s->joint_count;
    size_t nj = (size_t)jc;
    for (int f = 0; f < n; ++f) {
        mm_clip_fk(c, f, globals + (size_t)f * nj);
        for (int j = 0; j < jc; ++j)
            world[(size_t)f * nj + (size_t)j] = globals[(size_t)f * nj + (size_t)j].translation;
    }
    int heel_toe[4];
    heel_toe_of(s, cfg, heel_toe);
    mm__label_contacts(tracks, n, c->fps, contact_ground, cfg, contacts);
    mm_posture_joints pj = {mm_skeleton_find(s, cfg->hips),
                            mm_skeleton_find(s, cfg->head),
                            mm_skeleton_find(s, cfg->left_hand),
                            mm_skeleton_find(s, cfg->right_hand),
                            {-1, -1},
                            {-1, -1}};
    mm_posture_find_legs(s, mm_skeleton_find(s, cfg->left_foot), mm_skeleton_find(s, cfg->right_foot), &pj);
    /* the ground: the median over frames of the lowest joint (joint 0, the simulation bone, aside) */
    for (int f = 0; f < n; ++f) {
        float lowest = INFINITY;
        for (int j = 1; j < jc; ++j) lowest = fminf(lowest, world[(size_t)f * nj + (size_t)j].y);
        heights[f] = jc > 1 ? lowest : 0.0f;
    }
    float ground = mm__quantile(heights, n, 0.5f);
    mm_posture_reference ref = {head_height};
    if (!(ref.head_height > 0) && pj.head >= 0) {
        for (int f = 0; f < n; ++f) heights[f] = world[(size_t)f * nj + (size_t)pj.head].y - ground;
        ref.head_height = mm_posture_reference_height(heights, n);
    }
    int lf = heel_toe[0], rf = heel_toe[2];
    for (int f = 0; f < n; ++f) {
        const mm_vec3 *w = world + (size_t)f * nj;
        const mm_vec3 *prev = world + (size_t)(f > 0 ? f - 1 : (n > 1 ? 1 : 0)) * nj;
        frame_measure *x = &m[f];
        x->root_speed = ground_distance(w[0], prev[0]) * c->fps;
        float sum = 0.0f;
        for (int j = 1; j < jc; ++j) sum += mm_vec3_distance(w[j], prev[j]);
        x->joint_speed = jc > 1 ? sum / (float)(jc - 1) * c->fps : 0.0f;
        uint8_t k = contacts[f];
        /* flat: heel and toe (a toe the skeleton lacks aside) */
        int left = (k & 1u) && ((k & 2u) || heel_toe[1] < 0),
            right = (k & 4u) && ((k & 8u) || heel_toe[3] < 0);
        int upright =
            pj.hips < 0 || pj.head < 0 || mm_posture_classify(w, &pj, ground, &ref) == MM_POSTURE_UPRIGHT;
        x->standing = upright && left && right && lf >= 0 && rf >= 0;
        x->stride = x->offset = 0.0f;
        if (lf >= 0 && rf >= 0) {
            mm_vec3 forward =
                mm_quat_rotate(globals[(size_t)f * nj].rotation, mm_vec3_make(0.0f, 0.0f, 1.0f));
            mm_vec3 apart = mm_vec3_sub(w[lf], w[rf]);
            x->stride = fabsf(apart.x * forward.x + apart.z * forward.z);
            mm_vec3 mid = mm_vec3_scale(mm_vec3_add(w[lf], w[rf]), 0.5f);
            x->offset = ground_distance(mid, w[0]);
        }
    }
}

/* Puts x into the list picks[0..*n) kept sorted by cost (at most max; ties keep the earlier). */
static void insert_pick(mm__standing_pick *picks, int *n, int max, const mm__standing_pick *x)
{
    int at = *n;
    while (at > 0 && x->cost < picks[at - 1].cost) --at;
    if (at >= max) return;
    int last = *n < max ? *n : max - 1;
    for (int k = last; k > at; --k) picks[k] = picks[k - 1];
    picks[at] = *x;
    if (*n < max) ++*n;
}

mm_result mm__standing_find(const mm_config *cfg, const mm_clip *const *clips, const uint8_t *const *usable,
                            const int *take, int count, float head_height, int max, mm__standing_pick *picks,
                            int *found, int *standing_frames)
{
    *found = 0;
    *standing_frames = 0;
    int longest = 0, jc = 0;
    for (int i = 0; i < count; ++i) {
        if (clips[i]->frame_count > longest) longest = clips[i]->frame_count;
        if (clips[i]->skeleton.joint_count > jc) jc = clips[i]->skeleton.joint_count;
    }
    if (longest < 3 || jc < 1 || max < 1) return MM_OK;
    size_t cells = (size_t)longest * (size_t)jc;
    mm_xform *globals = (mm_xform *)malloc(sizeof(mm_xform) * cells);
    mm_vec3 *world = (mm_vec3 *)malloc(sizeof(mm_vec3) * cells);
    uint8_t *contacts = (uint8_t *)malloc((size_t)longest);
    float *heights = (float *)malloc(sizeof(float) * (size_t)longest);
    frame_measure *m = (frame_measure *)malloc(sizeof(frame_measure) * (size_t)longest);
    /* the contacts' floors over the takes: every clip's heel and toe tracks first */
    size_t total = 0;
    for (int i = 0; i < count; ++i) total += (size_t)clips[i]->frame_count;
    mm__contact_track *track_frames = (mm__contact_track *)malloc(sizeof(mm__contact_track) * 4 * total);
    mm__contact_track **tracks = (mm__contact_track **)calloc((size_t)count, sizeof *tracks);
    mm__contact_ground *grounds = (mm__contact_ground *)calloc((size_t)count, sizeof *grounds);
    int *frames = (int *)malloc(sizeof(int) * (size_t)count),
        *own = (int *)malloc(sizeof(int) * (size_t)count);
    mm_result r =
        globals && world && contacts && heights && m && track_frames && tracks && grounds && frames && own
            ? MM_OK
            : MM_ERR_OUT_OF_MEMORY;
    for (int i = 0, at = 0; i < count && r == MM_OK; at += clips[i++]->frame_count) {
        const mm_clip *c = clips[i];
        int heel_toe[4];
        heel_toe_of(&c->skeleton, cfg, heel_toe);
        for (int f = 0; f < c->frame_count; ++f)
            mm_clip_fk(c, f, globals + (size_t)f * (size_t)c->skeleton.joint_count);
        tracks[i] = track_frames + (size_t)at * 4;
        mm__contact_tracks(c, globals, heel_toe, tracks[i]);
        frames[i] = c->frame_count;
        own[i] = take ? take[i] : -1;
    }
    if (r == MM_OK)
        r = mm__contact_grounds(count, own, frames, (const mm__contact_track *const *)tracks, cfg, grounds);
    free(frames);
    free(own);
    if (r != MM_OK) {
        free(globals);
        free(world);
        free(contacts);
        free(heights);
        free(m);
        free(track_frames);
        free(tracks);
        free(grounds);
        return MM_ERR_OUT_OF_MEMORY;
    }
    for (int i = 0; i < count; ++i) {
        const mm_clip *c = clips[i];
        int n = c->frame_count;
        if (n < 3) continue;
        measure_clip(cfg, c, tracks[i], &grounds[i], head_height, globals, world, contacts, heights, m);
        if (usable[i])
            for (int f = 0; f < n; ++f) m[f].standing &= usable[i][f] != 0;
        for (int f = 0; f < n; ++f) *standing_frames += m[f].standing;
        int half = (int)lroundf(0.5f * MM__STANDING_WINDOW * c->fps);
        if (half < 1) half = 1;
        if (2 * half + 2 > n) half = (n - 2) / 2;
        mm__standing_pick best;
        best.clip = -1;
        best.cost = INFINITY;
        /* frame 0's speeds are a forward difference: windows start at frame 1 */
        for (int f = 1 + half; f + half < n; ++f) {
            if (!m[f].standing) continue;
            float root = 0.0f, joints = 0.0f;
            int steady = 1;
            for (int g = f - half; g <= f + half; ++g) {
                root += m[g].root_speed;
                joints += m[g].joint_speed;
                steady &= m[g].standing;
            }
            root /= (float)(2 * half + 1);
            joints /= (float)(2 * half + 1);
            float cost = root + joints + MM__STANDING_STRIDE * m[f].stride +
                         MM__STANDING_OFFSET * m[f].offset + (steady ? 0.0f : MM__STANDING_UNSTEADY);
            if (cost < best.cost) {
                best.clip = i;
                best.frame = f;
                best.root_speed = root;
                best.joint_speed = joints;
                best.stride = m[f].stride;
                best.offset = m[f].offset;
                best.cost = cost;
            }
        }
        if (best.clip >= 0) insert_pick(picks, found, max, &best);
    }
    /* the stillest, and those nearly as still */
    int keep = *found > 0 ? 1 : 0;
    while (keep < *found && picks[keep].cost <= picks[0].cost + MM__STANDING_COST_MARGIN) ++keep;
    *found = keep;
    free(globals);
    free(world);
    free(contacts);
    free(heights);
    free(m);
    free(track_frames);
    free(tracks);
    free(grounds);
    return MM_OK;
}

mm_result mm__standing_hold(const mm_clip *src, int frame, mm_clip *out, const mm_allocator *a)
{
    int n = (int)lroundf(MM__STANDING_SECONDS * src->fps);
    if (n < 2) n = 2;
    mm_result r = mm_clip_init(out, &src->skeleton, n, src->fps, a);
    if (r != MM_OK) return r;
    size_t nj = (size_t)src->skeleton.joint_count;
    for (int f = 0; f < n; ++f) {
        memcpy(mm_clip_rotations(out, f), mm_clip_rotations(src, frame), nj * sizeof(mm_quat));
        memcpy(mm_clip_positions(out, f), mm_clip_positions(src, frame), nj * sizeof(mm_vec3));
    }
    return MM_OK;
}
