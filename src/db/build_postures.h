/* build_postures.h (private) - the postures of the source frames a database is built from
 * (mm/posture.h), and what the build does with them: locomotion and idle clips lose their
 * calibration, lying, arms-spread (however briefly), hand-raised and knee-raised frames (with a
 * margin), and their crouched and bent-over frames carry the crouch gait's tag. */
#ifndef MM_DB_BUILD_POSTURES_H
#define MM_DB_BUILD_POSTURES_H

#include <stdint.h>

#include <mm/clip.h>
#include <mm/config.h>
#include <mm/database_build.h>

typedef struct mm__postures {
    uint8_t **frames; /* [clip_count]: mm_posture of each source frame; NULL where not judged */
    int clip_count;
    int crouch_tag;              /* the tag crouched frames carry (-1: none) */
    int tag_count;               /* the database's tags: the config's, and "Crouch" after them when added */
    float reference_head_height; /* m; 0: nothing judged */
} mm__postures;

/* Judges every frame of the config's locomotion and idle clips (cfg->postures_detect; without a
 * head or hips joint a clip is not judged). Fills report when given. */
mm_result mm__postures_find(const mm_config *cfg, const mm_clip *sources, mm__postures *out,
                            mm_db_build_report *report, mm_error *err);
void mm__postures_free(mm__postures *p);

/* The pieces of range [begin, end) of config clip ci that the database keeps, in order: the
 * calibration and lying frames cut out, the crouched (tagged) frames apart from the others, each
 * piece without the cfg->postures_pad seconds next to a frame of another kind (the way into or out
 * of a posture belongs to neither), pieces shorter than MM__POSTURES_MIN_PIECE seconds dropped; a
 * range with nothing cut out is kept as it is. out holds room for end - begin pieces. Returns how
 * many. */
#define MM__POSTURES_MIN_PIECE 0.5f
int mm__postures_split(const mm__postures *p, const mm_config *cfg, int ci, const mm_clip *source,
                       mm_config_range range, mm_config_range *out);

/* The tag bit config clip ci's frame at time t (seconds in its source, at fps) gets from its posture. */
uint64_t mm__postures_tags(const mm__postures *p, int ci, float t, float fps, int frame_count);

#endif
