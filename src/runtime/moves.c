/* The move layer: jump, vault, climb and drop-down on top of a character (mm/moves.h). No
 * allocation: everything lives in mm_moves. */
#include <mm/moves.h>

#include <math.h>
#include <string.h>

#include <mm/search.h>
#include <mm/trajectory.h>

#include "math_private.h"

/* ---- tuning constants, in the order the file uses them (docs/moves.md tells how they were set) ---- */

/* The clips, measured once at init. */
/* frames: a guard on root-motion integration against a cycle in frame_next: far more than a move spans */
#define ADVANCE_MAX_STEPS 100000
/* frames (last - first): a shorter tagged span is a stray tag, too short to be a move */
#define MIN_SPAN_FRAMES 4
/* frames either side of a tagged span searched for its events: a tag may stop a frame or two short */
#define EVENT_SEARCH_FRAMES 2
/* frames: a shorter run without foot contact is a shuffle of the feet, not a flight */
#define MIN_FLIGHT_FRAMES 3
/* s after the hand plant up to which the joints below the top place the near face (the knees then) */
#define FACE_AFTER_PLANT 0.2f
/* m: a joint this far below the planted hand is below the top (the hand's own joint is not) */
#define FACE_BELOW_HAND 0.05f
/* m: a joint further past the hand than this is over the wall (a leg swung over), not at its face */
#define FACE_BEYOND_HAND 0.25f
/* m added to the hand's distance from the face: the joints are centres, the face is at their skin */
#define HAND_INSET_MARGIN 0.02f
/* m: the least a hand plants in from the face: a palm needs that much of the top */
#define HAND_INSET_MIN 0.05f
/* m: the most: further in is an arm reaching over the top, not a plant on its edge */
#define HAND_INSET_MAX 0.35f
/* m: the inset when no joint places the face: a palm's width in from the edge */
#define HAND_INSET_DEFAULT 0.08f
/* m: a clip whose ground rises more than this ends on top of what it crosses (above a step) */
#define ONTO_MIN_RISE 0.4f

/* The side (mm_moves_pick_side). */
/* s: the feet's velocity difference counts as the distance it makes over this time */
#define SIDE_VELOCITY_WEIGHT 0.2f
/* m: a foot planted in one start and not in the other outweighs where the feet are */
#define SIDE_SWITCH_COST 1.0f
/* m: the twin plays only when it fits better than this (on a tie, the option itself) */
#define SIDE_TIE 1e-4f

/* the largest any number of mm_moves_desc may be (m, s, m/s^2): more is a unit mistake */
#define PARAM_MAX 100.0f

/* The height schedule. */
/* s after Landing over which the clip's ground is its lowest: a foot landing toes first settles */
#define LANDING_GROUND_TIME 0.1f
/* frames from the start giving a clip's ground when it has no take-off (0.1 s at 60 Hz: a step) */
#define START_GROUND_FRAMES 6

/* Planning a jump or a drop. */
/* m: the least a jump or drop lands ahead of the root (a clip that jumps on the spot leaves the ledge) */
#define MIN_JUMP_DISTANCE 0.2f
/* m between ground probes along the facing: finer than a foot */
#define PROBE_STEP 0.05f
/* m past ledge_probe where a ledge is still looked for: a drop may start a step before the edge */
#define LEDGE_SEARCH_BEYOND 0.3f
/* m: a drop lands at least this far past the ledge: the feet clear its edge */
#define DROP_PAST_LEDGE 0.35f
/* m past the longest jump's landing where gaps and walls are looked for: a stride of slack */
#define LOOK_BEYOND_JUMP 0.6f
/* m past a gap's far edge where a jump lands: about the collider's radius, the feet off the edge */
#define GAP_LANDING_MARGIN 0.4f
/* m: a top at least this deep is stood on (ONTO_MIN_IN + ONTO_MIN_FROM_EDGE); a thinner one crossed */
#define STAND_MIN_DEPTH 0.65f
/* m: a move onto a top lands at least this far in from its near face: the whole foot on it */
#define ONTO_MIN_IN 0.35f
/* m: and at least this far from its far edge: the heels off the drop behind */
#define ONTO_MIN_FROM_EDGE 0.3f
/* m on ahead of the planned landing searched for room for the body: a long stride */
#define ROOM_SEARCH_DISTANCE 1.5f
/* m between the spots tried */
#define ROOM_SEARCH_STEP 0.1f
/* a jump's height error counts this many times its distance's: the schedule lifts the whole body
 * for it, the legs do not */
#define JUMP_RISE_WEIGHT 2.0f
/* m: fits within this are a tie, the lower index plays (an original before its mirror) */
#define PICK_TIE 0.01f
/* s before take-off when the landing's target match starts: the push off steers the jump */
#define LAND_MATCH_LEAD 0.1f
/* m the feet clear a wall's top by at the fall moment of a jump over it */
#define OVER_CLEARANCE 0.1f
/* m above the top where a vault's landing ground is still found: the ray's rounding */
#define TOP_PROBE_STEP 0.05f

/* The lift over a wall. */
/* s: the planned envelope rises to and settles from each frame's need over this: no step at once */
#define LIFT_WIDTH 0.35f
/* m: a joint this far out of a box's footprint still needs the lift (the pose played strays a few cm) */
#define LIFT_REACH 0.15f
/* m a lifted joint ends above the top: out of it, not on it */
#define LIFT_MARGIN 0.01f
/* m under a top where a joint is lifted out; deeper it is against a face, which lifting does not cure */
#define CLEAR_WINDOW 0.25f
/* m: after the hand plant, when the body goes over the top */
#define OVER_WINDOW 0.6f
/* m: after the landing, only a toe dipping into the surface stood on */
#define LANDED_WINDOW 0.1f
/* ticks of the pose ahead tested for the reactive lift */
#define LOOK_TICKS 3
/* ticks for a jump (no hand plant): a jump rises fast */
#define JUMP_LOOK_TICKS 6
/* s: time constant of the reactive lift settling back */
#define LIFT_SETTLE 0.15f
/* m/s: the fastest the reactive lift rises: at once it pops the body */
#define LIFT_RATE 6.0f

/* The hand-back. */
/* s of clip time after which a move hands back whatever plays: a guard against one that never ends */
#define MAX_MOVE_TIME 30.0f
/* m: the feet's height counts in the landing error only with the root within this of the target */
#define LAND_ERROR_RADIUS 1.0f

/* Locomotion and the triggers. */
/* m: the root within this of the ground is on it (no step up, no fall) */
#define GROUND_TOLERANCE 1e-4f
/* m/s: a slower desired velocity gives no direction: the facing does */
#define DIRECTION_MIN_SPEED 0.3f
/* s: the least time after a move before a drop at a ledge (locomotion has searched again) */
#define LEDGE_COOLDOWN 0.15f
/* cos: walking within about 45 degrees of the facing heads for the ledge it faces */
#define LEDGE_HEADING_COS 0.7f
/* m: walls are looked for at least this far ahead, whatever the clips' reach */
#define MIN_WALL_REACH 0.7f
/* m past the farthest trigger distance where the obstacle is measured: a probe step */
#define WALL_LOOK_MARGIN 0.05f
/* cos: moving within about 45 degrees of a wall's normal is toward it */
#define WALL_HEADING_COS 0.7f
/* m: a jump onto a wall starts no farther from it: a standing jump's reach */
#define JUMP_ONTO_REACH 0.7f
/* cos: and facing it within about 25 degrees */
#define JUMP_FACING_COS 0.9f
/* m: a vault or climb triggers at least this far from the face: room for the transition into it */
#define MIN_TRIGGER_DISTANCE 0.3f

/* The height schedule's segments (mm_moves.key_shape): linear, smoothstep, ease-in (falling as
 * under gravity), ease-out (rising). */
enum { KEY_LINEAR, KEY_SMOOTH, KEY_FALLING, KEY_RISING };

static const char *const kind_names[MM_MOVE_KIND_COUNT] = {"jump", "vault_low", "vault_high", "climb",
                                                           "drop"};
static const char *const kind_tags[MM_MOVE_KIND_COUNT] = {"Jump", "VaultLow", "VaultHigh", "Climb", "Drop"};

const char *mm_move_kind_name(mm_move_kind kind)
{
    return (int)kind >= 0 && kind < MM_MOVE_KIND_COUNT ? kind_names[kind] : NULL;
}

void mm_moves_defaults(mm_moves_desc *d)
{
    memset(d, 0, sizeof *d);
    d->max_jump_height = 1.2f;
    d->jump_start_offset = 0.45f;
    d->rise_start = 0.0f;
    d->fall_start = 0.55f;
    d->step_height = 0.3f;
    d->ledge_probe = 0.45f;
    d->trigger_slack = 0.1f;
    d->low_max_height = 1.5f;
    d->high_max_height = 2.6f;
    d->short_max_depth = 1.0f;
    d->landing_margin = 0.5f;
    d->recover_time = 0.35f;
    d->transition_halflife = 0.12f;
    d->gravity = 9.81f;
    d->radius = 0.4f;
    d->cooldown = 0.25f;
    d->max_jump_distance = 3.0f;
    d->moving_speed = 0.5f;
    d->collider_height = 1.8f;
    d->knee_height = 0.4f;
    d->chest_height = 1.2f;
    d->max_lift = 0.6f;
    d->left_hand = d->right_hand = d->left_foot = d->right_foot = NULL; /* the database's roles */
}

/* The joint a desc names, else the role's joint. */
static int desc_joint(const mm_database *db, const char *name, mm_role role)
{
    return name ? mm_database_find_joint(db, name) : mm_database_role_joint(db, role);
}

/* A joint's transform relative to the root (joint 0) at a database frame. */
static mm_xform bone_in_root(const mm_database *db, int frame, int joint)
{
    mm_xform x = mm_xform_identity();
    for (int j = joint; j > 0; j = db->joints[j].parent) {
        mm_quat r;
        mm_vec3 p;
        mm_database_local_joint(db, frame, j, &r, &p);
        x = mm_xform_mul(mm_xform_make(r, p), x);
    }
    return x;
}

/* Where the clip's ground is at a frame, relative to the root: the lower ankle less the standing
 * ankle height (a clip recorded on a box is 1 m up there). */
static float clip_ground(const mm_moves *m, int frame)
{
    float y = INFINITY;
    for (int k = 0; k < 2; ++k)
        if (m->foot[k] >= 0) y = fminf(y, bone_in_root(m->db, frame, m->foot[k]).translation.y);
    return isfinite(y) ? y - m->ankle_height : 0.0f;
}

/* Where the clip's feet stand at a frame, relative to the root: the lowest of heel (the ankle)
 * and toe, each less its standing height (a foot pitched stands on its toes), as the hand-back
 * measures the feet. */
static float clip_feet(const mm_moves *m, int frame)
{
    float y = clip_ground(m, frame);
    for (int k = 0; k < 2; ++k)
        if (m->toe[k] >= 0) y = fminf(y, bone_in_root(m->db, frame, m->toe[k]).translation.y - m->toe_height);
    return y;
}

/* The clip's ground over frames [f0, f1] (one clip): the lowest, so that a foot landing toes
 * first or a heel raised does not count as ground. */
static float clip_ground_span(const mm_moves *m, int f0, int f1)
{
    float g = INFINITY;
    for (int f = f0; f <= f1 && f < m->db->frame_count; ++f) g = fminf(g, clip_ground(m, f));
    return isfinite(g) ? g : clip_ground(m, f0);
}

/* The root after playing `seconds` from the playhead (frame, fraction), starting at root, as the
 * character integrates root motion (the velocity of the frame an interval leads to). */
static mm_xform advance_root(const mm_database *db, int frame, float fraction, float seconds, mm_xform root)
{
    float yaw = yaw_of(root.rotation);
    mm_vec3 p = root.translation;
    float left = seconds / db->interval;
    for (int guard = 0; left > 1e-6f && guard < ADVANCE_MAX_STEPS; ++guard) {
        int next = db->frame_next[frame];
        if (next < 0) break;
        float step = fminf(1.0f - fraction, left), h = step * db->interval;
        mm_vec3 v = flat(mm_quat_rotate(yaw_quat(yaw), db->root_velocity[next]));
        p = mm_vec3_add(p, mm_vec3_scale(v, h));
        yaw += db->root_angular_velocity[next] * h;
        left -= step;
        fraction += step;
        if (fraction >= 1.0f - 1e-6f) fraction = 0.0f, frame = next;
    }
    return mm_xform_make(yaw_quat(yaw), p);
}

static int find_event(const mm_database *db, uint64_t tag, int first, int last)
{
    for (int f = first; tag && db->frame_tags && f <= last; ++f)
        if (db->frame_tags[f] & tag) return f;
    return -1;
}

/* s: the time from the start of move clip mc to database frame `frame` of it. */
static float clip_seconds(const mm_database *db, const mm_move_clip *mc, int frame)
{
    return (float)(frame - mc->start) * db->interval;
}

/* The root at database frame `frame` of move clip mc, relative to the root at its start, as the
 * character integrates root motion. */
static mm_xform root_at(const mm_database *db, const mm_move_clip *mc, int frame)
{
    return advance_root(db, mc->start, 0.0f, clip_seconds(db, mc, frame), mm_xform_identity());
}

/* Without a take-off or landing tag: the ends of the longest run of frames with no foot contact
 * strictly inside [first, last] (the flight), when it is at least MIN_FLIGHT_FRAMES long. */
static void flight_from_contacts(const mm_database *db, mm_move_clip *mc, int first, int last)
{
    int best = 0, best_start = -1;
    for (int f = first; f <= last;) {
        if (db->contacts[f] != 0) {
            ++f;
            continue;
        }
        int e = f;
        while (e + 1 <= last && db->contacts[e + 1] == 0) ++e;
        if (e - f + 1 > best && f > first && e < last) best = e - f + 1, best_start = f;
        f = e + 1;
    }
    if (best >= MIN_FLIGHT_FRAMES) {
        if (mc->take_off < 0) mc->take_off = best_start - 1;
        if (mc->landing < 0) mc->landing = best_start + best;
    }
}

/* The events of the span [first, last] of a clip [clip_first, clip_last]: the TakeOff, HandPlant
 * and Landing tags near it, else the flight; with a hand plant and no landing, recover_time before
 * the span's end. 0: nothing to aim at, or the events out of order. */
static int span_events(const mm_moves *m, mm_move_clip *mc, int first, int last, int clip_first,
                       int clip_last)
{
    const mm_database *db = m->db;
    int e0 = first - EVENT_SEARCH_FRAMES > clip_first ? first - EVENT_SEARCH_FRAMES : clip_first,
        e1 = last + EVENT_SEARCH_FRAMES < clip_last ? last + EVENT_SEARCH_FRAMES : clip_last;
    mc->take_off = find_event(db, mm_search_tag_mask(db, "TakeOff"), e0, e1);
    mc->hand_plant = find_event(db, mm_search_tag_mask(db, "HandPlant"), e0, e1);
    mc->landing = find_event(db, mm_search_tag_mask(db, "Landing"), e0, e1);
    if (mc->take_off < 0 || mc->landing < 0) flight_from_contacts(db, mc, first, last);
    if (mc->landing < 0) {
        if (mc->hand_plant < 0) return 0; /* nothing to aim at */
        mc->landing = last - (int)(m->desc.recover_time / db->interval);
    }
    if (mc->landing <= first || (mc->hand_plant >= 0 && mc->hand_plant >= mc->landing)) return 0;
    if (mc->take_off >= mc->landing) mc->take_off = -1;
    return 1;
}

/* Where the move starts: jump_start_offset before its first event (take-off or hand plant, else
 * the landing), within the clip and before that event; a hand plant at or before it is dropped. */
static void span_start(const mm_moves *m, mm_move_clip *mc, int clip_first)
{
    int event = mc->take_off >= 0 ? mc->take_off : mc->landing;
    if (mc->hand_plant >= 0 && mc->hand_plant < event) event = mc->hand_plant;
    int lead = event - (int)lroundf(m->desc.jump_start_offset / m->db->interval);
    mc->start = lead > clip_first ? lead : clip_first;
    if (mc->start >= event) mc->start = event > clip_first ? event - 1 : clip_first;
    if (mc->hand_plant >= 0 && mc->hand_plant <= mc->start) mc->hand_plant = -1;
}

/* The obstacle's near face in the clip (forward of the root at the start): ahead of every joint
 * below the planted hand (a knee against the wall) from the start to just after the plant, among
 * those not beyond the hand. -INFINITY: no such joint. */
static float near_face(const mm_database *db, const mm_move_clip *mc, mm_vec3 hand)
{
    float face = -INFINITY;
    int until = mc->hand_plant + (int)lroundf(FACE_AFTER_PLANT / db->interval);
    for (int f = mc->start; f <= until && f < mc->landing; ++f) {
        mm_xform rf = root_at(db, mc, f);
        for (int j = 1; j < db->joint_count; ++j) {
            mm_vec3 p = mm_xform_apply_point(rf, bone_in_root(db, f, j).translation);
            if (p.y < hand.y - FACE_BELOW_HAND && p.z < hand.z + FACE_BEYOND_HAND) face = fmaxf(face, p.z);
        }
    }
    return face;
}

/* The hand planted at HandPlant (the lower one) and where it plants: forward of the root at the
 * start, above the clip's ground there, in from the near face. No hand joint: no hand plant. */
static void measure_plant(const mm_moves *m, mm_move_clip *mc)
{
    const mm_database *db = m->db;
    float low = INFINITY;
    for (int k = 0; k < 2; ++k) {
        if (m->hand[k] < 0) continue;
        float y = bone_in_root(db, mc->hand_plant, m->hand[k]).translation.y;
        if (y < low) low = y, mc->hand = m->hand[k];
    }
    if (mc->hand < 0) {
        mc->hand_plant = -1;
        return;
    }
    mm_vec3 hand = mm_xform_apply_point(root_at(db, mc, mc->hand_plant),
                                        bone_in_root(db, mc->hand_plant, mc->hand).translation);
    mc->plant_distance = hand.z;
    mc->plant_height = hand.y - clip_ground(m, mc->start);
    float face = near_face(db, mc, hand);
    mc->hand_inset = isfinite(face)
                         ? clampf(hand.z - face + HAND_INSET_MARGIN, HAND_INSET_MIN, HAND_INSET_MAX)
                         : HAND_INSET_DEFAULT;
}

/* One span of frames tagged as the move: its events and measures in *mc (mc->clip -1: unusable). */
static void setup_span(mm_moves *m, mm_move_clip *mc, int first, int last)
{
    const mm_database *db = m->db;
    memset(mc, 0, sizeof *mc);
    mc->clip = mc->take_off = mc->hand_plant = mc->landing = mc->hand = mc->twin = -1;
    if (last - first < MIN_SPAN_FRAMES) return;
    /* the tag may cover the move alone: the clip around it gives the approach and the recovery */
    const mm_db_clip *clip = &db->clips[db->frame_clip[first]];
    int clip_first = clip->first_frame, clip_last = clip->first_frame + clip->frame_count - 1;
    mc->first = first;
    mc->last = clip_last;
    if (!span_events(m, mc, first, last, clip_first, clip_last)) return;
    span_start(m, mc, clip_first);
    if (mc->hand_plant >= 0) measure_plant(m, mc);
    mc->land_distance = root_at(db, mc, mc->landing).translation.z;
    mc->rise = clip_ground(m, mc->landing) - clip_ground(m, mc->start);
    mc->onto = mc->rise > ONTO_MIN_RISE;
    mc->clip = db->frame_clip[first];
}

/* Every usable span of frames tagged as a move, of every kind, measured once into m->options
 * (clips that are not mirrors first, so that on an equal fit the original plays); per kind the
 * first of them in m->clips. */
static void setup_clips(mm_moves *m)
{
    const mm_database *db = m->db;
    m->option_count = 0;
    for (int kind = 0; kind < MM_MOVE_KIND_COUNT; ++kind) {
        m->clips[kind].clip = -1;
        m->clips[kind].kind = (mm_move_kind)kind;
        uint64_t tag = mm_search_tag_mask(db, kind_tags[kind]);
        if (!tag || !db->frame_tags) continue;
        for (int pass = 0; pass < 2; ++pass)
            for (int f = 0; f < db->frame_count; ++f) {
                int clip = db->frame_clip[f];
                if (!(db->frame_tags[f] & tag) || db->clips[clip].mirrored != (pass == 1)) continue;
                if (f > 0 && db->frame_clip[f - 1] == clip && (db->frame_tags[f - 1] & tag))
                    continue; /* not a start */
                int e = f;
                while (e + 1 < db->frame_count && db->frame_clip[e + 1] == clip &&
                       (db->frame_tags[e + 1] & tag))
                    ++e;
                mm_move_clip mc;
                setup_span(m, &mc, f, e);
                if (mc.clip < 0) continue;
                mc.kind = (mm_move_kind)kind;
                if (m->clips[kind].clip < 0) m->clips[kind] = mc;
                if (m->option_count < MM_MOVES_MAX_CLIPS) m->options[m->option_count++] = mc;
            }
    }
    /* twins: the same span of the same source clip, mirrored and not */
    for (int i = 0; i < m->option_count; ++i)
        for (int k = 0; k < m->option_count && m->options[i].twin < 0; ++k) {
            const mm_move_clip *a = &m->options[i], *b = &m->options[k];
            const mm_db_clip *ca = &db->clips[a->clip], *cb = &db->clips[b->clip];
            if (a->kind == b->kind && ca->mirrored != cb->mirrored && ca->source == cb->source &&
                ca->blend_left < 0 && cb->blend_left < 0 &&
                a->first - ca->first_frame == b->first - cb->first_frame)
                m->options[i].twin = k;
        }
    for (int kind = 0; kind < MM_MOVE_KIND_COUNT; ++kind)
        for (int i = 0; i < m->option_count; ++i)
            if (m->clips[kind].clip >= 0 && m->options[i].first == m->clips[kind].first) {
                m->clips[kind].twin = m->options[i].twin;
                break;
            }
}

/* A frame's feet in the root's frame: where the ankles are, how fast they move (toward the next
 * frame) and whether they are planted. */
static void gait_feet(const mm_moves *m, int frame, mm_vec3 pos[2], mm_vec3 vel[2], int planted[2])
{
    const mm_database *db = m->db;
    int next = db->frame_next[frame];
    for (int k = 0; k < 2; ++k) {
        pos[k] = vel[k] = mm_vec3_make(0, 0, 0);
        unsigned bits = k == 0 ? MM_CONTACT_LEFT_HEEL | MM_CONTACT_LEFT_TOE
                               : MM_CONTACT_RIGHT_HEEL | MM_CONTACT_RIGHT_TOE;
        planted[k] = (db->contacts[frame] & bits) != 0;
        if (m->foot[k] < 0) continue;
        pos[k] = bone_in_root(db, frame, m->foot[k]).translation;
        if (next >= 0)
            vel[k] = mm_vec3_scale(mm_vec3_sub(bone_in_root(db, next, m->foot[k]).translation, pos[k]),
                                   1.0f / db->interval);
    }
}

/* How badly the gait at database frame `from` (what the character plays) fits a move starting at
 * frame `to`: per foot, where it is (m), where it goes over the next 0.2 s and 0.25 m when one is
 * planted and the other is not (a switch of the legs). */
static float side_cost(const mm_moves *m, int from, int to)
{
    mm_vec3 pa[2], va[2], pb[2], vb[2];
    int ca[2], cb[2];
    gait_feet(m, from, pa, va, ca);
    gait_feet(m, to, pb, vb, cb);
    float cost = 0.0f;
    for (int k = 0; k < 2; ++k)
        cost += mm_vec3_distance(pa[k], pb[k]) + SIDE_VELOCITY_WEIGHT * mm_vec3_distance(va[k], vb[k]) +
                (ca[k] != cb[k] ? SIDE_SWITCH_COST : 0.0f);
    return cost;
}

int mm_moves_pick_side(const mm_moves *m, const mm_character *c, int option)
{
    if (!m || !c || !m->db || c->db != m->db || option < 0 || option >= m->option_count) return option;
    int twin = m->options[option].twin;
    if (twin < 0 || twin >= m->option_count || c->frame < 0 || c->frame >= m->db->frame_count) return option;
    /* the move starts on the next update: the frame the character will have reached */
    int from = m->db->frame_next[c->frame] >= 0 ? m->db->frame_next[c->frame] : c->frame;
    float here = side_cost(m, from, m->options[option].start),
          there = side_cost(m, from, m->options[twin].start);
    return there < here - SIDE_TIE ? twin : option;
}

/* The feet standing: the ankles' and toes' (the feet's first children) heights above the ground
 * at the first idle frame, the lower of each pair. */
static void measure_standing(mm_moves *m)
{
    const mm_database *db = m->db;
    int stand = 0; /* the first idle frame */
    for (int k = 0; k < db->clip_count; ++k)
        if (db->clips[k].type == MM_CLIP_IDLE) {
            stand = db->clips[k].first_frame;
            break;
        }
    m->ankle_height = 0.0f;
    float y = INFINITY;
    for (int k = 0; k < 2; ++k)
        if (m->foot[k] >= 0) y = fminf(y, bone_in_root(db, stand, m->foot[k]).translation.y);
    if (isfinite(y)) m->ankle_height = y;
    m->toe_height = m->ankle_height;
    float toe = INFINITY;
    for (int k = 0; k < 2; ++k) {
        m->toe[k] = mm_database_toe_joint(db, m->foot[k], k ? MM_ROLE_RIGHT_TOE : MM_ROLE_LEFT_TOE);
        if (m->toe[k] >= 0) toe = fminf(toe, bone_in_root(db, stand, m->toe[k]).translation.y);
    }
    if (isfinite(toe)) m->toe_height = toe;
}

mm_result mm_moves_init(mm_moves *m, const mm_database *db, const mm_scene *scene, const mm_moves_desc *desc,
                        mm_error *err)
{
    if (!m) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no move layer given");
    memset(m, 0, sizeof *m);
    if (!db) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "the move layer needs a database");
    mm_moves_desc def;
    mm_moves_defaults(&def);
    m->desc = def;
    if (desc) m->desc = *desc;
    mm_moves_desc *d = &m->desc;
    /* zero means default; MM_OFF (negative) is 0 */
    float *field[] = {&d->max_jump_height,     &d->jump_start_offset, &d->rise_start,      &d->fall_start,
                      &d->step_height,         &d->ledge_probe,       &d->trigger_slack,   &d->low_max_height,
                      &d->high_max_height,     &d->short_max_depth,   &d->landing_margin,  &d->recover_time,
                      &d->transition_halflife, &d->gravity,           &d->radius,          &d->cooldown,
                      &d->max_jump_distance,   &d->moving_speed,      &d->collider_height, &d->knee_height,
                      &d->chest_height,        &d->max_lift};
    const float fallback[] = {
        def.max_jump_height,     def.jump_start_offset, def.rise_start,      def.fall_start,
        def.step_height,         def.ledge_probe,       def.trigger_slack,   def.low_max_height,
        def.high_max_height,     def.short_max_depth,   def.landing_margin,  def.recover_time,
        def.transition_halflife, def.gravity,           def.radius,          def.cooldown,
        def.max_jump_distance,   def.moving_speed,      def.collider_height, def.knee_height,
        def.chest_height,        def.max_lift};
    for (size_t i = 0; i < sizeof field / sizeof field[0]; ++i) {
        float v = *field[i];
        *field[i] = v == 0.0f ? fallback[i] : v < 0.0f ? 0.0f : v;
        if (!isfinite(*field[i]) || *field[i] > PARAM_MAX)
            return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0, "move parameter %d out of range", (int)i);
    }
    if (d->rise_start > 1.0f || d->fall_start > 1.0f || d->rise_start > d->fall_start)
        return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0,
                            "rise_start and fall_start must be fractions with rise_start <= fall_start");
    m->db = db;
    m->scene = scene;
    m->kind = MM_MOVE_NONE;
    m->since_move = INFINITY;
    m->hand[0] = desc_joint(db, d->left_hand, MM_ROLE_LEFT_HAND);
    m->hand[1] = desc_joint(db, d->right_hand, MM_ROLE_RIGHT_HAND);
    m->foot[0] = desc_joint(db, d->left_foot, MM_ROLE_LEFT_FOOT);
    m->foot[1] = desc_joint(db, d->right_foot, MM_ROLE_RIGHT_FOOT);
    d->left_hand = d->right_hand = d->left_foot = d->right_foot = NULL; /* the caller's strings */
    measure_standing(m);
    setup_clips(m);
    m->enabled = scene != NULL && m->option_count > 0;
    return MM_OK;
}

static const mm_move_clip *clip_of(const mm_moves *m, mm_move_kind kind)
{
    if ((int)kind < 0 || kind >= MM_MOVE_KIND_COUNT) return NULL;
    if (m->clips[kind].clip >= 0) return &m->clips[kind];
    if (kind == MM_MOVE_DROP && m->clips[MM_MOVE_JUMP].clip >= 0)
        return &m->clips[MM_MOVE_JUMP]; /* jump down */
    return NULL;
}

mm_move_kind mm_moves_choose(const mm_moves *m, const mm_obstacle *o)
{
    if (!m || !o || !isfinite(o->height) || !isfinite(o->depth)) return MM_MOVE_NONE;
    const mm_moves_desc *d = &m->desc;
    float h = o->height;
    if (h <= d->step_height || o->too_high || h > d->high_max_height) return MM_MOVE_NONE;
    int low = h <= d->low_max_height;
    int short_side = !o->too_deep && o->depth <= d->short_max_depth;
    mm_move_kind vault = low ? MM_MOVE_VAULT_LOW : MM_MOVE_VAULT_HIGH;
    const mm_move_clip *v = clip_of(m, vault), *climb = clip_of(m, MM_MOVE_CLIMB);
    /* the short side: over it (a vault that lands beyond); else onto it (then the drop-down) */
    if (short_side && v && !v->onto) return vault;
    if (climb) return MM_MOVE_CLIMB;
    if (v && v->onto) return vault; /* a vault that ends on top: onto it */
    if (h <= d->max_jump_height && clip_of(m, MM_MOVE_JUMP)) return MM_MOVE_JUMP; /* jump onto it */
    if (short_side && v) return vault;
    return MM_MOVE_NONE;
}

float mm_moves_penetration(const mm_scene *scene, const mm_vec3 *points, int count)
{
    float worst = 0.0f;
    if (!scene || !points) return 0.0f;
    for (int b = 0; b < scene->box_count; ++b) {
        const mm_scene_box *box = &scene->boxes[b];
        float s = sinf(box->yaw), c = cosf(box->yaw), hx = 0.5f * box->size.x, hz = 0.5f * box->size.z;
        for (int i = 0; i < count; ++i) {
            mm_vec3 p = mm_vec3_sub(points[i], box->position);
            /* into the box's frame: turn by -yaw about +Y */
            float lx = c * p.x - s * p.z, lz = s * p.x + c * p.z;
            float depth = fminf(fminf(hx - fabsf(lx), hz - fabsf(lz)), fminf(p.y, box->size.y - p.y));
            if (depth > worst) worst = depth;
        }
    }
    return worst;
}

/* Is there ground within step height at p? Its height in *h. */
static int ground_at(const mm_moves *m, mm_vec3 p, float step, float drop, float *h)
{
    mm_scene_hit hit;
    if (!mm_scene_ground_probe(m->scene, p, step, drop, &hit)) return 0;
    *h = hit.point.y;
    return 1;
}

static float clip_time(const mm_moves *m, const mm_character *c)
{
    return ((float)(c->frame - m->start_frame) + c->frame_fraction) * m->db->interval;
}

static float schedule(const mm_moves *m, float t)
{
    if (m->key_count == 0) return 0.0f;
    if (t <= m->key_time[0]) return m->key_y[0];
    for (int k = 0; k + 1 < m->key_count; ++k) {
        float t0 = m->key_time[k], t1 = m->key_time[k + 1];
        if (t >= t1) continue;
        float u = t1 > t0 ? clampf((t - t0) / (t1 - t0), 0.0f, 1.0f) : 1.0f;
        float s = m->key_shape[k] == KEY_SMOOTH    ? u * u * (3.0f - 2.0f * u)
                  : m->key_shape[k] == KEY_FALLING ? u * u
                  : m->key_shape[k] == KEY_RISING  ? 1.0f - (1.0f - u) * (1.0f - u)
                                                   : u;
        return m->key_y[k] + (m->key_y[k + 1] - m->key_y[k]) * s;
    }
    return m->key_y[m->key_count - 1];
}

static void add_key(mm_moves *m, float t, float y, int shape)
{
    if (m->key_count >= MM_MOVES_MAX_KEYS) return;
    if (m->key_count > 0 && t < m->key_time[m->key_count - 1]) t = m->key_time[m->key_count - 1];
    m->key_time[m->key_count] = t;
    m->key_y[m->key_count] = y;
    m->key_shape[m->key_count] = shape;
    ++m->key_count;
}

static int end_frame(const mm_moves *m, const mm_move_clip *mc)
{
    int end = mc->landing + (int)lroundf(m->desc.recover_time / m->db->interval);
    return end > mc->last ? mc->last : end;
}

/* The clip's ground at the landing: the lowest over the few frames after it (a foot landing toes
 * first is not the ground), not over the whole recovery, which may step onto another level. */
static float landing_ground(const mm_moves *m, const mm_move_clip *mc)
{
    int end = end_frame(m, mc), near = mc->landing + (int)lroundf(LANDING_GROUND_TIME / m->db->interval);
    return clip_ground_span(m, mc->landing, near < end ? near : end);
}

/* The last key, where the move hands back: the feet on the surface h at the end frame, whatever
 * level the clip's recovery walks on. */
static void add_end_key(mm_moves *m, const mm_move_clip *mc, float h)
{
    int end = end_frame(m, mc);
    add_key(m, (float)(end - mc->start) * m->db->interval, h - clip_feet(m, end), KEY_LINEAR);
}

/* Starts a move: the root lowered under the body to the clip's ground (the pose kept), the clip
 * asked for, the state reset. Returns the root height the schedule starts from. */
static float begin(mm_moves *m, mm_character *c, mm_move_kind kind, const mm_move_clip *mc)
{
    float g0 = clip_ground_span(m, mc->start,
                                mc->take_off > mc->start ? mc->take_off : mc->start + START_GROUND_FRAMES);
    mm_character_shift_root(c, mm_vec3_make(0.0f, -g0, 0.0f));
    int end = end_frame(m, mc);
    mm_character_play_move(c, mc->start, end, m->desc.transition_halflife);
    m->kind = kind;
    m->active = *mc;
    m->start_frame = mc->start;
    m->started = false;
    m->match_on[0] = m->match_on[1] = false;
    m->key_count = 0;
    m->hand_error = m->land_error = 0.0f;
    m->lift = m->planned_lift = m->applied_lift = 0.0f;
    for (int k = 0; k < MM_MOVES_PLAN_FRAMES; ++k) m->need[k] = 0.0f;
    m->current.kind = kind;
    m->current.clip = mc->clip;
    m->current.t_start = (float)m->time;
    m->current.t_end = m->current.t_start;
    m->current.target_error_cm = 0.0f;
    return c->root.translation.y;
}

/* Room for the body standing at p on a surface at height h: no box within the collider's radius
 * at the knees and the chest. */
static int clear_at(const mm_moves *m, mm_vec3 p, float h)
{
    float r = m->desc.radius;
    mm_vec3 pts[10];
    int n = 0;
    for (int k = 0; k < 2; ++k) {
        float y = h + (k ? m->desc.chest_height : m->desc.knee_height);
        pts[n++] = mm_vec3_make(p.x, y, p.z);
        pts[n++] = mm_vec3_make(p.x + r, y, p.z);
        pts[n++] = mm_vec3_make(p.x - r, y, p.z);
        pts[n++] = mm_vec3_make(p.x, y, p.z + r);
        pts[n++] = mm_vec3_make(p.x, y, p.z - r);
    }
    return mm_moves_penetration(m->scene, pts, n) <= 0.0f;
}

/* The first distance along f from root, from s0 to s1 in PROBE_STEP steps, with ground (want 1)
 * or with none (want 0) from `up` above to `down` below the root's height. -1: none. */
static float probe_along(const mm_moves *m, mm_vec3 root, mm_vec3 f, float s0, float s1, float up, float down,
                         int want)
{
    float h;
    for (float s = s0; s <= s1; s += PROBE_STEP)
        if (ground_at(m, mm_vec3_add(root, mm_vec3_scale(f, s)), up, down, &h) == want) return s;
    return -1.0f;
}

/* A jump's distance along f from root (*dist: the clip's own, at least): past a gap on the way, to
 * the ground across it; onto a wall on the way, or over one too thin to stand on. *need: the
 * distance the world asks for, *over: the top of a wall to clear. 0: nowhere to land (no ground
 * across the gap, a wall too high). */
static int jump_distance(const mm_moves *m, mm_vec3 root, mm_vec3 f, float *dist, float *need, float *over)
{
    const mm_moves_desc *d = &m->desc;
    float y = root.y;
    /* the world is looked at as far as the first jump clip reaches, whichever clip plays (a short
     * hop must not miss the wall or the gap a longer jump sees) */
    const mm_move_clip *first = clip_of(m, MM_MOVE_JUMP);
    float look = first ? fmaxf(*dist, first->land_distance) : *dist;
    /* a gap before the natural landing: land past it, where the ground is within reach */
    float ledge =
        probe_along(m, root, f, 0.0f, look + LOOK_BEYOND_JUMP, d->max_jump_height, d->step_height, 0);
    float across = ledge >= 0.0f ? probe_along(m, root, f, ledge, d->max_jump_distance, d->max_jump_height,
                                               d->step_height, 1)
                                 : -1.0f;
    if (ledge >= 0.0f && across < 0.0f) return 0;
    if (across >= 0.0f)
        *dist = fmaxf(*dist, across + GAP_LANDING_MARGIN), *need = across + GAP_LANDING_MARGIN;
    mm_obstacle o;
    mm_obstacle_desc od;
    memset(&od, 0, sizeof od);
    od.max_distance = fmaxf(*dist, look) + LOOK_BEYOND_JUMP;
    if (mm_scene_measure_obstacle(m->scene, root, f, &od, &o) && o.top - y > d->step_height) {
        if (o.top - y > d->max_jump_height) return 0; /* a wall too high to jump onto */
        float near = o.distance, far = o.distance + o.depth;
        if (o.depth >= STAND_MIN_DEPTH) {
            *dist = clampf(*dist, near + ONTO_MIN_IN, far - ONTO_MIN_FROM_EDGE); /* onto it */
            *need = *dist;
        } else { /* too thin to stand on: over it */
            *dist = fmaxf(*dist, far + d->landing_margin);
            *need = far + d->landing_margin;
            *over = o.top;
        }
    }
    return 1;
}

/* The landing in *land: from p on along f, the first spot where the body has room (not inside a
 * wall, not against a gap's far side) on the ground below height y. 0: none within
 * ROOM_SEARCH_DISTANCE, or no ground within max_jump_height on the way. */
static int room_to_land(const mm_moves *m, mm_vec3 p, mm_vec3 f, float y, mm_vec3 *land)
{
    float h;
    for (float extra = 0.0f; extra <= ROOM_SEARCH_DISTANCE; extra += ROOM_SEARCH_STEP) {
        mm_vec3 q = mm_vec3_add(p, mm_vec3_scale(f, extra));
        if (!ground_at(m, mm_vec3_make(q.x, y, q.z), m->desc.max_jump_height, INFINITY, &h)) return 0;
        if (clear_at(m, q, h)) {
            *land = mm_vec3_make(q.x, h, q.z);
            return 1;
        }
    }
    return 0;
}

/* The landing of a jump or a drop along the root's facing: past a ledge, across a gap, onto a
 * wall in the way, always where the body has room. 0 when there is nowhere to land (a jump at a
 * ledge with no ground across: the caller drops instead). */
static int plan_landing(const mm_moves *m, const mm_character *c, const mm_move_clip *mc, int drop,
                        mm_vec3 *land, float *over, float *need)
{
    *over = NAN;
    const mm_moves_desc *d = &m->desc;
    mm_vec3 root = c->root.translation, f = mm_quat_rotate(c->root.rotation, mm_vec3_make(0, 0, 1));
    float dist = fmaxf(mc->land_distance, MIN_JUMP_DISTANCE);
    *need = NAN; /* the distance the world asks for, if any (a gap's far side, a wall) */
    if (drop) {  /* past the ledge: where the ground falls away */
        float ledge = probe_along(m, root, f, 0.0f, d->ledge_probe + LEDGE_SEARCH_BEYOND, d->step_height,
                                  d->step_height, 0);
        if (ledge >= 0.0f) dist = fmaxf(dist, ledge + DROP_PAST_LEDGE);
    } else if (!jump_distance(m, root, f, &dist, need, over)) {
        return 0;
    }
    return room_to_land(m, mm_vec3_add(root, mm_vec3_scale(f, dist)), f, root.y, land);
}

/* Does clip mc serve a move of this kind? (the jump serves as the drop without a drop clip) */
static int serves(const mm_moves *m, mm_move_kind kind, const mm_move_clip *mc)
{
    return mc->kind == kind ||
           (kind == MM_MOVE_DROP && m->clips[MM_MOVE_DROP].clip < 0 && mc->kind == MM_MOVE_JUMP);
}

/* The jump (or drop) clip whose own flight fits the landing planned for it best: the least
 * correction of its horizontal distance and of its rise (negative: its fall) to the planned
 * landing's, the lowest index on a tie; the landing in *land, a wall to clear in *over. NULL:
 * nowhere to land. Plans once per clip: only when a jump or a drop is asked for. */
static const mm_move_clip *pick_jump(const mm_moves *m, const mm_character *c, mm_move_kind kind, int drop,
                                     mm_vec3 *land, float *over)
{
    const mm_move_clip *best = NULL;
    float best_cost = INFINITY, o, need;
    mm_vec3 root = c->root.translation, l;
    for (int i = 0; i < m->option_count; ++i) {
        const mm_move_clip *mc = &m->options[i];
        if (!serves(m, kind, mc) || !plan_landing(m, c, mc, drop, &l, &o, &need)) continue;
        /* the horizontal: against what a gap or a wall asks for (a jump just long enough), else
         * where it lands; the height counts double: the schedule lifts the whole body for it,
         * the legs do not */
        float dist = isfinite(need) ? need : mm_vec3_length(flat(mm_vec3_sub(l, root)));
        float cost = fabsf(dist - mc->land_distance) + JUMP_RISE_WEIGHT * fabsf(l.y - root.y - mc->rise);
        if (cost < best_cost - PICK_TIE) /* a tie: a mirror fits as its original */
            best = mc, best_cost = cost, *land = l, *over = o;
    }
    /* then the side: of it and its mirror (the same flight) the one that fits the gait */
    return best ? &m->options[mm_moves_pick_side(m, c, (int)(best - m->options))] : NULL;
}

/* over: the height of a wall to clear on the way (NAN: none). */
static void start_jump(mm_moves *m, mm_character *c, mm_move_kind kind, const mm_move_clip *mc, mm_vec3 land,
                       float over)
{
    const mm_moves_desc *d = &m->desc;
    float dt_frame = m->db->interval;
    float y0 = begin(m, c, kind, mc);
    float t_to = (float)(mc->take_off - mc->start) * dt_frame,
          t_land = (float)(mc->landing - mc->start) * dt_frame;
    float flight = t_land - t_to, y_land = land.y - landing_ground(m, mc);
    m->land_target = land;
    mm_target_match_init(&m->match[1], 0, land, c->root.rotation, fmaxf(0.0f, t_to - LAND_MATCH_LEAD),
                         t_land);
    m->match[1].position_weight = mm_vec3_make(1.0f, 0.0f, 1.0f);
    m->match[1].rotation_weight = 0.0f;
    m->match_on[1] = true;
    add_key(m, 0.0f, y0, KEY_LINEAR);
    if (isfinite(over)) { /* over a wall: the feet clear its top at the fall moment */
        int apex = mc->take_off + (int)lroundf(d->fall_start * flight / dt_frame);
        float feet = INFINITY;
        for (int k = 0; k < 2; ++k)
            if (m->foot[k] >= 0) feet = fminf(feet, bone_in_root(m->db, apex, m->foot[k]).translation.y);
        float y_apex = fmaxf(y0, over + OVER_CLEARANCE - (isfinite(feet) ? feet : 0.0f));
        add_key(m, t_to + d->rise_start * flight, y0, KEY_RISING);
        add_key(m, t_to + d->fall_start * flight, y_apex, KEY_FALLING);
    } else if (y_land >= y0) { /* up: risen by the fall moment */
        add_key(m, t_to + d->rise_start * flight, y0, KEY_RISING);
        add_key(m, t_to + d->fall_start * flight, y_land, KEY_LINEAR);
    } else { /* down: falling from take-off, as under gravity */
        add_key(m, t_to, y0, KEY_FALLING);
    }
    add_key(m, t_land, y_land, KEY_LINEAR);
    add_end_key(m, mc, land.y);
}

/* How far past the obstacle's near face a vault or climb lands (on its top, or beyond it); in
 * *from_face where the clip itself would land, measured from its hand plant (or from where it
 * starts). */
static float vault_landing(const mm_moves *m, mm_move_kind kind, const mm_move_clip *mc, const mm_obstacle *o,
                           float *from_face)
{
    *from_face = mc->hand_plant >= 0 ? mc->land_distance - mc->plant_distance + mc->hand_inset
                                     : mc->land_distance - o->distance;
    return mc->onto || kind == MM_MOVE_CLIMB
               ? (o->depth >= STAND_MIN_DEPTH ? clampf(*from_face, ONTO_MIN_IN, o->depth - ONTO_MIN_FROM_EDGE)
                                              : 0.5f * o->depth)
               : fmaxf(*from_face, o->depth + m->desc.landing_margin);
}

/* The vault or climb clip that fits the obstacle best: the least the target matching and the
 * height schedule must correct (the planted hand's height against the top; for a move onto it,
 * the clip's rise against the height too; the landing along the approach). The lowest index on
 * a tie. NULL: none of the kind. */
static const mm_move_clip *pick_vault(const mm_moves *m, const mm_character *c, mm_move_kind kind,
                                      const mm_obstacle *o)
{
    const mm_move_clip *best = NULL;
    float best_cost = INFINITY, from_face;
    for (int i = 0; i < m->option_count; ++i) {
        const mm_move_clip *mc = &m->options[i];
        if (mc->kind != kind) continue;
        float cost = fabsf(vault_landing(m, kind, mc, o, &from_face) - from_face);
        if (mc->hand_plant >= 0) cost += fabsf(o->height - mc->plant_height);
        if (mc->onto || kind == MM_MOVE_CLIMB) cost += fabsf(o->height - mc->rise);
        if (cost < best_cost - PICK_TIE) best = mc, best_cost = cost; /* else a tie */
    }
    /* then the side: of it and its mirror (the same geometry) the one that fits the gait */
    return best ? &m->options[mm_moves_pick_side(m, c, (int)(best - m->options))] : NULL;
}

static void start_vault(mm_moves *m, mm_character *c, mm_move_kind kind, const mm_move_clip *mc,
                        const mm_obstacle *o)
{
    const mm_database *db = m->db;
    mm_vec3 n = flat(o->hit.normal);
    if (mm_vec3_length(n) < 1e-4f) return;
    mm_vec3 f = mm_vec3_scale(mm_vec3_normalize(n), -1.0f);
    float facing = atan2f(f.x, f.z);
    mm_quat face = yaw_quat(facing);
    mm_vec3 q = mm_vec3_make(o->hit.point.x, 0.0f, o->hit.point.z); /* on the near face */
    mm_xform land_rel = advance_root(db, mc->start, 0.0f, (float)(mc->landing - mc->start) * db->interval,
                                     mm_xform_identity());
    float from_face, dist = vault_landing(m, kind, mc, o, &from_face);
    mm_vec3 p = mm_vec3_add(mm_vec3_add(q, mm_vec3_scale(f, dist)),
                            mm_quat_rotate(face, mm_vec3_make(land_rel.translation.x, 0.0f, 0.0f)));
    float h;
    if (!ground_at(m, mm_vec3_make(p.x, o->top, p.z), TOP_PROBE_STEP, INFINITY, &h)) return;
    float y0 = begin(m, c, kind, mc);
    float t_land = (float)(mc->landing - mc->start) * db->interval, y_land = h - landing_ground(m, mc);
    m->land_target = mm_vec3_make(p.x, h, p.z);
    add_key(m, 0.0f, y0, KEY_SMOOTH);
    float t_plant = 0.0f;
    if (mc->hand_plant >= 0) {
        t_plant = (float)(mc->hand_plant - mc->start) * db->interval;
        mm_vec3 hand = bone_in_root(db, mc->hand_plant, mc->hand).translation;
        mm_xform plant_rel = advance_root(db, mc->start, 0.0f, t_plant, mm_xform_identity());
        mm_vec3 hand_rel = mm_xform_apply_point(plant_rel, hand);
        m->hand_target = mm_vec3_add(mm_vec3_add(q, mm_vec3_scale(f, mc->hand_inset)),
                                     mm_quat_rotate(face, mm_vec3_make(hand_rel.x, 0.0f, 0.0f)));
        m->hand_target.y = o->top;
        mm_target_match_init(&m->match[0], mc->hand, m->hand_target, face, 0.0f, t_plant);
        m->match[0].position_weight = mm_vec3_make(1.0f, 0.0f, 1.0f);
        m->match_on[0] = true;
        float y_plant = o->top - hand.y;
        add_key(m, t_plant, y_plant, y_land < y_plant ? KEY_FALLING : KEY_SMOOTH);
    }
    mm_target_match_init(&m->match[1], 0, m->land_target, face, t_plant, t_land);
    m->match[1].position_weight = mm_vec3_make(1.0f, 0.0f, 1.0f);
    m->match_on[1] = true;
    add_key(m, t_land, y_land, KEY_LINEAR);
    add_end_key(m, mc, h);
}

/* The predicted transform at clip time `end` of the matched bone (joint 0: the root) if no
 * further correction were applied: position of the bone, facing of the root. */
static mm_xform predict(const mm_moves *m, const mm_character *c, int bone, float now, float end)
{
    const mm_database *db = m->db;
    mm_xform r = advance_root(db, c->frame, c->frame_fraction, fmaxf(0.0f, end - now), c->root);
    int frame = m->start_frame + (int)lroundf(end / db->interval);
    if (frame >= db->frame_count || db->frame_clip[frame] != db->frame_clip[m->start_frame]) frame = c->frame;
    mm_vec3 p = bone > 0 ? mm_xform_apply_point(r, bone_in_root(db, frame, bone).translation) : r.translation;
    return mm_xform_make(r.rotation, p);
}

/* (lx, lz): p's horizontal position in box's frame (turned by -yaw about +Y about its centre). */
static void box_local(const mm_scene_box *box, mm_vec3 p, float *lx, float *lz)
{
    float sn = sinf(box->yaw), cs = cosf(box->yaw);
    float px = p.x - box->position.x, pz = p.z - box->position.z;
    *lx = cs * px - sn * pz, *lz = sn * px + cs * pz;
}

/* How far p must rise to be LIFT_MARGIN above the top of a box it is in, when within window
 * under that top (INFINITY: at any depth), counting the box's footprint grown by reach. */
static float lift_out(const mm_scene *scene, mm_vec3 p, float window, float reach)
{
    float lift = 0.0f;
    for (int b = 0; b < scene->box_count; ++b) {
        const mm_scene_box *box = &scene->boxes[b];
        float top = box->position.y + box->size.y, lx, lz;
        if (p.y >= top + LIFT_MARGIN || p.y < top - window || p.y < box->position.y) continue;
        box_local(box, p, &lx, &lz);
        if (fabsf(lx) > 0.5f * box->size.x + reach || fabsf(lz) > 0.5f * box->size.z + reach) continue;
        lift = fmaxf(lift, top + LIFT_MARGIN - p.y);
    }
    return lift;
}

/* How far the root at height y must rise so that no joint of the clip's pose at clip time t is
 * inside a box within window of its top (a joint deeper than that is against a face, which
 * lifting does not cure). */
static float clearance(const mm_moves *m, const mm_character *c, float t, float y, float window)
{
    float ahead = t - clip_time(m, c);
    const mm_database *db = m->db;
    int frame = m->start_frame + (int)lroundf(t / db->interval);
    int clip = db->frame_clip[m->start_frame];
    const mm_db_clip *cl = &db->clips[clip];
    if (frame >= cl->first_frame + cl->frame_count) frame = cl->first_frame + cl->frame_count - 1;
    mm_xform root = advance_root(db, c->frame, c->frame_fraction, fmaxf(ahead, 0.0f), c->root);
    root.translation.y = y;
    float lift = 0.0f;
    for (int j = 1; j < db->joint_count; ++j) {
        mm_vec3 p = mm_xform_apply_point(root, bone_in_root(db, frame, j).translation);
        lift = fmaxf(lift, lift_out(m->scene, p, window, LIFT_MARGIN));
    }
    return lift;
}

/* How far the root at height y must rise so that every joint of the pose at database frame
 * `frame` (the root at `root`, the hands excepted: they are matched onto the top) that is over a
 * box (within LIFT_REACH of its footprint), at any depth in it, is above its top. */
static float over_tops(const mm_moves *m, int frame, mm_xform root)
{
    float lift = 0.0f;
    for (int j = 1; j < m->db->joint_count; ++j) {
        if (j == m->hand[0] || j == m->hand[1]) continue;
        mm_vec3 p = mm_xform_apply_point(root, bone_in_root(m->db, frame, j).translation);
        lift = fmaxf(lift, lift_out(m->scene, p, INFINITY, LIFT_REACH));
    }
    return lift;
}

/* The planned lift: the need of the frames ahead (over the boxes' tops after the hand plant, as
 * predicted from the root now and the schedule) spread as target matching spreads an error: a
 * smooth envelope that reaches each frame's need by that frame, rising over `width` seconds
 * before it and settling over as long after it, so that no step is taken at once. */
static float plan_lift(mm_moves *m, const mm_character *c, float t, float dt)
{
    const mm_database *db = m->db;
    const mm_move_clip *mc = &m->active;
    const float width = LIFT_WIDTH;
    if (mc->hand_plant < 0) return 0.0f; /* a jump: its schedule clears what it jumps over */
    int clip = db->frame_clip[m->start_frame];
    int clip_end = db->clips[clip].first_frame + db->clips[clip].frame_count - 1;
    int now = (int)floorf(t / db->interval), ahead = (int)ceilf((t + dt + width) / db->interval);
    int plant = mc->hand_plant - mc->start, land = mc->landing - mc->start;
    for (int k = now + 1 < plant ? plant : now + 1; k <= ahead && k <= land && k < MM_MOVES_PLAN_FRAMES;
         ++k) {
        int frame = m->start_frame + k;
        if (frame > clip_end) break;
        float tk = (float)k * db->interval;
        mm_xform root = advance_root(db, c->frame, c->frame_fraction, fmaxf(tk - t, 0.0f), c->root);
        root.translation.y = schedule(m, tk);
        m->need[k] = over_tops(m, frame, root);
    }
    float lift = 0.0f, tn = t + dt;
    int lo = (int)floorf((tn - width) / db->interval), hi = (int)ceilf((tn + width) / db->interval);
    for (int k = lo < 0 ? 0 : lo; k <= hi && k < MM_MOVES_PLAN_FRAMES; ++k) {
        float u = fabsf((float)k * db->interval - tn) / width;
        if (u < 1.0f) lift = fmaxf(lift, m->need[k] * (1.0f - u * u * (3.0f - 2.0f * u)));
    }
    /* not before the hand plant: the hand is on the top then */
    float u = clampf((tn - (float)plant * db->interval) / width, 0.0f, 1.0f);
    return lift * u * u * (3.0f - 2.0f * u);
}

/* The target matches of the move playing stepped to clip time t + dt: the root corrected. */
static void match_targets(mm_moves *m, mm_character *c, float t, float dt)
{
    for (int k = 0; k < 2; ++k) {
        if (!m->match_on[k]) continue;
        mm_xform correction;
        mm_xform pred = predict(m, c, m->match[k].bone, t, m->match[k].end_time);
        if (mm_target_match_step(&m->match[k], t, dt, pred, &correction))
            mm_character_set_root(c, mm_xform_mul(correction, c->root));
    }
}

/* m under a box's top within which a joint of the move playing at clip time t is lifted out:
 * after the landing only a toe dipping into the surface stood on; after the hand plant the body
 * goes over the top, so a joint deeper in is lifted over too. */
static float lift_window(const mm_moves *m, float t)
{
    const mm_move_clip *mc = &m->active;
    if (t >= clip_seconds(m->db, mc, mc->landing)) return LANDED_WINDOW;
    return mc->hand_plant >= 0 && t >= clip_seconds(m->db, mc, mc->hand_plant) ? OVER_WINDOW : CLEAR_WINDOW;
}

/* The reactive lift (m->lift) for the tick from clip time t: the pose about to play over the
 * next ticks, at the schedule's height with the lift kept, out of the boxes' tops; it rises at
 * most LIFT_RATE, settles back with LIFT_SETTLE, stays under max_lift and adds nothing from the
 * landing on (then the feet stand on the surface found). */
static void react_lift(mm_moves *m, const mm_character *c, float t, float dt)
{
    const mm_move_clip *mc = &m->active;
    float window = lift_window(m, t);
    int look = mc->hand_plant < 0 ? JUMP_LOOK_TICKS : LOOK_TICKS;
    float kept = m->lift * expf(-dt / LIFT_SETTLE), need = 0.0f;
    if (!(t + dt >= clip_seconds(m->db, mc, mc->landing)))
        for (int k = 1; k <= look; ++k)
            need = fmaxf(need,
                         clearance(m, c, t + (float)k * dt, schedule(m, t + (float)k * dt) + kept, window));
    m->lift = fminf(fminf(kept + need, m->lift + LIFT_RATE * dt), m->desc.max_lift);
}

/* The root at height y raised by lift, the feet's locks with it (a foot the clip has planted on
 * what it stepped onto would otherwise stay held inside the wall), the simulation to the root. */
static void raise_root(mm_moves *m, mm_character *c, float y, float lift)
{
    mm_xform root = c->root;
    root.translation.y = y + lift;
    mm_character_set_root(c, root);
    mm_character_move_foot_locks(c, mm_vec3_make(0.0f, lift - m->applied_lift, 0.0f));
    m->applied_lift = lift;
    mm_character_teleport_simulation(c, c->root.translation, c->root.rotation);
}

/* Before the character's update during a move: the targets matched, the root at the schedule's
 * height raised where the pose about to play would cut into a box's top (a trailing leg over a
 * wall, a toe on its edge) by the larger of the reactive and the planned lift. */
static void before_move(mm_moves *m, mm_character *c, float dt)
{
    if (!m->started) return; /* the character starts playing it on this update */
    float t = clip_time(m, c);
    match_targets(m, c, t, dt);
    float y = schedule(m, t + dt);
    react_lift(m, c, t, dt);
    m->planned_lift = plan_lift(m, c, t, dt);
    raise_root(m, c, y, fmaxf(m->lift, m->planned_lift));
}

/* The pose as played at clip time t (with its transition offsets and the feet's IK) may still cut
 * a top the prediction cleared: the reactive lift raised for the next tick (as fast as ever; the
 * hands excepted: they are matched onto the top). */
static void lift_played_pose(mm_moves *m, const mm_character *c, float t, float dt)
{
    float window = lift_window(m, t), extra = 0.0f;
    for (int j = 1; j < m->db->joint_count; ++j)
        if (j != m->hand[0] && j != m->hand[1])
            extra = fmaxf(extra, lift_out(m->scene, c->global[j].translation, window, LIFT_MARGIN));
    m->lift = fminf(m->lift + fminf(extra, LIFT_RATE * dt), m->desc.max_lift);
}

/* The targets' errors when the move reaches them on this tick (clip time t_before to t, the root
 * from root_before): the hand's at HandPlant; the root's horizontal one at Landing, at the Landing
 * itself between the tick's ends (a fast landing moves centimetres in a tick). */
static void measure_errors(mm_moves *m, const mm_character *c, float t_before, float t, mm_vec3 root_before)
{
    const mm_move_clip *mc = &m->active;
    if (mc->hand_plant >= 0 && m->match_on[0]) {
        float tp = clip_seconds(m->db, mc, mc->hand_plant);
        if (t_before < tp && t >= tp)
            m->hand_error = mm_vec3_distance(c->global[mc->hand].translation, m->hand_target);
    }
    float tl = clip_seconds(m->db, mc, mc->landing);
    if (t_before < tl && t >= tl) {
        mm_vec3 r = c->root.translation;
        if (t_before >= 0.0f && t > t_before)
            r = mm_vec3_add(root_before,
                            mm_vec3_scale(mm_vec3_sub(r, root_before), (tl - t_before) / (t - t_before)));
        float dx = r.x - m->land_target.x, dz = r.z - m->land_target.z;
        m->land_error = sqrtf(dx * dx + dz * dz);
    }
}

static float lower_ankle(const mm_character *c)
{
    return fminf(c->raw_contact_positions[0].y, c->raw_contact_positions[2].y);
}

/* The move hands back: the root onto the ground under the body (the pose kept), the simulation to
 * the root, the feet's height error added to the landing's, the move recorded, locomotion. */
static void hand_back(mm_moves *m, mm_character *c)
{
    /* the feet's height: the lowest of heel (the ankle) and toe, each less its standing height (a
     * foot pitched on landing stands on its toes) */
    float feet = fminf(lower_ankle(c) - m->ankle_height,
                       fminf(c->raw_contact_positions[1].y, c->raw_contact_positions[3].y) - m->toe_height),
          h;
    mm_vec3 r = c->root.translation;
    if (mm_vec3_length(flat(mm_vec3_sub(r, m->land_target))) < LAND_ERROR_RADIUS) /* on the ground aimed at */
        m->land_error =
            sqrtf(m->land_error * m->land_error + (feet - m->land_target.y) * (feet - m->land_target.y));
    if (ground_at(m, mm_vec3_make(r.x, feet, r.z), m->desc.step_height, INFINITY, &h))
        mm_character_shift_root(c, mm_vec3_make(0.0f, h - r.y, 0.0f));
    mm_character_teleport_simulation(c, c->root.translation, c->root.rotation);
    m->current.t_end = (float)m->time;
    m->current.target_error_cm = 100.0f * fmaxf(m->hand_error, m->land_error);
    m->last = m->current;
    m->finished = true;
    ++m->count;
    m->kind = MM_MOVE_NONE;
    m->since_move = 0.0f;
    m->fall_velocity = 0.0f;
}

/* After the character's update during a move; root_before: the root as this tick's update began
 * (after before_move), at clip time t_before. */
static void after_move(mm_moves *m, mm_character *c, float t_before, mm_vec3 root_before, float dt)
{
    if (!m->started) {
        if (!c->move_playing) { /* it did not start: give up */
            m->kind = MM_MOVE_NONE;
            return;
        }
        m->started = true;
        t_before = -1.0f;
    }
    float t = clip_time(m, c);
    lift_played_pose(m, c, t, dt);
    measure_errors(m, c, t_before, t, root_before);
    if (mm_character_move_playing(c) && t < MAX_MOVE_TIME) return;
    hand_back(m, c);
}

/* The root on the ground: a step up followed through the pose's offsets, with nothing under the
 * feet a fall under gravity. */
static void follow_ground(mm_moves *m, mm_character *c, float dt)
{
    const mm_moves_desc *d = &m->desc;
    if (!mm_scene_is_flat(c->scene)) return; /* a character on terrain follows the ground itself */
    mm_vec3 r = c->root.translation;
    float h;
    if (!ground_at(m, r, d->step_height, INFINITY, &h)) return;
    if (h > r.y + GROUND_TOLERANCE) { /* a step up */
        mm_character_shift_root(c, mm_vec3_make(0.0f, h - r.y, 0.0f));
        m->fall_velocity = 0.0f;
    } else if (r.y - h > GROUND_TOLERANCE) { /* nothing under the feet: fall */
        m->fall_velocity += d->gravity * dt;
        mm_xform root = c->root;
        root.translation.y = fmaxf(h, r.y - m->fall_velocity * dt);
        mm_character_set_root(c, root);
        if (c->root.translation.y <= h) m->fall_velocity = 0.0f;
    } else {
        m->fall_velocity = 0.0f;
    }
}

/* p (horizontally) out of box's footprint by radius, through the nearer side when inside it.
 * false: p is already clear of it. */
static bool push_out_of_box(const mm_scene_box *box, float radius, mm_vec3 *p)
{
    float sn = sinf(box->yaw), cs = cosf(box->yaw), hx = 0.5f * box->size.x, hz = 0.5f * box->size.z, lx, lz;
    box_local(box, *p, &lx, &lz);
    float cx = clampf(lx, -hx, hx), cz = clampf(lz, -hz, hz);
    float ex = lx - cx, ez = lz - cz, e = sqrtf(ex * ex + ez * ez);
    if (e >= radius) return false;
    if (e > 1e-6f) {
        ex *= (radius - e) / e, ez *= (radius - e) / e;
    } else if (hx - fabsf(lx) < hz - fabsf(lz)) { /* inside: out through the nearer side */
        ex = (lx >= 0.0f ? 1.0f : -1.0f) * (hx - fabsf(lx) + radius), ez = 0.0f;
    } else {
        ez = (lz >= 0.0f ? 1.0f : -1.0f) * (hz - fabsf(lz) + radius), ex = 0.0f;
    }
    p->x += cs * ex + sn * ez; /* back to the world: turn by +yaw */
    p->z += -sn * ex + cs * ez;
    return true;
}

/* The collider: a circle of radius about the root, and the simulation with it, out of the walls
 * (boxes whose top is above a step and whose bottom is below collider_height), but for those the
 * character collides with itself (higher than any move crosses, with mm_character_set_scene). */
static void push_out_of_walls(mm_moves *m, mm_character *c)
{
    const mm_moves_desc *d = &m->desc;
    const mm_scene *s = m->scene;
    /* the walls the character collides with itself (mm_character_set_scene): its own capsule's */
    float own = c->trajectory->scene == s ? c->trajectory->pass_height : INFINITY;
    for (int b = 0; b < s->box_count; ++b) {
        const mm_scene_box *box = &s->boxes[b];
        float y = c->root.translation.y;
        if (box->position.y + box->size.y <= y + d->step_height ||
            box->position.y >= y + d->collider_height || box->position.y + box->size.y > y + own)
            continue;
        mm_vec3 p = c->root.translation;
        if (push_out_of_box(box, d->radius, &p)) {
            mm_xform root = c->root;
            root.translation = p;
            mm_character_set_root(c, root);
        }
        p = c->trajectory->position;
        if (push_out_of_box(box, d->radius, &p)) mm_character_push_simulation(c, p);
    }
}

/* Ledge safety: a character not asked to move on (stopping, standing, turning on the spot) that
 * would step past a ledge (no ground within step_height under the root, where there was before)
 * stays at the edge; walking on toward it triggers the drop instead (look_for_move). */
static void stay_on_ledge(mm_moves *m, mm_character *c, const mm_input *in, mm_vec3 before)
{
    const mm_moves_desc *d = &m->desc;
    mm_vec3 desired = mm_vec3_make(0, 0, 0);
    if (in) mm_trajectory_desired(c->trajectory, in, &desired, NULL);
    float h;
    if (mm_vec3_length(flat(desired)) > d->moving_speed || m->fall_velocity != 0.0f) return;
    if (!ground_at(m, before, d->step_height, d->step_height, &h)) return; /* not on the ground */
    if (ground_at(m, c->root.translation, d->step_height, d->step_height, &h)) return;
    mm_vec3 back = mm_vec3_make(before.x - c->root.translation.x, 0.0f, before.z - c->root.translation.z);
    /* the whole body back by the step it took (a translation: the pose unchanged) */
    mm_character_translate(c, back);
    mm_character_halt_simulation(c);
}

/* The jump key, or walking on at a ledge: a jump (across a gap, onto a wall) or, at a ledge with
 * nothing across, a drop. 1: done (a move started, or a drop called for had nowhere to land). */
static int jump_or_drop(mm_moves *m, mm_character *c, int pressed, int moving, int ledge, mm_vec3 dir,
                        mm_vec3 facing)
{
    const mm_moves_desc *d = &m->desc;
    const mm_move_clip *drop = clip_of(m, MM_MOVE_DROP), *jump = clip_of(m, MM_MOVE_JUMP), *mc;
    mm_vec3 land;
    float over;
    if (pressed && jump && (mc = pick_jump(m, c, MM_MOVE_JUMP, 0, &land, &over)) != NULL) {
        start_jump(m, c, MM_MOVE_JUMP, mc, land, over);
        return 1;
    }
    if (!(pressed || (moving && ledge)) || !drop) return 0;
    int near_ledge =
        ledge || probe_along(m, c->root.translation, mm_vec3_normalize(facing), PROBE_STEP,
                             d->ledge_probe + LEDGE_SEARCH_BEYOND, d->step_height, d->step_height, 0) >= 0.0f;
    if (!near_ledge || !(pressed || mm_vec3_dot(dir, mm_vec3_normalize(facing)) > LEDGE_HEADING_COS))
        return 0;
    if ((mc = pick_jump(m, c, MM_MOVE_DROP, 1, &land, &over)) != NULL)
        start_jump(m, c, MM_MOVE_DROP, mc, land, over);
    return 1;
}

/* Moving along dir toward a wall (within WALL_HEADING_COS of its face): the move its height and
 * depth call for (mm_moves_choose), started when the wall is where it was in the chosen clip. */
static void toward_wall(mm_moves *m, mm_character *c, mm_vec3 dir, mm_vec3 facing)
{
    const mm_moves_desc *d = &m->desc;
    const mm_move_clip *mc;
    mm_vec3 land;
    float over;
    float reach = 0.0f; /* the farthest any move starts from a wall */
    for (int k = 0; k < m->option_count; ++k)
        reach = fmaxf(reach, fmaxf(m->options[k].plant_distance, MIN_WALL_REACH));
    mm_obstacle o;
    mm_obstacle_desc od;
    memset(&od, 0, sizeof od);
    od.max_distance = reach + d->trigger_slack + WALL_LOOK_MARGIN;
    if (!mm_scene_measure_obstacle(m->scene, c->root.translation, dir, &od, &o)) return;
    mm_vec3 n = flat(o.hit.normal);
    if (mm_vec3_length(n) < 1e-4f || mm_vec3_dot(dir, mm_vec3_normalize(n)) > -WALL_HEADING_COS)
        return; /* not toward it */
    mm_move_kind kind = mm_moves_choose(m, &o);
    if (kind == MM_MOVE_JUMP) { /* a jump onto it, close to the wall, facing it */
        if (o.distance > JUMP_ONTO_REACH ||
            mm_vec3_dot(mm_vec3_normalize(facing), mm_vec3_normalize(n)) > -JUMP_FACING_COS)
            return;
        if ((mc = pick_jump(m, c, MM_MOVE_JUMP, 0, &land, &over)) != NULL)
            start_jump(m, c, MM_MOVE_JUMP, mc, land, over);
        return;
    }
    mc = kind == MM_MOVE_NONE ? NULL : pick_vault(m, c, kind, &o);
    if (!mc) return;
    /* at the clip's own distance from the face to the hand plant: little left to correct */
    if (o.distance > fmaxf(mc->plant_distance - mc->hand_inset, MIN_TRIGGER_DISTANCE) + d->trigger_slack)
        return;
    start_vault(m, c, kind, mc, &o);
}

/* pieces the way to the ledge probe is walked in on terrain (a step's edge between two is found) */
#define TERRAIN_LEDGE_SAMPLES 8

/* On terrain (the character follows the ground, mm_character_set_scene): a ledge is where the
 * ground falls by more than step_height between two points on the way from the root to `ahead`
 * (stairs and slopes going down are walked; their root is not on the ground under it). */
static int terrain_ledge(const mm_moves *m, mm_vec3 root, mm_vec3 ahead)
{
    float before = mm_scene_ground_height(m->scene, root.x, root.z, NULL);
    for (int i = 1; i <= TERRAIN_LEDGE_SAMPLES; ++i) {
        mm_vec3 p = mm_vec3_lerp(root, ahead, (float)i / (float)TERRAIN_LEDGE_SAMPLES);
        float h = mm_scene_ground_height(m->scene, p.x, p.z, NULL);
        if (before - h > m->desc.step_height) return 1;
        before = h;
    }
    return 0;
}

/* After the character's update in locomotion: a move to start? Not within cooldown of the last
 * one, but a drop where walking on would fall waits only LEDGE_COOLDOWN (a move may end a step
 * from a ledge: a climb onto a wall half a metre deep). */
static void look_for_move(mm_moves *m, mm_character *c, const mm_input *in, int pressed)
{
    const mm_moves_desc *d = &m->desc;
    mm_vec3 root = c->root.translation, desired = mm_vec3_make(0, 0, 0);
    if (in) mm_trajectory_desired(c->trajectory, in, &desired, NULL);
    desired = flat(desired);
    float speed = mm_vec3_length(desired), h;
    mm_vec3 facing = flat(mm_quat_rotate(c->root.rotation, mm_vec3_make(0, 0, 1)));
    mm_vec3 dir =
        speed > DIRECTION_MIN_SPEED ? mm_vec3_scale(desired, 1.0f / speed) : mm_vec3_normalize(facing);
    int moving = speed > d->moving_speed && m->fall_velocity == 0.0f;
    mm_vec3 ahead = mm_vec3_add(root, mm_vec3_scale(dir, d->ledge_probe));
    int ledge = mm_scene_is_flat(c->scene) ? !ground_at(m, ahead, d->step_height, d->step_height, &h)
                                           : terrain_ledge(m, root, ahead);
    if (m->since_move < d->cooldown && !(moving && ledge && m->since_move >= LEDGE_COOLDOWN)) return;
    if (jump_or_drop(m, c, pressed, moving, ledge, dir, facing) || !moving) return;
    toward_wall(m, c, dir, facing);
}

/* A tick during a move: bent before the character's update, measured (and handed back) after. */
static void update_move(mm_moves *m, mm_character *c, const mm_input *in, float dt)
{
    float t_before = m->started ? clip_time(m, c) : -1.0f;
    before_move(m, c, dt);
    mm_vec3 root_before = c->root.translation;
    mm_character_update(c, in, dt);
    after_move(m, c, t_before, root_before, dt);
}

/* A tick of locomotion on the scene: on the ground and out of the walls, the character's update,
 * kept from walking off a ledge, then a move to start? */
static void update_locomotion(mm_moves *m, mm_character *c, const mm_input *in, float dt, int pressed)
{
    m->since_move += dt;
    follow_ground(m, c, dt);
    push_out_of_walls(m, c);
    mm_vec3 before = c->root.translation;
    mm_character_update(c, in, dt);
    stay_on_ledge(m, c, in, before);
    look_for_move(m, c, in, pressed);
}

void mm_moves_update(mm_moves *m, mm_character *c, const mm_input *in, float dt)
{
    if (!m || !c) return;
    if (!m->enabled || !m->scene || c->db != m->db || !(dt > 0.0f) || !isfinite(dt)) {
        if (m) m->finished = false;
        mm_character_update(c, in, dt);
        return;
    }
    m->finished = false;
    m->time += dt;
    /* a character colliding with this scene itself (mm_character_set_scene) leaves the boxes a
     * move crosses to the moves, and has no walls during one */
    if (c->trajectory && c->trajectory->scene == m->scene)
        mm_character_set_wall_pass(c, m->kind != MM_MOVE_NONE ? INFINITY : m->desc.high_max_height);
    int pressed = in && in->jump && !m->jump_held;
    m->jump_held = in && in->jump;
    if (m->kind != MM_MOVE_NONE)
        update_move(m, c, in, dt);
    else
        update_locomotion(m, c, in, dt, pressed);
}
