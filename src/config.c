#include <mm/config.h>
#include <mm/database.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "io/name_set.h"

static void set_name(char *dst, const char *src) { snprintf(dst, MM_NAME_MAX, "%s", src); }

void mm_config_defaults(mm_config *c)
{
    memset(c, 0, sizeof *c);
    c->interval = 1.0f / 60.0f;
    c->scale = 0.0f;
    c->axes_up = MM_AXIS_POS_Y;
    c->axes_forward = -1;
    /* the roles' joints by their default names (mm_role_default_name, the one table of them); the
     * root bone is no role of the runtime's: its default joint is written here */
    set_name(c->hips, mm_role_default_name(MM_ROLE_HIPS));
    set_name(c->root_bone, "Spine2");
    set_name(c->facing_bone, mm_role_default_name(MM_ROLE_HIPS));
    c->forward_axis = mm_vec3_make(0, 0, 1);
    set_name(c->left_foot, mm_role_default_name(MM_ROLE_LEFT_FOOT));
    set_name(c->right_foot, mm_role_default_name(MM_ROLE_RIGHT_FOOT));
    set_name(c->left_toe, mm_role_default_name(MM_ROLE_LEFT_TOE));
    set_name(c->right_toe, mm_role_default_name(MM_ROLE_RIGHT_TOE));
    set_name(c->left_hand, mm_role_default_name(MM_ROLE_LEFT_HAND));
    set_name(c->right_hand, mm_role_default_name(MM_ROLE_RIGHT_HAND));
    set_name(c->head, mm_role_default_name(MM_ROLE_HEAD));
    c->root_smoothing = 0.1f;
    c->contact_height = 0.05f;
    c->contact_speed = 0.6f;
    c->contact_min_time = 0.1f;
    c->contact_planted_tolerance = 0.01f;
    c->postures_detect = true;
    c->standing_make = true;
    c->idle_loop_make = true;
    c->postures_pad = 0.25f;
    c->bone_count = 3;
    set_name(c->bones[0].name, c->left_foot);
    set_name(c->bones[1].name, c->right_foot);
    set_name(c->bones[2].name, c->hips);
    for (int i = 0; i < 2; ++i) {
        c->bones[i].features = MM_MATCH_POSITION | MM_MATCH_VELOCITY;
        c->bones[i].position_weight = 0.75f;
        c->bones[i].velocity_weight = 1.0f;
    }
    c->bones[2].features = MM_MATCH_VELOCITY;
    c->bones[2].velocity_weight = 1.0f;
    c->traj_count = 3;
    c->traj_times[0] = 0.3333333f;
    c->traj_times[1] = 0.6666667f;
    c->traj_times[2] = 1.0f;
    c->root_velocity = false;
    c->body_velocity_weight = 1.0f;
    c->position_multiplier = 1.0f;
    c->angle_multiplier = 1.5f;
    c->mirror_pair_count = 2;
    set_name(c->mirror_pairs[0].left, "Left");
    set_name(c->mirror_pairs[0].right, "Right");
    set_name(c->mirror_pairs[1].left, "left");
    set_name(c->mirror_pairs[1].right, "right");
}

const char *mm_axis_name(int axis)
{
    static const char *const names[6] = {"+X", "+Y", "+Z", "-X", "-Y", "-Z"};
    return axis >= 0 && axis < 6 ? names[axis] : NULL;
}

int mm_axis_parse(const char *name)
{
    if (!name) return -1;
    int sign = 0;
    if (name[0] == '+' || name[0] == '-') sign = *name++ == '-';
    if (!name[0] || name[1]) return -1;
    int axis = name[0] == 'x' || name[0] == 'X'   ? 0
               : name[0] == 'y' || name[0] == 'Y' ? 1
               : name[0] == 'z' || name[0] == 'Z' ? 2
                                                  : -1;
    return axis < 0 ? -1 : axis + 3 * sign;
}

int mm_axes_forward(int up, int forward)
{
    if (forward >= 0 && forward < 6) return forward;
    if (up == MM_AXIS_POS_Z) return MM_AXIS_NEG_Y;
    if (up == MM_AXIS_NEG_Z) return MM_AXIS_POS_Y;
    return MM_AXIS_POS_Z;
}

static mm_vec3 axis_vector(int axis)
{
    float v[3] = {0.0f, 0.0f, 0.0f};
    v[axis % 3] = axis < 3 ? 1.0f : -1.0f;
    return mm_vec3_make(v[0], v[1], v[2]);
}

mm_quat mm_axes_turn(int up, int forward)
{
    forward = mm_axes_forward(up, forward);
    if (up < 0 || up > 5 || up % 3 == forward % 3) return mm_quat_identity();
    /* the rows of the turn are the file's vectors that become +X, +Y and +Z: left (up x forward),
     * up and forward */
    mm_vec3 u = axis_vector(up), f = axis_vector(forward), l = mm_vec3_cross(u, f);
    mm_mat3 m;
    const mm_vec3 rows[3] = {l, u, f};
    for (int r = 0; r < 3; ++r) {
        m.m[r][0] = rows[r].x;
        m.m[r][1] = rows[r].y;
        m.m[r][2] = rows[r].z;
    }
    return mm_quat_normalize(mm_quat_from_mat3(m));
}

void mm_config_free(mm_config *c)
{
    if (!c) return;
    for (int i = 0; i < c->clip_count && c->clips; ++i) {
        mm_free(&c->allocator, c->clips[i].ranges);
        mm_free(&c->allocator, c->clips[i].tag_ranges);
    }
    mm_free(&c->allocator, c->clips);
    mm_free(&c->allocator, c->blends);
    c->clips = NULL;
    c->blends = NULL;
    c->clip_count = c->blend_count = 0;
}

int mm_config_tag_index(const mm_config *c, const char *name)
{
    for (int i = 0; i < c->tag_count; ++i)
        if (strcmp(c->tag_names[i], name) == 0) return i;
    return -1;
}

static int finite_positive(float v) { return isfinite(v) && v > 0.0f; }
static int finite_nonneg(float v) { return isfinite(v) && v >= 0.0f; }

/* The runtime tuning: only the fields that are set. */
static mm_result validate_runtime(const mm_runtime_config *rt, mm_error *err)
{
#define FAIL(...) return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0, __VA_ARGS__)
    unsigned s = rt->set;
    if ((s & MM_RUNTIME_POSE_TRAJECTORY_RATIO) &&
        !(isfinite(rt->pose_trajectory_ratio) && rt->pose_trajectory_ratio >= 0.0f &&
          rt->pose_trajectory_ratio <= 1.0f))
        FAIL("runtime.pose_trajectory_ratio: %g is outside [0, 1]", rt->pose_trajectory_ratio);
    if ((s & MM_RUNTIME_NEXT_POSE_FAVOUR) && !finite_positive(rt->next_pose_favour))
        FAIL("runtime.next_pose_favour: %g must be positive", rt->next_pose_favour);
    if ((s & MM_RUNTIME_LOOP_ANIM_FAVOUR) && !finite_positive(rt->loop_anim_favour))
        FAIL("runtime.loop_anim_favour: %g must be positive", rt->loop_anim_favour);
    if ((s & MM_RUNTIME_CONTACT_FAVOUR) && !(isfinite(rt->contact_favour) && rt->contact_favour >= 1.0f))
        FAIL("runtime.contact_favour: %g must be at least 1", rt->contact_favour);
    if ((s & MM_RUNTIME_CONTINUING_BIAS) && !finite_nonneg(rt->continuing_bias))
        FAIL("runtime.continuing_bias: %g must be >= 0", rt->continuing_bias);
    if ((s & MM_RUNTIME_SEARCH_INTERVAL) &&
        !(finite_positive(rt->search_interval) && rt->search_interval <= 10.0f))
        FAIL("runtime.search_interval: %g s is out of range (above 0, at most 10 s)", rt->search_interval);
    if ((s & MM_RUNTIME_TRANSITION_HALFLIFE) &&
        !(finite_positive(rt->transition_halflife) && rt->transition_halflife <= 60.0f))
        FAIL("runtime.transition_halflife: %g s is out of range (above 0, at most 60 s)",
             rt->transition_halflife);
    if ((s & MM_RUNTIME_IDLE_SPEED) && !(finite_nonneg(rt->idle_speed) && rt->idle_speed <= 50.0f))
        FAIL("runtime.idle_speed: %g m/s is out of range (0 to 50 m/s)", rt->idle_speed);
    if ((s & MM_RUNTIME_SYNC_HALFLIFE) && !(finite_nonneg(rt->sync_halflife) && rt->sync_halflife <= 60.0f))
        FAIL("runtime.sync_halflife: %g s is out of range (0 to 60 s)", rt->sync_halflife);
    const mm_runtime_gait *gaits[3] = {&rt->walk, &rt->run, &rt->crouch};
    static const char *const gait_names[3] = {"walk", "run", "crouch"};
    for (int g = 0; g < 3; ++g) {
        const mm_runtime_gait *p = gaits[g];
        const float speeds[3] = {p->forward_speed, p->side_speed, p->backward_speed};
        static const char *const speed_names[3] = {"forward_speed", "side_speed", "backward_speed"};
        for (int k = 0; k < 3; ++k)
            if ((p->set & (MM_RUNTIME_FORWARD_SPEED << k)) &&
                !(finite_nonneg(speeds[k]) && speeds[k] <= 50.0f))
                FAIL("runtime.%s.%s: %g m/s is out of range (0 to 50 m/s)", gait_names[g], speed_names[k],
                     speeds[k]);
        const float lives[2] = {p->velocity_halflife, p->rotation_halflife};
        static const char *const life_names[2] = {"velocity_halflife", "rotation_halflife"};
        for (int k = 0; k < 2; ++k)
            if ((p->set & (MM_RUNTIME_VELOCITY_HALFLIFE << k)) &&
                !(finite_positive(lives[k]) && lives[k] <= 60.0f))
                FAIL("runtime.%s.%s: %g s is out of range (above 0, at most 60 s)", gait_names[g],
                     life_names[k], lives[k]);
    }
    return MM_OK;
#undef FAIL
}

mm_result mm_config_validate(const mm_config *c, mm_error *err)
{
#define FAIL(...) return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0, __VA_ARGS__)
    if (!(finite_positive(c->interval) && c->interval <= 1.0f))
        FAIL("interval: %g s is out of range (0 to 1 s)", c->interval);
    if (!(finite_nonneg(c->scale) && c->scale < 1e6f))
        FAIL("scale: %g must be 0 (detect) or positive", c->scale);
    if (c->axes_up < 0 || c->axes_up > 5)
        FAIL("axes.up: %d is not an axis (+X, +Y, +Z, -X, -Y, -Z)", c->axes_up);
    if (c->axes_forward < -1 || c->axes_forward > 5)
        FAIL("axes.forward: %d is not an axis (+X, +Y, +Z, -X, -Y, -Z)", c->axes_forward);
    if (c->axes_forward >= 0 && c->axes_forward % 3 == c->axes_up % 3)
        FAIL("axes: forward %s lies along up %s; forward must be at right angles to up",
             mm_axis_name(c->axes_forward), mm_axis_name(c->axes_up));
    if (!finite_nonneg(c->root_smoothing) || c->root_smoothing > 10.0f)
        FAIL("root_smoothing: %g s is out of range (0 to 10 s)", c->root_smoothing);
    if (!finite_positive(c->contact_height)) FAIL("contacts.height: %g must be positive", c->contact_height);
    if (!finite_positive(c->contact_speed)) FAIL("contacts.speed: %g must be positive", c->contact_speed);
    if (!finite_nonneg(c->contact_min_time)) FAIL("contacts.min_time: %g must be >= 0", c->contact_min_time);
    if (!finite_nonneg(c->contact_planted_tolerance))
        FAIL("contacts.planted_tolerance: %g must be >= 0", c->contact_planted_tolerance);
    if (!finite_nonneg(c->postures_pad) || c->postures_pad > 10.0f)
        FAIL("postures.pad: %g must be in [0, 10] seconds", c->postures_pad);
    if (!(isfinite(c->forward_axis.x) && isfinite(c->forward_axis.y) && isfinite(c->forward_axis.z)) ||
        mm_vec3_length(c->forward_axis) < 1e-6f)
        FAIL("roles.forward_axis must be a non-zero vector");
    if (c->bone_count < 0 || c->bone_count > MM_MAX_MATCH_BONES)
        FAIL("features.bones: %d bones (at most %d)", c->bone_count, MM_MAX_MATCH_BONES);
    for (int i = 0; i < c->bone_count; ++i) {
        const mm_config_bone *b = &c->bones[i];
        if (!b->name[0]) FAIL("features.bones[%d].name is empty", i);
        if (!b->features) FAIL("features.bones[%d] (%s) has neither position nor velocity", i, b->name);
        if (!finite_nonneg(b->position_weight) || !finite_nonneg(b->velocity_weight))
            FAIL("features.bones[%d] (%s): weights must be finite and >= 0", i, b->name);
    }
    if (c->traj_count < 0 || c->traj_count > MM_MAX_TRAJ_SAMPLES)
        FAIL("features.trajectory_times: %d times (at most %d)", c->traj_count, MM_MAX_TRAJ_SAMPLES);
    for (int i = 0; i < c->traj_count; ++i) {
        float t = c->traj_times[i];
        if (!isfinite(t) || fabsf(t) > 10.0f || t == 0.0f)
            FAIL("features.trajectory_times[%d]: %g s must be non-zero, within +-10 s", i, t);
        for (int k = 0; k < i; ++k)
            if (c->traj_times[k] == t) FAIL("features.trajectory_times[%d]: %g s is listed twice", i, t);
    }
    if (!finite_nonneg(c->body_velocity_weight) || !finite_nonneg(c->position_multiplier) ||
        !finite_nonneg(c->angle_multiplier))
        FAIL("features: body_velocity_weight, position_multiplier and angle_multiplier must be >= 0");
    if (c->tag_count < 0 || c->tag_count > MM_MAX_TAGS)
        FAIL("tags: %d tags (at most %d)", c->tag_count, MM_MAX_TAGS);
    if (c->clip_count < 0 || (c->clip_count > 0 && !c->clips)) FAIL("clips: invalid clip list");
    /* names through a hash table: a config may list 100,000 clips */
    int twice =
        c->clip_count > 0 ? mm__name_set_first_repeat(c->clips[0].name, sizeof *c->clips, c->clip_count) : -1;
    if (twice == -2) return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    for (int i = 0; i < c->clip_count; ++i) {
        const mm_config_clip *k = &c->clips[i];
        if (!k->name[0]) FAIL("clips[%d].name is empty", i);
        if (i == twice)
            return mm_error_set(err, MM_ERR_DUPLICATE_NAME, 0, 0, "clips[%d].name '%s' is used twice", i,
                                k->name);
        if (!k->file[0]) FAIL("clips[%d] (%s): file is empty", i, k->name);
        if (k->type != MM_CLIP_LOCOMOTION && k->type != MM_CLIP_IDLE)
            FAIL("clips[%d] (%s): unknown type", i, k->name);
        for (int r = 0; r < k->range_count; ++r)
            if (k->ranges[r].begin < 0 || k->ranges[r].end <= k->ranges[r].begin)
                FAIL("clips[%d] (%s).ranges[%d]: [%d, %d) is empty or negative", i, k->name, r,
                     k->ranges[r].begin, k->ranges[r].end);
        if (k->loop && k->range_count > 1)
            FAIL("clips[%d] (%s): a loop clip has one range (it has %d)", i, k->name, k->range_count);
        for (int t = 0; t < k->tag_range_count; ++t) {
            const mm_config_tag_range *tr = &k->tag_ranges[t];
            if (tr->tag < 0 || tr->tag >= c->tag_count)
                FAIL("clips[%d] (%s).tags[%d]: unknown tag", i, k->name, t);
            if (!isfinite(tr->begin) || !isfinite(tr->end) || tr->end < tr->begin || tr->begin < 0)
                FAIL("clips[%d] (%s).tags.%s[%d]: [%g, %g] is not a time range", i, k->name,
                     c->tag_names[tr->tag], t, tr->begin, tr->end);
        }
    }
    for (int i = 0; i < c->blend_count; ++i) {
        const mm_config_blend *b = &c->blends[i];
        if (b->left < 0 || b->left >= c->clip_count || b->right < 0 || b->right >= c->clip_count)
            FAIL("blend_clips[%d] (%s): left and right must name clips", i, b->name);
        if (!(isfinite(b->weight) && b->weight >= 0.0f && b->weight <= 1.0f))
            FAIL("blend_clips[%d] (%s): weight %g is outside [0, 1]", i, b->name, b->weight);
    }
    return validate_runtime(&c->runtime, err);
#undef FAIL
}
