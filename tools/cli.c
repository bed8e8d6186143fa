#define _POSIX_C_SOURCE 200809L
#include "cli.h"

#include <mm/bvh.h>

#include <errno.h>
#include <signal.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

int cli_report(const mm_error *err)
{
    char buf[MM_ERROR_FILE_MAX + MM_ERROR_MESSAGE_MAX + 64];
    mm_error_format(err, buf, sizeof buf);
    fprintf(stderr, "mm: %s\n", buf);
    return 1;
}

int cli_usage_error(const char *command, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "mm %s: ", command);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    return 2;
}

/* 1 when s is [+-]digits[.digits][(e|E)[+-]digits] (or [+-].digits...): strtod would also take
 * hexadecimal, "inf", "nan" and leading spaces, which no option means. */
static int is_decimal(const char *s)
{
    int digits = 0;
    if (*s == '+' || *s == '-') ++s;
    for (; *s >= '0' && *s <= '9'; ++s) ++digits;
    if (*s == '.')
        for (++s; *s >= '0' && *s <= '9'; ++s) ++digits;
    if (!digits) return 0;
    if (*s == 'e' || *s == 'E') {
        ++s;
        if (*s == '+' || *s == '-') ++s;
        if (*s < '0' || *s > '9') return 0;
        while (*s >= '0' && *s <= '9') ++s;
    }
    return *s == 0;
}

int cli_parse_double(const char *s, double *out)
{
    if (!s || !is_decimal(s)) return 0;
    char *end = NULL;
    errno = 0;
    double v = strtod(s, &end);
    /* every option ends up in a float: one that would become 0 or infinite there is refused */
    if (*end || errno || !isfinite(v) || fabs(v) > FLT_MAX || (v != 0.0 && fabs(v) < FLT_MIN)) return 0;
    *out = v;
    return 1;
}

int cli_parse_int(const char *s, long min, long max, long *out)
{
    if (!s || !*s) return 0;
    char *end = NULL;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (*end || errno || v < min || v > max) return 0;
    *out = v;
    return 1;
}

static const cli_option *find_option(const cli_option *options, int count, const char *a)
{
    for (int k = 0; k < count; ++k)
        if (strcmp(a, options[k].name) == 0 || (options[k].alias && strcmp(a, options[k].alias) == 0))
            return &options[k];
    return NULL;
}

/* "NAME needs ..." for a missing or bad value. */
static int needs(const char *command, const cli_option *o)
{
    if (o->need) return cli_usage_error(command, "%s needs %s", o->name, o->need);
    return cli_usage_error(command, "%s needs a number from %ld to %ld", o->name, (long)o->min, (long)o->max);
}

/* Stores v as o's value; 0, or the exit code after printing. */
static int take_value(const char *command, const cli_option *o, const char *v)
{
    int ok = 1;
    long n = 0;
    double x = 0.0;
    switch (o->kind) {
    case CLI_FLAG:
        break;
    case CLI_STRING:
        *(const char **)o->target = v;
        break;
    case CLI_INT:
        ok = cli_parse_int(v, (long)o->min, (long)o->max, &n);
        if (ok) *(long *)o->target = n;
        break;
    case CLI_DOUBLE:
        ok = cli_parse_double(v, &x) && (o->open_min ? x > o->min : x >= o->min) && x <= o->max;
        if (ok) *(double *)o->target = x;
        break;
    case CLI_SIZE:
        ok = cli_parse_size(v, &((int *)o->target)[0], &((int *)o->target)[1]);
        break;
    case CLI_CUSTOM:
        return o->parse(command, o, v);
    }
    return ok ? 0 : needs(command, o);
}

int cli_parse_options(const char *command, int argc, char **argv, const cli_option *options, int option_count,
                      const char *usage, const char **args, int max_args)
{
    int arg_count = 0;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        const cli_option *o = find_option(options, option_count, a);
        if (o && o->kind == CLI_FLAG) {
            *(int *)o->target = 1;
        } else if (o && i + 1 < argc) {
            int status = take_value(command, o, argv[++i]);
            if (status) return status;
        } else if (o && !usage) {
            return needs(command, o);
        } else if (a[0] == '-' && a[1]) {
            if (usage) return cli_usage_error(command, "unknown or incomplete option '%s'\n%s", a, usage);
            return cli_usage_error(command, "unknown option '%s'", a);
        } else if (arg_count < max_args) {
            args[arg_count++] = a;
        } else {
            return cli_usage_error(command, "unexpected argument '%s'", a);
        }
    }
    return 0;
}

int cli_parse_scale(const char *command, const cli_option *option, const char *value)
{
    double *scale = (double *)option->target, x = 0.0;
    if (strcmp(value, "auto") == 0)
        *scale = 0.0;
    else if (cli_parse_double(value, &x) && x > 0 && x <= 1000)
        *scale = x;
    else
        return cli_usage_error(command, "--scale needs a factor in (0, 1000] or auto");
    return 0;
}

/* The temporary files being written, removed if a signal ends the process before they are renamed
 * or removed (an interrupted run leaves nothing behind). */
#define CLI_MAX_TEMPS 8
static char cli_temps[CLI_MAX_TEMPS][CLI_TEMP_NAME_MAX];
static volatile sig_atomic_t cli_temp_used[CLI_MAX_TEMPS];

static volatile sig_atomic_t cli_child; /* an encoder writing one of them; 0: none */

static void cli_on_signal(int sig)
{
    if (cli_child > 0) { /* ended first: it could write its file again once removed */
        kill((pid_t)cli_child, SIGKILL);
        waitpid((pid_t)cli_child, NULL, 0);
    }
    for (int i = 0; i < CLI_MAX_TEMPS; ++i)
        if (cli_temp_used[i]) unlink(cli_temps[i]); /* async-signal-safe */
    signal(sig, SIG_DFL);
    raise(sig);
}

void cli_remember_temp(const char *tmp)
{
    static int installed = 0;
    if (!installed) {
        const int signals[3] = {SIGINT, SIGTERM, SIGHUP};
        for (int k = 0; k < 3; ++k) {
            struct sigaction sa;
            memset(&sa, 0, sizeof sa);
            sa.sa_handler = cli_on_signal;
            sigemptyset(&sa.sa_mask);
            sigaction(signals[k], &sa, NULL);
        }
        installed = 1;
    }
    if (strlen(tmp) >= CLI_TEMP_NAME_MAX) return;
    for (int i = 0; i < CLI_MAX_TEMPS; ++i)
        if (!cli_temp_used[i]) {
            memcpy(cli_temps[i], tmp, strlen(tmp) + 1);
            cli_temp_used[i] = 1;
            return;
        }
}

void cli_remember_child(long pid) { cli_child = (sig_atomic_t)pid; }

void cli_forget_temp(const char *tmp)
{
    for (int i = 0; i < CLI_MAX_TEMPS; ++i)
        if (cli_temp_used[i] && strcmp(cli_temps[i], tmp) == 0) cli_temp_used[i] = 0;
}

FILE *cli_create(const char *path, char *tmp, size_t tmp_size)
{
    struct stat st;
    if (!path[0]) {
        fprintf(stderr, "mm: cannot create a file: no file name given\n");
        return NULL;
    }
    if (stat(path, &st) == 0 && S_ISDIR(st.st_mode)) { /* the rename would fail only at the end */
        fprintf(stderr, "mm: %s: cannot create: %s\n", path, strerror(EISDIR));
        return NULL;
    }
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode)) {
        /* a device or a pipe (/dev/null, /dev/stdout): written in place, never replaced by a
         * renamed file; tmp is left empty for cli_finish and cli_publish */
        if (tmp_size > 0) tmp[0] = 0;
        FILE *f = fopen(path, "wb");
        if (!f) fprintf(stderr, "mm: %s: cannot create: %s\n", path, strerror(errno));
        return f;
    }
    int n = snprintf(tmp, tmp_size, "%s.tmp%ld", path, (long)getpid());
    if (n < 0 || (size_t)n >= tmp_size) {
        fprintf(stderr, "mm: %s: cannot create: the path is too long\n", path);
        return NULL;
    }
    FILE *f = fopen(tmp, "wb");
    if (!f)
        fprintf(stderr, "mm: %s: cannot create: %s\n", path, strerror(errno));
    else
        cli_remember_temp(tmp);
    return f;
}

int cli_load_clip(const char *path, double scale, mm_clip *clip)
{
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_bvh bvh;
    if (mm_bvh_load(path, NULL, &bvh, &err) != MM_OK) return cli_report(&err);
    mm_bvh_import_desc imp;
    memset(&imp, 0, sizeof imp);
    imp.auto_scale = !(scale > 0.0);
    imp.scale = scale > 0.0 ? (float)scale : 0.0f;
    mm_result r = mm_bvh_to_clip(&bvh, &imp, clip, &err);
    mm_bvh_free(&bvh);
    if (r != MM_OK) {
        snprintf(err.file, sizeof err.file, "%s", path);
        return cli_report(&err);
    }
    return 0;
}

int cli_finish(FILE *f, const char *tmp, const char *path)
{
    errno = 0;
    int bad = ferror(f) != 0;
    bad |= fclose(f) != 0;
    if (bad) {
        fprintf(stderr, "mm: %s: cannot write: %s\n", path, errno ? strerror(errno) : "write error");
        if (tmp[0]) remove(tmp);
        cli_forget_temp(tmp);
        return 1;
    }
    return 0;
}

int cli_publish(const char *tmp, const char *path)
{
    if (!tmp[0]) return 0; /* written in place (cli_create) */
    int renamed = rename(tmp, path) == 0;
    if (!renamed) {
        fprintf(stderr, "mm: %s: cannot write: %s\n", path, strerror(errno));
        remove(tmp);
    }
    cli_forget_temp(tmp);
    return renamed ? 0 : 1;
}

int cli_commit(FILE *f, const char *tmp, const char *path, int failed)
{
    if (failed) {
        fclose(f);
        if (tmp[0]) remove(tmp);
        cli_forget_temp(tmp);
        return 1;
    }
    return cli_finish(f, tmp, path) || cli_publish(tmp, path);
}

void cli_json_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s; ++s) {
        unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\')
            fprintf(f, "\\%c", c);
        else if (c < 0x20)
            fprintf(f, "\\u%04x", c);
        else
            fputc(c, f);
    }
    fputc('"', f);
}

int cli_parse_size(const char *s, int *width, int *height)
{
    long w = 0, h = 0;
    char tail = 0;
    if (sscanf(s, "%ldx%ld%c", &w, &h, &tail) != 2 || w < 16 || h < 16 || w > 4096 || h > 4096) return 0;
    *width = (int)w;
    *height = (int)h;
    return 1;
}

long cli_default_threads(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : n > 8 ? 8 : n;
}

double cli_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The file's name without folders and extension. */
void cli_file_stem(const char *path, char *out, size_t size)
{
    const char *s = strrchr(path, '/');
    s = s ? s + 1 : path;
    const char *dot = strrchr(s, '.');
    int len = dot && dot > s ? (int)(dot - s) : (int)strlen(s);
    snprintf(out, size, "%.*s", len, s);
}

/* How a config names the file: relative to $MM_DATA_DIR when it is inside it. */
void cli_config_file_name(const char *path, char *out, size_t size)
{
    const char *data = getenv("MM_DATA_DIR");
    size_t n = data ? strlen(data) : 0;
    while (n > 0 && data[n - 1] == '/') --n;
    if (n > 0 && strncmp(path, data, n) == 0 && path[n] == '/')
        snprintf(out, size, "%s", path + n + 1);
    else
        snprintf(out, size, "%s", path);
}
