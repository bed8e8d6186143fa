/* Seeded randomness (splitmix64: no global state, no rand()) and the per-seed style. */
#include "synth_internal.h"

void synth_rng_seed(synth_rng *r, uint64_t seed) { r->s = seed ^ 0x6d6d2d73796e7468ull; /* "mm-synth" */ }

uint64_t synth_rng_next(synth_rng *r)
{
    uint64_t z = (r->s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

float synth_rng_uniform(synth_rng *r, float lo, float hi)
{
    /* 24 random bits: exactly representable, the same on every platform. */
    float u = (float)(synth_rng_next(r) >> 40) * (1.0f / 16777216.0f);
    return lo + (hi - lo) * u;
}

void synth_style_init(synth_style *st, uint64_t seed)
{
    synth_rng r;
    synth_rng_seed(&r, seed);
    const float deg = (float)MM_DEG_TO_RAD;
    st->cadence = synth_rng_uniform(&r, 0.97f, 1.03f);
    st->arm_swing = synth_rng_uniform(&r, 0.85f, 1.15f);
    st->bob = synth_rng_uniform(&r, 0.85f, 1.15f);
    st->sway = synth_rng_uniform(&r, 0.85f, 1.15f);
    st->pelvis_rot = synth_rng_uniform(&r, 0.85f, 1.15f);
    st->step_width = synth_rng_uniform(&r, 0.065f, 0.08f);
    st->stand_width = synth_rng_uniform(&r, 0.10f, 0.12f);
    st->toe_out = synth_rng_uniform(&r, 4.0f, 8.0f) * deg;
    st->lean = synth_rng_uniform(&r, 0.85f, 1.15f);
    st->elbow = synth_rng_uniform(&r, 12.0f, 20.0f) * deg;
    st->head_pitch = synth_rng_uniform(&r, 2.0f, 6.0f) * deg;
    for (int i = 0; i < 4; ++i) {
        st->idle_phase[i] = synth_rng_uniform(&r, 0.0f, SYNTH_TAU);
        st->idle_amp[i] = synth_rng_uniform(&r, 0.8f, 1.2f);
    }
}
