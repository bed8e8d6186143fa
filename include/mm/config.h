/* mm/config.h - what a database is built from: sampling, bone roles, matched features, clips,
 * tags and blend clips; and the runtime tuning a database carries along (the mm_build library).
 *
 * The config is plain C data. It is usually read from JSON (mm/config_json.h); docs/config.md
 * documents every field with its meaning, unit and default, and `mm config explain` prints the
 * same text. mm_config_defaults gives the defaults listed there. mm_database_build
 * (mm/database_build.h) writes the runtime tuning into the database's settings section in binary
 * (mm_database_settings, mm/database.h), which the runtime reads without this header.
 *
 * Time ranges: clip frame ranges are half-open [begin, end) in frames of the source file; tag
 * ranges are [begin, end] in seconds from the start of the source file.
 *
 * Functions: mm_config_defaults mm_config_free mm_config_validate mm_config_tag_index
 *            mm_axis_name mm_axis_parse mm_axes_forward mm_axes_turn
 */
#ifndef MM_CONFIG_H
#define MM_CONFIG_H

#include <stdbool.h>

#include "alloc.h"
#include "database.h"
#include "math.h"
#include "result.h"
#include "skeleton.h"

#ifdef __cplusplus
extern "C" {
#endif

/* MM_MAX_TAGS, MM_TAG_NAME_MAX, MM_MAX_MATCH_BONES, MM_MAX_TRAJ_SAMPLES and mm_clip_type are in
 * mm/database.h, shared with the databases. */
#define MM_MAX_MIRROR_PAIRS 8 /* left/right name patterns */
#define MM_PATH_MAX         512
#define MM_CONFIG_MAX_CLIPS 1000000 /* clips, and blend clips, a config may list */

/* Feature kinds of a matched bone (bit mask). */
enum mm_match_features { MM_MATCH_POSITION = 1u << 0, MM_MATCH_VELOCITY = 1u << 1 };

typedef struct mm_config_bone {
    char name[MM_NAME_MAX];
    unsigned features;     /* mm_match_features: which features the database stores */
    float position_weight; /* the seed's JointPositionWeights entry */
    float velocity_weight; /* the seed's JointVelocityWeights entry */
} mm_config_bone;

typedef struct mm_config_range {
    int begin, end; /* source frames, half-open */
} mm_config_range;

typedef struct mm_config_tag_range {
    int tag;          /* index into mm_config.tag_names */
    float begin, end; /* seconds from the start of the source file, inclusive */
} mm_config_tag_range;

typedef struct mm_config_clip {
    char name[MM_NAME_MAX];
    char file[MM_PATH_MAX]; /* as written in the config; resolved by the loader */
    char take[MM_NAME_MAX]; /* the take to use in a file with several (FBX, glTF); empty: the first */
    mm_clip_type type;
    bool loop;
    bool mirror; /* also add the mirrored clip ("<name>_mirror") */
    int range_count;
    mm_config_range *ranges; /* [range_count]; none: the whole file. Each range is a clip. */
    int tag_range_count;
    mm_config_tag_range *tag_ranges;
} mm_config_clip;

typedef struct mm_config_blend {
    char name[MM_NAME_MAX];
    int left, right; /* indices into clips */
    float weight;    /* the left clip has weight w, the right 1 - w; loop = both loop */
} mm_config_blend;

typedef struct mm_config_mirror_pair {
    char left[MM_NAME_MAX], right[MM_NAME_MAX]; /* name substrings, e.g. "Left" / "Right" */
} mm_config_mirror_pair;

/* Runtime tuning a config may carry (its "runtime" object): what the character controller and
 * the search use at run time, so that a database brings its tuning along. Nothing here changes
 * the database's motion; a field whose bit (mm_runtime_field, mm/database.h) is not in `set` is
 * not set and keeps the runtime's default. mm_database_build stores it in the database's settings
 * section (mm_database_settings); mm_character_desc_apply_config applies it to a desc directly.
 * mm_runtime_gait (one gait's speeds and half-lives) is in mm/database.h. */
typedef struct mm_runtime_config {
    unsigned set;                /* mm_runtime_field bits of the fields given */
    float pose_trajectory_ratio; /* [0, 1] (mm_search_params) */
    float next_pose_favour;      /* > 0 */
    float loop_anim_favour;      /* > 0 */
    float continuing_bias;       /* >= 0 */
    float search_interval;       /* s, > 0 (mm_character_desc) */
    float transition_halflife;   /* s, > 0 */
    float idle_speed;            /* m/s, >= 0 */
    float sync_halflife;         /* s, [0, 60] (mm_character_desc) */
    bool distance_matching;      /* mm_character_desc's switches (mm/character.h) */
    bool warping;
    mm_runtime_gait walk, run, crouch;
    float contact_favour; /* >= 1 (mm_search_params.contact_mismatch_favour) */
    bool speed_envelope;  /* the desired velocity bounded by the data's speed envelope (default true) */
} mm_runtime_config;

typedef struct mm_config {
    /* Sampling and units */
    float interval; /* seconds between database frames (the seed's Interval); default 1/60 */
    float scale;    /* multiplies source lengths to get metres; 0: detect (docs/bvh.md) */

    /* The takes' axes, as mm_axis_name numbers them (0..5: +X +Y +Z -X -Y -Z): the way up and the way
     * the character faces in the files. mm_config_load_sources turns every clip to +Y up and +Z
     * forward (mm_axes_turn, mm_clip_turn). Default +Y up; forward -1: the one that goes with up
     * (mm_axes_forward). */
    int axes_up, axes_forward;

    /* Bone roles (names in the source skeleton) */
    char hips[MM_NAME_MAX];
    char root_bone[MM_NAME_MAX];   /* spine bone projected to the ground for the root position */
    char facing_bone[MM_NAME_MAX]; /* bone whose forward_axis, projected to the ground, is the facing */
    mm_vec3 forward_axis;          /* in facing_bone's local frame */
    char left_foot[MM_NAME_MAX], right_foot[MM_NAME_MAX];
    char left_toe[MM_NAME_MAX], right_toe[MM_NAME_MAX];
    char left_hand[MM_NAME_MAX], right_hand[MM_NAME_MAX];
    char head[MM_NAME_MAX];

    /* Root extraction */
    float root_smoothing; /* seconds: width (sigma) of the Gaussian smoothing root position and
                             facing; default 0.1; 0 disables */

    /* Contacts */
    float contact_height;            /* metres above the ground under which a foot/toe may be in contact */
    float contact_speed;             /* metres/second under which it may be in contact */
    float contact_min_time;          /* seconds: shorter runs of on or off are flicker and removed */
    float contact_planted_tolerance; /* metres above its planted height under which it may be in
                                        contact (docs/database.md, "Contacts"); default 0.01 */

    /* Postures (mm/posture.h): locomotion and idle clips lose their calibration and lying frames,
     * and their crouched and bent-over frames are tagged Crouch (docs/database.md, "Postures") */
    bool postures_detect; /* default true */
    float postures_pad;   /* seconds kept out around a removed posture; default 0.25 */

    /* Standing: when no clip is an idle clip, the build makes one from the takes' stillest
     * standing frame, held (docs/database.md, "A standing pose when the takes have no idle") */
    bool standing_make; /* default true */

    /* Idle loops: each idle clip with a still stretch gets a loop clip made of it, seamless, that
     * a character standing still plays without end (docs/database.md, "Idle that loops") */
    bool idle_loop_make; /* default true */

    /* Features */
    int bone_count;
    mm_config_bone bones[MM_MAX_MATCH_BONES]; /* the seed's Bones */
    int traj_count;
    float traj_times[MM_MAX_TRAJ_SAMPLES]; /* seconds, negative = past (the seed's TrajPoints) */
    bool root_velocity;                    /* store the root velocity feature group */
    float body_velocity_weight;            /* the seed's BodyVelocityWeight */
    float position_multiplier;             /* trajectory position weight (PositionMultiplier) */
    float angle_multiplier;                /* trajectory direction weight (AngleMultiplier) */

    /* Mirroring */
    int mirror_pair_count;
    mm_config_mirror_pair mirror_pairs[MM_MAX_MIRROR_PAIRS]; /* default Left/Right, left/right, L/R prefix */

    /* Tags */
    int tag_count;
    char tag_names[MM_MAX_TAGS][MM_TAG_NAME_MAX];

    /* Clips */
    int clip_count;
    mm_config_clip *clips;
    int blend_count;
    mm_config_blend *blends;

    /* Runtime tuning (not used to build the database); zeroed: nothing set */
    mm_runtime_config runtime;

    char base_dir[MM_PATH_MAX]; /* folder relative clip paths start from (the config's folder) */
    char data_dir[MM_PATH_MAX]; /* another folder for relative clip paths, looked at after base_dir
                                   and before $MM_DATA_DIR (mm db build --data); may be empty */
    mm_allocator allocator;
} mm_config;

/* Fills c with the documented defaults and no clips. */
void mm_config_defaults(mm_config *c);

/* Axes by number: 0..5 are +X, +Y, +Z, -X, -Y, -Z. */
#define MM_AXIS_POS_X 0
#define MM_AXIS_POS_Y 1
#define MM_AXIS_POS_Z 2
#define MM_AXIS_NEG_X 3
#define MM_AXIS_NEG_Y 4
#define MM_AXIS_NEG_Z 5

/* "+X", "+Y", "+Z", "-X", "-Y", "-Z"; NULL if out of range. */
const char *mm_axis_name(int axis);

/* The number of an axis name ("+Z", "-y"; a bare "Z" is +Z); -1 for anything else. */
int mm_axis_parse(const char *name);

/* The forward that goes with an up axis when none is given: +Z, except for a body standing along
 * Z, where it is -Y for +Z up (Blender's and 3ds Max's front view: the character faces -Y) and +Y
 * for -Z up; forward itself when it is an axis (0..5). */
int mm_axes_forward(int up, int forward);

/* The rotation that turns a world with these axes (forward -1: mm_axes_forward's) to +Y up and +Z
 * forward: the identity for +Y, +Z. Both must be axes and at right angles (mm_config_validate);
 * else the identity. */
mm_quat mm_axes_turn(int up, int forward);
/* Frees the clip, range and blend arrays (allocated by the JSON loader or by the caller with
 * c->allocator). */
void mm_config_free(mm_config *c);
/* Checks ranges of every number and the references between fields; err names the field. */
mm_result mm_config_validate(const mm_config *c, mm_error *err);
/* Index of a tag name, or -1. */
int mm_config_tag_index(const mm_config *c, const char *name);

#ifdef __cplusplus
}
#endif

#endif /* MM_CONFIG_H */
