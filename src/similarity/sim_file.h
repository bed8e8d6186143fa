/* sim_file.h (private) - the similarity tables file layout (docs/similarity.md). */
#ifndef MM_SIM_FILE_H
#define MM_SIM_FILE_H

#include <mm/similarity.h>

enum mm__sim_section {
    MM__SIM_SEC_JOINT_WEIGHTS,
    MM__SIM_SEC_CLIPS,
    MM__SIM_SEC_FRAME_CLIP,
    MM__SIM_SEC_LOOP_CLIPS,
    MM__SIM_SEC_SHOT_CLIPS,
    MM__SIM_SEC_FUSION,
    MM__SIM_SEC_LINK,
    MM__SIM_SEC_COUNT
};

/* Everything the tables hold, as separate arrays: what the build computes and packs. */
typedef struct mm__sim_parts {
    mm_sim_measure measure;
    unsigned channels;
    int window, joint_count, frame_count, clip_count, loop_count, shot_count, fusion_rows, link_rows;
    uint64_t db_checksum, db_size;
    float dim_weights[MM_SIM_DIMS];
    const void *data[MM__SIM_SEC_COUNT];
} mm__sim_parts;

void mm__sim_section_sizes(const mm__sim_parts *p, size_t size[MM__SIM_SEC_COUNT]);
mm_result mm__sim_pack(const mm__sim_parts *parts, const mm_allocator *allocator, mm_sim_tables *out,
                       mm_error *err);
/* The database's own checksum (its .mmdb header field), identifying it. */
uint64_t mm__sim_db_checksum(const mm_database *db);

#endif
