/* view_script.h - key scripts for the viewer (mm view --script KEYS.txt): what a person would
 * press, at set times, played frame by frame with a fixed tick so that a run is the same every
 * time. One event a line, '#' starts a comment:
 *
 *   TIME hold KEY        the key goes down (a press) and stays down
 *   TIME release KEY     it comes up
 *   TIME press KEY [N]   N presses (default 1) of a key that is not held
 *   TIME shot NAME       a screenshot DIR/NAME.png and DIR/NAME.json (what is on it) at the end of
 *                        this frame
 *   TIME scrub TICK      the timeline's slider dragged to recorded tick TICK
 *   TIME select N        candidate N (0: the search's winner) picked in the panel's list
 *   TIME quit            the last frame
 *
 * TIME is seconds from the start (frame = round(TIME / tick)), never decreasing down the file.
 * KEY is a letter, a digit, or one of space tab enter escape backspace left right up down home end
 * pageup pagedown minus equal comma period lbracket rbracket shift ctrl f1 ... f12. */
#ifndef MM_TOOLS_VIEW_SCRIPT_H
#define MM_TOOLS_VIEW_SCRIPT_H

#include <stdbool.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum view_script_action {
    VIEW_SCRIPT_HOLD,
    VIEW_SCRIPT_RELEASE,
    VIEW_SCRIPT_PRESS,
    VIEW_SCRIPT_SHOT,
    VIEW_SCRIPT_SCRUB,
    VIEW_SCRIPT_SELECT,
    VIEW_SCRIPT_QUIT
} view_script_action;

typedef struct view_script_event {
    long frame;
    view_script_action action;
    int key;    /* GLFW key code (hold, release, press) */
    long count; /* presses; the tick of a scrub; the candidate of a select */
    char name[64];
    int line;
} view_script_event;

typedef struct view_script {
    view_script_event *events;
    int count, next;
} view_script;

/* Reads a script; 0, or 1 after printing "mm: FILE:LINE: what is wrong" on stderr. */
int view_script_load(const char *path, double tick, view_script *s);
void view_script_free(view_script *s);
/* The next event due at frame (its frame <= frame), or NULL. */
const view_script_event *view_script_next(view_script *s, long frame);
/* The GLFW key code of a name, or -1. */
int view_script_key(const char *name);

#ifdef __cplusplus
}
#endif

#endif /* MM_TOOLS_VIEW_SCRIPT_H */
