#include "io/json_parse.h"

mm_result mm__json_parse(const char *text, size_t size, cJSON **out, mm_error *err)
{
    const char *end = NULL;
    *out = text && size ? cJSON_ParseWithLengthOpts(text, size, &end, 0) : NULL;
    if (*out) return MM_OK;
    if (!text || size == 0) return mm_error_set(err, MM_ERR_UNEXPECTED_EOF, 0, 0, "the file is empty");
    int line = 1, column = 1;
    for (const char *p = text; end && p < end && p < text + size; ++p) {
        if (*p == '\n') {
            ++line;
            column = 1;
        } else {
            ++column;
        }
    }
    return mm_error_set(err, MM_ERR_SYNTAX, line, column, "not valid JSON here");
}
