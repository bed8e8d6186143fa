/* view_debug.h - the viewer's motion-matching debugger, without a window: the character and its
 * move layer run tick by tick with every tick's input and every change of tuning recorded, so that
 * any recorded tick can be gone back to (the character made again and the ticks before it played
 * again: the runtime gives the same bits for the same input), resumed from, or stepped through;
 * the best candidates of the current search with every cost term; and the poses of database
 * frames as ghost skeletons (lines) beside the character. */
#ifndef MM_TOOLS_VIEW_DEBUG_H
#define MM_TOOLS_VIEW_DEBUG_H

#include <stdbool.h>

#include <mm/character.h>
#include <mm/moves.h>
#include <mm/render.h>
#include <mm/search.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The character, its moves and what it was given, tick by tick. */
typedef struct view_sim {
    const mm_database *db;
    const mm_searcher *searcher;
    const mm_scene *scene; /* NULL: no moves */
    mm_character character;
    mm_moves moves;
    float tick; /* s */
    long now;   /* the tick the character is at (ticks played since the start) */
    /* recorded: the input of every tick played, and the desc from each tick it changed */
    mm_input *inputs;
    long count, capacity; /* ticks recorded (count >= now) */
    struct view_sim_change {
        long tick;
        mm_character_desc desc;
    } * changes;
    int change_count, change_capacity;
} view_sim;

/* Makes the character with desc at tick 0 (desc is kept as the first change). */
mm_result view_sim_init(view_sim *s, const mm_database *db, const mm_searcher *searcher,
                        const mm_scene *scene, const mm_character_desc *desc, float tick, mm_error *err);
void view_sim_free(view_sim *s);
/* Plays one tick with in, recorded at tick `now` (a recording past now is dropped first: the
 * session resumes from here). False when out of memory. */
bool view_sim_step(view_sim *s, const mm_input *in);
/* Plays the recorded tick `now` again (stepping forward through the recording). False at its end. */
bool view_sim_replay_one(view_sim *s);
/* Goes to recorded tick `tick` (clamped to [0, count]): the character made again from the first
 * desc and the recording played up to it. */
mm_result view_sim_seek(view_sim *s, long tick, mm_error *err);
/* Hands desc to the character from now on, and records it. False when out of memory. */
bool view_sim_tune(view_sim *s, const mm_character_desc *desc);
/* Starts again at tick 0 with desc (the recording is dropped). */
mm_result view_sim_restart(view_sim *s, const mm_character_desc *desc, mm_error *err);

/* ---- candidates ---- */

#define VIEW_MAX_CANDIDATES 8

typedef struct view_candidate {
    int frame;      /* database frame; -1: none */
    int clip;       /* database clip */
    int clip_frame; /* frame within its clip */
    float base;     /* the weighted distance */
    float cost;     /* after favours and bias */
    mm_search_terms terms;
} view_candidate;

/* The best k (<= VIEW_MAX_CANDIDATES) frames for the character's last query with the parameters
 * it searched with, by its method (out[0] is the frame it chose). Returns how many (0 before the
 * first search). */
int view_candidates(const mm_character *c, int k, view_candidate *out);

/* ---- ghosts ---- */

/* The world transforms of database frame `frame`'s pose with its root (joint 0) at anchor:
 * global[joint_count]. */
void view_ghost_pose(const mm_database *db, int frame, mm_xform anchor, mm_xform *global);
/* Appends the bones of a pose (joints from 1) as lines of colour to lines (at most capacity in
 * all; *count grows). */
void view_ghost_lines(const mm_database *db, const mm_xform *global, mm_rgba color, mm_render_line *lines,
                      int *count, int capacity);

/* A clip played from a frame on (the preview of a candidate): the frame advances with time by
 * the database's interval, to the clip's next frame (around a loop), and starts again at `start`
 * at the clip's end. */
typedef struct view_preview {
    int start, frame; /* -1: none */
    double time;      /* s since the frame began */
} view_preview;

void view_preview_start(view_preview *p, int frame);
void view_preview_advance(view_preview *p, const mm_database *db, double dt);

#ifdef __cplusplus
}
#endif

#endif /* MM_TOOLS_VIEW_DEBUG_H */
