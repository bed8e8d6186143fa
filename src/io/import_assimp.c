/* FBX, glTF, Collada and the other formats assimp reads: every aiAnimation becomes a clip.
 *
 * This is the only file of the library that includes assimp's headers; it is compiled only when
 * mm is built with assimp (MM_HAVE_ASSIMP). All arithmetic is in double precision until the
 * clip's floats are written.
 *
 * For each take:
 *   1. channels are matched to nodes by name; a channel on one of assimp's FBX pivot helpers
 *      ("Name_$AssimpFbx$_Rotation" ...) counts for the real node the helper chain leads to;
 *   2. joints are the animated real nodes and the real nodes between them and their lowest common
 *      ancestor, in depth-first (topological) order;
 *   3. a joint's local transform is the product of every node from its parent joint (exclusive)
 *      down to it, each node animated (its channel sampled) or static (its mTransformation); the
 *      root joint's product starts at the scene root, so world positions match assimp's;
 *   4. world transforms are turned to Y up, positions kept exactly and rotations stripped of scale
 *      (Gram-Schmidt), then made local again: mm_fk reproduces every world joint position. */
#define _POSIX_C_SOURCE 200809L
#include <mm/import.h>

#include <assimp/cimport.h>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/file.h"
#include "io/import_private.h"

#define MAX_NODES  (1 << 22)
#define HELPER_TAG "$AssimpFbx$"

/* ---- double-precision math -------------------------------------------------------------- */

typedef struct dmat4 {
    double m[4][4]; /* row-major, acting on column vectors: translation in m[0..2][3] */
} dmat4;

typedef struct dquat {
    double x, y, z, w;
} dquat;

static dmat4 dmat4_identity(void)
{
    dmat4 r;
    memset(&r, 0, sizeof r);
    for (int i = 0; i < 4; ++i) r.m[i][i] = 1.0;
    return r;
}

static dmat4 dmat4_from_ai(const struct aiMatrix4x4 *a)
{
    dmat4 r;
    const ai_real v[16] = {a->a1, a->a2, a->a3, a->a4, a->b1, a->b2, a->b3, a->b4,
                           a->c1, a->c2, a->c3, a->c4, a->d1, a->d2, a->d3, a->d4};
    for (int i = 0; i < 16; ++i) r.m[i / 4][i % 4] = (double)v[i];
    return r;
}

static dmat4 dmat4_mul(const dmat4 *a, const dmat4 *b)
{
    dmat4 r;
    for (int i = 0; i < 4; ++i)
        for (int k = 0; k < 4; ++k)
            r.m[i][k] = a->m[i][0] * b->m[0][k] + a->m[i][1] * b->m[1][k] + a->m[i][2] * b->m[2][k] +
                        a->m[i][3] * b->m[3][k];
    return r;
}

static dquat dquat_make(double x, double y, double z, double w)
{
    dquat q;
    q.x = x;
    q.y = y;
    q.z = z;
    q.w = w;
    return q;
}

static dquat dquat_normalize(dquat q)
{
    double n = sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
    if (!(n > 1e-300)) return dquat_make(0, 0, 0, 1);
    return dquat_make(q.x / n, q.y / n, q.z / n, q.w / n);
}

static dquat dquat_mul(dquat a, dquat b)
{
    return dquat_make(
        a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y, a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
        a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w, a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z);
}

static dquat dquat_conj(dquat q) { return dquat_make(-q.x, -q.y, -q.z, q.w); }

static void dquat_rotate(dquat q, const double v[3], double out[3])
{
    /* v' = v + 2w (u x v) + 2 u x (u x v) */
    double t[3] = {2 * (q.y * v[2] - q.z * v[1]), 2 * (q.z * v[0] - q.x * v[2]),
                   2 * (q.x * v[1] - q.y * v[0])};
    out[0] = v[0] + q.w * t[0] + (q.y * t[2] - q.z * t[1]);
    out[1] = v[1] + q.w * t[1] + (q.z * t[0] - q.x * t[2]);
    out[2] = v[2] + q.w * t[2] + (q.x * t[1] - q.y * t[0]);
}

/* Shortest-path spherical interpolation. */
static dquat dquat_slerp(dquat a, dquat b, double t)
{
    double d = a.x * b.x + a.y * b.y + a.z * b.z + a.w * b.w;
    if (d < 0) {
        d = -d;
        b = dquat_make(-b.x, -b.y, -b.z, -b.w);
    }
    double wa, wb;
    if (d > 0.9999999) {
        wa = 1 - t;
        wb = t;
    } else {
        double th = acos(d), s = sin(th);
        wa = sin((1 - t) * th) / s;
        wb = sin(t * th) / s;
    }
    return dquat_normalize(
        dquat_make(wa * a.x + wb * b.x, wa * a.y + wb * b.y, wa * a.z + wb * b.z, wa * a.w + wb * b.w));
}

/* Unit quaternion of an orthonormal rotation matrix r (row-major, column vectors). */
static dquat dquat_from_rot(double r[3][3])
{
    double tr = r[0][0] + r[1][1] + r[2][2];
    dquat q;
    if (tr > 0) {
        double s = sqrt(tr + 1.0) * 2;
        q = dquat_make((r[2][1] - r[1][2]) / s, (r[0][2] - r[2][0]) / s, (r[1][0] - r[0][1]) / s, 0.25 * s);
    } else if (r[0][0] > r[1][1] && r[0][0] > r[2][2]) {
        double s = sqrt(1.0 + r[0][0] - r[1][1] - r[2][2]) * 2;
        q = dquat_make(0.25 * s, (r[0][1] + r[1][0]) / s, (r[0][2] + r[2][0]) / s, (r[2][1] - r[1][2]) / s);
    } else if (r[1][1] > r[2][2]) {
        double s = sqrt(1.0 + r[1][1] - r[0][0] - r[2][2]) * 2;
        q = dquat_make((r[0][1] + r[1][0]) / s, 0.25 * s, (r[1][2] + r[2][1]) / s, (r[0][2] - r[2][0]) / s);
    } else {
        double s = sqrt(1.0 + r[2][2] - r[0][0] - r[1][1]) * 2;
        q = dquat_make((r[0][2] + r[2][0]) / s, (r[1][2] + r[2][1]) / s, 0.25 * s, (r[1][0] - r[0][1]) / s);
    }
    return dquat_normalize(q);
}

static void dquat_to_rot(dquat q, double r[3][3])
{
    double xx = q.x * q.x, yy = q.y * q.y, zz = q.z * q.z, xy = q.x * q.y, xz = q.x * q.z, yz = q.y * q.z;
    double wx = q.w * q.x, wy = q.w * q.y, wz = q.w * q.z;
    r[0][0] = 1 - 2 * (yy + zz);
    r[0][1] = 2 * (xy - wz);
    r[0][2] = 2 * (xz + wy);
    r[1][0] = 2 * (xy + wz);
    r[1][1] = 1 - 2 * (xx + zz);
    r[1][2] = 2 * (yz - wx);
    r[2][0] = 2 * (xz - wy);
    r[2][1] = 2 * (yz + wx);
    r[2][2] = 1 - 2 * (xx + yy);
}

/* The rotation of the upper 3x3 of m with scale and shear removed: Gram-Schmidt on the columns
 * (x first, then y), z = x cross y. Degenerate columns fall back to the identity's. */
static dquat rotation_of(const dmat4 *m)
{
    double c[3][3]; /* c[k] = column k */
    for (int k = 0; k < 3; ++k)
        for (int i = 0; i < 3; ++i) c[k][i] = m->m[i][k];
    double n0 = sqrt(c[0][0] * c[0][0] + c[0][1] * c[0][1] + c[0][2] * c[0][2]);
    if (!(n0 > 1e-300)) return dquat_make(0, 0, 0, 1);
    for (int i = 0; i < 3; ++i) c[0][i] /= n0;
    double d = c[0][0] * c[1][0] + c[0][1] * c[1][1] + c[0][2] * c[1][2];
    for (int i = 0; i < 3; ++i) c[1][i] -= d * c[0][i];
    double n1 = sqrt(c[1][0] * c[1][0] + c[1][1] * c[1][1] + c[1][2] * c[1][2]);
    if (!(n1 > 1e-300)) return dquat_make(0, 0, 0, 1);
    for (int i = 0; i < 3; ++i) c[1][i] /= n1;
    c[2][0] = c[0][1] * c[1][2] - c[0][2] * c[1][1];
    c[2][1] = c[0][2] * c[1][0] - c[0][0] * c[1][2];
    c[2][2] = c[0][0] * c[1][1] - c[0][1] * c[1][0];
    double r[3][3];
    for (int k = 0; k < 3; ++k)
        for (int i = 0; i < 3; ++i) r[i][k] = c[k][i];
    return dquat_from_rot(r);
}

/* T * R * S, the composition assimp's channels describe. */
static dmat4 dmat4_trs(const double t[3], dquat q, const double s[3])
{
    double r[3][3];
    dquat_to_rot(q, r);
    dmat4 m = dmat4_identity();
    for (int i = 0; i < 3; ++i) {
        for (int k = 0; k < 3; ++k) m.m[i][k] = r[i][k] * s[k];
        m.m[i][3] = t[i];
    }
    return m;
}

/* Translation, rotation and scale of a static node transform (a negative determinant is put in
 * the x scale). */
static void decompose(const dmat4 *m, double t[3], dquat *q, double s[3])
{
    for (int i = 0; i < 3; ++i) {
        t[i] = m->m[i][3];
        s[i] = sqrt(m->m[0][i] * m->m[0][i] + m->m[1][i] * m->m[1][i] + m->m[2][i] * m->m[2][i]);
    }
    double det = m->m[0][0] * (m->m[1][1] * m->m[2][2] - m->m[1][2] * m->m[2][1]) -
                 m->m[0][1] * (m->m[1][0] * m->m[2][2] - m->m[1][2] * m->m[2][0]) +
                 m->m[0][2] * (m->m[1][0] * m->m[2][1] - m->m[1][1] * m->m[2][0]);
    dmat4 n = *m;
    if (det < 0) {
        s[0] = -s[0];
        for (int i = 0; i < 3; ++i) n.m[i][0] = -n.m[i][0];
    }
    *q = rotation_of(&n);
}

/* ---- channels --------------------------------------------------------------------------- */

/* Index of the last key with time <= t (keys sorted), or -1 when t is before the first. */
static long key_before_vec(const struct aiVectorKey *k, unsigned n, double t)
{
    long lo = 0, hi = (long)n - 1, r = -1;
    while (lo <= hi) {
        long mid = lo + (hi - lo) / 2;
        if (k[mid].mTime <= t) {
            r = mid;
            lo = mid + 1;
        } else {
            hi = mid - 1;
        }
    }
    return r;
}

static long key_before_quat(const struct aiQuatKey *k, unsigned n, double t)
{
    long lo = 0, hi = (long)n - 1, r = -1;
    while (lo <= hi) {
        long mid = lo + (hi - lo) / 2;
        if (k[mid].mTime <= t) {
            r = mid;
            lo = mid + 1;
        } else {
            hi = mid - 1;
        }
    }
    return r;
}

/* Linear between the keys around t, held constant before the first and after the last. */
static void sample_vec(const struct aiVectorKey *k, unsigned n, double t, double out[3])
{
    long i = key_before_vec(k, n, t);
    if (i < 0) i = 0;
    const struct aiVector3D *a = &k[i].mValue;
    double u = 0.0;
    const struct aiVector3D *b = a;
    if ((unsigned long)i + 1 < n) {
        double t0 = k[i].mTime, t1 = k[i + 1].mTime;
        b = &k[i + 1].mValue;
        u = t1 > t0 ? (t - t0) / (t1 - t0) : 1.0;
        if (u < 0) u = 0;
    }
    out[0] = a->x + (b->x - (double)a->x) * u;
    out[1] = a->y + (b->y - (double)a->y) * u;
    out[2] = a->z + (b->z - (double)a->z) * u;
}

static dquat ai_quat(const struct aiQuaternion *q)
{
    return dquat_normalize(dquat_make(q->x, q->y, q->z, q->w));
}

static dquat sample_quat(const struct aiQuatKey *k, unsigned n, double t)
{
    long i = key_before_quat(k, n, t);
    if (i < 0) i = 0;
    dquat a = ai_quat(&k[i].mValue);
    if ((unsigned long)i + 1 >= n) return a;
    double t0 = k[i].mTime, t1 = k[i + 1].mTime;
    double u = t1 > t0 ? (t - t0) / (t1 - t0) : 1.0;
    if (u <= 0) return a;
    return dquat_slerp(a, ai_quat(&k[i + 1].mValue), u);
}

/* ---- the scene's nodes ------------------------------------------------------------------ */

typedef struct anode {
    const struct aiNode *node;
    int parent; /* -1 for the scene root */
    int depth;
    int helper;  /* one of assimp's "$AssimpFbx$" pivot nodes */
    int owner;   /* the real node a helper belongs to (itself for real nodes), -1 if none */
    int channel; /* this take's channel on the node, -1 */
    int marked;  /* 1: this take animates it (or its helpers); 2: a joint between animated ones */
    int joint;   /* this take's joint index, -1 */
} anode;

typedef struct importer {
    const char *path;
    const struct aiScene *scene;
    const mm_allocator *allocator;
    anode *nodes;
    int node_count;
    double axes[3][3];    /* file axes to Y up */
    double declared_unit; /* metres per unit the file declares, 0 when unknown */
} importer;

static bool is_helper(const struct aiNode *n) { return strstr(n->mName.data, HELPER_TAG) != NULL; }

/* Depth-first (pre-order) flattening without recursion: parents come before children and a
 * node's first child directly follows it. */
static mm_result flatten(importer *im, mm_error *err)
{
    const struct aiNode *root = im->scene->mRootNode;
    /* Count first, with an explicit stack. */
    size_t cap = 64, top = 0;
    const struct aiNode **stack = (const struct aiNode **)mm_alloc_array(im->allocator, cap, sizeof *stack);
    int *parents = NULL;
    if (!stack) return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    long count = 0;
    stack[top++] = root;
    mm_result r = MM_OK;
    while (top > 0) {
        const struct aiNode *n = stack[--top];
        if (++count > MAX_NODES) {
            r = mm_error_set(err, MM_ERR_LIMIT, 0, 0, "the scene has more than %d nodes", MAX_NODES);
            goto done;
        }
        if (top + n->mNumChildren > cap) {
            size_t ncap = (top + n->mNumChildren) * 2;
            const struct aiNode **ns =
                (const struct aiNode **)mm_alloc_array(im->allocator, ncap, sizeof *ns);
            if (!ns) {
                r = mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
                goto done;
            }
            memcpy(ns, stack, top * sizeof *ns);
            mm_free(im->allocator, stack);
            stack = ns;
            cap = ncap;
        }
        for (unsigned i = n->mNumChildren; i-- > 0;)
            if (n->mChildren[i]) stack[top++] = n->mChildren[i];
    }
    im->nodes = (anode *)mm_alloc_array(im->allocator, (size_t)count, sizeof *im->nodes);
    parents = (int *)mm_alloc_array(im->allocator, cap, sizeof *parents);
    if (!im->nodes || !parents) {
        r = mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
        goto done;
    }
    /* Second pass: fill in pre-order, the parent index riding along on a parallel stack. */
    top = 0;
    stack[top] = root;
    parents[top++] = -1;
    int k = 0;
    while (top > 0) {
        --top;
        const struct aiNode *n = stack[top];
        int p = parents[top];
        anode *a = &im->nodes[k];
        a->node = n;
        a->parent = p;
        a->depth = p < 0 ? 0 : im->nodes[p].depth + 1;
        a->helper = is_helper(n);
        for (unsigned i = n->mNumChildren; i-- > 0;) {
            if (!n->mChildren[i]) continue;
            stack[top] = n->mChildren[i];
            parents[top++] = k;
        }
        ++k;
    }
    im->node_count = k;
    /* A helper chain runs down single children to the real node it belongs to. */
    for (int i = 0; i < k; ++i) {
        int o = i;
        while (o < k && im->nodes[o].helper && im->nodes[o].node->mNumChildren == 1 && o + 1 < k) ++o;
        im->nodes[i].owner = im->nodes[o].helper ? -1 : o;
    }
done:
    mm_free(im->allocator, stack);
    mm_free(im->allocator, parents);
    return r;
}

static int find_node(const importer *im, const char *name)
{
    for (int i = 0; i < im->node_count; ++i)
        if (strcmp(im->nodes[i].node->mName.data, name) == 0) return i;
    return -1;
}

/* ---- metadata: axes and units ------------------------------------------------------------- */

static bool meta_number(const struct aiScene *scene, const char *key, double *out)
{
    const struct aiMetadata *md = scene->mMetaData;
    if (!md || !md->mKeys || !md->mValues) return false;
    for (unsigned i = 0; i < md->mNumProperties; ++i) {
        if (strcmp(md->mKeys[i].data, key) != 0) continue;
        const struct aiMetadataEntry *e = &md->mValues[i];
        if (!e->mData) return false;
        switch (e->mType) {
        case AI_INT32:
            *out = *(const int32_t *)e->mData;
            return true;
        case AI_UINT64:
            *out = (double)*(const uint64_t *)e->mData;
            return true;
        case AI_FLOAT:
            *out = *(const float *)e->mData;
            return true;
        case AI_DOUBLE:
            *out = *(const double *)e->mData;
            return true;
        default:
            return false;
        }
    }
    return false;
}

/* FBX keeps its axes in the metadata (UpAxis, FrontAxis, CoordAxis and their signs): the rows of
 * the conversion are the file's right (coord), up and front axes, so right becomes X, up Y and
 * front Z. Other formats arrive Y up (glTF by definition, Collada converted by assimp). */
static void setup_axes(importer *im)
{
    memset(im->axes, 0, sizeof im->axes);
    for (int i = 0; i < 3; ++i) im->axes[i][i] = 1.0;
    double up, up_sign, front, front_sign, coord, coord_sign;
    const struct aiScene *s = im->scene;
    if (!meta_number(s, "UpAxis", &up) || !meta_number(s, "FrontAxis", &front) ||
        !meta_number(s, "CoordAxis", &coord))
        return;
    if (!meta_number(s, "UpAxisSign", &up_sign)) up_sign = 1;
    if (!meta_number(s, "FrontAxisSign", &front_sign)) front_sign = 1;
    if (!meta_number(s, "CoordAxisSign", &coord_sign)) coord_sign = 1;
    int u = (int)up, f = (int)front, c = (int)coord;
    if (u < 0 || u > 2 || f < 0 || f > 2 || c < 0 || c > 2 || u == f || u == c || f == c) return;
    double a[3][3];
    memset(a, 0, sizeof a);
    a[0][c] = coord_sign < 0 ? -1.0 : 1.0;
    a[1][u] = up_sign < 0 ? -1.0 : 1.0;
    a[2][f] = front_sign < 0 ? -1.0 : 1.0;
    /* A left-handed declaration would mirror the motion: keep it a rotation by flipping front. */
    double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                 a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                 a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    if (det < 0)
        for (int i = 0; i < 3; ++i) a[2][i] = -a[2][i];
    memcpy(im->axes, a, sizeof a);
}

/* ---- one take ----------------------------------------------------------------------------- */

typedef struct take {
    const struct aiAnimation *anim;
    int joint_count;
    int *joint_node;        /* [joint_count] node of each joint */
    int *chain;             /* nodes of every joint's chain, top-down, joint after joint */
    int *chain_first;       /* [joint_count + 1] */
    int *parents;           /* [joint_count] parent joint, -1 for the root */
    double tps, start, end; /* ticks per second, first and last key (ticks) */
    double fps;
    int frame_count;
    dmat4 *global;     /* [joint_count] scratch */
    double *world_pos; /* [3 * joint_count] scratch */
    dquat *world_rot;  /* [joint_count] scratch */
} take;

static void take_free(const importer *im, take *t)
{
    mm_free(im->allocator, t->joint_node);
    mm_free(im->allocator, t->chain);
    mm_free(im->allocator, t->chain_first);
    mm_free(im->allocator, t->parents);
    mm_free(im->allocator, t->global);
    mm_free(im->allocator, t->world_pos);
    mm_free(im->allocator, t->world_rot);
    memset(t, 0, sizeof *t);
}

/* The node's local transform at time ticks: its channel if the take animates it (components the
 * channel lacks come from the static transform), else its static transform. */
static dmat4 node_local(const importer *im, const take *t, int k, bool animated, double ticks)
{
    const anode *a = &im->nodes[k];
    dmat4 m = dmat4_from_ai(&a->node->mTransformation);
    if (!animated || a->channel < 0) return m;
    const struct aiNodeAnim *ch = t->anim->mChannels[a->channel];
    double tr[3], sc[3];
    dquat q;
    decompose(&m, tr, &q, sc);
    if (ch->mNumPositionKeys && ch->mPositionKeys)
        sample_vec(ch->mPositionKeys, ch->mNumPositionKeys, ticks, tr);
    if (ch->mNumRotationKeys && ch->mRotationKeys)
        q = sample_quat(ch->mRotationKeys, ch->mNumRotationKeys, ticks);
    if (ch->mNumScalingKeys && ch->mScalingKeys) sample_vec(ch->mScalingKeys, ch->mNumScalingKeys, ticks, sc);
    return dmat4_trs(tr, q, sc);
}

/* World positions and scale-free rotations of every joint, Y up, in file units. */
static void take_pose(const importer *im, take *t, bool animated, double ticks)
{
    for (int j = 0; j < t->joint_count; ++j) {
        dmat4 local = dmat4_identity();
        for (int c = t->chain_first[j]; c < t->chain_first[j + 1]; ++c) {
            dmat4 n = node_local(im, t, t->chain[c], animated, ticks);
            local = dmat4_mul(&local, &n);
        }
        int pj = t->parents[j];
        t->global[j] = pj < 0 ? local : dmat4_mul(&t->global[pj], &local);
        dmat4 w;
        memset(&w, 0, sizeof w);
        for (int r = 0; r < 3; ++r)
            for (int k = 0; k < 4; ++k)
                w.m[r][k] = im->axes[r][0] * t->global[j].m[0][k] + im->axes[r][1] * t->global[j].m[1][k] +
                            im->axes[r][2] * t->global[j].m[2][k];
        w.m[3][3] = 1.0;
        for (int r = 0; r < 3; ++r) t->world_pos[3 * j + r] = w.m[r][3];
        t->world_rot[j] = rotation_of(&w);
    }
}

/* Local rotations and translations from the world pose, as mm_global_to_local would, in double. */
static void take_locals(const take *t, mm_quat *rot, mm_vec3 *pos)
{
    for (int j = 0; j < t->joint_count; ++j) {
        int p = t->parents[j];
        dquat q = t->world_rot[j];
        double v[3] = {t->world_pos[3 * j], t->world_pos[3 * j + 1], t->world_pos[3 * j + 2]};
        if (p >= 0) {
            dquat inv = dquat_conj(t->world_rot[p]);
            q = dquat_normalize(dquat_mul(inv, q));
            double d[3] = {v[0] - t->world_pos[3 * p], v[1] - t->world_pos[3 * p + 1],
                           v[2] - t->world_pos[3 * p + 2]};
            dquat_rotate(inv, d, v);
        }
        rot[j] = mm_quat_make((float)q.x, (float)q.y, (float)q.z, (float)q.w);
        pos[j] = mm_vec3_make((float)v[0], (float)v[1], (float)v[2]);
    }
}

static const double standard_rates[] = {
    12,  15,  20, 24000.0 / 1001, 24, 25, 30000.0 / 1001, 30, 48, 50, 60000.0 / 1001, 60, 72, 90, 96, 100,
    120, 144, 240};

static int compare_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* The take's time span and sample rate (see docs/import.md). */
static mm_result take_timing(const importer *im, take *t, const mm_import_desc *desc, mm_error *err)
{
    const struct aiAnimation *an = t->anim;
    t->tps = an->mTicksPerSecond > 0 ? an->mTicksPerSecond : 25.0; /* assimp's convention */
    size_t key_count = 0;
    for (unsigned c = 0; c < an->mNumChannels; ++c) {
        const struct aiNodeAnim *ch = an->mChannels[c];
        if (ch) key_count += (size_t)ch->mNumPositionKeys + ch->mNumRotationKeys + ch->mNumScalingKeys;
    }
    double *times = key_count ? (double *)mm_alloc_array(im->allocator, key_count, sizeof(double)) : NULL;
    if (key_count && !times) return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    size_t n = 0;
    bool whole_ticks = true;
    for (unsigned c = 0; c < an->mNumChannels; ++c) {
        const struct aiNodeAnim *ch = an->mChannels[c];
        if (!ch) continue;
        for (unsigned i = 0; i < ch->mNumPositionKeys && ch->mPositionKeys; ++i)
            times[n++] = ch->mPositionKeys[i].mTime;
        for (unsigned i = 0; i < ch->mNumRotationKeys && ch->mRotationKeys; ++i)
            times[n++] = ch->mRotationKeys[i].mTime;
        for (unsigned i = 0; i < ch->mNumScalingKeys && ch->mScalingKeys; ++i)
            times[n++] = ch->mScalingKeys[i].mTime;
    }
    t->start = 0.0;
    t->end = 0.0;
    double gap = INFINITY;
    if (n > 0) {
        qsort(times, n, sizeof *times, compare_double);
        t->start = times[0];
        t->end = times[n - 1];
        for (size_t i = 0; i < n; ++i) {
            if (!isfinite(times[i])) {
                mm_free(im->allocator, times);
                return mm_error_set(err, MM_ERR_BAD_NUMBER, 0, 0, "take '%s' has a key at a non-finite time",
                                    an->mName.data);
            }
            if (fabs(times[i] - floor(times[i] + 0.5)) > 1e-3) whole_ticks = false;
            double d = (i + 1 < n ? times[i + 1] - times[i] : 0.0) / t->tps;
            if (d > 1e-5 && d < gap) gap = d;
        }
    }
    mm_free(im->allocator, times);
    if (desc && desc->fps > 0) {
        t->fps = desc->fps;
    } else if (whole_ticks && t->tps <= 240.0) {
        t->fps = t->tps; /* keys on the file's own frame grid (FBX, BVH) */
    } else if (isfinite(gap)) {
        /* The closest keys are one frame apart: snap to the nearest standard rate within 0.02%
         * (the key times of glTF are single-precision seconds). */
        double fps = 1.0 / gap, best = INFINITY;
        for (size_t i = 0; i < sizeof standard_rates / sizeof standard_rates[0]; ++i) {
            double d = fabs(fps / standard_rates[i] - 1.0);
            if (d < 2e-4 && d < best) {
                best = d;
                fps = standard_rates[i];
            }
        }
        t->fps = fps < 1.0 ? 1.0 : fps > 1000.0 ? 1000.0 : fps;
    } else {
        t->fps = t->tps <= 240.0 ? t->tps : 30.0;
    }
    /* A last frame within 1% of a frame period of the last key is kept (sampled at that key). */
    double frames = floor((t->end - t->start) / t->tps * t->fps + 0.01) + 1.0;
    if (!(frames <= (double)MM_MAX_FRAMES))
        return mm_error_set(err, MM_ERR_LIMIT, 0, 0,
                            "take '%s' would have %.0f frames at %g fps, more than %d", an->mName.data,
                            frames, t->fps, MM_MAX_FRAMES);
    t->frame_count = (int)frames;
    return MM_OK;
}

/* Copies name into a joint name of the skeleton, unique among the first j joints. */
static void set_joint_name(mm_skeleton *s, int j, const char *name)
{
    char base[MM_NAME_MAX];
    snprintf(base, sizeof base, "%.*s", MM_NAME_MAX - 1, name[0] ? name : "joint");
    snprintf(s->joints[j].name, MM_NAME_MAX, "%s", base);
    for (int suffix = 2;; ++suffix) {
        bool clash = false;
        for (int i = 0; i < j && !clash; ++i) clash = strcmp(s->joints[i].name, s->joints[j].name) == 0;
        if (!clash) return;
        char tail[16];
        int tl = snprintf(tail, sizeof tail, "~%d", suffix);
        int keep = (int)strlen(base);
        if (keep + tl > MM_NAME_MAX - 1) keep = MM_NAME_MAX - 1 - tl;
        snprintf(s->joints[j].name, MM_NAME_MAX, "%.*s%s", keep, base, tail);
    }
}

/* Whether the channel moves its node: some key differs from the node's static transform. A
 * channel that only repeats the rest transform (Blender keys its armature objects so) does not
 * make a joint. */
static bool channel_moves(const struct aiNodeAnim *ch, const struct aiNode *node)
{
    dmat4 m = dmat4_from_ai(&node->mTransformation);
    double t[3], sc[3];
    dquat q;
    decompose(&m, t, &q, sc);
    double size = 1.0 + sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
    for (unsigned i = 0; ch->mPositionKeys && i < ch->mNumPositionKeys; ++i) {
        const struct aiVector3D *v = &ch->mPositionKeys[i].mValue;
        if (fabs(v->x - t[0]) > 1e-5 * size || fabs(v->y - t[1]) > 1e-5 * size ||
            fabs(v->z - t[2]) > 1e-5 * size)
            return true;
    }
    for (unsigned i = 0; ch->mRotationKeys && i < ch->mNumRotationKeys; ++i) {
        dquat k = ai_quat(&ch->mRotationKeys[i].mValue);
        if (fabs(k.x * q.x + k.y * q.y + k.z * q.z + k.w * q.w) < 1.0 - 1e-9) return true;
    }
    for (unsigned i = 0; ch->mScalingKeys && i < ch->mNumScalingKeys; ++i) {
        const struct aiVector3D *v = &ch->mScalingKeys[i].mValue;
        if (fabs(v->x - sc[0]) > 1e-5 * fabs(sc[0]) || fabs(v->y - sc[1]) > 1e-5 * fabs(sc[1]) ||
            fabs(v->z - sc[2]) > 1e-5 * fabs(sc[2]))
            return true;
    }
    return false;
}

/* Builds the clip of one take; returns MM_ERR_NOT_FOUND (without message) for a take that
 * animates no node of the scene. */
static mm_result import_take(importer *im, const struct aiAnimation *an, const mm_import_desc *desc,
                             mm_clip *out, mm_error *err)
{
    take t;
    memset(&t, 0, sizeof t);
    t.anim = an;
    mm_skeleton skel;
    memset(&skel, 0, sizeof skel);
    mm_result r = MM_OK;
    for (int i = 0; i < im->node_count; ++i) {
        im->nodes[i].channel = -1;
        im->nodes[i].marked = 0;
        im->nodes[i].joint = -1;
    }
    /* 1. channels to nodes; the owners they animate */
    int lca = -1;
    for (unsigned c = 0; c < an->mNumChannels; ++c) {
        const struct aiNodeAnim *ch = an->mChannels[c];
        if (!ch) continue;
        int k = find_node(im, ch->mNodeName.data);
        if (k < 0 || im->nodes[k].channel >= 0) continue;
        im->nodes[k].channel = (int)c;
        int o = im->nodes[k].owner;
        if (o < 0 || !channel_moves(ch, im->nodes[k].node)) continue;
        im->nodes[o].marked = 1;
        /* 2. lowest common ancestor of the animated nodes */
        if (lca < 0) {
            lca = o;
        } else {
            int a = lca, b = o;
            while (im->nodes[a].depth > im->nodes[b].depth) a = im->nodes[a].parent;
            while (im->nodes[b].depth > im->nodes[a].depth) b = im->nodes[b].parent;
            while (a != b) {
                a = im->nodes[a].parent;
                b = im->nodes[b].parent;
            }
            lca = a;
        }
    }
    if (lca < 0) return MM_ERR_NOT_FOUND;
    while (im->nodes[lca].helper && im->nodes[lca].parent >= 0) lca = im->nodes[lca].parent;
    /* joints: the real nodes from each animated node up to the common ancestor */
    for (int k = 0; k < im->node_count; ++k) {
        if (im->nodes[k].marked != 1) continue;
        for (int a = k; a >= 0; a = im->nodes[a].parent) {
            if (!im->nodes[a].helper && !im->nodes[a].marked) im->nodes[a].marked = 2;
            if (a == lca) break;
        }
    }
    int n = 0;
    for (int k = 0; k < im->node_count; ++k)
        if (im->nodes[k].marked && !im->nodes[k].helper) im->nodes[k].joint = n++;
    if (n > MM_MAX_JOINTS) {
        r = mm_error_set(err, MM_ERR_LIMIT, 0, 0, "take '%s' animates %d joints, more than %d",
                         an->mName.data, n, MM_MAX_JOINTS);
        goto fail;
    }
    t.joint_count = n;
    t.joint_node = (int *)mm_alloc_array(im->allocator, (size_t)n, sizeof(int));
    t.parents = (int *)mm_alloc_array(im->allocator, (size_t)n, sizeof(int));
    t.chain_first = (int *)mm_alloc_array(im->allocator, (size_t)n + 1, sizeof(int));
    t.global = (dmat4 *)mm_alloc_array(im->allocator, (size_t)n, sizeof(dmat4));
    t.world_pos = (double *)mm_alloc_array(im->allocator, (size_t)n * 3, sizeof(double));
    t.world_rot = (dquat *)mm_alloc_array(im->allocator, (size_t)n, sizeof(dquat));
    if (!t.joint_node || !t.parents || !t.chain_first || !t.global || !t.world_pos || !t.world_rot) goto oom;
    /* 3. parents and chains */
    size_t chain_len = 0;
    for (int k = 0; k < im->node_count; ++k) {
        int j = im->nodes[k].joint;
        if (j < 0) continue;
        t.joint_node[j] = k;
        t.parents[j] = -1;
        int len = 1;
        for (int a = im->nodes[k].parent; a >= 0; a = im->nodes[a].parent) {
            if (im->nodes[a].joint >= 0) {
                t.parents[j] = im->nodes[a].joint;
                break;
            }
            ++len;
        }
        chain_len += (size_t)len;
    }
    t.chain = (int *)mm_alloc_array(im->allocator, chain_len, sizeof(int));
    if (!t.chain) goto oom;
    size_t pos = 0;
    for (int j = 0; j < n; ++j) {
        t.chain_first[j] = (int)pos;
        int len = 0;
        for (int a = t.joint_node[j]; a >= 0; a = im->nodes[a].parent) {
            if (a != t.joint_node[j] && im->nodes[a].joint >= 0) break;
            ++len;
        }
        int a = t.joint_node[j];
        for (int i = len - 1; i >= 0; --i, a = im->nodes[a].parent) t.chain[pos + (size_t)i] = a;
        pos += (size_t)len;
    }
    t.chain_first[n] = (int)pos;
    r = take_timing(im, &t, desc, err);
    if (r != MM_OK) goto fail;

    /* 4. skeleton from the rest pose (every node static) */
    r = mm_skeleton_init(&skel, n, im->allocator);
    if (r != MM_OK) goto oom;
    take_pose(im, &t, false, 0.0);
    {
        mm_quat *rest_rot = (mm_quat *)mm_alloc_array(im->allocator, (size_t)n, sizeof(mm_quat));
        mm_vec3 *rest_pos = (mm_vec3 *)mm_alloc_array(im->allocator, (size_t)n, sizeof(mm_vec3));
        if (!rest_rot || !rest_pos) {
            mm_free(im->allocator, rest_rot);
            mm_free(im->allocator, rest_pos);
            goto oom;
        }
        take_locals(&t, rest_rot, rest_pos);
        for (int j = 0; j < n; ++j) {
            mm_joint *jt = &skel.joints[j];
            const anode *a = &im->nodes[t.joint_node[j]];
            set_joint_name(&skel, j, a->node->mName.data);
            jt->parent = t.parents[j];
            jt->offset = rest_pos[j];
            jt->order = MM_EULER_NONE;
            jt->flags = 0;
            jt->has_end_site = false;
        }
        mm_free(im->allocator, rest_rot);
        mm_free(im->allocator, rest_pos);
    }
    /* End Sites: a joint without child joints whose node has a single, childless, unanimated
     * child (BVH's End Site, Blender's "_end" leaf bones), maybe behind static FBX helpers. */
    for (int j = 0; j < n; ++j) {
        int k = t.joint_node[j];
        const struct aiNode *node = im->nodes[k].node;
        bool has_child_joint = false;
        for (int i = j + 1; i < n && !has_child_joint; ++i) has_child_joint = t.parents[i] == j;
        if (has_child_joint || node->mNumChildren != 1) continue;
        /* down through static helpers (a single child each: the next node in pre-order) */
        dmat4 g = t.global[j];
        int c = k + 1;
        bool ok = false;
        for (; c < im->node_count && im->nodes[c].parent == c - 1 && im->nodes[c].channel < 0; ++c) {
            dmat4 m = dmat4_from_ai(&im->nodes[c].node->mTransformation);
            g = dmat4_mul(&g, &m);
            unsigned children = im->nodes[c].node->mNumChildren;
            if (!im->nodes[c].helper) {
                ok = children == 0;
                break;
            }
            if (children != 1) break;
        }
        if (!ok) continue;
        double w[3], d[3];
        for (int r2 = 0; r2 < 3; ++r2)
            w[r2] = im->axes[r2][0] * g.m[0][3] + im->axes[r2][1] * g.m[1][3] + im->axes[r2][2] * g.m[2][3];
        for (int r2 = 0; r2 < 3; ++r2) d[r2] = w[r2] - t.world_pos[3 * j + r2];
        double e[3];
        dquat_rotate(dquat_conj(t.world_rot[j]), d, e);
        skel.joints[j].has_end_site = true;
        skel.joints[j].end_site = mm_vec3_make((float)e[0], (float)e[1], (float)e[2]);
    }
    /* Rotation orders for writers: joints whose chain has rotation keys get ZYX. */
    for (int j = 0; j < n; ++j)
        for (int c = t.chain_first[j]; c < t.chain_first[j + 1]; ++c) {
            int ch = im->nodes[t.chain[c]].channel;
            if (ch >= 0 && an->mChannels[ch]->mNumRotationKeys > 0) skel.joints[j].order = MM_EULER_ZYX;
        }
    r = mm_skeleton_validate(&skel, err);
    if (r != MM_OK) goto fail;

    /* 5. the frames */
    r = mm_clip_init(out, &skel, t.frame_count, (float)t.fps, im->allocator);
    if (r != MM_OK) goto oom;
    for (int f = 0; f < t.frame_count; ++f) {
        double ticks = t.start + (double)f * t.tps / t.fps;
        if (ticks > t.end) ticks = t.end;
        take_pose(im, &t, true, ticks);
        take_locals(&t, mm_clip_rotations(out, f), mm_clip_positions(out, f));
    }
    /* Joints whose translation moves away from the rest offset translate. */
    for (int j = 0; j < n; ++j) {
        mm_vec3 o = out->skeleton.joints[j].offset;
        float tol = 1e-5f * (1.0f + mm_vec3_length(o));
        for (int f = 0; f < t.frame_count; ++f)
            if (mm_vec3_distance(mm_clip_positions(out, f)[j], o) > tol) {
                out->skeleton.joints[j].flags |= MM_JOINT_TRANSLATES;
                break;
            }
    }
    mm_skeleton_free(&skel);
    take_free(im, &t);
    return MM_OK;
oom:
    r = mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
fail:
    mm_skeleton_free(&skel);
    take_free(im, &t);
    return r;
}

/* ---- the file --------------------------------------------------------------------------- */

/* assimp's C API keeps the last error in a global string: imports are serialised. */
static pthread_mutex_t assimp_lock = PTHREAD_MUTEX_INITIALIZER;

static const char *extension(const char *path)
{
    const char *slash = strrchr(path, '/');
    const char *name = slash ? slash + 1 : path;
    const char *dot = strrchr(name, '.');
    return dot && dot != name ? dot + 1 : "";
}

static double declared_unit(const importer *im)
{
    char ext[16];
    snprintf(ext, sizeof ext, "%s", extension(im->path));
    for (char *c = ext; *c; ++c)
        if (*c >= 'A' && *c <= 'Z') *c = (char)(*c - 'A' + 'a');
    double f;
    if (strcmp(ext, "fbx") == 0)
        return meta_number(im->scene, "UnitScaleFactor", &f) && f > 0 ? f * 0.01 : 0.01;
    if (strcmp(ext, "gltf") == 0 || strcmp(ext, "glb") == 0) return 1.0;
    if (strcmp(ext, "dae") == 0) return 1.0; /* assimp applies <unit meter> */
    return 0.0;
}

/* assimp's Collada reader names the takes "<first take>_<take>" (the root of the animation
 * library takes the first <animation>'s name): when the first take is "P_P" and every take starts
 * with "P_", the prefix goes. */
static void strip_collada_prefix(mm_clip_list *list)
{
    const char *first = list->names[0];
    size_t len = strlen(first);
    if (len < 3 || len % 2 == 0 || first[len / 2] != '_' || strncmp(first, first + len / 2 + 1, len / 2) != 0)
        return;
    size_t strip = len / 2 + 1;
    for (int i = 0; i < list->count; ++i)
        if (strlen(list->names[i]) <= strip || strncmp(list->names[i], first, strip) != 0) return;
    for (int i = 0; i < list->count; ++i)
        memmove(list->names[i], list->names[i] + strip, strlen(list->names[i] + strip) + 1);
}

mm_result mm__import_assimp(const char *path, const mm_import_desc *desc, mm_clip_list *out, mm_error *err)
{
    FILE *f = fopen(path, "rb");
    if (!f) return mm_error_set(err, MM_ERR_IO, 0, 0, "cannot open: %s", strerror(errno));
    fclose(f);

    importer im;
    memset(&im, 0, sizeof im);
    im.path = path;
    im.allocator = desc ? desc->allocator : NULL;

    struct aiPropertyStore *props = aiCreatePropertyStore();
    if (!props) return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    /* Only the node hierarchy and the animations matter. The FBX pivot helpers are kept (they
     * carry FBX's per-component curves exactly) and folded into their joints here. */
    aiSetImportPropertyInteger(props, AI_CONFIG_IMPORT_FBX_READ_MATERIALS, 0);
    aiSetImportPropertyInteger(props, AI_CONFIG_IMPORT_FBX_READ_TEXTURES, 0);
    aiSetImportPropertyInteger(props, AI_CONFIG_IMPORT_FBX_READ_CAMERAS, 0);
    aiSetImportPropertyInteger(props, AI_CONFIG_IMPORT_FBX_READ_LIGHTS, 0);
    aiSetImportPropertyInteger(props, AI_CONFIG_IMPORT_FBX_READ_ANIMATIONS, 1);
    aiSetImportPropertyInteger(props, AI_CONFIG_IMPORT_FBX_PRESERVE_PIVOTS, 1);
    aiSetImportPropertyInteger(props, AI_CONFIG_IMPORT_NO_SKELETON_MESHES, 1);
    pthread_mutex_lock(&assimp_lock);
    im.scene = aiImportFileExWithProperties(path, aiProcess_ValidateDataStructure, NULL, props);
    if (!im.scene) {
        const char *why = aiGetErrorString();
        mm_error_set(err, MM_ERR_SYNTAX, 0, 0, "assimp cannot read it: %s",
                     why && *why ? why : "unknown error");
    }
    pthread_mutex_unlock(&assimp_lock);
    aiReleasePropertyStore(props);
    if (!im.scene) return err ? err->code : MM_ERR_SYNTAX;

    mm_result r = MM_OK;
    if (!im.scene->mRootNode) {
        r = mm_error_set(err, MM_ERR_NOT_FOUND, 0, 0, "the file has no node hierarchy");
        goto done;
    }
    if (im.scene->mNumAnimations == 0 || !im.scene->mAnimations) {
        r = mm_error_set(err, MM_ERR_NOT_FOUND, 0, 0, "the file has no animation take");
        goto done;
    }
    if ((r = flatten(&im, err)) != MM_OK) goto done;
    setup_axes(&im);
    im.declared_unit = declared_unit(&im);

    int takes = (int)im.scene->mNumAnimations;
    if ((r = mm__clip_list_alloc(out, takes, im.allocator)) != MM_OK) {
        r = mm_error_set(err, r, 0, 0, "out of memory");
        goto done;
    }
    out->count = 0;
    snprintf(out->format, sizeof out->format, "%s", extension(path));
    for (int c = 0; c < (int)sizeof out->format && out->format[c]; ++c)
        if (out->format[c] >= 'A' && out->format[c] <= 'Z')
            out->format[c] = (char)(out->format[c] - 'A' + 'a');
    for (int a = 0; a < takes; ++a) {
        const struct aiAnimation *an = im.scene->mAnimations[a];
        if (!an) continue;
        mm_clip *clip = &out->clips[out->count];
        r = import_take(&im, an, desc, clip, err);
        if (r == MM_ERR_NOT_FOUND) {
            r = MM_OK; /* a take animating nothing in the scene has no skeleton: skipped */
            continue;
        }
        if (r == MM_OK) r = mm__import_apply_scale(clip, desc, im.declared_unit, err);
        if (r != MM_OK) {
            if (clip->rotations) mm_clip_free(clip);
            if (err && err->message[0]) {
                char msg[MM_ERROR_MESSAGE_MAX];
                snprintf(msg, sizeof msg, "%s", err->message);
                mm_error_set(err, r, 0, 0, "take %d ('%s'): %s", a + 1, an->mName.data, msg);
            }
            goto done;
        }
        const char *name = an->mName.data;
        if (strncmp(name, "AnimStack::", 11) == 0) name += 11;
        if (name[0])
            snprintf(out->names[out->count], MM_TAKE_NAME_MAX, "%.*s", MM_TAKE_NAME_MAX - 1, name);
        else
            snprintf(out->names[out->count], MM_TAKE_NAME_MAX, "take%d", a + 1);
        ++out->count;
    }
    if (out->count == 0)
        r = mm_error_set(err, MM_ERR_NOT_FOUND, 0, 0, "none of the file's %d animation takes animates a node",
                         takes);
    else if (strcmp(out->format, "dae") == 0)
        strip_collada_prefix(out);
done:
    mm_free(im.allocator, im.nodes);
    aiReleaseImport(im.scene);
    return r;
}
