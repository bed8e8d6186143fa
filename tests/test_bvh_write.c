/* BVH writer: parse(write(clip)) reproduces every joint's world position, in every order. */
#define _POSIX_C_SOURCE 200809L
#include <locale.h>
#include <math.h>

#include <mm/bvh.h>

#include "test_util.h"

/* Largest distance between the double-precision world positions of two parsed files, matching
 * joints by name. */
static double max_position_error(const mm_bvh *a, const mm_bvh *b)
{
    assert_int_equal(a->frame_count, b->frame_count);
    assert_int_equal(a->skeleton.joint_count, b->skeleton.joint_count);
    int n = a->skeleton.joint_count;
    double *pa = malloc(sizeof(double) * 3 * n), *pb = malloc(sizeof(double) * 3 * n);
    int *map = malloc(sizeof(int) * n);
    for (int j = 0; j < n; ++j) {
        map[j] = mm_skeleton_find(&b->skeleton, a->skeleton.joints[j].name);
        assert_true(map[j] >= 0);
    }
    double worst = 0;
    for (int f = 0; f < a->frame_count; ++f) {
        assert_int_equal(mm_bvh_fk(a, f, pa), MM_OK);
        assert_int_equal(mm_bvh_fk(b, f, pb), MM_OK);
        for (int j = 0; j < n; ++j)
            for (int k = 0; k < 3; ++k) worst = fmax(worst, fabs(pa[3 * j + k] - pb[3 * map[j] + k]));
    }
    free(pa);
    free(pb);
    free(map);
    return worst;
}

static void round_trip(const char *path, mm_euler_order order, double tolerance)
{
    mm_bvh src, back;
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_bvh_load(path, NULL, &src, &err), MM_OK);
    mm_clip clip;
    assert_int_equal(mm_bvh_to_clip(&src, NULL, &clip, &err), MM_OK);
    mm_bvh_write_desc wd;
    memset(&wd, 0, sizeof wd);
    wd.order = order;
    char *text = NULL;
    size_t size = 0;
    assert_int_equal(mm_bvh_write(&clip, &wd, &text, &size, &err), MM_OK);
    assert_int_equal(strlen(text), size);
    assert_int_equal(mm_bvh_parse(text, size, NULL, &back, &err), MM_OK);
    assert_near(back.frame_time, src.frame_time, 1e-9);
    for (int j = 0; j < back.skeleton.joint_count; ++j) {
        mm_euler_order expect =
            order ? order
                  : src.skeleton.joints[mm_skeleton_find(&src.skeleton, back.skeleton.joints[j].name)].order;
        assert_int_equal(back.skeleton.joints[j].order, expect ? expect : MM_EULER_ZYX);
    }
    double e = max_position_error(&src, &back);
    if (e > tolerance) print_error("%s order %d: error %g\n", path, (int)order, e);
    assert_true(e <= tolerance);
    mm_free(NULL, text);
    mm_bvh_free(&back);
    mm_clip_free(&clip);
    mm_bvh_free(&src);
}

static void test_round_trip_all_orders(void **state)
{
    (void)state;
    const char *files[] = {"bvh/chain2.bvh", "bvh/mobu_style.bvh", test_cmu_take("cmu_write.bvh")};
    for (size_t i = 0; i < sizeof files / sizeof files[0]; ++i)
        for (int o = MM_EULER_NONE; o <= MM_EULER_ZYX && files[i]; ++o)
            round_trip(test_data_path(files[i]), (mm_euler_order)o, 1e-4);
}

/* A skeleton listed breadth-first is written depth-first, with its data reordered to match. */
static void test_breadth_first_skeleton(void **state)
{
    (void)state;
    mm_skeleton s;
    assert_int_equal(mm_skeleton_init(&s, 5, NULL), MM_OK);
    const char *names[5] = {"root", "left", "right", "left_end", "right_end"};
    const int parents[5] = {-1, 0, 0, 1, 2};
    for (int j = 0; j < 5; ++j) {
        strcpy(s.joints[j].name, names[j]);
        s.joints[j].parent = parents[j];
        s.joints[j].offset = mm_vec3_make(j == 1 ? 1.0f : j == 2 ? -1.0f : 0.0f, j >= 3 ? 1.0f : 0.0f, 0);
    }
    mm_clip clip;
    assert_int_equal(mm_clip_init(&clip, &s, 2, 30, NULL), MM_OK);
    mm_clip_rotations(&clip, 1)[2] = mm_quat_from_axis_angle(mm_vec3_make(1, 0, 0), 0.7f);
    mm_clip_positions(&clip, 1)[0] = mm_vec3_make(0.25f, 1, 2);
    char *text;
    size_t size;
    assert_int_equal(mm_bvh_write(&clip, NULL, &text, &size, NULL), MM_OK);
    mm_bvh back;
    assert_int_equal(mm_bvh_parse(text, size, NULL, &back, NULL), MM_OK);
    const char *dfs[5] = {"root", "left", "left_end", "right", "right_end"};
    for (int j = 0; j < 5; ++j) assert_string_equal(back.skeleton.joints[j].name, dfs[j]);
    double xyz[15];
    assert_int_equal(mm_bvh_fk(&back, 1, xyz), MM_OK);
    /* right_end: root (0.25,1,2) + right (-1,0,0) + Rx(0.7) (0,1,0) */
    assert_near(xyz[12], -0.75, 1e-6);
    assert_near(xyz[13], 1 + cos(0.7), 1e-6);
    assert_near(xyz[14], 2 + sin(0.7), 1e-6);
    mm_bvh_free(&back);
    mm_free(NULL, text);

    /* A NaN rotation is refused, not written as "nan". */
    mm_clip_rotations(&clip, 0)[3].x = NAN;
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_bvh_write(&clip, NULL, &text, &size, &err), MM_ERR_BAD_NUMBER);
    assert_non_null(strstr(err.message, "left_end"));
    assert_null(text);
    mm_clip_free(&clip);
    mm_skeleton_free(&s);
}

static void test_save_atomic(void **state)
{
    (void)state;
    mm_bvh src;
    assert_int_equal(mm_bvh_load(test_data_path("bvh/chain2.bvh"), NULL, &src, NULL), MM_OK);
    mm_clip clip;
    assert_int_equal(mm_bvh_to_clip(&src, NULL, &clip, NULL), MM_OK);
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_bvh_save("/nonexistent-dir/out.bvh", &clip, NULL, &err), MM_ERR_IO);
    assert_string_equal(err.file, "/nonexistent-dir/out.bvh");
    char path[] = "/tmp/mm_test_save_XXXXXX";
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    assert_int_equal(mm_bvh_save(path, &clip, NULL, &err), MM_OK);
    mm_bvh back;
    assert_int_equal(mm_bvh_load(path, NULL, &back, &err), MM_OK);
    assert_true(max_position_error(&src, &back) < 1e-6);
    mm_bvh_free(&back);
    remove(path);
    mm_clip_free(&clip);
    mm_bvh_free(&src);
}

/* The stream writes the bytes mm_bvh_write gives, whatever the length (many flushes), and a wrong
 * frame count is an error. */
static void test_stream(void **state)
{
    (void)state;
    mm_bvh src;
    assert_int_equal(mm_bvh_load(test_data_path("bvh/chain2.bvh"), NULL, &src, NULL), MM_OK);
    mm_clip one, clip;
    assert_int_equal(mm_bvh_to_clip(&src, NULL, &one, NULL), MM_OK);
    /* a long clip: the source's frames over and over, so the stream flushes many times */
    const int frames = 3000;
    assert_int_equal(mm_clip_init(&clip, &one.skeleton, frames, one.fps, NULL), MM_OK);
    int n = one.skeleton.joint_count;
    for (int f = 0; f < frames; ++f) {
        memcpy(mm_clip_rotations(&clip, f), mm_clip_rotations(&one, f % one.frame_count),
               sizeof(mm_quat) * (size_t)n);
        memcpy(mm_clip_positions(&clip, f), mm_clip_positions(&one, f % one.frame_count),
               sizeof(mm_vec3) * (size_t)n);
        mm_clip_positions(&clip, f)[0].x += 0.001f * (float)f; /* every line differs */
    }
    mm_bvh_write_desc wd;
    memset(&wd, 0, sizeof wd);
    wd.precision = 12;
    mm_error err;
    memset(&err, 0, sizeof err);
    char *text = NULL;
    size_t size = 0;
    assert_int_equal(mm_bvh_write(&clip, &wd, &text, &size, &err), MM_OK);
    char *streamed = NULL;
    size_t streamed_size = 0;
    FILE *f = open_memstream(&streamed, &streamed_size);
    assert_non_null(f);
    mm_bvh_stream *st = NULL;
    assert_int_equal(mm_bvh_stream_open(&st, f, &clip.skeleton, clip.fps, frames, &wd, &err), MM_OK);
    size_t longest = 0, line_start = 0;
    for (int k = 0; k < frames; ++k)
        assert_int_equal(
            mm_bvh_stream_frame(st, mm_clip_rotations(&clip, k), mm_clip_positions(&clip, k), &err), MM_OK);
    /* one more than declared is refused */
    assert_int_equal(mm_bvh_stream_frame(st, mm_clip_rotations(&clip, 0), mm_clip_positions(&clip, 0), &err),
                     MM_ERR_LIMIT);
    assert_int_equal(mm_bvh_stream_close(st, &err), MM_OK);
    fclose(f);
    assert_int_equal(streamed_size, size);
    assert_memory_equal(streamed, text, size);
    /* no frame line is longer than mm_bvh_frame_bytes_max says */
    const char *motion = strstr(text, "Frame Time:");
    assert_non_null(motion);
    line_start = (size_t)(strchr(motion, '\n') + 1 - text);
    for (size_t i = line_start; i < size; ++i)
        if (text[i] == '\n') {
            longest = i + 1 - line_start > longest ? i + 1 - line_start : longest;
            line_start = i + 1;
        }
    assert_true(longest > 0 && longest <= mm_bvh_frame_bytes_max(&clip.skeleton, &wd));
    free(streamed);
    /* fewer frames than declared: close says so */
    streamed = NULL;
    f = open_memstream(&streamed, &streamed_size);
    assert_int_equal(mm_bvh_stream_open(&st, f, &clip.skeleton, clip.fps, 5, &wd, &err), MM_OK);
    assert_int_equal(mm_bvh_stream_frame(st, mm_clip_rotations(&clip, 0), mm_clip_positions(&clip, 0), &err),
                     MM_OK);
    assert_int_equal(mm_bvh_stream_close(st, &err), MM_ERR_UNEXPECTED_EOF);
    assert_non_null(strstr(err.message, "1 of the 5 frames"));
    fclose(f);
    free(streamed);
    mm_free(NULL, text);
    mm_clip_free(&clip);
    mm_clip_free(&one);
    mm_bvh_free(&src);
}

/* Output does not depend on the process locale (a locale with a decimal comma, if installed). */
static void test_locale_independent(void **state)
{
    (void)state;
    mm_bvh src;
    assert_int_equal(mm_bvh_load(test_data_path("bvh/mobu_style.bvh"), NULL, &src, NULL), MM_OK);
    mm_clip clip;
    assert_int_equal(mm_bvh_to_clip(&src, NULL, &clip, NULL), MM_OK);
    char *a, *b;
    size_t na, nb;
    assert_int_equal(mm_bvh_write(&clip, NULL, &a, &na, NULL), MM_OK);
    const char *locales[] = {"de_DE.UTF-8", "fr_FR.UTF-8", "de_DE", "ru_RU.UTF-8"};
    int changed = 0;
    for (size_t i = 0; i < 4 && !changed; ++i) changed = setlocale(LC_NUMERIC, locales[i]) != NULL;
    if (!changed) {
        mm_free(NULL, a);
        mm_clip_free(&clip);
        mm_bvh_free(&src);
        skip();
    }
    assert_int_equal(mm_bvh_write(&clip, NULL, &b, &nb, NULL), MM_OK);
    mm_bvh back;
    assert_int_equal(mm_bvh_parse(a, na, NULL, &back, NULL), MM_OK);
    setlocale(LC_NUMERIC, "C");
    assert_int_equal(na, nb);
    assert_memory_equal(a, b, na);
    mm_bvh_free(&back);
    mm_free(NULL, a);
    mm_free(NULL, b);
    mm_clip_free(&clip);
    mm_bvh_free(&src);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_round_trip_all_orders), cmocka_unit_test(test_breadth_first_skeleton),
        cmocka_unit_test(test_save_atomic),           cmocka_unit_test(test_stream),
        cmocka_unit_test(test_locale_independent),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
