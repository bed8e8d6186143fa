/* mm/render.h - seeing the character: camera, scene description, OpenGL 3.3 renderer, offscreen
 * rendering (no display needed), PNG images and video. Library mm_render.
 *
 * The scene is plain data (bones, debug lines, markers, overlay text) so that whatever the source
 * (a character, a BVH clip) it draws the same way in the viewer's window and headless:
 *
 *   mm_offscreen *o;
 *   mm_offscreen_create(640, 360, &o, &err);
 *   mm_camera cam;  mm_camera_defaults(&cam);
 *   mm_render_scene scene = {...};
 *   const uint8_t *rgb = mm_offscreen_render(o, &cam, &scene);   (w x h x 3, top row first)
 *   mm_png_write("frame.png", rgb, 640, 360, &err);
 *   mm_offscreen_destroy(o);
 *
 * The camera orbits a target point: yaw 0 puts it on the -Z side looking toward +Z (behind a
 * character facing +Z), pitch lifts it above the horizon. Images use pixel coordinates with x to
 * the right and y down, pixel (i, j) covering [i, i+1) x [j, j+1).
 *
 * Functions: mm_camera_defaults mm_camera_eye mm_camera_view_matrix mm_camera_projection_matrix
 *            mm_camera_project mm_camera_orbit mm_camera_zoom mm_camera_follow
 *            mm_camera_framing_defaults mm_camera_chase mm_render_overlay_place mm_render_character_box
 *            mm_renderer_create mm_renderer_destroy mm_renderer_draw mm_renderer_read_pixels
 *            mm_offscreen_create mm_offscreen_render mm_offscreen_destroy mm_offscreen_size
 *            mm_png_write mm_png_read_size mm_video_open mm_video_write mm_video_temp_path
 *            mm_video_encoder_process mm_video_close
 *            mm_video_encoder_available mm_text_measure mm_render_find_head mm_render_box_corners
 *            mm_render_find_feet mm_render_facing mm_sheet_tile_size mm_sheet_cameras mm_sheet_render
 */
#ifndef MM_RENDER_H
#define MM_RENDER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "body_mesh.h"
#include "math.h"
#include "result.h"
#include "skeleton.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- camera (pure math) ---- */

typedef struct mm_camera {
    mm_vec3 target;      /* the point looked at */
    float yaw;           /* rad about +Y; 0: the eye is on the -Z side of the target */
    float pitch;         /* rad above the horizon, clamped to [-0.2, 1.5] by mm_camera_orbit */
    float distance;      /* m from the target, clamped to [0.5, 50] by mm_camera_zoom */
    float fov_y;         /* rad, vertical field of view */
    float z_near, z_far; /* m */
} mm_camera;

/* Target (0, 0.9, 0), yaw 0.6, pitch 0.22, distance 4.2, 45 degree field of view, near 0.05, far 200. */
void mm_camera_defaults(mm_camera *c);
mm_vec3 mm_camera_eye(const mm_camera *c);
/* Column-major 4x4 matrices (OpenGL's layout): m[col * 4 + row]. */
void mm_camera_view_matrix(const mm_camera *c, float m[16]);
void mm_camera_projection_matrix(const mm_camera *c, float aspect, float m[16]);
/* Where world point p lands in a width x height image (pixels, x right, y down). False when p
 * is not in front of the camera (then px, py are left unchanged). */
bool mm_camera_project(const mm_camera *c, int width, int height, mm_vec3 p, float *px, float *py);
/* Mouse orbit: angles added, pitch clamped. */
void mm_camera_orbit(mm_camera *c, float dyaw, float dpitch);
/* Distance multiplied by factor (wheel), clamped. */
void mm_camera_zoom(mm_camera *c, float factor);
/* The target approaches p exponentially: half the distance every halflife seconds, whatever
 * the tick (two ticks of dt equal one of 2 dt). dt <= 0 or a non-finite p leave it; halflife
 * <= 0 jumps to p. */
void mm_camera_follow(mm_camera *c, mm_vec3 p, float halflife, float dt);

/* A camera chasing a character: behind its facing (turned yaw_offset to one side), at a fixed
 * pitch, aimed so that the middle of the points to frame (the character's joints and its future
 * path) is the middle of a window of the image, and as far as they need to lie inside that window
 * (normalised coordinates: x within +-half_width, y from bottom to top; the band above top is left
 * to the overlay text), each eased
 * with its half-life (s; the distance draws back four times faster than it closes in). */
typedef struct mm_camera_framing {
    float yaw_offset, pitch;                                /* rad */
    float yaw_halflife, target_halflife, distance_halflife; /* s */
    float min_distance, max_distance;                       /* m */
    float half_width, top, bottom;                          /* normalised image coordinates, -1 to 1 */
} mm_camera_framing;

/* yaw_offset 0.35, pitch 0.30; half-lives 0.6, 0.25, 0.5 s; distance 2.5 to 25 m; window x within
 * +-0.80, y from -0.75 to 0.45. */
void mm_camera_framing_defaults(mm_camera_framing *f);
/* One step of dt seconds (dt <= 0: jump to the goal, for a first frame) of the chase: facing_yaw
 * is the character's (rad about +Y, 0 facing +Z; not finite: keep the yaw), points the count world
 * points to frame, aspect the image's width over height. */
void mm_camera_chase(mm_camera *c, const mm_camera_framing *f, float facing_yaw, const mm_vec3 *points,
                     int count, float aspect, float dt);

/* ---- scene ---- */

typedef struct mm_rgba {
    float r, g, b, a;
} mm_rgba;

typedef struct mm_render_line {
    mm_vec3 a, b;
    mm_rgba color;
} mm_render_line;

typedef struct mm_render_marker { /* a small sphere: trajectory samples, contacts */
    mm_vec3 position;
    float radius;
    mm_rgba color;
} mm_render_marker;

typedef struct mm_render_box { /* a solid, lit box standing upright (a scene's obstacle) */
    mm_vec3 position;          /* centre of the bottom face, m */
    mm_vec3 size;              /* full extents along the box's own x, y, z, m */
    float yaw;                 /* rad about +Y: a yaw of pi/2 turns the box's +Z axis to world +X */
    mm_rgba color;             /* alpha 0: a default sand colour */
} mm_render_box;

/* The box's 8 corners in world space: corner i is at local x = -size.x/2 or +size.x/2 (bit 0 of
 * i), y = 0 or size.y (bit 1), z = -size.z/2 or +size.z/2 (bit 2), turned by yaw and moved to
 * position. The renderer draws the box's faces and edges through the same transform. */
void mm_render_box_corners(const mm_render_box *box, mm_vec3 out[8]);

typedef struct mm_render_scene {
    /* the character: world transforms of joint_count joints and their parents (-1: none);
     * every joint is a sphere, every joint-to-parent segment a capsule of bone_radius */
    int joint_count;
    const int *parents;
    const mm_xform *global;
    int first_joint;             /* joints before this are not drawn (a database's simulation
                                    bone on the ground); bones to them neither */
    float bone_radius;           /* m; 0: 0.03 */
    int head_joint;              /* drawn as a 0.1 m sphere (0: none; see mm_render_find_head) */
    mm_rgba body_color;          /* alpha 0: a default grey-blue */
    const mm_rgba *joint_colors; /* optional per joint (highlighted bones); NULL: body_color */
    const int *shadow_joints;    /* joints casting a contact shadow on the ground; NULL: all */
    int shadow_joint_count;
    const mm_render_line *lines; /* debug lines, drawn over the ground, depth-tested */
    int line_count;
    const mm_render_marker *markers;
    int marker_count;
    const char *overlay;        /* text at the top left, '\n' separates lines; NULL: none */
    bool no_ground;             /* skip the ground grid */
    const mm_render_box *boxes; /* obstacles, drawn solid and lit with dark edges */
    int box_count;
    float ground_height; /* m: the height of the ground grid (0 by default) */
    /* a body skinned to the joints (mm/body_mesh.h), drawn in place of the spheres and capsules
     * when its joint_count is the scene's; NULL: the capsule figure */
    const mm_body_mesh *body_mesh;
    const float *terrain; /* a scene's terrain (mm/terrain_mesh.h: triangles of positions and
                             normals), drawn solid and lit; NULL: none */
    int terrain_triangle_count;
} mm_render_scene;

/* The joint named like a head: the head role's default name (mm_role_default_name) in any case,
 * the first such; 0 when none. For a skeleton without a database; with one, the head is its head
 * role (mm_database_role_joint), as the view of a character takes it. */
int mm_render_find_head(const mm_joint *joints, int count);

/* Where the renderer draws the scene's overlay text: its dark panel's top left corner and size
 * (pixels, y down) and the font's scale (2: glyph cells of 12 x 18 pixels; 1: 6 x 9). It goes in
 * the first corner (top left, top right, bottom left, bottom right; 8 pixels in) whose panel does
 * not cross the character's box (mm_render_character_box), at the font's 2x scale and then at 1x;
 * else where it covers the least of it. The top left at 2x when the scene has no character. */
typedef struct mm_overlay_place {
    int x, y, width, height, scale;
} mm_overlay_place;
void mm_render_overlay_place(const mm_camera *cam, int width, int height, const mm_render_scene *scene,
                             mm_overlay_place *out);
/* The box (min x, min y, max x, max y; pixels) around the projected joints (from first_joint),
 * each grown by the 0.15 m a body reaches around it at its depth. False when no joint projects. */
bool mm_render_character_box(const mm_camera *cam, int width, int height, const mm_render_scene *scene,
                             float box[4]);

/* Size in pixels of text drawn by the renderer (the built-in 5x7 font at 2x: glyph cells of
 * 12 x 18 pixels per character, lines 18 pixels apart). */
void mm_text_measure(const char *text, int *width, int *height);

/* The joints named like a foot ("foot", "toe" or "ankle" in any case; joint 0, a root, never):
 * at most max of their indices into out, in skeleton order. Returns how many. */
int mm_render_find_feet(const mm_joint *joints, int count, int *out, int max);

/* The yaw (rad about +Y, 0 facing +Z, as mm_camera's yaw) of the front of a pose: the horizontal
 * direction at right angles to the line from the joints named "right" to those named "left" (any
 * case; their mean positions), the left side on the +X side of a body facing +Z. fallback when
 * the skeleton has no such joints or the line is vertical or not finite. */
float mm_render_facing(const mm_joint *joints, int count, const mm_xform *global, float fallback);

/* ---- contact sheets ---- */

/* Many poses of one body side by side in one image, to check posture at a glance: columns x rows
 * tiles, left to right then top to bottom, each the pose seen from its left side turned 20
 * degrees toward its front (mm_render_facing; the body faces the tile's left), the camera level
 * (pitch 0) and centred on the body. Every tile has the same camera distance and height, so heights
 * compare across tiles, chosen so that every pose, head sphere included, fits whole in its tile
 * above a band at the bottom. Every tile is lit alike whatever the body's heading (the pose is
 * turned about the camera's target to face the renderer's light the same way). The body's joints
 * named "right" are drawn tan, the others in the renderer's body colour. Each tile shows:
 *   the ground: a dark line at ground_height, the background below it earth-coloured (drawn
 *     behind the body, so a joint below the ground shows on the earth, crossed by the line);
 *   a blue line at the head joint's height and a green one at the lowest foot joint's
 *     (mm_render_find_feet; every joint when none is named so), drawn behind the body;
 *   a label in the band: "t 1.25 s" and "head 165.2  feet 3.1 cm", the heights above the ground;
 *     on a red panel, and those joints drawn red, when a joint is below the ground (by more than
 *     1 mm); on a dark panel otherwise;
 *   a one-pixel dark border.
 * The label's font is the renderer's, at 1 to 3 times its 6 x 9 cell, the largest that fits. */
typedef struct mm_sheet_desc {
    int columns, rows;          /* tiles: 1 to 32 each */
    int width, height;          /* the whole image (pixels); tiles are width / columns x height / rows,
                                   each at least MM_SHEET_MIN_TILE pixels on a side; the pixels left
                                   over at the right and bottom are border */
    int joint_count;            /* of the body; joints before first_joint are neither drawn nor measured */
    const mm_joint *joints;     /* names (head, feet, left and right are found by name) and parents */
    int first_joint;            /* 0, or 1 to leave out a simulation root on the ground */
    const mm_xform *poses;      /* columns x rows poses of joint_count world transforms, tile by tile */
    const double *times;        /* the time of each tile's pose (s), for its label; NULL: none shown */
    float ground_height;        /* m */
    const mm_render_box *boxes; /* a scene's obstacles, drawn in every tile */
    int box_count;
} mm_sheet_desc;

#define MM_SHEET_MIN_TILE 64

/* Each tile's width and height; MM_OK, or MM_ERR_OUT_OF_RANGE when the grid or the size is out of
 * range or the tiles would be too small. */
mm_result mm_sheet_tile_size(const mm_sheet_desc *d, int *tile_width, int *tile_height, mm_error *err);
/* The camera of every tile (columns x rows of them), for a tile of mm_sheet_tile_size. */
mm_result mm_sheet_cameras(const mm_sheet_desc *d, mm_camera *cameras, mm_error *err);
/* Renders the sheet headless (OSMesa) into rgb: width x height x 3 bytes, top row first. */
mm_result mm_sheet_render(const mm_sheet_desc *d, uint8_t *rgb, mm_error *err);

/* ---- OpenGL renderer ---- */

typedef void (*mm_gl_proc)(void);
typedef mm_gl_proc (*mm_gl_loader)(const char *name);

typedef struct mm_renderer mm_renderer;

/* Needs a current OpenGL 3.3 core (or later) context; load looks up its functions. */
mm_result mm_renderer_create(mm_gl_loader load, mm_renderer **out, mm_error *err);
void mm_renderer_destroy(mm_renderer *r);
/* Draws into the current framebuffer's width x height viewport, clearing it first. */
void mm_renderer_draw(mm_renderer *r, const mm_camera *cam, int width, int height,
                      const mm_render_scene *scene);

/* Reads the current framebuffer's width x height pixels into rgb (top row first, 3 bytes each). */
void mm_renderer_read_pixels(mm_renderer *r, int width, int height, uint8_t *rgb);

/* ---- offscreen (OSMesa: software, no display) ---- */

typedef struct mm_offscreen mm_offscreen;

/* An OpenGL context of width x height (1..4096) that draws into memory, with a renderer. */
mm_result mm_offscreen_create(int width, int height, mm_offscreen **out, mm_error *err);
/* Draws the scene; returns width x height x 3 bytes of RGB, top row first, owned by o and valid
 * until the next call. NULL if the context was lost. */
const uint8_t *mm_offscreen_render(mm_offscreen *o, const mm_camera *cam, const mm_render_scene *scene);
void mm_offscreen_destroy(mm_offscreen *o);
/* The context's width and height (0 for NULL). */
void mm_offscreen_size(const mm_offscreen *o, int *width, int *height);

/* ---- images and video ---- */

/* Writes an 8-bit RGB PNG (rows top first) through a temporary file renamed into place. */
mm_result mm_png_write(const char *path, const uint8_t *rgb, int width, int height, mm_error *err);

typedef struct mm_video mm_video;

/* True when ffmpeg can be run (PATH, or $MM_FFMPEG). */
bool mm_video_encoder_available(void);
/* A path ending in .mp4 or .gif is encoded by ffmpeg (H.264 yuv420p / palette GIF) into a
 * temporary file renamed into place by mm_video_close; any other path is a directory that
 * receives frame_00000.png, frame_00001.png, ... Width and height must be even for .mp4. */
mm_result mm_video_open(const char *path, int width, int height, float fps, mm_video **out, mm_error *err);
mm_result mm_video_write(mm_video *v, const uint8_t *rgb, mm_error *err);
/* The temporary file an encoded video is written to until mm_video_close renames it (so that a
 * program can remove it if a signal ends it first); NULL for PNG frames. */
const char *mm_video_temp_path(const mm_video *v);
/* The encoder's process id (0 for PNG frames): a program ended by a signal ends it too, or it could
 * write the temporary file again after it was removed. */
long mm_video_encoder_process(const mm_video *v);
/* Finishes the file; frames counts what was written. On error (or abort) nothing is left behind
 * for an encoded file. Always frees v. */
mm_result mm_video_close(mm_video *v, bool abort, int *frames, mm_error *err);

#ifdef __cplusplus
}
#endif

#endif /* MM_RENDER_H */
