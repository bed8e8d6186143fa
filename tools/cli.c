#include "cli.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>

int cli_report(const mm_error *err)
{
    char buf[MM_ERROR_FILE_MAX + MM_ERROR_MESSAGE_MAX + 64];
    mm_error_format(err, buf, sizeof buf);
    fprintf(stderr, "mm: %s\n", buf);
    return 1;
}

int cli_usage_error(const char *command, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "mm %s: ", command);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    return 2;
}

int cli_parse_double(const char *s, double *out)
{
    if (!s || !*s) return 0;
    char *end = NULL;
    errno = 0;
    double v = strtod(s, &end);
    if (*end || errno || !isfinite(v)) return 0;
    *out = v;
    return 1;
}

int cli_parse_int(const char *s, long min, long max, long *out)
{
    if (!s || !*s) return 0;
    char *end = NULL;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (*end || errno || v < min || v > max) return 0;
    *out = v;
    return 1;
}

void cli_json_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s; ++s) {
        unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\')
            fprintf(f, "\\%c", c);
        else if (c < 0x20)
            fprintf(f, "\\u%04x", c);
        else
            fputc(c, f);
    }
    fputc('"', f);
}

int cli_parse_size(const char *s, int *width, int *height)
{
    long w = 0, h = 0;
    char tail = 0;
    if (sscanf(s, "%ldx%ld%c", &w, &h, &tail) != 2 || w < 16 || h < 16 || w > 4096 || h > 4096) return 0;
    *width = (int)w;
    *height = (int)h;
    return 1;
}
