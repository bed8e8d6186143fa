/* Import front end: BVH through mm's own reader, everything else through assimp when built with it
 * (src/io/import_assimp.c, the only file that includes assimp's headers). assimp runs in a child
 * process with a time limit: a crafted file that crashes it or makes it hang (known upstream bugs)
 * becomes an error naming the file, never a crash or a hang of mm or of a database build. */
#define _POSIX_C_SOURCE 200809L
#include <mm/bvh.h>
#include <mm/import.h>

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "io/file.h"
#include "io/import_private.h"

#ifdef MM_HAVE_ASSIMP
#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

/* An import taking longer is stopped: the importer hangs (seconds of wall time). */
#define MM_IMPORT_TIME_LIMIT 120
#endif

bool mm_import_has_assimp(void)
{
#ifdef MM_HAVE_ASSIMP
    return true;
#else
    return false;
#endif
}

void mm_clip_list_free(mm_clip_list *list)
{
    if (!list) return;
    if (list->clips)
        for (int i = 0; i < list->count; ++i) mm_clip_free(&list->clips[i]);
    mm_free(&list->allocator, list->clips);
    mm_free(&list->allocator, list->names);
    memset(list, 0, sizeof *list);
}

mm_result mm__clip_list_alloc(mm_clip_list *list, int count, const mm_allocator *allocator)
{
    memset(list, 0, sizeof *list);
    if (allocator) list->allocator = *allocator;
    list->clips = (mm_clip *)mm_alloc_array(allocator, (size_t)count, sizeof *list->clips);
    list->names = (char(*)[MM_TAKE_NAME_MAX])mm_alloc_array(allocator, (size_t)count, sizeof *list->names);
    if (!list->clips || !list->names) {
        mm_clip_list_free(list);
        if (allocator) list->allocator = *allocator;
        return MM_ERR_OUT_OF_MEMORY;
    }
    list->count = count;
    return MM_OK;
}

double mm__import_detect_unit(double height_units, double declared)
{
    if (!(height_units > 0.0) || !isfinite(height_units)) return 0.0;
    if (declared > 0.0) {
        double h = height_units * declared;
        if (h >= 0.8 && h <= 2.6) return declared;
    }
    return mm_unit_scale_for_height(height_units);
}

mm_result mm__import_apply_scale(mm_clip *clip, const mm_import_desc *desc, double declared, mm_error *err)
{
    double scale = 1.0;
    if (desc && desc->auto_scale) {
        const mm_quat *rot = clip->frame_count > 0 ? mm_clip_rotations(clip, 0) : NULL;
        const mm_vec3 *pos = clip->frame_count > 0 ? mm_clip_positions(clip, 0) : NULL;
        double height = mm_skeleton_estimate_height(&clip->skeleton, rot, pos);
        scale = mm__import_detect_unit(height, declared);
        if (scale == 0.0)
            return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0,
                                "cannot detect the unit: the character is %g units tall, which is no human "
                                "height in metres, centimetres, millimetres, inches or feet; give a scale",
                                height);
    } else if (desc && desc->scale != 0.0f) {
        scale = desc->scale;
    }
    if (scale != 1.0) mm_clip_scale(clip, (float)scale);
    return MM_OK;
}

/* The extension after the last dot of the file name, or "". */
static const char *extension(const char *path)
{
    const char *slash = strrchr(path, '/');
    const char *name = slash ? slash + 1 : path;
    const char *dot = strrchr(name, '.');
    return dot && dot != name ? dot + 1 : "";
}

static bool equal_nocase(const char *a, const char *b)
{
    for (; *a && *b; ++a, ++b)
        if (tolower((unsigned char)*a) != tolower((unsigned char)*b)) return false;
    return *a == *b;
}

static mm_result import_bvh(const char *path, const mm_import_desc *desc, mm_clip_list *out, mm_error *err)
{
    const mm_allocator *allocator = desc ? desc->allocator : NULL;
    mm_bvh_read_desc rd;
    memset(&rd, 0, sizeof rd);
    rd.allocator = allocator;
    mm_bvh bvh;
    mm_result r = mm_bvh_load(path, &rd, &bvh, err);
    if (r != MM_OK) return r;
    mm_bvh_import_desc imp;
    memset(&imp, 0, sizeof imp);
    if (desc) {
        imp.scale = desc->scale;
        imp.auto_scale = desc->auto_scale;
    }
    imp.allocator = allocator;
    mm_clip clip;
    r = mm_bvh_to_clip(&bvh, &imp, &clip, err);
    mm_bvh_free(&bvh);
    if (r != MM_OK) return r;
    if (desc && desc->fps > 0.0f && desc->fps != clip.fps) {
        mm_clip resampled;
        r = mm_clip_resample_interp(&resampled, &clip, desc->fps, MM_INTERP_CUBIC, allocator);
        mm_clip_free(&clip);
        if (r != MM_OK)
            return mm_error_set(err, r, 0, 0, "cannot resample to %g fps: %s", desc->fps, mm_result_str(r));
        clip = resampled;
    }
    r = mm__clip_list_alloc(out, 1, allocator);
    if (r != MM_OK) {
        mm_clip_free(&clip);
        return mm_error_set(err, r, 0, 0, "out of memory");
    }
    out->clips[0] = clip;
    /* A BVH file is one take, named after the file. */
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    size_t len = strlen(base) - (strlen(extension(base)) + 1);
    if (len >= MM_TAKE_NAME_MAX) len = MM_TAKE_NAME_MAX - 1;
    memcpy(out->names[0], base, len);
    out->names[0][len] = 0;
    if (!out->names[0][0]) snprintf(out->names[0], MM_TAKE_NAME_MAX, "take1");
    snprintf(out->format, sizeof out->format, "bvh");
    return MM_OK;
}

#ifdef MM_HAVE_ASSIMP
/* ---- assimp in a child process -------------------------------------------------------------
 * The child imports and writes the result down a pipe: the result code and error, then per take
 * its name, fps, counts, joints, rotations and positions, as they are in memory (the same
 * program on both ends). The parent reads it with a deadline and rebuilds the list. */

static int write_all(int fd, const void *data, size_t size)
{
    const char *p = (const char *)data;
    while (size > 0) {
        ssize_t n = write(fd, p, size);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return 0;
        p += n;
        size -= (size_t)n;
    }
    return 1;
}

static void import_child(int fd, const char *path, const mm_import_desc *desc)
{
    mm_import_desc d;
    memset(&d, 0, sizeof d);
    if (desc) d = *desc;
    d.allocator = NULL;
    mm_clip_list list;
    mm_error e;
    memset(&e, 0, sizeof e);
    mm_result r = mm__import_assimp(path, &d, &list, &e);
    int ok = write_all(fd, &r, sizeof r) && write_all(fd, &e, sizeof e);
    if (r == MM_OK) {
        ok = ok && write_all(fd, &list.count, sizeof list.count) &&
             write_all(fd, list.format, sizeof list.format);
        for (int i = 0; ok && i < list.count; ++i) {
            const mm_clip *c = &list.clips[i];
            int counts[2] = {c->frame_count, c->skeleton.joint_count};
            size_t frames = (size_t)c->frame_count * (size_t)c->skeleton.joint_count;
            ok = write_all(fd, list.names[i], MM_TAKE_NAME_MAX) && write_all(fd, &c->fps, sizeof c->fps) &&
                 write_all(fd, counts, sizeof counts) &&
                 write_all(fd, c->skeleton.joints, sizeof(mm_joint) * (size_t)counts[1]) &&
                 write_all(fd, c->rotations, sizeof(mm_quat) * frames) &&
                 write_all(fd, c->positions, sizeof(mm_vec3) * frames);
        }
        mm_clip_list_free(&list);
    }
    close(fd);
    _exit(ok ? 0 : 1);
}

/* What the child wrote, read as it comes. */
typedef struct child_bytes {
    unsigned char *data;
    size_t size, at;
} child_bytes;

static int take(child_bytes *b, void *out, size_t size)
{
    if (b->size - b->at < size) return 0;
    memcpy(out, b->data + b->at, size);
    b->at += size;
    return 1;
}

static double seconds_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Reads the child's output until it closes the pipe or the deadline; 1 when it closed in time. */
static int read_child(int fd, child_bytes *b, double deadline)
{
    size_t cap = 0;
    for (;;) {
        double left = deadline - seconds_now();
        if (left <= 0.0) return 0;
        struct pollfd p = {fd, POLLIN, 0};
        int ready = poll(&p, 1, (int)(left * 1000.0) + 1);
        if (ready < 0 && errno == EINTR) continue;
        if (ready <= 0) return 0;
        if (b->size + 65536 > cap) {
            size_t grown = cap ? 2 * cap : 1 << 20;
            while (grown < b->size + 65536) grown *= 2;
            unsigned char *d = (unsigned char *)realloc(b->data, grown);
            if (!d) return 0;
            b->data = d;
            cap = grown;
        }
        ssize_t n = read(fd, b->data + b->size, cap - b->size);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) return 0;
        if (n == 0) return 1;
        b->size += (size_t)n;
    }
}

/* Rebuilds the list the child imported; MM_ERR_SYNTAX when what it wrote does not hold together. */
static mm_result rebuild(child_bytes *b, const mm_import_desc *desc, mm_clip_list *out, mm_error *err)
{
    int count = 0;
    char format[sizeof out->format];
    if (!take(b, &count, sizeof count) || !take(b, format, sizeof format) || count < 1 ||
        count > MM_MAX_JOINTS)
        return mm_error_set(err, MM_ERR_SYNTAX, 0, 0, "the importer's output is incomplete");
    if (mm__clip_list_alloc(out, count, desc ? desc->allocator : NULL) != MM_OK)
        return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    memcpy(out->format, format, sizeof format);
    out->format[sizeof out->format - 1] = 0;
    for (int i = 0; i < count; ++i) {
        float fps;
        int counts[2];
        if (!take(b, out->names[i], MM_TAKE_NAME_MAX) || !take(b, &fps, sizeof fps) ||
            !take(b, counts, sizeof counts) || counts[0] < 0 || counts[0] > MM_MAX_FRAMES || counts[1] < 1 ||
            counts[1] > MM_MAX_JOINTS)
            return mm_error_set(err, MM_ERR_SYNTAX, 0, 0, "the importer's output is incomplete");
        out->names[i][MM_TAKE_NAME_MAX - 1] = 0;
        mm_skeleton s;
        if (mm_skeleton_init(&s, counts[1], NULL) != MM_OK)
            return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
        mm_result r = take(b, s.joints, sizeof(mm_joint) * (size_t)counts[1])
                          ? mm_skeleton_validate(&s, err)
                          : mm_error_set(err, MM_ERR_SYNTAX, 0, 0, "the importer's output is incomplete");
        if (r == MM_OK) r = mm_clip_init(&out->clips[i], &s, counts[0], fps, desc ? desc->allocator : NULL);
        mm_skeleton_free(&s);
        if (r != MM_OK) return r == MM_ERR_OUT_OF_MEMORY ? mm_error_set(err, r, 0, 0, "out of memory") : r;
        size_t frames = (size_t)counts[0] * (size_t)counts[1];
        if (!take(b, out->clips[i].rotations, sizeof(mm_quat) * frames) ||
            !take(b, out->clips[i].positions, sizeof(mm_vec3) * frames))
            return mm_error_set(err, MM_ERR_SYNTAX, 0, 0, "the importer's output is incomplete");
    }
    return MM_OK;
}

static mm_result import_child_process(const char *path, const mm_import_desc *desc, mm_clip_list *out,
                                      mm_error *err)
{
    int fds[2];
    if (pipe(fds) != 0)
        return mm_error_set(err, MM_ERR_IO, 0, 0, "cannot start the importer: %s", strerror(errno));
    fflush(NULL); /* nothing buffered is written twice */
    pid_t pid = fork();
    if (pid < 0) {
        close(fds[0]);
        close(fds[1]);
        return mm_error_set(err, MM_ERR_IO, 0, 0, "cannot start the importer: %s", strerror(errno));
    }
    if (pid == 0) {
        close(fds[0]);
        /* what the importer or a sanitizer prints as it goes down is not mm's message: mm says
         * what happened, on one line */
        int null = open("/dev/null", O_WRONLY);
        if (null >= 0) dup2(null, STDERR_FILENO);
        import_child(fds[1], path, desc);
    }
    close(fds[1]);
    child_bytes b = {NULL, 0, 0};
    int finished = read_child(fds[0], &b, seconds_now() + MM_IMPORT_TIME_LIMIT);
    close(fds[0]);
    if (!finished) kill(pid, SIGKILL);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    mm_result r;
    mm_error child;
    if (!finished)
        r = mm_error_set(err, MM_ERR_LIMIT, 0, 0, "the importer took more than %d s (stopped)",
                         MM_IMPORT_TIME_LIMIT);
    else if (WIFSIGNALED(status))
        r = mm_error_set(err, MM_ERR_SYNTAX, 0, 0, "the importer failed (signal %d)", WTERMSIG(status));
    else if (!take(&b, &r, sizeof r) || !take(&b, &child, sizeof child))
        r = mm_error_set(err, MM_ERR_SYNTAX, 0, 0, "the importer failed (exit %d)",
                         WIFEXITED(status) ? WEXITSTATUS(status) : -1);
    else if (r != MM_OK) {
        child.message[sizeof child.message - 1] = 0;
        r = mm_error_set(err, r, child.line, child.column, "%s", child.message);
    } else {
        r = rebuild(&b, desc, out, err);
    }
    free(b.data);
    return r;
}
/* One child at a time: assimp imports were serialised anyway (its C API's error is a global), and
 * no thread of this process is then inside assimp when another forks (the child's copy of the
 * importer's lock is free). */
static pthread_mutex_t isolate_lock = PTHREAD_MUTEX_INITIALIZER;

static mm_result import_isolated(const char *path, const mm_import_desc *desc, mm_clip_list *out,
                                 mm_error *err)
{
    pthread_mutex_lock(&isolate_lock);
    mm_result r = import_child_process(path, desc, out, err);
    pthread_mutex_unlock(&isolate_lock);
    return r;
}
#endif

mm_result mm_import_clips(const char *path, const mm_import_desc *desc, mm_clip_list *out, mm_error *err)
{
    if (err) memset(err, 0, sizeof *err);
    if (!out) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no output list given");
    memset(out, 0, sizeof *out);
    if (desc && desc->allocator) out->allocator = *desc->allocator;
    if (!path) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no file name given");
    mm__error_set_file(err, path);
    if (desc && (!isfinite(desc->scale) || desc->scale < 0.0f))
        return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0, "scale %g must be finite and positive (0: keep)",
                            (double)desc->scale);
    if (desc && (!isfinite(desc->fps) || desc->fps < 0.0f || desc->fps > 10000.0f))
        return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0,
                            "fps %g must be in (0, 10000] (0: the take's own)", (double)desc->fps);

    const char *ext = extension(path);
    mm_result r;
    if (equal_nocase(ext, "bvh")) {
        r = import_bvh(path, desc, out, err);
    } else {
#ifdef MM_HAVE_ASSIMP
        r = import_isolated(path, desc, out, err);
#else
        FILE *f = fopen(path, "rb");
        if (!f) return mm_error_set(err, MM_ERR_IO, 0, 0, "cannot open: %s", strerror(errno));
        fclose(f);
        r = mm_error_set(err, MM_ERR_UNSUPPORTED, 0, 0,
                         "mm was built without assimp, so only BVH files can be imported (install "
                         "libassimp-dev and configure with -DMM_WITH_ASSIMP=ON for FBX, glTF, Collada)");
#endif
    }
    if (r != MM_OK) mm_clip_list_free(out);
    return r;
}
