/* mm/diagnose.h - what a database lacks for the runtime, in words a technical animator can act on
 * (the mm_build library).
 *
 * mm_database_diagnose checks a built or loaded database, and the report of its build when there is
 * one (mm_db_build_report: the database does not keep it), and lists what will look wrong at run
 * time: no idle clip, gait speeds the runtime asks for that no clip moves at or that are above the
 * data's speed envelope (mm/speed_envelope.h), no stops or starts,
 * bone roles that name no joint, a body too small or too large for metres, most frames left out or
 * tagged by postures. `mm db build` and `mm db info` print the list (docs/database.md,
 * "Diagnostics"); `mm db info --json` gives it as "warnings", each with its code and message.
 *
 *   mm_diagnosis d;
 *   mm_database_diagnose(&db, &report, NULL, &d);   // report NULL after loading
 *   for (int i = 0; i < d.count; ++i) puts(d.items[i].message);
 *
 * Functions: mm_database_diagnose mm_diagnostic_code_name
 */
#ifndef MM_DIAGNOSE_H
#define MM_DIAGNOSE_H

#include <stdbool.h>

#include "alloc.h"
#include "database.h"
#include "database_build.h"
#include "result.h"
#include "speed_envelope.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum mm_diagnostic_code {
    MM_DIAG_NO_IDLE = 0,       /* no idle clip: stops slide */
    MM_DIAG_SPEED_NOT_COVERED, /* a gait speed of the runtime that no clip moves at */
    MM_DIAG_NO_STOPS,          /* no clip comes to a stop (the distance curves hold none) */
    MM_DIAG_NO_STARTS,         /* no clip starts from rest */
    MM_DIAG_ROLE_MISSING,      /* a bone role names no joint of the database */
    MM_DIAG_HEIGHT,            /* the body stands under MM_DIAGNOSE_MIN_HEIGHT or over MAX: units */
    MM_DIAG_POSTURES_LEFT_OUT, /* the build left out more than MM_DIAGNOSE_POSTURE_SHARE of the frames */
    MM_DIAG_POSTURES_TAGGED,   /* the build tagged more than MM_DIAGNOSE_POSTURE_SHARE of them Crouch */
    MM_DIAG_SPEED_ENVELOPE,    /* a gait speed above the data's speed envelope that way */
    MM_DIAG_CODE_COUNT
} mm_diagnostic_code;

/* Thresholds (docs/database.md, "Diagnostics"). */
#define MM_DIAGNOSE_SPEED_BAND      1.25f /* frames within [v / this, v x this] cover speed v */
#define MM_DIAGNOSE_COVER_SECONDS   1.0f  /* the seconds of such frames a covered speed needs */
#define MM_DIAGNOSE_MIN_HEIGHT      1.0f  /* m: standing heights outside [MIN, MAX] look like wrong units */
#define MM_DIAGNOSE_MAX_HEIGHT      2.5f
#define MM_DIAGNOSE_POSTURE_SHARE   0.25f /* of the judged source frames */
#define MM_DIAGNOSE_ENVELOPE_MARGIN 1.1f  /* a gait speed over its envelope times this is warned about */

#define MM_DIAGNOSTIC_MESSAGE_MAX 400
#define MM_DIAGNOSE_MAX           32

typedef struct mm_diagnostic {
    mm_diagnostic_code code;
    char message[MM_DIAGNOSTIC_MESSAGE_MAX]; /* one line, ending in what to do */
} mm_diagnostic;

/* One of the runtime's gait speeds against the locomotion the gait may play: the locomotion clips'
 * frames tagged with that gait or with no gait tag (the runtime leaves out frames tagged with
 * another gait), moving in that direction (as mm_database_speed_summary counts them: within 45
 * degrees of forward or backward in the root's facing frame, sideways otherwise, none under
 * MM_SPEED_SUMMARY_STILL). */
typedef struct mm_speed_coverage {
    int gait;            /* MM_GAIT_WALK or MM_GAIT_RUN */
    int direction;       /* 0 forward, 1 side, 2 backward */
    float speed;         /* m/s the runtime asks for at full stick */
    bool from_settings;  /* the database's settings give it (else the runtime's default) */
    int frames;          /* frames moving that way */
    float p10, p50, p90; /* their speeds (m/s; 0 without frames) */
    int near;            /* of them, within the band of speed */
    bool covered;        /* near x the interval >= MM_DIAGNOSE_COVER_SECONDS, or speed 0 */
    float envelope;      /* m/s: the speed envelope that way (sideways: the lower of left and right;
                            INFINITY where the gait has none) */
} mm_speed_coverage;

#define MM_DIAGNOSE_SPEEDS 6 /* walk and run, forward, side and backward */

typedef struct mm_diagnosis {
    int count; /* items */
    mm_diagnostic items[MM_DIAGNOSE_MAX];
    mm_speed_coverage speeds[MM_DIAGNOSE_SPEEDS]; /* walk forward, side, backward, then run's */
    int idle_clips;                               /* clips of type idle */
    int standing_clips;     /* of them, standing poses the build made (standing.make: their names start
                               "standing_from_"; docs/database.md) */
    int stops, starts;      /* stop segments of the distance curves; one-shot clips starting from rest */
    float height;           /* m: the standing height (the head's, or the top joint's, height above the
                               lowest joint, 90th percentile over frames, / MM_POSTURE_HEAD_TO_STATURE);
                               0 when the database has no frames */
    float posture_share[2]; /* of the build's judged frames: left out, tagged (0 without a report) */
    /* the speed envelope of each gait (mm/speed_envelope.h): the settings' (measured by the build),
     * or measured now for a database without settings; bounded: whether the runtime applies it
     * (runtime.speed_envelope) */
    mm_speed_envelope envelope[MM_GAIT_COUNT];
    bool bounded;
} mm_diagnosis;

/* "no_idle", "speed_not_covered", "no_stops", "no_starts", "role_missing", "height",
 * "postures_left_out", "postures_tagged", "speed_envelope"; NULL if out of range. */
const char *mm_diagnostic_code_name(mm_diagnostic_code code);

/* Fills out with what db lacks (report: its build's, or NULL; allocator NULL: malloc). The items
 * come in the order of the codes. MM_ERR_INVALID_ARGUMENT without db or out,
 * MM_ERR_OUT_OF_MEMORY. */
mm_result mm_database_diagnose(const mm_database *db, const mm_db_build_report *report, const mm_allocator *a,
                               mm_diagnosis *out);

#ifdef __cplusplus
}
#endif

#endif /* MM_DIAGNOSE_H */
