/* Stage 2, playback: the playhead in the database (clock, distance advance, play rate). */
#ifndef MM_RUNTIME_PLAYBACK_H
#define MM_RUNTIME_PLAYBACK_H

#include <stdbool.h>
#include <stdint.h>

#include <mm/character.h>
#include <mm/database.h>
#include <mm/distance_curve.h>
#include <mm/distance_matching.h>
#include <mm/prediction.h>

#include "intent.h"

typedef struct mm_playback {
    int frame;                  /* database frame playing */
    double fraction;            /* [0, 1): how far toward the next frame (double: it accumulates
                                   dt / interval every tick and must not drift) */
    mm_character_playback mode; /* how the playhead moved this tick */
    float play_rate;            /* clip seconds per second (1 without distance matching) */
    float stride_scale;         /* how far stride warping stretches the legs (1: not warped) */
    /* distance matching: 1 + the first frame of the clip whose rate was chosen last (0: none), and
     * what the rate played keeps of the rate before a change of clip (fading) */
    int rate_clip;
    float rate_kept;
} mm_playback;

/* What distance matching is tuned with (mm_character_desc's fields of the same names). */
typedef struct mm_playback_params {
    bool distance_matching, warping;
    float rate_min, rate_max, stride_min, stride_max;
    float idle_speed; /* m/s: a stop is matched only while less is asked for */
} mm_playback_params;

/* Distance matching: the play rate and stride scale of this tick (p->mode, p->play_rate,
 * p->stride_scale) on the distance curve of the clip playing (NULL: by the clock; clip_first_frame:
 * the database frame where that clip starts), from the simulation t, the intent and the input in
 * (the predicted stop and pivot). With warping on, the stride scale eases toward its target. */
void mm_playback_match_distance(mm_playback *p, const mm_playback_params *params,
                                const mm_distance_curve *curve, int clip_first_frame, const mm_trajectory *t,
                                const mm_input *in, const mm_intent *intent, float dt);

/* By the clock: rate 1, no stride warp. */
void mm_playback_by_clock(mm_playback *p);

/* Moves the playhead dt * play_rate seconds on along frame_next (interval s per frame). Returns
 * true when it reached the end of its clip (it then stays on the last frame, fraction 0). */
bool mm_playback_advance(mm_playback *p, const int32_t *frame_next, float interval, float dt);

/* s until foot k's contact label (heel or toe) turns on in the clip playing at its play rate, if it
 * does within `window`; -1 otherwise. */
float mm_playback_time_to_contact(const mm_playback *p, const int32_t *frame_next, const uint8_t *contacts,
                                  float interval, int foot, float window);

#endif
