/* The body mm makes from a skeleton: closed tubes of elliptic rings along the legs, the arms, the
 * spine and the neck, ellipsoids for the head (with a visor and a nose, so facing shows), the hands
 * and the feet; every ring bound to the joint that carries its bone, blended with the next one near
 * a joint so that the limb bends without cracks. And linear blend skinning for any such mesh. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <mm/body_mesh.h>

/* ---- proportions, for a 1.75 m adult whose thigh + shin is REFERENCE_LEG m; scaled by the leg ---- */
#define REFERENCE_LEG         0.86f
#define THIGH_TOP_RADIUS      0.085f
#define THIGH_BELLY           0.006f
#define KNEE_RADIUS           0.052f
#define CALF_BELLY            0.010f
#define ANKLE_RADIUS          0.038f
#define LEG_DEPTH_RATIO       1.05f /* front-to-back over side-to-side */
#define UPPER_ARM_RADIUS      0.050f
#define ELBOW_RADIUS          0.038f
#define FOREARM_BELLY         0.006f
#define WRIST_RADIUS          0.028f
#define PELVIS_EXTRA_WIDTH    0.085f /* beyond the hip joints, each side */
#define PELVIS_DEPTH          0.110f
#define WAIST_HALF_WIDTH      0.135f
#define WAIST_DEPTH           0.095f
#define CHEST_DEPTH           0.115f
#define SHOULDER_INSET        0.80f /* the chest's half width over half the distance between shoulders */
#define NECK_RADIUS           0.050f
#define HEAD_HALF_WIDTH       0.078f
#define HEAD_HALF_HEIGHT      0.112f
#define HEAD_HALF_DEPTH       0.098f
#define HEAD_LIFT             0.085f /* head centre above the head joint */
#define PELVIS_DROP           0.070f /* the torso's bottom below the hips joint */
#define TORSO_ABOVE_SHOULDERS 0.060f
#define HAND_LENGTH           0.190f /* wrist to finger tips */
#define HAND_HALF_WIDTH       0.045f
#define HAND_HALF_THICKNESS   0.022f
#define FOOT_HALF_WIDTH       0.046f
#define TOE_TIP_LENGTH        0.060f /* beyond the toe joint */
#define BLEND_REACH           1.2f   /* a joint's blend zone: this many times the tube's radius each side */

enum { RING_SEGMENTS = 20, SEGMENT_RINGS = 8, CAP_RINGS = 4, TORSO_RINGS = 18, ELLIPSOID_RINGS = 12 };

static const float skin_color[3] = {0.87f, 0.68f, 0.55f};
static const float shirt_color[3] = {0.28f, 0.47f, 0.72f};
static const float pants_color[3] = {0.22f, 0.24f, 0.30f};
static const float shoe_color[3] = {0.17f, 0.13f, 0.11f};
static const float visor_color[3] = {0.06f, 0.07f, 0.09f};
static const float hair_color[3] = {0.25f, 0.17f, 0.12f};

typedef struct ring {
    mm_vec3 center, u, v; /* u, v: unit axes of the ellipse's plane; u x v points along the tube */
    float ru, rv;
    int joint[2];
    float weight; /* of joint[1]; joint[0] has 1 - weight */
    const float *color;
} ring;

typedef struct builder {
    mm_body_mesh *m;
    const mm_xform *bind;
    int vertex_capacity, triangle_capacity;
    mm_vec3 *reference; /* a point inside the tube, per vertex, to turn normals outward */
    bool failed;
} builder;

static bool grow(builder *b, int vertices, int triangles)
{
    mm_body_mesh *m = b->m;
    if (m->vertex_count + vertices > b->vertex_capacity) {
        int cap = (m->vertex_count + vertices) * 2;
        mm_vec3 *p = realloc(m->bind_positions, sizeof(mm_vec3) * (size_t)cap);
        if (p) m->bind_positions = p;
        mm_vec3 *n = realloc(m->bind_normals, sizeof(mm_vec3) * (size_t)cap);
        if (n) m->bind_normals = n;
        mm_vec3 *r = realloc(b->reference, sizeof(mm_vec3) * (size_t)cap);
        if (r) b->reference = r;
        float *c = realloc(m->colors, sizeof(float) * 3 * (size_t)cap);
        if (c) m->colors = c;
        int32_t *j = realloc(m->joints, sizeof(int32_t) * MM_BODY_MAX_INFLUENCES * (size_t)cap);
        if (j) m->joints = j;
        float *w = realloc(m->weights, sizeof(float) * MM_BODY_MAX_INFLUENCES * (size_t)cap);
        if (w) m->weights = w;
        if (!p || !n || !r || !c || !j || !w) return false;
        b->vertex_capacity = cap;
    }
    if (m->triangle_count + triangles > b->triangle_capacity) {
        int cap = (m->triangle_count + triangles) * 2;
        uint32_t *i = realloc(m->indices, sizeof(uint32_t) * 3 * (size_t)cap);
        if (!i) return false;
        m->indices = i;
        b->triangle_capacity = cap;
    }
    return true;
}

static mm_vec3 orthonormal(mm_vec3 hint, mm_vec3 axis)
{
    mm_vec3 u = mm_vec3_sub(hint, mm_vec3_scale(axis, mm_vec3_dot(hint, axis)));
    if (mm_vec3_length(u) < 1e-4f) {
        /* the hint runs along the axis: any perpendicular */
        mm_vec3 other = fabsf(axis.y) < 0.9f ? mm_vec3_make(0, 1, 0) : mm_vec3_make(1, 0, 0);
        u = mm_vec3_cross(other, axis);
    }
    return mm_vec3_normalize(u);
}

/* A ring across a tube running along axis, its u axis toward side. */
static ring make_ring(mm_vec3 center, mm_vec3 axis, mm_vec3 side, float ru, float rv, int j0, int j1, float w,
                      const float *color)
{
    ring r;
    r.center = center;
    r.u = orthonormal(side, axis);
    r.v = mm_vec3_cross(axis, r.u);
    r.ru = ru;
    r.rv = rv;
    r.joint[0] = j0;
    r.joint[1] = j1;
    r.weight = w;
    r.color = color;
    return r;
}

static mm_vec3 ring_axis(const ring *r) { return mm_vec3_cross(r->u, r->v); }

/* The rings of a rounded end beyond ring e (direction +1: after it along the tube, -1: before). */
static void cap_rings(const ring *e, int direction, float depth, ring out[CAP_RINGS])
{
    mm_vec3 axis = ring_axis(e);
    for (int i = 0; i < CAP_RINGS; ++i) {
        float a = 0.5f * (float)MM_PI * (float)(i + 1) / CAP_RINGS;
        out[i] = *e;
        out[i].center = mm_vec3_add(e->center, mm_vec3_scale(axis, (float)direction * depth * sinf(a)));
        out[i].ru = e->ru * cosf(a);
        out[i].rv = e->rv * cosf(a);
    }
}

/* A closed tube through rings[0 .. n-1], with rounded ends of cap_depth (0: flat ends). */
static void add_tube(builder *b, const ring *rings, int n, float cap_depth_start, float cap_depth_end)
{
    if (b->failed || n < 2) return;
    ring start[CAP_RINGS], end[CAP_RINGS];
    cap_rings(&rings[0], -1, cap_depth_start, start);
    cap_rings(&rings[n - 1], 1, cap_depth_end, end);
    int total = n + 2 * CAP_RINGS;
    if (!grow(b, total * RING_SEGMENTS, (total - 1) * RING_SEGMENTS * 2)) {
        b->failed = true;
        return;
    }
    mm_body_mesh *m = b->m;
    int first = m->vertex_count;
    for (int k = 0; k < total; ++k) {
        const ring *r = k < CAP_RINGS       ? &start[CAP_RINGS - 1 - k]
                        : k < CAP_RINGS + n ? &rings[k - CAP_RINGS]
                                            : &end[k - CAP_RINGS - n];
        mm_vec3 inside = k < CAP_RINGS       ? rings[0].center
                         : k < CAP_RINGS + n ? r->center
                                             : rings[n - 1].center;
        for (int s = 0; s < RING_SEGMENTS; ++s) {
            float a = 2.0f * (float)MM_PI * (float)s / RING_SEGMENTS;
            int v = m->vertex_count++;
            m->bind_positions[v] = mm_vec3_add(r->center, mm_vec3_add(mm_vec3_scale(r->u, r->ru * cosf(a)),
                                                                      mm_vec3_scale(r->v, r->rv * sinf(a))));
            m->bind_normals[v] = mm_vec3_make(0, 0, 0);
            b->reference[v] = inside;
            memcpy(m->colors + 3 * v, r->color, sizeof(float) * 3);
            int32_t *j = m->joints + (size_t)v * MM_BODY_MAX_INFLUENCES;
            float *w = m->weights + (size_t)v * MM_BODY_MAX_INFLUENCES;
            for (int i = 0; i < MM_BODY_MAX_INFLUENCES; ++i) j[i] = -1, w[i] = 0.0f;
            if (r->weight <= 0.0f || r->joint[1] < 0 || r->joint[1] == r->joint[0]) {
                j[0] = r->joint[0], w[0] = 1.0f;
            } else if (r->weight >= 1.0f) {
                j[0] = r->joint[1], w[0] = 1.0f;
            } else {
                j[0] = r->joint[0], w[0] = 1.0f - r->weight;
                j[1] = r->joint[1], w[1] = r->weight;
            }
        }
    }
    for (int k = 0; k + 1 < total; ++k)
        for (int s = 0; s < RING_SEGMENTS; ++s) {
            uint32_t a = (uint32_t)(first + k * RING_SEGMENTS + s),
                     c = (uint32_t)(first + k * RING_SEGMENTS + (s + 1) % RING_SEGMENTS);
            uint32_t *t = m->indices + (size_t)m->triangle_count * 3;
            t[0] = a, t[1] = a + RING_SEGMENTS, t[2] = c;
            t[3] = c, t[4] = a + RING_SEGMENTS, t[5] = c + RING_SEGMENTS;
            m->triangle_count += 2;
        }
}

/* An ellipsoid of half axes ru along u, rv along v, rw along w = u x v, bound to one joint. */
static void add_ellipsoid(builder *b, mm_vec3 center, mm_vec3 w_axis, mm_vec3 u_hint, float ru, float rv,
                          float rw, int joint, const float *color)
{
    ring rings[ELLIPSOID_RINGS];
    for (int i = 0; i < ELLIPSOID_RINGS; ++i) {
        /* latitudes strictly inside (-90, 90) degrees; the caps close the poles */
        float a = (float)MM_PI * ((float)(i + 0.5f) / ELLIPSOID_RINGS - 0.5f) * 0.75f;
        rings[i] = make_ring(mm_vec3_add(center, mm_vec3_scale(w_axis, rw * sinf(a))), w_axis, u_hint,
                             ru * cosf(a), rv * cosf(a), joint, -1, 0.0f, color);
    }
    float a_end = (float)MM_PI * 0.5f * 0.75f * (1.0f - 1.0f / ELLIPSOID_RINGS);
    add_tube(b, rings, ELLIPSOID_RINGS, rw * (1.0f - sinf(a_end)), rw * (1.0f - sinf(a_end)));
}

static float smooth01(float x)
{
    x = fminf(fmaxf(x, 0.0f), 1.0f);
    return x * x * (3.0f - 2.0f * x);
}

/* A tube along a chain of joints points[0 .. count-1]: the segment from point k to k+1 is carried by
 * owner[k]; radius[k] at point k, bulging by belly[k] in the middle of segment k; depth_ratio: the
 * ellipse's extent along side x axis over its extent along side. Near every inner point the rings
 * blend from owner[k-1] to owner[k] over BLEND_REACH radii each side, their planes turning
 * halfway between the two segments. */
static void add_chain(builder *b, const mm_vec3 *points, const int *owner, int count, const float *radius,
                      const float *belly, float depth_ratio, mm_vec3 side, const float *const *colors,
                      float cap_start, float cap_end)
{
    enum { MAX_CHAIN = 6 };
    ring rings[MAX_CHAIN * SEGMENT_RINGS + 1];
    int n = 0;
    if (count < 2 || count > MAX_CHAIN) return;
    for (int k = 0; k + 1 < count; ++k) {
        mm_vec3 d = mm_vec3_sub(points[k + 1], points[k]);
        float len = mm_vec3_length(d);
        if (!(len > 1e-5f)) continue;
        mm_vec3 dir = mm_vec3_scale(d, 1.0f / len);
        int rings_here = k + 2 == count ? SEGMENT_RINGS + 1 : SEGMENT_RINGS;
        for (int i = 0; i < rings_here; ++i) {
            float t = (float)i / SEGMENT_RINGS, s = t * len;
            float r = radius[k] + (radius[k + 1] - radius[k]) * t + belly[k] * sinf((float)MM_PI * t);
            mm_vec3 axis = dir;
            int j0 = owner[k], j1 = -1;
            float w = 0.0f;
            /* blend with the previous segment near point k, or the next one near point k + 1 */
            float reach = BLEND_REACH * radius[k];
            if (k > 0 && s < reach) {
                mm_vec3 prev = mm_vec3_normalize(mm_vec3_sub(points[k], points[k - 1]));
                float wk = 0.5f + 0.5f * smooth01(s / reach); /* this segment's share */
                j0 = owner[k - 1], j1 = owner[k], w = wk;
                axis = mm_vec3_normalize(mm_vec3_lerp(prev, dir, wk));
            }
            float reach_end = BLEND_REACH * radius[k + 1];
            if (k + 2 < count && len - s < reach_end) {
                mm_vec3 next = mm_vec3_normalize(mm_vec3_sub(points[k + 2], points[k + 1]));
                float wn = 0.5f - 0.5f * smooth01((len - s) / reach_end); /* the next segment's share */
                j0 = owner[k], j1 = owner[k + 1], w = wn;
                axis = mm_vec3_normalize(mm_vec3_lerp(dir, next, wn));
            }
            rings[n++] = make_ring(mm_vec3_add(points[k], mm_vec3_scale(dir, s)), axis, side, r,
                                   r * depth_ratio, j0, j1, w, colors[k]);
        }
    }
    add_tube(b, rings, n, cap_start, cap_end);
}

/* The chain of joints from `from` up to (not including) `to`, as indices from `to`'s child down to
 * from; returns the count, 0 when `to` is not an ancestor of from. */
static int chain_up(const int *parents, int joint_count, int from, int to, int *out, int max)
{
    int n = 0;
    for (int j = from; j >= 0 && j < joint_count && j != to; j = parents[j]) {
        if (n == max) return 0;
        out[n++] = j;
    }
    if (n == 0 || parents[out[n - 1]] != to) return 0;
    for (int i = 0; i < n / 2; ++i) {
        int t = out[i];
        out[i] = out[n - 1 - i];
        out[n - 1 - i] = t;
    }
    return n;
}

static bool is_ancestor(const int *parents, int joint_count, int ancestor, int j)
{
    /* at most joint_count steps: parents that loop end the walk */
    for (int steps = 0; j >= 0 && j < joint_count && steps <= joint_count; j = parents[j], ++steps)
        if (j == ancestor) return true;
    return false;
}

static bool valid_joint(const mm_body_desc *d, int j) { return j >= 0 && j < d->joint_count; }

static int grandparent(const mm_body_desc *d, int j)
{
    int p = valid_joint(d, j) ? d->parents[j] : -1;
    return valid_joint(d, p) ? d->parents[p] : -1;
}

/* Straightness of the limb ending at end (its grandparent, parent, end): 1 when straight. */
static float limb_straightness(const mm_body_desc *d, const mm_xform *pose, int end)
{
    int mid = valid_joint(d, end) ? d->parents[end] : -1, top = grandparent(d, end);
    if (!valid_joint(d, mid) || !valid_joint(d, top)) return 0.0f;
    mm_vec3 a = pose[top].translation, b = pose[mid].translation, c = pose[end].translation;
    float bones = mm_vec3_distance(a, b) + mm_vec3_distance(b, c);
    return bones > 1e-6f ? mm_vec3_distance(a, c) / bones : 0.0f;
}

float mm_body_mesh_bind_score(const mm_body_desc *d, const mm_xform *pose)
{
    const mm_body_roles *r = &d->roles;
    float score = 0.0f;
    for (int s = 0; s < 2; ++s)
        score += limb_straightness(d, pose, r->foot[s]) + limb_straightness(d, pose, r->hand[s]);
    if (valid_joint(d, r->hips) && valid_joint(d, r->head)) {
        mm_vec3 spine = mm_vec3_sub(pose[r->head].translation, pose[r->hips].translation);
        float len = mm_vec3_length(spine);
        score += len > 1e-6f ? spine.y / len : 0.0f;
    }
    return score / 5.0f;
}

static bool pose_finite(const mm_xform *p, int n)
{
    for (int j = 0; j < n; ++j) {
        const float *f = &p[j].translation.x;
        for (int i = 0; i < 3; ++i)
            if (!isfinite(f[i])) return false;
        if (!isfinite(p[j].rotation.x + p[j].rotation.y + p[j].rotation.z + p[j].rotation.w)) return false;
    }
    return true;
}

typedef struct body_frame {
    mm_vec3 up, left, forward;
    float scale; /* leg length over REFERENCE_LEG */
} body_frame;

static void add_leg(builder *b, const mm_body_desc *d, const body_frame *f, int side)
{
    const mm_xform *pose = b->bind;
    int foot = d->roles.foot[side], knee = d->parents[foot], hip = d->parents[knee];
    float s = f->scale;
    mm_vec3 points[3] = {pose[hip].translation, pose[knee].translation, pose[foot].translation};
    int owner[3] = {hip, knee, foot};
    float radius[3] = {THIGH_TOP_RADIUS * s, KNEE_RADIUS * s, ANKLE_RADIUS * s};
    float belly[2] = {THIGH_BELLY * s, CALF_BELLY * s};
    const float *colors[2] = {pants_color, pants_color};
    add_chain(b, points, owner, 3, radius, belly, LEG_DEPTH_RATIO, f->left, colors, radius[0] * 0.8f,
              radius[2]);

    /* the foot: from behind the ankle, down to the sole, to past the toe */
    int toe = d->roles.toe[side];
    mm_vec3 ankle = pose[foot].translation;
    mm_vec3 toe_p;
    if (valid_joint(d, toe) && d->parents[toe] == foot &&
        mm_vec3_distance(pose[toe].translation, ankle) > 0.03f * s)
        toe_p = pose[toe].translation;
    else
        toe = foot, toe_p = mm_vec3_add(ankle, mm_vec3_add(mm_vec3_scale(f->forward, 0.14f * s),
                                                           mm_vec3_scale(f->up, -0.06f * s)));
    mm_vec3 along = mm_vec3_sub(toe_p, ankle);
    along = mm_vec3_sub(along, mm_vec3_scale(f->up, mm_vec3_dot(along, f->up))); /* level */
    float foot_len = mm_vec3_length(along);
    if (foot_len < 1e-4f) along = f->forward, foot_len = 0.14f * s;
    mm_vec3 dir = mm_vec3_scale(along, 1.0f / foot_len);
    float ankle_height = fmaxf(mm_vec3_dot(mm_vec3_sub(ankle, toe_p), f->up), 0.0f) + 0.025f * s;
    /* the sole: ankle_height below the ankle, level */
    mm_vec3 sole = mm_vec3_sub(ankle, mm_vec3_scale(f->up, ankle_height));
    ring rings[6];
    struct {
        float at, height, half_width, toe_share;
    } profile[6] = {
        {-0.28f, 0.55f, 0.75f, 0.0f}, {-0.05f, 0.80f, 0.85f, 0.0f},
        {0.35f, 0.70f, 1.00f, 0.0f},  {0.75f, 0.45f, 1.05f, 0.2f},
        {1.00f, 0.33f, 1.00f, 0.6f},  {1.00f + TOE_TIP_LENGTH * s / foot_len, 0.24f, 0.80f, 1.0f},
    };
    for (int i = 0; i < 6; ++i) {
        float h = profile[i].height * ankle_height;
        mm_vec3 c = mm_vec3_add(mm_vec3_add(sole, mm_vec3_scale(dir, profile[i].at * foot_len)),
                                mm_vec3_scale(f->up, 0.5f * h));
        rings[i] = make_ring(c, dir, f->left, FOOT_HALF_WIDTH * s * profile[i].half_width, 0.5f * h, foot,
                             toe, profile[i].toe_share, shoe_color);
    }
    add_tube(b, rings, 6, 0.03f * s, 0.02f * s);
}

static void add_arm(builder *b, const mm_body_desc *d, const body_frame *f, int side, int spine_joint)
{
    const mm_xform *pose = b->bind;
    int hand = d->roles.hand[side], elbow = d->parents[hand], shoulder = d->parents[elbow];
    float s = f->scale;
    mm_vec3 points[3] = {pose[shoulder].translation, pose[elbow].translation, pose[hand].translation};
    int owner[3] = {shoulder, elbow, hand};
    float radius[3] = {UPPER_ARM_RADIUS * s, ELBOW_RADIUS * s, WRIST_RADIUS * s};
    float belly[2] = {0.0f, FOREARM_BELLY * s};
    const float *colors[2] = {shirt_color, skin_color};
    add_chain(b, points, owner, 3, radius, belly, 1.0f, f->forward, colors, radius[0], radius[2]);

    /* the shoulder: from the spine joint the arm leaves, over the collar bones, to the upper arm */
    int clavicle = d->parents[shoulder];
    if (valid_joint(d, spine_joint) && clavicle != spine_joint && valid_joint(d, clavicle)) {
        mm_vec3 p[2] = {pose[clavicle].translation, pose[shoulder].translation};
        int o[2] = {clavicle, shoulder};
        float rr[2] = {0.055f * s, UPPER_ARM_RADIUS * s * 1.05f}, bb[1] = {0.0f};
        const float *cc[1] = {shirt_color};
        add_chain(b, p, o, 2, rr, bb, 0.9f, f->forward, cc, 0.05f * s, 0.05f * s);
    }

    /* the hand: a flat ellipsoid from the wrist on along the forearm, thin across the body */
    mm_vec3 dir = mm_vec3_normalize(mm_vec3_sub(pose[hand].translation, pose[elbow].translation));
    mm_vec3 c = mm_vec3_add(pose[hand].translation, mm_vec3_scale(dir, 0.45f * HAND_LENGTH * s));
    add_ellipsoid(b, c, dir, f->forward, HAND_HALF_WIDTH * s, HAND_HALF_THICKNESS * s, 0.5f * HAND_LENGTH * s,
                  hand, skin_color);
}

/* The spine's path: a point below the hips, the spine's joints, cut where it rises to top_height.
 * points[k] to points[k+1] is carried by owner[k]; returns the count of points. */
enum { MAX_SPINE = 24 };
static int spine_path(const mm_xform *pose, const body_frame *f, const int *spine, int spine_count,
                      float top_height, mm_vec3 *points, int *owner)
{
    int n = 0;
    points[n] = mm_vec3_sub(pose[spine[0]].translation, mm_vec3_scale(f->up, PELVIS_DROP * f->scale));
    owner[n++] = spine[0];
    for (int i = 0; i < spine_count && n < MAX_SPINE; ++i) {
        mm_vec3 p = pose[spine[i]].translation;
        float h = mm_vec3_dot(p, f->up);
        if (h >= top_height && n > 1) {
            /* cut the segment from the last point at top_height */
            mm_vec3 a = points[n - 1];
            float ha = mm_vec3_dot(a, f->up);
            float t = h - ha > 1e-6f ? (top_height - ha) / (h - ha) : 1.0f;
            points[n] = mm_vec3_lerp(a, p, fminf(fmaxf(t, 0.0f), 1.0f));
            owner[n] = owner[n - 1]; /* on the segment the previous point starts */
            ++n;
            return n;
        }
        points[n] = p;
        owner[n++] = spine[i];
    }
    return n;
}

/* Torso: rings along the spine's path, wide as the hips at the bottom, narrower at the waist, wide
 * as the shoulders at the chest, rounded over the shoulders to the neck. */
static void add_torso(builder *b, const body_frame *f, const mm_vec3 *pts, const int *owner, int n,
                      float hip_half, float shoulder_half, float shoulder_height)
{
    float s = f->scale;
    float cumulative[MAX_SPINE];
    cumulative[0] = 0.0f;
    for (int i = 1; i < n; ++i) cumulative[i] = cumulative[i - 1] + mm_vec3_distance(pts[i], pts[i - 1]);
    float total = cumulative[n - 1];
    if (n < 2 || !(total > 1e-4f)) return;
    float base = mm_vec3_dot(pts[0], f->up), span = fmaxf(shoulder_height - base, 1e-3f);
    float h_top = (mm_vec3_dot(pts[n - 1], f->up) - base) / span;
    ring rings[TORSO_RINGS];
    for (int r = 0; r < TORSO_RINGS; ++r) {
        float at = total * (float)r / (TORSO_RINGS - 1);
        int k = 0;
        while (k + 2 < n && cumulative[k + 1] < at) ++k;
        float seg = cumulative[k + 1] - cumulative[k], t = seg > 1e-6f ? (at - cumulative[k]) / seg : 0.0f;
        mm_vec3 c = mm_vec3_lerp(pts[k], pts[k + 1], t);
        mm_vec3 dir = mm_vec3_normalize(mm_vec3_sub(pts[k + 1], pts[k]));
        /* each spine joint's share rises over the second half of the segment below it and the first
           half of its own */
        int j0, j1;
        float w;
        if (k == 0) {
            j0 = j1 = owner[0], w = 0.0f; /* below the hips: the hips */
        } else if (t < 0.5f) {
            j0 = owner[k - 1], j1 = owner[k], w = 0.5f + 0.5f * smooth01(2.0f * t);
        } else {
            j0 = owner[k], j1 = k + 1 < n - 1 ? owner[k + 1] : owner[k], w = 0.5f * smooth01(2.0f * t - 1.0f);
        }
        /* height fraction: 0 at the bottom, 1 at the shoulders */
        float h = (mm_vec3_dot(c, f->up) - base) / span;
        float half_w, depth;
        if (h < 0.45f) {
            float x = smooth01(h / 0.45f);
            half_w = hip_half + (WAIST_HALF_WIDTH * s - hip_half) * x;
            depth = PELVIS_DEPTH * s + (WAIST_DEPTH - PELVIS_DEPTH) * s * x;
        } else if (h < 0.85f) {
            float x = smooth01((h - 0.45f) / 0.40f);
            half_w = WAIST_HALF_WIDTH * s + (shoulder_half - WAIST_HALF_WIDTH * s) * x;
            depth = WAIST_DEPTH * s + (CHEST_DEPTH - WAIST_DEPTH) * s * x;
        } else {
            /* over the shoulders toward the neck: rounded */
            float x = fminf((h - 0.85f) / fmaxf(h_top - 0.85f, 1e-3f), 1.0f);
            float round = sqrtf(fmaxf(1.0f - x * x, 0.0f));
            half_w = NECK_RADIUS * s + (shoulder_half - NECK_RADIUS * s) * round;
            depth = NECK_RADIUS * s + (CHEST_DEPTH * s - NECK_RADIUS * s) * round;
        }
        const float *color = h < 0.30f ? pants_color : shirt_color;
        rings[r] = make_ring(c, dir, f->left, half_w, depth, j0, j1, w, color);
    }
    add_tube(b, rings, TORSO_RINGS, 0.06f * s, 0.0f);
}

/* The neck from the torso's top (on the spine's segment of owner top_owner) to the head, and the
 * head: an ellipsoid, hair over its back, a visor across the eyes and a nose. */
static void add_head(builder *b, const mm_body_desc *d, const body_frame *f, const int *spine,
                     int spine_count, mm_vec3 top, int top_owner)
{
    const mm_xform *pose = b->bind;
    float s = f->scale;
    int head = d->roles.head;
    mm_vec3 hp = pose[head].translation;
    mm_vec3 pts[6];
    int owner[6], count = 0;
    float radius[6], belly[6] = {0};
    const float *colors[6];
    pts[count] = mm_vec3_sub(top, mm_vec3_scale(f->up, 0.03f * s)), owner[count++] = top_owner;
    bool above = false;
    for (int i = 0; i + 1 < spine_count && count < 5; ++i) {
        if (spine[i] == top_owner)
            above = true;
        else if (above && mm_vec3_dot(mm_vec3_sub(pose[spine[i]].translation, top), f->up) > 0.01f * s)
            pts[count] = pose[spine[i]].translation, owner[count++] = spine[i];
    }
    pts[count] = mm_vec3_add(hp, mm_vec3_scale(f->up, 0.02f * s)), owner[count++] = head;
    for (int i = 0; i < count; ++i) radius[i] = NECK_RADIUS * s, colors[i] = skin_color;
    if (mm_vec3_distance(pts[0], pts[count - 1]) > 0.01f * s)
        add_chain(b, pts, owner, count, radius, belly, 1.0f, f->left, colors, 0.0f, 0.0f);

    mm_vec3 center = mm_vec3_add(hp, mm_vec3_scale(f->up, HEAD_LIFT * s));
    center = mm_vec3_add(center, mm_vec3_scale(f->forward, 0.012f * s));
    add_ellipsoid(b, center, f->up, f->left, HEAD_HALF_WIDTH * s, HEAD_HALF_DEPTH * s, HEAD_HALF_HEIGHT * s,
                  head, skin_color);
    mm_vec3 hair = mm_vec3_add(
        center, mm_vec3_add(mm_vec3_scale(f->up, 0.02f * s), mm_vec3_scale(f->forward, -0.014f * s)));
    add_ellipsoid(b, hair, f->up, f->left, HEAD_HALF_WIDTH * s * 1.04f, HEAD_HALF_DEPTH * s * 1.02f,
                  HEAD_HALF_HEIGHT * s * 0.95f, head, hair_color);
    mm_vec3 visor = mm_vec3_add(
        center, mm_vec3_add(mm_vec3_scale(f->forward, 0.064f * s), mm_vec3_scale(f->up, 0.014f * s)));
    add_ellipsoid(b, visor, f->up, f->left, HEAD_HALF_WIDTH * s * 0.90f, 0.045f * s, 0.024f * s, head,
                  visor_color);
    mm_vec3 nose = mm_vec3_add(center, mm_vec3_add(mm_vec3_scale(f->forward, HEAD_HALF_DEPTH * s * 0.97f),
                                                   mm_vec3_scale(f->up, -0.030f * s)));
    add_ellipsoid(b, nose, f->forward, f->left, 0.014f * s, 0.017f * s, 0.024f * s, head, skin_color);
}

/* Each vertex's position and normal in the frames of its joints (the bind pose's inverse). */
static void bind_locals(mm_body_mesh *m, const mm_xform *bind)
{
    for (int v = 0; v < m->vertex_count; ++v)
        for (int i = 0; i < MM_BODY_MAX_INFLUENCES; ++i) {
            size_t k = (size_t)v * MM_BODY_MAX_INFLUENCES + (size_t)i;
            int j = m->joints[k];
            if (j < 0) {
                m->local_positions[k] = m->local_normals[k] = mm_vec3_make(0, 0, 0);
                continue;
            }
            mm_xform inv = mm_xform_inverse(bind[j]);
            m->local_positions[k] = mm_xform_apply_point(inv, m->bind_positions[v]);
            m->local_normals[k] = mm_xform_apply_vector(inv, m->bind_normals[v]);
        }
}

/* Vertex normals from the triangles' (area weighted), turned away from each tube's inside. */
static void vertex_normals(builder *b)
{
    mm_body_mesh *m = b->m;
    for (int t = 0; t < m->triangle_count; ++t) {
        const uint32_t *i = m->indices + 3 * (size_t)t;
        mm_vec3 a = m->bind_positions[i[0]], c1 = m->bind_positions[i[1]], c2 = m->bind_positions[i[2]];
        mm_vec3 n = mm_vec3_cross(mm_vec3_sub(c1, a), mm_vec3_sub(c2, a));
        for (int k = 0; k < 3; ++k) m->bind_normals[i[k]] = mm_vec3_add(m->bind_normals[i[k]], n);
    }
    for (int v = 0; v < m->vertex_count; ++v) {
        mm_vec3 n = m->bind_normals[v];
        if (mm_vec3_dot(n, mm_vec3_sub(m->bind_positions[v], b->reference[v])) < 0.0f) n = mm_vec3_neg(n);
        float len = mm_vec3_length(n);
        /* a pole of a cap (all its triangles degenerate on one side): outward from the inside */
        if (!(len > 1e-12f)) n = mm_vec3_sub(m->bind_positions[v], b->reference[v]), len = mm_vec3_length(n);
        m->bind_normals[v] = len > 1e-12f ? mm_vec3_scale(n, 1.0f / len) : mm_vec3_make(0, 1, 0);
    }
}

mm_result mm_body_mesh_build(const mm_body_desc *d, mm_body_mesh *out, mm_error *err)
{
    memset(out, 0, sizeof *out);
    if (!d || d->joint_count < 1 || !d->parents || !d->poses || d->pose_count < 1)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "a body needs a skeleton and a pose");
    const mm_body_roles *r = &d->roles;
    const char *missing = !valid_joint(d, r->hips)      ? "hips"
                          : !valid_joint(d, r->head)    ? "head"
                          : !valid_joint(d, r->foot[0]) ? "left foot"
                          : !valid_joint(d, r->foot[1]) ? "right foot"
                                                        : NULL;
    if (missing)
        return mm_error_set(err, MM_ERR_NOT_FOUND, 0, 0, "the body needs the %s role: none found", missing);
    for (int s = 0; s < 2; ++s)
        if (!valid_joint(d, grandparent(d, r->foot[s])) ||
            !is_ancestor(d->parents, d->joint_count, r->hips, r->foot[s]))
            return mm_error_set(err, MM_ERR_NOT_FOUND, 0, 0,
                                "the %s foot (joint %d) does not hang from the hips by a thigh and a shin",
                                s ? "right" : "left", r->foot[s]);
    int spine[32];
    int spine_count = chain_up(d->parents, d->joint_count, r->head, r->hips, spine + 1, 31);
    if (spine_count == 0)
        return mm_error_set(err, MM_ERR_NOT_FOUND, 0, 0,
                            "the head (joint %d) does not hang from the hips (joint %d)", r->head, r->hips);
    spine[0] = r->hips;
    ++spine_count; /* hips ... head */

    /* the bind pose: the straightest */
    int best = -1;
    float best_score = -1e30f;
    for (int p = 0; p < d->pose_count; ++p) {
        const mm_xform *pose = d->poses + (size_t)p * (size_t)d->joint_count;
        if (!pose_finite(pose, d->joint_count)) continue;
        float sc = mm_body_mesh_bind_score(d, pose);
        if (sc > best_score) best_score = sc, best = p;
    }
    if (best < 0)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no finite pose to bind the body to");
    const mm_xform *bind = d->poses + (size_t)best * (size_t)d->joint_count;

    body_frame f;
    f.up = mm_vec3_make(0, 1, 0);
    int hip_l = grandparent(d, r->foot[0]), hip_r = grandparent(d, r->foot[1]);
    mm_vec3 across = mm_vec3_sub(bind[hip_l].translation, bind[hip_r].translation);
    across.y = 0.0f;
    if (mm_vec3_length(across) < 1e-5f) across = mm_vec3_make(1, 0, 0);
    f.left = mm_vec3_normalize(across);
    f.forward = mm_vec3_cross(f.left, f.up);
    float leg = 0.0f;
    for (int s = 0; s < 2; ++s) {
        int foot = r->foot[s], knee = d->parents[foot], hip = d->parents[knee];
        leg += 0.5f * (mm_vec3_distance(bind[hip].translation, bind[knee].translation) +
                       mm_vec3_distance(bind[knee].translation, bind[foot].translation));
    }
    if (!(leg > 1e-4f)) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "the legs have no length");
    f.scale = leg / REFERENCE_LEG;

    builder b;
    memset(&b, 0, sizeof b);
    b.m = out;
    b.bind = bind;
    out->joint_count = d->joint_count;

    for (int s = 0; s < 2; ++s) add_leg(&b, d, &f, s);

    /* where the arms leave the spine, and the neck's base: the last spine joint below the head
       (the head's parent when the spine has one) */
    int arm_spine[2] = {-1, -1};
    bool arms[2] = {false, false};
    for (int s = 0; s < 2; ++s) {
        int hand = r->hand[s];
        if (!valid_joint(d, grandparent(d, hand))) continue;
        for (int j = d->parents[hand], steps = 0;
             valid_joint(d, j) && arm_spine[s] < 0 && steps <= d->joint_count; j = d->parents[j], ++steps)
            for (int i = 0; i < spine_count; ++i)
                if (spine[i] == j) arm_spine[s] = i;
        /* the upper arm must start off the spine */
        int shoulder = grandparent(d, hand);
        bool on_spine = false;
        for (int i = 0; i < spine_count; ++i) on_spine |= spine[i] == shoulder;
        arms[s] = arm_spine[s] >= 0 && !on_spine;
    }
    float hip_half = 0.5f * mm_vec3_distance(bind[hip_l].translation, bind[hip_r].translation) +
                     PELVIS_EXTRA_WIDTH * f.scale;
    float shoulder_half = 0.19f * f.scale,
          shoulder_height = mm_vec3_dot(bind[r->head].translation, f.up) - 0.04f * f.scale;
    if (arms[0] && arms[1]) {
        int sl = grandparent(d, r->hand[0]), sr = grandparent(d, r->hand[1]);
        shoulder_half = SHOULDER_INSET * 0.5f * mm_vec3_distance(bind[sl].translation, bind[sr].translation);
        shoulder_height = 0.5f * (bind[sl].translation.y + bind[sr].translation.y);
    }
    /* the torso ends a little above the shoulders, below the head */
    float top_height = fminf(shoulder_height + TORSO_ABOVE_SHOULDERS * f.scale,
                             mm_vec3_dot(bind[r->head].translation, f.up) - 0.01f * f.scale);
    mm_vec3 path[MAX_SPINE];
    int path_owner[MAX_SPINE];
    int path_count = spine_path(bind, &f, spine, spine_count, top_height, path, path_owner);
    add_torso(&b, &f, path, path_owner, path_count, hip_half, shoulder_half, shoulder_height);
    for (int s = 0; s < 2; ++s)
        if (arms[s]) add_arm(&b, d, &f, s, spine[arm_spine[s]]);
    add_head(&b, d, &f, spine, spine_count, path[path_count - 1], path_owner[path_count - 1]);

    if (!b.failed) {
        size_t k = (size_t)out->vertex_count * MM_BODY_MAX_INFLUENCES;
        out->local_positions = malloc(sizeof(mm_vec3) * k);
        out->local_normals = malloc(sizeof(mm_vec3) * k);
        b.failed = !out->local_positions || !out->local_normals;
    }
    if (b.failed) {
        free(b.reference);
        mm_body_mesh_free(out);
        return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    }
    vertex_normals(&b);
    free(b.reference);
    bind_locals(out, bind);
    return MM_OK;
}

void mm_body_roles_from_database(const mm_database *db, mm_body_roles *out)
{
    out->hips = mm_database_role_joint(db, MM_ROLE_HIPS);
    out->head = mm_database_role_joint(db, MM_ROLE_HEAD);
    out->foot[0] = mm_database_role_joint(db, MM_ROLE_LEFT_FOOT);
    out->foot[1] = mm_database_role_joint(db, MM_ROLE_RIGHT_FOOT);
    out->hand[0] = mm_database_role_joint(db, MM_ROLE_LEFT_HAND);
    out->hand[1] = mm_database_role_joint(db, MM_ROLE_RIGHT_HAND);
    out->toe[0] = out->foot[0] >= 0 ? mm_database_toe_joint(db, out->foot[0], MM_ROLE_LEFT_TOE) : -1;
    out->toe[1] = out->foot[1] >= 0 ? mm_database_toe_joint(db, out->foot[1], MM_ROLE_RIGHT_TOE) : -1;
}

mm_result mm_body_mesh_build_from_database(const mm_database *db, mm_body_mesh *out, mm_error *err)
{
    enum { CANDIDATES = 256 };
    memset(out, 0, sizeof *out);
    if (!db || db->joint_count < 1 || db->frame_count < 1)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no database to make a body for");
    int n = db->joint_count, count = db->frame_count < CANDIDATES ? db->frame_count : CANDIDATES;
    int *parents = malloc(sizeof(int) * (size_t)n);
    mm_xform *poses = malloc(sizeof(mm_xform) * (size_t)n * (size_t)count);
    if (!parents || !poses) {
        free(parents);
        free(poses);
        return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    }
    for (int j = 0; j < n; ++j) parents[j] = db->joints[j].parent;
    for (int c = 0; c < count; ++c) {
        int frame = (int)((long long)c * db->frame_count / count);
        const mm_quat *rot = db->rotations + (size_t)frame * (size_t)n;
        const mm_vec3 *pos = db->positions + (size_t)frame * (size_t)n;
        mm_xform *g = poses + (size_t)c * (size_t)n;
        g[0] = mm_xform_make(rot[0], pos[0]);
        mm_skeleton_global_from(db->joints, n, 1, rot, pos, g);
    }
    mm_body_desc d;
    memset(&d, 0, sizeof d);
    d.joint_count = n;
    d.parents = parents;
    d.poses = poses;
    d.pose_count = count;
    mm_body_roles_from_database(db, &d.roles);
    mm_result r = mm_body_mesh_build(&d, out, err);
    free(parents);
    free(poses);
    return r;
}

void mm_body_mesh_skin(const mm_body_mesh *m, const mm_xform *global, mm_vec3 *positions, mm_vec3 *normals)
{
    if (!m || !global) return;
    for (int v = 0; v < m->vertex_count; ++v) {
        mm_vec3 p = {0, 0, 0}, n = {0, 0, 0};
        const size_t base = (size_t)v * MM_BODY_MAX_INFLUENCES;
        for (int i = 0; i < MM_BODY_MAX_INFLUENCES; ++i) {
            int j = m->joints[base + i];
            if (j < 0 || j >= m->joint_count) continue;
            float w = m->weights[base + i];
            p = mm_vec3_add(p,
                            mm_vec3_scale(mm_xform_apply_point(global[j], m->local_positions[base + i]), w));
            n = mm_vec3_add(n,
                            mm_vec3_scale(mm_quat_rotate(global[j].rotation, m->local_normals[base + i]), w));
        }
        if (positions) positions[v] = p;
        if (normals) normals[v] = mm_vec3_normalize(n);
    }
}

void mm_body_mesh_free(mm_body_mesh *m)
{
    if (!m) return;
    free(m->bind_positions);
    free(m->bind_normals);
    free(m->colors);
    free(m->joints);
    free(m->weights);
    free(m->local_positions);
    free(m->local_normals);
    free(m->indices);
    memset(m, 0, sizeof *m);
}

float mm_body_facing(const mm_body_roles *roles, const int *parents, int joint_count, const mm_xform *pose,
                     float fallback)
{
    mm_body_desc d;
    memset(&d, 0, sizeof d);
    d.joint_count = joint_count;
    d.parents = parents;
    if (!roles || !parents || !pose) return fallback;
    int l = grandparent(&d, roles->foot[0]), r = grandparent(&d, roles->foot[1]);
    if (!valid_joint(&d, l) || !valid_joint(&d, r)) return fallback;
    mm_vec3 left = mm_vec3_sub(pose[l].translation, pose[r].translation);
    /* forward = left x up, on the ground: (-left.z, 0, left.x) */
    float fx = -left.z, fz = left.x;
    if (!isfinite(fx) || !isfinite(fz) || fx * fx + fz * fz < 1e-12f) return fallback;
    return atan2f(fx, fz);
}
