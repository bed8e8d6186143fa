/* sim_video.h - the video of a simulated character (mm simulate --video): headless frames of the
 * character with its debug drawing, the camera following it. */
#ifndef MM_TOOLS_SIM_VIDEO_H
#define MM_TOOLS_SIM_VIDEO_H

#include <mm/body_mesh.h>
#include <mm/character.h>
#include <mm/render.h>
#include <mm/scene.h>
#include <mm/view.h>

typedef struct sim_video {
    mm_offscreen *offscreen;
    mm_video *video;
    mm_view view;
    mm_view_flags flags;
    mm_camera camera;
    mm_camera_framing framing;
    mm_body_mesh mesh; /* a user's mesh (sim_video_set_mesh); none: the body mm makes */
    const mm_database *db;
    double tick_seconds, next_frame, frame_seconds, time;
    int frames;
} sim_video;

/* Opens the output (see mm_video_open) for ticks of tick_seconds, frames every 1 / video_fps s. */
mm_result sim_video_open(sim_video *s, const char *path, int width, int height, double video_fps,
                         double tick_seconds, const mm_database *db, mm_error *err);
/* Draws the scene's boxes (and its ground height) in every later frame; NULL removes them. The
 * boxes are copied: scene need not outlive the call. */
mm_result sim_video_set_scene(sim_video *s, const mm_scene *scene, mm_error *err);
/* Draws the skinned mesh of an FBX or glTF file (mm_body_mesh_load) in place of the body mm makes. */
mm_result sim_video_set_mesh(sim_video *s, const char *path, mm_error *err);
/* Called after every tick: draws a frame when one is due. */
mm_result sim_video_tick(sim_video *s, const mm_character *c, const mm_input *in, mm_error *err);
/* Finishes (or, with abort, removes) the output; frames receives the count written. */
mm_result sim_video_close(sim_video *s, int abort, int *frames, mm_error *err);

#endif
