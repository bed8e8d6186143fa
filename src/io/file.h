/* file.h (private) - whole-file reading and atomic writing for the loaders and writers. */
#ifndef MM_IO_FILE_H
#define MM_IO_FILE_H

#include <stddef.h>

#include <mm/alloc.h>
#include <mm/result.h>

#define MM__MAX_FILE_BYTES ((size_t)1 << 31) /* 2 GiB: larger inputs are refused */

/* Reads the whole file into a buffer from allocator (one extra zero byte after the data).
 * Errors name the path in err->file. */
mm_result mm__read_file(const char *path, const mm_allocator *allocator, char **out_data, size_t *out_size,
                        mm_error *err);

/* Writes data to path through a temporary file in the same folder and a rename, so readers
 * never see a half-written file and a failure leaves nothing behind. */
mm_result mm__write_file_atomic(const char *path, const void *data, size_t size, mm_error *err);

/* Copies name into err->file (truncated to fit) when err is not NULL. */
void mm__error_set_file(mm_error *err, const char *name);

#endif
