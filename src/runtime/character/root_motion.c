/* Stage 5: root motion. */
#include "root_motion.h"

#include <math.h>

#include <mm/spring.h>

#include "math_private.h"

/* the share of the gait's full forward speed from which the angle correction works */
#define ANGLE_CORRECTION_FROM_SPEED 0.9f
/* m: the root's ground is averaged from this far behind it to this far ahead (about a stride: a
 * step's edge comes in over the stride, not at once) */
#define ROOT_GROUND_SPAN 0.35f
/* points the root's ground is averaged over (odd: one under the root) */
#define ROOT_GROUND_SAMPLES 15
/* s: half-life of the spring the root's height follows the ground with */
#define ROOT_GROUND_HALFLIFE 0.08f

void mm_root_motion_update(mm_root_motion *r, const mm_character_desc *d, const mm_trajectory *t,
                           const mm_intent *intent, mm_root_played played, bool free_root, float dt)
{
    r->played = played;
    mm_vec3 v = mm_quat_rotate(r->root.rotation, played.velocity);
    float yaw = yaw_of(r->root.rotation) + played.yaw_rate * dt;
    mm_vec3 position = mm_vec3_add(r->root.translation, mm_vec3_scale(v, dt));
    float pull = free_root ? 0.0f : d->sync_halflife > 0.0f ? 1.0f - exp2f(-dt / d->sync_halflife) : 1.0f;
    mm_vec3 gap = mm_vec3_sub(t->position, position);
    gap.y = 0.0f;
    position = mm_vec3_add(position, mm_vec3_scale(gap, pull));
    float simulated_yaw = yaw_of(t->facing);
    yaw += wrap_angle(simulated_yaw - yaw) * pull;
    mm_vec3 off = mm_vec3_sub(position, t->position);
    off.y = 0.0f;
    float dist = mm_vec3_length(off);
    if (!free_root && dist > d->sync_max_distance)
        position = mm_vec3_add(t->position, mm_vec3_scale(off, d->sync_max_distance / dist));
    /* angle correction at full speed (seed 000): a small error between the character's facing and
     * the one asked for is turned away at a bounded rate, as the animation alone may never quite
     * line up */
    float full = t->desc.gaits[intent->gait].forward_speed;
    float error = wrap_angle(yaw_of(intent->desired_facing) - yaw);
    if (!free_root && full > 0.0f && mm_vec3_length(t->velocity) >= ANGLE_CORRECTION_FROM_SPEED * full &&
        fabsf(error) < d->angle_threshold) {
        float step = d->angle_revise_speed * dt;
        yaw += error > step ? step : error < -step ? -step : error;
    }
    float angle = wrap_angle(yaw - simulated_yaw);
    if (!free_root && fabsf(angle) > d->sync_max_angle)
        yaw = simulated_yaw + (angle > 0 ? d->sync_max_angle : -d->sync_max_angle);
    /* in a scene, the root is the simulation's capsule too: out of the walls, as it is */
    if (!free_root) mm_trajectory_collide(t, &position, NULL, 0);
    /* the height is kept: 0 on flat ground, or where the move layer put the character */
    r->root =
        mm_xform_make(yaw_quat(wrap_angle(yaw)), mm_vec3_make(position.x, r->root.translation.y, position.z));
}

/* The mean of the ground's height at ROOT_GROUND_SAMPLES points along the root's facing, from
 * ROOT_GROUND_SPAN behind to as far ahead, and its least-squares slope along the facing. */
static float ground_along(const mm_scene *scene, mm_xform root, mm_vec3 *forward_out, float *slope)
{
    mm_vec3 forward = mm_quat_rotate(root.rotation, mm_vec3_make(0.0f, 0.0f, 1.0f));
    forward.y = 0.0f;
    float flat = sqrtf(forward.x * forward.x + forward.z * forward.z);
    forward = flat > 1e-6f ? mm_vec3_scale(forward, 1.0f / flat) : mm_vec3_make(0.0f, 0.0f, 1.0f);
    float sum = 0.0f, moment = 0.0f, spread = 0.0f;
    for (int i = 0; i < ROOT_GROUND_SAMPLES; ++i) {
        float s = ROOT_GROUND_SPAN * (2.0f * (float)i / (float)(ROOT_GROUND_SAMPLES - 1) - 1.0f);
        float h = mm_scene_ground_height(scene, root.translation.x + s * forward.x,
                                         root.translation.z + s * forward.z, NULL);
        sum += h;
        moment += s * h;
        spread += s * s;
    }
    if (forward_out) *forward_out = forward;
    if (slope) *slope = moment / spread;
    return sum / (float)ROOT_GROUND_SAMPLES;
}

float mm_root_motion_ground(const mm_scene *scene, mm_xform root)
{
    return ground_along(scene, root, NULL, NULL);
}

void mm_root_motion_follow_ground(mm_root_motion *r, const mm_scene *scene, float dt)
{
    if (!scene) {
        r->on_ground = false;
        r->ground_velocity = 0.0f;
        return;
    }
    mm_vec3 forward;
    float slope;
    float target = ground_along(scene, r->root, &forward, &slope);
    /* the spring aims ahead of the ground by the lag a critically damped spring has behind a
     * steady climb (2 v / y): on a slope the root keeps to the ground's height, not under it */
    float speed = 0.0f;
    if (r->on_ground) {
        mm_vec3 moved = mm_vec3_sub(r->root.translation, r->ground_from);
        speed = (moved.x * forward.x + moved.z * forward.z) / dt;
    } else {
        r->ground_velocity = 0.0f;
    }
    r->on_ground = true;
    r->ground_from = r->root.translation;
    float lead = (float)(2.0 / mm_spring_damping(ROOT_GROUND_HALFLIFE)) * slope * speed;
    float y = r->root.translation.y;
    mm_spring_update(&y, &r->ground_velocity, target + lead, ROOT_GROUND_HALFLIFE, dt);
    r->root.translation.y = y;
}
