/* mm/config_init.h - a database config made from the takes alone (the mm_build library; what
 * `mm config init` writes, docs/config.md "A config from your takes").
 *
 * From the takes of one skeleton, mm_config_init finds:
 *   - the axes: up (mm_clip_up_axis; every take whose up is clear must agree) and the forward that
 *     goes with it (mm_axes_forward), written as the config's axes so that the build turns the takes
 *     to +Y up (the BVH reader does not turn axes; assimp turns FBX, glTF and Collada files to +Y up
 *     on import); everything below is found on the takes turned;
 *   - the unit (mm_unit_scale_for_height of the body's upright height) and so the config's scale;
 *   - the bone roles, the facing bone's forward axis and the mirror pairs (mm/skeleton_roles.h);
 *   - for each take, frame spans (mm/take_spans.h, as mm bvh spans finds them): calibration poses
 *     (T and A), lying, getting up and going down to the ground left out, standing still (an idle
 *     clip) and the rest (a locomotion clip), mirrored when the mirror pairs pair the skeleton;
 *   - the runtime's walk and run speeds from the root speeds of the locomotion spans, so that the
 *     simulation asks only for speeds the takes have (mm_gait_speed_estimate);
 * and writes the tuning measured on motion capture (mm_config_init_desc).
 *
 * Functions: mm_config_init
 */
#ifndef MM_CONFIG_INIT_H
#define MM_CONFIG_INIT_H

#include <stdbool.h>

#include "clip.h"
#include "config.h"
#include "result.h"
#include "skeleton_roles.h"
#include "take_spans.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- the config ------------------------------------------------------------------------- */

typedef struct mm_config_init_take {
    const char *file;    /* the clip file, as the config is to name it */
    const char *path;    /* where it was read from, for messages; NULL: file */
    const char *take;    /* the take's name in a file of several; NULL or "": the file's first */
    const char *name;    /* the locomotion clip's name (the idle clip adds "_idle"); NULL: the file's
                            name without folder and extension. Names are made unique (_2, _3 ...) */
    const mm_clip *clip; /* the take as imported, in the file's units */
} mm_config_init_take;

/* How one runtime speed was set. */
typedef struct mm_gait_speed_estimate {
    float speed;    /* m/s, what the config gets */
    float seconds;  /* seconds of moving windows it comes from; 0: none (a fallback) */
    float quantile; /* the quantile of their speeds taken (0.5, 0.6, 0.85, 0.95); 0 for a fallback */
} mm_gait_speed_estimate;

#define MM_GAIT_SPEED_RUN 2.2f /* m/s: windows faster than this are running, not walking */
#define MM_GAIT_SPEED_MIN 0.3f /* m/s: windows slower than this have no direction */
#define MM_GAIT_WINDOW                                                                                       \
    1.0f /* s: root speeds are averaged over windows this long (shorter in                                   \
            spans under 4 windows: a quarter of the span) */

/* Under this confidence (mm_clip_up_axis) a take's up is not clear: +Y is assumed (a body that
 * stands along one axis gives 0.3 or more walking; 0 is a pose as wide as it is tall). */
#define MM_UP_MIN_CONFIDENCE 0.15f

typedef struct mm_config_init_report {
    int up_axis;         /* the takes' up (0..5 as mm_axis_name): given, detected, or +Y when unclear */
    float up_confidence; /* mm_clip_up_axis's confidence on the first take whose up is clear (else the
                            highest of the takes') */
    bool up_detected;    /* the confidence reached MM_UP_MIN_CONFIDENCE */
    bool up_given;       /* desc gave it */
    int forward_axis;    /* the takes' forward: given, else mm_axes_forward's for up */
    bool forward_given;
    double scale; /* file units to metres, as given or detected */
    float height; /* m: the body's upright height (joints and End Sites) */
    float fps_min, fps_max;
    float seconds; /* of all the takes */
    float locomotion_seconds, idle_seconds, excluded_seconds;
    /* seconds of the frames left out by kind (MM_SPAN_KIND_COUNT kinds: calibration, a_pose, lying,
     * getting_up, down; before the pad) and the takes that open with a calibration pose */
    float kind_seconds[MM_SPAN_KIND_COUNT];
    int calibration_starts;
    int arms_missing; /* takes on which no A pose was looked for (no elbows and shoulders found) */
    mm_skeleton_roles roles;
    /* [0] walk, [1] run; forward, side, backward, from the windows of the frames the walk and run
     * gaits play (upright, not within postures.pad of a crouched, bent or arms-spread frame; all the
     * frames when none is). Walk: its pace is the speed under MM_GAIT_SPEED_RUN with the most windows
     * within /1.1 to x1.1 of it; the 0.85 quantile forward, the median sideways, the 0.6 quantile
     * backward of the windows within /1.5 to x1.5 of the pace. Run: the 0.95 quantile of all windows
     * when the takes run that way (0.25 s over MM_GAIT_SPEED_RUN; forward the median of the running
     * ones when faster: a short run among long walks), else of the walk's windows. A direction with
     * under 0.25 s of windows gets MM_GAIT_SPEED_MIN (a creep: asking more only drags the feet), one
     * with running alone the walk the 0.1 quantile of it, and no speed is set without moving windows
     * at all. Rounded to 0.05 m/s; a run is never slower than the walk. */
    mm_gait_speed_estimate speeds[2][3];
    float moving_seconds; /* seconds of those windows faster than MM_GAIT_SPEED_MIN */
} mm_config_init_report;

typedef struct mm_config_init_desc {
    double scale;  /* file units to metres; 0: detect from the body's height */
    bool up_given; /* up_axis is the takes' up (0..5 as mm_axis_name); else detected */
    int up_axis;
    bool forward_given; /* forward_axis is the way the character faces (0..5); else mm_axes_forward's */
    int forward_axis;
    bool no_tuning; /* leave contacts and the runtime at their defaults (but the speeds). Else the
                       tuning measured on motion capture (configs/mocap.json, docs/config.md):
                       contacts.speed 0.3, runtime sync_halflife 0.1, distance matching and
                       warping on, walk rotation_halflife 0.3, run rotation_halflife 0.35 and
                       velocity_halflife 0.4 */
} mm_config_init_desc;

/* Makes the config of takes[0 .. count-1] (one skeleton: the same joints and parents, listed in
 * any order) into out (mm_config_defaults, then what
 * was found: interval 1/60, scale, roles, forward axis, matched bones, mirror pairs, walk and
 * run speeds, the tuning (mm_config_init_desc), one locomotion and one idle clip per take where
 * it has such spans; free with mm_config_free). desc may be NULL (detect the unit, with the
 * tuning). report (may be NULL) receives what
 * was found and how sure it is. Errors: MM_ERR_INVALID_ARGUMENT (takes standing along different
 * axes, forward along up, another skeleton), MM_ERR_OUT_OF_RANGE (no unit gives a human height), the role
 * finder's, MM_ERR_NOT_FOUND (no take has frames to use). */
mm_result mm_config_init(const mm_config_init_take *takes, int count, const mm_config_init_desc *desc,
                         mm_config *out, mm_config_init_report *report, mm_error *err);

#ifdef __cplusplus
}
#endif

#endif /* MM_CONFIG_INIT_H */
