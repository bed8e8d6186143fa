#include <mm/alloc.h>

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

void *mm_alloc(const mm_allocator *a, size_t size)
{
    if (size == 0) return NULL;
    if (a && a->alloc) return a->alloc(size, a->user);
    return malloc(size);
}

void *mm_alloc_array(const mm_allocator *a, size_t count, size_t size)
{
    if (count == 0 || size == 0 || count > SIZE_MAX / size) return NULL;
    void *p = mm_alloc(a, count * size);
    if (p) memset(p, 0, count * size);
    return p;
}

void mm_free(const mm_allocator *a, void *ptr)
{
    if (!ptr) return;
    if (a && a->alloc) {
        if (a->free) a->free(ptr, a->user);
        return;
    }
    free(ptr);
}
