/* The fast number scanner (src/io/numscan.c) against strtod: edge cases, 200k deterministic
 * pseudo-random decimals, and, when MM_DATA_DIR is set, every number in the motion capture. The
 * scanner must give bit-identical values and stop where strtod stops, on every decimal. */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <locale.h>
#include <math.h>

#include "io/numscan.h"
#include "test_util.h"

static int same_bits(double a, double b) { return memcmp(&a, &b, sizeof a) == 0; }

/* Scans s (exactly strlen(s) bytes in a heap copy, so reading past the end is caught under
 * AddressSanitizer); returns the status, the value and how many characters were used. */
static mm__scan_status scan(const char *s, double *value, size_t *used)
{
    size_t n = strlen(s);
    char *copy = (char *)malloc(n ? n : 1);
    assert_non_null(copy);
    memcpy(copy, s, n);
    const char *stop = NULL;
    *value = -12345.0;
    mm__scan_status st = mm__scan_double(copy, copy + n, value, &stop);
    assert_true(stop >= copy && stop <= copy + n);
    *used = (size_t)(stop - copy);
    free(copy);
    return st;
}

/* s is a decimal number, possibly followed by other characters: the scanner and strtod (in the C
 * locale) agree on the value, bit for bit, and on where the number ends. Returns 1 if they do. */
static int agrees_with_strtod(const char *s)
{
    char *end = NULL;
    double expected = strtod(s, &end);
    double got;
    size_t used;
    mm__scan_status st = scan(s, &got, &used);
    if (!isfinite(expected)) {
        if (st == MM__SCAN_NOT_FINITE) return 1;
        print_error("'%s': strtod gives %g, the scanner status %d\n", s, expected, (int)st);
        return 0;
    }
    if (st != MM__SCAN_OK || !same_bits(got, expected) || used != (size_t)(end - s)) {
        print_error("'%s': strtod %.17g (%zu chars), scanner status %d %.17g (%zu chars)\n", s, expected,
                    (size_t)(end - s), (int)st, got, used);
        return 0;
    }
    return 1;
}

static void test_edge_cases(void **state)
{
    (void)state;
    static const char *const cases[] = {
        /* forms */
        "0", "1", "-1", "+1", "-0", "+0", "-0.0", "0.0", ".5", "-.5", "+.5", "5.", "-5.", "0.", "00012.5000",
        "1e5", "1E5", "1e+5", "1e-5", "1.5E-05", "-2.5e+10", "0e0", "-0e-999", "0.000e12", "12.34 ",
        "12.34\t5", "12.34\n", "12.34\r\n",
        /* stops where strtod stops */
        "1e", "1e+", "1E-", "1.5.3", "1..2", "1x", "2.5e3.7", "-1-2", "3e5e5", "1,5",
        /* 19, 20 and 25 significant digits, around 2^53 and 2^64 */
        "1234567890123456789", "9999999999999999999", "12345678901234567890", "18446744073709551615",
        "18446744073709551616", "1234567890123456789012345", "0.1234567890123456789",
        "0.12345678901234567890123", "1.234567890123456789012345e-5", "9007199254740992", "9007199254740993",
        "9007199254740993.0000000001", "-9007199254740991", "123456789012345678.5",
        "0.000000000000000000000000000001", "100000000000000000000000", "10000000000000000000000.5",
        /* Clinger's fast path limits and values that need the slow path */
        "1e22", "1e23", "9007199254740992e22", "9007199254740993e22", "1e-22", "1e-23", "123456e-22", "0.1",
        "0.2", "0.3", "0.30000000000000004", "2.675", "1.005", "4.35", "0.000001", "123.456e-300",
        "8.98846567431158e307", "2.2250738585072012e-308", "2.2250738585072011e-308",
        "2.2250738585072014e-308", "1.7976931348623157e308", "1.7976931348623158e308",
        /* denormals and underflow */
        "4.9406564584124654e-324", "5e-324", "2.4703282292062328e-324", "2.4703282292062327e-324", "1e-320",
        "1e-400", "-1e-400", "2.225073858507201e-308", "3e-310",
        /* overflow */
        "1e308", "1.8e308", "1e309", "-1e309", "1e999", "1e99999999999",
        "179769313486231580793728971405303415"
        "0799341327100378269361737789804449682927647509466490179775872070963302864166928879109465555478519404"
        "02"
        "6306574886715058206819089020007083836762738548458177115317644757302700698555713669596228429148198608"
        "34"
        "936475292719074168444365510704342711559699508093042880177904174497792",
        /* typical BVH */
        "-0.000000", "90.000000", "-179.999999", "0.0333333", ".0083333", "1.52587890625e-05", "-89.9999"};
    int bad = 0;
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) bad += !agrees_with_strtod(cases[i]);
    assert_int_equal(bad, 0);

    double v;
    size_t used;
    /* -0 keeps its sign. */
    assert_int_equal(scan("-0", &v, &used), MM__SCAN_OK);
    assert_true(v == 0.0 && signbit(v));
    assert_int_equal(scan("-0.000e5", &v, &used), MM__SCAN_OK);
    assert_true(v == 0.0 && signbit(v));
}

static void test_rejections(void **state)
{
    (void)state;
    double v;
    size_t used;
    static const char *const not_finite[] = {"nan",   "NaN",    "-nan",     "+NAN",     "inf",
                                             "-inf",  "+Inf",   "INFINITY", "infinity", "nan(0x1)",
                                             "1e309", "-1e999", "1.8e308"};
    for (size_t i = 0; i < sizeof not_finite / sizeof not_finite[0]; ++i) {
        if (scan(not_finite[i], &v, &used) != MM__SCAN_NOT_FINITE) {
            print_error("'%s' is not rejected as non-finite\n", not_finite[i]);
            fail();
        }
    }
    static const char *const not_a_number[] = {"",    ".",  "-",   "+",   "-.",  "+.e5", "e5", "E",
                                               "abc", " 1", "\t1", "--1", "+-1", ".e1",  "x1", "\n"};
    for (size_t i = 0; i < sizeof not_a_number / sizeof not_a_number[0]; ++i) {
        if (scan(not_a_number[i], &v, &used) != MM__SCAN_NOT_A_NUMBER) {
            print_error("'%s' is not rejected as not a number\n", not_a_number[i]);
            fail();
        }
    }
    /* Hexadecimal is not BVH: the scanner reads the "0" and stops (strtod would read it all). */
    assert_int_equal(scan("0x1p3", &v, &used), MM__SCAN_OK);
    assert_true(v == 0.0 && used == 1);
}

static void test_bounds(void **state)
{
    (void)state;
    /* Never reads past end, even in the middle of a number. */
    const char *s = "12345.678e9";
    for (size_t n = 1; n <= strlen(s); ++n) {
        char buf[32];
        memcpy(buf, s, n);
        buf[n] = 0;
        assert_true(agrees_with_strtod(buf));
    }

    /* Up to MM__SCAN_MAX_CHARS characters are converted exactly, however they must be; a longer
     * number that needs strtod is refused as too long. */
    char big[MM__SCAN_MAX_CHARS + 8];
    big[0] = '0';
    big[1] = '.';
    memset(big + 2, '3', MM__SCAN_MAX_CHARS - 2);
    big[MM__SCAN_MAX_CHARS] = 0;
    assert_true(agrees_with_strtod(big));
    big[MM__SCAN_MAX_CHARS] = '3';
    big[MM__SCAN_MAX_CHARS + 1] = 0;
    double v;
    size_t used;
    assert_int_equal(scan(big, &v, &used), MM__SCAN_TOO_LONG);
    /* Long numbers that need no strtod (zeros) are fine at any length. */
    memset(big, '0', MM__SCAN_MAX_CHARS + 4);
    big[MM__SCAN_MAX_CHARS + 4] = 0;
    assert_true(agrees_with_strtod(big));
    big[MM__SCAN_MAX_CHARS + 3] = '7';
    assert_true(agrees_with_strtod(big));
}

static void test_int64(void **state)
{
    (void)state;
    static const struct {
        const char *s;
        mm__scan_status st;
        int64_t value;
        size_t used;
    } cases[] = {
        {"0", MM__SCAN_OK, 0, 1},
        {"-0", MM__SCAN_OK, 0, 2},
        {"+7", MM__SCAN_OK, 7, 2},
        {"-5", MM__SCAN_OK, -5, 2},
        {"12a", MM__SCAN_OK, 12, 2},
        {"3.5", MM__SCAN_OK, 3, 1},
        {"2147483648", MM__SCAN_OK, INT64_C(2147483648), 10},
        {"9223372036854775807", MM__SCAN_OK, INT64_MAX, 19},
        {"-9223372036854775807", MM__SCAN_OK, -INT64_MAX, 20},
        {"9223372036854775808", MM__SCAN_NOT_FINITE, 0, 19},
        {"-9223372036854775808", MM__SCAN_NOT_FINITE, 0, 20},
        {"36893488147419103238", MM__SCAN_NOT_FINITE, 0, 20}, /* 2 * 2^64 + 6 must not wrap to 6 */
        {"99999999999999999999999", MM__SCAN_NOT_FINITE, 0, 23},
        {"", MM__SCAN_NOT_A_NUMBER, 0, 0},
        {"-", MM__SCAN_NOT_A_NUMBER, 0, 1},
        {"x", MM__SCAN_NOT_A_NUMBER, 0, 1},
        {".5", MM__SCAN_NOT_A_NUMBER, 0, 2},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        size_t n = strlen(cases[i].s);
        char *copy = (char *)malloc(n + 1);
        assert_non_null(copy);
        memcpy(copy, cases[i].s, n);
        int64_t v = -1;
        const char *stop = NULL;
        mm__scan_status st = mm__scan_int64(copy, copy + n, &v, &stop);
        if (st != cases[i].st || (st == MM__SCAN_OK && v != cases[i].value) ||
            (size_t)(stop - copy) != cases[i].used) {
            print_error("'%s': status %d value %lld used %zu\n", cases[i].s, (int)st, (long long)v,
                        (size_t)(stop - copy));
            fail();
        }
        free(copy);
    }
}

static void append_digits(test_rng *rng, char *buf, size_t *n, int count)
{
    for (int i = 0; i < count; ++i) buf[(*n)++] = (char)('0' + test_rng_next(rng) % 10);
}

/* One pseudo-random decimal: all the shapes the grammar allows, biased towards BVH-like ones. */
static void random_decimal(test_rng *rng, char *buf)
{
    size_t n = 0;
    uint64_t kind = test_rng_next(rng) % 8;
    if (kind < 3) { /* printf of a random double at a random precision */
        double mag = pow(10.0, test_rng_uniform(rng, -8, 8));
        double v = test_rng_uniform(rng, -mag, mag);
        if (kind == 0)
            snprintf(buf, 64, "%.*f", (int)(test_rng_next(rng) % 10), v);
        else if (kind == 1)
            snprintf(buf, 64, "%.*g", 1 + (int)(test_rng_next(rng) % 17), v);
        else
            snprintf(buf, 64, "%.17g", v * pow(10.0, test_rng_uniform(rng, -300, 300)));
        return;
    }
    uint64_t r = test_rng_next(rng);
    if (r % 3 == 0)
        buf[n++] = '-';
    else if (r % 7 == 0)
        buf[n++] = '+';
    int int_digits = (int)(test_rng_next(rng) % 26);
    int frac_digits = (int)(test_rng_next(rng) % 26);
    if (kind == 3 && test_rng_next(rng) % 2) { /* leading zeros */
        int z = 1 + (int)(test_rng_next(rng) % 20);
        for (int i = 0; i < z; ++i) buf[n++] = '0';
    }
    append_digits(rng, buf, &n, int_digits);
    int dot = frac_digits > 0 || test_rng_next(rng) % 4 == 0;
    if (dot) buf[n++] = '.';
    append_digits(rng, buf, &n, frac_digits);
    if (int_digits == 0 && (!dot || frac_digits == 0)) buf[n++] = (char)('0' + test_rng_next(rng) % 10);
    if (kind >= 6) {
        buf[n++] = test_rng_next(rng) % 2 ? 'e' : 'E';
        uint64_t s = test_rng_next(rng) % 3;
        if (s == 1)
            buf[n++] = '-';
        else if (s == 2)
            buf[n++] = '+';
        int ed = 1 + (int)(test_rng_next(rng) % 3);
        append_digits(rng, buf, &n, ed);
    }
    buf[n] = 0;
}

static void test_random_decimals(void **state)
{
    (void)state;
    test_rng rng = {0x2545F4914F6CDD1Du};
    char buf[128];
    int bad = 0;
    for (int i = 0; i < 200000; ++i) {
        random_decimal(&rng, buf);
        if (!agrees_with_strtod(buf) && ++bad > 20) break;
    }
    assert_int_equal(bad, 0);
}

static void test_comma_locale(void **state)
{
    (void)state;
    static const char *const locales[] = {"de_DE.UTF-8", "de_DE.utf8", "fr_FR.UTF-8", "fr_FR.utf8",
                                          "ru_RU.UTF-8"};
    const char *used_locale = NULL;
    for (size_t i = 0; i < sizeof locales / sizeof locales[0] && !used_locale; ++i)
        if (setlocale(LC_NUMERIC, locales[i])) used_locale = locales[i];
    if (!used_locale || strcmp(localeconv()->decimal_point, ",") != 0) {
        setlocale(LC_NUMERIC, "C");
        skip();
    }
    /* The slow path still reads '.' whatever the locale. */
    double v;
    size_t used;
    mm__scan_status st = scan("1.2345678901234567890123e-5", &v, &used);
    setlocale(LC_NUMERIC, "C");
    assert_int_equal(st, MM__SCAN_OK);
    assert_true(same_bits(v, strtod("1.2345678901234567890123e-5", NULL)));
}

/* Every whitespace-separated token of a file that starts like a number. */
static long check_file_numbers(const char *path, long *mismatches)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    fseek(f, 0, SEEK_END);
    long size = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *data = (char *)malloc((size_t)size + 1);
    assert_non_null(data);
    assert_int_equal(fread(data, 1, (size_t)size, f), (size_t)size);
    fclose(f);
    data[size] = 0;
    long count = 0;
    char *p = data, *end = data + size;
    while (p < end) {
        while (p < end && (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n')) ++p;
        char *t = p;
        while (p < end && *p != ' ' && *p != '\t' && *p != '\r' && *p != '\n') ++p;
        if (p == t) continue;
        char c = *t;
        if (!((c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.')) continue;
        char saved = *p;
        *p = 0;
        char *e = NULL;
        double expected = strtod(t, &e);
        double got = 0;
        const char *stop = NULL;
        mm__scan_status st = mm__scan_double(t, p, &got, &stop);
        if (st != MM__SCAN_OK || stop != e || !same_bits(got, expected)) {
            if (++*mismatches <= 10)
                print_error("%s: '%s' strtod %.17g, scanner %.17g\n", path, t, expected, got);
        }
        *p = saved;
        ++count;
    }
    free(data);
    return count;
}

static long check_folder(const char *dir_path, long *files, long *mismatches)
{
    DIR *dir = opendir(dir_path);
    if (!dir) return 0;
    long count = 0;
    struct dirent *d;
    while ((d = readdir(dir)) != NULL) {
        size_t len = strlen(d->d_name);
        if (len < 5 || strcmp(d->d_name + len - 4, ".bvh") != 0) continue;
        char path[2048];
        snprintf(path, sizeof path, "%s/%s", dir_path, d->d_name);
        count += check_file_numbers(path, mismatches);
        ++*files;
    }
    closedir(dir);
    return count;
}

static void test_data_files(void **state)
{
    (void)state;
    char buf[1024];
    if (!test_shared_data("", buf, sizeof buf)) skip();
    static const char *const folders[] = {"lafan1", "games105", "pfnn/bvh"};
    long files = 0, numbers = 0, mismatches = 0;
    for (size_t i = 0; i < sizeof folders / sizeof folders[0]; ++i) {
        char dir[1024];
        test_shared_data(folders[i], dir, sizeof dir);
        numbers += check_folder(dir, &files, &mismatches);
    }
    print_message("%ld numbers in %ld files, %ld mismatches\n", numbers, files, mismatches);
    assert_true(files > 0);
    assert_int_equal(mismatches, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_edge_cases),      cmocka_unit_test(test_rejections),
        cmocka_unit_test(test_bounds),          cmocka_unit_test(test_int64),
        cmocka_unit_test(test_random_decimals), cmocka_unit_test(test_comma_locale),
        cmocka_unit_test(test_data_files),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
