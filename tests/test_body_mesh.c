/* The body mesh and its camera, without OpenGL: the body made from a hand-built skeleton is a
 * closed surface of properly weighted vertices; skinning moves a vertex bound to one joint exactly
 * as that joint moved (checked against the bind pose's own transforms, a second route to the same
 * point); a bent elbow and knee keep every vertex of the limb near its bones and no triangle torn;
 * the body scales with the skeleton and shows which way it faces; a glTF written here (a two-bone
 * skinned mesh in centimetres) loads through assimp, matched by bone names and units, and a bone
 * no joint is named like is refused by name; the chase camera stands behind the facing and keeps
 * every framed point inside its window; the overlay never crosses the projected character; and
 * mm render and mm simulate --video draw a glTF body given with --mesh (its colour in the frames),
 * refusing one whose bones are not the skeleton's. */
#include <math.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <mm/body_mesh.h>
#include <mm/bvh.h>
#include <mm/render.h>

#include "test_databases.h"
#include "test_util.h"

/* ---- a hand-built skeleton, metres, facing +Z (left = +X), names that say nothing ---- */

enum {
    HIPS,
    L_HIP,
    L_KNEE,
    L_ANKLE,
    L_TOE,
    R_HIP,
    R_KNEE,
    R_ANKLE,
    R_TOE,
    SPINE,
    CHEST,
    NECK,
    HEAD,
    L_CLAVICLE,
    L_SHOULDER,
    L_ELBOW,
    L_HAND,
    R_CLAVICLE,
    R_SHOULDER,
    R_ELBOW,
    R_HAND,
    JOINTS
};

static const int parents[JOINTS] = {-1,         HIPS,       L_HIP,   L_KNEE, L_ANKLE,    HIPS,       R_HIP,
                                    R_KNEE,     R_ANKLE,    HIPS,    SPINE,  CHEST,      NECK,       CHEST,
                                    L_CLAVICLE, L_SHOULDER, L_ELBOW, CHEST,  R_CLAVICLE, R_SHOULDER, R_ELBOW};

static mm_vec3 offset_of(int j)
{
    static const float o[JOINTS][3] = {
        {0, 0.98f, 0},       {0.09f, -0.05f, 0}, {0, -0.43f, 0},     {0, -0.42f, 0},     {0, -0.06f, 0.13f},
        {-0.09f, -0.05f, 0}, {0, -0.43f, 0},     {0, -0.42f, 0},     {0, -0.06f, 0.13f}, {0, 0.12f, 0},
        {0, 0.15f, 0},       {0, 0.22f, 0},      {0, 0.10f, 0},      {0.03f, 0.18f, 0},  {0.15f, 0, 0},
        {0, -0.28f, 0},      {0, -0.26f, 0},     {-0.03f, 0.18f, 0}, {-0.15f, 0, 0},     {0, -0.28f, 0},
        {0, -0.26f, 0}};
    return mm_vec3_make(o[j][0], o[j][1], o[j][2]);
}

/* World transforms of local rotations (NULL: identity) times scale, root moved by root. */
static void pose_of(const mm_quat *local, float scale, mm_xform root, mm_xform *global)
{
    for (int j = 0; j < JOINTS; ++j) {
        mm_xform l = mm_xform_make(local ? local[j] : mm_quat_identity(), mm_vec3_scale(offset_of(j), scale));
        global[j] = parents[j] < 0 ? mm_xform_mul(root, l) : mm_xform_mul(global[parents[j]], l);
    }
}

static mm_body_desc desc_of(const mm_xform *poses, int count)
{
    mm_body_desc d;
    memset(&d, 0, sizeof d);
    d.joint_count = JOINTS;
    d.parents = parents;
    d.poses = poses;
    d.pose_count = count;
    d.roles.hips = HIPS;
    d.roles.head = HEAD;
    d.roles.foot[0] = L_ANKLE, d.roles.foot[1] = R_ANKLE;
    d.roles.toe[0] = L_TOE, d.roles.toe[1] = R_TOE;
    d.roles.hand[0] = L_HAND, d.roles.hand[1] = R_HAND;
    return d;
}

static void build_rest_body(mm_body_mesh *m, mm_xform bind[JOINTS])
{
    pose_of(NULL, 1.0f, mm_xform_identity(), bind);
    mm_body_desc d = desc_of(bind, 1);
    mm_error err;
    assert_int_equal(mm_body_mesh_build(&d, m, &err), MM_OK);
}

static float point_segment_distance(mm_vec3 p, mm_vec3 a, mm_vec3 b)
{
    mm_vec3 ab = mm_vec3_sub(b, a);
    float t = mm_vec3_dot(mm_vec3_sub(p, a), ab) / fmaxf(mm_vec3_dot(ab, ab), 1e-12f);
    t = fminf(fmaxf(t, 0.0f), 1.0f);
    return mm_vec3_distance(p, mm_vec3_add(a, mm_vec3_scale(ab, t)));
}

/* ---- structure ---- */

static int compare_edges(const void *a, const void *b)
{
    const uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

/* Every edge is shared by exactly two triangles, unless its ends lie on one point (a pole). */
static void assert_closed(const mm_body_mesh *m, const mm_vec3 *positions)
{
    size_t n = 3 * (size_t)m->triangle_count;
    uint64_t *edges = malloc(sizeof(uint64_t) * n);
    assert_non_null(edges);
    for (int t = 0; t < m->triangle_count; ++t)
        for (int k = 0; k < 3; ++k) {
            uint32_t a = m->indices[3 * t + k], b = m->indices[3 * t + (k + 1) % 3];
            edges[3 * t + k] = a < b ? (uint64_t)a << 32 | b : (uint64_t)b << 32 | a;
        }
    qsort(edges, n, sizeof *edges, compare_edges);
    int open = 0;
    for (size_t i = 0; i < n;) {
        size_t k = i;
        while (k < n && edges[k] == edges[i]) ++k;
        uint32_t a = (uint32_t)(edges[i] >> 32), b = (uint32_t)(edges[i] & 0xffffffffu);
        if (k - i != 2 && mm_vec3_distance(positions[a], positions[b]) > 1e-6f) ++open;
        i = k;
    }
    free(edges);
    assert_int_equal(open, 0);
}

static void test_body_structure(void **state)
{
    (void)state;
    mm_body_mesh m;
    mm_xform bind[JOINTS];
    build_rest_body(&m, bind);
    assert_true(m.vertex_count > 1000);
    assert_true(m.triangle_count > 1000);
    assert_int_equal(m.joint_count, JOINTS);
    int two = 0;
    bool bound[JOINTS] = {false};
    for (int v = 0; v < m.vertex_count; ++v) {
        float sum = 0.0f;
        int used = 0;
        for (int i = 0; i < MM_BODY_MAX_INFLUENCES; ++i) {
            int j = m.joints[v * MM_BODY_MAX_INFLUENCES + i];
            float w = m.weights[v * MM_BODY_MAX_INFLUENCES + i];
            if (j < 0) continue;
            assert_true(j < JOINTS);
            assert_true(w > 0.0f && w <= 1.0f);
            bound[j] = true;
            sum += w;
            ++used;
        }
        assert_true(used == 1 || used == 2); /* a made body: 1 or 2 joints per vertex */
        two += used == 2;
        assert_true(fabsf(sum - 1.0f) < 1e-5f);
        assert_true(fabsf(mm_vec3_length(m.bind_normals[v]) - 1.0f) < 1e-4f);
        for (int c = 0; c < 3; ++c) assert_true(m.colors[3 * v + c] >= 0.0f && m.colors[3 * v + c] <= 1.0f);
    }
    assert_true(two > 200); /* blended rings at the joints */
    /* every joint that carries a bone of the body moves some of it; the toes and the hands too */
    static const int carried[] = {HIPS,    L_HIP,  L_KNEE,     L_ANKLE, L_TOE, R_HIP, R_KNEE,
                                  R_ANKLE, R_TOE,  SPINE,      CHEST,   NECK,  HEAD,  L_SHOULDER,
                                  L_ELBOW, L_HAND, R_SHOULDER, R_ELBOW, R_HAND};
    for (size_t i = 0; i < sizeof carried / sizeof carried[0]; ++i) assert_true(bound[carried[i]]);
    for (int t = 0; t < 3 * m.triangle_count; ++t) assert_true(m.indices[t] < (uint32_t)m.vertex_count);
    assert_closed(&m, m.bind_positions);
    /* normals point out: away from the body's vertical axis on the torso at waist height */
    int outward = 0, waist = 0;
    for (int v = 0; v < m.vertex_count; ++v) {
        mm_vec3 p = m.bind_positions[v];
        if (fabsf(p.y - 1.08f) > 0.02f || fabsf(p.x) > 0.06f) continue; /* front and back of the waist */
        ++waist;
        outward += m.bind_normals[v].z * p.z > 0.0f;
    }
    assert_true(waist > 4);
    assert_int_equal(outward, waist);
    /* skinned in its own bind pose, every vertex stays where it was made */
    mm_vec3 *p = malloc(sizeof(mm_vec3) * (size_t)m.vertex_count),
            *n = malloc(sizeof(mm_vec3) * (size_t)m.vertex_count);
    mm_body_mesh_skin(&m, bind, p, n);
    for (int v = 0; v < m.vertex_count; ++v) {
        assert_true(mm_vec3_distance(p[v], m.bind_positions[v]) < 1e-5f);
        assert_true(mm_vec3_distance(n[v], m.bind_normals[v]) < 1e-4f);
    }
    free(p);
    free(n);
    mm_body_mesh_free(&m);
}

/* A body the size of a person: from the soles (at the ground, 0) to the top of the head about
 * 1.75 m; the head's vertices reach further forward (the visor and nose) than back. */
static void test_body_proportions_and_face(void **state)
{
    (void)state;
    mm_body_mesh m;
    mm_xform bind[JOINTS];
    build_rest_body(&m, bind);
    float lo = INFINITY, hi = -INFINITY, front = -INFINITY, back = INFINITY, wide = 0.0f;
    for (int v = 0; v < m.vertex_count; ++v) {
        mm_vec3 p = m.bind_positions[v];
        lo = fminf(lo, p.y), hi = fmaxf(hi, p.y);
        if (m.joints[v * MM_BODY_MAX_INFLUENCES] == HEAD && m.weights[v * MM_BODY_MAX_INFLUENCES] == 1.0f &&
            p.y > bind[HEAD].translation.y + 0.03f)
            front = fmaxf(front, p.z), back = fminf(back, p.z);
        if (fabsf(p.y - bind[HIPS].translation.y) < 0.02f) wide = fmaxf(wide, fabsf(p.x));
    }
    assert_true(fabsf(lo - 0.0f) < 0.03f); /* the soles at the ground */
    assert_true(hi > 1.65f && hi < 1.90f); /* head top */
    assert_true(front > 0.10f && back < -0.07f);
    assert_true(front + back > 0.01f); /* a face in front */
    assert_true(wide > 0.14f);         /* hips wider than a capsule */
    mm_body_mesh_free(&m);
}

/* ---- skinning ---- */

static void test_single_joint_vertex_follows_its_joint(void **state)
{
    (void)state;
    mm_body_mesh m;
    mm_xform bind[JOINTS];
    build_rest_body(&m, bind);
    mm_quat local[JOINTS];
    for (int j = 0; j < JOINTS; ++j) local[j] = mm_quat_identity();
    local[L_SHOULDER] = mm_quat_from_axis_angle(mm_vec3_make(0, 0, 1), 1.2f);
    local[L_ELBOW] = mm_quat_from_axis_angle(mm_vec3_make(1, 0, 0), -1.4f);
    local[R_KNEE] = mm_quat_from_axis_angle(mm_vec3_make(1, 0, 0), 0.9f);
    local[HEAD] = mm_quat_from_axis_angle(mm_vec3_make(0, 1, 0), 0.7f);
    local[SPINE] = mm_quat_from_axis_angle(mm_vec3_normalize(mm_vec3_make(1, 0.3f, 0.2f)), 0.4f);
    mm_xform root =
        mm_xform_make(mm_quat_from_axis_angle(mm_vec3_make(0, 1, 0), 2.0f), mm_vec3_make(3, 0.1f, -2));
    mm_xform pose[JOINTS];
    pose_of(local, 1.0f, root, pose);
    mm_vec3 *p = malloc(sizeof(mm_vec3) * (size_t)m.vertex_count);
    mm_body_mesh_skin(&m, pose, p, NULL);
    int single = 0;
    float worst = 0.0f;
    for (int v = 0; v < m.vertex_count; ++v) {
        int j = m.joints[v * MM_BODY_MAX_INFLUENCES];
        if (m.joints[v * MM_BODY_MAX_INFLUENCES + 1] >= 0) continue;
        /* pose * bind^-1 applied to the bind position: the joint's motion */
        mm_vec3 expect =
            mm_xform_apply_point(mm_xform_mul(pose[j], mm_xform_inverse(bind[j])), m.bind_positions[v]);
        worst = fmaxf(worst, mm_vec3_distance(p[v], expect));
        ++single;
    }
    assert_true(single > m.vertex_count / 2);
    assert_true(worst < 1e-5f);
    free(p);
    mm_body_mesh_free(&m);
}

/* Elbows and knees bent to 100 degrees: every vertex moved by them stays within the limb's reach
 * of its bones, and the surface stays closed and untorn. */
static void test_bent_limbs_stay_closed(void **state)
{
    (void)state;
    mm_body_mesh m;
    mm_xform bind[JOINTS];
    build_rest_body(&m, bind);
    mm_quat local[JOINTS];
    for (int j = 0; j < JOINTS; ++j) local[j] = mm_quat_identity();
    const float bend = 100.0f * (float)MM_DEG_TO_RAD;
    local[L_ELBOW] = local[R_ELBOW] =
        mm_quat_from_axis_angle(mm_vec3_make(1, 0, 0), -bend); /* forearm forward */
    local[L_KNEE] = local[R_KNEE] = mm_quat_from_axis_angle(mm_vec3_make(1, 0, 0), bend); /* shin back */
    mm_xform pose[JOINTS];
    pose_of(local, 1.0f, mm_xform_identity(), pose);
    mm_vec3 *p = malloc(sizeof(mm_vec3) * (size_t)m.vertex_count);
    mm_body_mesh_skin(&m, pose, p, NULL);
    /* the thickest limb is 0.078 m at the thigh's top, plus its bulge: nothing of a bent limb is
       further than 0.10 m from its two bones */
    const float reach = 0.10f;
    struct {
        int joint, upper, lower;
    } bends[4] = {{L_ELBOW, L_SHOULDER, L_HAND},
                  {R_ELBOW, R_SHOULDER, R_HAND},
                  {L_KNEE, L_HIP, L_ANKLE},
                  {R_KNEE, R_HIP, R_ANKLE}};
    int checked = 0;
    float nearest = INFINITY;
    for (int v = 0; v < m.vertex_count; ++v)
        for (int b = 0; b < 4; ++b) {
            bool moved = false;
            for (int i = 0; i < MM_BODY_MAX_INFLUENCES; ++i)
                moved |= m.joints[v * MM_BODY_MAX_INFLUENCES + i] == bends[b].joint;
            if (!moved) continue;
            mm_vec3 a = pose[bends[b].upper].translation, k = pose[bends[b].joint].translation,
                    c = pose[bends[b].lower].translation;
            float d = fminf(point_segment_distance(p[v], a, k), point_segment_distance(p[v], k, c));
            nearest = fminf(nearest, d);
            if (d > reach)
                print_error("vertex %d of the bend at joint %d lies %.3f m from its bones\n", v,
                            bends[b].joint, d);
            assert_true(d <= reach);
            ++checked;
        }
    assert_true(checked > 400);
    assert_closed(&m, p);
    /* no triangle torn: no edge more than twice its length in the bind pose (plus 1 mm); 1.6 here */
    float stretch = 0.0f;
    for (int t = 0; t < m.triangle_count; ++t)
        for (int k = 0; k < 3; ++k) {
            uint32_t a = m.indices[3 * t + k], b = m.indices[3 * t + (k + 1) % 3];
            float before = mm_vec3_distance(m.bind_positions[a], m.bind_positions[b]);
            stretch = fmaxf(stretch, (mm_vec3_distance(p[a], p[b]) - 0.001f) / fmaxf(before, 1e-6f));
        }
    assert_true(stretch < 2.0f);
    assert_true(nearest > 0.005f); /* nor squeezed onto its bones */
    free(p);
    mm_body_mesh_free(&m);
}

/* Sizes come from the bones: a skeleton half as large makes the same body at half the size. */
static void test_body_scales_with_the_skeleton(void **state)
{
    (void)state;
    mm_body_mesh full, half;
    mm_xform bind[JOINTS], small[JOINTS];
    build_rest_body(&full, bind);
    pose_of(NULL, 0.5f, mm_xform_identity(), small);
    mm_body_desc d = desc_of(small, 1);
    assert_int_equal(mm_body_mesh_build(&d, &half, NULL), MM_OK);
    assert_int_equal(half.vertex_count, full.vertex_count);
    for (int v = 0; v < full.vertex_count; ++v)
        assert_true(mm_vec3_distance(mm_vec3_scale(full.bind_positions[v], 0.5f), half.bind_positions[v]) <
                    1e-5f);
    mm_body_mesh_free(&full);
    mm_body_mesh_free(&half);
}

/* Of several poses the straightest is bound: a crouch listed first is passed over. */
static void test_bind_pose_is_the_straightest(void **state)
{
    (void)state;
    mm_quat local[JOINTS];
    for (int j = 0; j < JOINTS; ++j) local[j] = mm_quat_identity();
    local[L_KNEE] = local[R_KNEE] = mm_quat_from_axis_angle(mm_vec3_make(1, 0, 0), 1.2f);
    mm_xform poses[2 * JOINTS];
    pose_of(local, 1.0f, mm_xform_identity(), poses);
    pose_of(NULL, 1.0f, mm_xform_identity(), poses + JOINTS);
    mm_body_desc d = desc_of(poses, 2);
    assert_true(mm_body_mesh_bind_score(&d, poses + JOINTS) > mm_body_mesh_bind_score(&d, poses));
    assert_true(fabsf(mm_body_mesh_bind_score(&d, poses + JOINTS) - 1.0f) < 1e-5f);
    mm_body_mesh a, b;
    assert_int_equal(mm_body_mesh_build(&d, &a, NULL), MM_OK);
    mm_xform bind[JOINTS];
    build_rest_body(&b, bind);
    assert_int_equal(a.vertex_count, b.vertex_count);
    for (int v = 0; v < a.vertex_count; ++v)
        assert_true(mm_vec3_distance(a.bind_positions[v], b.bind_positions[v]) < 1e-6f);
    mm_body_mesh_free(&a);
    mm_body_mesh_free(&b);
}

static void test_body_refuses_what_it_cannot_make(void **state)
{
    (void)state;
    mm_xform bind[JOINTS];
    pose_of(NULL, 1.0f, mm_xform_identity(), bind);
    mm_body_mesh m;
    mm_error err;
    mm_body_desc d = desc_of(bind, 1);
    d.roles.head = -1;
    assert_int_equal(mm_body_mesh_build(&d, &m, &err), MM_ERR_NOT_FOUND);
    assert_non_null(strstr(err.message, "head"));
    assert_int_equal(m.vertex_count, 0);
    d = desc_of(bind, 1);
    d.roles.foot[1] = R_HIP; /* a "foot" without a thigh and a shin above it */
    assert_int_equal(mm_body_mesh_build(&d, &m, &err), MM_ERR_NOT_FOUND);
    assert_non_null(strstr(err.message, "right foot"));
    d = desc_of(bind, 1);
    bind[L_KNEE].translation.x = NAN;
    assert_int_equal(mm_body_mesh_build(&d, &m, &err), MM_ERR_INVALID_ARGUMENT);
    /* without hands: no arms, still a body */
    pose_of(NULL, 1.0f, mm_xform_identity(), bind);
    d = desc_of(bind, 1);
    d.roles.hand[0] = d.roles.hand[1] = -1;
    assert_int_equal(mm_body_mesh_build(&d, &m, &err), MM_OK);
    for (int v = 0; v < m.vertex_count; ++v) assert_true(m.joints[v * MM_BODY_MAX_INFLUENCES] != L_ELBOW);
    mm_body_mesh_free(&m);
    /* facing from the hips: +Z here, turned with the body */
    float yaw = mm_body_facing(&d.roles, parents, JOINTS, bind, 9.0f);
    assert_true(fabsf(yaw) < 1e-5f);
    mm_xform turned[JOINTS];
    pose_of(NULL, 1.0f,
            mm_xform_make(mm_quat_from_axis_angle(mm_vec3_make(0, 1, 0), 1.0f), mm_vec3_make(0, 0, 0)),
            turned);
    assert_true(fabsf(mm_body_facing(&d.roles, parents, JOINTS, turned, 9.0f) - 1.0f) < 1e-5f);
    d.roles.foot[0] = -1;
    assert_true(mm_body_facing(&d.roles, parents, JOINTS, turned, 9.0f) == 9.0f);
}

/* ---- a user's mesh: glTF written here ---- */

static void base64(const uint8_t *in, size_t n, char *out)
{
    static const char *digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    size_t o = 0;
    for (size_t i = 0; i < n; i += 3) {
        uint32_t v =
            (uint32_t)in[i] << 16 | (i + 1 < n ? (uint32_t)in[i + 1] << 8 : 0) | (i + 2 < n ? in[i + 2] : 0);
        out[o++] = digits[v >> 18 & 63];
        out[o++] = digits[v >> 12 & 63];
        out[o++] = i + 1 < n ? digits[v >> 6 & 63] : '=';
        out[o++] = i + 2 < n ? digits[v & 63] : '=';
    }
    out[o] = '\0';
}

/* Two boxes along +Y in centimetres: y 10..90 bound to the first bone, 110..190 to the second; one
 * more vertex shared half and half. Bones "Root" at 0, "Mid" at 100, "Tip" at 200 cm (names
 * bone_names). */
enum { GLTF_VERTICES = 17, GLTF_TRIANGLES = 24 };

static void gltf_box_vertex(int i, float out[3])
{
    int box = i / 8, corner = i % 8;
    out[0] = corner & 1 ? 5.0f : -5.0f;
    out[1] = (box ? 110.0f : 10.0f) + (corner & 2 ? 80.0f : 0.0f);
    out[2] = corner & 4 ? 5.0f : -5.0f;
}

static const char *write_gltf(const char *name, const char *const bone_names[3])
{
    static char path[1024];
    snprintf(path, sizeof path, "%s/%s", MM_TEST_OUT, name);
    struct {
        float positions[GLTF_VERTICES][3];
        uint16_t joints[GLTF_VERTICES][4];
        float weights[GLTF_VERTICES][4];
        uint16_t indices[GLTF_TRIANGLES * 3];
        float inverse_bind[3][16];
    } buf;
    memset(&buf, 0, sizeof buf);
    for (int i = 0; i < 16; ++i) {
        gltf_box_vertex(i, buf.positions[i]);
        buf.joints[i][0] = (uint16_t)(i / 8);
        buf.weights[i][0] = 1.0f;
    }
    buf.positions[16][1] = 100.0f, buf.positions[16][0] = 5.0f; /* at the joint, half each */
    buf.joints[16][0] = 0, buf.joints[16][1] = 1, buf.weights[16][0] = buf.weights[16][1] = 0.5f;
    static const int faces[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1},
                                    {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
    int t = 0;
    for (int box = 0; box < 2; ++box)
        for (int f = 0; f < 6; ++f) {
            const int *q = faces[f];
            uint16_t o = (uint16_t)(box * 8);
            uint16_t tri[6] = {(uint16_t)(o + q[0]), (uint16_t)(o + q[1]), (uint16_t)(o + q[2]),
                               (uint16_t)(o + q[0]), (uint16_t)(o + q[2]), (uint16_t)(o + q[3])};
            memcpy(buf.indices + t, tri, sizeof tri);
            t += 6;
        }
    /* the joint vertex rides on a degenerate triangle of the first box's top face */
    buf.indices[t - 1] = 16;
    for (int b = 0; b < 3; ++b) { /* inverse of a translation to (0, 100 b, 0), column-major */
        float *m = buf.inverse_bind[b];
        m[0] = m[5] = m[10] = m[15] = 1.0f;
        m[13] = -100.0f * (float)b;
    }
    static char b64[8192], json[16384];
    base64((const uint8_t *)&buf, sizeof buf, b64);
    size_t off_pos = 0, off_j = sizeof buf.positions, off_w = off_j + sizeof buf.joints,
           off_i = off_w + sizeof buf.weights, off_ib = off_i + sizeof buf.indices;
    snprintf(
        json, sizeof json,
        "{\"asset\": {\"version\": \"2.0\"}, \"scene\": 0, \"scenes\": [{\"nodes\": [0, 3]}],\n"
        " \"nodes\": [{\"name\": \"%s\", \"children\": [1]}, {\"name\": \"%s\", \"translation\": [0, 100, "
        "0], "
        "\"children\": [2]},\n"
        "  {\"name\": \"%s\", \"translation\": [0, 100, 0]}, {\"name\": \"body\", \"mesh\": 0, \"skin\": "
        "0}],\n"
        " \"skins\": [{\"joints\": [0, 1, 2], \"inverseBindMatrices\": 4, \"skeleton\": 0}],\n"
        " \"meshes\": [{\"name\": \"body\", \"primitives\": [{\"attributes\": {\"POSITION\": 0, "
        "\"JOINTS_0\": 1, "
        "\"WEIGHTS_0\": 2}, \"indices\": 3, \"material\": 0}]}],\n"
        " \"materials\": [{\"pbrMetallicRoughness\": {\"baseColorFactor\": [0.8, 0.2, 0.1, 1]}}],\n"
        " \"buffers\": [{\"byteLength\": %zu, \"uri\": \"data:application/octet-stream;base64,%s\"}],\n"
        " \"bufferViews\": [{\"buffer\": 0, \"byteOffset\": %zu, \"byteLength\": %zu},"
        " {\"buffer\": 0, \"byteOffset\": %zu, \"byteLength\": %zu},"
        " {\"buffer\": 0, \"byteOffset\": %zu, \"byteLength\": %zu},"
        " {\"buffer\": 0, \"byteOffset\": %zu, \"byteLength\": %zu},"
        " {\"buffer\": 0, \"byteOffset\": %zu, \"byteLength\": %zu}],\n"
        " \"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": %d, \"type\": \"VEC3\", "
        "\"min\": [-5, 0, -5], \"max\": [5, 190, 5]},\n"
        "  {\"bufferView\": 1, \"componentType\": 5123, \"count\": %d, \"type\": \"VEC4\"},\n"
        "  {\"bufferView\": 2, \"componentType\": 5126, \"count\": %d, \"type\": \"VEC4\"},\n"
        "  {\"bufferView\": 3, \"componentType\": 5123, \"count\": %d, \"type\": \"SCALAR\"},\n"
        "  {\"bufferView\": 4, \"componentType\": 5126, \"count\": 3, \"type\": \"MAT4\"}]}\n",
        bone_names[0], bone_names[1], bone_names[2], sizeof buf, b64, off_pos, sizeof buf.positions, off_j,
        sizeof buf.joints, off_w, sizeof buf.weights, off_i, sizeof buf.indices, off_ib,
        sizeof buf.inverse_bind, GLTF_VERTICES, GLTF_VERTICES, GLTF_VERTICES, GLTF_TRIANGLES * 3);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fputs(json, f);
    fclose(f);
    return path;
}

static void gltf_skeleton(mm_joint joints[3])
{
    memset(joints, 0, sizeof(mm_joint) * 3);
    static const char *names[3] = {"Root", "Mid", "Tip"};
    for (int j = 0; j < 3; ++j) {
        snprintf(joints[j].name, sizeof joints[j].name, "%s", names[j]);
        joints[j].parent = j - 1;
        joints[j].offset = mm_vec3_make(0.0f, j ? 1.0f : 0.0f, 0.0f); /* metres */
    }
}

static void test_gltf_mesh_loads_by_bone_names(void **state)
{
    (void)state;
    static const char *const names[3] = {"Root", "Mid", "Tip"};
    const char *path = write_gltf("body_mesh_two_bones.gltf", names);
    mm_joint joints[3];
    gltf_skeleton(joints);
    mm_body_mesh m;
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_result r = mm_body_mesh_load(path, joints, 3, &m, &err);
    if (r == MM_ERR_UNSUPPORTED) skip(); /* built without assimp */
    if (r != MM_OK) print_error("%s\n", err.message);
    assert_int_equal(r, MM_OK);
    assert_int_equal(m.joint_count, 3);
    assert_true(m.vertex_count >= 16 && m.vertex_count <= GLTF_VERTICES);
    assert_true(m.triangle_count >= GLTF_TRIANGLES - 1);
    /* centimetres found from the bones: the bind positions are in metres */
    float top = 0.0f;
    for (int v = 0; v < m.vertex_count; ++v) top = fmaxf(top, m.bind_positions[v].y);
    assert_true(fabsf(top - 1.90f) < 1e-4f);
    assert_true(fabsf(m.colors[0] - 0.8f) < 1e-3f && fabsf(m.colors[1] - 0.2f) < 1e-3f);
    /* the second bone turned 90 degrees about Z at 1 m: a vertex of its box at (x, y, z) m goes to
       (-(y - 1), 1 + x, z); the first box stays; the joint's vertex halfway */
    mm_xform pose[3];
    pose[0] = mm_xform_identity();
    pose[1] = mm_xform_make(mm_quat_from_axis_angle(mm_vec3_make(0, 0, 1), (float)(0.5 * MM_PI)),
                            mm_vec3_make(0, 1, 0));
    pose[2] = mm_xform_mul(pose[1], mm_xform_make(mm_quat_identity(), mm_vec3_make(0, 1, 0)));
    mm_vec3 *p = malloc(sizeof(mm_vec3) * (size_t)m.vertex_count);
    mm_body_mesh_skin(&m, pose, p, NULL);
    int moved = 0, still = 0, halves = 0;
    for (int v = 0; v < m.vertex_count; ++v) {
        mm_vec3 b = m.bind_positions[v], expect;
        if (b.y > 1.05f)
            expect = mm_vec3_make(-(b.y - 1.0f), 1.0f + b.x, b.z), ++moved;
        else if (b.y < 0.95f)
            expect = b, ++still;
        else
            expect = mm_vec3_scale(mm_vec3_add(b, mm_vec3_make(-(b.y - 1.0f), 1.0f + b.x, b.z)), 0.5f),
            ++halves;
        assert_true(mm_vec3_distance(p[v], expect) < 1e-4f);
    }
    assert_int_equal(moved, 8);
    assert_int_equal(still, 8);
    assert_int_equal(halves, 1);
    free(p);
    mm_body_mesh_free(&m);
}

static void test_gltf_mesh_refusals(void **state)
{
    (void)state;
    mm_joint joints[3];
    gltf_skeleton(joints);
    mm_body_mesh m;
    mm_error err;
    memset(&err, 0, sizeof err);
    static const char *const names[3] = {"Root", "Elbow_of_another", "Tip"};
    const char *path = write_gltf("body_mesh_wrong_bone.gltf", names);
    mm_result r = mm_body_mesh_load(path, joints, 3, &m, &err);
    if (r == MM_ERR_UNSUPPORTED) skip();
    assert_int_equal(r, MM_ERR_NOT_FOUND);
    assert_non_null(strstr(err.message, "Elbow_of_another"));
    assert_non_null(strstr(err.file, "body_mesh_wrong_bone.gltf"));
    assert_int_equal(m.vertex_count, 0);
    assert_int_equal(mm_body_mesh_load(MM_TEST_OUT "/no_such_mesh.gltf", joints, 3, &m, &err), MM_ERR_IO);
    /* a file that is not a mesh */
    char bad[1024];
    snprintf(bad, sizeof bad, "%s/not_a_mesh.gltf", MM_TEST_OUT);
    FILE *f = fopen(bad, "wb");
    assert_non_null(f);
    fputs(
        "{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [{\"name\": \"x\"}], \"scenes\": [{\"nodes\": [0]}]}",
        f);
    fclose(f);
    r = mm_body_mesh_load(bad, joints, 3, &m, &err);
    assert_true(r == MM_ERR_NOT_FOUND || r == MM_ERR_IO);
}

/* ---- the chase camera and the overlay ---- */

static bool inside_window(const mm_camera *c, const mm_camera_framing *f, mm_vec3 p, float aspect,
                          float slack)
{
    const int w = 1280, h = (int)(1280 / aspect);
    float px, py;
    if (!mm_camera_project(c, w, h, p, &px, &py)) return false;
    float x = 2.0f * px / (float)w - 1.0f, y = 1.0f - 2.0f * py / (float)h;
    return fabsf(x) <= f->half_width + slack && y <= f->top + slack && y >= f->bottom - slack;
}

static void test_chase_camera_frames_from_behind(void **state)
{
    (void)state;
    mm_camera_framing f;
    mm_camera_framing_defaults(&f);
    mm_camera c;
    mm_camera_defaults(&c);
    const float aspect = 16.0f / 9.0f, dt = 1.0f / 30.0f;
    mm_xform pose[JOINTS];
    /* along a circle of 4 m radius at 1.5 m/s, facing along it; the future path 1 s ahead */
    float worst_behind = -INFINITY;
    int frames = 0;
    for (int k = 0; k < 300; ++k) {
        float t = (float)k * dt, a = 1.5f * t / 4.0f;
        mm_vec3 at = mm_vec3_make(4.0f * sinf(a), 0.0f, 4.0f - 4.0f * cosf(a));
        float yaw = a; /* the tangent of the circle: facing (sin yaw, cos yaw) */
        pose_of(NULL, 1.0f, mm_xform_make(mm_quat_from_axis_angle(mm_vec3_make(0, 1, 0), yaw), at), pose);
        mm_vec3 points[JOINTS + 8];
        for (int j = 0; j < JOINTS; ++j) points[j] = pose[j].translation;
        for (int i = 0; i < 8; ++i) {
            float b = 1.5f * (t + (float)(i + 1) / 8.0f) / 4.0f;
            points[JOINTS + i] = mm_vec3_make(4.0f * sinf(b), 0.0f, 4.0f - 4.0f * cosf(b));
        }
        mm_camera_chase(&c, &f, yaw, points, JOINTS + 8, aspect, k == 0 ? 0.0f : dt);
        if (k == 0) { /* a jump: exactly behind plus the offset, every point inside the window */
            assert_true(fabsf(remainderf(c.yaw - (yaw + f.yaw_offset), 2.0f * (float)MM_PI)) < 1e-5f);
            for (int i = 0; i < JOINTS + 8; ++i) assert_true(inside_window(&c, &f, points[i], aspect, 1e-3f));
        }
        /* eased: never outside the image, the eye behind the body */
        for (int i = 0; i < JOINTS + 8; ++i) assert_true(inside_window(&c, &f, points[i], aspect, 0.2f));
        mm_vec3 eye = mm_camera_eye(&c), forward = mm_vec3_make(sinf(yaw), 0, cosf(yaw));
        float behind = mm_vec3_dot(mm_vec3_sub(eye, at), forward);
        worst_behind = fmaxf(worst_behind, behind);
        assert_true(c.distance >= f.min_distance - 1e-4f && c.distance <= f.max_distance);
        ++frames;
    }
    assert_int_equal(frames, 300);
    assert_true(worst_behind < -1.0f); /* at least a metre behind, always */
    /* far apart points: the camera draws back to hold both */
    mm_vec3 spread[2] = {{0, 0, 0}, {12, 0, 0}};
    mm_camera_chase(&c, &f, 0.0f, spread, 2, aspect, 0.0f);
    assert_true(c.distance > 5.0f);
    for (int i = 0; i < 2; ++i) assert_true(inside_window(&c, &f, spread[i], aspect, 1e-3f));
}

static void test_overlay_stays_off_the_character(void **state)
{
    (void)state;
    const int w = 640, h = 360;
    mm_xform pose[JOINTS];
    pose_of(NULL, 1.0f, mm_xform_identity(), pose);
    mm_render_scene s;
    memset(&s, 0, sizeof s);
    s.joint_count = JOINTS;
    s.parents = parents;
    s.global = pose;
    s.overlay =
        "clip walk  frame 120/361  t 2.00 s\ngait walk  speed 1.50 m/s\ncost 0.758  pose 0.246\nsearch 17 us";
    int placed_elsewhere = 0;
    /* the camera aimed so that the body lands all over the image */
    for (int k = 0; k < 64; ++k) {
        mm_camera c;
        mm_camera_defaults(&c);
        c.yaw = 0.3f * (float)k;
        c.distance = 2.5f + 0.25f * (float)(k % 9);
        c.target = mm_vec3_make(1.2f * sinf(1.7f * (float)k), 0.9f + 0.6f * cosf(1.3f * (float)k), 0.3f);
        float x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY, px, py;
        for (int j = 0; j < JOINTS; ++j)
            if (mm_camera_project(&c, w, h, pose[j].translation, &px, &py))
                x0 = fminf(x0, px), y0 = fminf(y0, py), x1 = fmaxf(x1, px), y1 = fmaxf(y1, py);
        if (!(x1 - x0 < 0.4f * w && y1 - y0 < 0.5f * h)) continue; /* a body that fills the image */
        mm_overlay_place o;
        mm_render_overlay_place(&c, w, h, &s, &o);
        assert_true(o.x >= 0 && o.y >= 0 && o.x + o.width <= w && o.y + o.height <= h);
        bool crosses = o.x < x1 && o.x + o.width > x0 && o.y < y1 && o.y + o.height > y0;
        if (crosses)
            print_error("camera %d: overlay %d %d %d %d crosses joints %.0f %.0f %.0f %.0f\n", k, o.x, o.y,
                        o.width, o.height, x0, y0, x1, y1);
        assert_false(crosses);
        placed_elsewhere += o.x != 8 || o.y != 8;
    }
    assert_true(placed_elsewhere > 0); /* it moved, some of the time */
    /* no character: the top left at the font's scale */
    mm_render_scene empty;
    memset(&empty, 0, sizeof empty);
    empty.overlay = "AB\nC";
    mm_camera c;
    mm_camera_defaults(&c);
    mm_overlay_place o;
    mm_render_overlay_place(&c, w, h, &empty, &o);
    assert_int_equal(o.x, 8);
    assert_int_equal(o.y, 8);
    assert_int_equal(o.scale, 2);
    assert_int_equal(o.width, 2 * 12);
    assert_int_equal(o.height, 2 * 18);
}

/* ---- --mesh through the program ---- */

/* A glTF body for a skeleton in its rest pose (rotations identity): a box around every bone, bound
 * to the joint that carries it, in centimetres, red. */
static void write_skeleton_gltf(const char *path, const mm_joint *joints, int n, const char *rename_first)
{
    enum { MAXJ = 64 };
    assert_true(n <= MAXJ);
    mm_vec3 rest[MAXJ];
    for (int j = 0; j < n; ++j)
        rest[j] =
            joints[j].parent < 0 ? joints[j].offset : mm_vec3_add(rest[joints[j].parent], joints[j].offset);
    static float positions[MAXJ * 8][3], weights[MAXJ * 8][4], inverse_bind[MAXJ][16];
    static uint16_t bone_of[MAXJ * 8][4], indices[MAXJ * 36];
    int v = 0, t = 0;
    static const int faces[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1},
                                    {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
    for (int j = 1; j < n; ++j) {
        int p = joints[j].parent;
        if (p < 0 || mm_vec3_distance(rest[p], rest[j]) < 0.02f) continue;
        mm_vec3 lo = {fminf(rest[p].x, rest[j].x) - 0.04f, fminf(rest[p].y, rest[j].y) - 0.04f,
                      fminf(rest[p].z, rest[j].z) - 0.04f};
        mm_vec3 hi = {fmaxf(rest[p].x, rest[j].x) + 0.04f, fmaxf(rest[p].y, rest[j].y) + 0.04f,
                      fmaxf(rest[p].z, rest[j].z) + 0.04f};
        for (int c = 0; c < 8; ++c) {
            positions[v + c][0] = 100.0f * (c & 1 ? hi.x : lo.x);
            positions[v + c][1] = 100.0f * (c & 2 ? hi.y : lo.y);
            positions[v + c][2] = 100.0f * (c & 4 ? hi.z : lo.z);
            memset(bone_of[v + c], 0, sizeof bone_of[0]);
            memset(weights[v + c], 0, sizeof weights[0]);
            bone_of[v + c][0] = (uint16_t)p;
            weights[v + c][0] = 1.0f;
        }
        for (int f = 0; f < 6; ++f) {
            const int *q = faces[f];
            uint16_t tri[6] = {(uint16_t)(v + q[0]), (uint16_t)(v + q[1]), (uint16_t)(v + q[2]),
                               (uint16_t)(v + q[0]), (uint16_t)(v + q[2]), (uint16_t)(v + q[3])};
            memcpy(indices + t, tri, sizeof tri);
            t += 6;
        }
        v += 8;
    }
    for (int j = 0; j < n; ++j) {
        memset(inverse_bind[j], 0, sizeof inverse_bind[j]);
        inverse_bind[j][0] = inverse_bind[j][5] = inverse_bind[j][10] = inverse_bind[j][15] = 1.0f;
        inverse_bind[j][12] = -100.0f * rest[j].x, inverse_bind[j][13] = -100.0f * rest[j].y;
        inverse_bind[j][14] = -100.0f * rest[j].z;
    }
    size_t sp = sizeof(float) * 3 * (size_t)v, sj = sizeof(uint16_t) * 4 * (size_t)v,
           sw = sizeof(float) * 4 * (size_t)v, si = sizeof(uint16_t) * (size_t)t,
           sb = sizeof(float) * 16 * (size_t)n;
    size_t total = sp + sj + sw + si + sb + 4;
    uint8_t *buf = calloc(1, total);
    char *b64 = malloc(total * 2 + 8);
    assert_non_null(buf);
    assert_non_null(b64);
    memcpy(buf, positions, sp);
    memcpy(buf + sp, bone_of, sj);
    memcpy(buf + sp + sj, weights, sw);
    memcpy(buf + sp + sj + sw, indices, si);
    size_t ob = (sp + sj + sw + si + 3) / 4 * 4; /* floats start on 4 bytes */
    memcpy(buf + ob, inverse_bind, sb);
    total = ob + sb;
    base64(buf, total, b64);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fprintf(f,
            "{\"asset\": {\"version\": \"2.0\"}, \"scene\": 0, \"scenes\": [{\"nodes\": [0, %d]}],\n "
            "\"nodes\": [",
            n);
    for (int j = 0; j < n; ++j) {
        fprintf(f, "%s{\"name\": \"%s\", \"translation\": [%g, %g, %g]", j ? ",\n  " : "",
                j == 1 && rename_first ? rename_first : joints[j].name, 100.0 * joints[j].offset.x,
                100.0 * joints[j].offset.y, 100.0 * joints[j].offset.z);
        int children = 0;
        for (int k = j + 1; k < n; ++k)
            if (joints[k].parent == j) fprintf(f, "%s%d", children++ ? ", " : ", \"children\": [", k);
        fprintf(f, "%s}", children ? "]" : "");
    }
    fprintf(f, ",\n  {\"name\": \"body\", \"mesh\": 0, \"skin\": 0}],\n \"skins\": [{\"joints\": [");
    for (int j = 0; j < n; ++j) fprintf(f, "%s%d", j ? ", " : "", j);
    fprintf(f, "], \"inverseBindMatrices\": 4, \"skeleton\": 0}],\n");
    fprintf(f, " \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0, \"JOINTS_0\": 1, "
               "\"WEIGHTS_0\": 2}, "
               "\"indices\": 3, \"material\": 0}]}],\n"
               " \"materials\": [{\"pbrMetallicRoughness\": {\"baseColorFactor\": [0.9, 0.1, 0.1, 1]}}],\n");
    fprintf(f,
            " \"buffers\": [{\"byteLength\": %zu, \"uri\": \"data:application/octet-stream;base64,%s\"}],\n",
            total, b64);
    fprintf(f,
            " \"bufferViews\": [{\"buffer\": 0, \"byteOffset\": 0, \"byteLength\": %zu}, {\"buffer\": 0, "
            "\"byteOffset\": "
            "%zu, \"byteLength\": %zu}, {\"buffer\": 0, \"byteOffset\": %zu, \"byteLength\": %zu}, "
            "{\"buffer\": 0, "
            "\"byteOffset\": %zu, \"byteLength\": %zu}, {\"buffer\": 0, \"byteOffset\": %zu, \"byteLength\": "
            "%zu}],\n",
            sp, sp, sj, sp + sj, sw, sp + sj + sw, si, ob, sb);
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < v; ++i)
        for (int c = 0; c < 3; ++c)
            lo[c] = fminf(lo[c], positions[i][c]), hi[c] = fmaxf(hi[c], positions[i][c]);
    fprintf(
        f,
        " \"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": %d, \"type\": \"VEC3\", "
        "\"min\": "
        "[%g, %g, %g], \"max\": [%g, %g, %g]},\n  {\"bufferView\": 1, \"componentType\": 5123, \"count\": "
        "%d, \"type\": "
        "\"VEC4\"},\n  {\"bufferView\": 2, \"componentType\": 5126, \"count\": %d, \"type\": \"VEC4\"},\n  "
        "{\"bufferView\": 3, \"componentType\": 5123, \"count\": %d, \"type\": \"SCALAR\"},\n  "
        "{\"bufferView\": 4, "
        "\"componentType\": 5126, \"count\": %d, \"type\": \"MAT4\"}]}\n",
        v, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2], v, v, t, n);
    fclose(f);
    free(buf);
    free(b64);
}

/* Pixels of the glTF's red (red well over green and blue) in a frame of a skeleton's pose. */
static int red_pixels(const mm_body_mesh *m, const mm_clip *clip)
{
    enum { PW = 320, PH = 180 };
    int n = clip->skeleton.joint_count;
    mm_quat *rot = malloc(sizeof(mm_quat) * (size_t)n);
    mm_vec3 *pos = malloc(sizeof(mm_vec3) * (size_t)n);
    mm_xform *global = malloc(sizeof(mm_xform) * (size_t)n);
    int *par = malloc(sizeof(int) * (size_t)n);
    assert_true(rot && pos && global && par);
    for (int j = 0; j < n; ++j) par[j] = clip->skeleton.joints[j].parent;
    mm_clip_sample(clip, 0.0f, rot, pos);
    mm_fk(&clip->skeleton, rot, pos, global);
    mm_render_scene s;
    memset(&s, 0, sizeof s);
    s.joint_count = n;
    s.parents = par;
    s.global = global;
    s.body_mesh = m;
    s.no_ground = true;
    mm_camera c;
    mm_camera_defaults(&c);
    c.target = global[0].translation;
    mm_offscreen *o;
    mm_error err;
    assert_int_equal(mm_offscreen_create(PW, PH, &o, &err), MM_OK);
    const uint8_t *rgb = mm_offscreen_render(o, &c, &s);
    assert_non_null(rgb);
    int red = 0;
    for (int i = 0; i < PW * PH; ++i)
        red += rgb[3 * i] > 2 * rgb[3 * i + 1] + 30 && rgb[3 * i] > 2 * rgb[3 * i + 2] + 30;
    mm_offscreen_destroy(o);
    free(rot);
    free(pos);
    free(global);
    free(par);
    return red;
}

static void test_mesh_option_through_the_program(void **state)
{
    (void)state;
    const char *mm = getenv("MM_BIN");
    if (!mm) skip();
    mm_error err;
    memset(&err, 0, sizeof err);
    /* a clip of the built-in set as BVH, and a body for its skeleton */
    mm_synth_desc sd;
    memset(&sd, 0, sizeof sd);
    mm_synth_set set;
    assert_int_equal(mm_synth_generate(&sd, &set, &err), MM_OK);
    const mm_clip *clip = &set.clips[0].clip;
    char bvh[1024], gltf[1024], wrong[1024], out[1024], cmd[8192];
    snprintf(bvh, sizeof bvh, "%s/mesh_option.bvh", MM_TEST_OUT);
    snprintf(gltf, sizeof gltf, "%s/mesh_option.gltf", MM_TEST_OUT);
    snprintf(wrong, sizeof wrong, "%s/mesh_option_wrong.gltf", MM_TEST_OUT);
    snprintf(out, sizeof out, "%s/mesh_option_frames", MM_TEST_OUT);
    assert_int_equal(mm_bvh_save(bvh, clip, NULL, &err), MM_OK);
    write_skeleton_gltf(gltf, clip->skeleton.joints, clip->skeleton.joint_count, NULL);
    write_skeleton_gltf(wrong, clip->skeleton.joints, clip->skeleton.joint_count, "NoSuchBone");
    /* the loader binds it to the clip's skeleton: a red body, its boxes on the bones */
    mm_body_mesh m;
    mm_result r = mm_body_mesh_load(gltf, clip->skeleton.joints, clip->skeleton.joint_count, &m, &err);
    if (r == MM_ERR_UNSUPPORTED) {
        mm_synth_set_free(&set);
        skip();
    }
    assert_int_equal(r, MM_OK);
    assert_true(m.vertex_count >= 8 * 10);
    assert_true(fabsf(m.colors[0] - 0.9f) < 1e-3f);
    assert_true(red_pixels(&m, clip) > 300);
    mm_body_mesh_free(&m);
    snprintf(cmd, sizeof cmd,
             "\"%s\" render \"%s\" -o \"%s\" --size 160x90 --seconds 0.2 --fps 10 --mesh \"%s\" >/dev/null",
             mm, bvh, out, gltf);
    assert_int_equal(system(cmd), 0);
    char frame[1200];
    snprintf(frame, sizeof frame, "%s/frame_00002.png", out);
    struct stat st;
    assert_int_equal(stat(frame, &st), 0);
    /* a bone no joint is named like: refused, naming it */
    snprintf(
        cmd, sizeof cmd,
        "\"%s\" render \"%s\" -o \"%s\" --size 160x90 --seconds 0.2 --mesh \"%s\" 2>&1 | grep -q NoSuchBone",
        mm, bvh, out, wrong);
    assert_int_equal(system(cmd), 0);
    snprintf(cmd, sizeof cmd,
             "\"%s\" render \"%s\" -o \"%s\" --size 160x90 --seconds 0.2 --mesh \"%s\" 2>/dev/null", mm, bvh,
             out, wrong);
    int status = system(cmd);
    assert_true(WIFEXITED(status) && WEXITSTATUS(status) == 1);
    mm_synth_set_free(&set);

    /* mm simulate --video --mesh on the built-in set's database, a body for its skeleton */
    mm_database db;
    assert_int_equal(test_build_synth_database(&db), 0);
    char dbpath[1024], dbgltf[1024], video[1024], motion[1024];
    snprintf(dbpath, sizeof dbpath, "%s/mesh_option.mmdb", MM_TEST_OUT);
    snprintf(dbgltf, sizeof dbgltf, "%s/mesh_option_db.gltf", MM_TEST_OUT);
    snprintf(video, sizeof video, "%s/mesh_option_video", MM_TEST_OUT);
    snprintf(motion, sizeof motion, "%s/mesh_option_motion.bvh", MM_TEST_OUT);
    assert_int_equal(mm_database_save(&db, dbpath, &err), MM_OK);
    write_skeleton_gltf(dbgltf, db.joints, db.joint_count, NULL);
    mm_database_free(&db);
    snprintf(cmd, sizeof cmd,
             "\"%s\" simulate \"%s\" --random 3 --seconds 0.5 -o \"%s\" --video \"%s\" --size 160x90 "
             "--video-fps 4 "
             "--mesh \"%s\" >/dev/null",
             mm, dbpath, motion, video, dbgltf);
    assert_int_equal(system(cmd), 0);
    snprintf(frame, sizeof frame, "%s/frame_00001.png", video);
    assert_int_equal(stat(frame, &st), 0);
    snprintf(cmd, sizeof cmd,
             "\"%s\" simulate \"%s\" --random 3 --seconds 0.5 -o \"%s\" --video \"%s\" --size 160x90 --mesh "
             "\"%s\" 2>&1 "
             "| grep -q NoSuchBone",
             mm, dbpath, motion, video, wrong);
    assert_int_equal(system(cmd), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_body_structure),
        cmocka_unit_test(test_body_proportions_and_face),
        cmocka_unit_test(test_single_joint_vertex_follows_its_joint),
        cmocka_unit_test(test_bent_limbs_stay_closed),
        cmocka_unit_test(test_body_scales_with_the_skeleton),
        cmocka_unit_test(test_bind_pose_is_the_straightest),
        cmocka_unit_test(test_body_refuses_what_it_cannot_make),
        cmocka_unit_test(test_gltf_mesh_loads_by_bone_names),
        cmocka_unit_test(test_gltf_mesh_refusals),
        cmocka_unit_test(test_chase_camera_frames_from_behind),
        cmocka_unit_test(test_overlay_stays_off_the_character),
        cmocka_unit_test(test_mesh_option_through_the_program),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
