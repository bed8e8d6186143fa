/* The crossfade mixer of seed 000: slot weights and playheads. */
#include <mm/mixer.h>

#include <math.h>
#include <string.h>

void mm_mixer_init(mm_mixer *m, int source, float fraction)
{
    if (!m) return;
    memset(m, 0, sizeof *m);
    m->slots[0].source = source;
    m->slots[0].fraction = isfinite(fraction) && fraction > 0.0f && fraction < 1.0f ? fraction : 0.0f;
    m->slots[0].weight = m->slots[0].share = 1.0f;
    m->count = 1;
    m->cancel_weight = MM_MIXER_CANCEL_WEIGHT;
}

/* Slot 0's weight: 1 minus the others', so that the sum stays 1 however the others round. */
static void settle_first(mm_mixer *m)
{
    float rest = 0.0f;
    for (int i = 1; i < m->count; ++i) rest += m->slots[i].weight;
    m->slots[0].weight = fmaxf(0.0f, 1.0f - rest);
}

/* Drops the older slots whose weight is 0 (or less), keeping the order; with first, slot 0 too
 * when it has weight 0 and others are in use (it has 0 only on the tick its transition started:
 * a second start in that tick replaces it). */
static void drop_empty(mm_mixer *m, bool first)
{
    int k = 1;
    if (first && m->count > 1 && !(m->slots[0].weight > 0.0f)) k = 0;
    for (int i = 1; i < m->count; ++i)
        if (m->slots[i].weight > 0.0f) m->slots[k++] = m->slots[i];
    if (k == 0) { /* every weight 0: cannot happen (they sum to 1), but keep one slot */
        m->slots[0].weight = 1.0f;
        k = 1;
    }
    m->count = k;
}

bool mm_mixer_start(mm_mixer *m, int source, float fraction, float time, bool uncancellable)
{
    if (!m) return false;
    if (m->count <= 0) {
        int cancelled = m->cancelled, started = m->started;
        mm_mixer_init(m, source, fraction);
        m->cancelled = cancelled, m->started = started + 1;
        return true;
    }
    drop_empty(m, true);
    if (m->count == MM_MIXER_SLOTS) {
        float evicted = m->slots[MM_MIXER_SLOTS - 1].weight;
        if (evicted > m->cancel_weight && !uncancellable) {
            ++m->cancelled;
            return false;
        }
        /* the evicted weight goes to the others in proportion to their own */
        --m->count;
        float rest = 0.0f;
        for (int i = 0; i < m->count; ++i) rest += m->slots[i].weight;
        for (int i = 0; i < m->count; ++i)
            m->slots[i].weight = rest > 0.0f ? m->slots[i].weight / rest : 0.0f;
        if (!(rest > 0.0f)) time = 0.0f; /* nothing left to fade from */
    }
    memmove(&m->slots[1], &m->slots[0], sizeof(mm_mixer_slot) * (size_t)m->count);
    ++m->count;
    for (int i = 1; i < m->count; ++i) m->slots[i].share = m->slots[i].weight;
    mm_mixer_slot *s = &m->slots[0];
    s->source = source;
    s->fraction = isfinite(fraction) && fraction > 0.0f && fraction < 1.0f ? fraction : 0.0f;
    s->weight = s->share = 0.0f;
    m->elapsed = 0.0f;
    m->duration = isfinite(time) && time > 0.0f ? time : 0.0f;
    ++m->started;
    if (m->duration == 0.0f) { /* at once: the others are gone */
        m->count = 1;
        s->weight = 1.0f;
    } /* else slot 0 starts at exactly 0: the others sum to 1 (to rounding, when renormalised) */
    return true;
}

void mm_mixer_advance(mm_mixer *m, float dt)
{
    if (!m || m->count <= 0 || !(dt > 0.0f) || !isfinite(dt)) return;
    m->elapsed += dt;
    float s = m->duration > 0.0f ? m->elapsed / m->duration : 1.0f;
    if (!(s < 1.0f)) s = 1.0f, m->elapsed = m->duration;
    for (int i = 1; i < m->count; ++i) m->slots[i].weight = s >= 1.0f ? 0.0f : m->slots[i].share * (1.0f - s);
    drop_empty(m, false);
    settle_first(m);
}

unsigned mm_mixer_play(mm_mixer *m, const int *next, int frame_count, float frames)
{
    unsigned ended = 0;
    if (!m || !next) return 0;
    if (!(frames >= 0.0f) || !isfinite(frames)) frames = 0.0f;
    for (int i = 0; i < m->count; ++i) {
        mm_mixer_slot *s = &m->slots[i];
        if (s->source < 0 || s->source >= frame_count) continue;
        s->fraction += frames;
        while (s->fraction >= 1.0f) {
            s->fraction -= 1.0f;
            int f = next[s->source];
            if (f < 0 || f >= frame_count) {
                s->fraction = 0.0f;
                break;
            }
            s->source = f;
        }
        if (next[s->source] < 0) ended |= 1u << i;
    }
    return ended;
}

float mm_mixer_weight_sum(const mm_mixer *m)
{
    float sum = 0.0f;
    for (int i = 0; m && i < m->count; ++i) sum += m->slots[i].weight;
    return sum;
}
