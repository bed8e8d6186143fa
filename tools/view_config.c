/* Saving the viewer's tuning into a config: a small scanner over the JSON text finds where each
 * value is (or where its object ends) and the text is changed there alone. */
#define _POSIX_C_SOURCE 200809L
#include "view_config.h"

#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <mm/config_json.h>

/* ---- scanning ---- */

typedef struct scan {
    const char *s;
    size_t n;
} scan;

static size_t skip_space(const scan *t, size_t i)
{
    while (i < t->n && (t->s[i] == ' ' || t->s[i] == '\t' || t->s[i] == '\n' || t->s[i] == '\r')) ++i;
    return i;
}

/* Past the string starting at i (a '"'); 0 when unterminated. */
static size_t skip_string(const scan *t, size_t i)
{
    for (++i; i < t->n; ++i) {
        if (t->s[i] == '\\')
            ++i;
        else if (t->s[i] == '"')
            return i + 1;
    }
    return 0;
}

/* Past the value starting at i; 0 when it is not one. */
static size_t skip_value(const scan *t, size_t i)
{
    if (i >= t->n) return 0;
    char c = t->s[i];
    if (c == '"') return skip_string(t, i);
    if (c == '{' || c == '[') {
        char close = c == '{' ? '}' : ']';
        i = skip_space(t, i + 1);
        if (i < t->n && t->s[i] == close) return i + 1;
        for (;;) {
            if (c == '{') {
                if (i >= t->n || t->s[i] != '"' || !(i = skip_string(t, i))) return 0;
                i = skip_space(t, i);
                if (i >= t->n || t->s[i] != ':') return 0;
                i = skip_space(t, i + 1);
            }
            if (!(i = skip_value(t, i))) return 0;
            i = skip_space(t, i);
            if (i < t->n && t->s[i] == ',') {
                i = skip_space(t, i + 1);
                continue;
            }
            return i < t->n && t->s[i] == close ? i + 1 : 0;
        }
    }
    size_t b = i;
    while (i < t->n && strchr("+-.0123456789eEtruefalsn", t->s[i])) ++i;
    return i > b ? i : 0;
}

/* A member of the object at o (its '{'): where its value begins and ends. When no member is named
 * key: found is false and last_end is where the last member's value ends (0: no member). */
typedef struct member {
    bool found;
    size_t value, value_end;
    size_t last_key, last_end; /* the last member's key and value end */
    size_t before_last;        /* the '{' or ',' before the last member */
    size_t close;              /* the object's '}' */
} member;

static bool find_member(const scan *t, size_t o, const char *key, member *m)
{
    memset(m, 0, sizeof *m);
    size_t klen = strlen(key), sep = o;
    size_t i = skip_space(t, o + 1);
    if (i < t->n && t->s[i] == '}') {
        m->close = i;
        return true;
    }
    for (;;) {
        if (i >= t->n || t->s[i] != '"') return false;
        size_t k = i, kend = skip_string(t, i);
        if (!kend) return false;
        i = skip_space(t, kend);
        if (i >= t->n || t->s[i] != ':') return false;
        i = skip_space(t, i + 1);
        size_t vend = skip_value(t, i);
        if (!vend) return false;
        m->last_key = k, m->last_end = vend, m->before_last = sep;
        if (!m->found && kend - k - 2 == klen && memcmp(t->s + k + 1, key, klen) == 0) {
            m->found = true;
            m->value = i, m->value_end = vend;
        }
        i = skip_space(t, vend);
        if (i < t->n && t->s[i] == ',') {
            sep = i;
            i = skip_space(t, i + 1);
            continue;
        }
        if (i < t->n && t->s[i] == '}') {
            m->close = i;
            return true;
        }
        return false;
    }
}

/* The entry of the array at a (its '[') that is an object whose "name" is name: its '{'. */
static bool find_named(const scan *t, size_t a, const char *name, size_t *entry)
{
    size_t i = skip_space(t, a + 1), len = strlen(name);
    while (i < t->n && t->s[i] != ']') {
        size_t end = skip_value(t, i);
        if (!end) return false;
        member m;
        if (t->s[i] == '{' && find_member(t, i, "name", &m) && m.found && t->s[m.value] == '"' &&
            m.value_end - m.value - 2 == len && memcmp(t->s + m.value + 1, name, len) == 0) {
            *entry = i;
            return true;
        }
        i = skip_space(t, end);
        if (i < t->n && t->s[i] == ',') i = skip_space(t, i + 1);
    }
    return false;
}

/* ---- editing ---- */

static void say(char *why, size_t n, const char *fmt, ...)
{
    if (!why || n == 0) return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(why, n, fmt, ap);
    va_end(ap);
}

/* text with [a, b) replaced by ins. */
static char *splice(const scan *t, size_t a, size_t b, const char *ins)
{
    size_t k = strlen(ins), size = t->n - (b - a) + k;
    char *out = malloc(size + 1);
    if (!out) return NULL;
    memcpy(out, t->s, a);
    memcpy(out + a, ins, k);
    memcpy(out + a + k, t->s + b, t->n - b);
    out[size] = 0;
    return out;
}

/* The text of a new member: "key": followed by the value, or by objects down the rest of the path
 * ({"b": {"c": value}}) when it must be made. */
static bool member_text(char *out, size_t n, const char *key, size_t klen, const char *rest,
                        const char *value)
{
    int w = snprintf(out, n, "\"%.*s\": ", (int)klen, key);
    size_t at = w < 0 ? n : (size_t)w, closes = 0;
    while (rest && *rest && at < n) {
        const char *dot = strchr(rest, '.');
        size_t len = dot ? (size_t)(dot - rest) : strlen(rest);
        if (memchr(rest, '[', len)) return false; /* an array entry cannot be made here */
        w = snprintf(out + at, n - at, "{\"%.*s\": ", (int)len, rest);
        at = w < 0 ? n : at + (size_t)w;
        ++closes;
        rest = dot ? dot + 1 : NULL;
    }
    w = snprintf(out + (at < n ? at : n - 1), at < n ? n - at : 1, "%s", value);
    at = w < 0 ? n : at + (size_t)w;
    for (; closes > 0 && at + 1 < n; --closes) out[at++] = '}', out[at] = 0;
    return at < n;
}

char *view_config_set(const char *text, const char *path, const char *value_text, char *why, size_t why_size)
{
    scan t = {text, strlen(text)};
    size_t o = skip_space(&t, 0);
    if (o >= t.n || text[o] != '{') {
        say(why, why_size, "the config is not a JSON object");
        return NULL;
    }
    const char *key = path;
    for (;;) {
        const char *dot = strchr(key, '.'), *bracket = strchr(key, '[');
        size_t klen = dot ? (size_t)(dot - key) : strlen(key);
        size_t name_len = bracket && (!dot || bracket < dot) ? (size_t)(bracket - key) : klen;
        char name[64];
        snprintf(name, sizeof name, "%.*s", (int)name_len, key);
        member m;
        if (!find_member(&t, o, name, &m)) {
            say(why, why_size, "cannot read the object holding %s", path);
            return NULL;
        }
        if (!m.found) {
            if (name_len != klen) {
                say(why, why_size,
                    "%s: this file has no %s list (it comes from the defaults or the config it "
                    "extends): add the list here to tune it",
                    path, name);
                return NULL;
            }
            char ins[512];
            if (!member_text(ins, sizeof ins, key, klen, dot ? dot + 1 : NULL, value_text)) {
                say(why, why_size, "%s: cannot add it", path);
                return NULL;
            }
            char full[640];
            if (m.last_end == 0) { /* an empty object */
                snprintf(full, sizeof full, "%s", ins);
                return splice(&t, m.close, m.close, full);
            }
            /* the new member laid out as the last one is: on a line of its own at its indent, or
             * on the same line */
            size_t gap = skip_space(&t, m.before_last + 1);
            const char *nl = memchr(text + m.before_last + 1, '\n', gap - m.before_last - 1);
            if (nl)
                snprintf(full, sizeof full, ",%.*s%s", (int)(text + gap - nl), nl, ins);
            else
                snprintf(full, sizeof full, ", %s", ins);
            char *out = splice(&t, m.last_end, m.last_end, full);
            if (!out) say(why, why_size, "out of memory");
            return out;
        }
        if (!dot) {
            char *out = splice(&t, m.value, m.value_end, value_text);
            if (!out) say(why, why_size, "out of memory");
            return out;
        }
        if (name_len != klen) { /* name[ENTRY] */
            char entry[48];
            snprintf(entry, sizeof entry, "%.*s", (int)(klen - name_len - 2), key + name_len + 1);
            if (text[m.value] != '[' || !find_named(&t, m.value, entry, &o)) {
                say(why, why_size, "%s: no entry named %s in %s", path, entry, name);
                return NULL;
            }
        } else if (text[m.value] == '{') {
            o = m.value;
        } else {
            say(why, why_size, "%s: %s is not an object", path, name);
            return NULL;
        }
        key = dot + 1;
    }
}

/* ---- saving ---- */

static char *read_text(const char *path, char *why, size_t why_size)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        say(why, why_size, "%s: cannot read it", path);
        return NULL;
    }
    size_t cap = 4096, n = 0;
    char *s = malloc(cap);
    for (size_t k; s && (k = fread(s + n, 1, cap - n - 1, f)) > 0;) {
        n += k;
        if (n + 1 == cap) {
            char *p = realloc(s, cap *= 2);
            if (!p) free(s);
            s = p;
        }
    }
    fclose(f);
    if (!s) say(why, why_size, "out of memory");
    if (s) s[n] = 0;
    return s;
}

/* Writes text beside path, checks it loads as a config, and renames it into place. */
static bool write_checked(const char *path, const char *text, char *why, size_t why_size)
{
    char tmp[4096];
    snprintf(tmp, sizeof tmp, "%s.saving%ld", path, (long)getpid());
    FILE *f = fopen(tmp, "wb");
    if (!f) {
        say(why, why_size, "%s: cannot write beside it", path);
        return false;
    }
    bool ok = fwrite(text, 1, strlen(text), f) == strlen(text);
    ok = fclose(f) == 0 && ok;
    mm_config cfg;
    memset(&cfg, 0, sizeof cfg);
    mm_error err;
    memset(&err, 0, sizeof err);
    if (!ok) {
        say(why, why_size, "%s: cannot write beside it", path);
    } else if (mm_config_load_json(tmp, &cfg, NULL, &err) != MM_OK) {
        say(why, why_size, "the saved config would not load: %.200s", err.message);
        ok = false;
    } else if (rename(tmp, path) != 0) {
        say(why, why_size, "%s: cannot replace it", path);
        ok = false;
    }
    mm_config_free(&cfg);
    if (!ok) remove(tmp);
    return ok;
}

int view_config_save(const char *path, mm_view_tuning *t, char *why, size_t why_size)
{
    char *text = read_text(path, why, why_size);
    if (!text) return -1;
    int written = 0;
    char key[128], value[32];
    for (int i = 0; i <= t->count + 1; ++i) {
        if (i < t->count) {
            mm_view_tuning_entry *e = &t->entries[i];
            float now = fmaxf(*e->value, 0.0f);
            if (!e->key[0] || now == fmaxf(e->saved, 0.0f)) continue;
            if (e->bone[0])
                snprintf(key, sizeof key, "features.bones[%s].%s", e->bone, e->key);
            else
                snprintf(key, sizeof key, "%s", e->key);
            snprintf(value, sizeof value, "%.6g", (double)now);
        } else {
            bool dm = i == t->count;
            bool now = dm ? t->layers.distance_matching : t->layers.warping;
            if (now == (dm ? t->saved_layers.distance_matching : t->saved_layers.warping)) continue;
            snprintf(key, sizeof key, "runtime.%s", dm ? "distance_matching" : "warping");
            snprintf(value, sizeof value, "%s", now ? "true" : "false");
        }
        char *next = view_config_set(text, key, value, why, why_size);
        free(text);
        if (!next) return -1;
        text = next;
        ++written;
    }
    if (written > 0 && !write_checked(path, text, why, why_size)) written = -1;
    free(text);
    if (written > 0) {
        for (int i = 0; i < t->count; ++i) t->entries[i].saved = *t->entries[i].value;
        t->saved_layers.distance_matching = t->layers.distance_matching;
        t->saved_layers.warping = t->layers.warping;
    }
    return written;
}
