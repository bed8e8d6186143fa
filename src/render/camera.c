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

void mm_camera_framing_defaults(mm_camera_framing *f)
{
    f->yaw_offset = 0.35f;
    f->pitch = 0.30f;
    f->yaw_halflife = 0.6f;
    f->target_halflife = 0.25f;
    f->distance_halflife = 0.5f;
    f->min_distance = 2.5f;
    f->max_distance = 25.0f;
    f->half_width = 0.80f;
    f->top = 0.45f;
    f->bottom = -0.75f;
}

static float approach(float value, float goal, float halflife, float dt)
{
    if (!(dt > 0.0f) || !(halflife > 0.0f)) return goal;
    return goal + (value - goal) * exp2f(-dt / halflife);
}

/* The distance at which every point lies inside the framing window, looking at target from yaw
 * and pitch: a point at x right, y up, z forward of the target is at depth distance + z, so it fits
 * when |x| <= half_width * tan_x * (distance + z) and likewise for y against the window's top or
 * bottom. */
static float framing_distance(const mm_camera *c, const mm_camera_framing *f, const mm_vec3 *points,
                              int count, float aspect)
{
    mm_camera probe = *c;
    probe.distance = 1.0f;
    mm_vec3 eye = mm_camera_eye(&probe);
    mm_vec3 fwd = mm_vec3_normalize(mm_vec3_sub(c->target, eye));
    mm_vec3 right = mm_vec3_normalize(mm_vec3_cross(fwd, mm_vec3_make(0.0f, 1.0f, 0.0f)));
    mm_vec3 up = mm_vec3_cross(right, fwd);
    float tan_y = tanf(0.5f * c->fov_y), tan_x = tan_y * (aspect > 0.0f ? aspect : 1.0f);
    float need = f->min_distance;
    for (int i = 0; i < count; ++i) {
        mm_vec3 d = mm_vec3_sub(points[i], c->target);
        if (!isfinite(d.x) || !isfinite(d.y) || !isfinite(d.z)) continue;
        float x = mm_vec3_dot(d, right), y = mm_vec3_dot(d, up), z = mm_vec3_dot(d, fwd);
        float by_x = fabsf(x) / (f->half_width * tan_x) - z;
        float limit = y >= 0.0f ? f->top : -f->bottom;
        /* the window's edge on this side of the centre (a window not containing the centre: skip) */
        float by_y = limit > 0.05f ? fabsf(y) / (limit * tan_y) - z : 0.0f;
        need = fmaxf(need, fmaxf(by_x, by_y));
    }
    return fminf(need, f->max_distance);
}

void mm_camera_chase(mm_camera *c, const mm_camera_framing *f, float facing_yaw, const mm_vec3 *points,
                     int count, float aspect, float dt)
{
    if (!c || !f || !points || count < 1) return;
    bool jump = !(dt > 0.0f) || !isfinite(dt);
    /* behind the facing (the eye on the side the character turns its back to), a little to one side */
    if (isfinite(facing_yaw)) {
        float goal = facing_yaw + f->yaw_offset;
        float diff = remainderf(goal - c->yaw, (float)(2.0 * MM_PI));
        c->yaw = remainderf(jump ? goal : c->yaw + diff * (1.0f - exp2f(-dt / f->yaw_halflife)),
                            (float)(2.0 * MM_PI));
    }
    c->pitch = f->pitch;
    /* aim at the middle of the points' box, placed so the window's centre is its middle */
    mm_vec3 lo = {INFINITY, INFINITY, INFINITY}, hi = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < count; ++i) {
        mm_vec3 p = points[i];
        if (!isfinite(p.x) || !isfinite(p.y) || !isfinite(p.z)) continue;
        lo = mm_vec3_make(fminf(lo.x, p.x), fminf(lo.y, p.y), fminf(lo.z, p.z));
        hi = mm_vec3_make(fmaxf(hi.x, p.x), fmaxf(hi.y, p.y), fmaxf(hi.z, p.z));
    }
    if (!(lo.x <= hi.x)) return;
    mm_vec3 middle = mm_vec3_scale(mm_vec3_add(lo, hi), 0.5f);
    /* the window's centre lies (top + bottom) / 2 off the image's: aim that far (at the distance the
       points need) along the camera's up from their middle, so that they sit in the window's middle */
    mm_camera probe = *c;
    probe.target = middle;
    probe.distance = 1.0f;
    mm_vec3 up = mm_vec3_sub(mm_camera_eye(&probe), middle); /* from the eye's side: -forward */
    mm_vec3 fwd = mm_vec3_normalize(mm_vec3_neg(up));
    mm_vec3 right = mm_vec3_normalize(mm_vec3_cross(fwd, mm_vec3_make(0.0f, 1.0f, 0.0f)));
    up = mm_vec3_cross(right, fwd);
    float lift = -0.5f * (f->top + f->bottom) * tanf(0.5f * c->fov_y);
    float need = framing_distance(&probe, f, points, count, aspect);
    mm_vec3 aim = mm_vec3_add(middle, mm_vec3_scale(up, lift * need));
    probe.target = aim;
    need = framing_distance(&probe, f, points, count, aspect);
    c->target = mm_vec3_make(approach(c->target.x, aim.x, jump ? 0.0f : f->target_halflife, dt),
                             approach(c->target.y, aim.y, jump ? 0.0f : f->target_halflife, dt),
                             approach(c->target.z, aim.z, jump ? 0.0f : f->target_halflife, dt));
    if (!jump) need = framing_distance(c, f, points, count, aspect);
    /* draw back quickly (nothing leaves the window), come closer slowly */
    float halflife = need > c->distance ? 0.25f * f->distance_halflife : f->distance_halflife;
    c->distance = jump ? need : approach(c->distance, need, halflife, dt);
    if (!isfinite(c->distance)) c->distance = need;
}
