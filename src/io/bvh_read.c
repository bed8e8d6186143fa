/* BVH reader: a hand-written scanner over a memory buffer.
 *
 * The hierarchy is read token by token; the motion section line by line with a fast number
 * scanner, checking that every line holds exactly one value per channel. Nothing is allocated
 * from a declared size before the input is known to be large enough to hold it, so a file that
 * declares 2^31 frames fails cleanly instead of asking for gigabytes. Nesting is handled with an
 * explicit stack, so deep input cannot overflow the C stack.
 */
#include <mm/bvh.h>

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "io/file.h"
#include "io/numscan.h"

typedef struct bvh_joint_tmp {
    char name[MM_NAME_MAX];
    int parent;
    double offset[3];
    mm_bvh_joint_channels channels;
    int has_channels;
    int has_end_site;
    double end_site[3];
} bvh_joint_tmp;

typedef struct parser {
    const char *p, *end;
    const char *line_start;
    int line;
    mm_error *err;
    const mm_allocator *allocator;
    bvh_joint_tmp *joints;
    int joint_count, joint_capacity;
    int channel_count;
    int root_line, root_column;
} parser;

typedef struct token {
    const char *s;
    size_t n;
    int line, column;
} token;

static int column_of(const parser *ps, const char *at) { return (int)(at - ps->line_start) + 1; }

static int is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

static void skip_space_and_lines(parser *ps)
{
    while (ps->p < ps->end) {
        char c = *ps->p;
        if (c == '\n') {
            ++ps->line;
            ps->line_start = ++ps->p;
        } else if (is_space(c)) {
            ++ps->p;
        } else {
            break;
        }
    }
}

/* Next whitespace-separated token; '{' and '}' are tokens of their own. n = 0 at end of input. */
static token next_token(parser *ps)
{
    skip_space_and_lines(ps);
    token t;
    t.s = ps->p;
    t.line = ps->line;
    t.column = column_of(ps, ps->p);
    if (ps->p < ps->end && (*ps->p == '{' || *ps->p == '}')) {
        ++ps->p;
    } else {
        while (ps->p < ps->end && !is_space(*ps->p) && *ps->p != '\n' && *ps->p != '{' && *ps->p != '}')
            ++ps->p;
    }
    t.n = (size_t)(ps->p - t.s);
    return t;
}

static int token_is(token t, const char *word)
{
    size_t n = strlen(word);
    if (t.n != n) return 0;
    for (size_t i = 0; i < n; ++i) {
        char a = t.s[i], b = word[i];
        if (a >= 'A' && a <= 'Z') a = (char)(a - 'A' + 'a');
        if (b >= 'A' && b <= 'Z') b = (char)(b - 'A' + 'a');
        if (a != b) return 0;
    }
    return 1;
}

/* Copies up to 40 characters of a token into buf for messages, with printable characters only. */
static const char *token_text(token t, char *buf, size_t size)
{
    size_t n = t.n < size - 4 ? t.n : size - 4;
    if (n > 40) n = 40;
    for (size_t i = 0; i < n; ++i) {
        unsigned char c = (unsigned char)t.s[i];
        buf[i] = (c >= 32 && c < 127) ? (char)c : '?';
    }
    if (n < t.n) {
        memcpy(buf + n, "...", 3);
        n += 3;
    }
    buf[n] = 0;
    return buf;
}

static mm_result unexpected(parser *ps, token t, const char *expected)
{
    char buf[64];
    if (t.n == 0)
        return mm_error_set(ps->err, MM_ERR_UNEXPECTED_EOF, t.line, t.column,
                            "input ends where %s was expected", expected);
    return mm_error_set(ps->err, MM_ERR_SYNTAX, t.line, t.column, "expected %s, found '%s'", expected,
                        token_text(t, buf, sizeof buf));
}

static mm_result expect_word(parser *ps, const char *word)
{
    token t = next_token(ps);
    if (token_is(t, word)) return MM_OK;
    char expected[64];
    snprintf(expected, sizeof expected, "'%s'", word);
    return unexpected(ps, t, expected);
}

static mm_result read_number(parser *ps, const char *what, double *out)
{
    token t = next_token(ps);
    if (t.n == 0) return unexpected(ps, t, what);
    const char *stop;
    mm__scan_status st = mm__scan_double(t.s, t.s + t.n, out, &stop);
    char buf[64];
    if (st == MM__SCAN_OK && stop == t.s + t.n) return MM_OK;
    if (st == MM__SCAN_NOT_FINITE)
        return mm_error_set(ps->err, MM_ERR_BAD_NUMBER, t.line, t.column, "%s is '%s', not a finite number",
                            what, token_text(t, buf, sizeof buf));
    if (st == MM__SCAN_TOO_LONG)
        return mm_error_set(ps->err, MM_ERR_BAD_NUMBER, t.line, t.column,
                            "%s '%s' is longer than %d characters", what, token_text(t, buf, sizeof buf),
                            MM__SCAN_MAX_CHARS);
    return mm_error_set(ps->err, MM_ERR_BAD_NUMBER, t.line, t.column, "%s: '%s' is not a number", what,
                        token_text(t, buf, sizeof buf));
}

static mm_result read_vec3(parser *ps, const char *what, double out[3])
{
    mm_result r;
    for (int i = 0; i < 3; ++i)
        if ((r = read_number(ps, what, &out[i])) != MM_OK) return r;
    return MM_OK;
}

static int channel_from_token(token t)
{
    static const char *names[6] = {"Xposition", "Yposition", "Zposition",
                                   "Xrotation", "Yrotation", "Zrotation"};
    for (int i = 0; i < 6; ++i)
        if (token_is(t, names[i])) return i;
    return -1;
}

/* A word that can follow a channel list: a sign that the list is shorter than declared. */
static int is_hierarchy_keyword(token t)
{
    return token_is(t, "JOINT") || token_is(t, "End") || token_is(t, "OFFSET") || token_is(t, "CHANNELS") ||
           token_is(t, "}") || token_is(t, "{") || token_is(t, "MOTION") || token_is(t, "ROOT");
}

static int starts_number(token t)
{
    const char *s = t.s;
    if (t.n > 1 && (*s == '+' || *s == '-')) ++s;
    return (*s >= '0' && *s <= '9') || *s == '.';
}

/* The joint name is the rest of the line (names may contain spaces), without a trailing '{'. */
static mm_result read_joint_name(parser *ps, char name[MM_NAME_MAX], int *out_column)
{
    while (ps->p < ps->end && is_space(*ps->p)) ++ps->p;
    const char *s = ps->p;
    int column = column_of(ps, s);
    *out_column = column;
    while (ps->p < ps->end && *ps->p != '\n' && *ps->p != '{') ++ps->p;
    const char *e = ps->p;
    while (e > s && is_space(e[-1])) --e;
    size_t n = (size_t)(e - s);
    if (n == 0) return mm_error_set(ps->err, MM_ERR_SYNTAX, ps->line, column, "joint has no name");
    if (n >= MM_NAME_MAX)
        return mm_error_set(ps->err, MM_ERR_LIMIT, ps->line, column,
                            "joint name is %zu characters (at most %d)", n, MM_NAME_MAX - 1);
    for (size_t i = 0; i < n; ++i)
        if ((unsigned char)s[i] < 32 || s[i] == 127)
            return mm_error_set(ps->err, MM_ERR_SYNTAX, ps->line, column + (int)i,
                                "joint name contains a control character");
    memcpy(name, s, n);
    name[n] = 0;
    return MM_OK;
}

static mm_result add_joint(parser *ps, int parent, int line, int column, int *out_index)
{
    if (ps->joint_count >= MM_MAX_JOINTS)
        return mm_error_set(ps->err, MM_ERR_LIMIT, line, column, "more than %d joints", MM_MAX_JOINTS);
    if (ps->joint_count == ps->joint_capacity) {
        int cap = ps->joint_capacity ? ps->joint_capacity * 2 : 32;
        if (cap > MM_MAX_JOINTS) cap = MM_MAX_JOINTS;
        bvh_joint_tmp *j = (bvh_joint_tmp *)mm_alloc_array(ps->allocator, (size_t)cap, sizeof *j);
        if (!j) return mm_error_set(ps->err, MM_ERR_OUT_OF_MEMORY, line, column, "out of memory");
        if (ps->joint_count) memcpy(j, ps->joints, (size_t)ps->joint_count * sizeof *j);
        mm_free(ps->allocator, ps->joints);
        ps->joints = j;
        ps->joint_capacity = cap;
    }
    int i = ps->joint_count++;
    memset(&ps->joints[i], 0, sizeof ps->joints[i]);
    ps->joints[i].parent = parent;
    int name_column = 0;
    mm_result r = read_joint_name(ps, ps->joints[i].name, &name_column);
    if (r != MM_OK) return r;
    for (int k = 0; k < i; ++k)
        if (strcmp(ps->joints[k].name, ps->joints[i].name) == 0)
            return mm_error_set(ps->err, MM_ERR_DUPLICATE_NAME, line, name_column,
                                "joint name '%s' is already used by joint %d", ps->joints[i].name, k);
    *out_index = i;
    return MM_OK;
}

static mm_result read_channels(parser *ps, bvh_joint_tmp *j, token keyword)
{
    char buf[64];
    if (j->has_channels)
        return mm_error_set(ps->err, MM_ERR_CHANNELS, keyword.line, keyword.column,
                            "joint '%s' declares CHANNELS twice", j->name);
    token t = next_token(ps);
    int64_t count = 0;
    const char *stop;
    if (t.n == 0) return unexpected(ps, t, "a channel count");
    mm__scan_status st = mm__scan_int64(t.s, t.s + t.n, &count, &stop);
    if (st == MM__SCAN_NOT_FINITE)
        return mm_error_set(ps->err, MM_ERR_CHANNELS, t.line, t.column, "channel count '%s' is out of range",
                            token_text(t, buf, sizeof buf));
    if (st != MM__SCAN_OK || stop != t.s + t.n)
        return mm_error_set(ps->err, MM_ERR_CHANNELS, t.line, t.column,
                            "channel count '%s' is not an integer", token_text(t, buf, sizeof buf));
    if (count != 0 && count != 3 && count != 6)
        return mm_error_set(ps->err, MM_ERR_CHANNELS, t.line, t.column,
                            "joint '%s' declares %lld channels (0, 3 or 6 are allowed)", j->name,
                            (long long)count);
    j->has_channels = 1;
    j->channels.first = ps->channel_count;
    j->channels.count = (int)count;
    int seen = 0, rotations = 0, positions = 0;
    for (int i = 0; i < (int)count; ++i) {
        t = next_token(ps);
        int c = channel_from_token(t);
        if (c < 0) {
            if (t.n == 0) return unexpected(ps, t, "a channel name");
            if (is_hierarchy_keyword(t))
                return mm_error_set(ps->err, MM_ERR_CHANNELS, t.line, t.column,
                                    "joint '%s' declares %d channels but lists %d (found '%s')", j->name,
                                    (int)count, i, token_text(t, buf, sizeof buf));
            return mm_error_set(ps->err, MM_ERR_CHANNELS, t.line, t.column,
                                "joint '%s': '%s' is not a channel name (Xposition ... Zrotation)", j->name,
                                token_text(t, buf, sizeof buf));
        }
        if (seen & (1 << c))
            return mm_error_set(ps->err, MM_ERR_CHANNELS, t.line, t.column,
                                "joint '%s' lists channel %s twice", j->name,
                                mm_bvh_channel_name((mm_bvh_channel)c));
        seen |= 1 << c;
        j->channels.type[i] = (unsigned char)c;
        if (c >= MM_BVH_XROTATION)
            ++rotations;
        else
            ++positions;
    }
    if ((rotations != 0 && rotations != 3) || (positions != 0 && positions != 3))
        return mm_error_set(ps->err, MM_ERR_CHANNELS, keyword.line, keyword.column,
                            "joint '%s' has %d rotation and %d position channels (each must be 0 or 3)",
                            j->name, rotations, positions);
    ps->channel_count += (int)count;
    return MM_OK;
}

/* HIERARCHY ... up to and including the root's closing brace. */
static mm_result read_hierarchy(parser *ps)
{
    mm_result r;
    char buf[64];
    if ((r = expect_word(ps, "HIERARCHY")) != MM_OK) return r;
    token t = next_token(ps);
    if (!token_is(t, "ROOT")) return unexpected(ps, t, "'ROOT'");
    ps->root_line = t.line;
    ps->root_column = t.column;
    int stack[MM_MAX_JOINTS + 1]; /* open joints; -2 marks an open End Site */
    int depth = 0, root = 0;
    if ((r = add_joint(ps, -1, t.line, t.column, &root)) != MM_OK) return r;
    if ((r = expect_word(ps, "{")) != MM_OK) return r;
    stack[depth++] = root;
    int have_offset[MM_MAX_JOINTS + 1] = {0}; /* per open level: OFFSET seen */
    while (depth > 0) {
        t = next_token(ps);
        int top = stack[depth - 1];
        if (t.n == 0) return unexpected(ps, t, "'}'");
        if (token_is(t, "}")) {
            if (!have_offset[depth - 1])
                return mm_error_set(ps->err, MM_ERR_SYNTAX, t.line, t.column, "%s '%s' has no OFFSET",
                                    top == -2 ? "End Site of" : "joint",
                                    top == -2 ? ps->joints[stack[depth - 2]].name : ps->joints[top].name);
            --depth;
            continue;
        }
        if (token_is(t, "OFFSET")) {
            if (have_offset[depth - 1])
                return mm_error_set(ps->err, MM_ERR_SYNTAX, t.line, t.column, "a second OFFSET in one block");
            double *dst = top == -2 ? ps->joints[stack[depth - 2]].end_site : ps->joints[top].offset;
            if ((r = read_vec3(ps, "OFFSET value", dst)) != MM_OK) return r;
            have_offset[depth - 1] = 1;
            continue;
        }
        if (top == -2)
            return mm_error_set(ps->err, MM_ERR_SYNTAX, t.line, t.column,
                                "an End Site may hold only an OFFSET, found '%s'",
                                token_text(t, buf, sizeof buf));
        if (token_is(t, "CHANNELS")) {
            if ((r = read_channels(ps, &ps->joints[top], t)) != MM_OK) return r;
        } else if (token_is(t, "JOINT")) {
            int child = 0;
            if ((r = add_joint(ps, top, t.line, t.column, &child)) != MM_OK) return r;
            if ((r = expect_word(ps, "{")) != MM_OK) return r;
            have_offset[depth] = 0;
            stack[depth++] = child;
        } else if (token_is(t, "End")) {
            if ((r = expect_word(ps, "Site")) != MM_OK) return r;
            if (ps->joints[top].has_end_site)
                return mm_error_set(ps->err, MM_ERR_SYNTAX, t.line, t.column,
                                    "joint '%s' has a second End Site", ps->joints[top].name);
            ps->joints[top].has_end_site = 1;
            if ((r = expect_word(ps, "{")) != MM_OK) return r;
            have_offset[depth] = 0;
            stack[depth++] = -2;
        } else if (channel_from_token(t) >= 0) {
            return mm_error_set(ps->err, MM_ERR_CHANNELS, t.line, t.column,
                                "joint '%s' lists more channels than it declares", ps->joints[top].name);
        } else if (token_is(t, "ROOT")) {
            return mm_error_set(ps->err, MM_ERR_SYNTAX, t.line, t.column, "ROOT inside a joint");
        } else if (token_is(t, "MOTION")) {
            return mm_error_set(ps->err, MM_ERR_SYNTAX, t.line, t.column,
                                "MOTION inside joint '%s': a '}' is missing", ps->joints[top].name);
        } else if (starts_number(t)) {
            return mm_error_set(ps->err, MM_ERR_SYNTAX, t.line, t.column,
                                "unexpected number '%s' in joint '%s' (an OFFSET has 3 values)",
                                token_text(t, buf, sizeof buf), ps->joints[top].name);
        } else {
            return mm_error_set(ps->err, MM_ERR_UNKNOWN_KEYWORD, t.line, t.column,
                                "unknown keyword '%s' in joint '%s'", token_text(t, buf, sizeof buf),
                                ps->joints[top].name);
        }
    }
    return MM_OK;
}

/* Reads one frame's line of values into row; the line must hold exactly count values. */
static mm_result read_motion_line(parser *ps, double *row, int count, int frame)
{
    const char *p = ps->p, *end = ps->end;
    int n = 0;
    for (;;) {
        while (p < end && is_space(*p)) ++p;
        if (p >= end || *p == '\n') break;
        if (n == count) {
            ps->p = p;
            return mm_error_set(ps->err, MM_ERR_VALUE_COUNT, ps->line, column_of(ps, p),
                                "frame %d has more than the %d values the channels declare", frame, count);
        }
        const char *stop;
        mm__scan_status st = mm__scan_double(p, end, &row[n], &stop);
        if (st == MM__SCAN_OK && stop < end && !is_space(*stop) && *stop != '\n') st = MM__SCAN_NOT_A_NUMBER;
        if (st != MM__SCAN_OK) {
            token t;
            t.s = p;
            t.n = 0;
            while (p + t.n < end && !is_space(p[t.n]) && p[t.n] != '\n') ++t.n;
            char buf[64];
            return mm_error_set(ps->err, MM_ERR_BAD_NUMBER, ps->line, column_of(ps, p),
                                st == MM__SCAN_NOT_FINITE ? "frame %d, value %d is '%s', not a finite number"
                                : st == MM__SCAN_TOO_LONG
                                    ? "frame %d, value %d '%s' is too long to be a number"
                                    : "frame %d, value %d: '%s' is not a number",
                                frame, n + 1, token_text(t, buf, sizeof buf));
        }
        p = stop;
        ++n;
    }
    if (n != count) {
        ps->p = p;
        return mm_error_set(ps->err, MM_ERR_VALUE_COUNT, ps->line, column_of(ps, p),
                            "frame %d has %d values, the channels declare %d", frame, n, count);
    }
    if (p < end) { /* consume the newline */
        ++ps->line;
        ps->line_start = p + 1;
        ++p;
    }
    ps->p = p;
    return MM_OK;
}

static int line_is_blank(const parser *ps)
{
    const char *p = ps->p;
    while (p < ps->end && is_space(*p)) ++p;
    return p >= ps->end || *p == '\n';
}

static void skip_line(parser *ps)
{
    while (ps->p < ps->end && *ps->p != '\n') ++ps->p;
    if (ps->p < ps->end) {
        ++ps->p;
        ++ps->line;
        ps->line_start = ps->p;
    }
}

static mm_result read_motion(parser *ps, mm_bvh *out)
{
    mm_result r;
    char buf[64];
    if ((r = expect_word(ps, "MOTION")) != MM_OK) return r;
    /* "Frames:" or "Frames :" */
    token t = next_token(ps);
    if (token_is(t, "Frames")) {
        if ((r = expect_word(ps, ":")) != MM_OK) return r;
    } else if (!token_is(t, "Frames:")) {
        return unexpected(ps, t, "'Frames:'");
    }
    t = next_token(ps);
    if (t.n == 0) return unexpected(ps, t, "a frame count");
    int64_t frames = 0;
    const char *stop;
    mm__scan_status st = mm__scan_int64(t.s, t.s + t.n, &frames, &stop);
    if (st == MM__SCAN_NOT_A_NUMBER || (st == MM__SCAN_OK && stop != t.s + t.n))
        return mm_error_set(ps->err, MM_ERR_SYNTAX, t.line, t.column, "frame count '%s' is not an integer",
                            token_text(t, buf, sizeof buf));
    if (st != MM__SCAN_OK || frames < 0 || frames > MM_MAX_FRAMES)
        return mm_error_set(ps->err, MM_ERR_LIMIT, t.line, t.column,
                            "frame count %s is out of range (0 to %d)", token_text(t, buf, sizeof buf),
                            MM_MAX_FRAMES);
    int frames_line = t.line, frames_column = t.column;
    t = next_token(ps);
    if (!token_is(t, "Frame")) return unexpected(ps, t, "'Frame Time:'");
    t = next_token(ps);
    if (token_is(t, "Time")) {
        if ((r = expect_word(ps, ":")) != MM_OK) return r;
    } else if (!token_is(t, "Time:")) {
        return unexpected(ps, t, "'Time:'");
    }
    if (line_is_blank(ps)) /* the value must be on the same line, not taken from the first frame */
        return mm_error_set(ps->err, MM_ERR_SYNTAX, ps->line, column_of(ps, ps->p),
                            "Frame Time has no value");
    skip_space_and_lines(ps);
    int time_line = ps->line, time_column = column_of(ps, ps->p);
    double frame_time = 0.0;
    if ((r = read_number(ps, "Frame Time", &frame_time)) != MM_OK) return r;
    if (!(frame_time >= 1e-6 && frame_time <= 3600.0))
        return mm_error_set(ps->err, MM_ERR_OUT_OF_RANGE, time_line, time_column,
                            "Frame Time %g is out of range (1e-6 to 3600 seconds)", frame_time);
    /* The rest of the Frame Time line must be empty. */
    if (!line_is_blank(ps)) {
        t = next_token(ps);
        return mm_error_set(ps->err, MM_ERR_SYNTAX, t.line, t.column, "unexpected '%s' after Frame Time",
                            token_text(t, buf, sizeof buf));
    }
    skip_line(ps);

    int channels = ps->channel_count;
    size_t remaining = (size_t)(ps->end - ps->p);
    /* Every value takes at least two bytes ("0 " or "0\n"). When the input cannot hold the
     * declared frames, allocate nothing from the declaration: read the lines into one scratch row
     * so the error points at the first bad line or at the end of the input. */
    int fits = !(frames > 0 && (uint64_t)frames * (uint64_t)channels > remaining / 2 + 1);
    out->frame_count = (int)frames;
    out->frame_time = frame_time;
    if (frames > 0) {
        size_t rows = fits ? (size_t)frames : 1;
        out->values = (double *)mm_alloc_array(ps->allocator, rows * (size_t)channels, sizeof(double));
        if (!out->values) return mm_error_set(ps->err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    }
    int f = 0;
    while (f < (int)frames) {
        if (ps->p >= ps->end)
            return mm_error_set(ps->err, MM_ERR_FRAME_COUNT, frames_line, frames_column,
                                "declares %lld frames but the file has %d", (long long)frames, f);
        if (line_is_blank(ps)) { /* tolerate empty lines between frames */
            skip_line(ps);
            continue;
        }
        double *row = out->values + (fits ? (size_t)f * (size_t)channels : 0);
        if ((r = read_motion_line(ps, row, channels, f)) != MM_OK) return r;
        ++f;
    }
    if (!fits) /* unreachable (the input is too short for the frames), but values holds one row */
        return mm_error_set(ps->err, MM_ERR_FRAME_COUNT, frames_line, frames_column,
                            "declares %lld frames, more than the input can hold", (long long)frames);
    while (ps->p < ps->end) {
        if (!line_is_blank(ps)) {
            const char *q = ps->p;
            while (is_space(*q)) ++q;
            return mm_error_set(ps->err, MM_ERR_FRAME_COUNT, ps->line, column_of(ps, q),
                                "declares %lld frames but the file has more", (long long)frames);
        }
        skip_line(ps);
    }
    return MM_OK;
}

static mm_result build_output(parser *ps, mm_bvh *out)
{
    mm_result r = mm_skeleton_init(&out->skeleton, ps->joint_count, ps->allocator);
    if (r != MM_OK) return mm_error_set(ps->err, r, 0, 0, "out of memory");
    out->channels = (mm_bvh_joint_channels *)mm_alloc_array(ps->allocator, (size_t)ps->joint_count,
                                                            sizeof(mm_bvh_joint_channels));
    out->offsets = (double *)mm_alloc_array(ps->allocator, (size_t)ps->joint_count * 3, sizeof(double));
    if (!out->channels || !out->offsets)
        return mm_error_set(ps->err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
    out->channel_count = ps->channel_count;
    for (int i = 0; i < ps->joint_count; ++i) {
        const bvh_joint_tmp *src = &ps->joints[i];
        mm_joint *j = &out->skeleton.joints[i];
        memcpy(j->name, src->name, MM_NAME_MAX);
        j->parent = src->parent;
        j->offset = mm_vec3_make((float)src->offset[0], (float)src->offset[1], (float)src->offset[2]);
        j->has_end_site = src->has_end_site != 0;
        j->end_site = mm_vec3_make((float)src->end_site[0], (float)src->end_site[1], (float)src->end_site[2]);
        memcpy(&out->offsets[3 * i], src->offset, sizeof src->offset);
        out->channels[i] = src->channels;
        char axes[4] = {0};
        int na = 0;
        for (int c = 0; c < src->channels.count; ++c) {
            int type = src->channels.type[c];
            if (type >= MM_BVH_XROTATION)
                axes[na++] = (char)('X' + (type - MM_BVH_XROTATION));
            else
                j->flags |= MM_JOINT_TRANSLATES;
        }
        j->order = na == 3 ? mm_euler_order_parse(axes) : MM_EULER_NONE;
    }
    return MM_OK;
}

mm_result mm_bvh_parse(const char *text, size_t size, const mm_bvh_read_desc *desc, mm_bvh *out,
                       mm_error *err)
{
    if (!out) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no output given");
    memset(out, 0, sizeof *out);
    if (err && desc && desc->name)
        mm__error_set_file(err, desc->name);
    else if (err && !err->file[0])
        mm__error_set_file(err, "<memory>");
    if (!text && size) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no input given");
    parser ps;
    memset(&ps, 0, sizeof ps);
    ps.p = text ? text : "";
    ps.end = ps.p + size;
    ps.line_start = ps.p;
    ps.line = 1;
    ps.err = err;
    ps.allocator = desc ? desc->allocator : NULL;
    if (ps.allocator) out->allocator = *ps.allocator;
    /* A UTF-8 byte order mark is allowed at the start. */
    if (size >= 3 && (unsigned char)ps.p[0] == 0xEF && (unsigned char)ps.p[1] == 0xBB &&
        (unsigned char)ps.p[2] == 0xBF) {
        ps.p += 3;
        ps.line_start = ps.p;
    }
    /* UTF-16 (a byte order mark, or a zero byte beside a letter of HIERARCHY): said so, not
     * "found 'H?I?E?...'" */
    const unsigned char *u = (const unsigned char *)ps.p;
    size_t left = (size_t)(ps.end - ps.p);
    if (left >= 2 && ((u[0] == 0xFF && u[1] == 0xFE) || (u[0] == 0xFE && u[1] == 0xFF) ||
                      (u[0] == 0 && u[1] != 0) || (u[0] != 0 && u[1] == 0)))
        return mm_error_set(err, MM_ERR_SYNTAX, 1, 1,
                            "the file is UTF-16 text: BVH is read as ASCII or UTF-8 (save it as UTF-8)");
    mm_result r = read_hierarchy(&ps);
    if (r == MM_OK && ps.channel_count == 0)
        r = mm_error_set(err, MM_ERR_CHANNELS, ps.root_line, ps.root_column,
                         "the hierarchy declares no channels");
    if (r == MM_OK) r = build_output(&ps, out);
    if (r == MM_OK) r = read_motion(&ps, out);
    mm_free(ps.allocator, ps.joints);
    if (r != MM_OK) {
        mm_bvh_free(out);
        if (err) err->code = r;
    }
    return r;
}

mm_result mm_bvh_load(const char *path, const mm_bvh_read_desc *desc, mm_bvh *out, mm_error *err)
{
    if (out) memset(out, 0, sizeof *out);
    char *data = NULL;
    size_t size = 0;
    const mm_allocator *allocator = desc ? desc->allocator : NULL;
    mm_result r = mm__read_file(path, allocator, &data, &size, err);
    if (r != MM_OK) return r;
    mm_bvh_read_desc d;
    memset(&d, 0, sizeof d);
    if (desc) d = *desc;
    if (!d.name) d.name = path;
    r = mm_bvh_parse(data, size, &d, out, err);
    mm_free(allocator, data);
    return r;
}

void mm_bvh_free(mm_bvh *bvh)
{
    if (!bvh) return;
    mm_allocator a = bvh->allocator;
    mm_free(&a, bvh->channels);
    mm_free(&a, bvh->offsets);
    mm_free(&a, bvh->values);
    mm_skeleton_free(&bvh->skeleton);
    memset(bvh, 0, sizeof *bvh);
}

const char *mm_bvh_channel_name(mm_bvh_channel c)
{
    static const char *names[6] = {"Xposition", "Yposition", "Zposition",
                                   "Xrotation", "Yrotation", "Zrotation"};
    return (int)c >= 0 && (int)c < 6 ? names[c] : NULL;
}
