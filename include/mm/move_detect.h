/* mm/move_detect.h - finding the moves beyond locomotion in motion capture: jumps, vaults,
 * climbs and drops, with their key events (take-off, hand plant, landing), so that a config can
 * tag them (`mm moves detect`; scripts/data_configs.sh makes lafan1_moves.json with it).
 *
 * The detector reads seven point tracks of a clip in metres, Y up: the hips, both ankles, both
 * toes and both hands. From them:
 *   - foot plants: an ankle or toe is planted when it is slower than plant_speed, horizontally
 *     (the database's contact detector, at any height) and vertically, for at least
 *     min_plant_time; a foot's plant has the height of the surface it stands on (the joint's
 *     height minus its own height above the sole, measured on the clip's floor);
 *   - flights: no foot planted for at least min_flight_time;
 *   - hand plants: a hand slower than plant_speed for at least min_plant_time, at least
 *     hand_min_height above the surface the feet last stood on, while the hips move at least
 *     hand_travel relative to it (the body passes over or climbs up the hand: a hand resting on a
 *     hip or hanging while standing is not a plant);
 *   - level changes: a foot plants on a surface level_change higher or lower than the one before.
 * These anchors, closer than merge_gap to each other, make one move. Its take-off is the last
 * frame a foot is on the surface it started from, its landing the first frame after that a foot
 * plants on the surface it ends on, its hand plant the first frame of the first hand plant. By
 * the start and end heights (h0, h1) and the obstacle's height (the planted hand above h0):
 *   drop       h1 <= h0 - drop_height
 *   jump       a flight without a hand plant (onto something higher, level, or lower by less
 *              than drop_height)
 *   climb      h1 >= h0 + level_change (hands or a step up, no flight without hands)
 *   vault      a hand plant, about the same level at both ends, and the hips pass over the hand;
 *              vault_high when the obstacle is at least vault_high_height, else vault_low
 * Anything else (a hand on something while walking, stairs) is not a move. Everything is
 * deterministic; thresholds are in docs/moves_data.md.
 *
 * Functions: mm_move_params_defaults mm_move_kind_tag mm_moves_detect
 *            mm_moves_detect_clip
 */
#ifndef MM_MOVE_DETECT_H
#define MM_MOVE_DETECT_H

#include "clip.h"
#include "config.h"
#include "math.h"
#include "move_kind.h" /* mm_move_kind, shared with the runtime's moves (mm/moves.h) */
#include "result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The tracks, in this order, of mm_moves_detect's input. */
enum mm_move_track {
    MM_MOVE_TRACK_HIPS = 0,
    MM_MOVE_TRACK_LEFT_FOOT = 1, /* ankle */
    MM_MOVE_TRACK_RIGHT_FOOT = 2,
    MM_MOVE_TRACK_LEFT_TOE = 3,
    MM_MOVE_TRACK_RIGHT_TOE = 4,
    MM_MOVE_TRACK_LEFT_HAND = 5,
    MM_MOVE_TRACK_RIGHT_HAND = 6,
    MM_MOVE_TRACK_COUNT = 7
};

/* Zero means default in every field (the values in brackets); MM_OFF (any negative value) is 0. */
typedef struct mm_move_params {
    float plant_speed;       /* m/s: a foot or hand slower than this may be planted [0.5] */
    float min_plant_time;    /* s: shorter plants and gaps are flicker [0.1] */
    float min_flight_time;   /* s: no foot planted this long is a flight (running's are shorter) [0.25] */
    float level_change;      /* m: a plant this much higher is a new level (a stair step is less) [0.4] */
    float drop_height;       /* m: ending this much lower is a drop [0.5] */
    float hand_min_height;   /* m: a hand plant is at least this above the feet's surface [0.5] */
    float hand_travel;       /* m: the hips move this much relative to a planted hand [0.3] */
    float vault_high_height; /* m: obstacles from this height are high [1.5] */
    float merge_gap;         /* s: anchors closer than this are one move [0.5] */
    float lead_in, lead_out; /* s: the move's range starts this before the take-off and ends this
                                after the landing [1, 1] */
} mm_move_params;

typedef struct mm_move {
    mm_move_kind kind;
    int begin, end;        /* frames, the move's range [begin, end) with lead-in and lead-out */
    int take_off;          /* the last frame a foot is on the start surface */
    int hand_plant;        /* the first frame of the first hand plant; -1 when none */
    int landing;           /* the first frame a foot plants on the end surface */
    int hand;              /* the planted hand: 0 left, 1 right, -1 none */
    bool flight;           /* no foot planted for min_flight_time or more in between */
    float start_height;    /* m, the surface at take-off */
    float end_height;      /* m, the surface at landing */
    float obstacle_height; /* m, the planted hand above start_height (0 without one) */
} mm_move;

/* The defaults in brackets above. */
void mm_move_params_defaults(mm_move_params *p);
/* The config tag names: "Jump", "VaultLow", "VaultHigh", "Climb", "Drop". The events' tags are
 * "TakeOff", "HandPlant" and "Landing". */
const char *mm_move_kind_tag(mm_move_kind k);

/* Finds the moves in tracks[frame * MM_MOVE_TRACK_COUNT + track] (metres, Y up) of frame_count
 * frames at fps. Writes up to capacity moves in frame order; *count receives how many were found
 * (may exceed capacity). params NULL: the defaults. */
mm_result mm_moves_detect(const mm_vec3 *tracks, int frame_count, float fps, const mm_move_params *params,
                          mm_move *out, int capacity, int *count, mm_error *err);

/* The same on a clip in metres, the tracks taken from the joints cfg's roles name (hips,
 * left_foot, right_foot, left_toe, right_toe, left_hand, right_hand). */
mm_result mm_moves_detect_clip(const mm_clip *clip, const mm_config *cfg, const mm_move_params *params,
                               mm_move *out, int capacity, int *count, mm_error *err);

#ifdef __cplusplus
}
#endif

#endif /* MM_MOVE_DETECT_H */
