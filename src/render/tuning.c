/* Live tuning of a character's parameters: a list of named values with their steps and ranges. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <mm/view.h>

static void add(mm_view_tuning *t, const char *name, float *value, float step, bool multiply, float min,
                float max)
{
    if (t->count >= MM_VIEW_TUNING_MAX) return;
    mm_view_tuning_entry *e = &t->entries[t->count++];
    snprintf(e->name, sizeof e->name, "%s", name);
    e->value = value;
    e->step = step;
    e->multiply = multiply;
    e->min = min;
    e->max = max;
}

void mm_view_tuning_init(mm_view_tuning *t, mm_character *c)
{
    memset(t, 0, sizeof *t);
    t->character = c;
    t->desc = c->desc; /* written out: every value shown is the one in use */
    mm_search_params *p = &t->desc.params;
    const mm_database *db = c->db;
    add(t, "pose_trajectory_ratio", &p->pose_trajectory_ratio, 0.05f, false, 0.0f, 1.0f);
    add(t, "body_velocity_weight", &p->body_velocity_weight, 1.25f, true, 0.0f, 100.0f);
    add(t, "position_multiplier", &p->position_multiplier, 1.25f, true, 0.0f, 100.0f);
    add(t, "angle_multiplier", &p->angle_multiplier, 1.25f, true, 0.0f, 100.0f);
    /* the matched bones, in the database's order */
    mm_pose_data pose;
    mm_database_pose(db, 0, &pose);
    char name[48];
    for (int b = 0; b < pose.bone_count && b < MM_MAX_MATCH_BONES; ++b) {
        const char *bone =
            pose.bones[b] >= 0 && pose.bones[b] < db->joint_count ? db->joints[pose.bones[b]].name : "?";
        snprintf(name, sizeof name, "%.30s position", bone);
        add(t, name, &p->joint_position_weights[b], 1.25f, true, 0.0f, 100.0f);
        snprintf(name, sizeof name, "%.30s velocity", bone);
        add(t, name, &p->joint_velocity_weights[b], 1.25f, true, 0.0f, 100.0f);
    }
    add(t, "next_pose_favour", &p->next_pose_favour, 0.05f, false, 0.05f, 1.0f);
    add(t, "loop_anim_favour", &p->loop_anim_favour, 0.05f, false, 0.05f, 1.0f);
    add(t, "search_interval", &t->desc.search_interval, 0.02f, false, 0.02f, 2.0f);
    add(t, "transition_halflife", &t->desc.transition_halflife, 0.02f, false, 0.02f, 2.0f);
    static const char *gaits[2] = {"walk", "run"};
    for (int g = 0; g < 2; ++g) {
        mm_gait_params *gp = &t->desc.trajectory.gaits[g];
        snprintf(name, sizeof name, "%s.forward_speed", gaits[g]);
        add(t, name, &gp->forward_speed, 0.1f, false, 0.0f, 12.0f);
        snprintf(name, sizeof name, "%s.side_speed", gaits[g]);
        add(t, name, &gp->side_speed, 0.1f, false, 0.0f, 12.0f);
        snprintf(name, sizeof name, "%s.backward_speed", gaits[g]);
        add(t, name, &gp->backward_speed, 0.1f, false, 0.0f, 12.0f);
        snprintf(name, sizeof name, "%s.velocity_halflife", gaits[g]);
        add(t, name, &gp->velocity_halflife, 0.02f, false, 0.02f, 2.0f);
        snprintf(name, sizeof name, "%s.rotation_halflife", gaits[g]);
        add(t, name, &gp->rotation_halflife, 0.02f, false, 0.02f, 2.0f);
    }
}

void mm_view_tuning_select(mm_view_tuning *t, int delta)
{
    if (t->count <= 0) return;
    t->selected = ((t->selected + delta) % t->count + t->count) % t->count;
}

void mm_view_tuning_step(mm_view_tuning *t, int direction)
{
    if (t->count <= 0 || direction == 0) return;
    mm_view_tuning_entry *e = &t->entries[t->selected];
    /* a value of 0 is kept as MM_OFF in the desc, where zero means default */
    float v = isfinite(*e->value) ? fmaxf(*e->value, 0.0f) : e->min;
    if (e->multiply) {
        /* a zero weight cannot grow by a factor: it starts again from a tenth */
        if (v <= 0.0f && direction > 0) v = 0.1f / e->step;
        v *= powf(e->step, (float)direction);
    } else {
        v += e->step * (float)direction;
    }
    v = fminf(fmaxf(v, e->min), e->max);
    *e->value = v == 0.0f ? MM_OFF : v;
    mm_character_tune(t->character, &t->desc);
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
                     t->entries[i].name, (double)fmaxf(*t->entries[i].value, 0.0f));
        if (w < 0) break;
        at = (size_t)w >= n - at ? n - 1 : at + (size_t)w;
    }
    return at;
}
