/* The quality metrics of docs/metrics.md, shared by mm simulate and mm pfnn run. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "motion_metrics.h"

#include <mm/moves.h>

int motion_metrics_init(motion_metrics *m, int joint_count, const int contact_joint[4], double fps,
                        long frames)
{
    memset(m, 0, sizeof *m);
    m->joint_count = joint_count;
    m->fps = fps;
    memcpy(m->contact_joint, contact_joint, sizeof m->contact_joint);
    for (int k = 0; k < 3; ++k)
        m->world[k] = malloc(sizeof(mm_vec3) * (size_t)(joint_count > 0 ? joint_count : 1));
    m->frame_capacity = frames > 0 ? frames : 1;
    m->frame_us = malloc(sizeof(float) * (size_t)m->frame_capacity);
    m->search_us = malloc(sizeof(float) * (size_t)m->frame_capacity);
    if (!m->world[0] || !m->world[1] || !m->world[2] || !m->frame_us || !m->search_us) {
        motion_metrics_free(m);
        return -1;
    }
    return 0;
}

void motion_metrics_free(motion_metrics *m)
{
    for (int k = 0; k < 3; ++k) free(m->world[k]);
    free(m->frame_us);
    free(m->search_us);
    memset(m, 0, sizeof *m);
}

void motion_metrics_input(motion_metrics *m, double t, const mm_input *in, mm_vec3 desired)
{
    /* a stick turn of more than 45 degrees while the desired speed is above 0.5 m/s */
    float stick_direction = atan2f(in->stick[0], in->stick[1]);
    int stick_on = in->stick[0] * in->stick[0] + in->stick[1] * in->stick[1] > 0.01f;
    if (stick_on && m->had_stick && mm_vec3_length(desired) > 0.5f &&
        fabsf(remainderf(stick_direction - m->last_stick_direction, (float)(2 * MM_PI))) >
            (float)(MM_PI / 4)) {
        m->pending = 1;
        m->pending_direction = atan2f(desired.x, desired.z);
        m->pending_since = (float)t;
    }
    if (stick_on) m->last_stick_direction = stick_direction;
    m->had_stick = stick_on;
}

void motion_metrics_frame(motion_metrics *m, double t, const mm_vec3 *world, unsigned contacts,
                          const mm_vec3 *raw_contacts, mm_vec3 sim_position, float sim_yaw, mm_vec3 root,
                          float root_yaw, float frame_us)
{
    long f = m->frames++;
    int n = m->joint_count;
    mm_vec3 *now = m->world[f % 3], *before = m->world[(f + 2) % 3], *before2 = m->world[(f + 1) % 3];
    int bad = 0;
    for (int j = 0; j < n; ++j) {
        mm_vec3 p = world[j];
        bad |= !isfinite(p.x) || !isfinite(p.y) || !isfinite(p.z);
        now[j] = p;
    }
    m->nan_frames += bad;
    if (m->scene && !bad) {
        /* the body's joints: joint 0, the simulation root, is a point on the ground under the hips,
         * which a move keeps at the clip's own ground (under the box it was recorded on) */
        double depth = n > 1 ? mm_moves_penetration(m->scene, world + 1, n - 1) : 0.0;
        if (depth > m->penetration_max) m->penetration_max = depth;
    }
    if (f >= 2)
        for (int j = 0; j < n; ++j) {
            mm_vec3 d = mm_vec3_add(mm_vec3_sub(now[j], mm_vec3_scale(before[j], 2.0f)), before2[j]);
            m->max_pop = fmax(m->max_pop, 100.0 * mm_vec3_length(d));
        }
    mm_vec3 raw[4];
    for (int k = 0; k < 4; ++k)
        raw[k] = raw_contacts               ? raw_contacts[k]
                 : m->contact_joint[k] >= 0 ? world[m->contact_joint[k]]
                                            : root;
    if (f >= 1)
        for (int k = 0; k < 4; ++k) {
            if (m->contact_joint[k] < 0 || !(contacts & (1u << k))) continue;
            mm_vec3 d = mm_vec3_sub(now[m->contact_joint[k]], before[m->contact_joint[k]]);
            m->slide_sum += 100.0 * sqrt(d.x * d.x + d.z * d.z) * m->fps;
            m->slide_frames += 1;
            mm_vec3 rd = mm_vec3_sub(raw[k], m->raw_previous[k]);
            m->raw_sum += 100.0 * sqrt(rd.x * rd.x + rd.z * rd.z) * m->fps;
        }
    memcpy(m->raw_previous, raw, sizeof raw);
    mm_vec3 e = mm_vec3_sub(sim_position, root);
    m->traj_err += 100.0 * sqrt(e.x * e.x + e.z * e.z);
    m->heading_err += fabs(remainderf(sim_yaw - root_yaw, (float)(2 * MM_PI))) * MM_RAD_TO_DEG;
    mm_vec3 v = mm_vec3_sub(root, f == 0 ? root : m->previous_root);
    m->previous_root = root;
    if (m->pending && v.x * v.x + v.z * v.z > 1e-10) {
        float a = fabsf(remainderf(atan2f(v.x, v.z) - m->pending_direction, (float)(2 * MM_PI)));
        if (a < (float)(20 * MM_DEG_TO_RAD)) {
            m->response_sum += t + 1.0 / m->fps - m->pending_since;
            ++m->responses;
            m->pending = 0;
        }
    }
    if (f < m->frame_capacity) m->frame_us[f] = frame_us;
}

void motion_metrics_scene(motion_metrics *m, const mm_scene *scene) { m->scene = scene; }

void motion_metrics_move(motion_metrics *m, const char *kind, double t_start, double t_end,
                         double target_error_cm)
{
    if (m->move_count >= MOTION_METRICS_MAX_MOVES) return;
    m->moves[m->move_count].kind = kind;
    m->moves[m->move_count].t_start = t_start;
    m->moves[m->move_count].t_end = t_end;
    m->moves[m->move_count].target_error_cm = target_error_cm;
    ++m->move_count;
}

void motion_metrics_search(motion_metrics *m, float us)
{
    if (m->search_count < m->frame_capacity) m->search_us[m->search_count++] = us;
}

static int compare_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

static void json_number(FILE *f, const char *key, double v, int last)
{
    if (isfinite(v))
        fprintf(f, "  \"%s\": %.6g%s\n", key, v, last ? "" : ",");
    else
        fprintf(f, "  \"%s\": null%s\n", key, last ? "" : ",");
}

/* Sorts values in place and returns the q-quantile (NAN when empty). */
static double quantile(float *values, long n, double q)
{
    if (n <= 0) return NAN;
    qsort(values, (size_t)n, sizeof(float), compare_float);
    return q == 0.5 ? values[n / 2] : values[(long)(q * (double)(n - 1))];
}

double motion_metrics_foot_slide(const motion_metrics *m)
{
    return m->slide_frames > 0 ? m->slide_sum / m->slide_frames : NAN;
}

double motion_metrics_traj_err(const motion_metrics *m)
{
    return m->frames ? m->traj_err / (double)m->frames : NAN;
}

void motion_metrics_write_json(motion_metrics *m, FILE *f, const motion_metrics_extra *x)
{
    long frames = m->frames < m->frame_capacity ? m->frames : m->frame_capacity;
    double frame_median = quantile(m->frame_us, frames, 0.5);
    double search_median = quantile(m->search_us, m->search_count, 0.5);
    double search_p99 = quantile(m->search_us, m->search_count, 0.99);
    double n = m->frames ? (double)m->frames : NAN;
    fprintf(f, "{\n");
    json_number(f, "foot_slide_cm_s", motion_metrics_foot_slide(m), 0);
    json_number(f, "foot_slide_raw_cm_s", m->slide_frames > 0 ? m->raw_sum / m->slide_frames : NAN, 0);
    json_number(f, "traj_err_cm", m->traj_err / n, 0);
    json_number(f, "heading_err_deg", m->heading_err / n, 0);
    json_number(f, "response_s", m->responses ? m->response_sum / m->responses : NAN, 0);
    json_number(f, "max_pop_cm", m->max_pop, 0);
    json_number(f, "db_max_pop_cm", x ? x->db_max_pop_cm : NAN, 0);
    json_number(f, "searches", x ? x->searches : NAN, 0);
    json_number(f, "transitions_per_s", x ? x->transitions_per_s : NAN, 0);
    json_number(f, "nan_frames", m->nan_frames, 0);
    json_number(f, "search_median_us", search_median, 0);
    json_number(f, "search_p99_us", search_p99, 0);
    json_number(f, "frame_median_us", frame_median, 0);
    json_number(f, "memory_mb", x ? x->memory_mb : NAN, 0);
    json_number(f, "penetration_max_cm", m->scene ? 100.0 * m->penetration_max : NAN, 0);
    fprintf(f, "  \"moves\": [");
    for (int k = 0; k < m->move_count; ++k) {
        fprintf(f, "%s\n    {\"kind\": \"%s\", \"t_start\": %.6g, \"t_end\": %.6g, \"target_error_cm\": ",
                k ? "," : "", m->moves[k].kind, m->moves[k].t_start, m->moves[k].t_end);
        if (isfinite(m->moves[k].target_error_cm))
            fprintf(f, "%.6g}", m->moves[k].target_error_cm);
        else
            fprintf(f, "null}");
    }
    fprintf(f, "%s]\n", m->move_count ? "\n  " : "");
    fprintf(f, "}\n");
}

float motion_metrics_yaw(mm_quat q)
{
    mm_vec3 f = mm_quat_rotate(q, mm_vec3_make(0, 0, 1));
    return atan2f(f.x, f.z);
}
