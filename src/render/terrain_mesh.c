/* A scene's terrain as triangles: the field's cells, the ramps' faces, the stairs' steps. */
#include <mm/terrain_mesh.h>

#include <math.h>

typedef struct mesh {
    float *out;
    int capacity, count;
} mesh;

/* Adds the triangle a, b, c (counter-clockwise seen from outside) with its face's normal. */
static void triangle(mesh *m, mm_vec3 a, mm_vec3 b, mm_vec3 c)
{
    if (m->out && m->count < m->capacity) {
        mm_vec3 n = mm_vec3_normalize(mm_vec3_cross(mm_vec3_sub(b, a), mm_vec3_sub(c, a)));
        float *o = m->out + (size_t)m->count * MM_TERRAIN_MESH_FLOATS;
        const mm_vec3 p[3] = {a, b, c};
        for (int k = 0; k < 3; ++k) {
            o[6 * k + 0] = p[k].x, o[6 * k + 1] = p[k].y, o[6 * k + 2] = p[k].z;
            o[6 * k + 3] = n.x, o[6 * k + 4] = n.y, o[6 * k + 5] = n.z;
        }
    }
    ++m->count;
}

/* a, b, c, d counter-clockwise seen from outside */
static void quad(mesh *m, mm_vec3 a, mm_vec3 b, mm_vec3 c, mm_vec3 d)
{
    triangle(m, a, b, c);
    triangle(m, a, c, d);
}

/* A point in a footprint's frame (local x, y above its base, z) to the world. */
static mm_vec3 world(mm_vec3 position, float yaw, float x, float y, float z)
{
    float c = cosf(yaw), s = sinf(yaw);
    return mm_vec3_make(position.x + c * x + s * z, position.y + y, position.z - s * x + c * z);
}

static void field(mesh *m, const mm_scene_field *f)
{
    if (f->columns < 2 || f->rows < 2 || f->columns * f->rows > MM_SCENE_MAX_FIELD_SAMPLES) return;
    for (int j = 0; j + 1 < f->rows; ++j)
        for (int i = 0; i + 1 < f->columns; ++i) {
            mm_vec3 p[4]; /* (i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1) */
            static const int di[4] = {0, 1, 1, 0}, dj[4] = {0, 0, 1, 1};
            for (int k = 0; k < 4; ++k)
                p[k] = mm_vec3_make(f->origin.x + f->spacing * (float)(i + di[k]),
                                    f->origin.y + f->heights[(j + dj[k]) * f->columns + i + di[k]],
                                    f->origin.z + f->spacing * (float)(j + dj[k]));
            /* up is +Y: seen from above, x then z turns clockwise, so the order is reversed */
            triangle(m, p[0], p[2], p[1]);
            triangle(m, p[0], p[3], p[2]);
        }
}

static void ramp(mesh *m, const mm_scene_ramp *r)
{
    float hx = 0.5f * r->size.x, hz = 0.5f * r->size.z, rise = r->size.y;
    mm_vec3 lo_l = world(r->position, r->yaw, -hx, 0, -hz), lo_r = world(r->position, r->yaw, hx, 0, -hz);
    mm_vec3 hi_l = world(r->position, r->yaw, -hx, rise, hz), hi_r = world(r->position, r->yaw, hx, rise, hz);
    mm_vec3 base_l = world(r->position, r->yaw, -hx, 0, hz), base_r = world(r->position, r->yaw, hx, 0, hz);
    quad(m, lo_l, hi_l, hi_r, lo_r);     /* top */
    triangle(m, lo_l, base_l, hi_l);     /* left side */
    triangle(m, lo_r, hi_r, base_r);     /* right side */
    quad(m, base_l, base_r, hi_r, hi_l); /* the high end */
}

/* A box without its bottom: the top and four sides. */
static void box(mesh *m, const mm_scene_box *b)
{
    float hx = 0.5f * b->size.x, hz = 0.5f * b->size.z, h = b->size.y;
    mm_vec3 c[8];
    for (int i = 0; i < 8; ++i)
        c[i] = world(b->position, b->yaw, i & 1 ? hx : -hx, i & 2 ? h : 0.0f, i & 4 ? hz : -hz);
    quad(m, c[2], c[6], c[7], c[3]); /* top (+y) */
    quad(m, c[0], c[2], c[3], c[1]); /* -z */
    quad(m, c[4], c[5], c[7], c[6]); /* +z */
    quad(m, c[0], c[4], c[6], c[2]); /* -x */
    quad(m, c[1], c[3], c[7], c[5]); /* +x */
}

int mm_terrain_mesh(const mm_scene *scene, float *out, int capacity)
{
    mesh m = {out, capacity > 0 ? capacity : 0, 0};
    if (!scene) return 0;
    field(&m, &scene->field);
    for (int k = 0; k < scene->ramp_count && k < MM_SCENE_MAX_RAMPS; ++k) ramp(&m, &scene->ramps[k]);
    for (int k = 0; k < scene->stairs_count && k < MM_SCENE_MAX_STAIRS; ++k) {
        mm_scene_box step;
        for (int i = 0; mm_scene_stairs_step(&scene->stairs[k], i, &step); ++i) box(&m, &step);
    }
    return m.count;
}
