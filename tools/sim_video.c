/* The video of mm simulate: one frame every 1 / video_fps seconds of simulated time, the camera
 * chasing the character from behind and framing it with its predicted path. */
#include <math.h>
#include <string.h>

#include "cli.h"
#include "sim_video.h"

mm_result sim_video_open(sim_video *s, const char *path, int width, int height, double video_fps,
                         double tick_seconds, const mm_database *db, mm_error *err)
{
    memset(s, 0, sizeof *s);
    mm_result r = mm_offscreen_create(width, height, &s->offscreen, err);
    if (r == MM_OK) r = mm_view_init(&s->view, db, err);
    if (r == MM_OK) r = mm_video_open(path, width, height, (float)video_fps, &s->video, err);
    if (r == MM_OK && mm_video_temp_path(s->video)) {
        cli_remember_child(mm_video_encoder_process(s->video));
        cli_remember_temp(mm_video_temp_path(s->video));
    }
    if (r != MM_OK) {
        mm_view_free(&s->view);
        mm_offscreen_destroy(s->offscreen);
        memset(s, 0, sizeof *s);
        return r;
    }
    mm_view_flags_defaults(&s->flags);
    mm_camera_defaults(&s->camera);
    mm_camera_framing_defaults(&s->framing);
    s->db = db;
    s->tick_seconds = tick_seconds;
    s->frame_seconds = 1.0 / video_fps;
    return MM_OK;
}

mm_result sim_video_set_scene(sim_video *s, const mm_scene *scene, mm_error *err)
{
    return mm_view_set_scene(&s->view, scene, err);
}

mm_result sim_video_set_mesh(sim_video *s, const char *path, mm_error *err)
{
    mm_body_mesh_free(&s->mesh);
    mm_result r = mm_body_mesh_load(path, s->db->joints, s->db->joint_count, &s->mesh, err);
    mm_view_set_body(&s->view, r == MM_OK ? &s->mesh : NULL);
    return r;
}

static void chase(sim_video *s, const mm_character *c, const mm_input *in, float dt)
{
    int w = 0, h = 0;
    mm_offscreen_size(s->offscreen, &w, &h);
    mm_view_chase(&s->camera, &s->framing, c, in, h > 0 ? (float)w / (float)h : 1.0f, dt);
}

mm_result sim_video_tick(sim_video *s, const mm_character *c, const mm_input *in, mm_error *err)
{
    if (!s->video) return MM_OK;
    s->time += s->tick_seconds;
    mm_input none;
    memset(&none, 0, sizeof none);
    chase(s, c, in ? in : &none, s->frames == 0 ? 0.0f : (float)s->tick_seconds);
    if (s->time + 1e-9 < s->next_frame) return MM_OK;
    s->next_frame += s->frame_seconds;
    mm_view_update(&s->view, c, in, &s->flags, 0.0f);
    const uint8_t *rgb = mm_offscreen_render(s->offscreen, &s->camera, &s->view.scene);
    if (!rgb) return mm_error_set(err, MM_ERR_UNSUPPORTED, 0, 0, "the offscreen context was lost");
    mm_result r = mm_video_write(s->video, rgb, err);
    if (r == MM_OK) ++s->frames;
    return r;
}

mm_result sim_video_close(sim_video *s, int abort, int *frames, mm_error *err)
{
    /* the temporary file is renamed or removed by the close: forgotten only then */
    char tmp[CLI_TEMP_NAME_MAX] = "";
    if (mm_video_temp_path(s->video)) snprintf(tmp, sizeof tmp, "%s", mm_video_temp_path(s->video));
    mm_result r = mm_video_close(s->video, abort != 0, frames, err);
    cli_remember_child(0);
    if (tmp[0]) cli_forget_temp(tmp);
    mm_view_free(&s->view);
    mm_body_mesh_free(&s->mesh);
    mm_offscreen_destroy(s->offscreen);
    memset(s, 0, sizeof *s);
    return r;
}
