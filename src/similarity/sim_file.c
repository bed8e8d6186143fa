/* The tables file (docs/similarity.md): one header, then aligned arrays; loading validates every
 * count and index and points into the buffer. Also the run-time lookups. */
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "io/file.h"
#include "io/checksum.h"
#include "io/sections.h"
#include "similarity/sim_file.h"

static const char sim_magic[8] = {'M', 'M', 'S', 'I', 'M', 0, '\n', 0x1a};
#define SIM_BYTE_ORDER 0x01020304u
#define SIM_ALIGN      64

typedef struct sim_header {
    char magic[8];
    uint32_t byte_order;
    uint32_t version;
    uint64_t checksum; /* of bytes [24, file_size) */
    uint64_t file_size;
    uint32_t header_size;
    int32_t measure;
    uint32_t channels;
    int32_t window;
    int32_t joint_count, frame_count, clip_count, loop_count, shot_count, fusion_rows, link_rows;
    uint32_t section_count;
    uint64_t db_checksum, db_size;
    float dim_weights[MM_SIM_DIMS];
    mm__section sections[MM__SIM_SEC_COUNT];
} sim_header;

_Static_assert(offsetof(sim_header, checksum) == 16, "header layout");
_Static_assert(offsetof(sim_header, db_checksum) == 80, "header layout");
_Static_assert(offsetof(sim_header, sections) == 144, "header layout");
_Static_assert(sizeof(sim_header) == 256, "header layout");
_Static_assert(sizeof(mm_sim_clip) == 20 && sizeof(mm_sim_match) == 8, "record layout");

uint64_t mm__sim_db_checksum(const mm_database *db)
{
    uint64_t c = 0;
    if (db && db->data && db->size >= 24) memcpy(&c, (const unsigned char *)db->data + 16, 8); /* format.md */
    return c;
}

void mm__sim_section_sizes(const mm__sim_parts *p, size_t size[MM__SIM_SEC_COUNT])
{
    size[MM__SIM_SEC_JOINT_WEIGHTS] = (size_t)p->joint_count * 4;
    size[MM__SIM_SEC_CLIPS] = (size_t)p->clip_count * sizeof(mm_sim_clip);
    size[MM__SIM_SEC_FRAME_CLIP] = (size_t)p->frame_count * 4;
    size[MM__SIM_SEC_LOOP_CLIPS] = (size_t)p->loop_count * 4;
    size[MM__SIM_SEC_SHOT_CLIPS] = (size_t)p->shot_count * 4;
    size[MM__SIM_SEC_FUSION] = (size_t)p->fusion_rows * (size_t)p->loop_count * sizeof(mm_sim_match);
    size[MM__SIM_SEC_LINK] = (size_t)p->link_rows * (size_t)p->shot_count * 4;
}

static void point_into(mm_sim_tables *t, const unsigned char *base, const sim_header *h)
{
#define AT(sec) ((const void *)(base + h->sections[sec].offset))
    t->measure = (mm_sim_measure)h->measure;
    t->channels = h->channels;
    t->window = h->window;
    t->joint_count = h->joint_count;
    t->frame_count = h->frame_count;
    t->clip_count = h->clip_count;
    t->loop_count = h->loop_count;
    t->shot_count = h->shot_count;
    t->fusion_rows = h->fusion_rows;
    t->link_rows = h->link_rows;
    t->db_checksum = h->db_checksum;
    t->db_size = h->db_size;
    memcpy(t->dim_weights, h->dim_weights, sizeof t->dim_weights);
    t->joint_weights = (const float *)AT(MM__SIM_SEC_JOINT_WEIGHTS);
    t->clips = (const mm_sim_clip *)AT(MM__SIM_SEC_CLIPS);
    t->frame_clip = (const int32_t *)AT(MM__SIM_SEC_FRAME_CLIP);
    t->loop_clips = (const int32_t *)AT(MM__SIM_SEC_LOOP_CLIPS);
    t->shot_clips = (const int32_t *)AT(MM__SIM_SEC_SHOT_CLIPS);
    t->fusion = (const mm_sim_match *)AT(MM__SIM_SEC_FUSION);
    t->link = (const float *)AT(MM__SIM_SEC_LINK);
#undef AT
}

mm_result mm__sim_pack(const mm__sim_parts *parts, const mm_allocator *allocator, mm_sim_tables *out,
                       mm_error *err)
{
    size_t size[MM__SIM_SEC_COUNT];
    mm__sim_section_sizes(parts, size);
    sim_header h;
    memset(&h, 0, sizeof h);
    memcpy(h.magic, sim_magic, 8);
    h.byte_order = SIM_BYTE_ORDER;
    h.version = MM_SIM_VERSION;
    h.header_size = (uint32_t)sizeof h;
    h.measure = (int32_t)parts->measure;
    h.channels = parts->channels;
    h.window = parts->window;
    h.joint_count = parts->joint_count;
    h.frame_count = parts->frame_count;
    h.clip_count = parts->clip_count;
    h.loop_count = parts->loop_count;
    h.shot_count = parts->shot_count;
    h.fusion_rows = parts->fusion_rows;
    h.link_rows = parts->link_rows;
    h.section_count = MM__SIM_SEC_COUNT;
    h.db_checksum = parts->db_checksum;
    h.db_size = parts->db_size;
    memcpy(h.dim_weights, parts->dim_weights, sizeof h.dim_weights);
    size_t at = mm__sections_layout(sizeof h, SIM_ALIGN, size, MM__SIM_SEC_COUNT, h.sections);
    h.file_size = at;
    unsigned char *raw;
    unsigned char *base =
        mm__sections_pack(allocator, at, SIM_ALIGN, h.sections, parts->data, MM__SIM_SEC_COUNT, &raw);
    if (!base) return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory (%zu bytes)", at);
    h.checksum = mm__sections_seal(base, at, &h, sizeof h);
    memset(out, 0, sizeof *out);
    if (allocator) out->allocator = *allocator;
    out->owned = raw;
    out->data = base;
    out->size = at;
    point_into(out, base, &h);
    return MM_OK;
}

#define BAD(...) mm_error_set(err, MM_ERR_SYNTAX, 0, 0, __VA_ARGS__)

static mm_result validate_header(const unsigned char *base, size_t size, sim_header *h, mm_error *err)
{
    if (size < 24 || memcmp(base, sim_magic, 8) != 0) return BAD("not mm similarity tables (bad magic)");
    if (size < sizeof *h)
        return mm_error_set(err, MM_ERR_UNEXPECTED_EOF, 0, 0, "truncated header (%zu bytes)", size);
    memcpy(h, base, sizeof *h);
    if (h->byte_order != SIM_BYTE_ORDER) return BAD("written on a machine of the other byte order");
    if (h->version != MM_SIM_VERSION)
        return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0,
                            "tables format version %u, this mm reads version %d: rebuild them", h->version,
                            MM_SIM_VERSION);
    if (h->header_size != sizeof *h || h->section_count != MM__SIM_SEC_COUNT)
        return BAD("unexpected header size");
    if (h->file_size != size)
        return mm_error_set(err, h->file_size > size ? MM_ERR_UNEXPECTED_EOF : MM_ERR_SYNTAX, 0, 0,
                            "the header says %llu bytes, the file has %zu (truncated or padded)",
                            (unsigned long long)h->file_size, size);
    if (mm__checksum64(base + 24, size - 24) != h->checksum)
        return BAD("checksum mismatch: the file is corrupted");
    if ((h->measure != MM_SIM_COSINE && h->measure != MM_SIM_EUCLIDEAN) || h->channels == 0 ||
        h->channels > 7 || h->window < 1 || h->window > MM_SIM_MAX_WINDOW || h->joint_count < 1 ||
        h->joint_count > MM_MAX_JOINTS || h->frame_count < 1 || h->frame_count > MM_MAX_FRAMES ||
        h->clip_count < 1 || h->clip_count > h->frame_count || h->loop_count < 0 || h->shot_count < 0 ||
        (int64_t)h->loop_count + h->shot_count != h->clip_count || h->fusion_rows < 0 || h->link_rows < 0 ||
        (int64_t)h->fusion_rows + h->link_rows != h->frame_count)
        return BAD("header counts are out of range");
    for (int i = 0; i < MM_SIM_DIMS; ++i)
        if (!(h->dim_weights[i] >= 0.0f) || !isfinite(h->dim_weights[i]))
            return BAD("dim weight %d is invalid", i);
    mm__sim_parts p;
    memset(&p, 0, sizeof p);
    p.joint_count = h->joint_count;
    p.frame_count = h->frame_count;
    p.clip_count = h->clip_count;
    p.loop_count = h->loop_count;
    p.shot_count = h->shot_count;
    p.fusion_rows = h->fusion_rows;
    p.link_rows = h->link_rows;
    size_t want[MM__SIM_SEC_COUNT];
    mm__sim_section_sizes(&p, want);
    int s = mm__sections_check(h->sections, MM__SIM_SEC_COUNT, sizeof *h, SIM_ALIGN, size, want);
    if (s >= 0)
        return BAD("section %d: offset %llu size %llu does not fit the file or the counts, or overlaps "
                   "the one before",
                   s, (unsigned long long)h->sections[s].offset, (unsigned long long)h->sections[s].size);
    return MM_OK;
}

/* Every index in the tables points where it should. */
static mm_result validate_content(const mm_sim_tables *t, mm_error *err)
{
    for (int j = 0; j < t->joint_count; ++j)
        if (!(t->joint_weights[j] >= 0.0f) || !isfinite(t->joint_weights[j]))
            return BAD("joint weight %d is invalid", j);
    int rows[2] = {0, 0}, next_frame = 0;
    for (int c = 0; c < t->clip_count; ++c) {
        const mm_sim_clip *k = &t->clips[c];
        if (k->loop != 0 && k->loop != 1) return BAD("clip %d: loop flag %d", c, k->loop);
        if (k->first_frame != next_frame || k->frame_count < 1 ||
            k->frame_count > t->frame_count - k->first_frame)
            return BAD("clip %d: frames %d + %d do not follow the previous clip", c, k->first_frame,
                       k->frame_count);
        next_frame += k->frame_count;
        const int32_t *list = k->loop ? t->loop_clips : t->shot_clips;
        int count = k->loop ? t->loop_count : t->shot_count;
        if (k->index < 0 || k->index >= count || list[k->index] != c)
            return BAD("clip %d: index %d is not its place among the %s clips", c, k->index,
                       k->loop ? "loop" : "one-shot");
        if (k->row != rows[k->loop])
            return BAD("clip %d: first row %d, expected %d", c, k->row, rows[k->loop]);
        rows[k->loop] += k->frame_count;
        for (int f = k->first_frame; f < k->first_frame + k->frame_count; ++f)
            if (t->frame_clip[f] != c) return BAD("frame %d: clip %d, expected %d", f, t->frame_clip[f], c);
    }
    if (next_frame != t->frame_count || rows[0] != t->fusion_rows || rows[1] != t->link_rows)
        return BAD("the clips do not cover the frames and rows");
    for (int i = 0; i < t->loop_count; ++i)
        if (t->loop_clips[i] < 0 || t->loop_clips[i] >= t->clip_count || !t->clips[t->loop_clips[i]].loop)
            return BAD("loop clip %d: %d is not a loop clip", i, t->loop_clips[i]);
    for (int i = 0; i < t->shot_count; ++i)
        if (t->shot_clips[i] < 0 || t->shot_clips[i] >= t->clip_count || t->clips[t->shot_clips[i]].loop)
            return BAD("one-shot clip %d: %d is not a one-shot clip", i, t->shot_clips[i]);
    for (int l = 0; l < t->loop_count; ++l) {
        const mm_sim_clip *k = &t->clips[t->loop_clips[l]];
        for (int r = 0; r < t->fusion_rows; ++r) {
            const mm_sim_match *m = &t->fusion[(size_t)r * (size_t)t->loop_count + (size_t)l];
            if (m->frame < k->first_frame || m->frame >= k->first_frame + k->frame_count ||
                !isfinite(m->score))
                return BAD("fusion row %d, loop clip %d: frame %d score %g is invalid", r, l, m->frame,
                           (double)m->score);
        }
    }
    size_t n = (size_t)t->link_rows * (size_t)t->shot_count;
    for (size_t i = 0; i < n; ++i)
        if (!isfinite(t->link[i])) return BAD("link score %zu is not finite", i);
    return MM_OK;
}

static mm_result check_database(const mm_sim_tables *t, const mm_database *db, mm_error *err)
{
    if (!db) return MM_OK;
    uint64_t cs = mm__sim_db_checksum(db);
    if (t->db_checksum != cs || t->db_size != (uint64_t)db->size || t->frame_count != db->frame_count ||
        t->clip_count != db->clip_count || t->joint_count != db->joint_count)
        return mm_error_set(
            err, MM_ERR_INVALID_ARGUMENT, 0, 0,
            "the tables belong to another database (built for checksum %016llx, %llu bytes; this "
            "one is %016llx, %zu bytes): rebuild them with mm similarity build",
            (unsigned long long)t->db_checksum, (unsigned long long)t->db_size, (unsigned long long)cs,
            db->size);
    for (int c = 0; c < t->clip_count; ++c)
        if (t->clips[c].first_frame != db->clips[c].first_frame ||
            t->clips[c].frame_count != db->clips[c].frame_count ||
            t->clips[c].loop != (db->clips[c].loop != 0))
            return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0,
                                "clip %d (%s) differs from the database's: rebuild the tables", c,
                                db->clips[c].name);
    return MM_OK;
}

mm_result mm_sim_tables_load_memory(const void *data, size_t size, const mm_database *db, mm_sim_tables *out,
                                    mm_error *err)
{
    memset(out, 0, sizeof *out);
    if (!data || ((uintptr_t)data & 7u))
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0,
                            "tables buffer is NULL or not 8-byte aligned");
    const unsigned char *base = (const unsigned char *)data;
    sim_header h;
    mm_result r = validate_header(base, size, &h, err);
    if (r != MM_OK) return r;
    mm_sim_tables t;
    memset(&t, 0, sizeof t);
    point_into(&t, base, &h);
    t.data = data;
    t.size = size;
    r = validate_content(&t, err);
    if (r == MM_OK) r = check_database(&t, db, err);
    if (r != MM_OK) return r;
    *out = t;
    return MM_OK;
}

mm_result mm_sim_tables_load(const char *path, const mm_database *db, const mm_allocator *allocator,
                             mm_sim_tables *out, mm_error *err)
{
    memset(out, 0, sizeof *out);
    char *data = NULL;
    size_t size = 0;
    mm_result r = mm__read_file(path, allocator, &data, &size, err);
    if (r != MM_OK) return r;
    mm__error_set_file(err, path);
    r = mm_sim_tables_load_memory(data, size, db, out, err);
    if (r != MM_OK) {
        mm_free(allocator, data);
        return r;
    }
    out->owned = data;
    if (allocator) out->allocator = *allocator;
    return MM_OK;
}

mm_result mm_sim_tables_save(const mm_sim_tables *t, const char *path, mm_error *err)
{
    if (!t || !t->data) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no tables");
    return mm__write_file_atomic(path, t->data, t->size, err);
}

void mm_sim_tables_free(mm_sim_tables *t)
{
    if (!t) return;
    mm_allocator a = t->allocator;
    mm_free(&a, t->owned);
    memset(t, 0, sizeof *t);
}

/* Run-time lookups: no allocation, reads only the tables. */

mm_sim_match mm_sim_fusion(const mm_sim_tables *t, int frame, int loop_clip)
{
    mm_sim_match none = {-1, 0.0f};
    if (!t || frame < 0 || frame >= t->frame_count || loop_clip < 0 || loop_clip >= t->clip_count)
        return none;
    const mm_sim_clip *src = &t->clips[t->frame_clip[frame]], *dst = &t->clips[loop_clip];
    if (src->loop || !dst->loop) return none;
    size_t row = (size_t)(src->row + frame - src->first_frame);
    return t->fusion[row * (size_t)t->loop_count + (size_t)dst->index];
}

int mm_sim_fusion_best(const mm_sim_tables *t, int frame, mm_sim_match *out)
{
    mm_sim_match best = {-1, 0.0f};
    int best_clip = -1;
    if (t && frame >= 0 && frame < t->frame_count && !t->clips[t->frame_clip[frame]].loop) {
        const mm_sim_clip *src = &t->clips[t->frame_clip[frame]];
        const mm_sim_match *row =
            t->fusion + (size_t)(src->row + frame - src->first_frame) * (size_t)t->loop_count;
        for (int l = 0; l < t->loop_count; ++l)
            if (best_clip < 0 || mm_sim_better(t->measure, row[l].score, best.score)) {
                best = row[l];
                best_clip = t->loop_clips[l];
            }
    }
    if (out) *out = best;
    return best_clip;
}

const float *mm_sim_link_row(const mm_sim_tables *t, int frame)
{
    if (!t || frame < 0 || frame >= t->frame_count) return NULL;
    const mm_sim_clip *c = &t->clips[t->frame_clip[frame]];
    if (!c->loop || t->shot_count == 0) return NULL;
    return t->link + (size_t)(c->row + frame - c->first_frame) * (size_t)t->shot_count;
}

int mm_sim_link(const mm_sim_tables *t, int frame, int rows, const int *candidates, int candidate_count,
                mm_sim_link_match *out)
{
    mm_sim_link_match best = {-1, -1, 0, 0.0f};
    if (t && frame >= 0 && frame < t->frame_count && t->clips[t->frame_clip[frame]].loop &&
        t->shot_count > 0) {
        const mm_sim_clip *c = &t->clips[t->frame_clip[frame]];
        int rel = frame - c->first_frame;
        if (rows < 1) rows = 1;
        if (rows > c->frame_count) rows = c->frame_count;
        int count = candidates && candidate_count > 0 ? candidate_count : t->shot_count;
        for (int d = 0; d < rows; ++d) {
            const float *row =
                t->link + (size_t)(c->row + (rel + d) % c->frame_count) * (size_t)t->shot_count;
            for (int i = 0; i < count; ++i) {
                int clip;
                if (candidates && candidate_count > 0) {
                    clip = candidates[i];
                    if (clip < 0 || clip >= t->clip_count || t->clips[clip].loop) continue;
                } else {
                    clip = t->shot_clips[i];
                }
                float s = row[t->clips[clip].index];
                if (best.clip < 0 || mm_sim_better(t->measure, s, best.score)) {
                    best.clip = clip;
                    best.frame = t->clips[clip].first_frame;
                    best.delay = d;
                    best.score = s;
                }
            }
        }
    }
    if (out) *out = best;
    return best.clip;
}
