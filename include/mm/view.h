/* mm/view.h - what the viewer and headless rendering show of a character, without OpenGL: the
 * scene (body and debug drawing), the overlay text, and keyboard / gamepad input mapped to
 * mm_input relative to the camera. Library mm_render.
 *
 *   mm_view v;
 *   mm_view_init(&v, &db, &err);
 *   each frame: mm_view_update(&v, &character, &input, &flags, fps);  draw v.scene
 *   mm_view_free(&v);
 *
 * Functions: mm_view_flags_defaults mm_view_init mm_view_set_body mm_view_free mm_view_update mm_view_overlay
 *            mm_view_scene_boxes mm_view_set_scene mm_view_input mm_view_chase mm_view_tuning_init
 * mm_view_tuning_select mm_view_tuning_step mm_view_tuning_set mm_view_tuning_value mm_view_tuning_desc
 *            mm_view_tuning_apply mm_view_tuning_text
 */
#ifndef MM_VIEW_H
#define MM_VIEW_H

#include <stdbool.h>
#include <stddef.h>

#include "character.h"
#include "database.h"
#include "input.h"
#include "render.h"
#include "scene.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct mm_view_flags {
    bool predicted;     /* the simulated future trajectory (the seed's "Show tra pre"), orange */
    bool matched;       /* the trajectory of the frame playing (the seed's "Show tra anim"), green */
    bool past;          /* the recorded past trajectory, blue */
    bool contacts;      /* feet: red spheres while locked, the lock point on the ground */
    bool matched_bones; /* the bones the search matches, highlighted */
    bool velocities;    /* matched bones' velocities and the root velocity, as arrows (0.1 s) */
    bool overlay;       /* the text panel */
} mm_view_flags;

/* Predicted, matched, past, contacts and overlay on; matched bones and velocities off. */
void mm_view_flags_defaults(mm_view_flags *f);

#define MM_VIEW_OVERLAY_MAX 1024

typedef struct mm_view {
    mm_render_scene scene; /* what to draw; points into the arrays below and the character */
    const mm_database *db;
    int *parents;
    mm_rgba *joint_colors;
    mm_render_line *lines;
    mm_render_marker *markers;
    int line_capacity, marker_capacity;
    char overlay[MM_VIEW_OVERLAY_MAX];
    mm_render_box *boxes; /* the scene set by mm_view_set_scene (owned) */
    int box_count;
    float ground;              /* its ground height */
    mm_body_mesh body;         /* the body mm_view_init made from the database (none: no triangles) */
    const mm_body_mesh *drawn; /* the body the scene shows: &body, a user's (mm_view_set_body), NULL */
    float *terrain;            /* its terrain's triangles (mm/terrain_mesh.h; owned) */
    int terrain_triangle_count;
} mm_view;

/* Also makes the database's body (mm_body_mesh_build_from_database); a database whose roles do not
 * make one is drawn as capsules. */
mm_result mm_view_init(mm_view *v, const mm_database *db, mm_error *err);
/* Draws body (skinned to the database's skeleton, kept by the caller while the view draws it) in
 * place of the body mm made; NULL: back to that one. */
void mm_view_set_body(mm_view *v, const mm_body_mesh *body);
void mm_view_free(mm_view *v);
/* Rebuilds v->scene for the character's current state (in: the input of this tick; fps: the
 * display rate shown in the overlay, 0 to leave it out). */
void mm_view_update(mm_view *v, const mm_character *c, const mm_input *in, const mm_view_flags *flags,
                    float fps);

/* The render boxes of a scene's boxes: the same position, size and yaw, in alternating sand
 * tones so that joined boxes stay apart. Writes min(box_count, capacity) boxes; returns the
 * scene's box count (0 for NULL). */
int mm_view_scene_boxes(const mm_scene *scene, mm_render_box *out, int capacity);
/* Draws the scene's boxes, and the ground at its height, in every later mm_view_update (the
 * boxes are copied; NULL removes them). */
mm_result mm_view_set_scene(mm_view *v, const mm_scene *scene, mm_error *err);

/* The overlay text: clip, frame and time; gait, speed, idle; the last search's cost and its five
 * terms; search time and counts; fps (when > 0). Returns the length written (truncated to n). */
size_t mm_view_overlay(char *out, size_t n, const mm_character *c, const mm_input *in, float fps);

/* Keyboard and gamepad state, as the viewer reads it. */
typedef struct mm_view_keys {
    bool forward, back, left, right; /* WASD or arrows */
    bool run, strafe, crouch;        /* shift, a strafe key, a crouch key */
    float pad_stick[2];              /* gamepad left stick: x right, y forward, in [-1, 1] */
    bool pad_run, pad_strafe;
} mm_view_keys;

/* Input relative to the camera: forward is where the camera looks, flattened on the ground, right
 * is the screen's right. Keys give a full stick (diagonals normalised); the gamepad stick, past a
 * 0.15 dead zone rescaled to [0, 1], replaces the keys when moved. Strafing faces the camera's
 * forward. Non-finite pad values count as zero. */
void mm_view_input(const mm_view_keys *k, float camera_yaw, mm_input *out);

/* One step of the camera chasing the character (mm_camera_chase): behind its facing, framing its
 * joints and its predicted path over the next second (in: this tick's input); aspect: the image's
 * width over height; dt <= 0 jumps there. */
void mm_view_chase(mm_camera *cam, const mm_camera_framing *framing, const mm_character *c,
                   const mm_input *in, float aspect, float dt);

/* Live tuning: a list of the character's parameters the database actually uses (a bone's
 * position or velocity weight only where its features match it, body_velocity_weight,
 * position_multiplier and angle_multiplier only where the database has that feature group,
 * loop_anim_favour only with loop clips, the crouch gait only with a "Crouch" tag, the
 * transition's half-life or crossfade time by the transition in use), one of them selected,
 * changed in steps or set on a copy of the character's desc (written out:
 * mm_character_desc_resolve). Beside them, the runtime layers as switches (mm_view_layers). The
 * desc the character runs with is the tuned values with the layers applied
 * (mm_view_tuning_desc); each change hands it to the character (mm_character_tune), so it acts
 * from the next tick. */
#define MM_VIEW_TUNING_MAX 64

typedef struct mm_view_tuning_entry {
    char name[48];
    float *value;
    float step; /* added per step, or the factor per step when multiply */
    bool multiply;
    float min, max; /* the value is kept within */
    /* where the value lives in a config: key is the path under the config's root ("runtime.walk.
     * forward_speed", "features.angle_multiplier"); bone weights name their bone instead (key is
     * "position_weight" or "velocity_weight" of features.bones' entry named bone) */
    char key[48];
    char bone[MM_NAME_MAX];
    float saved; /* the value when tuning started or was last saved: a save writes what differs */
} mm_view_tuning_entry;

/* The runtime layers a viewer switches (each on as the character's desc has it at init). */
typedef struct mm_view_layers {
    bool crossfade;         /* transitions through the crossfade mixer, else inertialization (fixed
                               at mm_character_init: switching it restarts the character) */
    bool foot_ik;           /* foot locking and leg IK (desc.no_foot_ik off) */
    bool distance_matching; /* desc.distance_matching */
    bool warping;           /* desc.warping */
    bool root_sync;         /* the root pulled toward the simulation (off: it follows the clip's
                               root motion alone, within the clamps) */
    bool root_clamps;       /* the root kept within sync_max_distance / sync_max_angle of it */
} mm_view_layers;

/* Half-life and clamps that switch the root's sync or clamps off (s, m, rad): past any session. */
#define MM_VIEW_NO_SYNC_HALFLIFE 1e9f
#define MM_VIEW_NO_CLAMP         1e9f

typedef struct mm_view_tuning {
    mm_view_tuning_entry entries[MM_VIEW_TUNING_MAX];
    int count, selected;
    mm_character_desc desc; /* the values tuned */
    mm_view_layers layers, saved_layers;
    mm_character *character;
} mm_view_tuning;

/* Copies c's tuning into t->desc and its layers into t->layers, and points the entries at it (c
 * must outlive t and not move). */
void mm_view_tuning_init(mm_view_tuning *t, mm_character *c);
/* The desc the character runs with: t->desc with the layers applied. */
void mm_view_tuning_desc(const mm_view_tuning *t, mm_character_desc *out);
/* Hands mm_view_tuning_desc to the character (after a value or a layer changed). Returns true
 * when the character must be made again for it to act (the transition layer switched). */
bool mm_view_tuning_apply(mm_view_tuning *t);
/* Moves the selection by delta entries, wrapping around. */
void mm_view_tuning_select(mm_view_tuning *t, int delta);
/* Changes the selected value by direction steps (negative: down), clamped to its range, and hands
 * the tuning to the character. */
void mm_view_tuning_step(mm_view_tuning *t, int direction);
/* Sets entry i to value (clamped to its range; 0 kept as MM_OFF) and hands the tuning to the
 * character. */
void mm_view_tuning_set(mm_view_tuning *t, int i, float value);
/* The value of entry i as it acts (MM_OFF as 0). */
float mm_view_tuning_value(const mm_view_tuning *t, int i);
/* The selected entry with its neighbours, one per line, the selected one marked '>'. Returns the
 * length written (truncated to n). */
size_t mm_view_tuning_text(const mm_view_tuning *t, char *out, size_t n);

#ifdef __cplusplus
}
#endif

#endif /* MM_VIEW_H */
