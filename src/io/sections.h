/* sections.h (private) - the layout shared by mm's binary files (.mmdb, similarity tables): a
 * header whose bytes [16, 24) hold the checksum of every byte from 24 to the end, then the
 * sections, each at a multiple of the file's alignment, padding zeroed so that the same content
 * always gives the same bytes. */
#ifndef MM_IO_SECTIONS_H
#define MM_IO_SECTIONS_H

#include <stddef.h>
#include <stdint.h>

#include <mm/alloc.h>

typedef struct mm__section {
    uint64_t offset, size; /* bytes from the start of the file */
} mm__section;

/* Places count sections of the given sizes after a header of header_size bytes, each at a
 * multiple of align (a power of two); returns the file size (a multiple of align too). */
size_t mm__sections_layout(size_t header_size, size_t align, const size_t *sizes, int count,
                           mm__section *sections);

/* An align-aligned, zeroed buffer of file_size bytes with data[s] copied to sections[s] (a NULL
 * data[s] stays zero); *raw receives the block to free with mm_free. NULL when out of memory. */
unsigned char *mm__sections_pack(const mm_allocator *allocator, size_t file_size, size_t align,
                                 const mm__section *sections, const void *const *data, int count,
                                 unsigned char **raw);

/* Copies the header to the start of the packed file and writes the checksum into it (bytes
 * [16, 24)); returns that checksum. */
uint64_t mm__sections_seal(unsigned char *file, size_t file_size, const void *header, size_t header_size);

/* Checks a loaded file's section table against the sizes its counts imply (want): each section
 * at a multiple of align, after the header and after the end of the section before it (so none
 * overlap), inside the file, and of exactly its expected size. Overflow-safe for any 64-bit
 * values. Returns the index of the first bad section, or -1 when all are good. */
int mm__sections_check(const mm__section *sections, int count, size_t header_size, size_t align,
                       uint64_t file_size, const size_t *want);

/* An align-aligned block of size bytes (not cleared); *raw receives the block to free. */
unsigned char *mm__alloc_aligned(const mm_allocator *allocator, size_t size, size_t align,
                                 unsigned char **raw);

#endif
