/* standing.h (private) - a standing pose for a database whose takes have no idle clip.
 *
 * Without an idle clip a character told to stop keeps playing locomotion and slides. When the
 * config's clips hold no idle clip (and standing.make is on), the build looks through its
 * locomotion clips for the stillest standing frame: upright (mm/posture.h), both feet in contact,
 * the root and the joints slowest over a window around it, the feet side by side under the body
 * rather than mid-stride; each clip gives its stillest, and the stillest of them (with those nearly as
 * still: a stop then settles on the pose nearest its own feet) held for MM__STANDING_SECONDS as a loop,
 * becomes an idle clip named MM__STANDING_PREFIX "<clip>_<frame>" (docs/database.md, "A standing pose when
 * the takes have no idle"). Held, its heels and toes never move: contact detection labels them planted. */
#ifndef MM_DB_STANDING_H
#define MM_DB_STANDING_H

#include <mm/clip.h>
#include <mm/config.h>

#define MM__STANDING_PREFIX      "standing_from_"
#define MM__STANDING_SECONDS     2.0f /* length of the held clip */
#define MM__STANDING_WINDOW      0.5f /* s: stillness is averaged over this window centred on the frame */
#define MM__STANDING_STRIDE      1.0f /* 1/s: a metre of the feet apart along the facing costs as 1 m/s */
#define MM__STANDING_OFFSET      1.0f /* 1/s: a metre from the root to the feet's midpoint costs as 1 m/s */
#define MM__STANDING_POSES       4    /* at most this many poses (each from its own clip) */
#define MM__STANDING_COST_MARGIN 0.1f /* m/s: poses whose cost is within this of the stillest's */
/* m/s: added when a frame's window is not all upright with both feet down (such a frame is taken
 * only when no frame has one) */
#define MM__STANDING_UNSTEADY 10.0f

/* Frames tagged with one of these (any case) are not taken: locomotion never plays them (the moves'
 * tags, DoNotUse), and a crouch is no way to stand. */
/* clang-format off */
#define MM__STANDING_SKIP_TAGS {"DoNotUse", "Jump", "VaultLow", "VaultHigh", "Climb", "Drop", "Crouch"}
/* clang-format on */

/* A frame chosen and what it measured. */
typedef struct mm__standing_pick {
    int clip;          /* index into the candidate clips */
    int frame;         /* frame of that clip */
    float root_speed;  /* m/s: the simulation bone's mean ground speed over the window */
    float joint_speed; /* m/s: the joints' mean world speed over the window */
    float stride;      /* m: the ankles apart along the facing */
    float offset;      /* m: the ankles' midpoint from the simulation bone, on the ground */
    float cost;        /* m/s: what the choice minimised */
} mm__standing_pick;

/* Finds the stillest standing frame of each of clips[0..count) (database clips: joint 0 the
 * simulation bone, at cfg->interval, their joints in one skeleton's order) among the frames
 * usable[i][f] is nonzero (usable[i] NULL: all of clip i's), and keeps the stillest of them and
 * those within MM__STANDING_COST_MARGIN of it, at most max, stillest first: picks[0..*found).
 * Several poses let a stop settle on the one nearest its own feet. head_height: the upright head
 * height postures are judged by (0: measured from each clip). take[i]: clip i's take for the
 * contacts' floors (mm__contact_grounds; NULL: each clip its own). standing_frames receives how
 * many frames were upright with both feet flat (heels and toes in contact). MM_ERR_OUT_OF_MEMORY
 * only; none found is *found 0. */
mm_result mm__standing_find(const mm_config *cfg, const mm_clip *const *clips, const uint8_t *const *usable,
                            const int *take, int count, float head_height, int max, mm__standing_pick *picks,
                            int *found, int *standing_frames);

/* A clip of MM__STANDING_SECONDS holding src's frame (as many frames as a loop of that length has
 * at src->fps). */
mm_result mm__standing_hold(const mm_clip *src, int frame, mm_clip *out, const mm_allocator *a);

#endif
