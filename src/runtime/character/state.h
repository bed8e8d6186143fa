/* The character's private state: one struct per stage of the tick, in the order the tick runs
 * them (mm/character.h's mm_character_update). Only the runtime writes it; tests read it. */
#ifndef MM_RUNTIME_CHARACTER_STATE_H
#define MM_RUNTIME_CHARACTER_STATE_H

#include <stdbool.h>

#include <mm/character.h>

#include "feet.h"
#include "intent.h"
#include "matching.h"
#include "playback.h"
#include "rig.h"
#include "root_motion.h"
#include "transition.h"
#include "walls.h"
#include "warping.h"

/* A move clip asked for by mm_character_play_move. */
typedef struct mm_move_playback {
    bool pending;   /* starts on the next update, at frame */
    bool playing;   /* plays without searching until the playhead reaches end */
    int frame, end; /* database frames */
    float halflife; /* s: its transition's half-life; 0: the desc's */
} mm_move_playback;

struct mm_character_state {
    mm_character_desc desc; /* the tuning the stages read: mm_character.desc with every MM_OFF a 0 */
    mm_rig rig;
    mm_trajectory trajectory; /* 1. input -> trajectory */
    mm_intent intent;
    mm_playback playback; /* 2. playback */
    mm_playback_params playback_params;
    uint64_t no_distance_tag; /* frames that play by the clock, unwarped ("NoDistanceMatching") */
    mm_move_playback move;    /* 3. search (none while a move plays) */
    mm_matching matching;
    mm_transition transition;   /* 4. transition */
    mm_root_motion root_motion; /* 5. root motion */
    mm_warping warping;         /* 6. warping */
    mm_feet feet;               /* 7. feet */
    mm_rig_pose pose;           /* 8. the output pose ([joint_count] each) */
    void *block;                /* everything above that is allocated, in one block */
};

#endif
