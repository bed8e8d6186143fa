/* mm/body_mesh.h - a skinned body for the renderer: one mm makes from any skeleton (limbs, torso,
 * head with a visor, hands and feet sized from the bone lengths), or a user's mesh skinned to the
 * skeleton (FBX, glTF: through assimp). Library mm_render.
 *
 *   mm_body_mesh body;
 *   mm_body_mesh_build_from_database(&db, &body, &err);     or mm_body_mesh_load(...)
 *   scene.body_mesh = &body;                                 the renderer skins and draws it
 *   mm_body_mesh_free(&body);
 *
 * Skinning is linear blend skinning on the CPU: every vertex is stored in the frame of each joint
 * that moves it (its position and normal there), and a pose places it at the weighted sum of those
 * joints' world transforms applied to it. A mesh made by mm_body_mesh_build has 1 or 2 joints per
 * vertex (2 where a limb or the spine bends: elbows, knees, shoulders, hips, the spine's joints);
 * a loaded mesh up to MM_BODY_MAX_INFLUENCES.
 *
 * The body made from a skeleton finds its limbs from the bone roles (the hips, the feet, toes,
 * hands and the head: mm_body_roles), never from the joint names: a leg is the chain from the hips
 * to a foot (thigh: the foot's grandparent to its parent; shin: the parent to the foot), an arm the
 * chain from the spine to a hand (upper arm, forearm: the hand's grandparent and parent), the spine
 * the chain from the hips to the head. Sizes follow the leg length (thigh + shin; 0.86 m is a
 * 1.75 m adult); left and right from the hip joints; forward = left x up.
 *
 * Functions: mm_body_roles_from_database mm_body_mesh_build mm_body_mesh_build_from_database
 *            mm_body_mesh_load mm_body_mesh_skin mm_body_mesh_free mm_body_mesh_bind_score mm_body_facing
 */
#ifndef MM_BODY_MESH_H
#define MM_BODY_MESH_H

#include <stdbool.h>
#include <stdint.h>

#include "database.h"
#include "math.h"
#include "result.h"
#include "skeleton.h"

#ifdef __cplusplus
extern "C" {
#endif

#define MM_BODY_MAX_INFLUENCES 4

typedef struct mm_body_mesh {
    int vertex_count, triangle_count;
    int joint_count; /* of the skeleton it is skinned to */
    /* in the bind pose (world, m): the pose the mesh was made or exported in */
    mm_vec3 *bind_positions; /* [vertex_count] */
    mm_vec3 *bind_normals;   /* [vertex_count], unit */
    float *colors;           /* [vertex_count * 3]: linear RGB, 0 to 1 */
    /* influences, MM_BODY_MAX_INFLUENCES per vertex: joint (-1: none), weight (they sum to 1), the
     * vertex's position and normal in that joint's frame */
    int32_t *joints;
    float *weights;
    mm_vec3 *local_positions;
    mm_vec3 *local_normals;
    uint32_t *indices; /* [3 * triangle_count], triangles of vertex indices */
} mm_body_mesh;

/* Index 0 is the left side, 1 the right. -1: not known. */
typedef struct mm_body_roles {
    int hips, head;
    int foot[2], toe[2], hand[2];
} mm_body_roles;

/* The database's bone roles (mm_database_role_joint); a toe not named is the foot's first child. */
void mm_body_roles_from_database(const mm_database *db, mm_body_roles *out);

typedef struct mm_body_desc {
    int joint_count;
    const int *parents;    /* [joint_count], -1 for a root */
    const mm_xform *poses; /* pose_count poses of joint_count world transforms (m, +Y up) */
    int pose_count;        /* the body is bound to the one of best mm_body_mesh_bind_score */
    mm_body_roles roles;   /* hips, head and both feet needed; without hands, no arms */
} mm_body_desc;

/* How well a pose suits binding (higher is better, at most 1): limbs straight (the distance from
 * a limb's first joint to its end over the sum of its two bones' lengths) and the spine upright. */
float mm_body_mesh_bind_score(const mm_body_desc *d, const mm_xform *pose);

/* Makes the body of the skeleton (see the top of this file). MM_ERR_NOT_FOUND when a role the body
 * needs is missing, MM_ERR_INVALID_ARGUMENT for a pose that is not finite or a skeleton whose legs
 * have no length. */
mm_result mm_body_mesh_build(const mm_body_desc *d, mm_body_mesh *out, mm_error *err);

/* The body of a database's skeleton, its roles from the database, bound to the most suitable of
 * up to 256 frames spread over the database. */
mm_result mm_body_mesh_build_from_database(const mm_database *db, mm_body_mesh *out, mm_error *err);

/* Loads the skinned meshes of an FBX, glTF or Collada file (through assimp) for the skeleton of
 * joint_count joints: every bone of the file is matched by name to a joint (a bone no joint is named
 * like is an error naming it), each bone's frame taken to be its joint's. Units are matched by the
 * bone lengths: the distance between a bone and its parent bone in the file against the skeleton's
 * offsets (their median ratio). Vertex colours from the materials' diffuse colour. MM_ERR_IO for a
 * file assimp cannot read, MM_ERR_NOT_FOUND for one without a skinned mesh or with a bone no joint is
 * named like, MM_ERR_UNSUPPORTED when mm is
 * built without assimp. */
mm_result mm_body_mesh_load(const char *path, const mm_joint *joints, int joint_count, mm_body_mesh *out,
                            mm_error *err);

/* Places the mesh in a pose: global holds the skeleton's joint_count world transforms; positions
 * and normals (vertex_count each) receive the skinned vertices. No allocation. */
void mm_body_mesh_skin(const mm_body_mesh *m, const mm_xform *global, mm_vec3 *positions, mm_vec3 *normals);

void mm_body_mesh_free(mm_body_mesh *m);

/* The yaw (rad about +Y, 0 facing +Z) a pose faces: at right angles to the line from the right hip
 * joint to the left one (the feet's grandparents), left = up x forward; fallback without them. */
float mm_body_facing(const mm_body_roles *roles, const int *parents, int joint_count, const mm_xform *pose,
                     float fallback);

#ifdef __cplusplus
}
#endif

#endif /* MM_BODY_MESH_H */
