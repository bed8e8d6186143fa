/* The OpenGL 3.3 core renderer: a lit character (a skinned body mesh, or capsules) with contact
 * shadows on a grid ground, debug lines and markers, and overlay text in the built-in font. */
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <mm/alloc.h>
#include <mm/database.h>
#include <mm/terrain_mesh.h>

#include "gl_api.h"
#include "render_internal.h"
#include "math_private.h"

#define MAX_SHADOWS 64

struct mm_renderer {
    mm_gl gl;
    GLuint lit, ground, flat, text;            /* programs */
    GLuint sphere_vao, sphere_vbo, sphere_ibo; /* unit sphere */
    GLuint cylinder_vao, cylinder_vbo;         /* unit cylinder, y in [0, 1] */
    GLuint cube_vao, cube_vbo;                 /* unit box, x and z in [-0.5, 0.5], y in [0, 1] */
    GLuint ground_vao, ground_vbo;             /* one quad, moved under the camera */
    GLuint dynamic_vao, dynamic_vbo;           /* lines and text, refilled every draw */
    GLuint skinned;                            /* program of the body mesh: per-vertex colours */
    GLuint body_vao, body_vbo, body_ibo;       /* the skinned body, refilled every draw */
    GLuint font_texture;
    int sphere_index_count, cylinder_vertex_count;
    float *scratch; /* vertex data for the dynamic buffer */
    size_t scratch_capacity;
    float *body_scratch; /* the skinned body: positions and normals, then interleaved vertices */
    size_t body_scratch_capacity;
};

static const mm_rgba default_body = {0.62f, 0.68f, 0.78f, 1.0f};
static const mm_rgba default_box = {0.80f, 0.64f, 0.46f, 1.0f};
static const mm_rgba terrain_color = {0.62f, 0.64f, 0.56f, 1.0f};
static const float fog_color[3] = {0.80f, 0.84f, 0.88f};

/* ---- shaders ---- */

static const char *lit_vs = "#version 330 core\n"
                            "layout(location = 0) in vec3 a_pos;\n"
                            "layout(location = 1) in vec3 a_normal;\n"
                            "uniform mat4 u_view_proj, u_model, u_normal;\n"
                            "out vec3 v_world, v_normal;\n"
                            "void main() {\n"
                            "  vec4 w = u_model * vec4(a_pos, 1.0);\n"
                            "  v_world = w.xyz;\n"
                            "  v_normal = mat3(u_normal) * a_normal;\n"
                            "  gl_Position = u_view_proj * w;\n"
                            "}\n";

/* hemisphere ambient, one key light, a little rim light, distance fog */
static const char *lit_fs =
    "#version 330 core\n"
    "in vec3 v_world, v_normal;\n"
    "uniform vec4 u_color;\n"
    "uniform vec3 u_eye, u_fog;\n"
    "out vec4 frag;\n"
    "void main() {\n"
    "  vec3 n = normalize(v_normal);\n"
    "  vec3 l = normalize(vec3(0.35, 1.0, 0.25));\n"
    "  vec3 v = normalize(u_eye - v_world);\n"
    "  vec3 ambient = mix(vec3(0.32, 0.29, 0.26), vec3(0.62, 0.68, 0.78), 0.5 + 0.5 * n.y);\n"
    "  vec3 c = u_color.rgb * (0.6 * ambient + 0.7 * max(dot(n, l), 0.0));\n"
    "  c += 0.18 * pow(1.0 - max(dot(n, v), 0.0), 3.0);\n"
    "  float f = clamp((length(u_eye - v_world) - 30.0) / 120.0, 0.0, 1.0);\n"
    "  frag = vec4(mix(c, u_fog, f), u_color.a);\n"
    "}\n";

/* the body: world positions (skinned on the CPU), normals and colours per vertex, lit as above
   with a softer key light and a little wrap so that the shaded side keeps its shape */
static const char *skinned_vs = "#version 330 core\n"
                                "layout(location = 0) in vec3 a_pos;\n"
                                "layout(location = 1) in vec3 a_normal;\n"
                                "layout(location = 2) in vec3 a_color;\n"
                                "uniform mat4 u_view_proj;\n"
                                "out vec3 v_world, v_normal, v_color;\n"
                                "void main() {\n"
                                "  v_world = a_pos;\n"
                                "  v_normal = a_normal;\n"
                                "  v_color = a_color;\n"
                                "  gl_Position = u_view_proj * vec4(a_pos, 1.0);\n"
                                "}\n";

static const char *skinned_fs =
    "#version 330 core\n"
    "in vec3 v_world, v_normal, v_color;\n"
    "uniform vec3 u_eye, u_fog;\n"
    "out vec4 frag;\n"
    "void main() {\n"
    "  vec3 n = normalize(v_normal);\n"
    "  vec3 v = normalize(u_eye - v_world);\n"
    "  if (dot(n, v) < 0.0) n = -n;\n"
    "  vec3 l = normalize(vec3(0.35, 1.0, 0.25));\n"
    "  float key = max((dot(n, l) + 0.25) / 1.25, 0.0);\n"
    "  vec3 ambient = mix(vec3(0.30, 0.28, 0.26), vec3(0.66, 0.70, 0.78), 0.5 + 0.5 * n.y);\n"
    "  vec3 c = v_color * (0.55 * ambient + 0.75 * key);\n"
    "  vec3 h = normalize(l + v);\n"
    "  c += 0.12 * pow(max(dot(n, h), 0.0), 24.0);\n"
    "  c += 0.10 * pow(1.0 - max(dot(n, v), 0.0), 3.0);\n"
    "  float f = clamp((length(u_eye - v_world) - 30.0) / 120.0, 0.0, 1.0);\n"
    "  frag = vec4(mix(c, u_fog, f), 1.0);\n"
    "}\n";

static const char *ground_vs = "#version 330 core\n"
                               "layout(location = 0) in vec3 a_pos;\n"
                               "uniform mat4 u_view_proj;\n"
                               "uniform vec3 u_offset;\n"
                               "out vec3 v_world;\n"
                               "void main() {\n"
                               "  v_world = a_pos + u_offset;\n"
                               "  gl_Position = u_view_proj * vec4(v_world, 1.0);\n"
                               "}\n";

/* a checker of 1 m tiles with anti-aliased lines every metre and fainter ones every 25 cm;
 * contact shadows are soft discs (x, z, radius, strength) */
static const char *ground_fs = "#version 330 core\n"
                               "in vec3 v_world;\n"
                               "uniform vec3 u_eye, u_fog;\n"
                               "uniform vec4 u_shadows[64];\n"
                               "uniform int u_shadow_count;\n"
                               "out vec4 frag;\n"
                               "float grid(vec2 p, float step) {\n"
                               "  vec2 q = p / step;\n"
                               "  vec2 g = abs(fract(q - 0.5) - 0.5) / max(fwidth(q), vec2(1e-6));\n"
                               "  return 1.0 - min(min(g.x, g.y), 1.0);\n"
                               "}\n"
                               "void main() {\n"
                               "  vec2 p = v_world.xz;\n"
                               "  vec2 cell = floor(p);\n"
                               "  float checker = mod(cell.x + cell.y, 2.0);\n"
                               "  vec3 c = mix(vec3(0.74, 0.75, 0.76), vec3(0.69, 0.70, 0.72), checker);\n"
                               "  c = mix(c, vec3(0.55, 0.56, 0.58), 0.5 * grid(p, 0.25));\n"
                               "  c = mix(c, vec3(0.40, 0.41, 0.43), grid(p, 1.0));\n"
                               "  float light = 1.0;\n"
                               "  for (int i = 0; i < u_shadow_count; ++i) {\n"
                               "    vec4 s = u_shadows[i];\n"
                               "    float d = length(p - s.xy) / s.z;\n"
                               "    light *= 1.0 - s.w * (1.0 - smoothstep(0.0, 1.0, d));\n"
                               "  }\n"
                               "  c *= light;\n"
                               "  float f = clamp((length(u_eye - v_world) - 30.0) / 120.0, 0.0, 1.0);\n"
                               "  frag = vec4(mix(c, u_fog, f), 1.0);\n"
                               "}\n";

static const char *flat_vs = "#version 330 core\n"
                             "layout(location = 0) in vec3 a_pos;\n"
                             "layout(location = 1) in vec4 a_color;\n"
                             "uniform mat4 u_view_proj;\n"
                             "out vec4 v_color;\n"
                             "void main() {\n"
                             "  v_color = a_color;\n"
                             "  gl_Position = u_view_proj * vec4(a_pos, 1.0);\n"
                             "}\n";

static const char *flat_fs = "#version 330 core\n"
                             "in vec4 v_color;\n"
                             "out vec4 frag;\n"
                             "void main() { frag = v_color; }\n";

/* text: positions in pixels (y down), texture coordinates into the font atlas */
static const char *text_vs =
    "#version 330 core\n"
    "layout(location = 0) in vec2 a_pos;\n"
    "layout(location = 1) in vec2 a_uv;\n"
    "uniform vec2 u_screen;\n"
    "out vec2 v_uv;\n"
    "void main() {\n"
    "  v_uv = a_uv;\n"
    "  gl_Position = vec4(2.0 * a_pos.x / u_screen.x - 1.0, 1.0 - 2.0 * a_pos.y / u_screen.y, 0.0, 1.0);\n"
    "}\n";

static const char *text_fs =
    "#version 330 core\n"
    "in vec2 v_uv;\n"
    "uniform sampler2D u_font;\n"
    "uniform vec4 u_color;\n"
    "out vec4 frag;\n"
    "void main() { frag = vec4(u_color.rgb, u_color.a * texture(u_font, v_uv).r); }\n";

static GLuint compile(mm_gl *gl, GLenum type, const char *source, const char *name, mm_error *err)
{
    GLuint s = gl->CreateShader(type);
    gl->ShaderSource(s, 1, &source, NULL);
    gl->CompileShader(s);
    GLint ok = 0;
    gl->GetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[512] = "";
        gl->GetShaderInfoLog(s, sizeof log, NULL, log);
        mm_error_set(err, MM_ERR_UNSUPPORTED, 0, 0, "the %s shader does not compile: %s", name, log);
        gl->DeleteShader(s);
        return 0;
    }
    return s;
}

static GLuint program(mm_gl *gl, const char *vs, const char *fs, const char *name, mm_error *err)
{
    GLuint v = compile(gl, GL_VERTEX_SHADER, vs, name, err);
    if (!v) return 0;
    GLuint f = compile(gl, GL_FRAGMENT_SHADER, fs, name, err);
    if (!f) {
        gl->DeleteShader(v);
        return 0;
    }
    GLuint p = gl->CreateProgram();
    gl->AttachShader(p, v);
    gl->AttachShader(p, f);
    gl->LinkProgram(p);
    gl->DeleteShader(v);
    gl->DeleteShader(f);
    GLint ok = 0;
    gl->GetProgramiv(p, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[512] = "";
        gl->GetProgramInfoLog(p, sizeof log, NULL, log);
        mm_error_set(err, MM_ERR_UNSUPPORTED, 0, 0, "the %s shader does not link: %s", name, log);
        gl->DeleteProgram(p);
        return 0;
    }
    return p;
}

/* ---- meshes ---- */

enum { SPHERE_RINGS = 10, SPHERE_SEGMENTS = 16, CYLINDER_SEGMENTS = 16 };

static void vertex_layout(mm_gl *gl, int floats_per_vertex, int first_size, int second_size)
{
    GLsizei stride = (GLsizei)(sizeof(float) * (size_t)floats_per_vertex);
    gl->VertexAttribPointer(0, first_size, GL_FLOAT, GL_FALSE, stride, (const void *)0);
    gl->EnableVertexAttribArray(0);
    if (second_size > 0) {
        gl->VertexAttribPointer(1, second_size, GL_FLOAT, GL_FALSE, stride,
                                (const void *)(sizeof(float) * (size_t)first_size));
        gl->EnableVertexAttribArray(1);
    }
}

static void make_meshes(mm_renderer *r)
{
    mm_gl *gl = &r->gl;
    /* sphere: position = normal */
    float sv[(SPHERE_RINGS + 1) * (SPHERE_SEGMENTS + 1) * 6];
    unsigned short si[SPHERE_RINGS * SPHERE_SEGMENTS * 6];
    int nv = 0, ni = 0;
    for (int i = 0; i <= SPHERE_RINGS; ++i) {
        double theta = MM_PI * i / SPHERE_RINGS;
        for (int k = 0; k <= SPHERE_SEGMENTS; ++k) {
            double phi = 2.0 * MM_PI * k / SPHERE_SEGMENTS;
            float p[3] = {(float)(sin(theta) * cos(phi)), (float)cos(theta), (float)(sin(theta) * sin(phi))};
            for (int c = 0; c < 3; ++c) sv[nv * 6 + c] = sv[nv * 6 + 3 + c] = p[c];
            ++nv;
        }
    }
    for (int i = 0; i < SPHERE_RINGS; ++i)
        for (int k = 0; k < SPHERE_SEGMENTS; ++k) {
            unsigned short a = (unsigned short)(i * (SPHERE_SEGMENTS + 1) + k),
                           b = (unsigned short)(a + SPHERE_SEGMENTS + 1);
            unsigned short quad[6] = {
                a, b, (unsigned short)(a + 1), (unsigned short)(a + 1), b, (unsigned short)(b + 1)};
            memcpy(si + ni, quad, sizeof quad);
            ni += 6;
        }
    r->sphere_index_count = ni;
    gl->GenVertexArrays(1, &r->sphere_vao);
    gl->BindVertexArray(r->sphere_vao);
    gl->GenBuffers(1, &r->sphere_vbo);
    gl->BindBuffer(GL_ARRAY_BUFFER, r->sphere_vbo);
    gl->BufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(sizeof(float) * (size_t)nv * 6), sv, GL_STATIC_DRAW);
    gl->GenBuffers(1, &r->sphere_ibo);
    gl->BindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->sphere_ibo);
    gl->BufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(sizeof(unsigned short) * (size_t)ni), si,
                   GL_STATIC_DRAW);
    vertex_layout(gl, 6, 3, 3);

    /* open cylinder of radius 1 from y = 0 to y = 1, as triangles */
    float cv[CYLINDER_SEGMENTS * 6 * 6];
    int nc = 0;
    for (int k = 0; k < CYLINDER_SEGMENTS; ++k) {
        double a0 = 2.0 * MM_PI * k / CYLINDER_SEGMENTS, a1 = 2.0 * MM_PI * (k + 1) / CYLINDER_SEGMENTS;
        float x0 = (float)cos(a0), z0 = (float)sin(a0), x1 = (float)cos(a1), z1 = (float)sin(a1);
        float corner[6][3] = {{x0, 0, z0}, {x0, 1, z0}, {x1, 0, z1}, {x1, 0, z1}, {x0, 1, z0}, {x1, 1, z1}};
        for (int v = 0; v < 6; ++v) {
            float *o = cv + nc * 6;
            o[0] = corner[v][0], o[1] = corner[v][1], o[2] = corner[v][2];
            o[3] = corner[v][0], o[4] = 0.0f, o[5] = corner[v][2];
            ++nc;
        }
    }
    r->cylinder_vertex_count = nc;
    gl->GenVertexArrays(1, &r->cylinder_vao);
    gl->BindVertexArray(r->cylinder_vao);
    gl->GenBuffers(1, &r->cylinder_vbo);
    gl->BindBuffer(GL_ARRAY_BUFFER, r->cylinder_vbo);
    gl->BufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(sizeof(float) * (size_t)nc * 6), cv, GL_STATIC_DRAW);
    vertex_layout(gl, 6, 3, 3);

    /* unit box: 6 faces of 2 triangles, each vertex with its face's normal */
    float bv[36 * 6];
    int nb = 0;
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side) {
            float sign = side ? 1.0f : -1.0f;
            int u = (axis + 1) % 3, w = (axis + 2) % 3;
            /* counter-clockwise seen from outside: (u, w) order flips with the side */
            float quad[6][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, -1}, {1, 1}, {-1, 1}};
            for (int k = 0; k < 6; ++k) {
                float p[3], n[3] = {0, 0, 0};
                p[axis] = 0.5f * sign;
                p[u] = 0.5f * quad[k][side ? 0 : 1];
                p[w] = 0.5f * quad[k][side ? 1 : 0];
                n[axis] = sign;
                float *o = bv + nb * 6;
                o[0] = p[0], o[1] = p[1] + 0.5f, o[2] = p[2];
                o[3] = n[0], o[4] = n[1], o[5] = n[2];
                ++nb;
            }
        }
    gl->GenVertexArrays(1, &r->cube_vao);
    gl->BindVertexArray(r->cube_vao);
    gl->GenBuffers(1, &r->cube_vbo);
    gl->BindBuffer(GL_ARRAY_BUFFER, r->cube_vbo);
    gl->BufferData(GL_ARRAY_BUFFER, (GLsizeiptr)sizeof bv, bv, GL_STATIC_DRAW);
    vertex_layout(gl, 6, 3, 3);

    /* ground: 400 m square, two triangles, moved under the camera target in 1 m steps */
    const float h = 200.0f;
    float gv[18] = {-h, 0, -h, -h, 0, h, h, 0, -h, h, 0, -h, -h, 0, h, h, 0, h};
    gl->GenVertexArrays(1, &r->ground_vao);
    gl->BindVertexArray(r->ground_vao);
    gl->GenBuffers(1, &r->ground_vbo);
    gl->BindBuffer(GL_ARRAY_BUFFER, r->ground_vbo);
    gl->BufferData(GL_ARRAY_BUFFER, sizeof gv, gv, GL_STATIC_DRAW);
    vertex_layout(gl, 3, 3, 0);

    gl->GenVertexArrays(1, &r->dynamic_vao);
    gl->GenBuffers(1, &r->dynamic_vbo);

    /* the body: position, normal, colour; contents every draw */
    gl->GenVertexArrays(1, &r->body_vao);
    gl->BindVertexArray(r->body_vao);
    gl->GenBuffers(1, &r->body_vbo);
    gl->GenBuffers(1, &r->body_ibo);
    gl->BindBuffer(GL_ARRAY_BUFFER, r->body_vbo);
    gl->BindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->body_ibo);
    for (int a = 0; a < 3; ++a) {
        gl->VertexAttribPointer((GLuint)a, 3, GL_FLOAT, GL_FALSE, (GLsizei)(sizeof(float) * 9),
                                (const void *)(sizeof(float) * 3 * (size_t)a));
        gl->EnableVertexAttribArray((GLuint)a);
    }
    gl->BindVertexArray(0);
}

static void make_font(mm_renderer *r)
{
    enum { W = 96 * MM_FONT_CELL_W, H = MM_FONT_CELL_H };
    static unsigned char atlas[H][W];
    for (int c = 32; c < 128; ++c)
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < MM_FONT_CELL_W; ++x)
                atlas[y][(c - 32) * MM_FONT_CELL_W + x] = mm_font_pixel(c, x, y) ? 255 : 0;
    mm_gl *gl = &r->gl;
    gl->GenTextures(1, &r->font_texture);
    gl->BindTexture(GL_TEXTURE_2D, r->font_texture);
    gl->PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    gl->TexImage2D(GL_TEXTURE_2D, 0, GL_R8, W, H, 0, GL_RED, GL_UNSIGNED_BYTE, atlas);
    gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

mm_result mm_renderer_create(mm_gl_loader load, mm_renderer **out, mm_error *err)
{
    *out = NULL;
    if (!load) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no OpenGL loader");
    mm_renderer *r = calloc(1, sizeof *r);
    if (!r) return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
#define MM_GL_LOAD(type, name)                                                                               \
    r->gl.name = (type)load("gl" #name);                                                                     \
    if (!r->gl.name) {                                                                                       \
        free(r);                                                                                             \
        return mm_error_set(err, MM_ERR_UNSUPPORTED, 0, 0, "OpenGL function gl%s is missing", #name);        \
    }
    MM_GL_FUNCTIONS(MM_GL_LOAD)
#undef MM_GL_LOAD
    mm_gl *gl = &r->gl;
    r->lit = program(gl, lit_vs, lit_fs, "lit", err);
    r->ground = r->lit ? program(gl, ground_vs, ground_fs, "ground", err) : 0;
    r->flat = r->ground ? program(gl, flat_vs, flat_fs, "line", err) : 0;
    r->text = r->flat ? program(gl, text_vs, text_fs, "text", err) : 0;
    r->skinned = r->text ? program(gl, skinned_vs, skinned_fs, "body", err) : 0;
    if (!r->skinned) {
        mm_renderer_destroy(r);
        return err ? err->code : MM_ERR_UNSUPPORTED;
    }
    make_meshes(r);
    make_font(r);
    *out = r;
    return MM_OK;
}

void mm_renderer_destroy(mm_renderer *r)
{
    if (!r) return;
    mm_gl *gl = &r->gl;
    GLuint programs[5] = {r->lit, r->ground, r->flat, r->text, r->skinned};
    for (int i = 0; i < 5; ++i)
        if (programs[i]) gl->DeleteProgram(programs[i]);
    GLuint vaos[5] = {r->sphere_vao, r->cylinder_vao, r->ground_vao, r->dynamic_vao, r->cube_vao};
    GLuint vbos[6] = {r->sphere_vbo, r->sphere_ibo,  r->cylinder_vbo,
                      r->ground_vbo, r->dynamic_vbo, r->cube_vbo};
    if (r->sphere_vao) {
        gl->DeleteVertexArrays(5, vaos);
        gl->DeleteBuffers(6, vbos);
    }
    if (r->body_vao) {
        GLuint body_buffers[2] = {r->body_vbo, r->body_ibo};
        gl->DeleteVertexArrays(1, &r->body_vao);
        gl->DeleteBuffers(2, body_buffers);
    }
    if (r->font_texture) gl->DeleteTextures(1, &r->font_texture);
    free(r->body_scratch);
    free(r->scratch);
    free(r);
}

/* ---- drawing ---- */

static void mat4_mul(const float a[16], const float b[16], float out[16])
{
    float m[16];
    for (int c = 0; c < 4; ++c)
        for (int rr = 0; rr < 4; ++rr) {
            float s = 0.0f;
            for (int k = 0; k < 4; ++k) s += a[k * 4 + rr] * b[c * 4 + k];
            m[c * 4 + rr] = s;
        }
    memcpy(out, m, sizeof m);
}

/* Model and normal matrices of rotation q, per-axis scale s, translation t. */
static void model_matrices(mm_quat q, mm_vec3 s, mm_vec3 t, float model[16], float normal[16])
{
    mm_mat3 r = mm_quat_to_mat3(q);
    float sc[3] = {s.x, s.y, s.z};
    for (int c = 0; c < 3; ++c)
        for (int rr = 0; rr < 3; ++rr) {
            model[c * 4 + rr] = r.m[rr][c] * sc[c];
            normal[c * 4 + rr] = r.m[rr][c] / sc[c];
        }
    model[3] = model[7] = model[11] = 0.0f;
    normal[3] = normal[7] = normal[11] = 0.0f;
    model[12] = t.x, model[13] = t.y, model[14] = t.z, model[15] = 1.0f;
    normal[12] = normal[13] = normal[14] = 0.0f, normal[15] = 1.0f;
}

/* Whether two names are the same in any case (ASCII). */
static bool same_name_any_case(const char *a, const char *b)
{
    for (; *a && *b; ++a, ++b)
        if (tolower((unsigned char)*a) != tolower((unsigned char)*b)) return false;
    return *a == *b;
}

int mm_render_find_head(const mm_joint *joints, int count)
{
    const char *head = mm_role_default_name(MM_ROLE_HEAD);
    for (int j = 1; j < count; ++j)
        if (same_name_any_case(joints[j].name, head)) return j;
    return 0;
}

static void draw_sphere(mm_renderer *r, GLint u_model, GLint u_normal, GLint u_color, mm_vec3 p, float radius,
                        mm_rgba color)
{
    if (!finite3(p) || !(radius > 0.0f)) return;
    float m[16], n[16];
    model_matrices(mm_quat_identity(), mm_vec3_make(radius, radius, radius), p, m, n);
    r->gl.UniformMatrix4fv(u_model, 1, GL_FALSE, m);
    r->gl.UniformMatrix4fv(u_normal, 1, GL_FALSE, n);
    r->gl.Uniform4f(u_color, color.r, color.g, color.b, color.a);
    r->gl.BindVertexArray(r->sphere_vao);
    r->gl.DrawElements(GL_TRIANGLES, r->sphere_index_count, GL_UNSIGNED_SHORT, (const void *)0);
}

static void draw_bone(mm_renderer *r, GLint u_model, GLint u_normal, GLint u_color, mm_vec3 a, mm_vec3 b,
                      float radius, mm_rgba color)
{
    mm_vec3 d = mm_vec3_sub(b, a);
    float len = mm_vec3_length(d);
    if (!finite3(a) || !finite3(b) || !(len > 1e-4f)) return;
    mm_quat q = mm_quat_between(mm_vec3_make(0.0f, 1.0f, 0.0f), mm_vec3_scale(d, 1.0f / len));
    float m[16], n[16];
    model_matrices(q, mm_vec3_make(radius, len, radius), a, m, n);
    r->gl.UniformMatrix4fv(u_model, 1, GL_FALSE, m);
    r->gl.UniformMatrix4fv(u_normal, 1, GL_FALSE, n);
    r->gl.Uniform4f(u_color, color.r, color.g, color.b, color.a);
    r->gl.BindVertexArray(r->cylinder_vao);
    r->gl.DrawArrays(GL_TRIANGLES, 0, r->cylinder_vertex_count);
}

void mm_render_box_corners(const mm_render_box *box, mm_vec3 out[8])
{
    float c = cosf(box->yaw), s = sinf(box->yaw);
    for (int i = 0; i < 8; ++i) {
        float x = (i & 1 ? 0.5f : -0.5f) * box->size.x, y = i & 2 ? box->size.y : 0.0f,
              z = (i & 4 ? 0.5f : -0.5f) * box->size.z;
        /* rotation about +Y: +Z turns toward +X */
        out[i] = mm_vec3_make(box->position.x + c * x + s * z, box->position.y + y,
                              box->position.z - s * x + c * z);
    }
}

static bool box_drawable(const mm_render_box *b)
{
    return isfinite(b->position.x) && isfinite(b->position.y) && isfinite(b->position.z) &&
           isfinite(b->size.x) && isfinite(b->size.y) && isfinite(b->size.z) && isfinite(b->yaw) &&
           b->size.x >= 0.0f && b->size.y >= 0.0f && b->size.z >= 0.0f;
}

static void draw_box(mm_renderer *r, GLint u_model, GLint u_normal, GLint u_color, const mm_render_box *b)
{
    if (!box_drawable(b)) return;
    float m[16], n[16];
    /* a flat plate (a size of 0) is drawn 2 mm thick: the normal matrix divides by the sizes */
    mm_vec3 size = mm_vec3_make(fmaxf(b->size.x, 0.002f), fmaxf(b->size.y, 0.002f), fmaxf(b->size.z, 0.002f));
    model_matrices(mm_quat_from_axis_angle(mm_vec3_make(0.0f, 1.0f, 0.0f), b->yaw), size, b->position, m, n);
    mm_rgba color = b->color.a > 0.0f ? b->color : default_box;
    r->gl.UniformMatrix4fv(u_model, 1, GL_FALSE, m);
    r->gl.UniformMatrix4fv(u_normal, 1, GL_FALSE, n);
    r->gl.Uniform4f(u_color, color.r, color.g, color.b, color.a);
    r->gl.BindVertexArray(r->cube_vao);
    r->gl.DrawArrays(GL_TRIANGLES, 0, 36);
}

static float *scratch(mm_renderer *r, size_t floats);
static void upload_dynamic(mm_renderer *r, const float *data, size_t floats, int first_size, int second_size);

/* The 12 edges of every box, dark, so that faces of the same shade stay apart. */
static void draw_box_edges(mm_renderer *r, const float view_proj[16], const mm_render_scene *s)
{
    static const int edges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                     {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
    float *v = scratch(r, (size_t)s->box_count * 24 * 7);
    if (!v) return;
    int n = 0;
    for (int i = 0; i < s->box_count; ++i) {
        if (!box_drawable(&s->boxes[i])) continue;
        /* on a box 1 cm larger, so that the faces do not hide the edges in the depth test */
        mm_render_box grown = s->boxes[i];
        grown.size = mm_vec3_add(grown.size, mm_vec3_make(0.01f, 0.01f, 0.01f));
        grown.position.y -= 0.005f;
        mm_vec3 c[8];
        mm_render_box_corners(&grown, c);
        for (int e = 0; e < 12; ++e)
            for (int k = 0; k < 2; ++k) {
                mm_vec3 p = c[edges[e][k]];
                float *o = v + (size_t)n * 7;
                o[0] = p.x, o[1] = p.y, o[2] = p.z;
                o[3] = 0.22f, o[4] = 0.17f, o[5] = 0.12f, o[6] = 1.0f;
                ++n;
            }
    }
    if (n == 0) return;
    mm_gl *gl = &r->gl;
    gl->UseProgram(r->flat);
    gl->UniformMatrix4fv(gl->GetUniformLocation(r->flat, "u_view_proj"), 1, GL_FALSE, view_proj);
    upload_dynamic(r, v, (size_t)n * 7, 3, 4);
    gl->DrawArrays(GL_LINES, 0, n);
}

static float *scratch(mm_renderer *r, size_t floats)
{
    if (floats > r->scratch_capacity) {
        size_t n = floats + floats / 2 + 1024;
        float *p = realloc(r->scratch, sizeof(float) * n);
        if (!p) return NULL;
        r->scratch = p;
        r->scratch_capacity = n;
    }
    return r->scratch;
}

static void upload_dynamic(mm_renderer *r, const float *data, size_t floats, int first_size, int second_size)
{
    mm_gl *gl = &r->gl;
    gl->BindVertexArray(r->dynamic_vao);
    gl->BindBuffer(GL_ARRAY_BUFFER, r->dynamic_vbo);
    gl->BufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(sizeof(float) * floats), data, GL_STREAM_DRAW);
    vertex_layout(gl, first_size + second_size, first_size, second_size);
}

/* The terrain's triangles (world positions and normals), lit in a stone colour. */
static void draw_terrain(mm_renderer *r, GLint u_model, GLint u_normal, GLint u_color,
                         const mm_render_scene *s)
{
    static const float identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    r->gl.UniformMatrix4fv(u_model, 1, GL_FALSE, identity);
    r->gl.UniformMatrix4fv(u_normal, 1, GL_FALSE, identity);
    r->gl.Uniform4f(u_color, terrain_color.r, terrain_color.g, terrain_color.b, terrain_color.a);
    upload_dynamic(r, s->terrain, (size_t)s->terrain_triangle_count * MM_TERRAIN_MESH_FLOATS, 3, 3);
    r->gl.DrawArrays(GL_TRIANGLES, 0, 3 * s->terrain_triangle_count);
}

static void draw_lines(mm_renderer *r, const float view_proj[16], const mm_render_scene *s)
{
    if (s->line_count <= 0 || !s->lines) return;
    float *v = scratch(r, (size_t)s->line_count * 14);
    if (!v) return;
    int n = 0;
    for (int i = 0; i < s->line_count; ++i) {
        const mm_render_line *l = &s->lines[i];
        if (!finite3(l->a) || !finite3(l->b)) continue;
        mm_vec3 ends[2] = {l->a, l->b};
        for (int e = 0; e < 2; ++e) {
            float *o = v + (size_t)n * 7;
            o[0] = ends[e].x, o[1] = ends[e].y, o[2] = ends[e].z;
            o[3] = l->color.r, o[4] = l->color.g, o[5] = l->color.b, o[6] = l->color.a;
            ++n;
        }
    }
    mm_gl *gl = &r->gl;
    gl->UseProgram(r->flat);
    gl->UniformMatrix4fv(gl->GetUniformLocation(r->flat, "u_view_proj"), 1, GL_FALSE, view_proj);
    upload_dynamic(r, v, (size_t)n * 7, 3, 4);
    gl->DrawArrays(GL_LINES, 0, n);
}

/* Quads of the font atlas for text at pixel (x, y), font pixels of scale screen pixels; solid
 * cells when panel. Returns vertex count. */
static int text_quads(float *v, const char *text, float x0, float y0, int scale, bool panel)
{
    const float cw = (float)(MM_FONT_CELL_W * scale), ch = (float)(MM_FONT_CELL_H * scale);
    const float atlas_w = 96.0f * MM_FONT_CELL_W;
    int n = 0;
    float x = x0, y = y0;
    for (const char *p = text; *p; ++p) {
        int c = (unsigned char)*p;
        if (c == '\n') {
            x = x0;
            y += ch;
            continue;
        }
        if (panel) c = MM_FONT_SOLID;
        if (c < 32 || c > 127) c = '?';
        float u0 = (float)((c - 32) * MM_FONT_CELL_W) / atlas_w, u1 = u0 + MM_FONT_CELL_W / atlas_w;
        float quad[6][4] = {{x, y, u0, 0},      {x, y + ch, u0, 1}, {x + cw, y, u1, 0},
                            {x + cw, y, u1, 0}, {x, y + ch, u0, 1}, {x + cw, y + ch, u1, 1}};
        memcpy(v + (size_t)n * 4, quad, sizeof quad);
        n += 6;
        x += cw;
    }
    return n;
}

/* The body mesh skinned to the scene's pose: vertex colours, tinted by a joint's colour where the
 * scene gives joints colours other than the body's (highlighted bones). */
static bool draw_body_mesh(mm_renderer *r, const float view_proj[16], mm_vec3 eye, const mm_render_scene *s,
                           mm_rgba body)
{
    const mm_body_mesh *m = s->body_mesh;
    if (!m || !s->global || m->vertex_count <= 0 || m->triangle_count <= 0 ||
        m->joint_count != s->joint_count)
        return false;
    size_t n = (size_t)m->vertex_count, need = n * 6 + n * 9;
    if (need > r->body_scratch_capacity) {
        float *p = realloc(r->body_scratch, sizeof(float) * need);
        if (!p) return false;
        r->body_scratch = p;
        r->body_scratch_capacity = need;
    }
    mm_vec3 *positions = (mm_vec3 *)r->body_scratch, *normals = positions + n;
    float *v = r->body_scratch + n * 6;
    mm_body_mesh_skin(m, s->global, positions, normals);
    for (size_t i = 0; i < n; ++i) {
        float *o = v + i * 9;
        o[0] = positions[i].x, o[1] = positions[i].y, o[2] = positions[i].z;
        o[3] = normals[i].x, o[4] = normals[i].y, o[5] = normals[i].z;
        const float *c = m->colors + i * 3;
        o[6] = c[0], o[7] = c[1], o[8] = c[2];
        int j = m->joints[i * MM_BODY_MAX_INFLUENCES];
        if (s->joint_colors && j >= 0 && j < s->joint_count) {
            mm_rgba t = s->joint_colors[j];
            if (t.r != body.r || t.g != body.g || t.b != body.b)
                o[6] = 0.3f * c[0] + 0.7f * t.r, o[7] = 0.3f * c[1] + 0.7f * t.g,
                o[8] = 0.3f * c[2] + 0.7f * t.b;
        }
    }
    mm_gl *gl = &r->gl;
    gl->UseProgram(r->skinned);
    gl->UniformMatrix4fv(gl->GetUniformLocation(r->skinned, "u_view_proj"), 1, GL_FALSE, view_proj);
    gl->Uniform3f(gl->GetUniformLocation(r->skinned, "u_eye"), eye.x, eye.y, eye.z);
    gl->Uniform3f(gl->GetUniformLocation(r->skinned, "u_fog"), fog_color[0], fog_color[1], fog_color[2]);
    gl->BindVertexArray(r->body_vao);
    gl->BindBuffer(GL_ARRAY_BUFFER, r->body_vbo);
    gl->BufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(sizeof(float) * n * 9), v, GL_STREAM_DRAW);
    gl->BufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(sizeof(uint32_t) * 3 * (size_t)m->triangle_count),
                   m->indices, GL_STREAM_DRAW);
    gl->DrawElements(GL_TRIANGLES, 3 * m->triangle_count, GL_UNSIGNED_INT, (const void *)0);
    return true;
}

#define OVERLAY_MARGIN     8     /* pixels between the text and the image's edge */
#define OVERLAY_BODY_REACH 0.15f /* m: the body's extent around its joints, for keeping the text off it */

bool mm_render_character_box(const mm_camera *cam, int width, int height, const mm_render_scene *s,
                             float box[4])
{
    box[0] = box[1] = INFINITY;
    box[2] = box[3] = -INFINITY;
    if (!cam || !s || !s->global || width <= 0 || height <= 0) return false;
    float focal = 0.5f * (float)height / tanf(0.5f * cam->fov_y);
    mm_vec3 eye = mm_camera_eye(cam);
    bool any = false;
    for (int j = s->first_joint > 0 ? s->first_joint : 0; j < s->joint_count; ++j) {
        mm_vec3 p = s->global[j].translation;
        float x, y;
        if (!finite3(p) || !mm_camera_project(cam, width, height, p, &x, &y)) continue;
        float reach = OVERLAY_BODY_REACH * focal / fmaxf(mm_vec3_distance(p, eye), cam->z_near);
        box[0] = fminf(box[0], x - reach), box[1] = fminf(box[1], y - reach);
        box[2] = fmaxf(box[2], x + reach), box[3] = fmaxf(box[3], y + reach);
        any = true;
    }
    return any;
}

static float overlap_area(const float a[4], const float b[4])
{
    float w = fminf(a[2], b[2]) - fmaxf(a[0], b[0]), h = fminf(a[3], b[3]) - fmaxf(a[1], b[1]);
    return w > 0.0f && h > 0.0f ? w * h : 0.0f;
}

void mm_render_overlay_place(const mm_camera *cam, int width, int height, const mm_render_scene *s,
                             mm_overlay_place *out)
{
    int tw = 0, th = 0;
    mm_text_measure(s ? s->overlay : NULL, &tw, &th);
    out->x = out->y = OVERLAY_MARGIN;
    out->scale = MM_FONT_SCALE;
    out->width = tw;
    out->height = th;
    float body[4];
    if (tw == 0 || !mm_render_character_box(cam, width, height, s, body)) return;
    /* the top left, top right, bottom left, bottom right corner, at the font's scale and then at
       half of it: the first clear of the body, else the one that covers least of it */
    float best = INFINITY;
    for (int scale = MM_FONT_SCALE; scale >= 1; --scale) {
        int w = tw * scale / MM_FONT_SCALE, h = th * scale / MM_FONT_SCALE;
        for (int corner = 0; corner < 4; ++corner) {
            int x = corner & 1 ? width - OVERLAY_MARGIN - w : OVERLAY_MARGIN;
            int y = corner & 2 ? height - OVERLAY_MARGIN - h : OVERLAY_MARGIN;
            float rect[4] = {(float)x, (float)y, (float)(x + w), (float)(y + h)};
            float covered = overlap_area(rect, body);
            if (covered < best) {
                best = covered;
                out->x = x, out->y = y, out->scale = scale, out->width = w, out->height = h;
            }
            if (covered <= 0.0f) return;
        }
    }
}

static void draw_overlay(mm_renderer *r, const mm_camera *cam, int width, int height,
                         const mm_render_scene *s)
{
    const char *text = s->overlay;
    if (!text || !*text) return;
    mm_overlay_place place;
    mm_render_overlay_place(cam, width, height, s, &place);
    size_t len = strlen(text);
    float *v = scratch(r, (len + 1) * 24 * 2);
    if (!v) return;
    mm_gl *gl = &r->gl;
    gl->Disable(GL_DEPTH_TEST);
    gl->Enable(GL_BLEND);
    gl->BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    gl->UseProgram(r->text);
    gl->Uniform2f(gl->GetUniformLocation(r->text, "u_screen"), (float)width, (float)height);
    gl->Uniform1i(gl->GetUniformLocation(r->text, "u_font"), 0);
    gl->ActiveTexture(GL_TEXTURE0);
    gl->BindTexture(GL_TEXTURE_2D, r->font_texture);
    GLint u_color = gl->GetUniformLocation(r->text, "u_color");
    /* a dark panel behind the characters, then the characters */
    for (int pass = 0; pass < 2; ++pass) {
        int n = text_quads(v, text, (float)place.x, (float)place.y, place.scale, pass == 0);
        if (pass == 0)
            gl->Uniform4f(u_color, 0.05f, 0.06f, 0.08f, 0.55f);
        else
            gl->Uniform4f(u_color, 1.0f, 1.0f, 1.0f, 1.0f);
        upload_dynamic(r, v, (size_t)n * 4, 2, 2);
        gl->DrawArrays(GL_TRIANGLES, 0, n);
    }
    gl->Disable(GL_BLEND);
    gl->Enable(GL_DEPTH_TEST);
}

/* The ground: a grid at the scene's ground height under the camera's target, darkened by soft
 * contact shadows of the joints (the nearer the ground, the darker and tighter). */
static void draw_ground(mm_renderer *r, const float view_proj[16], mm_vec3 eye, const mm_camera *cam,
                        const mm_render_scene *s)
{
    mm_gl *gl = &r->gl;
    int first = s->first_joint > 0 ? s->first_joint : 0;
    /* contact shadows: darker and tighter the closer a joint is to the ground */
    float shadows[MAX_SHADOWS][4];
    int count = 0, candidates = s->shadow_joints ? s->shadow_joint_count : s->joint_count;
    for (int i = 0; i < candidates && count < MAX_SHADOWS; ++i) {
        int j = s->shadow_joints ? s->shadow_joints[i] : i;
        if (j < first || j >= s->joint_count || !s->global) continue;
        mm_vec3 p = s->global[j].translation;
        if (!finite3(p)) continue;
        float h = fmaxf(p.y - s->ground_height, 0.0f), strength = 0.45f * fmaxf(0.0f, 1.0f - h / 1.2f);
        if (strength <= 0.0f) continue;
        shadows[count][0] = p.x, shadows[count][1] = p.z;
        shadows[count][2] = 0.10f + 0.25f * h, shadows[count][3] = strength;
        ++count;
    }
    gl->UseProgram(r->ground);
    gl->UniformMatrix4fv(gl->GetUniformLocation(r->ground, "u_view_proj"), 1, GL_FALSE, view_proj);
    gl->Uniform3f(gl->GetUniformLocation(r->ground, "u_offset"), floorf(cam->target.x),
                  isfinite(s->ground_height) ? s->ground_height : 0.0f, floorf(cam->target.z));
    gl->Uniform3f(gl->GetUniformLocation(r->ground, "u_eye"), eye.x, eye.y, eye.z);
    gl->Uniform3f(gl->GetUniformLocation(r->ground, "u_fog"), fog_color[0], fog_color[1], fog_color[2]);
    if (count) gl->Uniform4fv(gl->GetUniformLocation(r->ground, "u_shadows"), count, &shadows[0][0]);
    gl->Uniform1i(gl->GetUniformLocation(r->ground, "u_shadow_count"), count);
    gl->BindVertexArray(r->ground_vao);
    gl->DrawArrays(GL_TRIANGLES, 0, 6);
}

void mm_renderer_draw(mm_renderer *r, const mm_camera *cam, int width, int height, const mm_render_scene *s)
{
    if (!r || !cam || !s || width <= 0 || height <= 0) return;
    mm_gl *gl = &r->gl;
    float view[16], proj[16], view_proj[16];
    mm_camera_view_matrix(cam, view);
    mm_camera_projection_matrix(cam, (float)width / (float)height, proj);
    mat4_mul(proj, view, view_proj);
    mm_vec3 eye = mm_camera_eye(cam);

    gl->Viewport(0, 0, width, height);
    gl->ClearColor(fog_color[0], fog_color[1], fog_color[2], 1.0f);
    gl->Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    gl->Enable(GL_DEPTH_TEST);
    gl->Disable(GL_BLEND);

    float radius = s->bone_radius > 0.0f ? s->bone_radius : 0.03f;
    mm_rgba body = s->body_color.a > 0.0f ? s->body_color : default_body;
    int first = s->first_joint > 0 ? s->first_joint : 0;

    if (!s->no_ground) draw_ground(r, view_proj, eye, cam, s);

    bool body_drawn = draw_body_mesh(r, view_proj, eye, s, body);
    gl->UseProgram(r->lit);
    gl->UniformMatrix4fv(gl->GetUniformLocation(r->lit, "u_view_proj"), 1, GL_FALSE, view_proj);
    gl->Uniform3f(gl->GetUniformLocation(r->lit, "u_eye"), eye.x, eye.y, eye.z);
    gl->Uniform3f(gl->GetUniformLocation(r->lit, "u_fog"), fog_color[0], fog_color[1], fog_color[2]);
    GLint u_model = gl->GetUniformLocation(r->lit, "u_model"),
          u_normal = gl->GetUniformLocation(r->lit, "u_normal"),
          u_color = gl->GetUniformLocation(r->lit, "u_color");
    if (s->global && s->joint_count > 0 && !body_drawn)
        for (int j = first; j < s->joint_count; ++j) {
            mm_rgba c = s->joint_colors ? s->joint_colors[j] : body;
            draw_sphere(r, u_model, u_normal, u_color, s->global[j].translation,
                        j == s->head_joint ? 0.1f : radius * 1.2f, c);
            int p = s->parents ? s->parents[j] : -1;
            if (p >= first && p < s->joint_count)
                draw_bone(r, u_model, u_normal, u_color, s->global[p].translation, s->global[j].translation,
                          radius, c);
        }
    for (int i = 0; i < s->marker_count && s->markers; ++i)
        draw_sphere(r, u_model, u_normal, u_color, s->markers[i].position, s->markers[i].radius,
                    s->markers[i].color);
    if (s->terrain && s->terrain_triangle_count > 0) draw_terrain(r, u_model, u_normal, u_color, s);
    if (s->boxes && s->box_count > 0) {
        for (int i = 0; i < s->box_count; ++i) draw_box(r, u_model, u_normal, u_color, &s->boxes[i]);
        draw_box_edges(r, view_proj, s);
    }
    draw_lines(r, view_proj, s);
    draw_overlay(r, cam, width, height, s);
    gl->BindVertexArray(0);
}

void mm_renderer_read_pixels(mm_renderer *r, int width, int height, uint8_t *rgb)
{
    if (!r || !rgb || width <= 0 || height <= 0) return;
    mm_gl *gl = &r->gl;
    gl->Finish();
    gl->PixelStorei(GL_PACK_ALIGNMENT, 1);
    gl->ReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, rgb);
    /* OpenGL's rows run bottom to top: swap them */
    size_t stride = (size_t)width * 3;
    for (int y = 0; y < height / 2; ++y) {
        uint8_t *a = rgb + (size_t)y * stride, *b = rgb + (size_t)(height - 1 - y) * stride;
        for (size_t i = 0; i < stride; ++i) {
            uint8_t t = a[i];
            a[i] = b[i];
            b[i] = t;
        }
    }
}
