/* Input scripts in JSON (cJSON). */
#include <mm/input_json.h>

#include <cjson/cJSON.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "io/json_parse.h"
#include "io/file.h"
#include "io/text.h"

/* A number a float holds into *out; one that does not is reported as written (w), not as inf. */
static mm_result number(const mm__json_where *w, const cJSON *v, const char *what, float *out, mm_error *err)
{
    if (!cJSON_IsNumber(v) || !isfinite(v->valuedouble))
        return mm_error_set(err, MM_ERR_BAD_NUMBER, 0, 0, "%s must be a finite number", what);
    if (fabs(v->valuedouble) > FLT_MAX) {
        size_t n = 0;
        const char *text = mm__json_number_text(w, v, &n);
        return mm_error_set(err, MM_ERR_BAD_NUMBER, 0, 0, "%s: %.*s does not fit a float (at most %g)", what,
                            text ? (int)(n < 40 ? n : 40) : 5, text ? text : "large", (double)FLT_MAX);
    }
    *out = (float)v->valuedouble;
    return MM_OK;
}

static mm_result pair(const mm__json_where *w, const cJSON *v, const char *what, int i, float out[2],
                      mm_error *err)
{
    if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != 2)
        return mm_error_set(err, MM_ERR_SYNTAX, 0, 0, "keys[%d].%s must be [x, z]", i, what);
    const cJSON *e = v->child;
    for (int k = 0; k < 2; ++k, e = e->next) {
        char item[64];
        snprintf(item, sizeof item, "keys[%d].%s[%d]", i, what, k);
        mm_result r = number(w, e, item, &out[k], err);
        if (r != MM_OK) return r;
    }
    return MM_OK;
}

static mm_result parse_key(const mm__json_where *w, const cJSON *j, int i, mm_input_key *k, mm_error *err)
{
    static const char *const known[] = {"t", "stick", "gait", "strafe", "facing", "jump"};
    if (!cJSON_IsObject(j)) return mm_error_set(err, MM_ERR_SYNTAX, 0, 0, "keys[%d] must be an object", i);
    for (const cJSON *it = j->child; it; it = it->next) {
        int ok = 0;
        for (size_t n = 0; n < sizeof known / sizeof known[0]; ++n) ok |= strcmp(it->string, known[n]) == 0;
        if (!ok)
            return mm_error_set(err, MM_ERR_UNKNOWN_KEYWORD, 0, 0, "keys[%d].%s: unknown field", i,
                                it->string);
    }
    const cJSON *t = cJSON_GetObjectItemCaseSensitive(j, "t");
    if (!t) return mm_error_set(err, MM_ERR_SYNTAX, 0, 0, "keys[%d].t is missing", i);
    char what[32];
    snprintf(what, sizeof what, "keys[%d].t", i);
    mm_result r = number(w, t, what, &k->t, err);
    if (r != MM_OK) return r;
    const cJSON *stick = cJSON_GetObjectItemCaseSensitive(j, "stick");
    if (!stick) return mm_error_set(err, MM_ERR_SYNTAX, 0, 0, "keys[%d].stick is missing", i);
    r = pair(w, stick, "stick", i, k->input.stick, err);
    if (r != MM_OK) return r;
    const cJSON *gait = cJSON_GetObjectItemCaseSensitive(j, "gait");
    k->input.gait = MM_GAIT_WALK;
    if (gait) {
        if (!cJSON_IsString(gait) || (k->input.gait = mm_gait_parse(gait->valuestring)) == MM_GAIT_COUNT)
            return mm_error_set(err, MM_ERR_SYNTAX, 0, 0,
                                "keys[%d].gait must be \"walk\", \"run\", \"crouch\" or \"jump\"", i);
    }
    const cJSON *strafe = cJSON_GetObjectItemCaseSensitive(j, "strafe");
    if (strafe) {
        if (!cJSON_IsBool(strafe))
            return mm_error_set(err, MM_ERR_SYNTAX, 0, 0, "keys[%d].strafe must be true or false", i);
        k->input.strafe = cJSON_IsTrue(strafe);
    }
    const cJSON *jump = cJSON_GetObjectItemCaseSensitive(j, "jump");
    if (jump) {
        if (!cJSON_IsBool(jump))
            return mm_error_set(err, MM_ERR_SYNTAX, 0, 0, "keys[%d].jump must be true or false", i);
        k->input.jump = cJSON_IsTrue(jump);
    }
    const cJSON *facing = cJSON_GetObjectItemCaseSensitive(j, "facing");
    if (facing) {
        if ((r = pair(w, facing, "facing", i, k->input.facing, err)) != MM_OK) return r;
        float len = sqrtf(k->input.facing[0] * k->input.facing[0] + k->input.facing[1] * k->input.facing[1]);
        if (!(len > 1e-6f))
            return mm_error_set(err, MM_ERR_OUT_OF_RANGE, 0, 0, "keys[%d].facing must not be zero", i);
        k->input.facing[0] /= len; /* a direction: any length but zero */
        k->input.facing[1] /= len;
        k->input.has_facing = true;
    }
    return MM_OK;
}

mm_result mm_input_script_parse_json(const char *text, size_t size, const char *name, mm_input_script *out,
                                     mm_error *err)
{
    if (!out) return mm_error_set(err, MM_ERR_INVALID_ARGUMENT, 0, 0, "no script given");
    memset(out, 0, sizeof *out);
    mm__error_set_file(err, name ? name : "<input>");
    if (!text || size == 0)
        return mm_error_set(err, MM_ERR_UNEXPECTED_EOF, 0, 0, "the input script is empty");
    cJSON *root;
    mm__json_where *where = NULL;
    mm_result parsed = mm__json_parse_where(text, size, NULL, &root, &where, err);
    if (parsed != MM_OK) return parsed;
    mm_result r = MM_OK;
    const cJSON *keys = cJSON_IsObject(root) ? cJSON_GetObjectItemCaseSensitive(root, "keys") : NULL;
    if (!cJSON_IsObject(root))
        r = mm_error_set(err, MM_ERR_SYNTAX, 0, 0, "an input script is an object {\"keys\": [...]}");
    else if (!keys || !cJSON_IsArray(keys))
        r = mm_error_set(err, MM_ERR_SYNTAX, 0, 0, "keys: missing, or not an array");
    for (const cJSON *it = root->child; r == MM_OK && it; it = it->next)
        if (strcmp(it->string, "keys") != 0)
            r = mm_error_set(err, MM_ERR_UNKNOWN_KEYWORD, 0, 0, "%s: unknown field", it->string);
    if (r == MM_OK) {
        int n = cJSON_GetArraySize(keys);
        r = mm_input_script_init(out, n, NULL);
        if (r != MM_OK) r = mm_error_set(err, r, 0, 0, "cannot hold %d keys", n);
        int i = 0;
        for (const cJSON *k = keys->child; r == MM_OK && k; k = k->next, ++i)
            r = parse_key(where, k, i, &out->keys[i], err);
    }
    if (r == MM_OK) r = mm_input_script_validate(out, err);
    /* a meaning error names a field path: its value's line and column are added */
    if (r != MM_OK) mm__json_locate_error(root, where, err);
    cJSON_Delete(root);
    mm__json_where_free(where);
    if (r != MM_OK) mm_input_script_free(out);
    return r;
}

mm_result mm_input_script_load_json(const char *path, mm_input_script *out, mm_error *err)
{
    if (out) memset(out, 0, sizeof *out);
    char *text = NULL;
    size_t size = 0;
    mm_result r = mm__read_file(path, NULL, &text, &size, err);
    if (r != MM_OK) return r;
    r = mm_input_script_parse_json(text, size, path, out, err);
    free(text);
    return r;
}

mm_result mm_input_script_write_json(const mm_input_script *s, FILE *out)
{
    if (!s || !out) return MM_ERR_INVALID_ARGUMENT;
    char a[64], b[64], c[64];
    fputs("{\"keys\": [\n", out);
    for (int i = 0; i < s->key_count; ++i) {
        const mm_input_key *k = &s->keys[i];
        mm__format_number(a, sizeof a, k->t, 9);
        mm__format_number(b, sizeof b, k->input.stick[0], 9);
        mm__format_number(c, sizeof c, k->input.stick[1], 9);
        fprintf(out, "  {\"t\": %s, \"stick\": [%s, %s], \"gait\": \"%s\"", a, b, c,
                mm_gait_name(k->input.gait));
        if (k->input.strafe) fputs(", \"strafe\": true", out);
        if (k->input.jump) fputs(", \"jump\": true", out);
        if (k->input.has_facing) {
            mm__format_number(b, sizeof b, k->input.facing[0], 9);
            mm__format_number(c, sizeof c, k->input.facing[1], 9);
            fprintf(out, ", \"facing\": [%s, %s]", b, c);
        }
        fprintf(out, "}%s\n", i + 1 < s->key_count ? "," : "");
    }
    fputs("]}\n", out);
    return ferror(out) ? MM_ERR_IO : MM_OK;
}
