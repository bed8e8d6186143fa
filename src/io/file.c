#define _POSIX_C_SOURCE 200809L
#include "io/file.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

void mm__error_set_file(mm_error *err, const char *name)
{
    if (!err) return;
    snprintf(err->file, sizeof err->file, "%s", name ? name : "");
}

mm_result mm__read_file(const char *path, const mm_allocator *allocator, char **out_data, size_t *out_size,
                        mm_error *err)
{
    *out_data = NULL;
    *out_size = 0;
    mm__error_set_file(err, path);
    if (!path) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no file name given");
    FILE *f = fopen(path, "rb");
    if (!f) return mm_error_set(err, MM_ERR_IO, 0, 0, "cannot open: %s", strerror(errno));
    /* a folder opens for reading on Linux and then reports an absurd size: name it instead */
    struct stat st;
    if (fstat(fileno(f), &st) == 0 && S_ISDIR(st.st_mode)) {
        fclose(f);
        return mm_error_set(err, MM_ERR_IO, 0, 0, "is a folder, not a file");
    }
    mm_result r = MM_OK;
    char *data = NULL;
    long size = -1;
    if (fseek(f, 0, SEEK_END) == 0) size = ftell(f);
    if (size < 0 || fseek(f, 0, SEEK_SET) != 0) {
        r = mm_error_set(err, MM_ERR_IO, 0, 0, "cannot read (not a regular file?)");
    } else if ((unsigned long)size >= MM__MAX_FILE_BYTES) {
        r = mm_error_set(err, MM_ERR_LIMIT, 0, 0, "file is %ld bytes, more than the %zu allowed", size,
                         (size_t)MM__MAX_FILE_BYTES);
    } else if (!(data = (char *)mm_alloc(allocator, (size_t)size + 1))) {
        r = mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory reading %ld bytes", size);
    } else if (fread(data, 1, (size_t)size, f) != (size_t)size) {
        r = mm_error_set(err, MM_ERR_IO, 0, 0, "read error: %s", strerror(errno));
    }
    fclose(f);
    if (r != MM_OK) {
        mm_free(allocator, data);
        return r;
    }
    data[size] = 0;
    *out_data = data;
    *out_size = (size_t)size;
    return MM_OK;
}

mm_result mm__write_file_atomic(const char *path, const void *data, size_t size, mm_error *err)
{
    mm__error_set_file(err, path);
    if (!path || !path[0]) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no file name given");
    struct stat st;
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode)) {
        /* a device or a pipe (/dev/null): written in place, never replaced by a renamed file */
        FILE *f = fopen(path, "wb");
        if (!f) return mm_error_set(err, MM_ERR_IO, 0, 0, "cannot create: %s", strerror(errno));
        int ok = fwrite(data, 1, size, f) == size;
        ok &= fclose(f) == 0;
        return ok ? MM_OK : mm_error_set(err, MM_ERR_IO, 0, 0, "cannot write: %s", strerror(errno));
    }
    size_t n = strlen(path);
    char *tmp = (char *)malloc(n + 32);
    if (!tmp) return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    snprintf(tmp, n + 32, "%s.tmp%ld", path, (long)getpid());
    FILE *f = fopen(tmp, "wb");
    if (!f) {
        mm_result r = mm_error_set(err, MM_ERR_IO, 0, 0, "cannot create: %s", strerror(errno));
        free(tmp);
        return r;
    }
    int ok = fwrite(data, 1, size, f) == size;
    ok &= fflush(f) == 0;
    ok &= fclose(f) == 0;
    if (!ok || rename(tmp, path) != 0) {
        mm_result r = mm_error_set(err, MM_ERR_IO, 0, 0, "cannot write: %s", strerror(errno));
        remove(tmp);
        free(tmp);
        return r;
    }
    free(tmp);
    return MM_OK;
}
