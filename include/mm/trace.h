/* mm/trace.h - a run's searches as JSON lines (`mm simulate --trace`), read back and replayed.
 *
 * A trace is JSON Lines (docs/viewer.md, "Record, rewind, trace"): a header object first, with
 * everything a replay needs to run again exactly (the database's checksum and size, the input
 * script's text or the random seed, the tick rate and length, the switches the run was made with),
 * then one object per search ("type": "search": its time, the query, the winner, whether the
 * playhead jumped, and the best candidates with every cost term, winner first) and, with
 * --trace-ticks, one per tick ("type": "tick"). Part of mm_build.
 *
 *   mm_trace trace;
 *   mm_trace_read("run.jsonl", &trace, &err);              // every line parsed
 *   mm_trace_divergence d;
 *   mm_trace_replay(&trace, &db, &d, &err);                 // runs the header's input again
 *   if (d.diverged) printf("tick %d: %s\n", d.tick, d.message);
 *   mm_trace_free(&trace);
 *
 * Writing: mm_trace_write_header once, then after each tick mm_trace_write_tick (it writes a
 * search line when one ran, and a tick line when asked).
 *
 * Functions: mm_trace_run_defaults mm_trace_run_set_input_file mm_trace_run_free
 *            mm_trace_write_header mm_trace_write_tick mm_trace_read mm_trace_free mm_trace_replay
 *            mm_trace_player_open mm_trace_player_step mm_trace_player_character
 *            mm_trace_player_input mm_trace_player_tick mm_trace_player_search
 *            mm_trace_player_divergence mm_trace_player_close mm_trace_db_checksum
 */
#ifndef MM_TRACE_H
#define MM_TRACE_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "character.h"
#include "database.h"
#include "input.h"
#include "result.h"

#ifdef __cplusplus
extern "C" {
#endif

#define MM_TRACE_VERSION    1
#define MM_TRACE_DEFAULT_K  5  /* candidates per search line */
#define MM_TRACE_MAX_K      64 /* the most a trace keeps */
#define MM_TRACE_MAX_PATH   4096
#define MM_TRACE_TERM_COUNT 9 /* the cost terms of a candidate, in mm_trace_term_names order */

/* How a run was made: what its header says and a replay needs. */
typedef struct mm_trace_run {
    uint64_t db_checksum;            /* mm_trace_db_checksum of the database */
    uint64_t db_size;                /* bytes */
    int db_frames;                   /* frames in the database */
    char db_path[MM_TRACE_MAX_PATH]; /* as given (informative: a replay is given the database) */
    double fps;                      /* ticks per second */
    int ticks;                       /* ticks run */
    /* the input: a script (its file name and its text, verbatim), or a random script (seed and
     * seconds: mm_input_script_random with only its seconds set), or a path file (mm simulate --path) */
    char input_path[MM_TRACE_MAX_PATH];
    char *input_text; /* the script's text (NUL-terminated; the run owns it: mm_trace_run_free) */
    long random_seed; /* -1: none */
    double random_seconds;
    char path_file[MM_TRACE_MAX_PATH];
    char scene_path[MM_TRACE_MAX_PATH]; /* the move layer's scene, "" for none */
    /* the switches over the database's settings (-1: the database's) */
    int distance_matching, warping, transition_mode;
    double crossfade_time; /* s, -1: the database's */
    int top_k;             /* candidates per search */
    bool tick_lines;       /* one line per tick too */
} mm_trace_run;

/* Zero, with every switch -1, fps 60 and top_k MM_TRACE_DEFAULT_K. */
void mm_trace_run_defaults(mm_trace_run *run);

/* The database file's checksum: the 64-bit field of its file header at offset 16 (docs/format.md),
 * which covers every byte after it. */
uint64_t mm_trace_db_checksum(const mm_database *db);

/* The names of a candidate's terms ("pose_position", "pose_velocity", "root_velocity",
 * "traj_position", "traj_direction", "loop_favour", "contact_favour", "next_pose_favour",
 * "continuing_bias"). */
extern const char *const mm_trace_term_names[MM_TRACE_TERM_COUNT];

/* The script file a run reads (--input): its name and its text, verbatim, into run (which then
 * owns the text: mm_trace_run_free). */
mm_result mm_trace_run_set_input_file(mm_trace_run *run, const char *path, mm_error *err);
void mm_trace_run_free(mm_trace_run *run);

/* The header line (db: the run's database, for its query length). MM_ERR_IO on a write error. */
mm_result mm_trace_write_header(FILE *out, const mm_trace_run *run, const mm_database *db);

/* After tick `tick` (0-based; it ended at time t s): a search line when c searched during it
 * (searches_before: c->searches before the tick; transitions_before likewise), and a tick line when
 * run->tick_lines. */
mm_result mm_trace_write_tick(FILE *out, const mm_trace_run *run, const mm_character *c, int tick, double t,
                              int searches_before, int transitions_before);

#define MM_TRACE_NO_CHOICE (-2)

/* One candidate of a search line. */
typedef struct mm_trace_candidate {
    int frame, clip;
    float cost;
    float terms[MM_TRACE_TERM_COUNT];
} mm_trace_candidate;

typedef struct mm_trace_search {
    int tick;
    double t;            /* s: the end of its tick */
    int frame_before;    /* the frame playing when it searched */
    int winner;          /* the frame playback continues from (the frame playing when no jump) */
    bool transition;     /* the playhead jumped to the candidate chosen */
    int choice;          /* the candidate chosen (mm_character.last_choice): the winner, or one that plants no
                          * foot the animation has in a swing, or -1 for playing on until it lands;
                          * MM_TRACE_NO_CHOICE in traces written before the field */
    int query_offset;    /* into mm_trace.queries: dims floats */
    int candidate_first; /* into mm_trace.candidates */
    int candidate_count;
    long line; /* in the file */
} mm_trace_search;

typedef struct mm_trace_tick {
    int tick;
    double t;
    int frame, clip;
    mm_xform root;
    bool heel_contact[2], toe_contact[2], foot_locked[2];
    long line;
} mm_trace_tick;

typedef struct mm_trace {
    mm_trace_run run;
    int dims; /* query length */
    int search_count, tick_count, candidate_count;
    mm_trace_search *searches;
    mm_trace_tick *ticks;
    mm_trace_candidate *candidates;
    float *queries;
    char **search_lines; /* each search line's text as read (for the replay's comparison) */
} mm_trace;

/* Reads a whole trace. Bad input: MM_ERR_SYNTAX / MM_ERR_INVALID_ARGUMENT naming the file, line
 * and field. */
mm_result mm_trace_read(const char *path, mm_trace *out, mm_error *err);
void mm_trace_free(mm_trace *t);

/* Where a replay first differed from its trace. */
typedef struct mm_trace_divergence {
    bool diverged;
    int tick;          /* the tick, -1 when none */
    long line;         /* the trace's line, 0 when none (a search the trace lacks) */
    char message[512]; /* what differed: the field, the trace's value and the replay's */
} mm_trace_divergence;

/* Runs the trace's header input again on db (which must have the header's checksum and size:
 * MM_ERR_INVALID_ARGUMENT otherwise) and compares each search with the trace's line, byte for byte;
 * *out says where they first differed. */
mm_result mm_trace_replay(const mm_trace *t, const mm_database *db, mm_trace_divergence *out, mm_error *err);

/* A replay tick by tick (what mm_trace_replay runs, for a viewer that draws each tick): open makes
 * the run the header describes (the same checks as mm_trace_replay); each step runs one tick and,
 * when it searched, compares that search with the trace's line; the character, the input of the
 * last tick, the trace's search matched on it (an index into trace->searches, -1 when the tick did
 * not search) and the first divergence so far are there to read. step returns
 * MM_ERR_INVALID_ARGUMENT once every tick of the header has run. The trace must outlive the player. */
typedef struct mm_trace_player mm_trace_player;
mm_result mm_trace_player_open(mm_trace_player **player, const mm_trace *t, const mm_database *db,
                               mm_error *err);
mm_result mm_trace_player_step(mm_trace_player *player, mm_error *err);
mm_character *mm_trace_player_character(mm_trace_player *player);
const mm_input *mm_trace_player_input(const mm_trace_player *player);
int mm_trace_player_tick(const mm_trace_player *player); /* ticks run */
int mm_trace_player_search(const mm_trace_player *player);
const mm_trace_divergence *mm_trace_player_divergence(const mm_trace_player *player);
void mm_trace_player_close(mm_trace_player *player);

#ifdef __cplusplus
}
#endif

#endif /* MM_TRACE_H */
