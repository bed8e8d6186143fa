/* The orbit camera: pure math, shared by the viewer's window and headless rendering. */
#include <math.h>

#include <mm/render.h>

void mm_camera_defaults(mm_camera *c)
{
    c->target = mm_vec3_make(0.0f, 0.9f, 0.0f);
    c->yaw = 0.6f;
    c->pitch = 0.22f;
    c->distance = 4.2f;
    c->fov_y = (float)(45.0 * MM_DEG_TO_RAD);
    c->z_near = 0.05f;
    c->z_far = 200.0f;
}

mm_vec3 mm_camera_eye(const mm_camera *c)
{
    /* (0, 0, -distance) rotated by the pitch (about X, lifting it) and then the yaw (about Y) */
    float cp = cosf(c->pitch), sp = sinf(c->pitch);
    mm_vec3 back = mm_vec3_make(-sinf(c->yaw) * cp, sp, -cosf(c->yaw) * cp);
    return mm_vec3_add(c->target, mm_vec3_scale(back, c->distance));
}

void mm_camera_view_matrix(const mm_camera *c, float m[16])
{
    mm_vec3 eye = mm_camera_eye(c);
    mm_vec3 f = mm_vec3_normalize(mm_vec3_sub(c->target, eye));
    mm_vec3 s = mm_vec3_normalize(mm_vec3_cross(f, mm_vec3_make(0.0f, 1.0f, 0.0f)));
    mm_vec3 u = mm_vec3_cross(s, f);
    /* rows s, u, -f; translation -R eye */
    m[0] = s.x, m[4] = s.y, m[8] = s.z, m[12] = -mm_vec3_dot(s, eye);
    m[1] = u.x, m[5] = u.y, m[9] = u.z, m[13] = -mm_vec3_dot(u, eye);
    m[2] = -f.x, m[6] = -f.y, m[10] = -f.z, m[14] = mm_vec3_dot(f, eye);
    m[3] = 0.0f, m[7] = 0.0f, m[11] = 0.0f, m[15] = 1.0f;
}

void mm_camera_projection_matrix(const mm_camera *c, float aspect, float m[16])
{
    float f = 1.0f / tanf(0.5f * c->fov_y), n = c->z_near, far = c->z_far;
    for (int i = 0; i < 16; ++i) m[i] = 0.0f;
    m[0] = f / (aspect > 0.0f ? aspect : 1.0f);
    m[5] = f;
    m[10] = (far + n) / (n - far);
    m[11] = -1.0f;
    m[14] = 2.0f * far * n / (n - far);
}

bool mm_camera_project(const mm_camera *c, int width, int height, mm_vec3 p, float *px, float *py)
{
    float v[16], pr[16];
    mm_camera_view_matrix(c, v);
    mm_camera_projection_matrix(c, height > 0 ? (float)width / (float)height : 1.0f, pr);
    float e[4], clip[4];
    for (int r = 0; r < 4; ++r) e[r] = v[r] * p.x + v[4 + r] * p.y + v[8 + r] * p.z + v[12 + r];
    for (int r = 0; r < 4; ++r)
        clip[r] = pr[r] * e[0] + pr[4 + r] * e[1] + pr[8 + r] * e[2] + pr[12 + r] * e[3];
    if (!(clip[3] > 1e-6f)) return false;
    *px = 0.5f * (clip[0] / clip[3] + 1.0f) * (float)width;
    *py = 0.5f * (1.0f - clip[1] / clip[3]) * (float)height;
    return true;
}

void mm_camera_orbit(mm_camera *c, float dyaw, float dpitch)
{
    if (isfinite(dyaw)) c->yaw = remainderf(c->yaw + dyaw, (float)(2.0 * MM_PI));
    if (isfinite(dpitch)) c->pitch = fminf(fmaxf(c->pitch + dpitch, -0.2f), 1.5f);
}

void mm_camera_zoom(mm_camera *c, float factor)
{
    if (isfinite(factor) && factor > 0.0f) c->distance = fminf(fmaxf(c->distance * factor, 0.5f), 50.0f);
}

void mm_camera_follow(mm_camera *c, mm_vec3 p, float halflife, float dt)
{
    if (!isfinite(p.x) || !isfinite(p.y) || !isfinite(p.z)) return;
    if (!(halflife > 0.0f)) {
        c->target = p;
        return;
    }
    if (!(dt > 0.0f) || !isfinite(dt)) return;
    /* an exponential approach: composing two ticks of dt equals one tick of 2 dt */
    float keep = exp2f(-dt / halflife);
    c->target = mm_vec3_add(p, mm_vec3_scale(mm_vec3_sub(c->target, p), keep));
}
