/* mm convert BVH_FOLDER FBX_FOLDER [--batch-size N] [--blender PATH] [--verbose]
 *
 * Batch-converts BVH files to FBX through Blender: the .bvh files of the folder, sorted by name,
 * go in batches of N (files of one skeleton per batch) into one FBX each, one take per BVH, by
 * tools/blender/bvh_to_fbx.py (compiled into this program and written to a temporary file for
 * Blender to run). */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <mm/bvh.h>

#include "cli.h"
#include "commands.h"

/* tools/blender/bvh_to_fbx.py, embedded by CMake (generated/blender_script.c). */
extern const unsigned char mm_blender_script[];
extern const size_t mm_blender_script_size;

#define USAGE "usage: mm convert BVH_FOLDER FBX_FOLDER [--batch-size 10] [--blender PATH] [--verbose]"

/* The executable: path itself when it has a slash, else the first match on $PATH. */
static int find_program(const char *name, char *out, size_t size)
{
    if (strchr(name, '/')) {
        snprintf(out, size, "%s", name);
        return access(out, X_OK) == 0;
    }
    const char *path = getenv("PATH");
    if (!path || !*path) path = "/usr/local/bin:/usr/bin:/bin";
    while (*path) {
        const char *colon = strchr(path, ':');
        size_t len = colon ? (size_t)(colon - path) : strlen(path);
        if (len == 0)
            snprintf(out, size, "./%s", name);
        else
            snprintf(out, size, "%.*s/%s", (int)len, path, name);
        struct stat st;
        if (stat(out, &st) == 0 && S_ISREG(st.st_mode) && access(out, X_OK) == 0) return 1;
        path += len + (colon ? 1 : 0);
    }
    return 0;
}

static int has_bvh_extension(const char *name)
{
    size_t n = strlen(name);
    if (n < 5) return 0;
    const char *e = name + n - 4;
    return e[0] == '.' && (e[1] | 32) == 'b' && (e[2] | 32) == 'v' && (e[3] | 32) == 'h';
}

static int compare_names(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

typedef struct bvh_file {
    char *name;     /* file name in the folder */
    char *path;     /* folder/name */
    char *skeleton; /* joint names, one per line: files of one skeleton share it */
} bvh_file;

static void free_files(bvh_file *files, int count)
{
    for (int i = 0; i < count; ++i) {
        free(files[i].path);
        free(files[i].skeleton);
    }
    free(files);
}

/* Runs blender on one batch; returns its exit status (-1 if it could not run). */
static int run_blender(const char *blender, const char *script, const char *out, bvh_file *files, int count,
                       int verbose)
{
    char **argv = (char **)calloc((size_t)count + 12, sizeof *argv);
    if (!argv) return -1;
    int a = 0;
    argv[a++] = (char *)blender;
    argv[a++] = (char *)"--background";
    argv[a++] = (char *)"--factory-startup";
    argv[a++] = (char *)"--python-exit-code";
    argv[a++] = (char *)"2";
    argv[a++] = (char *)"--python";
    argv[a++] = (char *)script;
    argv[a++] = (char *)"--";
    argv[a++] = (char *)out;
    for (int i = 0; i < count; ++i) argv[a++] = files[i].path;
    argv[a] = NULL;
    fflush(stdout);
    fflush(stderr);
    pid_t pid = fork();
    if (pid < 0) {
        free(argv);
        return -1;
    }
    if (pid == 0) {
        if (!verbose) {
            FILE *null = freopen("/dev/null", "w", stdout);
            (void)null;
        }
        execv(blender, argv);
        fprintf(stderr, "mm convert: cannot run %s: %s\n", blender, strerror(errno));
        _exit(127);
    }
    free(argv);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR) return -1;
    if (WIFEXITED(status)) return WEXITSTATUS(status);
    return -1;
}

/* The output file of a batch: "<stem>.fbx" for one file, "<first>_to_<last>.fbx" for more. */
static void output_path(char *buf, size_t size, const char *folder, const bvh_file *first,
                        const bvh_file *last)
{
    int a = (int)strlen(first->name) - 4, b = (int)strlen(last->name) - 4;
    if (first == last)
        snprintf(buf, size, "%s/%.*s.fbx", folder, a, first->name);
    else
        snprintf(buf, size, "%s/%.*s_to_%.*s.fbx", folder, a, first->name, b, last->name);
}

int mm_cmd_convert(int argc, char **argv)
{
    const char *in_dir = NULL, *out_dir = NULL, *blender_arg = NULL;
    long batch_size = 10;
    int verbose = 0;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        if (strcmp(a, "--batch-size") == 0) {
            if (i + 1 >= argc || !cli_parse_int(argv[i + 1], 1, 100000, &batch_size))
                return cli_usage_error("convert",
                                       "--batch-size needs a number of takes per FBX file, 1 or more");
            ++i;
        } else if (strcmp(a, "--blender") == 0) {
            if (i + 1 >= argc)
                return cli_usage_error("convert", "--blender needs the path of the blender program");
            blender_arg = argv[++i];
        } else if (strcmp(a, "--verbose") == 0) {
            verbose = 1;
        } else if (a[0] == '-' && a[1]) {
            return cli_usage_error("convert", "unknown option '%s'", a);
        } else if (!in_dir) {
            in_dir = a;
        } else if (!out_dir) {
            out_dir = a;
        } else {
            return cli_usage_error("convert", "unexpected argument '%s'", a);
        }
    }
    if (!in_dir || !out_dir) return cli_usage_error("convert", USAGE);

    char blender[4096];
    if (!find_program(blender_arg ? blender_arg : "blender", blender, sizeof blender)) {
        if (blender_arg)
            fprintf(stderr, "mm convert: Blender is not installed at '%s' (no executable there).\n",
                    blender_arg);
        else
            fprintf(stderr, "mm convert: Blender is not installed (no 'blender' on PATH).\n");
        fprintf(stderr, "mm convert converts BVH to FBX through Blender: apt-get install blender (Debian, "
                        "Ubuntu), or download it from blender.org and give its path with --blender PATH.\n");
        return 1;
    }

    /* The BVH files, sorted by name, each read once to group them by skeleton. */
    DIR *dir = opendir(in_dir);
    if (!dir) {
        fprintf(stderr, "mm convert: %s: cannot open the folder: %s\n", in_dir, strerror(errno));
        return 1;
    }
    char **names = NULL;
    int count = 0, cap = 0;
    struct dirent *e;
    while ((e = readdir(dir)) != NULL) {
        if (!has_bvh_extension(e->d_name)) continue;
        if (count == cap) {
            cap = cap ? 2 * cap : 64;
            char **n = (char **)realloc(names, (size_t)cap * sizeof *n);
            if (!n) break;
            names = n;
        }
        if (!(names[count] = strdup(e->d_name))) break;
        ++count;
    }
    closedir(dir);
    if (count == 0) {
        fprintf(stderr, "mm convert: %s: no .bvh files in the folder\n", in_dir);
        free(names);
        return 1;
    }
    qsort(names, (size_t)count, sizeof *names, compare_names);
    bvh_file *files = (bvh_file *)calloc((size_t)count, sizeof *files);
    int rc = 0;
    for (int i = 0; i < count && files; ++i) {
        files[i].name = names[i];
        size_t len = strlen(in_dir) + strlen(names[i]) + 2;
        files[i].path = (char *)malloc(len);
        if (!files[i].path) {
            rc = 1;
            break;
        }
        snprintf(files[i].path, len, "%s/%s", in_dir, names[i]);
        mm_bvh bvh;
        mm_error err;
        memset(&err, 0, sizeof err);
        if (mm_bvh_load(files[i].path, NULL, &bvh, &err) != MM_OK) {
            rc = cli_report(&err);
            break;
        }
        size_t total = 1;
        for (int j = 0; j < bvh.skeleton.joint_count; ++j) total += strlen(bvh.skeleton.joints[j].name) + 1;
        files[i].skeleton = (char *)malloc(total);
        if (files[i].skeleton) {
            char *p = files[i].skeleton;
            for (int j = 0; j < bvh.skeleton.joint_count; ++j)
                p += sprintf(p, "%s\n", bvh.skeleton.joints[j].name);
            *p = 0;
        }
        mm_bvh_free(&bvh);
        if (!files[i].skeleton) rc = 1;
    }
    if (!files || rc) {
        if (!files || rc == 1) fprintf(stderr, "mm convert: cannot read the BVH files\n");
        if (files) free_files(files, count);
        for (int i = 0; i < count; ++i) free(names[i]);
        free(names);
        return 1;
    }

    if (mkdir(out_dir, 0777) != 0 && errno != EEXIST) {
        fprintf(stderr, "mm convert: %s: cannot create the folder: %s\n", out_dir, strerror(errno));
        rc = 1;
    }
    /* Blender runs the embedded script from a temporary file. */
    char script[4096] = "";
    if (!rc) {
        const char *tmp = getenv("TMPDIR");
        snprintf(script, sizeof script, "%s/mm_bvh_to_fbx_XXXXXX", tmp && *tmp ? tmp : "/tmp");
        int fd = mkstemp(script);
        FILE *f = fd >= 0 ? fdopen(fd, "wb") : NULL;
        if (!f || fwrite(mm_blender_script, 1, mm_blender_script_size, f) != mm_blender_script_size ||
            fclose(f) != 0) {
            fprintf(stderr, "mm convert: cannot write the Blender script %s: %s\n", script, strerror(errno));
            if (fd >= 0) unlink(script);
            script[0] = 0;
            rc = 1;
        }
    }
    int batches = 0;
    for (int first = 0; !rc && first < count;) {
        int n = 1;
        while (first + n < count && n < batch_size &&
               strcmp(files[first + n].skeleton, files[first].skeleton) == 0)
            ++n;
        char out[4096];
        output_path(out, sizeof out, out_dir, &files[first], &files[first + n - 1]);
        int status = run_blender(blender, script, out, &files[first], n, verbose);
        struct stat st;
        if (status != 0 || stat(out, &st) != 0) {
            fprintf(
                stderr,
                "mm convert: Blender failed on %s (exit status %d); run with --verbose to see its output\n",
                out, status);
            rc = 1;
            break;
        }
        printf("%s: %d take%s:", out, n, n == 1 ? "" : "s");
        for (int i = 0; i < n; ++i) printf(" %s", files[first + i].name);
        if (n < batch_size && first + n < count) printf(" (%s has other joints)", files[first + n].name);
        printf("\n");
        ++batches;
        first += n;
    }
    if (script[0]) unlink(script);
    if (!rc) printf("converted %d BVH files into %d FBX files in %s\n", count, batches, out_dir);
    free_files(files, count);
    for (int i = 0; i < count; ++i) free(names[i]);
    free(names);
    return rc;
}
