/* mm pfnn eval --weights DIR --x X.bin --phase P [--mode constant|linear|cubic] -o Y.bin
 *
 * Runs the phase-functioned network on raw inputs, for checking against other implementations:
 * X.bin holds rows of 342 little-endian float32 (un-normalised inputs), Y.bin receives rows of 311
 * float32 (de-normalised outputs). DIR is the folder holding network/ (default $MM_DATA_DIR/pfnn).
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <mm/mm.h>

#include "cli.h"
#include "commands.h"

#define EVAL_USAGE                                                                                           \
    "usage: mm pfnn eval --weights DIR --x X.bin --phase P [--mode constant|linear|cubic] -o Y.bin"

static void put_le(unsigned char *p, float v)
{
    unsigned bits;
    memcpy(&bits, &v, 4);
    p[0] = (unsigned char)(bits & 0xff);
    p[1] = (unsigned char)(bits >> 8 & 0xff);
    p[2] = (unsigned char)(bits >> 16 & 0xff);
    p[3] = (unsigned char)(bits >> 24 & 0xff);
}

static float get_le(const unsigned char *p)
{
    unsigned bits = (unsigned)p[0] | (unsigned)p[1] << 8 | (unsigned)p[2] << 16 | (unsigned)p[3] << 24;
    float v;
    memcpy(&v, &bits, 4);
    return v;
}

/* Reads all of path; *out_size bytes. Returns 0 or prints the error and returns 1. */
static int read_all(const char *path, unsigned char **out, size_t *out_size)
{
    *out = NULL;
    *out_size = 0;
    FILE *f = fopen(path, "rb");
    if (!f) {
        fprintf(stderr, "mm: %s: cannot open: %s\n", path, strerror(errno));
        return 1;
    }
    size_t cap = 1 << 16, n = 0;
    unsigned char *buf = (unsigned char *)malloc(cap);
    while (buf) {
        n += fread(buf + n, 1, cap - n, f);
        if (n < cap) break;
        unsigned char *nb = (unsigned char *)realloc(buf, cap * 2);
        if (!nb) {
            free(buf);
            buf = NULL;
            break;
        }
        buf = nb;
        cap *= 2;
    }
    int bad = ferror(f);
    fclose(f);
    if (!buf || bad) {
        fprintf(stderr, "mm: %s: %s\n", path, buf ? "read error" : "out of memory");
        free(buf);
        return 1;
    }
    *out = buf;
    *out_size = n;
    return 0;
}

static int cmd_eval(int argc, char **argv)
{
    const char *weights = NULL, *xpath = NULL, *ypath = NULL, *mode_name = "cubic", *phase_text = NULL;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        const char **slot = strcmp(a, "--weights") == 0 ? &weights
                            : strcmp(a, "--x") == 0     ? &xpath
                            : strcmp(a, "-o") == 0      ? &ypath
                            : strcmp(a, "--mode") == 0  ? &mode_name
                            : strcmp(a, "--phase") == 0 ? &phase_text
                                                        : NULL;
        if (!slot) return cli_usage_error("pfnn eval", "unknown argument '%s'\n%s", a, EVAL_USAGE);
        if (i + 1 >= argc) return cli_usage_error("pfnn eval", "%s needs a value\n%s", a, EVAL_USAGE);
        *slot = argv[++i];
    }
    char default_weights[4096];
    if (!weights) {
        const char *d = getenv("MM_DATA_DIR");
        if (d && *d) {
            snprintf(default_weights, sizeof default_weights, "%s/pfnn", d);
            weights = default_weights;
        }
    }
    if (!weights || !xpath || !ypath || !phase_text)
        return cli_usage_error(
            "pfnn eval", "--weights (or $MM_DATA_DIR), --x, --phase and -o are required\n%s", EVAL_USAGE);
    mm_pfnn_mode mode = mm_pfnn_mode_parse(mode_name);
    if (mode == MM_PFNN_MODE_DEFAULT)
        return cli_usage_error("pfnn eval", "--mode must be constant, linear or cubic, not '%s'", mode_name);
    double phase;
    if (!cli_parse_double(phase_text, &phase))
        return cli_usage_error("pfnn eval", "--phase must be a number (radians), not '%s'", phase_text);

    unsigned char *xdata;
    size_t xsize;
    if (read_all(xpath, &xdata, &xsize)) return 1;
    const size_t row_in = MM_PFNN_INPUT_DIM * 4, row_out = MM_PFNN_OUTPUT_DIM * 4;
    if (xsize == 0 || xsize % row_in != 0) {
        fprintf(stderr, "mm: %s: %zu bytes is not a whole number of rows of %d float32 (%zu bytes)\n", xpath,
                xsize, MM_PFNN_INPUT_DIM, row_in);
        free(xdata);
        return 1;
    }
    size_t rows = xsize / row_in;

    mm_error err;
    memset(&err, 0, sizeof err);
    mm_pfnn_network_desc nd;
    memset(&nd, 0, sizeof nd);
    nd.modes = MM_PFNN_MODE_BIT(mode);
    mm_pfnn_network *net = NULL;
    if (mm_pfnn_network_load(weights, &nd, &net, &err) != MM_OK) {
        free(xdata);
        return cli_report(&err);
    }
    unsigned char *ydata = (unsigned char *)malloc(rows * row_out);
    int rc = 0;
    if (!ydata) {
        fprintf(stderr, "mm: out of memory\n");
        rc = 1;
    }
    float x[MM_PFNN_INPUT_DIM], y[MM_PFNN_OUTPUT_DIM];
    for (size_t r = 0; !rc && r < rows; ++r) {
        for (int i = 0; i < MM_PFNN_INPUT_DIM; ++i) x[i] = get_le(xdata + r * row_in + 4 * (size_t)i);
        mm_pfnn_network_eval(net, mode, (float)mm_pfnn_wrap_phase(phase), x, y);
        for (int i = 0; i < MM_PFNN_OUTPUT_DIM; ++i) put_le(ydata + r * row_out + 4 * (size_t)i, y[i]);
    }
    mm_pfnn_network_free(net);
    free(xdata);
    if (!rc) {
        char tmp[4096 + 32];
        FILE *f = cli_create(ypath, tmp, sizeof tmp);
        if (!f) {
            rc = 1;
        } else {
            int ok = fwrite(ydata, 1, rows * row_out, f) == rows * row_out;
            if (!ok) fprintf(stderr, "mm: %s: cannot write: %s\n", ypath, strerror(errno));
            rc = cli_commit(f, tmp, ypath, !ok);
        }
    }
    free(ydata);
    return rc;
}

int mm_cmd_pfnn(int argc, char **argv)
{
    if (argc >= 2 && strcmp(argv[1], "eval") == 0) return cmd_eval(argc - 1, argv + 1);
    if (argc >= 2 && strcmp(argv[1], "run") == 0) return mm_cmd_pfnn_run(argc - 1, argv + 1);
    if (argc >= 2)
        return cli_usage_error("pfnn", "unknown subcommand '%s' (eval, run)\n%s", argv[1], EVAL_USAGE);
    return cli_usage_error("pfnn", "%s", EVAL_USAGE);
}
