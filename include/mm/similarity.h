/* mm/similarity.h - pose similarity, and the seed's transition tables (seed 001, 相似帧融合).
 *
 * Two poses (database frames) are compared joint by joint. Each joint j of a frame is a vector of
 * up to 12 numbers in the character frame (joint 0, the simulation bone, is the origin and +Z
 * forward): its position (3, metres), optionally its rotation (6: the rotated X and Y axes, the
 * first two columns of its character-frame rotation matrix) and its velocity (3, m/s). Each number
 * is multiplied by a per-dimension weight. Two measures (docs/similarity.md has the formulas):
 *
 *   cosine:    S = sum_j w_j cos(a_j, b_j) / sum_j w_j   over joints whose vectors are both non-zero
 *              (the root itself, at the origin, is skipped); in [-1, 1], higher is more similar.
 *   euclidean: S = sum_j w_j |a_j - b_j| / sum_j w_j     (metres for positions); lower is better.
 *
 * The motion trend is the windowed similarity, the mean over n consecutive frame pairs:
 *
 *   W(a, b, n) = (1/n) sum_{k=0}^{n-1} S(a + k, b + k)
 *
 * where "+ k" walks forward in the frame's clip: a loop clip wraps, a non-loop clip holds its last
 * frame. n = 1 is the plain pose similarity.
 *
 * Tables (built offline with threads, saved beside the database, used at run time):
 *   fusion (动作融合的相似矩阵): for each frame of each non-loop ("one-shot") clip and each loop
 *     clip, the frame of the loop clip with the best W and that W: where to enter a loop when a
 *     one-shot is interrupted or ends. Lookup O(1).
 *   link (衔接相似矩阵): for each frame of each loop clip and each one-shot clip, W between the
 *     loop from that frame and the one-shot from its first frame: which one-shot to start. A
 *     lookup scans `rows` consecutive rows (the seed's delayed start) and the candidate columns:
 *     O(rows x clips), and returns the best clip and how many frames to wait before starting it.
 * Lookups never allocate and read only the tables.
 *
 *   mm_sim_tables t;
 *   mm_sim_desc d = {0};                      // cosine, positions, window 1, one thread
 *   d.window = 8;
 *   mm_sim_tables_build(&db, &d, &t, &err);   // offline
 *   mm_sim_tables_save(&t, "walk.mmdb.sim", &err);
 *   ...
 *   mm_sim_tables_load("walk.mmdb.sim", &db, &t, &err);  // checks it belongs to db
 *   mm_sim_match m = mm_sim_fusion(&t, playing_frame, walk_clip);      // one-shot -> loop
 *   mm_sim_link_match l;
 *   mm_sim_link(&t, playing_frame, 5, NULL, 0, &l);   // loop -> one-shot, within 5 frames
 *   mm_sim_tables_free(&t);
 *
 * Functions: mm_sim_desc_defaults mm_sim_measure_name mm_sim_better
 *            mm_sim_poses_init mm_sim_poses_free mm_sim_pose mm_sim_window mm_sim_matrix
 *            mm_sim_tables_build mm_sim_tables_save mm_sim_tables_load mm_sim_tables_load_memory
 *            mm_sim_tables_free mm_sim_fusion mm_sim_fusion_best mm_sim_link mm_sim_link_row
 */
#ifndef MM_SIMILARITY_H
#define MM_SIMILARITY_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "alloc.h"
#include "database.h"
#include "result.h"

#ifdef __cplusplus
extern "C" {
#endif

#define MM_SIM_VERSION     1
#define MM_SIM_DIMS        12  /* per-joint dimensions: position 3, rotation 6, velocity 3 */
#define MM_SIM_MAX_WINDOW  256 /* frames */
#define MM_SIM_MAX_THREADS 64

typedef enum mm_sim_measure {
    MM_SIM_COSINE = 0,   /* mean per-joint cosine; higher is more similar */
    MM_SIM_EUCLIDEAN = 1 /* mean per-joint distance; lower is more similar */
} mm_sim_measure;

/* Which quantities make up a joint's vector. */
enum mm_sim_channels {
    MM_SIM_POSITION = 1u << 0, /* dims 0-2: position in the character frame (m) */
    MM_SIM_ROTATION = 1u << 1, /* dims 3-8: rotated X axis, rotated Y axis (character frame) */
    MM_SIM_VELOCITY = 1u << 2  /* dims 9-11: velocity in the character frame (m/s) */
};

/* "cos", "euclid"; NULL if invalid. */
const char *mm_sim_measure_name(mm_sim_measure m);
/* True when score a is strictly better than b under measure m. */
static inline bool mm_sim_better(mm_sim_measure m, float a, float b)
{
    return m == MM_SIM_COSINE ? a > b : a < b;
}

/* Settings. Zero means default:
 *   measure     MM_SIM_COSINE
 *   channels    MM_SIM_POSITION
 *   window      1 (frames; at most MM_SIM_MAX_WINDOW)
 *   dim_weights NULL: position 1, rotation 0.2, velocity 0.1 (seconds: a velocity counts as the
 *               distance covered in 0.1 s); else MM_SIM_DIMS weights >= 0 used as given
 *   joint_weights NULL: 0 for joint 0 (the simulation bone) and 1 for every other joint; else
 *               [joint_count] weights >= 0 (joints of weight 0 are left out)
 *   threads     1 (table building only; results never depend on it)
 *   allocator   NULL: malloc */
typedef struct mm_sim_desc {
    mm_sim_measure measure;
    unsigned channels; /* mm_sim_channels bits */
    int window;
    const float *dim_weights;
    const float *joint_weights;
    int threads;
    const mm_allocator *allocator;
} mm_sim_desc;

/* The per-frame joint vectors of a database, weighted (for the cosine: each joint's vector is
 * normalised and carries the square root of its joint weight, so a dot product gives the
 * weighted sum of cosines). Read-only once made; safe to share between threads. */
typedef struct mm_sim_poses {
    const mm_database *db;
    mm_sim_measure measure;
    unsigned channels;
    int window;
    int dims;          /* numbers per joint (3, 6, 9 or 12) */
    int joint_count;   /* active joints (weight > 0) */
    int joints_padded; /* joint_count rounded up to a multiple of 8 */
    int stride;        /* floats per frame: dims x joints_padded (dimension-major, padding zero) */
    float dim_weights[MM_SIM_DIMS];
    int32_t *joints;      /* [joint_count] database joint indices of the active joints */
    float *joint_weights; /* [joints_padded] their weights, then zeros */
    float weight_sum;     /* sum of joint_weights */
    float *values;        /* [frame_count x stride] */
    uint8_t *zero;        /* cosine: [frame_count x joint_count], 1 where the vector is zero */
    uint8_t *any_zero;    /* cosine: [frame_count], 1 when some joint of the frame is zero */
    size_t memory;        /* bytes of the arrays above */
    mm_allocator allocator;
} mm_sim_poses;

/* Computes every frame's joint vectors by forward kinematics (offline; allocates). desc may be NULL.
 * Errors (MM_ERR_INVALID_ARGUMENT) name the desc field that is wrong. */
mm_result mm_sim_poses_init(mm_sim_poses *p, const mm_database *db, const mm_sim_desc *desc, mm_error *err);
void mm_sim_poses_free(mm_sim_poses *p);

/* S of two database frames (0 <= a, b < frame_count), with the poses' measure. Never allocates. */
float mm_sim_pose(const mm_sim_poses *p, int a, int b);
/* W of two database frames over n frames (n < 1 is taken as 1), stepping each frame through its
 * own clip (loop: wraps; otherwise: holds the last frame). Never allocates. */
float mm_sim_window(const mm_sim_poses *p, int a, int b, int n);
/* W of every frame pair of two clips, window p->window: out[i * frames(clip_b) + j] compares frame
 * i of clip_a with frame j of clip_b (clip-relative). out holds frames(a) x frames(b) floats.
 * threads as in mm_sim_desc (< 2: the caller's thread). */
mm_result mm_sim_matrix(const mm_sim_poses *p, int clip_a, int clip_b, int threads, float *out,
                        mm_error *err);

/* A matched frame: a database frame and its score (frame -1: none). */
typedef struct mm_sim_match {
    int32_t frame;
    float score;
} mm_sim_match;

/* Per-clip record of the tables (file layout). */
typedef struct mm_sim_clip {
    int32_t first_frame, frame_count, loop;
    int32_t index; /* position among loop_clips (loop) or shot_clips (one-shot) */
    int32_t row;   /* first row of its frames: in link (loop) or fusion (one-shot) */
} mm_sim_clip;

typedef struct mm_sim_tables {
    mm_sim_measure measure;
    unsigned channels;
    int window;
    int joint_count, frame_count, clip_count; /* of the database */
    int loop_count, shot_count;               /* loop clips, one-shot clips */
    int fusion_rows, link_rows;               /* frames of one-shot clips, of loop clips */
    uint64_t db_checksum, db_size;            /* which database they belong to */
    float dim_weights[MM_SIM_DIMS];
    const float *joint_weights; /* [joint_count] as used */
    const mm_sim_clip *clips;   /* [clip_count] */
    const int32_t *frame_clip;  /* [frame_count] clip of each frame */
    const int32_t *loop_clips;  /* [loop_count] database clip indices */
    const int32_t *shot_clips;  /* [shot_count] database clip indices */
    const mm_sim_match *fusion; /* [fusion_rows x loop_count] */
    const float *link;          /* [link_rows x shot_count] */

    /* Storage: one buffer in file layout */
    const void *data;
    size_t size; /* bytes: the tables' whole memory */
    void *owned;
    mm_allocator allocator;
} mm_sim_tables;

/* Builds both tables for db (offline; allocates; threads per desc). desc may be NULL. */
mm_result mm_sim_tables_build(const mm_database *db, const mm_sim_desc *desc, mm_sim_tables *out,
                              mm_error *err);
/* Writes the tables' buffer (atomically). docs/similarity.md specifies the file. */
mm_result mm_sim_tables_save(const mm_sim_tables *t, const char *path, mm_error *err);
/* Reads and validates a tables file (magic, version, size, checksum, every count and index). With
 * db not NULL, also checks that the tables were built from that database (its checksum, size and
 * clips). allocator may be NULL. */
mm_result mm_sim_tables_load(const char *path, const mm_database *db, const mm_allocator *allocator,
                             mm_sim_tables *out, mm_error *err);
/* The same from a buffer the caller keeps alive (aligned to 8 bytes). */
mm_result mm_sim_tables_load_memory(const void *data, size_t size, const mm_database *db, mm_sim_tables *out,
                                    mm_error *err);
void mm_sim_tables_free(mm_sim_tables *t);

/* One-shot to loop: the best frame of loop_clip to go to from database frame `frame` of a
 * one-shot clip. {-1, 0} when frame is not in a one-shot clip or loop_clip is not a loop clip. O(1). */
mm_sim_match mm_sim_fusion(const mm_sim_tables *t, int frame, int loop_clip);
/* The same over every loop clip: returns the loop clip with the best score (ties: lowest index)
 * and its match in *out, or -1. O(loop clips). */
int mm_sim_fusion_best(const mm_sim_tables *t, int frame, mm_sim_match *out);

/* Loop to one-shot, with the seed's delayed start. */
typedef struct mm_sim_link_match {
    int clip;    /* database clip index of the one-shot, -1: none */
    int frame;   /* its first database frame */
    int delay;   /* frames to keep playing the loop before starting it (0 <= delay < rows) */
    float score; /* W of that row and column */
} mm_sim_link_match;

/* Scans the link rows of frame and the rows - 1 frames after it in its loop clip (wrapping) over
 * the candidate one-shot clips (database clip indices; NULL / 0: every one-shot clip) and returns
 * in *out the best (ties: the smaller delay, then the earlier candidate). Returns the clip or -1
 * (frame not in a loop clip, no valid candidate). O(rows x candidates); never allocates. */
int mm_sim_link(const mm_sim_tables *t, int frame, int rows, const int *candidates, int candidate_count,
                mm_sim_link_match *out);
/* The link row of a frame of a loop clip: shot_count scores in shot_clips order, or NULL. */
const float *mm_sim_link_row(const mm_sim_tables *t, int frame);

#ifdef __cplusplus
}
#endif

#endif /* MM_SIMILARITY_H */
