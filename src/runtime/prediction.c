/* Stop and pivot prediction in closed form from the trajectory's velocity spring. See
 * mm/prediction.h and docs/distance.md. Nothing here allocates. */
#include <mm/prediction.h>

#include <math.h>

#include <mm/spring.h>
#include "math_private.h"

/* the spring's own time between the samples searched for the last moment at the rest speed */
#define REST_SEARCH_STEP 0.05
/* halvings of the interval holding that moment: past double precision */
#define BISECTION_STEPS 60

/* In the spring's own time u = y t: v(u) = g + (j0 + k u) e^(-u), k = j1 / y. */
typedef struct vspring {
    double g[3], j0[3], k[3], y;
} vspring;

static double vs_speed(const vspring *s, double u)
{
    double e = exp(-u), q = 0.0;
    for (int i = 0; i < 3; ++i) {
        double v = s->g[i] + (s->j0[i] + s->k[i] * u) * e;
        q += v * v;
    }
    return sqrt(q);
}

/* Integral of the speed over u in [a, b]: 8-point Gauss-Legendre on panels that double in width
 * (0-1, 1-2, 2-4, ... 32-48), as the speed decays like e^-u; far below float rounding. */
static double vs_path(const vspring *s, double a, double b)
{
    static const double x[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267,
                                0.9602898564975363};
    static const double w[4] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745,
                                0.1012285362903763};
    static const double edge[] = {0.0, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 48.0};
    double sum = 0.0;
    for (int p = 0; p + 1 < (int)(sizeof edge / sizeof edge[0]); ++p) {
        double lo = edge[p] > a ? edge[p] : a, hi = edge[p + 1] < b ? edge[p + 1] : b;
        if (!(hi > lo)) continue;
        double mid = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
        for (int k = 0; k < 4; ++k)
            sum += half * w[k] * (vs_speed(s, mid - half * x[k]) + vs_speed(s, mid + half * x[k]));
    }
    return sum;
}

#define HORIZON 48.0 /* u = y t; (1 + u) e^-u is below 1e-19 there */

static void vs_make(vspring *s, mm_vec3 v, mm_vec3 a, mm_vec3 g, double y)
{
    const double vv[3] = {v.x, v.y, v.z}, av[3] = {a.x, a.y, a.z}, gv[3] = {g.x, g.y, g.z};
    s->y = y;
    for (int i = 0; i < 3; ++i) {
        s->g[i] = gv[i];
        s->j0[i] = vv[i] - gv[i];
        s->k[i] = (av[i] + s->j0[i] * y) / y;
    }
}

/* Offset travelled by time t (seconds) from the closed form of mm_spring_velocity_update. */
static mm_vec3 vs_offset(const vspring *s, double t)
{
    double y = s->y, e = exp(-y * t), o[3];
    for (int i = 0; i < 3; ++i) {
        double j1 = s->k[i] * y;
        o[i] = s->g[i] * t + s->j0[i] * (1.0 - e) / y + j1 * ((1.0 - e) / (y * y) - t * e / y);
    }
    return mm_vec3_make((float)o[0], (float)o[1], (float)o[2]);
}

static void prediction_zero(mm_distance_prediction *out)
{
    out->found = 0;
    out->offset = mm_vec3_make(0, 0, 0);
    out->distance = 0.0f;
    out->time = 0.0f;
}

/* Numbers too large for floats overflow to infinity: such a prediction is refused as a whole. */
static mm_result prediction_checked(mm_result r, mm_distance_prediction *out)
{
    if (r == MM_OK && (!finite3(out->offset) || !isfinite(out->distance) || !isfinite(out->time))) {
        prediction_zero(out);
        return MM_ERR_OUT_OF_RANGE;
    }
    return r;
}

static mm_result predict_stop(mm_vec3 velocity, mm_vec3 acceleration, float halflife, float rest_speed,
                              mm_distance_prediction *out)
{
    if (!out) return MM_ERR_INVALID_ARGUMENT;
    prediction_zero(out);
    if (!finite3(velocity) || !finite3(acceleration) || !(halflife >= 0.0f) || !isfinite(halflife) ||
        !(rest_speed >= 0.0f) || !isfinite(rest_speed))
        return MM_ERR_INVALID_ARGUMENT;
    double rest = rest_speed > 0.0f ? rest_speed : MM_DISTANCE_REST_SPEED_DEFAULT;
    double y = mm_spring_damping(halflife);
    if (!isfinite(y)) return MM_OK; /* no spring: at rest at once */
    vspring s;
    vs_make(&s, velocity, acceleration, mm_vec3_make(0, 0, 0), y);
    double o[3];
    for (int i = 0; i < 3; ++i) o[i] = (s.j0[i] + s.k[i]) / y; /* j0 / y + j1 / y^2 */
    out->offset = mm_vec3_make((float)o[0], (float)o[1], (float)o[2]);
    /* the path: split where |j0 + k u| is least (the only place the speed can touch zero) */
    double kk = s.k[0] * s.k[0] + s.k[1] * s.k[1] + s.k[2] * s.k[2];
    double us = kk > 0.0 ? -(s.j0[0] * s.k[0] + s.j0[1] * s.k[1] + s.j0[2] * s.k[2]) / kk : 0.0;
    double path = us > 0.0 && us < HORIZON ? vs_path(&s, 0.0, us) + vs_path(&s, us, HORIZON)
                                           : vs_path(&s, 0.0, HORIZON);
    out->distance = (float)(path / y);
    /* the time: the last moment the speed is at least rest. |j0 + k u|^2 = |j0 + k us|^2 +
     * |k|^2 (u - us)^2, so past u0 = us + 1 the speed falls all the way (its log falls by more
     * than it rises); before u0 the samples are searched from the end. */
    double u0 = us + 1.0 > 0.0 ? us + 1.0 : 0.0, lo, hi;
    if (u0 < HORIZON && vs_speed(&s, u0) >= rest) {
        lo = u0;
        hi = HORIZON;
    } else {
        const double h = REST_SEARCH_STEP;
        int last = -1;
        for (int i = (int)(fmin(u0, HORIZON) / h) + 1; i >= 0 && last < 0; --i)
            if (vs_speed(&s, i * h) >= rest) last = i;
        if (last < 0) return MM_OK; /* at rest already */
        lo = last * h;
        hi = lo + h;
    }
    for (int it = 0; it < BISECTION_STEPS; ++it) {
        double mid = 0.5 * (lo + hi);
        if (vs_speed(&s, mid) >= rest)
            lo = mid;
        else
            hi = mid;
    }
    out->found = 1;
    out->time = (float)(0.5 * (lo + hi) / y);
    return MM_OK;
}

mm_result mm_distance_predict_stop(mm_vec3 velocity, mm_vec3 acceleration, float halflife, float rest_speed,
                                   mm_distance_prediction *out)
{
    return prediction_checked(predict_stop(velocity, acceleration, halflife, rest_speed, out), out);
}

static mm_result predict_pivot(mm_vec3 velocity, mm_vec3 acceleration, mm_vec3 target_velocity,
                               float halflife, mm_distance_prediction *out)
{
    if (!out) return MM_ERR_INVALID_ARGUMENT;
    prediction_zero(out);
    if (!finite3(velocity) || !finite3(acceleration) || !finite3(target_velocity) || !(halflife >= 0.0f) ||
        !isfinite(halflife))
        return MM_ERR_INVALID_ARGUMENT;
    double gl = mm_vec3_length(target_velocity);
    if (!(gl > 1e-6)) return MM_OK;
    double gd[3] = {target_velocity.x / gl, target_velocity.y / gl, target_velocity.z / gl};
    double along0 = velocity.x * gd[0] + velocity.y * gd[1] + velocity.z * gd[2];
    if (!(along0 < 0.0)) return MM_OK; /* not moving against the target */
    double y = mm_spring_damping(halflife);
    out->found = 1;
    if (!isfinite(y)) return MM_OK; /* no spring: turns at once, here */
    vspring s;
    vs_make(&s, velocity, acceleration, target_velocity, y);
    double a = s.j0[0] * gd[0] + s.j0[1] * gd[1] + s.j0[2] * gd[2];
    double b = s.k[0] * gd[0] + s.k[1] * gd[1] + s.k[2] * gd[2];
#define ALONG(u) (gl + (a + b * (u)) * exp(-(u)))
    /* one crossing: (a + b u) e^-u has one extremum; the first sample at or above zero */
    const int steps = 960;
    const double h = HORIZON / steps;
    int i = 1;
    while (i < steps && ALONG(i * h) < 0.0) ++i;
    double lo = (i - 1) * h, hi = i * h;
    for (int it = 0; it < BISECTION_STEPS; ++it) {
        double mid = 0.5 * (lo + hi);
        if (ALONG(mid) < 0.0)
            lo = mid;
        else
            hi = mid;
    }
#undef ALONG
    double u = 0.5 * (lo + hi);
    out->time = (float)(u / y);
    out->offset = vs_offset(&s, u / y);
    out->distance = (float)(vs_path(&s, 0.0, u) / y);
    return MM_OK;
}

mm_result mm_distance_predict_pivot(mm_vec3 velocity, mm_vec3 acceleration, mm_vec3 target_velocity,
                                    float halflife, mm_distance_prediction *out)
{
    return prediction_checked(predict_pivot(velocity, acceleration, target_velocity, halflife, out), out);
}

mm_result mm_distance_predict_trajectory(const mm_trajectory *t, const mm_input *in, float rest_speed,
                                         mm_distance_prediction *stop, mm_distance_prediction *pivot)
{
    if (stop) prediction_zero(stop);
    if (pivot) prediction_zero(pivot);
    if (!t) return MM_ERR_INVALID_ARGUMENT;
    int g = (int)mm_input_gait(in);
    float halflife = t->desc.gaits[g].velocity_halflife;
    mm_result r = MM_OK;
    if (stop) r = mm_distance_predict_stop(t->velocity, t->acceleration, halflife, rest_speed, stop);
    if (stop && r == MM_OK && stop->found && t->scene) {
        /* in a scene the stop is stepped as the simulation is (mm/trajectory.h): a wall in the way
         * ends it there, the distance the path slid */
        mm_vec3 at;
        float path;
        if (mm_trajectory_predict(t, mm_vec3_make(0, 0, 0), t->target_facing, (mm_gait)g, stop->time, &at,
                                  NULL, &path) > 0) {
            stop->offset = mm_vec3_make(at.x - t->position.x, 0.0f, at.z - t->position.z);
            stop->distance = path;
        }
    }
    if (pivot && r == MM_OK) {
        mm_vec3 target;
        mm_trajectory_desired(t, in, &target, NULL);
        r = mm_distance_predict_pivot(t->velocity, t->acceleration, target, halflife, pivot);
    }
    return r;
}
