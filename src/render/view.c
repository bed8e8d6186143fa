/* The view of a character: its scene with debug drawing, the overlay text, and the mapping of
 * keys and gamepad to input. No OpenGL here; the renderer draws what this builds. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <mm/view.h>
#include <mm/terrain_mesh.h>

enum { LINE_CAPACITY = 256, MARKER_CAPACITY = 64, PATH_SAMPLES = 16 };

static const mm_rgba predicted_color = {1.0f, 0.55f, 0.1f, 1.0f};
static const mm_rgba matched_color = {0.15f, 0.75f, 0.25f, 1.0f};
static const mm_rgba past_color = {0.25f, 0.45f, 0.95f, 1.0f};
static const mm_rgba locked_color = {0.9f, 0.15f, 0.1f, 1.0f};
static const mm_rgba highlight_color = {0.95f, 0.8f, 0.25f, 1.0f};
static const mm_rgba velocity_color = {0.8f, 0.2f, 0.8f, 1.0f};
static const mm_rgba body_color = {0.62f, 0.68f, 0.78f, 1.0f};

void mm_view_flags_defaults(mm_view_flags *f)
{
    memset(f, 0, sizeof *f);
    f->predicted = f->matched = f->past = f->contacts = f->overlay = true;
}

mm_result mm_view_init(mm_view *v, const mm_database *db, mm_error *err)
{
    memset(v, 0, sizeof *v);
    if (!db || db->joint_count < 1)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no database to view");
    v->db = db;
    v->parents = malloc(sizeof(int) * (size_t)db->joint_count);
    v->joint_colors = malloc(sizeof(mm_rgba) * (size_t)db->joint_count);
    v->lines = malloc(sizeof(mm_render_line) * LINE_CAPACITY);
    v->markers = malloc(sizeof(mm_render_marker) * MARKER_CAPACITY);
    if (!v->parents || !v->joint_colors || !v->lines || !v->markers) {
        mm_view_free(v);
        return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    }
    v->line_capacity = LINE_CAPACITY;
    v->marker_capacity = MARKER_CAPACITY;
    for (int j = 0; j < db->joint_count; ++j) v->parents[j] = db->joints[j].parent;
    /* the body: without the roles it needs, the capsule figure */
    mm_error body_err;
    if (mm_body_mesh_build_from_database(db, &v->body, &body_err) == MM_OK) v->drawn = &v->body;
    return MM_OK;
}

void mm_view_set_body(mm_view *v, const mm_body_mesh *body)
{
    v->drawn = body ? body : v->body.vertex_count > 0 ? &v->body : NULL;
}

void mm_view_free(mm_view *v)
{
    mm_body_mesh_free(&v->body);
    free(v->boxes);
    free(v->terrain);
    free(v->parents);
    free(v->joint_colors);
    free(v->lines);
    free(v->markers);
    memset(v, 0, sizeof *v);
}

static void add_line(mm_view *v, mm_vec3 a, mm_vec3 b, mm_rgba color)
{
    if (v->scene.line_count >= v->line_capacity) return;
    mm_render_line *l = &v->lines[v->scene.line_count++];
    l->a = a;
    l->b = b;
    l->color = color;
}

static void add_marker(mm_view *v, mm_vec3 p, float radius, mm_rgba color)
{
    if (v->scene.marker_count >= v->marker_capacity) return;
    mm_render_marker *m = &v->markers[v->scene.marker_count++];
    m->position = p;
    m->radius = radius;
    m->color = color;
}

/* A path on the ground (lifted 2 cm so it is not hidden by the grid) with a facing tick and a
 * marker at every sample. */
static void add_path(mm_view *v, const mm_vec3 *p, const mm_vec3 *facing, int n, mm_rgba color)
{
    const mm_vec3 lift = {0.0f, 0.02f, 0.0f};
    for (int i = 0; i < n; ++i) {
        mm_vec3 a = mm_vec3_add(p[i], lift);
        if (i + 1 < n) add_line(v, a, mm_vec3_add(p[i + 1], lift), color);
        if (facing) add_line(v, a, mm_vec3_add(a, mm_vec3_scale(facing[i], 0.15f)), color);
        add_marker(v, a, 0.02f, color);
    }
}

void mm_view_update(mm_view *v, const mm_character *c, const mm_input *in, const mm_view_flags *flags,
                    float fps)
{
    mm_view_flags defaults;
    if (!flags) {
        mm_view_flags_defaults(&defaults);
        flags = &defaults;
    }
    const mm_database *db = v->db;
    mm_render_scene *s = &v->scene;
    memset(s, 0, sizeof *s);
    s->joint_count = db->joint_count;
    s->parents = v->parents;
    s->global = c->global;
    s->first_joint = db->joint_count > 1 ? 1 : 0; /* joint 0 is the simulation bone on the ground */
    s->bone_radius = 0.03f;
    int head = mm_database_role_joint(db, MM_ROLE_HEAD); /* the head role; 0: no sphere */
    s->head_joint = head > 0 ? head : 0;
    s->body_color = body_color;
    s->lines = v->lines;
    s->markers = v->markers;
    s->boxes = v->boxes;
    s->box_count = v->box_count;
    s->ground_height = v->ground;
    s->body_mesh = v->drawn;
    s->terrain = v->terrain;
    s->terrain_triangle_count = v->terrain_triangle_count;
    mm_input none;
    memset(&none, 0, sizeof none);
    if (!in) in = &none;

    int frame = c->frame >= 0 && c->frame < db->frame_count ? c->frame : 0;
    mm_pose_data pose;
    mm_database_pose(db, frame, &pose);

    if (flags->predicted || flags->past) {
        float times[PATH_SAMPLES];
        mm_vec3 positions[PATH_SAMPLES], directions[PATH_SAMPLES];
        mm_quat facings[PATH_SAMPLES];
        for (int pass = 0; pass < 2; ++pass) {
            if (!(pass == 0 ? flags->predicted : flags->past)) continue;
            /* 1 s ahead or behind, the first sample now */
            for (int i = 0; i < PATH_SAMPLES; ++i)
                times[i] = (pass == 0 ? 1.0f : -1.0f) * (float)i / (PATH_SAMPLES - 1);
            mm_trajectory_sample(c->trajectory, in, times, PATH_SAMPLES, positions, facings);
            for (int i = 0; i < PATH_SAMPLES; ++i)
                directions[i] = mm_quat_rotate(facings[i], mm_vec3_make(0, 0, 1));
            add_path(v, positions, directions, PATH_SAMPLES, pass == 0 ? predicted_color : past_color);
        }
    }
    if (flags->matched && pose.traj_count > 0) {
        /* the database frame's own trajectory, from where the character stands now */
        mm_vec3 positions[MM_MAX_TRAJ_SAMPLES + 1], directions[MM_MAX_TRAJ_SAMPLES + 1];
        int n = 0;
        positions[n] = mm_vec3_make(c->root.translation.x, 0.0f, c->root.translation.z);
        directions[n++] = mm_quat_rotate(c->root.rotation, mm_vec3_make(0, 0, 1));
        for (int i = 0; i < pose.traj_count; ++i) {
            if (pose.traj_times[i] <= 0.0f) continue;
            positions[n] = mm_xform_apply_point(c->root, pose.traj_positions[i]);
            positions[n].y = 0.0f;
            directions[n++] = mm_xform_apply_vector(c->root, pose.traj_directions[i]);
        }
        add_path(v, positions, directions, n, matched_color);
    }
    if (flags->contacts)
        for (int k = 0; k < 2; ++k) {
            int j = c->foot_joint[k];
            if (j < 0 || !c->foot_locked[k]) continue;
            add_marker(v, c->global[j].translation, 0.05f, locked_color);
            mm_vec3 ground = c->foot_lock[k];
            ground.y = 0.005f;
            add_marker(v, ground, 0.03f, locked_color);
        }
    if (flags->matched_bones) {
        for (int j = 0; j < db->joint_count; ++j) v->joint_colors[j] = body_color;
        for (int b = 0; b < pose.bone_count; ++b)
            if (pose.bones[b] >= 0 && pose.bones[b] < db->joint_count)
                v->joint_colors[pose.bones[b]] = highlight_color;
        s->joint_colors = v->joint_colors;
    }
    if (flags->velocities) {
        for (int b = 0; b < pose.bone_count; ++b) {
            int j = pose.bones[b];
            if (j < 0 || j >= db->joint_count) continue;
            mm_vec3 p = c->global[j].translation;
            add_line(
                v, p,
                mm_vec3_add(p, mm_vec3_scale(mm_xform_apply_vector(c->root, pose.bone_velocities[b]), 0.1f)),
                velocity_color);
        }
        mm_vec3 root = mm_vec3_add(c->root.translation, mm_vec3_make(0, 0.05f, 0));
        add_line(v, root,
                 mm_vec3_add(root, mm_vec3_scale(mm_xform_apply_vector(c->root, pose.root_velocity), 0.1f)),
                 velocity_color);
    }
    if (flags->overlay) {
        mm_view_overlay(v->overlay, sizeof v->overlay, c, in, fps);
        s->overlay = v->overlay;
    }
}

int mm_view_scene_boxes(const mm_scene *scene, mm_render_box *out, int capacity)
{
    if (!scene) return 0;
    static const mm_rgba tones[2] = {{0.80f, 0.64f, 0.46f, 1.0f}, {0.70f, 0.55f, 0.40f, 1.0f}};
    for (int i = 0; i < scene->box_count && i < capacity && out; ++i) {
        const mm_scene_box *b = &scene->boxes[i];
        out[i].position = b->position;
        out[i].size = b->size;
        out[i].yaw = b->yaw;
        out[i].color = tones[i & 1];
    }
    return scene->box_count;
}

mm_result mm_view_set_scene(mm_view *v, const mm_scene *scene, mm_error *err)
{
    free(v->boxes);
    v->boxes = NULL;
    v->box_count = 0;
    v->ground = 0.0f;
    free(v->terrain);
    v->terrain = NULL;
    v->terrain_triangle_count = 0;
    if (!scene) return MM_OK;
    int triangles = mm_terrain_mesh(scene, NULL, 0);
    if (triangles > 0) {
        v->terrain = malloc(sizeof(float) * MM_TERRAIN_MESH_FLOATS * (size_t)triangles);
        if (!v->terrain) return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
        v->terrain_triangle_count = mm_terrain_mesh(scene, v->terrain, triangles);
    }
    int n = scene->box_count;
    if (n < 0 || n > MM_SCENE_MAX_BOXES)
        return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0, "the scene has %d boxes (at most %d)", n,
                            MM_SCENE_MAX_BOXES);
    if (n > 0) {
        v->boxes = malloc(sizeof(mm_render_box) * (size_t)n);
        if (!v->boxes) return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    }
    v->box_count = mm_view_scene_boxes(scene, v->boxes, n);
    v->ground = scene->ground;
    return MM_OK;
}

static size_t append(char *out, size_t n, size_t at, const char *fmt, ...)
{
    if (at >= n) return at;
    va_list ap;
    va_start(ap, fmt);
    int k = vsnprintf(out + at, n - at, fmt, ap);
    va_end(ap);
    if (k < 0) return at;
    return (size_t)k >= n - at ? n - 1 : at + (size_t)k;
}

size_t mm_view_overlay(char *out, size_t n, const mm_character *c, const mm_input *in, float fps)
{
    if (!out || n == 0) return 0;
    out[0] = 0;
    const mm_database *db = c->db;
    int frame = c->frame >= 0 && c->frame < db->frame_count ? c->frame : 0;
    const mm_db_clip *clip = &db->clips[db->frame_clip[frame]];
    int in_clip = frame - clip->first_frame;
    size_t at = 0;
    at = append(out, n, at, "clip %s  frame %d/%d  t %.2f s\n", clip->name, in_clip, clip->frame_count,
                (double)((float)in_clip * db->interval));
    float speed = sqrtf(c->trajectory->velocity.x * c->trajectory->velocity.x +
                        c->trajectory->velocity.z * c->trajectory->velocity.z);
    const char *gait = in ? mm_gait_name(in->gait) : NULL;
    at = append(out, n, at, "gait %s%s  speed %.2f m/s%s\n", gait ? gait : "walk",
                in && in->strafe ? " strafe" : "", (double)speed, c->idle ? "  idle" : "");
    if (c->searches > 0 && c->last_result.frame >= 0 && c->query) {
        mm_search_terms t;
        mm_search_cost_terms(db, c->query, &c->last_params, c->last_result.frame, &t);
        at = append(out, n, at, "cost %.3f  pose %.3f vel %.3f root %.3f\n           traj %.3f dir %.3f\n",
                    (double)c->last_result.cost, (double)t.pose_position, (double)t.pose_velocity,
                    (double)t.root_velocity, (double)t.traj_position, (double)t.traj_direction);
    } else {
        at = append(out, n, at, "cost -\n");
    }
    at = append(out, n, at, "search %.0f us  searches %d  transitions %d", (double)c->last_search_us,
                c->searches, c->transitions);
    if (fps > 0.0f) at = append(out, n, at, "\nfps %.0f", (double)fps);
    return at;
}

void mm_view_input(const mm_view_keys *k, float camera_yaw, mm_input *out)
{
    memset(out, 0, sizeof *out);
    if (!isfinite(camera_yaw)) camera_yaw = 0.0f;
    /* camera forward and screen right on the ground (see mm_camera_eye: the eye looks along
     * (sin yaw, 0, cos yaw)); right = forward x up */
    float fx = sinf(camera_yaw), fz = cosf(camera_yaw), rx = -fz, rz = fx;
    float ahead = (float)k->forward - (float)k->back, side = (float)k->right - (float)k->left;
    float len = sqrtf(ahead * ahead + side * side);
    if (len > 1.0f) ahead /= len, side /= len;
    float px = isfinite(k->pad_stick[0]) ? k->pad_stick[0] : 0.0f,
          py = isfinite(k->pad_stick[1]) ? k->pad_stick[1] : 0.0f;
    float pad = sqrtf(px * px + py * py);
    const float dead = 0.15f;
    if (pad > dead) {
        float m = fminf((pad - dead) / (1.0f - dead), 1.0f) / pad;
        side = px * m;
        ahead = py * m;
    }
    out->stick[0] = fx * ahead + rx * side;
    out->stick[1] = fz * ahead + rz * side;
    out->gait = k->run || k->pad_run ? MM_GAIT_RUN : k->crouch ? MM_GAIT_CROUCH : MM_GAIT_WALK;
    out->strafe = k->strafe || k->pad_strafe;
    if (out->strafe) {
        out->has_facing = true;
        out->facing[0] = fx;
        out->facing[1] = fz;
    }
}

/* what the chase frames: the joints (up to CHASE_JOINTS) and the path over the next second */
enum { CHASE_PATH = 8, CHASE_JOINTS = 256 };

void mm_view_chase(mm_camera *cam, const mm_camera_framing *framing, const mm_character *c,
                   const mm_input *in, float aspect, float dt)
{
    mm_vec3 points[CHASE_JOINTS + CHASE_PATH];
    int n = 0;
    for (int j = 1; j < c->db->joint_count && n < CHASE_JOINTS; ++j) points[n++] = c->global[j].translation;
    float times[CHASE_PATH];
    mm_quat facings[CHASE_PATH];
    for (int i = 0; i < CHASE_PATH; ++i) times[i] = (float)(i + 1) / CHASE_PATH;
    mm_trajectory_sample(c->trajectory, in, times, CHASE_PATH, points + n, facings);
    n += CHASE_PATH;
    mm_vec3 forward = mm_quat_rotate(c->root.rotation, mm_vec3_make(0.0f, 0.0f, 1.0f));
    mm_camera_chase(cam, framing, atan2f(forward.x, forward.z), points, n, aspect, dt);
}
