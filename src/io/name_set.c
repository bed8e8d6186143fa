#include "io/name_set.h"

#include <stdlib.h>
#include <string.h>

uint64_t mm__name_hash(const char *s, uint64_t h)
{
    for (; *s; ++s) h = (h ^ (unsigned char)*s) * 1099511628211ull;
    return (h ^ 0xffu) * 1099511628211ull; /* the end of the string counts too: ("ab", "c") != ("a", "bc") */
}

static const char *name_at(const mm__name_index *x, int32_t i) { return x->first + (size_t)i * x->stride; }

/* The slot of name: where it is, or the free one where it would go. */
static size_t slot_of(const mm__name_index *x, const char *name)
{
    size_t k = (size_t)mm__name_hash(name, MM__NAME_HASH_SEED) & x->mask;
    while (x->slots[k] && strcmp(name_at(x, x->slots[k] - 1), name) != 0) k = (k + 1) & x->mask;
    return k;
}

/* Builds the table; *repeat receives the first record whose name was already there (or -1). */
static int build(mm__name_index *x, const char *first, size_t stride, int count, int *repeat)
{
    size_t capacity = 16;
    while (capacity < 2 * (size_t)(count > 0 ? count : 0)) capacity *= 2;
    x->slots = (int32_t *)calloc(capacity, sizeof *x->slots);
    x->mask = capacity - 1;
    x->first = first;
    x->stride = stride;
    *repeat = -1;
    if (!x->slots) return -1;
    for (int i = 0; i < count; ++i) {
        size_t k = slot_of(x, name_at(x, i));
        if (x->slots[k]) {
            if (*repeat < 0) *repeat = i;
        } else {
            x->slots[k] = i + 1;
        }
    }
    return 0;
}

int mm__name_index_init(mm__name_index *x, const char *first, size_t stride, int count)
{
    int repeat;
    return build(x, first, stride, count, &repeat);
}

int mm__name_index_find(const mm__name_index *x, const char *name)
{
    if (!x->slots) return -1;
    size_t k = slot_of(x, name);
    return x->slots[k] ? x->slots[k] - 1 : -1;
}

void mm__name_index_free(mm__name_index *x)
{
    free(x->slots);
    memset(x, 0, sizeof *x);
}

int mm__name_set_first_repeat(const char *first, size_t stride, int count)
{
    mm__name_index x;
    int repeat;
    if (build(&x, first, stride, count, &repeat) != 0) return -2;
    mm__name_index_free(&x);
    return repeat;
}
