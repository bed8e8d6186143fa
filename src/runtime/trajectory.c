#include <mm/trajectory.h>

#include <math.h>
#include <string.h>

#include <mm/spring.h>
#include "runtime/spring_private.h"
#include "runtime/trajectory_private.h"

/* The ranges mm_trajectory_init accepts: beyond them a number is a unit mistake. */
/* m/s: the fastest gait speed (a sprint is 10) */
#define MAX_GAIT_SPEED 50.0f
/* s: the longest half-life (a minute: no spring at all) */
#define MAX_HALFLIFE 60.0f
/* s: the longest history (an hour) */
#define MAX_HISTORY_SECONDS 3600.0f
/* samples per second of the history: at least one, at most well past any tick rate */
#define MIN_HISTORY_RATE 1.0f
#define MAX_HISTORY_RATE 1000.0f
/* samples the history holds beyond seconds x rate: one at each end of the span */
#define HISTORY_SLACK 2
/* the stick's squared length under which it asks for no facing (0.01 of its travel): a stick at
 * rest does not turn the character */
#define STICK_TURN_MIN_SQ 1e-4f
/* m: the largest collider radius and height (a building is not a character) */
#define MAX_COLLIDER_SIZE 100.0f
/* s: the longest look ahead mm_trajectory_predict steps through */
#define MAX_PREDICT_SECONDS 60.0f
/* below this speed (m/s) a stopping simulation has no course left to turn */
#define STOP_TURN_MIN_SPEED 0.05f

static mm_gait_params gait(float forward, float side, float backward, float velocity, float rotation)
{
    mm_gait_params g = {forward, side, backward, velocity, rotation};
    return g;
}

void mm_trajectory_defaults(mm_trajectory_desc *d)
{
    memset(d, 0, sizeof *d);
    d->gaits[MM_GAIT_WALK] = gait(1.5f, 1.1f, 1.0f, 0.25f, 0.2f);
    d->gaits[MM_GAIT_RUN] = gait(4.0f, 2.6f, 2.2f, 0.3f, 0.25f);
    d->gaits[MM_GAIT_CROUCH] = gait(0.9f, 0.7f, 0.6f, 0.25f, 0.2f);
    d->gaits[MM_GAIT_JUMP] = d->gaits[MM_GAIT_RUN];
    d->gait_halflife = 0.2f;
    d->history_seconds = 10.0f;
    d->history_rate = 60.0f;
    d->collider_radius = 0.3f;
    d->collider_height = 1.8f;
    d->collider_step = 0.3f;
}

static float resolved(float given, float fallback)
{
    return given == 0.0f ? fallback : given < 0.0f ? 0.0f : given;
}

void mm_trajectory_resolve_desc(const mm_trajectory_desc *in, mm_trajectory_desc *out)
{
    mm_trajectory_desc def, r = *in;
    mm_trajectory_defaults(&def);
    for (int g = 0; g < MM_GAIT_COUNT; ++g) {
        const mm_gait_params *a = &in->gaits[g], *b = &def.gaits[g];
        mm_gait_params *o = &r.gaits[g];
        o->forward_speed = resolved(a->forward_speed, b->forward_speed);
        o->side_speed = resolved(a->side_speed, b->side_speed);
        o->backward_speed = resolved(a->backward_speed, b->backward_speed);
        o->velocity_halflife = resolved(a->velocity_halflife, b->velocity_halflife);
        o->rotation_halflife = resolved(a->rotation_halflife, b->rotation_halflife);
    }
    r.gait_halflife = resolved(in->gait_halflife, def.gait_halflife);
    r.history_seconds = resolved(in->history_seconds, def.history_seconds);
    r.history_rate = resolved(in->history_rate, def.history_rate);
    r.collider_radius = resolved(in->collider_radius, def.collider_radius);
    r.collider_height = resolved(in->collider_height, def.collider_height);
    r.collider_step = resolved(in->collider_step, def.collider_step);
    *out = r;
}

static int sane(float v, float lo, float hi) { return isfinite(v) && v >= lo && v <= hi; }

mm_result mm_trajectory_init(mm_trajectory *t, const mm_trajectory_desc *desc, const mm_allocator *allocator)
{
    if (!t) return MM_ERR_INVALID_ARGUMENT;
    memset(t, 0, sizeof *t);
    mm_trajectory_defaults(&t->desc);
    if (desc) mm_trajectory_resolve_desc(desc, &t->desc);
    const mm_trajectory_desc *d = &t->desc;
    for (int g = 0; g < MM_GAIT_COUNT; ++g) {
        const mm_gait_params *p = &d->gaits[g];
        if (!sane(p->forward_speed, 0, MAX_GAIT_SPEED) || !sane(p->side_speed, 0, MAX_GAIT_SPEED) ||
            !sane(p->backward_speed, 0, MAX_GAIT_SPEED) || !sane(p->velocity_halflife, 0, MAX_HALFLIFE) ||
            !sane(p->rotation_halflife, 0, MAX_HALFLIFE))
            return MM_ERR_OUT_OF_RANGE;
    }
    for (int g = 0; g < MM_GAIT_COUNT && d->bounded; ++g)
        for (int k = 0; k < MM_SPEED_ENVELOPE_BINS; ++k)
            if (!sane(d->envelopes[g].speeds[k], 0, MM_SPEED_ENVELOPE_MAX)) return MM_ERR_OUT_OF_RANGE;
    if (!sane(d->gait_halflife, 0, MAX_HALFLIFE) || !sane(d->history_seconds, 0, MAX_HISTORY_SECONDS) ||
        !sane(d->history_rate, MIN_HISTORY_RATE, MAX_HISTORY_RATE) ||
        !sane(d->collider_radius, 0, MAX_COLLIDER_SIZE) || !sane(d->collider_height, 0, MAX_COLLIDER_SIZE) ||
        !sane(d->collider_step, 0, MAX_COLLIDER_SIZE))
        return MM_ERR_OUT_OF_RANGE;
    if (allocator) t->allocator = *allocator;
    int capacity = (int)ceil(d->history_seconds * d->history_rate) + HISTORY_SLACK;
    t->history_position = (mm_vec3 *)mm_alloc_array(&t->allocator, (size_t)capacity, sizeof(mm_vec3));
    t->history_facing = (mm_quat *)mm_alloc_array(&t->allocator, (size_t)capacity, sizeof(mm_quat));
    if (!t->history_position || !t->history_facing) {
        mm_trajectory_free(t);
        return MM_ERR_OUT_OF_MEMORY;
    }
    t->history_capacity = capacity;
    t->pass_height = -1.0f;
    mm_trajectory_reset(t, mm_vec3_make(0, 0, 0), mm_quat_identity());
    return MM_OK;
}

void mm_trajectory_free(mm_trajectory *t)
{
    if (!t) return;
    mm_allocator a = t->allocator;
    mm_free(&a, t->history_position);
    mm_free(&a, t->history_facing);
    memset(t, 0, sizeof *t);
}

void mm_trajectory_teleport(mm_trajectory *t, mm_vec3 position, mm_quat facing)
{
    if (!t || !isfinite(position.x) || !isfinite(position.z) || !isfinite(facing.x) || !isfinite(facing.y) ||
        !isfinite(facing.z) || !isfinite(facing.w) || mm_quat_length(facing) < 1e-6f)
        return;
    mm_vec3 delta = mm_vec3_make(position.x - t->position.x, 0.0f, position.z - t->position.z);
    t->position = mm_vec3_make(position.x, 0.0f, position.z);
    t->facing = mm_quat_normalize(facing);
    for (int k = 0; k < t->history_count; ++k) {
        int h = (t->history_head - k + t->history_capacity) % t->history_capacity;
        t->history_position[h] = mm_vec3_add(t->history_position[h], delta);
    }
}

void mm_trajectory_reset(mm_trajectory *t, mm_vec3 position, mm_quat facing)
{
    t->position = mm_vec3_make(position.x, 0.0f, position.z);
    t->velocity = t->acceleration = t->angular_velocity = t->last_desired = mm_vec3_make(0, 0, 0);
    t->facing = mm_quat_normalize(facing);
    t->target_facing = t->facing;
    memset(t->gait_weights, 0, sizeof t->gait_weights);
    memset(t->gait_rates, 0, sizeof t->gait_rates);
    t->gait_weights[MM_GAIT_WALK] = 1.0f;
    t->time = 0.0;
    t->history_count = 0;
    t->history_head = -1;
    t->history_time = 0.0;
    t->contact_count = 0;
}

/* The stick, cleaned: NaN counts as zero, longer than 1 is cut to 1. */
static void clean_stick(const mm_input *in, float *x, float *z)
{
    *x = in && isfinite(in->stick[0]) ? in->stick[0] : 0.0f;
    *z = in && isfinite(in->stick[1]) ? in->stick[1] : 0.0f;
    float m = sqrtf(*x * *x + *z * *z);
    if (!(m <= 1.0f)) {
        *x /= m;
        *z /= m;
    }
}

static mm_quat facing_toward(float x, float z)
{
    return mm_quat_from_axis_angle(mm_vec3_make(0, 1, 0), atan2f(x, z));
}

/* The facing the input asks for: the stick's direction, or when strafing the given facing; with
 * neither, the last one asked for (kept, so the spring's target stays fixed). */
static mm_quat target_facing(const mm_trajectory *t, const mm_input *in)
{
    float x, z;
    clean_stick(in, &x, &z);
    if (in && in->strafe) {
        if (in->has_facing && isfinite(in->facing[0]) && isfinite(in->facing[1]) &&
            in->facing[0] * in->facing[0] + in->facing[1] * in->facing[1] > 1e-8f)
            return facing_toward(in->facing[0], in->facing[1]);
        return t->target_facing;
    }
    if (x * x + z * z > STICK_TURN_MIN_SQ) return facing_toward(x, z);
    return t->target_facing;
}

static const mm_gait_params *gait_of(const mm_trajectory *t, const mm_input *in)
{
    int g = (int)mm_input_gait(in);
    return &t->desc.gaits[g];
}

float mm_trajectory_envelope_speed(const mm_trajectory_desc *d, mm_gait gait, float direction)
{
    if (!d || !d->bounded || (int)gait < 0 || (int)gait >= MM_GAIT_COUNT || !isfinite(direction))
        return INFINITY;
    const float *v = d->envelopes[gait].speeds;
    float top = 0.0f;
    for (int k = 0; k < MM_SPEED_ENVELOPE_BINS; ++k)
        if (v[k] > top) top = v[k];     /* fmaxf's answer here (top is never NaN), without its call */
    if (!(top > 0.0f)) return INFINITY; /* no envelope for this gait */
    /* the bins' directions, from forward toward the left, a full turn */
    float bins = direction / (2.0f * (float)MM_PI) * (float)MM_SPEED_ENVELOPE_BINS;
    bins -= floorf(bins / (float)MM_SPEED_ENVELOPE_BINS) * (float)MM_SPEED_ENVELOPE_BINS;
    int k0 = (int)floorf(bins);
    float a = bins - (float)k0;
    k0 %= MM_SPEED_ENVELOPE_BINS;
    int k1 = (k0 + 1) % MM_SPEED_ENVELOPE_BINS;
    return v[k0] + (v[k1] - v[k0]) * a;
}

void mm_trajectory_desired(const mm_trajectory *t, const mm_input *in, mm_vec3 *velocity, mm_quat *facing)
{
    float x, z;
    clean_stick(in, &x, &z);
    mm_quat f = target_facing(t, in);
    const mm_gait_params *p = gait_of(t, in);
    /* the stick in the frame of the facing asked for; speeds on an ellipse there */
    mm_vec3 local = mm_quat_inv_rotate(f, mm_vec3_make(x, 0, z));
    local.x *= p->side_speed;
    local.z *= local.z >= 0.0f ? p->forward_speed : p->backward_speed;
    local.y = 0.0f;
    /* and at most what the data covers that way (the envelope keeps the direction) */
    float speed = sqrtf(local.x * local.x + local.z * local.z);
    if (t->desc.bounded && speed > 0.0f) {
        float most = mm_trajectory_envelope_speed(&t->desc, mm_input_gait(in), atan2f(local.x, local.z));
        if (speed > most) local = mm_vec3_scale(local, most / speed);
    }
    mm_vec3 v = mm_quat_rotate(f, local);
    if (t->contact_count > 0) { /* against walls: along them */
        bool into = false;
        for (int k = 0; k < t->contact_count && k < MM_TRAJECTORY_MAX_CONTACTS; ++k) {
            float d = mm_vec3_dot(v, t->contact_normals[k]);
            if (d < 0.0f) v = mm_vec3_sub(v, mm_vec3_scale(t->contact_normals[k], d)), into = true;
        }
        v.y = 0.0f;
        if (into && !(in && in->strafe) && mm_vec3_length(v) >= MM_TRAJECTORY_SLIDE_MIN_SPEED)
            f = facing_toward(v.x, v.z);
    }
    if (velocity) *velocity = v;
    if (facing) *facing = f;
}

/* The simulated state after dt with fixed targets: position, velocity, acceleration, facing. */
typedef struct state {
    mm_vec3 position, velocity, acceleration, angular_velocity;
    mm_quat facing;
    int contacts;                                /* steps that touched a wall (collided simulation) */
    mm_vec3 normals[MM_TRAJECTORY_MAX_CONTACTS]; /* the walls the last step touched */
    int normal_count;
} state;

static void advance(state *s, mm_vec3 velocity, mm_quat facing, const mm_gait_params *p, float dt)
{
    mm_spring_velocity_update(&s->position, &s->velocity, &s->acceleration, velocity, p->velocity_halflife,
                              dt);
    mm_spring_update_quat(&s->facing, &s->angular_velocity, facing, p->rotation_halflife, dt);
}

/* advance() given the facing's gap to its target (mm__spring_quat_gap(s->facing, facing)): the
 * same bits, the gap computed once for the several times stepped from one state */
static void advance_gap(state *s, mm_vec3 velocity, mm_quat facing, mm_vec3 gap, const mm_gait_params *p,
                        float dt)
{
    mm_spring_velocity_update(&s->position, &s->velocity, &s->acceleration, velocity, p->velocity_halflife,
                              dt);
    mm__spring_update_quat_gap(&s->facing, &s->angular_velocity, gap, facing, p->rotation_halflife, dt);
}

static state current(const mm_trajectory *t)
{
    state s;
    memset(&s, 0, sizeof s);
    s.position = t->position, s.velocity = t->velocity, s.acceleration = t->acceleration;
    s.angular_velocity = t->angular_velocity, s.facing = t->facing;
    return s;
}

void mm_trajectory_set_scene(mm_trajectory *t, const mm_scene *scene, float pass_height)
{
    if (!t) return;
    if (scene != t->scene) t->contact_count = 0;
    t->scene = scene;
    t->pass_height = pass_height >= 0.0f ? pass_height : -1.0f;
}

int mm_trajectory_collide(const mm_trajectory *t, mm_vec3 *position, mm_vec3 *normals, int max_normals)
{
    if (!t || !t->scene || !position) return 0;
    const mm_trajectory_desc *d = &t->desc;
    float pass = t->pass_height >= 0.0f ? t->pass_height : d->collider_step;
    return mm_scene_collide_capsule(t->scene, d->collider_radius, MM_TRAJECTORY_CONTACT_SKIN, t->floor + pass,
                                    t->floor + d->collider_height, position, normals, max_normals);
}

/* In a scene with boxes: the collided simulation (without any, the closed form, to the bit). */
static bool colliding(const mm_trajectory *t) { return t->scene && t->scene->box_count > 0; }

/* The capsule out of the walls, and the motion into them taken away: what is left slides along.
 * Pushed off a face while moving into it, the velocity and the acceleration lose their parts
 * along its normal: the spring there starts again from rest at the wall (an acceleration left
 * along the normal, the braking of a stop, would carry the character back off the wall). */
static void collide(const mm_trajectory *t, state *s)
{
    mm_vec3 *normals = s->normals, before = s->position;
    int n = mm_trajectory_collide(t, &s->position, normals, MM_TRAJECTORY_MAX_CONTACTS);
    if (n > MM_TRAJECTORY_MAX_CONTACTS) n = MM_TRAJECTORY_MAX_CONTACTS;
    mm_vec3 pushed = mm_vec3_sub(s->position, before);
    for (int k = 0; k < n; ++k) {
        float into = mm_vec3_dot(s->velocity, normals[k]);
        if (!(mm_vec3_dot(pushed, normals[k]) > 0.0f) || into > 0.0f) continue; /* resting, or leaving */
        s->velocity = mm_vec3_sub(s->velocity, mm_vec3_scale(normals[k], into));
        float along = mm_vec3_dot(s->acceleration, normals[k]);
        s->acceleration = mm_vec3_sub(s->acceleration, mm_vec3_scale(normals[k], along));
    }
    s->position.y = 0.0f;
    s->normal_count = n;
    s->contacts += n > 0;
}

/* One step of the collided simulation: the closed form over dt, then the collision. */
static void step(const mm_trajectory *t, state *s, mm_vec3 velocity, mm_quat facing, const mm_gait_params *p,
                 float dt)
{
    advance(s, velocity, facing, p, dt);
    collide(t, s);
}

/* The whole steps of the collided simulation from now that fit in `seconds`. */
static int whole_steps(float seconds) { return (int)floorf(seconds / MM_TRAJECTORY_COLLISION_STEP); }

static void push_history(mm_trajectory *t, mm_vec3 position, mm_quat facing, double time)
{
    t->history_head = (t->history_head + 1) % t->history_capacity;
    t->history_position[t->history_head] = position;
    t->history_facing[t->history_head] = facing;
    if (t->history_count < t->history_capacity) ++t->history_count;
    t->history_time = time;
}

/* The collided simulation over dt in equal steps of at most MM_TRAJECTORY_COLLISION_STEP; the
 * history samples from k / rate on that fall inside it, each stepped from the start of its step
 * and collided. The state at the end. */
static state update_colliding(mm_trajectory *t, mm_vec3 velocity, mm_quat facing, const mm_gait_params *p,
                              float dt, double k)
{
    double rate = t->desc.history_rate, end = t->time + dt;
    int steps = (int)ceilf(dt / MM_TRAJECTORY_COLLISION_STEP);
    if (steps < 1) steps = 1;
    float h = dt / (float)steps;
    state s = current(t);
    for (int i = 0; i < steps; ++i) {
        double t0 = t->time + (double)h * i, t1 = i + 1 == steps ? end : t->time + (double)h * (i + 1);
        for (; k / rate <= t1 + 1e-9; k += 1.0) {
            state q = s;
            float tau = (float)(k / rate - t0);
            if (tau > 0.0f) step(t, &q, velocity, facing, p, tau);
            push_history(t, q.position, q.facing, k / rate);
        }
        step(t, &s, velocity, facing, p, (float)(t1 - t0));
    }
    return s;
}

/* A stop keeps the last turn: with the stick let go (nothing asked for) the velocity spring brings
 * the velocity to zero along a straight line from where it was, so a stick turned and let go within
 * a fraction of a second stopped on the old course, the turn lost. While stopping, the velocity and
 * its spring's acceleration are turned toward the last velocity asked for (last_desired), by the
 * share the velocity spring closes in dt: the stop bends toward the turn as the velocity would
 * have. A rotation commutes with the spring toward zero, so the speed's decay is unchanged. */
static void stop_toward_last_turn(const mm_trajectory *t, const mm_gait_params *p, mm_vec3 desired, state *s,
                                  float dt)
{
    mm_vec3 last = t->last_desired;
    if (desired.x * desired.x + desired.z * desired.z > 0.0f || !(last.x * last.x + last.z * last.z > 0.0f))
        return;
    float speed = sqrtf(s->velocity.x * s->velocity.x + s->velocity.z * s->velocity.z);
    if (!(speed > STOP_TURN_MIN_SPEED) || !(p->velocity_halflife > 0.0f)) return;
    float gap =
        remainderf(atan2f(last.x, last.z) - atan2f(s->velocity.x, s->velocity.z), 2.0f * (float)MM_PI);
    float share = 1.0f - exp2f(-dt / p->velocity_halflife);
    mm_quat turn = mm_quat_from_axis_angle(mm_vec3_make(0, 1, 0), gap * share);
    s->velocity = mm_quat_rotate(turn, s->velocity);
    s->acceleration = mm_quat_rotate(turn, s->acceleration);
}

/* mm_trajectory_update, giving the velocity and facing it moved toward; false when it did not run. */
static bool update(mm_trajectory *t, const mm_input *in, float dt, mm_vec3 *desired_velocity,
                   mm_quat *desired_facing)
{
    if (!t || !t->history_position || !(dt > 0.0f) || !isfinite(dt)) return false;
    mm_vec3 velocity;
    mm_quat facing;
    mm_trajectory_desired(t, in, &velocity, &facing);
    const mm_gait_params *p = gait_of(t, in);
    /* the history at fixed times inside (time, time + dt], each from the closed form */
    double rate = t->desc.history_rate, end = t->time + dt;
    double k = t->history_count ? floor(t->history_time * rate + 0.5) + 1.0 : ceil(t->time * rate - 1e-9);
    state s;
    if (colliding(t)) {
        s = update_colliding(t, velocity, facing, p, dt, k);
        stop_toward_last_turn(t, p, velocity, &s, dt);
        t->contact_count = s.normal_count;
        for (int i = 0; i < s.normal_count; ++i) t->contact_normals[i] = s.normals[i];
    } else {
        /* every sample steps from the present toward the same facing */
        mm_vec3 gap = mm__spring_quat_gap(t->facing, facing);
        for (; k / rate <= end + 1e-9; k += 1.0) {
            state q = current(t);
            float tau = (float)(k / rate - t->time);
            if (tau > 0.0f) advance_gap(&q, velocity, facing, gap, p, tau);
            push_history(t, q.position, q.facing, k / rate);
        }
        s = current(t);
        advance_gap(&s, velocity, facing, gap, p, dt);
        stop_toward_last_turn(t, p, velocity, &s, dt);
    }
    t->position = mm_vec3_make(s.position.x, 0.0f, s.position.z);
    t->velocity = s.velocity;
    t->acceleration = s.acceleration;
    t->facing = s.facing;
    t->angular_velocity = s.angular_velocity;
    t->target_facing = facing;
    if (velocity.x * velocity.x + velocity.z * velocity.z > 0.0f) t->last_desired = velocity;
    int g = (int)mm_input_gait(in);
    mm_spring_step gait_step =
        mm_spring_step_make(t->desc.gait_halflife, dt); /* the gaits' springs share it */
    for (int i = 0; i < MM_GAIT_COUNT; ++i)
        mm_spring_update_step(&t->gait_weights[i], &t->gait_rates[i], i == g ? 1.0f : 0.0f, &gait_step);
    t->time = end;
    *desired_velocity = velocity;
    *desired_facing = facing;
    return true;
}

void mm_trajectory_update(mm_trajectory *t, const mm_input *in, float dt)
{
    mm_vec3 velocity;
    mm_quat facing;
    update(t, in, dt, &velocity, &facing);
}

void mm__trajectory_update_desired(mm_trajectory *t, const mm_input *in, float dt, mm_vec3 *velocity,
                                   mm_quat *facing)
{
    int walls_before = t ? t->contact_count : 0;
    /* mm_trajectory_desired reads the simulation's last target facing, which the update sets to
     * the one it moved toward, and its walls: without walls before or after, the same answer */
    if (!update(t, in, dt, velocity, facing) || walls_before > 0 || t->contact_count > 0)
        mm_trajectory_desired(t, in, velocity, facing);
}

/* The recorded state at absolute time `when` (<= now): interpolated between history samples. */
static void past(const mm_trajectory *t, double when, mm_vec3 *position, mm_quat *facing)
{
    if (t->history_count == 0 || when >= t->time) {
        *position = t->position;
        *facing = t->facing;
        return;
    }
    if (when >= t->history_time) { /* between the newest sample and now */
        int h = t->history_head;
        float a = (float)((when - t->history_time) / (t->time - t->history_time));
        *position = mm_vec3_lerp(t->history_position[h], t->position, a);
        *facing = mm_quat_slerp(t->history_facing[h], t->facing, a);
        return;
    }
    double back = (t->history_time - when) * t->desc.history_rate; /* samples back from the newest */
    double oldest = t->history_count - 1;
    if (back >= oldest) back = oldest;
    int i0 = (int)floor(back), i1 = i0 + 1 <= oldest ? i0 + 1 : i0;
    float a = (float)(back - i0);
    int cap = t->history_capacity;
    int h0 = ((t->history_head - i0) % cap + cap) % cap, h1 = ((t->history_head - i1) % cap + cap) % cap;
    *position = mm_vec3_lerp(t->history_position[h0], t->history_position[h1], a);
    *facing = mm_quat_slerp(t->history_facing[h0], t->history_facing[h1], a);
}

void mm_trajectory_sample(const mm_trajectory *t, const mm_input *in, const float *times, int count,
                          mm_vec3 *positions, mm_quat *facings)
{
    mm_vec3 velocity;
    mm_quat facing;
    mm_trajectory_desired(t, in, &velocity, &facing);
    const mm_gait_params *p = gait_of(t, in);
    /* in a scene: the collided simulation on a grid of whole steps from now, walked forward from
     * one time to the next (and back to now when the times go back), each time the grid's last
     * step before it and then the rest */
    state grid = current(t);
    int grid_steps = 0;
    mm_vec3 gap = {0.0f, 0.0f, 0.0f}; /* every sample steps from the present toward one facing */
    bool have_gap = false;
    for (int i = 0; i < count; ++i) {
        float tau = isfinite(times[i]) ? times[i] : 0.0f;
        if (tau <= 0.0f) {
            past(t, t->time + tau, &positions[i], &facings[i]);
            continue;
        }
        state s = current(t);
        if (colliding(t)) {
            int n = whole_steps(fminf(tau, MAX_PREDICT_SECONDS));
            if (n < grid_steps) grid = current(t), grid_steps = 0;
            for (; grid_steps < n; ++grid_steps)
                step(t, &grid, velocity, facing, p, MM_TRAJECTORY_COLLISION_STEP);
            s = grid;
            float rest = tau - (float)n * MM_TRAJECTORY_COLLISION_STEP;
            if (rest > 0.0f) step(t, &s, velocity, facing, p, rest);
        } else {
            if (!have_gap) gap = mm__spring_quat_gap(t->facing, facing), have_gap = true;
            advance_gap(&s, velocity, facing, gap, p, tau);
        }
        positions[i] = mm_vec3_make(s.position.x, 0.0f, s.position.z);
        facings[i] = s.facing;
    }
}

int mm_trajectory_predict(const mm_trajectory *t, mm_vec3 velocity, mm_quat facing, mm_gait gait,
                          float seconds, mm_vec3 *position, mm_quat *facing_out, float *path)
{
    if (!t || (int)gait < 0 || (int)gait >= MM_GAIT_COUNT) return 0;
    const mm_gait_params *p = &t->desc.gaits[gait];
    float tau = isfinite(seconds) ? fminf(fmaxf(seconds, 0.0f), MAX_PREDICT_SECONDS) : 0.0f;
    state s = current(t);
    float travelled = 0.0f;
    if (colliding(t)) {
        int n = whole_steps(tau);
        for (int i = 0; i <= n; ++i) {
            float h = i < n ? MM_TRAJECTORY_COLLISION_STEP : tau - (float)n * MM_TRAJECTORY_COLLISION_STEP;
            if (!(h > 0.0f)) continue;
            mm_vec3 before = s.position;
            step(t, &s, velocity, facing, p, h);
            travelled += mm_vec3_length(mm_vec3_sub(s.position, before));
        }
    } else if (tau > 0.0f) {
        advance(&s, velocity, facing, p, tau);
        s.position.y = 0.0f;
        travelled = mm_vec3_length(mm_vec3_sub(s.position, t->position));
    }
    if (position) *position = mm_vec3_make(s.position.x, 0.0f, s.position.z);
    if (facing_out) *facing_out = s.facing;
    if (path) *path = travelled;
    return s.contacts;
}
