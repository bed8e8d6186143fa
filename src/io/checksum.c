#include "io/checksum.h"

#include <string.h>

/* 64-bit checksum: four independent multiply-rotate lanes over 8-byte words (fast enough to
 * verify a whole database on load), folded together with the tail and the length. */
static uint64_t rotl64(uint64_t x, int r) { return (x << r) | (x >> (64 - r)); }
uint64_t mm__checksum64(const void *data, size_t n)
{
    const unsigned char *p = (const unsigned char *)data;
    const uint64_t k1 = 0x9E3779B185EBCA87ull, k2 = 0xC2B2AE3D27D4EB4Full;
    uint64_t h[4] = {k1, k2, ~k1, ~k2};
    size_t i = 0;
    for (; i + 32 <= n; i += 32)
        for (int l = 0; l < 4; ++l) {
            uint64_t w;
            memcpy(&w, p + i + 8 * l, 8);
            h[l] = rotl64(h[l] + w * k2, 31) * k1;
        }
    uint64_t r = (uint64_t)n * k1;
    for (int l = 0; l < 4; ++l) r = rotl64(r ^ h[l], 27) * k2 + k1;
    for (; i < n; ++i) r = rotl64(r ^ p[i], 11) * k1;
    r ^= r >> 33;
    r *= k2;
    r ^= r >> 29;
    return r;
}
