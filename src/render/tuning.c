/* Live tuning of a character's parameters: a list of named values with their steps, ranges and
 * config keys (only those the database uses), and the runtime layers as switches. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <mm/view.h>

/* Steps: weights change by a factor, fractions and times by a fixed amount. */
#define WEIGHT_FACTOR 1.25f
#define WEIGHT_MAX    100.0f
#define RATIO_STEP    0.05f
#define TIME_STEP     0.02f
#define TIME_MIN      0.02f
#define TIME_MAX      2.0f
#define SPEED_STEP    0.1f
#define SPEED_MAX     12.0f

static mm_view_tuning_entry *add(mm_view_tuning *t, const char *name, const char *key, float *value,
                                 float step, bool multiply, float min, float max)
{
    if (t->count >= MM_VIEW_TUNING_MAX) return NULL;
    mm_view_tuning_entry *e = &t->entries[t->count++];
    memset(e, 0, sizeof *e);
    snprintf(e->name, sizeof e->name, "%s", name);
    snprintf(e->key, sizeof e->key, "%s", key);
    e->value = value;
    e->step = step;
    e->multiply = multiply;
    e->min = min;
    e->max = max;
    e->saved = *value;
    return e;
}

static bool has_group(const mm_database *db, mm_feature_kind kind, int bone)
{
    for (int g = 0; g < db->group_count; ++g)
        if (db->groups[g].kind == (int32_t)kind && (bone < 0 || db->groups[g].bone == bone)) return true;
    return false;
}

static bool has_loop_clip(const mm_database *db)
{
    for (int i = 0; i < db->clip_count; ++i)
        if (db->clips[i].loop) return true;
    return false;
}

static void layers_of(const mm_character_desc *d, mm_view_layers *l)
{
    memset(l, 0, sizeof *l);
    l->crossfade = d->transition_mode == MM_TRANSITION_CROSSFADE;
    l->foot_ik = !d->no_foot_ik;
    l->distance_matching = d->distance_matching;
    l->warping = d->warping;
    l->root_sync = !(d->sync_halflife >= MM_VIEW_NO_SYNC_HALFLIFE);
    l->root_clamps = !(d->sync_max_distance >= MM_VIEW_NO_CLAMP);
}

void mm_view_tuning_init(mm_view_tuning *t, mm_character *c)
{
    memset(t, 0, sizeof *t);
    t->character = c;
    t->desc = c->desc; /* written out: every value shown is the one in use */
    layers_of(&c->desc, &t->layers);
    t->saved_layers = t->layers;
    mm_search_params *p = &t->desc.params;
    const mm_database *db = c->db;
    add(t, "pose_trajectory_ratio", "runtime.pose_trajectory_ratio", &p->pose_trajectory_ratio, RATIO_STEP,
        false, 0.0f, 1.0f);
    if (has_group(db, MM_FEATURE_ROOT_VELOCITY, -1))
        add(t, "body_velocity_weight", "features.body_velocity_weight", &p->body_velocity_weight,
            WEIGHT_FACTOR, true, 0.0f, WEIGHT_MAX);
    if (has_group(db, MM_FEATURE_TRAJ_POSITION, -1))
        add(t, "position_multiplier", "features.position_multiplier", &p->position_multiplier, WEIGHT_FACTOR,
            true, 0.0f, WEIGHT_MAX);
    if (has_group(db, MM_FEATURE_TRAJ_DIRECTION, -1))
        add(t, "angle_multiplier", "features.angle_multiplier", &p->angle_multiplier, WEIGHT_FACTOR, true,
            0.0f, WEIGHT_MAX);
    /* the matched bones, in the database's order, each weight only where a feature uses it */
    mm_pose_data pose;
    mm_database_pose(db, 0, &pose);
    char name[48];
    for (int b = 0; b < pose.bone_count && b < MM_MAX_MATCH_BONES; ++b) {
        int joint = pose.bones[b];
        const char *bone = joint >= 0 && joint < db->joint_count ? db->joints[joint].name : "?";
        for (int v = 0; v < 2; ++v) {
            if (!has_group(db, v ? MM_FEATURE_BONE_VELOCITY : MM_FEATURE_BONE_POSITION, joint)) continue;
            snprintf(name, sizeof name, "%.30s %s", bone, v ? "velocity" : "position");
            mm_view_tuning_entry *e = add(t, name, v ? "velocity_weight" : "position_weight",
                                          v ? &p->joint_velocity_weights[b] : &p->joint_position_weights[b],
                                          WEIGHT_FACTOR, true, 0.0f, WEIGHT_MAX);
            if (e) snprintf(e->bone, sizeof e->bone, "%.*s", (int)sizeof e->bone - 1, bone);
        }
    }
    add(t, "next_pose_favour", "runtime.next_pose_favour", &p->next_pose_favour, RATIO_STEP, false,
        RATIO_STEP, 1.0f);
    if (has_loop_clip(db))
        add(t, "loop_anim_favour", "runtime.loop_anim_favour", &p->loop_anim_favour, RATIO_STEP, false,
            RATIO_STEP, 1.0f);
    add(t, "continuing_bias", "runtime.continuing_bias", &p->continuing_bias, RATIO_STEP, false, 0.0f, 10.0f);
    add(t, "contact_favour", "runtime.contact_favour", &p->contact_mismatch_favour, RATIO_STEP, false, 1.0f,
        10.0f);
    add(t, "search_interval", "runtime.search_interval", &t->desc.search_interval, TIME_STEP, false, TIME_MIN,
        TIME_MAX);
    if (t->layers.crossfade) /* no config key: the crossfade is a viewer's experiment */
        add(t, "crossfade_time", "", &t->desc.crossfade_time, TIME_STEP, false, TIME_MIN, TIME_MAX);
    else
        add(t, "transition_halflife", "runtime.transition_halflife", &t->desc.transition_halflife, TIME_STEP,
            false, TIME_MIN, TIME_MAX);
    add(t, "idle_speed", "runtime.idle_speed", &t->desc.idle_speed, SPEED_STEP / 2, false, 0.0f, 2.0f);
    if (t->layers.root_sync)
        add(t, "sync_halflife", "runtime.sync_halflife", &t->desc.sync_halflife, TIME_STEP, false, 0.0f,
            TIME_MAX);
    static const char *const gait_names[3] = {"walk", "run", "crouch"};
    static const mm_gait gaits[3] = {MM_GAIT_WALK, MM_GAIT_RUN, MM_GAIT_CROUCH};
    static const struct {
        const char *field;
        float step, min, max;
    } gait_fields[5] = {{"forward_speed", SPEED_STEP, 0.0f, SPEED_MAX},
                        {"side_speed", SPEED_STEP, 0.0f, SPEED_MAX},
                        {"backward_speed", SPEED_STEP, 0.0f, SPEED_MAX},
                        {"velocity_halflife", TIME_STEP, TIME_MIN, TIME_MAX},
                        {"rotation_halflife", TIME_STEP, TIME_MIN, TIME_MAX}};
    bool crouch = mm_search_tag_mask(db, "Crouch") != 0;
    char key[sizeof t->entries[0].key];
    for (int g = 0; g < (crouch ? 3 : 2); ++g) {
        mm_gait_params *gp = &t->desc.trajectory.gaits[gaits[g]];
        float *values[5] = {&gp->forward_speed, &gp->side_speed, &gp->backward_speed, &gp->velocity_halflife,
                            &gp->rotation_halflife};
        for (int f = 0; f < 5; ++f) {
            snprintf(name, sizeof name, "%s.%s", gait_names[g], gait_fields[f].field);
            snprintf(key, sizeof key, "runtime.%.36s", name);
            add(t, name, key, values[f], gait_fields[f].step, false, gait_fields[f].min, gait_fields[f].max);
        }
    }
}

void mm_view_tuning_desc(const mm_view_tuning *t, mm_character_desc *out)
{
    *out = t->desc;
    const mm_view_layers *l = &t->layers;
    out->transition_mode = l->crossfade ? MM_TRANSITION_CROSSFADE : MM_TRANSITION_INERTIALIZE;
    out->no_foot_ik = !l->foot_ik;
    out->distance_matching = l->distance_matching;
    out->warping = l->warping;
    if (!l->root_sync) out->sync_halflife = MM_VIEW_NO_SYNC_HALFLIFE;
    if (!l->root_clamps) out->sync_max_distance = out->sync_max_angle = MM_VIEW_NO_CLAMP;
}

bool mm_view_tuning_apply(mm_view_tuning *t)
{
    mm_character_desc d;
    mm_view_tuning_desc(t, &d);
    mm_character_tune(t->character, &d);
    return d.transition_mode != t->character->desc.transition_mode;
}

void mm_view_tuning_select(mm_view_tuning *t, int delta)
{
    if (t->count <= 0) return;
    t->selected = ((t->selected + delta) % t->count + t->count) % t->count;
}

static void store(mm_view_tuning_entry *e, float v)
{
    v = fminf(fmaxf(v, e->min), e->max);
    *e->value =
        v == 0.0f ? MM_OFF : v; /* a value of 0 is kept as MM_OFF in the desc, where zero means default */
}

void mm_view_tuning_step(mm_view_tuning *t, int direction)
{
    if (t->count <= 0 || direction == 0) return;
    mm_view_tuning_entry *e = &t->entries[t->selected];
    float v = isfinite(*e->value) ? fmaxf(*e->value, 0.0f) : e->min;
    if (e->multiply) {
        /* a zero weight cannot grow by a factor: it starts again from a tenth */
        if (v <= 0.0f && direction > 0) v = 0.1f / e->step;
        v *= powf(e->step, (float)direction);
    } else {
        v += e->step * (float)direction;
    }
    store(e, v);
    mm_view_tuning_apply(t);
}

void mm_view_tuning_set(mm_view_tuning *t, int i, float value)
{
    if (i < 0 || i >= t->count || !isfinite(value)) return;
    store(&t->entries[i], value);
    mm_view_tuning_apply(t);
}

float mm_view_tuning_value(const mm_view_tuning *t, int i)
{
    if (i < 0 || i >= t->count) return 0.0f;
    return fmaxf(*t->entries[i].value, 0.0f);
}

size_t mm_view_tuning_text(const mm_view_tuning *t, char *out, size_t n)
{
    if (!out || n == 0) return 0;
    out[0] = 0;
    size_t at = 0;
    int lines = t->count < 5 ? t->count : 5;
    for (int k = 0; k < lines; ++k) {
        int i = ((t->selected - lines / 2 + k) % t->count + t->count) % t->count;
        int w =
            snprintf(out + at, n - at, "%s%c %-28s %.4g", k == 0 ? "" : "\n", i == t->selected ? '>' : ' ',
                     t->entries[i].name, (double)mm_view_tuning_value(t, i));
        if (w < 0) break;
        at = (size_t)w >= n - at ? n - 1 : at + (size_t)w;
    }
    return at;
}
