/* The quality metrics of docs/metrics.md, shared by mm simulate and mm pfnn run. */
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "motion_metrics.h"

#include <mm/clip.h>
#include <mm/gait.h>
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
    size_t cap = (size_t)m->frame_capacity;
    m->frame_us = malloc(sizeof(float) * cap);
    m->search_us = malloc(sizeof(float) * cap);
    m->head_height = malloc(sizeof(float) * cap);
    m->pop = malloc(sizeof(float) * cap);
    m->posture = calloc(cap, 1);
    m->crouch = calloc(cap, 1);
    m->slide = calloc(cap, sizeof(float));
    m->slide_count = calloc(cap, 1);
    if (!m->world[0] || !m->world[1] || !m->world[2] || !m->frame_us || !m->search_us || !m->head_height ||
        !m->pop || !m->posture || !m->crouch || !m->slide || !m->slide_count) {
        motion_metrics_free(m);
        return -1;
    }
    const motion_metrics_worst none = {0.0, -1, -1};
    m->worst_pop = m->worst_below = m->worst_float = none;
    motion_metrics_reference(m, NULL, 0.0f, NULL);
    return 0;
}

void motion_metrics_free(motion_metrics *m)
{
    for (int k = 0; k < 3; ++k) free(m->world[k]);
    free(m->frame_us);
    free(m->search_us);
    free(m->head_height);
    free(m->pop);
    free(m->posture);
    free(m->crouch);
    free(m->slide);
    free(m->slide_count);
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
        motion_metrics_response *r[2] = {&m->response_root, &m->response_sim};
        for (int k = 0; k < 2; ++k) {
            r[k]->pending = 1;
            r[k]->direction = atan2f(desired.x, desired.z);
            r[k]->since = (float)t;
        }
    }
    if (stick_on) m->last_stick_direction = stick_direction;
    m->had_stick = stick_on;
    m->crouch_input = in->gait == MM_GAIT_CROUCH;
}

void motion_metrics_reference(motion_metrics *m, const mm_posture_joints *joints, float head_height,
                              const double planted[4])
{
    mm_posture_joints none = {-1, -1, -1, -1, {-1, -1}, {-1, -1}};
    m->posture_joints = joints ? *joints : none;
    m->reference.head_height = head_height > 0 ? head_height : 0.0f;
    for (int k = 0; k < 4; ++k) m->planted[k] = planted ? planted[k] : NAN;
}

/* The ground under a point: without a scene y = 0; with one, the highest surface under it (the
 * ground plane or a box top) at most MOTION_METRICS_STEP_HEIGHT above it, else the ground plane. */
static double ground_under(const motion_metrics *m, mm_vec3 p)
{
    if (!m->scene) return 0.0;
    mm_scene_hit hit;
    if (mm_scene_ground_probe(m->scene, p, MOTION_METRICS_STEP_HEIGHT, INFINITY, &hit)) return hit.point.y;
    return m->scene->ground;
}

static int finite3(mm_vec3 p) { return isfinite(p.x) && isfinite(p.y) && isfinite(p.z); }

/* The ground the body stands on, for the head's height and the posture: the lowest of the grounds
 * under the contact joints (the head's without them). */
static double support_ground(const motion_metrics *m, const mm_vec3 *world)
{
    if (!m->scene) return 0.0;
    double g = INFINITY;
    for (int k = 0; k < 4; ++k)
        if (m->contact_joint[k] >= 0 && finite3(world[m->contact_joint[k]]))
            g = fmin(g, ground_under(m, world[m->contact_joint[k]]));
    if (isfinite(g)) return g;
    int head = m->posture_joints.head;
    return head >= 0 && finite3(world[head]) ? ground_under(m, world[head]) : m->scene->ground;
}

/* A joint's height above the ground under it (m). */
static double height_above(const motion_metrics *m, mm_vec3 p) { return p.y - ground_under(m, p); }

void motion_metrics_reference_from_motion(motion_metrics *m, const mm_posture_joints *joints,
                                          const mm_vec3 *world, long frames)
{
    motion_metrics_reference(m, joints, 0.0f, NULL);
    float *h = malloc(sizeof(float) * (size_t)(frames > 0 ? frames : 1));
    if (!h) return;
    int n = m->joint_count, head = m->posture_joints.head, count = 0;
    if (head >= 0) {
        for (long f = 0; f < frames; ++f) {
            const mm_vec3 *w = world + (size_t)f * (size_t)n;
            if (finite3(w[head])) h[count++] = (float)(w[head].y - support_ground(m, w));
        }
        m->reference.head_height = fmaxf(mm_posture_reference_height(h, count), 0.0f);
    }
    for (int k = 0; k < 4; ++k) {
        int j = m->contact_joint[k];
        if (j < 0) continue;
        for (long f = 0; f < frames; ++f) h[f] = (float)height_above(m, world[(size_t)f * (size_t)n + j]);
        m->planted[k] = motion_metrics_percentile(h, frames, 0.05);
    }
    free(h);
}

double motion_metrics_frame_pop(const mm_vec3 *now, const mm_vec3 *before, const mm_vec3 *before2, int n,
                                int *joint)
{
    /* the joint: the first within a rounding of the largest (a motion in other units names the same) */
    double worst = 0.0, at_value = 0.0;
    int at = -1;
    for (int j = 0; j < n; ++j) {
        double x = (double)now[j].x - 2.0 * before[j].x + before2[j].x,
               y = (double)now[j].y - 2.0 * before[j].y + before2[j].y,
               z = (double)now[j].z - 2.0 * before[j].z + before2[j].z;
        double d = sqrt(x * x + y * y + z * z);
        if (d > worst) worst = d; /* a NaN is left out */
        if (d > at_value * (1.0 + 1e-6)) {
            at_value = d;
            at = j;
        }
    }
    if (joint) *joint = at;
    return worst;
}

/* The measures of the pose of frame f (world positions), kept in m->world[f % 3]. */
static void pose_frame(motion_metrics *m, long f, const mm_vec3 *world)
{
    int n = m->joint_count;
    mm_vec3 *now = m->world[f % 3], *before = m->world[(f + 2) % 3], *before2 = m->world[(f + 1) % 3];
    int bad = 0;
    for (int j = 0; j < n; ++j) {
        mm_vec3 p = world[j];
        bad |= !finite3(p);
        now[j] = p;
    }
    m->nan_frames += bad;
    if (m->scene && !bad) {
        /* the body's joints: joint 0, the simulation root, is a point on the ground under the hips,
         * which a move keeps at the clip's own ground (under the box it was recorded on) */
        double depth = n > 1 ? mm_moves_penetration(m->scene, world + 1, n - 1) : 0.0;
        if (depth > m->penetration_max) m->penetration_max = depth;
    }
    int keep = f < m->frame_capacity;
    if (f >= 2) {
        int joint;
        double pop = motion_metrics_frame_pop(now, before, before2, n, &joint);
        m->max_pop = fmax(m->max_pop, 100.0 * pop);
        /* the second difference is the acceleration at the middle frame */
        if (100.0 * pop > m->worst_pop.value)
            m->worst_pop = (motion_metrics_worst){100.0 * pop, f - 1, joint};
        if (f - 2 < m->frame_capacity) m->pop[f - 2] = (float)pop;
    }
    for (int j = 1; j < n; ++j) {
        double depth = -height_above(m, now[j]);
        if (depth > m->below_ground) {
            m->below_ground = depth;
            m->worst_below = (motion_metrics_worst){100.0 * depth, f, j};
        }
    }
    const mm_posture_joints *pj = &m->posture_joints;
    double support = support_ground(m, now);
    if (keep) {
        m->head_height[f] =
            pj->head >= 0 && finite3(now[pj->head]) ? (float)(now[pj->head].y - support) : NAN;
        m->posture[f] = m->reference.head_height > 0
                            ? (uint8_t)mm_posture_classify(now, pj, (float)support, &m->reference)
                            : MM_POSTURE_UPRIGHT;
        m->crouch[f] = (uint8_t)(m->crouch_input != 0);
    }
    if (m->reference.head_height > 0 && mm_posture_arms_out(now, pj, &m->reference)) ++m->arms_out_frames;
    if (pj->left_hand >= 0 && pj->right_hand >= 0) {
        double apart = mm_vec3_length(mm_vec3_sub(now[pj->left_hand], now[pj->right_hand]));
        if (apart > m->hands_apart_max) m->hands_apart_max = apart;
    }
    if (f >= 1)
        for (int k = 0; k < 4; ++k) {
            int j = m->contact_joint[k];
            if (j < 0 || !isfinite(m->planted[k])) continue;
            motion_metrics_slide_add(&m->slide_height, k, height_above(m, now[j]) - m->planted[k],
                                     (double)now[j].x - before[j].x, (double)now[j].z - before[j].z, m->fps);
        }
}

/* A foot or toe within MOTION_METRICS_SLIDE_HEIGHT of its planted height for longer than
 * MOTION_METRICS_SLIDE_DWELL counts its ground speed with weight 2 - 2^(max(h, 0) / H), whatever
 * the labels say. */
void motion_metrics_slide_add(motion_metrics_slide *s, int k, double h, double dx, double dz, double fps)
{
    if (!(h < MOTION_METRICS_SLIDE_HEIGHT)) {
        s->near[k] = 0;
        return;
    }
    if (++s->near[k] <= lround(MOTION_METRICS_SLIDE_DWELL * fps)) return;
    double w = 2.0 - pow(2.0, fmax(h, 0.0) / MOTION_METRICS_SLIDE_HEIGHT);
    double v = 100.0 * sqrt(dx * dx + dz * dz) * fps;
    if (!isfinite(v)) return;
    s->sum += w * v;
    s->weight += w;
}

double motion_metrics_slide_value(const motion_metrics_slide *s)
{
    return s->weight > 0 ? s->sum / s->weight : NAN;
}

void motion_metrics_pose(motion_metrics *m, const mm_vec3 *world)
{
    m->pose_only = 1;
    pose_frame(m, m->frames++, world);
}

/* Frame f at time t: the point p moved since the frame before; a pending turn ends once it moves
 * within 20 degrees of the turn's direction. */
static void response_step(motion_metrics_response *r, long f, double t, double fps, mm_vec3 p)
{
    mm_vec3 v = mm_vec3_sub(p, f == 0 ? p : r->previous);
    r->previous = p;
    if (!r->pending || !(v.x * v.x + v.z * v.z > 1e-10)) return;
    float a = fabsf(remainderf(atan2f(v.x, v.z) - r->direction, (float)(2 * MM_PI)));
    if (a < (float)(20 * MM_DEG_TO_RAD)) {
        r->sum += t + 1.0 / fps - r->since;
        ++r->count;
        r->pending = 0;
    }
}

void motion_metrics_frame(motion_metrics *m, double t, const mm_vec3 *world, unsigned contacts,
                          const mm_vec3 *raw_contacts, mm_vec3 sim_position, float sim_yaw, mm_vec3 root,
                          float root_yaw, float frame_us)
{
    long f = m->frames++;
    pose_frame(m, f, world);
    mm_vec3 *now = m->world[f % 3], *before = m->world[(f + 2) % 3];
    /* the contact labels: their share, the labelled joints' height against their planted height */
    for (int k = 0; k < 4; ++k) {
        int j = m->contact_joint[k];
        if (j < 0) continue;
        m->contact_pairs += 1;
        if (!(contacts & (1u << k))) continue;
        m->contact_on += 1;
        double e = fabs(height_above(m, now[j]) - m->planted[k]);
        if (isfinite(e)) {
            m->contact_err_sum += e;
            m->contact_err_count += 1;
        }
    }
    /* a foot whose heel or toe label is on floats by the lower gap of its ankle and toe above their
     * planted heights over the ground under each (one of them on the ground: the foot stands), once
     * its label has been on for MOTION_METRICS_FLOAT_LANDING: before, a foot shown in the air is
     * landing (a transition to a frame whose foot is down brings it down over that time) */
    for (int foot = 0; foot < 2; ++foot) {
        if (!(contacts & (3u << (2 * foot)))) {
            m->labelled_frames[foot] = 0;
            continue;
        }
        if (++m->labelled_frames[foot] <= lround(MOTION_METRICS_FLOAT_LANDING * m->fps)) continue;
        double gap = INFINITY;
        int lower = -1;
        for (int k = 2 * foot; k < 2 * foot + 2; ++k) {
            int j = m->contact_joint[k];
            if (j < 0 || !isfinite(m->planted[k])) continue;
            double g = height_above(m, now[j]) - m->planted[k];
            if (isfinite(g) && g < gap) {
                gap = g;
                lower = j;
            }
        }
        if (!isfinite(gap)) continue;
        ++m->foot_float_frames;
        if (gap > m->foot_float) {
            m->foot_float = gap;
            m->worst_float = (motion_metrics_worst){100.0 * gap, f, lower};
        }
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
            double speed = 100.0 * sqrt(d.x * d.x + d.z * d.z) * m->fps;
            m->slide_sum += speed;
            m->slide_frames += 1;
            if (f < m->frame_capacity && isfinite(speed)) {
                m->slide[f] += (float)speed;
                m->slide_count[f] += 1;
            }
            mm_vec3 rd = mm_vec3_sub(raw[k], m->raw_previous[k]);
            m->raw_sum += 100.0 * sqrt(rd.x * rd.x + rd.z * rd.z) * m->fps;
        }
    memcpy(m->raw_previous, raw, sizeof raw);
    mm_vec3 e = mm_vec3_sub(sim_position, root);
    m->traj_err += 100.0 * sqrt(e.x * e.x + e.z * e.z);
    m->heading_err += fabs(remainderf(sim_yaw - root_yaw, (float)(2 * MM_PI))) * MM_RAD_TO_DEG;
    response_step(&m->response_root, f, t, m->fps, root);
    response_step(&m->response_sim, f, t, m->fps, sim_position);
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

/* A joint name as a JSON string (names come from files: quotes, backslashes and control characters
 * escaped). */
static void json_name(FILE *f, const char *name)
{
    fputc('"', f);
    for (const unsigned char *c = (const unsigned char *)name; *c; ++c) {
        if (*c == '"' || *c == '\\')
            fprintf(f, "\\%c", *c);
        else if (*c < 0x20)
            fprintf(f, "\\u%04x", *c);
        else
            fputc(*c, f);
    }
    fputc('"', f);
}

/* "key": where a worst value happened ({t_s, frame, joint, unit}), or null when it never was measured
 * or stayed 0. */
static void json_worst(FILE *f, const motion_metrics *m, const char *key, const motion_metrics_worst *w,
                       const char *unit, int last)
{
    fprintf(f, "\n    \"%s\": ", key);
    if (!w || w->frame < 0 || !(w->value > 0.0)) {
        fprintf(f, "null%s", last ? "" : ",");
        return;
    }
    fprintf(f, "{\"t_s\": %.6g, \"frame\": %ld, \"joint\": ", (double)w->frame / m->fps, w->frame);
    if (w->joint < 0)
        fprintf(f, "null");
    else if (m->joints)
        json_name(f, m->joints[w->joint].name);
    else
        fprintf(f, "%d", w->joint);
    fprintf(f, ", \"%s\": %.6g}%s", unit, w->value, last ? "" : ",");
}

/* Sorts values in place and returns the q-quantile (NAN when empty). */
static double quantile(float *values, long n, double q)
{
    if (n <= 0) return NAN;
    qsort(values, (size_t)n, sizeof(float), compare_float);
    return q == 0.5 ? values[n / 2] : values[(long)(q * (double)(n - 1))];
}

double motion_metrics_percentile(const float *v, long n, double q)
{
    float *sorted = malloc(sizeof(float) * (size_t)(n > 0 ? n : 1));
    if (!sorted) return NAN;
    long count = 0;
    for (long i = 0; i < n; ++i)
        if (isfinite(v[i])) sorted[count++] = v[i];
    double r = NAN;
    if (count > 0) {
        qsort(sorted, (size_t)count, sizeof(float), compare_float);
        r = sorted[(long)floor(q * (double)(count - 1))];
    }
    free(sorted);
    return r;
}

double motion_metrics_foot_slide(const motion_metrics *m)
{
    return m->slide_frames > 0 ? m->slide_sum / m->slide_frames : NAN;
}

double motion_metrics_traj_err(const motion_metrics *m)
{
    return m->frames ? m->traj_err / (double)m->frames : NAN;
}

long motion_metrics_worst_slide(const motion_metrics *m, double *seconds, double *cm_s, double *share)
{
    long frames = m->frames < m->frame_capacity ? m->frames : m->frame_capacity;
    long window = lround(MOTION_METRICS_SLIDE_WINDOW * m->fps);
    if (window < 1) window = 1;
    if (window > frames) window = frames;
    double sum = 0.0, total = 0.0, best = 0.0;
    long count = 0, best_count = 0, best_first = -1;
    for (long f = 0; f < frames; ++f) {
        total += m->slide[f];
        sum += m->slide[f];
        count += m->slide_count[f];
        if (f >= window) {
            sum -= m->slide[f - window];
            count -= m->slide_count[f - window];
        }
        if (f + 1 >= window && sum > best) {
            best = sum;
            best_count = count;
            best_first = f + 1 - window;
        }
    }
    *seconds = (double)window / m->fps;
    *cm_s = best_count > 0 ? best / (double)best_count : NAN;
    *share = total > 0.0 ? best / total : NAN;
    return best_first;
}

int motion_metrics_summary(const motion_metrics *m, motion_metrics_seen *out)
{
    long frames = m->frames < m->frame_capacity ? m->frames : m->frame_capacity;
    const mm_posture_joints *pj = &m->posture_joints;
    int labels = !m->pose_only, hands = pj->left_hand >= 0 && pj->right_hand >= 0;
    int posture = m->reference.head_height > 0 && pj->hips >= 0 && pj->head >= 0;
    out->below_ground_cm = 100.0 * m->below_ground;
    out->contact_height_err_cm =
        labels && m->contact_err_count > 0 ? 100.0 * m->contact_err_sum / m->contact_err_count : NAN;
    out->foot_float_cm = labels && m->foot_float_frames > 0 ? 100.0 * m->foot_float : NAN;
    out->contact_share = labels && m->contact_pairs > 0 ? m->contact_on / m->contact_pairs : NAN;
    out->foot_slide_height_cm_s = motion_metrics_slide_value(&m->slide_height);
    out->max_pop_cm = m->max_pop;
    out->pop_p99_cm = 100.0 * motion_metrics_percentile(m->pop, frames - 2, 0.99);
    out->head_p2_cm = 100.0 * motion_metrics_percentile(m->head_height, frames, 0.02);
    out->head_p5_cm = 100.0 * motion_metrics_percentile(m->head_height, frames, 0.05);
    out->head_p50_cm = 100.0 * motion_metrics_percentile(m->head_height, frames, 0.5);
    out->posture_first = -1;
    out->posture_frames = 0;
    out->posture_worst = MM_POSTURE_UPRIGHT;
    out->crouched_s = out->bent_s = out->lying_s = out->calibration_s = out->arms_spread_s =
        out->hand_raised_s = out->knee_raised_s = NAN;
    out->arms_out_s = m->reference.head_height > 0 && hands ? m->arms_out_frames / m->fps : NAN;
    out->hands_apart_max_cm = hands ? 100.0 * m->hands_apart_max : NAN;
    if (posture) {
        uint8_t *p = malloc((size_t)(frames > 0 ? frames : 1));
        if (!p) return -1; /* the posture's seconds stay NAN */
        memcpy(p, m->posture, (size_t)frames);
        long min_frames = lround(MM_POSTURE_MIN_SECONDS * m->fps);
        mm_posture_remove_flicker(p, (int)frames, min_frames > 1 ? (int)min_frames : 1);
        long count[MM_POSTURE_COUNT] = {0}, run = 0;
        for (long f = 0; f < frames; ++f) {
            int counted = p[f] == MM_POSTURE_CALIBRATION || !m->crouch[f];
            if (counted) ++count[p[f] < MM_POSTURE_COUNT ? p[f] : 0];
            /* the stretch of one posture other than upright, every frame counted, this frame ends */
            int other = counted && p[f] != MM_POSTURE_UPRIGHT && p[f] < MM_POSTURE_COUNT;
            run = !other ? 0 : run > 0 && p[f - 1] == p[f] ? run + 1 : 1;
            if (run > out->posture_frames) {
                out->posture_frames = run;
                out->posture_first = f + 1 - run;
                out->posture_worst = (mm_posture)p[f];
            }
        }
        free(p);
        out->crouched_s = count[MM_POSTURE_CROUCHED] / m->fps;
        out->bent_s = count[MM_POSTURE_BENT] / m->fps;
        out->lying_s = count[MM_POSTURE_LYING] / m->fps;
        out->calibration_s = count[MM_POSTURE_CALIBRATION] / m->fps;
        out->arms_spread_s = count[MM_POSTURE_ARMS_SPREAD] / m->fps;
        out->hand_raised_s = count[MM_POSTURE_HAND_RAISED] / m->fps;
        out->knee_raised_s = count[MM_POSTURE_KNEE_RAISED] / m->fps;
    }
    return 0;
}

static double response_mean(const motion_metrics_response *r) { return r->count ? r->sum / r->count : NAN; }

void motion_metrics_write_json(motion_metrics *m, FILE *f, const motion_metrics_extra *x)
{
    long frames = m->frames < m->frame_capacity ? m->frames : m->frame_capacity;
    int controller = !m->pose_only;
    double frame_median = controller ? quantile(m->frame_us, frames, 0.5) : NAN;
    double search_median = quantile(m->search_us, m->search_count, 0.5);
    double search_p99 = quantile(m->search_us, m->search_count, 0.99);
    double n = m->frames && controller ? (double)m->frames : NAN;
    motion_metrics_seen s;
    motion_metrics_summary(m, &s); /* out of memory: the posture's seconds are null */
    const motion_metrics_extra none = {NAN, NAN, NAN, NAN, NAN, NAN, NAN, NAN};
    if (!x) x = &none;
    fprintf(f, "{\n");
    json_number(f, "foot_slide_cm_s", motion_metrics_foot_slide(m), 0);
    json_number(f, "foot_slide_raw_cm_s", m->slide_frames > 0 ? m->raw_sum / m->slide_frames : NAN, 0);
    json_number(f, "traj_err_cm", m->traj_err / n, 0);
    json_number(f, "heading_err_deg", m->heading_err / n, 0);
    json_number(f, "response_s", response_mean(&m->response_root), 0);
    json_number(f, "response_sim_s", response_mean(&m->response_sim), 0);
    json_number(f, "max_pop_cm", m->max_pop, 0);
    json_number(f, "db_max_pop_cm", x->db_max_pop_cm, 0);
    json_number(f, "searches", x->searches, 0);
    json_number(f, "transitions_per_s", x->transitions_per_s, 0);
    json_number(f, "nan_frames", m->nan_frames, 0);
    json_number(f, "search_median_us", search_median, 0);
    json_number(f, "search_p99_us", search_p99, 0);
    json_number(f, "frame_median_us", frame_median, 0);
    json_number(f, "memory_mb", x->memory_mb, 0);
    json_number(f, "penetration_max_cm", m->scene ? 100.0 * m->penetration_max : NAN, 0);
    json_number(f, "below_ground_cm", s.below_ground_cm, 0);
    json_number(f, "contact_height_err_cm", s.contact_height_err_cm, 0);
    json_number(f, "contact_share", s.contact_share, 0);
    json_number(f, "foot_float_cm", s.foot_float_cm, 0);
    json_number(f, "foot_slide_height_cm_s", s.foot_slide_height_cm_s, 0);
    json_number(f, "pop_p99_cm", s.pop_p99_cm, 0);
    json_number(f, "db_pop_p99_cm", x->db_pop_p99_cm, 0);
    json_number(f, "db_foot_slide_height_cm_s", x->db_foot_slide_height_cm_s, 0);
    json_number(f, "head_p2_cm", s.head_p2_cm, 0);
    json_number(f, "head_p5_cm", s.head_p5_cm, 0);
    json_number(f, "head_p50_cm", s.head_p50_cm, 0);
    json_number(f, "db_head_p5_cm", x->db_head_p5_cm, 0);
    json_number(f, "db_head_p50_cm", x->db_head_p50_cm, 0);
    json_number(f, "crouched_s", s.crouched_s, 0);
    json_number(f, "bent_s", s.bent_s, 0);
    json_number(f, "lying_s", s.lying_s, 0);
    json_number(f, "calibration_s", s.calibration_s, 0);
    json_number(f, "arms_spread_s", s.arms_spread_s, 0);
    json_number(f, "hand_raised_s", s.hand_raised_s, 0);
    json_number(f, "knee_raised_s", s.knee_raised_s, 0);
    json_number(f, "arms_out_s", s.arms_out_s, 0);
    json_number(f, "hands_apart_max_cm", s.hands_apart_max_cm, 0);
    fprintf(f, "  \"where\": {");
    json_worst(f, m, "max_pop", &m->worst_pop, "cm", 0);
    json_worst(f, m, "below_ground", &m->worst_below, "cm", 0);
    json_worst(f, m, "foot_float", controller ? &m->worst_float : NULL, "cm", 0);
    double slide_seconds = NAN, slide_cm_s = NAN, slide_share = NAN;
    long slide_first =
        controller ? motion_metrics_worst_slide(m, &slide_seconds, &slide_cm_s, &slide_share) : -1;
    fprintf(f, "\n    \"foot_slide\": ");
    if (slide_first >= 0)
        fprintf(f, "{\"t_s\": %.6g, \"frame\": %ld, \"seconds\": %.6g, \"cm_s\": %.6g, \"share\": %.6g}",
                (double)slide_first / m->fps, slide_first, slide_seconds, slide_cm_s, slide_share);
    else
        fprintf(f, "null");
    fprintf(f, ",\n    \"posture\": ");
    if (s.posture_first >= 0)
        fprintf(f, "{\"t_s\": %.6g, \"frame\": %ld, \"seconds\": %.6g, \"posture\": \"%s\"}",
                (double)s.posture_first / m->fps, s.posture_first, (double)s.posture_frames / m->fps,
                mm_posture_name(s.posture_worst));
    else
        fprintf(f, "null");
    fprintf(f, "\n  },\n");
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

/* The contacts' roles, in the order of motion_metrics' contacts. */
static const mm_role contact_roles[4] = {MM_ROLE_LEFT_FOOT, MM_ROLE_LEFT_TOE, MM_ROLE_RIGHT_FOOT,
                                         MM_ROLE_RIGHT_TOE};

void motion_metrics_roles_of_database(const mm_database *db, int contact[4], mm_posture_joints *joints)
{
    for (int k = 0; k < 4; ++k) contact[k] = mm_database_role_joint(db, contact_roles[k]);
    joints->hips = mm_database_role_joint(db, MM_ROLE_HIPS);
    joints->head = mm_database_role_joint(db, MM_ROLE_HEAD);
    joints->left_hand = mm_database_role_joint(db, MM_ROLE_LEFT_HAND);
    joints->right_hand = mm_database_role_joint(db, MM_ROLE_RIGHT_HAND);
    const mm_skeleton view = {.joint_count = db->joint_count, .joints = (mm_joint *)db->joints};
    mm_posture_find_legs(&view, contact[0], contact[2], joints);
}

/* The joint of a role by its default name; a toe also as the default name with "Base" after it
 * (LeftToeBase: the CMU and Mixamo toes, the PFNN skeleton's), which wins. */
static int find_by_default_name(const mm_skeleton *s, mm_role role)
{
    const char *name = mm_role_default_name(role);
    if (role == MM_ROLE_LEFT_TOE || role == MM_ROLE_RIGHT_TOE) {
        char base[MM_NAME_MAX];
        snprintf(base, sizeof base, "%sBase", name);
        int j = mm_skeleton_find(s, base);
        if (j >= 0) return j;
    }
    return mm_skeleton_find(s, name);
}

void motion_metrics_roles_by_name(const mm_skeleton *s, int contact[4], mm_posture_joints *joints)
{
    for (int k = 0; k < 4; ++k) contact[k] = find_by_default_name(s, contact_roles[k]);
    joints->hips = find_by_default_name(s, MM_ROLE_HIPS);
    joints->head = find_by_default_name(s, MM_ROLE_HEAD);
    joints->left_hand = find_by_default_name(s, MM_ROLE_LEFT_HAND);
    joints->right_hand = find_by_default_name(s, MM_ROLE_RIGHT_HAND);
    mm_posture_find_legs(s, contact[0], contact[2], joints);
}

/* A tag that names a gait other than walk and run (crouch, jump), in any case. */
static int other_gait_tag(const char *name)
{
    for (int g = MM_GAIT_CROUCH; g <= MM_GAIT_JUMP; ++g) {
        const char *gait = mm_gait_name((mm_gait)g);
        size_t i = 0;
        while (gait[i] && tolower((unsigned char)name[i]) == gait[i]) ++i;
        if (!gait[i] && !name[i]) return 1;
    }
    return 0;
}

/* The database's clips played in order at fps: the largest second difference over joints of every
 * sample (from each clip's third sample on), in pops[] (m), and the height-weighted slide of the
 * contact joints on their planted heights (each clip from its second sample on); returns the
 * pops' count, -1 when out of memory. */
static long database_playback(const mm_database *db, const mm_skeleton *s, double fps, const int contact[4],
                              const double planted[4], float **pops, motion_metrics_slide *slide)
{
    int n = db->joint_count;
    long total = 0;
    for (int c = 0; c < db->clip_count; ++c) {
        double duration = (db->clips[c].frame_count - 1) * (double)db->interval;
        total += (long)floor(duration * fps) + 1;
    }
    mm_xform *g = malloc(sizeof(mm_xform) * (size_t)n);
    mm_vec3 *w[3];
    for (int k = 0; k < 3; ++k) w[k] = malloc(sizeof(mm_vec3) * (size_t)n);
    mm_quat *rot = malloc(sizeof(mm_quat) * (size_t)n);
    mm_vec3 *pos = malloc(sizeof(mm_vec3) * (size_t)n);
    *pops = malloc(sizeof(float) * (size_t)(total > 0 ? total : 1));
    long count = 0;
    if (!g || !w[0] || !w[1] || !w[2] || !rot || !pos || !*pops) {
        free(*pops);
        *pops = NULL;
        count = -1;
    } else {
        for (int c = 0; c < db->clip_count; ++c) {
            const mm_db_clip *clip = &db->clips[c];
            double duration = (clip->frame_count - 1) * (double)db->interval;
            int samples = (int)floor(duration * fps) + 1;
            for (int i = 0; i < samples; ++i) {
                double x = i / fps / db->interval;
                int f0 = (int)floor(x), f1 = f0 + 1 < clip->frame_count ? f0 + 1 : f0;
                float a = (float)(x - f0);
                mm_quat r0[MM_MAX_JOINTS], r1[MM_MAX_JOINTS];
                mm_vec3 p0[MM_MAX_JOINTS], p1[MM_MAX_JOINTS];
                mm_database_local_pose(db, clip->first_frame + f0, r0, p0);
                mm_database_local_pose(db, clip->first_frame + f1, r1, p1);
                for (int j = 0; j < n; ++j) {
                    rot[j] = mm_quat_slerp(r0[j], r1[j], a);
                    pos[j] = mm_vec3_lerp(p0[j], p1[j], a);
                }
                mm_fk(s, rot, pos, g);
                for (int j = 0; j < n; ++j) w[i % 3][j] = g[j].translation;
                for (int k = 0; k < 4; ++k) {
                    int j = contact[k];
                    if (i == 0) slide->near[k] = 0;
                    if (i == 0 || j < 0 || !isfinite(planted[k])) continue;
                    mm_vec3 now = w[i % 3][j], before = w[(i + 2) % 3][j];
                    motion_metrics_slide_add(slide, k, now.y - planted[k], (double)now.x - before.x,
                                             (double)now.z - before.z, fps);
                }
                if (i >= 2)
                    (*pops)[count++] =
                        (float)motion_metrics_frame_pop(w[i % 3], w[(i + 2) % 3], w[(i + 1) % 3], n, NULL);
            }
        }
    }
    free(g);
    for (int k = 0; k < 3; ++k) free(w[k]);
    free(rot);
    free(pos);
    return count;
}

int motion_metrics_database(const mm_database *db, double fps, motion_metrics_db *out)
{
    out->max_pop_cm = out->pop_p99_cm = out->head_p5_cm = out->head_p50_cm = out->foot_slide_height_cm_s =
        NAN;
    out->reference = 0.0f;
    for (int k = 0; k < 4; ++k) out->planted[k] = NAN;
    int n = db->joint_count, contact[4];
    mm_posture_joints pj;
    motion_metrics_roles_of_database(db, contact, &pj);
    mm_skeleton s;
    if (mm_skeleton_init(&s, n, NULL) != MM_OK) return -1;
    memcpy(s.joints, db->joints, sizeof(mm_joint) * (size_t)n);
    /* the frames: heights above the ground (joint 0, the simulation root, is on it at y = 0) */
    size_t frames = (size_t)(db->frame_count > 0 ? db->frame_count : 1);
    mm_xform *g = malloc(sizeof(mm_xform) * (size_t)n);
    mm_quat local_rotations[MM_MAX_JOINTS];
    mm_vec3 local_positions[MM_MAX_JOINTS];
    float *all = malloc(sizeof(float) * frames), *upright = malloc(sizeof(float) * frames);
    float *planted[4];
    for (int k = 0; k < 4; ++k) planted[k] = malloc(sizeof(float) * frames);
    int ok = g && all && upright && planted[0] && planted[1] && planted[2] && planted[3];
    float *pops = NULL;
    if (ok) {
        uint64_t other = 0; /* tags of the gaits that are not upright locomotion */
        for (int t = 0; t < db->tag_count && t < MM_MAX_TAGS; ++t)
            if (other_gait_tag(db->tag_names[t])) other |= 1ull << t;
        long all_count = 0, upright_count = 0, planted_count[4] = {0};
        for (int f = 0; f < db->frame_count; ++f) {
            mm_database_local_pose(db, f, local_rotations, local_positions);
            mm_fk(&s, local_rotations, local_positions, g);
            int type = db->clips[db->frame_clip[f]].type;
            if (pj.head >= 0) {
                float h = g[pj.head].translation.y;
                if (type == MM_CLIP_LOCOMOTION || type == MM_CLIP_IDLE) all[all_count++] = h;
                if (type == MM_CLIP_LOCOMOTION && !(db->frame_tags[f] & other)) upright[upright_count++] = h;
            }
            for (int k = 0; k < 4; ++k)
                if (contact[k] >= 0 && (db->contacts[f] & (1u << k)))
                    planted[k][planted_count[k]++] = g[contact[k]].translation.y;
        }
        for (int k = 0; k < 4; ++k)
            out->planted[k] = motion_metrics_percentile(planted[k], planted_count[k], 0.5);
        motion_metrics_slide slide = {0};
        long pop_count = database_playback(db, &s, fps, contact, out->planted, &pops, &slide);
        ok = pop_count >= 0;
        out->foot_slide_height_cm_s = motion_metrics_slide_value(&slide);
        if (ok) {
            out->max_pop_cm = 0.0;
            for (long i = 0; i < pop_count; ++i) out->max_pop_cm = fmax(out->max_pop_cm, 100.0 * pops[i]);
            out->pop_p99_cm = 100.0 * motion_metrics_percentile(pops, pop_count, 0.99);
        }
        out->head_p5_cm = 100.0 * motion_metrics_percentile(upright, upright_count, 0.05);
        out->head_p50_cm = 100.0 * motion_metrics_percentile(upright, upright_count, 0.5);
        out->reference = all_count > 0 ? fmaxf(mm_posture_reference_height(all, (int)all_count), 0.0f) : 0.0f;
    }
    free(pops);
    free(g);
    free(all);
    free(upright);
    for (int k = 0; k < 4; ++k) free(planted[k]);
    mm_skeleton_free(&s);
    return ok ? 0 : -1;
}
