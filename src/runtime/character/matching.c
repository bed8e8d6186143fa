/* Stage 3: when to search, the query, the search and the winner. */
#include "matching.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <mm/spring.h>

#include "math_private.h"

/* m/s: the simulated character counts as stopped */
#define IDLE_STOPPED 0.01f
/* m/s: slower desired motion has no direction (turns and the search's direction) */
#define DIRECTION_MIN_SPEED 0.3f
/* m/s: under this simulated speed the velocity-change weights come in with the speed (a start is
 * the pose's to choose: with the trajectory alone a standing pose went into the run-up of a jump) */
#define VELOCITY_CHANGE_FROM_SPEED 0.5f
/* leg lengths (hip to knee to ankle, at rest) the character may travel over a planted foot before
 * the contact favour stops keeping that foot planted: the favour chains frames in the same
 * contacts across jumps, and a stance carried on that long while moving leaves the planted foot
 * out of the leg's reach (docs/runtime.md, "Why the defaults") */
#define STANCE_REACH_LEGS 1.0f
/* s: a jump back within the playing clip shorter than this (or than the search interval) is not
 * taken: a stretch replayed every other search is seen as a stutter (a standing clip that would
 * go on into a start jumped back 12 frames every 0.2 s) */
#define MIN_REPLAY 0.5f
/* the contact bits of foot k (heel and toe) */
#define FOOT_CONTACT_BITS(k) (3u << (2 * (k)))
/* the four mm_contact_bits: the pattern the search's contact favour compares */
#define MATCHING_CONTACT_BITS                                                                                \
    (MM_CONTACT_LEFT_HEEL | MM_CONTACT_LEFT_TOE | MM_CONTACT_RIGHT_HEEL | MM_CONTACT_RIGHT_TOE)

/* Jumps that plant a foot the animation playing has up in a swing (docs/metrics.md, "Jumps that
 * plant a swinging foot"): s over which the frames after a jump's destination are compared with
 * the frames the animation playing would go on to */
#define PLANT_AHEAD 0.25f
/* s: a destination's planted foot is refused only where the animation playing has that foot off
 * the ground from this long before (a foot it lifts a little sooner: the end of a stance, slow) */
#define SWING_SLACK 0.1f
/* s: ... to this long after (a foot it lands a little later; a running foot landed sooner than
 * that is carried into the ground at its swing's speed) */
#define LANDING_SLACK 0.034f
/* frames of labels looked at past a frame: the longest window above at 240 fps */
#define PLANT_MAX_STEPS 96

void mm_matching_init(mm_matching *m, const mm_database *db, float *query, float leg_length)
{
    memset(m, 0, sizeof *m);
    m->query = query;
    for (int g = 0; g < MM_GAIT_COUNT; ++g) {
        char name[16];
        snprintf(name, sizeof name, "%s", mm_gait_name((mm_gait)g));
        name[0] = (char)(name[0] - 'a' + 'A'); /* "Walk" */
        m->gait_tags[g] = mm_search_tag_mask(db, name) | mm_search_tag_mask(db, mm_gait_name((mm_gait)g));
    }
    for (int k = 0; k < db->clip_count && !m->has_idle; ++k) m->has_idle = db->clips[k].type == MM_CLIP_IDLE;
    m->idle = true;
    m->since_search = INFINITY; /* search on the first tick */
    m->last_result.frame = m->last_choice.frame = -1;
    m->stance_reach = leg_length > 0.0f ? STANCE_REACH_LEGS * leg_length : 0.0f;
    m->since_jump = INFINITY;
}

void mm_matching_track_stances(mm_matching *m, unsigned label, mm_vec3 root)
{
    for (int k = 0; k < 2; ++k) {
        bool on = (label & FOOT_CONTACT_BITS(k)) != 0;
        if (on && !m->in_stance[k]) m->stance_from[k] = root;
        m->in_stance[k] = on;
    }
}

int mm_matching_contact_pattern(const mm_matching *m, unsigned label, mm_xform root)
{
    unsigned pattern = label & MATCHING_CONTACT_BITS;
    for (int k = 0; k < 2 && m->stance_reach > 0.0f; ++k) {
        float dx = root.translation.x - m->stance_from[k].x, dz = root.translation.z - m->stance_from[k].z;
        if (m->in_stance[k] && (pattern & FOOT_CONTACT_BITS(k)) &&
            dx * dx + dz * dz > m->stance_reach * m->stance_reach)
            pattern &= ~FOOT_CONTACT_BITS(k);
    }
    return (int)pattern;
}

/* The query: the pose of the frame playing (from the database) and the simulated trajectory in
 * the character's frame. */
static void build_query(const mm_matching *m, const mm_database *db, int frame, const mm_trajectory *t,
                        const mm_input *in, mm_xform root)
{
    mm_pose_data pd;
    mm_database_pose(db, frame, &pd);
    mm_vec3 positions[MM_MAX_TRAJ_SAMPLES];
    mm_quat facings[MM_MAX_TRAJ_SAMPLES];
    mm_trajectory_sample(t, in, pd.traj_times, pd.traj_count, positions, facings);
    /* the game's own future, where it gave one: the future samples in order (the past is the
     * simulation's recorded one) */
    for (int i = 0, k = 0; i < pd.traj_count && m->future_count > 0; ++i)
        if (pd.traj_times[i] > 0.0f && k < m->future_count) {
            positions[i] = m->future_positions[k];
            facings[i] = m->future_facings[k++];
        }
    mm_xform inverse = mm_xform_inverse(root);
    for (int i = 0; i < pd.traj_count; ++i) {
        pd.traj_positions[i] = mm_xform_apply_point(inverse, positions[i]);
        pd.traj_directions[i] =
            mm_quat_inv_rotate(root.rotation, mm_quat_rotate(facings[i], mm_vec3_make(0, 0, 1)));
    }
    mm_search_query_from_pose(db, &pd, m->query);
}

/* Stops and turns: when the stick is let go at a run, or turned, the playing clip carries on while
 * the simulation changes its velocity; the stops and turns are other clips', far in pose, and lose
 * to carrying on. While the simulated velocity must change (its distance to the desired one) the
 * trajectory weighs more: the ratio moves toward velocity_change_ratio in proportion to the change,
 * fully at velocity_change_speed. */
static void velocity_change_weights(const mm_character_desc *d, const mm_trajectory *t,
                                    const mm_intent *intent, mm_search_params *p)
{
    mm_vec3 desired = intent->desired_velocity, v = t->velocity;
    float dx = desired.x - v.x, dz = desired.z - v.z, change = sqrtf(dx * dx + dz * dz);
    float speed = mm_intent_ground_speed(t);
    if (speed < VELOCITY_CHANGE_FROM_SPEED) change *= speed / VELOCITY_CHANGE_FROM_SPEED;
    if (change > 0.0f && d->velocity_change_speed > 0.0f &&
        d->velocity_change_ratio > p->pose_trajectory_ratio && d->velocity_change_ratio <= 1.0f) {
        float s = change < d->velocity_change_speed ? change / d->velocity_change_speed : 1.0f;
        p->pose_trajectory_ratio += (d->velocity_change_ratio - p->pose_trajectory_ratio) * s;
    }
}

/* The share of a jump the transition has still to hide since_jump s after it: with
 * inertialization its offsets' spring decaying from rest, (1 + y t) e^(-y t) (mm_spring_damping),
 * 1/2 after one transition_halflife; with the crossfade mixer the weight the sources before it
 * still have (1 - t / crossfade_time); 0 with no jump yet, no halflife or no crossfade time. */
static float jump_offset_left(float since_jump, const mm_character_desc *d)
{
    if (!isfinite(since_jump)) return 0.0f;
    if (d->transition_mode == MM_TRANSITION_CROSSFADE)
        return d->crossfade_time > 0.0f ? fmaxf(1.0f - since_jump / d->crossfade_time, 0.0f) : 0.0f;
    if (!(d->transition_halflife > 0.0f)) return 0.0f;
    double yt = mm_spring_damping(d->transition_halflife) * fmax(since_jump, 0.0);
    return (float)((1.0 + yt) * exp(-yt));
}

float mm_matching_ratio(const mm_matching *m, const mm_character_desc *d, const mm_trajectory *t,
                        const mm_intent *intent)
{
    mm_search_params p = d->params;
    velocity_change_weights(d, t, intent, &p);
    /* the pose weighed back up after a jump: the query's pose is the new frame's, but the pose
     * shown is still that frame plus the offsets left to hide; the velocity change's trajectory
     * weight chose the next jump on top of them, and jumps in a row while the input turns stacked
     * their offsets into lunges (docs/transitions.md, "Transitions in a row") */
    float base = d->params.pose_trajectory_ratio, raised = p.pose_trajectory_ratio;
    return raised - (raised - base) * jump_offset_left(m->since_jump, d);
}

/* The desired direction (rad) and speed (m/s). */
static float desired_direction(const mm_intent *intent, float *speed)
{
    mm_vec3 desired = intent->desired_velocity;
    *speed = mm_vec3_length(desired);
    return atan2f(desired.x, desired.z);
}

bool mm_matching_due(mm_matching *m, const mm_character_desc *d, const mm_intent *intent,
                     float simulated_speed, float root_speed, bool ended, bool move_playing, float dt)
{
    float speed, direction = desired_direction(intent, &speed);
    /* idle is asked for once the simulated character has (nearly) stopped too, not when the stick
     * is let go: until then the locomotion search finds the stops, where an idle pose would have
     * its planted feet dragged along by the root still moving. Nor while the animation still runs
     * (its root faster than idle_root_speed): the jump from a stride into a standing pose, both
     * feet labelled planted, slides them; once the simulation has stopped idle is asked for
     * whatever plays */
    float moving = simulated_speed;
    int idle_changed = 0;
    if (m->idle && speed > d->idle_speed + d->idle_hysteresis)
        m->idle = false, idle_changed = 1;
    else if (!m->idle && speed < d->idle_speed && moving < d->idle_speed + d->idle_hysteresis &&
             (!(d->idle_root_speed > 0.0f) || root_speed < d->idle_root_speed || moving < IDLE_STOPPED))
        m->idle = true, idle_changed = 1;
    int turned =
        speed > DIRECTION_MIN_SPEED && fabsf(wrap_angle(direction - m->last_direction)) > d->turn_threshold;
    m->since_search += dt;
    if (m->plant_waiting) m->plant_waited += dt;
    m->since_jump += dt;
    return !move_playing && (m->since_search >= d->search_interval || turned || idle_changed || ended);
}

/* The contact labels of the n frames from frame on as playback goes (a clip's last frame held). */
static void labels_ahead(const mm_database *db, int frame, int n, unsigned *labels)
{
    for (int i = 0; i < n; ++i) {
        labels[i] = db->contacts[frame];
        if (db->frame_next[frame] >= 0) frame = db->frame_next[frame];
    }
}

/* The label windows of plants_swinging_foot at the database's rate (frames) and the labels of the
 * frames the animation playing goes on to (ahead + slack of them). */
typedef struct swing_view {
    int playing, ahead, slack, early;
    unsigned from[PLANT_MAX_STEPS];
} swing_view;

static void swing_view_of(const mm_database *db, int playing, swing_view *v)
{
    v->playing = playing;
    v->slack = (int)ceilf(SWING_SLACK / db->interval);
    v->early = (int)ceilf(LANDING_SLACK / db->interval);
    v->ahead = (int)ceilf(PLANT_AHEAD / db->interval);
    if (v->ahead + v->slack > PLANT_MAX_STEPS) v->ahead = PLANT_MAX_STEPS - v->slack;
    if (v->early > v->slack) v->early = v->slack;
    labels_ahead(db, playing, v->ahead + v->slack, v->from);
}

/* The feet (bit k: foot k) a jump from the frame playing to frame to plants while the animation
 * playing has them in a swing: over PLANT_AHEAD, a frame after `to` whose foot is labelled while
 * the frames after the frame playing have that foot unlabelled from SWING_SLACK before to
 * LANDING_SLACK after it. The transition carries the foot on with its swing's speed under a label
 * that says it stands. */
static unsigned swinging_feet(const mm_database *db, const swing_view *v, int to)
{
    unsigned dest[PLANT_MAX_STEPS], feet = 0;
    labels_ahead(db, to, v->ahead, dest);
    for (int t = 0; t < v->ahead; ++t)
        for (int k = 0; k < 2; ++k) {
            if (!(dest[t] & FOOT_CONTACT_BITS(k)) || (feet & (1u << k))) continue;
            bool swinging = true;
            for (int u = t > v->slack ? t - v->slack : 0; u <= t + v->early && swinging; ++u)
                swinging = !(v->from[u] & FOOT_CONTACT_BITS(k));
            if (swinging) feet |= 1u << k;
        }
    return feet;
}

static bool plants_swinging_foot(const mm_database *db, const swing_view *v, int to)
{
    return swinging_feet(db, v, to) != 0;
}

/* Whether the animation playing lands every one of `feet` (labels it after a frame without its
 * label: a foot still down that lifts lands after its swing) within `frames` frames from the frame
 * playing (a clip's last frame held). */
static bool lands_within(const mm_database *db, const swing_view *v, unsigned feet, int frames)
{
    unsigned up = 0, landed = 0;
    for (int u = 0, f = v->playing; u <= frames && (landed & feet) != feet; ++u) {
        for (int k = 0; k < 2; ++k) {
            if (!(db->contacts[f] & FOOT_CONTACT_BITS(k)))
                up |= 1u << k;
            else if (up & (1u << k))
                landed |= 1u << k;
        }
        if (db->frame_next[f] >= 0) f = db->frame_next[f];
    }
    return (landed & feet) == feet;
}

/* mm_matching_plant_choice from the frame playing's view; `landing`: the wait only for feet the
 * animation playing lands within STOP_LANDING_WITHIN (a stop's). */
static int plant_choice(const mm_database *db, const swing_view *v, const mm_search_result *results, int n,
                        float waited, float max_wait, bool landing, float *priced)
{
    float price = PLANT_PRICE * fabsf(results[0].cost);
    int chosen = 0;
    unsigned plants = 0;
    float best = INFINITY;
    /* by cost: none further on can undercut the best once its own cost does not */
    for (int i = 0; i < n && !(results[i].cost >= best); ++i) {
        if (results[i].frame < 0) continue;
        unsigned lands = swinging_feet(db, v, results[i].frame);
        float total = lands ? results[i].cost + price : results[i].cost;
        if (total < best) chosen = i, best = total, plants = lands;
    }
    if (!(best < INFINITY)) best = results[0].cost; /* NaN costs: the winner */
    *priced = best;
    if (!plants || !(waited < max_wait)) return chosen;
    if (landing && !lands_within(db, v, plants, (int)ceilf(STOP_LANDING_WITHIN / db->interval)))
        return chosen;
    return -1;
}

bool mm_matching_plants_swinging_foot(const mm_database *db, int playing, int to)
{
    swing_view v;
    swing_view_of(db, playing, &v);
    return plants_swinging_foot(db, &v, to);
}

int mm_matching_plant_choice(const mm_database *db, int playing, const mm_search_result *results, int n,
                             float waited, float *priced)
{
    swing_view v;
    swing_view_of(db, playing, &v);
    return plant_choice(db, &v, results, n, waited, PLANT_MAX_WAIT, false, priced);
}

int mm_matching_stop_plant_choice(const mm_database *db, int playing, const mm_search_result *results, int n,
                                  float waited, float *priced)
{
    swing_view v;
    swing_view_of(db, playing, &v);
    return plant_choice(db, &v, results, n, waited, STOP_PLANT_MAX_WAIT, true, priced);
}

float mm_matching_plant_max_wait(const mm_database *db, bool moving, int to)
{
    if (moving) return PLANT_MAX_WAIT;
    return to >= 0 && db->clips[db->frame_clip[to]].type == MM_CLIP_IDLE ? STOP_PLANT_MAX_WAIT : 0.0f;
}

void mm_matching_search(mm_matching *m, const mm_character_desc *d, const mm_database *db,
                        const mm_searcher *searcher, const mm_trajectory *t, const mm_input *in,
                        const mm_intent *intent, mm_xform root, const mm_playback *pb, mm_jump *jump)
{
    jump->frame = -1;
    float speed, direction = desired_direction(intent, &speed);
    bool keep_contacts = mm_intent_ground_speed(t) >= KEEP_CONTACTS_FROM_SPEED;
    build_query(m, db, pb->frame, t, in, root);
    mm_search_params p = d->params;
    p.current_frame = pb->frame;
    /* frames whose feet are in other contacts than the frame playing's cost contact_mismatch_favour
     * times more (the desc's; 1: off) */
    p.contact_pattern = keep_contacts ? mm_matching_contact_pattern(m, db->contacts[pb->frame], root) : -1;
    p.type = !m->has_idle ? MM_SEARCH_ANY : m->idle ? MM_SEARCH_IDLE : MM_SEARCH_LOCOMOTION;
    /* the gait influences matching through tags named after the gaits: frames tagged with another
     * gait than the one asked for are left out */
    for (int g = 0; g < MM_GAIT_COUNT; ++g)
        if (g != (int)intent->gait) p.excluded_tags |= m->gait_tags[g];
    p.pose_trajectory_ratio = mm_matching_ratio(m, d, t, intent);
    /* a jump back within the playing clip by less than `behind` is not taken (below); at the clip's
     * last frame, where playback cannot go on, such a winner left the playhead standing there every
     * tick while the root moved on with the simulation, dragging the planted feet: those frames are
     * left out of the search instead, so that it finds a frame it jumps to */
    int behind = d->skip_frames + (int)ceilf(fmaxf(d->search_interval, MIN_REPLAY) / db->interval);
    if (db->frame_next[pb->frame] < 0 && p.exclude_window < behind) p.exclude_window = behind;
    /* the winner, or the best candidates a debugger asked for (the winner is the same whatever k) */
    mm_search_result winner_only, *results = m->candidate_capacity > 0 ? m->candidates : &winner_only;
    int k = m->candidate_capacity > 0 ? m->candidate_capacity : 1;
    double start = d->clock ? d->clock() : 0.0;
    /* waiting for a swinging foot, the winner mostly plants it still: the PLANT_CANDIDATES are
     * searched at once, their first the winner of a search for one (the search's tie rule) */
    mm_search_result near[PLANT_CANDIDATES];
    int near_found = -1, found;
    if (m->plant_waiting && m->candidate_capacity == 0) {
        /* the candidates of the tick before, whose costs under this query bound the search's */
        near_found = mm_searcher_search_hinted(searcher, m->query, &p, d->method, near, PLANT_CANDIDATES,
                                               m->plant_hints, m->plant_hint_count, NULL);
        winner_only = near[0];
        found = near_found > 0;
    } else {
        found = mm_searcher_search(searcher, m->query, &p, d->method, results, k);
    }
    /* moving, a winner that plants a foot the animation has in a swing is priced against the best
     * PLANT_CANDIDATES (searched again for them: a search for one is much the quicker, and most
     * winners plant no swinging foot); when the cheapest still does, playback goes on (the next
     * search on the next tick) until that foot lands or PLANT_MAX_WAIT. Stopping or standing, the
     * same for a winner in an idle clip, up to STOP_PLANT_MAX_WAIT (mm_matching_plant_max_wait); at
     * a clip's end, or any other winner, the search's winner */
    const mm_search_result *priced_from = results;
    swing_view view;
    int n = 0;
    float max_wait = found ? mm_matching_plant_max_wait(db, keep_contacts, results[0].frame) : 0.0f;
    if (found && results[0].frame >= 0 && max_wait > 0.0f && db->frame_next[pb->frame] >= 0) {
        swing_view_of(db, pb->frame, &view);
        if (plants_swinging_foot(db, &view, results[0].frame)) {
            n = k >= PLANT_CANDIDATES ? (found < PLANT_CANDIDATES ? found : PLANT_CANDIDATES)
                : near_found >= 0
                    ? near_found
                    : mm_searcher_search(searcher, m->query, &p, d->method, near, PLANT_CANDIDATES);
            if (k < PLANT_CANDIDATES) priced_from = near;
        }
    }
    m->plant_hint_count = n;
    for (int i = 0; i < n; ++i) m->plant_hints[i] = priced_from[i].frame;
    if (d->clock) m->last_search_us = (float)(1e6 * (d->clock() - start));
    ++m->searches;
    /* a phase set: the search after this one comes search_phase of the interval sooner */
    m->since_search = m->phase_pending ? m->search_phase * d->search_interval : 0.0f;
    m->phase_pending = false;
    m->last_params = p;
    if (speed > DIRECTION_MIN_SPEED) m->last_direction = direction;
    m->last_result = m->last_choice = results[0];
    m->candidate_count = found;
    if (!found || results[0].frame < 0) return;
    int chosen = 0;
    if (n > 0) {
        float priced;
        chosen = plant_choice(db, &view, priced_from, n, m->plant_waiting ? m->plant_waited : 0.0f, max_wait,
                              !keep_contacts, &priced);
        m->last_choice = chosen >= 0 ? priced_from[chosen] : (mm_search_result){.frame = -1, .base = 0.0f};
        m->last_choice.cost = priced;
    }
    if (chosen < 0) { /* wait: search again on the next tick */
        m->since_search = d->search_interval;
        if (!m->plant_waiting) m->plant_waiting = true, m->plant_waited = 0.0f;
        return;
    }
    m->plant_waiting = false;
    mm_search_result best = priced_from[chosen];
    /* where playback goes anyway (a few frames ahead in the same clip): no jump; nor back in the
     * same clip by less than MIN_REPLAY or what played since the last search: that would replay
     * the same stretch over and over (an idle frozen in a loop of a few frames) */
    int ahead = best.frame - pb->frame;
    if (db->frame_clip[best.frame] == db->frame_clip[pb->frame] && ahead >= -behind &&
        ahead <= d->skip_frames)
        return;
    jump->frame = best.frame;
    jump->fraction = pb->fraction;
    m->since_jump = 0.0f;
    /* crossfade: cancellable, but not at the end of the clip (the playhead would stand still) */
    jump->uncancellable = db->frame_next[pb->frame] < 0;
}
