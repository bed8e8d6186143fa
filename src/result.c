#include <mm/result.h>

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

const char *mm_result_str(mm_result r)
{
    switch (r) {
#define MM__RESULT_TEXT(code, text)                                                                          \
    case code:                                                                                               \
        return text;
        MM_RESULT_LIST(MM__RESULT_TEXT)
#undef MM__RESULT_TEXT
    default:
        return "unknown result code";
    }
}

const char *mm_result_name(mm_result r)
{
    switch (r) {
#define MM__RESULT_NAME(code, text)                                                                          \
    case code:                                                                                               \
        return #code;
        MM_RESULT_LIST(MM__RESULT_NAME)
#undef MM__RESULT_NAME
    default:
        return "MM_ERR_UNKNOWN";
    }
}

mm_result mm_error_set(mm_error *err, mm_result code, int line, int column, const char *fmt, ...)
{
    if (!err) return code;
    err->code = code;
    err->line = line;
    err->column = column;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err->message, sizeof err->message, fmt, ap);
    va_end(ap);
    return code;
}

void mm_error_format(const mm_error *err, char *buf, size_t size)
{
    if (!buf || size == 0) return;
    buf[0] = 0;
    if (!err) return;
    const char *msg = err->message[0] ? err->message : mm_result_str(err->code);
    const char *file = err->file[0] ? err->file : NULL;
    if (file && err->line > 0 && err->column > 0)
        snprintf(buf, size, "%s:%d:%d: %s", file, err->line, err->column, msg);
    else if (file && err->line > 0)
        snprintf(buf, size, "%s:%d: %s", file, err->line, msg);
    else if (file)
        snprintf(buf, size, "%s: %s", file, msg);
    else if (err->line > 0)
        snprintf(buf, size, "line %d, column %d: %s", err->line, err->column, msg);
    else
        snprintf(buf, size, "%s", msg);
}
