/* libFuzzer target: the .mmdb loader. Any bytes must load or be refused; a loaded database must
 * be safe to read everywhere (the dump reads every array and the settings section; the distance
 * curves are read through their own functions; the settings make a character desc and a moves
 * desc). The checksum is always verified, as mm db search and mm simulate do: the custom mutator
 * (fuzz_reseal.h) recomputes it after each mutation, so the checks behind it are reached. */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <mm/character.h>
#include <mm/database.h>
#include <mm/database_build.h>
#include <mm/distance_matching.h>
#include <mm/moves.h>

#include "fuzz_reseal.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    void *buf = aligned_alloc(MM_DB_ALIGN, (size + MM_DB_ALIGN) / MM_DB_ALIGN * MM_DB_ALIGN);
    if (!buf) return 0;
    if (size) memcpy(buf, data, size);
    mm_database db;
    mm_error err;
    memset(&err, 0, sizeof err);
    if (mm_database_load_memory(buf, size, true, &db, &err) == MM_OK) {
        FILE *out = fopen("/dev/null", "w");
        if (out) {
            mm_database_dump(&db, out);
            fclose(out);
        }
        mm_pose_data pd;
        mm_quat rot[MM_MAX_JOINTS];
        mm_vec3 pos[MM_MAX_JOINTS];
        for (int f = 0; f < db.frame_count; f += 1 + db.frame_count / 16) {
            mm_database_pose(&db, f, &pd);
            mm_database_local_pose(&db, f, rot, pos); /* decoded, when compressed */
            for (int j = 0; j < db.joint_count; ++j) {
                mm_quat q;
                mm_vec3 p;
                mm_database_local_joint(&db, f, j, &q, &p);
                if (memcmp(&q, &rot[j], sizeof q) != 0 || memcmp(&p, &pos[j], sizeof p) != 0)
                    __builtin_trap();
            }
        }
        /* the distance curves passed validation: the readers must be safe on them */
        for (int c = 0; c < db.clip_count && c < 64; ++c) {
            mm_distance_curve curve;
            if (mm_database_distance_curve(&db, c, &curve) != MM_OK) continue;
            float t = 0.37f * mm_distance_duration(&curve), at;
            (void)mm_distance_signed(&curve, t);
            (void)mm_distance_time_after(&curve, t, 0.5f);
            (void)mm_distance_match_to_target(&curve, mm_distance_segment_at(&curve, t), 0.25f, &at);
        }
        /* the settings section, as a game reads it */
        mm_character_desc desc;
        if (mm_character_desc_from_database(&desc, &db, &err) != MM_OK) __builtin_trap();
        mm_moves_desc moves;
        mm_moves_desc_from_database(&moves, &db);
        (void)moves;
    } else if (err.message[0] == 0) {
        __builtin_trap();
    }
    free(buf);
    return 0;
}
