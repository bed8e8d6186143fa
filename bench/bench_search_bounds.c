/* bench_search_bounds: how tight the exact search's leaf bounds are, in counts that do not depend on
 * the machine's load (bench_search gives the times). On the LAFAN1 database (lafan1.json, as
 * bench_search) or the built-in set when MM_DATA_DIR is unset, for near, transition and random
 * queries (as bench_search makes them, default weights), with L the query's lowest cost (brute
 * force), it counts per query the leaves of the searcher's tree
 *   box      whose lane box bound (the search's, pose and trajectory slots) is at most L: the leaves
 *            the descent must scan even when it knows L from the start;
 *   split    whose least pose part plus least trajectory part (each over the leaf's frames, the
 *            cost split into the two blocks) is at most L: what the tightest bound that takes the
 *            two blocks apart (as the boxes do) would leave;
 *   pairs    one of whose frames has its pose group's box distance plus its trajectory group's at
 *            most L, the groups made per leaf: PAIR_GROUPS by median splits of the leaf's frames
 *            along its pose axes, and apart as many along its trajectory axes (a bound between box
 *            and split that a search could compute per leaf);
 *   holding  that hold a frame within 1.5 L;
 * and, as the search runs, the leaves it scans (frames bounded / 32 on average) for comparison, and
 * the frames whose exact cost it computes (the ones the quantized first pass lets through).
 *
 * usage: bench_search_bounds [QUERIES]   (per kind, default 100; each costs a brute-force pass). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <mm/search.h>

#include "../tests/test_databases.h"
#include "bench_common.h"

#define NEAR_NOISE   0.1 /* per normalised dimension, as bench_search */
#define KINDS        3
#define HOLDING_SPAN 1.5f
#define PAIR_LEVELS  3 /* median splits per leaf and block: PAIR_GROUPS groups */
#define PAIR_GROUPS  (1 << PAIR_LEVELS)

static const char *const KIND_NAMES[KINDS] = {"near", "transition", "random"};

static void make_query(const mm_database *db, int kind, float *q, mm_search_params *p)
{
    mm_search_params_defaults(db, p);
    int a = (int)(uniform() * db->frame_count) % db->frame_count;
    int b = (int)(uniform() * db->frame_count) % db->frame_count;
    if (kind == 0) {
        mm_search_query_from_frames(db, a, a, q);
        for (int d = 0; d < db->dims; ++d) q[d] += (float)(NEAR_NOISE * normal());
    } else if (kind == 1) {
        mm_search_query_from_frames(db, a, b, q);
    } else {
        memset(q, 0, sizeof(float) * (size_t)db->dims_padded);
        for (int d = 0; d < db->dims; ++d) q[d] = (float)normal();
    }
}

/* The query in the tree's coordinates (the searcher's rotation, in double). */
static void tree_coordinates(const mm_searcher *s, const float *q, double *z)
{
    for (int j = 0; j < s->tree_dims; ++j) {
        z[j] = 0.0;
        for (int k = 0; k < s->db->dims_padded; ++k)
            z[j] += s->basis[(size_t)k * s->tree_dims + j] * (s->sqrt_w0[k] * (double)q[k] - s->center[k]);
    }
}

/* Labels the positions local[0..n) of a leaf (coordinates coords[position x slots]) with groups:
 * levels median splits along the slot of [s0, s1) of largest variance, numbered from group << levels. */
static void split_groups(const double *coords, int slots, int *local, int n, int s0, int s1, int levels,
                         int group, unsigned char *out)
{
    if (levels == 0 || n <= 1) {
        for (int i = 0; i < n; ++i) out[local[i]] = (unsigned char)(group << levels);
        return;
    }
    int axis = s0;
    double widest = -1.0;
    for (int d = s0; d < s1; ++d) {
        double sum = 0, sq = 0;
        for (int i = 0; i < n; ++i) {
            double v = coords[(size_t)local[i] * slots + d];
            sum += v;
            sq += v * v;
        }
        double var = sq / n - (sum / n) * (sum / n);
        if (var > widest) {
            widest = var;
            axis = d;
        }
    }
    for (int i = 1; i < n && s1 > s0; ++i) { /* insertion sort along the axis (n <= MM_SEARCH_LEAF) */
        int x = local[i], j = i;
        while (j > 0 && coords[(size_t)local[j - 1] * slots + axis] > coords[(size_t)x * slots + axis]) {
            local[j] = local[j - 1];
            --j;
        }
        local[j] = x;
    }
    split_groups(coords, slots, local, n / 2, s0, s1, levels - 1, group * 2, out);
    split_groups(coords, slots, local + n / 2, n - n / 2, s0, s1, levels - 1, group * 2 + 1, out);
}

/* Box distance of zq to the frames at[i] with group[at[i]] == g over slots [s0, s1). */
static double group_distance(const double *coords, int slots, const int *at, int n,
                             const unsigned char *group, int g, int s0, int s1, const double *zq)
{
    double sum = 0.0;
    for (int d = s0; d < s1; ++d) {
        double lo = INFINITY, hi = -INFINITY;
        for (int i = 0; i < n; ++i)
            if (group[at[i]] == g) {
                double v = coords[(size_t)at[i] * slots + d];
                lo = v < lo ? v : lo;
                hi = v > hi ? v : hi;
            }
        if (!(lo <= hi)) return INFINITY; /* an empty group */
        double below = lo - zq[d], above = zq[d] - hi, gap = below > above ? below : above;
        if (gap > 0.0) sum += gap * gap;
    }
    return sum;
}

int main(int argc, char **argv)
{
    int n = argc > 1 ? atoi(argv[1]) : 100;
    if (n < 1) n = 1;
    mm_database db;
    int lafan = 0;
    if (test_build_real_database(&db, &lafan) != 0) return 1;
    mm_searcher s;
    mm_error err;
    if (mm_searcher_init(&s, &db, NULL, &err) != MM_OK) return 1;
    int frames = db.frame_count, slots = s.tree_dims;
    float *pose = malloc(sizeof(float) * (size_t)frames), *traj = malloc(sizeof(float) * (size_t)frames);
    float q[MM_SEARCH_MAX_DIMS];
    double *zq = malloc(sizeof(double) * (size_t)slots);
    int leaves = 0;
    for (int node = 0; node < s.node_count; ++node)
        for (int l = 0; l < s.nodes[node].count; ++l) leaves += s.nodes[node].child[l] < 0;
    /* the frames in the tree's coordinates (by position), and each leaf's pose and trajectory groups */
    double *coords = malloc(sizeof(double) * (size_t)frames * slots);
    unsigned char *pose_group = malloc((size_t)frames), *traj_group = malloc((size_t)frames);
    for (int at = 0; at < frames; ++at)
        tree_coordinates(&s, s.features + (size_t)at * db.dims_padded, coords + (size_t)at * slots);
    for (int node = 0; node < s.node_count; ++node)
        for (int l = 0; l < s.nodes[node].count; ++l) {
            const mm_search_node *nd = &s.nodes[node];
            int local[MM_SEARCH_LEAF], size = nd->end[l] - nd->begin[l];
            if (nd->child[l] >= 0) continue;
            for (int i = 0; i < size; ++i) local[i] = nd->begin[l] + i;
            split_groups(coords, slots, local, size, 0, s.pose_dims, PAIR_LEVELS, 0, pose_group);
            for (int i = 0; i < size; ++i) local[i] = nd->begin[l] + i;
            split_groups(coords, slots, local, size, s.pose_dims, slots, PAIR_LEVELS, 0, traj_group);
        }
    printf("%s: %d frames, %d leaves; per query, leaves (mean over %d queries of each kind)\n",
           lafan ? "LAFAN1" : "built-in set", frames, leaves, n);
    printf("%-10s %8s %8s %8s %8s %8s %8s\n", "kind", "scanned", "box", "split", "pairs", "holding", "exact");
    for (int kind = 0; kind < KINDS; ++kind) {
        double scanned = 0, box = 0, split = 0, pairs = 0, holding = 0, exact = 0;
        for (int i = 0; i < n; ++i) {
            mm_search_params p;
            make_query(&db, kind, q, &p);
            p.current_frame = -1; /* no favours: the cost is the distance */
            mm_search_result best;
            mm_search_stats st;
            mm_searcher_search_stats(&s, q, &p, MM_SEARCH_FAST, &best, 1, &st);
            scanned += (double)st.frames_bounded / MM_SEARCH_LEAF;
            exact += st.frames_evaluated;
            float limit = best.cost;
            for (int f = 0; f < frames; ++f) {
                mm_search_terms t;
                mm_search_cost_terms(&db, q, &p, f, &t);
                pose[f] = t.pose_position + t.pose_velocity + t.root_velocity;
                traj[f] = t.traj_position + t.traj_direction;
            }
            tree_coordinates(&s, q, zq);
            for (int node = 0; node < s.node_count; ++node) {
                const mm_search_node *nd = &s.nodes[node];
                const float *lo = s.boxes + (size_t)node * 2 * slots * MM_SEARCH_WIDTH,
                            *hi = lo + (size_t)slots * MM_SEARCH_WIDTH;
                for (int l = 0; l < nd->count; ++l) {
                    if (nd->child[l] >= 0) continue;
                    double bound = 0.0;
                    for (int j = 0; j < slots; ++j) {
                        double below = lo[j * MM_SEARCH_WIDTH + l] - zq[j],
                               above = zq[j] - hi[j * MM_SEARCH_WIDTH + l];
                        double g = below > above ? below : above;
                        if (g > 0.0) bound += g * g;
                    }
                    float least_pose = INFINITY, least_traj = INFINITY, least = INFINITY;
                    for (int at = nd->begin[l]; at < nd->end[l]; ++at) {
                        int f = s.order[at];
                        least_pose = pose[f] < least_pose ? pose[f] : least_pose;
                        least_traj = traj[f] < least_traj ? traj[f] : least_traj;
                        least = pose[f] + traj[f] < least ? pose[f] + traj[f] : least;
                    }
                    box += bound * (1.0 - 1e-5) <= limit;
                    if (bound * (1.0 - 1e-5) <= limit) { /* the groups bound within the box */
                        int at[MM_SEARCH_LEAF], size = nd->end[l] - nd->begin[l];
                        double pose_d[PAIR_GROUPS], traj_d[PAIR_GROUPS], least_pair = INFINITY;
                        for (int k = 0; k < size; ++k) at[k] = nd->begin[l] + k;
                        for (int g = 0; g < PAIR_GROUPS; ++g) {
                            pose_d[g] =
                                group_distance(coords, slots, at, size, pose_group, g, 0, s.pose_dims, zq);
                            traj_d[g] = group_distance(coords, slots, at, size, traj_group, g, s.pose_dims,
                                                       slots, zq);
                        }
                        for (int k = 0; k < size; ++k) {
                            double b = pose_d[pose_group[at[k]]] + traj_d[traj_group[at[k]]];
                            least_pair = b < least_pair ? b : least_pair;
                        }
                        pairs += least_pair * (1.0 - 1e-5) <= limit;
                    }
                    split += least_pose + least_traj <= limit;
                    holding += least <= HOLDING_SPAN * limit;
                }
            }
        }
        printf("%-10s %8.1f %8.1f %8.1f %8.1f %8.1f %8.1f\n", KIND_NAMES[kind], scanned / n, box / n,
               split / n, pairs / n, holding / n, exact / n);
    }
    free(pose);
    free(traj);
    free(coords);
    free(pose_group);
    free(traj_group);
    free(zq);
    mm_searcher_free(&s);
    mm_database_free(&db);
    return 0;
}
