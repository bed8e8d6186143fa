/* sim_internal.h (private) - shared pieces of the similarity module. */
#ifndef MM_SIM_INTERNAL_H
#define MM_SIM_INTERNAL_H

#include <mm/similarity.h>

#define MM__SIM_LANES 8 /* joints are padded to a multiple of this; kernels sum in this many lanes */

/* Clip-relative frame k frames after rel in clip c: wraps in a loop clip, holds the last frame
 * otherwise. */
static inline int mm__sim_step(const mm_db_clip *c, int rel, int k)
{
    int r = rel + k;
    if (c->loop) return r % c->frame_count;
    return r < c->frame_count ? r : c->frame_count - 1;
}

/* S of rows rA(i0 + t), t in [0, rows), of clip a against every frame of clip b (clip-relative):
 * out[t * frames(b) + j]. */
void mm__sim_strip(const mm_sim_poses *p, const mm_db_clip *a, const mm_db_clip *b, int i0, int rows,
                   float *out);

/* W(i0 + t, j) from a strip made with rows >= t + n: the mean of strip[t + k][step_b(j, k)]. */
static inline float mm__sim_window_cell(const float *strip, const mm_db_clip *b, int t, int j, int n)
{
    int w = b->frame_count;
    double sum = 0.0;
    for (int k = 0; k < n; ++k)
        sum += (double)strip[(size_t)(t + k) * (size_t)w + (size_t)mm__sim_step(b, j, k)];
    return (float)(sum / (double)n);
}

#endif
