/* The video of mm simulate: one frame every 1 / video_fps seconds of simulated time. */
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
    s->tick_seconds = tick_seconds;
    s->frame_seconds = 1.0 / video_fps;
    return MM_OK;
}

mm_result sim_video_set_scene(sim_video *s, const mm_scene *scene, mm_error *err)
{
    return mm_view_set_scene(&s->view, scene, err);
}

mm_result sim_video_tick(sim_video *s, const mm_character *c, const mm_input *in, mm_error *err)
{
    if (!s->video) return MM_OK;
    s->time += s->tick_seconds;
    /* the camera eases after the character; aiming ahead by the distance an exponential follower
       lags at constant velocity (v * halflife / ln 2) keeps a moving character in the middle */
    const float halflife = 0.5f;
    mm_vec3 aim =
        mm_vec3_add(c->root.translation, mm_vec3_scale(c->trajectory->velocity, halflife / 0.6931472f));
    mm_camera_follow(&s->camera, mm_vec3_make(aim.x, 0.9f, aim.z), s->frames == 0 ? 0.0f : halflife,
                     (float)s->tick_seconds);
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
    mm_offscreen_destroy(s->offscreen);
    memset(s, 0, sizeof *s);
    return r;
}
