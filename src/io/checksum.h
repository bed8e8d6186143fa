/* checksum.h (private) - the 64-bit checksum of mm's binary files (.mmdb, similarity tables). */
#ifndef MM_IO_CHECKSUM_H
#define MM_IO_CHECKSUM_H

#include <stddef.h>
#include <stdint.h>

/* Four independent multiply-rotate lanes over 8-byte little-endian words (lane i takes words
 * 4k + i), folded with the length and the tail bytes: several GB/s, so a whole file can be
 * verified on load. */
uint64_t mm__checksum64(const void *data, size_t size);

#endif
