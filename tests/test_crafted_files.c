/* Crafted database and similarity-table files: a valid file with one field set to a boundary value
 * (0, 1, -1, INT_MAX, INT_MIN, infinity, the counts, sizes past the end, overlapping sections) and
 * its checksum recomputed, as an attacker would. Every one must be refused with a message, or load
 * and then be safe to use: the test checks the loaded file's cross references itself (a second
 * method, not the loader's code), and reads it everywhere a run does (dump, poses, search, a
 * character, the table lookups), which the AddressSanitizer build turns into a crash if not.
 * Float data fields whose value is free (positions, velocities, the normalisation mean) are
 * checked both ways: a value within the documented limit loads, a NaN, an infinity or a value past
 * the limit is refused. */
#define _POSIX_C_SOURCE 200809L
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>

#include <mm/character.h>
#include <mm/database_build.h>
#include <mm/distance_matching.h>
#include <mm/search.h>
#include <mm/similarity.h>

#include "io/checksum.h"
#include "test_util.h"

/* The .mmdb header (docs/format.md): the byte offsets of its fields. */
#define DB_FILE_SIZE_AT 24
#define DB_COUNTS_AT    32 /* header_size, the 11 int32 counts, interval, the 6 pose fields, section_count */
#define DB_COUNTS_END   112
#define DB_SECTIONS_AT  112 /* MM_DB_SECTIONS x {offset, size}, uint64 each */
#define DB_SECTIONS     31

/* The similarity tables header (docs/similarity.md). */
#define SIM_COUNTS_AT   32  /* header_size ... section_count */
#define SIM_COUNTS_END  96  /* then db_checksum and db_size: checked against a database, not alone */
#define SIM_WEIGHTS_AT  96  /* dim_weights: floats up to the sections */
#define SIM_SECTIONS_AT 144 /* 7 x {offset, size} */
#define SIM_SECTIONS    7

/* The largest magnitude a stored length or speed may have (docs/format.md). */
#define VALUE_LIMIT 1e6f

typedef struct tally {
    int crafted, refused, loaded, loaded_changed;
} tally;

static void make_skeleton(mm_skeleton *s)
{
    assert_int_equal(mm_skeleton_init(s, 6, NULL), MM_OK);
    const char *names[6] = {"Hips", "Spine2", "LeftFoot", "LeftToe", "RightFoot", "RightToe"};
    const int parents[6] = {-1, 0, 0, 2, 0, 4};
    const float off[6][3] = {{0, 1, 0},          {0, 0.3f, 0},      {0.1f, -0.9f, 0},
                             {0, -0.05f, 0.15f}, {-0.1f, -0.9f, 0}, {0, -0.05f, 0.15f}};
    for (int j = 0; j < 6; ++j) {
        snprintf(s->joints[j].name, MM_NAME_MAX, "%s", names[j]);
        s->joints[j].parent = parents[j];
        s->joints[j].offset = mm_vec3_make(off[j][0], off[j][1], off[j][2]);
        s->joints[j].order = MM_EULER_ZYX;
    }
    s->joints[0].flags = MM_JOINT_TRANSLATES;
    s->joints[3].has_end_site = true;
    s->joints[3].end_site = mm_vec3_make(0, 0, 0.05f);
}

/* The hips walk a circle (radius > 0) or a line at speed, the feet swinging. */
static void make_motion(mm_clip *clip, int frames, double radius, double speed)
{
    mm_skeleton s;
    make_skeleton(&s);
    assert_int_equal(mm_clip_init(clip, &s, frames, 30.0f, NULL), MM_OK);
    mm_skeleton_free(&s);
    for (int f = 0; f < frames; ++f) {
        double t = f / 30.0, yaw = radius > 0 ? speed / radius * t : 0.0;
        double x = radius > 0 ? -radius * cos(yaw) + radius : 0.0,
               z = radius > 0 ? radius * sin(yaw) : speed * t;
        mm_clip_rotations(clip, f)[0] = mm_quat_from_axis_angle(mm_vec3_make(0, 1, 0), (float)yaw);
        mm_clip_positions(clip, f)[0] = mm_vec3_make((float)x, 1.0f, (float)z);
        mm_clip_rotations(clip, f)[2] =
            mm_quat_from_axis_angle(mm_vec3_make(1, 0, 0), (float)(0.4 * sin(6 * t)));
        mm_clip_rotations(clip, f)[4] =
            mm_quat_from_axis_angle(mm_vec3_make(1, 0, 0), (float)(-0.4 * sin(6 * t)));
    }
}

/* Three clips (a loop, a one-shot, and the one-shot's mirror), two tags. */
static mm_database build_db(void)
{
    mm_clip clips[2];
    make_motion(&clips[0], 40, 2.0, 1.0);
    make_motion(&clips[1], 35, 0.0, 2.0);
    mm_config cfg;
    mm_config_defaults(&cfg);
    cfg.scale = 1.0f;
    cfg.root_smoothing = 0.0f;
    cfg.left_hand[0] = cfg.right_hand[0] = cfg.head[0] = 0;
    cfg.clip_count = 2;
    cfg.clips = calloc(2, sizeof(mm_config_clip));
    for (int i = 0; i < 2; ++i) {
        snprintf(cfg.clips[i].name, MM_NAME_MAX, "clip%d", i);
        snprintf(cfg.clips[i].file, MM_PATH_MAX, "clip%d.bvh", i);
    }
    cfg.clips[0].loop = true;
    cfg.clips[1].mirror = true;
    mm_db_build_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.config_json = "{\"interval\": 0.0333333}";
    mm_database db;
    mm_error err;
    memset(&err, 0, sizeof err);
    if (mm_database_build(&cfg, clips, &desc, &db, &err) != MM_OK) fail_msg("build: %s", err.message);
    mm_config_free(&cfg);
    mm_clip_free(&clips[0]);
    mm_clip_free(&clips[1]);
    return db;
}

static void reseal(unsigned char *file, size_t size)
{
    uint64_t c = mm__checksum64(file + 24, size - 24);
    memcpy(file + 16, &c, 8);
}

/* The test's own account of what makes a loaded database safe to read (every index in range, every
 * count consistent with the section sizes), written from docs/format.md. */
static void check_database_invariants(const mm_database *db)
{
    assert_true(db->frame_count >= 1 && db->clip_count >= 1 && db->joint_count >= 1);
    assert_true(db->dims >= 0 && db->dims <= db->dims_padded && db->dims_padded % MM_DB_SIMD_WIDTH == 0);
    assert_true(db->interval > 0.0f && db->interval <= 1.0f);
    int64_t covered = 0;
    for (int c = 0; c < db->clip_count; ++c) {
        const mm_db_clip *k = &db->clips[c];
        assert_int_equal(k->first_frame, covered);
        assert_true(k->frame_count >= 1);
        covered += k->frame_count;
        assert_true(k->blend_left >= -1 && k->blend_left < db->clip_count);
        assert_true(k->blend_right >= -1 && k->blend_right < db->clip_count);
        assert_non_null(memchr(k->name, 0, MM_NAME_MAX));
    }
    assert_int_equal(covered, db->frame_count);
    for (int j = 0; j < db->joint_count; ++j)
        assert_true(j == 0 ? db->joints[j].parent == -1
                           : db->joints[j].parent >= 0 && db->joints[j].parent < j);
    for (int f = 0; f < db->frame_count; ++f) {
        int c = db->frame_clip[f], n = db->frame_next[f];
        assert_true(c >= 0 && c < db->clip_count);
        assert_true(f >= db->clips[c].first_frame && f - db->clips[c].first_frame < db->clips[c].frame_count);
        assert_true(n >= -1 && n < db->frame_count);
        if (n >= 0) assert_int_equal(db->frame_clip[n], c);
    }
    int64_t dims = 0;
    for (int g = 0; g < db->group_count; ++g) {
        const mm_feature_group *grp = &db->groups[g];
        assert_int_equal(grp->offset, dims);
        assert_true(grp->dims >= 1 && grp->dims <= 3);
        dims += grp->dims;
        assert_true(grp->bone >= -1 && grp->bone < db->joint_count);
    }
    assert_int_equal(dims, db->dims);
    for (int f = 0; f < db->frame_count; ++f)
        for (int d = 0; d < db->dims_padded; ++d)
            assert_true(isfinite(db->features[(size_t)f * db->dims_padded + d]));
    int64_t segments = 0;
    for (int c = 0; c < db->clip_count; ++c) {
        assert_int_equal(db->distance_clips[c].first_segment, segments);
        segments += db->distance_clips[c].segment_count;
    }
    assert_int_equal(segments, db->distance_segment_count);
    for (int k = 0; k < MM_ROLE_COUNT; ++k)
        assert_true(db->settings->roles[k] >= -1 && db->settings->roles[k] < db->joint_count);
}

/* Reads a loaded database everywhere a run does. */
static void exercise_database(const mm_database *db)
{
    check_database_invariants(db);
    FILE *null = fopen("/dev/null", "w");
    assert_non_null(null);
    mm_database_dump(db, null);
    fclose(null);
    mm_pose_data pd;
    for (int f = 0; f < db->frame_count; ++f) mm_database_pose(db, f, &pd);
    for (int c = 0; c < db->clip_count; ++c) {
        mm_distance_curve curve;
        if (mm_database_distance_curve(db, c, &curve) == MM_OK) {
            float at;
            float t = 0.4f * mm_distance_duration(&curve);
            (void)mm_distance_time_after(&curve, t, 0.5f);
            (void)mm_distance_match_to_target(&curve, mm_distance_segment_at(&curve, t), 0.25f, &at);
        }
    }
    mm_searcher s;
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_searcher_init(&s, db, NULL, &err), MM_OK);
    mm_character_desc desc;
    assert_int_equal(mm_character_desc_from_database(&desc, db, &err), MM_OK);
    mm_character ch;
    assert_int_equal(mm_character_init(&ch, db, &s, &desc, &err), MM_OK);
    mm_input in;
    memset(&in, 0, sizeof in);
    for (int i = 0; i < 60; ++i) {
        in.stick[0] = sinf(0.1f * (float)i);
        in.stick[1] = 0.8f;
        mm_character_update(&ch, &in, 1.0f / 30.0f);
        for (int j = 0; j < db->joint_count; ++j)
            assert_true(isfinite(ch.global[j].translation.x) && isfinite(ch.global[j].translation.z));
    }
    mm_character_free(&ch);
    mm_searcher_free(&s);
}

static void *aligned_copy(const void *data, size_t size)
{
    void *copy = aligned_alloc(MM_DB_ALIGN, (size + MM_DB_ALIGN) / MM_DB_ALIGN * MM_DB_ALIGN);
    assert_non_null(copy);
    memcpy(copy, data, size);
    return copy;
}

/* Loads the database file with `width` bytes at `at` replaced by value, checksum recomputed.
 * float_free: the word is a float whose value is free: finite must load, non-finite be refused. */
static void try_db(const mm_database *db, size_t at, int width, uint64_t value, int float_free, tally *t)
{
    unsigned char *copy = aligned_copy(db->data, db->size);
    memcpy(copy + at, &value, (size_t)width); /* little-endian: the low bytes */
    int changed = memcmp(copy + at, (const unsigned char *)db->data + at, (size_t)width) != 0;
    reseal(copy, db->size);
    mm_database out;
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_result r = mm_database_load_memory(copy, db->size, true, &out, &err);
    ++t->crafted;
    if (float_free) {
        float f;
        memcpy(&f, copy + at, 4);
        if ((r == MM_OK) != (fabsf(f) <= VALUE_LIMIT))
            fail_msg("byte %zu = %g: %s (%s)", at, (double)f, r == MM_OK ? "loaded" : "refused", err.message);
    }
    if (r != MM_OK) {
        ++t->refused;
        if (err.message[0] == 0)
            fail_msg("byte %zu = %llx refused without a message", at, (unsigned long long)value);
    } else {
        ++t->loaded;
        t->loaded_changed += changed;
        exercise_database(&out);
        mm_database_free(&out);
    }
    free(copy);
}

static const uint32_t word_values[] = {0u,
                                       1u,
                                       2u,
                                       3u,
                                       0xFFFFFFFFu /* -1 */,
                                       0xFFFFFFFEu /* -2 */,
                                       0x7FFFFFFFu /* INT_MAX */,
                                       0x80000000u /* INT_MIN */,
                                       0x7FFFFFFDu /* INT_MAX - 2 */,
                                       0x7F800000u /* +inf */,
                                       0xFF800000u /* -inf */,
                                       0x3F800000u /* 1.0f */,
                                       0x7F7FFFFFu /* FLT_MAX */};

/* Every value above, plus the given extra ones (the file's counts, a size past the end). */
static void try_db_word(const mm_database *db, size_t at, const uint32_t *extra, int extra_count,
                        int float_free, tally *t)
{
    for (size_t v = 0; v < sizeof word_values / sizeof word_values[0]; ++v)
        try_db(db, at, 4, word_values[v], float_free, t);
    for (int v = 0; v < extra_count; ++v) try_db(db, at, 4, extra[v], float_free, t);
}

static uint64_t db_section(const mm_database *db, int s, int field)
{
    uint64_t v;
    memcpy(&v, (const unsigned char *)db->data + DB_SECTIONS_AT + 16 * s + 8 * field, 8);
    return v;
}

/* The record sections: their index, record size, and whether their floats are free values. */
typedef struct record_section {
    int section;
    size_t record;
    int float_free;
} record_section;

/* Every crafted file of db: the header, the section table, the records of the given sections. */
static void craft_database(const mm_database *base, const record_section *records, size_t record_count)
{
    mm_database db = *base;
    assert_int_equal(db.clip_count, 3);
    const uint32_t counts[] = {(uint32_t)db.frame_count,
                               (uint32_t)db.frame_count + 1,
                               (uint32_t)db.clip_count,
                               (uint32_t)db.joint_count,
                               (uint32_t)db.dims,
                               (uint32_t)db.dims_padded,
                               (uint32_t)db.dims_padded + 8,
                               (uint32_t)db.group_count,
                               (uint32_t)db.compressed.segment_count,
                               (uint32_t)db.compressed.translating_count};
    const int ncounts = (int)(sizeof counts / sizeof counts[0]);
    tally t = {0, 0, 0, 0};

    /* the header: file size, then every 32-bit field */
    const uint64_t sizes[] = {0, 1, db.size - 64, db.size + 64, UINT64_MAX, (uint64_t)1 << 63};
    for (int v = 0; v < 6; ++v) try_db(&db, DB_FILE_SIZE_AT, 8, sizes[v], 0, &t);
    for (size_t at = DB_COUNTS_AT; at < DB_COUNTS_END; at += 4) try_db_word(&db, at, counts, ncounts, 0, &t);

    /* the section table: offsets and sizes at boundaries, past the end, onto the section before */
    for (int s = 0; s < DB_SECTIONS; ++s) {
        uint64_t off = db_section(&db, s, 0), size = db_section(&db, s, 1);
        uint64_t prev = s > 0 ? db_section(&db, s - 1, 0) : 0;
        const uint64_t offsets[] = {0,       64,           off - 64,   off + 64,       prev,
                                    db.size, db.size - 64, UINT64_MAX, UINT64_MAX - 63};
        const uint64_t lengths[] = {
            0, size + 4, size + 64, db.size, db.size - off + 64, UINT64_MAX, UINT64_MAX - off + 1};
        for (int v = 0; v < 9; ++v) try_db(&db, DB_SECTIONS_AT + 16 * (size_t)s, 8, offsets[v], 0, &t);
        for (int v = 0; v < 7; ++v) try_db(&db, DB_SECTIONS_AT + 16 * (size_t)s + 8, 8, lengths[v], 0, &t);
    }

    /* the records: every 32-bit word of the first and last record of each section */
    for (size_t i = 0; i < record_count; ++i) {
        const record_section *rs = &records[i];
        uint64_t off = db_section(&db, rs->section, 0), size = db_section(&db, rs->section, 1);
        assert_true(size >= rs->record);
        size_t n = (size_t)(size / rs->record), firsts[2] = {0, (n - 1) * rs->record};
        for (int k = 0; k < (n > 1 ? 2 : 1); ++k)
            for (size_t w = 0; w + 4 <= rs->record; w += 4) {
                /* of a name (the records that start with one), its first and last words */
                int named = rs->section == 0 || rs->section == 1 || rs->section == 3;
                if (named && w > 0 && w < MM_NAME_MAX - 4) continue;
                /* the mean of a padding dimension is 0, not free */
                int is_free = rs->float_free && !(rs->section == 13 && k == 1 && db.dims < db.dims_padded);
                try_db_word(&db, (size_t)off + firsts[k] + w, counts, ncounts, is_free, &t);
            }
    }
    /* the bytes of a section that are not whole words (contacts), and a bool (a joint's End Site) */
    for (int v = 0; v < 256; v += 15) try_db(&db, (size_t)db_section(&db, 7, 0), 1, (uint64_t)v, 0, &t);
    for (int v = 0; v < 256; v += 15)
        try_db(&db, (size_t)db_section(&db, 0, 0) + offsetof(mm_joint, has_end_site), 1, (uint64_t)v, 0, &t);
    printf("crafted databases (%s poses): %d, refused %d, loaded %d (%d of them changed, all safe to run)\n",
           db.pose_codec == MM_POSE_SEGMENTS ? "compressed" : "float", t.crafted, t.refused, t.loaded,
           t.loaded_changed);
    assert_true(t.refused > t.crafted / 2); /* the mutations mostly break something */
}

static void test_crafted_database(void **state)
{
    (void)state;
    mm_database db = build_db();
    const record_section records[] = {{0, sizeof(mm_joint), 0},
                                      {1, sizeof(mm_db_clip), 0},
                                      {3, sizeof(mm_feature_group), 0},
                                      {4, 4, 0} /* frame_clip */,
                                      {5, 4, 0} /* frame_next */,
                                      {6, 8, 0} /* frame_tags */,
                                      {7, 4, 0} /* contacts */,
                                      {8, 12, 1} /* root velocity */,
                                      {9, 4, 1} /* angular velocity */,
                                      {10, 16, 0} /* rotations */,
                                      {11, 12, 1} /* positions */,
                                      {12, 4, 0} /* features */,
                                      {13, 4, 1} /* mean */,
                                      {14, 4, 0} /* scale */,
                                      {15, 4, 0},
                                      {16, 4, 0},
                                      {17, 4, 0},
                                      {18, 4, 0} /* bounds */,
                                      {20, sizeof(mm_db_distance_clip), 0},
                                      {21, 4, 0} /* travelled */,
                                      {22, 4, 0} /* signed */,
                                      {23, sizeof(mm_distance_segment), 0},
                                      {24, sizeof(mm_database_settings), 0}};
    craft_database(&db, records, sizeof records / sizeof records[0]);

    /* the crash of issue 25: a feature group's offset near INT_MAX passed an overflowing range check */
    unsigned char *copy = aligned_copy(db.data, db.size);
    int32_t big = INT_MAX - 1;
    memcpy(copy + db_section(&db, 3, 0) + offsetof(mm_feature_group, offset), &big, 4);
    reseal(copy, db.size);
    mm_database out;
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_database_load_memory(copy, db.size, true, &out, &err), MM_ERR_SYNTAX);
    assert_non_null(strstr(err.message, "feature group 0"));
    free(copy);

    mm_database_free(&db);
}

/* The same with the poses compressed: sections 10 and 11 empty, 25-30 the segments. */
static void test_crafted_compressed(void **state)
{
    (void)state;
    mm_database floats = build_db(), db;
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_db_compress_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.segment_frames = 8; /* several segments per clip: first and last records differ */
    assert_int_equal(mm_database_compress(&floats, &desc, &db, &err), MM_OK);
    mm_database_free(&floats);
    assert_int_equal(db.pose_codec, MM_POSE_SEGMENTS);
    const record_section records[] = {{25, sizeof(mm_vec3), 0} /* constants */,
                                      {26, 4, 0} /* translating joints */,
                                      {27, sizeof(mm_db_pose_segment), 0},
                                      {28, sizeof(mm_db_rotation_track), 0},
                                      {29, sizeof(mm_db_translation_track), 0},
                                      {30, 4, 0} /* the bit stream's first and last words */,
                                      {4, 4, 0} /* frame_clip: the segments follow the clips */,
                                      {1, sizeof(mm_db_clip), 0}};
    craft_database(&db, records, sizeof records / sizeof records[0]);
    /* the reserved and dropped bytes of a rotation track, one bit each */
    tally t = {0, 0, 0, 0};
    size_t track = (size_t)db_section(&db, 28, 0) + offsetof(mm_db_rotation_track, dropped);
    for (int bit = 0; bit < 8; ++bit)
        try_db(&db, track, 1, (uint64_t)(db.compressed.rotation_tracks[0].dropped ^ (1u << bit)), 0, &t);
    assert_true(t.refused >= 5); /* bits 3-7 are not components nor the sign */
    mm_database_free(&db);
}

/* ---- similarity tables ------------------------------------------------------------------- */

static void exercise_tables(const mm_sim_tables *tb)
{
    for (int f = -1; f <= tb->frame_count; ++f) {
        for (int c = -1; c <= tb->clip_count; ++c) (void)mm_sim_fusion(tb, f, c);
        mm_sim_match m;
        int best = mm_sim_fusion_best(tb, f, &m);
        assert_true(best >= -1 && best < tb->clip_count);
        const float *row = mm_sim_link_row(tb, f);
        if (row)
            for (int i = 0; i < tb->shot_count; ++i) assert_true(isfinite(row[i]));
        mm_sim_link_match lm;
        int clip = mm_sim_link(tb, f, 3, NULL, 0, &lm);
        assert_true(clip >= -1 && clip < tb->clip_count);
    }
}

static void try_sim(const mm_sim_tables *tb, const mm_database *db, size_t at, int width, uint64_t value,
                    tally *t)
{
    unsigned char *copy = aligned_copy(tb->data, tb->size);
    memcpy(copy + at, &value, (size_t)width);
    int changed = memcmp(copy + at, (const unsigned char *)tb->data + at, (size_t)width) != 0;
    reseal(copy, tb->size);
    mm_sim_tables out;
    mm_error err;
    memset(&err, 0, sizeof err);
    /* alone (the fuzz target's case) and against its database (mm simulate's) */
    for (int with_db = 0; with_db < 2; ++with_db) {
        mm_result r = mm_sim_tables_load_memory(copy, tb->size, with_db ? db : NULL, &out, &err);
        ++t->crafted;
        if (r != MM_OK) {
            ++t->refused;
            if (err.message[0] == 0) fail_msg("tables byte %zu refused without a message", at);
        } else {
            ++t->loaded;
            t->loaded_changed += changed;
            exercise_tables(&out);
        }
    }
    free(copy);
}

static void test_crafted_tables(void **state)
{
    (void)state;
    mm_database db = build_db();
    mm_sim_desc d;
    memset(&d, 0, sizeof d);
    d.window = 3;
    mm_sim_tables tb;
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_sim_tables_build(&db, &d, &tb, &err), MM_OK);
    assert_true(tb.loop_count >= 1 && tb.shot_count >= 1);
    const uint32_t counts[] = {(uint32_t)tb.frame_count, (uint32_t)tb.frame_count + 1,
                               (uint32_t)tb.clip_count,  (uint32_t)tb.loop_count,
                               (uint32_t)tb.shot_count,  (uint32_t)tb.fusion_rows,
                               (uint32_t)tb.link_rows,   (uint32_t)tb.joint_count};
    tally t = {0, 0, 0, 0};
    const uint64_t sizes[] = {0, 1, tb.size - 64, tb.size + 64, UINT64_MAX};
    for (int v = 0; v < 5; ++v) try_sim(&tb, &db, 24, 8, sizes[v], &t);
    for (size_t at = SIM_COUNTS_AT; at < SIM_SECTIONS_AT; at += 4) {
        for (size_t v = 0; v < sizeof word_values / sizeof word_values[0]; ++v)
            try_sim(&tb, &db, at, 4, word_values[v], &t);
        for (size_t v = 0; v < sizeof counts / sizeof counts[0]; ++v) try_sim(&tb, &db, at, 4, counts[v], &t);
    }
    /* the signed overflow of issue 25: loop + shot counts, fusion + link rows, that wrap to the truth */
    const size_t pairs[2][2] = {{60, 64}, {68, 72}};
    for (int p = 0; p < 2; ++p) {
        unsigned char *copy = aligned_copy(tb.data, tb.size);
        int32_t a = INT_MAX, b;
        memcpy(&b, copy + pairs[p][0], 4);
        int32_t total = b;
        memcpy(&b, copy + pairs[p][1], 4);
        total += b;
        b = (int32_t)((uint32_t)total - (uint32_t)a); /* a + b wraps to total in 32 bits */
        memcpy(copy + pairs[p][0], &a, 4);
        memcpy(copy + pairs[p][1], &b, 4);
        reseal(copy, tb.size);
        mm_sim_tables out;
        assert_int_equal(mm_sim_tables_load_memory(copy, tb.size, NULL, &out, &err), MM_ERR_SYNTAX);
        assert_non_null(strstr(err.message, "header counts"));
        free(copy);
    }
    for (int s = 0; s < SIM_SECTIONS; ++s) {
        uint64_t off, size, prev = 0;
        memcpy(&off, (const unsigned char *)tb.data + SIM_SECTIONS_AT + 16 * s, 8);
        memcpy(&size, (const unsigned char *)tb.data + SIM_SECTIONS_AT + 16 * s + 8, 8);
        if (s > 0) memcpy(&prev, (const unsigned char *)tb.data + SIM_SECTIONS_AT + 16 * (s - 1), 8);
        const uint64_t offsets[] = {0, 64, off + 64, prev, tb.size, UINT64_MAX, UINT64_MAX - 63};
        const uint64_t lengths[] = {size + 4, size + 64, tb.size, UINT64_MAX, UINT64_MAX - off + 1};
        for (int v = 0; v < 7; ++v) try_sim(&tb, &db, SIM_SECTIONS_AT + 16 * (size_t)s, 8, offsets[v], &t);
        for (int v = 0; v < 5; ++v)
            try_sim(&tb, &db, SIM_SECTIONS_AT + 16 * (size_t)s + 8, 8, lengths[v], &t);
        /* the first and last word of the section's data */
        if (size >= 4)
            for (size_t v = 0; v < sizeof word_values / sizeof word_values[0]; ++v) {
                try_sim(&tb, &db, (size_t)off, 4, word_values[v], &t);
                try_sim(&tb, &db, (size_t)(off + size - 4), 4, word_values[v], &t);
            }
    }
    printf("crafted tables: %d loads, refused %d, loaded %d (%d of them changed, all safe to use)\n",
           t.crafted, t.refused, t.loaded, t.loaded_changed);
    assert_true(t.refused > t.crafted / 2);
    mm_sim_tables_free(&tb);
    mm_database_free(&db);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_crafted_database),
        cmocka_unit_test(test_crafted_compressed),
        cmocka_unit_test(test_crafted_tables),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
