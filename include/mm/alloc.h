/* mm/alloc.h - caller-controlled memory.
 *
 * Every desc struct that leads to allocation takes an optional const mm_allocator *. NULL means
 * malloc and free. Offline code (import, build) allocates through it; the per-tick runtime path
 * never allocates.
 *
 * Functions: mm_alloc, mm_free, mm_alloc_array
 */
#ifndef MM_ALLOC_H
#define MM_ALLOC_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct mm_allocator {
    void *(*alloc)(size_t size, void *user); /* returns NULL on failure; 16-byte aligned */
    void (*free)(void *ptr, void *user);     /* ptr may be NULL */
    void *user;
} mm_allocator;

/* Allocates size bytes with a (NULL = malloc). Returns NULL on failure or when size is 0. */
void *mm_alloc(const mm_allocator *a, size_t size);
/* Allocates count * size bytes, zeroed; NULL on overflow, failure or a zero total. */
void *mm_alloc_array(const mm_allocator *a, size_t count, size_t size);
void mm_free(const mm_allocator *a, void *ptr);

#ifdef __cplusplus
}
#endif

#endif /* MM_ALLOC_H */
