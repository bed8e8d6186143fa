/* Every BVH file of the shared motion capture ($MM_DATA_DIR): read, convert, write in two
 * rotation orders and read back; world positions agree within 1e-3 file units everywhere.
 * Skipped when MM_DATA_DIR is unset. */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <math.h>

#include <mm/bvh.h>

#include "test_util.h"

static double max_position_error(const mm_bvh *a, const mm_bvh *b)
{
    int n = a->skeleton.joint_count;
    double *pa = malloc(sizeof(double) * 3 * n), *pb = malloc(sizeof(double) * 3 * n);
    double worst = 0;
    for (int f = 0; f < a->frame_count; ++f) {
        assert_int_equal(mm_bvh_fk(a, f, pa), MM_OK);
        assert_int_equal(mm_bvh_fk(b, f, pb), MM_OK);
        for (int k = 0; k < 3 * n; ++k) worst = fmax(worst, fabs(pa[k] - pb[k]));
    }
    free(pa);
    free(pb);
    return worst;
}

/* Checks every .bvh in folder; returns how many were checked. */
static int check_folder(const char *folder, int expect_joints)
{
    char dir[1024];
    if (!test_shared_data(folder, dir, sizeof dir)) return -1;
    DIR *d = opendir(dir);
    if (!d) return 0;
    int checked = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        size_t len = strlen(e->d_name);
        if (len < 5 || strcmp(e->d_name + len - 4, ".bvh") != 0) continue;
        char path[2048];
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        mm_bvh src;
        mm_error err;
        memset(&err, 0, sizeof err);
        mm_result r = mm_bvh_load(path, NULL, &src, &err);
        if (r != MM_OK) print_error("%s: %s\n", path, err.message);
        assert_int_equal(r, MM_OK);
        assert_int_equal(src.skeleton.joint_count, expect_joints);
        assert_true(src.frame_count >= 1);
        mm_clip clip;
        assert_int_equal(mm_bvh_to_clip(&src, NULL, &clip, &err), MM_OK);
        const mm_euler_order orders[2] = {MM_EULER_NONE, MM_EULER_XYZ};
        for (int o = 0; o < 2; ++o) {
            mm_bvh_write_desc wd;
            memset(&wd, 0, sizeof wd);
            wd.order = orders[o];
            char *text;
            size_t size;
            assert_int_equal(mm_bvh_write(&clip, &wd, &text, &size, &err), MM_OK);
            mm_bvh back;
            assert_int_equal(mm_bvh_parse(text, size, NULL, &back, &err), MM_OK);
            double worst = max_position_error(&src, &back);
            print_message("%-32s order %-4s frames %5d  max position error %.3g\n", e->d_name,
                          orders[o] ? mm_euler_order_name(orders[o]) : "file", src.frame_count, worst);
            assert_true(worst < 1e-3);
            mm_bvh_free(&back);
            mm_free(NULL, text);
        }
        mm_clip_free(&clip);
        mm_bvh_free(&src);
        ++checked;
    }
    closedir(d);
    return checked;
}

static void test_lafan1(void **state)
{
    (void)state;
    int n = check_folder("lafan1", 22);
    if (n < 0) skip();
    assert_true(n >= 1);
}

static void test_games105(void **state)
{
    (void)state;
    int n = check_folder("games105", 20);
    if (n < 0) skip();
    assert_true(n >= 1);
}

static void test_pfnn(void **state)
{
    (void)state;
    int n = check_folder("pfnn/bvh", 31);
    if (n < 0) skip();
    assert_true(n >= 1);
}

int main(void)
{
    TEST_SKIP_WITHOUT_DATA_DIR();
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_lafan1),
        cmocka_unit_test(test_games105),
        cmocka_unit_test(test_pfnn),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
