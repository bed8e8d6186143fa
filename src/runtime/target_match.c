/* Target matching (Unity's MatchTarget semantics): the remaining error, spread over the window. */
#include <mm/target_match.h>

#include <string.h>

#include "math_private.h"

void mm_target_match_init(mm_target_match *m, int bone, mm_vec3 target_position, mm_quat target_rotation,
                          float start_time, float end_time)
{
    if (!m) return;
    memset(m, 0, sizeof *m);
    m->bone = bone;
    m->target_position = target_position;
    m->target_rotation = target_rotation;
    m->position_weight = mm_vec3_make(1.0f, 1.0f, 1.0f);
    m->rotation_weight = 1.0f;
    m->start_time = start_time;
    m->end_time = end_time;
}

void mm_target_match_set_normalized(mm_target_match *m, float start, float end, float clip_duration)
{
    if (!m) return;
    m->start_time = start * clip_duration;
    m->end_time = end * clip_duration;
}

float mm_target_match_yaw(mm_quat q)
{
    if (!(fabsf(q.y) > 0.0f) && !(fabsf(q.w) > 0.0f)) return 0.0f;
    return wrap_angle(2.0f * atan2f(q.y, q.w));
}

static bool finite4(mm_quat q) { return isfinite(q.x) && isfinite(q.y) && isfinite(q.z) && isfinite(q.w); }

bool mm_target_match_step(mm_target_match *m, float time, float dt, mm_xform predicted_end,
                          mm_xform *correction)
{
    if (correction) *correction = mm_xform_identity();
    if (!m) return false;
    if (!isfinite(time) || !isfinite(dt) || !finite3(predicted_end.translation) ||
        !finite4(predicted_end.rotation) || !finite3(m->target_position) || !finite4(m->target_rotation) ||
        !finite3(m->position_weight) || !isfinite(m->rotation_weight) || !isfinite(m->start_time) ||
        !isfinite(m->end_time) || !finite3(m->applied_translation) || !isfinite(m->applied_yaw))
        return false;
    if (!(dt > 0.0f) || !(m->end_time > m->start_time)) return false;
    float t1 = time + dt;
    if (time >= m->end_time || t1 <= m->start_time) return false;

    /* the share of the remaining window this tick covers */
    float from = time > m->start_time ? time : m->start_time;
    float f = 1.0f;
    if (t1 < m->end_time) f = clamp01((t1 - from) / (m->end_time - from));

    /* position: the goal is the weighted way from where the clip alone would put the bone */
    mm_vec3 p = predicted_end.translation;
    mm_vec3 p0 = mm_vec3_sub(p, m->applied_translation);
    mm_vec3 w = mm_vec3_make(clamp01(m->position_weight.x), clamp01(m->position_weight.y),
                             clamp01(m->position_weight.z));
    mm_vec3 goal = mm_vec3_add(p0, mm_vec3_mul(w, mm_vec3_sub(m->target_position, p0)));
    mm_vec3 move = mm_vec3_scale(mm_vec3_sub(goal, p), f);

    /* yaw, likewise */
    float applied_yaw = wrap_angle(m->applied_yaw);
    float yaw_pred = mm_target_match_yaw(predicted_end.rotation);
    float error0 = wrap_angle(mm_target_match_yaw(m->target_rotation) - (yaw_pred - applied_yaw));
    float turn = wrap_angle(clamp01(m->rotation_weight) * error0 - applied_yaw) * f;

    mm_quat r = mm_quat_from_axis_angle(mm_vec3_make(0.0f, 1.0f, 0.0f), turn);
    mm_xform c = mm_xform_make(r, mm_vec3_add(mm_vec3_sub(p, mm_quat_rotate(r, p)), move));
    if (!finite3(c.translation) || !finite4(c.rotation)) return false;
    m->applied_translation = mm_vec3_add(m->applied_translation, move);
    m->applied_yaw = wrap_angle(applied_yaw + turn);
    if (correction) *correction = c;
    return true;
}
