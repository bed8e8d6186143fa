/* Foot contacts: a heel or toe is in contact when it rests at its planted height and is slow.
 *
 * Each joint's floor is the 5th percentile of its own height (a joint's lowest steady height;
 * robust to a few bad frames), so the thresholds do not depend on where in the foot the joint
 * sits. The floor comes from the whole take (every clip cut from the same source, mirrored apart),
 * so a short clip whose foot stays raised does not take the raised height for its floor; a clip
 * whose joints all stay well above the take's floors (standing on something else) keeps floors
 * of its own. A joint's planted height is the median of its height above the floor over the
 * take's frames in which it is low (under contact_height) and slow (under contact_speed): where it
 * comes to rest. A joint is in contact when it is slow and within contact_planted_tolerance of its
 * planted height, so a foot still coming down is not yet in contact. Runs of on or off shorter
 * than contact_min_time are flicker and are removed: first short gaps inside a contact are
 * filled, then short contacts dropped. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <mm/database_build.h>

#include "db/process.h"

/* The fraction of a joint's heights under its floor (a few bad frames). */
#define FLOOR_QUANTILE 0.05f
/* The fraction of its low, slow heights under its planted height (their median). */
#define PLANTED_QUANTILE 0.5f

static int compare_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

float mm__quantile(float *v, int n, float q)
{
    qsort(v, (size_t)n, sizeof(float), compare_float);
    int i = (int)floorf(q * (float)(n - 1));
    return v[i < 0 ? 0 : i];
}

void mm__remove_short_runs(uint8_t *on, int n, uint8_t v, int min_len)
{
    int i = 0;
    while (i < n) {
        int j = i;
        while (j < n && on[j] == on[i]) ++j;
        if (on[i] == v && i > 0 && j < n && j - i < min_len) memset(on + i, !v, (size_t)(j - i));
        i = j;
    }
}

void mm__contact_tracks(const mm_clip *clip, const mm_xform *globals, const int heel_toe[4],
                        mm__contact_track *out)
{
    int n = clip->frame_count, jc = clip->skeleton.joint_count;
    for (int f = 0; f < n; ++f)
        for (int b = 0; b < 4; ++b) {
            mm__contact_track *t = &out[(size_t)f * 4 + (size_t)b];
            int j = heel_toe[b];
            if (j < 0 || n < 2) {
                t->height = t->speed = NAN;
                continue;
            }
            mm_vec3 p = globals[(size_t)f * jc + j].translation;
            mm_vec3 q = globals[(size_t)(f > 0 ? f - 1 : 1) * jc + j].translation;
            t->height = p.y;
            t->speed = sqrtf((p.x - q.x) * (p.x - q.x) + (p.z - q.z) * (p.z - q.z)) * clip->fps;
        }
}

/* Joint b's floor over the frames of the clips in list[0..count) (NAN when none has frames). */
static float take_floor(const mm__contact_track *const *tracks, const int *frames, const int *list, int count,
                        int b, float *scratch)
{
    int m = 0;
    for (int k = 0; k < count; ++k)
        for (int f = 0; f < frames[list[k]]; ++f) {
            float h = tracks[list[k]][(size_t)f * 4 + (size_t)b].height;
            if (isfinite(h)) scratch[m++] = h;
        }
    return m > 0 ? mm__quantile(scratch, m, FLOOR_QUANTILE) : NAN;
}

mm_result mm__contact_grounds(int clip_count, const int *take, const int *frames,
                              const mm__contact_track *const *tracks, const mm_config *cfg,
                              mm__contact_ground *out)
{
    int total = 0;
    for (int i = 0; i < clip_count; ++i) total += frames[i];
    float *scratch = (float *)malloc(sizeof(float) * (size_t)(total > 0 ? total : 1));
    int *list = (int *)malloc(sizeof(int) * (size_t)(clip_count > 0 ? clip_count : 1));
    uint8_t *done = (uint8_t *)calloc((size_t)(clip_count > 0 ? clip_count : 1), 1);
    if (!scratch || !list || !done) {
        free(scratch);
        free(list);
        free(done);
        return MM_ERR_OUT_OF_MEMORY;
    }
    for (int i = 0; i < clip_count; ++i) {
        if (done[i]) continue;
        int count = 0; /* the take's clips */
        for (int k = i; k < clip_count; ++k)
            if (!done[k] && (k == i || (take[i] >= 0 && take[k] == take[i]))) {
                list[count++] = k;
                done[k] = 1;
            }
        float floor_of_take[4];
        for (int b = 0; b < 4; ++b) floor_of_take[b] = take_floor(tracks, frames, list, count, b, scratch);
        /* each clip: the take's floors, or its own when every joint stays above them */
        for (int k = 0; k < count; ++k) {
            mm__contact_ground *g = &out[list[k]];
            int elsewhere = 0, measured = 0;
            for (int b = 0; b < 4; ++b) {
                g->floor[b] = take_floor(tracks, frames, &list[k], 1, b, scratch);
                if (!isfinite(g->floor[b]) || !isfinite(floor_of_take[b])) continue;
                ++measured;
                elsewhere += g->floor[b] - floor_of_take[b] >= cfg->contact_height;
            }
            if (!(measured > 0 && elsewhere == measured))
                for (int b = 0; b < 4; ++b) g->floor[b] = floor_of_take[b];
        }
        /* planted heights: over the take's low, slow frames, each above its clip's floor */
        for (int b = 0; b < 4; ++b) {
            int m = 0;
            for (int k = 0; k < count; ++k) {
                const mm__contact_track *t = tracks[list[k]];
                float fl = out[list[k]].floor[b];
                for (int f = 0; f < frames[list[k]]; ++f) {
                    float above = t[(size_t)f * 4 + (size_t)b].height - fl;
                    if (above < cfg->contact_height &&
                        t[(size_t)f * 4 + (size_t)b].speed < cfg->contact_speed)
                        scratch[m++] = above;
                }
            }
            float planted = m > 0 ? mm__quantile(scratch, m, PLANTED_QUANTILE) : 0.0f;
            for (int k = 0; k < count; ++k) out[list[k]].planted[b] = planted;
        }
    }
    free(scratch);
    free(list);
    free(done);
    return MM_OK;
}

void mm__label_contacts(const mm__contact_track *tracks, int n, float fps, const mm__contact_ground *ground,
                        const mm_config *cfg, uint8_t *out)
{
    memset(out, 0, (size_t)n);
    uint8_t *on = (uint8_t *)malloc((size_t)(n > 0 ? n : 1));
    if (!on) return;
    int min_len = (int)lroundf(cfg->contact_min_time * fps);
    for (int b = 0; b < 4; ++b) {
        if (n < 2 || !isfinite(ground->floor[b])) continue;
        float rest = ground->planted[b] + cfg->contact_planted_tolerance;
        for (int f = 0; f < n; ++f) {
            const mm__contact_track *t = &tracks[(size_t)f * 4 + (size_t)b];
            float above = t->height - ground->floor[b];
            on[f] = above < cfg->contact_height && above <= rest && t->speed < cfg->contact_speed;
        }
        mm__remove_short_runs(on, n, 0, min_len);
        mm__remove_short_runs(on, n, 1, min_len);
        for (int f = 0; f < n; ++f)
            if (on[f]) out[f] |= (uint8_t)(1u << b);
    }
    free(on);
}

void mm__detect_contacts(const mm_clip *clip, const mm_xform *globals, const int heel_toe[4],
                         const mm_config *cfg, uint8_t *out)
{
    int n = clip->frame_count;
    memset(out, 0, (size_t)n);
    mm__contact_track *tracks =
        (mm__contact_track *)malloc(sizeof(mm__contact_track) * 4 * (size_t)(n > 0 ? n : 1));
    float *h = (float *)malloc(sizeof(float) * (size_t)(n > 0 ? n : 1));
    if (!tracks || !h) {
        free(tracks);
        free(h);
        return;
    }
    mm__contact_tracks(clip, globals, heel_toe, tracks);
    mm__contact_ground ground;
    for (int b = 0; b < 4; ++b) {
        int m = 0;
        for (int f = 0; f < n; ++f)
            if (isfinite(tracks[(size_t)f * 4 + (size_t)b].height))
                h[m++] = tracks[(size_t)f * 4 + (size_t)b].height;
        ground.floor[b] = m > 0 ? mm__quantile(h, m, FLOOR_QUANTILE) : NAN;
        ground.planted[b] = INFINITY; /* any height under contact_height */
    }
    mm__label_contacts(tracks, n, clip->fps, &ground, cfg, out);
    free(tracks);
    free(h);
}
