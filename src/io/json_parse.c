/* Strict JSON: cJSON builds the tree, then one pass over the text walks it alongside, checking
 * what cJSON lets through (RFC 8259's number grammar and whitespace, control characters in
 * strings, keys given twice, text after the value) and recording where each value is. Keys are
 * compared through a hash table per object, so the whole pass is linear in the text. */
#include "io/json_parse.h"

#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/file.h"

/* Objects up to this many keys compare them pairwise (cheaper than a table); larger ones hash. */
#define JSON_SMALL_OBJECT 8

typedef struct where_entry {
    const cJSON *node;
    int32_t line, column;
    uint32_t offset, length; /* the value's text */
} where_entry;

/* The entries are appended in the order of the text (sequential writes: recording costs little
 * even for a million values) and searched one by one only when an error is reported. */
struct mm__json_where {
    char file[MM_ERROR_FILE_MAX];
    char *text; /* a copy: numbers are reported as written */
    where_entry *entries;
    size_t count, capacity;
    mm__json_where *next;
};

static size_t hash_string(const char *s)
{
    uint64_t h = 1469598103934665603ull; /* FNV-1a */
    for (; *s; ++s) h = (h ^ (unsigned char)*s) * 1099511628211ull;
    return (size_t)h;
}

/* ---- the pass over the text --------------------------------------------------------------- */

typedef struct scan {
    const char *t;
    size_t n, i, line_start;
    int line;
    mm__json_where *where; /* NULL: record nothing */
    mm_error *err;
    mm_result failed;
} scan;

static int column(const scan *s) { return (int)(s->i - s->line_start) + 1; }

/* Records the first failure, at line and col (0: where the pass is); returns 0. */
static int fail_at(scan *s, int line, int col, mm_result code, const char *fmt, ...)
{
    if (s->failed != MM_OK) return 0;
    char msg[MM_ERROR_MESSAGE_MAX];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    s->failed = mm_error_set(s->err, code, line ? line : s->line, line ? col : column(s), "%s", msg);
    return 0;
}
#define fail(s, ...) fail_at(s, 0, 0, __VA_ARGS__)

static void skip_space(scan *s)
{
    while (s->i < s->n) {
        char c = s->t[s->i];
        if (c == '\n') {
            ++s->line;
            s->line_start = s->i + 1;
        } else if (c != ' ' && c != '\t' && c != '\r') {
            return;
        }
        ++s->i;
    }
}

static int is_digit(char c) { return c >= '0' && c <= '9'; }

static void record(scan *s, const cJSON *node, size_t at, int line, int col)
{
    mm__json_where *w = s->where;
    if (!w) return;
    if (w->count == w->capacity) { /* out of memory: the positions stay unknown, nothing fails */
        size_t capacity = w->capacity ? 2 * w->capacity : 256;
        where_entry *grown = (where_entry *)realloc(w->entries, capacity * sizeof *grown);
        if (!grown) return;
        w->entries = grown;
        w->capacity = capacity;
    }
    where_entry *e = &w->entries[w->count++];
    e->node = node;
    e->line = line;
    e->column = col;
    e->offset = (uint32_t)at;
    e->length = (uint32_t)(s->i - at);
}

static int skip_string(scan *s)
{
    ++s->i; /* the opening quote */
    while (s->i < s->n && s->t[s->i] != '"') {
        unsigned char c = (unsigned char)s->t[s->i];
        if (c < 0x20) return fail(s, MM_ERR_SYNTAX, "not valid JSON here: a control character in a string");
        s->i += c == '\\' ? 2 : 1;
    }
    if (s->i >= s->n) return fail(s, MM_ERR_SYNTAX, "not valid JSON here: the string does not end");
    ++s->i;
    return 1;
}

static int skip_number(scan *s)
{
    const char *t = s->t;
    size_t i = s->i;
    if (i < s->n && t[i] == '-') ++i;
    if (i < s->n && t[i] == '0') {
        ++i;
    } else if (i < s->n && is_digit(t[i])) {
        while (i < s->n && is_digit(t[i])) ++i;
    } else {
        return fail(s, MM_ERR_SYNTAX, "not valid JSON here: not a JSON number");
    }
    if (i < s->n && t[i] == '.') {
        if (!(++i < s->n && is_digit(t[i])))
            return fail(s, MM_ERR_SYNTAX, "not valid JSON here: not a JSON number");
        while (i < s->n && is_digit(t[i])) ++i;
    }
    if (i < s->n && (t[i] == 'e' || t[i] == 'E')) {
        ++i;
        if (i < s->n && (t[i] == '+' || t[i] == '-')) ++i;
        if (!(i < s->n && is_digit(t[i])))
            return fail(s, MM_ERR_SYNTAX, "not valid JSON here: not a JSON number");
        while (i < s->n && is_digit(t[i])) ++i;
    }
    if (i < s->n &&
        (is_digit(t[i]) || t[i] == '.' || t[i] == 'e' || t[i] == 'E' || t[i] == '+' || t[i] == '-'))
        return fail(s, MM_ERR_SYNTAX, "not valid JSON here: not a JSON number");
    s->i = i;
    return 1;
}

typedef struct key_seen {
    const char *key;
    int line, column;
} key_seen;

static int value(scan *s, const cJSON *node, int depth);

/* The members of an object (s->i just past '{'): each key compared with those before it. */
static int object(scan *s, const cJSON *node, int depth)
{
    size_t count = 0;
    for (const cJSON *m = node->child; m; m = m->next) ++count;
    key_seen small[JSON_SMALL_OBJECT], *table = small;
    size_t capacity = JSON_SMALL_OBJECT;
    if (count > JSON_SMALL_OBJECT) {
        capacity = 16;
        while (capacity < 2 * count) capacity *= 2;
        table = (key_seen *)calloc(capacity, sizeof *table);
        if (!table) return fail(s, MM_ERR_OUT_OF_MEMORY, "out of memory");
    }
    size_t seen = 0;
    int ok = 1;
    skip_space(s);
    if (s->i < s->n && s->t[s->i] == '}') {
        ++s->i;
    } else {
        for (const cJSON *m = node->child; ok; m = m->next) {
            skip_space(s);
            if (!m || s->i >= s->n || s->t[s->i] != '"') {
                ok = fail(s, MM_ERR_SYNTAX, "not valid JSON here");
                break;
            }
            int line = s->line, col = column(s);
            if (!(ok = skip_string(s))) break;
            const key_seen *first = NULL;
            if (count <= JSON_SMALL_OBJECT) {
                for (size_t k = 0; k < seen && !first; ++k)
                    if (strcmp(small[k].key, m->string) == 0) first = &small[k];
                if (!first) small[seen] = (key_seen){m->string, line, col};
            } else {
                size_t mask = capacity - 1, k = hash_string(m->string) & mask;
                while (table[k].key && strcmp(table[k].key, m->string) != 0) k = (k + 1) & mask;
                if (table[k].key)
                    first = &table[k];
                else
                    table[k] = (key_seen){m->string, line, col};
            }
            ++seen;
            if (first) {
                ok = fail_at(s, line, col, MM_ERR_DUPLICATE_NAME,
                             "key '%s' given twice (first at line %d, column %d)", m->string, first->line,
                             first->column);
                break;
            }
            skip_space(s);
            if (s->i >= s->n || s->t[s->i] != ':') {
                ok = fail(s, MM_ERR_SYNTAX, "not valid JSON here");
                break;
            }
            ++s->i;
            if (!(ok = value(s, m, depth + 1))) break;
            skip_space(s);
            if (s->i < s->n && s->t[s->i] == ',') {
                ++s->i;
                continue;
            }
            if (s->i < s->n && s->t[s->i] == '}' && !m->next) {
                ++s->i;
                break;
            }
            ok = fail(s, MM_ERR_SYNTAX, "not valid JSON here");
        }
    }
    if (table != small) free(table);
    return ok;
}

static int array(scan *s, const cJSON *node, int depth)
{
    skip_space(s);
    if (s->i < s->n && s->t[s->i] == ']') {
        ++s->i;
        return 1;
    }
    for (const cJSON *e = node->child;; e = e->next) {
        if (!e) return fail(s, MM_ERR_SYNTAX, "not valid JSON here");
        if (!value(s, e, depth + 1)) return 0;
        skip_space(s);
        if (s->i < s->n && s->t[s->i] == ',') {
            ++s->i;
            continue;
        }
        if (s->i < s->n && s->t[s->i] == ']' && !e->next) {
            ++s->i;
            return 1;
        }
        return fail(s, MM_ERR_SYNTAX, "not valid JSON here");
    }
}

static int literal(scan *s, const char *word)
{
    size_t n = strlen(word);
    if (s->n - s->i < n || memcmp(s->t + s->i, word, n) != 0)
        return fail(s, MM_ERR_SYNTAX, "not valid JSON here");
    s->i += n;
    return 1;
}

static int value(scan *s, const cJSON *node, int depth)
{
    skip_space(s);
    if (s->i >= s->n) return fail(s, MM_ERR_SYNTAX, "not valid JSON here: the text ends");
    size_t at = s->i;
    int line = s->line, col = column(s), ok;
    char c = s->t[s->i];
    if (c == '{' && cJSON_IsObject(node)) {
        ++s->i;
        ok = object(s, node, depth);
    } else if (c == '[' && cJSON_IsArray(node)) {
        ++s->i;
        ok = array(s, node, depth);
    } else if (c == '"' && cJSON_IsString(node)) {
        ok = skip_string(s);
    } else if (cJSON_IsNumber(node) && (c == '-' || is_digit(c))) {
        ok = skip_number(s);
    } else if (cJSON_IsTrue(node)) {
        ok = literal(s, "true");
    } else if (cJSON_IsFalse(node)) {
        ok = literal(s, "false");
    } else if (cJSON_IsNull(node)) {
        ok = literal(s, "null");
    } else {
        ok = fail(s, MM_ERR_SYNTAX, "not valid JSON here");
    }
    if (ok) record(s, node, at, line, col);
    return ok;
}

/* ---- entry points ----------------------------------------------------------------------- */

/* The line and column of byte `at` of text. */
static void position(const char *text, size_t at, int *line, int *column)
{
    *line = 1;
    size_t start = 0;
    for (size_t p = 0; p < at; ++p)
        if (text[p] == '\n') {
            ++*line;
            start = p + 1;
        }
    *column = (int)(at - start) + 1;
}

mm_result mm__json_parse_where(const char *text, size_t size, const char *file, cJSON **out,
                               mm__json_where **where, mm_error *err)
{
    *out = NULL;
    if (where) *where = NULL;
    if (!text || size == 0) return mm_error_set(err, MM_ERR_UNEXPECTED_EOF, 0, 0, "the file is empty");
    size_t skip = size >= 3 && memcmp(text, "\xEF\xBB\xBF", 3) == 0 ? 3 : 0; /* a UTF-8 byte order mark */
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithLengthOpts(text + skip, size - skip, &end, 0);
    if (!root) {
        int line, col;
        size_t at = end && end >= text && end <= text + size ? (size_t)(end - text) : 0;
        if (!end) {
            const char *e = cJSON_GetErrorPtr();
            at = e && e >= text && e <= text + size ? (size_t)(e - text) : 0;
        }
        position(text, at, &line, &col);
        return mm_error_set(err, MM_ERR_SYNTAX, line, col, "not valid JSON here");
    }
    mm__json_where *w = NULL;
    if (where) {
        w = (mm__json_where *)calloc(1, sizeof *w);
        if (w) {
            w->text = (char *)malloc(size);
            snprintf(w->file, sizeof w->file, "%s", file ? file : "");
        }
        if (!w || !w->text) {
            mm__json_where_free(w);
            cJSON_Delete(root);
            return mm_error_set(err, MM_ERR_OUT_OF_MEMORY, 0, 0, "out of memory");
        }
        memcpy(w->text, text, size);
    }
    scan s = {text, size, skip, skip, 1, w, err, MM_OK};
    if (value(&s, root, 0)) {
        skip_space(&s);
        if (s.i < s.n) fail(&s, MM_ERR_SYNTAX, "text after the JSON value");
    }
    if (s.failed != MM_OK) {
        mm__json_where_free(w);
        cJSON_Delete(root);
        return s.failed;
    }
    *out = root;
    if (where) *where = w;
    return MM_OK;
}

mm_result mm__json_parse(const char *text, size_t size, cJSON **out, mm_error *err)
{
    return mm__json_parse_where(text, size, NULL, out, NULL, err);
}

mm__json_where *mm__json_where_join(mm__json_where *head, mm__json_where *tail)
{
    if (!head) return tail;
    mm__json_where *w = head;
    while (w->next) w = w->next;
    w->next = tail;
    return head;
}

void mm__json_where_free(mm__json_where *where)
{
    while (where) {
        mm__json_where *next = where->next;
        free(where->entries);
        free(where->text);
        free(where);
        where = next;
    }
}

static const where_entry *find(const mm__json_where *where, const cJSON *node, const mm__json_where **in)
{
    for (const mm__json_where *w = where; w && node; w = w->next)
        for (size_t k = 0; k < w->count; ++k)
            if (w->entries[k].node == node) {
                if (in) *in = w;
                return &w->entries[k];
            }
    return NULL;
}

int mm__json_where_at(const mm__json_where *where, const cJSON *node, int *line, int *column,
                      const char **file)
{
    const mm__json_where *in = NULL;
    const where_entry *e = find(where, node, &in);
    if (!e) return 0;
    if (line) *line = e->line;
    if (column) *column = e->column;
    if (file) *file = in->file[0] ? in->file : NULL;
    return 1;
}

const char *mm__json_number_text(const mm__json_where *where, const cJSON *node, size_t *length)
{
    const mm__json_where *in = NULL;
    const where_entry *e = find(where, node, &in);
    if (!e || !cJSON_IsNumber(node)) return NULL;
    *length = e->length;
    return in->text + e->offset;
}

static int is_path_char(char c)
{
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || is_digit(c) || c == '_' || c == '.' ||
           c == '[' || c == ']' || c == '-';
}

const cJSON *mm__json_path_node(const cJSON *root, const char *message)
{
    const cJSON *at = root;
    const char *p = message;
    while (at && *p) {
        if (p[0] == ' ' && p[1] == '(') { /* "clips[3] (walk).ranges[0]": a name in passing */
            const char *close = strchr(p, ')');
            if (!close || close[1] != '.') break;
            p = close + 1;
            continue;
        }
        if (!is_path_char(*p)) break;
        if (*p == '.') {
            ++p;
            continue;
        }
        if (*p == '[') {
            char *end = NULL;
            long index = strtol(p + 1, &end, 10);
            if (!end || *end != ']' || index < 0 || !cJSON_IsArray(at)) break;
            const cJSON *e = at->child;
            for (long k = 0; e && k < index; ++k) e = e->next;
            if (!e) break;
            at = e;
            p = end + 1;
            continue;
        }
        size_t n = 0;
        while (p[n] && is_path_char(p[n]) && p[n] != '.' && p[n] != '[') ++n;
        if (!cJSON_IsObject(at)) break;
        const cJSON *m = at->child;
        while (m && !(m->string && strlen(m->string) == n && memcmp(m->string, p, n) == 0)) m = m->next;
        if (!m) break;
        at = m;
        p += n;
    }
    return at;
}

mm_result mm__json_locate_error(const cJSON *root, const mm__json_where *where, mm_error *err)
{
    if (!err) return MM_ERR_INVALID_ARGUMENT;
    if (err->line > 0 || !root || !where) return err->code;
    const cJSON *node = mm__json_path_node(root, err->message);
    int line, col;
    const char *file = NULL;
    if (node && mm__json_where_at(where, node, &line, &col, &file)) {
        err->line = line;
        err->column = col;
        if (file) mm__error_set_file(err, file);
    }
    return err->code;
}
