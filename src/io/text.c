#include "io/text.h"

#include <locale.h>
#include <stdio.h>
#include <string.h>

int mm__format_number(char *buf, size_t size, double v, int precision)
{
    if (v == 0.0) v = 0.0; /* -0 -> 0 */
    int n = snprintf(buf, size, "%.*g", precision, v);
    if (n < 0 || (size_t)n >= size) {
        buf[0] = 0;
        return 0;
    }
    const char *dp = localeconv()->decimal_point;
    if (dp && dp[0] && dp[0] != '.' && dp[1] == 0) {
        char *c = memchr(buf, dp[0], (size_t)n);
        if (c) *c = '.';
    }
    return n;
}
