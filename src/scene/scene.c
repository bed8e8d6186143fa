/* Scenes of boxes, ramps, stairs and a height field on a ground plane: the ground's height, ray
 * casts, the ground probe and the obstacle measure. */
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
/* share of the field's spacing a ray marches by before it refines a crossing (a triangle's surface
 * is planar: one crossing per step is found; a sliver of a crossing shorter than this is missed) */
#define FIELD_MARCH 0.25f
/* bisections that refine a ray's crossing of the field (the step shrinks 2^this times) */
#define FIELD_BISECTIONS 24

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

static bool valid_solid(mm_vec3 position, mm_vec3 size, float yaw)
{
    return in_range(position.x) && in_range(position.y) && in_range(position.z) && in_range(size.x) &&
           in_range(size.y) && in_range(size.z) && isfinite(yaw) && fabsf(yaw) <= MAX_YAW && size.x >= 0.0f &&
           size.y >= 0.0f && size.z >= 0.0f;
}

mm_result mm_scene_add_ramp(mm_scene *scene, mm_vec3 position, mm_vec3 size, float yaw)
{
    if (!scene) return MM_ERR_INVALID_ARGUMENT;
    if (scene->ramp_count < 0 || scene->ramp_count >= MM_SCENE_MAX_RAMPS) return MM_ERR_LIMIT;
    if (!valid_solid(position, size, yaw) || !(size.z > 0.0f)) return MM_ERR_OUT_OF_RANGE;
    mm_scene_ramp *r = &scene->ramps[scene->ramp_count++];
    r->position = position;
    r->size = size;
    r->yaw = yaw;
    return MM_OK;
}

mm_result mm_scene_add_stairs(mm_scene *scene, mm_vec3 position, mm_vec3 size, float yaw, int steps)
{
    if (!scene) return MM_ERR_INVALID_ARGUMENT;
    if (scene->stairs_count < 0 || scene->stairs_count >= MM_SCENE_MAX_STAIRS) return MM_ERR_LIMIT;
    if (!valid_solid(position, size, yaw) || steps < 1 || steps > MM_SCENE_MAX_STEPS)
        return MM_ERR_OUT_OF_RANGE;
    mm_scene_stairs *st = &scene->stairs[scene->stairs_count++];
    st->position = position;
    st->size = size;
    st->yaw = yaw;
    st->steps = steps;
    return MM_OK;
}

mm_result mm_scene_set_field(mm_scene *scene, mm_vec3 origin, float spacing, int columns, int rows,
                             const float *heights)
{
    if (!scene) return MM_ERR_INVALID_ARGUMENT;
    if (columns == 0 && rows == 0) {
        memset(&scene->field, 0, sizeof scene->field);
        return MM_OK;
    }
    if (!heights) return MM_ERR_INVALID_ARGUMENT;
    if (columns < 2 || rows < 2) return MM_ERR_OUT_OF_RANGE;
    if ((long)columns * rows > MM_SCENE_MAX_FIELD_SAMPLES) return MM_ERR_LIMIT;
    if (!in_range(origin.x) || !in_range(origin.y) || !in_range(origin.z) || !in_range(spacing) ||
        !(spacing > 0.0f) || !in_range(origin.x + spacing * (float)(columns - 1)) ||
        !in_range(origin.z + spacing * (float)(rows - 1)))
        return MM_ERR_OUT_OF_RANGE;
    for (int i = 0; i < columns * rows; ++i)
        if (!in_range(heights[i]) || !in_range(origin.y + heights[i])) return MM_ERR_OUT_OF_RANGE;
    mm_scene_field *f = &scene->field;
    f->origin = origin;
    f->spacing = spacing;
    f->columns = columns;
    f->rows = rows;
    memcpy(f->heights, heights, sizeof(float) * (size_t)(columns * rows));
    return MM_OK;
}

bool mm_scene_stairs_step(const mm_scene_stairs *s, int i, mm_scene_box *out)
{
    if (!s || i < 0 || i >= s->steps || s->steps < 1) return false;
    float run = s->size.z / (float)s->steps, rise = s->size.y / (float)s->steps;
    float c = cosf(s->yaw), sn = sinf(s->yaw);
    float lz = -0.5f * s->size.z + ((float)i + 0.5f) * run; /* the step's centre along the flight */
    /* world from local: x = c lx + s lz, z = -s lx + c lz */
    out->position = mm_vec3_make(s->position.x + sn * lz, s->position.y, s->position.z + c * lz);
    out->size = mm_vec3_make(s->size.x, rise * (float)(i + 1), run);
    out->yaw = s->yaw;
    return true;
}

bool mm_scene_is_flat(const mm_scene *scene)
{
    return !scene || (scene->ground == 0.0f && scene->box_count == 0 && scene->ramp_count == 0 &&
                      scene->stairs_count == 0 && scene->field.columns == 0);
}

bool mm_scene_has_terrain(const mm_scene *scene)
{
    return scene && (scene->ramp_count > 0 || scene->stairs_count > 0 || scene->field.columns > 0);
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

/* ---- surfaces ---------------------------------------------------------------------------- */

static int clamp_count(int n, int max) { return n < 0 ? 0 : n > max ? max : n; }

bool mm_scene_field_height(const mm_scene_field *f, float x, float z, float *height, mm_vec3 *normal)
{
    if (!f || f->columns < 2 || f->rows < 2 || !(f->spacing > 0.0f) || !isfinite(x) || !isfinite(z))
        return false;
    float u = (x - f->origin.x) / f->spacing, v = (z - f->origin.z) / f->spacing;
    float last_u = (float)(f->columns - 1), last_v = (float)(f->rows - 1);
    if (!(u >= 0.0f && u <= last_u && v >= 0.0f && v <= last_v)) return false;
    int i = (int)floorf(u), j = (int)floorf(v);
    if (i > f->columns - 2) i = f->columns - 2;
    if (j > f->rows - 2) j = f->rows - 2;
    u -= (float)i, v -= (float)j;
    const float *row0 = f->heights + (size_t)j * (size_t)f->columns + i, *row1 = row0 + f->columns;
    float h00 = row0[0], h10 = row0[1], h01 = row1[0], h11 = row1[1], dx, dz;
    if (u >= v) { /* the triangle (i, j), (i + 1, j), (i + 1, j + 1) */
        dx = h10 - h00;
        dz = h11 - h10;
    } else { /* (i, j), (i, j + 1), (i + 1, j + 1) */
        dx = h11 - h01;
        dz = h01 - h00;
    }
    if (height) *height = f->origin.y + h00 + u * dx + v * dz;
    if (normal) *normal = mm_vec3_normalize(mm_vec3_make(-dx / f->spacing, 1.0f, -dz / f->spacing));
    return true;
}

/* A point in a footprint's local frame (x and z about its centre, the yaw undone). */
static void footprint_local(mm_vec3 position, float yaw, float x, float z, float *lx, float *lz)
{
    float c = cosf(yaw), s = sinf(yaw), dx = x - position.x, dz = z - position.z;
    *lx = c * dx - s * dz;
    *lz = s * dx + c * dz;
}

static mm_vec3 yawed(float yaw, mm_vec3 v)
{
    float c = cosf(yaw), s = sinf(yaw);
    return mm_vec3_make(c * v.x + s * v.z, v.y, -s * v.x + c * v.z);
}

/* The top of ramp r at (x, z) and its normal; false outside its footprint. */
static bool ramp_top(const mm_scene_ramp *r, float x, float z, float *top, mm_vec3 *normal)
{
    float lx, lz, hx = 0.5f * r->size.x, hz = 0.5f * r->size.z;
    footprint_local(r->position, r->yaw, x, z, &lx, &lz);
    if (!(fabsf(lx) <= hx && fabsf(lz) <= hz)) return false;
    float slope = r->size.y / r->size.z;
    *top = r->position.y + r->size.y * (lz / r->size.z + 0.5f);
    *normal = yawed(r->yaw, mm_vec3_normalize(mm_vec3_make(0.0f, 1.0f, -slope)));
    return true;
}

/* The top of the step of stairs s under (x, z); false outside the flight's footprint. */
static bool stairs_top(const mm_scene_stairs *s, float x, float z, float *top)
{
    float lx, lz, hx = 0.5f * s->size.x, hz = 0.5f * s->size.z;
    footprint_local(s->position, s->yaw, x, z, &lx, &lz);
    if (!(fabsf(lx) <= hx && fabsf(lz) <= hz) || s->steps < 1) return false;
    float run = s->size.z / (float)s->steps;
    int i = run > 0.0f ? (int)floorf((lz + hz) / run) : s->steps - 1;
    if (i > s->steps - 1) i = s->steps - 1;
    if (i < 0) i = 0;
    *top = s->position.y + s->size.y * (float)(i + 1) / (float)s->steps;
    return true;
}

/* The highest surface other than the ground plane (box tops, steps, ramps, the field) under (x, z)
 * whose height lies in [lo, hi], if higher than *best: *best, *normal and *box (the box's index,
 * -1 for terrain) updated. Returns whether one was. */
static bool highest_surface(const mm_scene *scene, float x, float z, float lo, float hi, float *best,
                            mm_vec3 *normal, int *box)
{
    bool found = false;
    mm_vec3 up = mm_vec3_make(0.0f, 1.0f, 0.0f);
    int boxes = clamp_count(scene->box_count, MM_SCENE_MAX_BOXES);
    for (int b = 0; b < boxes; ++b) {
        const mm_scene_box *bx = &scene->boxes[b];
        float top = bx->position.y + bx->size.y, lx, lz;
        if (top < lo || top > hi || !(top > *best)) continue;
        footprint_local(bx->position, bx->yaw, x, z, &lx, &lz);
        if (!(fabsf(lx) <= 0.5f * bx->size.x && fabsf(lz) <= 0.5f * bx->size.z)) continue;
        *best = top, *normal = up, *box = b;
        found = true;
    }
    int stairs = clamp_count(scene->stairs_count, MM_SCENE_MAX_STAIRS);
    for (int k = 0; k < stairs; ++k) {
        float top;
        if (!stairs_top(&scene->stairs[k], x, z, &top) || top < lo || top > hi || !(top > *best)) continue;
        *best = top, *normal = up, *box = -1;
        found = true;
    }
    int ramps = clamp_count(scene->ramp_count, MM_SCENE_MAX_RAMPS);
    for (int k = 0; k < ramps; ++k) {
        float top;
        mm_vec3 n;
        if (!ramp_top(&scene->ramps[k], x, z, &top, &n) || top < lo || top > hi || !(top > *best)) continue;
        *best = top, *normal = n, *box = -1;
        found = true;
    }
    float top;
    mm_vec3 n;
    if (mm_scene_field_height(&scene->field, x, z, &top, &n) && top >= lo && top <= hi && top > *best) {
        *best = top, *normal = n, *box = -1;
        found = true;
    }
    return found;
}

float mm_scene_ground_height(const mm_scene *scene, float x, float z, mm_vec3 *normal)
{
    mm_vec3 n = mm_vec3_make(0.0f, 1.0f, 0.0f);
    float best = scene ? scene->ground : 0.0f;
    int box;
    if (scene && isfinite(x) && isfinite(z))
        highest_surface(scene, x, z, -INFINITY, INFINITY, &best, &n, &box);
    if (normal) *normal = n;
    return best;
}

/* ---- ray casts -------------------------------------------------------------------------- */

/* The hit of o + t d (d unit), 0 <= t <= max_t, with box bx when nearer than best->distance: best
 * updated (box index `index`). */
static bool cast_box(const mm_scene_box *bx, int index, mm_vec3 o, mm_vec3 d, float max_t, mm_scene_hit *best)
{
    frame f = box_frame(bx);
    float lo[3], ld[3], tn, tf;
    int axis;
    to_local_point(&f, o, lo);
    to_local_vector(&f, d, ld);
    if (!slab(lo, ld, f.half, &tn, &tf, &axis)) return false;
    if (tf < 0.0f || (tn < 0.0f && tf <= 0.0f)) return false; /* behind, or leaving from a surface */
    float t = tn > 0.0f ? tn : 0.0f;
    if (t > max_t || !(t < best->distance)) return false;
    best->distance = t;
    best->box = index;
    best->inside = tn < 0.0f;
    if (best->inside || axis < 0) {
        best->normal = mm_vec3_neg(d);
        best->inside = true;
    } else {
        float n[3] = {0.0f, 0.0f, 0.0f};
        n[axis] = ld[axis] > 0.0f ? -1.0f : 1.0f;
        best->normal = to_world_vector(&f, n);
    }
    best->point = best->inside ? o : mm_vec3_add(o, mm_vec3_scale(d, t));
    return true;
}

/* The hit of the ray with ramp r (a convex wedge: five planes n.p <= c in its frame, about its
 * footprint's centre at its base) when nearer than best->distance. */
static bool cast_ramp(const mm_scene_ramp *r, mm_vec3 o, mm_vec3 d, float max_t, mm_scene_hit *best)
{
    float c = cosf(r->yaw), s = sinf(r->yaw);
    mm_vec3 p = mm_vec3_sub(o, r->position);
    float lo[3] = {c * p.x - s * p.z, p.y, s * p.x + c * p.z},
          ld[3] = {c * d.x - s * d.z, d.y, s * d.x + c * d.z};
    float hx = 0.5f * r->size.x, hz = 0.5f * r->size.z, k = r->size.y / r->size.z;
    /* planes: x <= hx, -x <= hx, -y <= 0, z <= hz, -z <= hz, y - k z <= rise / 2 */
    const float planes[6][4] = {{1, 0, 0, hx}, {-1, 0, 0, hx}, {0, -1, 0, 0},
                                {0, 0, 1, hz}, {0, 0, -1, hz}, {0, 1, -k, 0.5f * r->size.y}};
    float tn = -INFINITY, tf = INFINITY;
    int entry = -1;
    for (int i = 0; i < 6; ++i) {
        const float *n = planes[i];
        float dist = n[0] * lo[0] + n[1] * lo[1] + n[2] * lo[2] - n[3],
              along = n[0] * ld[0] + n[1] * ld[1] + n[2] * ld[2];
        if (fabsf(along) < 1e-30f) {
            if (dist > 0.0f) return false;
            continue;
        }
        float t = -dist / along;
        if (along < 0.0f) {
            if (t > tn) tn = t, entry = i;
        } else if (t < tf) {
            tf = t;
        }
    }
    if (!(tn <= tf) || tf < 0.0f || (tn < 0.0f && tf <= 0.0f)) return false;
    float t = tn > 0.0f ? tn : 0.0f;
    if (t > max_t || !(t < best->distance)) return false;
    best->distance = t;
    best->box = -1;
    best->inside = tn < 0.0f || entry < 0;
    if (best->inside) {
        best->normal = mm_vec3_neg(d);
        best->point = o;
    } else {
        const float *n = planes[entry];
        best->normal = yawed(r->yaw, mm_vec3_normalize(mm_vec3_make(n[0], n[1], n[2])));
        best->point = mm_vec3_add(o, mm_vec3_scale(d, t));
    }
    return true;
}

/* How far the ray's point at t is above the field (-INFINITY outside its footprint). */
static float above_field(const mm_scene_field *f, mm_vec3 o, mm_vec3 d, float t)
{
    float h;
    if (!mm_scene_field_height(f, o.x + d.x * t, o.z + d.z * t, &h, NULL)) return -INFINITY;
    return o.y + d.y * t - h;
}

/* The first crossing of the ray down through the height field (from above: a ray under it passes)
 * when nearer than best->distance: marched by a share of the spacing, refined by bisection. */
static bool cast_field(const mm_scene_field *f, mm_vec3 o, mm_vec3 d, float max_t, mm_scene_hit *best)
{
    if (f->columns < 2 || f->rows < 2) return false;
    float end = fminf(max_t, best->distance);
    if (!(sqrtf(d.x * d.x + d.z * d.z) > 1e-6f)) { /* straight up or down: the height under it */
        mm_vec3 normal;
        float h;
        if (!(d.y < 0.0f) || !mm_scene_field_height(f, o.x, o.z, &h, &normal) || !(o.y > h)) return false;
        float t = (o.y - h) / -d.y;
        if (t > end) return false;
        best->distance = t;
        best->box = -1;
        best->inside = false;
        best->normal = normal;
        best->point = mm_vec3_make(o.x, h, o.z);
        return true;
    }
    /* the ray's stretch over the footprint (x and z slabs) */
    float lo = 0.0f, hi = end;
    const float o2[2] = {o.x, o.z}, d2[2] = {d.x, d.z}, base[2] = {f->origin.x, f->origin.z};
    const float span[2] = {f->spacing * (float)(f->columns - 1), f->spacing * (float)(f->rows - 1)};
    for (int a = 0; a < 2; ++a) {
        if (fabsf(d2[a]) < 1e-30f) {
            if (o2[a] < base[a] || o2[a] > base[a] + span[a]) return false;
            continue;
        }
        float t0 = (base[a] - o2[a]) / d2[a], t1 = (base[a] + span[a] - o2[a]) / d2[a];
        if (t0 > t1) {
            float tmp = t0;
            t0 = t1;
            t1 = tmp;
        }
        lo = fmaxf(lo, t0);
        hi = fminf(hi, t1);
    }
    if (!(lo <= hi) || !isfinite(hi)) return false;
    float horizontal = sqrtf(d.x * d.x + d.z * d.z);
    float step = horizontal > 1e-6f ? FIELD_MARCH * f->spacing / horizontal : hi - lo;
    if (!(step > 0.0f)) step = hi - lo;
    float t0 = lo, g0 = above_field(f, o, d, t0);
    if (g0 == 0.0f && lo == 0.0f) g0 = 1.0f; /* starting on the surface: leaving it is no hit */
    if (t0 > 0.0f && g0 <= 0.0f && g0 > -INFINITY) g0 = 1.0f; /* entering the footprint below: no hit here */
    for (int n = 0; t0 < hi && n < 1 << 24; ++n) {
        float t1 = fminf(t0 + (step > 0.0f ? step : hi - t0), hi), g1 = above_field(f, o, d, t1);
        if (g0 > 0.0f && g1 <= 0.0f && g1 > -INFINITY) {
            float a = t0, b = t1;
            for (int k = 0; k < FIELD_BISECTIONS; ++k) {
                float m = 0.5f * (a + b);
                if (above_field(f, o, d, m) > 0.0f)
                    a = m;
                else
                    b = m;
            }
            mm_vec3 normal;
            float h;
            mm_vec3 p = mm_vec3_add(o, mm_vec3_scale(d, b));
            mm_scene_field_height(f, p.x, p.z, &h, &normal);
            best->distance = b;
            best->box = -1;
            best->inside = false;
            best->normal = normal;
            best->point = mm_vec3_make(p.x, h, p.z);
            return true;
        }
        if (t1 >= hi) break;
        t0 = t1, g0 = g1;
    }
    return false;
}

/* The nearest hit of o + t d (d unit), 0 <= t <= max_t, with the boxes and, when with_ground,
 * the ground plane and the terrain (stairs, ramps, field). */
static bool cast(const mm_scene *scene, mm_vec3 o, mm_vec3 d, float max_t, bool with_ground,
                 mm_scene_hit *out)
{
    bool found = false;
    mm_scene_hit best;
    memset(&best, 0, sizeof best);
    best.distance = INFINITY;
    int count = clamp_count(scene->box_count, MM_SCENE_MAX_BOXES);
    for (int b = 0; b < count; ++b) found |= cast_box(&scene->boxes[b], b, o, d, max_t, &best);
    if (with_ground) {
        int stairs = clamp_count(scene->stairs_count, MM_SCENE_MAX_STAIRS);
        for (int k = 0; k < stairs; ++k) {
            mm_scene_box step;
            for (int i = 0; mm_scene_stairs_step(&scene->stairs[k], i, &step); ++i)
                found |= cast_box(&step, -1, o, d, max_t, &best);
        }
        int ramps = clamp_count(scene->ramp_count, MM_SCENE_MAX_RAMPS);
        for (int k = 0; k < ramps; ++k) found |= cast_ramp(&scene->ramps[k], o, d, max_t, &best);
        found |= cast_field(&scene->field, o, d, max_t, &best);
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
    float best = -INFINITY;
    int best_box = -1;
    mm_vec3 normal = mm_vec3_make(0.0f, 1.0f, 0.0f);
    bool found = highest_surface(scene, point.x, point.z, lo, hi, &best, &normal, &best_box);
    float g = scene->ground;
    if (g >= lo && g <= hi && g > best) {
        best = g;
        best_box = -1;
        normal = mm_vec3_make(0.0f, 1.0f, 0.0f);
        found = true;
    }
    if (!found) return false;
    if (hit) {
        hit->point = mm_vec3_make(point.x, best, point.z);
        hit->normal = normal;
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
