/* Pose vectors of database frames and the two measures (docs/similarity.md). */
#include <math.h>
#include <string.h>

#include <mm/clip.h>

#include "search/pool.h"
#include "similarity/sim_internal.h"

static const float default_dim_weights[MM_SIM_DIMS] = {1.0f, 1.0f, 1.0f, 0.2f, 0.2f, 0.2f,
                                                       0.2f, 0.2f, 0.2f, 0.1f, 0.1f, 0.1f};

const char *mm_sim_measure_name(mm_sim_measure m)
{
    switch (m) {
    case MM_SIM_COSINE:
        return "cos";
    case MM_SIM_EUCLIDEAN:
        return "euclid";
    }
    return NULL;
}

/* Global transforms of frame f (scratch: joint_count transforms). */
static void frame_fk(const mm_database *db, int f, mm_xform *out)
{
    mm_skeleton s;
    memset(&s, 0, sizeof s);
    s.joint_count = db->joint_count;
    s.joints = (mm_joint *)(uintptr_t)db->joints; /* mm_fk only reads it */
    mm_quat rot[MM_MAX_JOINTS];
    mm_vec3 pos[MM_MAX_JOINTS];
    mm_database_local_pose(db, f, rot, pos);
    mm_fk(&s, rot, pos, out);
}

static mm_result check_desc(const mm_database *db, const mm_sim_desc *d, mm_error *err)
{
#define BAD_FIELD(...) mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, __VA_ARGS__)
    if (!db || !db->frame_count || !db->joints) return BAD_FIELD("similarity: no database");
    if (d->measure != MM_SIM_COSINE && d->measure != MM_SIM_EUCLIDEAN)
        return BAD_FIELD("mm_sim_desc.measure: %d is not a measure (0 cosine, 1 euclidean)", (int)d->measure);
    if (d->channels & ~7u) return BAD_FIELD("mm_sim_desc.channels: unknown bits 0x%x", d->channels & ~7u);
    if (d->window < 0 || d->window > MM_SIM_MAX_WINDOW)
        return BAD_FIELD("mm_sim_desc.window: %d is outside 1..%d frames", d->window, MM_SIM_MAX_WINDOW);
    if (d->threads < 0 || d->threads > MM_SIM_MAX_THREADS)
        return BAD_FIELD("mm_sim_desc.threads: %d is outside 1..%d", d->threads, MM_SIM_MAX_THREADS);
    if (d->dim_weights)
        for (int i = 0; i < MM_SIM_DIMS; ++i)
            if (!(d->dim_weights[i] >= 0.0f) || !isfinite(d->dim_weights[i]))
                return BAD_FIELD("mm_sim_desc.dim_weights[%d]: must be finite and >= 0", i);
    if (d->joint_weights)
        for (int j = 0; j < db->joint_count; ++j)
            if (!(d->joint_weights[j] >= 0.0f) || !isfinite(d->joint_weights[j]))
                return BAD_FIELD("mm_sim_desc.joint_weights[%d] (%s): must be finite and >= 0", j,
                                 db->joints[j].name);
    return MM_OK;
#undef BAD_FIELD
}

void mm_sim_poses_free(mm_sim_poses *p)
{
    if (!p) return;
    mm_allocator a = p->allocator;
    mm_free(&a, p->joints);
    mm_free(&a, p->joint_weights);
    mm_free(&a, p->values);
    mm_free(&a, p->zero);
    mm_free(&a, p->any_zero);
    memset(p, 0, sizeof *p);
}

/* Fills the vectors of the frames of one clip. g, h: joint_count transforms of scratch. */
static void clip_vectors(mm_sim_poses *p, const mm_db_clip *c, mm_xform *g, mm_xform *h)
{
    const mm_database *db = p->db;
    const float *dw = p->dim_weights;
    for (int k = 0; k < c->frame_count; ++k) {
        int f = c->first_frame + k;
        frame_fk(db, f, g);
        /* velocity: backward difference, forward on the first frame (as the database's features) */
        int other = -1;
        float sign = 1.0f;
        if (p->channels & MM_SIM_VELOCITY) {
            if (k > 0) {
                other = f - 1;
            } else if (c->frame_count > 1) {
                other = f + 1;
                sign = -1.0f;
            }
            if (other >= 0) frame_fk(db, other, h);
        }
        mm_quat root = g[0].rotation;
        mm_vec3 origin = g[0].translation;
        float *out = p->values + (size_t)f * (size_t)p->stride;
        for (int a = 0; a < p->joint_count; ++a) {
            int j = p->joints[a];
            float v[MM_SIM_DIMS];
            int n = 0;
            if (p->channels & MM_SIM_POSITION) {
                mm_vec3 q = mm_quat_inv_rotate(root, mm_vec3_sub(g[j].translation, origin));
                v[n++] = q.x * dw[0];
                v[n++] = q.y * dw[1];
                v[n++] = q.z * dw[2];
            }
            if (p->channels & MM_SIM_ROTATION) {
                mm_quat r = mm_quat_mul(mm_quat_conj(root), g[j].rotation);
                mm_vec3 x = mm_quat_rotate(r, mm_vec3_make(1, 0, 0)),
                        y = mm_quat_rotate(r, mm_vec3_make(0, 1, 0));
                v[n++] = x.x * dw[3];
                v[n++] = x.y * dw[4];
                v[n++] = x.z * dw[5];
                v[n++] = y.x * dw[6];
                v[n++] = y.y * dw[7];
                v[n++] = y.z * dw[8];
            }
            if (p->channels & MM_SIM_VELOCITY) {
                mm_vec3 vel = mm_vec3_make(0, 0, 0);
                if (other >= 0)
                    vel = mm_quat_inv_rotate(
                        root,
                        mm_vec3_scale(mm_vec3_sub(g[j].translation, h[j].translation), sign / db->interval));
                v[n++] = vel.x * dw[9];
                v[n++] = vel.y * dw[10];
                v[n++] = vel.z * dw[11];
            }
            float *o = out + a; /* dimension d at o[d * joints_padded] */
            size_t jp = (size_t)p->joints_padded;
            if (p->measure == MM_SIM_COSINE) {
                double sq = 0.0;
                for (int d = 0; d < n; ++d) sq += (double)v[d] * (double)v[d];
                if (sq < 1e-18) { /* a zero vector (the root, a joint at the root): skipped */
                    p->zero[(size_t)f * (size_t)p->joint_count + (size_t)a] = 1;
                    p->any_zero[f] = 1;
                    for (int d = 0; d < n; ++d) o[d * jp] = 0.0f;
                } else {
                    double s = sqrt((double)p->joint_weights[a]) / sqrt(sq);
                    for (int d = 0; d < n; ++d) o[d * jp] = (float)(v[d] * s);
                }
            } else {
                for (int d = 0; d < n; ++d) o[d * jp] = v[d];
            }
        }
    }
}

mm_result mm_sim_poses_init(mm_sim_poses *p, const mm_database *db, const mm_sim_desc *desc, mm_error *err)
{
    mm_sim_desc d;
    memset(&d, 0, sizeof d);
    if (desc) d = *desc;
    memset(p, 0, sizeof *p);
    mm_result r = check_desc(db, &d, err);
    if (r != MM_OK) return r;
    if (d.allocator) p->allocator = *d.allocator;
    const mm_allocator *al = d.allocator;
    p->db = db;
    p->measure = d.measure;
    p->channels = d.channels ? d.channels : MM_SIM_POSITION;
    p->window = d.window ? d.window : 1;
    memcpy(p->dim_weights, d.dim_weights ? d.dim_weights : default_dim_weights, sizeof p->dim_weights);
    p->dims = ((p->channels & MM_SIM_POSITION) ? 3 : 0) + ((p->channels & MM_SIM_ROTATION) ? 6 : 0) +
              ((p->channels & MM_SIM_VELOCITY) ? 3 : 0);
    int jc = db->joint_count;
    p->joints = (int32_t *)mm_alloc_array(al, (size_t)jc, sizeof(int32_t));
    p->joint_weights =
        (float *)mm_alloc_array(al, (size_t)jc + MM__SIM_LANES, sizeof(float)); /* zero padded */
    if (!p->joints || !p->joint_weights) goto oom;
    for (int j = 0; j < jc; ++j) {
        float w = d.joint_weights ? d.joint_weights[j] : (j == 0 ? 0.0f : 1.0f);
        if (w > 0.0f) {
            p->joints[p->joint_count] = j;
            p->joint_weights[p->joint_count++] = w;
            p->weight_sum += w;
        }
    }
    if (p->joint_count == 0) {
        mm_sim_poses_free(p);
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0,
                            "mm_sim_desc.joint_weights: every weight is 0");
    }
    p->joints_padded = (p->joint_count + MM__SIM_LANES - 1) / MM__SIM_LANES * MM__SIM_LANES;
    p->stride = p->joints_padded * p->dims;
    size_t frames = (size_t)db->frame_count;
    p->values = (float *)mm_alloc_array(al, frames * (size_t)p->stride, sizeof(float));
    if (!p->values) goto oom;
    p->memory = (size_t)jc * 8 + frames * (size_t)p->stride * sizeof(float);
    if (p->measure == MM_SIM_COSINE) {
        p->zero = (uint8_t *)mm_alloc_array(al, frames, (size_t)p->joint_count);
        p->any_zero = (uint8_t *)mm_alloc_array(al, frames, 1);
        if (!p->zero || !p->any_zero) goto oom;
        p->memory += frames * (size_t)(p->joint_count + 1);
    }
    mm_xform *scratch = (mm_xform *)mm_alloc_array(al, 2 * (size_t)jc, sizeof(mm_xform));
    if (!scratch) goto oom;
    for (int c = 0; c < db->clip_count; ++c) clip_vectors(p, &db->clips[c], scratch, scratch + jc);
    mm_free(al, scratch);
    return MM_OK;
oom:
    mm_sim_poses_free(p);
    return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "similarity: out of memory for %d frames",
                        db->frame_count);
}

/* The kernels sum in MM__SIM_LANES independent lanes folded in a fixed order: they vectorise, and
 * the result is the same on every machine and thread. */
static inline float pose_kernel(const mm_sim_poses *p, int a, int b)
{
    const float *x = p->values + (size_t)a * (size_t)p->stride,
                *y = p->values + (size_t)b * (size_t)p->stride;
    float acc[MM__SIM_LANES] = {0};
    if (p->measure == MM_SIM_COSINE) {
        for (int i = 0; i < p->stride; i += MM__SIM_LANES)
            for (int l = 0; l < MM__SIM_LANES; ++l) acc[l] += x[i + l] * y[i + l];
        float num = ((acc[0] + acc[1]) + (acc[2] + acc[3])) + ((acc[4] + acc[5]) + (acc[6] + acc[7]));
        float den = p->weight_sum;
        if (p->any_zero[a] || p->any_zero[b]) {
            const uint8_t *za = p->zero + (size_t)a * (size_t)p->joint_count,
                          *zb = p->zero + (size_t)b * (size_t)p->joint_count;
            den = 0.0f;
            for (int j = 0; j < p->joint_count; ++j)
                if (!za[j] && !zb[j]) den += p->joint_weights[j];
        }
        return den > 0.0f ? num / den : 0.0f;
    }
    int jp = p->joints_padded;
    for (int j0 = 0; j0 < jp; j0 += MM__SIM_LANES) {
        float d2[MM__SIM_LANES] = {0};
        for (int d = 0; d < p->dims; ++d) {
            const float *u = x + d * jp + j0, *v = y + d * jp + j0;
            for (int l = 0; l < MM__SIM_LANES; ++l) {
                float t = u[l] - v[l];
                d2[l] += t * t;
            }
        }
        for (int l = 0; l < MM__SIM_LANES; ++l) acc[l] += p->joint_weights[j0 + l] * sqrtf(d2[l]);
    }
    float sum = ((acc[0] + acc[1]) + (acc[2] + acc[3])) + ((acc[4] + acc[5]) + (acc[6] + acc[7]));
    return sum / p->weight_sum;
}

float mm_sim_pose(const mm_sim_poses *p, int a, int b) { return pose_kernel(p, a, b); }

float mm_sim_window(const mm_sim_poses *p, int a, int b, int n)
{
    if (n < 1) n = 1;
    const mm_database *db = p->db;
    const mm_db_clip *ca = &db->clips[db->frame_clip[a]], *cb = &db->clips[db->frame_clip[b]];
    int ra = a - ca->first_frame, rb = b - cb->first_frame;
    double sum = 0.0;
    for (int k = 0; k < n; ++k)
        sum += (double)mm_sim_pose(p, ca->first_frame + mm__sim_step(ca, ra, k),
                                   cb->first_frame + mm__sim_step(cb, rb, k));
    return (float)(sum / (double)n);
}

void mm__sim_strip(const mm_sim_poses *p, const mm_db_clip *a, const mm_db_clip *b, int i0, int rows,
                   float *out)
{
    int w = b->frame_count;
    for (int t = 0; t < rows; ++t) {
        int fa = a->first_frame + mm__sim_step(a, i0, t);
        float *o = out + (size_t)t * (size_t)w;
        if (t > 0 && fa == a->first_frame + mm__sim_step(a, i0, t - 1)) { /* a held last frame */
            memcpy(o, o - w, (size_t)w * sizeof(float));
            continue;
        }
        for (int j = 0; j < w; ++j) o[j] = pose_kernel(p, fa, b->first_frame + j);
    }
}

/* mm_sim_matrix: strips of rows spread over threads. */
#define MATRIX_STRIP 32

typedef struct matrix_job {
    const mm_sim_poses *p;
    const mm_db_clip *a, *b;
    int n, strips;
    float *out;
    float *scratch; /* per worker: (MATRIX_STRIP + n - 1) x frames(b) */
    size_t scratch_floats;
} matrix_job;

static void matrix_worker(void *ctx, int worker, int workers)
{
    matrix_job *job = (matrix_job *)ctx;
    float *s = job->scratch + (size_t)worker * job->scratch_floats;
    int wb = job->b->frame_count;
    for (int u = worker; u < job->strips; u += workers) {
        int i0 = u * MATRIX_STRIP, rows = job->a->frame_count - i0;
        if (rows > MATRIX_STRIP) rows = MATRIX_STRIP;
        mm__sim_strip(job->p, job->a, job->b, i0, rows + job->n - 1, s);
        for (int t = 0; t < rows; ++t)
            for (int j = 0; j < wb; ++j)
                job->out[(size_t)(i0 + t) * (size_t)wb + (size_t)j] =
                    mm__sim_window_cell(s, job->b, t, j, job->n);
    }
}

mm_result mm_sim_matrix(const mm_sim_poses *p, int clip_a, int clip_b, int threads, float *out, mm_error *err)
{
    const mm_database *db = p->db;
    if (clip_a < 0 || clip_a >= db->clip_count || clip_b < 0 || clip_b >= db->clip_count)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "mm_sim_matrix: no clip %d",
                            clip_a < 0 || clip_a >= db->clip_count ? clip_a : clip_b);
    matrix_job job;
    memset(&job, 0, sizeof job);
    job.p = p;
    job.a = &db->clips[clip_a];
    job.b = &db->clips[clip_b];
    job.n = p->window;
    job.out = out;
    job.strips = (job.a->frame_count + MATRIX_STRIP - 1) / MATRIX_STRIP;
    if (threads > MM_SIM_MAX_THREADS) threads = MM_SIM_MAX_THREADS;
    mm_searcher_pool *pool = threads > 1 && job.strips > 1 ? mm__pool_create(threads, &p->allocator) : NULL;
    int workers = mm__pool_size(pool);
    job.scratch_floats = (size_t)(MATRIX_STRIP + job.n - 1) * (size_t)job.b->frame_count;
    job.scratch = (float *)mm_alloc_array(&p->allocator, job.scratch_floats * (size_t)workers, sizeof(float));
    if (!job.scratch) {
        mm__pool_destroy(pool);
        return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "mm_sim_matrix: out of memory");
    }
    mm__pool_run(pool, matrix_worker, &job);
    mm__pool_destroy(pool);
    mm_free(&p->allocator, job.scratch);
    return MM_OK;
}
