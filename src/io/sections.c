#include "io/sections.h"

#include <string.h>

#include "io/checksum.h"

static size_t align_up(size_t x, size_t align) { return (x + align - 1) & ~(align - 1); }

size_t mm__sections_layout(size_t header_size, size_t align, const size_t *sizes, int count,
                           mm__section *sections)
{
    size_t at = align_up(header_size, align);
    for (int s = 0; s < count; ++s) {
        sections[s].offset = at;
        sections[s].size = sizes[s];
        at = align_up(at + sizes[s], align);
    }
    return at;
}

int mm__sections_check(const mm__section *sections, int count, size_t header_size, size_t align,
                       uint64_t file_size, const size_t *want)
{
    uint64_t end = header_size; /* where the previous section ends */
    for (int s = 0; s < count; ++s) {
        uint64_t off = sections[s].offset, sz = sections[s].size;
        if (off % align != 0 || off < end || off > file_size || sz > file_size - off ||
            sz != (uint64_t)want[s])
            return s;
        end = off + sz; /* cannot wrap: off + sz <= file_size */
    }
    return -1;
}

unsigned char *mm__alloc_aligned(const mm_allocator *allocator, size_t size, size_t align,
                                 unsigned char **raw)
{
    *raw = (unsigned char *)mm_alloc(allocator, size + align);
    if (!*raw) return NULL;
    return *raw + (align_up((size_t)(uintptr_t)*raw, align) - (size_t)(uintptr_t)*raw);
}

unsigned char *mm__sections_pack(const mm_allocator *allocator, size_t file_size, size_t align,
                                 const mm__section *sections, const void *const *data, int count,
                                 unsigned char **raw)
{
    unsigned char *base = mm__alloc_aligned(allocator, file_size, align, raw);
    if (!base) return NULL;
    memset(base, 0, file_size);
    for (int s = 0; s < count; ++s)
        if (sections[s].size && data[s]) memcpy(base + sections[s].offset, data[s], (size_t)sections[s].size);
    return base;
}

uint64_t mm__sections_seal(unsigned char *file, size_t file_size, const void *header, size_t header_size)
{
    memcpy(file, header, header_size);
    uint64_t checksum = mm__checksum64(file + 24, file_size - 24);
    memcpy(file + 16, &checksum, 8);
    return checksum;
}
