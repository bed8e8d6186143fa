/* Stage 7: foot locking on the contact labels, the hips lowered where the legs cannot reach, then
 * two-bone IK. */
#include "feet.h"

#include <math.h>

#include <mm/leg_ik.h>
#include <mm/scene.h>
#include <mm/spring.h>

/* share of the leg's length over which the IK's reach softens (mm_leg_ik_params.soft_reach) */
#define SOFT_REACH 0.05f
/* rad: the most a foot planted on heel and toe is turned from its animated orientation */
#define MAX_FOOT_TURN 1.2f
/* share of a foot's turn about its leg's axis that the leg turns with (solve_leg) */
#define LEG_TURN_SHARE 1.0f
/* a foot whose ankle-to-toe vector is shorter than this share of it on the ground plane has no
 * heading to keep (keep_heading) */
#define HEADING_MIN_SHARE 0.5f
/* s: half-life of the spring the hips are lowered and raised through */
#define HIP_DROP_HALFLIFE 0.05f
/* a free foot's target far out of reach is brought in to the leg's length and this many widths of
 * the IK's softening (SOFT_REACH of the length each) */
#define ONTO_SOFT_WIDTHS 3.0f
/* m: how far below its planted height a toe may go as the ankle is raised to keep it up (a soft
 * floor: the ankle rises smoothly over twice this as the toe comes down) */
#define TOE_SINK 0.01f
/* m: below the soft floor, where a toe the leg cannot raise is lifted by pitching the foot */
#define TOE_LIFT_MARGIN 0.002f
/* m: an ankle-to-toe vector shorter than this has no direction to turn the foot by */
#define MIN_FOOT_LENGTH 1e-6f
/* s: a lock above its animated joint halves its height above it at least this often (settle) */
#define LOCK_SETTLE_HALFLIFE 0.1f
/* m: a foot whose labelled joints are all further than this above where they stand waits to be
 * planted (aloft) */
#define PLANT_MAX_HEIGHT 0.04f
/* a landing is done once this little of plant_time is left */
#define LANDING_DONE 1e-4f
/* a free foot catching up with its animated place along the ground plane (the offset a lock let go
 * of leaves, a transition's) is lifted by this share of the way left, at most STEP_LIFT_MAX: it
 * steps there instead of skating over the ground; no lift while a contact is on or coming */
#define STEP_LIFT_SHARE 0.25f
#define STEP_LIFT_MAX   0.04f
/* s: half-life of the spring the lift follows with (up, and down before a landing) */
#define STEP_LIFT_HALFLIFE 0.15f
/* m: past unlock_radius, how far the creep of a lock after the animation grows from nothing to a
 * whole spring step a tick (a threshold would move the lock by a whole step at once) */
#define UNLOCK_RAMP 0.05f
/* m: how far short of its target a leg may leave its ankle before the lock creeps after the
 * animation (the IK's softened reach leaves a straightening leg a little short) */
#define REACH_SLACK 0.02f
/* m/s^2: the most a landing slows a foot on the ground plane: a foot faster than this times
 * plant_time (a transition's offsets still carrying a swing onto a frame whose label is on) lands
 * over longer, as its speed asks */
#define LANDING_DECELERATION 150.0f
/* rad: on terrain, the most a foot is turned to the ground's slope (about 26 degrees) */
#define MAX_FOOT_TILT 0.45f
/* m: a free foot this far above where it would stand is not turned to the ground at all (fully
 * at 0, linearly between) */
#define TILT_FADE_HEIGHT 0.15f
/* s: half-life over which the normal a foot is turned to follows the ground's (an edge of a ramp
 * passes under the foot over a few ticks, not at once) */
#define TILT_HALFLIFE 0.05f
/* m/s: on terrain, the fastest growth of the hips' drop that the spring aims ahead of (a need that
 * jumps, a lock placed, is followed through the spring alone) */
#define HIP_LEAD_MAX_RATE 1.5f
/* m: on terrain, how much further than max_hip_drop the hips may come down (a leg reaching the
 * step below) */
#define TERRAIN_HIP_DROP 0.15f
/* m: and for a planted foot behind its hip (the body climbing away from a trailing foot on a
 * lower tread): the other leg's foot is ahead and above, its knee bends up toward the step it
 * stands on, not down into the edge behind it as a trailing leg's does going down */
#define TERRAIN_TRAILING_HIP_DROP 0.3f
/* m: a free foot moving over terrain is kept above the ground this far ahead of its toe, less
 * CLEAR_SLOPE per metre ahead: it rises toward a step's edge along a slope before it gets there
 * (a floor continuous in the foot's place, not one that jumps a riser as the edge passes) */
#define CLEAR_AHEAD 0.3f
#define CLEAR_SLOPE 0.6f
/* points the ground ahead of a free foot is read at */
#define CLEAR_SAMPLES 8
/* m/s: the fastest the ground ahead raises a free foot above its target and last tick's height */
#define CLEAR_RISE_SPEED 2.0f
/* m/s: a free foot slower than this looks nowhere ahead */
#define CLEAR_MIN_SPEED 0.2f
/* s: half-life of the spring an animated foot's shift to the ground under it follows with (a
 * step's edge passing under the foot comes in over a few ticks) */
#define GROUND_SHIFT_HALFLIFE 0.04f
/* m: how far the sole reaches behind the ankle and ahead of the toe joint, the part of the foot
 * that must stand on one tread */
#define SOLE_BEHIND_ANKLE 0.05f
#define SOLE_AHEAD_OF_TOE 0.04f
/* m: a rise of the ground between two neighbouring points along the sole larger than this is a
 * step's edge (a slope of 21 degrees rises 0.6 cm between them) */
#define TREAD_EDGE_RISE 0.03f
/* points the ground along the sole is read at, to find a step's edge under a landing foot */
#define TREAD_SAMPLES 24
/* m/s: the fastest a landing foot is moved onto one tread */
#define TREAD_SPEED 1.5f
/* m: a free foot this little above where it would stand is moved onto one tread */
#define TREAD_NEAR 0.06f
/* m/s: the fastest a landing foot is brought down to the ground beyond its own fall */
#define LANDING_FALL_SPEED 2.0f
/* m: how far past a step's edge the sole's end is moved (the leg's reach may leave the ankle a
 * little short of its target) */
#define TREAD_MARGIN 0.02f
/* s: a free foot held below the animated one by its offset (the height of a lock just let go)
 * comes up with this half-life, at most foot_halflife: at foot_halflife it skated along the ground
 * while its offset on the ground plane faded (docs/metrics.md, "The independent slide") */
#define LIFT_HALFLIFE 0.05f

/* rad: the most a foot planted on its toe alone is pivoted about it, heel up, so that a leg that
 * cannot reach its ankle's target still reaches the toe (pivot_on_toe) */
#define MAX_TOE_PIVOT 0.8f
/* rad/s: the fastest that pivot grows (a foot whose heel lets go far out of its leg's reach rolls
 * up onto its toe over a few ticks, not in one) */
#define TOE_PIVOT_RATE 3.0f

/* Where foot k's ankle goes by its locks alone: the heel lock; or the toe lock less the animated
 * ankle-to-toe vector (turned by the foot's turn), so that the foot rolls about its planted toe as
 * animated; or, free, the animated ankle. */
static mm_vec3 foot_source(const mm_feet *f, int k, mm_vec3 ankle, mm_vec3 toe)
{
    if (f->heel_locked[k]) return f->heel_lock[k];
    if (f->toe_locked[k])
        return mm_vec3_sub(f->toe_lock[k], mm_quat_rotate(mm_quat_exp(f->turn[k]), mm_vec3_sub(toe, ankle)));
    return ankle;
}

/* The velocity of what foot k follows (foot_source with the locks as they are now) over the last
 * tick, from last tick's animated ankle and toe; zero before the first tick. */
static mm_vec3 source_velocity(const mm_feet *f, int k, mm_vec3 ankle, mm_vec3 toe, float dt)
{
    if (!f->placed) return mm_vec3_make(0, 0, 0);
    mm_vec3 now = foot_source(f, k, ankle, toe), then = foot_source(f, k, f->last_ankle[k], f->last_toe[k]);
    return mm_vec3_scale(mm_vec3_sub(now, then), 1.0f / dt);
}

/* Foot k's leg solved by the leg IK (mm/leg_ik.h) so that its ankle reaches target, the knee
 * bending the way its hinge does (mm_rig_knee_pole) where the animated bend does not say, the reach softened
 * near full extension; the ankle takes the world orientation ankle_world. Works on the local rotations and
 * the global transforms of the three joints. */
static void solve_leg(const mm_rig *rig, int k, mm_vec3 target, mm_quat ankle_world, mm_rig_pose *pose)
{
    int ankle = rig->ankle[k], knee = rig->knee[k], hip = rig->hip[k], hip_parent = rig->joints[hip].parent;
    mm_xform *g = pose->global;
    mm_leg_pose leg = {g[hip].translation, g[knee].translation, g[ankle].translation};
    mm_leg_ik_params params = {1.0f, SOFT_REACH};
    mm_leg_warp out;
    mm_vec3 pole = mm_rig_knee_pole(rig, pose, k);
    mm_quat about = mm_quat_identity();
    /* the leg turns with its foot about the hip-to-ankle axis (the twist of the foot's turn from its
     * animated orientation about that axis): a planted foot held while the body turns away from it
     * keeps its knee over it instead of twisting below the shin */
    mm_vec3 axis = mm_vec3_sub(leg.foot, leg.hip);
    float reach = mm_vec3_length(axis);
    if (reach > MIN_FOOT_LENGTH) {
        axis = mm_vec3_scale(axis, 1.0f / reach);
        mm_quat turn = mm_quat_mul(ankle_world, mm_quat_conj(g[ankle].rotation));
        if (turn.w < 0.0f) turn = (mm_quat){-turn.x, -turn.y, -turn.z, -turn.w};
        float twist = 2.0f * atan2f(turn.x * axis.x + turn.y * axis.y + turn.z * axis.z, turn.w);
        about = mm_quat_exp(mm_vec3_scale(axis, LEG_TURN_SHARE * twist));
        leg.knee = mm_vec3_add(leg.hip, mm_quat_rotate(about, mm_vec3_sub(leg.knee, leg.hip)));
        pole = mm_quat_rotate(about, pole);
    }
    if (mm_leg_ik_solve(&leg, target, pole, &params, &out) != MM_OK) return;
    mm_quat hip_world = mm_quat_normalize(mm_quat_mul(out.thigh, mm_quat_mul(about, g[hip].rotation)));
    mm_quat knee_world = mm_quat_normalize(mm_quat_mul(out.shin, mm_quat_mul(about, g[knee].rotation)));
    pose->local_rotations[hip] =
        mm_quat_normalize(mm_quat_mul(mm_quat_conj(g[hip_parent].rotation), hip_world));
    g[hip] =
        mm_xform_mul(g[hip_parent], mm_xform_make(pose->local_rotations[hip], pose->local_positions[hip]));
    pose->local_rotations[knee] = mm_quat_normalize(mm_quat_mul(mm_quat_conj(g[hip].rotation), knee_world));
    g[knee] = mm_xform_mul(g[hip], mm_xform_make(pose->local_rotations[knee], pose->local_positions[knee]));
    pose->local_rotations[ankle] =
        mm_quat_normalize(mm_quat_mul(mm_quat_conj(g[knee].rotation), ankle_world));
}

void mm_feet_record(mm_feet *f, const mm_rig *rig, const mm_rig_pose *pose)
{
    for (int k = 0; k < 2; ++k) { /* the ankle and the ankle's first child (the toe) */
        int ankle = rig->ankle[k], toe = rig->toe[k];
        f->raw_contacts[2 * k] = ankle >= 0 ? pose->global[ankle].translation : mm_vec3_make(0, 0, 0);
        f->raw_contacts[2 * k + 1] = toe >= 0 ? pose->global[toe].translation : f->raw_contacts[2 * k];
    }
}

/* The height at which an ankle or a toe that the data plants `planted` above flat ground stands
 * over (x, z): on the plane, its height + planted; on terrain, the ground under the point +
 * planted along its normal (planted / cos(slope), the slope as far as a foot is turned). */
static float stand_height(const mm_feet_ground *ground, float x, float z, float planted)
{
    if (!ground->scene) return ground->height + planted;
    mm_vec3 n;
    float h = mm_scene_ground_height(ground->scene, x, z, &n);
    return h + planted / fmaxf(n.y, cosf(MAX_FOOT_TILT));
}

/* A height for a lock placed at p: not below where it stands (when the feet keep to the ground);
 * on terrain, where it stands (a foot planted in the air, its label on early or a transition's
 * offset holding it up, comes down onto the ground as its offset fades). */
static float above_ground(const mm_feet_ground *ground, float planted, mm_vec3 p)
{
    if (!ground->hold) return p.y;
    float floor = stand_height(ground, p.x, p.z, planted);
    return p.y < floor || ground->scene ? floor : p.y;
}

/* The height of a lock at p whose joint is animated at height animated, having come down by fall
 * (m) over the last tick. A lock is planted where the foot is, at times above the animated foot (an
 * offset holding the foot up: a transition's, or its own after a release); it comes down to the
 * animated joint (not below the ground it stands on), at the faster of the animated joint's descent
 * and halving its height above it every LOCK_SETTLE_HALFLIFE: gradually, where a lock put there at
 * once would snap the foot down (and a held toe turn the foot at once). A foot planted while still
 * settling thus follows the animated foot down instead of hovering where it was planted. On terrain
 * a lock is on the ground from the start (its offset takes the foot down); in a move (no ground
 * held) it comes down with the animated joint. */
static float settle(const mm_feet_ground *ground, float planted, mm_vec3 p, float animated, float fall,
                    float dt)
{
    if (!ground->hold) return fminf(p.y, animated);
    float floor = stand_height(ground, p.x, p.z, planted), rest = fmaxf(floor, animated);
    if (ground->scene) return floor;
    if (!(p.y > rest)) return fmaxf(p.y, floor);
    float eased = rest + (p.y - rest) * exp2f(-dt / LOCK_SETTLE_HALFLIFE);
    return fmaxf(rest, fminf(p.y - fmaxf(fall, 0.0f), eased));
}

/* An ankle's height y kept so that its toe is at most TOE_SINK below floor (the ankle height at which
 * the toe is at its planted height): unchanged from floor up, floor - TOE_SINK from 2 TOE_SINK below,
 * a parabola between (continuous in value and slope, so that a foot coming down slows smoothly). */
static float toe_floor(float y, float floor)
{
    float s = TOE_SINK, below = y - floor + 2.0f * s;
    if (y >= floor) return y;
    return below <= 0.0f ? floor - s : floor - s + below * below / (4.0f * s);
}

/* On terrain: the step, on the ground plane, that moves a free foot coming down (its ankle at
 * most TREAD_NEAR above where it would stand, planted above the highest ground under its sole)
 * whose sole (ankle at heel + ahead, toe joint at heel + ahead + along, SOLE_BEHIND_ANKLE and
 * SOLE_AHEAD_OF_TOE beyond) lies across a step's edge toward standing on one tread: forward past
 * the edge or back behind it, TREAD_MARGIN beyond, whichever is shorter, at most TREAD_SPEED over
 * dt. Zero where the ground under the sole has no edge, or the foot is higher. `ahead` (on the
 * ground plane) is how far a landing foot has yet to go before it stops: the edge that matters is
 * the one under the sole where it will be planted (judged where it is, a foot still sliding over
 * edges is sent forward and back in turn and planted wherever the landing ends). A foot planted
 * across an edge would stand on the tread under its heel or under its toe with the other end in
 * the air or in the riser, and its heel and toe locks would read the ground of different treads. */
static mm_vec3 tread_step(const mm_scene *scene, mm_vec3 heel, mm_vec3 ahead, mm_vec3 along, float planted,
                          float dt)
{
    mm_vec3 none = mm_vec3_make(0.0f, 0.0f, 0.0f);
    heel.x += ahead.x, heel.z += ahead.z;
    float length = sqrtf(along.x * along.x + along.z * along.z);
    if (!scene || !(length > MIN_FOOT_LENGTH)) return none;
    float ux = along.x / length, uz = along.z / length;
    float sole = SOLE_BEHIND_ANKLE + length + SOLE_AHEAD_OF_TOE, spacing = sole / (float)(TREAD_SAMPLES - 1);
    float back_x = heel.x - ux * SOLE_BEHIND_ANKLE, back_z = heel.z - uz * SOLE_BEHIND_ANKLE;
    float previous = mm_scene_ground_height(scene, back_x, back_z, NULL), edge = -1.0f, biggest = 0.0f;
    float highest = previous;
    for (int i = 1; i < TREAD_SAMPLES; ++i) {
        float s = spacing * (float)i,
              h = mm_scene_ground_height(scene, back_x + ux * s, back_z + uz * s, NULL);
        float rise = fabsf(h - previous);
        if (rise > TREAD_EDGE_RISE && rise > biggest) biggest = rise, edge = s - 0.5f * spacing;
        previous = h, highest = fmaxf(highest, h);
    }
    if (edge < 0.0f || heel.y - planted - highest > TREAD_NEAR) return none;
    float forward = edge + TREAD_MARGIN, backward = sole - edge + TREAD_MARGIN;
    float move = forward <= backward ? forward : -backward;
    float most = TREAD_SPEED * dt;
    move = fminf(fmaxf(move, -most), most);
    return mm_vec3_make(ux * move, 0.0f, uz * move);
}

/* On terrain: the ground a foot whose ankle is over heel stands on, its toe at heel + along before
 * it is turned by tilt to the ground: the higher of the ground under its ankle and the ground under
 * its toe less the rise the turn gives the toe (on a slope both read the ground under the ankle; a
 * foot across a step's edge stands on the higher tread). Read where the foot is (held, or animated
 * and carried by its offset), not where it is animated: a landing foot moved onto one tread stands
 * on that tread. */
static float foot_ground(const mm_scene *scene, mm_vec3 heel, mm_vec3 along, mm_quat tilt)
{
    float rise = mm_quat_rotate(tilt, along).y - along.y;
    return fmaxf(mm_scene_ground_height(scene, heel.x, heel.z, NULL),
                 mm_scene_ground_height(scene, heel.x + along.x, heel.z + along.z, NULL) - rise);
}

/* On terrain: the height at which foot k's ankle, at ankle (its toe at ankle + along), stands on
 * the ground under it: the highest of its ankle's, its toe's and its sole's back end's (where the
 * ankle or the toe is at its planted height). */
static float sole_stand(const mm_feet_ground *ground, const mm_rig *rig, int k, mm_vec3 ankle, mm_vec3 along)
{
    float length = sqrtf(along.x * along.x + along.z * along.z);
    float back = length > MIN_FOOT_LENGTH ? SOLE_BEHIND_ANKLE / length : 0.0f;
    float stand =
        fmaxf(stand_height(ground, ankle.x, ankle.z, rig->planted_ankle[k]),
              stand_height(ground, ankle.x + along.x, ankle.z + along.z, rig->planted_toe[k]) - along.y);
    /* the heel's end too: a foot landing just past a step's edge is held on the higher tread until
     * it is planted (the leg's reach, short of a lower tread, would leave the heel in the edge). Only
     * an edge's rise: down a slope the heel's end is uphill of the ankle by what the foot turned to
     * the slope already gives it, and the ankle is planted over its own ground */
    float heel_end =
        stand_height(ground, ankle.x - back * along.x, ankle.z - back * along.z, rig->planted_ankle[k]);
    return heel_end - stand_height(ground, ankle.x, ankle.z, rig->planted_ankle[k]) > TREAD_EDGE_RISE
               ? fmaxf(stand, heel_end)
               : stand;
}

/* On terrain: the height of a landing foot's ankle w of the way (the landing's share) from its
 * height down to where it stands (sole_stand): a foot is planted on the ground, not where its
 * label finds it (early, over a lower tread or down a slope) to come down as the offset fades.
 * Never raised. */
static float landing_height(const mm_feet_ground *ground, const mm_rig *rig, int k, mm_vec3 ankle,
                            mm_vec3 along, float w)
{
    return ankle.y - w * fmaxf(ankle.y - sole_stand(ground, rig, k, ankle, along), 0.0f);
}

/* On terrain: how long foot k's ankle, at ankle (its toe at ankle + along), takes to come down to
 * where it stands at LANDING_FALL_SPEED. */
static float landing_fall_time(const mm_feet_ground *ground, const mm_rig *rig, int k, mm_vec3 ankle,
                               mm_vec3 along)
{
    return fmaxf(ankle.y - sole_stand(ground, rig, k, ankle, along), 0.0f) / LANDING_FALL_SPEED;
}

/* Whether foot k, its ankle going to ankle and its toe toe_above higher, is too far above the ground
 * to plant on the labels that are on (heel_on, toe_on): each labelled joint more than
 * PLANT_MAX_HEIGHT above where it stands. A transition's offset can hold a foot up while its clip's
 * label is on; planted there, it would be held in the air (and let go again as the label turns
 * off), so it waits for the foot to come down, held on the ground plane by the landing. On terrain
 * too, where it stands is the ground under it: a foot labelled over a lower tread while still
 * shown above it (going down stairs) waits until it is down. */
static bool aloft(const mm_feet_ground *ground, const mm_rig *rig, int k, int heel_on, int toe_on,
                  mm_vec3 ankle, float toe_above)
{
    if (!ground->hold) return false;
    bool heel_up = ankle.y - stand_height(ground, ankle.x, ankle.z, rig->planted_ankle[k]) > PLANT_MAX_HEIGHT;
    bool toe_up =
        ankle.y + toe_above - stand_height(ground, ankle.x, ankle.z, rig->planted_toe[k]) > PLANT_MAX_HEIGHT;
    return (heel_on || toe_on) && (!heel_on || heel_up) && (!toe_on || toe_up);
}

/* On terrain: a swinging foot k (free, its contact coming in `left`) is moved toward the ground it
 * will land on, so that it arrives there by its contact: its shift from the root's ground to the
 * ground under it goes toward the ground at its landing place over the time left, evenly (a share
 * dt / left of the way each tick). The landing place is where the foot is (at, on the ground plane)
 * plus its velocity times left over two (it slows to rest by then); read again each tick, it grows
 * more exact as the contact nears. Followed only as the ground under the foot, it would still be
 * at the tread it left when its label turns on over a lower one (and held up by its offset after). */
static void plan_swing(mm_feet *f, int k, const mm_feet_ground *ground, float planted, mm_vec3 ankle,
                       mm_vec3 at, mm_vec3 along, mm_quat tilt, float left, float dt)
{
    float vx = (ankle.x - f->last_ankle[k].x) / dt + f->offset_velocity[k].x,
          vz = (ankle.z - f->last_ankle[k].z) / dt + f->offset_velocity[k].z;
    mm_vec3 landing = mm_vec3_make(at.x + vx * 0.5f * left, at.y, at.z + vz * 0.5f * left);
    float goal = foot_ground(ground->scene, landing, along, tilt) - ground->height;
    float before = f->ground_shift[k], shift = before + (goal - before) * fminf(dt / left, 1.0f);
    /* not down through the ground under the ankle (the tread it is still over): held on it, the
     * rest of the way is gone once the edge has passed, in the time then left (kept here, not
     * only in the ankle's target, so that the foot does not drop the riser at once) */
    shift = fmaxf(shift, stand_height(ground, at.x, at.z, planted) - (ankle.y + f->offset[k].y));
    /* and never faster down than LANDING_FALL_SPEED: a foot that passes the edge just before its
     * contact comes down the riser over ticks (and lands late) instead of dropping it in one */
    shift = fmaxf(shift, before - LANDING_FALL_SPEED * dt);
    f->ground_shift[k] = shift;
    f->ground_shift_velocity[k] = (shift - before) / dt;
}

/* How far free foot k is lifted this tick as it catches up with its animated place: STEP_LIFT_SHARE
 * of its offset left on the ground plane, at most STEP_LIFT_MAX, followed through a spring (from
 * nothing as a lock lets go: the foot rises as it moves off); none while the foot is locked, and
 * down toward none while a contact is on or coming (`free` false) or the ground is not held. */
static float step_lift(mm_feet *f, int k, bool free, float dt)
{
    if (f->locked[k]) {
        f->step_lift[k] = f->step_lift_velocity[k] = 0.0f;
        return 0.0f;
    }
    float left = sqrtf(f->offset[k].x * f->offset[k].x + f->offset[k].z * f->offset[k].z);
    float want = free ? fminf(STEP_LIFT_SHARE * left, STEP_LIFT_MAX) : 0.0f;
    mm_spring_update(&f->step_lift[k], &f->step_lift_velocity[k], want, STEP_LIFT_HALFLIFE, dt);
    return f->step_lift[k];
}

/* m/s: a free foot moving over the ground faster than this is kept above where it would stand
 * (swing_clear): a swing that a transition's offsets bring down to the ground (the legs' offsets
 * act on rotations, and carry the toe through the floor) skimmed it at 1-6 m/s, and a lock let go
 * far behind its animated place dragged its toe along the ground as it caught up (docs/metrics.md,
 * "The independent slide: swings kept off the ground") */
#define SWING_CLEAR_FROM 0.5f
/* s: the clearance is this times the speed beyond SWING_CLEAR_FROM (2 cm at 1.5 m/s), at most
 * SWING_CLEAR_MAX */
#define SWING_CLEAR_TIME 0.02f
#define SWING_CLEAR_MAX  0.04f
/* s: half-life of the spring the clearance follows its speed's with (a foot let go speeds up by up
 * to 2.5 m/s a tick, SWING_ACCELERATION: followed at once the foot rose by up to 4 cm in a tick) */
#define SWING_CLEAR_HALFLIFE 0.05f
/* s: a contact coming within this takes the clearance down in proportion to the time left (all of
 * it, with the landing's share, by the time the foot is planted) */
#define SWING_CLEAR_LAND 0.15f

/* Whether foot k's label is on or is seen coming within the landing's look-ahead (until_label). */
static bool landing_now(const mm_feet_contacts *contacts, int k)
{
    return ((contacts->label >> (2 * k)) & 3u) != 0 || contacts->until_label[k] >= 0.0f;
}

/* The height a clearance `clear` adds to an ankle target at height y above stand (the ankle's height
 * at which its ankle and toe are at their planted heights), as toe_floor's soft floor, eased in over
 * the first TOE_SINK of clearance: the soft floor lifts a foot within TOE_SINK of stand by a quarter
 * of that even at no clearance, which would lift it by that in the tick it is let go. */
static float cleared(float y, float stand, float clear)
{
    if (!(clear > 0.0f)) return y;
    return y + (toe_floor(y, stand + clear + TOE_SINK) - y) * fminf(clear / TOE_SINK, 1.0f);
}

/* Free foot k's ankle target height y kept clear of the ground for the foot's speed over it (last
 * tick's target's): SWING_CLEAR_TIME of the speed beyond SWING_CLEAR_FROM, at most SWING_CLEAR_MAX,
 * less as a contact comes in `left` s (within SWING_CLEAR_LAND), none while `landing` (a label on or
 * coming within the landing's look-ahead), followed through a spring (cleared). On the tick the
 * foot is planted, what is left of it is handed to the foot's offset in place and velocity, fading
 * from there over foot_halflife as any other offset: the foot comes down through the landing with
 * no step in its vertical velocity (taken down with the landing's share, a clearance was gone in the
 * one or two ticks of an unforeseen landing; docs/metrics.md, "Pops, fifth pass"). A foot at rest
 * is not moved; nothing before the first tick. */
static float swing_clear(mm_feet *f, int k, float y, float stand, float left, bool landing, float dt)
{
    if (f->locked[k] || !f->placed) {
        float out = y;
        if (f->locked[k] && f->placed) {
            /* planted: this tick's step, then handed over with the rate at which the height it adds
             * changed over the step (continuous in the foot's place: a rounding apart, two feet
             * hand over nearly the same) */
            float from = cleared(y, stand, f->clearance[k]);
            mm_spring_update(&f->clearance[k], &f->clearance_velocity[k], 0.0f, SWING_CLEAR_HALFLIFE, dt);
            out = cleared(y, stand, f->clearance[k]);
            f->offset[k].y += out - y;
            f->offset_velocity[k].y += (out - from) / dt;
        }
        f->clearance[k] = f->clearance_velocity[k] = 0.0f;
        return out;
    }
    mm_vec3 v = f->target_velocity[k];
    float speed = sqrtf(v.x * v.x + v.z * v.z);
    float want = fminf(SWING_CLEAR_TIME * fmaxf(speed - SWING_CLEAR_FROM, 0.0f), SWING_CLEAR_MAX);
    if (left > 0.0f) want *= fminf(left / SWING_CLEAR_LAND, 1.0f);
    if (landing) want = 0.0f;
    mm_spring_update(&f->clearance[k], &f->clearance_velocity[k], want, SWING_CLEAR_HALFLIFE, dt);
    return cleared(y, stand, f->clearance[k]);
}

/* a free foot whose contact is coming catches up with its animated place on the ground plane faster
 * than foot_halflife: its offset there fades with the half-life of the time left over this many (little
 * of it left by its landing), at least SWING_CATCH_UP_MIN_HALFLIFE */
#define SWING_CATCH_UP_HALFLIVES    3.0f
#define SWING_CATCH_UP_MIN_HALFLIFE 0.08f
/* m: an offset on the ground plane of this length is caught up as by foot_halflife alone, one
 * SWING_CATCH_UP_RAMP longer wholly as above, one between in proportion (a threshold would part
 * two runs whose offsets differ in their last bit) */
#define SWING_CATCH_UP_FROM 0.2f
#define SWING_CATCH_UP_RAMP 0.1f

/* Free foot k's offset on the ground plane after this tick's decay (*offset, *velocity: on entry
 * decayed by foot_halflife, from `before`, `before_velocity`), faster where it is long and its contact
 * comes in `left` s: the foot is planted nearer where the animation plants it, not where a
 * transition's offset or a released lock left it (planted there, the hips come down and the legs
 * spread to reach it). */
static void swing_catch_up(mm_vec3 *offset, mm_vec3 *velocity, mm_vec3 before, mm_vec3 before_velocity,
                           float left, float foot_halflife, float dt)
{
    float length = sqrtf(before.x * before.x + before.z * before.z);
    float share = fminf(fmaxf((length - SWING_CATCH_UP_FROM) / SWING_CATCH_UP_RAMP, 0.0f), 1.0f);
    float halflife = fmaxf(left / SWING_CATCH_UP_HALFLIVES, SWING_CATCH_UP_MIN_HALFLIFE);
    if (!(left > 0.0f) || !(share > 0.0f) || !(halflife < foot_halflife)) return;
    mm_spring_step step = mm_spring_step_make(halflife, dt);
    mm_spring_decay_vec3_step(&before, &before_velocity, &step);
    offset->x += share * (before.x - offset->x), offset->z += share * (before.z - offset->z);
    velocity->x += share * (before_velocity.x - velocity->x);
    velocity->z += share * (before_velocity.z - velocity->z);
}

/* A lock that begins while the animated foot still rolls (the toe's label turning on as the foot
 * flattens over its held heel, the heel's as the foot rolls down off its held toe) holds its joint
 * where the foot was shown last tick: the foot keeps the turn it was shown with (its turn from the
 * animated foot `have`, ankle to toe, to last tick's shown one), so that the toe's lock, placed
 * along the turned foot, is where the toe was shown, and a heel planted under a held toe is where
 * the ankle was. The roll then goes on as the turn offset fades instead of carrying the joint along
 * the ground on its first labelled tick. Returns false, the turn unchanged, where the foot was
 * shown turned further than MAX_FOOT_TURN from the animation (or has no length). */
static bool foot_as_shown(mm_feet *f, int k, mm_vec3 have)
{
    mm_vec3 shown = f->shown_foot[k];
    if (!(mm_vec3_length(shown) > MIN_FOOT_LENGTH) || !(mm_vec3_length(have) > MIN_FOOT_LENGTH)) return false;
    mm_vec3 turn = mm_quat_log(mm_quat_between(have, shown));
    if (!(mm_vec3_length(turn) <= MAX_FOOT_TURN)) return false;
    f->turn[k] = turn;
    f->turn_velocity[k] = mm_vec3_make(0.0f, 0.0f, 0.0f);
    return true;
}

/* Foot k turned about the vertical so that its ankle-to-toe vector (have, as animated, turned by the
 * foot's turn) points on the ground plane where last tick's shown one did; nothing where either is
 * shorter than HEADING_MIN_SHARE of the foot on the ground plane (a foot pointing down has no
 * heading to keep), or where the foot would be turned more than MAX_FOOT_TURN. */
static void keep_heading(mm_feet *f, int k, mm_vec3 have)
{
    mm_vec3 now = mm_quat_rotate(mm_quat_exp(f->turn[k]), have), shown = f->shown_foot[k];
    float a = sqrtf(now.x * now.x + now.z * now.z), b = sqrtf(shown.x * shown.x + shown.z * shown.z);
    float least = HEADING_MIN_SHARE * mm_vec3_length(have);
    if (!(a > least) || !(b > least)) return;
    /* the angle about +Y from now to shown on the ground plane */
    float yaw = atan2f(now.z * shown.x - now.x * shown.z, now.x * shown.x + now.z * shown.z);
    mm_quat about = mm_quat_from_axis_angle(mm_vec3_make(0.0f, 1.0f, 0.0f), yaw);
    mm_vec3 turn = mm_quat_log(mm_quat_mul(about, mm_quat_exp(f->turn[k])));
    if (!(mm_vec3_length(turn) <= MAX_FOOT_TURN)) return;
    f->turn[k] = turn;
    f->turn_velocity[k] = mm_vec3_make(0.0f, 0.0f, 0.0f);
}

/* m/s^2: the most a free foot's offset changes the velocity of its ankle's target on the ground
 * plane beyond the animation's own change: as much as a landing slows a foot. The offset's
 * spring pulls hardest on its first tick, and a swing's catch-up harder still: a foot let go far
 * behind its animated place with its contact near (a toe held by its pivot while the body ran on)
 * went from rest to 5 m/s in one tick */
#define SWING_ACCELERATION LANDING_DECELERATION

/* Free foot k's offset on the ground plane (*offset, *velocity: after this tick's decay and
 * catch-up, from before and before_velocity) eased so that the velocity of its ankle's target
 * (shown: last tick's, m/s) changes by at most SWING_ACCELERATION dt, or by the animation's own
 * change when that is larger (moving: the animated ankle's velocity now; shown less before_velocity
 * is what it was last tick): the foot swings as animated, and the offset adds no jolt of its own.
 * The part of the pull held back stays in the offset, caught up over the next ticks. */
static void ease_swing(mm_vec3 *offset, mm_vec3 *velocity, mm_vec3 before, mm_vec3 before_velocity,
                       mm_vec3 moving, mm_vec3 shown, float dt)
{
    float own_x = moving.x - (shown.x - before_velocity.x), own_z = moving.z - (shown.z - before_velocity.z);
    float dvx = moving.x + velocity->x - shown.x, dvz = moving.z + velocity->z - shown.z;
    float change = sqrtf(dvx * dvx + dvz * dvz);
    float most = fmaxf(SWING_ACCELERATION * dt, sqrtf(own_x * own_x + own_z * own_z));
    if (!(change > most)) return;
    float keep = most / change;
    velocity->x = shown.x + dvx * keep - moving.x, velocity->z = shown.z + dvz * keep - moving.z;
    /* the offset moved at the mean of its velocities over the tick (an even acceleration) */
    offset->x = before.x + 0.5f * (before_velocity.x + velocity->x) * dt;
    offset->z = before.z + 0.5f * (before_velocity.z + velocity->z) * dt;
}

/* Foot k's locks on this tick's labels; returns the ankle's target (*orientation: the foot's). The
 * offset decays first; a change of what the foot follows then adds to it the difference in place and
 * in velocity on the ground plane, so that the ankle keeps them (as inertialization does). */
static mm_vec3 lock_foot(mm_feet *f, const mm_character_desc *d, const mm_rig *rig,
                         const mm_feet_contacts *contacts, int k, const mm_feet_ground *ground,
                         const mm_quat *tilt, float dt, const mm_spring_step *foot_step,
                         const mm_spring_step *lift_step, const mm_rig_pose *pose, mm_quat *orientation)
{
    int ankle = rig->ankle[k], toe = rig->toe[k];
    mm_vec3 a = pose->global[ankle].translation, t = toe >= 0 ? pose->global[toe].translation : a;
    mm_quat animated = pose->global[ankle].rotation;
    if (tilt) { /* on terrain: the animated foot moved from the root's ground to the ground under it */
        mm_vec3 at = !f->placed ? a : f->locked[k] ? f->lock[k] : mm_vec3_add(a, f->offset[k]);
        float h = foot_ground(ground->scene, at, mm_vec3_sub(t, a), *tilt);
        if (!f->placed) f->ground_shift[k] = h - ground->height, f->ground_shift_velocity[k] = 0.0f;
        float left = contacts->until_contact[k];
        if (f->placed && !f->locked[k] && left > 0.0f)
            plan_swing(f, k, ground, rig->planted_ankle[k], a, at, mm_vec3_sub(t, a), *tilt, left, dt);
        else
            mm_spring_update(&f->ground_shift[k], &f->ground_shift_velocity[k], h - ground->height,
                             GROUND_SHIFT_HALFLIFE, dt);
        a.y += f->ground_shift[k];
        t.y += f->ground_shift[k];
    }
    if (tilt) { /* and turned to the ground about its ankle */
        t = mm_vec3_add(a, mm_quat_rotate(*tilt, mm_vec3_sub(t, a)));
        animated = mm_quat_normalize(mm_quat_mul(*tilt, animated));
    }
    int heel_on = (contacts->label >> (2 * k)) & 1u, toe_on = (contacts->label >> (2 * k + 1)) & 1u;
    if (toe < 0) heel_on |= toe_on, toe_on = 0; /* no toe: the ankle holds for both */
    /* a lock planted above the ground comes down onto it (settle) */
    if (f->heel_locked[k]) {
        float fall = f->placed ? f->last_ankle[k].y - a.y : 0.0f;
        f->heel_lock[k].y = settle(ground, rig->planted_ankle[k], f->heel_lock[k], a.y, fall, dt);
    }
    if (f->toe_locked[k]) {
        float fall = f->placed ? f->last_toe[k].y - t.y : 0.0f;
        f->toe_lock[k].y = settle(ground, rig->planted_toe[k], f->toe_lock[k], t.y, fall, dt);
    }
    /* a lock the animation has pulled more than unlock_radius away, or that its leg did not reach
     * last tick by more than REACH_SLACK (the pelvis's move and the hips' drop spent), creeps after
     * the animation: its locks move toward the animated foot by a spring step from rest each tick
     * (foot_halflife), in full from UNLOCK_RAMP past the radius or the slack and in proportion
     * before */
    if (f->heel_locked[k] || f->toe_locked[k]) {
        mm_vec3 held = foot_source(f, k, a, t);
        float gap = mm_vec3_distance(held, a);
        float past = fmaxf(gap - d->unlock_radius, f->placed ? f->reach_miss[k] - REACH_SLACK : 0.0f);
        if (past > 0.0f) {
            double y = mm_spring_damping(d->foot_halflife);
            float step = isfinite(y) ? (float)(1.0 - (1.0 + y * dt) * exp(-y * dt)) : 1.0f;
            float share = fminf(past / UNLOCK_RAMP, 1.0f) * step;
            mm_vec3 delta = mm_vec3_scale(mm_vec3_sub(a, held), share);
            f->heel_lock[k] = mm_vec3_add(f->heel_lock[k], delta);
            f->toe_lock[k] = mm_vec3_add(f->toe_lock[k], delta);
            f->heel_lock[k].y = above_ground(ground, rig->planted_ankle[k], f->heel_lock[k]);
            f->toe_lock[k].y = above_ground(ground, rig->planted_toe[k], f->toe_lock[k]);
        }
    }
    mm_vec3 before = foot_source(f, k, a, t), before_velocity = source_velocity(f, k, a, t, dt);
    int was_locked = f->heel_locked[k] || f->toe_locked[k];
    bool heel_was_locked = f->heel_locked[k], toe_was_locked = f->toe_locked[k];
    mm_vec3 below = {f->offset[k].y, 0, 0}, below_velocity = {f->offset_velocity[k].y, 0, 0};
    mm_vec3 along = f->offset[k], along_velocity = f->offset_velocity[k];
    mm_spring_decay_vec3_step(&f->offset[k], &f->offset_velocity[k], foot_step);
    if (!was_locked && f->placed)
        swing_catch_up(&f->offset[k], &f->offset_velocity[k], along, along_velocity,
                       contacts->until_contact[k], d->foot_halflife, dt);
    if (!was_locked && f->placed)
        ease_swing(&f->offset[k], &f->offset_velocity[k], along, along_velocity,
                   source_velocity(f, k, a, t, dt), f->target_velocity[k], dt);
    if (!was_locked && below.x < 0.0f) { /* free and held down: lifts off as animated */
        mm_spring_decay_vec3_step(&below, &below_velocity, lift_step);
        f->offset[k].y = below.x, f->offset_velocity[k].y = below_velocity.x;
    }
    if (!heel_on) f->heel_locked[k] = false;
    if (!toe_on) f->toe_locked[k] = false;
    /* a foot pivoted about its toe (pivot_on_toe) whose toe lets go, or whose heel is planted, goes
     * on from where it was shown: the pivot's move and turn are carried by the offset and the turn,
     * fading (dropped at once, the foot jumped back by up to 10 cm in a tick) */
    mm_vec3 let_go = mm_vec3_make(0.0f, 0.0f, 0.0f);
    bool pivoted = mm_vec3_length(f->pivot_turn[k]) > 0.0f;
    if (pivoted && (!f->toe_locked[k] || heel_on)) {
        let_go = f->pivot_shift[k];
        f->turn[k] = mm_quat_log(mm_quat_mul(mm_quat_exp(f->pivot_turn[k]), mm_quat_exp(f->turn[k])));
        f->turn_velocity[k] = mm_vec3_make(0.0f, 0.0f, 0.0f);
    }
    f->pivot_shift[k] = f->pivot_turn[k] = mm_vec3_make(0.0f, 0.0f, 0.0f);
    /* the heel lifts off while the toe holds: the foot stays as it was shown, its ankle at last
     * tick's target and its toe that far along the foot as shown (the toe's lock moves there), turned
     * to match; the roll goes on from there as the turn fades. Both planted, the toe is shown off its
     * lock by the fading turn offset, the heel's and the toe's locks settle apart, and the leg may
     * fall short of the heel's: turning the foot onto the toe's lock moved the toe a centimetre or
     * two in the tick the heel lifted */
    bool toe_held = toe_was_locked && f->toe_locked[k];
    if (toe_held && heel_was_locked && !f->heel_locked[k] && f->placed) {
        mm_vec3 shown = f->shown_foot[k], have = mm_vec3_sub(t, a);
        f->toe_lock[k] = mm_vec3_add(f->lock[k], shown);
        f->toe_lock[k].y = above_ground(ground, rig->planted_toe[k], f->toe_lock[k]);
        if (mm_vec3_length(shown) > MIN_FOOT_LENGTH && mm_vec3_length(have) > MIN_FOOT_LENGTH) {
            mm_vec3 turn = mm_quat_log(mm_quat_between(have, shown));
            float angle = mm_vec3_length(turn);
            f->turn[k] = angle > MAX_FOOT_TURN ? mm_vec3_scale(turn, MAX_FOOT_TURN / angle) : turn;
            f->turn_velocity[k] = mm_vec3_make(0, 0, 0);
        }
        f->offset[k] = mm_vec3_sub(f->lock[k], foot_source(f, k, a, t)); /* the ankle where it was held */
    } else {
        f->offset[k] = mm_vec3_add(f->offset[k], mm_vec3_sub(before, foot_source(f, k, a, t)));
        f->offset[k] = mm_vec3_add(f->offset[k], let_go);
    }
    /* the velocity on the ground plane only: upward the foot takes what it follows at once (let
     * go, it lifts off as animated instead of dragging along the ground while its offset fades).
     * Not while the toe holds through the tick: the foot rolls about it as animated (keeping the
     * ankle's velocity would hold the ankle still and drag the toe across the ground) */
    mm_vec3 kept = mm_vec3_sub(before_velocity, source_velocity(f, k, a, t, dt));
    kept.y = 0.0f;
    if (!toe_held) f->offset_velocity[k] = mm_vec3_add(f->offset_velocity[k], kept);
    mm_vec3 out = mm_vec3_add(foot_source(f, k, a, t), f->offset[k]);
    mm_vec3 velocity = mm_vec3_add(source_velocity(f, k, a, t, dt), f->offset_velocity[k]);
    mm_vec3 onto_tread = mm_vec3_make(0.0f, 0.0f, 0.0f);
    if (tilt && f->placed && !was_locked) {
        /* a free foot coming down across a step's edge: moved onto one tread (by its offset). A
         * contact coming in `left`: the landing slows the foot evenly to rest by then, so it stops
         * velocity * left / 2 further on */
        float left = heel_on || toe_on ? 0.0f : fmaxf(contacts->until_label[k], 0.0f);
        mm_vec3 ahead = mm_vec3_make(velocity.x * 0.5f * left, 0.0f, velocity.z * 0.5f * left);
        onto_tread = tread_step(ground->scene, out, ahead, mm_vec3_sub(t, a), rig->planted_ankle[k], dt);
        out = mm_vec3_add(out, onto_tread);
        f->offset[k] = mm_vec3_add(f->offset[k], onto_tread);
    }
    bool wait = false, held_heading = false;
    if (d->plant_time > 0.0f && f->placed && !was_locked) {
        /* landing: the foot's step on the ground plane shrinks to nothing as its contact comes (w:
         * the share of plant_time gone before the label turns on), where the foot is planted where
         * it was; the difference is carried by the offset like any other. A transition's offsets,
         * or the root's pull, would otherwise bring the foot down at the speed they give it, and
         * the lock would stop it dead from there. The share grows by at most a tick's worth each
         * tick: a contact seen late (less than plant_time ahead, or on already: a jump onto a frame
         * whose label is on) is planted once the landing has run its plant_time, waited for. A
         * contact no longer coming ends the landing. The step is (1 - w) of the one the landing
         * began with (the foot slows evenly), over plant_time or, for a fast foot, over as long
         * as LANDING_DECELERATION needs to stop it. */
        bool on = heel_on || toe_on, up = false;
        float left = contacts->until_label[k], w = 0.0f, w_before = f->landed[k];
        if (on || left >= 0.0f) {
            if (!(w_before > 0.0f)) { /* a landing begins: its length from the foot's speed now */
                float speed = sqrtf(velocity.x * velocity.x + velocity.z * velocity.z);
                /* on terrain, and from its height above where it stands: a foot held up (a
                 * transition's offsets) comes down by a contact seen coming at LANDING_FALL_SPEED
                 * (one on already is planted once it is down, as soon as it can) */
                float fall = tilt && !on ? landing_fall_time(ground, rig, k, out, mm_vec3_sub(t, a)) : 0.0f;
                f->landing_time[k] = fmaxf(d->plant_time, fminf(fmaxf(speed / LANDING_DECELERATION, fall),
                                                                MM_FEET_LANDING_MAX_TIME));
            }
            float landing = fmaxf(f->landing_time[k], d->plant_time);
            float due = on ? 1.0f : fmaxf(1.0f - left / landing, 0.0f);
            w = fmaxf(w_before, fminf(w_before + dt / landing, due));
            up = on && aloft(ground, rig, k, heel_on, toe_on, out, t.y - a.y);
            wait = on && (w < 1.0f - LANDING_DONE || up);
            if (w > 1.0f) w = 1.0f;
        }
        f->landed[k] = on && !wait ? 0.0f : w;
        if (w > 0.0f) {
            mm_vec3 from = f->lock[k];
            from = mm_vec3_add(from, onto_tread);
            /* the step so far is (1 - w_before) of the landing's first */
            float keep = w_before < 1.0f - LANDING_DONE ? (1.0f - w) / (1.0f - w_before) : 0.0f;
            out.x = from.x + keep * (out.x - from.x);
            out.z = from.z + keep * (out.z - from.z);
            velocity.x *= keep, velocity.z *= keep;
            if (tilt) {
                /* brought down no faster than LANDING_FALL_SPEED beyond what the animation does */
                float lowered = landing_height(ground, rig, k, out, mm_vec3_sub(t, a), w);
                out.y = fmaxf(lowered, fminf(out.y, from.y - LANDING_FALL_SPEED * dt));
            }
            if (up) out.y = fminf(out.y, from.y); /* aloft: held on the ground plane, not rising */
            held_heading = up && toe_on && w_before >= 1.0f - LANDING_DONE;
            f->offset[k] = mm_vec3_sub(out, foot_source(f, k, a, t));
            f->offset_velocity[k] = mm_vec3_sub(velocity, source_velocity(f, k, a, t, dt));
        }
    }
    /* planted where the foot is, at rest, never lower than the data plants it; a heel or a toe
     * planted while the other holds takes its place on the foot as it is held. Not above the
     * animated foot: the height the foot is held above it (an offset holding it up) is carried by
     * the offset, fading, not dropped in a tick; a lock the animated foot later sinks below comes
     * down after it (settle, above) */
    bool held_heel = f->heel_locked[k], held_toe = f->toe_locked[k];
    int planted = 0;
    /* a lock that begins while the foot rolls holds its joint where it was shown last tick: a toe
     * landing alone is planted where the toe was, its ankle put round it as the animated foot is
     * turned (a foot pitching down onto its toe); a toe planted with or after its heel, and a heel
     * under a held toe, with the foot as it was shown (foot_as_shown) */
    bool toe_alone = toe_on && !held_toe && !heel_on && !held_heel && !wait && f->placed &&
                     mm_vec3_length(f->shown_foot[k]) > MIN_FOOT_LENGTH;
    bool as_shown = ((toe_on && !held_toe) || (heel_on && !held_heel && held_toe)) && !wait && f->placed &&
                    !pivoted && !toe_alone && foot_as_shown(f, k, mm_vec3_sub(t, a));
    if (heel_on && !held_heel && !wait) {
        f->heel_lock[k] = held_toe ? foot_source(f, k, a, t) : out;
        f->heel_lock[k].y = fminf(f->heel_lock[k].y, a.y);
        f->heel_lock[k].y = above_ground(ground, rig->planted_ankle[k], f->heel_lock[k]);
        f->heel_locked[k] = true;
        planted = 1;
    }
    if (toe_on && !held_toe && !wait) {
        f->toe_lock[k] = mm_vec3_add(held_heel ? f->heel_lock[k] : out,
                                     mm_quat_rotate(mm_quat_exp(f->turn[k]), mm_vec3_sub(t, a)));
        if (toe_alone) /* where the toe was shown */
            f->toe_lock[k].x = f->lock[k].x + f->shown_foot[k].x,
            f->toe_lock[k].z = f->lock[k].z + f->shown_foot[k].z;
        f->toe_lock[k].y = fminf(f->toe_lock[k].y, t.y);
        f->toe_lock[k].y = above_ground(ground, rig->planted_toe[k], f->toe_lock[k]);
        f->toe_locked[k] = true;
        planted = 1;
    }
    if (planted) { /* held exactly from here (a lock raised to the ground: once the offset has faded) */
        mm_vec3 source = foot_source(f, k, a, t);
        f->offset[k] = mm_vec3_sub(out, source);
        if (as_shown && held_toe) /* the ankle where it was held, as the heel comes down */
            f->offset[k].x = f->lock[k].x - source.x, f->offset[k].z = f->lock[k].z - source.z;
        if (toe_alone) f->offset[k].x = f->offset[k].z = 0.0f; /* the toe on its lock at once */
        /* on terrain, a foot planted on its toe whose ankle would come below where the ankle
         * stands (the foot turned less than the slope it lands on) is held there by the ankle's
         * floor: the offset carries only the height above that, so that the toe, aimed at its lock
         * lifted by the offset's height, comes onto it */
        if (tilt) {
            /* and only what is above that floor: an ankle shown under it (the foot landing lower
             * than the data plants it) is raised to it all the same, and a negative height would
             * aim the toe under its lock */
            float floor = stand_height(ground, source.x, source.z, rig->planted_ankle[k]);
            f->offset[k].y = fmaxf(out.y, floor) - fmaxf(source.y, floor);
        }
        f->offset_velocity[k] = mm_vec3_make(0, 0, 0);
    }
    if (f->heel_locked[k] && f->toe_locked[k]) {
        /* both planted: the foot turns so that its toe stays on the toe lock (the animated foot may
         * pitch or yaw under a transition's offsets while both labels are on) */
        mm_vec3 turn =
            mm_quat_log(mm_quat_between(mm_vec3_sub(t, a), mm_vec3_sub(f->toe_lock[k], f->heel_lock[k])));
        float angle = mm_vec3_length(turn);
        if (angle > MAX_FOOT_TURN) {
            /* the animation turns the foot further than a planted foot should follow: the toe lock
             * goes round the heel's as far as it must */
            turn = mm_vec3_scale(turn, MAX_FOOT_TURN / angle);
            f->toe_lock[k] =
                mm_vec3_add(f->heel_lock[k], mm_quat_rotate(mm_quat_exp(turn), mm_vec3_sub(t, a)));
        }
        /* the turn the foot had carried over as an offset when both locks begin, fading */
        if (heel_was_locked && toe_was_locked) {
            mm_spring_decay_vec3_step(&f->turn_offset[k], &f->turn_offset_velocity[k], foot_step);
        } else {
            f->turn_offset[k] = mm_vec3_sub(f->turn[k], turn);
            f->turn_offset_velocity[k] = f->turn_velocity[k];
        }
        turn = mm_vec3_add(turn, f->turn_offset[k]);
        f->turn_velocity[k] = mm_vec3_scale(mm_vec3_sub(turn, f->turn[k]), 1.0f / dt);
        f->turn[k] = turn;
    } else {
        mm_spring_decay_vec3_step(&f->turn[k], &f->turn_velocity[k], foot_step);
    }
    /* landed but still aloft, its toe labelled: the foot keeps the heading it was shown with about
     * the held ankle (its pitch as animated, so that it comes down as the data has it) instead of
     * swinging the toe round it */
    if (held_heading) keep_heading(f, k, mm_vec3_sub(t, a));
    f->last_ankle[k] = a, f->last_toe[k] = t;
    *orientation = mm_quat_mul(mm_quat_exp(f->turn[k]), animated);
    f->locked[k] = f->heel_locked[k] || f->toe_locked[k];
    mm_vec3 target = mm_vec3_add(foot_source(f, k, a, t), f->offset[k]);
    target.y += step_lift(f, k, ground->hold && !heel_on && !toe_on && contacts->until_label[k] < 0.0f, dt);
    if (tilt && f->toe_locked[k]) {
        /* on terrain the locks stand at the data's planted heights over the ground, not where the
         * foot was: a held toe stays over its lock while the ankle's offset fades (the foot turns
         * about the toe, at most MAX_FOOT_TURN from the animation), not carried along the ground by
         * it; it comes down with the offset's height */
        mm_vec3 toe_at = mm_vec3_make(f->toe_lock[k].x, f->toe_lock[k].y + f->offset[k].y, f->toe_lock[k].z);
        /* Toe down under a raised heel: planted on heel and toe with its ankle still above where it
         * stands (a foot landing toe first, its ankle's height carried by the offset), the toe is
         * aimed at its lock itself, not lifted with the ankle: the foot stands on its toe and rolls
         * down onto its heel as the offset fades, instead of being held flat in the air above both
         * locks (docs/scene.md, "Toe down under a raised heel") */
        if (f->heel_locked[k]) toe_at.y = f->toe_lock[k].y;
        /* Aimed from where the ankle will be: no lower than where it stands (the floor the caller
         * raises the target to). An offset holding the ankle below that floor (a foot planted toe
         * first on ground that falls away under the toe) would otherwise pitch the foot for an
         * ankle that is then raised, lifting the toe off its lock by as much */
        mm_vec3 from = target;
        from.y = fmaxf(from.y, stand_height(ground, target.x, target.z, rig->planted_ankle[k]));
        mm_vec3 aim = mm_quat_log(mm_quat_between(mm_vec3_sub(t, a), mm_vec3_sub(toe_at, from)));
        float angle = mm_vec3_length(aim);
        if (angle > MAX_FOOT_TURN) aim = mm_vec3_scale(aim, MAX_FOOT_TURN / angle);
        *orientation = mm_quat_mul(mm_quat_exp(aim), animated);
    }
    return target;
}

/* The leg's length: hip to knee to ankle. */
static float leg_length(const mm_rig *rig, int k, const mm_rig_pose *pose)
{
    mm_vec3 h = pose->global[rig->hip[k]].translation, knee = pose->global[rig->knee[k]].translation;
    return mm_vec3_distance(h, knee) + mm_vec3_distance(knee, pose->global[rig->ankle[k]].translation);
}

/* The angle at the hip between the thigh (l1) and the hip-to-ankle line of a leg whose ankle is len
 * from its hip (the shin l2): the law of cosines. */
static float hip_bend(float l1, float l2, float len)
{
    float c = (l1 * l1 - l2 * l2 + len * len) / (2.0f * l1 * len);
    return acosf(fminf(1.0f, fmaxf(-1.0f, c)));
}

/* The hip-to-ankle distance of a leg bent by `bend` at the hip (hip_bend's inverse). */
static float bend_length(float l1, float l2, float bend)
{
    float across = l1 * sinf(bend);
    return l1 * cosf(bend) + sqrtf(fmaxf(0.0f, l2 * l2 - across * across));
}

/* The hip-to-ankle distance the leg IK solves a target at len to (its softened reach, leg_ik.c). */
static float softened(float len, float length)
{
    float s = SOFT_REACH * length, start = length - s;
    return len > start ? length - s * expf(-(len - start) / s) : len;
}

/* The target distance the leg IK solves to reach (softened's inverse), at most `most`. */
static float unsoftened(float reach, float length, float most)
{
    float s = SOFT_REACH * length, start = length - s;
    if (!(reach > start)) return reach;
    float left = length - reach;
    return left > s * expf(-(most - start) / s) ? start - s * logf(left / s) : most;
}

/* rad/s^2: the most a leg's bend at the hip may change its rate by in a second near full extension,
 * beyond the animation's own change (ease_bend; 300 x the thigh's 0.4 m x dt^2 is 3.3 cm of the
 * knee's move a tick squared) */
#define BEND_ACCELERATION 300.0f
/* rad: the bend over which that limit widens, as 1 + (bend / this)^2: a leg clearly bent moves its
 * knee in proportion to its target, and a limit there lagged ordinary swings */
#define BEND_NEAR_STRAIGHT 0.3f

/* Foot k's ankle target (*target, from hip h) eased so that the leg's bend at the hip changes its rate
 * by at most BEND_ACCELERATION dt a tick near full extension (more as the leg is bent, 1 + (bend /
 * BEND_NEAR_STRAIGHT)^2 times), or by the animated leg's own change when that is larger: near full
 * extension the knee moves as the square root of what the leg lacks, and a target that goes out of
 * reach and comes back at a few m/s (a foot let go behind the body) bends a straight leg by 0.25 rad
 * in a tick. The bend follows what the target asks for at the rate that changes, and closes the gap
 * left no faster than it could still stop; the target is moved along its line from the hip to where
 * the IK solves to that bend. Locked feet too: a free foot locked while its bend lags would snap. */
static void ease_bend(mm_feet *f, const mm_rig *rig, int k, mm_vec3 h, const mm_rig_pose *pose, float dt,
                      mm_vec3 *target)
{
    mm_vec3 knee = pose->global[rig->knee[k]].translation, ankle = pose->global[rig->ankle[k]].translation;
    float l1 = mm_vec3_distance(h, knee), l2 = mm_vec3_distance(knee, ankle), length = l1 + l2;
    float away = mm_vec3_distance(*target, h);
    if (!(l1 > MIN_FOOT_LENGTH && l2 > MIN_FOOT_LENGTH && away > 1e-4f)) return;
    float low = fabsf(l1 - l2);
    float want = hip_bend(l1, l2, fminf(length, fmaxf(low, softened(away, length))));
    float animated = hip_bend(l1, l2, fminf(length, fmaxf(low, mm_vec3_distance(ankle, h))));
    bool follow = !f->placed;
    float want_velocity = f->placed ? (want - f->bend_want[k]) / dt : 0.0f;
    float behind = f->bend_want[k] - f->bend[k]; /* the gap left last tick */
    float animated_velocity = f->placed ? (animated - f->animated_bend[k]) / dt : 0.0f;
    float own = fabsf(animated_velocity - f->animated_bend_velocity[k]);
    f->bend_want[k] = want;
    f->animated_bend[k] = animated, f->animated_bend_velocity[k] = animated_velocity;
    float bend = want;
    if (!follow) {
        float bent = fminf(want, f->bend[k]) / BEND_NEAR_STRAIGHT;
        float most = fmaxf(BEND_ACCELERATION * (1.0f + bent * bent) * dt, own);
        float close = fminf(fabsf(behind) / dt, sqrtf(2.0f * most / dt * fabsf(behind)));
        float wanted = want_velocity + copysignf(close, behind);
        float change = fminf(most, fmaxf(-most, wanted - f->bend_velocity[k]));
        bend = fmaxf(0.0f, f->bend[k] + (f->bend_velocity[k] + change) * dt);
    }
    f->bend_velocity[k] = f->placed ? (bend - f->bend[k]) / dt : 0.0f;
    f->bend[k] = bend;
    if (bend == want) return;
    float reach = bend_length(l1, l2, bend);
    float far = unsoftened(fminf(length, fmaxf(low, reach)), length,
                           fmaxf(away, length * (1.0f + ONTO_SOFT_WIDTHS * SOFT_REACH)));
    *target = mm_vec3_add(h, mm_vec3_scale(mm_vec3_sub(*target, h), far / away));
}

/* the furthest the pelvis is moved on the ground plane toward planted feet out of reach, in leg
 * lengths (hip to knee to ankle): as far as a body leans back over a planted foot while the root
 * goes on ahead (a transition's root motion, the pull toward the simulation) */
#define MAX_PELVIS_SHIFT_LEGS 0.35f
/* s: half-life of the spring the pelvis is moved through (and back) */
#define PELVIS_SHIFT_HALFLIFE 0.05f
/* the most the pelvis's move asks for per unit of a leg's excess over its reach, for a foot
 * nearly under its hip (see shift_pelvis) */
#define SHIFT_GAIN 3.0f

/* The pelvis moves on the ground plane, in the pose only (the simulated root stays), as far as the
 * locked feet need to come within their legs' softened reach from the hips lowered as they are:
 * each locked foot out of reach asks for its excess toward it, the sum at most MAX_PELVIS_SHIFT_LEGS,
 * followed through a spring both ways (back to none while the feet do not keep to the ground). A locked foot
 * the hips were carried away from (a transition's root motion, the simulation's pull) stays on its lock
 * instead of being dragged by its straight leg, or crept after the animation. */
static void shift_pelvis(mm_feet *f, const mm_rig *rig, const mm_vec3 *target, bool hold, float dt,
                         mm_rig_pose *pose)
{
    int pelvis = rig->pelvis;
    mm_vec3 need = mm_vec3_make(0.0f, 0.0f, 0.0f);
    float most = 0.0f;
    for (int k = 0; k < 2; ++k)
        if (rig->ankle[k] >= 0) most = fmaxf(most, MAX_PELVIS_SHIFT_LEGS * leg_length(rig, k, pose));
    for (int k = 0; k < 2; ++k) {
        if (!hold || rig->ankle[k] < 0 || !f->locked[k]) continue;
        mm_vec3 h = pose->global[rig->hip[k]].translation;
        float reach = (1.0f - SOFT_REACH) * leg_length(rig, k, pose);
        mm_vec3 r = mm_vec3_sub(target[k], mm_vec3_make(h.x, h.y - f->hip_drop, h.z));
        float length = mm_vec3_length(r), across = sqrtf(r.x * r.x + r.z * r.z);
        if (!(length > reach)) continue;
        /* the move on the ground plane that shortens the leg by its excess, to first order; a foot
         * nearly under the hip asks for less (at most SHIFT_GAIN times the excess per unit of the
         * leg's lean), where the exact move would grow without bound */
        float lean = fmaxf(across, length / SHIFT_GAIN);
        float move = (length - reach) * length / (lean * lean);
        need.x += r.x * move, need.z += r.z * move;
    }
    float size = mm_vec3_length(need);
    if (size > most) need = mm_vec3_scale(need, most / size);
    if (!f->placed) f->pelvis_shift = need, f->pelvis_shift_velocity = mm_vec3_make(0.0f, 0.0f, 0.0f);
    mm_spring_update_vec3(&f->pelvis_shift, &f->pelvis_shift_velocity, need, PELVIS_SHIFT_HALFLIFE, dt);
    if (mm_vec3_length(f->pelvis_shift) > 1e-7f) {
        mm_vec3 along =
            mm_quat_inv_rotate(pose->global[rig->joints[pelvis].parent].rotation, f->pelvis_shift);
        pose->local_positions[pelvis] = mm_vec3_add(pose->local_positions[pelvis], along);
        mm_rig_forward_pelvis(rig, pose);
    }
}

/* m: how far above the metric's crouch line (mm_rig.head_floor) the hips' drop keeps the head, for
 * what the stages after it move the head by */
#define HEAD_FLOOR_MARGIN 0.01f

/* The most the hips may come down this tick: most, but on flat ground no lower than the data's
 * upright locomotion carries them (mm_rig.hip_floor, above the ground): a lock further than the legs
 * reach from there creeps after the animation (reach_miss) instead of the body sinking into a lunge
 * (docs/metrics.md, "Crouched time: the hips no lower than the data's upright locomotion"), and no
 * lower than keeps the head HEAD_FLOOR_MARGIN above the line under which it is crouched
 * (mm_rig.head_floor: a stooped clip's hips above the floor, its head low; docs/metrics.md,
 * "Crouched time: the head kept above the crouch line"). As most while a foot whose label is on or
 * coming is not locked yet (its landing: held up, it would wait aloft), on terrain (a leg reaching
 * a lower tread) and during a move (its clip's own postures: a climb's legs reach for the wall's
 * top). */
static float hip_drop_limit(const mm_feet *f, const mm_rig *rig, const mm_feet_contacts *contacts,
                            const mm_feet_ground *ground, bool terrain, float most, const mm_rig_pose *pose)
{
    if (terrain || !ground->hold || !(rig->hip_floor > 0.0f || rig->head_floor > 0.0f)) return most;
    for (int k = 0; k < 2; ++k)
        if (rig->ankle[k] >= 0 && !f->locked[k] && landing_now(contacts, k)) return most;
    float pelvis = pose->global[rig->pelvis].translation.y - ground->height;
    float above = rig->hip_floor > 0.0f ? pelvis - rig->hip_floor : most;
    if (rig->head >= 0 && rig->head_floor > 0.0f)
        above =
            fminf(above, pelvis + mm_rig_head_above_pelvis(rig, pose) - rig->head_floor - HEAD_FLOOR_MARGIN);
    return fminf(most, fmaxf(above, 0.0f));
}

/* The hips come down as far as the legs need to reach their targets (never below what they need,
 * rising back through a spring), at most max_hip_drop, and to reach a swinging foot's landing
 * height (landing: the targets lowered to it; the targets themselves elsewhere); stepping (a foot
 * on terrain below the root's ground), ahead of a growing need. */
static void lower_hips(mm_feet *f, float max_hip_drop, bool stepping, const mm_rig *rig,
                       const mm_vec3 *target, const mm_vec3 *landing, float dt, mm_rig_pose *pose)
{
    int pelvis = rig->pelvis;
    float need = 0.0f;
    for (int k = 0; k < 2; ++k) {
        mm_vec3 h = pose->global[rig->hip[k]].translation;
        float reach = (1.0f - SOFT_REACH) * leg_length(rig, k, pose);
        float dx = target[k].x - h.x, dz = target[k].z - h.z, across = dx * dx + dz * dz;
        float low = fminf(target[k].y, landing[k].y);
        float down = across < reach * reach ? h.y - low - sqrtf(reach * reach - across) : max_hip_drop;
        need = fmaxf(need, down);
    }
    need = fminf(need, max_hip_drop);
    if (!stepping) f->hip_need = need;
    if (stepping) {
        /* on terrain the need grows as the body climbs away from a trailing foot or a swinging foot
         * is planned down to a lower tread: the spring aims ahead of it by the lag a critically
         * damped spring has behind a steady rise (2 v / y), so that the leg reaches as it goes */
        float rate = f->placed ? fminf(fmaxf((need - f->hip_need) / dt, 0.0f), HIP_LEAD_MAX_RATE) : 0.0f;
        f->hip_need = need;
        need = fminf(need + (float)(2.0 / mm_spring_damping(HIP_DROP_HALFLIFE)) * rate, max_hip_drop);
    }
    /* through a spring both ways (a drop followed at once would move the body as fast as the need
     * changes, which grows without bound as a target nears the leg's reach across), never past
     * [0, max_hip_drop]; on terrain max_hip_drop falls as a foot lower than the root's ground lets
     * go: a drop above it comes back up through the spring (held there at once, the whole body
     * jumped up by the difference in a tick), never further down */
    float before = f->hip_drop, most = fmaxf(max_hip_drop, before);
    mm_spring_update(&f->hip_drop, &f->hip_drop_velocity, need, HIP_DROP_HALFLIFE, dt);
    if (f->hip_drop > most || f->hip_drop < 0.0f) {
        f->hip_drop = fminf(fmaxf(f->hip_drop, 0.0f), most);
        f->hip_drop_velocity = 0.0f;
    }
    if (f->hip_drop > 0.0f) {
        mm_vec3 down = mm_quat_inv_rotate(pose->global[rig->joints[pelvis].parent].rotation,
                                          mm_vec3_make(0.0f, -f->hip_drop, 0.0f));
        pose->local_positions[pelvis] = mm_vec3_add(pose->local_positions[pelvis], down);
        mm_rig_forward_pelvis(rig, pose);
    }
}

/* A toe below floor_y (an animated foot pitched into the ground, or a transition's offset) is lifted
 * by pitching the foot about its ankle, as far as the foot's length allows. The globals of the ankle
 * and the toe must be current; sets the ankle's local rotation (the caller runs the forward
 * kinematics again). Returns whether it turned the foot. */
static int lift_toe(const mm_rig *rig, int k, float floor_y, mm_rig_pose *pose)
{
    int ankle = rig->ankle[k], toe = rig->toe[k];
    if (ankle < 0 || toe < 0) return 0;
    mm_xform *g = pose->global;
    mm_vec3 a = g[ankle].translation, v = mm_vec3_sub(g[toe].translation, a);
    if (!(a.y + v.y < floor_y)) return 0;
    float length = mm_vec3_length(v), across = sqrtf(v.x * v.x + v.z * v.z), rise = floor_y - a.y;
    if (!(across > 1e-4f) || !(fabsf(rise) < length)) return 0;
    float keep = sqrtf(length * length - rise * rise) / across;
    mm_vec3 lifted = mm_vec3_make(v.x * keep, rise, v.z * keep);
    mm_quat ankle_world = mm_quat_normalize(mm_quat_mul(mm_quat_between(v, lifted), g[ankle].rotation));
    int knee = rig->joints[ankle].parent;
    pose->local_rotations[ankle] =
        mm_quat_normalize(mm_quat_mul(mm_quat_conj(g[knee].rotation), ankle_world));
    return 1;
}

/* On terrain: the rotation that turns foot k to the ground's normal under it (where it was held or
 * aimed last tick; the animated ankle before the first), the normal followed over TILT_HALFLIFE,
 * at most MAX_FOOT_TILT, fading out as a free foot rises TILT_FADE_HEIGHT above where it stands. */
static mm_quat foot_tilt(mm_feet *f, const mm_rig *rig, int k, const mm_feet_ground *ground, float dt,
                         const mm_rig_pose *pose)
{
    int ankle = rig->ankle[k], toe = rig->toe[k];
    mm_vec3 a = pose->global[ankle].translation;
    mm_vec3 along = toe >= 0 ? mm_vec3_sub(pose->global[toe].translation, a) : mm_vec3_make(0, 0, 0);
    mm_vec3 where = f->placed ? f->lock[k] : a;
    mm_vec3 heel_normal, toe_normal;
    mm_scene_ground_height(ground->scene, where.x, where.z, &heel_normal);
    mm_scene_ground_height(ground->scene, where.x + along.x, where.z + along.z, &toe_normal);
    mm_vec3 n = mm_vec3_normalize(mm_vec3_add(heel_normal, toe_normal));
    mm_vec3 before = f->tilt_normal[k];
    if (f->placed && mm_vec3_length(before) > 0.5f)
        n = mm_vec3_normalize(mm_vec3_lerp(before, n, 1.0f - exp2f(-dt / TILT_HALFLIFE)));
    f->tilt_normal[k] = n;
    float share = 1.0f;
    if (!f->locked[k]) {
        float above = where.y - stand_height(ground, where.x, where.z, rig->planted_ankle[k]);
        share = fminf(fmaxf(1.0f - above / TILT_FADE_HEIGHT, 0.0f), 1.0f);
    }
    mm_vec3 axis = mm_vec3_cross(mm_vec3_make(0.0f, 1.0f, 0.0f), n);
    float sine = mm_vec3_length(axis), angle = fminf(atan2f(sine, n.y), MAX_FOOT_TILT) * share;
    if (!(sine > 1e-6f)) return mm_quat_identity();
    return mm_quat_from_axis_angle(mm_vec3_scale(axis, 1.0f / sine), angle);
}

/* The geometry of the toe pivot below: foot k's ankle target (*target, the foot turned by
 * *orientation) pivoted about its toe toward hip by the least angle that brings it within reach,
 * at most limit (rad). Returns the rotation vector of the pivot (zero when none is needed or
 * possible) and moves *target and *orientation by it. */
static mm_vec3 toe_pivot(const mm_rig *rig, int k, mm_vec3 hip, float reach, float limit,
                         const mm_rig_pose *pose, mm_vec3 *target, mm_quat *orientation)
{
    mm_vec3 none = mm_vec3_make(0.0f, 0.0f, 0.0f);
    if (!(mm_vec3_distance(*target, hip) > reach)) return none;
    mm_vec3 toe_to_ankle =
        mm_vec3_scale(mm_quat_rotate(*orientation, pose->local_positions[rig->toe[k]]), -1.0f);
    mm_vec3 toe = mm_vec3_sub(*target, toe_to_ankle), to_hip = mm_vec3_sub(hip, toe);
    float foot = mm_vec3_length(toe_to_ankle), away = mm_vec3_length(to_hip);
    if (!(foot > MIN_FOOT_LENGTH) || !(away > MIN_FOOT_LENGTH)) return none;
    mm_vec3 axis = mm_vec3_cross(toe_to_ankle, to_hip);
    float sine = mm_vec3_length(axis);
    if (!(sine > MIN_FOOT_LENGTH * MIN_FOOT_LENGTH)) return none;
    /* the angle between the toe-to-ankle and toe-to-hip directions now, and the largest at which
     * the ankle is within reach of the hip (the law of cosines) */
    float now = atan2f(sine, mm_vec3_dot(toe_to_ankle, to_hip));
    float within = (away * away + foot * foot - reach * reach) / (2.0f * foot * away);
    float most = within >= 1.0f ? 0.0f : within <= -1.0f ? (float)MM_PI : acosf(within);
    float angle = fminf(now - most, limit);
    if (!(angle > 0.0f)) return none;
    mm_vec3 turn = mm_vec3_scale(axis, angle / sine);
    mm_quat pivot = mm_quat_exp(turn);
    *target = mm_vec3_add(toe, mm_quat_rotate(pivot, toe_to_ankle));
    *orientation = mm_quat_normalize(mm_quat_mul(pivot, *orientation));
    return turn;
}

/* Toe pivot: foot k, planted on its toe alone, has its ankle's target (*target, the foot turned by
 * *orientation) further than reach from its hip: the foot is pivoted about its toe, heel up, toward
 * the hip by the least angle that brings the ankle within reach (at most MAX_TOE_PIVOT, growing by
 * at most TOE_PIVOT_RATE), the toe staying on its lock. A body carried on past a foot planted behind
 * it (a root faster than its clip, a transition's offsets still swinging the foot when its label
 * turns on) would otherwise leave the leg straight and short of the whole foot: the foot lifted off
 * the ground by its straight leg and dragged along while its label holds it. Records the pivot
 * (f->pivot_shift, f->pivot_turn) for the tick the toe lets go. */
static void pivot_on_toe(mm_feet *f, const mm_rig *rig, int k, mm_vec3 hip, float reach, float last, float dt,
                         const mm_rig_pose *pose, mm_vec3 *target, mm_quat *orientation)
{
    mm_vec3 from = *target;
    mm_vec3 turn = toe_pivot(rig, k, hip, reach, fminf(MAX_TOE_PIVOT, last + TOE_PIVOT_RATE * dt), pose,
                             target, orientation);
    if (!(mm_vec3_length(turn) > 0.0f)) return;
    f->pivot_shift[k] = mm_vec3_sub(*target, from);
    f->pivot_turn[k] = turn;
}

void mm_feet_update(mm_feet *f, const mm_character_desc *d, const mm_rig *rig,
                    const mm_feet_contacts *contacts, const mm_feet_ground *ground, float dt,
                    mm_rig_pose *pose)
{
    mm_vec3 target[2] = {{0, 0, 0}, {0, 0, 0}}, landing[2] = {{0, 0, 0}, {0, 0, 0}};
    mm_quat orientation[2] = {{0, 0, 0, 1}, {0, 0, 0, 1}};
    float last_pivot[2] = {mm_vec3_length(f->pivot_turn[0]), mm_vec3_length(f->pivot_turn[1])};
    bool terrain = ground->scene && ground->hold;
    /* the springs of both feet's offsets and turns share a half-life and dt */
    mm_spring_step foot_step = mm_spring_step_make(d->foot_halflife, dt);
    mm_spring_step lift_step = mm_spring_step_make(fminf(LIFT_HALFLIFE, d->foot_halflife), dt);
    for (int k = 0; k < 2; ++k) {
        if (rig->ankle[k] < 0) continue;
        mm_quat tilt = terrain ? foot_tilt(f, rig, k, ground, dt, pose) : mm_quat_identity();
        target[k] = lock_foot(f, d, rig, contacts, k, ground, terrain ? &tilt : NULL, dt, &foot_step,
                              &lift_step, pose, &orientation[k]);
        /* never lower than the data puts a planted ankle above the ground (the root's height in
         * locomotion: it stands on the ground, which a scene may put anywhere) */
        float floor = stand_height(ground, target[k].x, target[k].z, rig->planted_ankle[k]);
        if (ground->hold && target[k].y < floor) target[k].y = floor;
        if (ground->hold && rig->toe[k] >= 0) { /* and high enough for the toe as the foot is turned */
            mm_vec3 v = mm_quat_rotate(orientation[k], pose->local_positions[rig->toe[k]]);
            float toe_y = stand_height(ground, target[k].x + v.x, target[k].z + v.z, rig->planted_toe[k]);
            float unlifted = toe_floor(target[k].y, toe_y - v.y), most = INFINITY;
            if (terrain && !f->locked[k] && f->placed) {
                /* a free foot: above the ground ahead of its toe too, along a slope (a step's edge
                 * is cleared) */
                float vx = (target[k].x - f->lock[k].x) / dt, vz = (target[k].z - f->lock[k].z) / dt;
                float speed = sqrtf(vx * vx + vz * vz);
                for (int i = 1; speed > CLEAR_MIN_SPEED && i <= CLEAR_SAMPLES; ++i) {
                    float ahead = CLEAR_AHEAD * (float)i / (float)CLEAR_SAMPLES;
                    float x = target[k].x + v.x + vx / speed * ahead,
                          z = target[k].z + v.z + vz / speed * ahead;
                    toe_y =
                        fmaxf(toe_y, stand_height(ground, x, z, rig->planted_toe[k]) - CLEAR_SLOPE * ahead);
                }
                /* raising the foot no faster than CLEAR_RISE_SPEED from where it was last tick: a
                 * foot let go just short of a riser would otherwise jump onto the clearance at once */
                most = fmaxf(unlifted, f->lock[k].y + CLEAR_RISE_SPEED * dt);
            }
            target[k].y = fminf(toe_floor(target[k].y, toe_y - v.y), most);
            if (!terrain)
                target[k].y = swing_clear(f, k, target[k].y, fmaxf(floor, toe_y - v.y),
                                          contacts->until_contact[k], landing_now(contacts, k), dt);
        }
        /* a swinging foot on terrain is reached for at the height it will land at too (the hips
         * come down during the swing toward a lower tread, not once the foot is planted there) */
        landing[k] = target[k];
        float left = contacts->until_contact[k];
        if (terrain && !f->locked[k] && f->placed && left > 0.0f) {
            float x = target[k].x + 0.5f * left * (target[k].x - f->lock[k].x) / dt,
                  z = target[k].z + 0.5f * left * (target[k].z - f->lock[k].z) / dt;
            landing[k].y = fminf(target[k].y, stand_height(ground, x, z, rig->planted_ankle[k]));
        }
        f->lock[k] = target[k];
    }
    if (rig->pelvis >= 0) shift_pelvis(f, rig, target, ground->hold, dt, pose);
    if (rig->pelvis >= 0 && d->max_hip_drop > 0.0f) {
        /* on terrain the hips may come down further by as much as a foot's target or landing is
         * below where it would stand on the root's ground (a step down, a trailing foot on the
         * tread below), or the ground the foot stands on is below the root's (its ground shift: a
         * trailing foot rolled up onto its toe has its ankle raised above where it would stand, the
         * ground under it is still lower), at most TERRAIN_HIP_DROP (TERRAIN_TRAILING_HIP_DROP for
         * a planted foot behind its hip): on flat ground, raised or not, as without terrain */
        float step_down = 0.0f;
        mm_vec3 forward = terrain ? mm_rig_pelvis_forward(rig, pose) : mm_vec3_make(0.0f, 0.0f, 0.0f);
        for (int k = 0; terrain && k < 2; ++k) {
            if (rig->ankle[k] < 0) continue;
            float below = fmaxf(ground->height + rig->planted_ankle[k] - fminf(target[k].y, landing[k].y),
                                -f->ground_shift[k]);
            mm_vec3 h = pose->global[rig->hip[k]].translation;
            bool trailing =
                f->locked[k] && (target[k].x - h.x) * forward.x + (target[k].z - h.z) * forward.z < 0.0f;
            step_down =
                fmaxf(step_down, fminf(below, trailing ? TERRAIN_TRAILING_HIP_DROP : TERRAIN_HIP_DROP));
        }
        /* a foot planted on its toe alone is reached for as far as it can be pivoted (pivot_on_toe,
         * MAX_TOE_PIVOT, which the pivot grows to within a few ticks): the heel comes up before the
         * hips come down (docs/metrics.md, "Crouched time: the heel up before the hips down") */
        mm_vec3 reach_target[2] = {target[0], target[1]}, reach_landing[2] = {landing[0], landing[1]};
        for (int k = 0; k < 2; ++k) {
            if (rig->ankle[k] < 0 || rig->toe[k] < 0 || !ground->hold || !f->toe_locked[k] ||
                f->heel_locked[k])
                continue;
            mm_quat pivoted = orientation[k];
            toe_pivot(rig, k, pose->global[rig->hip[k]].translation,
                      (1.0f - SOFT_REACH) * leg_length(rig, k, pose), MAX_TOE_PIVOT, pose, &reach_target[k],
                      &pivoted);
            reach_landing[k] = reach_target[k];
        }
        lower_hips(f, hip_drop_limit(f, rig, contacts, ground, terrain, d->max_hip_drop + step_down, pose),
                   terrain && step_down > 0.0f, rig, reach_target, reach_landing, dt, pose);
    }
    for (int k = 0; k < 2; ++k) {
        if (rig->ankle[k] < 0) continue;
        /* a target far out of the leg's reach (a lock the hips moved away from, or the offset a
         * released lock leaves) is brought in to a few widths of the softened reach, and the offset
         * with it: otherwise the offset fades out of reach (the leg stays straight) and then sweeps
         * the ankle through its reach at the spring's speed. Not onto the reach itself: the leg
         * there is short of straight by the softening, and the ankle and knee would jump to it */
        mm_vec3 h = pose->global[rig->hip[k]].translation;
        float beyond = leg_length(rig, k, pose) * (1.0f + ONTO_SOFT_WIDTHS * SOFT_REACH);
        mm_vec3 r = mm_vec3_sub(target[k], h);
        float len = mm_vec3_length(r);
        if (!f->locked[k] && len > beyond && len > 1e-6f) {
            mm_vec3 u = mm_vec3_scale(r, 1.0f / len), onto = mm_vec3_add(h, mm_vec3_scale(u, beyond));
            f->offset[k] = mm_vec3_add(f->offset[k], mm_vec3_sub(onto, target[k]));
            float out = mm_vec3_dot(f->offset_velocity[k], u);
            if (out > 0.0f) f->offset_velocity[k] = mm_vec3_sub(f->offset_velocity[k], mm_vec3_scale(u, out));
            target[k] = onto;
            f->lock[k] = onto;
        }
        if (ground->hold && f->toe_locked[k] && !f->heel_locked[k] && rig->toe[k] >= 0)
            pivot_on_toe(f, rig, k, h, (1.0f - SOFT_REACH) * leg_length(rig, k, pose), last_pivot[k], dt,
                         pose, &target[k], &orientation[k]);
        ease_bend(f, rig, k, h, pose, dt, &target[k]);
        solve_leg(rig, k, target[k], orientation[k], pose);
        f->target_velocity[k] = f->placed
                                    ? mm_vec3_scale(mm_vec3_sub(target[k], f->last_target[k]), 1.0f / dt)
                                    : mm_vec3_make(0.0f, 0.0f, 0.0f);
        f->last_target[k] = target[k];
        int ankle = rig->ankle[k], knee = rig->knee[k]; /* the ankle where the solved leg puts it */
        mm_xform reached = mm_xform_mul(
            pose->global[knee], mm_xform_make(pose->local_rotations[ankle], pose->local_positions[ankle]));
        f->reach_miss[k] = mm_vec3_distance(reached.translation, target[k]);
    }
    f->placed = true;
    mm_rig_forward_legs(rig, pose); /* below the ankles: the legs alone changed */
    if (ground->hold) {
        int lifted = 0;
        for (int k = 0; k < 2; ++k) {
            int toe = rig->toe[k];
            if (rig->ankle[k] < 0 || toe < 0) continue;
            mm_vec3 p = pose->global[toe].translation;
            float floor = stand_height(ground, p.x, p.z, rig->planted_toe[k]);
            lifted |= lift_toe(rig, k, floor - TOE_SINK - TOE_LIFT_MARGIN, pose);
        }
        if (lifted) mm_rig_forward_legs(rig, pose);
    }
    for (int k = 0; k < 2; ++k)
        if (rig->ankle[k] >= 0 && rig->toe[k] >= 0)
            f->shown_foot[k] =
                mm_vec3_sub(pose->global[rig->toe[k]].translation, pose->global[rig->ankle[k]].translation);
}
