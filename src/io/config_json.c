/* Database configs in JSON (cJSON), their documentation table, and loading the clips they name. */
#define _POSIX_C_SOURCE 200809L
#define _XOPEN_SOURCE   700 /* realpath */
#include <mm/config_json.h>

#include <cjson/cJSON.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <mm/import.h>

#include "io/file.h"
#include "io/json_parse.h"
#include "io/name_set.h"

/* ---- documentation ---------------------------------------------------------------------- */

static const mm_config_field_doc docs[] = {
    {"extends", "string", "", "none",
     "A base config this one adds to: a path relative to this file's folder (or absolute). Its clips, "
     "blend clips and tag names come first and this file's are appended; objects (roles, contacts, features, "
     "runtime) are merged field by field and any other field given here replaces the base's. Bases may "
     "extend others; a cycle or a missing file is an error."},
    {"interval", "number", "s", "0.0166667 (1/60)",
     "Seconds between database frames (the seed's Interval: 0.05 gives 20 frames per second of animation). "
     "Every clip is resampled to it on C1 splines through its frames (docs/database.md, Resampling). A "
     "value within 0.001% of 1/N for a whole rate N (0.0166667, 0.05) is read as exactly 1/N, so that a "
     "tick at that rate is exactly one frame."},
    {"scale", "number", "", "0 (detect)",
     "Multiplies source lengths to get metres: 0.01 for centimetre files, 1 for metres. 0 detects the unit "
     "from the character's height (docs/bvh.md)."},
    {"axes.up", "string", "", "+Y",
     "The way up in the takes: +X, +Y, +Z, -X, -Y or -Z. Clips are turned to mm's +Y up as they are loaded "
     "for the build (the root joints' rotations, translations and rest offsets), so that every joint's "
     "world position is turned exactly. Files from Blender, 3ds Max and converted CMU takes are often +Z "
     "up. mm config init detects it from the poses (docs/config.md, \"Axes\")."},
    {"axes.forward", "string", "", "+Z (-Y for +Z up, +Y for -Z up)",
     "The way the character faces in the takes' world, at right angles to up: turned to mm's +Z with up. "
     "Only the world's turn about up depends on it (the database's features are in the character's own "
     "frame); give it to keep a character facing +X or -Z in its files facing +Z in mm's world."},
    {"roles.hips", "string", "", "Hips",
     "The pelvis joint, where the body starts: joints above it (a Root or Reference joint, whatever "
     "part of the travel they carry) are folded into the simulation bone, and the hips hang from it at "
     "their world place (docs/database.md, \"Roots\")."},
    {"roles.root_bone", "string", "", "Spine2",
     "Joint projected to the ground to give the simulation bone's position (a spine joint moves more "
     "steadily "
     "than the hips)."},
    {"roles.facing_bone", "string", "", "Hips",
     "Joint whose forward axis, projected to the ground, gives the simulation bone's facing."},
    {"roles.forward_axis", "[number, number, number]", "", "[0, 0, 1]",
     "The axis of facing_bone's local frame that points forward. Skeletons differ: LAFAN1's hips use [0, 1, "
     "0]."},
    {"roles.left_foot", "string", "", "LeftFoot",
     "Left ankle: the heel contact and a matched bone by default."},
    {"roles.right_foot", "string", "", "RightFoot", "Right ankle."},
    {"roles.left_toe", "string", "", "LeftToe", "Left toe: the toe contact."},
    {"roles.right_toe", "string", "", "RightToe", "Right toe."},
    {"roles.left_hand", "string", "", "LeftHand", "Left hand (used by moves that plant hands)."},
    {"roles.right_hand", "string", "", "RightHand", "Right hand."},
    {"roles.head", "string", "", "Head", "Head joint."},
    {"root_smoothing", "number", "s", "0.1",
     "Standard deviation of the Gaussian that smooths the simulation bone's position and facing over time. "
     "0 disables smoothing."},
    {"contacts.height", "number", "m", "0.05",
     "A heel or toe can be in contact when it is less than this above its floor (its own lowest steady "
     "height over the take: every clip of the same source file; a clip whose heels and toes all stay this "
     "much above it has its own)."},
    {"contacts.speed", "number", "m/s", "0.6", "... and moves horizontally slower than this."},
    {"contacts.min_time", "number", "s", "0.1",
     "Contact or lift-off runs shorter than this are flicker and are removed."},
    {"contacts.planted_tolerance", "number", "m", "0.01",
     "... and is at most this above its planted height: the median height above its floor of its low, slow "
     "frames over the take, where it comes to rest (a foot still coming down is not yet in contact)."},
    {"postures.detect", "bool", "", "true",
     "Judge the posture of every frame of the locomotion and idle clips (docs/database.md, \"Postures\"): "
     "calibration poses (arms straight out) and lying frames are left out, with postures.pad around them; "
     "crouched and bent-over frames get the tag Crouch (added after the config's tags unless one of them is "
     "named so), the crouch gait, which an ordinary walk or run does not play. Frames the config tags with a "
     "gait (walk, run, crouch, jump) keep what the config says."},
    {"postures.pad", "number", "s", "0.25", "Seconds left out before and after a calibration or lying pose."},
    {"standing.make", "bool", "", "true",
     "When no clip is an idle clip, make some: the stillest standing frame of the locomotion clips (upright, "
     "both feet down, the root and joints slowest around it, the feet side by side under the body), and up "
     "to 3 others nearly as still from other clips, each held for 2 s as an idle loop named "
     "standing_from_<clip>_<frame> (mirrored too when its clip is), so that a character told to stop stands "
     "still instead of sliding on walking frames (docs/database.md, \"A standing pose when the takes have no "
     "idle\"). mm db build says which frames it took; false: none."},
    {"idle_loop.make", "bool", "", "true",
     "Give every idle clip that has a still stretch (root and joints slow, at least 1 s) a loop clip made of "
     "it: the stretch cut where its end pose meets an earlier pose best (joint positions and velocities), "
     "the seam's difference spread over the loop's last 0.3 s so that pose and velocity run on across it, "
     "an idle clip named <clip>_loop (mirrored too when its clip is) that playback wraps, so that a "
     "character standing still plays on instead of jumping back from the end of its clip (docs/database.md, "
     "\"Idle that loops\"). mm db build says how many it made; false: none."},
    {"features.bones", "[object]", "", "LeftFoot, RightFoot (position and velocity), Hips (velocity)",
     "The bones whose position and velocity, relative to the character, are matched (the seed's Bones)."},
    {"features.bones[].name", "string", "", "", "Joint name."},
    {"features.bones[].position", "bool", "", "true", "Store the bone's position (3 dimensions)."},
    {"features.bones[].velocity", "bool", "", "true", "Store the bone's velocity (3 dimensions)."},
    {"features.bones[].position_weight", "number", "", "0.75 (feet), 0",
     "The seed's JointPositionWeights entry: how much the position matters. Feet most, neck next, hands "
     "little."},
    {"features.bones[].velocity_weight", "number", "", "1",
     "The seed's JointVelocityWeights entry: how much the velocity matters (helps; usually lower)."},
    {"features.trajectory_times", "[number]", "s", "[0.333, 0.667, 1.0]",
     "Times of the trajectory samples relative to the current frame (the seed's TrajPoints); negative times "
     "are the past (e.g. -0.33). Each time stores the root position (x, z) and facing (x, z) then."},
    {"features.root_velocity", "bool", "", "false",
     "Also store the simulation bone's velocity (3 dimensions), weighted by body_velocity_weight."},
    {"features.body_velocity_weight", "number", "", "1",
     "The seed's BodyVelocityWeight: weight of the root velocity."},
    {"features.position_multiplier", "number", "", "1",
     "The seed's PositionMultiplier: weight of the trajectory positions."},
    {"features.angle_multiplier", "number", "", "1.5",
     "The seed's AngleMultiplier: weight of the trajectory directions."},
    {"mirror_pairs", "[[string, string]]", "", "[[\"Left\", \"Right\"], [\"left\", \"right\"]]",
     "Name patterns of left and right joints for mirroring: a joint whose name contains the left pattern "
     "pairs with the joint named with the right pattern instead. A pattern starting with ^ matches only "
     "at the start (e.g. [\"^l\", \"^r\"] for lHip / rHip). A one-letter pattern names a side only "
     "where no lowercase letter follows it (lHip, Hand_L; not lowerback)."},
    {"tags", "[string]", "", "[]",
     "Names of the tags clips may use (at most 64), e.g. the seed's Required and DoNotUse."},
    {"clips", "[object]", "", "",
     "The clips (the seed's IdleClips and LocomotionClips). Each frame range of a clip becomes a database "
     "clip."},
    {"clips[].name", "string", "", "the file name",
     "Unique name; ranges add #0, #1...; mirrors add _mirror."},
    {"clips[].file", "string", "", "",
     "Motion file: absolute, or relative to the config's folder, to the folder given by mm db build --data, "
     "or "
     "to $MM_DATA_DIR (looked up in that order)."},
    {"clips[].take", "string", "", "the first take",
     "For files with several takes (FBX, glTF, Collada; `mm import info FILE` lists them): the take's name."},
    {"clips[].ranges", "[[int, int]]", "frames", "the whole file",
     "Half-open frame ranges [begin, end) in the file's own frames; each becomes a clip."},
    {"clips[].type", "string", "", "locomotion", "idle or locomotion: the search can require either."},
    {"clips[].loop", "bool", "", "false",
     "The frame after the last is the first: playback and trajectories wrap. A loop clip has one range."},
    {"clips[].mirror", "bool", "", "false",
     "Also add the clip mirrored left to right (data augmentation; docs/database.md, \"Mirroring\"). "
     "Refused when a joint named for a side has no partner, or partners' bones differ in length by more "
     "than 10%."},
    {"clips[].tags", "{string: [[number, number]]}", "s", "{}",
     "Tag ranges: for each tag name, [begin, end] times in seconds from the start of the file."},
    {"blend_clips", "[object]", "", "[]",
     "Clips made by blending two clips on a common time base (the seed's BlendClips), from each source's "
     "first "
     "range (and from their mirrors too when both are mirrored); loop when both loop."},
    {"blend_clips[].name", "string", "", "", "Unique name."},
    {"blend_clips[].left", "string", "", "", "Name of the left source clip."},
    {"blend_clips[].right", "string", "", "", "Name of the right source clip."},
    {"blend_clips[].weight", "number", "", "0.5", "Weight of the left clip; the right gets 1 - weight."},
    {"runtime", "object", "", "{}",
     "Runtime tuning the database carries along (it changes nothing in the database): the character's and "
     "its search's parameters, saved by a viewer's live tuning. A field left out keeps the runtime's "
     "default."},
    {"runtime.pose_trajectory_ratio", "number", "", "0.5",
     "The seed's PoseTrajectoryRatio, in [0, 1]: higher follows the trajectory more (more responsive, less "
     "smooth)."},
    {"runtime.next_pose_favour", "number", "", "0.6",
     "The seed's NextPoseFavour, above 0: factor on the cost of the frame after the one playing; lower keeps "
     "playing."},
    {"runtime.contact_favour", "number", "", "2",
     "At least 1: factor on the cost of frames whose feet are in other contacts than the frame playing's "
     "(a planted foot in the air, or the other way round); 1 is off."},
    {"runtime.loop_anim_favour", "number", "", "1",
     "The seed's LoopAnimFavour, above 0: factor on the cost of frames of loop clips; lower prefers loops."},
    {"runtime.continuing_bias", "number", "", "0",
     "At least 0: subtracted from the cost of the frame after the one playing; a jump must gain this much."},
    {"runtime.search_interval", "number", "s", "0.1",
     "Seconds between searches (a sharp input change or a clip's end searches at once)."},
    {"runtime.transition_halflife", "number", "s", "0.2",
     "Half-life of the inertialization that hides a jump to another frame: longer is smoother and slower."},
    {"runtime.idle_speed", "number", "m/s", "0.15",
     "Desired speed under which the character asks for idle frames."},
    {"runtime.sync_halflife", "number", "s", "0.3",
     "Half-life with which the character's root is pulled toward the simulated trajectory, in [0, 60]: "
     "shorter follows the input more closely (more foot slide), 0 puts the root on the simulation every "
     "tick."},
    {"runtime.distance_matching", "bool", "", "false",
     "Distance matching (docs/distance.md, \"In the controller\"): clips advance by the distance travelled, "
     "stops and pivots match the predicted points, cycles play at the speed asked."},
    {"runtime.warping", "bool", "", "false",
     "Stride and orientation warping of the legs (docs/distance.md); mm simulate's --distance-matching and "
     "--warping override both."},
    {"runtime.speed_envelope", "bool", "", "true",
     "Bound each gait's desired velocity by the speed the database's own locomotion covers in its "
     "direction (the envelope mm db info prints; docs/runtime.md, \"The speed envelope\"): false asks "
     "for the gait speeds alone."},
    {"runtime.walk", "object", "", "", "The walk gait's speeds and half-lives (fields below)."},
    {"runtime.walk.forward_speed", "number", "m/s", "1.5",
     "Speed at full stick, straight ahead (at least 0)."},
    {"runtime.walk.side_speed", "number", "m/s", "1.1", "Speed at full stick, sideways (strafing)."},
    {"runtime.walk.backward_speed", "number", "m/s", "1", "Speed at full stick, backwards (strafing)."},
    {"runtime.walk.velocity_halflife", "number", "s", "0.25",
     "How quickly the velocity follows the stick (the seed's acceleration and drag); above 0."},
    {"runtime.walk.rotation_halflife", "number", "s", "0.2",
     "How quickly the facing follows (the seed's angular speed); above 0."},
    {"runtime.run", "object", "", "", "The run gait: the fields of runtime.walk."},
    {"runtime.run.forward_speed", "number", "m/s", "4", "As runtime.walk.forward_speed."},
    {"runtime.run.side_speed", "number", "m/s", "2.6", "As runtime.walk.side_speed."},
    {"runtime.run.backward_speed", "number", "m/s", "2.2", "As runtime.walk.backward_speed."},
    {"runtime.run.velocity_halflife", "number", "s", "0.3", "As runtime.walk.velocity_halflife."},
    {"runtime.run.rotation_halflife", "number", "s", "0.25", "As runtime.walk.rotation_halflife."},
    {"runtime.crouch", "object", "", "", "The crouch gait: the fields of runtime.walk."},
    {"runtime.crouch.forward_speed", "number", "m/s", "0.9", "As runtime.walk.forward_speed."},
    {"runtime.crouch.side_speed", "number", "m/s", "0.7", "As runtime.walk.side_speed."},
    {"runtime.crouch.backward_speed", "number", "m/s", "0.6", "As runtime.walk.backward_speed."},
    {"runtime.crouch.velocity_halflife", "number", "s", "0.25", "As runtime.walk.velocity_halflife."},
    {"runtime.crouch.rotation_halflife", "number", "s", "0.2", "As runtime.walk.rotation_halflife."},
};

const mm_config_field_doc *mm_config_field_docs(int *count)
{
    if (count) *count = (int)(sizeof docs / sizeof docs[0]);
    return docs;
}

/* ---- parsing ---------------------------------------------------------------------------- */

typedef struct ctx {
    mm_config *cfg;
    mm_error *err;
    const mm__json_where *where; /* where each value is in the text (numbers as written) */
} ctx;

#define FAIL(code, ...) mm_error_set(c->err, code, 0, 0, __VA_ARGS__)

static int is_one_of(const char *key, const char *const *keys)
{
    for (; *keys; ++keys)
        if (strcmp(key, *keys) == 0) return 1;
    return 0;
}

static mm_result check_keys(ctx *c, const cJSON *obj, const char *where, const char *const *keys)
{
    if (!cJSON_IsObject(obj))
        return FAIL(MM_ERR_SYNTAX, "%s must be an object", where[0] ? where : "the config");
    for (const cJSON *it = obj->child; it; it = it->next)
        if (!is_one_of(it->string, keys))
            return FAIL(MM_ERR_UNKNOWN_KEYWORD, "%s%s%s: unknown field (see mm config explain)", where,
                        where[0] ? "." : "", it->string);
    return MM_OK;
}

/* A number a float holds: one that does not is reported as written, not as the inf it would become. */
static mm_result float_of(ctx *c, const cJSON *v, const char *what, float *out)
{
    if (!cJSON_IsNumber(v) || !isfinite(v->valuedouble))
        return FAIL(MM_ERR_BAD_NUMBER, "%s must be a finite number", what);
    if (fabs(v->valuedouble) > FLT_MAX) {
        size_t n = 0;
        const char *text = mm__json_number_text(c->where, v, &n);
        return FAIL(MM_ERR_BAD_NUMBER, "%s: %.*s does not fit a float (at most %g)", what,
                    text ? (int)(n < 40 ? n : 40) : 5, text ? text : "large", (double)FLT_MAX);
    }
    *out = (float)v->valuedouble;
    return MM_OK;
}

static mm_result get_number(ctx *c, const cJSON *obj, const char *key, const char *where, float *out)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!v) return MM_OK;
    char what[160];
    snprintf(what, sizeof what, "%s%s%s", where, where[0] ? "." : "", key);
    return float_of(c, v, what, out);
}

static mm_result get_bool(ctx *c, const cJSON *obj, const char *key, const char *where, bool *out)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!v) return MM_OK;
    if (!cJSON_IsBool(v))
        return FAIL(MM_ERR_SYNTAX, "%s%s%s must be true or false", where, where[0] ? "." : "", key);
    *out = cJSON_IsTrue(v);
    return MM_OK;
}

static mm_result copy_string(ctx *c, const cJSON *v, const char *what, char *out, size_t size)
{
    if (!cJSON_IsString(v) || !v->valuestring) return FAIL(MM_ERR_SYNTAX, "%s must be a string", what);
    size_t n = strlen(v->valuestring);
    if (n >= size) return FAIL(MM_ERR_LIMIT, "%s is %zu characters (at most %zu)", what, n, size - 1);
    memcpy(out, v->valuestring, n + 1);
    return MM_OK;
}

static mm_result get_string(ctx *c, const cJSON *obj, const char *key, const char *where, char *out,
                            size_t size)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!v) return MM_OK;
    char what[160];
    snprintf(what, sizeof what, "%s%s%s", where, where[0] ? "." : "", key);
    return copy_string(c, v, what, out, size);
}

static mm_result get_int(ctx *c, const cJSON *v, const char *what, int *out)
{
    if (!cJSON_IsNumber(v) || !isfinite(v->valuedouble) || v->valuedouble != floor(v->valuedouble) ||
        fabs(v->valuedouble) > 2e9)
        return FAIL(MM_ERR_BAD_NUMBER, "%s must be an integer", what);
    *out = (int)v->valuedouble;
    return MM_OK;
}

static mm_result parse_roles(ctx *c, const cJSON *roles)
{
    static const char *const keys[] = {"hips",      "root_bone",  "facing_bone", "forward_axis",
                                       "left_foot", "right_foot", "left_toe",    "right_toe",
                                       "left_hand", "right_hand", "head",        NULL};
    mm_result r = check_keys(c, roles, "roles", keys);
    mm_config *cfg = c->cfg;
    char *fields[] = {cfg->hips,     cfg->root_bone, cfg->facing_bone, cfg->left_foot,  cfg->right_foot,
                      cfg->left_toe, cfg->right_toe, cfg->left_hand,   cfg->right_hand, cfg->head};
    const char *names[] = {"hips",     "root_bone", "facing_bone", "left_foot",  "right_foot",
                           "left_toe", "right_toe", "left_hand",   "right_hand", "head"};
    for (int i = 0; i < 10 && r == MM_OK; ++i)
        r = get_string(c, roles, names[i], "roles", fields[i], MM_NAME_MAX);
    const cJSON *axis = cJSON_GetObjectItemCaseSensitive(roles, "forward_axis");
    if (r == MM_OK && axis) {
        if (!cJSON_IsArray(axis) || cJSON_GetArraySize(axis) != 3)
            return FAIL(MM_ERR_SYNTAX, "roles.forward_axis must be an array of 3 numbers");
        float v[3];
        const cJSON *e = axis->child;
        for (int i = 0; i < 3; ++i, e = e->next) {
            char what[40];
            snprintf(what, sizeof what, "roles.forward_axis[%d]", i);
            if ((r = float_of(c, e, what, &v[i])) != MM_OK) return r;
        }
        cfg->forward_axis = mm_vec3_make(v[0], v[1], v[2]);
    }
    return r;
}

/* axes: {"up": "+Z", "forward": "-Y"}, each one of the six axis names */
static mm_result parse_axes(ctx *c, const cJSON *axes)
{
    static const char *const keys[] = {"up", "forward", NULL};
    mm_result r = check_keys(c, axes, "axes", keys);
    for (int k = 0; k < 2 && r == MM_OK; ++k) {
        char name[16] = "";
        if (!cJSON_GetObjectItemCaseSensitive(axes, keys[k])) continue;
        r = get_string(c, axes, keys[k], "axes", name, sizeof name);
        int axis = mm_axis_parse(name);
        if (r == MM_OK && axis < 0)
            return FAIL(MM_ERR_SYNTAX, "axes.%s: '%s' is not an axis: one of +X, +Y, +Z, -X, -Y, -Z", keys[k],
                        name);
        if (r == MM_OK) *(k == 0 ? &c->cfg->axes_up : &c->cfg->axes_forward) = axis;
    }
    return r;
}

static mm_result parse_features(ctx *c, const cJSON *f)
{
    static const char *const keys[] = {"bones",
                                       "trajectory_times",
                                       "root_velocity",
                                       "body_velocity_weight",
                                       "position_multiplier",
                                       "angle_multiplier",
                                       NULL};
    mm_config *cfg = c->cfg;
    mm_result r = check_keys(c, f, "features", keys);
    if (r == MM_OK) r = get_bool(c, f, "root_velocity", "features", &cfg->root_velocity);
    if (r == MM_OK) r = get_number(c, f, "body_velocity_weight", "features", &cfg->body_velocity_weight);
    if (r == MM_OK) r = get_number(c, f, "position_multiplier", "features", &cfg->position_multiplier);
    if (r == MM_OK) r = get_number(c, f, "angle_multiplier", "features", &cfg->angle_multiplier);
    if (r != MM_OK) return r;
    const cJSON *bones = cJSON_GetObjectItemCaseSensitive(f, "bones");
    if (bones) {
        if (!cJSON_IsArray(bones)) return FAIL(MM_ERR_SYNTAX, "features.bones must be an array");
        int n = cJSON_GetArraySize(bones);
        if (n > MM_MAX_MATCH_BONES)
            return FAIL(MM_ERR_LIMIT, "features.bones: %d bones (at most %d)", n, MM_MAX_MATCH_BONES);
        cfg->bone_count = n;
        static const char *const bkeys[] = {
            "name", "position", "velocity", "position_weight", "velocity_weight", NULL};
        const cJSON *b = bones->child;
        for (int i = 0; i < n; ++i, b = b->next) {
            char where[64];
            snprintf(where, sizeof where, "features.bones[%d]", i);
            mm_config_bone *cb = &cfg->bones[i];
            memset(cb, 0, sizeof *cb);
            cb->velocity_weight = 1.0f;
            bool pos = true, vel = true;
            if ((r = check_keys(c, b, where, bkeys)) != MM_OK) return r;
            const cJSON *name = cJSON_GetObjectItemCaseSensitive(b, "name");
            if (!name) return FAIL(MM_ERR_SYNTAX, "%s.name is missing", where);
            if ((r = get_string(c, b, "name", where, cb->name, MM_NAME_MAX)) != MM_OK) return r;
            if ((r = get_bool(c, b, "position", where, &pos)) != MM_OK) return r;
            if ((r = get_bool(c, b, "velocity", where, &vel)) != MM_OK) return r;
            if ((r = get_number(c, b, "position_weight", where, &cb->position_weight)) != MM_OK) return r;
            if ((r = get_number(c, b, "velocity_weight", where, &cb->velocity_weight)) != MM_OK) return r;
            cb->features = (pos ? MM_MATCH_POSITION : 0u) | (vel ? MM_MATCH_VELOCITY : 0u);
        }
    }
    const cJSON *times = cJSON_GetObjectItemCaseSensitive(f, "trajectory_times");
    if (times) {
        if (!cJSON_IsArray(times)) return FAIL(MM_ERR_SYNTAX, "features.trajectory_times must be an array");
        int n = cJSON_GetArraySize(times);
        if (n > MM_MAX_TRAJ_SAMPLES)
            return FAIL(MM_ERR_LIMIT, "features.trajectory_times: %d times (at most %d)", n,
                        MM_MAX_TRAJ_SAMPLES);
        cfg->traj_count = n;
        const cJSON *e = times->child;
        for (int i = 0; i < n; ++i, e = e->next) {
            char what[48];
            snprintf(what, sizeof what, "features.trajectory_times[%d]", i);
            if ((r = float_of(c, e, what, &cfg->traj_times[i])) != MM_OK) return r;
        }
    }
    return MM_OK;
}

static mm_result parse_pair_list(ctx *c, const cJSON *arr, const char *where, int max, int *count,
                                 mm_config_range *ranges, float (*times)[2])
{
    if (!cJSON_IsArray(arr)) return FAIL(MM_ERR_SYNTAX, "%s must be an array of [begin, end] pairs", where);
    int n = cJSON_GetArraySize(arr);
    if (n > max) return FAIL(MM_ERR_LIMIT, "%s: %d entries (at most %d)", where, n, max);
    const cJSON *p = arr->child;
    for (int i = 0; i < n; ++i, p = p->next) {
        char what[200];
        snprintf(what, sizeof what, "%s[%d]", where, i);
        if (!cJSON_IsArray(p) || cJSON_GetArraySize(p) != 2)
            return FAIL(MM_ERR_SYNTAX, "%s must be a [begin, end] pair", what);
        if (ranges) {
            mm_result r = get_int(c, p->child, what, &ranges[i].begin);
            if (r == MM_OK) r = get_int(c, p->child->next, what, &ranges[i].end);
            if (r != MM_OK) return r;
        } else {
            const cJSON *e = p->child;
            for (int k = 0; k < 2; ++k, e = e->next) {
                if (!cJSON_IsNumber(e) || !isfinite(e->valuedouble))
                    return FAIL(MM_ERR_BAD_NUMBER, "%s must hold two finite numbers", what);
                mm_result r = float_of(c, e, what, &times[i][k]);
                if (r != MM_OK) return r;
            }
        }
    }
    *count = n;
    return MM_OK;
}

static mm_result parse_clip(ctx *c, const cJSON *j, int i, mm_config_clip *clip)
{
    static const char *const keys[] = {"name", "file",   "take", "ranges", "type",
                                       "loop", "mirror", "tags", NULL};
    mm_config *cfg = c->cfg;
    char where[64];
    snprintf(where, sizeof where, "clips[%d]", i);
    mm_result r = check_keys(c, j, where, keys);
    if (r != MM_OK) return r;
    const cJSON *file = cJSON_GetObjectItemCaseSensitive(j, "file");
    if (!file) return FAIL(MM_ERR_SYNTAX, "%s.file is missing", where);
    if ((r = get_string(c, j, "file", where, clip->file, MM_PATH_MAX)) != MM_OK) return r;
    if ((r = get_string(c, j, "take", where, clip->take, MM_NAME_MAX)) != MM_OK) return r;
    if (cJSON_GetObjectItemCaseSensitive(j, "name")) {
        if ((r = get_string(c, j, "name", where, clip->name, MM_NAME_MAX)) != MM_OK) return r;
    } else { /* the file name without folder and extension */
        const char *base = strrchr(clip->file, '/');
        base = base ? base + 1 : clip->file;
        size_t n = strcspn(base, ".");
        snprintf(clip->name, MM_NAME_MAX, "%.*s", (int)(n < MM_NAME_MAX - 1 ? n : MM_NAME_MAX - 1), base);
    }
    const cJSON *type = cJSON_GetObjectItemCaseSensitive(j, "type");
    if (type) {
        if (cJSON_IsString(type) && strcmp(type->valuestring, "idle") == 0)
            clip->type = MM_CLIP_IDLE;
        else if (cJSON_IsString(type) && strcmp(type->valuestring, "locomotion") == 0)
            clip->type = MM_CLIP_LOCOMOTION;
        else
            return FAIL(MM_ERR_SYNTAX, "%s.type must be \"idle\" or \"locomotion\"", where);
    }
    if ((r = get_bool(c, j, "loop", where, &clip->loop)) != MM_OK) return r;
    if ((r = get_bool(c, j, "mirror", where, &clip->mirror)) != MM_OK) return r;
    const cJSON *ranges = cJSON_GetObjectItemCaseSensitive(j, "ranges");
    if (ranges) {
        char w[80];
        snprintf(w, sizeof w, "%s.ranges", where);
        int n = cJSON_IsArray(ranges) ? cJSON_GetArraySize(ranges) : 0;
        if (n > 0) {
            clip->ranges =
                (mm_config_range *)mm_alloc_array(&cfg->allocator, (size_t)n, sizeof(mm_config_range));
            if (!clip->ranges) return FAIL(MM_ERR_OUT_OF_MEMORY, "out of memory");
        }
        if ((r = parse_pair_list(c, ranges, w, 100000, &clip->range_count, clip->ranges, NULL)) != MM_OK)
            return r;
    }
    const cJSON *tags = cJSON_GetObjectItemCaseSensitive(j, "tags");
    if (tags) {
        if (!cJSON_IsObject(tags))
            return FAIL(MM_ERR_SYNTAX, "%s.tags must be an object {tag: [[begin, end], ...]}", where);
        int total = 0;
        for (const cJSON *t = tags->child; t; t = t->next)
            total += cJSON_IsArray(t) ? cJSON_GetArraySize(t) : 0;
        if (total > 0) {
            clip->tag_ranges = (mm_config_tag_range *)mm_alloc_array(&cfg->allocator, (size_t)total,
                                                                     sizeof(mm_config_tag_range));
            if (!clip->tag_ranges) return FAIL(MM_ERR_OUT_OF_MEMORY, "out of memory");
        }
        for (const cJSON *t = tags->child; t; t = t->next) {
            int tag = mm_config_tag_index(cfg, t->string);
            if (tag < 0) return FAIL(MM_ERR_NOT_FOUND, "%s.tags.%s: not declared in tags", where, t->string);
            char w[120];
            snprintf(w, sizeof w, "%s.tags.%s", where, t->string);
            int n = 0;
            float(*times)[2] = (float(*)[2])calloc((size_t)(cJSON_IsArray(t) ? cJSON_GetArraySize(t) : 0) + 1,
                                                   sizeof *times);
            if (!times) return FAIL(MM_ERR_OUT_OF_MEMORY, "out of memory");
            r = parse_pair_list(c, t, w, 100000, &n, NULL, times);
            for (int k = 0; k < n && r == MM_OK; ++k) {
                mm_config_tag_range *tr = &clip->tag_ranges[clip->tag_range_count++];
                tr->tag = tag;
                tr->begin = times[k][0];
                tr->end = times[k][1];
            }
            free(times);
            if (r != MM_OK) return r;
        }
    }
    return MM_OK;
}

/* A number that sets bit in *set when present. */
static mm_result get_set_number(ctx *c, const cJSON *obj, const char *key, const char *where, float *out,
                                unsigned *set, unsigned bit)
{
    if (!cJSON_GetObjectItemCaseSensitive(obj, key)) return MM_OK;
    mm_result r = get_number(c, obj, key, where, out);
    if (r == MM_OK) *set |= bit;
    return r;
}

static mm_result parse_runtime(ctx *c, const cJSON *rt)
{
    static const char *const keys[] = {"pose_trajectory_ratio",
                                       "next_pose_favour",
                                       "loop_anim_favour",
                                       "continuing_bias",
                                       "search_interval",
                                       "transition_halflife",
                                       "idle_speed",
                                       "sync_halflife",
                                       "distance_matching",
                                       "warping",
                                       "walk",
                                       "run",
                                       "crouch",
                                       "contact_favour",
                                       "speed_envelope",
                                       NULL};
    static const char *const gkeys[] = {"forward_speed",     "side_speed",        "backward_speed",
                                        "velocity_halflife", "rotation_halflife", NULL};
    mm_runtime_config *o = &c->cfg->runtime;
    mm_result r = check_keys(c, rt, "runtime", keys);
    float *values[] = {
        &o->pose_trajectory_ratio, &o->next_pose_favour,    &o->loop_anim_favour, &o->continuing_bias,
        &o->search_interval,       &o->transition_halflife, &o->idle_speed,       &o->sync_halflife};
    for (int i = 0; i < 8 && r == MM_OK; ++i)
        r = get_set_number(c, rt, keys[i], "runtime", values[i], &o->set, 1u << i);
    /* 0 is allowed: the root is put on the simulation every tick */
    if (r == MM_OK && (o->set & MM_RUNTIME_SYNC_HALFLIFE) &&
        !(o->sync_halflife >= 0.0f && o->sync_halflife <= 60.0f))
        r = FAIL(MM_ERR_OUT_OF_RANGE, "runtime.sync_halflife: %g s is out of range (0 to 60 s)",
                 o->sync_halflife);
    if (r == MM_OK)
        r = get_set_number(c, rt, keys[13], "runtime", &o->contact_favour, &o->set,
                           MM_RUNTIME_CONTACT_FAVOUR);
    bool *switches[2] = {&o->distance_matching, &o->warping};
    for (int i = 0; i < 2 && r == MM_OK; ++i)
        if (cJSON_GetObjectItemCaseSensitive(rt, keys[8 + i])) {
            r = get_bool(c, rt, keys[8 + i], "runtime", switches[i]);
            o->set |= MM_RUNTIME_DISTANCE_MATCHING << i;
        }
    if (r == MM_OK && cJSON_GetObjectItemCaseSensitive(rt, keys[14])) {
        r = get_bool(c, rt, keys[14], "runtime", &o->speed_envelope);
        o->set |= MM_RUNTIME_SPEED_ENVELOPE;
    }
    mm_runtime_gait *gaits[3] = {&o->walk, &o->run, &o->crouch};
    for (int g = 0; g < 3 && r == MM_OK; ++g) {
        const cJSON *j = cJSON_GetObjectItemCaseSensitive(rt, keys[10 + g]);
        if (!j) continue;
        char where[32];
        snprintf(where, sizeof where, "runtime.%s", keys[10 + g]);
        mm_runtime_gait *p = gaits[g];
        float *fields[] = {&p->forward_speed, &p->side_speed, &p->backward_speed, &p->velocity_halflife,
                           &p->rotation_halflife};
        r = check_keys(c, j, where, gkeys);
        for (int k = 0; k < 5 && r == MM_OK; ++k)
            r = get_set_number(c, j, gkeys[k], where, fields[k], &p->set, 1u << k);
    }
    return r;
}

/* An interval written to a few digits stands for a whole frame rate: 0.0166667 is 1/60, not
 * 59.9999 frames per second, whose frames a 60 Hz tick would miss by 2e-6 of a frame every tick
 * (the playhead would sit just short of the frame it shows). Within 1e-5 of 1/N relatively (six
 * significant digits are within 5e-6) it is read as exactly 1/N; anything else as written. */
static float whole_rate_interval(float interval)
{
    if (!(interval > 0.0f) || !isfinite(interval)) return interval; /* validation reports it */
    double rate = 1.0 / (double)interval, n = floor(rate + 0.5);
    return n >= 1.0 && fabs(rate - n) <= 1e-5 * n ? (float)(1.0 / n) : interval;
}

static mm_result parse_root(ctx *c, const cJSON *root)
{
    static const char *const keys[] = {
        "interval", "scale",        "axes", "roles", "root_smoothing", "contacts", "postures",
        "features", "mirror_pairs", "tags", "clips", "blend_clips",    "runtime",  "extends",
        "standing", "idle_loop",    NULL};
    mm_config *cfg = c->cfg;
    mm_result r = check_keys(c, root, "", keys);
    if (r == MM_OK) r = get_number(c, root, "interval", "", &cfg->interval);
    if (r == MM_OK) cfg->interval = whole_rate_interval(cfg->interval);
    if (r == MM_OK) r = get_number(c, root, "scale", "", &cfg->scale);
    if (r == MM_OK) r = get_number(c, root, "root_smoothing", "", &cfg->root_smoothing);
    if (r != MM_OK) return r;
    const cJSON *axes = cJSON_GetObjectItemCaseSensitive(root, "axes");
    if (axes && (r = parse_axes(c, axes)) != MM_OK) return r;
    const cJSON *roles = cJSON_GetObjectItemCaseSensitive(root, "roles");
    if (roles && (r = parse_roles(c, roles)) != MM_OK) return r;
    const cJSON *contacts = cJSON_GetObjectItemCaseSensitive(root, "contacts");
    if (contacts) {
        static const char *const ckeys[] = {"height", "speed", "min_time", "planted_tolerance", NULL};
        if ((r = check_keys(c, contacts, "contacts", ckeys)) != MM_OK) return r;
        if ((r = get_number(c, contacts, "height", "contacts", &cfg->contact_height)) != MM_OK) return r;
        if ((r = get_number(c, contacts, "speed", "contacts", &cfg->contact_speed)) != MM_OK) return r;
        if ((r = get_number(c, contacts, "min_time", "contacts", &cfg->contact_min_time)) != MM_OK) return r;
        if ((r = get_number(c, contacts, "planted_tolerance", "contacts", &cfg->contact_planted_tolerance)) !=
            MM_OK)
            return r;
    }
    const cJSON *postures = cJSON_GetObjectItemCaseSensitive(root, "postures");
    if (postures) {
        static const char *const pkeys[] = {"detect", "pad", NULL};
        if ((r = check_keys(c, postures, "postures", pkeys)) != MM_OK) return r;
        if ((r = get_bool(c, postures, "detect", "postures", &cfg->postures_detect)) != MM_OK) return r;
        if ((r = get_number(c, postures, "pad", "postures", &cfg->postures_pad)) != MM_OK) return r;
    }
    const cJSON *standing = cJSON_GetObjectItemCaseSensitive(root, "standing");
    if (standing) {
        static const char *const skeys[] = {"make", NULL};
        if ((r = check_keys(c, standing, "standing", skeys)) != MM_OK) return r;
        if ((r = get_bool(c, standing, "make", "standing", &cfg->standing_make)) != MM_OK) return r;
    }
    const cJSON *idle_loop = cJSON_GetObjectItemCaseSensitive(root, "idle_loop");
    if (idle_loop) {
        static const char *const ikeys[] = {"make", NULL};
        if ((r = check_keys(c, idle_loop, "idle_loop", ikeys)) != MM_OK) return r;
        if ((r = get_bool(c, idle_loop, "make", "idle_loop", &cfg->idle_loop_make)) != MM_OK) return r;
    }
    const cJSON *features = cJSON_GetObjectItemCaseSensitive(root, "features");
    if (features && (r = parse_features(c, features)) != MM_OK) return r;
    const cJSON *pairs = cJSON_GetObjectItemCaseSensitive(root, "mirror_pairs");
    if (pairs) {
        int n = cJSON_IsArray(pairs) ? cJSON_GetArraySize(pairs) : -1;
        if (n < 0 || n > MM_MAX_MIRROR_PAIRS)
            return FAIL(MM_ERR_SYNTAX, "mirror_pairs must be an array of at most %d [left, right] pairs",
                        MM_MAX_MIRROR_PAIRS);
        cfg->mirror_pair_count = n;
        const cJSON *p = pairs->child;
        for (int i = 0; i < n; ++i, p = p->next) {
            char w[40];
            snprintf(w, sizeof w, "mirror_pairs[%d]", i);
            if (!cJSON_IsArray(p) || cJSON_GetArraySize(p) != 2)
                return FAIL(MM_ERR_SYNTAX, "%s must be [left, right]", w);
            if ((r = copy_string(c, p->child, w, cfg->mirror_pairs[i].left, MM_NAME_MAX)) != MM_OK) return r;
            if ((r = copy_string(c, p->child->next, w, cfg->mirror_pairs[i].right, MM_NAME_MAX)) != MM_OK)
                return r;
        }
    }
    const cJSON *tags = cJSON_GetObjectItemCaseSensitive(root, "tags");
    if (tags) {
        int n = cJSON_IsArray(tags) ? cJSON_GetArraySize(tags) : -1;
        if (n < 0) return FAIL(MM_ERR_SYNTAX, "tags must be an array of names");
        if (n > MM_MAX_TAGS) return FAIL(MM_ERR_LIMIT, "tags: %d tags (at most %d)", n, MM_MAX_TAGS);
        const cJSON *t = tags->child;
        for (int i = 0; i < n; ++i, t = t->next) {
            char w[40];
            snprintf(w, sizeof w, "tags[%d]", i);
            if ((r = copy_string(c, t, w, cfg->tag_names[i], MM_TAG_NAME_MAX)) != MM_OK) return r;
            if (!cfg->tag_names[i][0]) return FAIL(MM_ERR_SYNTAX, "%s is empty", w);
            cfg->tag_count = i + 1;
            if (mm_config_tag_index(cfg, cfg->tag_names[i]) != i)
                return FAIL(MM_ERR_DUPLICATE_NAME, "%s: '%s' is listed twice", w, cfg->tag_names[i]);
        }
    }
    const cJSON *clips = cJSON_GetObjectItemCaseSensitive(root, "clips");
    if (clips) {
        int n = cJSON_IsArray(clips) ? cJSON_GetArraySize(clips) : -1;
        if (n < 0) return FAIL(MM_ERR_SYNTAX, "clips must be an array");
        if (n > MM_CONFIG_MAX_CLIPS)
            return FAIL(MM_ERR_LIMIT, "clips: %d clips (at most %d)", n, MM_CONFIG_MAX_CLIPS);
        if (n > 0) {
            cfg->clips = (mm_config_clip *)mm_alloc_array(&cfg->allocator, (size_t)n, sizeof(mm_config_clip));
            if (!cfg->clips) return FAIL(MM_ERR_OUT_OF_MEMORY, "out of memory");
        }
        const cJSON *j = clips->child;
        for (int i = 0; i < n; ++i, j = j->next) {
            cfg->clip_count = i + 1;
            if ((r = parse_clip(c, j, i, &cfg->clips[i])) != MM_OK) return r;
        }
        /* names compared through a hash table (mm_config_validate says which is used twice) */
        int twice = n > 0 ? mm__name_set_first_repeat(cfg->clips[0].name, sizeof(mm_config_clip), n) : -1;
        if (twice == -2) return FAIL(MM_ERR_OUT_OF_MEMORY, "out of memory");
        if (twice >= 0)
            return FAIL(MM_ERR_DUPLICATE_NAME, "clips[%d].name '%s' is used twice", twice,
                        cfg->clips[twice].name);
    }
    const cJSON *runtime = cJSON_GetObjectItemCaseSensitive(root, "runtime");
    if (runtime && (r = parse_runtime(c, runtime)) != MM_OK) return r;
    const cJSON *blends = cJSON_GetObjectItemCaseSensitive(root, "blend_clips");
    if (blends) {
        int n = cJSON_IsArray(blends) ? cJSON_GetArraySize(blends) : -1;
        if (n < 0) return FAIL(MM_ERR_SYNTAX, "blend_clips must be an array");
        if (n > MM_CONFIG_MAX_CLIPS)
            return FAIL(MM_ERR_LIMIT, "blend_clips: %d blend clips (at most %d)", n, MM_CONFIG_MAX_CLIPS);
        if (n > 0) {
            cfg->blends =
                (mm_config_blend *)mm_alloc_array(&cfg->allocator, (size_t)n, sizeof(mm_config_blend));
            if (!cfg->blends) return FAIL(MM_ERR_OUT_OF_MEMORY, "out of memory");
        }
        static const char *const bkeys[] = {"name", "left", "right", "weight", NULL};
        mm__name_index names;
        memset(&names, 0, sizeof names);
        if (n > 0 && cfg->clip_count > 0 &&
            mm__name_index_init(&names, cfg->clips[0].name, sizeof(mm_config_clip), cfg->clip_count) != 0)
            return FAIL(MM_ERR_OUT_OF_MEMORY, "out of memory");
        const cJSON *b = blends->child;
        for (int i = 0; i < n; ++i, b = b->next) {
            mm_config_blend *cb = &cfg->blends[i];
            char where[40], left[MM_NAME_MAX] = "", right[MM_NAME_MAX] = "";
            snprintf(where, sizeof where, "blend_clips[%d]", i);
            cfg->blend_count = i + 1;
            cb->weight = 0.5f;
            if ((r = check_keys(c, b, where, bkeys)) == MM_OK &&
                (r = get_string(c, b, "name", where, cb->name, MM_NAME_MAX)) == MM_OK &&
                (r = get_string(c, b, "left", where, left, MM_NAME_MAX)) == MM_OK &&
                (r = get_string(c, b, "right", where, right, MM_NAME_MAX)) == MM_OK)
                r = get_number(c, b, "weight", where, &cb->weight);
            if (r == MM_OK && !cb->name[0]) r = FAIL(MM_ERR_SYNTAX, "%s.name is missing", where);
            cb->left = mm__name_index_find(&names, left);
            cb->right = mm__name_index_find(&names, right);
            if (r == MM_OK && cb->left < 0)
                r = FAIL(MM_ERR_NOT_FOUND, "%s.left: no clip named '%s'", where, left);
            if (r == MM_OK && cb->right < 0)
                r = FAIL(MM_ERR_NOT_FOUND, "%s.right: no clip named '%s'", where, right);
            if (r != MM_OK) break;
        }
        mm__name_index_free(&names);
        if (r != MM_OK) return r;
    }
    return MM_OK;
}

/* ---- extends ---------------------------------------------------------------------------- */

#define MM_EXTENDS_MAX_DEPTH 16

/* The canonical path of an existing file into out (truncated to MM_PATH_MAX); 0 when it does not
 * exist. */
static int real_path(const char *path, char *out)
{
    char *p = realpath(path, NULL);
    if (!p) return 0;
    snprintf(out, MM_PATH_MAX, "%s", p);
    free(p);
    return 1;
}

/* Folder of a path ("." when it has none). */
static void folder_of(const char *path, char *out, size_t size)
{
    const char *slash = strrchr(path, '/');
    if (slash)
        snprintf(out, size, "%.*s", (int)(slash - path), path);
    else
        snprintf(out, size, ".");
}

/* Moves what over adds into base: clips and blend_clips appended, tag names added when new,
 * objects merged key by key (recursively), anything else replaced. Consumes over. 0: no memory. */
static int merge_into(cJSON *base, cJSON *over, int top)
{
    while (over->child) {
        cJSON *item = cJSON_DetachItemViaPointer(over, over->child);
        const char *key = item->string;
        cJSON *have = cJSON_GetObjectItemCaseSensitive(base, key);
        if (top && strcmp(key, "extends") == 0) {
            cJSON_Delete(item);
            continue;
        }
        if (have && top && cJSON_IsArray(have) && cJSON_IsArray(item) &&
            (strcmp(key, "clips") == 0 || strcmp(key, "blend_clips") == 0 || strcmp(key, "tags") == 0)) {
            int tags = strcmp(key, "tags") == 0;
            while (item->child) {
                cJSON *e = cJSON_DetachItemViaPointer(item, item->child);
                int dup = 0;
                if (tags && cJSON_IsString(e))
                    for (const cJSON *t = have->child; t && !dup; t = t->next)
                        dup = cJSON_IsString(t) && strcmp(t->valuestring, e->valuestring) == 0;
                if (dup)
                    cJSON_Delete(e);
                else
                    cJSON_AddItemToArray(have, e);
            }
            cJSON_Delete(item);
        } else if (have && cJSON_IsObject(have) && cJSON_IsObject(item)) {
            int ok = merge_into(have, item, 0);
            cJSON_Delete(item);
            if (!ok) return 0;
        } else if (have) {
            if (!cJSON_ReplaceItemViaPointer(base, have, item)) {
                cJSON_Delete(item);
                return 0;
            }
        } else if (!cJSON_AddItemToObject(base, key, item)) {
            cJSON_Delete(item);
            return 0;
        }
    }
    return 1;
}

/* The config tree of text with its "extends" chain resolved. chain: the real paths of the files
 * being read (for cycles), depth of them. The error's file is the file at fault. */
static mm_result resolve_tree(const char *text, size_t size, const char *name, const char *base_dir,
                              char (*chain)[MM_PATH_MAX], int depth, cJSON **out, int *extended,
                              mm__json_where **where, mm_error *err)
{
    *out = NULL;
    mm__error_set_file(err, name);
    cJSON *root = NULL;
    mm__json_where *mine = NULL;
    mm_result r = mm__json_parse_where(text, size, name, &root, &mine, err);
    if (r != MM_OK) return r;
    *where = mm__json_where_join(*where, mine);
    const cJSON *ext = cJSON_GetObjectItemCaseSensitive(root, "extends");
    if (!ext || !cJSON_IsObject(root)) {
        *out = root;
        return MM_OK;
    }
    if (!cJSON_IsString(ext) || !ext->valuestring[0]) {
        cJSON_Delete(root);
        return mm_error_set(err, MM_ERR_SYNTAX, 0, 0, "extends must be the path of a config file");
    }
    char path[MM_PATH_MAX], real[MM_PATH_MAX];
    if (ext->valuestring[0] == '/' || !base_dir)
        snprintf(path, sizeof path, "%s", ext->valuestring);
    else
        snprintf(path, sizeof path, "%s/%s", base_dir, ext->valuestring);
    if (!real_path(path, real)) {
        mm_error_set(err, MM_ERR_NOT_FOUND, 0, 0, "extends: '%s' does not exist", path);
        cJSON_Delete(root);
        return MM_ERR_NOT_FOUND;
    }
    for (int i = 0; i < depth; ++i)
        if (strcmp(chain[i], real) == 0) {
            cJSON_Delete(root);
            return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "extends: '%s' extends itself (a cycle)",
                                path);
        }
    if (depth >= MM_EXTENDS_MAX_DEPTH) {
        cJSON_Delete(root);
        return mm_error_set(err, MM_ERR_LIMIT, 0, 0, "extends: more than %d configs deep",
                            MM_EXTENDS_MAX_DEPTH);
    }
    snprintf(chain[depth], MM_PATH_MAX, "%s", real);
    char *base_text = NULL, dir[MM_PATH_MAX];
    size_t base_size = 0;
    r = mm__read_file(path, NULL, &base_text, &base_size, err);
    if (r != MM_OK) {
        cJSON_Delete(root);
        return r;
    }
    folder_of(path, dir, sizeof dir);
    cJSON *base = NULL;
    r = resolve_tree(base_text, base_size, path, dir, chain, depth + 1, &base, extended, where, err);
    free(base_text);
    if (r == MM_OK && !cJSON_IsObject(base))
        r = mm_error_set(err, MM_ERR_SYNTAX, 0, 0, "the config must be an object");
    if (r != MM_OK) {
        cJSON_Delete(root);
        cJSON_Delete(base);
        return r;
    }
    mm__error_set_file(err, name);
    int ok = merge_into(base, root, 1);
    cJSON_Delete(root);
    if (!ok) {
        cJSON_Delete(base);
        return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    }
    *extended = 1;
    *out = base;
    return MM_OK;
}

/* Parses text (resolving extends) into cfg; *out_flat receives the merged config as text when it
 * extends another (malloc'd), else NULL. */
static mm_result parse_config(const char *text, size_t size, const char *name, const char *base_dir,
                              mm_config *cfg, char **out_flat, mm_error *err)
{
    mm_allocator keep = cfg ? cfg->allocator : (mm_allocator){0};
    if (out_flat) *out_flat = NULL;
    if (!cfg) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no config given");
    mm_config_defaults(cfg);
    cfg->allocator = keep;
    if (!name) name = "<config>";
    mm__error_set_file(err, name);
    if (base_dir) snprintf(cfg->base_dir, sizeof cfg->base_dir, "%s", base_dir);
    if (!text) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no text given");
    char chain[MM_EXTENDS_MAX_DEPTH + 1][MM_PATH_MAX];
    int depth = 0, extended = 0;
    if (real_path(name, chain[0])) depth = 1;
    cJSON *root = NULL;
    mm__json_where *where = NULL;
    mm_result r = resolve_tree(text, size, name, base_dir, chain, depth, &root, &extended, &where, err);
    if (r != MM_OK) {
        mm__json_where_free(where);
        return r;
    }
    ctx c = {cfg, err, where};
    r = parse_root(&c, root);
    if (r == MM_OK && extended && out_flat) {
        *out_flat = cJSON_Print(root);
        if (!*out_flat) r = mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    }
    if (r == MM_OK) r = mm_config_validate(cfg, err);
    /* a meaning error names a field path: its value's line and column (and file) are added */
    if (r != MM_OK) mm__json_locate_error(root, where, err);
    cJSON_Delete(root);
    mm__json_where_free(where);
    if (r != MM_OK) {
        mm_config_free(cfg);
        if (out_flat) {
            free(*out_flat);
            *out_flat = NULL;
        }
    }
    return r;
}

mm_result mm_config_parse_json(const char *text, size_t size, const char *name, const char *base_dir,
                               mm_config *cfg, mm_error *err)
{
    return parse_config(text, size, name, base_dir, cfg, NULL, err);
}

mm_result mm_config_load_json(const char *path, mm_config *cfg, char **out_text, mm_error *err)
{
    if (out_text) *out_text = NULL;
    char *text = NULL;
    size_t size = 0;
    mm_result r = mm__read_file(path, NULL, &text, &size, err);
    if (r != MM_OK) return r;
    char dir[MM_PATH_MAX];
    folder_of(path, dir, sizeof dir);
    char *flat = NULL;
    r = parse_config(text, size, path, dir, cfg, out_text ? &flat : NULL, err);
    if (r == MM_OK && out_text) {
        /* a config that extends another is embedded whole, so it reads without its base */
        if (flat) {
            free(text);
            *out_text = flat;
        } else {
            *out_text = text;
        }
    } else {
        free(text);
    }
    return r;
}

/* ---- sources ---------------------------------------------------------------------------- */

static int file_exists(const char *path) { return access(path, R_OK) == 0; }

mm_result mm_config_resolve_path(const mm_config *cfg, const char *file, char *out, size_t size,
                                 mm_error *err)
{
    if (file[0] == '/') {
        snprintf(out, size, "%s", file);
        if (file_exists(out)) return MM_OK;
        return mm_error_set(err, MM_ERR_NOT_FOUND, 0, 0, "clip file '%s' does not exist", file);
    }
    snprintf(out, size, "%s/%s", cfg->base_dir[0] ? cfg->base_dir : ".", file);
    if (file_exists(out)) return MM_OK;
    if (cfg->data_dir[0]) {
        snprintf(out, size, "%s/%s", cfg->data_dir, file);
        if (file_exists(out)) return MM_OK;
    }
    const char *data = getenv("MM_DATA_DIR");
    if (data && data[0]) {
        snprintf(out, size, "%s/%s", data, file);
        if (file_exists(out)) return MM_OK;
    }
    return mm_error_set(err, MM_ERR_NOT_FOUND, 0, 0,
                        "clip file '%s' is not in %s%s%s nor in $MM_DATA_DIR (%s)", file,
                        cfg->base_dir[0] ? cfg->base_dir : ".", cfg->data_dir[0] ? " or " : "", cfg->data_dir,
                        data && data[0] ? data : "unset");
}

void mm_config_free_sources(const mm_config *cfg, mm_clip *clips)
{
    if (!clips) return;
    for (int i = 0; i < cfg->clip_count; ++i) mm_clip_free(&clips[i]);
    free(clips);
}

mm_result mm_config_import_takes(const mm_config *cfg, const char *path, mm_clip_list *out, mm_error *err)
{
    /* takes of other axes are turned before the unit is detected: the height is measured along +Y */
    int turned =
        cfg->axes_up != MM_AXIS_POS_Y || mm_axes_forward(cfg->axes_up, cfg->axes_forward) != MM_AXIS_POS_Z;
    mm_import_desc imp;
    memset(&imp, 0, sizeof imp);
    imp.scale = cfg->scale;
    imp.auto_scale = cfg->scale == 0.0f && !turned;
    mm_result r = mm_import_clips(path, &imp, out, err);
    if (r != MM_OK || !turned) return r;
    for (int t = 0; t < out->count; ++t) {
        mm_clip *k = &out->clips[t];
        mm_clip_turn(k, mm_axes_turn(cfg->axes_up, cfg->axes_forward));
        if (cfg->scale != 0.0f) continue;
        const mm_quat *rot = k->frame_count > 0 ? mm_clip_rotations(k, 0) : NULL;
        const mm_vec3 *pos = k->frame_count > 0 ? mm_clip_positions(k, 0) : NULL;
        double height = mm_skeleton_estimate_height(&k->skeleton, rot, pos);
        double unit = mm_unit_scale_for_height(height);
        if (unit == 0.0) {
            mm_clip_list_free(out);
            mm__error_set_file(err, path);
            return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0,
                                "cannot detect the unit: the character is %g units tall along axes.up %s, "
                                "which is no human height; give the scale",
                                height, mm_axis_name(cfg->axes_up));
        }
        mm_clip_scale(k, (float)unit);
    }
    return MM_OK;
}

mm_result mm_config_load_sources(const mm_config *cfg, mm_clip **out_clips, mm_error *err)
{
    *out_clips = NULL;
    if (cfg->clip_count < 1)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "clips: the config lists no clip");
    mm_clip *clips = (mm_clip *)calloc((size_t)cfg->clip_count, sizeof(mm_clip));
    char(*paths)[MM_PATH_MAX] = (char(*)[MM_PATH_MAX])calloc((size_t)cfg->clip_count, MM_PATH_MAX);
    if (!clips || !paths) {
        free(clips);
        free(paths);
        return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    }
    mm_result r = MM_OK;
    for (int i = 0; i < cfg->clip_count && r == MM_OK; ++i) {
        r = mm_config_resolve_path(cfg, cfg->clips[i].file, paths[i], MM_PATH_MAX, err);
        if (r != MM_OK) break;
        int same = -1;
        for (int k = 0; k < i && same < 0; ++k)
            if (strcmp(paths[k], paths[i]) == 0 && strcmp(cfg->clips[k].take, cfg->clips[i].take) == 0)
                same = k;
        if (same >= 0) {
            r = mm_clip_copy(&clips[i], &clips[same], NULL);
            continue;
        }
        mm_clip_list takes;
        r = mm_config_import_takes(cfg, paths[i], &takes, err);
        if (r != MM_OK) break;
        int pick = 0;
        if (cfg->clips[i].take[0]) {
            pick = -1;
            for (int t = 0; t < takes.count && pick < 0; ++t)
                if (strcmp(takes.names[t], cfg->clips[i].take) == 0) pick = t;
        }
        if (pick < 0) {
            r = mm_error_set(err, MM_ERR_NOT_FOUND, 0, 0, "clips[%d] (%s): the file has no take named '%s'",
                             i, cfg->clips[i].name, cfg->clips[i].take);
        } else {
            clips[i] = takes.clips[pick]; /* moved out of the list */
            memset(&takes.clips[pick], 0, sizeof takes.clips[pick]);
        }
        mm_clip_list_free(&takes);
    }
    free(paths);
    if (r != MM_OK) {
        mm_config_free_sources(cfg, clips);
        return r;
    }
    *out_clips = clips;
    return MM_OK;
}
