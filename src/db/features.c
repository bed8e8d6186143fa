#include "db/features.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "db/process.h"

static void add_group(mm_feature_group *g, int *count, int *dims, const char *name, mm_feature_kind kind,
                      int bone, float time, int n, float weight)
{
    mm_feature_group *x = &g[(*count)++];
    memset(x, 0, sizeof *x);
    snprintf(x->name, sizeof x->name, "%.63s", name);
    x->kind = kind;
    x->bone = bone;
    x->time = time;
    x->offset = *dims;
    x->dims = n;
    x->weight = weight;
    x->scale = 1.0f;
    *dims += n;
}

int mm__feature_layout(const mm_config *cfg, const mm_skeleton *s, mm_feature_group *groups, int *dims,
                       mm_error *err)
{
    int count = 0;
    *dims = 0;
    char name[MM_NAME_MAX];
    for (int i = 0; i < cfg->bone_count; ++i) {
        const mm_config_bone *b = &cfg->bones[i];
        int j = mm_skeleton_find(s, b->name);
        if (j < 0) {
            mm_error_set(err, MM_ERR_NOT_FOUND, 0, 0, "features.bones[%d]: no joint named '%s'", i, b->name);
            return -1;
        }
        if (b->features & MM_MATCH_POSITION) {
            snprintf(name, sizeof name, "%.40s.position", b->name);
            add_group(groups, &count, dims, name, MM_FEATURE_BONE_POSITION, j, 0, 3, b->position_weight);
        }
        if (b->features & MM_MATCH_VELOCITY) {
            snprintf(name, sizeof name, "%.40s.velocity", b->name);
            add_group(groups, &count, dims, name, MM_FEATURE_BONE_VELOCITY, j, 0, 3, b->velocity_weight);
        }
    }
    if (cfg->root_velocity)
        add_group(groups, &count, dims, "root.velocity", MM_FEATURE_ROOT_VELOCITY, 0, 0, 3,
                  cfg->body_velocity_weight);
    for (int i = 0; i < cfg->traj_count; ++i) {
        snprintf(name, sizeof name, "trajectory.position@%g", cfg->traj_times[i]);
        add_group(groups, &count, dims, name, MM_FEATURE_TRAJ_POSITION, -1, cfg->traj_times[i], 2,
                  cfg->position_multiplier);
    }
    for (int i = 0; i < cfg->traj_count; ++i) {
        snprintf(name, sizeof name, "trajectory.direction@%g", cfg->traj_times[i]);
        add_group(groups, &count, dims, name, MM_FEATURE_TRAJ_DIRECTION, -1, cfg->traj_times[i], 2,
                  cfg->angle_multiplier);
    }
    return count;
}

/* Ground transform of the root: yaw and position. */
typedef struct ground {
    double yaw, x, z;
} ground;

static ground ground_of(const mm_clip *c, int f)
{
    ground g;
    g.yaw = mm__yaw_of(mm_clip_rotations(c, f)[0]);
    mm_vec3 p = mm_clip_positions(c, f)[0];
    g.x = p.x;
    g.z = p.z;
    return g;
}

/* a * b: b expressed in a's frame, then placed in the world. */
static ground ground_mul(ground a, ground b)
{
    ground r;
    double c = cos(a.yaw), s = sin(a.yaw);
    r.x = a.x + c * b.x + s * b.z;
    r.z = a.z - s * b.x + c * b.z;
    r.yaw = a.yaw + b.yaw;
    return r;
}

static ground ground_inverse(ground a)
{
    ground r;
    double c = cos(a.yaw), s = sin(a.yaw);
    r.yaw = -a.yaw;
    r.x = -(c * a.x - s * a.z);
    r.z = -(s * a.x + c * a.z);
    return r;
}

/* Root ground transform at frame m, which may lie outside [0, n). */
static ground ground_at(const mm_clip *c, int loop, int m)
{
    int n = c->frame_count;
    if (m >= 0 && m < n) return ground_of(c, m);
    if (m < 0 || !loop) {
        int edge = m < 0 ? 0 : n - 1, other = m < 0 ? 1 : n - 2;
        ground e = ground_of(c, edge), o = ground_of(c, other);
        /* the velocity (per frame) at the edge, continued for the frames beyond it */
        double steps = m - edge;
        e.x += (m < 0 ? o.x - e.x : e.x - o.x) * steps;
        e.z += (m < 0 ? o.z - e.z : e.z - o.z) * steps;
        return e;
    }
    /* Loop: one cycle moves the root by C = R_n R_0^-1, where R_n continues the last step. */
    ground last = ground_of(c, n - 1), before = ground_of(c, n - 2);
    ground step = ground_mul(ground_inverse(before), last);
    ground cycle = ground_mul(ground_mul(last, step), ground_inverse(ground_of(c, 0)));
    ground r = ground_of(c, m % n);
    for (int k = 0; k < m / n; ++k) r = ground_mul(cycle, r);
    return r;
}

void mm__clip_features(const mm_clip *clip, int loop, const mm_xform *globals, const mm_vec3 *root_velocity,
                       const mm_feature_group *groups, int group_count, float interval, float *out,
                       int stride)
{
    int n = clip->frame_count, jc = clip->skeleton.joint_count;
    for (int f = 0; f < n; ++f) {
        float *row = out + (size_t)f * stride;
        const mm_xform *g = globals + (size_t)f * jc;
        mm_xform root = g[0];
        ground here = ground_of(clip, f), inv = ground_inverse(here);
        for (int i = 0; i < group_count; ++i) {
            const mm_feature_group *grp = &groups[i];
            float *dst = row + grp->offset;
            mm_vec3 v;
            switch (grp->kind) {
            case MM_FEATURE_BONE_POSITION:
                v = mm_quat_inv_rotate(root.rotation,
                                       mm_vec3_sub(g[grp->bone].translation, root.translation));
                break;
            case MM_FEATURE_BONE_VELOCITY: {
                int a = f > 0 ? f - 1 : 0, b = f > 0 ? f : 1;
                mm_vec3 d = mm_vec3_sub(globals[(size_t)b * jc + grp->bone].translation,
                                        globals[(size_t)a * jc + grp->bone].translation);
                v = mm_quat_inv_rotate(root.rotation, mm_vec3_scale(d, 1.0f / interval));
                break;
            }
            case MM_FEATURE_ROOT_VELOCITY:
                v = root_velocity[f];
                break;
            default: {
                int k = (int)lround(grp->time / interval);
                ground t = ground_mul(inv, ground_at(clip, loop, f + k));
                if (grp->kind == MM_FEATURE_TRAJ_POSITION)
                    v = mm_vec3_make((float)t.x, 0, (float)t.z);
                else
                    v = mm_vec3_make((float)sin(t.yaw), 0, (float)cos(t.yaw));
                dst[0] = v.x;
                dst[1] = v.z;
                continue;
            }
            }
            dst[0] = v.x;
            dst[1] = v.y;
            dst[2] = v.z;
        }
    }
}
