/* BVH reader on bad input: the hand-written corpus in tests/data/bad (code, position and message of
 * every error, as listed in tests/data/bad/expected.txt), input built in code (deep nesting, too
 * many joints, a 10 MB line, every truncation of a valid file, random mutations), and an
 * allocator that fails at every possible point. Nothing may crash, leak or leave output behind. */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <math.h>

#include <mm/bvh.h>

#include "test_util.h"

/* A small valid file that uses most of the syntax. It ends in a one-character value with no
 * newline, so every proper prefix of it is invalid. */
static const char valid_bvh[] = "HIERARCHY\n"
                                "ROOT Hips\n"
                                "{\n"
                                "\tOFFSET 0 90.5 -1\n"
                                "\tCHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n"
                                "\tJOINT Left Leg\n"
                                "\t{\n"
                                "\t\tOFFSET 10 -45 0\n"
                                "\t\tCHANNELS 3 Zrotation Xrotation Yrotation\n"
                                "\t\tEnd Site\n"
                                "\t\t{\n"
                                "\t\t\tOFFSET 0 -40 .5\n"
                                "\t\t}\n"
                                "\t}\n"
                                "\tJOINT Head{\n"
                                "\t\tOFFSET 0 60 0\n"
                                "\t\tCHANNELS 0\n"
                                "\t}\n"
                                "}\n"
                                "MOTION\n"
                                "Frames: 3\n"
                                "Frame Time: 0.0333333\r\n"
                                "0 90 0 0 0 0 10 -20 30\n"
                                "\n"
                                "1.5 91 -2e-1 5 0 0 0 0 0  \n"
                                "2 92 0 0 0 0 0 0 5";

/* True when every byte of the mm_bvh is zero. */
static int bvh_is_zeroed(const mm_bvh *b)
{
    const unsigned char *p = (const unsigned char *)b;
    for (size_t i = 0; i < sizeof *b; ++i)
        if (p[i]) return 0;
    return 1;
}

/* Parses size bytes from a heap copy of exactly that size, so reads past the end are caught by
 * AddressSanitizer. The output starts filled with garbage to check that failure zeroes it. */
static mm_result parse_exact(const char *text, size_t size, const mm_bvh_read_desc *desc, mm_bvh *out,
                             mm_error *err)
{
    char *copy = size ? (char *)malloc(size) : NULL;
    if (size) {
        assert_non_null(copy);
        memcpy(copy, text, size);
    }
    memset(out, 0xAB, sizeof *out);
    memset(err, 0, sizeof *err);
    mm_result r = mm_bvh_parse(copy, size, desc, out, err);
    free(copy);
    return r;
}

/* Checks what every failure must give: a real error code in err, a message, zeroed output. */
static void assert_clean_failure(mm_result r, const mm_error *err, const mm_bvh *out)
{
    assert_int_not_equal(r, MM_OK);
    assert_true(r > MM_OK && r < MM_RESULT_COUNT);
    assert_int_equal(err->code, r);
    assert_true(err->message[0] != 0);
    assert_true(err->line >= 0 && err->column >= 0);
    assert_true(bvh_is_zeroed(out));
}

/* ---- the corpus ---------------------------------------------------------------------------- */

typedef struct manifest_entry {
    char file[128];
    char code[64];
    int line, column;
    char message[256];
} manifest_entry;

/* Reads expected.txt; lines starting with '#' and blank lines are comments. */
static int read_manifest(manifest_entry *entries, int max)
{
    FILE *f = fopen(test_data_path("bad/expected.txt"), "rb");
    assert_non_null(f);
    char line[512];
    int n = 0, line_no = 0;
    while (fgets(line, sizeof line, f)) {
        ++line_no;
        size_t len = strlen(line);
        while (len && (line[len - 1] == '\n' || line[len - 1] == '\r')) line[--len] = 0;
        if (len == 0 || line[0] == '#') continue;
        assert_true(n < max);
        manifest_entry *e = &entries[n];
        int consumed = 0;
        if (sscanf(line, "%127s %63s %d %d %n", e->file, e->code, &e->line, &e->column, &consumed) != 4 ||
            consumed == 0 || line[consumed] == 0) {
            print_error("expected.txt:%d: malformed line '%s'\n", line_no, line);
            fail();
        }
        snprintf(e->message, sizeof e->message, "%s", line + consumed);
        ++n;
    }
    fclose(f);
    return n;
}

static int manifest_has(const manifest_entry *entries, int n, const char *file)
{
    for (int i = 0; i < n; ++i)
        if (strcmp(entries[i].file, file) == 0) return 1;
    return 0;
}

static void test_corpus(void **state)
{
    (void)state;
    static manifest_entry entries[256];
    int n = read_manifest(entries, 256);
    assert_true(n >= 24);

    /* Every .bvh in the folder is listed, and nothing is listed twice. */
    DIR *dir = opendir(test_data_path("bad"));
    assert_non_null(dir);
    int files = 0;
    struct dirent *d;
    while ((d = readdir(dir)) != NULL) {
        size_t len = strlen(d->d_name);
        if (len < 5 || strcmp(d->d_name + len - 4, ".bvh") != 0) continue;
        ++files;
        if (!manifest_has(entries, n, d->d_name)) {
            print_error("%s is not listed in expected.txt\n", d->d_name);
            fail();
        }
    }
    closedir(dir);
    assert_int_equal(files, n);

    int failures = 0;
    for (int i = 0; i < n; ++i) {
        const manifest_entry *e = &entries[i];
        char relative[160] = "bad/";
        size_t file_len = strlen(e->file);
        assert_true(file_len < sizeof relative - 4);
        memcpy(relative + 4, e->file, file_len + 1);
        const char *path = test_data_path(relative);

        mm_bvh bvh;
        mm_error err;
        memset(&bvh, 0xAB, sizeof bvh);
        memset(&err, 0, sizeof err);
        mm_result r = mm_bvh_load(path, NULL, &bvh, &err);
        char formatted[700];
        mm_error_format(&err, formatted, sizeof formatted);
        char position[64];
        snprintf(position, sizeof position, ":%d:%d: ", e->line, e->column);

        int ok = r != MM_OK && strcmp(mm_result_name(r), e->code) == 0 && err.code == r &&
                 err.line == e->line && err.column == e->column && strstr(err.message, e->message) &&
                 strstr(formatted, e->file) && strstr(formatted, position) && bvh_is_zeroed(&bvh);
        if (!ok) {
            print_error("%s: expected %s %d %d '%s'\n   got %s %d %d '%s' (formatted: %s)%s\n", e->file,
                        e->code, e->line, e->column, e->message, mm_result_name(r), err.line, err.column,
                        err.message, formatted, bvh_is_zeroed(&bvh) ? "" : " [output not zeroed]");
            ++failures;
        }
        if (r == MM_OK) mm_bvh_free(&bvh);

        /* The same bytes parsed from memory give the same error. */
        FILE *f = fopen(path, "rb");
        assert_non_null(f);
        static char data[8192];
        size_t size = fread(data, 1, sizeof data, f);
        fclose(f);
        mm_bvh_read_desc desc = {0};
        desc.name = e->file;
        mm_error err2;
        r = parse_exact(data, size, &desc, &bvh, &err2);
        assert_clean_failure(r, &err2, &bvh);
        assert_int_equal(err2.code, err.code);
        assert_int_equal(err2.line, err.line);
        assert_int_equal(err2.column, err.column);
        assert_string_equal(err2.message, err.message);
    }
    assert_int_equal(failures, 0);
}

static void test_valid_reference_parses(void **state)
{
    (void)state;
    mm_bvh bvh;
    mm_error err;
    mm_result r = parse_exact(valid_bvh, sizeof valid_bvh - 1, NULL, &bvh, &err);
    if (r != MM_OK) print_error("%d:%d: %s\n", err.line, err.column, err.message);
    assert_int_equal(r, MM_OK);
    assert_int_equal(bvh.skeleton.joint_count, 3);
    assert_string_equal(bvh.skeleton.joints[1].name, "Left Leg");
    assert_string_equal(bvh.skeleton.joints[2].name, "Head");
    assert_int_equal(bvh.channel_count, 9);
    assert_int_equal(bvh.frame_count, 3);
    assert_true(bvh.values[9 + 2] == -0.2);
    assert_true(bvh.values[2 * 9 + 8] == 5.0);
    mm_bvh_free(&bvh);
}

static void test_argument_errors(void **state)
{
    (void)state;
    mm_bvh bvh;
    mm_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_bvh_parse(NULL, 10, NULL, &bvh, &err), MM_ERR_INVALID_ARGUMENT);
    assert_true(bvh_is_zeroed(&bvh));
    assert_int_equal(mm_bvh_parse(valid_bvh, 10, NULL, NULL, &err), MM_ERR_INVALID_ARGUMENT);
    memset(&bvh, 0xAB, sizeof bvh);
    assert_int_equal(mm_bvh_load(test_data_path("bad/no-such-file.bvh"), NULL, &bvh, &err), MM_ERR_IO);
    assert_true(bvh_is_zeroed(&bvh));
    assert_non_null(strstr(err.file, "no-such-file.bvh"));
    /* No error struct: still fails cleanly. */
    assert_int_equal(mm_bvh_parse("HIERARCHY", 9, NULL, &bvh, NULL), MM_ERR_UNEXPECTED_EOF);
    /* In-memory input is named "<memory>" in messages. */
    memset(&err, 0, sizeof err);
    assert_int_equal(mm_bvh_parse("HIERARCHY\nROOT", 14, NULL, &bvh, &err), MM_ERR_SYNTAX);
    char buf[600];
    mm_error_format(&err, buf, sizeof buf);
    assert_non_null(strstr(buf, "<memory>:2:5: "));
}

/* ---- input built in code ------------------------------------------------------------------- */

typedef struct text {
    char *s;
    size_t n, cap;
} text;

static void put(text *t, const char *s)
{
    size_t n = strlen(s);
    if (t->n + n + 1 > t->cap) {
        size_t cap = t->cap ? t->cap : 4096;
        while (cap < t->n + n + 1) cap *= 2;
        char *p = (char *)realloc(t->s, cap);
        assert_non_null(p);
        t->s = p;
        t->cap = cap;
    }
    memcpy(t->s + t->n, s, n + 1);
    t->n += n;
}

/* A chain of `depth` joints each nested in the previous one. */
static text nested_bvh(int depth)
{
    text t = {0};
    put(&t,
        "HIERARCHY\nROOT j0\n{\nOFFSET 0 0 0\nCHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation "
        "Yrotation\n");
    char line[128];
    for (int i = 1; i < depth; ++i) {
        snprintf(line, sizeof line, "JOINT j%d\n{\nOFFSET 0 1 0\nCHANNELS 3 Zrotation Xrotation Yrotation\n",
                 i);
        put(&t, line);
    }
    put(&t, "End Site\n{\nOFFSET 0 1 0\n}\n");
    for (int i = 0; i < depth; ++i) put(&t, "}\n");
    put(&t, "MOTION\nFrames: 1\nFrame Time: 0.5\n");
    for (int i = 0; i < 6 + 3 * (depth - 1); ++i) put(&t, "1 ");
    put(&t, "\n");
    return t;
}

/* A root with `children` leaf joints. */
static text flat_bvh(int children)
{
    text t = {0};
    put(&t, "HIERARCHY\nROOT j0\n{\nOFFSET 0 0 0\nCHANNELS 3 Zrotation Xrotation Yrotation\n");
    char line[96];
    for (int i = 1; i <= children; ++i) {
        snprintf(line, sizeof line, "JOINT j%d\n{\nOFFSET 0 1 0\nCHANNELS 0\n}\n", i);
        put(&t, line);
    }
    put(&t, "}\nMOTION\nFrames: 1\nFrame Time: 0.5\n1 2 3\n");
    return t;
}

/* Line of the first "JOINT j<index>" in t. */
static int line_of_joint(const text *t, int index)
{
    char key[32];
    snprintf(key, sizeof key, "JOINT j%d\n", index);
    const char *at = strstr(t->s, key);
    assert_non_null(at);
    int line = 1;
    for (const char *p = t->s; p < at; ++p) line += *p == '\n';
    return line;
}

/* Hexadecimal (and C99 hex-float) numbers: BVH files never hold them, strtod would take them; every
 * place a number goes refuses them with the line and column of the token. */
static void test_hex_numbers(void **state)
{
    (void)state;
    static const struct {
        const char *find, *replace;
        mm_result code;
        int line, column;
    } cases[] = {
        {"OFFSET 0 90.5 -1", "OFFSET 0x10 90.5 -1", MM_ERR_BAD_NUMBER, 4, 9},
        {"OFFSET 10 -45 0", "OFFSET 10 -0x2D 0", MM_ERR_BAD_NUMBER, 8, 13},
        {"Frames: 3", "Frames: 0x3", MM_ERR_SYNTAX, 21, 9},
        {"Frame Time: 0.0333333", "Frame Time: 0x1p-5", MM_ERR_BAD_NUMBER, 22, 13},
        {"1.5 91 -2e-1", "1.5 0x5B -2e-1", MM_ERR_BAD_NUMBER, 25, 5},
        {"2 92 0 0 0 0 0 0 5", "2 92 0 0 0 0 0 0 0X5", MM_ERR_BAD_NUMBER, 26, 18},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        const char *at = strstr(valid_bvh, cases[i].find);
        assert_non_null(at);
        char buf[sizeof valid_bvh + 32];
        size_t head = (size_t)(at - valid_bvh);
        snprintf(buf, sizeof buf, "%.*s%s%s", (int)head, valid_bvh, cases[i].replace,
                 at + strlen(cases[i].find));
        mm_bvh bvh;
        mm_error err;
        mm_result r = parse_exact(buf, strlen(buf), NULL, &bvh, &err);
        assert_clean_failure(r, &err, &bvh);
        if (r != cases[i].code || err.line != cases[i].line || err.column != cases[i].column)
            print_error("case %zu: %d at %d:%d: %s\n", i, (int)r, err.line, err.column, err.message);
        assert_int_equal(r, cases[i].code);
        assert_int_equal(err.line, cases[i].line);
        assert_int_equal(err.column, cases[i].column);
        assert_non_null(strchr(err.message, 'x') ? strchr(err.message, 'x') : strchr(err.message, 'X'));
    }
}

/* The valid reference as UTF-16 (little and big endian, with and without a byte order mark):
 * refused as UTF-16, not as a garbled keyword. */
static void test_utf16(void **state)
{
    (void)state;
    size_t n = strlen(valid_bvh);
    unsigned char *buf = malloc(2 * n + 2);
    assert_non_null(buf);
    for (int variant = 0; variant < 4; ++variant) {
        int big = variant & 1, bom = variant >> 1;
        size_t size = 0;
        if (bom) {
            buf[size++] = big ? 0xFE : 0xFF;
            buf[size++] = big ? 0xFF : 0xFE;
        }
        for (size_t i = 0; i < n; ++i) {
            buf[size++] = big ? 0 : (unsigned char)valid_bvh[i];
            buf[size++] = big ? (unsigned char)valid_bvh[i] : 0;
        }
        mm_bvh bvh;
        mm_error err;
        mm_result r = parse_exact((const char *)buf, size, NULL, &bvh, &err);
        assert_clean_failure(r, &err, &bvh);
        assert_int_equal(r, MM_ERR_SYNTAX);
        assert_non_null(strstr(err.message, "the file is UTF-16 text"));
    }
    free(buf);
}

static void test_deep_nesting(void **state)
{
    (void)state;
    mm_bvh bvh;
    mm_error err;
    /* 2000 deep: refused at the first joint over the limit, with no recursion to overflow. */
    text t = nested_bvh(2000);
    mm_result r = parse_exact(t.s, t.n, NULL, &bvh, &err);
    assert_clean_failure(r, &err, &bvh);
    assert_int_equal(r, MM_ERR_LIMIT);
    assert_int_equal(err.line, line_of_joint(&t, MM_MAX_JOINTS));
    assert_int_equal(err.column, 1);
    assert_non_null(strstr(err.message, "joints"));
    free(t.s);

    /* Exactly the limit, with an End Site at the bottom, is fine. */
    t = nested_bvh(MM_MAX_JOINTS);
    r = parse_exact(t.s, t.n, NULL, &bvh, &err);
    if (r != MM_OK) print_error("%d:%d: %s\n", err.line, err.column, err.message);
    assert_int_equal(r, MM_OK);
    assert_int_equal(bvh.skeleton.joint_count, MM_MAX_JOINTS);
    assert_true(bvh.skeleton.joints[MM_MAX_JOINTS - 1].has_end_site);
    double *xyz = (double *)malloc(3 * sizeof(double) * MM_MAX_JOINTS);
    assert_non_null(xyz);
    assert_int_equal(mm_bvh_fk(&bvh, 0, xyz), MM_OK);
    free(xyz);
    mm_bvh_free(&bvh);
    free(t.s);
}

static void test_too_many_joints(void **state)
{
    (void)state;
    mm_bvh bvh;
    mm_error err;
    text t = flat_bvh(1099); /* 1100 joints */
    mm_result r = parse_exact(t.s, t.n, NULL, &bvh, &err);
    assert_clean_failure(r, &err, &bvh);
    assert_int_equal(r, MM_ERR_LIMIT);
    assert_int_equal(err.line, line_of_joint(&t, MM_MAX_JOINTS));
    assert_non_null(strstr(err.message, "joints"));
    free(t.s);

    t = flat_bvh(MM_MAX_JOINTS - 1);
    r = parse_exact(t.s, t.n, NULL, &bvh, &err);
    assert_int_equal(r, MM_OK);
    assert_int_equal(bvh.skeleton.joint_count, MM_MAX_JOINTS);
    mm_bvh_free(&bvh);
    free(t.s);
}

static void test_huge_line(void **state)
{
    (void)state;
    const size_t digits = 10u << 20; /* 10 MB */
    const char *head = "HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\nCHANNELS 3 Zrotation Xrotation Yrotation\n}\n"
                       "MOTION\nFrames: 1\nFrame Time: 0.5\n";
    size_t hn = strlen(head);
    char *buf = (char *)malloc(hn + digits + 8);
    assert_non_null(buf);
    mm_bvh bvh;
    mm_error err;

    /* As a motion value. */
    memcpy(buf, head, hn);
    memset(buf + hn, '7', digits);
    memcpy(buf + hn + digits, " 0 0\n", 5);
    mm_result r = parse_exact(buf, hn + digits + 5, NULL, &bvh, &err);
    assert_clean_failure(r, &err, &bvh);
    assert_int_equal(r, MM_ERR_BAD_NUMBER);
    assert_int_equal(err.line, 10);
    assert_int_equal(err.column, 1);
    assert_non_null(strstr(err.message, "too long"));

    /* As a fractional motion value: digits after the point are never dropped silently. */
    memcpy(buf + hn, "0.", 2);
    r = parse_exact(buf, hn + digits + 5, NULL, &bvh, &err);
    assert_clean_failure(r, &err, &bvh);
    assert_int_equal(r, MM_ERR_BAD_NUMBER);

    /* As a joint name. */
    memcpy(buf, "HIERARCHY\nROOT ", 15);
    memset(buf + 15, 'n', digits);
    r = parse_exact(buf, 15 + digits, NULL, &bvh, &err);
    assert_clean_failure(r, &err, &bvh);
    assert_int_equal(r, MM_ERR_LIMIT);
    assert_int_equal(err.line, 2);
    assert_int_equal(err.column, 6);

    /* As an OFFSET value. */
    const char *h2 = "HIERARCHY\nROOT a\n{\nOFFSET ";
    size_t h2n = strlen(h2);
    memcpy(buf, h2, h2n);
    memset(buf + h2n, '3', digits);
    r = parse_exact(buf, h2n + digits, NULL, &bvh, &err);
    assert_clean_failure(r, &err, &bvh);
    assert_int_equal(r, MM_ERR_BAD_NUMBER);
    assert_int_equal(err.line, 4);
    assert_int_equal(err.column, 8);

    /* As the first token: one 10 MB line of digits. */
    memset(buf, '1', digits);
    r = parse_exact(buf, digits, NULL, &bvh, &err);
    assert_clean_failure(r, &err, &bvh);
    assert_int_equal(r, MM_ERR_SYNTAX);
    assert_int_equal(err.line, 1);
    assert_int_equal(err.column, 1);
    free(buf);
}

static void test_every_truncation(void **state)
{
    (void)state;
    size_t n = sizeof valid_bvh - 1;
    mm_bvh bvh;
    mm_error err;
    for (size_t len = 0; len < n; ++len) {
        mm_result r = parse_exact(valid_bvh, len, NULL, &bvh, &err);
        if (r == MM_OK) {
            print_error("prefix of %zu bytes was accepted\n", len);
            fail();
        }
        assert_clean_failure(r, &err, &bvh);
        assert_true(err.line >= 1 && err.column >= 1);
    }
    assert_int_equal(parse_exact(valid_bvh, n, NULL, &bvh, &err), MM_OK);
    mm_bvh_free(&bvh);
}

/* Everything a caller may do with a parsed file; nothing may crash or leak. */
static void exercise(const mm_bvh *bvh, const mm_allocator *allocator)
{
    mm_clip clip;
    mm_error err;
    mm_bvh_import_desc imp = {0};
    imp.allocator = allocator;
    if (mm_bvh_to_clip(bvh, &imp, &clip, &err) == MM_OK) {
        mm_bvh_write_desc wd = {0};
        wd.allocator = allocator;
        char *out = NULL;
        size_t size = 0;
        if (mm_bvh_write(&clip, &wd, &out, &size, &err) == MM_OK) mm_free(allocator, out);
        mm_clip_free(&clip);
    }
    double *xyz = (double *)malloc(3 * sizeof(double) * (size_t)bvh->skeleton.joint_count);
    assert_non_null(xyz);
    if (bvh->frame_count > 0) {
        mm_result r = mm_bvh_fk(bvh, 0, xyz);
        assert_true(r == MM_OK || r == MM_ERR_OUT_OF_MEMORY);
        r = mm_bvh_fk(bvh, bvh->frame_count - 1, xyz);
        assert_true(r == MM_OK || r == MM_ERR_OUT_OF_MEMORY);
    }
    free(xyz);
    (void)mm_bvh_detect_scale(bvh, NULL);
}

static void test_random_mutations(void **state)
{
    (void)state;
    static const char *const dictionary[] = {"{",           "}",           "\n",        " ",
                                             "JOINT x\n",   "End Site",    "OFFSET",    "CHANNELS 6",
                                             "CHANNELS 3",  "Xposition",   "Zrotation", "MOTION",
                                             "Frames:",     "Frame Time:", "1e999",     "nan",
                                             "-",           ".",           "0",         "\0",
                                             "99999999999", "-0.5e-3",     "\r\n",      "\t",
                                             "ROOT y\n"};
    const size_t dict_n = sizeof dictionary / sizeof dictionary[0];
    size_t n = sizeof valid_bvh - 1;
    char *buf = (char *)malloc(4 * n + 256);
    assert_non_null(buf);
    test_rng rng = {0x9E3779B97F4A7C15u};
    int accepted = 0;
    for (int iter = 0; iter < 5000; ++iter) {
        size_t len = n;
        memcpy(buf, valid_bvh, n);
        int edits = 1 + (int)(test_rng_next(&rng) % 4);
        for (int e = 0; e < edits; ++e) {
            size_t at = len ? (size_t)(test_rng_next(&rng) % len) : 0;
            switch (test_rng_next(&rng) % 6) {
            case 0: /* replace a byte with anything */
                if (len) buf[at] = (char)(test_rng_next(&rng) & 0xFF);
                break;
            case 1: /* delete a run */
            {
                size_t k = 1 + (size_t)(test_rng_next(&rng) % 8);
                if (at + k > len) k = len - at;
                memmove(buf + at, buf + at + k, len - at - k);
                len -= k;
            } break;
            case 2: /* insert a random byte */
                if (len < 3 * n) {
                    memmove(buf + at + 1, buf + at, len - at);
                    buf[at] = (char)(test_rng_next(&rng) & 0xFF);
                    ++len;
                }
                break;
            case 3: /* insert a dictionary word */
            {
                const char *w = dictionary[test_rng_next(&rng) % dict_n];
                size_t k = w[0] ? strlen(w) : 1;
                if (len + k < 3 * n) {
                    memmove(buf + at + k, buf + at, len - at);
                    memcpy(buf + at, w, k);
                    len += k;
                }
            } break;
            case 4: /* duplicate a chunk */
            {
                size_t k = 1 + (size_t)(test_rng_next(&rng) % 40);
                if (at + k > len) k = len - at;
                if (len + k < 3 * n) {
                    memmove(buf + at + k, buf + at, len - at);
                    len += k;
                }
            } break;
            default: /* truncate */
                len = at;
                break;
            }
        }
        mm_bvh bvh;
        mm_error err;
        mm_result r = parse_exact(buf, len, NULL, &bvh, &err);
        if (r == MM_OK) {
            ++accepted;
            assert_true(bvh.skeleton.joint_count >= 1 && bvh.channel_count >= 1);
            assert_true(bvh.frame_time > 0 && isfinite(bvh.frame_time));
            for (size_t i = 0; i < (size_t)bvh.frame_count * (size_t)bvh.channel_count; ++i)
                assert_true(isfinite(bvh.values[i]));
            exercise(&bvh, NULL);
            mm_bvh_free(&bvh);
        } else {
            assert_clean_failure(r, &err, &bvh);
        }
    }
    free(buf);
    /* Some mutations (spaces, digits) keep the file valid; most do not. */
    assert_true(accepted > 0 && accepted < 5000);
}

/* ---- failing allocator --------------------------------------------------------------------- */

typedef struct counting_allocator {
    long calls;   /* allocations attempted */
    long fail_at; /* the fail_at-th allocation (1-based) fails; 0: never */
    long live;    /* allocations not yet freed */
} counting_allocator;

static void *counting_alloc(size_t size, void *user)
{
    counting_allocator *c = (counting_allocator *)user;
    if (++c->calls == c->fail_at) return NULL;
    void *p = malloc(size);
    if (p) ++c->live;
    return p;
}

static void counting_free(void *ptr, void *user)
{
    counting_allocator *c = (counting_allocator *)user;
    if (ptr) --c->live;
    free(ptr);
}

/* Loads bvh/chain2.bvh (or parses valid_bvh) and uses it, with an allocator that fails at the
 * k-th allocation; returns the number of allocations attempted. */
static long run_with_failure(long fail_at, int from_file, int *out_failed)
{
    counting_allocator c = {0, fail_at, 0};
    mm_allocator a = {counting_alloc, counting_free, &c};
    mm_bvh_read_desc desc = {0};
    desc.allocator = &a;
    mm_bvh bvh;
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_result r;
    if (from_file) {
        memset(&bvh, 0xAB, sizeof bvh);
        r = mm_bvh_load(test_data_path("bvh/chain2.bvh"), &desc, &bvh, &err);
    } else {
        r = parse_exact(valid_bvh, sizeof valid_bvh - 1, &desc, &bvh, &err);
    }
    *out_failed = 0;
    if (r != MM_OK) {
        assert_int_equal(r, MM_ERR_OUT_OF_MEMORY);
        assert_clean_failure(r, &err, &bvh);
        assert_int_equal(c.live, 0);
        *out_failed = 1;
        return c.calls;
    }
    /* Conversion, forward kinematics and writing through the same allocator. */
    mm_clip clip;
    mm_bvh_import_desc imp = {0};
    imp.allocator = &a;
    r = mm_bvh_to_clip(&bvh, &imp, &clip, &err);
    if (r != MM_OK) {
        assert_int_equal(r, MM_ERR_OUT_OF_MEMORY);
        *out_failed = 1;
    } else {
        mm_bvh_write_desc wd = {0};
        wd.allocator = &a;
        char *out = NULL;
        size_t size = 0;
        r = mm_bvh_write(&clip, &wd, &out, &size, &err);
        if (r != MM_OK) {
            assert_int_equal(r, MM_ERR_OUT_OF_MEMORY);
            assert_null(out);
            *out_failed = 1;
        }
        mm_free(&a, out);
        mm_clip_free(&clip);
    }
    double xyz[3 * 8];
    assert_true(bvh.skeleton.joint_count <= 8);
    r = mm_bvh_fk(&bvh, 0, xyz);
    if (r != MM_OK) {
        assert_int_equal(r, MM_ERR_OUT_OF_MEMORY);
        *out_failed = 1;
    }
    mm_bvh_free(&bvh);
    assert_int_equal(c.live, 0);
    return c.calls;
}

static void test_allocation_failures(void **state)
{
    (void)state;
    for (int from_file = 0; from_file < 2; ++from_file) {
        int failed = 0;
        long total = run_with_failure(0, from_file, &failed);
        assert_false(failed);
        assert_true(total >= 4);
        for (long k = 1; k <= total; ++k) {
            run_with_failure(k, from_file, &failed);
            if (!failed) {
                print_error("allocation %ld of %ld failed but nothing reported it\n", k, total);
                fail();
            }
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_corpus),
        cmocka_unit_test(test_valid_reference_parses),
        cmocka_unit_test(test_argument_errors),
        cmocka_unit_test(test_hex_numbers),
        cmocka_unit_test(test_utf16),
        cmocka_unit_test(test_deep_nesting),
        cmocka_unit_test(test_too_many_joints),
        cmocka_unit_test(test_huge_line),
        cmocka_unit_test(test_every_truncation),
        cmocka_unit_test(test_random_mutations),
        cmocka_unit_test(test_allocation_failures),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
