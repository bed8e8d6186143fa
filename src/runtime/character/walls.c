/* Stage 8: the body out of the walls. */
#include "walls.h"

#include <math.h>

/* rounds over the walls: a push out of one wall may go into another (a corner) */
#define WALL_ROUNDS 4
/* m: a joint this close to a face counts as out (float rounding) */
#define WALL_SKIN 1e-5f

/* A box's frame: the world point p in it (horizontal), and a local direction back in the world. */
static void to_box(const mm_scene_box *b, mm_vec3 p, float *lx, float *lz)
{
    float s = sinf(b->yaw), c = cosf(b->yaw), dx = p.x - b->position.x, dz = p.z - b->position.z;
    *lx = c * dx - s * dz;
    *lz = s * dx + c * dz;
}

static mm_vec3 from_box(const mm_scene_box *b, float lx, float lz)
{
    float s = sinf(b->yaw), c = cosf(b->yaw);
    return mm_vec3_make(c * lx + s * lz, 0.0f, -s * lx + c * lz);
}

/* The depth of p in the box through the face (axis 0: x, 1: z; side +-1): how far it moves along
 * that face's normal to leave; 0 outside. */
static float depth_through(const mm_scene_box *b, mm_vec3 p, int axis, float side)
{
    if (!(p.y > b->position.y && p.y < b->position.y + b->size.y)) return 0.0f;
    float lx, lz, hx = 0.5f * b->size.x, hz = 0.5f * b->size.z;
    to_box(b, p, &lx, &lz);
    if (!(fabsf(lx) < hx && fabsf(lz) < hz)) return 0.0f;
    return axis == 0 ? hx - side * lx : hz - side * lz;
}

mm_vec3 mm_walls_push(const mm_trajectory *t, mm_vec3 root, const mm_rig_pose *pose, int joint_count)
{
    mm_vec3 delta = mm_vec3_make(0, 0, 0);
    const mm_scene *scene = t ? t->scene : NULL;
    if (!scene) return delta;
    const mm_trajectory_desc *d = &t->desc;
    float pass = t->pass_height >= 0.0f ? t->pass_height : d->collider_step;
    float bottom = t->floor + pass, top = t->floor + d->collider_height;
    for (int round = 0; round < WALL_ROUNDS; ++round) {
        bool moved = false;
        for (int b = 0; b < scene->box_count; ++b) {
            const mm_scene_box *box = &scene->boxes[b];
            if (box->position.y + box->size.y <= bottom || box->position.y >= top) continue;
            /* the face toward the root: the axis it is farthest out along */
            float lx, lz;
            to_box(box, mm_vec3_add(root, delta), &lx, &lz);
            float out_x = fabsf(lx) - 0.5f * box->size.x, out_z = fabsf(lz) - 0.5f * box->size.z;
            int axis = out_x > out_z ? 0 : 1;
            float side = (axis == 0 ? lx : lz) >= 0.0f ? 1.0f : -1.0f;
            float deepest = 0.0f;
            for (int j = 1; j < joint_count; ++j)
                deepest = fmaxf(
                    deepest, depth_through(box, mm_vec3_add(pose->global[j].translation, delta), axis, side));
            if (deepest <= WALL_SKIN) continue;
            mm_vec3 push =
                from_box(box, axis == 0 ? side * deepest : 0.0f, axis == 1 ? side * deepest : 0.0f);
            delta = mm_vec3_add(delta, push);
            moved = true;
        }
        if (!moved) break;
    }
    return delta;
}

void mm_walls_move_body(mm_xform *root, mm_rig_pose *pose, int joint_count, mm_feet *feet, mm_vec3 delta)
{
    root->translation = mm_vec3_add(root->translation, delta);
    pose->local_positions[0] = root->translation;
    for (int j = 0; j < joint_count; ++j)
        pose->global[j].translation = mm_vec3_add(pose->global[j].translation, delta);
    for (int k = 0; k < 2; ++k) { /* what a planted foot holds moves out with it */
        feet->lock[k] = mm_vec3_add(feet->lock[k], delta);
        feet->heel_lock[k] = mm_vec3_add(feet->heel_lock[k], delta);
        feet->toe_lock[k] = mm_vec3_add(feet->toe_lock[k], delta);
        feet->last_ankle[k] = mm_vec3_add(feet->last_ankle[k], delta);
        feet->last_toe[k] = mm_vec3_add(feet->last_toe[k], delta);
    }
}
