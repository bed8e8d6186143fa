/* name_set.h (private) - names compared through a hash table, so that checking n names for
 * repeats or finding a name among them costs O(n), not the O(n^2) of comparing them pairwise (a
 * config may list 100,000 clips). The names are strings inside an array of records (at a stride). */
#ifndef MM_IO_NAME_SET_H
#define MM_IO_NAME_SET_H

#include <stddef.h>
#include <stdint.h>

typedef struct mm__name_index {
    int32_t *slots; /* record index + 1; 0: free */
    size_t mask;
    const char *first;
    size_t stride;
} mm__name_index;

/* Indexes count names, the first at first and each next one stride bytes on; a name given more
 * than once finds its first record. Returns 0, or -1 when out of memory. */
int mm__name_index_init(mm__name_index *x, const char *first, size_t stride, int count);
/* The record index of name, or -1. */
int mm__name_index_find(const mm__name_index *x, const char *name);
void mm__name_index_free(mm__name_index *x);

/* The first record whose name an earlier record already has, -1 when all differ, -2 when out of
 * memory. */
int mm__name_set_first_repeat(const char *first, size_t stride, int count);

/* FNV-1a of a string, and of a second one after it (for keys made of two names). */
uint64_t mm__name_hash(const char *s, uint64_t h);
#define MM__NAME_HASH_SEED 1469598103934665603ull

#endif
