/* mm similarity: the audit of two clips (CSV, heat-map PNG, poorly matched frames), and building
 * and inspecting the fusion / link tables (docs/similarity.md). */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <mm/database.h>
#include <mm/similarity.h>

#include "cli.h"
#include "commands.h"

/* Options shared by the audit and build. Returns 1 when argv[*i] was one of them, 0 when not,
 * -1 (after printing) when its value is bad. */
typedef struct sim_options {
    mm_sim_desc desc;
    const char *output;
} sim_options;

static int shared_option(const char *cmd, int argc, char **argv, int *i, sim_options *o)
{
    const char *a = argv[*i];
    int has_value = *i + 1 < argc;
    long v;
    if (strcmp(a, "-o") == 0 || strcmp(a, "--output") == 0) {
        if (!has_value) return cli_usage_error(cmd, "-o needs a path"), -1;
        o->output = argv[++*i];
    } else if (strcmp(a, "--window") == 0) {
        if (!has_value || !cli_parse_int(argv[*i + 1], 1, MM_SIM_MAX_WINDOW, &v))
            return cli_usage_error(cmd, "--window needs a frame count from 1 to %d", MM_SIM_MAX_WINDOW), -1;
        o->desc.window = (int)v;
        ++*i;
    } else if (strcmp(a, "--threads") == 0) {
        if (!has_value || !cli_parse_int(argv[*i + 1], 1, MM_SIM_MAX_THREADS, &v))
            return cli_usage_error(cmd, "--threads needs a count from 1 to %d", MM_SIM_MAX_THREADS), -1;
        o->desc.threads = (int)v;
        ++*i;
    } else if (strcmp(a, "--measure") == 0) {
        const char *m = has_value ? argv[*i + 1] : "";
        if (strcmp(m, "cos") == 0)
            o->desc.measure = MM_SIM_COSINE;
        else if (strcmp(m, "euclid") == 0)
            o->desc.measure = MM_SIM_EUCLIDEAN;
        else
            return cli_usage_error(cmd, "--measure is cos or euclid"), -1;
        ++*i;
    } else if (strcmp(a, "--channels") == 0) {
        if (!has_value) return cli_usage_error(cmd, "--channels needs a list such as pos,rot,vel"), -1;
        unsigned ch = 0;
        char buf[64];
        snprintf(buf, sizeof buf, "%s", argv[++*i]);
        for (char *save = NULL, *t = strtok_r(buf, ",", &save); t; t = strtok_r(NULL, ",", &save)) {
            if (strcmp(t, "pos") == 0)
                ch |= MM_SIM_POSITION;
            else if (strcmp(t, "rot") == 0)
                ch |= MM_SIM_ROTATION;
            else if (strcmp(t, "vel") == 0)
                ch |= MM_SIM_VELOCITY;
            else
                return cli_usage_error(cmd, "--channels: unknown '%s' (pos, rot, vel)", t), -1;
        }
        if (!ch) return cli_usage_error(cmd, "--channels needs a list such as pos,rot,vel"), -1;
        o->desc.channels = ch;
    } else {
        return 0;
    }
    return 1;
}

static int load_db(const char *path, mm_database *db)
{
    mm_error err;
    memset(&err, 0, sizeof err);
    if (mm_database_load(path, NULL, db, &err) != MM_OK) return cli_report(&err);
    return 0;
}

/* PNG writer: 8-bit RGB, stored (uncompressed) deflate blocks, so no library is needed. Returns 1,
 * or 0 after printing the error. */
static uint32_t crc_table[256];
static void crc_init(void)
{
    for (uint32_t n = 0; n < 256; ++n) {
        uint32_t c = n;
        for (int k = 0; k < 8; ++k) c = c & 1 ? 0xEDB88320u ^ (c >> 1) : c >> 1;
        crc_table[n] = c;
    }
}
static uint32_t crc_update(uint32_t c, const unsigned char *p, size_t n)
{
    for (size_t i = 0; i < n; ++i) c = crc_table[(c ^ p[i]) & 0xff] ^ (c >> 8);
    return c;
}
static void put32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)(v >> 24);
    p[1] = (unsigned char)(v >> 16);
    p[2] = (unsigned char)(v >> 8);
    p[3] = (unsigned char)v;
}
static int write_chunk(FILE *f, const char *type, const unsigned char *data, size_t n)
{
    unsigned char head[8];
    put32(head, (uint32_t)n);
    memcpy(head + 4, type, 4);
    uint32_t crc = crc_update(0xffffffffu, head + 4, 4);
    crc = crc_update(crc, data, n) ^ 0xffffffffu;
    unsigned char tail[4];
    put32(tail, crc);
    return fwrite(head, 1, 8, f) == 8 && (n == 0 || fwrite(data, 1, n, f) == n) && fwrite(tail, 1, 4, f) == 4;
}

/* Writes the PNG to a temporary file beside path (named in tmp) and closes it; 1 on success. The
 * caller renames it (cli_publish) or removes it. */
static int write_png(const char *path, char *tmp, size_t tmp_size, const unsigned char *rgb, int w, int h)
{
    size_t raw_size = (size_t)h * (size_t)(3 * w + 1);
    size_t blocks = (raw_size + 65534) / 65535;
    unsigned char *z = malloc(2 + raw_size + 5 * blocks + 4);
    if (!z) {
        fprintf(stderr, "mm: %s: out of memory\n", path);
        return 0;
    }
    size_t at = 0;
    z[at++] = 0x78; /* deflate, 32K window */
    z[at++] = 0x01; /* no compression preset; (0x7801 % 31 == 0) */
    uint32_t a = 1, b = 0;
    size_t done = 0;
    unsigned char *raw = malloc(raw_size);
    if (!raw) {
        fprintf(stderr, "mm: %s: out of memory\n", path);
        free(z);
        return 0;
    }
    for (int y = 0; y < h; ++y) {
        unsigned char *row = raw + (size_t)y * (size_t)(3 * w + 1);
        row[0] = 0; /* filter: none */
        memcpy(row + 1, rgb + (size_t)y * 3 * (size_t)w, (size_t)3 * (size_t)w);
    }
    while (done < raw_size) {
        size_t n = raw_size - done > 65535 ? 65535 : raw_size - done;
        z[at++] = done + n == raw_size ? 1 : 0; /* BFINAL, BTYPE 00 (stored) */
        z[at++] = (unsigned char)(n & 0xff);
        z[at++] = (unsigned char)(n >> 8);
        z[at++] = (unsigned char)(~n & 0xff);
        z[at++] = (unsigned char)((~n >> 8) & 0xff);
        memcpy(z + at, raw + done, n);
        for (size_t i = 0; i < n; ++i) {
            a = (a + raw[done + i]) % 65521u;
            b = (b + a) % 65521u;
        }
        at += n;
        done += n;
    }
    put32(z + at, (b << 16) | a);
    at += 4;
    free(raw);
    crc_init();
    FILE *f = cli_create(path, tmp, tmp_size);
    int ok = f != NULL;
    if (ok) {
        static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
        unsigned char ihdr[13];
        put32(ihdr, (uint32_t)w);
        put32(ihdr + 4, (uint32_t)h);
        ihdr[8] = 8;  /* bit depth */
        ihdr[9] = 2;  /* RGB */
        ihdr[10] = 0; /* deflate */
        ihdr[11] = 0; /* adaptive filtering */
        ihdr[12] = 0; /* no interlace */
        ok = fwrite(sig, 1, 8, f) == 8 && write_chunk(f, "IHDR", ihdr, 13) && write_chunk(f, "IDAT", z, at) &&
             write_chunk(f, "IEND", NULL, 0);
        if (!ok) fprintf(stderr, "mm: %s: cannot write: %s\n", path, strerror(errno));
        ok = ok ? cli_finish(f, tmp, path) == 0 : (cli_commit(f, tmp, path, 1), 0);
    }
    free(z);
    return ok;
}

/* Colour map from poor (0: dark blue) to good (1: yellow) through magenta and orange. */
static void colour(double t, unsigned char *rgb)
{
    static const double stops[5][3] = {
        {0, 0, 40}, {90, 20, 140}, {200, 40, 110}, {250, 140, 30}, {255, 250, 150}};
    if (!(t > 0)) t = 0;
    if (t > 1) t = 1;
    double x = t * 4;
    int i = (int)x;
    if (i > 3) i = 3;
    double f = x - i;
    for (int c = 0; c < 3; ++c)
        rgb[c] = (unsigned char)lround(stops[i][c] + f * (stops[i + 1][c] - stops[i][c]));
}

static int make_dir(const char *dir)
{
    if (mkdir(dir, 0777) == 0 || errno == EEXIST) return 0;
    fprintf(stderr, "mm: %s: cannot create the folder: %s\n", dir, strerror(errno));
    return 1;
}

#define MAX_IMAGE 2048 /* pixels per side of the heat map; larger matrices are sampled */

static int cmd_audit(int argc, char **argv)
{
    const char *cmd = "similarity", *db_path = NULL, *from = NULL, *to = NULL;
    sim_options o;
    memset(&o, 0, sizeof o);
    o.desc.threads = 2;
    double poor = NAN;
    for (int i = 1; i < argc; ++i) {
        int r = shared_option(cmd, argc, argv, &i, &o);
        if (r < 0) return 2;
        if (r) continue;
        if (strcmp(argv[i], "--from") == 0 || strcmp(argv[i], "--to") == 0) {
            if (i + 1 >= argc) return cli_usage_error(cmd, "%s needs a clip name", argv[i]);
            *(strcmp(argv[i], "--from") == 0 ? &from : &to) = argv[i + 1];
            ++i;
        } else if (strcmp(argv[i], "--poor") == 0) {
            if (i + 1 >= argc || !cli_parse_double(argv[i + 1], &poor))
                return cli_usage_error(cmd, "--poor needs a score");
            ++i;
        } else if (argv[i][0] == '-' && argv[i][1]) {
            return cli_usage_error(cmd, "unknown option '%s'", argv[i]);
        } else if (!db_path) {
            db_path = argv[i];
        } else {
            return cli_usage_error(cmd, "unexpected argument '%s'", argv[i]);
        }
    }
    if (!db_path || !from || !to || !o.output)
        return cli_usage_error(cmd, "usage: mm similarity DB.mmdb --from CLIP --to CLIP [--window N] "
                                    "[--measure cos|euclid] [--channels pos,rot,vel] [--poor S] -o DIR");
    if (isnan(poor)) poor = o.desc.measure == MM_SIM_COSINE ? 0.95 : 0.10;
    /* the three outputs are written to temporary files and renamed only when all were written */
    enum { CSV, POOR, PNG, OUTPUTS };
    char paths[OUTPUTS][4096], tmps[OUTPUTS][4096 + 32];
    int finished = 0;
    if (strlen(o.output) + sizeof "/similarity.csv" > sizeof paths[0]) {
        fprintf(stderr, "mm: %s: the path is too long\n", o.output);
        return 1;
    }
    mm_database db;
    if (load_db(db_path, &db)) return 1;
    int ca = mm_database_find_clip(&db, from), cb = mm_database_find_clip(&db, to);
    if (ca < 0 || cb < 0) {
        fprintf(stderr, "mm: %s: no clip named '%s' (mm db info lists them)\n", db_path, ca < 0 ? from : to);
        mm_database_free(&db);
        return 1;
    }
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_sim_poses p;
    if (mm_sim_poses_init(&p, &db, &o.desc, &err) != MM_OK) {
        mm_database_free(&db);
        return cli_report(&err);
    }
    int na = db.clips[ca].frame_count, nb = db.clips[cb].frame_count;
    float *m = malloc(sizeof(float) * (size_t)na * (size_t)nb);
    int status = 1;
    if (!m || mm_sim_matrix(&p, ca, cb, o.desc.threads, m, &err) != MM_OK) {
        if (!m) mm_error_set(&err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory for %d x %d scores", na, nb);
        cli_report(&err);
        goto done;
    }
    if (make_dir(o.output)) goto done;
    /* CSV: one row per frame of --from, one column per frame of --to */
    snprintf(paths[CSV], sizeof paths[CSV], "%s/similarity.csv", o.output);
    snprintf(paths[POOR], sizeof paths[POOR], "%s/poor.csv", o.output);
    snprintf(paths[PNG], sizeof paths[PNG], "%s/similarity.png", o.output);
    FILE *f = cli_create(paths[CSV], tmps[CSV], sizeof tmps[CSV]);
    if (!f) goto done;
    fprintf(f, "frame");
    for (int j = 0; j < nb; ++j) fprintf(f, ",%d", j);
    fputc('\n', f);
    for (int i = 0; i < na; ++i) {
        fprintf(f, "%d", i);
        for (int j = 0; j < nb; ++j) fprintf(f, ",%.6f", (double)m[(size_t)i * (size_t)nb + (size_t)j]);
        fputc('\n', f);
    }
    if (cli_finish(f, tmps[CSV], paths[CSV])) goto done;
    finished = 1;
    /* best match per row; poor rows */
    f = cli_create(paths[POOR], tmps[POOR], sizeof tmps[POOR]);
    if (!f) goto done;
    fprintf(f, "frame,best_frame,score\n");
    int poor_count = 0;
    float lo = m[0], hi = m[0];
    double mean_best = 0;
    for (int i = 0; i < na; ++i) {
        const float *row = m + (size_t)i * (size_t)nb;
        int b = 0;
        for (int j = 0; j < nb; ++j) {
            if (mm_sim_better(p.measure, row[j], row[b])) b = j;
            if (row[j] < lo) lo = row[j];
            if (row[j] > hi) hi = row[j];
        }
        mean_best += row[b];
        if (mm_sim_better(p.measure, (float)poor, row[b])) {
            fprintf(f, "%d,%d,%.6f\n", i, b, (double)row[b]);
            ++poor_count;
        }
    }
    if (cli_finish(f, tmps[POOR], paths[POOR])) goto done;
    finished = 2;
    /* heat map: rows = --from frames (top to bottom), columns = --to frames; bright = similar */
    int w = nb < MAX_IMAGE ? nb : MAX_IMAGE, h = na < MAX_IMAGE ? na : MAX_IMAGE;
    unsigned char *rgb = malloc((size_t)w * (size_t)h * 3);
    if (!rgb) {
        fprintf(stderr, "mm: out of memory for a %d x %d image\n", w, h);
        goto done;
    }
    double range = hi > lo ? (double)hi - (double)lo : 1.0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            int i = (int)((long)y * na / h), j = (int)((long)x * nb / w);
            double v = ((double)m[(size_t)i * (size_t)nb + (size_t)j] - lo) / range;
            colour(p.measure == MM_SIM_COSINE ? v : 1.0 - v, rgb + ((size_t)y * (size_t)w + (size_t)x) * 3);
        }
    int ok = write_png(paths[PNG], tmps[PNG], sizeof tmps[PNG], rgb, w, h);
    free(rgb);
    if (!ok) goto done;
    finished = 3;
    for (int k = 0; k < OUTPUTS; ++k)
        if (cli_publish(tmps[k], paths[k]) != 0) {
            while (k-- > 0) remove(paths[k]);
            for (k = 0; k < OUTPUTS; ++k) remove(tmps[k]); /* the ones not yet renamed */
            finished = 0;
            goto done;
        }
    finished = 0;
    printf("%s (%d frames) -> %s (%d frames): %s, window %d\n", from, na, to, nb,
           mm_sim_measure_name(p.measure), p.window);
    printf("scores from %.6f to %.6f; mean best match %.6f\n", (double)lo, (double)hi, mean_best / na);
    printf("%d of %d frames have a poor best match (%s %g): %s/poor.csv\n", poor_count, na,
           p.measure == MM_SIM_COSINE ? "below" : "above", poor, o.output);
    printf("wrote %s/similarity.csv, %s/similarity.png (%d x %d)\n", o.output, o.output, w, h);
    status = 0;
done:
    for (int k = 0; k < finished; ++k) remove(tmps[k]);
    free(m);
    mm_sim_poses_free(&p);
    mm_database_free(&db);
    return status;
}

static void print_tables(const mm_sim_tables *t)
{
    printf("measure:     %s\n", mm_sim_measure_name(t->measure));
    printf("window:      %d frames\n", t->window);
    printf("channels:   %s%s%s\n", t->channels & MM_SIM_POSITION ? " pos" : "",
           t->channels & MM_SIM_ROTATION ? " rot" : "", t->channels & MM_SIM_VELOCITY ? " vel" : "");
    printf("database:    %d frames, %d clips, %d joints, %llu bytes, checksum %016llx\n", t->frame_count,
           t->clip_count, t->joint_count, (unsigned long long)t->db_size, (unsigned long long)t->db_checksum);
    printf("fusion:      %d one-shot frames x %d loop clips\n", t->fusion_rows, t->loop_count);
    printf("link:        %d loop frames x %d one-shot clips\n", t->link_rows, t->shot_count);
    printf("memory:      %zu bytes (%.2f MB)\n", t->size, (double)t->size / 1048576.0);
}

static int cmd_build(int argc, char **argv)
{
    const char *cmd = "similarity build", *db_path = NULL;
    sim_options o;
    memset(&o, 0, sizeof o);
    o.desc.threads = 2;
    for (int i = 1; i < argc; ++i) {
        int r = shared_option(cmd, argc, argv, &i, &o);
        if (r < 0) return 2;
        if (r) continue;
        if (argv[i][0] == '-' && argv[i][1]) return cli_usage_error(cmd, "unknown option '%s'", argv[i]);
        if (db_path) return cli_usage_error(cmd, "unexpected argument '%s'", argv[i]);
        db_path = argv[i];
    }
    if (!db_path)
        return cli_usage_error(cmd, "usage: mm similarity build DB.mmdb [-o TABLES] [--window N] "
                                    "[--measure cos|euclid] [--channels pos,rot,vel] [--threads N]");
    char out[4096];
    if (snprintf(out, sizeof out, "%s%s", o.output ? o.output : db_path, o.output ? "" : ".sim") >=
        (int)sizeof out) {
        fprintf(stderr, "mm: %s: the path is too long\n", o.output ? o.output : db_path);
        return 1;
    }
    mm_database db;
    if (load_db(db_path, &db)) return 1;
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_sim_tables t;
    double t0 = cli_now();
    mm_result r = mm_sim_tables_build(&db, &o.desc, &t, &err);
    double t1 = cli_now();
    if (r == MM_OK) r = mm_sim_tables_save(&t, out, &err);
    mm_database_free(&db);
    if (r != MM_OK) {
        mm_sim_tables_free(&t);
        return cli_report(&err);
    }
    printf("wrote %s in %.2f s (%d thread%s)\n", out, t1 - t0, o.desc.threads, o.desc.threads > 1 ? "s" : "");
    print_tables(&t);
    mm_sim_tables_free(&t);
    return 0;
}

static int cmd_info(int argc, char **argv)
{
    const char *cmd = "similarity info", *path = NULL, *db_path = NULL;
    for (int i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--db") == 0) {
            if (i + 1 >= argc) return cli_usage_error(cmd, "--db needs a database file");
            db_path = argv[++i];
        } else if (argv[i][0] == '-' && argv[i][1]) {
            return cli_usage_error(cmd, "unknown option '%s'", argv[i]);
        } else if (path) {
            return cli_usage_error(cmd, "unexpected argument '%s'", argv[i]);
        } else {
            path = argv[i];
        }
    }
    if (!path) return cli_usage_error(cmd, "usage: mm similarity info TABLES [--db DB.mmdb]");
    mm_database db;
    memset(&db, 0, sizeof db);
    if (db_path && load_db(db_path, &db)) return 1;
    mm_error err;
    memset(&err, 0, sizeof err);
    mm_sim_tables t;
    mm_result r = mm_sim_tables_load(path, db_path ? &db : NULL, NULL, &t, &err);
    if (r != MM_OK) {
        if (db_path) mm_database_free(&db);
        return cli_report(&err);
    }
    print_tables(&t);
    if (db_path) {
        printf("belongs to:  %s\n", db_path);
        mm_database_free(&db);
    }
    mm_sim_tables_free(&t);
    return 0;
}

int mm_cmd_similarity(int argc, char **argv)
{
    if (argc >= 2 && strcmp(argv[1], "build") == 0) return cmd_build(argc - 1, argv + 1);
    if (argc >= 2 && strcmp(argv[1], "info") == 0) return cmd_info(argc - 1, argv + 1);
    return cmd_audit(argc, argv);
}
