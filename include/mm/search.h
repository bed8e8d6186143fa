/* mm/search.h - finding the database frame that best fits a query (the seed's 动作匹配).
 *
 * A query is a row of normalised features, laid out like the database's (mm_search_query_*
 * build one). The cost of a frame is the weighted squared distance of its features to the
 * query, split into five terms (docs/search.md has the exact formula):
 *
 *   base = 2 (1 - r) (pose_position + pose_velocity + root_velocity)
 *        + 2 r (traj_position + traj_direction),        r = pose_trajectory_ratio
 *   cost = base x loop_anim_favour (frames of loop clips)
 *               x contact_mismatch_favour (frames whose contact bits differ from contact_pattern)
 *               x next_pose_favour (the frame after the current one)
 *          - continuing_bias (the frame after the current one)
 *
 * Candidates must have every required tag, no excluded tag, the requested type, must not be
 * within exclude_window frames of the current frame in its clip (the current frame itself never
 * is a candidate; the frame after it always may be), nor among the last end_margin frames of a
 * non-loop clip. Among the frames whose cost is within 1e-6
 * (relative) of the lowest, the lowest index wins, so every method and every thread count gives
 * the same answer.
 *
 * Methods: MM_SEARCH_BRUTE (every frame, a vectorised kernel), MM_SEARCH_FAST (exact: a tree of
 * bounding boxes, built by the searcher from median splits of the features, prunes with a lower
 * bound that never exceeds a frame's cost, so it returns the brute-force winner), MM_SEARCH_FACING
 * (approximate, seed 002: only frames whose future facing is within facing_threshold of the query's, then
 * brute force).
 *
 * Threads: a searcher made with threads > 1 splits one query across a pool, and
 * mm_searcher_batch answers many queries at once; results never depend on the thread count.
 * mm_searcher_search allocates nothing. A searcher is read-only while searching: with one thread
 * it may serve several threads at once; with a pool, calls are serialised.
 *
 *   mm_searcher s;
 *   mm_searcher_init(&s, &db, NULL, &err);
 *   mm_search_params p;
 *   mm_search_params_defaults(&db, &p);
 *   p.current_frame = playing;
 *   float query[MM_SEARCH_MAX_DIMS];
 *   mm_search_query_from_frames(&db, playing, playing, query);   // or from a simulated pose
 *   mm_search_result best;
 *   mm_searcher_search(&s, query, &p, MM_SEARCH_FAST, &best, 1);
 *   mm_searcher_free(&s);
 *
 * Functions: mm_search_params_defaults mm_search_query_from_frames mm_search_query_from_pose
 *            mm_searcher_init mm_searcher_free mm_searcher_search mm_searcher_search_hinted
 *            mm_searcher_batch
 *            mm_search_cost_terms mm_search_tag_mask mm_search_method_name
 */
#ifndef MM_SEARCH_H
#define MM_SEARCH_H

#include <stdbool.h>
#include <stdint.h>

#include "alloc.h"
#include "database.h"
#include "result.h"

#ifdef __cplusplus
extern "C" {
#endif

#define MM_SEARCH_MAX_DIMS    512 /* padded feature dimensions a searcher accepts */
#define MM_SEARCH_MAX_THREADS 16

typedef enum mm_search_method {
    MM_SEARCH_FAST = 0, /* the default: zero in a desc */
    MM_SEARCH_BRUTE = 1,
    MM_SEARCH_FACING = 2
} mm_search_method;

/* "brute", "fast", "facing"; NULL if invalid. */
const char *mm_search_method_name(mm_search_method m);

/* Which clip types a search accepts. */
typedef enum mm_search_type {
    MM_SEARCH_ANY = 0,
    MM_SEARCH_LOCOMOTION = 1, /* only MM_CLIP_LOCOMOTION clips */
    MM_SEARCH_IDLE = 2        /* only MM_CLIP_IDLE clips */
} mm_search_type;

typedef struct mm_search_params {
    /* Weights (the seed's names). mm_search_params_defaults copies them from the database. */
    float pose_trajectory_ratio; /* r in [0, 1]: higher = more responsive, less smooth; 0.5 */
    float joint_position_weights[MM_MAX_MATCH_BONES]; /* per matched bone, database order */
    float joint_velocity_weights[MM_MAX_MATCH_BONES];
    float body_velocity_weight; /* root velocity */
    float position_multiplier;  /* trajectory positions */
    float angle_multiplier;     /* trajectory directions */

    /* Favours and bias (factors: lower = stronger preference; 1 = none). */
    float next_pose_favour; /* the frame after current_frame; default 0.95 */
    float loop_anim_favour; /* frames of loop clips; default 1 */
    float continuing_bias;  /* subtracted from the cost of the frame after current_frame; default 0 */
    /* Contacts: frames whose four mm_contact_bits differ from contact_pattern (those of the frame
     * playing, 0..15) cost contact_mismatch_favour times more (>= 1 disfavours them; 1 = off).
     * contact_pattern -1 (the default): no contact favour. */
    int contact_pattern;
    float contact_mismatch_favour; /* default 1 */

    /* Candidates */
    int current_frame;      /* the frame playing now (excluded, and the favours refer to it); -1: none */
    int exclude_window;     /* also exclude frames within this many frames of it in its clip; 0 */
    int end_margin;         /* exclude the last end_margin frames of non-loop clips; 0 */
    mm_search_type type;    /* MM_SEARCH_ANY */
    uint64_t required_tags; /* every one of these tags must be set */
    uint64_t excluded_tags; /* none of these may be set (DoNotUse-style) */

    /* MM_SEARCH_FACING */
    float facing_threshold; /* radians; 1.0 (about 57 degrees) */
} mm_search_params;

/* Defaults, with the weights the database was built with. */
void mm_search_params_defaults(const mm_database *db, mm_search_params *p);

/* Bit mask of a tag name, 0 if the database has no such tag. */
uint64_t mm_search_tag_mask(const mm_database *db, const char *name);

/* A query from database rows: the pose groups (bones, root velocity) of pose_frame and the
 * trajectory groups of traj_frame. out holds db->dims_padded floats. */
void mm_search_query_from_frames(const mm_database *db, int pose_frame, int traj_frame, float *out);
/* A query from raw, character-frame quantities (the runtime's simulated trajectory and current
 * pose), laid out as mm_pose_data: bone_positions / bone_velocities in the database's matched-bone
 * order, root_velocity, and traj_positions / traj_directions at the database's trajectory times.
 * Normalised with the database's means and scales. out holds db->dims_padded floats. */
void mm_search_query_from_pose(const mm_database *db, const mm_pose_data *pose, float *out);

typedef struct mm_search_result {
    int frame;  /* database row; -1 when no frame passes the filters */
    float base; /* weighted distance, before favours and bias */
    float cost; /* after favours and bias (what is minimised) */
} mm_search_result;

/* The five cost terms of frame for query (weights and ratio applied); their sum is base. */
typedef struct mm_search_terms {
    float pose_position, pose_velocity, root_velocity, traj_position, traj_direction;
} mm_search_terms;
void mm_search_cost_terms(const mm_database *db, const float *query, const mm_search_params *p, int frame,
                          mm_search_terms *out);

typedef struct mm_searcher_desc {
    int threads;                   /* 0 or 1: the calling thread only */
    const mm_allocator *allocator; /* NULL: malloc */
} mm_searcher_desc;

typedef struct mm_searcher_pool mm_searcher_pool;

#define MM_SEARCH_LEAF       32 /* frames per leaf of the searcher's tree, at most */
#define MM_SEARCH_WIDTH      4  /* children per node of the searcher's tree, at most */
#define MM_SEARCH_UNIT_DEPTH 5  /* the tree is split into about 2^5 work units for threads */
#define MM_SEARCH_MAX_UNITS  (2 << MM_SEARCH_UNIT_DEPTH)

/* A node of the searcher's tree (internal): up to MM_SEARCH_WIDTH children ("lanes"), whose
 * boxes are stored lane by lane per dimension (mm_searcher.boxes) so that one pass bounds them
 * all. A lane is another node or a leaf: the frames at positions [begin, end) of the tree order. */
typedef struct mm_search_node {
    int32_t child[MM_SEARCH_WIDTH];                                /* the lane's node, -1 for a leaf */
    int32_t begin[MM_SEARCH_WIDTH], end[MM_SEARCH_WIDTH];          /* positions in mm_searcher.order */
    int32_t min_frame[MM_SEARCH_WIDTH];                            /* lowest frame index below */
    uint64_t tags_any[MM_SEARCH_WIDTH], tags_all[MM_SEARCH_WIDTH]; /* tags set in some / every frame */
    uint8_t types[MM_SEARCH_WIDTH];                                /* type bits (1 locomotion, 2 idle) */
    uint8_t loop[MM_SEARCH_WIDTH];      /* bit 0: some frame loops, bit 1: all frames loop */
    uint16_t contacts[MM_SEARCH_WIDTH]; /* bit c: some frame has the contact bits c (0..15) */
    int32_t count;                      /* lanes used */
} mm_search_node;

typedef struct mm_searcher {
    const mm_database *db;
    int threads;
    /* The tree: frames reordered by median splits of the widest dimension; their features copied
     * in that order; per node the boxes of its lanes (boxes: minima and maxima, tree_dims x
     * MM_SEARCH_WIDTH floats each, [axis][lane]). Node 0 is the root. */
    int32_t *order;       /* position -> frame */
    int32_t *order_clip;  /* position -> the frame's clip */
    uint64_t *order_tags; /* position -> the frame's tags */
    float *features;
    mm_search_node *nodes;
    float *boxes; /* per node, in the tree's coordinates (below): its lanes' minima (tree_dims x
                   * MM_SEARCH_WIDTH floats, [axis][lane]), then their maxima */
    int node_count;
    /* The tree's coordinates: z = basis^T (sqrt_w0 x - center), the principal axes of the
     * features weighted by the database's default weights w0 (boxes along them are much tighter),
     * those of the pose dimensions (bones, root velocity) and those of the trajectory apart, so that
     * a bound weighs each block by its own ratio of weights. */
    float w0[MM_SEARCH_MAX_DIMS], sqrt_w0[MM_SEARCH_MAX_DIMS];
    double center[MM_SEARCH_MAX_DIMS];
    int tree_dims; /* slots of the coordinates (and of the boxes): [0, pose_dims) the pose axes,
                    * [pose_dims, tree_dims) the trajectory axes, each block by decreasing variance
                    * and padded with zero axes to a multiple of 4; at most dims_padded + 8 */
    int pose_dims;
    double *basis; /* [dims_padded x tree_dims]: basis[k * tree_dims + j] is component k of slot j */
    int units[MM_SEARCH_MAX_UNITS]; /* work units: node * MM_SEARCH_WIDTH + lane */
    int unit_count;
    float *facing; /* per frame: unit (x, z) of the furthest future trajectory direction (MM_SEARCH_FACING) */
    int facing_group;
    /* A quantized copy of the features in tree order, for a first pass that bounds each frame's
     * cost from below before the exact cost is computed: one byte per dimension (code c of
     * dimension d stands for quant_lo[d] + c quant_step[d], within half a step of the feature; codes
     * 0 and 255 also for everything below and above the grid). The dimensions of default weight
     * above 0 are its slots, by decreasing weighted variance (quant_order: slot -> dimension).
     * Blocks of 16 positions, slot by slot (16 codes side by side): first every block's first
     * quant_head slots, then every block's others. */
    uint8_t *quantized;
    int16_t quant_order[MM_SEARCH_MAX_DIMS];
    int quant_slots, quant_head;
    double quant_lo[MM_SEARCH_MAX_DIMS], quant_step[MM_SEARCH_MAX_DIMS];
    size_t memory; /* bytes of all the above */
    mm_searcher_pool *pool;
    void *job; /* scratch for one threaded query */
    mm_allocator allocator;
} mm_searcher;

mm_result mm_searcher_init(mm_searcher *s, const mm_database *db, const mm_searcher_desc *desc,
                           mm_error *err);
void mm_searcher_free(mm_searcher *s);

/* The best k frames (k >= 1) into results[0..k-1], best first: results[0] is the winner as
 * defined above, the rest follow by cost then index; missing ones have frame -1. Returns the number
 * found. Never allocates. */
int mm_searcher_search(const mm_searcher *s, const float *query, const mm_search_params *p,
                       mm_search_method method, mm_search_result *results, int k);

/* What one search did, for benchmarks and tuning. */
typedef struct mm_search_stats {
    int frames_evaluated; /* frames whose full cost was computed (both passes) */
    int boxes_tested;     /* bounding boxes whose lower bound was computed */
    int frames_bounded;   /* frames whose cost was bounded from the quantized copy */
} mm_search_stats;

/* mm_searcher_search that also reports its work (stats may be NULL). */
int mm_searcher_search_stats(const mm_searcher *s, const float *query, const mm_search_params *p,
                             mm_search_method method, mm_search_result *results, int k,
                             mm_search_stats *stats);

/* Hints: frames likely among the best k, such as the best k of a search a moment before (at most
 * MM_SEARCH_MAX_HINTS; -1, repeats and frames that are no candidates are passed over). With k > 1,
 * the k-th lowest of their costs under this query bounds the k-th lowest of all from above, so the
 * search prunes from its start; the answer is mm_searcher_search's bit for bit, whatever the hints
 * (stats count the hints' costs among the frames evaluated). */
#define MM_SEARCH_MAX_HINTS 32
int mm_searcher_search_hinted(const mm_searcher *s, const float *query, const mm_search_params *p,
                              mm_search_method method, mm_search_result *results, int k, const int *hints,
                              int hint_count, mm_search_stats *stats);

/* count independent queries (rows of dims_padded floats) with their params (one each, or all
 * the same when params_stride is 0), each answered as by mm_searcher_search with k = 1,
 * spread over the searcher's threads. */
void mm_searcher_batch(const mm_searcher *s, const float *queries, const mm_search_params *params,
                       int params_stride, mm_search_method method, mm_search_result *results, int count);

#ifdef __cplusplus
}
#endif

#endif /* MM_SEARCH_H */
