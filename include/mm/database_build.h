/* mm/database_build.h - building a motion database and reading it as text (the mm_build
 * library: the offline side of mm/database.h).
 *
 * mm_database_build makes a database from a config (mm/config.h) and its source clips: it
 * extracts the simulation bone, mirrors and blends clips, labels contacts, computes and
 * normalises the features and distance curves, and writes the config's runtime tuning into the
 * settings section (docs/format.md). The result is saved with mm_database_save and loaded by the
 * runtime (mm/database.h, the mm_runtime library) with no part of this header.
 *
 * mm_database_compress makes the shipping form of a database: its local transforms quantized per
 * clip segment, every frame's world joint positions within a bound of the floats (measured on every
 * frame as it compresses); features and search data unchanged (docs/database.md, "A smaller
 * database for shipping").
 *
 * Functions: mm_database_build mm_database_compress mm_database_dump mm_database_speed_summary
 */
#ifndef MM_DATABASE_BUILD_H
#define MM_DATABASE_BUILD_H

#include <stdio.h>

#include "alloc.h"
#include "clip.h"
#include "config.h"
#include "database.h"
#include "posture.h"
#include "result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Whether the build made a standing clip (config standing.make; docs/database.md, "A standing pose
 * when the takes have no idle"). */
typedef enum mm_standing_status {
    MM_STANDING_NOT_NEEDED = 0, /* the config has an idle clip */
    MM_STANDING_OFF,            /* none, and standing.make is false */
    MM_STANDING_MADE,           /* none: the build made one */
    MM_STANDING_NOT_FOUND       /* none, and no locomotion frame is upright with both feet down */
} mm_standing_status;

/* The standing clips a build made: how many, and which frame of which clip the first (the stillest)
 * holds, and how still that was. */
typedef struct mm_db_standing_report {
    int status;                    /* mm_standing_status */
    int poses;                     /* standing clips made (mirrors aside): the stillest pose and those
                                      nearly as still, each from its own clip */
    char clip[MM_NAME_MAX];        /* the first clip made: "standing_from_<from_clip>_<from_frame>" */
    char from_clip[MM_NAME_MAX];   /* the database clip whose pose it holds */
    int from_frame;                /* that pose's frame in the source file (its own frame rate) */
    float from_time;               /* s: the same, in seconds from the start of the file */
    bool mirrored;                 /* the mirrored pose was added too ("<clip>_mirror") */
    float root_speed, joint_speed; /* m/s: the root's and the joints' mean speed around the frame */
    float stride;                  /* m: the ankles apart along the facing */
    float offset;                  /* m: the ankles' midpoint from the root, on the ground */
    int standing_frames;           /* locomotion frames judged upright with both feet down */
} mm_db_standing_report;

/* The name of an idle loop clip: its idle clip's, then this ("<clip>_loop", its mirror
 * "<clip>_loop_mirror"). */
#define MM_IDLE_LOOP_SUFFIX "_loop"

/* The idle loops a build made (config idle_loop.make; docs/database.md, "Idle that loops"): of the
 * idle clips that do not loop already (mirrors aside), how many got a loop clip "<clip>_loop" and
 * why the others did not. */
typedef struct mm_db_idle_loop_report {
    bool make;         /* idle_loop.make: false, none looked for */
    int idle_clips;    /* idle clips looked at */
    int made;          /* loop clips made (their mirrors aside) */
    int no_still;      /* clips without a still stretch of a loop's length */
    int no_match;      /* clips whose best seam was farther than the build accepts */
    float seconds;     /* s: the loops' total length */
    float worst_error; /* m: the largest seam distance (RMS over joints) of the loops made */
} mm_db_idle_loop_report;

/* What a build found in its sources (mm_db_build_desc.report). */
typedef struct mm_db_build_report {
    float reference_head_height;         /* m: the upright head height postures are judged by (0: none) */
    int source_frames[MM_POSTURE_COUNT]; /* source frames of the locomotion and idle clips judged to
                                            hold each posture (mm/posture.h): calibration and lying
                                            ones are left out, crouched and bent ones tagged Crouch */
    mm_db_standing_report standing;      /* the standing clip made when no clip is an idle clip */
    mm_db_idle_loop_report idle_loops;   /* the loop clips made of the idle clips */
} mm_db_build_report;

/* Compressing the local transforms (mm_database_compress; mm_db_build_desc.compress). */
#define MM_POSE_ERROR_DEFAULT          0.0005f /* m: the default bound on world joint positions */
#define MM_POSE_SEGMENT_FRAMES_DEFAULT 32      /* frames per segment */
/* m: besides the joints, points this far from each joint along its three axes are held to the
 * bound, so that a joint's own rotation (a hand's, the head's: no joint below them) and its twist
 * are kept too */
#define MM_POSE_SHELL_DISTANCE 0.1f
typedef struct mm_db_compress_desc {
    float error_bound;  /* m: 0 for MM_POSE_ERROR_DEFAULT; at most 0.1 */
    int segment_frames; /* 0 for MM_POSE_SEGMENT_FRAMES_DEFAULT; at most MM_POSE_SEGMENT_FRAMES_MAX */
    int threads;        /* 0 or 1: the calling thread; the bytes never depend on it */
    const mm_allocator *allocator; /* for the result; NULL: malloc */
} mm_db_compress_desc;

typedef struct mm_db_build_desc {
    const char *config_json;       /* text to embed (the config as read); NULL: none */
    const mm_allocator *allocator; /* NULL: malloc */
    void (*progress)(int done, int total,
                     void *user); /* optional, called per clip (from the calling thread) */
    void *progress_user;
    int threads; /* 0 or 1: the calling thread alone; at most MM_DB_MAX_THREADS. The bytes never depend on it
                  */
    mm_db_build_report *report;          /* optional: filled with what the build found */
    const mm_db_compress_desc *compress; /* optional: the local transforms compressed (its threads: the
                                            build's when 0) */
} mm_db_build_desc;

#define MM_DB_MAX_THREADS 64

/* Builds a database. sources[i] is config->clips[i]'s file, loaded, in metres (scale applied),
 * at any frame rate. The result owns one buffer in file layout. Its settings section holds the
 * config's runtime tuning resolved against the database (mm_database_settings): the feature
 * weights of the groups it has, the runtime fields set, the joints of the bone roles; a value out
 * of the range loading accepts is MM_ERR_OUT_OF_RANGE. */
mm_result mm_database_build(const mm_config *config, const mm_clip *sources, const mm_db_build_desc *desc,
                            mm_database *out, mm_error *err);

/* A copy of db (stored with floats) whose local transforms are compressed (desc may be NULL: the
 * defaults): segments of segment_frames frames per clip, each track with the fewest bits that keep
 * every frame's world joint positions (FK) and shell points within error_bound of db's, measured
 * as the runtime decodes them (out->compressed.max_error: the largest joint error). Every other
 * section is db's, byte for byte. MM_ERR_INVALID_ARGUMENT for a database compressed already,
 * MM_ERR_OUT_OF_RANGE for a bound or segment length out of range. */
mm_result mm_database_compress(const mm_database *db, const mm_db_compress_desc *desc, mm_database *out,
                               mm_error *err);

/* Deterministic text form of everything in the database, its settings included (for diffs and
 * bug reports). Numbers are printed with %.9g in the C locale. */
mm_result mm_database_dump(const mm_database *db, FILE *out);

/* Root speeds of one kind of motion in the database, for setting the runtime's gait speeds
 * (docs/config.md "Gait speeds from the data"; mm db info prints them). Each frame's root
 * velocity (root_velocity: horizontal, in the root's facing frame) counts as forward when within
 * 45 degrees of the facing, backward within 45 degrees of the opposite, sideways (either side)
 * otherwise; frames slower than MM_SPEED_SUMMARY_STILL have no direction and count as still.
 * A percentile q is the sorted value at index floor(q (n - 1)); 0 with no frames. */
#define MM_SPEED_SUMMARY_STILL 0.1f /* m/s */
#define MM_SPEED_SUMMARY_MAX   6    /* 4 gait tags, untagged locomotion, idle */
typedef struct mm_speed_percentiles {
    int frames;          /* frames moving this way */
    float p10, p50, p90; /* m/s */
} mm_speed_percentiles;
typedef struct mm_speed_summary {
    char name[MM_TAG_NAME_MAX]; /* a gait tag as the database spells it ("Walk", "run"), "locomotion"
                                   (locomotion clips' frames without a gait tag) or "idle" (idle
                                   clips' frames) */
    int frames;                 /* frames of this kind */
    int still;                  /* of them, slower than MM_SPEED_SUMMARY_STILL */
    mm_speed_percentiles forward, side, backward;
} mm_speed_summary;

/* One summary per kind of motion the database has, in this order: a tag named after each gait
 * (mm_gait_name, any case: walk, run, crouch, jump) that tags frames, then locomotion frames
 * without a gait tag, then idle; a frame with two gait tags counts in both. *count receives how
 * many (at most MM_SPEED_SUMMARY_MAX). Allocates scratch (a allocator; NULL: malloc) and frees
 * it. */
mm_result mm_database_speed_summary(const mm_database *db, const mm_allocator *a,
                                    mm_speed_summary out[MM_SPEED_SUMMARY_MAX], int *count);

#ifdef __cplusplus
}
#endif

#endif /* MM_DATABASE_BUILD_H */
