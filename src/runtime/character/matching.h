/* Stage 3, search: when to search, the query, and the frame to go to. */
#ifndef MM_RUNTIME_MATCHING_H
#define MM_RUNTIME_MATCHING_H

#include <stdbool.h>
#include <stdint.h>

#include <mm/character.h>
#include <mm/search.h>

#include "intent.h"
#include "playback.h"

/* A candidate that plants a foot the animation playing has in a swing is priced this share of the
 * search winner's cost above its own (a price, not a cut: candidates and the wait compete on
 * cost plus price; docs/metrics.md, "Jumps that plant a swinging foot, priced") */
#define PLANT_PRICE 0.25f
/* s: the longest the jump waits for a swinging foot to land before the cheapest candidate is
 * taken all the same (the simulation goes on meanwhile) */
#define PLANT_MAX_WAIT 1.0f
/* s: the same wait stopping or standing (under KEEP_CONTACTS_FROM_SPEED), where only a jump onto
 * an idle frame is weighed: a stop that lands a foot in mid-swing on a standing frame plants heel
 * and toe together under the transition's pitch, and the foot stands on its toes the whole idle.
 * A swing lands within this; longer would delay the stop itself (docs/metrics.md, "A heel held up
 * by its locks") */
#define STOP_PLANT_MAX_WAIT 0.25f
/* s: that wait is only for a swinging foot the animation playing lands within this (a walking
 * swing: the wait ends before it, the winner's cost falling as the foot comes down); a foot held
 * up longer (a leg kicked up behind) is shown higher still when the jump comes, and snaps down
 * (docs/metrics.md, "Late responses and the stop's wait for a foot held up") */
#define STOP_LANDING_WITHIN 0.4f

/* the best candidates looked through for one that plants no swinging foot (the search's winner
 * is the same whatever k) */
#define PLANT_CANDIDATES 16

typedef struct mm_matching {
    float since_search; /* s */
    float search_phase; /* share of the search interval by which the schedule shifts */
    bool phase_pending; /* the next search shifts it (mm_character_set_search_phase) */
    bool plant_waiting; /* playing on until a swinging foot lands (no jump taken since) */
    float plant_waited; /* s: how long, while plant_waiting */
    /* the frames of the candidates priced at the last search (hints for the next while waiting:
     * mm_searcher_search_hinted) */
    int plant_hints[PLANT_CANDIDATES];
    int plant_hint_count;
    float last_direction;              /* rad: desired direction at the last search */
    bool idle;                         /* asking for idle */
    bool has_idle;                     /* the database has idle clips */
    uint64_t gait_tags[MM_GAIT_COUNT]; /* tags named after each gait ("Walk", "Run", ...) */
    float *query;                      /* [dims_padded] */
    int searches;
    float last_search_us;
    mm_search_result last_result; /* the search's winner */
    mm_search_result last_choice; /* what the jump went to: a candidate or, frame -1, playing on
                                   * (a wait); cost: the cheapest's cost plus its plant price */
    mm_search_params last_params; /* what the last search weighed with */
    /* the last search's best candidates, winner first (mm_character_set_candidates: allocated
     * apart from the state's block; NULL with capacity 0: the winner alone, in last_result) */
    mm_search_result *candidates;
    int candidate_capacity, candidate_count;
    /* the game's desired future for this tick's search (mm_character_set_future), in place of the
     * simulation's prediction at the database's future trajectory times; 0: none */
    int future_count;
    mm_vec3 future_positions[MM_MAX_TRAJ_SAMPLES];
    mm_quat future_facings[MM_MAX_TRAJ_SAMPLES];
    /* the stances as played, per foot: whether its contact label (of the frames played, across
     * jumps) is on, and where the character stood when it turned on */
    bool in_stance[2];
    mm_vec3 stance_from[2];
    /* m: a foot whose stance the character has travelled this far from is no longer kept planted
     * by the contact favour (a leg's length, mm_matching_init); 0: never */
    float stance_reach;
    /* s since the search last asked for a jump (INFINITY: none yet): its offsets are still being
     * hidden, and the search weighs the pose back up meanwhile (mm_matching_ratio) */
    float since_jump;
} mm_matching;

/* m/s: under this simulated speed (standing, starting, stopping) the search does not favour the
 * frame playing's contacts: a stance held since the last stop is no guide to how to start (docs/metrics.md,
 * "Transitions that keep the contacts") */
#define KEEP_CONTACTS_FROM_SPEED 0.3f

/* A jump of the playhead asked for: to frame at fraction (-1: none); uncancellable: the crossfade
 * mixer may not drop it. */
typedef struct mm_jump {
    int frame;
    double fraction;
    bool uncancellable;
} mm_jump;

/* The tags and the idle clips of db; idle, searching on the first tick. leg_length (m): how far
 * the character may travel over a planted foot before the search stops keeping it planted
 * (STANCE_REACH_LEGS of it; 0: no such limit). */
void mm_matching_init(mm_matching *m, const mm_database *db, float *query, float leg_length);

/* Each tick, once the character has moved: the feet's stances as played (label: the contact bits
 * of the frame playing; root: where the character stands). */
void mm_matching_track_stances(mm_matching *m, unsigned label, mm_vec3 root);

/* When to search, each tick: updates idle (from the intent, the simulation's ground speed and
 * root_speed, the speed of the root motion played last tick) and the time since the last search;
 * true when it is time (search_interval), the desired direction turned sharply, idle changed, or
 * the clip ended (ended) — never while a move plays (move_playing). */
bool mm_matching_due(mm_matching *m, const mm_character_desc *d, const mm_intent *intent,
                     float simulated_speed, float root_speed, bool ended, bool move_playing, float dt);

/* The contact pattern the search favours (the four mm_contact_bits): label's (the frame
 * playing's), less the bits of the feet the character (at root) has travelled stance_reach from
 * since they were planted. */
int mm_matching_contact_pattern(const mm_matching *m, unsigned label, mm_xform root);

/* The pose_trajectory_ratio the search weighs with: the desc's, moved toward
 * velocity_change_ratio while the simulated velocity (t) must change toward the intent's; that
 * move held back, right after a jump, by the share of the jump still to hide (the transition's
 * spring over transition_halflife: all of it at the jump, half after one halflife; with the
 * crossfade mixer the old sources' weight over crossfade_time). */
float mm_matching_ratio(const mm_matching *m, const mm_character_desc *d, const mm_trajectory *t,
                        const mm_intent *intent);

/* Searches with the pose of the frame playing and t's future in the frame of root (in: the input
 * that future is sampled under; m's future instead, when given); frames in other contacts than the
 * frame playing's get the desc's contact_mismatch_favour, from KEEP_CONTACTS_FROM_SPEED of
 * simulated speed on; a foot the character has travelled stance_reach from since it was planted
 * counts as lifted in that pattern (frames that lift it are favoured). *jump: where to go (frame
 * -1 when playback goes on where it is). */
void mm_matching_search(mm_matching *m, const mm_character_desc *d, const mm_database *db,
                        const mm_searcher *searcher, const mm_trajectory *t, const mm_input *in,
                        const mm_intent *intent, mm_xform root, const mm_playback *p, mm_jump *jump);

/* Whether a jump from the frame playing to frame `to` plants a foot that the animation playing has
 * up in a swing (labelled at `to` or soon after while the frames after `playing` have that foot
 * unlabelled around that time): the search passes such a winner over while moving. */
bool mm_matching_plants_swinging_foot(const mm_database *db, int playing, int to);

/* Which of the search's best n candidates (best first) a jump from the frame playing goes to: the
 * one whose cost plus price is lowest (price: PLANT_PRICE of the winner's cost when it plants a
 * swinging foot, else 0); -1 (play on, wait) when that one plants a swinging foot while `waited`
 * (s played on in a row for that) is under PLANT_MAX_WAIT. *priced: that one's cost plus price. */
int mm_matching_plant_choice(const mm_database *db, int playing, const mm_search_result *results, int n,
                             float waited, float *priced);

/* mm_matching_plant_choice stopping or standing: the wait under STOP_PLANT_MAX_WAIT, and only while
 * the animation playing lands every swinging foot the choice plants within STOP_LANDING_WITHIN of
 * frames from `playing` (else the choice at once). */
int mm_matching_stop_plant_choice(const mm_database *db, int playing, const mm_search_result *results, int n,
                                  float waited, float *priced);

/* How long playback may wait for a swinging foot to land before a jump to frame `to` that plants
 * it is taken all the same: PLANT_MAX_WAIT moving; stopping or standing, STOP_PLANT_MAX_WAIT when
 * `to` is an idle clip's frame and 0 otherwise (not weighed: a start, or a slow turn, goes where the
 * search says). */
float mm_matching_plant_max_wait(const mm_database *db, bool moving, int to);

#endif
