/* fuzz_reseal.h - the custom mutator of fuzz_mmdb and fuzz_sim. Both formats end their header's
 * first 24 bytes with a checksum of every byte after them (src/io/sections.h) and then hold the
 * file size: a random mutation almost never keeps them right, so without help the fuzzer only ever
 * meets the checksum check. This mutator mutates as libFuzzer does, then (7 times in 8) writes the
 * new size and recomputes the checksum, as an attacker crafting a file would, so that the checks
 * behind them are reached; the 8th keeps the damage so that those two checks stay fuzzed too. */
#ifndef MM_FUZZ_RESEAL_H
#define MM_FUZZ_RESEAL_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "io/checksum.h"

#define MM_FUZZ_RESEAL_EVERY 8 /* 1 mutation in this many keeps a stale checksum and size */

size_t LLVMFuzzerMutate(uint8_t *data, size_t size, size_t max_size);
size_t LLVMFuzzerCustomMutator(uint8_t *data, size_t size, size_t max_size, unsigned int seed);

size_t LLVMFuzzerCustomMutator(uint8_t *data, size_t size, size_t max_size, unsigned int seed)
{
    size = LLVMFuzzerMutate(data, size, max_size);
    if (size < 32 || seed % MM_FUZZ_RESEAL_EVERY == 0) return size;
    uint64_t file_size = size;
    memcpy(data + 24, &file_size, 8);
    uint64_t checksum = mm__checksum64(data + 24, size - 24);
    memcpy(data + 16, &checksum, 8);
    return size;
}

#endif
