#include "io/numscan.h"

#include <locale.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static const double pow10_exact[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                       1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

static int is_digit(char c) { return c >= '0' && c <= '9'; }

static const char *token_end(const char *p, const char *end)
{
    while (p < end && *p != ' ' && *p != '\t' && *p != '\r' && *p != '\n') ++p;
    return p;
}

/* Slow path: strtod on a zero-terminated copy, with '.' replaced by the locale's decimal point
 * so the result does not depend on the process locale. */
static mm__scan_status scan_with_strtod(const char *start, const char *stop, double *out)
{
    char buf[MM__SCAN_MAX_CHARS + 8];
    size_t n = (size_t)(stop - start);
    if (n > MM__SCAN_MAX_CHARS) return MM__SCAN_TOO_LONG;
    memcpy(buf, start, n);
    buf[n] = 0;
    const char *dp = localeconv()->decimal_point;
    if (dp && dp[0] && dp[0] != '.' && dp[1] == 0) {
        char *dot = strchr(buf, '.');
        if (dot) *dot = dp[0];
    }
    char *e = NULL;
    double v = strtod(buf, &e);
    if (e != buf + n) return MM__SCAN_NOT_A_NUMBER;
    if (!isfinite(v)) return MM__SCAN_NOT_FINITE;
    *out = v;
    return MM__SCAN_OK;
}

mm__scan_status mm__scan_double(const char *p, const char *end, double *out, const char **out_end)
{
    const char *start = p;
    int negative = 0;
    if (p < end && (*p == '+' || *p == '-')) negative = *p++ == '-';

    uint64_t mantissa = 0;
    int digits = 0;    /* significant digits accumulated into mantissa */
    int dropped = 0;   /* significant integer digits beyond 19, not accumulated */
    int any_digit = 0; /* at least one digit in the integer or fraction part */
    int exponent = 0;  /* decimal exponent applied to mantissa */
    int truncated = 0; /* non-zero digits were dropped: the fast path cannot be exact */

    for (; p < end && is_digit(*p); ++p) {
        any_digit = 1;
        if (digits < 19) {
            mantissa = mantissa * 10 + (uint64_t)(*p - '0');
            if (mantissa) ++digits;
        } else {
            ++dropped;
            truncated |= *p != '0';
        }
    }
    exponent = dropped;
    if (p < end && *p == '.') {
        ++p;
        for (; p < end && is_digit(*p); ++p) {
            any_digit = 1;
            if (digits < 19) {
                mantissa = mantissa * 10 + (uint64_t)(*p - '0');
                if (mantissa) ++digits;
                --exponent;
            } else {
                truncated |= *p != '0';
            }
        }
    }
    if (!any_digit) {
        *out_end = token_end(start, end);
        const char *q = start + (start < end && (*start == '+' || *start == '-'));
        if (q < end && (*q == 'n' || *q == 'N' || *q == 'i' || *q == 'I')) return MM__SCAN_NOT_FINITE;
        return MM__SCAN_NOT_A_NUMBER;
    }
    if (p < end && (*p == 'e' || *p == 'E')) {
        const char *q = p + 1;
        int eneg = 0;
        if (q < end && (*q == '+' || *q == '-')) eneg = *q++ == '-';
        if (q < end && is_digit(*q)) {
            int e = 0;
            for (; q < end && is_digit(*q); ++q)
                if (e < 100000) e = e * 10 + (*q - '0');
            exponent += eneg ? -e : e;
            p = q;
        }
        /* "1e" or "1e+" without digits: strtod stops before the 'e'; so does this scanner, and
         * the caller then sees an unexpected character after the number. */
    }
    *out_end = p;

    if (mantissa == 0) {
        *out = negative ? -0.0 : 0.0;
        return MM__SCAN_OK;
    }
    if (!truncated && mantissa <= (UINT64_C(1) << 53) && exponent >= -22 && exponent <= 22) {
        double v = (double)mantissa;
        v = exponent < 0 ? v / pow10_exact[-exponent] : v * pow10_exact[exponent];
        *out = negative ? -v : v;
        return MM__SCAN_OK;
    }
    return scan_with_strtod(start, p, out);
}

mm__scan_status mm__scan_int64(const char *p, const char *end, int64_t *out, const char **out_end)
{
    const char *start = p;
    int negative = 0;
    if (p < end && (*p == '+' || *p == '-')) negative = *p++ == '-';
    if (p >= end || !is_digit(*p)) {
        *out_end = token_end(start, end);
        return MM__SCAN_NOT_A_NUMBER;
    }
    /* Magnitudes up to INT64_MAX; checked before each step so v never wraps. */
    uint64_t v = 0;
    for (; p < end && is_digit(*p); ++p) {
        uint64_t d = (uint64_t)(*p - '0');
        if (v > ((uint64_t)INT64_MAX - d) / 10) {
            *out_end = token_end(start, end);
            return MM__SCAN_NOT_FINITE;
        }
        v = v * 10 + d;
    }
    *out_end = p;
    *out = negative ? -(int64_t)v : (int64_t)v;
    return MM__SCAN_OK;
}
