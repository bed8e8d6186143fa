/* mm/scene.h - a static scene: boxes, ramps, stairs and a height field on a ground plane; the
 * height of the ground under any point, and the ray queries the moves need.
 *
 * A scene is a ground plane at height `ground` (the solid half-space y <= ground) and up to
 * MM_SCENE_MAX_BOXES boxes. A box stands upright: `position` is the centre of its BOTTOM face
 * (so a box resting on the ground has position.y == ground), `size` its full extents along its
 * own x, y and z axes, and `yaw` its rotation in radians about +Y (right-handed: a yaw of pi/2
 * turns the box's +Z axis to world +X). Boxes are closed solids: a ray that touches an edge or
 * runs along a face hits it. Everything is in metres, Y up; a scene is a plain struct the caller
 * owns, and no function here allocates.
 *
 * Terrain: a ramp is a solid wedge whose top rises along its own +Z; stairs are solid steps rising
 * along their own +Z; a height field is a grid of heights over the x-z plane, triangulated (see
 * mm_scene_field). mm_scene_ground_height gives the height and normal of the highest surface
 * under a point (the ground plane, the field, ramps, steps and box tops): where a foot stands.
 *
 * Rays: mm_scene_raycast returns the nearest hit of a ray with the boxes and the ground. A ray
 * that starts inside a box (or below the ground) hits at distance 0, at its origin, with the
 * normal facing back along the ray and `inside` set; a ray starting on a surface and leaving it
 * does not hit that surface.
 *
 * Queries for the moves (seed 000, 三.4): a ground probe (the surface a foot would stand on) and
 * an obstacle measure (the wall ahead: its distance, height and depth, found with rays).
 *
 * Loading scenes from JSON is in mm/scene_json.h (the mm_build library); the format and these
 * functions are described in docs/scene.md.
 *
 * Functions: mm_scene_init mm_scene_add_box mm_scene_box_centre mm_scene_raycast
 *            mm_scene_ground_probe mm_scene_measure_obstacle mm_scene_add_ramp mm_scene_add_stairs
 *            mm_scene_set_field mm_scene_stairs_step mm_scene_ground_height mm_scene_is_flat
 *            mm_scene_field_height mm_scene_collide_capsule
 */
#ifndef MM_SCENE_H
#define MM_SCENE_H

#include <stdbool.h>

#include "math.h"
#include "result.h"

#ifdef __cplusplus
extern "C" {
#endif

#define MM_SCENE_MAX_BOXES 256
/* The largest coordinate or size a scene accepts (metres); keeps the ray arithmetic finite. */
#define MM_SCENE_MAX_EXTENT 1.0e6f

typedef struct mm_scene_box {
    mm_vec3 position; /* centre of the bottom face, metres */
    mm_vec3 size;     /* full extents along the box's x, y, z (>= 0), metres */
    float yaw;        /* radians about +Y */
} mm_scene_box;

#define MM_SCENE_MAX_RAMPS  64
#define MM_SCENE_MAX_STAIRS 64
#define MM_SCENE_MAX_STEPS  128 /* steps in one flight of stairs */
/* samples in the height field (columns * rows), e.g. 128 x 128 */
#define MM_SCENE_MAX_FIELD_SAMPLES 16384

/* A ramp: a solid wedge standing on its base. position is the centre of its footprint at its base
 * height; size.x its width (along its own x), size.y its rise, size.z its length (along its own
 * z); its top rises linearly from position.y at local z = -size.z / 2 to position.y + size.y at
 * local z = +size.z / 2. yaw as a box's (a ramp rising toward world +X has yaw pi/2). */
typedef struct mm_scene_ramp {
    mm_vec3 position;
    mm_vec3 size;
    float yaw;
} mm_scene_ramp;

/* Stairs: `steps` solid steps filling the footprint size.x by size.z centred on position (at the
 * base height position.y), rising along their own +Z: step i (0 first) spans local z in
 * [-size.z / 2 + i run, -size.z / 2 + (i + 1) run] with run = size.z / steps and its top at
 * position.y + (i + 1) size.y / steps (the riser). Each step is a box from the base up. Stairs
 * going down are stairs turned round (yaw + pi). */
typedef struct mm_scene_stairs {
    mm_vec3 position;
    mm_vec3 size;
    float yaw;
    int steps;
} mm_scene_stairs;

/* A height field: columns x rows samples, spacing metres apart along world x (columns) and z
 * (rows), sample (i, j) at (origin.x + i spacing, origin.y + heights[j columns + i], origin.z +
 * j spacing). Each cell is two triangles split along its diagonal from (i, j) to (i + 1, j + 1):
 * the surface is continuous and planar on each triangle. Outside its footprint there is no
 * field. A field is a surface, not a solid: rays hit it from above only. columns 0: none. */
typedef struct mm_scene_field {
    mm_vec3 origin;
    float spacing;
    int columns, rows;
    float heights[MM_SCENE_MAX_FIELD_SAMPLES];
} mm_scene_field;

typedef struct mm_scene {
    float ground; /* height of the ground plane, metres */
    int box_count;
    mm_scene_box boxes[MM_SCENE_MAX_BOXES];
    int ramp_count;
    mm_scene_ramp ramps[MM_SCENE_MAX_RAMPS];
    int stairs_count;
    mm_scene_stairs stairs[MM_SCENE_MAX_STAIRS];
    mm_scene_field field;
} mm_scene;

typedef struct mm_scene_hit {
    mm_vec3 point;  /* where the ray hit */
    mm_vec3 normal; /* unit normal of the surface hit, facing the ray's origin */
    float distance; /* metres along the ray from its origin (0 when it starts inside) */
    int box;        /* index of the box hit; -1 for the ground plane and the terrain (field, ramps,
                       stairs) */
    bool inside;    /* the ray started inside the solid hit */
} mm_scene_hit;

/* An empty scene with the ground at the given height. */
void mm_scene_init(mm_scene *scene, float ground);

/* Adds a box (see the top of this file for the meaning of the fields). MM_ERR_LIMIT when the
 * scene is full; MM_ERR_OUT_OF_RANGE for a non-finite value, a negative size or a value beyond
 * MM_SCENE_MAX_EXTENT. */
mm_result mm_scene_add_box(mm_scene *scene, mm_vec3 position, mm_vec3 size, float yaw);

/* The centre of a box's volume (its position raised by half its height). */
mm_vec3 mm_scene_box_centre(const mm_scene_box *box);

/* The nearest hit of the ray origin + t * direction, 0 <= t <= max_distance, with the boxes, the
 * ramps and steps (solids), the height field (from above) and the ground plane (direction need not
 * be unit: distances are along the normalised direction; max_distance may be INFINITY). Returns
 * false (hit untouched) when nothing is hit, when direction is zero, or for non-finite input.
 * When a box and the ground are hit at the same distance the box is reported; between boxes,
 * the lowest index; at an edge or a corner the normal is that of the face entered along x, then
 * y, then z. hit may be NULL. */
bool mm_scene_raycast(const mm_scene *scene, mm_vec3 origin, mm_vec3 direction, float max_distance,
                      mm_scene_hit *hit);

/* The ground under a point: the highest surface, among the ground, the box tops and the terrain's
 * surfaces (field, ramp tops, step tops) whose
 * footprint contains (point.x, point.z), whose height lies within [point.y - max_drop,
 * point.y + step_height]. It is what a ray cast straight down from step_height above the point
 * meets first, except that a box whose top is above that window is a wall, not ground, and is
 * passed through. max_drop may be INFINITY. On success hit->point is (point.x, height,
 * point.z), hit->normal the surface's upward normal (+Y on the plane and flat tops), hit->distance is point.y
 * - height (negative for a step up) and hit->box the box (-1 for the ground). Returns false when no surface
 * is in the window. */
bool mm_scene_ground_probe(const mm_scene *scene, mm_vec3 point, float step_height, float max_drop,
                           mm_scene_hit *hit);

/* Adds a ramp or stairs (see mm_scene_ramp, mm_scene_stairs). MM_ERR_LIMIT when the scene has
 * no room; MM_ERR_OUT_OF_RANGE for a non-finite value, a negative size, a value beyond
 * MM_SCENE_MAX_EXTENT, a ramp of zero length, or steps outside [1, MM_SCENE_MAX_STEPS]. */
mm_result mm_scene_add_ramp(mm_scene *scene, mm_vec3 position, mm_vec3 size, float yaw);
mm_result mm_scene_add_stairs(mm_scene *scene, mm_vec3 position, mm_vec3 size, float yaw, int steps);

/* Sets the height field (mm_scene_field): heights has columns * rows values, row by row (z), x
 * fastest. MM_ERR_LIMIT beyond MM_SCENE_MAX_FIELD_SAMPLES; MM_ERR_OUT_OF_RANGE for fewer than 2
 * columns or rows, a spacing not > 0, or a non-finite or oversized value. columns 0 and rows 0
 * (heights may be NULL) removes the field. */
mm_result mm_scene_set_field(mm_scene *scene, mm_vec3 origin, float spacing, int columns, int rows,
                             const float *heights);

/* Step i of stairs s as a box (false when i is out of range). */
bool mm_scene_stairs_step(const mm_scene_stairs *s, int i, mm_scene_box *out);

/* The field's height and normal at (x, z); false (outputs untouched) outside its footprint or
 * without a field. normal may be NULL. */
bool mm_scene_field_height(const mm_scene_field *field, float x, float z, float *height, mm_vec3 *normal);

/* The ground under (x, z): the height of the highest surface whose footprint contains the point,
 * among the ground plane, the height field, the ramps' tops, the steps' tops and the boxes' tops
 * (footprints are closed: on an edge the higher side counts). *normal (may be NULL) is that
 * surface's unit upward normal (+Y on a flat top). Non-finite input, or no scene: the ground
 * plane of a NULL scene is y = 0 with normal +Y. */
float mm_scene_ground_height(const mm_scene *scene, float x, float z, mm_vec3 *normal);

/* True when the scene's ground is the plane y = 0 and nothing else (no boxes, ramps, stairs or
 * field): a character on it runs exactly as on no scene. NULL is flat. */
bool mm_scene_is_flat(const mm_scene *scene);

/* True when the scene has terrain to walk on: ramps, stairs or a height field (NULL: false). */
bool mm_scene_has_terrain(const mm_scene *scene);

#define MM_OBSTACLE_MAX_PROBES 16

/* How an obstacle is looked for. Zero fields take the defaults in brackets. */
typedef struct mm_obstacle_desc {
    float max_distance;         /* how far ahead to look, metres [1.5] */
    float max_height;           /* the height-measuring ray starts this far above the feet [3] */
    float max_depth;            /* depth measured at most this far past the near face [5] */
    const float *probe_heights; /* heights above the feet of the forward rays [0.3 0.7 1.1 1.5 1.9] */
    int probe_count;            /* at most MM_OBSTACLE_MAX_PROBES; 0 with NULL: the default list */
} mm_obstacle_desc;

typedef struct mm_obstacle {
    mm_scene_hit hit; /* the forward ray's hit on the near face (box >= 0) */
    int probe;        /* index of the probe height whose ray hit nearest (the lowest of equals) */
    float distance;   /* horizontal distance from the feet to the near face, metres */
    float floor;      /* height of the surface in front of the near face (where it stands) */
    float top;        /* world height of the obstacle's top over the near face */
    float height;     /* top - floor: how high it is above the ground at the hit, metres */
    float depth;      /* extent along the direction from the near face to the far face, metres */
    bool too_high;    /* no top below feet + max_height: top and height are clamped to it */
    bool too_deep;    /* not left within max_depth: depth is max_depth */
} mm_obstacle;

/* Measures the first obstacle ahead, with rays, as the vault needs it (seed 000, 三.4):
 *  1. forward rays, one per probe height above `feet`, along `forward` projected onto the
 *     ground plane, find the nearest box face within max_distance (the ground and the terrain
 *     (field, ramps, stairs) are walked on, not obstacles);
 *  2. a ray along the direction from the hit point, through the obstacle, finds where it is
 *     left: the depth. Boxes that touch or overlap along the way count as one obstacle (joined
 *     walls in a row);
 *  3. a ray straight up from just inside the near face finds where the solid ends: the top
 *     (again through boxes stacked on it), clamped to feet.y + max_height; a ray straight down
 *     from 1 mm in front of the face, at the hit height, finds the floor it stands on.
 * Returns false (out untouched) when nothing is ahead, when forward has no horizontal part, or
 * for non-finite input. desc may be NULL (defaults). */
bool mm_scene_measure_obstacle(const mm_scene *scene, mm_vec3 feet, mm_vec3 forward,
                               const mm_obstacle_desc *desc, mm_obstacle *out);

/* Collision (src/scene/collide.c): a vertical capsule of `radius` whose axis passes through
 * (position.x, position.z) is pushed sideways out of every box whose top is above `bottom` and
 * whose bottom is below `top` (lower boxes are stepped over, higher ones walked under; bottom may
 * be above top: a box must then reach over bottom and under top, and INFINITY makes none a wall), through the
 * nearer side when its axis is inside one; boxes meeting at a corner are settled in a few rounds. position.y
 * is untouched. A face within radius + skin touches it (skin >= 0: a capsule resting against a wall, pushed
 * out on the last step, still touches it). Writes up to max_normals unit horizontal normals of the faces
 * touched (pointing out of the boxes; normals may be NULL) and returns how many faces touched (0: clear, or
 * bad input). Allocates nothing. */
int mm_scene_collide_capsule(const mm_scene *scene, float radius, float skin, float bottom, float top,
                             mm_vec3 *position, mm_vec3 *normals, int max_normals);

#ifdef __cplusplus
}
#endif

#endif /* MM_SCENE_H */
