#include <mm/spring.h>

#include <math.h>
#include <stdint.h>
#include <string.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "math_private.h"
#include "runtime/spring_private.h"

/* exp(-y h) (1 + y h) = 1/2 */
#define HALFLIFE_ROOT 1.6783469900166603

double mm_spring_damping(float halflife)
{
    if (!(halflife > 0.0f)) return INFINITY;
    return HALFLIFE_ROOT / (double)halflife;
}

static mm_spring_step step_make(float halflife, float dt)
{
    mm_spring_step s = {mm_spring_damping(halflife), dt, 0.0, dt > 0.0f};
    if (s.moves && isfinite(s.damping)) s.decay = exp(-s.damping * s.dt);
    return s;
}

/* The steps last made on this thread, by the bits of their half-life and dt: a character's springs
 * take a handful of half-lives over the same dt tick after tick, and the exponential is most of a
 * step's cost. A step found here is the one step_make gives (a pure function of those bits). The
 * memo is small and in the thread's static block (initial-exec: no call to find it, and the
 * runtime library needs nothing past libc, libm and pthreads). */
#define STEP_MEMO_SIZE 8 /* a power of two */
typedef struct step_memo {
    uint32_t halflife, dt;
    double damping, decay;
    bool used;
} step_memo;
#if defined(__GNUC__)
static _Thread_local step_memo step_memos[STEP_MEMO_SIZE] __attribute__((tls_model("initial-exec")));
#else
static _Thread_local step_memo step_memos[STEP_MEMO_SIZE];
#endif

mm_spring_step mm_spring_step_make(float halflife, float dt)
{
    uint32_t h, d;
    memcpy(&h, &halflife, sizeof h);
    memcpy(&d, &dt, sizeof d);
    step_memo *m = &step_memos[((h * 0x9E3779B1u) ^ d) >> 29 & (STEP_MEMO_SIZE - 1)];
    if (!m->used || m->halflife != h || m->dt != d) {
        mm_spring_step s = step_make(halflife, dt);
        m->halflife = h, m->dt = d, m->damping = s.damping, m->decay = s.decay, m->used = true;
        return s;
    }
    mm_spring_step s = {m->damping, dt, m->decay, dt > 0.0f};
    return s;
}

/* One coordinate, in double: the closed form over the step's dt. */
static void step(double *x, double *v, double target, const mm_spring_step *s)
{
    if (!isfinite(s->damping)) {
        *x = target;
        *v = 0.0;
        return;
    }
    double y = s->damping, dt = s->dt, e = s->decay;
    double j0 = *x - target, j1 = *v + j0 * y;
    *x = target + (j0 + j1 * dt) * e;
    *v = (*v - j1 * y * dt) * e;
}

static void update_with(float *x, float *v, float target, const mm_spring_step *s)
{
    if (!s->moves) return;
    double xd = *x, vd = *v;
    step(&xd, &vd, target, s);
    *x = (float)xd;
    *v = (float)vd;
}

void mm_spring_update(float *x, float *v, float target, float halflife, float dt)
{
    if (!(dt > 0.0f)) return;
    mm_spring_step s = mm_spring_step_make(halflife, dt);
    update_with(x, v, target, &s);
}

void mm_spring_update_step(float *x, float *v, float target, const mm_spring_step *s)
{
    update_with(x, v, target, s);
}

void mm_spring_update_vec3_step(mm_vec3 *x, mm_vec3 *v, mm_vec3 target, const mm_spring_step *s)
{
    update_with(&x->x, &v->x, target.x, s);
    update_with(&x->y, &v->y, target.y, s);
    update_with(&x->z, &v->z, target.z, s);
}

void mm_spring_update_vec3(mm_vec3 *x, mm_vec3 *v, mm_vec3 target, float halflife, float dt)
{
    mm_spring_step s = mm_spring_step_make(halflife, dt);
    mm_spring_update_vec3_step(x, v, target, &s);
}

void mm_spring_decay_vec3_step(mm_vec3 *x, mm_vec3 *v, const mm_spring_step *s)
{
    mm_spring_update_vec3_step(x, v, mm_vec3_make(0, 0, 0), s);
}

/* One coordinate decaying to 0: step() with target 0, written out so that the coordinates of many
 * springs go side by side. */
static inline void decay_coordinate(float *x, float *v, double y, double dt, double e)
{
    double j0 = (double)*x - 0.0, vd = *v, j1 = vd + j0 * y;
    *x = (float)(0.0 + (j0 + j1 * dt) * e);
    *v = (float)((vd - j1 * y * dt) * e);
}

#if defined(MM_WIDE_KERNELS)
/* The SSE2 loop below four coordinates at a time (AVX): each lane decay_coordinate's operations in
 * its order. Returns how many coordinates it did (a multiple of four). */
MM_WIDE static int decay_coordinates4(float *xs, float *vs, int n, double y, double dt, double e)
{
    const __m256d yy = _mm256_set1_pd(y), tt = _mm256_set1_pd(dt), ee = _mm256_set1_pd(e),
                  zero = _mm256_setzero_pd();
    int i = 0;
    for (; i + 4 <= n; i += 4) {
        __m256d j0 = _mm256_cvtps_pd(_mm_loadu_ps(xs + i)), vd = _mm256_cvtps_pd(_mm_loadu_ps(vs + i));
        __m256d j1 = _mm256_add_pd(vd, _mm256_mul_pd(j0, yy));
        __m256d xn = _mm256_add_pd(zero, _mm256_mul_pd(_mm256_add_pd(j0, _mm256_mul_pd(j1, tt)), ee));
        __m256d vn = _mm256_mul_pd(_mm256_sub_pd(vd, _mm256_mul_pd(_mm256_mul_pd(j1, yy), tt)), ee);
        _mm_storeu_ps(xs + i, _mm256_cvtpd_ps(xn));
        _mm_storeu_ps(vs + i, _mm256_cvtpd_ps(vn));
    }
    return i;
}
#endif

void mm_spring_decay_vec3_steps(mm_vec3 *x, mm_vec3 *v, int count, const mm_spring_step *s)
{
    if (!s->moves) return;
    if (!isfinite(s->damping)) {
        for (int i = 0; i < count; ++i) x[i] = v[i] = mm_vec3_make(0.0f, 0.0f, 0.0f);
        return;
    }
    const double y = s->damping, dt = s->dt, e = s->decay;
    /* the coordinates of all the springs, one after another */
    float *xs = &x[0].x, *vs = &v[0].x;
    int n = 3 * count, i = 0;
#if defined(MM_WIDE_KERNELS)
    if (mm__wide_kernels()) i = decay_coordinates4(xs, vs, n, y, dt, e);
#endif
#if defined(__SSE2__)
    /* two coordinates at a time in packed doubles, each lane decay_coordinate's operations in its
     * order (the same bits) */
    const __m128d yy = _mm_set1_pd(y), tt = _mm_set1_pd(dt), ee = _mm_set1_pd(e), zero = _mm_setzero_pd();
    for (; i + 2 <= n; i += 2) {
        __m128d j0 = _mm_cvtps_pd(_mm_castsi128_ps(_mm_loadl_epi64((const __m128i *)(const void *)(xs + i))));
        __m128d vd = _mm_cvtps_pd(_mm_castsi128_ps(_mm_loadl_epi64((const __m128i *)(const void *)(vs + i))));
        __m128d j1 = _mm_add_pd(vd, _mm_mul_pd(j0, yy));
        __m128d xn = _mm_add_pd(zero, _mm_mul_pd(_mm_add_pd(j0, _mm_mul_pd(j1, tt)), ee));
        __m128d vn = _mm_mul_pd(_mm_sub_pd(vd, _mm_mul_pd(_mm_mul_pd(j1, yy), tt)), ee);
        _mm_storel_epi64((__m128i *)(void *)(xs + i), _mm_castps_si128(_mm_cvtpd_ps(xn)));
        _mm_storel_epi64((__m128i *)(void *)(vs + i), _mm_castps_si128(_mm_cvtpd_ps(vn)));
    }
#endif
    for (; i < n; ++i) decay_coordinate(&xs[i], &vs[i], y, dt, e);
}

void mm_spring_decay_vec3(mm_vec3 *x, mm_vec3 *v, float halflife, float dt)
{
    mm_spring_update_vec3(x, v, mm_vec3_make(0, 0, 0), halflife, dt);
}

mm_vec3 mm__spring_quat_gap(mm_quat q, mm_quat target)
{
    return mm__quat_log_series(mm_quat_abs(mm_quat_mul(q, mm_quat_inverse(target))));
}

void mm__spring_update_quat_gap(mm_quat *q, mm_vec3 *w, mm_vec3 gap, mm_quat target, float halflife, float dt)
{
    if (!(dt > 0.0f)) return;
    double y = mm_spring_damping(halflife);
    if (!isfinite(y)) {
        *q = target;
        *w = mm_vec3_make(0, 0, 0);
        return;
    }
    /* the rotation still to go, as a rotation vector, springs to zero */
    double e = exp(-y * dt);
    double rv[3] = {gap.x, gap.y, gap.z}, wv[3] = {w->x, w->y, w->z}, out_r[3], out_w[3];
    for (int i = 0; i < 3; ++i) {
        double j1 = wv[i] + rv[i] * y;
        out_r[i] = (rv[i] + j1 * dt) * e;
        out_w[i] = (wv[i] - j1 * y * dt) * e;
    }
    *q = mm_quat_normalize(mm_quat_mul(
        mm__quat_exp_series(mm_vec3_make((float)out_r[0], (float)out_r[1], (float)out_r[2])), target));
    *w = mm_vec3_make((float)out_w[0], (float)out_w[1], (float)out_w[2]);
}

void mm_spring_update_quat(mm_quat *q, mm_vec3 *w, mm_quat target, float halflife, float dt)
{
    bool moves = dt > 0.0f && isfinite(mm_spring_damping(halflife)); /* else no gap is read */
    mm_vec3 gap = moves ? mm__spring_quat_gap(*q, target) : mm_vec3_make(0, 0, 0);
    mm__spring_update_quat_gap(q, w, gap, target, halflife, dt);
}

void mm_spring_velocity_update(mm_vec3 *position, mm_vec3 *velocity, mm_vec3 *acceleration,
                               mm_vec3 target_velocity, float halflife, float dt)
{
    if (!(dt > 0.0f)) return;
    double y = mm_spring_damping(halflife);
    float *p[3] = {&position->x, &position->y, &position->z};
    float *v[3] = {&velocity->x, &velocity->y, &velocity->z};
    float *a[3] = {&acceleration->x, &acceleration->y, &acceleration->z};
    const float g[3] = {target_velocity.x, target_velocity.y, target_velocity.z};
    const double e = isfinite(y) ? exp(-y * dt) : 0.0; /* the same for the three coordinates */
    for (int i = 0; i < 3; ++i) {
        if (!isfinite(y)) { /* no spring: the velocity is the target at once */
            *p[i] = (float)(*p[i] + (double)g[i] * dt);
            *v[i] = g[i];
            *a[i] = 0.0f;
            continue;
        }
        /* v(t) = g + (j0 + j1 t) e^(-y t); x integrates it; a differentiates it */
        double j0 = (double)*v[i] - g[i], j1 = (double)*a[i] + j0 * y;
        double x = *p[i] + g[i] * dt + j0 * (1.0 - e) / y + j1 * ((1.0 - e) / (y * y) - dt * e / y);
        *p[i] = (float)x;
        *v[i] = (float)(g[i] + (j0 + j1 * dt) * e);
        *a[i] = (float)((j1 - j0 * y - j1 * y * dt) * e);
    }
}
