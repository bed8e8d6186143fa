/* The role finder (mm/skeleton_roles.h): names and geometry, each judged on its own, then compared.
 *
 * Geometry works on a few dozen poses sampled over all the takes (world positions, +Y up, metres)
 * and on the bone lengths (each joint's translation from its parent in the first frame). Names are
 * split into a side (from the first side convention that fits) and a base: the rest, lower case,
 * letters and digits only ("mixamorig:LeftToeBase" -> left, "toebase"). */
#include <mm/skeleton_roles.h>

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "db/process.h"

#define MAX_SAMPLES       96
#define TRAVEL_SPEED      0.5f /* m/s: faster than this, the hips travel */
#define TRAVEL_HALFWINDOW 0.2f /* s: velocity by central differences over +-this */
#define SNAP_DEGREES      30.0f

/* ---- names ------------------------------------------------------------------------------ */

enum pattern_kind { ANYWHERE, PREFIX, SUFFIX, PREFIX_CAPITAL };

typedef struct side_pattern {
    const char *left, *right;
    int kind;
    const char *text; /* how the report names it */
} side_pattern;

/* In the order a name is tried against them (and the order of the config's mirror pairs: the
 * build's mirroring takes the first pattern a name contains). */
static const side_pattern patterns[] = {
    {"Left", "Right", ANYWHERE, "Left*/Right*"},
    {"left", "right", ANYWHERE, "left*/right*"},
    {"LEFT", "RIGHT", ANYWHERE, "LEFT*/RIGHT*"},
    {"_L_", "_R_", ANYWHERE, "*_L_*/*_R_*"},
    {" L ", " R ", ANYWHERE, "* L */* R *"},
    {"_L", "_R", SUFFIX, "*_L/*_R"},
    {"_l", "_r", SUFFIX, "*_l/*_r"},
    {".L", ".R", SUFFIX, "*.L/*.R"},
    {".l", ".r", SUFFIX, "*.l/*.r"},
    {"l_", "r_", PREFIX, "l_*/r_*"},
    {"L_", "R_", PREFIX, "L_*/R_*"},
    {"L", "R", PREFIX_CAPITAL, "LXxx/RXxx"},
    {"l", "r", PREFIX_CAPITAL, "lXxx/rXxx"},
};
#define PATTERN_COUNT ((int)(sizeof patterns / sizeof patterns[0]))

typedef struct name_info {
    int side;    /* 0: none, 1: left, 2: right */
    int pattern; /* index into patterns, -1 */
    int ns;      /* length of the namespace ("mixamorig:"), 0 without */
    char base[MM_NAME_MAX];
} name_info;

static void parse_name(const char *full, name_info *out)
{
    const char *colon = strrchr(full, ':');
    const char *name = colon ? colon + 1 : full;
    char rest[MM_NAME_MAX];
    size_t n = strlen(name);
    out->ns = (int)(name - full);
    out->side = 0;
    out->pattern = -1;
    snprintf(rest, sizeof rest, "%s", name);
    for (int p = 0; p < PATTERN_COUNT && !out->side; ++p)
        for (int s = 0; s < 2 && !out->side; ++s) {
            const char *tok = s ? patterns[p].right : patterns[p].left;
            size_t tl = strlen(tok);
            const char *at = NULL;
            if (n <= tl) continue;
            switch (patterns[p].kind) {
            case ANYWHERE:
                at = strstr(name, tok);
                break;
            case PREFIX:
                at = strncmp(name, tok, tl) == 0 ? name : NULL;
                break;
            case SUFFIX:
                at = strcmp(name + n - tl, tok) == 0 ? name + n - tl : NULL;
                break;
            default: /* a capital (or a digit) follows: LHipJoint, lAnkle, not LowerBack */
                at = strncmp(name, tok, tl) == 0 &&
                             (isupper((unsigned char)name[tl]) || isdigit((unsigned char)name[tl]))
                         ? name
                         : NULL;
                break;
            }
            if (at) {
                out->side = s + 1;
                out->pattern = p;
                snprintf(rest, sizeof rest, "%.*s%s", (int)(at - name), name, at + tl);
            }
        }
    size_t k = 0;
    for (const char *c = rest; *c && k + 1 < sizeof out->base; ++c)
        if (isalnum((unsigned char)*c)) out->base[k++] = (char)tolower((unsigned char)*c);
    out->base[k] = 0;
}

static int has(const char *base, const char *word) { return strstr(base, word) != NULL; }

/* An end marker rather than a joint of its own (HeadTop_End, LeftToe_End, Head_Nub). */
static int end_word(const char *b)
{
    return has(b, "end") || has(b, "nub") || has(b, "tip") || has(b, "site") || has(b, "top");
}

static int finger_word(const char *b)
{
    return has(b, "thumb") || has(b, "index") || has(b, "middle") || has(b, "ring") || has(b, "pinky") ||
           has(b, "little") || has(b, "finger") || has(b, "carpal");
}

/* Kinds of part a name may say. */
enum part { PART_NONE, PART_HIPS, PART_FOOT, PART_TOE, PART_HAND, PART_HEAD, PART_SPINE };

static int name_part(const name_info *ni)
{
    const char *b = ni->base;
    if (!ni->side) {
        int spine = has(b, "spine") || has(b, "chest") || has(b, "torso") || has(b, "back");
        if ((strcmp(b, "hip") == 0 || has(b, "hips") || has(b, "pelvis")) && !spine) return PART_HIPS;
        if (has(b, "head") && !end_word(b)) return PART_HEAD;
        return spine ? PART_SPINE : PART_NONE;
    }
    if (end_word(b) || finger_word(b)) return PART_NONE;
    if (has(b, "toe") || has(b, "ball")) return PART_TOE;
    if (has(b, "foot") || has(b, "ankle")) return PART_FOOT;
    if (has(b, "hand") || has(b, "wrist")) return PART_HAND;
    return PART_NONE;
}

/* ---- the skeleton's shape --------------------------------------------------------------- */

typedef struct finder {
    const mm_skeleton *s;
    int jc;
    int *depth;
    unsigned char *leaf; /* [jc] no joint below */
    float *seg;          /* [jc] bone length: the joint's translation from its parent, first frame */
    float *longest;      /* [jc] longest chain of bones below the joint */
    int samples;
    mm_vec3 *pos;  /* [samples * jc] world positions */
    mm_vec3 *tip;  /* [samples * jc] End Site positions (the joint's own without one) */
    mm_quat *rot;  /* [samples * jc] world rotations */
    float *height; /* [jc] mean height of the tip above the body's lowest point */
    float stature; /* median extent of the body, m */
    name_info *names;
} finder;

static int lca(const finder *f, int a, int b)
{
    while (a != b && a >= 0 && b >= 0) {
        if (f->depth[a] >= f->depth[b])
            a = f->s->joints[a].parent;
        else
            b = f->s->joints[b].parent;
    }
    return a == b ? a : -1;
}

static int is_ancestor(const finder *f, int a, int j) /* a is j or above it */
{
    for (; j >= 0; j = f->s->joints[j].parent)
        if (j == a) return 1;
    return 0;
}

/* Length of the bones from ancestor a down to j. */
static float chain_length(const finder *f, int a, int j)
{
    float len = 0.0f;
    for (; j >= 0 && j != a; j = f->s->joints[j].parent) len += f->seg[j];
    return len;
}

#define CHAIN_MAX 256 /* joints in a limb or a spine: longer ones are not looked at */

/* The joints from just below ancestor a down to j, top first; returns how many (0 when over
 * CHAIN_MAX). */
static int path_below(const finder *f, int a, int j, int *out)
{
    int n = 0;
    for (int k = j; k >= 0 && k != a; k = f->s->joints[k].parent) ++n;
    if (n > CHAIN_MAX) return 0;
    int i = n;
    for (int k = j; k >= 0 && k != a; k = f->s->joints[k].parent) out[--i] = k;
    return n;
}

/* Index in chain[0..n-1] of the joint ending the later of the two longest bones (the foot after
 * thigh and shin), counting bones from chain[first] on. */
static int after_two_longest(const finder *f, const int *chain, int n, int first)
{
    int a = -1, b = -1; /* the longest, the second */
    for (int i = first; i < n; ++i) {
        float l = f->seg[chain[i]];
        if (a < 0 || l > f->seg[chain[a]]) {
            b = a;
            a = i;
        } else if (b < 0 || l > f->seg[chain[b]]) {
            b = i;
        }
    }
    if (a < 0) return n - 1;
    return b > a ? b : a;
}

/* Index in chain[0..n-1] of the last joint ending a long bone: at least 0.6 of the longest,
 * counting bones from chain[first] on (the hand, after the forearm; the fingers are short). */
static int last_long(const finder *f, const int *chain, int n, int first)
{
    float longest = 0.0f;
    for (int i = first; i < n; ++i) longest = fmaxf(longest, f->seg[chain[i]]);
    int last = n - 1;
    for (int i = first; i < n; ++i)
        if (f->seg[chain[i]] >= 0.6f * longest) last = i;
    return last;
}

/* The chain from the branch root c down the longest way to an end. */
static int longest_chain(const finder *f, int c, int *out)
{
    int n = 0;
    out[n++] = c;
    while (n < CHAIN_MAX) {
        int next = -1;
        float best = -1.0f;
        for (int k = c + 1; k < f->jc; ++k)
            if (f->s->joints[k].parent == c && f->seg[k] + f->longest[k] > best) {
                best = f->seg[k] + f->longest[k];
                next = k;
            }
        if (next < 0) break;
        out[n++] = c = next;
    }
    return n;
}

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

static mm_vec3 horizontal(mm_vec3 v) { return mm_vec3_make(v.x, 0.0f, v.z); }

/* Samples poses over all takes: positions, End Sites, rotations. */
static void sample_poses(finder *f, const mm_clip *takes, int count, mm_xform *g)
{
    long total = 0;
    for (int t = 0; t < count; ++t) total += takes[t].frame_count;
    int n = total < MAX_SAMPLES ? (int)total : MAX_SAMPLES;
    f->samples = n;
    for (int k = 0; k < n; ++k) {
        long at = (long)((k + 0.5) * (double)total / n);
        int t = 0;
        while (t < count - 1 && at >= takes[t].frame_count) at -= takes[t++].frame_count;
        mm_clip_fk(&takes[t], (int)at, g);
        for (int j = 0; j < f->jc; ++j) {
            f->pos[k * f->jc + j] = g[j].translation;
            f->rot[k * f->jc + j] = g[j].rotation;
            f->tip[k * f->jc + j] = f->s->joints[j].has_end_site
                                        ? mm_xform_apply_point(g[j], f->s->joints[j].end_site)
                                        : g[j].translation;
        }
    }
    float *extent = (float *)malloc(sizeof(float) * (size_t)(n > 0 ? n : 1));
    for (int j = 0; j < f->jc; ++j) f->height[j] = 0.0f;
    for (int k = 0; k < n; ++k) {
        float lo = INFINITY, hi = -INFINITY;
        for (int j = 0; j < f->jc; ++j) {
            lo = fminf(lo, fminf(f->pos[k * f->jc + j].y, f->tip[k * f->jc + j].y));
            hi = fmaxf(hi, fmaxf(f->pos[k * f->jc + j].y, f->tip[k * f->jc + j].y));
        }
        for (int j = 0; j < f->jc; ++j) f->height[j] += (f->tip[k * f->jc + j].y - lo) / (float)n;
        if (extent) extent[k] = hi - lo;
    }
    f->stature = 0.0f;
    if (extent && n > 0) {
        qsort(extent, (size_t)n, sizeof(float), cmp_float); /* upright for a tenth of the time */
        f->stature = extent[(int)(0.9f * (float)(n - 1))];
    }
    free(extent);
}

/* ---- combining the evidence ------------------------------------------------------------- */

/* The joint a name points at for part (and side), preferring one of chain[0..n-1], then the one
 * nearest the root. *on_chain: whether it is on the chain. */
static int name_pick(const finder *f, int part, int side, const int *chain, int n, int *on_chain)
{
    int best = -1, best_on = 0;
    for (int j = 0; j < f->jc; ++j) {
        if (name_part(&f->names[j]) != part || (side && f->names[j].side != side)) continue;
        int on = 0;
        for (int i = 0; i < n; ++i) on |= chain[i] == j;
        if (best < 0 || on > best_on || (on == best_on && f->depth[j] < f->depth[best])) {
            best = j;
            best_on = on;
        }
    }
    *on_chain = best_on;
    return best;
}

static void decide(mm_role_match *m, int geo, int named, int named_on_chain)
{
    m->joint = -1;
    m->confidence = 0.0f;
    m->evidence = m->conflict = 0;
    m->other = -1;
    if (geo >= 0 && named == geo) {
        m->joint = geo;
        m->confidence = 1.0f;
        m->evidence = MM_EVIDENCE_NAME | MM_EVIDENCE_GEOMETRY;
    } else if (geo >= 0 && named >= 0 && named_on_chain) { /* the name refines geometry's limb */
        m->joint = named;
        m->confidence = 0.9f;
        m->evidence = MM_EVIDENCE_NAME | MM_EVIDENCE_GEOMETRY;
        m->conflict = MM_EVIDENCE_GEOMETRY;
        m->other = geo;
    } else if (geo >= 0 && named >= 0) {
        m->joint = geo;
        m->confidence = 0.4f;
        m->evidence = MM_EVIDENCE_GEOMETRY;
        m->conflict = MM_EVIDENCE_NAME;
        m->other = named;
    } else if (geo >= 0) {
        m->joint = geo;
        m->confidence = 0.8f;
        m->evidence = MM_EVIDENCE_GEOMETRY;
    } else if (named >= 0) {
        m->joint = named;
        m->confidence = 0.6f;
        m->evidence = MM_EVIDENCE_NAME;
    }
}

/* Snaps a unit vector to the nearest of +-X, +-Y, +-Z when within SNAP_DEGREES. */
static mm_vec3 snap_axis(mm_vec3 v)
{
    float c[3] = {v.x, v.y, v.z};
    int a = 0;
    for (int i = 1; i < 3; ++i)
        if (fabsf(c[i]) > fabsf(c[a])) a = i;
    if (fabsf(c[a]) < cosf(SNAP_DEGREES * (float)(MM_PI / 180.0))) {
        for (int i = 0; i < 3; ++i) c[i] = roundf(c[i] * 1000.0f) / 1000.0f;
        return mm_vec3_make(c[0], c[1], c[2]);
    }
    float s[3] = {0.0f, 0.0f, 0.0f};
    s[a] = c[a] > 0.0f ? 1.0f : -1.0f;
    return mm_vec3_make(s[0], s[1], s[2]);
}

static float degrees_between(mm_vec3 a, mm_vec3 b)
{
    float la = mm_vec3_length(a), lb = mm_vec3_length(b);
    if (!(la > 0.0f) || !(lb > 0.0f)) return -1.0f;
    float c = mm_vec3_dot(a, b) / (la * lb);
    c = c > 1.0f ? 1.0f : c < -1.0f ? -1.0f : c;
    return acosf(c) * (float)(180.0 / MM_PI);
}

/* Where the body travels, in the hips' frame: the sum of unit travel directions over the frames
 * where the hips move faster than TRAVEL_SPEED; *seconds: how long that is. */
static mm_vec3 travel_direction(const mm_clip *takes, int count, int hips, mm_xform *g, float *seconds)
{
    mm_vec3 sum = mm_vec3_make(0, 0, 0);
    long total = 0;
    *seconds = 0.0f;
    for (int t = 0; t < count; ++t) total += takes[t].frame_count;
    int stride = total > 4000 ? (int)(total / 4000) : 1;
    for (int t = 0; t < count; ++t) {
        const mm_clip *c = &takes[t];
        int h = (int)lroundf(TRAVEL_HALFWINDOW * c->fps);
        if (h < 1) h = 1;
        for (int fr = h; fr + h < c->frame_count; fr += stride) {
            mm_clip_fk(c, fr - h, g);
            mm_vec3 a = g[hips].translation;
            mm_clip_fk(c, fr + h, g);
            mm_vec3 v = mm_vec3_scale(horizontal(mm_vec3_sub(g[hips].translation, a)), c->fps / (2.0f * h));
            float speed = mm_vec3_length(v);
            if (!(speed > TRAVEL_SPEED)) continue;
            mm_clip_fk(c, fr, g);
            sum = mm_vec3_add(sum, mm_quat_inv_rotate(g[hips].rotation, mm_vec3_scale(v, 1.0f / speed)));
            *seconds += (float)stride / c->fps;
        }
    }
    return sum;
}

/* ---- mirror pairs ----------------------------------------------------------------------- */

static void find_mirror_pairs(const finder *f, mm_skeleton_roles *out)
{
    int used[PATTERN_COUNT] = {0}, ns = 0;
    for (int j = 0; j < f->jc; ++j) {
        const name_info *a = &f->names[j];
        if (a->side != 1) continue;
        if (a->ns) ns = 1;
        for (int k = 0; k < f->jc; ++k) {
            const name_info *b = &f->names[k];
            if (b->side == 2 && b->pattern == a->pattern && strcmp(a->base, b->base) == 0)
                used[a->pattern] = 1;
        }
    }
    out->mirror_pair_count = 0;
    out->naming[0] = 0;
    for (int p = 0; p < PATTERN_COUNT && out->mirror_pair_count < MM_MAX_MIRROR_PAIRS; ++p) {
        if (!used[p]) continue;
        mm_config_mirror_pair *mp = &out->mirror_pairs[out->mirror_pair_count++];
        int anchored = patterns[p].kind == PREFIX || patterns[p].kind == PREFIX_CAPITAL;
        const char *lead = anchored ? (ns ? ":" : "^") : "";
        snprintf(mp->left, MM_NAME_MAX, "%s%s", lead, patterns[p].left);
        snprintf(mp->right, MM_NAME_MAX, "%s%s", lead, patterns[p].right);
        size_t len = strlen(out->naming);
        snprintf(out->naming + len, sizeof out->naming - len, "%s%s", len ? ", " : "", patterns[p].text);
    }
    out->paired_joints = out->unpaired_joints = 0;
    out->mirror = false;
    out->mirror_confidence = 0.0f;
    if (!out->mirror_pair_count) return;
    mm_config cfg;
    memset(&cfg, 0, sizeof cfg);
    cfg.mirror_pair_count = out->mirror_pair_count;
    memcpy(cfg.mirror_pairs, out->mirror_pairs, sizeof cfg.mirror_pairs);
    int *partner = (int *)malloc(sizeof(int) * (size_t)f->jc);
    if (!partner) return;
    mm__mirror_map(f->s, &cfg, partner);
    int symmetric = 0;
    for (int j = 0; j < f->jc; ++j) {
        int k = partner[j], side = f->names[j].side;
        int ok = side ? (k != j && partner[k] == j && f->names[k].side == 3 - side) : k == j;
        if (!ok)
            ++out->unpaired_joints;
        else if (side) {
            ++out->paired_joints;
            float a = f->seg[j], b = f->seg[k];
            if (fabsf(a - b) <= 0.05f * fmaxf(fmaxf(a, b), 0.01f * f->stature)) ++symmetric;
        }
    }
    const mm_role_match *r = out->roles;
    int limbs = 1;
    for (int i = MM_BODY_LEFT_FOOT; i <= MM_BODY_LEFT_HAND; i += 2) {
        int a = r[i].joint, b = r[i + 1].joint;
        if (a >= 0 && b >= 0 && a != b && partner[a] != b) limbs = 0;
    }
    free(partner);
    out->mirror = out->unpaired_joints == 0 && out->paired_joints > 0 && limbs;
    if (out->mirror) out->mirror_confidence = 0.5f + 0.5f * (float)symmetric / (float)out->paired_joints;
}

/* ---- the finder ------------------------------------------------------------------------- */

static mm_result same_skeleton(const mm_clip *takes, int count, mm_error *err)
{
    const mm_skeleton *a = &takes[0].skeleton;
    for (int t = 1; t < count; ++t) {
        const mm_skeleton *b = &takes[t].skeleton;
        int same = a->joint_count == b->joint_count;
        for (int j = 0; same && j < a->joint_count; ++j)
            same = a->joints[j].parent == b->joints[j].parent &&
                   strcmp(a->joints[j].name, b->joints[j].name) == 0;
        if (!same)
            return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0,
                                "take %d has another skeleton than take 0 (joints or names differ)", t);
    }
    return MM_OK;
}

/* Side of chain a against chain b in the sampled poses: +1 when a is on the left (the +X side
 * when facing +Z); *agree: the fraction of poses that say so. */
static int chain_side(const finder *f, const int *a, int na, const int *b, int nb, const mm_vec3 *forward,
                      float *agree)
{
    int left = 0, right = 0;
    for (int k = 0; k < f->samples; ++k) {
        mm_vec3 fw = forward[k];
        if (mm_vec3_length(fw) < 0.5f) continue;
        mm_vec3 ma = mm_vec3_make(0, 0, 0), mb = mm_vec3_make(0, 0, 0);
        for (int i = 0; i < na; ++i) ma = mm_vec3_add(ma, mm_vec3_scale(f->pos[k * f->jc + a[i]], 1.0f / na));
        for (int i = 0; i < nb; ++i) mb = mm_vec3_add(mb, mm_vec3_scale(f->pos[k * f->jc + b[i]], 1.0f / nb));
        mm_vec3 leftward = mm_vec3_make(fw.z, 0.0f, -fw.x); /* up x forward */
        float d = mm_vec3_dot(mm_vec3_sub(ma, mb), leftward);
        if (d > 0.0f)
            ++left;
        else if (d < 0.0f)
            ++right;
    }
    if (left + right == 0) {
        *agree = 0.0f;
        return 0;
    }
    *agree = (float)(left > right ? left : right) / (float)(left + right);
    return left >= right ? 1 : -1;
}

/* Side the names of a chain's joints say: +1 left, -1 right, 0 none or a tie. */
static int chain_name_side(const finder *f, const int *chain, int n)
{
    int votes = 0;
    for (int i = 0; i < n; ++i)
        votes += f->names[chain[i]].side == 1 ? 1 : f->names[chain[i]].side == 2 ? -1 : 0;
    return votes > 0 ? 1 : votes < 0 ? -1 : 0;
}

typedef struct limb {
    int chain[CHAIN_MAX];
    int n;
    int end; /* the foot or hand geometry picks (index into chain) */
} limb;

static mm_result find_roles(finder *f, const mm_clip *takes, int count, mm_xform *g, mm_skeleton_roles *out,
                            mm_error *err)
{
    const mm_skeleton *s = f->s;
    int jc = f->jc;
    float T = f->stature > 0.0f ? f->stature : 1.7f;
    /* legs: the lowest end, and the lowest end of another chain that parts well above it */
    int A = -1, B = -1;
    for (int j = 0; j < jc; ++j) {
        if (!f->leaf[j]) continue;
        if (A < 0 || f->height[j] < f->height[A]) A = j;
    }
    for (int j = 0; A >= 0 && j < jc; ++j) {
        if (!f->leaf[j] || j == A) continue;
        int c = lca(f, A, j);
        if (c < 0 || chain_length(f, c, A) < 0.25f * T || chain_length(f, c, j) < 0.25f * T) continue;
        if (f->height[j] > 0.25f * T) continue; /* not down at the ground */
        if (B < 0 || f->height[j] < f->height[B]) B = j;
    }
    int top = -1; /* the highest end: the head */
    for (int j = 0; j < jc; ++j)
        if (f->leaf[j] && (top < 0 || f->height[j] > f->height[top])) top = j;
    int legs_at = A >= 0 && B >= 0 ? lca(f, A, B) : -1;
    int hips_geo = legs_at >= 0 && top >= 0 ? lca(f, legs_at, top) : -1;
    if (hips_geo >= 0 && (hips_geo == top || is_ancestor(f, top, A))) hips_geo = -1;

    /* hips */
    int root_path[CHAIN_MAX] = {0}, nroot = 0;
    for (int j = hips_geo; j >= 0 && nroot < CHAIN_MAX; j = s->joints[j].parent) root_path[nroot++] = j;
    int on = 0, named = name_pick(f, PART_HIPS, 0, root_path, nroot, &on);
    decide(&out->roles[MM_BODY_HIPS], hips_geo, named, on);
    int hips = out->roles[MM_BODY_HIPS].joint;
    if (hips < 0)
        return mm_error_set(err, MM_ERR_NOT_FOUND, 0, 0,
                            "no hips: no joint is named as hips or pelvis and no two legs meet a spine");

    /* legs and arms from geometry: chains below the hips / the chest */
    limb leg[2], arm[2];
    int have_legs = 0, have_arms = 0;
    if (hips_geo >= 0) {
        int ends[2] = {A, B};
        for (int i = 0; i < 2; ++i) {
            leg[i].n = path_below(f, legs_at, ends[i], leg[i].chain);
            leg[i].end = after_two_longest(f, leg[i].chain, leg[i].n, 0);
        }
        have_legs = leg[0].n > 0 && leg[1].n > 0;
    }
    int spine[CHAIN_MAX], nspine = 0;
    if (top >= 0 && is_ancestor(f, hips, top)) nspine = path_below(f, hips, top, spine);
    if (nspine > 0) {
        /* the arms: the two longest branches off the spine above the hips */
        int c1 = -1, c2 = -1;
        float l1 = 0.0f, l2 = 0.0f;
        for (int k = 0; k < jc; ++k) {
            int p = s->joints[k].parent, on_spine = 0, is_spine = 0;
            for (int i = 0; i < nspine; ++i) {
                on_spine |= spine[i] == p;
                is_spine |= spine[i] == k;
            }
            if (!on_spine || is_spine) continue;
            float l = f->seg[k] + f->longest[k];
            if (l < 0.25f * T) continue;
            if (l > l1) {
                c2 = c1;
                l2 = l1;
                c1 = k;
                l1 = l;
            } else if (l > l2) {
                c2 = k;
                l2 = l;
            }
        }
        if (c1 >= 0 && c2 >= 0) {
            int cs[2] = {c1, c2};
            for (int i = 0; i < 2; ++i) {
                arm[i].n = longest_chain(f, cs[i], arm[i].chain);
                arm[i].end = last_long(f, arm[i].chain, arm[i].n, 1);
            }
            have_arms = 1;
        }
    }

    /* forward: where the toes point (geometry) and where the body travels (motion), in the hips'
     * frame */
    mm_vec3 toes = mm_vec3_make(0, 0, 0);
    if (have_legs)
        for (int k = 0; k < f->samples; ++k) {
            mm_vec3 d = mm_vec3_make(0, 0, 0);
            int n = 0;
            for (int i = 0; i < 2; ++i) {
                int foot = leg[i].chain[leg[i].end];
                int toe = leg[i].end + 1 < leg[i].n ? leg[i].chain[leg[i].end + 1] : -1;
                mm_vec3 a = f->pos[k * jc + foot];
                mm_vec3 b = toe >= 0 ? f->pos[k * jc + toe] : f->tip[k * jc + foot];
                if (toe < 0 && !s->joints[foot].has_end_site) continue;
                d = mm_vec3_add(d, horizontal(mm_vec3_sub(b, a)));
                ++n;
            }
            if (n == 0 || mm_vec3_length(d) < 1e-3f * T) continue;
            d = mm_vec3_normalize(d);
            toes = mm_vec3_add(toes, mm_quat_inv_rotate(f->rot[k * jc + hips], d));
        }
    float travel_seconds = 0.0f;
    mm_vec3 travel = travel_direction(takes, count, hips, g, &travel_seconds);
    int have_toes = mm_vec3_length(toes) > 0.2f * f->samples, have_travel = travel_seconds >= 0.5f;
    mm_vec3 tu = have_toes ? mm_vec3_normalize(toes) : toes,
            mu = have_travel ? mm_vec3_normalize(travel) : travel;
    mm_vec3 fwd = mm_vec3_make(0, 0, 1);
    out->forward_evidence = 0;
    float between = have_toes && have_travel ? degrees_between(tu, mu) : -1.0f;
    if (have_toes && have_travel && between < 60.0f) {
        fwd = snap_axis(mm_vec3_normalize(mm_vec3_add(tu, mu)));
        out->forward_evidence = MM_EVIDENCE_GEOMETRY | MM_EVIDENCE_MOTION;
    } else if (have_toes) {
        fwd = snap_axis(tu);
        out->forward_evidence = MM_EVIDENCE_GEOMETRY;
    } else if (have_travel) {
        fwd = snap_axis(mu);
        out->forward_evidence = MM_EVIDENCE_MOTION;
    }
    out->forward_axis = fwd;
    out->forward_toes_degrees = have_toes ? degrees_between(fwd, tu) : -1.0f;
    out->forward_travel_degrees = have_travel ? degrees_between(fwd, mu) : -1.0f;
    out->travel_seconds = travel_seconds;
    {
        int sources = (have_toes ? 1 : 0) + (have_travel ? 1 : 0), close = 0;
        if (have_toes && out->forward_toes_degrees < SNAP_DEGREES) ++close;
        if (have_travel && out->forward_travel_degrees < SNAP_DEGREES) ++close;
        out->forward_confidence = sources == 0                 ? 0.0f
                                  : close == 2                 ? 1.0f
                                  : close == 1 && sources == 1 ? 0.8f
                                  : close == 1                 ? 0.5f
                                                               : 0.3f;
    }

    /* sides: left = up x forward, forward the hips' forward axis in each pose */
    mm_vec3 *facing = (mm_vec3 *)malloc(sizeof(mm_vec3) * (size_t)(f->samples > 0 ? f->samples : 1));
    if (!facing) return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    for (int k = 0; k < f->samples; ++k) {
        mm_vec3 d = horizontal(mm_quat_rotate(f->rot[k * jc + hips], fwd));
        facing[k] = mm_vec3_length(d) > 1e-3f ? mm_vec3_normalize(d) : mm_vec3_make(0, 0, 0);
    }
    float leg_agree = 1.0f, arm_agree = 1.0f;
    int leg_geo =
        have_legs ? chain_side(f, leg[0].chain, leg[0].n, leg[1].chain, leg[1].n, facing, &leg_agree) : 0;
    int arm_geo =
        have_arms ? chain_side(f, arm[0].chain, arm[0].n, arm[1].chain, arm[1].n, facing, &arm_agree) : 0;
    free(facing);
    int leg_name = have_legs ? chain_name_side(f, leg[0].chain, leg[0].n) : 0;
    int arm_name = have_arms ? chain_name_side(f, arm[0].chain, arm[0].n) : 0;
    int leg_left = leg_name ? leg_name : leg_geo, arm_left = arm_name ? arm_name : arm_geo;
    out->sides_from_names = leg_name != 0 || arm_name != 0;
    out->side_agreement = fminf(have_legs ? leg_agree : 1.0f, have_arms ? arm_agree : 1.0f);
    int leg_conflict = leg_name && leg_geo && leg_name != leg_geo;
    int arm_conflict = arm_name && arm_geo && arm_name != arm_geo;

    /* feet, toes, hands */
    for (int side = 1; side <= 2; ++side) {
        const limb *l = NULL, *a = NULL;
        if (have_legs && leg_left) l = &leg[(leg_left > 0) == (side == 1) ? 0 : 1];
        if (have_arms && arm_left) a = &arm[(arm_left > 0) == (side == 1) ? 0 : 1];
        int r_foot = side == 1 ? MM_BODY_LEFT_FOOT : MM_BODY_RIGHT_FOOT;
        int r_toe = side == 1 ? MM_BODY_LEFT_TOE : MM_BODY_RIGHT_TOE;
        int r_hand = side == 1 ? MM_BODY_LEFT_HAND : MM_BODY_RIGHT_HAND;
        int geo = l ? l->chain[l->end] : -1;
        named = name_pick(f, PART_FOOT, side, l ? l->chain : NULL, l ? l->n : 0, &on);
        decide(&out->roles[r_foot], geo, named, on);
        int foot = out->roles[r_foot].joint;
        /* the toe: the foot's next joint down the leg */
        int toe_geo = -1;
        if (l)
            for (int i = 0; i + 1 < l->n; ++i)
                if (l->chain[i] == foot) toe_geo = l->chain[i + 1];
        named = name_pick(f, PART_TOE, side, l ? l->chain : NULL, l ? l->n : 0, &on);
        decide(&out->roles[r_toe], toe_geo, named, on);
        geo = a ? a->chain[a->end] : -1;
        named = name_pick(f, PART_HAND, side, a ? a->chain : NULL, a ? a->n : 0, &on);
        decide(&out->roles[r_hand], geo, named, on);
        for (int r = 0; r < 3; ++r) {
            mm_role_match *m = &out->roles[r == 0 ? r_foot : r == 1 ? r_toe : r_hand];
            int conflict = r < 2 ? leg_conflict : arm_conflict;
            float agree = r < 2 ? leg_agree : arm_agree;
            if (conflict) {
                m->conflict |= MM_EVIDENCE_GEOMETRY;
                m->confidence *= 0.6f;
            } else if (!(m->evidence & MM_EVIDENCE_NAME)) {
                m->confidence *= agree;
            }
        }
    }

    /* head: the top of the spine */
    named = name_pick(f, PART_HEAD, 0, spine, nspine, &on);
    decide(&out->roles[MM_BODY_HEAD], nspine > 0 ? top : -1, named, on);

    /* root bone: the chest, where the arms leave the spine; else 60% of the way up to the head */
    int chest = -1;
    if (have_arms) chest = lca(f, arm[0].chain[0], arm[1].chain[0]);
    if (chest >= 0 && !is_ancestor(f, hips, chest)) chest = -1;
    mm_role_match *rb = &out->roles[MM_BODY_ROOT_BONE];
    memset(rb, 0, sizeof *rb);
    rb->other = -1;
    if (chest >= 0 && chest != hips) {
        rb->joint = chest;
        rb->evidence = MM_EVIDENCE_GEOMETRY;
        rb->confidence = 0.8f;
        if (name_part(&f->names[chest]) == PART_SPINE) {
            rb->evidence |= MM_EVIDENCE_NAME;
            rb->confidence = 1.0f;
        }
    } else {
        int head = out->roles[MM_BODY_HEAD].joint, path[CHAIN_MAX];
        int n = head >= 0 && is_ancestor(f, hips, head) ? path_below(f, hips, head, path) : 0;
        float total = n ? chain_length(f, hips, head) : 0.0f;
        rb->joint = -1;
        for (int i = 0; i < n && rb->joint < 0; ++i)
            if (chain_length(f, hips, path[i]) >= 0.6f * total) rb->joint = path[i];
        if (rb->joint < 0 && n > 0) rb->joint = path[0];
        if (rb->joint >= 0) {
            rb->evidence = MM_EVIDENCE_GEOMETRY;
            rb->confidence = 0.5f;
        }
    }
    out->roles[MM_BODY_FACING_BONE] = out->roles[MM_BODY_HIPS];

    static const int needed[] = {MM_BODY_LEFT_FOOT,  MM_BODY_RIGHT_FOOT, MM_BODY_LEFT_HAND,
                                 MM_BODY_RIGHT_HAND, MM_BODY_HEAD,       MM_BODY_ROOT_BONE};
    for (size_t i = 0; i < sizeof needed / sizeof needed[0]; ++i)
        if (out->roles[needed[i]].joint < 0)
            return mm_error_set(err, MM_ERR_NOT_FOUND, 0, 0,
                                "no %s: no joint is named so and the skeleton's shape does not show one",
                                mm_body_role_name((mm_body_role)needed[i]));
    if (out->roles[MM_BODY_LEFT_FOOT].joint == out->roles[MM_BODY_RIGHT_FOOT].joint ||
        out->roles[MM_BODY_LEFT_HAND].joint == out->roles[MM_BODY_RIGHT_HAND].joint)
        return mm_error_set(
            err, MM_ERR_NOT_FOUND, 0, 0, "the left and right %s are the same joint",
            out->roles[MM_BODY_LEFT_FOOT].joint == out->roles[MM_BODY_RIGHT_FOOT].joint ? "feet" : "hands");
    return MM_OK;
}

mm_result mm_skeleton_roles_find(const mm_clip *takes, int count, mm_skeleton_roles *out, mm_error *err)
{
    memset(out, 0, sizeof *out);
    for (int i = 0; i < MM_BODY_ROLE_COUNT; ++i) out->roles[i].joint = out->roles[i].other = -1;
    if (!takes || count < 1)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no takes to find the roles in");
    mm_result r = same_skeleton(takes, count, err);
    if (r != MM_OK) return r;
    const mm_skeleton *s = &takes[0].skeleton;
    int jc = s->joint_count;
    if (jc < 1) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "the skeleton has no joints");
    finder f;
    memset(&f, 0, sizeof f);
    f.s = s;
    f.jc = jc;
    size_t per = (size_t)MAX_SAMPLES * (size_t)jc;
    f.depth = (int *)calloc((size_t)jc, sizeof(int));
    f.seg = (float *)calloc((size_t)jc, sizeof(float));
    f.longest = (float *)calloc((size_t)jc, sizeof(float));
    f.height = (float *)calloc((size_t)jc, sizeof(float));
    f.pos = (mm_vec3 *)malloc(sizeof(mm_vec3) * per);
    f.tip = (mm_vec3 *)malloc(sizeof(mm_vec3) * per);
    f.rot = (mm_quat *)malloc(sizeof(mm_quat) * per);
    f.names = (name_info *)calloc((size_t)jc, sizeof(name_info));
    f.leaf = (unsigned char *)malloc((size_t)jc);
    mm_xform *g = (mm_xform *)malloc(sizeof(mm_xform) * (size_t)jc);
    if (!f.depth || !f.seg || !f.longest || !f.height || !f.pos || !f.tip || !f.rot || !f.names || !f.leaf ||
        !g) {
        r = mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    } else {
        const mm_vec3 *first = takes[0].frame_count > 0 ? mm_clip_positions(&takes[0], 0) : NULL;
        for (int j = 0; j < jc; ++j) {
            int p = s->joints[j].parent;
            f.depth[j] = p >= 0 ? f.depth[p] + 1 : 0;
            f.seg[j] = p >= 0 ? mm_vec3_length(first ? first[j] : s->joints[j].offset) : 0.0f;
            parse_name(s->joints[j].name, &f.names[j]);
        }
        memset(f.leaf, 1, (size_t)jc);
        for (int j = 1; j < jc; ++j) f.leaf[s->joints[j].parent] = 0;
        for (int j = jc - 1; j > 0; --j) {
            int p = s->joints[j].parent;
            f.longest[p] = fmaxf(f.longest[p], f.seg[j] + f.longest[j]);
        }
        sample_poses(&f, takes, count, g);
        out->stature = f.stature;
        if (f.samples < 1) r = mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "the takes have no frames");
        if (r == MM_OK) r = find_roles(&f, takes, count, g, out, err);
        if (r == MM_OK) find_mirror_pairs(&f, out);
    }
    free(f.depth);
    free(f.seg);
    free(f.longest);
    free(f.height);
    free(f.pos);
    free(f.tip);
    free(f.rot);
    free(f.names);
    free(f.leaf);
    free(g);
    return r;
}

void mm_skeleton_roles_apply(const mm_skeleton_roles *roles, const mm_skeleton *skeleton, mm_config *cfg)
{
    char *fields[MM_BODY_ROLE_COUNT] = {cfg->hips,       cfg->root_bone, cfg->facing_bone, cfg->left_foot,
                                        cfg->right_foot, cfg->left_toe,  cfg->right_toe,   cfg->left_hand,
                                        cfg->right_hand, cfg->head};
    for (int i = 0; i < MM_BODY_ROLE_COUNT; ++i) {
        int j = roles->roles[i].joint;
        /* without a toe joint the toe contact is the ankle's */
        if (j < 0 && (i == MM_BODY_LEFT_TOE || i == MM_BODY_RIGHT_TOE)) j = roles->roles[i - 2].joint;
        if (j >= 0 && j < skeleton->joint_count)
            snprintf(fields[i], MM_NAME_MAX, "%s", skeleton->joints[j].name);
    }
    cfg->forward_axis = roles->forward_axis;
    cfg->bone_count = 3;
    memset(cfg->bones, 0, sizeof cfg->bones[0] * 3);
    snprintf(cfg->bones[0].name, MM_NAME_MAX, "%s", cfg->left_foot);
    snprintf(cfg->bones[1].name, MM_NAME_MAX, "%s", cfg->right_foot);
    snprintf(cfg->bones[2].name, MM_NAME_MAX, "%s", cfg->hips);
    for (int i = 0; i < 2; ++i) {
        cfg->bones[i].features = MM_MATCH_POSITION | MM_MATCH_VELOCITY;
        cfg->bones[i].position_weight = 0.75f;
        cfg->bones[i].velocity_weight = 1.0f;
    }
    cfg->bones[2].features = MM_MATCH_VELOCITY;
    cfg->bones[2].velocity_weight = 1.0f;
    if (roles->mirror) {
        cfg->mirror_pair_count = roles->mirror_pair_count;
        memcpy(cfg->mirror_pairs, roles->mirror_pairs, sizeof cfg->mirror_pairs);
    }
}

const char *mm_body_role_name(mm_body_role role)
{
    static const char *const names[MM_BODY_ROLE_COUNT] = {
        "hips",     "root_bone", "facing_bone", "left_foot",  "right_foot",
        "left_toe", "right_toe", "left_hand",   "right_hand", "head"};
    return (int)role >= 0 && role < MM_BODY_ROLE_COUNT ? names[role] : NULL;
}

const char *mm_axis_name(int axis)
{
    static const char *const names[6] = {"+X", "+Y", "+Z", "-X", "-Y", "-Z"};
    return axis >= 0 && axis < 6 ? names[axis] : NULL;
}

/* Joints with two children or more between the root and j (the root left out): the spine carries
 * the arms and the neck, a leg carries nothing. */
static int branches_above(const mm_skeleton *s, const int *children, int j)
{
    int n = 0;
    for (j = s->joints[j].parent; j > 0; j = s->joints[j].parent) n += children[j] >= 2;
    return n;
}

int mm_clip_up_axis(const mm_clip *clip, float *out_confidence)
{
    const mm_skeleton *s = &clip->skeleton;
    int jc = s->joint_count, n = clip->frame_count < 32 ? clip->frame_count : 32;
    if (out_confidence) *out_confidence = 0.0f;
    if (jc < 2) return 1;
    int samples = n > 0 ? n : 1;
    mm_xform *g = (mm_xform *)malloc(sizeof(mm_xform) * (size_t)jc);
    float *ext = (float *)malloc(sizeof(float) * 3 * (size_t)samples);
    int *children = (int *)calloc((size_t)jc, sizeof(int));
    if (!g || !ext || !children) {
        free(g);
        free(ext);
        free(children);
        return 1;
    }
    for (int j = 1; j < jc; ++j) children[s->joints[j].parent]++;
    /* per axis: +1 when the end at the + side hangs from more branches than the end at the - side
     * (it is the head's, or a hand's), -1 the other way; near: the root nearer the + end (the
     * legs are longer than the trunk and head) */
    long votes[3] = {0, 0, 0}, near[3] = {0, 0, 0};
    for (int k = 0; k < samples; ++k) {
        if (n > 0)
            mm_clip_fk(clip, (int)((k + 0.5) * clip->frame_count / samples), g);
        else
            mm_fk(s, NULL, NULL, g);
        float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        int jlo[3] = {0, 0, 0}, jhi[3] = {0, 0, 0};
        float root[3] = {g[0].translation.x, g[0].translation.y, g[0].translation.z};
        for (int j = 0; j < jc; ++j) {
            mm_vec3 p[2] = {g[j].translation, s->joints[j].has_end_site
                                                  ? mm_xform_apply_point(g[j], s->joints[j].end_site)
                                                  : g[j].translation};
            for (int e = 0; e < 2; ++e) {
                float c[3] = {p[e].x, p[e].y, p[e].z};
                for (int a = 0; a < 3; ++a) {
                    if (c[a] < lo[a]) {
                        lo[a] = c[a];
                        jlo[a] = j;
                    }
                    if (c[a] > hi[a]) {
                        hi[a] = c[a];
                        jhi[a] = j;
                    }
                }
            }
        }
        for (int a = 0; a < 3; ++a) {
            ext[a * samples + k] = hi[a] - lo[a];
            int up = branches_above(s, children, jhi[a]), down = branches_above(s, children, jlo[a]);
            votes[a] += up > down ? 1 : up < down ? -1 : 0;
            near[a] += hi[a] - root[a] < root[a] - lo[a] ? 1 : -1;
        }
    }
    float med[3];
    for (int a = 0; a < 3; ++a) {
        qsort(ext + a * samples, (size_t)samples, sizeof(float), cmp_float);
        med[a] = ext[a * samples + samples / 2];
    }
    int best = 0;
    for (int a = 1; a < 3; ++a)
        if (med[a] > med[best]) best = a;
    float second = 0.0f;
    for (int a = 0; a < 3; ++a)
        if (a != best) second = fmaxf(second, med[a]);
    if (out_confidence) *out_confidence = med[best] > 0.0f ? 1.0f - second / med[best] : 0.0f;
    int negative = votes[best] < 0 || (votes[best] == 0 && near[best] < 0);
    free(g);
    free(ext);
    free(children);
    return best + (negative ? 3 : 0);
}
