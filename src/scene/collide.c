/* A vertical capsule against a scene's boxes: pushed out sideways, with the faces it rests on
 * (mm/scene.h, mm_scene_collide_capsule; docs/scene.md, "Collision"). */
#include <mm/scene.h>

#include <math.h>

#include "math_private.h"

/* rounds of pushing out: a capsule in a corner is pushed out of one box into another and back;
 * a few rounds settle it between boxes meeting at any angle */
#define COLLIDE_ROUNDS 4
/* m: a distance shorter than this is rounding: no direction can be taken from it */
#define CONTACT_EPSILON 1e-6f
/* two contacts whose normals are this close (cosine) are the same face */
#define SAME_FACE_COS 0.9999f

/* A circle of radius r about p against the box's footprint: false when it is farther than r +
 * skin. Else the unit normal (world, horizontal, out of the box) of the contact and the push
 * (metres along it, 0 within the skin) that takes the circle out, through the nearer side when
 * its centre is inside. */
static bool touch_footprint(const mm_scene_box *box, float r, float skin, mm_vec3 p, mm_vec3 *normal,
                            float *push)
{
    float s = sinf(box->yaw), c = cosf(box->yaw), hx = 0.5f * box->size.x, hz = 0.5f * box->size.z;
    float dx = p.x - box->position.x, dz = p.z - box->position.z;
    /* into the box's frame: turn by -yaw about +Y */
    float lx = c * dx - s * dz, lz = s * dx + c * dz;
    float cx = clampf(lx, -hx, hx), cz = clampf(lz, -hz, hz);
    float ex = lx - cx, ez = lz - cz, e = sqrtf(ex * ex + ez * ez), nx, nz;
    if (e >= r + skin) return false;
    if (e > CONTACT_EPSILON) { /* the centre outside: along the line from the nearest point */
        nx = ex / e, nz = ez / e;
        *push = e < r ? r - e : 0.0f;
    } else if (hx - fabsf(lx) < hz - fabsf(lz)) { /* inside: out through the nearer side */
        nx = lx >= 0.0f ? 1.0f : -1.0f, nz = 0.0f;
        *push = hx - fabsf(lx) + r;
    } else {
        nx = 0.0f, nz = lz >= 0.0f ? 1.0f : -1.0f;
        *push = hz - fabsf(lz) + r;
    }
    *normal = mm_vec3_make(c * nx + s * nz, 0.0f, -s * nx + c * nz); /* back to the world: by +yaw */
    return true;
}

int mm_scene_collide_capsule(const mm_scene *scene, float radius, float skin, float bottom, float top,
                             mm_vec3 *position, mm_vec3 *normals, int max_normals)
{
    if (!scene || !position || !(radius > 0.0f) || !isfinite(radius) || !(skin >= 0.0f) || !isfinite(skin) ||
        !isfinite(bottom) || !isfinite(top) || !isfinite(position->x) || !isfinite(position->z))
        return 0;
    int count = 0, limit = normals && max_normals > 0 ? max_normals : 0;
    for (int round = 0; round < COLLIDE_ROUNDS; ++round) {
        bool moved = false;
        for (int b = 0; b < scene->box_count; ++b) {
            const mm_scene_box *box = &scene->boxes[b];
            /* only boxes across the capsule's tested span: lower ones are stepped over, higher
             * ones walked under */
            if (box->position.y + box->size.y <= bottom || box->position.y >= top) continue;
            mm_vec3 n;
            float push;
            if (!touch_footprint(box, radius, skin, *position, &n, &push)) continue;
            if (push > 0.0f) {
                position->x += n.x * push;
                position->z += n.z * push;
                moved = true;
            }
            int stored = count < limit ? count : limit, k = 0;
            /* a face met again in a later round is the same contact */
            while (k < stored && mm_vec3_dot(normals[k], n) < SAME_FACE_COS) ++k;
            if (k == stored && (round == 0 || count < limit)) {
                if (count < limit) normals[count] = n;
                ++count;
            }
        }
        if (!moved) break;
    }
    return count;
}
