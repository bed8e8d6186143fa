/* libFuzzer target: similarity tables files. Any bytes load or are refused with a message; loaded
 * tables answer every lookup safely. The custom mutator (fuzz_reseal.h) recomputes the checksum
 * after each mutation, so the checks behind it are reached. */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <mm/similarity.h>

#include "fuzz_reseal.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    void *buf = aligned_alloc(64, (size + 64) / 64 * 64);
    if (!buf) return 0;
    if (size) memcpy(buf, data, size);
    mm_sim_tables t;
    mm_error err;
    memset(&err, 0, sizeof err);
    if (mm_sim_tables_load_memory(buf, size, NULL, &t, &err) == MM_OK) {
        for (int f = -1; f <= t.frame_count; f += 1 + t.frame_count / 8)
            for (int c = -1; c <= t.clip_count; ++c) (void)mm_sim_fusion(&t, f, c);
        for (int f = -1; f <= t.frame_count; f += 1 + t.frame_count / 8) {
            mm_sim_match best;
            mm_sim_link_match link;
            (void)mm_sim_fusion_best(&t, f, &best);
            (void)mm_sim_link_row(&t, f);
            (void)mm_sim_link(&t, f, 3, NULL, 0, &link);
        }
    } else if (err.message[0] == 0) {
        __builtin_trap();
    }
    free(buf);
    return 0;
}
