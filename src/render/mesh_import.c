/* A user's skinned mesh (FBX, glTF, Collada) read through assimp and bound to a skeleton by bone
 * names: each bone's frame is its joint's, the file's units matched to the skeleton's by the bone
 * lengths. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <mm/body_mesh.h>

#ifdef MM_HAVE_ASSIMP
#include <assimp/cimport.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

static const float default_color[3] = {0.62f, 0.68f, 0.78f};

/* A bone's offset matrix (mesh space to bone space, maybe scaled) as the bone's position in mesh
 * space, its rotation (rows: mesh to bone) and its scale. */
typedef struct bone_frame {
    mm_vec3 origin; /* in mesh space */
    float r[3][3];  /* bone-space axes in mesh space, as rows: bone = r (mesh - origin) */
    int joint;
} bone_frame;

static void bone_frame_from(const struct aiMatrix4x4 *o, bone_frame *f)
{
    const float m[3][4] = {
        {o->a1, o->a2, o->a3, o->a4}, {o->b1, o->b2, o->b3, o->b4}, {o->c1, o->c2, o->c3, o->c4}};
    float scale = cbrtf(fabsf(m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                              m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                              m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])));
    if (!(scale > 1e-12f)) scale = 1.0f;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) f->r[i][j] = m[i][j] / scale;
    /* bone = R (mesh) + t  ->  origin = -R^T t (in mesh units: t / scale) */
    mm_vec3 t = mm_vec3_make(m[0][3] / scale, m[1][3] / scale, m[2][3] / scale);
    f->origin = mm_vec3_make(-(f->r[0][0] * t.x + f->r[1][0] * t.y + f->r[2][0] * t.z),
                             -(f->r[0][1] * t.x + f->r[1][1] * t.y + f->r[2][1] * t.z),
                             -(f->r[0][2] * t.x + f->r[1][2] * t.y + f->r[2][2] * t.z));
}

static mm_vec3 rotate_rows(const float r[3][3], mm_vec3 v)
{
    return mm_vec3_make(r[0][0] * v.x + r[0][1] * v.y + r[0][2] * v.z,
                        r[1][0] * v.x + r[1][1] * v.y + r[1][2] * v.z,
                        r[2][0] * v.x + r[2][1] * v.y + r[2][2] * v.z);
}

static int find_joint(const mm_joint *joints, int count, const char *name)
{
    for (int j = 0; j < count; ++j)
        if (strcmp(joints[j].name, name) == 0) return j;
    return -1;
}

static int compare_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

mm_result mm_body_mesh_load(const char *path, const mm_joint *joints, int joint_count, mm_body_mesh *out,
                            mm_error *err)
{
    memset(out, 0, sizeof *out);
    if (err) snprintf(err->file, sizeof err->file, "%s", path ? path : "");
    if (!path || !joints || joint_count < 1)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no mesh file or no skeleton to bind it to");
    const struct aiScene *scene = aiImportFile(
        path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_GenSmoothNormals |
                  aiProcess_LimitBoneWeights | aiProcess_ValidateDataStructure);
    if (!scene) return mm_error_set(err, MM_ERR_IO, 0, 0, "cannot read the mesh: %s", aiGetErrorString());
    mm_result result = MM_OK;
    /* every bone of every skinned mesh: its joint, and the scale (metres per file unit) */
    int vertices = 0, triangles = 0, bones = 0;
    for (unsigned i = 0; i < scene->mNumMeshes; ++i) {
        const struct aiMesh *m = scene->mMeshes[i];
        if (m->mNumBones == 0) continue;
        vertices += (int)m->mNumVertices;
        bones += (int)m->mNumBones;
        for (unsigned f = 0; f < m->mNumFaces; ++f) triangles += m->mFaces[f].mNumIndices == 3;
    }
    if (vertices == 0 || triangles == 0) {
        aiReleaseImport(scene);
        return mm_error_set(err, MM_ERR_NOT_FOUND, 0, 0, "the file has no skinned mesh (no mesh with bones)");
    }
    bone_frame *frames = calloc((size_t)bones, sizeof *frames);
    float *ratios = calloc((size_t)bones, sizeof *ratios);
    out->joint_count = joint_count;
    out->bind_positions = malloc(sizeof(mm_vec3) * (size_t)vertices);
    out->bind_normals = malloc(sizeof(mm_vec3) * (size_t)vertices);
    out->colors = malloc(sizeof(float) * 3 * (size_t)vertices);
    out->joints = malloc(sizeof(int32_t) * MM_BODY_MAX_INFLUENCES * (size_t)vertices);
    out->weights = calloc(MM_BODY_MAX_INFLUENCES * (size_t)vertices, sizeof(float));
    out->local_positions = calloc(MM_BODY_MAX_INFLUENCES * (size_t)vertices, sizeof(mm_vec3));
    out->local_normals = calloc(MM_BODY_MAX_INFLUENCES * (size_t)vertices, sizeof(mm_vec3));
    out->indices = malloc(sizeof(uint32_t) * 3 * (size_t)triangles);
    if (!frames || !ratios || !out->bind_positions || !out->bind_normals || !out->colors || !out->joints ||
        !out->weights || !out->local_positions || !out->local_normals || !out->indices) {
        result = mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
        goto done;
    }
    /* the bones' joints and frames */
    int b = 0;
    for (unsigned i = 0; i < scene->mNumMeshes; ++i) {
        const struct aiMesh *m = scene->mMeshes[i];
        for (unsigned k = 0; k < m->mNumBones; ++k, ++b) {
            const struct aiBone *bone = m->mBones[k];
            int j = find_joint(joints, joint_count, bone->mName.data);
            if (j < 0) {
                result = mm_error_set(
                    err, MM_ERR_NOT_FOUND, 0, 0,
                    "bone '%s' of mesh '%s' is no joint of the skeleton (%d joints: %s, %s, ...); "
                    "the mesh must be skinned to the database's skeleton, bones named as its joints",
                    bone->mName.data, m->mName.data, joint_count, joints[0].name,
                    joint_count > 1 ? joints[1].name : "");
                goto done;
            }
            frames[b].joint = j;
            bone_frame_from(&bone->mOffsetMatrix, &frames[b]);
        }
    }
    /* units: a joint's offset from its parent (m) over the distance of their bones in the file */
    int ratio_count = 0;
    for (int x = 0; x < bones; ++x) {
        int parent = joints[frames[x].joint].parent;
        for (int y = 0; y < bones && parent >= 0; ++y) {
            if (frames[y].joint != parent) continue;
            float file = mm_vec3_distance(frames[x].origin, frames[y].origin);
            float metres = mm_vec3_length(joints[frames[x].joint].offset);
            if (file > 1e-9f && metres > 1e-6f) ratios[ratio_count++] = metres / file;
            break;
        }
    }
    float unit = 1.0f;
    if (ratio_count > 0) {
        qsort(ratios, (size_t)ratio_count, sizeof(float), compare_float);
        unit = ratios[ratio_count / 2];
    }
    /* vertices, their influences and triangles */
    int v0 = 0, t = 0;
    b = 0;
    for (unsigned i = 0; i < scene->mNumMeshes; ++i) {
        const struct aiMesh *m = scene->mMeshes[i];
        if (m->mNumBones == 0) continue;
        float color[3] = {default_color[0], default_color[1], default_color[2]};
        struct aiColor4D c;
        if (m->mMaterialIndex < scene->mNumMaterials) {
            const struct aiMaterial *mat = scene->mMaterials[m->mMaterialIndex];
            if (aiGetMaterialColor(mat, AI_MATKEY_BASE_COLOR, &c) == aiReturn_SUCCESS ||
                aiGetMaterialColor(mat, AI_MATKEY_COLOR_DIFFUSE, &c) == aiReturn_SUCCESS)
                color[0] = c.r, color[1] = c.g, color[2] = c.b;
        }
        for (unsigned v = 0; v < m->mNumVertices; ++v) {
            int o = v0 + (int)v;
            const struct aiVector3D *p = &m->mVertices[v];
            out->bind_positions[o] = mm_vec3_scale(mm_vec3_make(p->x, p->y, p->z), unit);
            out->bind_normals[o] =
                m->mNormals
                    ? mm_vec3_normalize(mm_vec3_make(m->mNormals[v].x, m->mNormals[v].y, m->mNormals[v].z))
                    : mm_vec3_make(0, 1, 0);
            memcpy(out->colors + 3 * o, color, sizeof color);
            for (int q = 0; q < MM_BODY_MAX_INFLUENCES; ++q) out->joints[o * MM_BODY_MAX_INFLUENCES + q] = -1;
        }
        /* keep the largest weights of each vertex */
        int *bone_of = malloc(sizeof(int) * MM_BODY_MAX_INFLUENCES * (size_t)m->mNumVertices);
        if (!bone_of) {
            result = mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
            goto done;
        }
        for (unsigned k = 0; k < m->mNumBones; ++k) {
            const struct aiBone *bone = m->mBones[k];
            for (unsigned w = 0; w < bone->mNumWeights; ++w) {
                unsigned v = bone->mWeights[w].mVertexId;
                float weight = bone->mWeights[w].mWeight;
                if (v >= m->mNumVertices || !(weight > 0.0f)) continue;
                int o = v0 + (int)v;
                float *ws = out->weights + (size_t)o * MM_BODY_MAX_INFLUENCES;
                int smallest = 0;
                for (int q = 1; q < MM_BODY_MAX_INFLUENCES; ++q)
                    if (ws[q] < ws[smallest]) smallest = q;
                if (weight > ws[smallest]) {
                    ws[smallest] = weight;
                    bone_of[v * MM_BODY_MAX_INFLUENCES + (unsigned)smallest] = b + (int)k;
                    out->joints[(size_t)o * MM_BODY_MAX_INFLUENCES + (size_t)smallest] = 0; /* set below */
                }
            }
        }
        for (unsigned v = 0; v < m->mNumVertices; ++v) {
            int o = v0 + (int)v;
            float *ws = out->weights + (size_t)o * MM_BODY_MAX_INFLUENCES;
            int32_t *js = out->joints + (size_t)o * MM_BODY_MAX_INFLUENCES;
            float sum = 0.0f;
            for (int q = 0; q < MM_BODY_MAX_INFLUENCES; ++q) sum += js[q] >= 0 ? ws[q] : 0.0f;
            if (!(sum > 0.0f)) {
                /* a vertex no bone moves: the bone nearest it */
                int nearest = b;
                float best = INFINITY;
                for (unsigned k = 0; k < m->mNumBones; ++k) {
                    float dd = mm_vec3_distance(frames[b + (int)k].origin, out->bind_positions[o]);
                    if (dd < best) best = dd, nearest = b + (int)k;
                }
                js[0] = 0, ws[0] = 1.0f, sum = 1.0f;
                bone_of[v * MM_BODY_MAX_INFLUENCES] = nearest;
            }
            for (int q = 0; q < MM_BODY_MAX_INFLUENCES; ++q) {
                size_t k = (size_t)o * MM_BODY_MAX_INFLUENCES + (size_t)q;
                if (js[q] < 0) {
                    ws[q] = 0.0f;
                    continue;
                }
                const bone_frame *f = &frames[bone_of[v * MM_BODY_MAX_INFLUENCES + (unsigned)q]];
                js[q] = f->joint;
                ws[q] /= sum;
                const struct aiVector3D *p = &m->mVertices[v];
                mm_vec3 rel = mm_vec3_sub(mm_vec3_make(p->x, p->y, p->z), f->origin);
                out->local_positions[k] = mm_vec3_scale(rotate_rows(f->r, rel), unit);
                out->local_normals[k] = rotate_rows(f->r, out->bind_normals[o]);
            }
        }
        free(bone_of);
        for (unsigned f = 0; f < m->mNumFaces; ++f) {
            const struct aiFace *face = &m->mFaces[f];
            if (face->mNumIndices != 3) continue;
            for (int q = 0; q < 3; ++q) out->indices[3 * t + q] = (uint32_t)(v0 + (int)face->mIndices[q]);
            ++t;
        }
        v0 += (int)m->mNumVertices;
        b += (int)m->mNumBones;
    }
    out->vertex_count = vertices;
    out->triangle_count = t;
done:
    free(frames);
    free(ratios);
    aiReleaseImport(scene);
    if (result != MM_OK) mm_body_mesh_free(out);
    return result;
}

#else

mm_result mm_body_mesh_load(const char *path, const mm_joint *joints, int joint_count, mm_body_mesh *out,
                            mm_error *err)
{
    (void)joints, (void)joint_count;
    memset(out, 0, sizeof *out);
    if (err) snprintf(err->file, sizeof err->file, "%s", path ? path : "");
    return mm_error_set(err, MM_ERR_UNSUPPORTED, 0, 0,
                        "this mm is built without assimp: it cannot read meshes");
}

#endif
