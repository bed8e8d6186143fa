/* The phase-functioned network: loading, the phase function, the three modes, the forward pass.
 *
 * Layout: every weight set (a control point, or a precomputed sample of the spline) is one
 * contiguous block of floats holding the three layers. A layer's matrix is stored in panels of
 * PANEL output rows: panel p holds, for every input c, the PANEL weights W[p*PANEL + l][c] side by
 * side, so the product is a stream of "acc[l] += w[l] * x[c]" over contiguous memory: plain loops
 * the compiler turns into SIMD without reordering any sum (each output is accumulated over the
 * inputs in order, whatever the vector width, so results do not depend on the machine). Output
 * counts are padded with zero rows to a multiple of PANEL (311 -> 320).
 *
 * A mode evaluates a weighted sum of K weight sets: constant K = 1, linear K = 2, cubic K = 4 (the
 * control points, with the spline's coefficients). The sum is taken over the K products, not the
 * weights: sum_k c_k (W_k x) = (sum_k c_k W_k) x. */
#include <mm/pfnn.h>

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "io/file.h"
#include "pfnn/pfnn_private.h"

#define PANEL       16
#define MAX_SAMPLES 1000
#define GRID        100 /* phases on multiples of 1/GRID cycle are snapped onto them */
#define SNAP        1e-6

static const int layer_in[3] = {MM_PFNN_INPUT_DIM, MM_PFNN_HIDDEN_DIM, MM_PFNN_HIDDEN_DIM};
static const int layer_out[3] = {MM_PFNN_HIDDEN_DIM, MM_PFNN_HIDDEN_DIM, MM_PFNN_OUTPUT_DIM};

static int padded(int n) { return (n + PANEL - 1) / PANEL * PANEL; }

/* Offsets (in floats) of each layer's weights and bias inside a set, and the set's size. */
typedef struct set_layout {
    size_t w[3], b[3], size;
} set_layout;

static set_layout layout(void)
{
    set_layout s;
    size_t o = 0;
    for (int l = 0; l < 3; ++l) {
        s.w[l] = o;
        o += (size_t)padded(layer_out[l]) * (size_t)layer_in[l];
        s.b[l] = o;
        o += (size_t)padded(layer_out[l]);
    }
    s.size = o;
    return s;
}

struct mm_pfnn_network {
    mm_allocator allocator;
    bool has_allocator;
    unsigned modes;
    int constant_samples, linear_samples;
    set_layout lay;
    float xmean[MM_PFNN_INPUT_DIM], xstd[MM_PFNN_INPUT_DIM];
    float ymean[MM_PFNN_OUTPUT_DIM], ystd[MM_PFNN_OUTPUT_DIM];
    float *control;  /* [4][lay.size] */
    float *constant; /* [constant_samples][lay.size] or NULL */
    float *linear;   /* [linear_samples][lay.size] or NULL */
};

const float *mm__pfnn_network_ymean(const mm_pfnn_network *net) { return net->ymean; }

const char *mm_pfnn_mode_name(mm_pfnn_mode mode)
{
    switch (mode) {
    case MM_PFNN_MODE_CONSTANT:
        return "constant";
    case MM_PFNN_MODE_LINEAR:
        return "linear";
    case MM_PFNN_MODE_CUBIC:
        return "cubic";
    default:
        return NULL;
    }
}

mm_pfnn_mode mm_pfnn_mode_parse(const char *name)
{
    if (!name) return MM_PFNN_MODE_DEFAULT;
    for (int m = MM_PFNN_MODE_CONSTANT; m <= MM_PFNN_MODE_CUBIC; ++m)
        if (strcmp(name, mm_pfnn_mode_name((mm_pfnn_mode)m)) == 0) return (mm_pfnn_mode)m;
    return MM_PFNN_MODE_DEFAULT;
}

/* ---- phase ------------------------------------------------------------------------------------ */

/* A phase in cycles, u in [0, 1); grid >= 0 when u is exactly grid / GRID. */
typedef struct cycle_pos {
    double u;
    int grid;
} cycle_pos;

static cycle_pos to_cycles(double phase)
{
    cycle_pos c;
    c.grid = -1;
    if (!isfinite(phase)) phase = 0.0;
    double u = phase / (2.0 * MM_PI);
    u -= floor(u);
    double g = nearbyint(u * GRID);
    if (fabs(u - g / GRID) < SNAP) {
        c.grid = (int)g % GRID;
        u = (double)c.grid / GRID;
    }
    if (!(u >= 0.0 && u < 1.0)) u = 0.0;
    c.u = u;
    return c;
}

double mm_pfnn_wrap_phase(double phase) { return to_cycles(phase).u * 2.0 * MM_PI; }

/* Index i in [0, count) and fraction t in [0, 1) with u * count = i + t; exact on the grid. */
static void sample_at(cycle_pos c, int count, int *i, double *t)
{
    if (c.grid >= 0) {
        long n = (long)c.grid * count;
        *i = (int)(n / GRID);
        *t = (double)(n % GRID) / GRID;
    } else {
        double w = c.u * count;
        double f = floor(w);
        *i = (int)f;
        *t = w - f;
        if (*t < 0.0) *t = 0.0;
    }
    if (*i >= count) *i = count - 1;
    if (*i < 0) *i = 0;
}

static void spline_coefficients(cycle_pos c, double coef[4])
{
    int k1;
    double t;
    sample_at(c, 4, &k1, &t);
    int k0 = (k1 + 3) % 4, k2 = (k1 + 1) % 4, k3 = (k1 + 2) % 4;
    double t2 = t * t, t3 = t2 * t;
    for (int k = 0; k < 4; ++k) coef[k] = 0.0;
    coef[k1] = 1.0 - 2.5 * t2 + 1.5 * t3;
    coef[k2] = 0.5 * t + 2.0 * t2 - 1.5 * t3;
    coef[k0] = -0.5 * t + t2 - 0.5 * t3;
    coef[k3] = -0.5 * t2 + 0.5 * t3;
}

void mm_pfnn_spline_coefficients(double phase, double coef[MM_PFNN_CONTROL_POINTS])
{
    spline_coefficients(to_cycles(phase), coef);
}

/* ---- loading ---------------------------------------------------------------------------------- */

static bool host_little_endian(void)
{
    const uint32_t one = 1;
    unsigned char b;
    memcpy(&b, &one, 1);
    return b == 1;
}

/* Reads dir/network/name: exactly count float32, into out[count] (out may be NULL to only check). */
static mm_result read_floats(const char *dir, const char *name, size_t count, const char *shape,
                             const mm_allocator *a, float *out, mm_error *err)
{
    char path[4096];
    int n = snprintf(path, sizeof path, "%s/network/%s", dir, name);
    mm__error_set_file(err, n > 0 && (size_t)n < sizeof path ? path : name);
    if (n <= 0 || (size_t)n >= sizeof path)
        return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "path too long");
    char *data = NULL;
    size_t size = 0;
    mm_result r = mm__read_file(path, a, &data, &size, err);
    if (r != MM_OK) return r;
    if (size != count * 4) {
        mm_free(a, data);
        return mm_error_set(err, size < count * 4 ? MM_ERR_UNEXPECTED_EOF : MM_ERR_VALUE_COUNT, 0, 0,
                            "%s file: %zu bytes, expected %zu (%s float32)",
                            size < count * 4 ? "short" : "long", size, count * 4, shape);
    }
    bool swap = !host_little_endian();
    for (size_t i = 0; i < count; ++i) {
        unsigned char *p = (unsigned char *)data + 4 * i;
        if (swap) {
            unsigned char t = p[0];
            p[0] = p[3];
            p[3] = t;
            t = p[1];
            p[1] = p[2];
            p[2] = t;
        }
        float v;
        memcpy(&v, p, 4);
        if (!isfinite(v)) {
            mm_free(a, data);
            return mm_error_set(err, MM_ERR_BAD_NUMBER, 0, 0, "value %zu is not finite", i);
        }
        out[i] = v;
    }
    mm_free(a, data);
    return MM_OK;
}

/* Reads a row-major [out][in] matrix file into the panel layout at dst. */
static mm_result read_matrix(const char *dir, const char *name, int out_dim, int in_dim,
                             const mm_allocator *a, float *dst, mm_error *err)
{
    size_t count = (size_t)out_dim * (size_t)in_dim;
    float *tmp = (float *)mm_alloc(a, count * sizeof(float));
    if (!tmp) return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    char shape[32];
    snprintf(shape, sizeof shape, "%d x %d", out_dim, in_dim);
    mm_result r = read_floats(dir, name, count, shape, a, tmp, err);
    if (r == MM_OK) {
        for (int o = 0; o < out_dim; ++o)
            for (int c = 0; c < in_dim; ++c)
                dst[(size_t)(o / PANEL) * in_dim * PANEL + (size_t)c * PANEL + o % PANEL] =
                    tmp[(size_t)o * in_dim + c];
    }
    mm_free(a, tmp);
    return r;
}

/* dst = sum_k coef[k] * src[k], element by element over whole sets, in double. */
static void combine_sets(float *dst, const float *const *src, const double *coef, int k_count, size_t size)
{
    for (size_t i = 0; i < size; ++i) {
        double s = 0.0;
        for (int k = 0; k < k_count; ++k) s += coef[k] * (double)src[k][i];
        dst[i] = (float)s;
    }
}

/* Fills count samples of the spline at phases 2 pi s / count. */
static void make_samples(const mm_pfnn_network *net, float *dst, int count)
{
    const float *src[4];
    for (int k = 0; k < 4; ++k) src[k] = net->control + (size_t)k * net->lay.size;
    for (int s = 0; s < count; ++s) {
        cycle_pos c;
        c.u = (double)s / count;
        c.grid = (s * GRID) % count == 0 ? s * GRID / count : -1;
        double coef[4];
        spline_coefficients(c, coef);
        combine_sets(dst + (size_t)s * net->lay.size, src, coef, 4, net->lay.size);
    }
}

mm_result mm_pfnn_network_load(const char *dir, const mm_pfnn_network_desc *desc, mm_pfnn_network **out,
                               mm_error *err)
{
    if (out) *out = NULL;
    if (!dir || !out) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no folder or output given");
    mm_pfnn_network_desc d;
    memset(&d, 0, sizeof d);
    if (desc) d = *desc;
    if (!d.modes) d.modes = MM_PFNN_MODE_BIT(MM_PFNN_MODE_CUBIC);
    if (d.modes & MM_PFNN_MODE_BIT(MM_PFNN_MODE_DEFAULT)) d.modes |= MM_PFNN_MODE_BIT(MM_PFNN_MODE_CUBIC);
    d.modes &= MM_PFNN_MODE_BIT(MM_PFNN_MODE_CONSTANT) | MM_PFNN_MODE_BIT(MM_PFNN_MODE_LINEAR) |
               MM_PFNN_MODE_BIT(MM_PFNN_MODE_CUBIC);
    if (!d.constant_samples) d.constant_samples = 50;
    if (!d.linear_samples) d.linear_samples = 10;
    if (d.constant_samples < 1 || d.constant_samples > MAX_SAMPLES || d.linear_samples < 1 ||
        d.linear_samples > MAX_SAMPLES)
        return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0, "sample counts must be 1..%d", MAX_SAMPLES);

    const mm_allocator *a = d.allocator;
    mm_pfnn_network *net = (mm_pfnn_network *)mm_alloc_array(a, 1, sizeof *net);
    if (!net) return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    if (a) {
        net->allocator = *a;
        net->has_allocator = true;
    }
    net->modes = d.modes;
    net->constant_samples = d.constant_samples;
    net->linear_samples = d.linear_samples;
    net->lay = layout();
    mm_result r = MM_OK;
    net->control = (float *)mm_alloc_array(a, 4 * net->lay.size, sizeof(float));
    if (!net->control) r = mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");

    if (r == MM_OK) r = read_floats(dir, "Xmean.bin", MM_PFNN_INPUT_DIM, "342", a, net->xmean, err);
    if (r == MM_OK) r = read_floats(dir, "Xstd.bin", MM_PFNN_INPUT_DIM, "342", a, net->xstd, err);
    if (r == MM_OK) r = read_floats(dir, "Ymean.bin", MM_PFNN_OUTPUT_DIM, "311", a, net->ymean, err);
    if (r == MM_OK) r = read_floats(dir, "Ystd.bin", MM_PFNN_OUTPUT_DIM, "311", a, net->ystd, err);
    for (int i = 0; r == MM_OK && i < MM_PFNN_INPUT_DIM; ++i)
        if (!(net->xstd[i] > 0.0f))
            r = mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0, "Xstd[%d] = %g is not positive", i,
                             (double)net->xstd[i]);
    for (int k = 0; r == MM_OK && k < 4; ++k) {
        float *set = net->control + (size_t)k * net->lay.size;
        for (int l = 0; r == MM_OK && l < 3; ++l) {
            char name[32], shape[16];
            snprintf(name, sizeof name, "W%d_ctrl%d.bin", l, k);
            r = read_matrix(dir, name, layer_out[l], layer_in[l], a, set + net->lay.w[l], err);
            if (r != MM_OK) break;
            snprintf(name, sizeof name, "b%d_ctrl%d.bin", l, k);
            snprintf(shape, sizeof shape, "%d", layer_out[l]);
            r = read_floats(dir, name, (size_t)layer_out[l], shape, a, set + net->lay.b[l], err);
        }
    }
    if (r == MM_OK && (d.modes & MM_PFNN_MODE_BIT(MM_PFNN_MODE_CONSTANT))) {
        net->constant = (float *)mm_alloc_array(a, (size_t)d.constant_samples * net->lay.size, sizeof(float));
        if (!net->constant)
            r = mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory for the constant mode");
        else
            make_samples(net, net->constant, d.constant_samples);
    }
    if (r == MM_OK && (d.modes & MM_PFNN_MODE_BIT(MM_PFNN_MODE_LINEAR))) {
        net->linear = (float *)mm_alloc_array(a, (size_t)d.linear_samples * net->lay.size, sizeof(float));
        if (!net->linear)
            r = mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory for the linear mode");
        else
            make_samples(net, net->linear, d.linear_samples);
    }
    if (r != MM_OK) {
        mm_pfnn_network_free(net);
        return r;
    }
    if (err) memset(err, 0, sizeof *err);
    *out = net;
    return MM_OK;
}

void mm_pfnn_network_free(mm_pfnn_network *net)
{
    if (!net) return;
    mm_allocator a = net->allocator;
    const mm_allocator *pa = net->has_allocator ? &a : NULL;
    mm_free(pa, net->control);
    mm_free(pa, net->constant);
    mm_free(pa, net->linear);
    mm_free(pa, net);
}

static mm_pfnn_mode resolve(mm_pfnn_mode mode)
{
    return mode == MM_PFNN_MODE_DEFAULT ? MM_PFNN_MODE_CUBIC : mode;
}

bool mm_pfnn_network_has_mode(const mm_pfnn_network *net, mm_pfnn_mode mode)
{
    mode = resolve(mode);
    if (!net || mode < MM_PFNN_MODE_CONSTANT || mode > MM_PFNN_MODE_CUBIC) return false;
    return (net->modes & MM_PFNN_MODE_BIT(mode)) != 0;
}

size_t mm_pfnn_network_bytes(const mm_pfnn_network *net, mm_pfnn_mode mode)
{
    if (!net) return 0;
    size_t set = net->lay.size * sizeof(float);
    size_t norm = 2 * (MM_PFNN_INPUT_DIM + MM_PFNN_OUTPUT_DIM) * sizeof(float);
    size_t constant = net->constant ? (size_t)net->constant_samples * set : 0;
    size_t linear = net->linear ? (size_t)net->linear_samples * set : 0;
    switch (mode) {
    case MM_PFNN_MODE_DEFAULT:
        return sizeof *net + 4 * set + constant + linear;
    case MM_PFNN_MODE_CONSTANT:
        return constant ? constant + norm : 0;
    case MM_PFNN_MODE_LINEAR:
        return linear ? linear + norm : 0;
    case MM_PFNN_MODE_CUBIC:
        return (net->modes & MM_PFNN_MODE_BIT(MM_PFNN_MODE_CUBIC)) ? 4 * set + norm : 0;
    }
    return 0;
}

/* The K weight sets and coefficients a mode uses at phase. Returns K, 0 for an unprepared mode. */
static int mode_sets(const mm_pfnn_network *net, mm_pfnn_mode mode, double phase, const float *sets[4],
                     double coef[4])
{
    if (!mm_pfnn_network_has_mode(net, mode)) return 0;
    cycle_pos c = to_cycles(phase);
    int i;
    double t;
    switch (resolve(mode)) {
    case MM_PFNN_MODE_CONSTANT:
        sample_at(c, net->constant_samples, &i, &t);
        sets[0] = net->constant + (size_t)i * net->lay.size;
        coef[0] = 1.0;
        return 1;
    case MM_PFNN_MODE_LINEAR:
        sample_at(c, net->linear_samples, &i, &t);
        sets[0] = net->linear + (size_t)i * net->lay.size;
        sets[1] = net->linear + (size_t)((i + 1) % net->linear_samples) * net->lay.size;
        coef[0] = 1.0 - t;
        coef[1] = t;
        return 2;
    default:
        spline_coefficients(c, coef);
        for (int k = 0; k < 4; ++k) sets[k] = net->control + (size_t)k * net->lay.size;
        return 4;
    }
}

mm_result mm_pfnn_network_layer(const mm_pfnn_network *net, mm_pfnn_mode mode, float phase, int layer,
                                float *W, float *b)
{
    const float *sets[4];
    double coef[4];
    int K = mode_sets(net, mode, phase, sets, coef);
    if (!K || layer < 0 || layer > 2 || !W || !b) return MM_ERR_INVALID_ARGUMENT;
    int in = layer_in[layer], out = layer_out[layer];
    for (int o = 0; o < out; ++o) {
        for (int c = 0; c < in; ++c) {
            size_t idx = net->lay.w[layer] + (size_t)(o / PANEL) * in * PANEL + (size_t)c * PANEL + o % PANEL;
            double s = 0.0;
            for (int k = 0; k < K; ++k) s += coef[k] * (double)sets[k][idx];
            W[(size_t)o * in + c] = (float)s;
        }
        double s = 0.0;
        for (int k = 0; k < K; ++k) s += coef[k] * (double)sets[k][net->lay.b[layer] + o];
        b[o] = (float)s;
    }
    return MM_OK;
}

/* ---- forward pass ----------------------------------------------------------------------------- */

/* y[0 .. padded(out)) = sum_k coef[k] * (W_k x + b_k) for K weight sets given by their layer
 * offsets. Written for K = 1, 2, 4 and inlined with K constant. */
static inline void layer_product(int K, const float *const *sets, size_t w_off, size_t b_off,
                                 const float *coef, int in, int out, const float *restrict x,
                                 float *restrict y)
{
    int panels = padded(out) / PANEL;
    for (int p = 0; p < panels; ++p) {
        float acc[4][PANEL];
        for (int k = 0; k < K; ++k)
            for (int l = 0; l < PANEL; ++l) acc[k][l] = 0.0f;
        const float *w[4];
        for (int k = 0; k < K; ++k) w[k] = sets[k] + w_off + (size_t)p * in * PANEL;
        for (int c = 0; c < in; ++c) {
            float xc = x[c];
            for (int k = 0; k < K; ++k) {
                const float *restrict wk = w[k] + (size_t)c * PANEL;
                for (int l = 0; l < PANEL; ++l) acc[k][l] += wk[l] * xc;
            }
        }
        for (int l = 0; l < PANEL; ++l) {
            float s = 0.0f;
            for (int k = 0; k < K; ++k) s += coef[k] * (acc[k][l] + sets[k][b_off + (size_t)p * PANEL + l]);
            y[p * PANEL + l] = s;
        }
    }
}

static void layer_any(int K, const float *const *sets, size_t w_off, size_t b_off, const float *coef, int in,
                      int out, const float *x, float *y)
{
    if (K == 1)
        layer_product(1, sets, w_off, b_off, coef, in, out, x, y);
    else if (K == 2)
        layer_product(2, sets, w_off, b_off, coef, in, out, x, y);
    else
        layer_product(4, sets, w_off, b_off, coef, in, out, x, y);
}

static void elu(float *v, int n)
{
    for (int i = 0; i < n; ++i) v[i] = fmaxf(v[i], 0.0f) + expf(fminf(v[i], 0.0f)) - 1.0f;
}

mm_result mm_pfnn_network_eval(const mm_pfnn_network *net, mm_pfnn_mode mode, float phase, const float *x,
                               float *y)
{
    const float *sets[4];
    double coef_d[4];
    int K = mode_sets(net, mode, phase, sets, coef_d);
    if (!K || !x || !y) return MM_ERR_INVALID_ARGUMENT;
    float coef[4];
    for (int k = 0; k < K; ++k) coef[k] = (float)coef_d[k];
    float xn[MM_PFNN_INPUT_DIM], h0[MM_PFNN_HIDDEN_DIM], h1[MM_PFNN_HIDDEN_DIM];
    float yn[(MM_PFNN_OUTPUT_DIM + PANEL - 1) / PANEL * PANEL];
    for (int i = 0; i < MM_PFNN_INPUT_DIM; ++i) xn[i] = (x[i] - net->xmean[i]) / net->xstd[i];
    const set_layout *L = &net->lay;
    layer_any(K, sets, L->w[0], L->b[0], coef, MM_PFNN_INPUT_DIM, MM_PFNN_HIDDEN_DIM, xn, h0);
    elu(h0, MM_PFNN_HIDDEN_DIM);
    layer_any(K, sets, L->w[1], L->b[1], coef, MM_PFNN_HIDDEN_DIM, MM_PFNN_HIDDEN_DIM, h0, h1);
    elu(h1, MM_PFNN_HIDDEN_DIM);
    layer_any(K, sets, L->w[2], L->b[2], coef, MM_PFNN_HIDDEN_DIM, MM_PFNN_OUTPUT_DIM, h1, yn);
    for (int i = 0; i < MM_PFNN_OUTPUT_DIM; ++i) y[i] = yn[i] * net->ystd[i] + net->ymean[i];
    return MM_OK;
}
