/* Foot contacts: a heel or toe is in contact when it is close to the floor and slow.
 *
 * The floor of each joint is the 5th percentile of its own height over the clip (a joint's
 * lowest steady height; robust to a few bad frames), so the thresholds do not depend on where
 * in the foot the joint sits. Runs of on or off shorter than contact_min_time are flicker and
 * are removed: first short gaps inside a contact are filled, then short contacts dropped. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <mm/database_build.h>

#include "db/process.h"

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

void mm__detect_contacts(const mm_clip *clip, const mm_xform *globals, const int heel_toe[4],
                         const mm_config *cfg, uint8_t *out)
{
    int n = clip->frame_count, jc = clip->skeleton.joint_count;
    memset(out, 0, (size_t)n);
    float *h = (float *)malloc(sizeof(float) * (size_t)n);
    uint8_t *on = (uint8_t *)malloc((size_t)n);
    if (!h || !on) {
        free(h);
        free(on);
        return;
    }
    int min_len = (int)lroundf(cfg->contact_min_time * clip->fps);
    for (int b = 0; b < 4; ++b) {
        int j = heel_toe[b];
        if (j < 0 || n < 2) continue;
        for (int f = 0; f < n; ++f) h[f] = globals[(size_t)f * jc + j].translation.y;
        float floor_y = mm__quantile(h, n, 0.05f);
        for (int f = 0; f < n; ++f) {
            mm_vec3 p = globals[(size_t)f * jc + j].translation;
            mm_vec3 q = globals[(size_t)(f > 0 ? f - 1 : 1) * jc + j].translation;
            float speed = sqrtf((p.x - q.x) * (p.x - q.x) + (p.z - q.z) * (p.z - q.z)) * clip->fps;
            on[f] = (p.y - floor_y) < cfg->contact_height && speed < cfg->contact_speed;
        }
        mm__remove_short_runs(on, n, 0, min_len);
        mm__remove_short_runs(on, n, 1, min_len);
        for (int f = 0; f < n; ++f)
            if (on[f]) out[f] |= (uint8_t)(1u << b);
    }
    free(h);
    free(on);
}
