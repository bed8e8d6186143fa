/* Video output: raw RGB frames piped into ffmpeg (H.264 MP4 or palette GIF), or a folder of PNG
 * frames. An encoded file is written under a temporary name and renamed when complete. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <mm/render.h>

#include "io/file.h"

extern char **environ;

struct mm_video {
    char *path, *tmp; /* final and temporary paths (encoded), or the folder (PNG frames) */
    int width, height, frames;
    bool encoded;
    pid_t pid;
    int pipe_fd;
    struct sigaction old_sigpipe;
};

static bool has_suffix(const char *s, const char *suffix)
{
    size_t n = strlen(s), k = strlen(suffix);
    return n > k && strcmp(s + n - k, suffix) == 0;
}

/* The ffmpeg to run: $MM_FFMPEG, else "ffmpeg" when some PATH entry has it. NULL when none. */
static const char *ffmpeg_program(void)
{
    const char *env = getenv("MM_FFMPEG");
    if (env && *env) return access(env, X_OK) == 0 ? env : NULL;
    const char *path = getenv("PATH");
    if (!path) return NULL;
    char buf[4096];
    while (*path) {
        size_t n = strcspn(path, ":");
        if (n > 0 && n + 8 < sizeof buf) {
            memcpy(buf, path, n);
            memcpy(buf + n, "/ffmpeg", 8);
            if (access(buf, X_OK) == 0) return "ffmpeg";
        }
        path += n + (path[n] == ':');
    }
    return NULL;
}

bool mm_video_encoder_available(void) { return ffmpeg_program() != NULL; }

static mm_result start_encoder(mm_video *v, const char *program, float fps, bool gif, mm_error *err)
{
    char size[32], rate[32], filter[160];
    snprintf(size, sizeof size, "%dx%d", v->width, v->height);
    snprintf(rate, sizeof rate, "%.6g", fps);
    snprintf(filter, sizeof filter,
             "split[a][b];[a]palettegen=stats_mode=diff[p];[b][p]paletteuse=dither=bayer");
    const char *mp4_args[] = {program,      "-nostdin", "-y",    "-loglevel", "error",   "-f",
                              "rawvideo",   "-pix_fmt", "rgb24", "-s",        size,      "-r",
                              rate,         "-i",       "-",     "-c:v",      "libx264", "-preset",
                              "veryfast",   "-crf",     "20",    "-pix_fmt",  "yuv420p", "-movflags",
                              "+faststart", "-f",       "mp4",   v->tmp,      NULL};
    const char *gif_args[] = {program,    "-nostdin",        "-y",   "-loglevel", "error", "-f",   "rawvideo",
                              "-pix_fmt", "rgb24",           "-s",   size,        "-r",    rate,   "-i",
                              "-",        "-filter_complex", filter, "-f",        "gif",   v->tmp, NULL};
    int fds[2];
    if (pipe(fds) != 0) return mm_error_set(err, MM_ERR_IO, 0, 0, "cannot make a pipe: %s", strerror(errno));
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, fds[0], 0);
    posix_spawn_file_actions_addclose(&actions, fds[1]);
    posix_spawn_file_actions_addclose(&actions, fds[0]);
    int rc =
        posix_spawnp(&v->pid, program, &actions, NULL, (char *const *)(gif ? gif_args : mp4_args), environ);
    posix_spawn_file_actions_destroy(&actions);
    close(fds[0]);
    if (rc != 0) {
        close(fds[1]);
        return mm_error_set(err, MM_ERR_UNSUPPORTED, 0, 0, "cannot run %s: %s", program, strerror(rc));
    }
    v->pipe_fd = fds[1];
    /* a dying encoder must give an error from write, not kill the process */
    struct sigaction ignore;
    memset(&ignore, 0, sizeof ignore);
    ignore.sa_handler = SIG_IGN;
    sigaction(SIGPIPE, &ignore, &v->old_sigpipe);
    return MM_OK;
}

mm_result mm_video_open(const char *path, int width, int height, float fps, mm_video **out, mm_error *err)
{
    *out = NULL;
    mm__error_set_file(err, path);
    if (!path || !*path) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no video path given");
    if (width < 2 || height < 2 || width > 8192 || height > 8192)
        return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0, "video size %d x %d: each side must be 2 to 8192",
                            width, height);
    if (!(fps >= 1.0f && fps <= 240.0f))
        return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0, "video frame rate %g: must be 1 to 240",
                            (double)fps);
    bool mp4 = has_suffix(path, ".mp4"), gif = has_suffix(path, ".gif");
    if (mp4 && (width % 2 || height % 2))
        return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0,
                            "an MP4 needs an even width and height, not %d x %d", width, height);
    const char *program = NULL;
    if (mp4 || gif) {
        program = ffmpeg_program();
        if (!program)
            return mm_error_set(
                err, MM_ERR_UNSUPPORTED, 0, 0,
                "ffmpeg is not installed (apt-get install ffmpeg); give a folder to get PNG frames");
    }
    mm_video *v = calloc(1, sizeof *v);
    size_t n = strlen(path);
    if (!v || !(v->path = malloc(n + 1)) || !(v->tmp = malloc(n + 32))) {
        if (v) free(v->path);
        free(v);
        return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    }
    memcpy(v->path, path, n + 1);
    snprintf(v->tmp, n + 32, "%s.tmp%ld", path, (long)getpid());
    v->width = width;
    v->height = height;
    v->encoded = mp4 || gif;
    v->pipe_fd = -1;
    mm_result r = MM_OK;
    if (v->encoded) {
        /* the temporary file is made here first: a path that cannot be written is said so, naming
         * the output, not by the encoder naming its temporary file */
        FILE *probe = fopen(v->tmp, "wb");
        if (!probe) {
            mm__error_set_file(err, path);
            r = mm_error_set(err, MM_ERR_IO, 0, 0, "cannot create: %s", strerror(errno));
        } else {
            fclose(probe);
            r = start_encoder(v, program, fps, gif, err);
            if (r != MM_OK) remove(v->tmp);
        }
    } else if (mkdir(path, 0777) != 0 && errno != EEXIST) {
        r = mm_error_set(err, MM_ERR_IO, 0, 0, "cannot make the frame folder: %s", strerror(errno));
    } else {
        struct stat st;
        if (stat(path, &st) != 0 || !S_ISDIR(st.st_mode))
            r = mm_error_set(err, MM_ERR_IO, 0, 0, "not a folder (give a .mp4 or .gif file or a folder)");
    }
    if (r != MM_OK) {
        free(v->path);
        free(v->tmp);
        free(v);
        return r;
    }
    *out = v;
    return MM_OK;
}

mm_result mm_video_write(mm_video *v, const uint8_t *rgb, mm_error *err)
{
    if (!v || !rgb) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no frame");
    if (!v->encoded) {
        size_t n = strlen(v->path) + 32;
        char *name = malloc(n);
        if (!name) return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
        snprintf(name, n, "%s/frame_%05d.png", v->path, v->frames);
        mm_result r = mm_png_write(name, rgb, v->width, v->height, err);
        free(name);
        if (r == MM_OK) ++v->frames;
        return r;
    }
    size_t left = (size_t)v->width * (size_t)v->height * 3;
    const uint8_t *p = rgb;
    while (left > 0) {
        ssize_t w = write(v->pipe_fd, p, left);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) {
            mm__error_set_file(err, v->path);
            return mm_error_set(err, MM_ERR_IO, 0, 0, "the video encoder stopped: %s", strerror(errno));
        }
        p += w;
        left -= (size_t)w;
    }
    ++v->frames;
    return MM_OK;
}

const char *mm_video_temp_path(const mm_video *v) { return v && v->encoded ? v->tmp : NULL; }

long mm_video_encoder_process(const mm_video *v) { return v && v->encoded ? (long)v->pid : 0; }

mm_result mm_video_close(mm_video *v, bool abort, int *frames, mm_error *err)
{
    if (frames) *frames = v ? v->frames : 0;
    if (!v) return MM_OK;
    mm_result r = MM_OK;
    if (v->encoded) {
        close(v->pipe_fd);
        int status = 0;
        while (waitpid(v->pid, &status, 0) < 0 && errno == EINTR) {
        }
        sigaction(SIGPIPE, &v->old_sigpipe, NULL);
        mm__error_set_file(err, v->path);
        if (abort) {
            remove(v->tmp);
        } else if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || v->frames == 0) {
            remove(v->tmp);
            r = mm_error_set(err, MM_ERR_IO, 0, 0, "the video encoder failed (%s)",
                             v->frames == 0 ? "no frames" : "ffmpeg exited with an error");
        } else if (rename(v->tmp, v->path) != 0) {
            remove(v->tmp);
            r = mm_error_set(err, MM_ERR_IO, 0, 0, "cannot write: %s", strerror(errno));
        }
    }
    free(v->path);
    free(v->tmp);
    free(v);
    return r;
}
