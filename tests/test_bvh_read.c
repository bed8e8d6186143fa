/* BVH reader on the project's own files: values computed by hand, style variants, conversion. */
#include <math.h>

#include <mm/bvh.h>

#include "test_util.h"

static mm_bvh load_ok(const char *relative)
{
    mm_bvh bvh;
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_result r = mm_bvh_load(test_data_path(relative), NULL, &bvh, &err);
    if (r != MM_OK) {
        char buf[600];
        mm_error_format(&err, buf, sizeof buf);
        print_error("%s\n", buf);
    }
    assert_int_equal(r, MM_OK);
    return bvh;
}

static void assert_joint_at(const double *xyz, int j, double x, double y, double z)
{
    assert_near(xyz[3 * j + 0], x, 1e-12);
    assert_near(xyz[3 * j + 1], y, 1e-12);
    assert_near(xyz[3 * j + 2], z, 1e-12);
}

static void test_chain_by_hand(void **state)
{
    (void)state;
    mm_bvh bvh = load_ok("bvh/chain2.bvh");
    assert_int_equal(bvh.skeleton.joint_count, 2);
    assert_int_equal(bvh.channel_count, 9);
    assert_int_equal(bvh.frame_count, 3);
    assert_near(bvh.frame_time, 0.5, 0);
    assert_string_equal(bvh.skeleton.joints[1].name, "Tip");
    assert_int_equal(bvh.skeleton.joints[0].order, MM_EULER_ZYX);
    assert_int_equal(bvh.skeleton.joints[1].order, MM_EULER_ZXY);
    assert_true(bvh.skeleton.joints[0].flags & MM_JOINT_TRANSLATES);
    assert_false(bvh.skeleton.joints[1].flags & MM_JOINT_TRANSLATES);
    assert_true(bvh.skeleton.joints[1].has_end_site);
    assert_near(bvh.skeleton.joints[1].end_site.z, 2, 0);
    assert_int_equal(bvh.channels[1].first, 6);

    double xyz[6];
    /* Frame 0: the position channels (0 0 0) replace the root OFFSET (1 2 3). */
    assert_int_equal(mm_bvh_fk(&bvh, 0, xyz), MM_OK);
    assert_joint_at(xyz, 0, 0, 0, 0);
    assert_joint_at(xyz, 1, 0, 1, 0);
    /* Frame 1: root at (10,0,0) turned 90 degrees about Z: the tip's +Y offset points to -X. */
    assert_int_equal(mm_bvh_fk(&bvh, 1, xyz), MM_OK);
    assert_joint_at(xyz, 0, 10, 0, 0);
    assert_joint_at(xyz, 1, 9, 0, 0);
    /* Frame 2: a turn about Y leaves the +Y offset alone. */
    assert_int_equal(mm_bvh_fk(&bvh, 2, xyz), MM_OK);
    assert_joint_at(xyz, 1, 0, 6, 0);
    assert_int_equal(mm_bvh_fk(&bvh, 3, xyz), MM_ERR_OUT_OF_RANGE);
    assert_int_equal(mm_bvh_fk(&bvh, -1, xyz), MM_ERR_OUT_OF_RANGE);

    /* The clip agrees with the double-precision reference, including the End Site, whose
     * world position at frame 2 is (0,6,0) + Ry(90) Rx(90) (0,0,2) = (0,4,0). */
    mm_clip clip;
    assert_int_equal(mm_bvh_to_clip(&bvh, NULL, &clip, NULL), MM_OK);
    assert_near(clip.fps, 2.0, 0);
    mm_xform g[2];
    mm_clip_fk(&clip, 2, g);
    assert_near(g[1].translation.y, 6, 1e-6);
    mm_vec3 end = mm_xform_apply_point(g[1], clip.skeleton.joints[1].end_site);
    assert_near(end.x, 0, 1e-6);
    assert_near(end.y, 4, 1e-6);
    assert_near(end.z, 0, 1e-6);
    mm_clip_free(&clip);
    mm_bvh_free(&bvh);
}

/* 6 channels on every joint (MotionBuilder), XYZ order, CRLF, tabs, trailing spaces,
 * "Frame Time: .0333333". */
static void test_motionbuilder_style(void **state)
{
    (void)state;
    mm_bvh bvh = load_ok("bvh/mobu_style.bvh");
    assert_int_equal(bvh.skeleton.joint_count, 3);
    assert_int_equal(bvh.channel_count, 18);
    assert_int_equal(bvh.frame_count, 2);
    assert_near(bvh.frame_time, 0.0333333, 0);
    assert_string_equal(bvh.skeleton.joints[0].name, "Hips");
    for (int j = 0; j < 3; ++j) {
        assert_int_equal(bvh.skeleton.joints[j].order, MM_EULER_XYZ);
        assert_true(bvh.skeleton.joints[j].flags & MM_JOINT_TRANSLATES);
    }
    double xyz[9];
    assert_int_equal(mm_bvh_fk(&bvh, 0, xyz), MM_OK);
    /* Frame 0: hips at (1.5, 90, -2); the spine's position channels (0,12,0) replace its OFFSET
     * (0,10,0); the spine turns 10 degrees about X, so the head (0,50,0) tilts toward +Z. */
    assert_joint_at(xyz, 0, 1.5, 90, -2);
    assert_joint_at(xyz, 1, 1.5, 102, -2);
    assert_near(xyz[7], 102 + 50 * cos(10 * MM_PI / 180), 1e-9);
    assert_near(xyz[8], -2 + 50 * sin(10 * MM_PI / 180), 1e-9);
    /* Frame 1: spine turned 20 degrees about Y leaves the head straight above. */
    assert_int_equal(mm_bvh_fk(&bvh, 1, xyz), MM_OK);
    assert_joint_at(xyz, 2, 2.5, 153, -2);
    mm_bvh_free(&bvh);
}

/* CMU converter style (a take cut from the shared data): 31 joints, 120 fps written as
 * "0.008333", joints without End Sites between others, "Hips" root with ZYX channels. */
static void test_cmu_style(void **state)
{
    (void)state;
    const char *path = test_cmu_take("cmu_read.bvh");
    if (!path) skip();
    mm_bvh bvh;
    assert_int_equal(mm_bvh_load(path, NULL, &bvh, NULL), MM_OK);
    assert_int_equal(bvh.skeleton.joint_count, 31);
    assert_int_equal(bvh.channel_count, 6 + 30 * 3);
    assert_int_equal(bvh.frame_count, CMU_TAKE_FRAMES);
    assert_near(1.0 / bvh.frame_time, 120.0, 0.01);
    assert_int_equal(mm_skeleton_find(&bvh.skeleton, "RThumb"), 30);
    assert_int_equal(bvh.skeleton.joints[mm_skeleton_find(&bvh.skeleton, "LeftUpLeg")].parent,
                     mm_skeleton_find(&bvh.skeleton, "LHipJoint"));
    /* Every value of the last line made it, in order: against strtod on the file's last line. */
    FILE *f = fopen(path, "rb");
    static char line[1 << 16], last[1 << 16];
    while (fgets(line, sizeof line, f)) memcpy(last, line, sizeof line);
    fclose(f);
    char *p = last;
    for (int i = 0; i < bvh.channel_count; ++i) {
        char *end;
        double v = strtod(p, &end);
        assert_true(end != p);
        assert_true(bvh.values[(size_t)(CMU_TAKE_FRAMES - 1) * bvh.channel_count + i] == v);
        p = end;
    }
    mm_bvh_free(&bvh);
}

/* Float clip FK agrees with the double reference on every frame of every project file. */
static void test_clip_matches_reference(void **state)
{
    (void)state;
    const char *files[] = {"bvh/chain2.bvh", "bvh/mobu_style.bvh", test_cmu_take("cmu_fk.bvh")};
    for (size_t i = 0; i < sizeof files / sizeof files[0]; ++i) {
        if (!files[i]) continue; /* no shared data */
        mm_bvh bvh = load_ok(files[i]);
        mm_clip clip;
        assert_int_equal(mm_bvh_to_clip(&bvh, NULL, &clip, NULL), MM_OK);
        int n = bvh.skeleton.joint_count;
        double *xyz = malloc(sizeof(double) * 3 * n);
        mm_xform *g = malloc(sizeof(mm_xform) * n);
        for (int f = 0; f < bvh.frame_count; ++f) {
            assert_int_equal(mm_bvh_fk(&bvh, f, xyz), MM_OK);
            mm_clip_fk(&clip, f, g);
            for (int j = 0; j < n; ++j) {
                assert_near(g[j].translation.x, xyz[3 * j], 1e-4);
                assert_near(g[j].translation.y, xyz[3 * j + 1], 1e-4);
                assert_near(g[j].translation.z, xyz[3 * j + 2], 1e-4);
            }
        }
        free(xyz);
        free(g);
        mm_clip_free(&clip);
        mm_bvh_free(&bvh);
    }
}

static void test_scale_and_units(void **state)
{
    (void)state;
    mm_bvh bvh;
    mm_bvh_import_desc imp;
    memset(&imp, 0, sizeof imp);
    mm_clip clip;
    mm_error err;
    memset(&err, 0, sizeof err);
    double height = 0;
    const char *cmu = test_cmu_take("cmu_units.bvh");
    if (cmu) { /* needs the shared data */
        bvh = load_ok(cmu);
        double scale = mm_bvh_detect_scale(&bvh, &height);
        /* 24.3 units tall: the CMU converter's unit (0.056444 m) gives a human height (1.37 m). */
        assert_true(height > 20 && height < 30);
        assert_near(scale, 0.056444, 1e-9);

        imp.scale = 0.01f;
        assert_int_equal(mm_bvh_to_clip(&bvh, &imp, &clip, NULL), MM_OK);
        double xyz[93];
        assert_int_equal(mm_bvh_fk(&bvh, 2, xyz), MM_OK);
        mm_xform g[31];
        mm_clip_fk(&clip, 2, g);
        assert_near(g[4].translation.y, 0.01 * xyz[13], 1e-6);
        mm_clip_free(&clip);

        imp.scale = -1.0f;
        assert_int_equal(mm_bvh_to_clip(&bvh, &imp, &clip, &err), MM_ERR_OUT_OF_RANGE);
        assert_non_null(strstr(err.message, "scale"));
        mm_bvh_free(&bvh);
    }

    /* The two-joint chain is 1 unit tall at frame 0: metres. */
    bvh = load_ok("bvh/chain2.bvh");
    assert_near(mm_bvh_detect_scale(&bvh, &height), 1.0, 0);
    assert_near(height, 1.0, 1e-6);
    mm_bvh_free(&bvh);

    /* 0.3 units tall: no unit gives a human height, so auto fails with a message. */
    const char small[] =
        "HIERARCHY\nROOT A\n{\nOFFSET 0 0 0\nCHANNELS 3 Zrotation Yrotation Xrotation\n"
        "JOINT B\n{\nOFFSET 0 0.3 0\nCHANNELS 0\n}\n}\nMOTION\nFrames: 1\nFrame Time: 0.1\n0 0 0\n";
    assert_int_equal(mm_bvh_parse(small, sizeof small - 1, NULL, &bvh, NULL), MM_OK);
    assert_near(mm_bvh_detect_scale(&bvh, &height), 0.0, 0);
    assert_near(height, 0.3, 1e-6);
    imp.scale = 0;
    imp.auto_scale = true;
    assert_int_equal(mm_bvh_to_clip(&bvh, &imp, &clip, &err), MM_ERR_OUT_OF_RANGE);
    assert_non_null(strstr(err.message, "unit"));
    mm_bvh_free(&bvh);
}

static void test_parse_from_memory(void **state)
{
    (void)state;
    /* Not zero-terminated: the reader must stop at size. A UTF-8 BOM is skipped. */
    const char text[] =
        "\xEF\xBB\xBFHIERARCHY\nROOT A\n{\nOFFSET 0 0 0\nCHANNELS 3 Yrotation Xrotation Zrotation\n}\n"
        "MOTION\nFrames: 1\nFrame Time: 1\n1 2 3\nGARBAGE";
    mm_bvh bvh;
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_bvh_parse(text, sizeof text - 1 - 8, NULL, &bvh, &err), MM_OK);
    assert_int_equal(bvh.skeleton.joints[0].order, MM_EULER_YXZ);
    assert_near(bvh.values[2], 3, 0);
    mm_bvh_free(&bvh);
    assert_int_equal(mm_bvh_parse(text, sizeof text - 1, NULL, &bvh, &err), MM_ERR_FRAME_COUNT);
    assert_string_equal(err.file, "<memory>");
    assert_int_equal(err.line, 11);
    mm_bvh_read_desc desc = {"walk.bvh", NULL};
    assert_int_equal(mm_bvh_parse(text, sizeof text - 1, &desc, &bvh, &err), MM_ERR_FRAME_COUNT);
    char buf[512];
    mm_error_format(&err, buf, sizeof buf);
    assert_non_null(strstr(buf, "walk.bvh:11:1:"));
}

static void test_missing_file(void **state)
{
    (void)state;
    mm_bvh bvh;
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_bvh_load("/nonexistent/x.bvh", NULL, &bvh, &err), MM_ERR_IO);
    assert_string_equal(err.file, "/nonexistent/x.bvh");
    assert_non_null(strstr(err.message, "No such file"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_chain_by_hand),   cmocka_unit_test(test_motionbuilder_style),
        cmocka_unit_test(test_cmu_style),       cmocka_unit_test(test_clip_matches_reference),
        cmocka_unit_test(test_scale_and_units), cmocka_unit_test(test_parse_from_memory),
        cmocka_unit_test(test_missing_file),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
