/* Building the fusion and link tables (offline, threaded; docs/similarity.md).
 *
 * Work is cut into units of STRIP rows of one clip; a unit computes the pose similarities it needs
 * into its worker's scratch and writes only its own rows, so the tables are the same whatever the
 * number of threads and whichever thread takes which unit. */
#include <stdatomic.h>
#include <string.h>

#include "search/pool.h"
#include "similarity/sim_file.h"
#include "similarity/sim_internal.h"

#define STRIP 32

typedef struct unit {
    int link; /* 0: fusion rows of a one-shot clip; 1: link rows of a loop clip */
    int clip; /* database clip */
    int i0, rows;
} unit;

typedef struct build_job {
    const mm_sim_poses *p;
    const mm_database *db;
    int n, loop_count, shot_count;
    const int32_t *loop_clips, *shot_clips;
    const mm_sim_clip *clips;
    const unit *units;
    int unit_count;
    atomic_int next;
    float *scratch;
    size_t scratch_floats;
    mm_sim_match *fusion;
    float *link;
} build_job;

static void fusion_unit(build_job *job, const unit *u, float *s)
{
    const mm_database *db = job->db;
    const mm_db_clip *a = &db->clips[u->clip];
    int row0 = job->clips[u->clip].row + u->i0;
    for (int l = 0; l < job->loop_count; ++l) {
        const mm_db_clip *b = &db->clips[job->loop_clips[l]];
        mm__sim_strip(job->p, a, b, u->i0, u->rows + job->n - 1, s);
        for (int t = 0; t < u->rows; ++t) {
            mm_sim_match best = {-1, 0.0f};
            for (int j = 0; j < b->frame_count; ++j) {
                float w = mm__sim_window_cell(s, b, t, j, job->n);
                if (best.frame < 0 || mm_sim_better(job->p->measure, w, best.score)) {
                    best.frame = b->first_frame + j;
                    best.score = w;
                }
            }
            job->fusion[(size_t)(row0 + t) * (size_t)job->loop_count + (size_t)l] = best;
        }
    }
}

static void link_unit(build_job *job, const unit *u, float *s)
{
    const mm_database *db = job->db;
    const mm_db_clip *a = &db->clips[u->clip];
    int n = job->n, shots = job->shot_count, width = shots * n;
    /* s[t][c * n + k] = S(frame i0 + t of the loop, frame k of one-shot c, held at its end) */
    for (int t = 0; t < u->rows + n - 1; ++t) {
        int fa = a->first_frame + mm__sim_step(a, u->i0, t);
        for (int c = 0; c < shots; ++c) {
            const mm_db_clip *b = &db->clips[job->shot_clips[c]];
            for (int k = 0; k < n; ++k)
                s[(size_t)t * (size_t)width + (size_t)(c * n + k)] =
                    mm_sim_pose(job->p, fa, b->first_frame + mm__sim_step(b, 0, k));
        }
    }
    int row0 = job->clips[u->clip].row + u->i0;
    for (int t = 0; t < u->rows; ++t)
        for (int c = 0; c < shots; ++c) {
            double sum = 0.0;
            for (int k = 0; k < n; ++k)
                sum += (double)s[(size_t)(t + k) * (size_t)width + (size_t)(c * n + k)];
            job->link[(size_t)(row0 + t) * (size_t)shots + (size_t)c] = (float)(sum / (double)n);
        }
}

static void build_worker(void *ctx, int worker, int workers)
{
    (void)workers;
    build_job *job = (build_job *)ctx;
    float *s = job->scratch + (size_t)worker * job->scratch_floats;
    for (;;) {
        int i = atomic_fetch_add(&job->next, 1);
        if (i >= job->unit_count) break;
        const unit *u = &job->units[i];
        if (u->link)
            link_unit(job, u, s);
        else
            fusion_unit(job, u, s);
    }
}

mm_result mm_sim_tables_build(const mm_database *db, const mm_sim_desc *desc, mm_sim_tables *out,
                              mm_error *err)
{
    memset(out, 0, sizeof *out);
    mm_sim_desc d;
    memset(&d, 0, sizeof d);
    if (desc) d = *desc;
    mm_sim_poses p;
    mm_result r = mm_sim_poses_init(&p, db, &d, err);
    if (r != MM_OK) return r;
    const mm_allocator *al = d.allocator;
    int cc = db->clip_count, fc = db->frame_count, jc = db->joint_count;
    mm_sim_clip *clips = (mm_sim_clip *)mm_alloc_array(al, (size_t)cc, sizeof *clips);
    int32_t *frame_clip = (int32_t *)mm_alloc_array(al, (size_t)fc, 4);
    int32_t *lists = (int32_t *)mm_alloc_array(al, (size_t)cc, 4); /* loop clips, then one-shot clips */
    float *joint_weights = (float *)mm_alloc_array(al, (size_t)jc, 4);
    unit *units = (unit *)mm_alloc_array(al, (size_t)fc / STRIP + (size_t)cc + 1, sizeof(unit));
    mm_sim_match *fusion = NULL;
    float *link = NULL, *scratch = NULL;
    mm_searcher_pool *pool = NULL;
    if (!clips || !frame_clip || !lists || !joint_weights || !units) goto oom;
    for (int a = 0; a < p.joint_count; ++a) joint_weights[p.joints[a]] = p.joint_weights[a];

    int loops = 0, shots = 0, li = 0, rows[2] = {0, 0}, max_loop = 0;
    for (int c = 0; c < cc; ++c) loops += db->clips[c].loop != 0;
    int32_t *loop_clips = lists, *shot_clips = lists + loops;
    for (int c = 0; c < cc; ++c) {
        const mm_db_clip *k = &db->clips[c];
        int lp = k->loop != 0;
        clips[c].first_frame = k->first_frame;
        clips[c].frame_count = k->frame_count;
        clips[c].loop = lp;
        if (lp) {
            clips[c].index = li;
            loop_clips[li++] = c;
            if (k->frame_count > max_loop) max_loop = k->frame_count;
        } else {
            clips[c].index = shots;
            shot_clips[shots++] = c;
        }
        clips[c].row = rows[lp];
        rows[lp] += k->frame_count;
        for (int f = k->first_frame; f < k->first_frame + k->frame_count; ++f) frame_clip[f] = c;
    }
    int n = p.window;
    if (rows[0] > 0 && loops > 0)
        if (!(fusion = (mm_sim_match *)mm_alloc_array(al, (size_t)rows[0] * (size_t)loops, sizeof *fusion)))
            goto oom;
    if (rows[1] > 0 && shots > 0)
        if (!(link = (float *)mm_alloc_array(al, (size_t)rows[1] * (size_t)shots, sizeof *link))) goto oom;

    /* Units: one-shot clips' rows when there are loop clips to fuse into, loop clips' rows when
     * there are one-shots to link to. */
    int unit_count = 0;
    for (int c = 0; c < cc; ++c) {
        int lp = db->clips[c].loop != 0;
        if (lp ? shots == 0 : loops == 0) continue;
        for (int i0 = 0; i0 < db->clips[c].frame_count; i0 += STRIP) {
            unit *u = &units[unit_count++];
            u->link = lp;
            u->clip = c;
            u->i0 = i0;
            u->rows = db->clips[c].frame_count - i0 < STRIP ? db->clips[c].frame_count - i0 : STRIP;
        }
    }
    build_job job;
    memset(&job, 0, sizeof job);
    job.p = &p;
    job.db = db;
    job.n = n;
    job.loop_count = loops;
    job.shot_count = shots;
    job.loop_clips = loop_clips;
    job.shot_clips = shot_clips;
    job.clips = clips;
    job.units = units;
    job.unit_count = unit_count;
    atomic_init(&job.next, 0);
    job.fusion = fusion;
    job.link = link;
    size_t need_fusion = (size_t)(STRIP + n - 1) * (size_t)max_loop;
    size_t need_link = (size_t)(STRIP + n - 1) * (size_t)shots * (size_t)n;
    job.scratch_floats = need_fusion > need_link ? need_fusion : need_link;
    int threads = d.threads > 1 ? d.threads : 1;
    if (threads > 1 && unit_count > 1)
        pool = mm__pool_create(threads < unit_count ? threads : unit_count, al);
    int workers = mm__pool_size(pool);
    if (unit_count > 0) {
        scratch = (float *)mm_alloc_array(al, job.scratch_floats * (size_t)workers, sizeof(float));
        if (!scratch) goto oom;
        job.scratch = scratch;
        mm__pool_run(pool, build_worker, &job);
    }

    mm__sim_parts parts;
    memset(&parts, 0, sizeof parts);
    parts.measure = p.measure;
    parts.channels = p.channels;
    parts.window = n;
    parts.joint_count = jc;
    parts.frame_count = fc;
    parts.clip_count = cc;
    parts.loop_count = loops;
    parts.shot_count = shots;
    parts.fusion_rows = rows[0];
    parts.link_rows = rows[1];
    parts.db_checksum = mm__sim_db_checksum(db);
    parts.db_size = db->size;
    memcpy(parts.dim_weights, p.dim_weights, sizeof parts.dim_weights);
    parts.data[MM__SIM_SEC_JOINT_WEIGHTS] = joint_weights;
    parts.data[MM__SIM_SEC_CLIPS] = clips;
    parts.data[MM__SIM_SEC_FRAME_CLIP] = frame_clip;
    parts.data[MM__SIM_SEC_LOOP_CLIPS] = loop_clips;
    parts.data[MM__SIM_SEC_SHOT_CLIPS] = shot_clips;
    parts.data[MM__SIM_SEC_FUSION] = fusion;
    parts.data[MM__SIM_SEC_LINK] = link;
    r = mm__sim_pack(&parts, al, out, err);
    goto done;
oom:
    r = mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "similarity tables: out of memory");
done:
    mm__pool_destroy(pool);
    mm_free(al, scratch);
    mm_free(al, fusion);
    mm_free(al, link);
    mm_free(al, units);
    mm_free(al, joint_weights);
    mm_free(al, lists);
    mm_free(al, frame_clip);
    mm_free(al, clips);
    mm_sim_poses_free(&p);
    return r;
}
