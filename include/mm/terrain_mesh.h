/* mm/terrain_mesh.h - a scene's terrain as triangles to draw: the height field, the ramps and the
 * stairs (mm/scene.h). The boxes are not in it (the renderer draws them as boxes).
 *
 * Each triangle is 3 vertices of 6 floats: position x, y, z then the unit normal of its face,
 * counter-clockwise seen from outside (from above for the field). The field gives two triangles per
 * cell, split along the same diagonal as mm_scene_ground_height's (the drawn surface is the one
 * the feet stand on); a ramp gives its top, its two sides and its high end (6); a flight of stairs
 * each step's box without its bottom (10 a step). Nothing here allocates.
 *
 *   int n = mm_terrain_mesh(scene, NULL, 0);
 *   float *v = malloc(sizeof(float) * MM_TERRAIN_MESH_FLOATS * n);
 *   mm_terrain_mesh(scene, v, n);
 *
 * Functions: mm_terrain_mesh
 */
#ifndef MM_TERRAIN_MESH_H
#define MM_TERRAIN_MESH_H

#include "scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* floats per triangle: 3 vertices of position and normal */
#define MM_TERRAIN_MESH_FLOATS 18

/* Writes at most capacity triangles of the scene's terrain into out (may be NULL with capacity 0);
 * returns how many the whole terrain has (0 for NULL or a scene without terrain). */
int mm_terrain_mesh(const mm_scene *scene, float *out, int capacity);

#ifdef __cplusplus
}
#endif

#endif /* MM_TERRAIN_MESH_H */
