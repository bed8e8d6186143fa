/* Reading the viewer's key scripts. */
#include "view_script.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include <GLFW/glfw3.h>

#include "cli.h"

#define MAX_SECONDS 1e6 /* a script longer than this is a mistake */

int view_script_key(const char *name)
{
    static const struct {
        const char *name;
        int key;
    } named[] = {
        {"space", GLFW_KEY_SPACE},
        {"tab", GLFW_KEY_TAB},
        {"enter", GLFW_KEY_ENTER},
        {"escape", GLFW_KEY_ESCAPE},
        {"backspace", GLFW_KEY_BACKSPACE},
        {"left", GLFW_KEY_LEFT},
        {"right", GLFW_KEY_RIGHT},
        {"up", GLFW_KEY_UP},
        {"down", GLFW_KEY_DOWN},
        {"home", GLFW_KEY_HOME},
        {"end", GLFW_KEY_END},
        {"pageup", GLFW_KEY_PAGE_UP},
        {"pagedown", GLFW_KEY_PAGE_DOWN},
        {"minus", GLFW_KEY_MINUS},
        {"equal", GLFW_KEY_EQUAL},
        {"comma", GLFW_KEY_COMMA},
        {"period", GLFW_KEY_PERIOD},
        {"lbracket", GLFW_KEY_LEFT_BRACKET},
        {"rbracket", GLFW_KEY_RIGHT_BRACKET},
        {"shift", GLFW_KEY_LEFT_SHIFT},
        {"ctrl", GLFW_KEY_LEFT_CONTROL},
    };
    if (!name || !name[0]) return -1;
    if (!name[1]) {
        char c = (char)toupper((unsigned char)name[0]);
        if ((c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9')) return c; /* GLFW's codes are ASCII */
        return -1;
    }
    for (size_t i = 0; i < sizeof named / sizeof named[0]; ++i)
        if (strcasecmp(name, named[i].name) == 0) return named[i].key;
    if ((name[0] == 'f' || name[0] == 'F') && isdigit((unsigned char)name[1])) {
        int n = atoi(name + 1);
        if (n >= 1 && n <= 12) return GLFW_KEY_F1 + n - 1;
    }
    return -1;
}

static int fail(const char *path, int line, const char *what, const char *word)
{
    fprintf(stderr, "mm: %s:%d: %s%s%s%s\n", path, line, what, word ? " '" : "", word ? word : "",
            word ? "'" : "");
    return 1;
}

int view_script_load(const char *path, double tick, view_script *s)
{
    memset(s, 0, sizeof *s);
    FILE *f = fopen(path, "r");
    if (!f) {
        fprintf(stderr, "mm: %s: cannot read it\n", path);
        return 1;
    }
    static const char *const actions[] = {"hold", "release", "press", "shot", "scrub", "select", "quit"};
    char text[512];
    int line = 0, capacity = 0, status = 0;
    double last = 0.0;
    while (status == 0 && fgets(text, sizeof text, f)) {
        ++line;
        char *hash = strchr(text, '#');
        if (hash) *hash = 0;
        char words[4][128];
        int n = sscanf(text, "%127s %127s %127s %127s", words[0], words[1], words[2], words[3]);
        if (n <= 0) continue;
        double t;
        if (!cli_parse_double(words[0], &t) || t < 0.0 || t > MAX_SECONDS) {
            status = fail(path, line, "a time needs seconds from 0, not", words[0]);
            break;
        }
        if (t < last) {
            status = fail(path, line, "times must not decrease down the file", NULL);
            break;
        }
        last = t;
        if (n < 2) {
            status = fail(path, line, "an action follows the time", NULL);
            break;
        }
        int a = 0;
        while (a < (int)(sizeof actions / sizeof actions[0]) && strcmp(words[1], actions[a]) != 0) ++a;
        if (a == (int)(sizeof actions / sizeof actions[0])) {
            status = fail(path, line, "unknown action", words[1]);
            break;
        }
        view_script_event e;
        memset(&e, 0, sizeof e);
        e.frame = lround(t / tick);
        e.action = (view_script_action)a;
        e.line = line;
        e.count = 1;
        bool needs_arg = e.action != VIEW_SCRIPT_QUIT;
        int max_words = e.action == VIEW_SCRIPT_PRESS ? 4 : needs_arg ? 3 : 2;
        if ((needs_arg && n < 3) || n > max_words) {
            status =
                fail(path, line, needs_arg ? "wrong number of words after" : "nothing may follow", words[1]);
            break;
        }
        if (e.action <= VIEW_SCRIPT_PRESS) {
            e.key = view_script_key(words[2]);
            if (e.key < 0) {
                status = fail(path, line, "unknown key", words[2]);
                break;
            }
            if (n == 4 && !cli_parse_int(words[3], 1, 10000, &e.count)) {
                status = fail(path, line, "a count needs 1 to 10000, not", words[3]);
                break;
            }
        } else if (e.action == VIEW_SCRIPT_SHOT) {
            for (const char *c = words[2]; *c; ++c)
                if (!isalnum((unsigned char)*c) && *c != '_' && *c != '-') {
                    status = fail(path, line, "a shot's name takes letters, digits, _ and -, not", words[2]);
                    break;
                }
            if (strlen(words[2]) >= sizeof e.name)
                status = fail(path, line, "a shot's name is too long", NULL);
            snprintf(e.name, sizeof e.name, "%.*s", (int)sizeof e.name - 1, words[2]);
        } else if (e.action == VIEW_SCRIPT_SCRUB || e.action == VIEW_SCRIPT_SELECT) {
            if (!cli_parse_int(words[2], 0, 100000000, &e.count)) {
                status = fail(path, line, "a tick or candidate needs a whole number, not", words[2]);
                break;
            }
        }
        if (status) break;
        if (s->count == capacity) {
            capacity = capacity ? capacity * 2 : 64;
            view_script_event *p = realloc(s->events, sizeof *p * (size_t)capacity);
            if (!p) {
                status = fail(path, line, "out of memory", NULL);
                break;
            }
            s->events = p;
        }
        s->events[s->count++] = e;
    }
    fclose(f);
    if (status) view_script_free(s);
    return status;
}

void view_script_free(view_script *s)
{
    free(s->events);
    memset(s, 0, sizeof *s);
}

const view_script_event *view_script_next(view_script *s, long frame)
{
    if (s->next >= s->count || s->events[s->next].frame > frame) return NULL;
    return &s->events[s->next++];
}
