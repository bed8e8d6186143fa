/* mm/result.h - result codes and parse errors shared by every module.
 *
 * Every fallible mm function returns an mm_result. Functions that read input also fill an
 * optional mm_error with the file, the 1-based line and column, and a message, so a user can be
 * told exactly what is wrong and where. mm never aborts on bad input and keeps no global error.
 *
 * Functions: mm_result_str, mm_error_set, mm_error_format
 */
#ifndef MM_RESULT_H
#define MM_RESULT_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* X(code, description) */
#define MM_RESULT_LIST(X)                                                                                    \
    X(MM_OK, "success")                                                                                      \
    X(MM_ERR_INVALID_ARGUMENT, "invalid argument")                                                           \
    X(MM_ERR_OUT_OF_MEMORY, "out of memory")                                                                 \
    X(MM_ERR_IO, "file could not be read or written")                                                        \
    X(MM_ERR_SYNTAX, "syntax error")                                                                         \
    X(MM_ERR_UNEXPECTED_EOF, "unexpected end of input")                                                      \
    X(MM_ERR_UNKNOWN_KEYWORD, "unknown keyword")                                                             \
    X(MM_ERR_BAD_NUMBER, "malformed or non-finite number")                                                   \
    X(MM_ERR_LIMIT, "a declared size exceeds a limit")                                                       \
    X(MM_ERR_DUPLICATE_NAME, "duplicate name")                                                               \
    X(MM_ERR_CHANNELS, "invalid channel declaration")                                                        \
    X(MM_ERR_VALUE_COUNT, "wrong number of values on a motion line")                                         \
    X(MM_ERR_FRAME_COUNT, "frame count does not match the declaration")                                      \
    X(MM_ERR_OUT_OF_RANGE, "value out of range")                                                             \
    X(MM_ERR_NOT_FOUND, "not found")                                                                         \
    X(MM_ERR_UNSUPPORTED, "not supported by this build")

typedef enum mm_result {
#define MM__RESULT_ENUM(code, text) code,
    MM_RESULT_LIST(MM__RESULT_ENUM)
#undef MM__RESULT_ENUM
        MM_RESULT_COUNT
} mm_result;

/* Short description of a code ("syntax error"); never NULL. */
const char *mm_result_str(mm_result r);
/* The code's identifier ("MM_ERR_SYNTAX"); never NULL. */
const char *mm_result_name(mm_result r);

#define MM_ERROR_FILE_MAX    256
#define MM_ERROR_MESSAGE_MAX 256

typedef struct mm_error {
    mm_result code;
    int line;                           /* 1-based; 0 when the error has no position */
    int column;                         /* 1-based; 0 when the error has no position */
    char file[MM_ERROR_FILE_MAX];       /* file or input name; may be empty */
    char message[MM_ERROR_MESSAGE_MAX]; /* what is wrong, in words */
} mm_error;

/* Fills err (if not NULL) with a printf-style message and returns code. Keeps err->file. */
mm_result mm_error_set(mm_error *err, mm_result code, int line, int column, const char *fmt, ...)
#if defined(__GNUC__) || defined(__clang__)
    __attribute__((format(printf, 5, 6)))
#endif
    ;

/* Writes "file:line:column: message" (parts that are unknown are left out) into buf. */
void mm_error_format(const mm_error *err, char *buf, size_t size);

#ifdef __cplusplus
}
#endif

#endif /* MM_RESULT_H */
