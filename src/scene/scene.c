/* Scenes of boxes on a flat ground: ray casts, the ground probe and the obstacle measure. */
#include <mm/scene.h>

#include <math.h>
#include <string.h>

#include "math_private.h"

/* radians: the largest yaw a box may have (a larger one is degrees, or garbage: sinf and cosf
 * lose their precision) */
#define MAX_YAW 1.0e4f
/* m: boxes this close along a ray are one solid (touching, or rounding apart) */
#define SOLID_TOLERANCE 1e-4f
/* m: how far inside, and in front of, an obstacle's near face its top and floor are measured from:
 * clear of the face's own rounding, far less than any box */
#define FACE_STEP 1e-3f

void mm_scene_init(mm_scene *scene, float ground)
{
    if (!scene) return;
    memset(scene, 0, sizeof *scene);
    scene->ground = ground;
}

static bool in_range(float v) { return isfinite(v) && fabsf(v) <= MM_SCENE_MAX_EXTENT; }

mm_result mm_scene_add_box(mm_scene *scene, mm_vec3 position, mm_vec3 size, float yaw)
{
    if (!scene) return MM_ERR_INVALID_ARGUMENT;
    if (scene->box_count < 0 || scene->box_count >= MM_SCENE_MAX_BOXES) return MM_ERR_LIMIT;
    if (!in_range(position.x) || !in_range(position.y) || !in_range(position.z) || !in_range(size.x) ||
        !in_range(size.y) || !in_range(size.z) || !isfinite(yaw) || fabsf(yaw) > MAX_YAW)
        return MM_ERR_OUT_OF_RANGE;
    if (size.x < 0.0f || size.y < 0.0f || size.z < 0.0f) return MM_ERR_OUT_OF_RANGE;
    mm_scene_box *b = &scene->boxes[scene->box_count++];
    b->position = position;
    b->size = size;
    b->yaw = yaw;
    return MM_OK;
}

mm_vec3 mm_scene_box_centre(const mm_scene_box *box)
{
    return mm_vec3_make(box->position.x, box->position.y + 0.5f * box->size.y, box->position.z);
}

/* ---- box frames ------------------------------------------------------------------------- */

/* A box's local frame: centre, the yaw's cosine and sine, and half extents. World from local:
 * x = c lx + s lz, z = -s lx + c lz (the rotation about +Y by yaw). */
typedef struct frame {
    mm_vec3 centre;
    float c, s;
    float half[3];
} frame;

static frame box_frame(const mm_scene_box *b)
{
    frame f;
    f.centre = mm_scene_box_centre(b);
    f.c = cosf(b->yaw);
    f.s = sinf(b->yaw);
    f.half[0] = 0.5f * b->size.x;
    f.half[1] = 0.5f * b->size.y;
    f.half[2] = 0.5f * b->size.z;
    return f;
}

static void to_local_vector(const frame *f, mm_vec3 v, float out[3])
{
    out[0] = f->c * v.x - f->s * v.z;
    out[1] = v.y;
    out[2] = f->s * v.x + f->c * v.z;
}

static void to_local_point(const frame *f, mm_vec3 p, float out[3])
{
    to_local_vector(f, mm_vec3_sub(p, f->centre), out);
}

static mm_vec3 to_world_vector(const frame *f, const float v[3])
{
    return mm_vec3_make(f->c * v[0] + f->s * v[2], v[1], -f->s * v[0] + f->c * v[2]);
}

/* Slab test of the ray o + t d (local coordinates) with the closed box |x_i| <= half_i, over all
 * t. On an overlap gives its entry and exit parameters and the axis of the entry (ties keep
 * the lower axis). */
static bool slab(const float o[3], const float d[3], const float half[3], float *t_in, float *t_out,
                 int *axis_in)
{
    float tn = -INFINITY, tf = INFINITY;
    int an = -1;
    for (int i = 0; i < 3; ++i) {
        if (fabsf(d[i]) < 1e-30f) {
            if (o[i] < -half[i] || o[i] > half[i]) return false;
            continue;
        }
        float inv = 1.0f / d[i];
        float t0 = (-half[i] - o[i]) * inv, t1 = (half[i] - o[i]) * inv;
        if (t0 > t1) {
            float tmp = t0;
            t0 = t1;
            t1 = tmp;
        }
        if (t0 > tn) {
            tn = t0;
            an = i;
        }
        if (t1 < tf) tf = t1;
    }
    if (!(tn <= tf)) return false;
    *t_in = tn;
    *t_out = tf;
    *axis_in = an;
    return true;
}

/* ---- ray casts -------------------------------------------------------------------------- */

/* The nearest hit of o + t d (d unit), 0 <= t <= max_t, with the boxes and, when with_ground,
 * the ground. */
static bool cast(const mm_scene *scene, mm_vec3 o, mm_vec3 d, float max_t, bool with_ground,
                 mm_scene_hit *out)
{
    bool found = false;
    mm_scene_hit best;
    memset(&best, 0, sizeof best);
    best.distance = INFINITY;
    int count = scene->box_count < 0                    ? 0
                : scene->box_count > MM_SCENE_MAX_BOXES ? MM_SCENE_MAX_BOXES
                                                        : scene->box_count;
    for (int b = 0; b < count; ++b) {
        frame f = box_frame(&scene->boxes[b]);
        float lo[3], ld[3], tn, tf;
        int axis;
        to_local_point(&f, o, lo);
        to_local_vector(&f, d, ld);
        if (!slab(lo, ld, f.half, &tn, &tf, &axis)) continue;
        if (tf < 0.0f || (tn < 0.0f && tf <= 0.0f)) continue; /* behind, or leaving from a surface */
        float t = tn > 0.0f ? tn : 0.0f;
        if (t > max_t || !(t < best.distance)) continue;
        best.distance = t;
        best.box = b;
        best.inside = tn < 0.0f;
        if (best.inside || axis < 0) {
            best.normal = mm_vec3_neg(d);
            best.inside = true;
        } else {
            float n[3] = {0.0f, 0.0f, 0.0f};
            n[axis] = ld[axis] > 0.0f ? -1.0f : 1.0f;
            best.normal = to_world_vector(&f, n);
        }
        best.point = best.inside ? o : mm_vec3_add(o, mm_vec3_scale(d, t));
        found = true;
    }
    if (with_ground) {
        float g = scene->ground, t = 0.0f;
        bool inside = o.y < g, hits = inside;
        if (!inside && d.y < 0.0f) {
            t = (g - o.y) / d.y + 0.0f; /* never -0 */
            hits = true;
        }
        if (hits && t <= max_t && t < best.distance) {
            best.distance = t;
            best.box = -1;
            best.inside = inside;
            best.normal = inside ? mm_vec3_neg(d) : mm_vec3_make(0.0f, 1.0f, 0.0f);
            best.point = inside ? o : mm_vec3_make(o.x + d.x * t, g, o.z + d.z * t);
            found = true;
        }
    }
    if (found && out) *out = best;
    return found;
}

bool mm_scene_raycast(const mm_scene *scene, mm_vec3 origin, mm_vec3 direction, float max_distance,
                      mm_scene_hit *hit)
{
    if (!scene || !finite3(origin) || !finite3(direction) || isnan(max_distance) || max_distance < 0.0f)
        return false;
    float len = mm_vec3_length(direction);
    if (!(len > 1e-12f) || !isfinite(len)) return false;
    return cast(scene, origin, mm_vec3_scale(direction, 1.0f / len), max_distance, true, hit);
}

/* ---- ground probe ----------------------------------------------------------------------- */

bool mm_scene_ground_probe(const mm_scene *scene, mm_vec3 point, float step_height, float max_drop,
                           mm_scene_hit *hit)
{
    if (!scene || !finite3(point) || !isfinite(step_height) || isnan(max_drop)) return false;
    float lo = point.y - max_drop, hi = point.y + step_height;
    bool found = false;
    float best = -INFINITY;
    int best_box = -1;
    int count = scene->box_count < 0                    ? 0
                : scene->box_count > MM_SCENE_MAX_BOXES ? MM_SCENE_MAX_BOXES
                                                        : scene->box_count;
    for (int b = 0; b < count; ++b) {
        const mm_scene_box *box = &scene->boxes[b];
        float top = box->position.y + box->size.y;
        if (top < lo || top > hi || !(top > best)) continue;
        frame f = box_frame(box);
        float lp[3];
        to_local_point(&f, point, lp);
        if (fabsf(lp[0]) > f.half[0] || fabsf(lp[2]) > f.half[2]) continue;
        best = top;
        best_box = b;
        found = true;
    }
    float g = scene->ground;
    if (g >= lo && g <= hi && g > best) {
        best = g;
        best_box = -1;
        found = true;
    }
    if (!found) return false;
    if (hit) {
        hit->point = mm_vec3_make(point.x, best, point.z);
        hit->normal = mm_vec3_make(0.0f, 1.0f, 0.0f);
        hit->distance = point.y - best;
        hit->box = best_box;
        hit->inside = false;
    }
    return true;
}

/* ---- obstacle measure ------------------------------------------------------------------- */

/* How far the ray p + t d (d unit) runs through solid from t = 0, where p is inside a box or on
 * its surface: the exit of the box containing the point, then of any box containing the exit
 * point (touching or overlapping boxes are one solid), up to limit. */
static float solid_exit(const mm_scene *scene, mm_vec3 p, mm_vec3 d, float limit)
{
    int count = scene->box_count < 0                    ? 0
                : scene->box_count > MM_SCENE_MAX_BOXES ? MM_SCENE_MAX_BOXES
                                                        : scene->box_count;
    float t = 0.0f;
    for (int iteration = 0; iteration <= count; ++iteration) {
        float next = t;
        for (int b = 0; b < count; ++b) {
            frame f = box_frame(&scene->boxes[b]);
            float lo[3], ld[3], tn, tf;
            int axis;
            to_local_point(&f, p, lo);
            to_local_vector(&f, d, ld);
            if (!slab(lo, ld, f.half, &tn, &tf, &axis)) continue;
            if (tn <= t + SOLID_TOLERANCE && tf > next) next = tf;
        }
        if (!(next > t + 1e-6f)) break;
        t = next;
        if (t >= limit) return limit;
    }
    return t;
}

/* m above the feet: the default forward rays of the obstacle measure, a step above the ground to
 * head height every 0.4 m (mm_obstacle_desc.probe_heights) */
static const float default_probes[] = {0.3f, 0.7f, 1.1f, 1.5f, 1.9f};

bool mm_scene_measure_obstacle(const mm_scene *scene, mm_vec3 feet, mm_vec3 forward,
                               const mm_obstacle_desc *desc, mm_obstacle *out)
{
    if (!scene || !finite3(feet) || !finite3(forward)) return false;
    mm_obstacle_desc d;
    memset(&d, 0, sizeof d);
    if (desc) d = *desc;
    if (d.max_distance == 0.0f) d.max_distance = 1.5f;
    if (d.max_height == 0.0f) d.max_height = 3.0f;
    if (d.max_depth == 0.0f) d.max_depth = 5.0f;
    if (!d.probe_heights || d.probe_count == 0) {
        d.probe_heights = default_probes;
        d.probe_count = (int)(sizeof default_probes / sizeof default_probes[0]);
    }
    if (!(d.max_distance > 0.0f) || !(d.max_height > 0.0f) || !(d.max_depth > 0.0f) ||
        !isfinite(d.max_height) || !isfinite(d.max_depth) || isnan(d.max_distance) || d.probe_count < 0 ||
        d.probe_count > MM_OBSTACLE_MAX_PROBES)
        return false;
    float flat = sqrtf(forward.x * forward.x + forward.z * forward.z);
    if (!(flat > 1e-6f) || !isfinite(flat)) return false;
    mm_vec3 dir = mm_vec3_make(forward.x / flat, 0.0f, forward.z / flat);

    mm_obstacle o;
    memset(&o, 0, sizeof o);
    bool found = false;
    for (int k = 0; k < d.probe_count; ++k) {
        float h = d.probe_heights[k];
        if (!isfinite(h)) continue;
        mm_scene_hit hit;
        mm_vec3 origin = mm_vec3_make(feet.x, feet.y + h, feet.z);
        if (!cast(scene, origin, dir, d.max_distance, false, &hit)) continue;
        if (found && !(hit.distance < o.hit.distance) &&
            !(hit.distance == o.hit.distance && h < d.probe_heights[o.probe]))
            continue; /* the nearest hit; of equals, the lowest ray */
        o.hit = hit;
        o.probe = k;
        found = true;
    }
    if (!found) return false;
    o.distance = o.hit.distance;

    /* depth: through the obstacle along the direction */
    o.depth = solid_exit(scene, o.hit.point, dir, d.max_depth);
    o.too_deep = o.depth >= d.max_depth;

    /* top: straight up from just inside the near face */
    float step_in = o.depth * 0.5f < FACE_STEP ? o.depth * 0.5f : FACE_STEP;
    mm_vec3 inner = mm_vec3_add(o.hit.point, mm_vec3_scale(dir, step_in));
    float ceiling = feet.y + d.max_height;
    float up_limit = ceiling - inner.y;
    if (up_limit <= 0.0f) {
        o.top = ceiling;
        o.too_high = true;
    } else {
        float rise = solid_exit(scene, inner, mm_vec3_make(0.0f, 1.0f, 0.0f), up_limit);
        o.too_high = rise >= up_limit;
        o.top = o.too_high ? ceiling : inner.y + rise;
    }

    /* floor: straight down from just in front of the face */
    mm_vec3 front = mm_vec3_sub(o.hit.point, mm_vec3_scale(dir, FACE_STEP));
    mm_scene_hit below;
    if (cast(scene, front, mm_vec3_make(0.0f, -1.0f, 0.0f), INFINITY, true, &below))
        o.floor = below.point.y;
    else
        o.floor = scene->ground; /* unreachable: the ground is below anything above it */
    o.height = o.top - o.floor;
    if (out) *out = o;
    return true;
}
