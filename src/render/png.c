/* PNG writer: 8-bit RGB, each row filtered by its difference to the row above, deflated by zlib. */
#include <stdlib.h>
#include <string.h>

#include <zlib.h>

#include <mm/render.h>

#include "io/file.h"

static void put32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)(v >> 24);
    p[1] = (unsigned char)(v >> 16);
    p[2] = (unsigned char)(v >> 8);
    p[3] = (unsigned char)v;
}

/* Appends a chunk (length, type, data, CRC of type and data) at out; returns the bytes written. */
static size_t chunk(unsigned char *out, const char *type, const unsigned char *data, size_t n)
{
    put32(out, (uint32_t)n);
    memcpy(out + 4, type, 4);
    if (n) memcpy(out + 8, data, n);
    put32(out + 8 + n, (uint32_t)crc32(0L, out + 4, (uInt)(n + 4)));
    return n + 12;
}

mm_result mm_png_write(const char *path, const uint8_t *rgb, int width, int height, mm_error *err)
{
    if (!path || !rgb || width < 1 || height < 1 || width > 65536 || height > 65536)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "PNG of %d x %d pixels: nothing to write",
                            width, height);
    size_t stride = (size_t)width * 3, raw_size = (size_t)height * (stride + 1);
    unsigned char *raw = malloc(raw_size);
    uLongf z_size = compressBound((uLong)raw_size);
    unsigned char *file = malloc(8 + 25 + 12 + z_size + 12);
    if (!raw || !file) {
        free(raw);
        free(file);
        return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory for a %d x %d PNG", width,
                            height);
    }
    for (int y = 0; y < height; ++y) {
        unsigned char *row = raw + (size_t)y * (stride + 1);
        const uint8_t *src = rgb + (size_t)y * stride, *above = y > 0 ? src - stride : NULL;
        row[0] = 2; /* filter "Up" (the row above is zero for the first row) */
        for (size_t i = 0; i < stride; ++i) row[1 + i] = (unsigned char)(src[i] - (above ? above[i] : 0));
    }
    static const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    unsigned char ihdr[13];
    put32(ihdr, (uint32_t)width);
    put32(ihdr + 4, (uint32_t)height);
    ihdr[8] = 8;  /* bits per sample */
    ihdr[9] = 2;  /* RGB */
    ihdr[10] = 0; /* deflate */
    ihdr[11] = 0; /* adaptive filtering */
    ihdr[12] = 0; /* not interlaced */
    size_t at = 0;
    memcpy(file, signature, 8);
    at += 8;
    at += chunk(file + at, "IHDR", ihdr, 13);
    /* IDAT: compress straight into its place after the 8-byte chunk header */
    uLongf written = z_size;
    int zr = compress2(file + at + 8, &written, raw, (uLong)raw_size, 6);
    free(raw);
    if (zr != Z_OK) {
        free(file);
        return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "zlib could not compress the image (%d)", zr);
    }
    put32(file + at, (uint32_t)written);
    memcpy(file + at + 4, "IDAT", 4);
    put32(file + at + 8 + written, (uint32_t)crc32(0L, file + at + 4, (uInt)(written + 4)));
    at += written + 12;
    at += chunk(file + at, "IEND", NULL, 0);
    mm_result r = mm__write_file_atomic(path, file, at, err);
    free(file);
    return r;
}
