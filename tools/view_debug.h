/* view_debug.h - the viewer's motion-matching debugger, without a window: the character and its
 * move layer run tick by tick, the last ticks recorded (mm/recorder.h) so that any of them can be
 * gone back to bit for bit, resumed from, or stepped through; and the poses of database frames
 * (the search's candidates) as ghost skeletons (lines) beside the character. */
#ifndef MM_TOOLS_VIEW_DEBUG_H
#define MM_TOOLS_VIEW_DEBUG_H

#include <stdbool.h>

#include <mm/character.h>
#include <mm/moves.h>
#include <mm/recorder.h>
#include <mm/render.h>
#include <mm/search.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The character and its moves, with the last ticks recorded (mm/recorder.h, the move layer's
 * state beside each) so that any of them can be gone back to. */
typedef struct view_sim {
    const mm_database *db;
    const mm_searcher *searcher;
    const mm_scene *scene; /* NULL: no moves */
    mm_character character;
    mm_moves moves;
    float tick;     /* s */
    int candidates; /* kept per search */
    mm_recorder recorder;
    void *memory; /* the recorder's */
    size_t memory_bytes;
    mm_moves *history; /* the move layer after each tick kept ([recorder capacity]; NULL: no scene) */
    int64_t now;       /* ticks played: the tick shown is number now - 1 of the recorder */
    bool looking_back; /* restored to a recorded tick (not the newest) */
    bool diverged;     /* tuned while looking back: stepping on runs again instead of restoring */
} view_sim;

/* Makes the character with desc and a recorder of `seconds` of ticks (fewer when that would take
 * more than max_bytes), asking for `candidates` per search. */
mm_result view_sim_init(view_sim *s, const mm_database *db, const mm_searcher *searcher,
                        const mm_scene *scene, const mm_character_desc *desc, float tick, double seconds,
                        size_t max_bytes, int candidates, mm_error *err);
void view_sim_free(view_sim *s);
/* Plays one tick with in and records it (looking back, the ticks after the one shown are dropped
 * first: the run resumes from there, with desc, the tuning now). */
void view_sim_step(view_sim *s, const mm_input *in, const mm_character_desc *desc);
/* Steps one tick on: to the next recorded tick, or (at the newest, or diverged) plays one with the
 * recorded input of the next tick when there is one, else with in. */
void view_sim_forward(view_sim *s, const mm_input *in, const mm_character_desc *desc);
/* Goes to recorded tick `tick` (ticks played; clamped to what is kept). */
mm_result view_sim_seek(view_sim *s, int64_t tick, mm_error *err);
/* The first and last ticks that can be gone to (0, 0 when none is kept). */
void view_sim_range(const view_sim *s, int64_t *first, int64_t *last);
/* Hands desc to the character from now on. */
void view_sim_tune(view_sim *s, const mm_character_desc *desc);
/* Starts again at tick 0 with desc (the recording is dropped). */
mm_result view_sim_restart(view_sim *s, const mm_character_desc *desc, mm_error *err);
/* The input of the tick shown (neutral before the first). */
mm_input view_sim_input(const view_sim *s);

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
